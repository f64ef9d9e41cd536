r"""Njit kernels of constrained Delaunay refinement: encroachment, subsegment splits, the loop.

Shared by :mod:`meshwright.tri.cdt` (constrained insertion, the conforming option) and
:mod:`meshwright.tri.ruppert` (quality refinement).  Sources: J. Ruppert, "A Delaunay
refinement algorithm for quality 2-dimensional mesh generation", J. Algorithms 18(3), 1995;
J. R. Shewchuk, "Delaunay refinement algorithms for triangular mesh generation", Comput.
Geom. 22, 2002 (concentric shells, the rule that leaves triangles at small input angles
alone); A. Üngör, "Off-centers: a new type of Steiner points for computing size-optimal
quality-guaranteed Delaunay triangulations", LATIN 2004.

State (all flat arrays, grown by the Python driver between calls)
----------------------------------------------------------------
Kernel arrays of :mod:`meshwright.tri._kernel2d` (``pts tri nbr cons circ rank meta work
vmark``) plus::

    vtri  (rows,) int32     a triangle slot incident to each vertex (kept exact)
    treg  (cap,)  int32     per slot: -1 exterior or ghost, 0 inside, r + 1 region r
    vseg  (rows,) int32     segment piece a split vertex lies on, -1 for input vertices
    vpar  (rows,) float64   its curve parameter (arcs and parametric curves)
    vacute(rows,) int8      1 at input vertices where segments meet below 60 degrees
    seg   (P, 2)  int32     piece endpoints; ``cons[h] = p + 1`` on the subsegments of p
    pkind (P,)    int8      0 straight, 1 circular arc, 2 curve evaluated in Python
    pdat  (P, 5)  float64   arc centre x, y, radius; curve parameters at both endpoints
    rarea (R+1,)  float64   max area per ``treg`` value (inf when unconstrained)
    hk, hp                  bad-triangle min-heap: int64 keys, (t, a, b, c) payloads
    sq                      stack of subsegments (a, b) to split
    pend, pcen              triangles (t, a, b, c) waiting for the size field at pcen
    st (int64), prm (float64)   counters, caps, parameters; slots ``S_*`` and ``P_*``

Encroachment (exact): p encroaches subsegment ab iff ``(a - p) . (b - p) < 0``, i.e. p is
strictly inside the diametral circle.  Only vertices seen from the domain side count: the
apexes of inside triangles.

Split points: the midpoint of ab (on the true curve for arcs and curves); a subsegment
touching exactly one *acute* input vertex (segments meeting there below 60 degrees) is split
where the distance from that vertex is the power of two nearest to a third of... two thirds
of its length (Ruppert's concentric shells, as in Triangle), so that the vertices on the
segments of a small angle sit on common shells and stop encroaching each other::

        apex *----x---------x-------------------x----  shells at 2^k from the apex
              \    .         .                   .
               *---x---------x-------------------x--

A skinny triangle whose shortest edge joins two vertices on different segments that meet
at a common vertex, equally far from it, is left alone (it cannot be improved: Shewchuk's
rule, implemented as in Triangle), so the loop terminates on input angles of 1 degree.

Loop (:func:`refine_loop`): split every queued subsegment first; then pop the worst bad
triangle, compute its off-centre (the circumcentre when nearer to the shortest edge), walk
there from the triangle; if the walk is blocked by a subsegment, split that one instead; if
the point lies in the diametral circle of a subsegment on its cavity boundary, queue those
subsegments instead.  Otherwise insert it.  The loop returns a ``R_*`` status to Python
whenever it needs room, a size-field evaluation or a curve point, and continues from where it
stopped on the next call.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.expansion import diff_into, estimate, expansion_sum, mul_small
from meshwright.core.flat import GHOST
from meshwright.core.predicates import CCW_ERRBOUND_A, incircle_sos, orient2d
from meshwright.tri._kernel2d import (
    BROKEN,
    DUP_BASE,
    M_LAST,
    M_NTRI,
    M_RNG,
    NEED_SPACE,
    insert_vertex,
    walk,
)

# statuses of refine_loop
R_DONE = 0
R_ROOM = 1
R_SIZES = 2
R_CURVE = 3
R_CAP_POINTS = 4
R_CAP_STEPS = 5
R_BROKEN = 6
R_OFF_CURVE = 7
# st slots
S_NV = 0  # vertices in use
S_HN = 1  # heap size
S_QN = 2  # subsegment stack size
S_PN = 3  # triangles waiting for sizes
S_SEQ = 4  # heap insertion counter (FIFO among equal keys)
S_STEPS = 5
S_MAXPTS = 6
S_MAXSTEPS = 7
S_GROW_WORK = 8  # the cavity scratch must double
S_CREADY = 9  # prm[P_CX:P_CT] holds the curve point asked for
S_REQ_A = 10  # curve point request: subsegment (a, b) of piece p
S_REQ_B = 11
S_REQ_P = 12
S_MODE = 13  # MODE_RUPPERT or MODE_CONFORM
S_SIZED = 14  # 1 when the size field must be evaluated in Python
S_SKIPPED = 15  # triangles left alone (small input angles, unreachable off-centres)
S_LEN = 16
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
KIND_STRAIGHT = 0
KIND_ARC = 1
KIND_CURVE = 2
_EQUILATERAL = np.sqrt(3.0) / 4.0  # area of the equilateral triangle of side 1
_BUCKETS = 4096  # resolution of the quality key: worst first, FIFO inside a bucket
_SEQ_BITS = 40


@njit(inline="always")
def _next(k):
    return 0 if k == 2 else k + 1


@njit(inline="always")
def _prev(k):
    return 2 if k == 0 else k - 1


@njit(inline="always")
def _index(tri, t, v):
    """Position of vertex v in triangle t."""
    return 0 if tri[3 * t] == v else (1 if tri[3 * t + 1] == v else 2)


@njit(inline="always")
def key_of(rank, v):
    """Symbolic-perturbation key of vertex v (as in :mod:`meshwright.tri.bowyer`)."""
    return rank[v] if v < rank.shape[0] else v


@njit(cache=True)
def _dot_exact(ax, ay, bx, by, px, py):
    """``(a - p) . (b - p)`` rounded from its exact expansion (so its sign is exact)."""
    # Regions: four differences at 0..8, the two products at 8 and 16, scratch at 24,
    # the sum at 32 (each product has at most 8 components).
    w = np.empty(48)
    n1 = diff_into(ax, px, w, 0)
    n2 = diff_into(ay, py, w, 2)
    n3 = diff_into(bx, px, w, 4)
    n4 = diff_into(by, py, w, 6)
    m1 = mul_small(w, 0, n1, 4, n3, 1.0, 8, 24)
    m2 = mul_small(w, 2, n2, 6, n4, 1.0, 16, 24)
    n = expansion_sum(w, 8, m1, 16, m2, 1.0, 32)
    return estimate(w, 32, n)


@njit(cache=True)
def encroaches(ax, ay, bx, by, px, py):
    """Whether p lies strictly inside the diametral circle of ab (exact).

    Returns
    -------
    bool
        ``(a - p) . (b - p) < 0``.
    """
    l = (ax - px) * (bx - px)
    r = (ay - py) * (by - py)
    d = l + r
    bound = CCW_ERRBOUND_A * (abs(l) + abs(r))
    if d > bound:
        return False
    if d < -bound:
        return True
    return _dot_exact(ax, ay, bx, by, px, py) < 0.0


@njit(cache=True)
def edge_of(a, b, tri, nbr, vtri):
    """Half-edge ``a -> b`` (its triangle on the left), or -1 when ab is not an edge.

    Rotates counter-clockwise around a from ``vtri[a]``; O(degree).
    """
    t = vtri[a]
    start = t
    while True:
        i = _index(tri, t, a)
        if tri[3 * t + _next(i)] == b:
            return 3 * t + _prev(i)
        t = nbr[3 * t + _next(i)]
        if t == start:
            return -1


@njit(cache=True)
def set_flags(v, tn, a, b, fl, fr, f0, tri, nbr, vtri, treg):
    """Region flags and vertex->triangle links of the new triangles around vertex v.

    All triangles incident to v are new.  After an ordinary insertion they get ``f0`` (the
    cavity never crosses a constrained edge, so it lies in one region); after splitting
    subsegment ``a -> b`` the ones counter-clockwise from v->b to v->a (left of a-v-b) get
    ``fl`` and the others ``fr``.  Ghosts get -1.
    """
    t = tn
    i = _index(tri, t, v)
    cur = f0
    if a >= 0:
        while tri[3 * t + _next(i)] != b:
            t = nbr[3 * t + _next(i)]
            i = _index(tri, t, v)
        cur = fl
    start = t
    while True:
        x = tri[3 * t + _next(i)]
        y = tri[3 * t + _prev(i)]
        treg[t] = -1 if tri[3 * t + 2] == GHOST else cur
        vtri[v] = t
        if x >= 0:
            vtri[x] = t
        if y >= 0:
            vtri[y] = t
        if a >= 0 and y == a:
            cur = fr
        t = nbr[3 * t + _next(i)]
        if t == start:
            return
        i = _index(tri, t, v)


@njit(cache=True)
def walk_blocked(pts, tri, nbr, cons, meta, t, px, py):
    """Stochastic visibility walk from t to p that stops at constrained edges.

    Returns
    -------
    (int, int)
        ``(t_end, -1)`` with p in the closure of finite ``t_end`` (or ``t_end`` a ghost), or
        ``(t, h)`` when every edge of t that p lies strictly beyond is constrained: h is one
        of them, the subsegment hiding p from t.
    """
    came = -1
    r = meta[M_RNG]
    while True:
        r ^= (r << 13) & 0xFFFFFFFF
        r ^= r >> 17
        r ^= (r << 5) & 0xFFFFFFFF
        k = r % 3
        base = 3 * t
        nxt = -1
        hit = -1
        for _ in range(3):
            n = nbr[base + k]
            if n != came:
                a = tri[base + _next(k)]
                b = tri[base + _prev(k)]
                if orient2d(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], px, py) < 0.0:
                    if cons[base + k] == 0:
                        nxt = n
                        break
                    hit = base + k
            k = _next(k)
        if nxt < 0:
            meta[M_RNG] = r
            return t, hit
        came = t
        t = nxt
        if tri[3 * t + 2] == GHOST:
            meta[M_RNG] = r
            return t, -1


# ------------------------------------------------------------------ split points
@njit(inline="always")
def param_of(p, x, seg, pdat, vpar):
    """Curve parameter of vertex x on piece p."""
    if x == seg[p, 0]:
        return pdat[p, 3]
    if x == seg[p, 1]:
        return pdat[p, 4]
    return vpar[x]


@njit(cache=True)
def _shell_fraction(length):
    """Distance (power of two) from an acute apex where a subsegment is split, over its length."""
    p2 = 1.0
    while length > 3.0 * p2:
        p2 *= 2.0
    while length < 1.5 * p2:
        p2 *= 0.5
    return p2 / length


@njit(cache=True)
def split_point(p, a, b, pts, seg, pkind, pdat, vpar, vacute):
    """Where to split subsegment ``a -> b`` of piece p.

    Returns
    -------
    (float, float, float, bool)
        ``(x, y, t, ok)``: the point and its curve parameter; ``ok`` is False for curves
        evaluated in Python (kind 2), which need the parameters of a and b instead.
    """
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
    kind = pkind[p]
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
def on_constraint(t, px, py, pts, tri, cons):
    """A constrained half-edge of finite triangle t through p (p in its closure), or -1."""
    for k in range(3):
        h = 3 * t + k
        if cons[h] != 0:
            a = tri[3 * t + _next(k)]
            b = tri[3 * t + _prev(k)]
            if orient2d(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], px, py) == 0.0:
                return h
    return -1


@njit(cache=True)
def link_vertices(tri, ntri, vtri):
    """``vtri[v]`` = some triangle slot of vertex v, for every vertex of the first ntri slots."""
    for t in range(ntri):
        for k in range(3):
            v = tri[3 * t + k]
            if v >= 0:
                vtri[v] = t


# ------------------------------------------------------------------ segment recovery
@njit(cache=True)
def _twin(h, nbr):
    """The opposite half-edge of h."""
    t = h // 3
    n = nbr[h]
    return 3 * n + (0 if nbr[3 * n] == t else (1 if nbr[3 * n + 1] == t else 2))


@njit(cache=True)
def flip(h, tri, nbr, cons, vtri):
    """Flip the edge of half-edge h (two finite triangles forming a strictly convex quad)::

              p                       p
             / \\                     /|\\
          B /   \\ A                B / | \\ A
           /  t  \\                  /  |  \\
          u ----- w      ----->     u t | n w
           \\  n  /                  \\  |  /
          C \\   / D                C \\ | / D
             \\ /                     \\|/
              q                       q

    t = (p, u, w) with h = u -> w, n = (q, w, u); afterwards t = (p, u, q), n = (q, w, p).
    Constraint flags travel with the outer edges A-D; ``vtri`` stays exact.
    """
    t = h // 3
    k = h - 3 * t
    n = nbr[h]
    j = 0 if nbr[3 * n] == t else (1 if nbr[3 * n + 1] == t else 2)
    p = tri[3 * t + k]
    u = tri[3 * t + _next(k)]
    w = tri[3 * t + _prev(k)]
    q = tri[3 * n + j]
    ea = nbr[3 * t + _next(k)]  # across w-p
    eb = nbr[3 * t + _prev(k)]  # across p-u
    ec = nbr[3 * n + _next(j)]  # across u-q
    ed = nbr[3 * n + _prev(j)]  # across q-w
    ca = cons[3 * t + _next(k)]
    cb = cons[3 * t + _prev(k)]
    cc = cons[3 * n + _next(j)]
    cd = cons[3 * n + _prev(j)]
    tri[3 * t] = p
    tri[3 * t + 1] = u
    tri[3 * t + 2] = q
    nbr[3 * t] = ec
    nbr[3 * t + 1] = n
    nbr[3 * t + 2] = eb
    cons[3 * t] = cc
    cons[3 * t + 1] = 0
    cons[3 * t + 2] = cb
    tri[3 * n] = q
    tri[3 * n + 1] = w
    tri[3 * n + 2] = p
    nbr[3 * n] = ea
    nbr[3 * n + 1] = t
    nbr[3 * n + 2] = ed
    cons[3 * n] = ca
    cons[3 * n + 1] = 0
    cons[3 * n + 2] = cd
    for m in range(3):
        if nbr[3 * ec + m] == n:
            nbr[3 * ec + m] = t
        if nbr[3 * ea + m] == t:
            nbr[3 * ea + m] = n
    vtri[p] = t
    vtri[u] = t
    vtri[q] = t
    vtri[w] = n


@njit(inline="always")
def _ahead(pts, a, b, c):
    """Whether c, collinear with a and b, lies on the ray from a through b (c != a)."""
    if pts[a, 0] != pts[b, 0]:
        return (pts[c, 0] > pts[a, 0]) == (pts[b, 0] > pts[a, 0])
    return (pts[c, 1] > pts[a, 1]) == (pts[b, 1] > pts[a, 1])


@njit(cache=True)
def _crossings(a, b, pts, tri, nbr, cons, vtri, elist):
    """Trace segment a -> b through the triangulation.

    Returns
    -------
    (int, int, int)
        ``(0, 0, 0)`` when ab is an edge; ``(1, r, ne)`` when the segment runs into vertex r,
        with the ``ne`` edges it crosses before r in ``elist`` as (left, right) pairs;
        ``(2, 0, ne)`` when it reaches b; ``(3, h, ne)`` when it crosses constrained half-edge h.
    """
    t = vtri[a]
    start = t
    while True:
        i = _index(tri, t, a)
        c = tri[3 * t + _next(i)]
        d = tri[3 * t + _prev(i)]
        if c == b or d == b:
            return 0, 0, 0
        if c >= 0 and d >= 0:
            oc = orient2d(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[c, 0], pts[c, 1])
            od = orient2d(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[d, 0], pts[d, 1])
            if oc == 0.0 and _ahead(pts, a, b, c):
                return 1, c, 0
            if od == 0.0 and _ahead(pts, a, b, d):
                return 1, d, 0
            if oc < 0.0 and od > 0.0:
                break
        t = nbr[3 * t + _next(i)]
        if t == start:
            return 3, -1, 0
    left = d
    right = c
    h = 3 * t + i
    ne = 0
    while True:
        if cons[h] != 0:
            return 3, h, ne
        elist[2 * ne] = left
        elist[2 * ne + 1] = right
        ne += 1
        n = nbr[h]
        j = 0 if nbr[3 * n] == t else (1 if nbr[3 * n + 1] == t else 2)
        r = tri[3 * n + j]
        if r == b:
            return 2, 0, ne
        o = orient2d(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[r, 0], pts[r, 1])
        if o == 0.0:
            return 1, r, ne
        if o > 0.0:
            h = 3 * n + _index(tri, n, left)
            left = r
        else:
            h = 3 * n + _index(tri, n, right)
            right = r
        t = n


@njit(cache=True)
def _sloan(a, b, ne, pts, tri, nbr, cons, rank, vtri, elist, nlist):
    """Make ab an edge by flipping the ``ne`` crossing edges, then restore Delaunay.

    S. W. Sloan, "A fast algorithm for generating constrained Delaunay triangulations",
    Computers & Structures 47(3), 1993: a crossing edge whose quad is strictly convex is
    flipped (the new diagonal is queued again if it still crosses ab, else recorded as new);
    otherwise it goes to the back of the queue.  Then every new edge that is not locally
    Delaunay (exact ``incircle_sos``) is flipped until none is.
    """
    head = 0
    cnt = ne
    nn = 0
    while cnt > 0:
        u = elist[2 * head]
        w = elist[2 * head + 1]
        head = head + 1 if head + 1 < ne else 0
        cnt -= 1
        h = edge_of(u, w, tri, nbr, vtri)
        t = h // 3
        p = tri[h]
        n = nbr[h]
        q = tri[3 * n + (0 if nbr[3 * n] == t else (1 if nbr[3 * n + 1] == t else 2))]
        ou = orient2d(pts[p, 0], pts[p, 1], pts[q, 0], pts[q, 1], pts[u, 0], pts[u, 1])
        ow = orient2d(pts[p, 0], pts[p, 1], pts[q, 0], pts[q, 1], pts[w, 0], pts[w, 1])
        tail = head + cnt if head + cnt < ne else head + cnt - ne
        if (ou > 0.0 and ow < 0.0) or (ou < 0.0 and ow > 0.0):
            flip(h, tri, nbr, cons, vtri)
            crosses = False
            if p != a and p != b and q != a and q != b:
                op = orient2d(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[p, 0], pts[p, 1])
                oq = orient2d(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[q, 0], pts[q, 1])
                crosses = (op > 0.0 and oq < 0.0) or (op < 0.0 and oq > 0.0)
            if crosses:
                elist[2 * tail] = p
                elist[2 * tail + 1] = q
                cnt += 1
            elif not ((p == a and q == b) or (p == b and q == a)):
                nlist[2 * nn] = p
                nlist[2 * nn + 1] = q
                nn += 1
        else:
            elist[2 * tail] = u
            elist[2 * tail + 1] = w
            cnt += 1
    changed = True
    while changed:
        changed = False
        for e in range(nn):
            h = edge_of(nlist[2 * e], nlist[2 * e + 1], tri, nbr, vtri)
            t = h // 3
            n = nbr[h]
            if cons[h] != 0 or tri[3 * t + 2] == GHOST or tri[3 * n + 2] == GHOST:
                continue
            x = tri[3 * t]
            y = tri[3 * t + 1]
            z = tri[3 * t + 2]
            q = tri[3 * n + (0 if nbr[3 * n] == t else (1 if nbr[3 * n + 1] == t else 2))]
            if incircle_sos(
                pts[x, 0], pts[x, 1], pts[y, 0], pts[y, 1], pts[z, 0], pts[z, 1], pts[q, 0], pts[q, 1],
                key_of(rank, x), key_of(rank, y), key_of(rank, z), key_of(rank, q),
            ) > 0:
                p = tri[h]
                flip(h, tri, nbr, cons, vtri)
                nlist[2 * e] = p
                nlist[2 * e + 1] = q
                changed = True


@njit(cache=True)
def recover_segments(pts, tri, nbr, cons, rank, vtri, seg, seg_in, todo, rs, elist, nlist):
    """Recover every queued segment piece as constrained edges (no new vertices).

    ``todo[:rs[1]]`` are pieces (rows of ``seg``) still to recover, ``rs[0]`` pieces in use.
    A piece running exactly through a vertex r is cut there: it becomes (a, r) and the new
    piece (r, b) (same input row ``seg_in``) is queued.  A piece already present as a
    constrained edge of another piece (a duplicate or overlapping segment) keeps the first.

    Returns
    -------
    int
        0 done; 1 the piece table ``seg`` is full (grow it and call again); 2 two segments
        intersect: ``rs[2]`` is the piece being recovered, ``rs[3]`` the crossed constrained
        half-edge (or -1 if the trace failed).
    """
    while rs[1] > 0:
        p = todo[rs[1] - 1]
        a = seg[p, 0]
        b = seg[p, 1]
        kind, r, ne = _crossings(a, b, pts, tri, nbr, cons, vtri, elist)
        if kind == 3:
            rs[2] = p
            rs[3] = r
            return 2
        if kind == 1:
            if rs[0] == seg.shape[0]:
                return 1
            np_ = rs[0]
            seg[np_, 0] = r
            seg[np_, 1] = b
            seg_in[np_] = seg_in[p]
            seg[p, 1] = r
            b = r
            rs[0] = np_ + 1
            todo[rs[1] - 1] = np_
            rs[1] += 1
            todo[rs[1] - 1] = p
        rs[1] -= 1
        if ne > 0:
            _sloan(a, b, ne, pts, tri, nbr, cons, rank, vtri, elist, nlist)
        h = edge_of(a, b, tri, nbr, vtri)
        if cons[h] == 0:
            cons[h] = p + 1
            cons[_twin(h, nbr)] = p + 1
    return 0


@njit(cache=True)
def insert_points(
    xy, i0, out, pts, tri, nbr, cons, circ, rank, meta, work, vmark, vtri, treg, vseg, vpar, vacute,
    seg, pkind, pdat, st,
):
    """Constrained insertion of ``xy[i0:]`` (a point on a subsegment splits it).

    ``out[i]`` receives the vertex of ``xy[i]`` (an existing one for a duplicate).  Returns
    ``(i, status)``: ``R_DONE`` with i = len(xy), or ``R_ROOM`` / ``R_BROKEN`` at point i
    (nothing of point i was inserted).
    """
    for i in range(i0, xy.shape[0]):
        nv = st[S_NV]
        ntri = meta[M_NTRI]
        need = 3 * (ntri + 2)
        if (
            need > tri.shape[0] or need > nbr.shape[0] or need > cons.shape[0] or ntri + 2 > treg.shape[0]
            or nv + 1 > pts.shape[0] or vmark.shape[0] <= pts.shape[0]
            or nv + 1 > min(vtri.shape[0], vseg.shape[0], vpar.shape[0], vacute.shape[0])
        ):
            return i, R_ROOM
        x = xy[i, 0]
        y = xy[i, 1]
        pts[nv, 0] = x
        pts[nv, 1] = y
        t0 = walk(pts, tri, nbr, meta, meta[M_LAST] if meta[M_LAST] < ntri else 0, x, y)
        a = -1
        b = -1
        fl = -1
        fr = -1
        f0 = -1
        piece = -1
        if tri[3 * t0 + 2] != GHOST:
            f0 = treg[t0]
            h = on_constraint(t0, x, y, pts, tri, cons)
            if h >= 0:
                a = tri[3 * t0 + _next(h % 3)]
                b = tri[3 * t0 + _prev(h % 3)]
                fl = treg[t0]
                fr = treg[nbr[h]]
                piece = cons[h] - 1
        tn = insert_vertex(nv, t0, pts, tri, nbr, cons, circ, rank, meta, work, vmark)
        if tn == NEED_SPACE:
            st[S_GROW_WORK] = 1
            return i, R_ROOM
        if tn == BROKEN:
            return i, R_BROKEN
        if tn <= DUP_BASE:
            out[i] = DUP_BASE - tn
            continue
        vseg[nv] = piece
        vacute[nv] = 0
        vpar[nv] = np.nan
        if piece >= 0 and pkind[piece] == KIND_ARC:
            # Angle of the point, on the branch of the piece's end parameters.
            ta = param_of(piece, a, seg, pdat, vpar)
            th = np.arctan2(y - pdat[piece, 1], x - pdat[piece, 0])
            vpar[nv] = ta + (th - ta + np.pi) % (2.0 * np.pi) - np.pi
        st[S_NV] = nv + 1
        set_flags(nv, tn, a, b, fl, fr, f0, tri, nbr, vtri, treg)
        out[i] = nv
    return xy.shape[0], R_DONE


# ------------------------------------------------------------------ queues
@njit(inline="always")
def push_seg(u, w, sq, st):
    q = st[S_QN]
    sq[2 * q] = u
    sq[2 * q + 1] = w
    st[S_QN] = q + 1


@njit(cache=True)
def heap_push(key, t, tri, hk, hp, st):
    """Push triangle t (its vertices for validation) with quality key."""
    i = st[S_HN]
    st[S_HN] = i + 1
    seq = st[S_SEQ]
    st[S_SEQ] = seq + 1
    bucket = min(_BUCKETS - 1, int(key * (_BUCKETS / 0.75)))
    k = (np.int64(bucket) << _SEQ_BITS) | (seq & ((np.int64(1) << _SEQ_BITS) - 1))
    a = tri[3 * t]
    b = tri[3 * t + 1]
    c = tri[3 * t + 2]
    while i > 0:
        par = (i - 1) >> 1
        if hk[par] <= k:
            break
        hk[i] = hk[par]
        for j in range(4):
            hp[4 * i + j] = hp[4 * par + j]
        i = par
    hk[i] = k
    hp[4 * i] = t
    hp[4 * i + 1] = a
    hp[4 * i + 2] = b
    hp[4 * i + 3] = c


@njit(cache=True)
def heap_pop(hk, hp, st, out):
    """Pop the minimum into ``out[0:4]``."""
    n = st[S_HN] - 1
    st[S_HN] = n
    for j in range(4):
        out[j] = hp[j]
    if n == 0:
        return
    k = hk[n]
    i = 0
    while True:
        c = 2 * i + 1
        if c >= n:
            break
        if c + 1 < n and hk[c + 1] < hk[c]:
            c += 1
        if hk[c] >= k:
            break
        hk[i] = hk[c]
        for j in range(4):
            hp[4 * i + j] = hp[4 * c + j]
        i = c
    hk[i] = k
    for j in range(4):
        hp[4 * i + j] = hp[4 * n + j]
