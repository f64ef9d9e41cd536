"""The state bundle of Delaunay refinement and its per-triangle tests (:mod:`.ruppert`).

:class:`RefineState`, the third kernel argument of :func:`meshwright.tri.ruppert.refine_loop`
(the insertion kernel's ``TriState`` and the constrained layer's ``CdtState`` are the first
two), with the slots of its counter and parameter arrays, and what decides which triangles
and subsegments go to its queues: :func:`examine` (Ruppert 1995 / Shewchuk 2002 tests:
encroached subsegments, small angles, area and size bounds, Shewchuk's small-input-angle
rule), :func:`apply_sizes` (sizes evaluated in Python, in batches), the bucket-queue pushes.

Layout::

    qhead (QB,)     int32    bad-triangle bucket queue (:mod:`meshwright.core.bucket_queue`):
                               newest entry of each bucket,
    qnext (qcap,)   int32      next entry of a bucket or of the free list,
    qval  (qcap, 4) int32      payloads (t, a, b, c): stale entries are recognised,
    qhdr  (4,)      int64      count, free list, lowest bucket, entries handed out
    sq   (2 q,)     int32    stack of subsegments (a, b) to split
    pend (4 p,)     int32    triangles (t, a, b, c) waiting for the size field at pcen
    pcen (2 p,)     float64  their circumcentres
    st   (S_LEN,)   int64    counters, caps, requests (slots ``S_*``)
    prm  (P_LEN,)   float64  parameters, curve points, where the loop works (slots ``P_*``)
    fz   (P,)       uint8    1 for the pieces of frozen segments (never split by the loop)
    held (2 k,)     int32    subsegments (a, b) of frozen segments that needed a split

Priority (:func:`push_bad`): one bucket per half power of two of the squared shortest edge,
shortest first (Triangle's order), newest first inside a bucket.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from meshwright.core.borrowed import borrowed
from meshwright.core.bucket_queue import bq_push
from meshwright.core.flat import GHOST, back3, index3, next3, prev3
from meshwright.core.geom2d import circumcentre, corners, off_centre
from meshwright.core.jit import inner
from meshwright.core.predicates import incircle_sos
from meshwright.tri._encroach import encroaches, key_of
from meshwright.tri._kernel2d import M_NTRI

# st slots
S_QN = 2  # subsegment stack size
S_PN = 3  # triangles waiting for sizes
S_STEPS = 5
S_MAXPTS = 6
S_MAXSTEPS = 7
S_NIN = 8  # vertices when the run started (later ones have their piece in vseg)
S_CREADY = 9  # prm[P_CX:P_CT] holds the curve point asked for
S_REQ_A = 10  # curve point request: subsegment (a, b) of piece p
S_REQ_B = 11
S_REQ_P = 12
S_MODE = 13  # MODE_RUPPERT or MODE_CONFORM
S_SIZED = 14  # 1 when the size field must be evaluated in Python
S_SKIPPED = 15  # triangles left alone (small input angles, unreachable off-centres)
S_HN = 16  # entries in held
S_LEN = 17
# prm slots
P_SIN2 = 0  # sin^2 of the minimum angle (0: no angle criterion)
P_AMAX = 1  # global max area (inf: none)
P_OFF = 2  # off-centre constant (0: circumcentres)
P_CX = 3  # curve point given by Python
P_CY = 4
P_CT = 5
P_TA = 6  # curve parameters of a request
P_TB = 7
P_WX = 8  # where the loop last worked (error messages)
P_WY = 9
P_LEN = 10
MODE_RUPPERT = 0
MODE_CONFORM = 1
EQUILATERAL = np.sqrt(3.0) / 4.0  # area of the equilateral triangle of side 1
# Queue buckets: 2 e + (m > 1/sqrt 2) + shift for the squared shortest edge m 2^e.
QB = 4200
QB_SHIFT = 2150
SQRT_HALF = np.sqrt(0.5)


class RefineState(NamedTuple):
    """Queues and counters of one refinement run (layout in the module docstring)."""

    qhead: np.ndarray
    qnext: np.ndarray
    qval: np.ndarray
    qhdr: np.ndarray
    sq: np.ndarray
    pend: np.ndarray
    pcen: np.ndarray
    st: np.ndarray
    prm: np.ndarray
    fz: np.ndarray
    held: np.ndarray


# ------------------------------------------------------------------ queues
# The per-step helpers below take arrays, not bundles: refine_loop reads the bundles' fields
# once (a field read where a helper runs per triangle costs a reference-count pair each
# time; docs/ARCHITECTURE.md).
@njit(inline="always")
def push_seg(u, w, sq, st):
    """Queue subsegment u-w for splitting."""
    q = st[S_QN]
    sq[2 * q] = u
    sq[2 * q + 1] = w
    st[S_QN] = q + 1


@njit(inline="always")
def hold_subsegment(u, w, h, cons, fz, held, st):
    """Record subsegment u-w (half-edge h) instead of queueing it when its segment is frozen."""
    if fz[cons[h] - 1] == 0:
        return False
    i = st[S_HN]
    held[2 * i] = u
    held[2 * i + 1] = w
    st[S_HN] = i + 1
    return True


@njit(inline="always")
def push_bad(lmin, t, tri, qhead, qnext, qval, qhdr):
    """Queue triangle t (with its vertices, to recognise it later) by its squared shortest
    edge ``lmin``: bucket ``2 e + (m > 1/sqrt 2)`` for ``lmin = m 2^e``, ``m`` in [0.5, 1)."""
    m, e = math.frexp(lmin)
    b = min(QB - 1, max(0, 2 * e + (1 if m > SQRT_HALF else 0) + QB_SHIFT))
    i = bq_push(qhead, qnext, qhdr, b)
    qval[i, 0] = t
    for j in range(3):
        qval[i, j + 1] = tri[3 * t + j]


# ------------------------------------------------------------------ triangle tests
@inner
def vertex_piece(u, nin, tri, nbr, cons, vtri, vseg):
    """A segment piece through vertex u (its own for split vertices), or -1.

    Vertices from ``nin`` on were inserted by this run, which records the piece of every
    vertex it puts on a segment (``vseg``), so only older ones need the search of their star.
    """
    if vseg[u] >= 0:
        return vseg[u]
    if u >= nin:
        return -1
    t = vtri[u]
    start = t
    while True:
        i = index3(tri, t, u)
        for k in (next3(i), prev3(i)):
            if cons[3 * t + k] != 0:
                return cons[3 * t + k] - 1
        t = nbr[3 * t + next3(i)]
        if t == start:
            return -1


@inner
def _small_angle_apex(u, w, nin, pts, tri, nbr, cons, vtri, vseg, seg):
    """Shewchuk's rule: u and w on two segments meeting at a vertex, equally far from it."""
    pu = vertex_piece(u, nin, tri, nbr, cons, vtri, vseg)
    if pu < 0:
        return False
    pw = vertex_piece(w, nin, tri, nbr, cons, vtri, vseg)
    if pw < 0 or pu == pw:
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


