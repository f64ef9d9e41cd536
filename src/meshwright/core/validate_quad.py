"""Orientation check of 2-D meshes whose quads may be non-convex (``allow_nonconvex``).

``Mesh.validate`` requires every quad to be strictly convex: all four corner triples
``(q[k-1], q[k], q[k+1])`` strictly counter-clockwise by the exact ``orient2d``, i.e. a
strictly positive Jacobian at every corner.  The advancing-front pairing of section
18.5.1 (Zhu et al. 1991) tolerates angles of 180 degrees and more before its shape
enhancement, so :func:`check_orientation_nonconvex` accepts any *simple*
counter-clockwise quad instead: one whose diagonal from corner 0 or from corner 1 splits
it into two strictly counter-clockwise triangles.  A convex quad passes by either
diagonal, a quad with one reflex corner by the diagonal from that corner, a
self-intersecting (bow-tie) or clockwise quad by neither (each diagonal leaves one
triangle clockwise or flat).  Triangles of the mesh must still be strictly
counter-clockwise.  Every sign is exact (:mod:`meshwright.core.predicates`).

:func:`one_sided_edges` is the cover check's search (``quadrangulate``'s door out): the
directed cell edges with no cell on their other side, and the line cells that are no cell's
edge, found in O(cells) through a vertex-to-outgoing-edge table in CSR form (a sort of all
edge keys cost a tenth of a paving run on the disk).

Array layout: points (n, 2) float64; quads (m, 4) and triangles (t, 3) int32,
counter-clockwise.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.errors import ValidationError
from meshwright.core.predicates import orient2d_batch

__all__ = ["check_orientation_nonconvex", "one_sided_edges", "simple_ccw_quads"]


def _fmt(points: np.ndarray, cell: np.ndarray) -> str:
    return ", ".join(f"({points[v, 0]:.17g}, {points[v, 1]:.17g})" for v in cell)


@njit(cache=True)
def _cover(n, ea, eb, la, lb):
    """Flags of the directed edges ``ea[e] -> eb[e]`` (ids below ``n``) whose reverse is
    not among them, and of the lines ``la[i] - lb[i]`` that are no such edge either way."""
    m = ea.shape[0]
    ptr = np.zeros(n + 1, dtype=np.int64)
    for e in range(m):
        ptr[ea[e] + 1] += 1
    for v in range(n):
        ptr[v + 1] += ptr[v]
    fill = ptr[:-1].copy()
    head = np.empty(m, dtype=np.int64)
    for e in range(m):
        head[fill[ea[e]]] = eb[e]
        fill[ea[e]] += 1
    lone = np.ones(m, dtype=np.bool_)
    for e in range(m):
        u = ea[e]
        for j in range(ptr[eb[e]], ptr[eb[e] + 1]):
            if head[j] == u:
                lone[e] = False
                break
    orphan = np.ones(la.shape[0], dtype=np.bool_)
    for i in range(la.shape[0]):
        for u, w in ((la[i], lb[i]), (lb[i], la[i])):
            for j in range(ptr[u], ptr[u + 1]):
                if head[j] == w:
                    orphan[i] = False
                    break
    return lone, orphan


def one_sided_edges(n_points: int, quads: np.ndarray, triangles: np.ndarray, lines=None):
    """Directed cell edges with no cell on their other side (and, given ``lines``, the
    lines that are no cell's edge).

    Parameters
    ----------
    n_points : int
        Number of points (every id below it).
    quads : (m, 4) int
    triangles : (t, 3) int
        Counter-clockwise cells.
    lines : (k, 2) int, optional
        Line cells to look up among the cell edges (either direction).

    Returns
    -------
    (e, 2) int64
        Each edge ``(u, v)`` of a cell (the cell on its left) whose reverse ``(v, u)``
        belongs to no cell, quads' edges first.
    (j,) int64
        Only with ``lines``: the rows of ``lines`` that are no cell's edge.
    """
    q = np.asarray(quads, dtype=np.int64).reshape(-1, 4)
    t = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    ea = np.concatenate([q.ravel(), t.ravel()])
    eb = np.concatenate([q[:, [1, 2, 3, 0]].ravel(), t[:, [1, 2, 0]].ravel()])
    ln = np.zeros((0, 2), dtype=np.int64) if lines is None else np.asarray(lines, dtype=np.int64).reshape(-1, 2)
    lone, orphan = _cover(np.int64(n_points), ea, eb, np.ascontiguousarray(ln[:, 0]), np.ascontiguousarray(ln[:, 1]))
    edges = np.stack([ea[lone], eb[lone]], axis=1)
    return edges if lines is None else (edges, np.flatnonzero(orphan))


def simple_ccw_quads(points: np.ndarray, quads: np.ndarray) -> np.ndarray:
    """Which quads are simple and counter-clockwise (non-convex allowed).

    Parameters
    ----------
    points : (n, 2) float64
    quads : (m, 4) int

    Returns
    -------
    (m,) bool
    """
    q = np.asarray(quads, dtype=np.int64)
    ok = np.zeros(len(q), dtype=bool)
    for k in (0, 1):
        first = np.ascontiguousarray(q[:, [k, k + 1, k + 2]])
        second = np.ascontiguousarray(q[:, [k + 2, (k + 3) % 4, k]])
        s1 = np.asarray(orient2d_batch(points, first))
        s2 = np.asarray(orient2d_batch(points, second))
        ok |= (s1 > 0) & (s2 > 0)
    return ok


def check_orientation_nonconvex(mesh) -> None:
    """Raise :class:`ValidationError` unless every triangle is strictly counter-clockwise
    and every quad simple and counter-clockwise (module docstring).

    Parameters
    ----------
    mesh : Mesh
        A 2-D mesh.
    """
    points = mesh.points
    tris = mesh.cells_of("triangle")
    if len(tris):
        sign = np.asarray(orient2d_batch(points, np.ascontiguousarray(tris, dtype=np.int64)))
        bad = np.flatnonzero(sign <= 0)
        if len(bad):
            c = int(bad[0])
            what = "degenerate (zero area)" if sign[c] == 0 else "inverted (negative area)"
            raise ValidationError(
                f"triangle {c} (vertices {', '.join(str(int(v)) for v in tris[c])}) at {_fmt(points, tris[c])} "
                f"is {what}; {len(bad)} such cells in total"
            )
    quads = mesh.cells_of("quad")
    if len(quads):
        bad = np.flatnonzero(~simple_ccw_quads(points, quads))
        if len(bad):
            c = int(bad[0])
            raise ValidationError(
                f"quad {c} (vertices {', '.join(str(int(v)) for v in quads[c])}) at {_fmt(points, quads[c])} "
                f"is not a simple counter-clockwise quadrilateral (self-intersecting, clockwise or flat); "
                f"{len(bad)} such cells in total"
            )
