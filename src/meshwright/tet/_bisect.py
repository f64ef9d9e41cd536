"""Longest-edge bisection of subfaces (Rivara 1984) at midpoints or concentric-shell points.

Split out of :mod:`meshwright.tet.recovery`, which describes the scheme: marked edges are
closed under "a subface with a marked edge has its longest edge marked", each subface is
bisected at its longest edge and its halves at their other marked edges, so the subfaces stay
conforming.  Boundary recovery and the quality refinement's encroachment splits both use it.

Arrays: ``faces`` (m, 3) int32 subfaces, ``parent`` (m,) int32 their input faces, ``edges``
(e, 2) int32 and ``face_edges`` (m, 3) int64 from :func:`meshwright.tet.recovery.unique_edges`.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["bisect_marked", "shell_points"]


@njit(cache=True)
def _longest(pts, faces, face_edges, f):
    """Corner opposite the longest edge of face f (ties to the larger edge id)."""
    best = -1.0
    kb = 0
    for k in range(3):
        a = faces[f, (k + 1) % 3]
        b = faces[f, (k + 2) % 3]
        d = 0.0
        for j in range(3):
            x = pts[a, j] - pts[b, j]
            d += x * x
        if d > best or (d == best and face_edges[f, k] > face_edges[f, kb]):
            best = d
            kb = k
    return kb


@njit(cache=True)
def _close_marks(pts, faces, face_edges, mark):
    """Rivara's closure: every face with a marked edge gets its longest edge marked."""
    changed = True
    while changed:
        changed = False
        for f in range(faces.shape[0]):
            if mark[face_edges[f, 0]] or mark[face_edges[f, 1]] or mark[face_edges[f, 2]]:
                e = face_edges[f, _longest(pts, faces, face_edges, f)]
                if not mark[e]:
                    mark[e] = True
                    changed = True


@njit(cache=True)
def _bisect(pts, faces, parent, face_edges, mark, mid):
    """Split every face with marked edges (longest first); (faces', parent', kept) new arrays,
    ``kept`` (m',) int64 the face each unsplit row is a copy of, -1 for the halves."""
    m = faces.shape[0]
    out = np.empty((4 * m, 3), dtype=np.int32)
    par = np.empty(4 * m, dtype=np.int32)
    kept = np.full(4 * m, -1, dtype=np.int64)
    n = 0
    for f in range(m):
        k = _longest(pts, faces, face_edges, f)
        if not mark[face_edges[f, k]]:
            out[n, 0] = faces[f, 0]
            out[n, 1] = faces[f, 1]
            out[n, 2] = faces[f, 2]
            par[n] = parent[f]
            kept[n] = f
            n += 1
            continue
        vi = faces[f, k]
        v1 = faces[f, (k + 1) % 3]
        v2 = faces[f, (k + 2) % 3]
        mm = mid[face_edges[f, k]]
        e2 = face_edges[f, (k + 2) % 3]  # edge v_i v_i+1 (opposite v_i+2)
        e1 = face_edges[f, (k + 1) % 3]  # edge v_i+2 v_i (opposite v_i+1)
        if mark[e2]:  # half (v_i, v_i+1, m) split at m2 on v_i v_i+1
            m2 = mid[e2]
            out[n, 0], out[n, 1], out[n, 2] = mm, vi, m2
            out[n + 1, 0], out[n + 1, 1], out[n + 1, 2] = mm, m2, v1
            par[n] = parent[f]
            par[n + 1] = parent[f]
            n += 2
        else:
            out[n, 0], out[n, 1], out[n, 2] = vi, v1, mm
            par[n] = parent[f]
            n += 1
        if mark[e1]:  # half (v_i, m, v_i+2) split at m3 on v_i+2 v_i
            m3 = mid[e1]
            out[n, 0], out[n, 1], out[n, 2] = mm, v2, m3
            out[n + 1, 0], out[n + 1, 1], out[n + 1, 2] = mm, m3, vi
            par[n] = parent[f]
            par[n + 1] = parent[f]
            n += 2
        else:
            out[n, 0], out[n, 1], out[n, 2] = vi, mm, v2
            par[n] = parent[f]
            n += 1
    return out[:n].copy(), par[:n].copy(), kept[:n].copy()


def shell_points(pts: np.ndarray, e: np.ndarray, n_apex: int) -> np.ndarray:
    """Split points (k, 3) float64 of the edges ``e`` (k, 2): midpoints, except on concentric shells.

    An edge with exactly one end below ``n_apex`` (an input vertex) is split at the power of
    two nearest half its length, measured from that end (Ruppert's and Shewchuk's concentric
    shells, as Triangle splits segments).  Two input edges meeting at a small angle are then
    split at the same radii around their common vertex, so a split point on one never lies
    in the diametral ball of the other's piece at that vertex: with midpoints the two edges'
    pieces encroached on each other in turn and each split made the other edge's piece
    missing again, down to the guard (an extruded star's 6-degree corner, fuzz seed 21
    case 18).  The pieces keep between 0.29 and 0.71 of the edge's length.
    """
    a = pts[e[:, 0]]
    b = pts[e[:, 1]]
    out = 0.5 * (a + b)
    first = e[:, 0] < n_apex
    one = first != (e[:, 1] < n_apex)
    if one.any():
        apex = np.where(first[one, None], a[one], b[one])
        other = np.where(first[one, None], b[one], a[one])
        length = np.linalg.norm(other - apex, axis=1)
        radius = np.exp2(np.round(np.log2(0.5 * length)))
        out[one] = apex + (radius / length)[:, None] * (other - apex)
    return out


def bisect_marked(pts, faces, parent, edges, face_edges, mark, new_vertex, origins=None, n_apex=0):
    """Close ``mark`` (Rivara), create the split points and bisect the subfaces.

    Parameters
    ----------
    pts : (n, 3) float64
        Coordinates of every vertex the faces use.
    faces : (m, 3) int32
    parent : (m,) int32
    edges : (e, 2) int32
    face_edges : (m, 3) int64
    mark : (e,) bool
        Edges to split (closed in place).
    new_vertex : callable
        ``new_vertex(points (k, 3)) -> (k,) int32`` inserts the split points, returns their ids.
    origins : SplitOrigins, optional
        Records the edge each split point splits.
    n_apex : int
        Vertices below this id are shell centres (:func:`shell_points`); 0: midpoints only.

    Returns
    -------
    faces, parent : the bisected subfaces; ``pts`` rows are not updated (read them again).
    count : int
        Midpoints inserted.
    kept : (m',) int64
        The input face each unsplit output face is, -1 for the halves.
    """
    _close_marks(pts, faces, face_edges, mark)
    sel = np.flatnonzero(mark)
    if sel.size == 0:
        return faces, parent, 0, np.arange(faces.shape[0], dtype=np.int64)
    e = edges[sel]
    ids = new_vertex(shell_points(pts, e, n_apex))
    if origins is not None:
        origins.record(ids, e)
    mid = np.full(edges.shape[0], -1, dtype=np.int32)
    mid[sel] = ids
    faces2, parent2, kept = _bisect(pts, faces, parent, face_edges, mark, mid)
    return faces2, parent2, int(sel.size), kept
