"""tet layer: 3-D tetrahedral methods (see docs/ARCHITECTURE.md).

``TET_ALGORITHMS`` maps the name of each 3-D Delaunay insertion algorithm (chapter 18.1.1
Watson, 18.1.2 Bowyer; the same names as ``meshwright.DELAUNAY_ALGORITHMS``) to its kernel
plug-in; :func:`delaunay3d` builds a :class:`Tetrahedralization` (``meshwright.delaunay``
dispatches (n, 3) points to it); :func:`remove_slivers` improves a tetra mesh (18.1.1).
"""

from meshwright.tet.slivers import SliverReport, remove_slivers
from meshwright.tet.tetrahedralization import SUPERSTRUCTURES, TET_ALGORITHMS, Tetrahedralization, delaunay3d

__all__ = ["TET_ALGORITHMS", "SUPERSTRUCTURES", "Tetrahedralization", "delaunay3d", "remove_slivers", "SliverReport"]