@njit(inline="always")
def quality(t, pts, tri):
    """``(sin^2 of the smallest angle, area, u, w, |uw|^2)`` of triangle t, uw its shortest edge.

    The smallest angle is opposite the shortest edge; its sine squared is (2 area)^2 over
    the product of the other two squared lengths.
    """
    a = tri[3 * t]
    b = tri[3 * t + 1]
    c = tri[3 * t + 2]
    ax, ay, bx, by, cx, cy = corners(pts, tri, t)
    l0 = (cx - bx) ** 2 + (cy - by) ** 2
    l1 = (ax - cx) ** 2 + (ay - cy) ** 2
    l2 = (bx - ax) ** 2 + (by - ay) ** 2
    cross = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    if l0 <= l1 and l0 <= l2:
        return cross * cross / (l1 * l2), 0.5 * cross, b, c, l0
    if l1 <= l2:
        return cross * cross / (l0 * l2), 0.5 * cross, c, a, l1
    return cross * cross / (l0 * l1), 0.5 * cross, a, b, l2


@inner
def requeue(t, pts, tri, qhead, qnext, qval, qhdr):
    """Put triangle t back on the queue (its point was refused or a cap stopped the loop).

    A call, not inlined: :func:`refine_loop` requeues from five places, and each inlined
    copy of :func:`quality` and :func:`push_bad` cost compile time on every first run
    while the requeue itself is rare.
    """
    push_bad(quality(t, pts, tri)[4], t, tri, qhead, qnext, qval, qhdr)


@njit(inline="always")
def steiner_point(t, pts, tri, off):
    """Off-centre of triangle t (Üngör 2004, with Triangle's constant ``off``), else its
    circumcentre when nearer (:func:`meshwright.core.geom2d.off_centre`)."""
    ax, ay, bx, by, cx, cy = corners(pts, tri, t)
    return off_centre(ax, ay, bx, by, cx, cy, off)


