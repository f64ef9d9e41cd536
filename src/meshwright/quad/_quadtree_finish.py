"""The quadtree's finish before and after its midpoint split (:mod:`meshwright.quad.quadtree`).

The gap triangulation of a thin wedge (a segment meeting a boundary edge or another
segment at a small angle) is a ladder of slivers whose vertices all lie on the wedge's
two sides: Delaunay refinement cannot split them (their small angles face the input's
own), and the midpoint split keeps each sliver's small angle at a corner whose sides are
not both line cells.  Two steps fix what the input does not force:

* :func:`merge_slivers`, before the split: a triangle whose smallest corner sine is below
  a floor is joined with the neighbour across one of its interior edges when the quad
  they make is strictly convex (exact ``orient2d``) and its smallest corner sine is larger
  than both triangles' (the ladder's rungs become trapezoids).  The split makes quads of
  quads as of triangles, so the fill stays conforming.
* :func:`recentre`, after the split: the centre of a split cell is a corner of the cell's
  sub-quads only, so it moves freely; where the smallest sine of the corners it shapes
  (at itself and at the two edge midpoints beside it) is below a floor, it takes the best
  of a few points between each corner's midpoint pair and the centroid (the tip of a
  wedge: the centroid at two thirds of the height leaves the tip quad's other corners
  near 180 degrees; near the tip's mid-line they are near 120).

Quality rules in floating point (sines), validity by exact predicates.  Array layout:
points (n, 2) float64, triangles (t, 3) and quads (q, 4) int64 counter-clockwise, lines
(k, 2) int64.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.predicates import orient2d_batch

__all__ = ["merge_slivers", "recentre", "CENTRE_STEPS"]

# Fractions of the way from a corner's midpoint pair to the centroid tried by recentre:
# halving down to 2^-20 near the pair, where the tip of a wedge of angle t wants its
# centre (about 0.9 t radians of the way: input corners of 0.003 degrees occur).
CENTRE_STEPS = np.concatenate([2.0 ** -np.arange(20, 0, -1), [3 / 16, 3 / 8, 5 / 8, 3 / 4, 7 / 8]])


@njit(inline="always")
def _sine(ax, ay, bx, by, cx, cy):
    """Sine of the corner at (ax, ay) from the ray to (bx, by) (next, counter-clockwise)
    to the ray to (cx, cy) (previous); -1 with a zero-length side."""
    ux = bx - ax
    uy = by - ay
    wx = cx - ax
    wy = cy - ay
    den = np.sqrt((ux * ux + uy * uy) * (wx * wx + wy * wy))
    return (ux * wy - uy * wx) / den if den > 0.0 else -1.0


@njit(cache=True)
def cell_min_sines(p, cells):
    """(c,) float64: the smallest corner sine of each counter-clockwise cell (3 or 4 columns)."""
    c, k = cells.shape
    out = np.empty(c)
    for i in range(c):
        worst = 1.0
        for j in range(k):
            a = cells[i, j]
            b = cells[i, (j + 1) % k]
            d = cells[i, (j + k - 1) % k]
            worst = min(worst, _sine(p[a, 0], p[a, 1], p[b, 0], p[b, 1], p[d, 0], p[d, 1]))
        out[i] = worst
    return out


@njit(cache=True)
def _greedy(t1, t2, order, n_tri):
    """Candidate pairs in ``order`` taken while neither triangle is taken; (k,) rows."""
    used = np.zeros(n_tri, dtype=np.bool_)
    take = np.empty(order.shape[0], dtype=np.int64)
    m = 0
    for r in order:
        if not used[t1[r]] and not used[t2[r]]:
            used[t1[r]] = True
            used[t2[r]] = True
            take[m] = r
            m += 1
    return take[:m]


def merge_slivers(points, triangles, lines, floor: float):
    """Join triangles below ``floor`` with a neighbour into better quads (module docstring).

    Parameters
    ----------
    points : (n, 2) float64
    triangles : (t, 3) int
        Counter-clockwise.
    lines : (k, 2) int
        Line cells: their edges are never crossed by a merge.
    floor : float
        A triangle whose smallest corner sine is below this looks for a partner.

    Returns
    -------
    quads : (m, 4) int64
        The merged pairs, counter-clockwise and strictly convex.
    triangles : (t - 2 m, 3) int64
        The triangles left, in their order.
    """
    tri = np.ascontiguousarray(triangles, dtype=np.int64)
    sines = cell_min_sines(points, tri)
    bad = sines < floor
    none = np.zeros((0, 4), dtype=np.int64)
    if not bad.any():
        return none, tri
    n = np.int64(len(points))
    a = tri.ravel()
    b = np.roll(tri, -1, axis=1).ravel()
    opp = np.roll(tri, -2, axis=1).ravel()
    owner = np.repeat(np.arange(len(tri)), 3)
    key = np.minimum(a, b) * n + np.maximum(a, b)
    lines = np.asarray(lines, dtype=np.int64).reshape(-1, 2)
    line_key = np.minimum(lines[:, 0], lines[:, 1]) * n + np.maximum(lines[:, 0], lines[:, 1])
    order = np.argsort(key, kind="stable")
    shared = np.flatnonzero(key[order][1:] == key[order][:-1])
    e1, e2 = order[shared], order[shared + 1]
    ok = (bad[owner[e1]] | bad[owner[e2]]) & ~np.isin(key[e1], line_key)
    e1, e2 = e1[ok], e2[ok]
    if not len(e1):
        return none, tri
    # Triangle (a, b, o1) and its neighbour (b, a, o2) make the quad (o1, a, o2, b).
    quads = np.column_stack([opp[e1], a[e1], opp[e2], b[e1]])
    convex = np.ones(len(quads), dtype=bool)
    for k in range(4):
        corner = np.column_stack([quads[:, (k + 3) % 4], quads[:, k], quads[:, (k + 1) % 4]])
        convex &= np.asarray(orient2d_batch(points, np.ascontiguousarray(corner))) > 0
    t1, t2 = owner[e1], owner[e2]
    worst = np.minimum(sines[t1], sines[t2])
    quad_sines = cell_min_sines(points, np.ascontiguousarray(quads))
    cand = np.flatnonzero(convex & (quad_sines > worst))
    if not len(cand):
        return none, tri
    # The worst triangles choose first, each its best partner.
    cand = cand[np.lexsort((-quad_sines[cand], worst[cand]))]
    take = _greedy(t1, t2, cand, len(tri))
    used = np.zeros(len(tri), dtype=bool)
    used[t1[take]] = True
    used[t2[take]] = True
    return quads[take], tri[~used]


@njit(inline="always")
def _centre_value(p, q, idx, lo, hi, x, y):
    """Smallest sine of the corners a centre at (x, y) shapes in sub-quads ``idx[lo:hi]``
    (corner, midpoint, centre, midpoint)."""
    worst = 1.0
    for r in range(lo, hi):
        c = idx[r]
        v = q[c, 0]
        ma = q[c, 1]
        mb = q[c, 3]
        s1 = _sine(p[ma, 0], p[ma, 1], x, y, p[v, 0], p[v, 1])
        s2 = _sine(x, y, p[mb, 0], p[mb, 1], p[ma, 0], p[ma, 1])
        s3 = _sine(p[mb, 0], p[mb, 1], p[v, 0], p[v, 1], x, y)
        worst = min(worst, s1, s2, s3)
    return worst


@njit(cache=True)
def recentre(p, q, first, floor, steps):
    """Move split centres whose corners are below ``floor`` (module docstring), in place.

    Parameters
    ----------
    p : (n, 2) float64
        Points; rows ``first`` on are the split's centres.
    q : (m, 4) int64
        The split's quads (corner, midpoint, centre, midpoint), counter-clockwise.
    first : int
        The first centre.
    floor : float
    steps : (s,) float64
        Fractions of the way from each corner's midpoint pair to the centroid.

    Returns
    -------
    int
        Centres moved; a move only raises the smallest sine of the corners it shapes
        (the cell's own corners do not depend on it), so no sub-quad inverts.
    """
    n = p.shape[0]
    nc = n - first
    ptr = np.zeros(nc + 1, dtype=np.int64)
    for c in range(q.shape[0]):
        if q[c, 2] >= first:
            ptr[q[c, 2] - first + 1] += 1
    for k in range(nc):
        ptr[k + 1] += ptr[k]
    idx = np.empty(ptr[nc], dtype=np.int64)
    fill = ptr[:nc].copy()
    for c in range(q.shape[0]):
        if q[c, 2] >= first:
            k = q[c, 2] - first
            idx[fill[k]] = c
            fill[k] += 1
    moved = 0
    for k in range(nc):
        lo = ptr[k]
        hi = ptr[k + 1]
        v = first + k
        cx = p[v, 0]
        cy = p[v, 1]
        now = _centre_value(p, q, idx, lo, hi, cx, cy)
        if hi == lo or now >= floor:
            continue
        best = now
        bx = cx
        by = cy
        for r in range(lo, hi):
            c = idx[r]
            mx = 0.5 * (p[q[c, 1], 0] + p[q[c, 3], 0])
            my = 0.5 * (p[q[c, 1], 1] + p[q[c, 3], 1])
            for s in steps:
                x = mx + s * (cx - mx)
                y = my + s * (cy - my)
                val = _centre_value(p, q, idx, lo, hi, x, y)
                if val > best:
                    best = val
                    bx = x
                    by = y
        if best > now:
            p[v, 0] = bx
            p[v, 1] = by
            moved += 1
    return moved
