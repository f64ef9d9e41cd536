r"""Guaranteed-quality Delaunay refinement (Ruppert / Chew with off-centres) of a CDT.

Sources: J. Ruppert, "A Delaunay refinement algorithm for quality 2-dimensional mesh
generation", J. Algorithms 18(3):548-585, 1995; J. R. Shewchuk, "Delaunay refinement
algorithms for triangular mesh generation", Comput. Geom. 22:21-74, 2002 (concentric
shells and the rule that leaves triangles at small input angles alone, both as implemented
in Triangle); A. Üngör, "Off-centers: a new type of Steiner points for computing
size-optimal quality-guaranteed Delaunay triangulations", LATIN 2004 (with Triangle's
constant 0.475 for the off-centre distance).

Algorithm (:func:`refine_loop`, one Numba loop over flat arrays)
--------------------------------------------------------------
1. Queue every encroached subsegment (its diametral circle holds the apex of an inside
   triangle, exact test) and every bad inside triangle: smallest angle below ``min_angle``,
   or area above ``max_area`` / its region's maximum / the area of the equilateral triangle
   of side ``h`` (the size field at its circumcentre).
2. While subsegments are queued, split them: at the midpoint (on the true curve), or at a
   power-of-two distance from an acute input vertex (concentric shells)::

        a *========m========* b          a *====*====*====* b
          \       /|\       /    split       \   /|\  |  /|   new triangles around m;
           \ t   / | \  n  /   ------>        \ / | \ | / |   the halves a-m, m-b keep
            \   /  |  \   /                   ...           the segment's id

3. Else pop the worst bad triangle (a binary heap on the smallest angle, bucketed, FIFO
   inside a bucket; stale entries are recognised by their vertices) and compute its
   off-centre (circumcentre when nearer).  Walk there; a subsegment hiding the point from the
   triangle is split instead; a point in the diametral circle of a subsegment on its cavity
   boundary is rejected and those subsegments are split instead (the triangle is requeued).
   Otherwise insert it: the cavity never crosses a constrained edge.
4. Every new triangle is examined as in 1.  Triangles whose shortest edge joins two segments
   meeting at a small input angle, at equal distance from the apex, are left alone.

Priority queue: a binary min-heap (``hk`` int64 keys = quality bucket << 40 | sequence,
``hp`` (t, a, b, c) payloads).  Sizes from a Python callable are evaluated in batches: new
triangles wait in ``pend`` with their circumcentres, and the loop returns when nothing else
is left.  Curves that are not arcs are evaluated in Python one split at a time.

Termination: guaranteed by Ruppert's and Shewchuk's analyses for ``min_angle`` up to about
20.7 degrees and practical (as in Triangle) up to about 33.8 degrees; ``max_points`` and
``max_steps`` caps raise :class:`~meshwright.core.errors.MeshingError` naming the cap and the
place where the loop was working.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.errors import GeometryError, InputError, MeshingError
from meshwright.core.flat import GHOST
from meshwright.core.predicates import incircle_sos
from meshwright.sizing.field import as_size_field
from meshwright.tri._encroach import (
    MODE_CONFORM,
    MODE_RUPPERT,
    P_AMAX,
    P_CT,
    P_CX,
    P_CY,
    P_LEN,
    P_OFF,
    P_SIN2,
    P_TA,
    P_TB,
    P_WX,
    P_WY,
    R_BROKEN,
    R_CAP_POINTS,
    R_CAP_STEPS,
    R_CURVE,
    R_DONE,
    R_OFF_CURVE,
    R_ROOM,
    R_SIZES,
    S_CREADY,
    S_GROW_WORK,
    S_HN,
    S_LEN,
    S_MAXPTS,
    S_MAXSTEPS,
    S_MODE,
    S_NV,
    S_PN,
    S_QN,
    S_REQ_A,
    S_REQ_B,
    S_REQ_P,
    S_SIZED,
    S_SKIPPED,
    S_STEPS,
    edge_of,
    heap_pop,
    heap_push,
    push_seg,
    encroaches,
    key_of,
    on_constraint,
    param_of,
    set_flags,
    split_point,
    walk_blocked,
)
from meshwright.tri._kernel2d import BROKEN, DUP_BASE, M_NTRI, NEED_SPACE, cavity, fan, split_edge

__all__ = ["refine", "conform", "split_subsegment"]

_EQUILATERAL = np.sqrt(3.0) / 4.0  # area of the equilateral triangle of side 1


@njit(inline="always")
def _next(k):
    return 0 if k == 2 else k + 1


@njit(inline="always")
def _prev(k):
    return 2 if k == 0 else k - 1


@njit(inline="always")
def _index(tri, t, v):
    return 0 if tri[3 * t] == v else (1 if tri[3 * t + 1] == v else 2)


# ------------------------------------------------------------------ triangle tests
@njit(cache=True)
def vertex_piece(u, tri, nbr, cons, vtri, vseg):
    """A segment piece through vertex u (its own for split vertices), or -1."""
    if vseg[u] >= 0:
        return vseg[u]
    t = vtri[u]
    start = t
    while True:
        i = _index(tri, t, u)
        for k in (_next(i), _prev(i)):
            if cons[3 * t + k] != 0:
                return cons[3 * t + k] - 1
        t = nbr[3 * t + _next(i)]
        if t == start:
            return -1


@njit(cache=True)
def _small_angle_apex(u, w, pts, tri, nbr, cons, vtri, vseg, seg):
    """Shewchuk's rule: u and w on two segments meeting at a vertex, equally far from it."""
    pu = vertex_piece(u, tri, nbr, cons, vtri, vseg)
    pw = vertex_piece(w, tri, nbr, cons, vtri, vseg)
    if pu < 0 or pw < 0 or pu == pw:
        return False
    j = -1
    for x in (seg[pu, 0], seg[pu, 1]):
        if x == seg[pw, 0] or x == seg[pw, 1]:
            j = x
    if j < 0:
        return False
    du = (pts[u, 0] - pts[j, 0]) ** 2 + (pts[u, 1] - pts[j, 1]) ** 2
    dw = (pts[w, 0] - pts[j, 0]) ** 2 + (pts[w, 1] - pts[j, 1]) ** 2
    return 0.999 * dw < du < 1.001 * dw


