"""Numba kernels behind geometry validation: segment intersection and point-in-polygon.

Every topological decision goes through :func:`meshwright.core.predicates.orient2d`
(exact sign) or exact coordinate comparisons, so a valid input is never rejected and an
invalid one never accepted because of rounding.

* :func:`find_bad_pairs` reports segments that intersect other than by sharing an endpoint
  (crossing, touching, overlapping, duplicate).  Candidate pairs share a cell of a sparse
  uniform grid (cells keyed and sorted, each segment registered in the cells it passes
  through), so loops of 1e5 segments cost near-linear time instead of the O(m^2)
  all-pairs test.
* :func:`classify_points` is crossing-number ray casting (the ray to +x, half-open rule on
  y) with horizontal bands to select candidate segments; it also detects points lying on a
  segment.
* :func:`parity_by_label` is the brute-force per-label parity used for few queries against
  many labelled polygons (face classification when reading ``.poly`` files).

Reference: J. O'Rourke, *Computational Geometry in C*, 2nd ed., Cambridge University Press,
1998, sections 1.5 (segment intersection) and 7.4 (point in polygon).
"""

from __future__ import annotations

import numba as nb
import numpy as np

from meshwright.core.predicates import orient2d

__all__ = [
    "find_bad_pairs",
    "classify_points",
    "parity_by_label",
    "nearest_segment",
    "trace_chains",
]

OUTSIDE = 0
INSIDE = 1
ON_BOUNDARY = 2


@nb.njit(cache=True)
def _same_direction(sx, sy, ux, uy, vx, vy):
    """Whether collinear u and v lie on the same side of s (exact: only comparisons)."""
    if ux != sx:
        return (ux > sx) == (vx > sx) and vx != sx
    return (uy > sy) == (vy > sy) and vy != sy


@nb.njit(cache=True)
def _overlap_1d(a0, a1, b0, b1):
    lo_a = min(a0, a1)
    hi_a = max(a0, a1)
    lo_b = min(b0, b1)
    hi_b = max(b0, b1)
    return lo_a <= hi_b and lo_b <= hi_a


@nb.njit(cache=True)
def _pair_is_bad(x, y, a, b, c, d):
    """Whether segments (a, b) and (c, d) (vertex indices) meet other than at a shared end."""
    if (a == c and b == d) or (a == d and b == c):
        return True
    if a == c or a == d or b == c or b == d:
        if a == c:
            s, u, v = a, b, d
        elif a == d:
            s, u, v = a, b, c
        elif b == c:
            s, u, v = b, a, d
        else:
            s, u, v = b, a, c
        # Adjacent segments only conflict when they fold back onto each other.
        if orient2d(x[s], y[s], x[u], y[u], x[v], y[v]) != 0.0:
            return False
        return _same_direction(x[s], y[s], x[u], y[u], x[v], y[v])
    o1 = orient2d(x[a], y[a], x[b], y[b], x[c], y[c])
    o2 = orient2d(x[a], y[a], x[b], y[b], x[d], y[d])
    if (o1 > 0.0 and o2 > 0.0) or (o1 < 0.0 and o2 < 0.0):
        return False
    o3 = orient2d(x[c], y[c], x[d], y[d], x[a], y[a])
    o4 = orient2d(x[c], y[c], x[d], y[d], x[b], y[b])
    if (o3 > 0.0 and o4 > 0.0) or (o3 < 0.0 and o4 < 0.0):
        return False
    if o1 == 0.0 and o2 == 0.0:
        # Collinear: they meet iff their projections on both axes overlap.
        return _overlap_1d(x[a], x[b], x[c], x[d]) and _overlap_1d(y[a], y[b], y[c], y[d])
    return True


@nb.njit(cache=True)
def _cell(v, vmin, w, g):
    k = int((v - vmin) / w)
    return min(max(k, 0), g - 1)


@nb.njit(cache=True)
def _supercover(ax, ay, bx, by, x0, y0, w, nx, ny, keys, pos):
    """Write the keys ``i * ny + j`` of the cells the segment passes through at ``pos``.

    The per-column y range is widened by far more than its rounding error, so the cell
    holding an intersection point is never dropped.  With ``len(keys) == 0`` only counts.
    Returns the next free position.
    """
    if ax > bx:
        ax, ay, bx, by = bx, by, ax, ay
    eps = 1e-12 * (abs(ax) + abs(ay) + abs(bx) + abs(by)) + 1e-9 * w
    i0 = _cell(ax, x0, w, nx)
    i1 = _cell(bx, x0, w, nx)
    for i in range(i0, i1 + 1):
        if bx == ax:
            ylo, yhi = min(ay, by), max(ay, by)
        else:
            xl = max(ax, x0 + i * w)
            xr = min(bx, x0 + (i + 1) * w)
            yl = ay + (xl - ax) / (bx - ax) * (by - ay)
            yr = ay + (xr - ax) / (bx - ax) * (by - ay)
            ylo, yhi = min(yl, yr), max(yl, yr)
        j0 = _cell(ylo - eps, y0, w, ny)
        j1 = _cell(yhi + eps, y0, w, ny)
        for j in range(j0, j1 + 1):
            if len(keys):
                keys[pos] = i * ny + j
            pos += 1
    return pos


