"""Start and finish of a 2-D kernel build: first triangle, slot compaction, relabelling.

Helpers of :class:`meshwright.tri.triangulation.Triangulation` around the insertion kernel
(:mod:`meshwright.tri._kernel2d`, whose module docstring gives the flat array layout):
:func:`find_start` / :func:`promote` choose three non-collinear points to start from
(:func:`init_triangle` builds them with their three ghosts), :func:`insert_batch` inserts
the rest (growing the :class:`~meshwright.tri._kernel2d.TriState` as needed),
:func:`locate_points` answers point location, and after the insertions
:func:`compact` moves finite triangles before ghosts, :func:`relabel` renumbers vertices
from insertion order to input order (the caller copies the input rows back), and
:func:`hull_loop` reads the convex hull off the ghosts.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.borrowed import borrowed
from meshwright.core.flat import GHOST, grown
from meshwright.core.jit import inner
from meshwright.core.predicates import orient2d
from meshwright.tri import watson
from meshwright.tri._kernel2d import (
    BROKEN, DUP_BASE, M_LAST, M_NTRI, M_SHORT_WORK, NEED_SPACE, I_WALK, TriState, insert_arrays, walk,
)

__all__ = [
    "find_start", "promote", "init_triangle", "make_room", "insert_batch", "locate_points", "compact", "relabel",
    "hull_loop",
]


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
def init_triangle(s, a, b, c):
    """Write the first triangle (made counter-clockwise) and its three ghosts into slots 0-3.

    Parameters
    ----------
    s : TriState
        Kernel state with room for four triangles.
    a, b, c : int
        Non-collinear vertices.
    """
    pts, tri, nbr, meta = s.pts, s.tri, s.nbr, s.meta
    if orient2d(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[c, 0], pts[c, 1]) < 0.0:
        b, c = c, b
    # 0: (a, b, c); 1: (c, b, G) across b->c; 2: (a, c, G) across c->a; 3: (b, a, G) across a->b
    tri[0], tri[1], tri[2], nbr[0], nbr[1], nbr[2] = a, b, c, 1, 2, 3
    tri[3], tri[4], tri[5], nbr[3], nbr[4], nbr[5] = c, b, GHOST, 3, 2, 0
    tri[6], tri[7], tri[8], nbr[6], nbr[7], nbr[8] = a, c, GHOST, 1, 3, 0
    tri[9], tri[10], tri[11], nbr[9], nbr[10], nbr[11] = b, a, GHOST, 2, 1, 0
    meta[M_NTRI] = 4
    meta[M_LAST] = 0
    if s.circ.shape[0] > 0:
        watson.circle(pts, tri, s.circ, np.int64(0))


@inner
def make_room(s, rows):
    """Inside a kernel: the bundle grown where ``insert_vertex`` found it short (the in-kernel
    twin of :func:`meshwright.tri._kernel2d.grow`).

    Parameters
    ----------
    s : TriState
    rows : int
        Rows of the points array the next insertion uses.

    Returns
    -------
    TriState
        A new bundle of grown copies (unchanged arrays shared).
    """
    tri, nbr, cons, circ, work, vmark = s.tri, s.nbr, s.cons, s.circ, s.work, s.vmark
    need = s.meta[M_NTRI] + 2
    if (
        3 * need > tri.shape[0]
        or 3 * need > nbr.shape[0]
        or (cons.shape[0] > 0 and 3 * need > cons.shape[0])
        or (circ.shape[0] > 0 and 4 * need > circ.shape[0])
    ):
        tri = grown(tri, 3 * need)
        nbr = grown(nbr, 3 * need)
        if cons.shape[0] > 0:
            m = cons.shape[0]
            cons = grown(cons, 3 * need)
            cons[m:] = 0
        if circ.shape[0] > 0:
            circ = grown(circ, 4 * need)
    if vmark.shape[0] <= rows:
        vmark = grown(vmark, rows + 1)
    if s.meta[M_SHORT_WORK] != 0:
        s.meta[M_SHORT_WORK] = 0
        work = np.empty(2 * work.shape[0], dtype=np.int32)
    return TriState(s.pts, tri, nbr, circ, s.rank, cons, s.meta, work, vmark)

@njit(cache=True, nogil=True)
def insert_batch(order, start, stop, vbase, s, vmap):
    """Insert ``order[start:stop]`` one by one, each walk starting where the last one ended.

    Parameters
    ----------
    order : (m,) int32 or (0,)
        Vertices (rows of ``pts``) in insertion order; empty means vertices start..stop-1.
    start, stop : int
        Positions of ``order`` to insert.
    vbase : int
        ``vmap`` is indexed by ``v - vbase``.
    s : TriState
    vmap : (m,) int32
        Output: ``vmap[v - vbase] = v`` for an inserted vertex v, else the vertex v coincides
        with.

    Returns
    -------
    tuple
        ``(bad, s)``: ``bad`` is -1, or the vertex whose insertion found an inconsistent
        cavity (the triangulation is then unchanged by it and the later vertices are not
        inserted); ``s`` the bundle, grown if it had to be.
    """
    t = s.meta[M_LAST]
    rows = s.pts.shape[0]
    # The bundle's fields are read once (and after each growth), never per point: a field
    # read is an atomic reference-count pair (see insert_arrays).
    pts, tri, nbr, circ, rank, cons, meta, work, vmark = borrowed(s)
    mode = np.int64(I_WALK)  # a variable, not a literal: insert_arrays keeps one signature
    for i in range(start, stop):
        v = order[i] if order.shape[0] > 0 else i
        st = insert_arrays(pts, tri, nbr, circ, rank, cons, meta, work, vmark, v, t, mode)
        while st == NEED_SPACE:
            s = make_room(s, rows)
            pts, tri, nbr, circ, rank, cons, meta, work, vmark = borrowed(s)
            st = insert_arrays(pts, tri, nbr, circ, rank, cons, meta, work, vmark, v, t, mode)
        if st >= 0:
            vmap[v - vbase] = v
            t = st
        elif st == BROKEN:
            return v, s
        else:
            vmap[v - vbase] = DUP_BASE - st
    return -1, s


@njit(cache=True, nogil=True)
def locate_points(s, xy):
    """Finite triangle containing each query point (in its closure), -1 outside the hull.

    Parameters
    ----------
    s : TriState
        Its walk state ``meta[M_RNG]`` advances (pass a bundle with a copied ``meta`` to
        leave it alone).
    xy : (m, 2) float64

    Returns
    -------
    (m,) int32
    """
    m = xy.shape[0]
    out = np.empty(m, dtype=np.int32)
    t = s.meta[M_LAST]
    for i in range(m):
        t, _ = walk(s, t, xy[i, 0], xy[i, 1], False)
        out[i] = -1 if s.tri[3 * t + 2] == GHOST else t
    return out


@inner
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
def compact(s):
    """Reorder slots so finite triangles come first and ghosts last; return their count.

    At most h (hull size) slot exchanges, each fixing the pointers of the neighbours.

    Parameters
    ----------
    s : TriState
        Modified in place, ``meta[M_LAST]`` reset to 0.

    Returns
    -------
    int
        ``nt``: triangles ``[0, nt)`` are finite, ``[nt, meta[M_NTRI])`` are ghosts.
    """
    tri, meta = s.tri, s.meta
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
        _swap_slots(i, j, tri, s.nbr, s.circ, back)
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
