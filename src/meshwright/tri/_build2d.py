"""Start and finish of a 2-D kernel build: first triangle, slot compaction, relabelling.

Helpers of :class:`meshwright.tri.triangulation.Triangulation` around the insertion kernel
(:mod:`meshwright.tri._kernel2d`, whose module docstring gives the flat array layout):
:func:`find_start` / :func:`promote` choose three non-collinear points to start from
(:func:`init_triangle` builds them with their three ghosts), and after the insertions
:func:`compact` moves finite triangles before ghosts, :func:`relabel` and
:func:`scatter_rows` renumber vertices from insertion order to input order, and
:func:`hull_loop` reads the convex hull off the ghosts.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.flat import GHOST
from meshwright.core.predicates import orient2d
from meshwright.tri import watson
from meshwright.tri._kernel2d import M_LAST, M_NTRI

__all__ = ["find_start", "promote", "init_triangle", "compact", "relabel", "scatter_rows", "hull_loop"]


@njit(cache=True)
def find_start(pts, order):
    """Positions in ``order`` of the first non-degenerate triangle ``order[0], order[i], order[j]``.

    Parameters
    ----------
    pts : (rows, 2) float64
    order : (m,) int32 or int64

    Returns
    -------
    tuple of int
        ``(i, j)``: i is the first position whose point differs from ``order[0]``'s, j the
        first after it not collinear with both; -1 where none exists.
    """
    a = order[0]
    ax = pts[a, 0]
    ay = pts[a, 1]
    m = order.shape[0]
    i = 1
    while i < m and pts[order[i], 0] == ax and pts[order[i], 1] == ay:
        i += 1
    if i == m:
        return -1, -1
    b = order[i]
    for j in range(i + 1, m):
        c = order[j]
        if orient2d(ax, ay, pts[b, 0], pts[b, 1], pts[c, 0], pts[c, 1]) != 0.0:
            return i, j
    return i, -1


@njit(cache=True)
def promote(order, src, dst):
    """Move ``order[src]`` to position ``dst <= src``, shifting the entries between up by one."""
    x = order[src]
    for i in range(src, dst, -1):
        order[i] = order[i - 1]
    order[dst] = x


@njit(cache=True)
def init_triangle(pts, a, b, c, tri, nbr, circ, meta):
    """Write the first triangle (made counter-clockwise) and its three ghosts into slots 0-3.

    Parameters
    ----------
    pts : (rows, 2) float64
    a, b, c : int
        Non-collinear vertices.
    tri, nbr, circ, meta
        Kernel state with room for four triangles.
    """
    if orient2d(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[c, 0], pts[c, 1]) < 0.0:
        b, c = c, b
    # 0: (a, b, c); 1: (c, b, G) across b->c; 2: (a, c, G) across c->a; 3: (b, a, G) across a->b
    tri[0], tri[1], tri[2], nbr[0], nbr[1], nbr[2] = a, b, c, 1, 2, 3
    tri[3], tri[4], tri[5], nbr[3], nbr[4], nbr[5] = c, b, GHOST, 3, 2, 0
    tri[6], tri[7], tri[8], nbr[6], nbr[7], nbr[8] = a, c, GHOST, 1, 3, 0
    tri[9], tri[10], tri[11], nbr[9], nbr[10], nbr[11] = b, a, GHOST, 2, 1, 0
    meta[M_NTRI] = 4
    meta[M_LAST] = 0
    if circ.shape[0] > 0:
        watson.circle(pts, tri, circ, 0)


@njit(cache=True)
def _swap_slots(i, j, tri, nbr, circ, back):
    """Exchange triangles i and j, redirecting every pointer to them."""
    for k in range(3):
        back[k] = -1
        back[3 + k] = -1
        n = nbr[3 * i + k]
        if n != i and n != j:
            back[k] = 3 * n + (0 if nbr[3 * n] == i else (1 if nbr[3 * n + 1] == i else 2))
        n = nbr[3 * j + k]
        if n != i and n != j:
            back[3 + k] = 3 * n + (0 if nbr[3 * n] == j else (1 if nbr[3 * n + 1] == j else 2))
    for k in range(3):
        x = tri[3 * i + k]
        tri[3 * i + k] = tri[3 * j + k]
        tri[3 * j + k] = x
        x = nbr[3 * i + k]
        nbr[3 * i + k] = nbr[3 * j + k]
        nbr[3 * j + k] = x
    for k in range(3):
        if nbr[3 * i + k] == i:
            nbr[3 * i + k] = j
        if nbr[3 * j + k] == j:
            nbr[3 * j + k] = i
        if back[k] >= 0:
            nbr[back[k]] = j
        if back[3 + k] >= 0:
            nbr[back[3 + k]] = i
    if circ.shape[0] > 0:
        for k in range(4):
            y = circ[4 * i + k]
            circ[4 * i + k] = circ[4 * j + k]
            circ[4 * j + k] = y


@njit(cache=True)
def compact(tri, nbr, circ, meta):
    """Reorder slots so finite triangles come first and ghosts last; return their count.

    At most h (hull size) slot exchanges, each fixing the pointers of the neighbours.

    Parameters
    ----------
    tri, nbr, circ, meta
        Kernel state; modified in place, ``meta[M_LAST]`` reset to 0.

    Returns
    -------
    int
        ``nt``: triangles ``[0, nt)`` are finite, ``[nt, meta[M_NTRI])`` are ghosts.
    """
    ntri = meta[M_NTRI]
    nt = 0
    for t in range(ntri):
        if tri[3 * t + 2] != GHOST:
            nt += 1
    back = np.empty(6, dtype=np.int64)
    i = 0
    j = ntri - 1
    while True:
        while i < nt and tri[3 * i + 2] != GHOST:
            i += 1
        while j >= nt and tri[3 * j + 2] == GHOST:
            j -= 1
        if i >= nt or j < nt:
            break
        _swap_slots(i, j, tri, nbr, circ, back)
    meta[M_LAST] = 0
    return nt


@njit(cache=True)
def relabel(tri, ntri, newid, base):
    """Replace every vertex id ``v >= base`` in the first ``ntri`` triangles by ``newid[v - base]``.

    Parameters
    ----------
    tri : (3 cap,) int32
    ntri : int
    newid : (m,) int32
    base : int
        Ids below ``base`` (and GHOST) are kept.
    """
    for e in range(3 * ntri):
        v = tri[e]
        if v >= base:
            tri[e] = newid[v - base]


@njit(cache=True)
def scatter_rows(a, dest):
    """Move row i of ``a`` to row ``dest[i]`` in place, following the permutation's cycles.

    Parameters
    ----------
    a : (m, 2) float64
    dest : (m,) int32
        A permutation of ``range(m)``.
    """
    m = dest.shape[0]
    done = np.zeros(m, dtype=np.bool_)
    for i in range(m):
        if done[i]:
            continue
        x = a[i, 0]
        y = a[i, 1]
        j = dest[i]
        while j != i:
            xj = a[j, 0]
            yj = a[j, 1]
            a[j, 0] = x
            a[j, 1] = y
            done[j] = True
            x = xj
            y = yj
            j = dest[j]
        a[i, 0] = x
        a[i, 1] = y
        done[i] = True


@njit(cache=True)
def hull_loop(tri, nbr, g, h):
    """Counter-clockwise convex-hull vertex loop read off the ghost triangles.

    Parameters
    ----------
    tri, nbr : (3 cap,) int32
    g : int
        Any ghost triangle.
    h : int
        Number of ghost triangles (= hull vertices).

    Returns
    -------
    (h,) int32
    """
    out = np.empty(h, dtype=np.int32)
    for i in range(h):
        # Ghost (a, b, GHOST) holds hull edge b -> a; the next one along the hull is across G->a.
        out[i] = tri[3 * g + 1]
        g = nbr[3 * g + 1]
    return out
