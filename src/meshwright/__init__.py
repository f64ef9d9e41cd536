"""meshwright: unstructured grid generation for finite-volume and finite-element solvers."""

from meshwright.core.errors import (
    DegenerateInputError,
    DuplicatePointError,
    FormatError,
    GeometryError,
    InputError,
    MeshingError,
    MeshwrightError,
    SizeError,
    ValidationError,
)

__version__ = "0.1.0"

__all__ = [
    "__version__",
    "MeshwrightError",
    "InputError",
    "DuplicatePointError",
    "DegenerateInputError",
    "GeometryError",
    "SizeError",
    "MeshingError",
    "ValidationError",
    "FormatError",
]