@njit(cache=True, nogil=True)
def examine(v, tn, s, c, r):
    """Queue what is wrong with the triangles that take part (inside; all in conforming mode)
    around vertex v, from its triangle tn; with v < 0, with every slot (tn unused).

    Ruppert mode: each constrained edge of a triangle encroached by its apex there is
    pushed; the triangle goes to the queue when its minimum angle is below the bound or its
    area above the (regional) maximum, else to the size queue when the size field is
    evaluated in Python.  Conforming mode: constrained edges that are not locally Delaunay
    are pushed.  The test is written once, inside this loop, not in a helper called per
    triangle: a call handing a helper the bundles' seventeen arrays costs a reference-count
    pair per array, which measured four times the test itself.
    """
    s, c, r = borrowed(s), borrowed(c), borrowed(r)
    pts, tri, nbr, cons, rank = s.pts, s.tri, s.nbr, s.cons, s.rank
    vtri, treg, vseg, seg, rarea = c.vtri, c.treg, c.vseg, c.seg, c.rarea
    qhead, qnext, qval, qhdr, sq, pend, pcen, st, prm, fz, held = r
    conform = st[S_MODE] == MODE_CONFORM
    ntri = s.meta[M_NTRI]
    t = tn if v >= 0 else 0
    while True:
        if v >= 0:
            nxt = nbr[3 * t + next3(index3(tri, t, v))]
        elif t >= ntri:
            return
        else:
            nxt = t + 1
        b3 = 3 * t
        if tri[b3 + 2] != GHOST and (conform or treg[t] >= 0):
            a = tri[b3]
            b = tri[b3 + 1]
            cc = tri[b3 + 2]
            ax, ay, bx, by, cx, cy = corners(pts, tri, t)
            if conform:
                for k in range(3):
                    n = nbr[b3 + k]
                    if cons[b3 + k] != 0 and tri[3 * n + 2] != GHOST:
                        d = tri[3 * n + back3(nbr, n, t)]
                        if incircle_sos(
                            ax, ay, bx, by, cx, cy, pts[d, 0], pts[d, 1],
                            key_of(rank, a), key_of(rank, b), key_of(rank, cc), key_of(rank, d),
                        ) > 0:
                            push_seg(tri[b3 + next3(k)], tri[b3 + prev3(k)], sq, st)
            else:
                for k in range(3):
                    if cons[b3 + k] != 0:
                        x = tri[b3 + k]
                        u = tri[b3 + next3(k)]
                        w = tri[b3 + prev3(k)]
                        if encroaches(pts[u, 0], pts[u, 1], pts[w, 0], pts[w, 1], pts[x, 0], pts[x, 1]) and not hold_subsegment(
                            u, w, b3 + k, cons, fz, held, st
                        ):
                            push_seg(u, w, sq, st)
                sin2, area, su, sw, lmin = quality(t, pts, tri)
                bad_area = area > prm[P_AMAX] or area > rarea[treg[t]]
                bad_angle = sin2 < prm[P_SIN2]
                # Shewchuk's small-angle rule is for a shortest edge between two segments; a
                # shortest edge that is a subsegment itself is split as usual (Triangle's
                # testtriangle does the same).
                kx = 0
                while tri[b3 + kx] == su or tri[b3 + kx] == sw:
                    kx += 1
                own = cons[b3 + kx] != 0
                if bad_angle and not bad_area and not own and _small_angle_apex(
                    su, sw, st[S_NIN], pts, tri, nbr, cons, vtri, vseg, seg
                ):
                    st[S_SKIPPED] += 1
                    bad_angle = False
                if bad_angle or bad_area:
                    push_bad(lmin, t, tri, qhead, qnext, qval, qhdr)
                elif st[S_SIZED] != 0:
                    i = st[S_PN]
                    st[S_PN] = i + 1
                    pend[4 * i] = t
                    pend[4 * i + 1] = a
                    pend[4 * i + 2] = b
                    pend[4 * i + 3] = cc
                    ox, oy = circumcentre(ax, ay, bx, by, cx, cy)
                    pcen[2 * i] = ox
                    pcen[2 * i + 1] = oy
        if v >= 0 and nxt == tn:
            return
        t = nxt


@njit(cache=True, nogil=True)
def apply_sizes(h, s, r):
    """Queue the waiting triangles larger than the equilateral triangle of side h.

    ``h`` (pn,) float64 is the size field at their circumcentres ``pcen``; triangles that
    changed since they were queued are dropped (their successors were examined).
    """
    tri = s.tri
    pend, st = r.pend, r.st
    for i in range(st[S_PN]):
        t = pend[4 * i]
        if tri[3 * t] == pend[4 * i + 1] and tri[3 * t + 1] == pend[4 * i + 2] and tri[3 * t + 2] == pend[4 * i + 3]:
            _, area, _, _, lmin = quality(t, s.pts, tri)
            if area > EQUILATERAL * h[i] * h[i]:
                push_bad(lmin, t, tri, r.qhead, r.qnext, r.qval, r.qhdr)
    st[S_PN] = 0
