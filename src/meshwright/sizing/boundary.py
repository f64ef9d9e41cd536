"""Sizes derived from a discretised boundary: Weatherill's point distribution and gradation.

* :func:`point_distribution` is the point distribution function of the automatic point
  generation scheme (N. P. Weatherill, "Delaunay triangulation in computational fluid
  dynamics", Computers & Mathematics with Applications 24(5/6):129-150, 1992; chapter
  18.1.3 of the reference text): for boundary point ``i`` with neighbours ``i - 1`` and
  ``i + 1``, ``dP_i = (|x_{i+1} - x_i| + |x_i - x_{i-1}|) / 2``, the mean length of the two
  boundary segments meeting there.
* :func:`gradation` bounds how fast the size may grow away from points with prescribed
  sizes: ``h(x) = min_i (h_i + (g - 1) |x - x_i|)`` (capped by ``hmax`` and an optional base
  field), the Lipschitz-continuous size of P.-O. Persson, "Mesh size functions for implicit
  geometries and PDE-based gradient limiting", Engineering with Computers 22:95-109, 2006.
  The minimum over sources uses a uniform grid of the sources under a pyramid of cell
  minima and source bounding boxes, searched depth first, nearest lower bound first, and
  started from the previous query's nearest source, so no KD-tree (and no SciPy) is
  needed; the result is the exact floating-point minimum over all sources.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from meshwright.core.errors import InputError, SizeError
from meshwright.sizing.field import SizeField, as_size_field, fmt_point

__all__ = ["FINER", "boundary_size", "graded_from_boundary", "gradation", "is_stretched", "point_distribution"]

# A boundary point grades a given size only where its spacing is below this fraction of the
# size: rounding segment counts leaves spacings down to 2/3 of it on pieces 1.5 sizes long,
# which must not change a boundary that already follows the size.
FINER = 0.6


def point_distribution(points, segments) -> np.ndarray:
    """Weatherill's point distribution function of boundary points.

    Parameters
    ----------
    points : (n, 2) float64
    segments : (m, 2) int
        Boundary segments (vertex indices).

    Returns
    -------
    (n,) float64
        Mean length of the segments at each point: ``dP_i`` of chapter 18.1.3 for a point
        with two neighbours.  NaN for points on no segment.
    """
    p = np.asarray(points, dtype=np.float64)
    s = np.asarray(segments, dtype=np.int64)
    if p.ndim != 2 or p.shape[1] != 2 or s.ndim != 2 or s.shape[1] != 2:
        raise InputError(f"need points (n, 2) and segments (m, 2), got {p.shape} and {s.shape}")
    if len(s) and (s.min() < 0 or s.max() >= len(p)):
        raise InputError(f"segment indices must lie in [0, {len(p)}), got [{s.min()}, {s.max()}]")
    length = np.hypot(*(p[s[:, 1]] - p[s[:, 0]]).T)
    total = np.bincount(s.ravel(), np.repeat(length, 2), minlength=len(p))
    count = np.bincount(s.ravel(), minlength=len(p))
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(count > 0, total / np.maximum(count, 1), np.nan)


@nb.njit(inline="always")
def _cell_bound(hm, box, c, qx, qy, slope):
    """``hm + slope dist(q, box_c)``: at most ``h_i + slope |q - x_i|`` for every source i
    of cell c, in floating point too (the box is the sources' own bounding box, so every
    rounded difference to it is at most the rounded difference to a source)."""
    dx = max(box[c, 0] - qx, 0.0, qx - box[c, 2])
    dy = max(box[c, 1] - qy, 0.0, qy - box[c, 3])
    return hm + slope * np.sqrt(dx * dx + dy * dy)


@nb.njit(cache=True)
def _cone_min(query, upper, src, h, slope, start, items, hmin, box, off, gxs, gys):
    """``min(upper_k, min_i h_i + slope |q_k - src_i|)`` for each query ``q_k``, depth first
    over a pyramid of cells (:func:`_pyramid`): a cell's children are opened nearest
    bound first (:func:`_cell_bound`), and a cell whose bound is not below the best
    value found is skipped, also when it comes off the stack.  The search starts from
    the value of the source that gave the previous query its minimum: queries come in
    spatial order (a front's new nodes, a boundary table, a quadtree's corners), so that
    value is nearly the answer and prunes from the first cell.  Every value is one of the
    sources' ``h_i + slope |q - x_i|`` computed as written here, and a cell is skipped
    only when its bound (a floating-point lower bound) is not below the best value, so
    the result is exactly the brute-force minimum, in any order of the cells.  The stack
    holds at most the top level's cells and four children per level below; the cells are
    kept in small sorted arrays written out here (a binary heap's calls with array
    arguments cost Numba's reference counts on each: the best-first search this
    replaced took 2.3-2.4 times as long on the airfoils' size queries)."""
    out = np.empty(query.shape[0])
    top = gxs.shape[0] - 1
    cap = 4 * (top + 1) + gxs[top] * gys[top]
    sk = np.empty(cap)
    sl = np.empty(cap, dtype=np.int64)
    si = np.empty(cap, dtype=np.int64)
    sj = np.empty(cap, dtype=np.int64)
    ck = np.empty(4)
    ci4 = np.empty(4, dtype=np.int64)
    cj4 = np.empty(4, dtype=np.int64)
    last = -1
    for k in range(query.shape[0]):
        qx, qy = query[k, 0], query[k, 1]
        best = upper[k]
        if last >= 0:
            ex = qx - src[last, 0]
            ey = qy - src[last, 1]
            best = min(best, h[last] + slope * np.sqrt(ex * ex + ey * ey))
        n = 0
        for j in range(gys[top]):
            for i in range(gxs[top]):
                c = off[top] + j * gxs[top] + i
                if hmin[c] < best:
                    bound = _cell_bound(hmin[c], box, c, qx, qy, slope)
                    if bound < best:
                        # Sorted in: the stack's top holds the smallest bound.
                        t = n
                        while t > 0 and sk[t - 1] < bound:
                            sk[t] = sk[t - 1]
                            sl[t] = sl[t - 1]
                            si[t] = si[t - 1]
                            sj[t] = sj[t - 1]
                            t -= 1
                        sk[t] = bound
                        sl[t] = top
                        si[t] = i
                        sj[t] = j
                        n += 1
        while n > 0:
            n -= 1
            if sk[n] >= best:
                continue
            lev, i, j = sl[n], si[n], sj[n]
            if lev == 0:
                c = j * gxs[0] + i
                for p in range(start[c], start[c + 1]):
                    s = items[p]
                    ex = qx - src[s, 0]
                    ey = qy - src[s, 1]
                    v = h[s] + slope * np.sqrt(ex * ex + ey * ey)
                    if v < best:
                        best = v
                        last = s
                continue
            m = 0
            for b in range(2):
                for a in range(2):
                    ci = 2 * i + a
                    cj = 2 * j + b
                    if ci >= gxs[lev - 1] or cj >= gys[lev - 1]:
                        continue
                    c = off[lev - 1] + cj * gxs[lev - 1] + ci
                    if hmin[c] < best:
                        bound = _cell_bound(hmin[c], box, c, qx, qy, slope)
                        if bound < best:
                            t = m
                            while t > 0 and ck[t - 1] < bound:
                                ck[t] = ck[t - 1]
                                ci4[t] = ci4[t - 1]
                                cj4[t] = cj4[t - 1]
                                t -= 1
                            ck[t] = bound
                            ci4[t] = ci
                            cj4[t] = cj
                            m += 1
            # The children go on largest bound first, so the nearest comes off next.
            for t in range(m):
                sk[n] = ck[t]
                sl[n] = lev - 1
                si[n] = ci4[t]
                sj[n] = cj4[t]
                n += 1
        out[k] = best
    return out


def _pyramid(items: np.ndarray, start: np.ndarray, src: np.ndarray, h: np.ndarray, gx: int, gy: int):
    """Min-pyramid of a (gy, gx) grid of sources: a cell of level 0 holds the smallest size
    of its sources and their bounding box; a cell of level L + 1 the minimum and the union
    of its four cells of level L (inf and an empty box outside), up to a level of at most 4
    cells.

    Parameters
    ----------
    items : (n,) int64
        The sources ordered by their level-0 cell ``j * gx + i``.
    start : (gx * gy + 1,) int64
        Cell c holds ``items[start[c]:start[c + 1]]``.
    src : (n, 2) float64
    h : (n,) float64
    gx, gy : int

    Returns
    -------
    hmin : (total,) float64
        Every level's cells, row-major, level 0 first.
    box : (total, 4) float64
        ``xmin, ymin, xmax, ymax`` of each cell's sources (``inf, inf, -inf, -inf`` if none).
    off : (levels + 1,) int64
        Start of each level in ``hmin``.
    gxs, gys : (levels,) int64
        Cells per row and per column of each level.
    """
    ncell = gx * gy
    # Five planes per level: the smallest size, then xmin, ymin (reduced by min) and xmax,
    # ymax (by max) of the sources' box; an empty cell holds inf, inf, inf, -inf, -inf.
    planes = [np.full(ncell, np.inf), np.full(ncell, np.inf), np.full(ncell, np.inf),
              np.full(ncell, -np.inf), np.full(ncell, -np.inf)]
    full = np.flatnonzero(start[1:] > start[:-1])
    if len(full):
        # Segment reductions over the cell-sorted sources (ufunc.at is several times slower).
        first = start[full]
        for plane, values, red in zip(planes, (h, src[:, 0], src[:, 1], src[:, 0], src[:, 1]),
                                      (np.minimum,) * 3 + (np.maximum,) * 2):
            plane[full] = red.reduceat(values[items], first)
    levels = [[p.reshape(gy, gx) for p in planes]]
    while levels[-1][0].size > 4:
        ny, nx = levels[-1][0].shape
        my, mx = (ny + 1) // 2, (nx + 1) // 2
        up = []
        for k, a in enumerate(levels[-1]):
            red = np.minimum if k < 3 else np.maximum
            pad = np.full((2 * my, 2 * mx), np.inf if k < 3 else -np.inf)
            pad[:ny, :nx] = a
            up.append(red(red(pad[0::2, 0::2], pad[0::2, 1::2]), red(pad[1::2, 0::2], pad[1::2, 1::2])))
        levels.append(up)
    off = np.concatenate([[0], np.cumsum([lv[0].size for lv in levels])]).astype(np.int64)
    gxs = np.array([lv[0].shape[1] for lv in levels], dtype=np.int64)
    gys = np.array([lv[0].shape[0] for lv in levels], dtype=np.int64)
    hmin = np.concatenate([lv[0].ravel() for lv in levels])
    box = np.column_stack([np.concatenate([lv[k].ravel() for lv in levels]) for k in (1, 2, 3, 4)])
    return hmin, box, off, gxs, gys


class _Graded:
    """Callable ``xy -> min(base, hmax, min_i h_i + slope |x - x_i|)`` over a source grid."""

    def __init__(self, src, h, slope, hmax, base):
        self.src, self.h, self.slope, self.hmax, self.base = src, h, slope, hmax, base
        lo = src.min(axis=0)
        ext = float(np.ptp(src, axis=0).max())
        g = max(1, int(np.ceil(np.sqrt(len(src) / 2.0))))
        self.w = ext / g if ext > 0 else 1.0
        # A thin box (aspect above 4) gets as many cells as a square one, not one row of
        # crowded cells; other boxes keep their grid.
        thin = float(np.sqrt(ext * float(np.ptp(src, axis=0).min()) / max(len(src) / 2.0, 1.0)))
        if ext > 0 and thin < 0.5 * self.w:
            self.w = max(thin, ext / (2.0 * len(src) + 2.0))
        self.x0, self.y0 = float(lo[0]), float(lo[1])
        self.gx = int(np.ptp(src[:, 0]) / self.w) + 1
        self.gy = int(np.ptp(src[:, 1]) / self.w) + 1
        ci = np.minimum(((src[:, 0] - self.x0) / self.w).astype(np.int64), self.gx - 1)
        cj = np.minimum(((src[:, 1] - self.y0) / self.w).astype(np.int64), self.gy - 1)
        cell = cj * self.gx + ci
        self.items = np.argsort(cell, kind="stable")
        ncell = self.gx * self.gy
        self.start = np.concatenate([[0], np.cumsum(np.bincount(cell, minlength=ncell))])
        self.pyramid = _pyramid(self.items, self.start, src, h, self.gx, self.gy)

    def __call__(self, xy: np.ndarray) -> np.ndarray:
        q = np.ascontiguousarray(xy, dtype=np.float64)
        upper = np.full(len(q), np.inf if self.hmax is None else float(self.hmax))
        if self.base is not None:
            upper = np.minimum(upper, self.base(q))
        if self.slope == 0.0:
            out = np.minimum(upper, self.h.min())
        else:
            out = _cone_min(q, upper, self.src, self.h, self.slope, self.start, self.items, *self.pyramid)
        return out


def gradation(
    points, sizes, growth: float = 1.2, hmax: float | None = None, base=None
) -> SizeField:
    """Size field growing at most linearly, by ``growth - 1`` per unit length, from sources.

    Parameters
    ----------
    points : (n, 2) float64
        Source points (e.g. boundary vertices).
    sizes : (n,) float64 or float
        Size at each source (positive, finite).
    growth : float
        ``g >= 1``: ``h(x) <= h_i + (g - 1) |x - x_i|`` for every source ``i``.
    hmax : float, optional
        Upper bound on the size.
    base : size specification, optional
        Another field (number or callable); the result never exceeds it.

    Returns
    -------
    SizeField
    """
    src = np.ascontiguousarray(np.asarray(points, dtype=np.float64).reshape(-1, 2))
    if len(src) == 0:
        raise SizeError("gradation needs at least one source point")
    h = np.broadcast_to(np.asarray(sizes, dtype=np.float64), (len(src),)).copy()
    bad = np.flatnonzero(~(np.isfinite(h) & (h > 0)) | ~np.isfinite(src).all(axis=1))
    if len(bad):
        i = bad[0]
        raise SizeError(f"gradation source {i} at {fmt_point(src[i])} has size {float(h[i])!r}")
    if not (np.isfinite(growth) and growth >= 1.0):
        raise SizeError(f"growth must be a finite factor >= 1, got {growth!r}")
    if hmax is not None and not (np.isfinite(hmax) and hmax > 0):
        raise SizeError(f"hmax must be positive and finite, got {hmax!r}")
    b = None if base is None else as_size_field(base)
    return SizeField(_Graded(src, h, float(growth) - 1.0, hmax, b), name=f"gradation(g={growth})")


def boundary_size(
    points, segments, growth: float = 1.2, hmax: float | None = None, scale: float = 1.0, base=None
) -> SizeField:
    """Graded size field from a discretised boundary's own spacing.

    Sources are the boundary points with size ``scale * dP_i`` (:func:`point_distribution`);
    points on no segment are ignored.  ``scale`` plays the role of Weatherill's ``alpha``.
    With ``base`` (a size the caller asked for) this is the grading of that size from the
    boundary: ``h(x) = min(base(x), min_i (dP_i + (g - 1) |x - x_i|))``, so that where the
    boundary is finer than ``base`` the size grows from the boundary spacing at most by
    ``g - 1`` per unit length (Persson 2006) instead of jumping, and ``base`` stays the
    upper bound (what Gmsh's ``Mesh.MeshSizeExtendFromBoundary`` does by interpolation).

    Parameters
    ----------
    points : (n, 2) float64
        Boundary vertices.
    segments : (m, 2) int
        Boundary segments (vertex indices).
    growth : float
        ``g >= 1``, as for :func:`gradation`.
    hmax : float, optional
        Upper bound on the size.
    scale : float
        Factor on the spacing at the sources, positive.
    base : size specification, optional
        Upper bound field (number or callable, :func:`~meshwright.sizing.field.as_size_field`).

    Returns
    -------
    SizeField

    Raises
    ------
    InputError
        Malformed points or segments.
    SizeError
        No segment, a bad ``growth``, ``hmax``, ``scale`` or ``base``.
    """
    if isinstance(scale, bool) or not isinstance(scale, (int, float)) or not (np.isfinite(scale) and scale > 0):
        raise SizeError(f"scale must be positive and finite, got {scale!r}")
    dp = point_distribution(points, segments)
    keep = np.isfinite(dp) & (dp > 0.0)
    if not keep.any():
        raise SizeError("boundary_size needs at least one segment of positive length")
    field = gradation(np.asarray(points, dtype=np.float64)[keep], scale * dp[keep], growth, hmax, base)
    field.name = f"{'' if base is None else as_size_field(base).name + ' '}graded from the boundary (g={growth:g})"
    return field


def is_stretched(field) -> bool:
    """Whether ``field`` is a 2-D background grid with stretching somewhere."""
    from meshwright.sizing.background import BackgroundGrid  # background imports this module

    return isinstance(field, BackgroundGrid) and field.dim == 2 and bool(np.any(field.stretch != 1.0))


def graded_from_boundary(field: SizeField | None, points, segments, grading: float | None) -> SizeField | None:
    """A given size graded from the boundary points spaced closer than it.

    What ``triangulate`` and the pairing methods follow when a size is given: ``field``
    capped by :func:`gradation` from the boundary points whose spacing (their point
    distribution, :func:`point_distribution`) is below :data:`FINER` times ``field``
    there, so that a fine boundary does not meet the size as a jump.

    Parameters
    ----------
    field : SizeField or None
    points : (n, 2) float64
        The boundary discretisation's points.
    segments : (m, 2) int
        Its segments.
    grading : float or None
        The growth ``g`` > 1 of :func:`gradation`.

    Returns
    -------
    SizeField or None
        ``field`` itself when no point is finer, ``grading`` is None, there is no size or
        no segment, or ``field`` is a stretched background grid (used as drawn).
    """
    if field is None or grading is None or not len(segments) or is_stretched(field):
        return field
    dp = point_distribution(points, segments)
    fine = np.isfinite(dp)
    fine[fine] = dp[fine] < FINER * field(points[fine])
    if not fine.any():
        return field
    graded = gradation(points[fine], dp[fine], grading, base=field)
    graded.name = f"{field.name} graded from the boundary (g={grading:g})"
    return graded
