"""Flip kernels and the sliver quality of sliver removal, over flat tetrahedron arrays.

Sources: the chapter's sliver treatment (section 18.1.1, after Cavendish, Field and Frey,
1985); 2-3 / 3-2 flips and edge removal with the ring triangulations tabulated
(Shewchuk, "Two discrete optimization algorithms for the topological improvement of
tetrahedral meshes", 2002; Klingner and Shewchuk, "Aggressive tetrahedral mesh
improvement", IMR 2007).  The vertex moves, which share the quality measure, are in
:mod:`meshwright.tet._moves`.

Layout (:mod:`meshwright.core.flat`): ``tet[4*t + k]`` vertex k of slot t, positively
oriented (exact ``orient3d > 0``); ``nbr[4*t + k]`` the tet across the face opposite
vertex k (-1 = boundary); ``lock[4*t + k]`` 1 when that face may not be removed (a
constrained face, or a face between two regions); ``region[t]`` the region marker of
slot t.  A dead slot has ``tet[4*t] == -1`` and sits on the ``free`` stack.

Invariants kept by every operation: all live tets positive (every new tet is checked
with the exact ``orient3d``), ``nbr`` symmetric, the union of the replaced tets equals
the union of the new ones (so boundary faces, locked faces and region borders are
unchanged), and the minimum quality of the affected tets strictly rises, which orders
the flips so that they cannot cycle.  Quality is the chapter's sliver ratio
``a = r_in / R_circ`` (1/3 for the regular tetrahedron), computed in floating point: it
ranks candidates, it never decides validity.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.flat import TET_FACES, grown
from meshwright.core.predicates import orient3d

__all__ = ["MAX_RING", "all_ratios", "flip_pass", "ring_tables"]

# Largest ring of tets around an edge that edge removal tries (42 triangulations).
MAX_RING = 7
# Local vertex pairs of the six edges of a tet.
_EDGES = np.array([[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]], dtype=np.int64)
# Counter slots of flip_pass / move_pass: flips by kind, then sliver bookkeeping.
C_23, C_RING, C_MOVES, C_REMOVED_FLIP, C_REMOVED_MOVE, C_CREATED, C_WORK = 0, 1, 9, 10, 11, 12, 13
N_COUNTERS = 14  # C_RING + m counts edge removals of ring size m (3..7); C_WORK: move_pass's work


def ring_tables():
    """Every triangulation of a convex m-gon, m = 3 .. MAX_RING, by interval dynamic programming.

    Returns
    -------
    rows : (r, 3) int64
        Triangles (i, j, k), i < j < k, of ring positions; triangulation ``s`` of the
        m-gon is ``rows[start[m] + s*(m-2) : start[m] + (s+1)*(m-2)]``.
    start, count : (MAX_RING + 1,) int64
        First row and number of triangulations (Catalan numbers 1, 2, 5, 14, 42).
    """
    rows: list[tuple[int, int, int]] = []
    start = np.zeros(MAX_RING + 1, np.int64)
    count = np.zeros(MAX_RING + 1, np.int64)
    for m in range(3, MAX_RING + 1):
        table = {(i, i + 1): [[]] for i in range(m - 1)}
        for length in range(2, m):
            for i in range(m - length):
                j = i + length
                table[(i, j)] = [
                    [(i, k, j)] + left + right
                    for k in range(i + 1, j)
                    for left in table[(i, k)]
                    for right in table[(k, j)]
                ]
        start[m] = len(rows)
        count[m] = len(table[(0, m - 1)])
        for triangulation in table[(0, m - 1)]:
            rows.extend(triangulation)
    return np.array(rows, dtype=np.int64), start, count


@njit(inline="always")
def _orient(pts, a, b, c, d):
    return orient3d(
        pts[a, 0], pts[a, 1], pts[a, 2], pts[b, 0], pts[b, 1], pts[b, 2],
        pts[c, 0], pts[c, 1], pts[c, 2], pts[d, 0], pts[d, 1], pts[d, 2],
    )


@njit(inline="always")
def _ratio_xyz(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz):
    """Signed r_in / R_circ of the tet (a, b, c, d); 0 when the float volume or radius is 0."""
    return _ratio_radius(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz)[0]


@njit(inline="always")
def _quality_xyz(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz, bound):
    """The sliver ratio, times ``(B l_min / R)**2 / 2`` when the radius-edge ratio R / l_min
    exceeds ``B = bound[0]`` (> 0; 0: no bound) and ``l_min**2 >= bound[1]``: a flip or move that
    would lift a tet over the refinement's bound counts as making a sliver of it, so the
    sliver stage keeps the bound.  Tets with an edge shorter than the refinement's exemption
    are left out (near acute input angles no bound is reachable, and vertex moves for them
    crawled on: 14 s of a 39 s fuzz case)."""
    q, big_r = _ratio_radius(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz)
    if bound[0] > 0.0 and q > 0.0:
        l2 = min(
            (bx - ax) ** 2 + (by - ay) ** 2 + (bz - az) ** 2,
            (cx - ax) ** 2 + (cy - ay) ** 2 + (cz - az) ** 2,
            (dx - ax) ** 2 + (dy - ay) ** 2 + (dz - az) ** 2,
            (cx - bx) ** 2 + (cy - by) ** 2 + (cz - bz) ** 2,
            (dx - bx) ** 2 + (dy - by) ** 2 + (dz - bz) ** 2,
            (dx - cx) ** 2 + (dy - cy) ** 2 + (dz - cz) ** 2,
        )
        lim = bound[0] * bound[0] * l2
        if big_r * big_r > lim and l2 >= bound[1]:
            q *= 0.5 * lim / (big_r * big_r)
    return q


@njit(inline="always")
def _ratio_radius(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz):
    """``(r_in / R_circ, R_circ)`` of the tet (a, b, c, d), signed; ratio 0 when flat."""
    ux, uy, uz = bx - ax, by - ay, bz - az
    vx, vy, vz = cx - ax, cy - ay, cz - az
    wx, wy, wz = dx - ax, dy - ay, dz - az
    # v x w, w x u, u x v
    p0, p1, p2 = vy * wz - vz * wy, vz * wx - vx * wz, vx * wy - vy * wx
    q0, q1, q2 = wy * uz - wz * uy, wz * ux - wx * uz, wx * uy - wy * ux
    s0, s1, s2 = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
    det = ux * p0 + uy * p1 + uz * p2
    if det == 0.0:
        return 0.0, 0.0
    lu, lv, lw = ux * ux + uy * uy + uz * uz, vx * vx + vy * vy + vz * vz, wx * wx + wy * wy + wz * wz
    inv = 0.5 / det
    ox = (lu * p0 + lv * q0 + lw * s0) * inv
    oy = (lu * p1 + lv * q1 + lw * s1) * inv
    oz = (lu * p2 + lv * q2 + lw * s2) * inv
    big_r = np.sqrt(ox * ox + oy * oy + oz * oz)
    # Face (b, c, d): (c - b) x (d - b) = (v - u) x (w - u).
    ex, ey, ez = vx - ux, vy - uy, vz - uz
    fx, fy, fz = wx - ux, wy - uy, wz - uz
    g0, g1, g2 = ey * fz - ez * fy, ez * fx - ex * fz, ex * fy - ey * fx
    area2 = (
        np.sqrt(p0 * p0 + p1 * p1 + p2 * p2)
        + np.sqrt(q0 * q0 + q1 * q1 + q2 * q2)
        + np.sqrt(s0 * s0 + s1 * s1 + s2 * s2)
        + np.sqrt(g0 * g0 + g1 * g1 + g2 * g2)
    )
    if big_r == 0.0:
        return 0.0, 0.0  # nearly flat and cocircular: the centre's numerator cancelled exactly
    # r = 3 V / S = det / (2 S) = det / area2, with area2 = 2 S.
    return (det / area2) / big_r, big_r


@njit(inline="always")
def _ratio(pts, a, b, c, d, bound):
    return _quality_xyz(
        pts[a, 0], pts[a, 1], pts[a, 2], pts[b, 0], pts[b, 1], pts[b, 2],
        pts[c, 0], pts[c, 1], pts[c, 2], pts[d, 0], pts[d, 1], pts[d, 2], bound,
    )


@njit(inline="always")
def _tet_ratio(pts, tet, t, bound):
    return _ratio(pts, tet[4 * t], tet[4 * t + 1], tet[4 * t + 2], tet[4 * t + 3], bound)


@njit(cache=True)
def all_ratios(pts, tet, ntet, bound):
    """Sliver ratio of every slot, ``inf`` for dead slots.

    Parameters
    ----------
    pts : (n, 3) float64
    tet : (>= 4 ntet,) int32
    ntet : int

    Returns
    -------
    (ntet,) float64
    """
    out = np.empty(ntet)
    for t in range(ntet):
        out[t] = np.inf if tet[4 * t] < 0 else _tet_ratio(pts, tet, t, bound)
    return out


@njit(inline="always")
def _slot_of(tet, t, v):
    for k in range(4):
        if tet[4 * t + k] == v:
            return k
    return -1


@njit(inline="always")
def _back_slot(nbr, u, t):
    for j in range(4):
        if nbr[4 * u + j] == t:
            return j
    return -1


@njit(inline="always")
def _edge_locked(ekeys, nv, a, b):
    if ekeys.shape[0] == 0:
        return False
    key = min(a, b) * nv + max(a, b)
    i = np.searchsorted(ekeys, key)
    return i < ekeys.shape[0] and ekeys[i] == key


@njit(inline="always")
def _sort3(a, b, c):
    if a > b:
        a, b = b, a
    if b > c:
        b, c = c, b
    if a > b:
        a, b = b, a
    return a, b, c


@njit(cache=True)
def _eval_23(pts, tet, nbr, lock, t, k, newv, bound):
    """2-3 flip of slot t across its face k; new tets into ``newv[0:12]``.

    ::

             e                      e
            /|\\                   /|\\
           / | \\                 / | \\
          a--|--c     2 -> 3    a--d--c     face abc goes; edge de comes,
           \\ | /                 \\ | /      three tets around it
            \\|/                   \\|/
             d                      d

    Returns the smaller new sliver ratio, or -inf when the face is on the boundary or
    locked, or segment de does not cross triangle abc (a new tet not positive).
    """
    if lock[4 * t + k] != 0:
        return -np.inf
    u = nbr[4 * t + k]
    if u < 0:
        return -np.inf
    d = tet[4 * t + k]
    a = tet[4 * t + TET_FACES[k, 0]]
    b = tet[4 * t + TET_FACES[k, 1]]
    c = tet[4 * t + TET_FACES[k, 2]]
    e = tet[4 * u + _back_slot(nbr, u, t)]
    # (a, b, c) is t's outward face, so (a, b, c, e) is positive and so is (a, b, d, e).
    worst = np.inf
    for i in range(3):
        x = a if i == 0 else (b if i == 1 else c)
        y = b if i == 0 else (c if i == 1 else a)
        if not _orient(pts, x, y, d, e) > 0.0:
            return -np.inf
        worst = min(worst, _ratio(pts, x, y, d, e, bound))
        newv[4 * i] = x
        newv[4 * i + 1] = y
        newv[4 * i + 2] = d
        newv[4 * i + 3] = e
    return worst


@njit(cache=True)
def _eval_ring(pts, tet, nbr, lock, ekeys, nv, t, i, j, ring, rtets, tq, rows, start, count, bound):
    """Edge removal of the edge (i, j) (local vertices) of slot t.

    Walks the ring of tets around the edge pq into ``rtets`` and its vertices w_0 .. w_m-1
    into ``ring``, oriented so that every (p, q, w_s, w_s+1) is positive; then every
    triangulation of the ring polygon gives 2 (m - 2) tets (w_a, w_b, w_c, q) and
    (w_a, w_c, w_b, p).  m = 3 is the 3-2 flip (the chapter's flip: sliver ABCD with
    neighbours ABDE and BCDE sharing E becomes ABCE, ACDE, edge BD removed), m = 4 the
    4-4 flip.  Seen down the edge from q (x is the edge pq, p below, q above)::

        3-2:        w2                      w2
                   / | \\                    /  \\
                  /  x  \\       ->         /    \\     3 tets (p, q, w_i, w_i+1) become
                 / /   \\ \\                /      \\    2 tets on the triangle w0 w1 w2:
                w0-------w1              w0------w1   (w0, w1, w2, q) and (w0, w2, w1, p)

        4-4:    w3-------w2              w3-------w2
                | \\     / |              |       / |
                |   \\ /   |     ->       |     /   |  4 tets around x become 2 tets on
                |   / x   |              |   /     |  each of the triangles w0 w1 w2 and
                | /     \\ |              | /       |  w0 w2 w3 (or on w0 w1 w3, w1 w2 w3)
                w0-------w1              w0-------w1

    Returns (best smaller new ratio or -inf, ring size m, best triangulation index).
    ``tq[a, b, c]`` is scratch: the worse ratio of the two tets on triangle (a, b, c), or
    -inf when one of them is not positive.
    """
    p = tet[4 * t + i]
    q = tet[4 * t + j]
    if _edge_locked(ekeys, nv, p, q):
        return -np.inf, 0, 0
    r = -1
    s = -1
    for k in range(4):
        if k != i and k != j:
            if r < 0:
                r = k
            else:
                s = k
    # Parity of the permutation (i, j, r, s) of (0, 1, 2, 3), r < s: count inversions.
    inv = int(i > j) + int(i > r) + int(i > s) + int(j > r) + int(j > s)
    w0 = tet[4 * t + r]
    w1 = tet[4 * t + s]
    if inv % 2 == 1:
        w0, w1 = w1, w0
    ring[0] = w0
    ring[1] = w1
    rtets[0] = t
    m = 1
    cur = t
    while True:
        k = _slot_of(tet, cur, ring[m - 1])
        if lock[4 * cur + k] != 0:
            return -np.inf, 0, 0
        nxt = nbr[4 * cur + k]
        if nxt < 0:
            return -np.inf, 0, 0  # boundary edge: its ring is open
        if nxt == t:
            break
        if m == MAX_RING:
            return -np.inf, 0, 0
        rtets[m] = nxt
        w = -1
        for x in range(4):
            v = tet[4 * nxt + x]
            if v != p and v != q and v != ring[m]:
                w = v
        m += 1
        ring[m] = w
        cur = nxt
    if m < 3:
        return -np.inf, 0, 0
    for a in range(m):
        for b in range(a + 1, m):
            for c in range(b + 1, m):
                wa, wb, wc = ring[a], ring[b], ring[c]
                if _orient(pts, wa, wb, wc, q) > 0.0 and _orient(pts, wa, wc, wb, p) > 0.0:
                    tq[a, b, c] = min(_ratio(pts, wa, wb, wc, q, bound), _ratio(pts, wa, wc, wb, p, bound))
                else:
                    tq[a, b, c] = -np.inf
    best = -np.inf
    best_s = 0
    for sidx in range(count[m]):
        worst = np.inf
        base = start[m] + sidx * (m - 2)
        for row in range(base, base + m - 2):
            worst = min(worst, tq[rows[row, 0], rows[row, 1], rows[row, 2]])
        if worst > best:
            best = worst
            best_s = sidx
    return best, m, best_s


@njit(cache=True)
def _replace(tet, nbr, lock, region, old, n_old, newv, n_new, free, nfree, ntet, ext, slots):
    """Replace the live slots ``old[:n_old]`` by the tets ``newv[4 s : 4 s + 4]``, s < n_new.

    The new tets must fill the same polyhedron: each of their faces is either shared by
    two new tets or equal to a face of the old set's boundary, whose neighbour, lock and
    back pointer it takes over.  Slots are reused (old ones first, then the free stack,
    then appended at ``ntet``; the caller guarantees the capacity).

    Returns (nfree, ntet, ok); ok is False when a face matched nothing, which no
    correct flip produces (the arrays are then left inconsistent).
    """
    reg = region[old[0]]
    nx = 0
    for o in range(n_old):
        to = old[o]
        for k in range(4):
            x = nbr[4 * to + k]
            inside = False
            for o2 in range(n_old):
                if old[o2] == x:
                    inside = True
            if inside:
                continue
            f0, f1, f2 = _sort3(
                tet[4 * to + TET_FACES[k, 0]], tet[4 * to + TET_FACES[k, 1]], tet[4 * to + TET_FACES[k, 2]]
            )
            ext[nx, 0] = f0
            ext[nx, 1] = f1
            ext[nx, 2] = f2
            ext[nx, 3] = x
            ext[nx, 4] = _back_slot(nbr, x, to) if x >= 0 else -1
            ext[nx, 5] = lock[4 * to + k]
            nx += 1
    for s in range(n_new):
        if s < n_old:
            slots[s] = old[s]
        elif nfree > 0:
            nfree -= 1
            slots[s] = free[nfree]
        else:
            slots[s] = ntet
            ntet += 1
    for o in range(n_new, n_old):
        dead = old[o]
        for k in range(4):
            tet[4 * dead + k] = -1
            nbr[4 * dead + k] = -1
            lock[4 * dead + k] = 0
        free[nfree] = dead
        nfree += 1
    for s in range(n_new):
        for k in range(4):
            tet[4 * slots[s] + k] = newv[4 * s + k]
        region[slots[s]] = reg
    ok = True
    for s in range(n_new):
        ts = slots[s]
        for k in range(4):
            f0, f1, f2 = _sort3(
                newv[4 * s + TET_FACES[k, 0]], newv[4 * s + TET_FACES[k, 1]], newv[4 * s + TET_FACES[k, 2]]
            )
            found = False
            for s2 in range(n_new):
                if s2 == s:
                    continue
                for k2 in range(4):
                    g0, g1, g2 = _sort3(
                        newv[4 * s2 + TET_FACES[k2, 0]], newv[4 * s2 + TET_FACES[k2, 1]], newv[4 * s2 + TET_FACES[k2, 2]]
                    )
                    if f0 == g0 and f1 == g1 and f2 == g2:
                        nbr[4 * ts + k] = slots[s2]
                        lock[4 * ts + k] = 0
                        found = True
            if found:
                continue
            for e in range(nx):
                if ext[e, 0] == f0 and ext[e, 1] == f1 and ext[e, 2] == f2:
                    x = ext[e, 3]
                    nbr[4 * ts + k] = x
                    lock[4 * ts + k] = ext[e, 5]
                    if x >= 0:
                        nbr[4 * x + ext[e, 4]] = ts
                    found = True
            if not found:
                ok = False
    return nfree, ntet, ok


@njit(cache=True)
def flip_pass(pts, tet, nbr, lock, region, ratios, ntet, free, nfree, cand, threshold, ekeys, nv, rows, start, count, counters, bound):
    """Try to flip every slot of ``cand`` that is still a sliver (ratio < threshold).

    For each, every 2-3 flip across its four faces and every edge removal (ring size
    3 .. MAX_RING) of its six edges is evaluated; the one with the largest smallest new
    ratio is applied if that exceeds the smallest ratio of the tets it replaces.

    Parameters
    ----------
    pts : (n, 3) float64
    tet, nbr : (4 cap,) int32
    lock : (4 cap,) uint8
    region : (cap,) int32
    ratios : (cap,) float64
        :func:`all_ratios` of the slots in use, kept up to date: the new tets of a flip get
        theirs, its dead slots ``inf`` (the same numbers a whole-mesh call gives, without
        one after every pass).
    ntet : int
        Slots in use (live or dead).
    free : (cap,) int64
        Stack of dead slots, ``nfree`` of them.
    cand : (c,) int64
        Slots to try, worst first.
    threshold : float
    ekeys : (e,) int64
        Sorted keys ``min * nv + max`` of edges that may not be removed.
    nv : int
        Number of points.
    rows, start, count : from :func:`ring_tables`
    counters : (N_COUNTERS,) int64
        Incremented: ``C_23``, ``C_RING + m``, and by the net change of the number of
        slivers among the tets a flip replaces, ``C_REMOVED_FLIP`` (fewer) or
        ``C_CREATED`` (more).
    bound : (2,) float64
        Radius-edge bound and squared exempt edge of the quality (:func:`_quality_xyz`).

    Returns
    -------
    tet, nbr, lock, region, ratios, free : the arrays, reallocated when they grew
    ntet, nfree : int
    flips : int
        Flips applied.
    ok : bool
        False on an internal inconsistency (a bug), after which the arrays are invalid.
    """
    newv = np.empty(4 * 2 * (MAX_RING - 2), np.int32)
    ring = np.empty(MAX_RING + 1, np.int64)
    rtets = np.empty(MAX_RING, np.int64)
    old = np.empty(MAX_RING, np.int64)
    tq = np.empty((MAX_RING, MAX_RING, MAX_RING))
    ext = np.empty((4 * MAX_RING, 6), np.int64)
    slots = np.empty(2 * (MAX_RING - 2), np.int64)
    flips = 0
    for ci in range(cand.shape[0]):
        t = cand[ci]
        if tet[4 * t] < 0:
            continue
        q0 = _tet_ratio(pts, tet, t, bound)
        if not q0 < threshold:
            continue
        best = -np.inf
        kind = -1
        arg = 0
        for k in range(4):
            u = nbr[4 * t + k]
            if u < 0:
                continue
            v = _eval_23(pts, tet, nbr, lock, t, k, newv, bound)
            worst_old = min(q0, _tet_ratio(pts, tet, u, bound))
            if v > worst_old and v > best:
                best = v
                kind = 0
                arg = k
        for e in range(6):
            v, m, sidx = _eval_ring(
                pts, tet, nbr, lock, ekeys, nv, t, _EDGES[e, 0], _EDGES[e, 1], ring, rtets, tq, rows, start, count, bound
            )
            if m == 0 or not v > best:
                continue
            worst_old = np.inf
            for o in range(m):
                worst_old = min(worst_old, _tet_ratio(pts, tet, rtets[o], bound))
            if v > worst_old:
                best = v
                kind = 1
                arg = e
        if kind < 0:
            continue
        # Re-evaluate the winner to refill the buffers, then apply it.
        if kind == 0:
            _eval_23(pts, tet, nbr, lock, t, arg, newv, bound)
            old[0] = t
            old[1] = nbr[4 * t + arg]
            n_old = 2
            n_new = 3
        else:
            v, m, sidx = _eval_ring(
                pts, tet, nbr, lock, ekeys, nv, t, _EDGES[arg, 0], _EDGES[arg, 1], ring, rtets, tq, rows, start, count, bound
            )
            p = tet[4 * t + _EDGES[arg, 0]]
            q = tet[4 * t + _EDGES[arg, 1]]
            n_old = m
            n_new = 2 * (m - 2)
            for o in range(m):
                old[o] = rtets[o]
            base = start[m] + sidx * (m - 2)
            for s in range(m - 2):
                wa, wb, wc = ring[rows[base + s, 0]], ring[rows[base + s, 1]], ring[rows[base + s, 2]]
                newv[8 * s] = wa
                newv[8 * s + 1] = wb
                newv[8 * s + 2] = wc
                newv[8 * s + 3] = q
                newv[8 * s + 4] = wa
                newv[8 * s + 5] = wc
                newv[8 * s + 6] = wb
                newv[8 * s + 7] = p
        n_bad = 0
        for o in range(n_old):
            if _tet_ratio(pts, tet, old[o], bound) < threshold:
                n_bad += 1
        for s in range(n_new):
            if _ratio(pts, newv[4 * s], newv[4 * s + 1], newv[4 * s + 2], newv[4 * s + 3], bound) < threshold:
                n_bad -= 1
        counters[C_REMOVED_FLIP] += max(n_bad, 0)
        counters[C_CREATED] += max(-n_bad, 0)
        need = ntet + n_new
        if 4 * need > tet.shape[0]:
            room = max(2 * (tet.shape[0] // 4), need)
            tet = grown(tet, 4 * room)
            nbr = grown(nbr, 4 * room)
            lock = grown(lock, 4 * room)
            region = grown(region, room)
            ratios = grown(ratios, room)
            free = grown(free, room)
        nfree, ntet, ok = _replace(tet, nbr, lock, region, old, n_old, newv, n_new, free, nfree, ntet, ext, slots)
        if not ok:
            return tet, nbr, lock, region, ratios, free, ntet, nfree, flips, False
        for s in range(n_new):
            ratios[slots[s]] = _tet_ratio(pts, tet, slots[s], bound)
        for o in range(n_new, n_old):
            ratios[old[o]] = np.inf
        flips += 1
        if kind == 0:
            counters[C_23] += 1
        else:
            counters[C_RING + n_old] += 1
    return tet, nbr, lock, region, ratios, free, ntet, nfree, flips, True