@nb.njit(cache=True)
def _register(points, segments):
    """Grid cell keys of every segment (sparse grid, cells about one segment long).

    Returns ``keys`` and ``owner`` (the segment of each key), both (r,) int64.
    """
    m = segments.shape[0]
    x = points[:, 0]
    y = points[:, 1]
    xmin, ymin = np.inf, np.inf
    xmax, ymax = -np.inf, -np.inf
    total = 0.0
    for s in range(m):
        a = segments[s, 0]
        b = segments[s, 1]
        total += np.hypot(x[b] - x[a], y[b] - y[a])
        xmin = min(xmin, x[a], x[b])
        xmax = max(xmax, x[a], x[b])
        ymin = min(ymin, y[a], y[b])
        ymax = max(ymax, y[a], y[b])
    ext = max(xmax - xmin, ymax - ymin)
    # Cells about one segment long (no larger than the mean area per segment, for dense
    # inputs of long segments), at most 2^20 per axis.
    w = max(min(total / m, np.sqrt((xmax - xmin) * (ymax - ymin) / m)), ext * 2.0**-20)
    if not w > 0.0:
        w = 1.0
    nx = int((xmax - xmin) / w) + 1
    ny = int((ymax - ymin) / w) + 1
    empty = np.empty(0, dtype=np.int64)
    count = np.int64(0)
    for s in range(m):
        a, b = segments[s, 0], segments[s, 1]
        count = _supercover(x[a], y[a], x[b], y[b], xmin, ymin, w, nx, ny, empty, count)
    keys = np.empty(count, dtype=np.int64)
    owner = np.empty(count, dtype=np.int64)
    pos = np.int64(0)
    for s in range(m):
        a, b = segments[s, 0], segments[s, 1]
        nxt = _supercover(x[a], y[a], x[b], y[b], xmin, ymin, w, nx, ny, keys, pos)
        owner[pos:nxt] = s
        pos = nxt
    return keys, owner


@nb.njit(cache=True)
def _test_cells(points, segments, keys, owner, max_pairs):
    """Test the segment pairs sharing a cell; ``keys`` sorted, ``owner`` in the same order."""
    x = points[:, 0]
    y = points[:, 1]
    out = np.empty((max(max_pairs, 1), 2), dtype=np.int64)
    count = keys.shape[0]
    found = 0
    lo = 0
    while lo < count:
        hi = lo + 1
        while hi < count and keys[hi] == keys[lo]:
            hi += 1
        for p in range(lo, hi):
            s = owner[p]
            for q in range(p + 1, hi):
                t = owner[q]
                if s == t:
                    continue
                if _pair_is_bad(
                    x, y, segments[s, 0], segments[s, 1], segments[t, 0], segments[t, 1]
                ):
                    i, j = min(s, t), max(s, t)
                    seen = False
                    for k in range(found):
                        if out[k, 0] == i and out[k, 1] == j:
                            seen = True
                    if not seen:
                        out[found, 0] = i
                        out[found, 1] = j
                        found += 1
                        if found == max_pairs:
                            return out[:found]
        lo = hi
    return out[:found]


def find_bad_pairs(points: np.ndarray, segments: np.ndarray, max_pairs: int) -> np.ndarray:
    """Find pairs of segments that cross, touch, overlap or duplicate each other.

    Candidates share a cell of a sparse uniform grid whose cell size is the mean segment
    length; each segment is registered in the cells it passes through (not its bounding
    box), so the work is near-linear for boundary-like inputs of any shape.  The keys are
    sorted by NumPy (numba's own sort is slow to compile).

    Parameters
    ----------
    points : (n, 2) float64
        Vertex coordinates; coincident vertices must already share one index.
    segments : (m, 2) int64
        Vertex indices of each segment.
    max_pairs : int
        Stop after this many offending pairs.

    Returns
    -------
    (p, 2) int64
        Distinct offending segment index pairs ``(i, j)`` with ``i < j``; empty when valid.
    """
    pts = np.ascontiguousarray(points, dtype=np.float64)
    seg = np.ascontiguousarray(segments, dtype=np.int64)
    if len(seg) < 2:
        return np.zeros((0, 2), dtype=np.int64)
    keys, owner = _register(pts, seg)
    order = np.argsort(keys, kind="stable")
    return _test_cells(pts, seg, keys[order], owner[order], int(max_pairs))


