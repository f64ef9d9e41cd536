"""meshwright: unstructured grid generation for finite-volume and finite-element solvers.

The public API is re-exported here; everything else is private kernels over flat arrays.

>>> import meshwright as mw
>>> tri = mw.delaunay(points)                 # Bowyer (default) or Watson, exact predicates
>>> tet = mw.delaunay(points3d)               # (n, 3) points: a Tetrahedralization
>>> vor = mw.voronoi(points, clip=(0, 0, 1, 1))
>>> mesh = mw.triangulate(mw.geometry.naca("0012"), size=0.02, min_angle=30, smooth=5)
>>> quads = mw.quadrangulate("three-element", method="quadtree")   # all-quad
>>> tets = mw.tetrahedralize(mw.geometry.sphere(level=4), radius_edge=1.5)
>>> mesh = tri.to_mesh(); mesh.validate(); mesh.write("out.vtu")
"""

from meshwright import geometry, sizing
from meshwright.core.errors import (
    DegenerateInputError,
    DuplicatePointError,
    FormatError,
    GeometryError,
    InputError,
    MeshingError,
    MeshwrightError,
    MeshwrightWarning,
    SizeError,
    SliverWarning,
    ValidationError,
)
from meshwright.core.mesh import Mesh
from meshwright.core.quality import QualityReport
from meshwright.geometry import Domain
from meshwright.io import read, read_points
from meshwright._api import delaunay
from meshwright.tri import DELAUNAY_ALGORITHMS, MESH_METHODS, Triangulation, triangulate
from meshwright.tri.smoothing import smooth
from meshwright.tri.voronoi import Voronoi, voronoi

__version__ = "0.1.0"

# Imported on first use (PEP 562): a 2-D user does not load the quad and tet floors.
_LAZY = {
    "QUAD_METHODS": "meshwright.quad",
    "quadrangulate": "meshwright.quad",
    "TET_METHODS": "meshwright.tet",
    "Tetrahedralization": "meshwright.tet",
    "tetrahedralize": "meshwright.tet",
}


def __getattr__(name: str):
    if name in _LAZY:
        import importlib

        value = getattr(importlib.import_module(_LAZY[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'meshwright' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))

__all__ = [
    "__version__",
    "Mesh",
    "QualityReport",
    "Domain",
    "Triangulation",
    "Tetrahedralization",
    "Voronoi",
    "DELAUNAY_ALGORITHMS",
    "MESH_METHODS",
    "QUAD_METHODS",
    "TET_METHODS",
    "delaunay",
    "triangulate",
    "quadrangulate",
    "tetrahedralize",
    "voronoi",
    "smooth",
    "read",
    "read_points",
    "geometry",
    "sizing",
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
]
