"""Quality-guarded Laplacian smoothing of quad-dominant meshes (shared by the quad methods).

Each free vertex moves towards the mean of its edge neighbours (Gauss-Seidel sweeps, the
plain Laplacian of Herrmann 1976 as used by every chapter 18.5 method after its
topology is fixed); a move is kept only if the smallest corner sine (the scaled Jacobian
of quads, the sine of the angle for triangles) over the cells around the vertex does not
fall, else half the move is tried, else the vertex stays.  This is the "smart" Laplacian
of Canann, Tristano and Staten (IMR 1998): it never inverts a cell and never lowers the
mesh's minimum scaled Jacobian, so a valid mesh stays valid.  Vertices on ``line`` cells
(the boundary and interior segments) are fixed, which keeps them on their true curves.

Array layout: points (n, 2) float64; cells (m, 4) int64, a triangle padded with -1 in
column 3, counter-clockwise; vertex-to-cell and vertex-to-neighbour tables in CSR form
(``ptr`` (n + 1,), ``idx``).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.validate_input import check_count

__all__ = ["smooth_cells"]


@njit(cache=True)
def _min_sine(points, cells, cell_ptr, cell_idx, v):
    """Smallest corner sine over the cells around vertex ``v``."""
    worst = 1.0
    for t in range(cell_ptr[v], cell_ptr[v + 1]):
        c = cell_idx[t]
        nv = 4 if cells[c, 3] >= 0 else 3
        for k in range(nv):
            a = cells[c, (k + nv - 1) % nv]
            b = cells[c, k]
            d = cells[c, (k + 1) % nv]
            ux = points[d, 0] - points[b, 0]
            uy = points[d, 1] - points[b, 1]
            wx = points[a, 0] - points[b, 0]
            wy = points[a, 1] - points[b, 1]
            den = np.sqrt((ux * ux + uy * uy) * (wx * wx + wy * wy))
            s = (ux * wy - uy * wx) / den if den > 0.0 else -1.0
            if s < worst:
                worst = s
    return worst


@njit(cache=True)
def _sweeps(points, cells, cell_ptr, cell_idx, nbr_ptr, nbr_idx, free, passes):
    """Gauss-Seidel guarded Laplacian sweeps in place; returns the moves kept."""
    kept = 0
    for _ in range(passes):
        for v in range(points.shape[0]):
            if not free[v] or nbr_ptr[v + 1] == nbr_ptr[v]:
                continue
            tx = 0.0
            ty = 0.0
            for t in range(nbr_ptr[v], nbr_ptr[v + 1]):
                tx += points[nbr_idx[t], 0]
                ty += points[nbr_idx[t], 1]
            k = nbr_ptr[v + 1] - nbr_ptr[v]
            tx /= k
            ty /= k
            x0 = points[v, 0]
            y0 = points[v, 1]
            before = _min_sine(points, cells, cell_ptr, cell_idx, v)
            for step in (1.0, 0.5):
                points[v, 0] = x0 + step * (tx - x0)
                points[v, 1] = y0 + step * (ty - y0)
                if _min_sine(points, cells, cell_ptr, cell_idx, v) >= before:
                    kept += 1
                    break
                points[v, 0] = x0
                points[v, 1] = y0
    return kept


def _csr(n: int, rows: np.ndarray, values: np.ndarray):
    order = np.argsort(rows, kind="stable")
    ptr = np.zeros(n + 1, np.int64)
    np.add.at(ptr, rows + 1, 1)
    return np.cumsum(ptr), np.ascontiguousarray(values[order])


def smooth_cells(points, quads, triangles, fixed, passes: int) -> np.ndarray:
    """Guarded Laplacian smoothing (module docstring).

    Parameters
    ----------
    points : (n, 2) float64
    quads : (m, 4) int
    triangles : (t, 3) int
        Counter-clockwise cells of a valid mesh.
    fixed : (n,) bool
        Vertices that never move (boundary and interior-segment vertices).
    passes : int
        Gauss-Seidel sweeps (>= 0).

    Returns
    -------
    (n, 2) float64
        New coordinates (the input is not modified).
    """
    passes = check_count(passes, "passes")
    pts = np.array(points, dtype=np.float64, order="C")
    cells = np.full((len(quads) + len(triangles), 4), -1, np.int64)
    cells[: len(quads)] = quads
    cells[len(quads) :, :3] = triangles
    n = len(pts)
    nv = np.where(cells[:, 3] >= 0, 4, 3)
    owner = np.repeat(np.arange(len(cells)), 4)
    flat = cells.ravel()
    used = flat >= 0
    cell_ptr, cell_idx = _csr(n, flat[used], owner[used])
    # Edges of every cell, both directions, deduplicated.
    nxt = np.where(np.arange(4)[None, :] + 1 < nv[:, None], np.roll(cells, -1, axis=1), cells[:, :1])
    a, b = cells.ravel()[used], nxt.ravel()[used]
    # One int64 key per directed edge: a 1-D unique, same order as the rows' lexicographic one.
    e0, e1 = np.divmod(np.unique(np.concatenate([a * n + b, b * n + a])), n)
    nbr_ptr, nbr_idx = _csr(n, e0, e1)
    free = ~np.asarray(fixed, dtype=bool)
    _sweeps(pts, cells, cell_ptr, cell_idx, nbr_ptr, nbr_idx, free, passes)
    return pts
