r"""Njit kernels of the constrained layer: encroachment, split points, constrained insertion.

Shared by :mod:`meshwright.tri.cdt` (constrained insertion), :mod:`meshwright.tri.ruppert`
(quality refinement and the conforming option) and :mod:`meshwright.tri._frontal_kernel`.
Segment recovery is :mod:`meshwright.tri.sloan`.  Sources: J. Ruppert, "A Delaunay
refinement algorithm for quality 2-dimensional mesh generation", J. Algorithms 18(3), 1995;
J. R. Shewchuk, "Delaunay refinement algorithms for triangular mesh generation", Comput.
Geom. 22, 2002 (concentric shells, as implemented in Triangle).

State: two bundles, each passed as one argument
-----------------------------------------------
The insertion kernel's :class:`~meshwright.tri._kernel2d.TriState` ``s`` (``pts tri nbr
circ rank cons meta work vmark``; ``cons[h] = p + 1`` on the subsegments of piece p,
``meta[M_NV]`` vertices in use) and the constrained layer's :class:`CdtState` ``c``::

    vtri   (rows,)  int32    a triangle slot incident to each vertex (kept exact)
    treg   (cap,)   int32    per slot: -1 exterior or ghost, 0 inside, r + 1 region r
    vseg   (rows,)  int32    segment piece a split vertex lies on, -1 for input vertices
    vpar   (rows,)  float64  its curve parameter (arcs and parametric curves)
    vacute (rows,)  int8     1 at input vertices where segments meet below 60 degrees
    seg    (P, 2)   int32    piece endpoints
    seg_in (P,)     int32    input segment of each piece (-1: a convex-hull piece)
    pkind  (P,)     int8     0 straight, 1 circular arc, 2 curve evaluated in Python
    pdat   (P, 5)   float64  arc centre x, y, radius; curve parameters at both endpoints
    rarea  (R + 1,) float64  max area per ``treg`` value (inf when unconstrained)

A kernel that lacks room returns ``R_ROOM`` before modifying anything; the Python side then
grows both bundles (:func:`meshwright.tri._kernel2d.grow` and :func:`grow`) and calls again.

Encroachment (exact): p encroaches subsegment ab iff ``(a - p) . (b - p) < 0``, i.e. p is
strictly inside the diametral circle.  Only vertices seen from the domain side count: the
apexes of inside triangles.

Split points: the midpoint of ab (on the true curve for arcs and curves), except that a
subsegment touching exactly one *acute* input vertex (segments meeting there below 60
degrees) is split where the distance from that vertex is a power of two, between a third
and two thirds of its length (Ruppert's concentric shells, as in Triangle), so that the
vertices on the segments of a small angle sit on common shells and stop encroaching each
other::

        apex *----x---------x-------------------x----  shells at 2^k from the apex
              \    .         .                   .
               *---x---------x-------------------x--
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from meshwright.core.borrowed import borrowed
from meshwright.core.flat import GHOST, grown_rows, index3, next3, prev3
from meshwright.core.jit import inner
from meshwright.tri._diametral import encroaches
from meshwright.tri._kernel2d import (
    BROKEN,
    DUP_BASE,
    M_LAST,
    M_NTRI,
    M_NV,
    NEED_SPACE,
    insert_vertex,
    on_constraint,
    walk,
)

__all__ = [
    "CdtState", "grow", "room_of", "key_of", "encroaches", "edge_of", "link_vertices", "set_flags",
    "param_of", "split_point", "insert_points",
    "R_DONE", "R_ROOM", "R_BROKEN", "KIND_STRAIGHT", "KIND_ARC", "KIND_CURVE",
]

# statuses of the constrained kernels (insert_points; refine_loop adds its own)
R_DONE = 0
R_ROOM = 1
R_BROKEN = 6
KIND_STRAIGHT = 0
KIND_ARC = 1
KIND_CURVE = 2


class CdtState(NamedTuple):
    """The constrained layer's arrays (layout in the module docstring), one kernel argument."""

    vtri: np.ndarray
    treg: np.ndarray
    vseg: np.ndarray
    vpar: np.ndarray
    vacute: np.ndarray
    seg: np.ndarray
    seg_in: np.ndarray
    pkind: np.ndarray
    pdat: np.ndarray
    rarea: np.ndarray


def grow(c: CdtState, rows: int, slots: int) -> CdtState:
    """Bundle with room for ``rows`` vertices and ``slots`` triangle slots (doubling; new
    entries 0), or ``c`` itself when it has it."""
    new = {}
    if rows > c.vtri.shape[0]:
        for name in ("vtri", "vseg", "vpar", "vacute"):
            new[name] = grown_rows(getattr(c, name), rows, 0)
    if slots > c.treg.shape[0]:
        new["treg"] = grown_rows(c.treg, slots, 0)
    return c._replace(**new) if new else c


