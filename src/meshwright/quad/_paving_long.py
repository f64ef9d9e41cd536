"""Closure of long paving boundaries by chords, in one Numba kernel (step 2 / step 7 of
:mod:`meshwright.quad.paving` on thin regions).

:func:`meshwright.quad._paving_close.close_loop` cuts a paving boundary by the best chord
over every pair of its nodes, one chord per Python round: fine for the few dozen nodes
of a closure, cubic on a thin domain whose rows never start (a sliver thinner than its
size keeps its whole boundary, 9,000 to 65,000 nodes in the stress harness's
reproducers, which ran past a minute).  :func:`close_long` keeps the same rules for a
chord (both ends leave at least ``min_angle`` beside it, a score from those angles, the
spacing against the size and the nodes on it, no crossing with any paving-boundary edge
or the part's own, both parts even) with three changes that make it
O(n log n) on a thin region:

* only chords no longer than ``reach`` times the larger size at their ends are
  candidates, found by a window sweep along the part's longer bounding-box axis;
* a part of more than :data:`BALANCED` nodes takes the best chord that leaves at least
  a quarter of its nodes on each side when one passes, else the best that leaves a
  sixteenth (a sliver is cut in halves, not shaved from one end, so every part's work
  is paid about log n times); only parts up to :data:`SHAVE_MAX` nodes take any other
  chord;
* a part that no chord cuts and no template or centre node closes is handed back open
  (the caller fills it as a void) while the other parts still close: a large part
  with no near balanced chord is thick at its own spacing, and a small one is often a
  transition (one edge against three) that no template of one centre node takes;
* template and centre-node quads keep every corner sine at least :data:`SINE_FLOOR`;
* the size on a chord is the mean of the sizes at its ends (nodes a chord adds get the
  size interpolated along it), so the field is asked once, at the boundary's nodes.

Parts of four or six nodes close by the templates of
:func:`~meshwright.quad._paving_close.closure_quads` (one quad; two along a long diagonal
or three around the nodes' mean, the valid one with the best smallest corner sine), a
part of up to ``star_max`` nodes no chord cuts by a centre node (the nodes' mean or the
polygon's centroid, as :func:`~meshwright.quad._paving_close.star_quads`).  Every quad is
strictly convex by exact ``orient2d``; every chord is checked by exact segment tests.

Array layout: points (c, 2) float64 with the loop's nodes first (local ids 0..n-1 in
loop order, region on the left) and room for new nodes after them; sizes (c,) float64;
other edges as (m, 4) float64 rows ``x0, y0, x1, y1``; quads (q, 4) int64 of local ids.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.predicates import orient2d
from meshwright.quad._paving_kernel import corner_min_sine, sweep_axis

__all__ = ["BALANCED", "close_long"]

BALANCED = 24  # parts above this many nodes are cut near their middle when a chord allows
SMALL = 16  # parts up to this many nodes try chords of any length
SHAVE_MAX = 128  # parts up to this many nodes may take a chord that leaves few nodes on one side
# A template or centre-node quad needs every corner sine at least this (about 3 degrees
# from flat): a chord's own nodes are collinear, and a quad with a corner at one of them
# between its chord neighbours passes the exact convexity test by rounding alone; the
# chord refinement and smoothing that follow turned such quads inside out.
SINE_FLOOR = 0.05


@njit
def _side(ax, ay, bx, by, cx, cy):
    o = orient2d(ax, ay, bx, by, cx, cy)
    return 1 if o > 0.0 else (-1 if o < 0.0 else 0)


@njit
def _on(ax, ay, bx, by, cx, cy):
    """c, collinear with a b, lies on the closed segment a b."""
    return min(ax, bx) <= cx <= max(ax, bx) and min(ay, by) <= cy <= max(ay, by)


@njit
def _meet(ax, ay, bx, by, cx, cy, dx, dy):
    """Closed segments a b and c d share a point (exact)."""
    d1 = _side(ax, ay, bx, by, cx, cy)
    d2 = _side(ax, ay, bx, by, dx, dy)
    d3 = _side(cx, cy, dx, dy, ax, ay)
    d4 = _side(cx, cy, dx, dy, bx, by)
    if d1 * d2 < 0 and d3 * d4 < 0:
        return True
    if d1 == 0 and _on(ax, ay, bx, by, cx, cy):
        return True
    if d2 == 0 and _on(ax, ay, bx, by, dx, dy):
        return True
    if d3 == 0 and _on(cx, cy, dx, dy, ax, ay):
        return True
    return d4 == 0 and _on(cx, cy, dx, dy, bx, by)


@njit
def _convex(P, a, b, c, d):
    """Quad a b c d strictly convex and counter-clockwise (exact)."""
    v = (a, b, c, d)
    for k in range(4):
        u = v[(k + 3) % 4]
        w = v[k]
        z = v[(k + 1) % 4]
        if orient2d(P[u, 0], P[u, 1], P[w, 0], P[w, 1], P[z, 0], P[z, 1]) <= 0.0:
            return False
    return True


@njit
def _distinct(g):
    """No node twice in the small part ``g`` (a part pinched at a joint's node is no
    polygon a template or a star may close)."""
    for i in range(g.shape[0]):
        for j in range(i + 1, g.shape[0]):
            if g[i] == g[j]:
                return False
    return True


@njit
def _template(P, H, cnt, g, out, nq):
    """Close a part of four or six nodes (see the module docstring).  Returns (quads
    written, points used) or (-1, cnt) when no template is valid."""
    m = g.shape[0]
    if (m != 4 and m != 6) or not _distinct(g):
        return -1, cnt
    if m == 4:
        if not _convex(P, g[0], g[1], g[2], g[3]) or corner_min_sine(P, g[0], g[1], g[2], g[3]) < SINE_FLOOR:
            return -1, cnt
        out[nq, 0], out[nq, 1], out[nq, 2], out[nq, 3] = g[0], g[1], g[2], g[3]
        return 1, cnt
    best = SINE_FLOOR
    pick = -1
    for s in range(3):
        r0, r1, r2, r3, r4, r5 = g[s], g[s + 1], g[s + 2], g[s + 3], g[(s + 4) % 6], g[(s + 5) % 6]
        if _convex(P, r0, r1, r2, r3) and _convex(P, r3, r4, r5, r0):
            w = min(corner_min_sine(P, r0, r1, r2, r3), corner_min_sine(P, r3, r4, r5, r0))
            if w > best:
                best = w
                pick = s
    c = cnt
    P[c, 0] = 0.0
    P[c, 1] = 0.0
    for i in range(6):
        P[c, 0] += P[g[i], 0] / 6.0
        P[c, 1] += P[g[i], 1] / 6.0
    for s in range(2):
        r0, r1, r2, r3, r4, r5 = g[s], g[s + 1], g[s + 2], g[s + 3], g[s + 4], g[(s + 5) % 6]
        if _convex(P, c, r0, r1, r2) and _convex(P, c, r2, r3, r4) and _convex(P, c, r4, r5, r0):
            w = min(corner_min_sine(P, c, r0, r1, r2), min(corner_min_sine(P, c, r2, r3, r4), corner_min_sine(P, c, r4, r5, r0)))
            if w > best:
                best = w
                pick = 3 + s
    if pick < 0:
        return -1, cnt
    if pick < 3:
        s = pick
        out[nq, 0], out[nq, 1], out[nq, 2], out[nq, 3] = g[s], g[s + 1], g[s + 2], g[s + 3]
        out[nq + 1, 0], out[nq + 1, 1], out[nq + 1, 2], out[nq + 1, 3] = g[s + 3], g[(s + 4) % 6], g[(s + 5) % 6], g[s]
        return 2, cnt
    s = pick - 3
    for j in range(3):
        out[nq + j, 0] = c
        out[nq + j, 1] = g[(s + 2 * j) % 6]
        out[nq + j, 2] = g[(s + 2 * j + 1) % 6]
        out[nq + j, 3] = g[(s + 2 * j + 2) % 6]
    H[c] = 0.0
    for i in range(6):
        H[c] += H[g[i]] / 6.0
    return 3, cnt + 1


@njit
def _star(P, H, cnt, g, out, nq):
    """Close an even part around one centre node (the nodes' mean or the polygon's
    centroid, whichever valid choice has the best smallest corner sine).  Returns
    (quads written, points used) or (-1, cnt)."""
    m = g.shape[0]
    if m % 2 or not _distinct(g):
        return -1, cnt
    mx = 0.0
    my = 0.0
    area = 0.0
    cx = 0.0
    cy = 0.0
    for i in range(m):
        a = g[i]
        b = g[(i + 1) % m]
        mx += P[a, 0] / m
        my += P[a, 1] / m
        cr = P[a, 0] * P[b, 1] - P[b, 0] * P[a, 1]
        area += 0.5 * cr
        cx += (P[a, 0] + P[b, 0]) * cr
        cy += (P[a, 1] + P[b, 1]) * cr
    if area <= 0.0:
        return -1, cnt
    best = SINE_FLOOR
    pick = -1
    c = cnt
    for choice in range(2):
        P[c, 0] = mx if choice == 0 else cx / (6.0 * area)
        P[c, 1] = my if choice == 0 else cy / (6.0 * area)
        for s in range(2):
            ok = True
            w = 1.0
            for j in range(m // 2):
                a = g[(s + 2 * j) % m]
                b = g[(s + 2 * j + 1) % m]
                d = g[(s + 2 * j + 2) % m]
                if not _convex(P, c, a, b, d):
                    ok = False
                    break
                w = min(w, corner_min_sine(P, c, a, b, d))
            if ok and w > best:
                best = w
                pick = 2 * choice + s
    if pick < 0:
        return -1, cnt
    P[c, 0] = mx if pick < 2 else cx / (6.0 * area)
    P[c, 1] = my if pick < 2 else cy / (6.0 * area)
    s = pick % 2
    for j in range(m // 2):
        out[nq + j, 0] = c
        out[nq + j, 1] = g[(s + 2 * j) % m]
        out[nq + j, 2] = g[(s + 2 * j + 1) % m]
        out[nq + j, 3] = g[(s + 2 * j + 2) % m]
    H[c] = 0.0
    for i in range(m):
        H[c] += H[g[i]] / m
    return m // 2, cnt + 1


@njit
def _clear(P, a, b, g, other):
    """Segment a b meets no edge of part ``g`` other than those at a or b, and no edge
    of ``other`` (exact)."""
    ax, ay, bx, by = P[a, 0], P[a, 1], P[b, 0], P[b, 1]
    x0, x1 = min(ax, bx), max(ax, bx)
    y0, y1 = min(ay, by), max(ay, by)
    m = g.shape[0]
    for i in range(m):
        c = g[i]
        d = g[(i + 1) % m]
        if c == a or c == b or d == a or d == b:
            continue
        cx, cy, dx, dy = P[c, 0], P[c, 1], P[d, 0], P[d, 1]
        if max(cx, dx) < x0 or min(cx, dx) > x1 or max(cy, dy) < y0 or min(cy, dy) > y1:
            continue
        if _meet(ax, ay, bx, by, cx, cy, dx, dy):
            return False
    for i in range(other.shape[0]):
        cx, cy, dx, dy = other[i, 0], other[i, 1], other[i, 2], other[i, 3]
        if max(cx, dx) < x0 or min(cx, dx) > x1 or max(cy, dy) < y0 or min(cy, dy) > y1:
            continue
        if _meet(ax, ay, bx, by, cx, cy, dx, dy):
            return False
    return True


@njit
def _chord_nodes(P, H, cnt, a, b, k):
    """Write the ``k`` nodes evenly spaced on the chord from ``a`` to ``b`` at
    ``P[cnt:cnt + k]``, their sizes interpolated along it at ``H[cnt:cnt + k]``."""
    for t in range(k):
        f = (t + 1) / (k + 1)
        P[cnt + t, 0] = P[a, 0] + f * (P[b, 0] - P[a, 0])
        P[cnt + t, 1] = P[a, 1] + f * (P[b, 1] - P[a, 1])
        H[cnt + t] = H[a] + f * (H[b] - H[a])


@njit
def _write_part(g, i, j, k, cnt, second, out, at):
    """Write one of the two parts that the chord from ``g[i]`` to ``g[j]`` (i < j) with
    ``k`` nodes numbered from ``cnt`` (from ``g[i]``'s end) leaves, region on the left,
    to ``out[at:]``; returns the position after it.  The first part is ``g[i..j]`` and
    the chord back from ``g[j]`` to ``g[i]``, the second ``g[j..]``, ``g[..i]`` and the
    chord from ``g[i]`` to ``g[j]``."""
    w = at
    if not second:
        for t in range(i, j + 1):
            out[w] = g[t]
            w += 1
        for t in range(k - 1, -1, -1):
            out[w] = cnt + t
            w += 1
        return w
    for t in range(j, g.shape[0]):
        out[w] = g[t]
        w += 1
    for t in range(0, i + 1):
        out[w] = g[t]
        w += 1
    for t in range(k):
        out[w] = cnt + t
        w += 1
    return w


@njit
def _parts_close(P, H, cnt, g, i, j, k, scratch):
    """Whether the parts of six nodes or fewer that the chord from ``g[i]`` to ``g[j]``
    with ``k`` nodes leaves take a template (written as scratch from ``P[cnt]``): a cut
    that leaves a part no template closes is not taken while another is left."""
    m = g.shape[0]
    sizes = (j - i + 1 + k, m - (j - i) + 1 + k)
    if sizes[0] > 6 and sizes[1] > 6:
        return True
    _chord_nodes(P, H, cnt, g[i], g[j], k)
    part = np.empty(6, dtype=np.int64)
    for second in range(2):
        if sizes[second] <= 6:
            _write_part(g, i, j, k, cnt, second == 1, part, 0)
            if _template(P, H, cnt + k, part[: sizes[second]], scratch, 0)[0] < 0:
                return False
    return True


@njit
def _angles(P, g):
    """Interior angle (degrees, (0, 360]) and direction of the edge to the next node
    (degrees) at every node of part ``g``."""
    m = g.shape[0]
    ang = np.empty(m)
    th = np.empty(m)
    for i in range(m):
        a = g[i]
        nx_ = P[g[(i + 1) % m], 0] - P[a, 0]
        ny_ = P[g[(i + 1) % m], 1] - P[a, 1]
        px = P[g[(i - 1) % m], 0] - P[a, 0]
        py = P[g[(i - 1) % m], 1] - P[a, 1]
        t = np.arctan2(nx_ * py - ny_ * px, nx_ * px + ny_ * py)
        if t <= 0.0:
            t += 2.0 * np.pi
        ang[i] = np.degrees(t)
        th[i] = np.degrees(np.arctan2(ny_, nx_))
    return ang, th


@njit
def _end_split(dx, dy, th, ang):
    """The smaller angle beside a chord leaving in direction dx, dy at a node whose
    next edge points at ``th`` degrees and whose interior angle is ``ang``."""
    a = np.degrees(np.arctan2(dy, dx)) - th
    # a % 360.0 (Python's sign rule) without the library call on the usual range.
    if -360.0 < a < 360.0:
        a = a + 360.0 if a < 0.0 else a + 0.0
    else:
        a = a % 360.0
    return min(a, ang - a)


@njit
def _split(dx, dy, th_i, ang_i, th_j, ang_j, min_angle):
    """The smaller angle that a chord in direction dx, dy leaves beside it at either
    end; the far end is not measured when the near one already leaves less than
    ``min_angle`` (the chord fails either way).  Scalars only: an array argument
    costs two atomic reference counts per call, and this runs for every near pair."""
    si = _end_split(dx, dy, th_i, ang_i)
    if si < min_angle:
        return si
    return min(si, _end_split(-dx, -dy, th_j, ang_j))


@njit(inline="always")
def _score(split, length, h, k):
    return split - 45.0 * abs(length / ((k + 1) * h) - 1.0) - 15.0 * k


@njit
def _pairs(P, H, g, key, order, hs, wide, min_angle, defer, ang, th, ci, cj, ck, cs, cb, dl, dh):
    """Enumerate the chords of part ``g`` no longer than ``wide`` times the larger
    size at their ends, by a window sweep along ``key``.  A chord that leaves at
    least ``min_angle`` beside it is written to ``ci, cj, ck, cs, cb`` (positions,
    nodes on it, score, balance class); with ``defer``, a chord outside class 0 is
    written unmeasured (``cs`` unset, its length and size in ``dl, dh``) after the
    measured ones' room, from the end of the buffers backwards.  Returns (measured,
    deferred, full): full when the buffers filled (with ``defer`` the enumeration is
    then incomplete and must be redone without it)."""
    m = g.shape[0]
    cap = ci.shape[0]
    quarter = m // 4
    sixteenth = m // 16
    nc = 0
    nd = 0
    # A part above SHAVE_MAX nodes never takes a chord outside classes 0 and 1, and a
    # pair whose ends are fewer than a sixteenth of the nodes apart along the part, less
    # the most nodes a chord no longer than ``wide`` sizes gets (k <= 2 wide, h being at
    # least half the larger end size), is of class 2 whatever its length: with
    # ``defer`` it is only counted (``skip``, towards the cap, as it would have been
    # at most once).
    kmax = 2.0 * wide + 1.0
    skip = 0
    for u in range(m):
        i0 = order[u]
        # A pair is found from its end with the larger size (the smaller position on a
        # tie), whose reach bounds the window both ways.
        h0 = hs[u]
        r0 = wide * h0
        lo = key[u] - r0
        hi = key[u] + r0
        # The window's first slot by bisection over the sorted keys: a walk back over
        # the window cost as much as the window itself.
        w = 0
        e = u
        while w < e:
            mid = (w + e) >> 1
            if key[mid] < lo:
                w = mid + 1
            else:
                e = mid
        while w < m and key[w] <= hi:
            if nc + nd + skip >= cap:
                return nc, nd, True
            j0 = order[w]
            hj = hs[w]
            w += 1
            if j0 == i0 or hj > h0 or (hj == h0 and j0 < i0):
                continue
            i = min(i0, j0)
            j = max(i0, j0)
            if j - i < 2 or (i == 0 and j == m - 1) or g[i] == g[j]:
                continue
            if defer and m > SHAVE_MAX and min(j - i + 1, m - (j - i) + 1) + kmax < sixteenth:
                skip += 1
                continue
            dx = P[g[j], 0] - P[g[i], 0]
            dy = P[g[j], 1] - P[g[i], 1]
            length = np.hypot(dx, dy)
            h = 0.5 * (H[g[i]] + H[g[j]])
            if length > wide * max(H[g[i]], H[g[j]]):
                continue
            ideal = length / h - 1.0
            k = max(0, int(np.rint(ideal)))
            if (k % 2) != ((j - i + 1) % 2):
                k = k + 1 if (ideal >= k or k == 0) else k - 1
            inner = min(j - i + 1 + k, m - (j - i) + 1 + k)
            cls = 0 if inner >= quarter else (1 if inner >= sixteenth else 2)
            if defer and cls != 0:
                d = cap - 1 - nd
                ci[d], cj[d], ck[d], cb[d], dl[d], dh[d] = i, j, k, cls, length, h
                nd += 1
                continue
            split = _split(dx, dy, th[i], ang[i], th[j], ang[j], min_angle)
            if split < min_angle:
                continue
            ci[nc], cj[nc], ck[nc], cb[nc] = i, j, k, cls
            cs[nc] = _score(split, length, h, k)
            nc += 1
    return nc, nd, nc + nd + skip >= cap


@njit
def _best_cut(P, H, cnt, g, other, min_angle, reach, tries):
    """The chord of part ``g`` to cut along: (i, j, k) positions in ``g`` (i < j) and
    nodes on the chord, or (-1, -1, -1).  ``P[cnt:]`` is scratch room."""
    m = g.shape[0]
    axis = sweep_axis(P, g, g)
    raw = np.empty(m)
    for i in range(m):
        raw[i] = P[g[i], axis]
    order = np.argsort(raw)
    # Keys and sizes in sweep order, read in sequence by the window.
    key = raw[order]
    hs = np.empty(m)
    for u in range(m):
        hs[u] = H[g[order[u]]]
    ang, th = _angles(P, g)
    cap = 64 * m
    ci = np.empty(cap, dtype=np.int64)
    cj = np.empty(cap, dtype=np.int64)
    ck = np.empty(cap, dtype=np.int64)
    cs = np.empty(cap)
    cb = np.empty(cap, dtype=np.int64)
    dl = np.empty(cap)
    dh = np.empty(cap)
    # A small part no near chord cuts tries every chord, as close_loop does.
    wide = reach if m > SMALL else np.inf
    balanced = m > BALANCED
    # Class 0 (balanced) chords are measured first; the others only when no balanced
    # one holds (most of a sliver's near pairs run along one side and fail the angle
    # test: measuring them was most of the closure's time).  The candidates, their
    # order and the cap are those of measuring every pair: a deferred enumeration that
    # reaches the cap is redone in full.
    nc, nd, full = _pairs(P, H, g, key, order, hs, wide, min_angle, balanced, ang, th, ci, cj, ck, cs, cb, dl, dh)
    if full and balanced:
        nc, nd, full = _pairs(P, H, g, key, order, hs, wide, min_angle, False, ang, th, ci, cj, ck, cs, cb, dl, dh)
    scratch = np.empty((3, 4), dtype=np.int64)
    # Balanced chords first; when the best of them all cross the boundary, those that
    # leave a sixteenth of the nodes on each side, then (parts up to SHAVE_MAX nodes)
    # the others.  A sliver folded into layers (a star squashed flat) has its balanced
    # chords across two or more layers only, each crossing the layers between its ends.
    # A large part with no near chord that leaves a sixteenth on each side is thick at
    # its spacing (no chord reaches across): it is left to the void fill, which costs
    # its area, where shaving a few nodes off per cut cost its length squared (20 s).
    sel = np.empty(max(nc, nd), dtype=np.int64)
    for stage in range((3 if m <= SHAVE_MAX else 2) if balanced else 1):
        ns = 0
        if stage == 0 or not nd:
            for c in range(nc):
                if not balanced or cb[c] == stage:
                    sel[ns] = c
                    ns += 1
        else:
            # The deferred chords of this class, measured now, in enumeration order.
            for t in range(nd):
                d = cap - 1 - t
                if cb[d] != stage:
                    continue
                i, j = ci[d], cj[d]
                dx = P[g[j], 0] - P[g[i], 0]
                dy = P[g[j], 1] - P[g[i], 1]
                split = _split(dx, dy, th[i], ang[i], th[j], ang[j], min_angle)
                if split < min_angle:
                    continue
                cs[d] = _score(split, dl[d], dh[d], ck[d])
                sel[ns] = d
                ns += 1
        # Best score first, the earlier chord on a tie (a stable sort's order), picked
        # one at a time: the first pick usually holds, and sorting every candidate of
        # every part was most of the closure's time.
        for _ in range(min(ns, tries)):
            top = -1
            for t in range(ns):
                if sel[t] >= 0 and (top < 0 or cs[sel[t]] > cs[sel[top]]):
                    top = t
            c = sel[top]
            sel[top] = -1
            if _clear(P, g[ci[c]], g[cj[c]], g, other) and _parts_close(P, H, cnt, g, ci[c], cj[c], ck[c], scratch):
                return ci[c], cj[c], ck[c]
    return -1, -1, -1


@njit
def _keep_open(g, open_ids, open_ptr, n_open):
    """Append part ``g`` to the open parts, the buffers doubled when full.  Returns
    ``(open_ids, open_ptr, n_open)``."""
    at = open_ptr[n_open]
    if at + g.shape[0] > open_ids.shape[0]:
        grown = np.empty(2 * open_ids.shape[0] + g.shape[0], dtype=np.int64)
        grown[:at] = open_ids[:at]
        open_ids = grown
    if n_open + 2 > open_ptr.shape[0]:
        grown_p = np.zeros(2 * open_ptr.shape[0], dtype=np.int64)
        grown_p[: n_open + 1] = open_ptr[: n_open + 1]
        open_ptr = grown_p
    for t in range(g.shape[0]):
        open_ids[at + t] = g[t]
    open_ptr[n_open + 1] = at + g.shape[0]
    return open_ids, open_ptr, n_open + 1


@njit(cache=True)
def close_long(P, H, n, other, min_angle, reach, tries, star_max, max_parts):
    """Close the loop ``P[:n]`` (even, region on the left) by chords and templates, as
    far as they go: a part that no chord cuts and no template or centre node closes is
    handed back open (for the caller's void fill), and the other parts still close.

    Parameters
    ----------
    P : (c, 2) float64
        The loop's nodes in order, then room for new nodes (written in place).
    H : (c,) float64
        The size at the loop's nodes (new nodes' sizes are written in place).
    n : int
        Nodes on the loop.
    other : (m, 4) float64
        Edges no chord may meet (``x0, y0, x1, y1``).
    min_angle : float
        Degrees a chord leaves beside it at least.
    reach : float
        Chords up to this many times the larger size at their ends are tried.
    tries : int
        Best-scored chords tested for crossings per part (balanced ones, then others).
    star_max : int
        Parts up to this many nodes that no chord cuts close around a centre node.
    max_parts : int
        Cap on chords and closures (the parts still to do when it is reached are
        handed back open).

    Returns
    -------
    quads : (q, 4) int64
        Local ids (new nodes from ``n`` on).
    used : int
        Points used in ``P`` (new nodes are ``P[n:used]``).
    open_ids : (r,) int64
        The open parts' local ids, one after another (each region on its left).
    open_ptr : (p + 1,) int64
        Part ``t`` is ``open_ids[open_ptr[t]:open_ptr[t + 1]]``.
    """
    cnt = n
    c_pts = P.shape[0]
    quads = np.empty((n, 4), dtype=np.int64)
    nq = 0
    buf = np.empty(4 * n + 16, dtype=np.int64)
    for i in range(n):
        buf[i] = i
    top = n
    st_s = np.empty(n + 2, dtype=np.int64)
    st_n = np.empty(n + 2, dtype=np.int64)
    st_s[0] = 0
    st_n[0] = n
    depth = 1
    open_ids = np.empty(64, dtype=np.int64)
    open_ptr = np.zeros(8, dtype=np.int64)
    n_open = 0
    for _ in range(max_parts):
        if depth == 0:
            break
        depth -= 1
        g = buf[st_s[depth] : st_s[depth] + st_n[depth]].copy()
        m = g.shape[0]
        if nq + m > quads.shape[0]:
            grown = np.empty((2 * quads.shape[0] + m, 4), dtype=np.int64)
            grown[:nq] = quads[:nq]
            quads = grown
        got = -1
        if m <= 6:
            if m % 2 == 0 and cnt + 1 <= c_pts:
                got, cnt = _template(P, H, cnt, g, quads, nq)
                if got < 0:
                    # Six nodes: a centre at the polygon's centroid may hold where the mean failed.
                    got, cnt = _star(P, H, cnt, g, quads, nq)
        elif cnt + 8 <= c_pts:
            i, j, k = _best_cut(P, H, cnt, g, other, min_angle, reach, tries)
            if i >= 0 and cnt + k <= c_pts and depth + 2 <= st_s.shape[0]:
                _chord_nodes(P, H, cnt, g[i], g[j], k)
                need = (j - i + 1 + k) + (m - (j - i) + 1 + k)
                if top + need > buf.shape[0]:
                    grown_b = np.empty(2 * buf.shape[0] + need, dtype=np.int64)
                    grown_b[:top] = buf[:top]
                    buf = grown_b
                s2 = _write_part(g, i, j, k, cnt, False, buf, top)
                end = _write_part(g, i, j, k, cnt, True, buf, s2)
                cnt += k
                st_s[depth] = top
                st_n[depth] = s2 - top
                st_s[depth + 1] = s2
                st_n[depth + 1] = end - s2
                top = end
                depth += 2
                continue
            if i < 0 and m <= star_max and cnt + 1 <= c_pts:
                got, cnt = _star(P, H, cnt, g, quads, nq)
        if got >= 0:
            nq += got
            continue
        open_ids, open_ptr, n_open = _keep_open(g, open_ids, open_ptr, n_open)
    # Parts still stacked when the cap ran out stay open too.
    for d in range(depth):
        open_ids, open_ptr, n_open = _keep_open(buf[st_s[d] : st_s[d] + st_n[d]], open_ids, open_ptr, n_open)
    return quads[:nq], cnt, open_ids[: open_ptr[n_open]].copy(), open_ptr[: n_open + 1].copy()
