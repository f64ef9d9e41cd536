"""tet layer: 3-D tetrahedral methods (see docs/ARCHITECTURE.md).

``TET_ALGORITHMS`` maps the name of each 3-D Delaunay insertion algorithm (chapter 18.1.1
Watson, 18.1.2 Bowyer; the same names as ``meshwright.DELAUNAY_ALGORITHMS``) to its kernel
plug-in; :func:`delaunay3d` builds a :class:`Tetrahedralization` (``meshwright.delaunay``
dispatches (n, 3) points to it); :func:`remove_slivers` improves a tetra mesh (18.1.1);
:func:`tetrahedralize` meshes the solid a closed surface bounds (18.4.1), its methods in
``TET_METHODS``; :func:`smooth_tets` is the spring-analogy smoothing in 3-D.
"""

from meshwright.tet.mesher import TET_METHODS, tetrahedralize
from meshwright.tet.slivers import SliverReport, remove_slivers
from meshwright.tet.smoothing import smooth_tets
from meshwright.tet.tetrahedralization import SUPERSTRUCTURES, TET_ALGORITHMS, Tetrahedralization, delaunay3d

__all__ = [
    "TET_ALGORITHMS",
    "TET_METHODS",
    "SUPERSTRUCTURES",
    "Tetrahedralization",
    "delaunay3d",
    "tetrahedralize",
    "remove_slivers",
    "SliverReport",
    "smooth_tets",
]
