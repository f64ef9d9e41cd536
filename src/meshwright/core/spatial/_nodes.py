"""Node creation shared by the flat-array quadtrees of :mod:`meshwright.core.spatial`.

Both trees (:mod:`~meshwright.core.spatial.cell_quadtree` and
:mod:`~meshwright.core.spatial.loose_quadtree`) keep their nodes in the same arrays: the
node count at ``qmeta[0]``, children ``qchild`` (4 cap,) int32 with child ``q`` of node
``n`` at ``4 n + q`` (-1 none), and each node's first list entry in ``qhead`` (cap,) int32.
"""

from __future__ import annotations

from numba import njit

__all__ = ["child_of"]


@njit(inline="always")
def child_of(node, q, qmeta, qchild, qhead):
    """Child ``q`` of ``node``, made empty and childless when it does not exist yet.

    The caller guarantees room for one more node (``qhead`` length, ``qchild`` four times
    it); ``qmeta[0]`` counts the nodes in use.  Returns the child's id.
    """
    child = qchild[4 * node + q]
    if child < 0:
        child = qmeta[0]
        qmeta[0] += 1
        qhead[child] = -1
        for j in range(4):
            qchild[4 * child + j] = -1
        qchild[4 * node + q] = child
    return child
