"""quad layer: 2-D quadrilateral methods of section 18.5 (see docs/ARCHITECTURE.md).

``QUAD_METHODS`` maps each method of :func:`quadrangulate` to its implementation and
declares what it honours (size needed, smoothing, progress, interior segments / points /
regions), which :func:`quadrangulate` checks at its door; the CLI (``meshwright quad``)
takes its choices from it.
"""

from meshwright.quad.mesher import QUAD_METHODS, QuadFill, QuadJob, QuadMethod, quadrangulate

__all__ = ["QUAD_METHODS", "QuadMethod", "QuadJob", "QuadFill", "quadrangulate"]
