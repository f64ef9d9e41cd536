"""Search structures over flat arrays for the ``@njit`` kernels (not meshers).

:mod:`meshwright.core.spatial.loose_quadtree` is the loose quadtree of boxes that the
advancing front queries for nearby faces (Ulrich 2000); an octree for the 3-D front belongs
beside it.  Not to be confused with the quadtree *mesher* of chapter 18.5.3.
"""
