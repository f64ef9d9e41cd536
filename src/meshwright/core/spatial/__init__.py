"""Search structures over flat arrays for the ``@njit`` kernels (not meshers).

:mod:`meshwright.core.spatial.cell_quadtree` is the quadtree of boxes split over the cells
they meet, which the advancing front queries for nearby faces and nodes (a query passes one
cell per level down to the cell holding its box); :mod:`meshwright.core.spatial.loose_quadtree`
is the loose quadtree of boxes (Ulrich 2000) under the local feature size.  An octree for the
3-D front belongs beside them.  Not to be confused with the quadtree *mesher* of chapter 18.5.3.
"""
