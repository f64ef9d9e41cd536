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
from meshwright.core.predicates import orient2d, orient2d_batch

__all__ = ["check_orientation_nonconvex", "one_sided_edges", "simple_ccw_quads"]


def _fmt(points: np.ndarray, cell: np.ndarray) -> str:
    return ", ".join(f"({points[v, 0]:.17g}, {points[v, 1]:.17g})" for v in cell)


@njit(cache=True)
def _cover(n, q, t, la, lb):
    """The cells' directed edges ``a -> b`` (quads' (m, 4) int64 ``q`` first, then the
    triangles' (k, 3) int64 ``t``; ids below ``n``) whose reverse is no cell's edge, as an
    (e, 2) int64 array, and the flags of the lines ``la[i] - lb[i]`` that are no cell's edge
    either way.  The edge lists are built here, not gathered and concatenated by NumPy
    (that was half the check's time on a disk of 36,000 quads)."""
    mq = q.shape[0]
    m = 4 * mq + 3 * t.shape[0]
    ea = np.empty(m, dtype=np.int64)
    eb = np.empty(m, dtype=np.int64)
    for c in range(mq):
        for k in range(4):
            ea[4 * c + k] = q[c, k]
            eb[4 * c + k] = q[c, (k + 1) % 4]
    for c in range(t.shape[0]):
        for k in range(3):
            ea[4 * mq + 3 * c + k] = t[c, k]
            eb[4 * mq + 3 * c + k] = t[c, (k + 1) % 3]
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
    count = 0
    for e in range(m):
        u = ea[e]
        for j in range(ptr[eb[e]], ptr[eb[e] + 1]):
            if head[j] == u:
                lone[e] = False
                break
        if lone[e]:
            count += 1
    edges = np.empty((count, 2), dtype=np.int64)
    count = 0
    for e in range(m):
        if lone[e]:
            edges[count, 0] = ea[e]
            edges[count, 1] = eb[e]
            count += 1
    orphan = np.ones(la.shape[0], dtype=np.bool_)
    for i in range(la.shape[0]):
        for u, w in ((la[i], lb[i]), (lb[i], la[i])):
            for j in range(ptr[u], ptr[u + 1]):
                if head[j] == w:
                    orphan[i] = False
                    break
    return edges, orphan


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
    q = np.ascontiguousarray(quads, dtype=np.int64).reshape(-1, 4)
    t = np.ascontiguousarray(triangles, dtype=np.int64).reshape(-1, 3)
    ln = np.zeros((0, 2), dtype=np.int64) if lines is None else np.asarray(lines, dtype=np.int64).reshape(-1, 2)
    edges, orphan = _cover(np.int64(n_points), q, t, np.ascontiguousarray(ln[:, 0]), np.ascontiguousarray(ln[:, 1]))
    return edges if lines is None else (edges, np.flatnonzero(orphan))


@njit(cache=True)
def _simple_ccw(points, q):
    """(m,) bool: quads ``q`` (m, 4) int64 split into two strictly counter-clockwise
    triangles by the diagonal from corner 0 or from corner 1 (exact ``orient2d``; one pass,
    not four gathered batches)."""
    out = np.zeros(q.shape[0], dtype=np.bool_)
    for c in range(q.shape[0]):
        for k in range(2):
            a = q[c, k]
            b = q[c, k + 1]
            d = q[c, k + 2]
            e = q[c, (k + 3) % 4]
            if (orient2d(points[a, 0], points[a, 1], points[b, 0], points[b, 1], points[d, 0], points[d, 1]) > 0.0
                    and orient2d(points[d, 0], points[d, 1], points[e, 0], points[e, 1],
                                 points[a, 0], points[a, 1]) > 0.0):
                out[c] = True
                break
    return out


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
    return _simple_ccw(points, np.ascontiguousarray(quads, dtype=np.int64).reshape(-1, 4))


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