@njit(cache=True)
def quality(t, pts, tri):
    """``(sin^2 of the smallest angle, area, u, w)`` of triangle t, uw its shortest edge.

    The smallest angle is opposite the shortest edge; its sine squared is (2 area)^2 over
    the product of the other two squared lengths.
    """
    a = tri[3 * t]
    b = tri[3 * t + 1]
    c = tri[3 * t + 2]
    ax = pts[a, 0]
    ay = pts[a, 1]
    bx = pts[b, 0]
    by = pts[b, 1]
    cx = pts[c, 0]
    cy = pts[c, 1]
    l0 = (cx - bx) ** 2 + (cy - by) ** 2
    l1 = (ax - cx) ** 2 + (ay - cy) ** 2
    l2 = (bx - ax) ** 2 + (by - ay) ** 2
    cross = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    if l0 <= l1 and l0 <= l2:
        return cross * cross / (l1 * l2), 0.5 * cross, b, c
    if l1 <= l2:
        return cross * cross / (l0 * l2), 0.5 * cross, c, a
    return cross * cross / (l0 * l1), 0.5 * cross, a, b


@njit(inline="always")
def _circumcentre(ax, ay, bx, by, cx, cy):
    """Circumcentre of a counter-clockwise triangle (floating point, relative to a)."""
    ux = bx - ax
    uy = by - ay
    wx = cx - ax
    wy = cy - ay
    uu = ux * ux + uy * uy
    ww = wx * wx + wy * wy
    d = 0.5 / (ux * wy - uy * wx)
    return ax + (wy * uu - uy * ww) * d, ay + (ux * ww - wx * uu) * d


@njit(cache=True)
def steiner_point(t, pts, tri, off):
    """Off-centre of triangle t (Üngör 2004, with Triangle's constant), else its circumcentre.

    On the bisector of the shortest edge pq, at ``off * |pq|`` from its midpoint towards the
    third vertex: the apex of the isosceles triangle on pq whose apex angle is the bound.
    Used when it is nearer to pq than the circumcentre.
    """
    a = tri[3 * t]
    b = tri[3 * t + 1]
    c = tri[3 * t + 2]
    ax = pts[a, 0]
    ay = pts[a, 1]
    bx = pts[b, 0]
    by = pts[b, 1]
    cx = pts[c, 0]
    cy = pts[c, 1]
    ox, oy = _circumcentre(ax, ay, bx, by, cx, cy)
    if off <= 0.0:
        return ox, oy
    l0 = (cx - bx) ** 2 + (cy - by) ** 2
    l1 = (ax - cx) ** 2 + (ay - cy) ** 2
    l2 = (bx - ax) ** 2 + (by - ay) ** 2
    if l0 <= l1 and l0 <= l2:
        px, py, qx, qy = bx, by, cx, cy
    elif l1 <= l2:
        px, py, qx, qy = cx, cy, ax, ay
    else:
        px, py, qx, qy = ax, ay, bx, by
    # Left normal of p -> q points into the counter-clockwise triangle.
    fx = 0.5 * (px + qx) - off * (qy - py)
    fy = 0.5 * (py + qy) + off * (qx - px)
    if (fx - px) ** 2 + (fy - py) ** 2 < (ox - px) ** 2 + (oy - py) ** 2:
        return fx, fy
    return ox, oy


