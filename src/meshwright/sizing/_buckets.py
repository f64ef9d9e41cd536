r"""Point-location scaffolding shared by the 2-D and 3-D background grids: a uniform bucket
grid over simplices in any dimension d (2 or 3).

The bucket grid is the classical uniform "cell list" of computational geometry: the
bounding box of the background is cut into cubes of side ``cell`` and each simplex is listed
in every cube its bounding box touches; a query looks only at the simplices of its own cube
(and of rings of cubes around it when it lies in none).  About two simplices per cube on
average (``cells`` per axis is ``(m / 2) ** (1 / d)`` over the longest extent).

Layout
------
``pts`` (n, d) float64, ``cells`` (m, d + 1) int32 (simplex vertices), ``lo`` (d,) float64
the grid's lower corner, ``cell`` float the cube side, ``dims`` (d,) int64 the number of cubes
per axis.  Cube ``(i0, i1, i2)`` has the flat index ``i0 + dims[0] * (i1 + dims[1] * i2)``
(in 2-D ``j * nx + i``); the lists are CSR: ``start`` (cubes + 1,) int64 and ``items``
(total,) int32, cube c holding ``items[start[c]:start[c + 1]]``.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["bucket_grid", "bucket_shape"]


def bucket_shape(pts: np.ndarray, m: int) -> tuple[np.ndarray, float, np.ndarray]:
    """Lower corner, cube side and cubes per axis for ``m`` simplices on ``pts`` (n, d).

    Returns
    -------
    lo : (d,) float64
    cell : float
        Positive (1.0 when all points coincide).
    dims : (d,) int64
        At least 1 per axis.
    """
    d = pts.shape[1]
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    ext = float(max(hi - lo))
    # np.sqrt in 2-D keeps the 2-D grid exactly the one it has always been.
    per_axis = np.sqrt(m / 2.0) if d == 2 else np.cbrt(m / 2.0)
    cells = max(1, int(per_axis))
    cell = ext / cells if ext > 0 else 1.0
    if d == 2 and ext > 0:
        # A thin box (aspect above 4) gets as many cubes as a square one, not one row of
        # sqrt(m) crowded cubes; other boxes keep their grid.
        thin = float(np.sqrt(ext * float(min(hi - lo)) / max(m / 2.0, 1.0)))
        if thin < 0.5 * cell:
            cell = max(thin, ext / (2.0 * m + 2.0))
    dims = np.array([max(1, int(np.ceil((hi[k] - lo[k]) / cell)) + 1) for k in range(d)], dtype=np.int64)
    return np.ascontiguousarray(lo, dtype=np.float64), cell, dims


@njit(inline="always")
def _axis_range(pts, cells, t, k, lo, cell, dims):
    """Cube indices ``(i0, i1)`` along axis k touched by the bounding box of simplex t."""
    a = pts[cells[t, 0], k]
    b = a
    for j in range(1, cells.shape[1]):
        v = pts[cells[t, j], k]
        a = min(a, v)
        b = max(b, v)
    i0 = min(dims[k] - 1, max(0, int((a - lo[k]) / cell)))
    i1 = min(dims[k] - 1, max(0, int((b - lo[k]) / cell)))
    return i0, i1


@njit(inline="always")
def _box(pts, cells, t, lo, cell, dims, first, count):
    """Fill ``first`` (d,) and ``count`` (d,) with the cube box of simplex t; returns its size."""
    total = 1
    for k in range(pts.shape[1]):
        i0, i1 = _axis_range(pts, cells, t, k, lo, cell, dims)
        first[k] = i0
        count[k] = i1 - i0 + 1
        total *= count[k]
    return total


@njit(inline="always")
def _cube_of(first, count, dims, r):
    """Flat index of the r-th cube of the box ``first`` + [0, count) (axis 0 fastest)."""
    c = 0
    stride = 1
    for k in range(first.shape[0]):
        c += (first[k] + r % count[k]) * stride
        r //= count[k]
        stride *= dims[k]
    return c


@njit(cache=True)
def bucket_grid(pts, cells, lo, cell, dims):
    """CSR lists ``(start, items)`` of the simplices whose bounding box touches each cube.

    Parameters
    ----------
    pts : (n, d) float64
    cells : (m, d + 1) int32
    lo : (d,) float64
    cell : float
    dims : (d,) int64

    Returns
    -------
    start : (prod(dims) + 1,) int64
    items : (start[-1],) int32
    """
    d = pts.shape[1]
    m = cells.shape[0]
    ncubes = 1
    for k in range(d):
        ncubes *= dims[k]
    first = np.empty(d, dtype=np.int64)
    count = np.empty(d, dtype=np.int64)
    start = np.zeros(ncubes + 1, dtype=np.int64)
    for t in range(m):
        total = _box(pts, cells, t, lo, cell, dims, first, count)
        for r in range(total):
            start[_cube_of(first, count, dims, r) + 1] += 1
    for c in range(ncubes):
        start[c + 1] += start[c]
    items = np.empty(start[ncubes], dtype=np.int32)
    fill = start[:-1].copy()
    for t in range(m):
        total = _box(pts, cells, t, lo, cell, dims, first, count)
        for r in range(total):
            c = _cube_of(first, count, dims, r)
            items[fill[c]] = t
            fill[c] += 1
    return start, items