@njit(inline="always")
def room_of(s, c):
    """``(rows, slots)``: vertices and triangle slots both bundles have room for.

    Arrays never change size inside a kernel call, so a kernel computes this once and
    compares counters with it per step (``rows`` is 0 when ``vmark`` is short).
    """
    rows = min(s.pts.shape[0], c.vtri.shape[0], c.vseg.shape[0], c.vpar.shape[0], c.vacute.shape[0])
    if s.vmark.shape[0] <= s.pts.shape[0]:
        rows = 0
    slots = min(min(s.tri.shape[0], s.nbr.shape[0], s.cons.shape[0]) // 3, c.treg.shape[0])
    return rows, slots


@njit(inline="always")
def key_of(rank, v):
    """Symbolic-perturbation key of vertex v (as in :mod:`meshwright.tri.bowyer`); int64."""
    return np.int64(rank[v]) if v < rank.shape[0] else np.int64(v)


@njit(cache=True)
def edge_of(a, b, tri, nbr, vtri):
    """Half-edge ``a -> b`` (its triangle on the left), or -1 when ab is not an edge.

    Rotates counter-clockwise around a from ``vtri[a]``; O(degree).
    """
    t = vtri[a]
    start = t
    while True:
        i = index3(tri, t, a)
        if tri[3 * t + next3(i)] == b:
            return 3 * t + prev3(i)
        t = nbr[3 * t + next3(i)]
        if t == start:
            return -1


@njit(cache=True)
def link_vertices(tri, ntri, vtri):
    """``vtri[v]`` = some triangle slot of vertex v, for every vertex of the first ntri slots."""
    for t in range(ntri):
        for k in range(3):
            v = tri[3 * t + k]
            if v >= 0:
                vtri[v] = t


@njit(inline="always")
def set_flags(v, tn, a, b, fl, fr, f0, s, c):
    """Region flags and vertex->triangle links of the new triangles around vertex v.

    All triangles incident to v are new.  After an ordinary insertion they get ``f0`` (the
    cavity never crosses a constrained edge, so it lies in one region); after splitting
    subsegment ``a -> b`` the ones counter-clockwise from v->b to v->a (left of a-v-b) get
    ``fl`` and the others ``fr``.  Ghosts get -1.  ``s`` TriState, ``c`` CdtState.
    """
    link_star(v, tn, a, b, fl, fr, f0, s.tri, s.nbr, c.vtri, c.treg)


@njit(inline="always")
def link_star(v, tn, a, b, fl, fr, f0, tri, nbr, vtri, treg):
    """:func:`set_flags` over arrays, for kernels that unpacked their bundles once (a field
    read per insertion costs a reference-count pair).  A star has fewer triangles than the
    slots, which caps both walks."""
    t = tn
    i = index3(tri, t, v)
    cur = f0
    if a >= 0:
        for _ in range(tri.shape[0]):
            if tri[3 * t + next3(i)] == b:
                break
            t = nbr[3 * t + next3(i)]
            i = index3(tri, t, v)
        cur = fl
    start = t
    for _ in range(tri.shape[0]):
        x = tri[3 * t + next3(i)]
        y = tri[3 * t + prev3(i)]
        treg[t] = -1 if tri[3 * t + 2] == GHOST else cur
        vtri[v] = t
        if x >= 0:
            vtri[x] = t
        if y >= 0:
            vtri[y] = t
        if a >= 0 and y == a:
            cur = fr
        t = nbr[3 * t + next3(i)]
        if t == start:
            return
        i = index3(tri, t, v)


@njit(inline="always")
def param_of(p, x, seg, pdat, vpar):
    """Curve parameter of vertex x on piece p."""
    if x == seg[p, 0]:
        return pdat[p, 3]
    if x == seg[p, 1]:
        return pdat[p, 4]
    return vpar[x]


@inner
def _shell_fraction(length):
    """Distance (power of two) from an acute apex where a subsegment is split, over its length."""
    p2 = 1.0
    while length > 3.0 * p2:
        p2 *= 2.0
    while length < 1.5 * p2:
        p2 *= 0.5
    return p2 / length


@njit(inline="always")
def split_point(p, a, b, s, c):
    """Where to split subsegment ``a -> b`` of piece p.

    Returns
    -------
    (float, float, float, bool)
        ``(x, y, t, ok)``: the point and its curve parameter; ``ok`` is False for curves
        evaluated in Python (kind 2), which need the parameters of a and b instead.
    """
    pts, seg, pdat, vpar, vacute = s.pts, c.seg, c.pdat, c.vpar, c.vacute
    ax = pts[a, 0]
    ay = pts[a, 1]
    bx = pts[b, 0]
    by = pts[b, 1]
    # Concentric shells from an acute input vertex (only one end: a subsegment between two
    # apexes is halved first).
    frac = 0.5
    from_b = False
    if vacute[a] != vacute[b]:
        dx = bx - ax
        dy = by - ay
        frac = _shell_fraction(np.sqrt(dx * dx + dy * dy))
        from_b = vacute[b] != 0
    kind = c.pkind[p]
    if kind == KIND_STRAIGHT:
        if from_b:
            return bx + frac * (ax - bx), by + frac * (ay - by), 0.0, True
        return ax + frac * (bx - ax), ay + frac * (by - ay), 0.0, True
    ta = param_of(p, a, seg, pdat, vpar)
    tb = param_of(p, b, seg, pdat, vpar)
    if kind == KIND_CURVE:
        return 0.0, 0.0, 0.5 * (ta + tb), False
    cx = pdat[p, 0]
    cy = pdat[p, 1]
    rr = pdat[p, 2]
    if frac == 0.5:
        t = 0.5 * (ta + tb)
    else:
        # The chord of length d from the apex subtends 2 asin(d / 2r).
        dx = bx - ax
        dy = by - ay
        d = frac * np.sqrt(dx * dx + dy * dy)
        dt = 2.0 * np.arcsin(min(1.0, d / (2.0 * rr)))
        t = tb - np.sign(tb - ta) * dt if from_b else ta + np.sign(tb - ta) * dt
    return cx + rr * np.cos(t), cy + rr * np.sin(t), t, True


@njit(cache=True)
def insert_points(xy, i0, out, s, c):
    """Constrained insertion of ``xy[i0:]`` (a point on a subsegment splits it).

    Parameters
    ----------
    xy : (k, 2) float64
    i0 : int
        First point to insert.
    out : (k,) int32
        ``out[i]`` receives the vertex of ``xy[i]`` (an existing one for a duplicate).
    s : TriState
        New vertices are appended at row ``meta[M_NV]``.
    c : CdtState

    Returns
    -------
    (int, int)
        ``(i, status)``: ``R_DONE`` with i = len(xy), or ``R_ROOM`` (grow both bundles) /
        ``R_BROKEN`` at point i (nothing of point i was inserted).
    """
    s, c = borrowed(s), borrowed(c)
    pts, tri, nbr, cons, meta, treg, vseg, vpar = s.pts, s.tri, s.nbr, s.cons, s.meta, c.treg, c.vseg, c.vpar
    rows, slots = room_of(s, c)
    for i in range(i0, xy.shape[0]):
        nv = meta[M_NV]
        ntri = meta[M_NTRI]
        if nv + 1 > rows or ntri + 2 > slots:
            return i, R_ROOM
        x = xy[i, 0]
        y = xy[i, 1]
        pts[nv, 0] = x
        pts[nv, 1] = y
        t0, _ = walk(s, meta[M_LAST] if meta[M_LAST] < ntri else 0, x, y, False)
        a = -1
        b = -1
        fl = -1
        fr = -1
        f0 = -1
        piece = -1
        if tri[3 * t0 + 2] != GHOST:
            f0 = treg[t0]
            h = on_constraint(t0, x, y, s)
            if h >= 0:
                a = tri[3 * t0 + next3(h % 3)]
                b = tri[3 * t0 + prev3(h % 3)]
                fl = treg[t0]
                fr = treg[nbr[h]]
                piece = cons[h] - 1
        tn = insert_vertex(nv, t0, s)
        if tn == NEED_SPACE:
            return i, R_ROOM
        if tn == BROKEN:
            return i, R_BROKEN
        if tn <= DUP_BASE:
            out[i] = DUP_BASE - tn
            continue
        vseg[nv] = piece
        c.vacute[nv] = 0
        vpar[nv] = np.nan
        if piece >= 0 and c.pkind[piece] == KIND_ARC:
            # Angle of the point, on the branch of the piece's end parameters.
            ta = param_of(piece, a, c.seg, c.pdat, vpar)
            th = np.arctan2(y - c.pdat[piece, 1], x - c.pdat[piece, 0])
            vpar[nv] = ta + (th - ta + np.pi) % (2.0 * np.pi) - np.pi
        meta[M_NV] = nv + 1
        set_flags(nv, tn, a, b, fl, fr, f0, s, c)
        out[i] = nv
    return xy.shape[0], R_DONE