@njit(cache=True)
def examine(t, pts, tri, nbr, cons, rank, vtri, treg, vseg, seg, rarea, hk, hp, sq, pend, pcen, st, prm):
    """Queue what is wrong with finite triangle t: encroached subsegments, bad quality.

    Ruppert mode (t inside): each constrained edge of t encroached by its apex in t is
    pushed; t goes to the heap when its minimum angle is below the bound or its area above
    the (regional) maximum, else to the size queue when the size field is evaluated in
    Python.  Conforming mode: constrained edges of t that are not locally Delaunay are pushed.
    """
    b3 = 3 * t
    a = tri[b3]
    b = tri[b3 + 1]
    c = tri[b3 + 2]
    ax = pts[a, 0]
    ay = pts[a, 1]
    bx = pts[b, 0]
    by = pts[b, 1]
    cx = pts[c, 0]
    cy = pts[c, 1]
    if st[S_MODE] == MODE_CONFORM:
        for k in range(3):
            n = nbr[b3 + k]
            if cons[b3 + k] != 0 and tri[3 * n + 2] != GHOST:
                d = tri[3 * n + (0 if nbr[3 * n] == t else (1 if nbr[3 * n + 1] == t else 2))]
                if incircle_sos(
                    ax, ay, bx, by, cx, cy, pts[d, 0], pts[d, 1],
                    key_of(rank, a), key_of(rank, b), key_of(rank, c), key_of(rank, d),
                ) > 0:
                    push_seg(tri[b3 + _next(k)], tri[b3 + _prev(k)], sq, st)
        return
    for k in range(3):
        if cons[b3 + k] != 0:
            x = tri[b3 + k]
            u = tri[b3 + _next(k)]
            w = tri[b3 + _prev(k)]
            if encroaches(pts[u, 0], pts[u, 1], pts[w, 0], pts[w, 1], pts[x, 0], pts[x, 1]):
                push_seg(u, w, sq, st)
    sin2, area, su, sw = quality(t, pts, tri)
    bad_area = area > prm[P_AMAX] or area > rarea[treg[t]]
    bad_angle = sin2 < prm[P_SIN2]
    if bad_angle and not bad_area and _small_angle_apex(su, sw, pts, tri, nbr, cons, vtri, vseg, seg):
        st[S_SKIPPED] += 1
        bad_angle = False
    if bad_angle or bad_area:
        heap_push(sin2, t, tri, hk, hp, st)
    elif st[S_SIZED] != 0:
        i = st[S_PN]
        st[S_PN] = i + 1
        pend[4 * i] = t
        pend[4 * i + 1] = a
        pend[4 * i + 2] = b
        pend[4 * i + 3] = c
        ox, oy = _circumcentre(ax, ay, bx, by, cx, cy)
        pcen[2 * i] = ox
        pcen[2 * i + 1] = oy


@njit(cache=True)
def _examine_star(v, tn, pts, tri, nbr, cons, rank, vtri, treg, vseg, seg, rarea, hk, hp, sq, pend, pcen, st, prm):
    """:func:`examine` every new triangle around v that takes part (inside; all in conforming)."""
    conform = st[S_MODE] == MODE_CONFORM
    t = tn
    while True:
        i = _index(tri, t, v)
        if tri[3 * t + 2] != GHOST and (conform or treg[t] >= 0):
            examine(t, pts, tri, nbr, cons, rank, vtri, treg, vseg, seg, rarea, hk, hp, sq, pend, pcen, st, prm)
        t = nbr[3 * t + _next(i)]
        if t == tn:
            return


@njit(cache=True)
def seed_queues(pts, tri, nbr, cons, rank, meta, vtri, treg, vseg, seg, rarea, hk, hp, sq, pend, pcen, st, prm):
    """Examine every taking-part triangle once (the start of a refinement run)."""
    conform = st[S_MODE] == MODE_CONFORM
    for t in range(meta[M_NTRI]):
        if tri[3 * t + 2] != GHOST and (conform or treg[t] >= 0):
            examine(t, pts, tri, nbr, cons, rank, vtri, treg, vseg, seg, rarea, hk, hp, sq, pend, pcen, st, prm)


@njit(cache=True)
def apply_sizes(h, pts, tri, hk, hp, pend, st):
    """Heap the waiting triangles larger than the equilateral triangle of side h.

    ``h`` (pn,) float64 is the size field at their circumcentres ``pcen``; triangles that
    changed since they were queued are dropped (their successors were examined).
    """
    for i in range(st[S_PN]):
        t = pend[4 * i]
        if tri[3 * t] == pend[4 * i + 1] and tri[3 * t + 1] == pend[4 * i + 2] and tri[3 * t + 2] == pend[4 * i + 3]:
            sin2, area, _, _ = quality(t, pts, tri)
            if area > _EQUILATERAL * h[i] * h[i]:
                heap_push(sin2, t, tri, hk, hp, st)
    st[S_PN] = 0


