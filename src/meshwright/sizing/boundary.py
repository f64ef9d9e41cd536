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
  minima, searched best first by a lower bound per cell, so no KD-tree (and no SciPy) is
  needed.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from meshwright.core.errors import InputError, SizeError
from meshwright.core.heap import heap_pop, heap_push
from meshwright.sizing.field import SizeField, as_size_field, fmt_point

__all__ = ["point_distribution", "gradation", "boundary_size"]


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


@nb.njit(cache=True)
def _cone_min(query, upper, src, h, slope, start, items, hmin, off, gxs, gys, x0, y0, w):
    """``min(upper_k, min_i h_i + slope |q_k - src_i|)`` for each query ``q_k``, best first
    over a pyramid of cells (:func:`_pyramid`): a cell is opened in the order of its lower
    bound ``hmin(cell) + slope dist(q_k, cell)`` and the search stops when the next bound
    is not below the best value found.  A ring search on the finest grid with the global
    smallest size as its bound visited every cell within ``best / slope`` of a query far
    from a fine source: O(sources) per query on a boundary with a tiny feature."""
    out = np.empty(query.shape[0])
    top = gxs.shape[0] - 1
    hkey = np.empty(256)
    hval = np.empty((256, 3), dtype=np.int32)
    for k in range(query.shape[0]):
        qx, qy = query[k, 0], query[k, 1]
        best = upper[k]
        n = 0
        for j in range(gys[top]):
            for i in range(gxs[top]):
                hkey, hval = _grow_heap(hkey, hval, n + 1)
                e = heap_push(hkey, hval, n, hmin[off[top] + j * gxs[top] + i])
                hval[e, 0], hval[e, 1], hval[e, 2] = top, i, j
                n += 1
        while n > 0:
            if hkey[0] >= best:
                break
            lev, i, j = hval[0, 0], hval[0, 1], hval[0, 2]
            heap_pop(hkey, hval, n)
            n -= 1
            if lev == 0:
                c = j * gxs[0] + i
                for p in range(start[c], start[c + 1]):
                    s = items[p]
                    ex = qx - src[s, 0]
                    ey = qy - src[s, 1]
                    v = h[s] + slope * np.sqrt(ex * ex + ey * ey)
                    if v < best:
                        best = v
                continue
            side = w * 2.0 ** (lev - 1)
            for b in range(2):
                for a in range(2):
                    ci = 2 * i + a
                    cj = 2 * j + b
                    if ci >= gxs[lev - 1] or cj >= gys[lev - 1]:
                        continue
                    hm = hmin[off[lev - 1] + cj * gxs[lev - 1] + ci]
                    if not hm < best:
                        continue
                    dx = max(x0 + ci * side - qx, 0.0, qx - (x0 + (ci + 1) * side))
                    dy = max(y0 + cj * side - qy, 0.0, qy - (y0 + (cj + 1) * side))
                    bound = hm + slope * np.sqrt(dx * dx + dy * dy)
                    if bound < best:
                        hkey, hval = _grow_heap(hkey, hval, n + 1)
                        e = heap_push(hkey, hval, n, bound)
                        hval[e, 0], hval[e, 1], hval[e, 2] = lev - 1, ci, cj
                        n += 1
        out[k] = best
    return out


@nb.njit(inline="always")
def _grow_heap(hkey, hval, need):
    """The heap arrays with room for ``need`` entries (doubling)."""
    if need <= hkey.shape[0]:
        return hkey, hval
    cap = 2 * hkey.shape[0]
    while cap < need:
        cap *= 2
    nk = np.empty(cap)
    nv = np.empty((cap, 3), dtype=np.int32)
    nk[: hkey.shape[0]] = hkey
    nv[: hkey.shape[0]] = hval
    return nk, nv


def _pyramid(cell_hmin: np.ndarray, gx: int, gy: int):
    """Min-pyramid of a (gy, gx) grid of cell minima: a cell of level L + 1 holds the
    minimum of its four cells of level L (inf outside), up to a level of at most 4 cells.

    Returns
    -------
    hmin : (total,) float64
        Every level's cells, row-major, level 0 first.
    off : (levels + 1,) int64
        Start of each level in ``hmin``.
    gxs, gys : (levels,) int64
        Cells per row and per column of each level.
    """
    levels = [cell_hmin.reshape(gy, gx)]
    while levels[-1].size > 4:
        a = levels[-1]
        ny, nx = a.shape
        b = np.full((ny + ny % 2, nx + nx % 2), np.inf)
        b[:ny, :nx] = a
        levels.append(b.reshape(b.shape[0] // 2, 2, b.shape[1] // 2, 2).min(axis=(1, 3)))
    off = np.concatenate([[0], np.cumsum([a.size for a in levels])]).astype(np.int64)
    gxs = np.array([a.shape[1] for a in levels], dtype=np.int64)
    gys = np.array([a.shape[0] for a in levels], dtype=np.int64)
    return np.concatenate([a.ravel() for a in levels]), off, gxs, gys


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
        self.cell_hmin = np.full(ncell, np.inf)
        np.minimum.at(self.cell_hmin, cell, h)
        self.pyramid = _pyramid(self.cell_hmin, self.gx, self.gy)

    def __call__(self, xy: np.ndarray) -> np.ndarray:
        q = np.ascontiguousarray(xy, dtype=np.float64)
        upper = np.full(len(q), np.inf if self.hmax is None else float(self.hmax))
        if self.base is not None:
            upper = np.minimum(upper, self.base(q))
        if self.slope == 0.0:
            out = np.minimum(upper, self.h.min())
        else:
            out = _cone_min(
                q, upper, self.src, self.h, self.slope, self.start, self.items, *self.pyramid, self.x0, self.y0, self.w
            )
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
