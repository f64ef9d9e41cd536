"""Region markers of a finished quad-dominant mesh: flood fill from the domain's seeds.

As in Triangle's regional attributes (Shewchuk 1996) and the triangle layer's
``ConstrainedTriangulation.classify``: each region seed ``(x, y, marker, ...)`` marks the
cell containing it and every cell reachable from there without crossing a ``line`` cell
(a boundary or interior segment); later seeds overwrite earlier ones, cells reached by no
seed get marker 0.  Working on the finished cells makes it independent of the method
that made them: any method honouring the interior segments as line cells gets markers.

Array layout: points (n, 2) float64; quads (m, 4) and triangles (t, 3) int32
counter-clockwise; lines (k, 2) int32.  Cell ``c`` of the combined numbering is quad
``c`` for ``c < m``, else triangle ``c - m``.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.errors import GeometryError
from meshwright.core.predicates import orient2d_batch

__all__ = ["region_markers"]


@njit(cache=True)
def _root(parent, a):
    while parent[a] != a:
        parent[a] = parent[parent[a]]  # path halving keeps the trees shallow
        a = parent[a]
    return a


@njit(cache=True)
def _components(n_cells, pairs):
    """Component label (its root cell) of each cell, cells joined across ``pairs`` (p, 2)."""
    parent = np.arange(n_cells)
    for e in range(pairs.shape[0]):
        a = _root(parent, pairs[e, 0])
        b = _root(parent, pairs[e, 1])
        if a != b:
            parent[max(a, b)] = min(a, b)
    for c in range(n_cells):
        parent[c] = _root(parent, c)
    return parent


def _contains(points: np.ndarray, tri: np.ndarray, xy: np.ndarray) -> np.ndarray:
    """(t,) bool: triangles (t, 3) containing ``xy``, their closed edges included (exact
    ``orient2d`` of the point against each edge)."""
    ext = np.ascontiguousarray(np.vstack([points, xy[None, :]]))
    q = np.full(len(tri), len(points), dtype=np.int64)
    inside = np.ones(len(tri), dtype=bool)
    for k in range(3):
        edge = np.ascontiguousarray(np.column_stack([tri[:, k], tri[:, (k + 1) % 3], q]))
        inside &= np.asarray(orient2d_batch(ext, edge)) >= 0
    return inside


def region_markers(points, quads, triangles, lines, regions) -> tuple[np.ndarray, np.ndarray]:
    """Markers of the quads and triangles by flood fill from the region seeds.

    Parameters
    ----------
    points : (n, 2) float64
    quads : (m, 4) int
    triangles : (t, 3) int
    lines : (k, 2) int
        Edges the fill does not cross.
    regions : sequence of (x, y, marker[, max_area])

    Returns
    -------
    quad_markers : (m,) int32
    triangle_markers : (t,) int32

    Raises
    ------
    GeometryError
        A seed in no cell (named by index and coordinates).
    """
    quads = np.asarray(quads, dtype=np.int64)
    triangles = np.asarray(triangles, dtype=np.int64)
    m, n_cells = len(quads), len(quads) + len(triangles)
    n = len(points)
    edges, owner = [], []
    for block, base in ((quads, 0), (triangles, m)):
        if len(block):
            edges.append(np.column_stack([block.ravel(), np.roll(block, -1, axis=1).ravel()]))
            owner.append(base + np.repeat(np.arange(len(block)), block.shape[1]))
    e = np.concatenate(edges)
    own = np.concatenate(owner)
    key = np.minimum(e[:, 0], e[:, 1]) * n + np.maximum(e[:, 0], e[:, 1])
    lines = np.asarray(lines, dtype=np.int64).reshape(-1, 2)
    cut = np.isin(key, np.minimum(lines[:, 0], lines[:, 1]) * n + np.maximum(lines[:, 0], lines[:, 1]))
    order = np.argsort(key, kind="stable")
    ks, os_ = key[order], own[order]
    twin = np.flatnonzero((ks[1:] == ks[:-1]) & ~cut[order][1:])
    label = _components(n_cells, np.column_stack([os_[twin], os_[twin + 1]]))
    # Each quad as two triangles for the seed location.
    tris = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]], triangles])
    tri_cell = np.concatenate([np.arange(m), np.arange(m), m + np.arange(len(triangles))])
    marker = np.zeros(n_cells, dtype=np.int32)
    for i, r in enumerate(regions):
        xy = np.array(r[:2], dtype=np.float64)
        hit = np.flatnonzero(_contains(points, tris, xy))
        if not len(hit):
            raise GeometryError(f"region {i} seed ({xy[0]:.17g}, {xy[1]:.17g}) lies in no cell of the mesh")
        marker[label == label[tri_cell[hit[0]]]] = int(r[2])
    return marker[:m], marker[m:]
