"""tri layer: 2-D triangle methods (see docs/ARCHITECTURE.md).

``DELAUNAY_ALGORITHMS`` maps the name of each Delaunay insertion algorithm (chapter 18.1.1
Watson, 18.1.2 Bowyer) to its kernel plug-in; the CLI takes its choices from it.
"""

from meshwright.tri.triangulation import DELAUNAY_ALGORITHMS, Triangulation, delaunay

__all__ = ["DELAUNAY_ALGORITHMS", "Triangulation", "delaunay"]