@njit(inline="always")
def _short(nv, ntri, pts, tri, nbr, cons, vmark, work, vtri, treg, vseg, vpar, vacute, hk, sq, pend, st):
    """Whether some array lacks room for one more step (one insertion and its queue pushes)."""
    wcap = work.shape[0] // 5
    need = 3 * (ntri + 2)
    return (
        need > tri.shape[0]
        or need > nbr.shape[0]
        or need > cons.shape[0]
        or ntri + 2 > treg.shape[0]
        or nv + 1 > pts.shape[0]
        or vmark.shape[0] <= pts.shape[0]
        or nv + 1 > min(vtri.shape[0], vseg.shape[0], vpar.shape[0], vacute.shape[0])
        or st[S_HN] + wcap + 1 > hk.shape[0]
        or 2 * (st[S_QN] + 3 * wcap + 3) > sq.shape[0]
        or 4 * (st[S_PN] + wcap + 1) > pend.shape[0]
    )


@njit(cache=True)
def refine_loop(
    pts, tri, nbr, cons, circ, rank, meta, work, vmark, vtri, treg, vseg, vpar, vacute,
    seg, pkind, pdat, rarea, hk, hp, sq, pend, pcen, st, prm,
):
    """Run Delaunay refinement (or conforming splits) until done or Python is needed.

    Parameters are the state arrays of the module docstring.  Every return leaves the state
    consistent, so calling again continues.

    Returns
    -------
    int
        ``R_DONE``; ``R_ROOM`` (grow the arrays; ``st[S_GROW_WORK]`` asks for the cavity
        scratch); ``R_SIZES`` (evaluate the size field at ``pcen``, call
        :func:`apply_sizes`); ``R_CURVE`` (put the split point of subsegment
        ``st[S_REQ_A], st[S_REQ_B]`` of piece ``st[S_REQ_P]``, between parameters
        ``prm[P_TA], prm[P_TB]``, in ``prm[P_CX:P_CT + 1]`` and set ``st[S_CREADY]``);
        ``R_CAP_POINTS`` / ``R_CAP_STEPS`` (a cap was hit near ``prm[P_WX], prm[P_WY]``);
        ``R_BROKEN`` (inconsistent cavity); ``R_OFF_CURVE`` (the split point of the requested
        subsegment lies neither on it nor inside its two triangles).
    """
    popped = np.empty(4, dtype=np.int32)
    while True:
        nv = st[S_NV]
        if _short(nv, meta[M_NTRI], pts, tri, nbr, cons, vmark, work, vtri, treg, vseg, vpar, vacute, hk, sq, pend, st):
            return R_ROOM
        if st[S_QN] > 0:
            q = st[S_QN] - 1
            a = sq[2 * q]
            b = sq[2 * q + 1]
            h = edge_of(a, b, tri, nbr, vtri)
            if h < 0 or cons[h] == 0:
                st[S_QN] = q  # split or freed meanwhile
                continue
            p = cons[h] - 1
            x, y, tpar, ok = split_point(p, a, b, pts, seg, pkind, pdat, vpar, vacute)
            if not ok:
                if st[S_CREADY] == 0 or st[S_REQ_A] != a or st[S_REQ_B] != b:
                    st[S_REQ_A] = a
                    st[S_REQ_B] = b
                    st[S_REQ_P] = p
                    prm[P_TA] = param_of(p, a, seg, pdat, vpar)
                    prm[P_TB] = param_of(p, b, seg, pdat, vpar)
                    return R_CURVE
                x = prm[P_CX]
                y = prm[P_CY]
                tpar = prm[P_CT]
            prm[P_WX] = x
            prm[P_WY] = y
            st[S_STEPS] += 1
            if st[S_STEPS] > st[S_MAXSTEPS]:
                return R_CAP_STEPS
            if nv >= st[S_MAXPTS]:
                return R_CAP_POINTS
            pts[nv, 0] = x
            pts[nv, 1] = y
            fl = treg[h // 3]
            fr = treg[nbr[h]]
            tn = split_edge(nv, h, pts, tri, nbr, cons, circ, rank, meta, work, vmark)
            if tn == NEED_SPACE:
                st[S_STEPS] -= 1
                st[S_GROW_WORK] = 1
                return R_ROOM
            if tn < 0:
                st[S_REQ_A] = a
                st[S_REQ_B] = b
                st[S_REQ_P] = p
                return R_OFF_CURVE
            st[S_CREADY] = 0
            st[S_QN] = q
            vseg[nv] = p
            vpar[nv] = tpar
            vacute[nv] = 0
            st[S_NV] = nv + 1
            set_flags(nv, tn, a, b, fl, fr, 0, tri, nbr, vtri, treg)
            _examine_star(nv, tn, pts, tri, nbr, cons, rank, vtri, treg, vseg, seg, rarea, hk, hp, sq, pend, pcen, st, prm)
            continue
        if st[S_HN] > 0:
            heap_pop(hk, hp, st, popped)
            t = popped[0]
            if (
                t >= meta[M_NTRI]
                or tri[3 * t] != popped[1]
                or tri[3 * t + 1] != popped[2]
                or tri[3 * t + 2] != popped[3]
                or treg[t] < 0
            ):
                continue
            st[S_STEPS] += 1
            x, y = steiner_point(t, pts, tri, prm[P_OFF])
            prm[P_WX] = x
            prm[P_WY] = y
            if st[S_STEPS] > st[S_MAXSTEPS]:
                return R_CAP_STEPS
            t0, hb = walk_blocked(pts, tri, nbr, cons, meta, t, x, y)
            if hb < 0 and tri[3 * t0 + 2] != GHOST:
                hb = on_constraint(t0, x, y, pts, tri, cons)
            if hb >= 0:
                # Hidden behind, or on, a subsegment: split that one first.
                push_seg(tri[_next(hb % 3) + hb - hb % 3], tri[_prev(hb % 3) + hb - hb % 3], sq, st)
                heap_push(quality(t, pts, tri)[0], t, tri, hk, hp, st)
                continue
            if tri[3 * t0 + 2] == GHOST or treg[t0] < 0:
                st[S_SKIPPED] += 1  # unreachable without crossing a segment: cannot happen
                continue
            if nv >= st[S_MAXPTS]:
                return R_CAP_POINTS
            pts[nv, 0] = x
            pts[nv, 1] = y
            ncav = cavity(nv, t0, pts, tri, nbr, cons, circ, rank, meta, work, vmark)
            if ncav == NEED_SPACE:
                heap_push(quality(t, pts, tri)[0], t, tri, hk, hp, st)
                st[S_GROW_WORK] = 1
                return R_ROOM
            if ncav == BROKEN:
                return R_BROKEN
            if ncav <= DUP_BASE:
                st[S_SKIPPED] += 1
                continue
            # Reject a point inside the diametral circle of a subsegment on its cavity
            # boundary (the only subsegments it can encroach): split those instead.
            bo = 2 * (work.shape[0] // 5)
            enc = False
            for j in range(ncav + 2):
                o = bo + 3 * j
                if cons[work[o + 2]] != 0:
                    u = work[o]
                    w = work[o + 1]
                    if encroaches(pts[u, 0], pts[u, 1], pts[w, 0], pts[w, 1], x, y):
                        push_seg(u, w, sq, st)
                        enc = True
            if enc:
                heap_push(quality(t, pts, tri)[0], t, tri, hk, hp, st)
                continue
            f0 = treg[t0]
            tn = fan(nv, ncav, pts, tri, nbr, cons, circ, rank, meta, work, vmark)
            vseg[nv] = -1
            vpar[nv] = 0.0
            vacute[nv] = 0
            st[S_NV] = nv + 1
            set_flags(nv, tn, -1, -1, 0, 0, f0, tri, nbr, vtri, treg)
            _examine_star(nv, tn, pts, tri, nbr, cons, rank, vtri, treg, vseg, seg, rarea, hk, hp, sq, pend, pcen, st, prm)
            continue
        if st[S_PN] > 0:
            return R_SIZES
        return R_DONE


@njit(cache=True)
def _split_at(v, h, pts, tri, nbr, cons, circ, rank, meta, work, vmark, vtri, treg):
    """Split the subsegment of half-edge h at ``pts[v]`` and flag the new triangles."""
    a = tri[3 * (h // 3) + _next(h % 3)]
    b = tri[3 * (h // 3) + _prev(h % 3)]
    fl = treg[h // 3]
    fr = treg[nbr[h]]
    tn = split_edge(v, h, pts, tri, nbr, cons, circ, rank, meta, work, vmark)
    if tn >= 0:
        set_flags(v, tn, a, b, fl, fr, 0, tri, nbr, vtri, treg)
    return tn


# ---------------------------------------------------------------------------- driver
class _Run:
    """Queues and counters of one refinement run on a ConstrainedTriangulation ``ct``."""

    def __init__(self, ct, mode: int, sin2: float, amax: float, off: float, sized: bool, max_points: int, max_steps: int):
        self.ct = ct
        self.kind, self.data = ct._piece_tables()
        ct._acute()
        ntri = int(ct._meta[M_NTRI])
        self.st = np.zeros(S_LEN, dtype=np.int64)
        self.st[S_NV] = ct._nv
        self.st[S_MODE] = mode
        self.st[S_SIZED] = int(sized)
        self.st[S_MAXPTS] = max_points
        self.st[S_MAXSTEPS] = max_steps
        self.prm = np.zeros(P_LEN)
        self.prm[P_SIN2] = sin2
        self.prm[P_AMAX] = amax
        self.prm[P_OFF] = off
        cap = 2 * ntri + 1024
        self.hk = np.empty(cap, dtype=np.int64)
        self.hp = np.empty(4 * cap, dtype=np.int32)
        self.sq = np.empty(2 * (3 * cap), dtype=np.int32)
        self.pend = np.empty(4 * cap, dtype=np.int32)
        self.pcen = np.empty(2 * cap)

    def args(self):
        ct = self.ct
        return (
            ct._pts, ct._tri, ct._nbr, ct._cons, ct._circ, ct._rank, ct._meta, ct._work, ct._vmark,
            ct._vtri, ct._treg, ct._vseg, ct._vpar, ct._vacute, ct._seg, self.kind, self.data,
            ct._rarea, self.hk, self.hp, self.sq, self.pend, self.pcen, self.st, self.prm,
        )

    def seed(self) -> None:
        ct = self.ct
        seed_queues(
            ct._pts, ct._tri, ct._nbr, ct._cons, ct._rank, ct._meta, ct._vtri, ct._treg, ct._vseg,
            ct._seg, ct._rarea, self.hk, self.hp, self.sq, self.pend, self.pcen, self.st, self.prm,
        )

    def grow(self, estimate: int) -> None:
        """Double whatever :func:`refine_loop` found short (``estimate``: expected vertices)."""
        ct, st = self.ct, self.st
        if st[S_GROW_WORK]:
            st[S_GROW_WORK] = 0
            ct._grow_work()
        nv = int(st[S_NV])
        ct._nv = nv
        ntri = int(ct._meta[M_NTRI])
        wcap = ct._work.shape[0] // 5
        ct._ensure_points(max(nv + 2, min(estimate, 2 * nv + 2)))
        ct._ensure_slots(max(ntri + 4, min(2 * estimate + 8, 2 * ntri + 4)))
        if st[S_HN] + wcap + 1 > len(self.hk):
            self.hk = _doubled(self.hk, st[S_HN] + wcap + 1)
            self.hp = _doubled(self.hp, 4 * len(self.hk))
        if 2 * (st[S_QN] + 3 * wcap + 3) > len(self.sq):
            self.sq = _doubled(self.sq, 2 * (st[S_QN] + 3 * wcap + 3))
        if 4 * (st[S_PN] + wcap + 1) > len(self.pend):
            self.pend = _doubled(self.pend, 4 * (st[S_PN] + wcap + 1))
            self.pcen = _doubled(self.pcen, len(self.pend) // 2)

    def curve_point(self) -> None:
        """Answer an ``R_CURVE`` request: the split point on a curve known only to Python."""
        ct, st, prm = self.ct, self.st, self.prm
        a, b, p = int(st[S_REQ_A]), int(st[S_REQ_B]), int(st[S_REQ_P])
        row = int(ct._seg_in[p])
        if callable(ct.curves) and not hasattr(ct.curves, "split"):
            xy = np.asarray(ct.curves(int(ct.segment_ids[row]), ct._pts[a].copy(), ct._pts[b].copy()), dtype=np.float64)
            if xy.shape != (2,) or not np.isfinite(xy).all():
                raise InputError(f"curves({int(ct.segment_ids[row])}, ...) must return a finite (2,) point, got {xy!r}")
            x, y, t = float(xy[0]), float(xy[1]), 0.0
        else:
            ta, tb = float(prm[P_TA]), float(prm[P_TB])
            # Vertices inserted on a curved segment by hand have no parameter yet.
            ta = ct.curves.project(row, ct._pts[a]) if np.isnan(ta) else ta
            tb = ct.curves.project(row, ct._pts[b]) if np.isnan(tb) else tb
            x, y, t = ct.curves.split(row, ta, tb)
        prm[P_CX], prm[P_CY], prm[P_CT] = x, y, t
        st[S_CREADY] = 1

    def run(self, size, estimate: int, what: str, progress=None) -> None:
        """Call the loop until it is done, serving its requests; raise on caps and errors.

        ``progress(n_vertices)`` is called whenever the loop hands control back to Python.
        """
        ct, st = self.ct, self.st
        try:
            while True:
                code = refine_loop(*self.args())
                if progress is not None:
                    progress(int(st[S_NV]))
                if code == R_DONE:
                    return
                if code == R_ROOM:
                    self.grow(estimate)
                elif code == R_SIZES:
                    pn = int(st[S_PN])
                    h = size(self.pcen[: 2 * pn].reshape(pn, 2))
                    # Every waiting triangle may go to the heap.
                    if st[S_HN] + pn + 1 > len(self.hk):
                        self.hk = _doubled(self.hk, int(st[S_HN]) + pn + 1)
                        self.hp = _doubled(self.hp, 4 * len(self.hk))
                    apply_sizes(h, ct._pts, ct._tri, self.hk, self.hp, self.pend, st)
                elif code == R_CURVE:
                    self.curve_point()
                else:
                    self._fail(code, what)
        finally:
            ct._nv = int(st[S_NV])

    def _fail(self, code: int, what: str) -> None:
        ct, st, prm = self.ct, self.st, self.prm
        where = f"({prm[P_WX]:.17g}, {prm[P_WY]:.17g})"
        done = int(st[S_NV])
        if code == R_CAP_POINTS:
            raise MeshingError(
                f"{what}: max_points={int(st[S_MAXPTS])} reached while working near {where}; "
                "raise max_points, or coarsen the size / relax min_angle"
            )
        if code == R_CAP_STEPS:
            raise MeshingError(
                f"{what}: max_steps={int(st[S_MAXSTEPS])} reached with {done} vertices while working "
                f"near {where}; the input may have features the angle bound cannot resolve"
            )
        if code == R_OFF_CURVE:
            a, b, p = int(st[S_REQ_A]), int(st[S_REQ_B]), int(st[S_REQ_P])
            raise GeometryError(
                f"{what}: subsegment {tuple(ct._pts[a])}-{tuple(ct._pts[b])} of segment "
                f"{int(ct._seg_in[p])} cannot be split at {where}: the point is neither on it nor "
                "inside its two triangles (a vertex lies between the chord and the true curve)"
            )
        raise MeshingError(f"{what}: inserting a vertex near {where} met an inconsistent cavity")


def _doubled(a: np.ndarray, need: int) -> np.ndarray:
    out = np.empty(max(need, 2 * len(a)), dtype=a.dtype)
    out[: len(a)] = a
    return out


def _estimate(ct, amax: float, size) -> float:
    """Vertices a size-bounded mesh of the inside triangles needs, roughly (area / bound)."""
    tris = ct.triangles(True)
    if not len(tris):
        return 0.0
    p = ct._pts
    a, b, c = p[tris[:, 0]], p[tris[:, 1]], p[tris[:, 2]]
    area = 0.5 * np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
    ntri = int(ct._meta[M_NTRI])
    reg = ct._treg[:ntri][ct._mask(True)]
    bound = np.minimum(amax, ct._rarea[np.maximum(reg, 0)])
    if size is not None and size.constant is None:
        h = np.minimum(np.minimum(size(a), size(b)), np.minimum(size(c), size((a + b + c) / 3.0)))
        bound = np.minimum(bound, _EQUILATERAL * h * h)
    return float(np.sum(area / bound))


def refine(
    ct, *, min_angle: float = 30.0, size=None, max_area=None, max_points=None, max_steps=None,
    offcenters: bool = True, curves=None, progress=None,
):
    """Guaranteed-quality Delaunay refinement of a constrained triangulation, in place.

    Parameters
    ----------
    ct : ConstrainedTriangulation
        From :func:`meshwright.tri.cdt.cdt_build`; classified first if it was not (free
        convex-hull edges bounding the inside become segments, :meth:`close_hull`).
    min_angle : float
        Smallest angle wanted, degrees in ``[0, 60)``; 0 refines by size only.  Up to about
        33.8 terminates in practice; angles next to smaller input angles are left alone.
    size : number, callable or SizeField, optional
        Local edge length h(x): a triangle is split while its area exceeds that of the
        equilateral triangle of side h at its circumcentre.
    max_area : float, optional
        Largest triangle area (region seeds of :meth:`classify` may lower it locally).
    max_points : int, optional
        Cap on the number of vertices; default ``nv + 50 nv + 4 * estimate + 1000`` with the
        estimate from ``size`` / ``max_area``.
    max_steps : int, optional
        Cap on loop steps (default ``20 * max_points``).
    offcenters : bool
        Insert Üngör's off-centres instead of circumcentres where nearer (fewer vertices).
    curves : SegmentCurves or callable, optional
        Replaces ``ct.curves`` (true curve of each segment for the split points).
    progress : callable, optional
        ``progress(n_vertices)``, called now and then (progress bars).

    Returns
    -------
    ConstrainedTriangulation
        ``ct``, refined.

    Raises
    ------
    MeshingError
        A cap was hit (the message names it and where the loop was working).
    GeometryError
        A curved segment cannot be split on its curve.
    """
    if not (0.0 <= float(min_angle) < 60.0):
        raise InputError(f"min_angle must be in [0, 60) degrees, got {min_angle!r}")
    if max_area is not None and not (np.isfinite(max_area) and max_area > 0.0):
        raise InputError(f"max_area must be positive and finite, got {max_area!r}")
    if curves is not None:
        ct.curves = curves
    if not ct.classified:
        ct.classify()
    _close_open_hull(ct)
    field = None if size is None else as_size_field(size)
    amax = np.inf if max_area is None else float(max_area)
    if field is not None and field.constant is not None:
        amax = min(amax, _EQUILATERAL * field.constant**2)
    theta = np.radians(float(min_angle))
    sin2 = np.sin(theta) ** 2
    off = 0.475 * np.sqrt((1.0 + np.cos(theta)) / (1.0 - np.cos(theta))) if offcenters and theta > 0 else 0.0
    est = _estimate(ct, amax, field)
    nv = ct.n_points
    if max_points is None:
        max_points = int(min(nv + 50 * nv + 4 * est + 1000, 2**31 - 16))
    if max_steps is None:
        max_steps = 20 * int(max_points)
    sized = field is not None and field.constant is None
    run = _Run(ct, MODE_RUPPERT, sin2, amax, off, sized, int(max_points), int(max_steps))
    run.seed()
    run.run(field, int(min(max_points, nv + 1.2 * est + 16)), "refine", progress)
    return ct


def _close_open_hull(ct) -> None:
    """Constrain free hull edges whose inner triangle is inside (they bound the domain)."""
    ntri = int(ct._meta[M_NTRI])
    g = np.flatnonzero(ct._tri[2 : 3 * ntri : 3] == GHOST)
    h = 3 * g + 2
    inner = ct._nbr[h]
    if np.any((ct._cons[h] == 0) & (ct._treg[inner] >= 0)):
        ct.close_hull()


def conform(ct) -> None:
    """Split subsegments until each is locally Delaunay: a conforming Delaunay triangulation.

    Split points as in :func:`refine` (midpoints on the true curve, shells at acute input
    vertices); no triangle is refined.
    """
    nv = ct.n_points
    run = _Run(ct, MODE_CONFORM, 0.0, np.inf, 0.0, False, 50 * nv + 1000, 1000 * nv + 10000)
    run.seed()
    run.run(None, 2 * nv, "conforming Delaunay")


def split_subsegment(ct, a: int, b: int, xy=None) -> int:
    """Split subsegment ab of ``ct`` at ``xy`` or at its split point; return the new vertex."""
    h = int(edge_of(a, b, ct._tri, ct._nbr, ct._vtri)) if 0 <= min(a, b) and max(a, b) < ct.n_points else -1
    if h < 0 or ct._cons[h] == 0:
        raise InputError(f"vertices {a} and {b} are not the ends of a subsegment")
    run = _Run(ct, MODE_CONFORM, 0.0, np.inf, 0.0, False, 2**31 - 16, 1)
    p = int(ct._cons[h]) - 1
    row = int(ct._seg_in[p])
    if xy is None:
        x, y, t, ok = split_point(p, a, b, ct._pts, ct._seg, run.kind, run.data, ct._vpar, ct._vacute)
        if not ok:
            run.st[S_REQ_A], run.st[S_REQ_B], run.st[S_REQ_P] = a, b, p
            run.prm[P_TA] = param_of(p, a, ct._seg, run.data, ct._vpar)
            run.prm[P_TB] = param_of(p, b, ct._seg, run.data, ct._vpar)
            run.curve_point()
            x, y, t = run.prm[P_CX], run.prm[P_CY], run.prm[P_CT]
    else:
        x, y = (float(c) for c in np.asarray(xy, dtype=np.float64).ravel()[:2])
        t = ct.curves.project(row, (x, y)) if hasattr(ct.curves, "project") and row >= 0 else np.nan
    v = ct.n_points
    ct._ensure_points(v + 1)
    ct._ensure_slots(int(ct._meta[M_NTRI]) + 2)
    ct._pts[v] = x, y
    while True:
        tn = _split_at(v, h, ct._pts, ct._tri, ct._nbr, ct._cons, ct._circ, ct._rank, ct._meta, ct._work, ct._vmark, ct._vtri, ct._treg)
        if tn != NEED_SPACE:
            break
        ct._grow_work()
    if tn < 0:
        raise GeometryError(
            f"subsegment {a}-{b} cannot be split at ({x:.17g}, {y:.17g}): the point is neither on it "
            "nor inside one of its two triangles"
        )
    ct._vseg[v], ct._vpar[v], ct._vacute[v] = p, t, 0
    ct._nv = v + 1
    return v
