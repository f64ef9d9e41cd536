"""Uniform grids for the paving row check (:mod:`meshwright.quad.paving`, step 7): which
of a row's new edges meet another segment (:func:`grid_crossings`), which of its quads
hold a paving node (:func:`grid_nodes_in_quads`).

:func:`~meshwright.quad._paving_kernel.row_crossings` sweeps the segments sorted along
one axis: on a row around a ring (a disk's, an airfoil's), each query's window held about
forty segments at the same abscissa (the ring's far side among them), of which about one
in four hundred reached the exact test, and the window scan was most of a row's check.  Here each segment is listed in every cell of a uniform grid its bounding box
overlaps, and a query visits the cells its own box overlaps: the same candidates that
can meet it (every segment whose box overlaps the query's), so the answer is the same.

Array layout: ``pts`` (n, 2) float64; segments as two (m,) int64 end arrays ``sa``,
``sb``; queries likewise ``na``, ``nb``; quads (q, 4) int64; node lists (r,) int64.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.predicates import orient2d

__all__ = ["grid_crossings", "grid_nodes_in_quads", "orient_sign", "segments_meet"]

GRID_CELLS = 16  # cells per segment at most (the cells double in side until they fit)
LONG_CELLS = 64  # a segment whose box covers more cells than this is tested by every query instead


@njit
def orient_sign(pts, a, b, c):
    """Sign of the exact ``orient2d`` of nodes a, b, c: 1 left turn, -1 right turn, 0
    collinear."""
    o = orient2d(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[c, 0], pts[c, 1])
    if o > 0.0:
        return 1
    if o < 0.0:
        return -1
    return 0


@njit(inline="always")
def _between(pts, a, b, c):
    """c, collinear with a b, lies on the closed segment a b."""
    return (min(pts[a, 0], pts[b, 0]) <= pts[c, 0] <= max(pts[a, 0], pts[b, 0])) and (
        min(pts[a, 1], pts[b, 1]) <= pts[c, 1] <= max(pts[a, 1], pts[b, 1])
    )


@njit
def segments_meet(pts, a, b, c, d):
    """Closed segments a b and c d share a point (exact)."""
    o1 = orient_sign(pts, a, b, c)
    o2 = orient_sign(pts, a, b, d)
    o3 = orient_sign(pts, c, d, a)
    o4 = orient_sign(pts, c, d, b)
    if o1 * o2 < 0 and o3 * o4 < 0:
        return True
    if o1 == 0 and _between(pts, a, b, c):
        return True
    if o2 == 0 and _between(pts, a, b, d):
        return True
    if o3 == 0 and _between(pts, c, d, a):
        return True
    return o4 == 0 and _between(pts, c, d, b)


@njit(inline="always")
def _cell(v, lo, size, n):
    """Grid column (or row) of coordinate ``v``: monotone in ``v`` (rounding included), so
    two boxes that overlap get index ranges that overlap."""
    return min(n - 1, max(0, int((v - lo) / size)))


@njit(cache=True)
def grid_crossings(pts, na, nb, sa, sb):
    """(k,) bool: which segments ``(na[i], nb[i])`` meet a segment of ``sa, sb`` (closed
    segments, exact) other than one sharing an end node with it; the answer of
    :func:`~meshwright.quad._paving_kernel.row_crossings` on the same arguments.

    The cells are as wide as the queries' mean extent, doubled until there are at most
    :data:`GRID_CELLS` cells per segment; a segment covering more than
    :data:`LONG_CELLS` cells is kept in a list every query scans (with the box test), so
    a few long edges beside many short ones cost neither a crowded grid nor a scan of
    their cells.  A candidate's box test and shared-end test are written out in the
    loops: an inlined helper taking the point and box arrays cost Numba's reference
    counts on every candidate (half of the queries' time).
    """
    m = sa.shape[0]
    k = na.shape[0]
    bad = np.zeros(k, dtype=np.bool_)
    if m == 0 or k == 0:
        return bad
    x0 = np.inf
    x1 = -np.inf
    y0 = np.inf
    y1 = -np.inf
    for j in range(m):
        for v in (sa[j], sb[j]):
            x0 = min(x0, pts[v, 0])
            x1 = max(x1, pts[v, 0])
            y0 = min(y0, pts[v, 1])
            y1 = max(y1, pts[v, 1])
    reach = 0.0
    for i in range(k):
        reach += max(abs(pts[nb[i], 0] - pts[na[i], 0]), abs(pts[nb[i], 1] - pts[na[i], 1]))
    size = reach / k
    if not size > 0.0:
        size = max(x1 - x0, y1 - y0, 1.0)
    # Capped before the conversion: a tiny query over a wide box must not overflow it.
    nx = int(min((x1 - x0) / size, float(m))) + 1
    ny = int(min((y1 - y0) / size, float(m))) + 1
    while nx * ny > GRID_CELLS * m + 16:
        size *= 2.0
        nx = int(min((x1 - x0) / size, float(m))) + 1
        ny = int(min((y1 - y0) / size, float(m))) + 1
    # Counting sort of (cell, segment) entries, the long segments apart; each segment's
    # box kept (a candidate is mostly rejected by it).
    start = np.zeros(nx * ny + 1, dtype=np.int64)
    span = np.empty((m, 4))
    cells = np.empty((m, 4), dtype=np.int64)
    long = np.empty(m, dtype=np.int64)
    nlong = 0
    for j in range(m):
        ua = sa[j]
        ub = sb[j]
        span[j, 0] = min(pts[ua, 0], pts[ub, 0])
        span[j, 1] = max(pts[ua, 0], pts[ub, 0])
        span[j, 2] = min(pts[ua, 1], pts[ub, 1])
        span[j, 3] = max(pts[ua, 1], pts[ub, 1])
        i0 = _cell(span[j, 0], x0, size, nx)
        i1 = _cell(span[j, 1], x0, size, nx)
        j0 = _cell(span[j, 2], y0, size, ny)
        j1 = _cell(span[j, 3], y0, size, ny)
        cells[j, 0], cells[j, 1], cells[j, 2], cells[j, 3] = i0, i1, j0, j1
        if (i1 - i0 + 1) * (j1 - j0 + 1) > LONG_CELLS:
            long[nlong] = j
            nlong += 1
            continue
        for cj in range(j0, j1 + 1):
            for ci in range(i0, i1 + 1):
                start[cj * nx + ci + 1] += 1
    for c in range(nx * ny):
        start[c + 1] += start[c]
    fill = start[:-1].copy()
    items = np.empty(start[nx * ny], dtype=np.int64)
    for j in range(m):
        i0, i1, j0, j1 = cells[j, 0], cells[j, 1], cells[j, 2], cells[j, 3]
        if (i1 - i0 + 1) * (j1 - j0 + 1) > LONG_CELLS:
            continue
        for cj in range(j0, j1 + 1):
            for ci in range(i0, i1 + 1):
                c = cj * nx + ci
                items[fill[c]] = j
                fill[c] += 1
    # A segment listed in several cells of one query is tested once (a stamp per query).
    stamp = np.full(m, -1, dtype=np.int64)
    for i in range(k):
        a = na[i]
        b = nb[i]
        qx0 = min(pts[a, 0], pts[b, 0])
        qx1 = max(pts[a, 0], pts[b, 0])
        qy0 = min(pts[a, 1], pts[b, 1])
        qy1 = max(pts[a, 1], pts[b, 1])
        hit = False
        for s in range(nlong):
            j = long[s]
            if span[j, 1] < qx0 or span[j, 0] > qx1 or span[j, 3] < qy0 or span[j, 2] > qy1:
                continue
            u = sa[j]
            d = sb[j]
            if u == a or u == b or d == a or d == b:
                continue
            if segments_meet(pts, a, b, u, d):
                hit = True
                break
        i0 = _cell(qx0, x0, size, nx)
        i1 = _cell(qx1, x0, size, nx)
        cj = _cell(qy0, y0, size, ny)
        j1 = _cell(qy1, y0, size, ny)
        while not hit and cj <= j1:
            for ci in range(i0, i1 + 1):
                c = cj * nx + ci
                for s in range(start[c], start[c + 1]):
                    j = items[s]
                    if stamp[j] == i:
                        continue
                    stamp[j] = i
                    if span[j, 1] < qx0 or span[j, 0] > qx1 or span[j, 3] < qy0 or span[j, 2] > qy1:
                        continue
                    u = sa[j]
                    d = sb[j]
                    if u == a or u == b or d == a or d == b:
                        continue
                    if segments_meet(pts, a, b, u, d):
                        hit = True
                        break
                if hit:
                    break
            cj += 1
        bad[i] = hit
    return bad


@njit(cache=True)
def grid_nodes_in_quads(pts, quads, nodes):
    """(q,) bool: which quads (convex, counter-clockwise) hold one of ``nodes`` inside or
    on their boundary, the node not being one of their corners (exact ``orient2d``).

    The nodes are counted into a uniform grid of their box (cells as wide as the quads'
    mean extent, doubled until there are at most four cells per node) and each quad
    visits the cells its box overlaps: every node in its box, as the sorted sweep this
    replaced found them, without that sweep's sort (half its time on a row's check).
    """
    m = nodes.shape[0]
    nq = quads.shape[0]
    bad = np.zeros(nq, dtype=np.bool_)
    if m == 0 or nq == 0:
        return bad
    x0 = np.inf
    x1 = -np.inf
    y0 = np.inf
    y1 = -np.inf
    for j in range(m):
        v = nodes[j]
        x0 = min(x0, pts[v, 0])
        x1 = max(x1, pts[v, 0])
        y0 = min(y0, pts[v, 1])
        y1 = max(y1, pts[v, 1])
    reach = 0.0
    for q in range(nq):
        a0 = np.inf
        a1 = -np.inf
        b0 = np.inf
        b1 = -np.inf
        for k in range(4):
            v = quads[q, k]
            a0 = min(a0, pts[v, 0])
            a1 = max(a1, pts[v, 0])
            b0 = min(b0, pts[v, 1])
            b1 = max(b1, pts[v, 1])
        reach += max(a1 - a0, b1 - b0)
    size = reach / nq
    if not size > 0.0:
        size = max(x1 - x0, y1 - y0, 1.0)
    nx = int(min((x1 - x0) / size, float(m))) + 1
    ny = int(min((y1 - y0) / size, float(m))) + 1
    while nx * ny > 4 * m + 16:
        size *= 2.0
        nx = int(min((x1 - x0) / size, float(m))) + 1
        ny = int(min((y1 - y0) / size, float(m))) + 1
    start = np.zeros(nx * ny + 1, dtype=np.int64)
    cell = np.empty(m, dtype=np.int64)
    for j in range(m):
        v = nodes[j]
        c = _cell(pts[v, 1], y0, size, ny) * nx + _cell(pts[v, 0], x0, size, nx)
        cell[j] = c
        start[c + 1] += 1
    for c in range(nx * ny):
        start[c + 1] += start[c]
    fill = start[:-1].copy()
    items = np.empty(m, dtype=np.int64)
    for j in range(m):
        items[fill[cell[j]]] = nodes[j]
        fill[cell[j]] += 1
    for q in range(nq):
        a0 = np.inf
        a1 = -np.inf
        b0 = np.inf
        b1 = -np.inf
        for k in range(4):
            v = quads[q, k]
            a0 = min(a0, pts[v, 0])
            a1 = max(a1, pts[v, 0])
            b0 = min(b0, pts[v, 1])
            b1 = max(b1, pts[v, 1])
        i0 = _cell(a0, x0, size, nx)
        i1 = _cell(a1, x0, size, nx)
        j0 = _cell(b0, y0, size, ny)
        j1 = _cell(b1, y0, size, ny)
        hit = False
        for cj in range(j0, j1 + 1):
            for ci in range(i0, i1 + 1):
                c = cj * nx + ci
                for s in range(start[c], start[c + 1]):
                    v = items[s]
                    if pts[v, 0] < a0 or pts[v, 0] > a1 or pts[v, 1] < b0 or pts[v, 1] > b1:
                        continue
                    if v == quads[q, 0] or v == quads[q, 1] or v == quads[q, 2] or v == quads[q, 3]:
                        continue
                    inside = True
                    for e in range(4):
                        if orient_sign(pts, quads[q, e], quads[q, (e + 1) % 4], v) < 0:
                            inside = False
                            break
                    if inside:
                        hit = True
                        break
                if hit:
                    break
            if hit:
                break
        bad[q] = hit
    return bad
