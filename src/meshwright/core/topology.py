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


def edges_of(triangles: np.ndarray) -> np.ndarray:
    """Return the unique undirected edges, shape (e, 2) int32, each row sorted."""
    d = np.sort(directed_edges(triangles), axis=1)
    return np.unique(d, axis=0).astype(np.int32)


def boundary_edges_of(triangles: np.ndarray) -> np.ndarray:
    """Return the edges used by exactly one triangle, shape (b, 2) int32, in the triangle's direction.

    For a counter-clockwise mesh the returned edges run counter-clockwise around the outer
    boundary and clockwise around holes (the domain lies to their left).
    """
    d = directed_edges(triangles)
    key = np.sort(d, axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    return d[counts[inverse.ravel()] == 1].astype(np.int32)
