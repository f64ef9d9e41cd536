"""All-quad finish: one midpoint split of every element (triangle -> 3 quads, quad -> 4).

The classical route to an all-quad mesh from a mixed one (Gmsh's
``Mesh.SubdivisionAlgorithm = 1``, TQMesh's quad refinement; see
``design-notes-quads.md`` section 1): every edge gets its midpoint, every element its
centroid, and corner ``k`` of an element with its two edge midpoints and the centroid
forms one quad.  Midpoints are shared by the two elements of an edge, so a conforming
mesh stays conforming; a boundary or interior-segment edge's midpoint is projected onto
its true curve (the arc-length midpoint, ``Domain.split``), so boundary vertices stay on the curves.  The split
halves the spacing and keeps every corner angle of the parent at its corner quad.

Array layout (a :class:`~meshwright.quad.mesher.QuadFill` in and out): points (n, 2)
float64; quads (m, 4) and triangles (t, 3) int32 counter-clockwise; lines (k, 2) int32
with (k,) int32 markers and curve indices.  Quad ``k`` of a parent with corners
``c_0..c_{p-1}`` is ``(c_k, mid(c_k, c_{k+1}), centroid, mid(c_{k-1}, c_k))``.
"""

from __future__ import annotations

import numpy as np

from meshwright.core.errors import MeshingError
from meshwright.geometry.domain import Domain

__all__ = ["split_all", "curve_midpoints"]


def _split_block(cells: np.ndarray, edge_id: np.ndarray, mid0: int, cen0: int) -> np.ndarray:
    """Quads of the split of a (c, p) block whose edge ``k`` of cell ``i`` has midpoint
    ``mid0 + edge_id[i, k]`` and whose centroids are ``cen0 + i``; (p c, 4) int32."""
    c, p = cells.shape
    cen = cen0 + np.arange(c)
    out = np.empty((c, p, 4), dtype=np.int64)
    for k in range(p):
        out[:, k, 0] = cells[:, k]
        out[:, k, 1] = mid0 + edge_id[:, k]
        out[:, k, 2] = cen
        out[:, k, 3] = mid0 + edge_id[:, (k - 1) % p]
    return out.reshape(-1, 4).astype(np.int32)


def curve_midpoints(domain: Domain, curves: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Arc-length midpoints on their curves of segments whose ends lie on them.

    On a closed curve a segment with an end at the seam takes the short way round (that
    end's parameter moves by one period).

    Parameters
    ----------
    domain : Domain
    curves : (k,) int
        Index into ``domain.curves`` of each segment's curve.
    a, b : (k, 2) float64
        Segment ends.

    Returns
    -------
    (k, 2) float64
    """
    curves = np.asarray(curves, dtype=np.int64)
    k = len(curves)
    # Segments share their ends: each (curve, point) is projected once.
    key = np.column_stack([np.concatenate([curves, curves]).astype(np.float64), np.vstack([a, b])])
    uniq, inv = np.unique(key, axis=0, return_inverse=True)
    chord = 0.5 * (a + b)
    # One projection for the ends and the chord midpoints (used below): its cost is per
    # curve (a vectorised golden-section search), not per point.
    t_all, on_all = domain.project(
        np.concatenate([uniq[:, 0].astype(np.int64), curves]), np.vstack([uniq[:, 1:], chord])
    )
    t = t_all[: len(uniq)][inv.ravel()]
    ta, tb = t[:k].copy(), t[k:].copy()
    for c in np.unique(curves):
        cur = domain.curves[c]
        ends = cur.evaluate(np.array([cur.t0, cur.t1]))
        if not np.array_equal(ends[0], ends[1]):
            continue
        # A closed curve: an end at the seam has two parameters; take the one beside the other end.
        period = cur.t1 - cur.t0
        sel = np.flatnonzero((curves == c) & (np.abs(tb - ta) > 0.5 * period))
        a0, b0 = ta[sel], tb[sel]
        up = a0 < b0
        # The end nearer its end of the range is the one at the seam.
        move_a = np.where(up, a0 - cur.t0 < cur.t1 - b0, cur.t1 - a0 < b0 - cur.t0)
        shift = np.where(up, period, -period)
        ta[sel] = np.where(move_a, a0 + shift, a0)
        tb[sel] = np.where(move_a, b0, b0 - shift)
    by_arc = domain.split(curves, ta, tb)[1]
    # Projection is not exact near a cusp (a trailing edge): the arc midpoint and the
    # projected chord midpoint are both on the curve; the one nearer the chord is the arc's.
    by_projection = on_all[len(uniq) :]
    nearer = np.hypot(*(by_projection - chord).T) < np.hypot(*(by_arc - chord).T)
    return np.where(nearer[:, None], by_projection, by_arc)


def split_all(fill, domain: Domain, max_points: int):
    """Split every quad into 4 and every triangle into 3 quads.

    Parameters
    ----------
    fill : QuadFill
        A conforming mixed mesh (see :mod:`meshwright.quad.mesher`).
    domain : Domain
        Its domain; ``fill.line_curves`` index ``domain.curves`` (-1: straight, no
        projection).
    max_points : int
        Cap on the vertices of the result.

    Returns
    -------
    QuadFill
        No triangles; lines split in two with their markers and curves.

    Raises
    ------
    MeshingError
        The split would exceed ``max_points`` (both counts named).
    """
    from meshwright.quad.mesher import QuadFill

    pts = fill.points
    n = len(pts)
    blocks = [b for b in (fill.quads, fill.triangles) if len(b)]
    edges = np.concatenate([np.column_stack([b.ravel(), np.roll(b, -1, axis=1).ravel()]) for b in blocks])
    lo, hi = np.minimum(edges[:, 0], edges[:, 1]).astype(np.int64), np.maximum(edges[:, 0], edges[:, 1])
    uniq, inv = np.unique(lo * n + hi, return_inverse=True)
    n_cells = sum(len(b) for b in blocks)
    total = n + len(uniq) + n_cells
    if total > max_points:
        raise MeshingError(
            f"the all-quad split needs {total} vertices, above max_points = {max_points}; "
            "coarsen the size, raise max_points or pass all_quad=False"
        )
    ea, eb = uniq // n, uniq % n
    mids = 0.5 * (pts[ea] + pts[eb])
    lines = fill.lines.astype(np.int64)
    line_mid = np.searchsorted(uniq, np.minimum(lines[:, 0], lines[:, 1]) * n + np.maximum(lines[:, 0], lines[:, 1]))
    on_curve = fill.line_curves >= 0
    if on_curve.any():
        ends = lines[on_curve]
        mids[line_mid[on_curve]] = curve_midpoints(domain, fill.line_curves[on_curve], pts[ends[:, 0]], pts[ends[:, 1]])
    centroids = [pts[b].mean(axis=1) for b in blocks]
    new_points = np.ascontiguousarray(np.concatenate([pts, mids] + centroids))
    quads = []
    offset, cen0 = 0, n + len(uniq)
    for b in blocks:
        eid = inv[offset : offset + b.size].reshape(b.shape)
        quads.append(_split_block(b, eid, n, cen0))
        offset += b.size
        cen0 += len(b)
    m = n + line_mid
    new_lines = np.stack([np.column_stack([lines[:, 0], m]), np.column_stack([m, lines[:, 1]])], axis=1)
    return QuadFill(
        new_points,
        np.ascontiguousarray(np.concatenate(quads)),
        np.zeros((0, 3), np.int32),
        new_lines.reshape(-1, 2).astype(np.int32),
        np.repeat(fill.line_markers, 2).astype(np.int32),
        np.repeat(fill.line_curves, 2).astype(np.int32),
    )
