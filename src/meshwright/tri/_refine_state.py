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
    pcor (P, 3)     int32    chain of each piece and the chain's two end vertices (-1: none)

A *chain* is one straight input segment however finely the boundary was discretised into
pieces (a line or one edge of a polyline, up to where other pieces meet it; ``chains`` in
:mod:`.ruppert`): the small-angle rules below are about the segments meeting at an input
vertex, which the pieces of a discretised boundary hide (the pieces next to a needle's tip
meet at the tip, the ones after them meet nowhere).  A piece of a curve is its own chain:
the rules' premise, straight sides at the input angle, holds there only piece by piece.

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
    pcor: np.ndarray


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
def _common_end(pu, pw, pcor):
    """The end vertex the chains of pieces pu and pw share (two segments meeting there), or -1."""
    if pu < 0 or pw < 0 or pcor[pu, 0] == pcor[pw, 0]:
        return -1
    j = -1
    for x in (pcor[pu, 1], pcor[pu, 2]):
        if x >= 0 and (x == pcor[pw, 1] or x == pcor[pw, 2]):
            j = x
    return j


@njit(inline="always")
def _equally_far(u, w, j, pts):
    """Whether u and w are equally far from j, to the 0.1 % of Shewchuk's rule (squared)."""
    du = (pts[u, 0] - pts[j, 0]) ** 2 + (pts[u, 1] - pts[j, 1]) ** 2
    dw = (pts[w, 0] - pts[j, 0]) ** 2 + (pts[w, 1] - pts[j, 1]) ** 2
    return 0.999 * dw < du < 1.001 * dw


@inner
def _small_angle_apex(u, w, nin, pts, tri, nbr, cons, vtri, vseg, pcor):
    """Shewchuk's rule: u and w on two segments (chains) meeting at a vertex, equally far from it."""
    pu = vertex_piece(u, nin, tri, nbr, cons, vtri, vseg)
    if pu < 0:
        return False
    j = _common_end(pu, vertex_piece(w, nin, tri, nbr, cons, vtri, vseg), pcor)
    return j >= 0 and _equally_far(u, w, j, pts)


@inner
def common_shell(x, u, w, p, nin, pts, tri, nbr, cons, vtri, vseg, pcor, vacute):
    """Whether vertex x, found inside the diametral circle of subsegment u-w of piece p, is
    on a segment (chain) meeting p's at an acute input vertex j, as far from j as u or w is.

    Concentric shells put the vertices of two segments at a small angle at equal distances
    from j, where in exact arithmetic none encroaches the other segment's subsegments: x
    at distance r from j encroaches a subsegment ending at distance r on the other segment
    only when it is closer to j than ``r cos(angle)``.  For an angle below about 1e-5 rad
    ``r (1 - cos(angle))`` is under the rounding of the shell points' coordinates once r
    is small against them, so the rounded test answers at random there, and a split made
    on its answer puts a new shell vertex that meets the same coin toss one shell closer
    to j: a cascade down to subsegments that can no longer be split (stress reproducers
    of thin domains).  So such an x counts as on the shell of u or w, as Shewchuk's rule
    takes the triangle between them as the best there is.
    """
    j = _common_end(vertex_piece(x, nin, tri, nbr, cons, vtri, vseg), p, pcor)
    if j < 0 or vacute[j] == 0:
        return False
    return _equally_far(x, u, j, pts) or _equally_far(x, w, j, pts)


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
    vtri, treg, vseg, rarea, vacute = c.vtri, c.treg, c.vseg, c.rarea, c.vacute
    qhead, qnext, qval, qhdr, sq, pend, pcen, st, prm, fz, held, pcor = r
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
                        if (
                            encroaches(pts[u, 0], pts[u, 1], pts[w, 0], pts[w, 1], pts[x, 0], pts[x, 1])
                            and not common_shell(
                                x, u, w, cons[b3 + k] - 1, st[S_NIN], pts, tri, nbr, cons, vtri, vseg, pcor, vacute
                            )
                            and not hold_subsegment(u, w, b3 + k, cons, fz, held, st)
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
                    su, sw, st[S_NIN], pts, tri, nbr, cons, vtri, vseg, pcor
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
