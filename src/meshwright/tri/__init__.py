"""tri layer: 2-D triangle methods (see docs/ARCHITECTURE.md).

``DELAUNAY_ALGORITHMS`` maps the name of each Delaunay insertion algorithm (chapter 18.1.1
Watson, 18.1.2 Bowyer) to its kernel plug-in; ``MESH_METHODS`` maps each point-placement
method of :func:`triangulate` to its implementation and declares what it honours (largest
``min_angle``, progress reports, options such as Weatherill's ``alpha``), which
:func:`triangulate` checks at its door.  The CLI takes its choices and defaults from both.
"""

from meshwright.tri.cdt import ConstrainedTriangulation, cdt_build
from meshwright.tri.mesher import MESH_METHODS, triangulate
from meshwright.tri.triangulation import DELAUNAY_ALGORITHMS, Triangulation, delaunay

__all__ = [
    "DELAUNAY_ALGORITHMS",
    "MESH_METHODS",
    "Triangulation",
    "ConstrainedTriangulation",
    "delaunay",
    "cdt_build",
    "triangulate",
]
