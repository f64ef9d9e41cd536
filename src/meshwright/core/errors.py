"""Exception hierarchy of meshwright.

Every error raised on bad input or on a failure the library can diagnose is a
:class:`MeshwrightError`, so callers can catch one type.  Messages name the
culprit: the loop, segment, point index or coordinates at fault.

Hierarchy::

    MeshwrightError
    ├── InputError (also ValueError)       malformed arrays, wrong shapes, NaN/inf
    │   ├── DuplicatePointError            coincident input points when rejected
    │   └── DegenerateInputError           too few points, all points collinear
    ├── GeometryError (also ValueError)    self-intersecting or open boundaries
    ├── SizeError (also ValueError)        impossible or non-positive sizes
    ├── MeshingError (also RuntimeError)   an algorithm hit its cap or could not close
    ├── ValidationError                    a mesh fails Mesh.validate()
    └── FormatError (also ValueError)      unreadable or unsupported file
"""

__all__ = [
    "MeshwrightError",
    "InputError",
    "DuplicatePointError",
    "DegenerateInputError",
    "GeometryError",
    "SizeError",
    "MeshingError",
    "ValidationError",
    "FormatError",
    "MeshwrightWarning",
    "SliverWarning",
    "fmt_point",
]


def fmt_point(p) -> str:
    """Coordinates for error messages: ``(x, y)`` or ``(x, y, z)`` with round-trip precision.

    Parameters
    ----------
    p : (d,) array_like of float
        One point of any dimension.

    Returns
    -------
    str
        ``"(" + ", ".join(...) + ")"``; ``float(s)`` of each entry gives the coordinate back.
    """
    return "(" + ", ".join(f"{float(x):.17g}" for x in p) + ")"


class MeshwrightError(Exception):
    """Base class of every error meshwright raises on purpose."""


class InputError(MeshwrightError, ValueError):
    """Input arrays are malformed: wrong shape or dtype, NaN or infinite values."""


class DuplicatePointError(InputError):
    """Two input points coincide and duplicates were asked to be rejected."""


class DegenerateInputError(InputError):
    """Input cannot be triangulated: fewer than three points, or all collinear."""


class GeometryError(MeshwrightError, ValueError):
    """A domain is invalid: open or self-intersecting loops, misplaced holes."""


class SizeError(MeshwrightError, ValueError):
    """A size specification is impossible: non-positive, non-finite, too small."""


class MeshingError(MeshwrightError, RuntimeError):
    """An algorithm could not finish: a cap on points or iterations was hit."""


class ValidationError(MeshwrightError):
    """A mesh violates an invariant checked by :meth:`meshwright.Mesh.validate`."""


class FormatError(MeshwrightError, ValueError):
    """A file cannot be read or written in the requested format."""


class MeshwrightWarning(UserWarning):
    """Base class of the warnings meshwright gives on purpose (a documented shortfall)."""


class SliverWarning(MeshwrightWarning):
    """A tetrahedral mesh keeps slivers (sliver ratio r_in / R below 0.01) after sliver
    removal; ``min_dihedral`` turns an unmet bound into a :class:`MeshingError`."""