@nb.njit(cache=True)
def _classify_one(px, py, sx0, sy0, sx1, sy1, cand, lo, hi):
    inside = False
    for p in range(lo, hi):
        s = cand[p]
        ax, ay, bx, by = sx0[s], sy0[s], sx1[s], sy1[s]
        if py < min(ay, by) or py > max(ay, by):
            continue
        if px > max(ax, bx):
            continue
        o = orient2d(ax, ay, bx, by, px, py)
        if o == 0.0 and px >= min(ax, bx):
            return ON_BOUNDARY
        if (ay > py) != (by > py):
            if (by > ay and o > 0.0) or (by < ay and o < 0.0):
                inside = not inside
    return INSIDE if inside else OUTSIDE


@nb.njit(cache=True)
def classify_points(query, seg_a, seg_b):
    """Classify points against a set of closed polygons by the crossing-number rule.

    Parameters
    ----------
    query : (k, 2) float64
    seg_a, seg_b : (m, 2) float64
        Segment end points.  The segments together form closed polygons (any orientation);
        a point is inside when a ray from it crosses them an odd number of times.

    Returns
    -------
    (k,) int8
        0 outside, 1 inside, 2 on a segment.
    """
    k = query.shape[0]
    m = seg_a.shape[0]
    out = np.zeros(k, dtype=np.int8)
    if m == 0:
        return out
    sx0 = seg_a[:, 0].copy()
    sy0 = seg_a[:, 1].copy()
    sx1 = seg_b[:, 0].copy()
    sy1 = seg_b[:, 1].copy()
    ymin = min(sy0.min(), sy1.min())
    ymax = max(sy0.max(), sy1.max())
    # About one segment per band for boundary-like inputs, but at most ~8 registrations
    # per segment when segments are long compared with their spacing.
    span = 0.0
    for s in range(m):
        span += abs(sy1[s] - sy0[s])
    nb_ = m if span <= 0.0 else min(m, int(7.0 * m * (ymax - ymin) / span) + 1)
    nb_ = min(max(nb_, 1), 1 << 20)
    w = (ymax - ymin) / nb_
    if w <= 0.0:
        w = 1.0
    start = np.zeros(nb_ + 1, dtype=np.int64)
    for s in range(m):
        b0 = _cell(min(sy0[s], sy1[s]), ymin, w, nb_)
        b1 = _cell(max(sy0[s], sy1[s]), ymin, w, nb_)
        for b in range(b0, b1 + 1):
            start[b + 1] += 1
    for b in range(nb_):
        start[b + 1] += start[b]
    fill = start[:-1].copy()
    cand = np.empty(start[-1], dtype=np.int64)
    for s in range(m):
        b0 = _cell(min(sy0[s], sy1[s]), ymin, w, nb_)
        b1 = _cell(max(sy0[s], sy1[s]), ymin, w, nb_)
        for b in range(b0, b1 + 1):
            cand[fill[b]] = s
            fill[b] += 1
    for i in range(k):
        px = query[i, 0]
        py = query[i, 1]
        if py < ymin or py > ymax:
            continue
        b = _cell(py, ymin, w, nb_)
        out[i] = _classify_one(px, py, sx0, sy0, sx1, sy1, cand, start[b], start[b + 1])
    return out


@nb.njit(cache=True)
def parity_by_label(query, seg_a, seg_b, label, nlabels):
    """Crossing parity of each point with respect to each labelled polygon.

    Parameters
    ----------
    query : (k, 2) float64
    seg_a, seg_b : (m, 2) float64
        Segment end points.
    label : (m,) int64
        Polygon label in ``[0, nlabels)`` of each segment.
    nlabels : int

    Returns
    -------
    (k, nlabels) int8
        1 where the point is strictly inside the polygon, 2 where it lies on one of its
        segments, 0 otherwise.
    """
    k = query.shape[0]
    out = np.zeros((k, nlabels), dtype=np.int8)
    for i in range(k):
        px = query[i, 0]
        py = query[i, 1]
        for s in range(seg_a.shape[0]):
            lab = label[s]
            if out[i, lab] == ON_BOUNDARY:
                continue
            ax, ay, bx, by = seg_a[s, 0], seg_a[s, 1], seg_b[s, 0], seg_b[s, 1]
            if py < min(ay, by) or py > max(ay, by) or px > max(ax, bx):
                continue
            o = orient2d(ax, ay, bx, by, px, py)
            if o == 0.0 and px >= min(ax, bx):
                out[i, lab] = ON_BOUNDARY
            elif (ay > py) != (by > py):
                if (by > ay and o > 0.0) or (by < ay and o < 0.0):
                    out[i, lab] ^= 1
    return out


