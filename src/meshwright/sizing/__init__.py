"""How fine: size fields (constant, callable, graded from boundary spacing, background grids).

Fields take (n, 2) points, or (n, 3) for the 3-D mesher (``as_size_field(size, dim=3)``);
a :class:`BackgroundGrid` is a triangulation (2-D, with stretching) or a tetrahedralization
(3-D) with nodal spacing.  Below :mod:`meshwright.geometry` in the layer order; depends only
on ``core``.
"""

from meshwright.sizing.background import BackgroundGrid
from meshwright.sizing.boundary import boundary_size, gradation, point_distribution
from meshwright.sizing.field import SizeField, as_size_field, minimum

__all__ = [
    "SizeField",
    "BackgroundGrid",
    "as_size_field",
    "minimum",
    "point_distribution",
    "gradation",
    "boundary_size",
]
