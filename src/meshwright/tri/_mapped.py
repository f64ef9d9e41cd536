r"""Region transfer between two constrained triangulations of the same vertices and pieces.

Used by the frontal Delaunay method under a uniformly stretched background grid
(:mod:`meshwright.tri.frontal_delaunay`): the boundary vertices are mapped by the chapter's
transformation ``T`` (section 18.2: elements of size delta, equilateral after ``T``), the
constrained Delaunay triangulation is rebuilt there (Delaunay is not affine invariant, so
the plane's triangulation cannot simply be mapped), and its triangles take the regions of
the plane's: a constrained edge ``a -> b`` bounds the same region on its left in both (the
pieces are the same), and the regions are then flooded across free edges, as the
exterior removal of chapter 18.1.2 does.

Arrays (flat, as :mod:`meshwright.tri._kernel2d`): ``tri``/``nbr``/``cons`` (3 cap,) int32
and ``vtri`` (rows,) int32 of the plane's triangulation (``old_*``, its regions ``old_treg``
(cap,) int32) and of the mapped one (``tri``, ``nbr``, ``cons``, ``ntri`` slots in use);
``treg`` (cap,) int32 receives the regions (-1 for ghosts and the exterior).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.flat import GHOST, next3, prev3
from meshwright.tri._encroach import edge_of

__all__ = ["transfer_regions"]


@njit(cache=True)
def transfer_regions(tri, nbr, cons, ntri, treg, old_tri, old_nbr, old_vtri, old_treg):
    """Regions of the mapped triangulation's triangles from the plane's (module docstring).

    Returns
    -------
    int
        -1 on success; otherwise the first finite triangle slot no constrained edge reaches,
        or whose constrained edge the plane's triangulation lacks (treg then incomplete).
    """
    stack = np.empty(ntri + 1, dtype=np.int32)
    top = 0
    for t in range(ntri):
        treg[t] = -2
    for t in range(ntri):
        if tri[3 * t + 2] == GHOST:
            treg[t] = -1
            continue
        for k in range(3):
            if cons[3 * t + k] == 0:
                continue
            h = edge_of(tri[3 * t + next3(k)], tri[3 * t + prev3(k)], old_tri, old_nbr, old_vtri)
            if h < 0:
                return t
            if treg[t] == -2:
                treg[t] = old_treg[h // 3]
                stack[top] = t
                top += 1
    while top > 0:
        top -= 1
        t = stack[top]
        for k in range(3):
            n = nbr[3 * t + k]
            if cons[3 * t + k] == 0 and treg[n] == -2:
                treg[n] = treg[t]
                stack[top] = n
                top += 1
    for t in range(ntri):
        if treg[t] == -2:
            return t
    return -1