@nb.njit(cache=True)
def nearest_segment(query, seg_a, seg_b):
    """Index of the nearest segment and the clamped fraction along it, for each point.

    Parameters
    ----------
    query : (k, 2) float64
    seg_a, seg_b : (m, 2) float64
        Segment end points (m >= 1).

    Returns
    -------
    index : (k,) int64
    fraction : (k,) float64
        Position of the closest point on that segment, 0 at ``seg_a``, 1 at ``seg_b``.
    """
    k = query.shape[0]
    idx = np.zeros(k, dtype=np.int64)
    frac = np.zeros(k)
    for i in range(k):
        best = np.inf
        for s in range(seg_a.shape[0]):
            dx = seg_b[s, 0] - seg_a[s, 0]
            dy = seg_b[s, 1] - seg_a[s, 1]
            qx = query[i, 0] - seg_a[s, 0]
            qy = query[i, 1] - seg_a[s, 1]
            ll = dx * dx + dy * dy
            f = 0.0 if ll == 0.0 else min(max((qx * dx + qy * dy) / ll, 0.0), 1.0)
            ex = qx - f * dx
            ey = qy - f * dy
            d = ex * ex + ey * ey
            if d < best:
                best = d
                idx[i] = s
                frac[i] = f
    return idx, frac


@nb.njit(cache=True)
def trace_chains(nv, edges):
    """Split an undirected graph into maximal chains through degree-2 vertices.

    Parameters
    ----------
    nv : int
        Number of vertices.
    edges : (m, 2) int64
        Vertex indices (no self loops).

    Returns
    -------
    vertices : (m + c,) int64
        Chain ``k`` visits ``vertices[offsets[k] + k : offsets[k + 1] + k + 1]``; a closed
        chain repeats its first vertex at the end.
    edge_order : (m,) int64
        Chain ``k`` uses edges ``edge_order[offsets[k]:offsets[k + 1]]``, edge ``j`` of it
        joining its vertices ``j`` and ``j + 1``.
    offsets : (c + 1,) int64
    closed : (c,) bool
    """
    m = edges.shape[0]
    deg = np.zeros(nv + 1, dtype=np.int64)
    for e in range(m):
        deg[edges[e, 0] + 1] += 1
        deg[edges[e, 1] + 1] += 1
    start = np.cumsum(deg)
    fill = start[:-1].copy()
    adj = np.empty(2 * m, dtype=np.int64)
    for e in range(m):
        for k in range(2):
            v = edges[e, k]
            adj[fill[v]] = e
            fill[v] += 1
    used = np.zeros(m, dtype=np.bool_)
    vseq = np.empty(2 * m, dtype=np.int64)
    eseq = np.empty(m, dtype=np.int64)
    offsets = np.zeros(m + 1, dtype=np.int64)
    closed = np.zeros(m, dtype=np.bool_)
    nch = 0
    pv = 0
    pe = 0
    for phase in range(2):
        for s in range(nv if phase == 0 else m):
            if phase == 0:
                v0 = s
                if start[v0 + 1] - start[v0] == 2:
                    continue
            else:
                if used[s]:
                    continue
                v0 = edges[s, 0]
            for k in range(start[v0], start[v0 + 1]):
                e = adj[k]
                if used[e]:
                    continue
                vseq[pv] = v0
                pv += 1
                cur = v0
                while e >= 0:
                    used[e] = True
                    eseq[pe] = e
                    pe += 1
                    cur = edges[e, 1] if edges[e, 0] == cur else edges[e, 0]
                    vseq[pv] = cur
                    pv += 1
                    e = -1
                    if start[cur + 1] - start[cur] == 2:
                        for kk in range(start[cur], start[cur + 1]):
                            if not used[adj[kk]]:
                                e = adj[kk]
                closed[nch] = phase == 1
                nch += 1
                offsets[nch] = pe
                if phase == 1:
                    break
    return vseq[:pv], eseq[:pe], offsets[: nch + 1], closed[:nch]
