"""Edge extraction for simplicial meshes (vectorised NumPy, no per-element Python loops).

Array layout: triangles (m, 3) int32 counter-clockwise; edges returned as (e, 2) int32 with
``edges[:, 0] < edges[:, 1]`` unless stated otherwise.
"""

from __future__ import annotations

import numpy as np

__all__ = ["directed_edges", "edges_of", "boundary_edges_of"]


def directed_edges(triangles: np.ndarray) -> np.ndarray:
    """Return the 3m directed edges of counter-clockwise triangles.

    Row ``3*t + k`` is edge k of triangle t, the edge opposite vertex k, running from
    vertex ``(k+1) % 3`` to vertex ``(k+2) % 3``.

    Parameters
    ----------
    triangles : (m, 3) int

    Returns
    -------
    (3m, 2) int64
    """
    t = np.asarray(triangles, dtype=np.int64)
    return np.stack([t[:, [1, 2, 0]], t[:, [2, 0, 1]]], axis=-1).reshape(-1, 2)


def _edge_keys(pairs: np.ndarray) -> tuple[np.ndarray, int]:
    """One int64 key ``a * n + b`` per row of ``pairs`` (e, 2) int64 (non-negative), and n.

    A 1-D sort of these keys orders the rows lexicographically, as ``np.unique(..., axis=0)``
    does, 10-30x faster: that one sorts a void view of the rows (0.96 s of 1.01 s for the
    boundary edges of 289,000 triangles).
    """
    n = int(pairs.max()) + 1 if len(pairs) else 1
    return pairs[:, 0] * n + pairs[:, 1], n


def edges_of(triangles: np.ndarray) -> np.ndarray:
    """Return the unique undirected edges, shape (e, 2) int32, each row sorted, rows in
    lexicographic order."""
    key, n = _edge_keys(np.sort(directed_edges(triangles), axis=1))
    u = np.unique(key)
    return np.column_stack([u // n, u % n]).astype(np.int32)


def boundary_edges_of(triangles: np.ndarray) -> np.ndarray:
    """Return the edges used by exactly one triangle, shape (b, 2) int32, in the triangle's direction.

    For a counter-clockwise mesh the returned edges run counter-clockwise around the outer
    boundary and clockwise around holes (the domain lies to their left).
    """
    d = directed_edges(triangles)
    key, _ = _edge_keys(np.sort(d, axis=1))
    _, inverse, counts = np.unique(key, return_inverse=True, return_counts=True)
    return d[counts[inverse] == 1].astype(np.int32)
