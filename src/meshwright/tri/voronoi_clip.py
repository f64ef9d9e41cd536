"""Clipping a Voronoi diagram to a polygon: Sutherland-Hodgman with each cell as the window.

Source: I. E. Sutherland and G. W. Hodgman, "Reentrant polygon clipping", Communications of
the ACM 17(1):32-42, 1974.  Their algorithm clips an arbitrary *subject* polygon against a
*convex* window, one window side (half-plane) at a time, each pass walking the subject's
sides once and emitting the vertices inside and the crossings.  A Voronoi cell is convex and
is the intersection of the half-planes ``|x - P_i| <= |x - P_j|`` of its Delaunay neighbours
``P_j``, so here the roles are swapped: the *subject* is the clip region (any simple polygon)
and the *window* is the cell.  The result is the cell intersected with the region, also for
an unbounded cell (its half-planes alone bound it inside the region), with no far box.

Invariants
----------
* Every output vertex is labelled by the geometric entity it is, ``(kind, a, b)``: ``_TRI``
  the circumcentre of Delaunay triangle ``a``, ``_CORNER`` clip corner ``a``, ``_CROSS`` the
  crossing of clip side ``a`` with the bisector of ridge ``b``.  A crossing is always computed
  from the whole clip side and the ridge's own point order (:func:`_crossing`), so every cell
  and ridge that meets it gets bitwise the same coordinates, and the labels merge shared
  vertices into one (:func:`clip_diagram`): neighbouring clipped cells share vertex indices.
* Where two bisectors meet inside the region the vertex is a Voronoi vertex; it is renamed to
  its fan triangle and takes the stored circumcentre's coordinates, so clipping never moves
  an unclipped vertex.
* The working polygon carries, per vertex, the *support* of the side leaving it (a clip side
  or a bisector); zero-width spikes that a non-convex region leaves have the same support in
  and out and are removed (:func:`_tidy`).
* Which side of a bisector a working vertex lies on is decided in floating point: the
  working vertices are themselves rounded crossings, so an exact sign on them would be exact
  about the wrong point.  A vertex within rounding of a bisector may fall on either side,
  which changes the clipped cell by a sliver of that width.  The diagram's topology (cells,
  ridges, Voronoi vertices) comes from the exact Delaunay triangulation; only the simplicity
  of the clip polygon is decided here exactly (``orient2d``).

Array layout (``n`` points, ``nt`` triangles, ``r`` ridges, ``k`` clip corners)
------------------------------------------------------------------------------
Inputs are those of :mod:`meshwright.tri.voronoi`: ``points`` (n, 2) float64, ``centres``
(nt, 2) float64, ``poly`` (k, 2) float64 counter-clockwise, ``ridge_points`` /
``ridge_vertices`` (r, 2) int32, the unclipped cells as CSR (``voff`` (n + 1,) int64, ``cv``
int32 with -1 at the open ends of hull cells) and each cell's neighbours in the same order
(``noff`` (n + 1,) int64, ``nb_pts`` int32, ``nb_ridges`` int64).  Working buffers are
``(c, 2)`` float64 coordinates beside ``(c, 3)`` or ``(c, 5)`` int64 labels
``(kind, a, b[, support kind, support id])``, grown by doubling.  Cost: O((n + r) k).

Limitation: where a non-convex region cuts a cell into several pieces, the cell is one
polygon joining the pieces by zero-width bridges along the cell's sides, through Voronoi
vertices that may lie outside the region; its area is right but it is not simple.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.errors import GeometryError, InputError
from meshwright.core.predicates import orient2d

__all__ = ["clip_diagram", "clip_region"]

# Kind of a vertex produced by clipping: circumcentre of triangle a, clip corner a,
# crossing of clip side a with the bisector of ridge b.
_TRI, _CORNER, _CROSS = 0, 1, 2
# What the side leaving a working vertex of Sutherland-Hodgman lies on: a clip side or a bisector.
_ON_CLIP, _ON_BISECTOR = 0, 1


def clip_diagram(points, centres, poly, ridge_points, ridge_vertices, voff, cv, noff, nb_pts, nb_ridges):
    """Clip every cell and every ridge of a Voronoi diagram to a polygon.

    Parameters
    ----------
    points : (n, 2) float64
    centres : (nt, 2) float64
        Circumcentres: the unclipped Voronoi vertices.
    poly : (k, 2) float64
        Counter-clockwise simple polygon (from :func:`clip_region`).
    ridge_points, ridge_vertices : (r, 2) int32
        The unclipped ridges (end vertex -1 for a ray).
    voff : (n + 1,) int64
    cv : (voff[-1],) int32
        Unclipped cells, CSR, -1 at both open ends of a hull cell.
    noff : (n + 1,) int64
    nb_pts : (noff[-1],) int32
    nb_ridges : (noff[-1],) int64
        Each cell's Delaunay neighbours and the ridges towards them, in cell order.

    Returns
    -------
    vertices : (m, 2) float64
        ``centres`` then the clip corners and crossings used, each once.
    ridge_points : (p, 2) int32
        The points of each clipped ridge piece (a ridge may give several pieces).
    ridge_vertices : (p, 2) int32
        Start and end vertex of each piece (no -1).
    cell_offsets : (n + 1,) int64
    cell_vertices : (cell_offsets[-1],) int32
        The clipped cells, counter-clockwise; an empty cell misses the region.
    """
    n, nt, k, nr = len(points), len(centres), len(poly), len(ridge_points)
    counts, cell_lab, cell_xy = _clip_cells(points, centres, poly, voff, cv, noff, nb_pts, nb_ridges, ridge_points)
    piece_ridge, ridge_lab, ridge_xy = _clip_ridges(points, centres, poly, ridge_points, ridge_vertices)
    lab = np.concatenate([cell_lab, ridge_lab])
    index = lab[:, 1].copy()
    new = lab[:, 0] != _TRI
    # One key per geometric entity, so two cells (or a cell and a ridge) share the vertex.
    key = np.where(lab[new, 0] == _CORNER, lab[new, 1], k + lab[new, 1] * nr + lab[new, 2])
    _, first, inverse = np.unique(key, return_index=True, return_inverse=True)
    index[new] = nt + inverse.ravel()
    vertices = np.concatenate([centres, np.concatenate([cell_xy, ridge_xy])[new][first]])
    clipped_ridge_vertices = index[len(cell_lab) :].reshape(-1, 2).astype(np.int32)
    cell_offsets = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(counts, out=cell_offsets[1:])
    cell_vertices = index[: len(cell_lab)].astype(np.int32)
    return vertices, ridge_points[piece_ridge], clipped_ridge_vertices, cell_offsets, cell_vertices


def clip_region(clip) -> np.ndarray:
    """Check a clip argument at the door and return it as a counter-clockwise simple polygon.

    Parameters
    ----------
    clip : (4,) array_like or (k, 2) array_like of float
        A box ``(xmin, ymin, xmax, ymax)`` or a simple polygon of either orientation, convex
        or not; a repeated closing vertex is allowed.

    Returns
    -------
    (k, 2) float64
        The polygon, counter-clockwise, without repeated consecutive vertices.

    Raises
    ------
    InputError
        Not numbers, a wrong shape, a non-finite vertex, an empty box.
    GeometryError
        Fewer than 3 distinct vertices, or two sides meet (both named).
    """
    try:
        arr = np.asarray(clip, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(
            f"clip must be a box (xmin, ymin, xmax, ymax) or a (k, 2) polygon, got {clip!r}"
        ) from exc
    if arr.shape == (4,):
        xmin, ymin, xmax, ymax = arr
        if not (np.isfinite(arr).all() and xmin < xmax and ymin < ymax):
            raise InputError(f"clip box {arr.tolist()} needs finite xmin < xmax and ymin < ymax")
        return np.array([[xmin, ymin], [xmax, ymin], [xmax, ymax], [xmin, ymax]])
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise InputError(
            f"clip must be a box of 4 numbers or a (k, 2) polygon, got shape {arr.shape}"
        )
    bad = np.flatnonzero(~np.isfinite(arr).all(axis=1))
    if bad.size:
        raise InputError(f"clip polygon vertex {bad[0]} is not finite: {arr[bad[0]].tolist()}")
    # A repeated closing vertex, or any vertex repeated next to itself, is a zero-length side.
    kept = np.flatnonzero((arr != np.roll(arr, 1, axis=0)).any(axis=1))
    poly = np.ascontiguousarray(arr[kept])
    if len(poly) < 3:
        raise GeometryError(f"clip polygon needs at least 3 distinct vertices, got {len(poly)}")
    i, j = _first_crossing(poly)
    if i >= 0:
        a, b = kept[i], kept[(i + 1) % len(kept)]
        c, d = kept[j], kept[(j + 1) % len(kept)]
        raise GeometryError(
            f"clip polygon is not simple: side {a}->{b} {arr[a].tolist()}->{arr[b].tolist()} "
            f"meets side {c}->{d} {arr[c].tolist()}->{arr[d].tolist()}"
        )
    rel = poly - poly[0]
    twice_area = np.sum(rel[:-1, 0] * rel[1:, 1] - rel[:-1, 1] * rel[1:, 0])
    return poly if twice_area > 0 else np.ascontiguousarray(poly[::-1])


@njit(cache=True)
def _first_crossing(poly):
    """Return the first pair of sides (i, j) of a polygon that meet illegally, else (-1, -1).

    Non-neighbouring sides must not touch; neighbouring sides must not fold back onto each
    other.  Exact ``orient2d`` decides, O(k^2) with a bounding-box reject.
    """
    k = poly.shape[0]
    for i in range(k):
        ax, ay = poly[i, 0], poly[i, 1]
        bx, by = poly[(i + 1) % k, 0], poly[(i + 1) % k, 1]
        for j in range(i + 1, k):
            cx, cy = poly[j, 0], poly[j, 1]
            dx, dy = poly[(j + 1) % k, 0], poly[(j + 1) % k, 1]
            if j == i + 1 or (i == 0 and j == k - 1):
                # Shared vertex s, other ends p and q: a fold puts q on the ray from s through p.
                if j == i + 1:
                    sx, sy, px, py, qx, qy = bx, by, ax, ay, dx, dy
                else:
                    sx, sy, px, py, qx, qy = ax, ay, bx, by, cx, cy
                if orient2d(sx, sy, px, py, qx, qy) == 0.0 and (
                    (px - sx) * (qx - sx) + (py - sy) * (qy - sy) > 0.0
                ):
                    return i, j
                continue
            if not _overlaps(poly, j, min(ax, bx), min(ay, by), max(ax, bx), max(ay, by)):
                continue
            o1 = np.sign(orient2d(ax, ay, bx, by, cx, cy))
            o2 = np.sign(orient2d(ax, ay, bx, by, dx, dy))
            o3 = np.sign(orient2d(cx, cy, dx, dy, ax, ay))
            o4 = np.sign(orient2d(cx, cy, dx, dy, bx, by))
            # Collinear sides pass the bounding-box test only when they overlap.
            if o1 * o2 <= 0.0 and o3 * o4 <= 0.0:
                return i, j
    return -1, -1


@njit(cache=True)
def _overlaps(poly, e, x0, y0, x1, y1):
    """Whether the bounding box of polygon side ``e`` meets the box [x0, x1] x [y0, y1]."""
    k = poly.shape[0]
    ax, ay, bx, by = poly[e, 0], poly[e, 1], poly[(e + 1) % k, 0], poly[(e + 1) % k, 1]
    return min(ax, bx) <= x1 and max(ax, bx) >= x0 and min(ay, by) <= y1 and max(ay, by) >= y0


@njit(cache=True)
def _inside(x, y, poly):
    """Even-odd ray casting; the half-open test in y counts a vertex on the ray once."""
    k = poly.shape[0]
    inside = False
    for e in range(k):
        x0, y0 = poly[e, 0], poly[e, 1]
        x1, y1 = poly[(e + 1) % k, 0], poly[(e + 1) % k, 1]
        if (y0 > y) != (y1 > y) and x0 + (y - y0) * (x1 - x0) / (y1 - y0) > x:
            inside = not inside
    return inside


@njit(cache=True)
def _crossing(poly, e, points, ridge_points, r):
    """Crossing of clip side ``e`` with the bisector of ridge ``r``, and the sides' signs.

    Always computed from the whole side and the ridge's own point order, so every cell and
    ridge that meets this crossing gets bitwise the same coordinates.
    """
    k = poly.shape[0]
    u, v = ridge_points[r, 0], ridge_points[r, 1]
    dx, dy = points[v, 0] - points[u, 0], points[v, 1] - points[u, 1]
    mx, my = 0.5 * (points[u, 0] + points[v, 0]), 0.5 * (points[u, 1] + points[v, 1])
    x0, y0 = poly[e, 0], poly[e, 1]
    x1, y1 = poly[(e + 1) % k, 0], poly[(e + 1) % k, 1]
    s0 = dx * (x0 - mx) + dy * (y0 - my)
    s1 = dx * (x1 - mx) + dy * (y1 - my)
    lam = 0.5 if s0 == s1 else min(max(s0 / (s0 - s1), 0.0), 1.0)
    return x0 + lam * (x1 - x0), y0 + lam * (y1 - y0), s0, s1


@njit(cache=True)
def _reserve(xy, lab, used, extra):
    """Return buffers (c, 2) float64 and (c, w) int64 keeping ``used`` rows, room for ``extra``."""
    if used + extra <= lab.shape[0]:
        return xy, lab
    cap = max(2 * lab.shape[0], used + extra)
    xy2, lab2 = np.empty((cap, 2)), np.empty((cap, lab.shape[1]), dtype=np.int64)
    for s in range(used):
        _copy_row(xy2, lab2, s, xy, lab, s)
    return xy2, lab2


@njit(cache=True)
def _copy_row(dst_xy, dst_lab, d, src_xy, src_lab, s):
    """Copy row ``s`` of a (coordinates, labels) buffer pair to row ``d`` of another."""
    dst_xy[d, 0], dst_xy[d, 1] = src_xy[s, 0], src_xy[s, 1]
    for c in range(min(dst_lab.shape[1], src_lab.shape[1])):
        dst_lab[d, c] = src_lab[s, c]


@njit(cache=True)
def _fan_triangle(j1, j2, x, y, cv, first, m, closed, centres):
    """Name the meeting point of bisectors j1 and j2 of a cell by its Delaunay triangle.

    The vertex between sides j and j+1 of the cell is its fan triangle j (``cv[first + j]``,
    ``m`` of them; the sides of a closed cell wrap around).  Non-consecutive sides meet on the
    cell only through zero-length ridges of cocircular points; the nearest circumcentre is then
    the same point.
    """
    nh = m if closed else m + 1
    if j2 == j1 + 1 or (closed and j2 == 0 and j1 == nh - 1):
        return cv[first + j1]
    if j1 == j2 + 1 or (closed and j1 == 0 and j2 == nh - 1):
        return cv[first + j2]
    best, best_d = cv[first], np.inf
    for s in range(first, first + m):
        d = (centres[cv[s], 0] - x) ** 2 + (centres[cv[s], 1] - y) ** 2
        if d < best_d:
            best, best_d = cv[s], d
    return best


@njit(cache=True)
def _tidy(wxy, wlab, cnt):
    """Drop repeated vertices and zero-width spikes from the first ``cnt`` rows, in place.

    ``wxy`` (c, 2) float64 and ``wlab`` (c, 5) int64 (kind, a, b, support kind, support id, the
    support being the line the side to the next vertex lies on).  A clip side through a Voronoi
    vertex repeats it; a non-convex region leaves spikes out along one line and back, whose tip
    has the same support in and out (as has a vertex inside a straight run): dropping it merges
    the two sides.  A removal can expose another, so repeat.  Returns the new count.
    """
    drop = np.zeros(cnt, dtype=np.bool_)
    changed = True
    while changed and cnt >= 3:
        changed = False
        for phase in range(2):
            for s in range(cnt):
                if phase == 0:
                    # Of two equal vertices keep the second: its support is the real side.
                    o = s + 1 if s + 1 < cnt else 0
                    same = wlab[o, 0] == wlab[s, 0] and wlab[o, 1] == wlab[s, 1]
                    drop[s] = same and wlab[o, 2] == wlab[s, 2]
                else:
                    o = s - 1 if s > 0 else cnt - 1
                    drop[s] = wlab[o, 3] == wlab[s, 3] and wlab[o, 4] == wlab[s, 4]
            kept = np.int64(0)
            for s in range(cnt):
                if not drop[s]:
                    _copy_row(wxy, wlab, kept, wxy, wlab, s)
                    kept += 1
            changed = changed or kept < cnt
            cnt = kept
            if cnt < 3:
                break
    return cnt


@njit(cache=True)
def _clip_cells(points, centres, poly, voff, cv, noff, nb_pts, nb_ridges, ridge_points):
    """Clip every cell to the polygon (Sutherland-Hodgman, the cell's half-planes as window).

    Returns ``counts`` (n,) int64, the number of vertices of each clipped cell; ``lab``
    (sum(counts), 3) int64, their labels (kind, a, b) cell after cell (see ``_TRI``); ``xy``
    (sum(counts), 2) float64, their coordinates.
    """
    n, k = points.shape[0], poly.shape[0]
    counts = np.zeros(n, dtype=np.int64)
    lab = np.empty((4 * (n + k), 3), dtype=np.int64)
    xy = np.empty((4 * (n + k), 2))
    used = np.int64(0)
    # Working polygon: coordinates, and (kind, a, b, support kind, support id) where the
    # support is what the side from this vertex to the next lies on.
    wxy, wlab = np.empty((2 * k + 8, 2)), np.empty((2 * k + 8, 5), dtype=np.int64)
    nxy, nlab = np.empty_like(wxy), np.empty_like(wlab)
    for i in range(n):
        v0, v1 = voff[i], voff[i + 1]
        if v0 == v1:
            continue
        closed = cv[v0] >= 0
        first = v0 if closed else v0 + 1
        m = v1 - first if closed else v1 - first - 1
        if closed:
            x0, y0, x1, y1 = np.inf, np.inf, -np.inf, -np.inf
            for s in range(v0, v1):
                cx, cy = centres[cv[s], 0], centres[cv[s], 1]
                x0, y0, x1, y1 = min(x0, cx), min(y0, cy), max(x1, cx), max(y1, cy)
            touches = False
            for e in range(k):
                if _overlaps(poly, e, x0, y0, x1, y1):
                    touches = True
                    break
            if not touches:
                # Off the clip boundary the cell is wholly in or out, like its generator.
                if _inside(points[i, 0], points[i, 1], poly):
                    xy, lab = _reserve(xy, lab, used, m)
                    for s in range(v0, v1):
                        lab[used, 0], lab[used, 1], lab[used, 2] = _TRI, cv[s], 0
                        xy[used, 0], xy[used, 1] = centres[cv[s], 0], centres[cv[s], 1]
                        used += 1
                    counts[i] = m
                continue
        for c in range(k):
            wxy[c, 0], wxy[c, 1] = poly[c, 0], poly[c, 1]
            wlab[c, 0], wlab[c, 1], wlab[c, 2], wlab[c, 3], wlab[c, 4] = _CORNER, c, 0, _ON_CLIP, c
        cnt = k
        h0, nh = noff[i], noff[i + 1] - noff[i]
        for j in range(nh):
            q, r = nb_pts[h0 + j], nb_ridges[h0 + j]
            dx, dy = points[q, 0] - points[i, 0], points[q, 1] - points[i, 1]
            mx, my = 0.5 * (points[q, 0] + points[i, 0]), 0.5 * (points[q, 1] + points[i, 1])
            nxy, nlab = _reserve(nxy, nlab, np.int64(0), 2 * cnt)  # each side yields at most two
            out = np.int64(0)
            for s in range(cnt):
                s2 = s + 1 if s + 1 < cnt else 0
                ax, ay, bx, by = wxy[s, 0], wxy[s, 1], wxy[s2, 0], wxy[s2, 1]
                sa = dx * (ax - mx) + dy * (ay - my)
                sb = dx * (bx - mx) + dy * (by - my)
                a_in, b_in = sa <= 0.0, sb <= 0.0
                if a_in:
                    _copy_row(nxy, nlab, out, wxy, wlab, s)
                    out += 1
                if a_in != b_in:
                    if wlab[s, 3] == _ON_CLIP:
                        x, y, _, _ = _crossing(poly, wlab[s, 4], points, ridge_points, r)
                        nlab[out, 0], nlab[out, 1], nlab[out, 2] = _CROSS, wlab[s, 4], r
                    else:
                        lam = sa / (sa - sb)
                        x, y = ax + lam * (bx - ax), ay + lam * (by - ay)
                        # Two bisectors meet: a Voronoi vertex, named once clipping is done.
                        nlab[out, 0], nlab[out, 1], nlab[out, 2] = _TRI, wlab[s, 4], j
                    nxy[out, 0], nxy[out, 1] = x, y
                    if a_in:
                        nlab[out, 3], nlab[out, 4] = _ON_BISECTOR, j
                    else:
                        nlab[out, 3], nlab[out, 4] = wlab[s, 3], wlab[s, 4]
                    out += 1
            wxy, nxy, wlab, nlab, cnt = nxy, wxy, nlab, wlab, out
            if cnt == 0:
                break
        if cnt < 3:
            continue
        for s in range(cnt):
            if wlab[s, 0] == _TRI:
                wlab[s, 1] = _fan_triangle(
                    wlab[s, 1], wlab[s, 2], wxy[s, 0], wxy[s, 1], cv, first, m, closed, centres
                )
                wlab[s, 2] = 0
                wxy[s, 0], wxy[s, 1] = centres[wlab[s, 1], 0], centres[wlab[s, 1], 1]
        cnt = _tidy(wxy, wlab, cnt)
        if cnt >= 3:
            xy, lab = _reserve(xy, lab, used, cnt)
            for s in range(cnt):
                _copy_row(xy, lab, used + s, wxy, wlab, s)
            counts[i] = cnt
            used += cnt
    return counts, lab[:used], xy[:used]


@njit(cache=True)
def _clip_ridges(points, centres, poly, ridge_points, ridge_vertices):
    """Cut every ridge (segment or ray) to the pieces inside the polygon.

    Returns ``piece_ridge`` (p,) int64, the ridge of each piece (in ridge order, then along the
    ridge); ``lab`` (2 p, 3) int64, start and end label (kind, a, b) of each piece; ``xy``
    (2 p, 2) float64, their coordinates.
    """
    k, nr = poly.shape[0], ridge_points.shape[0]
    piece_ridge = np.empty(nr, dtype=np.int64)
    lab = np.empty((2 * nr, 3), dtype=np.int64)
    xy = np.empty((2 * nr, 2))
    pieces = 0
    lam_buf, side_buf = np.empty(k), np.empty(k, dtype=np.int64)
    for r in range(nr):
        t0, t1 = ridge_vertices[r, 0], ridge_vertices[r, 1]
        ax, ay = centres[t0, 0], centres[t0, 1]
        if t1 >= 0:
            dx, dy, lam_max = centres[t1, 0] - ax, centres[t1, 1] - ay, 1.0
            x0, x1 = min(ax, ax + dx), max(ax, ax + dx)
            y0, y1 = min(ay, ay + dy), max(ay, ay + dy)
        else:
            u, v = ridge_points[r, 0], ridge_points[r, 1]
            # Outward normal of hull edge u -> v (the outside is on its right).
            dx, dy, lam_max = points[v, 1] - points[u, 1], points[u, 0] - points[v, 0], np.inf
            x0, x1 = (-np.inf if dx < 0 else ax), (np.inf if dx > 0 else ax)
            y0, y1 = (-np.inf if dy < 0 else ay), (np.inf if dy > 0 else ay)
        dd = dx * dx + dy * dy
        nc = 0
        for e in range(k):
            if dd == 0.0 or not _overlaps(poly, e, x0, y0, x1, y1):
                continue
            x, y, s0, s1 = _crossing(poly, e, points, ridge_points, r)
            # Half-open in the side's end signs: a clip corner on the bisector counts once.
            if (s0 <= 0.0 < s1) or (s1 <= 0.0 < s0):
                lam = ((x - ax) * dx + (y - ay) * dy) / dd
                if 0.0 <= lam <= lam_max:
                    c = nc
                    while c > 0 and lam_buf[c - 1] > lam:
                        lam_buf[c], side_buf[c] = lam_buf[c - 1], side_buf[c - 1]
                        c -= 1
                    lam_buf[c], side_buf[c] = lam, e
                    nc += 1
        inside = _inside(ax, ay, poly)
        xy, lab = _reserve(xy, lab, 2 * pieces, 2 * (nc + 1))
        if piece_ridge.shape[0] < pieces + nc + 1:
            grown = np.empty(2 * (pieces + nc + 1), dtype=np.int64)
            for c in range(pieces):
                grown[c] = piece_ridge[c]
            piece_ridge = grown
        skind, sa, sb, sx, sy = _TRI, t0, 0, ax, ay
        for c in range(nc + 1):
            if c < nc:
                e = side_buf[c]
                ekind, ea, eb = _CROSS, e, r
                ex, ey, _, _ = _crossing(poly, e, points, ridge_points, r)
            elif t1 >= 0:
                ekind, ea, eb, ex, ey = _TRI, t1, 0, centres[t1, 0], centres[t1, 1]
            else:
                break  # a ray ends outside a bounded region
            if inside:
                piece_ridge[pieces] = r
                row = 2 * pieces
                lab[row, 0], lab[row, 1], lab[row, 2] = skind, sa, sb
                lab[row + 1, 0], lab[row + 1, 1], lab[row + 1, 2] = ekind, ea, eb
                xy[row, 0], xy[row, 1], xy[row + 1, 0], xy[row + 1, 1] = sx, sy, ex, ey
                pieces += 1
            skind, sa, sb, sx, sy = ekind, ea, eb, ex, ey
            inside = not inside
    return piece_ridge[:pieces], lab[: 2 * pieces], xy[: 2 * pieces]
