"""Voronoi diagram (Dirichlet tessellation) read off a Delaunay triangulation.

The Voronoi polygon of an input point ``P_i`` is the region nearer to ``P_i`` than to any other
input point (Voronoi, 1908); the polygons together tile the plane, the Dirichlet tessellation
(Dirichlet, 1850), and joining the points whose polygons share a side gives the Delaunay
triangulation (chapter 18.1, Figure 18.1.1a).  Following Bowyer (1981; chapter 18.1.2,
Figure 18.1.8) every Voronoi vertex is stored with its *forming points*, the three points of a
Delaunay triangle whose circumcentre it is, and its *neighbouring vertices*, the circumcentres of
the three adjacent triangles (-1, Bowyer's 0, where the Voronoi edge runs to infinity).  The
diagram is therefore a relabelling of a :class:`~meshwright.tri.triangulation.Triangulation`,
built in O(n) by vectorised NumPy and ``@njit`` walks; no geometric decision is taken here, so
exact predicates are needed only to validate a clip polygon.

Layout and invariants (``n`` points, ``nt`` triangles, ``r`` ridges)
------------------------------------------------------------------
* ``vertices[t]`` for ``t < nt`` is the circumcentre of triangle ``t``; its forming points are
  ``forming_points[t]`` and its neighbouring vertices ``vertex_neighbors[t]`` (the Delaunay
  ``triangles`` and ``neighbors``).  Cocircular points give several vertices at one position.
  Clipping appends its new vertices after these ``nt``.
* Ridge ``k`` separates ``ridge_points[k, 0]`` and ``ridge_points[k, 1]`` (a Delaunay edge) and
  lies on their perpendicular bisector.  It runs from ``vertices[ridge_vertices[k, 0]]`` to
  ``vertices[ridge_vertices[k, 1]]``; ``ridge_points[k, 1]`` lies on its left and
  ``ridge_points[k, 0]`` on its right, so the ridge appears in the same direction in the
  counter-clockwise boundary of the cell of ``ridge_points[k, 1]``.  Unclipped, a hull edge gives
  an infinite ridge: ``ridge_vertices[k, 1] == -1`` and it leaves ``vertices[ridge_vertices[k, 0]]``
  along the unit vector ``ridge_directions[k]``, perpendicular to the hull edge and pointing out
  of the hull (``ridge_directions`` rows of finite ridges are zero).
* Cells are CSR: the cell of point ``i`` is ``cell_vertices[cell_offsets[i]:cell_offsets[i + 1]]``,
  indices into ``vertices`` in counter-clockwise order, not repeating the first vertex.
  Unclipped, the cell of a convex-hull point is unbounded (``bounded[i]`` False) and its list is
  the open chain ``[-1, c_0, ..., c_m, -1]``: the boundary arrives from infinity along the ray of
  the ridge shared with the hull successor of ``i``, passes the circumcentres ``c_0 .. c_m`` of the
  triangles around ``i`` counter-clockwise, and leaves to infinity along the ray of the ridge
  shared with the hull predecessor (:meth:`Voronoi.cell_rays`).  ``-1`` never occurs elsewhere.
  A point that belongs to no triangle (a merged duplicate) has an empty cell.

Clipping
--------
With ``clip`` (a box or any simple polygon) every cell is the intersection of its Voronoi
polygon with the clip region, so the cells still tile the region, also where a point lies outside
it; a cell that misses the region is empty.  Each cell is the clip polygon clipped by the
half-planes of the cell's bisectors (Sutherland-Hodgman with the convex cell as the clipping
window), which closes unbounded cells without a far box.  New vertices are clip corners and the
crossings of clip sides with bisectors; each is created once, so neighbouring cells share it.
Zero-width spikes that Sutherland-Hodgman leaves on a non-convex region are removed.  Ridges
are clipped too (a ridge crossing a non-convex region may give several rows with the same
``ridge_points``); no ``-1`` remains.  Limitation: where a non-convex region cuts a cell into
several pieces, the cell is one polygon joining the pieces by zero-width bridges along the
cell's sides, through Voronoi vertices that may lie outside the region; its area is right but
it is not simple.  Clipping costs O((n + r) k) for a clip polygon of k sides.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from meshwright.core.errors import DegenerateInputError, GeometryError, InputError
from meshwright.core.predicates import orient2d
from meshwright.tri.triangulation import delaunay

__all__ = ["Voronoi", "voronoi"]

# Kind of a vertex produced by clipping: circumcentre of triangle a, clip corner a,
# crossing of clip side a with the bisector of ridge b.
_TRI, _CORNER, _CROSS = 0, 1, 2
# What the side leaving a working vertex of Sutherland-Hodgman lies on: a clip side or a bisector.
_ON_CLIP, _ON_BISECTOR = 0, 1


@dataclass(frozen=True, eq=False)
class Voronoi:
    """Voronoi diagram of a planar point set (see the module docstring for the conventions).

    Attributes
    ----------
    points : (n, 2) float64
        The input points (generators).
    vertices : (m, 2) float64
        Circumcentres of the ``nt`` Delaunay triangles, then the vertices added by clipping.
    ridge_points : (r, 2) int32
        The two points each ridge separates (a Delaunay edge); ``ridge_points[k, 1]`` is on the
        left of the ridge.
    ridge_vertices : (r, 2) int32
        Start and end vertex of each ridge; end -1 for an infinite ridge (unclipped only).
    ridge_directions : (r, 2) float64
        Outward unit direction of infinite ridges, zero rows for finite ridges.
    cell_offsets : (n + 1,) int32
        CSR offsets of the cells into ``cell_vertices``.
    cell_vertices : (cell_offsets[-1],) int32
        Vertex indices of each cell, counter-clockwise; -1 marks both open ends of an unbounded
        cell.
    bounded : (n,) bool
        True where the cell is a closed polygon (every cell once clipped; empty cells count as
        bounded only when clipped).
    forming_points : (nt, 3) int32
        Bowyer's forming points of vertex ``t < nt``: the counter-clockwise Delaunay triangle.
    vertex_neighbors : (nt, 3) int32
        Bowyer's neighbouring vertices: ``vertex_neighbors[t, k]`` is the vertex across the
        Delaunay edge opposite ``forming_points[t, k]``, -1 for the vertex at infinity.
    clip_polygon : (k, 2) float64 or None
        The counter-clockwise clip region, None for the unclipped diagram.
    """

    points: np.ndarray
    vertices: np.ndarray
    ridge_points: np.ndarray
    ridge_vertices: np.ndarray
    ridge_directions: np.ndarray
    cell_offsets: np.ndarray
    cell_vertices: np.ndarray
    bounded: np.ndarray
    forming_points: np.ndarray
    vertex_neighbors: np.ndarray
    clip_polygon: np.ndarray | None

    def _check_index(self, i: int) -> int:
        n = len(self.points)
        if not -n <= i < n:
            raise InputError(f"point index {i} out of range for a diagram of {n} points")
        return int(i) % n

    def cell(self, i: int) -> np.ndarray:
        """Return the vertices of the cell of point ``i``, counter-clockwise.

        Returns
        -------
        (k, 2) float64
            The polygon (first vertex not repeated) when ``bounded[i]``, else the open chain
            between the two rays (:meth:`cell_rays`); (0, 2) for an empty cell.
        """
        i = self._check_index(i)
        ids = self.cell_vertices[self.cell_offsets[i] : self.cell_offsets[i + 1]]
        return self.vertices[ids[ids >= 0]]

    def cell_rays(self, i: int) -> np.ndarray:
        """Return the outward unit directions of the two rays of unbounded cell ``i``.

        Returns
        -------
        (2, 2) float64
            Row 0: the ray along which the boundary arrives from infinity at the first vertex of
            :meth:`cell`; row 1: the ray leaving its last vertex.
        """
        i = self._check_index(i)
        if self.bounded[i] or self.cell_offsets[i] == self.cell_offsets[i + 1]:
            raise InputError(f"cell {i} is not unbounded, it has no rays")
        infinite = self.ridge_vertices[:, 1] < 0
        # The arriving ray is traversed backwards, so point i is on its right (column 0).
        arriving = np.flatnonzero(infinite & (self.ridge_points[:, 0] == i))[0]
        leaving = np.flatnonzero(infinite & (self.ridge_points[:, 1] == i))[0]
        return self.ridge_directions[[arriving, leaving]]

    def cell_areas(self) -> np.ndarray:
        """Return the area of every cell.

        Returns
        -------
        (n,) float64
            Shoelace area of each bounded cell, ``inf`` for unbounded cells, 0 for empty ones.
        """
        n = len(self.points)
        off = self.cell_offsets.astype(np.int64)
        counts = np.diff(off)
        owner = np.repeat(np.arange(n), counts)
        nxt = np.arange(1, len(self.cell_vertices) + 1)
        full = counts > 0
        nxt[off[1:][full] - 1] = off[:-1][full]
        use = self.bounded[owner]
        # Coordinates relative to the generator keep the shoelace sum free of cancellation.
        a = self.vertices[self.cell_vertices[use]] - self.points[owner[use]]
        b = self.vertices[self.cell_vertices[nxt[use]]] - self.points[owner[use]]
        cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
        area = 0.5 * np.bincount(owner[use], weights=cross, minlength=n)
        area[~self.bounded & full] = np.inf
        return area


def voronoi(points_or_triangulation, clip=None, seed: int = 0) -> Voronoi:
    """Build the Voronoi diagram (Dirichlet tessellation) of a planar point set.

    Parameters
    ----------
    points_or_triangulation : (n, 2) array_like of float or Triangulation
        Points, triangulated by :func:`meshwright.tri.triangulation.delaunay` (numbering kept:
        merged duplicates get empty cells), or any object with ``points`` (n, 2) float,
        ``triangles`` (nt, 3) int counter-clockwise and ``neighbors`` (nt, 3) int (neighbour k
        opposite vertex k, -1 on the hull).
    clip : None, (4,) array_like or (k, 2) array_like of float
        None for the unbounded diagram, a box ``(xmin, ymin, xmax, ymax)``, or a simple polygon
        of either orientation, convex or not, to clip every cell to.
    seed : int
        Seed of the Delaunay insertion order (points only).

    Returns
    -------
    Voronoi

    Raises
    ------
    InputError
        Malformed points (shape, NaN/inf), triangulation arrays or clip box.
    GeometryError
        The clip polygon has fewer than 3 distinct vertices or is not simple.
    DegenerateInputError
        Fewer than three points or all collinear (no triangle).
    """
    points, tri, nbr = _delaunay_arrays(points_or_triangulation, seed)
    poly = None if clip is None else _clip_polygon(clip)
    n, nt = len(points), len(tri)
    centres = _circumcentres(points, tri)
    ridge_points, ridge_vertices, he_ridge = _ridges(tri, nbr)

    start, on_hull, voff, noff = _fan_starts(tri, nbr, n)
    cv, nb_pts, nb_ridges, bad = _cell_fans(tri, nbr, start, on_hull, he_ridge, voff, noff)
    if bad >= 0:
        raise InputError(f"triangulation neighbours do not form a fan around point {bad}")

    if poly is None:
        directions = np.zeros((len(ridge_points), 2))
        infinite = ridge_vertices[:, 1] < 0
        edge = points[ridge_points[infinite, 1]] - points[ridge_points[infinite, 0]]
        # The hull runs counter-clockwise, so the outside is to the right of each hull edge.
        out = np.stack([edge[:, 1], -edge[:, 0]], axis=1)
        directions[infinite] = out / np.hypot(out[:, 0], out[:, 1])[:, None]
        vertices, bounded = centres, (np.diff(voff) > 0) & ~on_hull
    else:
        counts, cell_lab, cell_xy = _clip_cells(
            points, centres, poly, voff, cv, noff, nb_pts, nb_ridges, ridge_points
        )
        piece_ridge, ridge_lab, ridge_xy = _clip_ridges(
            points, centres, poly, ridge_points, ridge_vertices
        )
        lab = np.concatenate([cell_lab, ridge_lab])
        index = lab[:, 1].copy()
        new = lab[:, 0] != _TRI
        k, nr = len(poly), len(ridge_points)
        # One key per geometric entity, so two cells (or a cell and a ridge) share the vertex.
        key = np.where(lab[new, 0] == _CORNER, lab[new, 1], k + lab[new, 1] * nr + lab[new, 2])
        _, first, inverse = np.unique(key, return_index=True, return_inverse=True)
        index[new] = nt + inverse.ravel()
        vertices = np.concatenate([centres, np.concatenate([cell_xy, ridge_xy])[new][first]])
        ridge_points = ridge_points[piece_ridge]
        ridge_vertices = index[len(cell_lab) :].reshape(-1, 2).astype(np.int32)
        directions = np.zeros((len(piece_ridge), 2))
        voff = np.concatenate([[0], np.cumsum(counts)])
        cv = index[: len(cell_lab)].astype(np.int32)
        bounded = np.ones(n, dtype=bool)
    return Voronoi(
        points=points,
        vertices=vertices,
        ridge_points=ridge_points,
        ridge_vertices=ridge_vertices,
        ridge_directions=directions,
        cell_offsets=voff.astype(np.int32),
        cell_vertices=cv,
        bounded=bounded,
        forming_points=tri,
        vertex_neighbors=nbr,
        clip_polygon=poly,
    )


# --------------------------------------------------------------------------- input checks


def _as_points(obj) -> np.ndarray:
    """Return a C-contiguous (n, 2) float64 copy of ``obj``; InputError names the culprit."""
    try:
        points = np.array(obj, dtype=np.float64, order="C")
    except (TypeError, ValueError) as exc:
        raise InputError(f"points must be an (n, 2) array of numbers: {exc}") from exc
    if points.ndim != 2 or points.shape[1] != 2:
        raise InputError(f"points must have shape (n, 2), got {points.shape}")
    bad = np.flatnonzero(~np.isfinite(points).all(axis=1))
    if bad.size:
        raise InputError(f"point {bad[0]} is not finite: {points[bad[0]].tolist()}")
    return points


def _delaunay_arrays(obj, seed: int):
    """Return ``points`` (n, 2) float64, ``triangles`` and ``neighbors`` (nt, 3) int32."""
    if hasattr(obj, "triangles") and hasattr(obj, "neighbors"):
        points, tri = _as_points(obj.points), np.ascontiguousarray(obj.triangles, dtype=np.int32)
    else:
        points = _as_points(obj)
        obj = delaunay(points, seed=seed)
        # Keep the caller's numbering: a vertex stands for the first of the points merged
        # into it, so the other duplicates are in no triangle and get empty cells.
        _, first = np.unique(obj.index_map, return_index=True)
        tri = np.ascontiguousarray(first.astype(np.int32)[obj.triangles])
    nbr = np.ascontiguousarray(obj.neighbors, dtype=np.int32)
    if tri.ndim != 2 or tri.shape[1] != 3 or nbr.shape != tri.shape:
        raise InputError(
            f"triangles and neighbors must both have shape (nt, 3), got {tri.shape} and {nbr.shape}"
        )
    if len(tri) == 0:
        raise DegenerateInputError("no triangle: fewer than 3 points, or all collinear")
    n, nt = len(points), len(tri)
    bad = np.flatnonzero(((tri < 0) | (tri >= n)).any(axis=1))
    if bad.size:
        raise InputError(f"triangle {bad[0]} {tri[bad[0]].tolist()} names a point outside 0..{n - 1}")
    bad = np.flatnonzero(((nbr < -1) | (nbr >= nt)).any(axis=1))
    if bad.size:
        raise InputError(f"neighbors {nbr[bad[0]].tolist()} of triangle {bad[0]} not in -1..{nt - 1}")
    return points, tri, nbr


def _clip_polygon(clip) -> np.ndarray:
    """Return the clip region as a counter-clockwise simple polygon, (k, 2) float64."""
    try:
        arr = np.asarray(clip, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(
            f"clip must be a box (xmin, ymin, xmax, ymax) or a (k, 2) polygon, got {clip!r}"
        ) from exc
    if arr.shape == (4,):
        xmin, ymin, xmax, ymax = arr
        if not (np.isfinite(arr).all() and xmin < xmax and ymin < ymax):
            raise InputError(f"clip box {arr.tolist()} needs finite xmin < xmax and ymin < ymax")
        return np.array([[xmin, ymin], [xmax, ymin], [xmax, ymax], [xmin, ymax]])
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise InputError(
            f"clip must be a box of 4 numbers or a (k, 2) polygon, got shape {arr.shape}"
        )
    bad = np.flatnonzero(~np.isfinite(arr).all(axis=1))
    if bad.size:
        raise InputError(f"clip polygon vertex {bad[0]} is not finite: {arr[bad[0]].tolist()}")
    # A repeated closing vertex, or any vertex repeated next to itself, is a zero-length side.
    kept = np.flatnonzero((arr != np.roll(arr, 1, axis=0)).any(axis=1))
    poly = np.ascontiguousarray(arr[kept])
    if len(poly) < 3:
        raise GeometryError(f"clip polygon needs at least 3 distinct vertices, got {len(poly)}")
    i, j = _first_crossing(poly)
    if i >= 0:
        a, b = kept[i], kept[(i + 1) % len(kept)]
        c, d = kept[j], kept[(j + 1) % len(kept)]
        raise GeometryError(
            f"clip polygon is not simple: side {a}->{b} {arr[a].tolist()}->{arr[b].tolist()} "
            f"meets side {c}->{d} {arr[c].tolist()}->{arr[d].tolist()}"
        )
    rel = poly - poly[0]
    twice_area = np.sum(rel[:-1, 0] * rel[1:, 1] - rel[:-1, 1] * rel[1:, 0])
    return poly if twice_area > 0 else np.ascontiguousarray(poly[::-1])


@njit(cache=True)
def _first_crossing(poly):
    """Return the first pair of sides (i, j) of a polygon that meet illegally, else (-1, -1).

    Non-neighbouring sides must not touch; neighbouring sides must not fold back onto each
    other.  Exact ``orient2d`` decides, O(k^2) with a bounding-box reject.
    """
    k = poly.shape[0]
    for i in range(k):
        ax, ay = poly[i, 0], poly[i, 1]
        bx, by = poly[(i + 1) % k, 0], poly[(i + 1) % k, 1]
        for j in range(i + 1, k):
            cx, cy = poly[j, 0], poly[j, 1]
            dx, dy = poly[(j + 1) % k, 0], poly[(j + 1) % k, 1]
            if j == i + 1 or (i == 0 and j == k - 1):
                # Shared vertex s, other ends p and q: a fold puts q on the ray from s through p.
                if j == i + 1:
                    sx, sy, px, py, qx, qy = bx, by, ax, ay, dx, dy
                else:
                    sx, sy, px, py, qx, qy = ax, ay, bx, by, cx, cy
                if orient2d(sx, sy, px, py, qx, qy) == 0.0 and (
                    (px - sx) * (qx - sx) + (py - sy) * (qy - sy) > 0.0
                ):
                    return i, j
                continue
            if not _overlaps(poly, j, min(ax, bx), min(ay, by), max(ax, bx), max(ay, by)):
                continue
            o1 = np.sign(orient2d(ax, ay, bx, by, cx, cy))
            o2 = np.sign(orient2d(ax, ay, bx, by, dx, dy))
            o3 = np.sign(orient2d(cx, cy, dx, dy, ax, ay))
            o4 = np.sign(orient2d(cx, cy, dx, dy, bx, by))
            # Collinear sides pass the bounding-box test only when they overlap.
            if o1 * o2 <= 0.0 and o3 * o4 <= 0.0:
                return i, j
    return -1, -1


# --------------------------------------------------------------------------- the dual


def _circumcentres(points: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """Return the circumcentre of every triangle, (nt, 2) float64.

    Computed relative to the first vertex so that the subtractions are exact for nearby
    points and the result does not lose digits to large absolute coordinates.
    """
    a = points[tri[:, 0]]
    b = points[tri[:, 1]] - a
    c = points[tri[:, 2]] - a
    b2 = b[:, 0] ** 2 + b[:, 1] ** 2
    c2 = c[:, 0] ** 2 + c[:, 1] ** 2
    d = 2.0 * (b[:, 0] * c[:, 1] - b[:, 1] * c[:, 0])
    ux = (c[:, 1] * b2 - b[:, 1] * c2) / d
    uy = (b[:, 0] * c2 - c[:, 0] * b2) / d
    return a + np.stack([ux, uy], axis=1)


def _ridges(tri: np.ndarray, nbr: np.ndarray):
    """Return one ridge per Delaunay edge.

    Returns ``ridge_points`` (r, 2) int32, edge ``(u, v)`` as it runs in the triangle of smaller
    index (or the hull triangle), which is thus on its left; ``ridge_vertices`` (r, 2) int32,
    that triangle and the one across (-1 on the hull); ``he_ridge`` (3 nt,) int64, the ridge of
    half-edge ``3 t + k`` (the edge opposite vertex k of triangle t).
    """
    nt = len(tri)
    he_t = np.repeat(np.arange(nt, dtype=np.int64), 3)
    he_k = np.tile(np.arange(3), nt)
    across = nbr.reshape(-1).astype(np.int64)
    own = (across < 0) | (he_t < across)
    he_ridge = np.empty(3 * nt, dtype=np.int64)
    he_ridge[own] = np.arange(np.count_nonzero(own))
    twin = np.flatnonzero(~own)
    match = nbr[across[twin]] == he_t[twin, None]
    lonely = ~match.any(axis=1)
    if lonely.any():
        h = twin[np.flatnonzero(lonely)[0]]
        raise InputError(f"triangle {h // 3} lists neighbour {across[h]}, which does not list it")
    he_ridge[twin] = he_ridge[3 * across[twin] + match.argmax(axis=1)]
    t, k = he_t[own], he_k[own]
    ridge_points = np.stack([tri[t, (k + 1) % 3], tri[t, (k + 2) % 3]], axis=1)
    ridge_vertices = np.stack([t, across[own]], axis=1).astype(np.int32)
    return ridge_points.astype(np.int32), ridge_vertices, he_ridge


def _fan_starts(tri: np.ndarray, nbr: np.ndarray, n: int):
    """Return where the counter-clockwise walk around each point starts, and the CSR offsets.

    Returns ``start`` (n,) int32, a triangle at the point, for a hull point the one whose
    clockwise side is on the hull (-1: in no triangle); ``on_hull`` (n,) bool; ``voff``
    (n + 1,) int64, cell offsets (one per incident triangle, plus two -1 ends on the hull);
    ``noff`` (n + 1,) int64, offsets of the neighbour lists (one more on the hull).
    """
    flat = tri.reshape(-1)
    start = np.full(n, -1, dtype=np.int32)
    start[flat] = np.repeat(np.arange(len(tri), dtype=np.int32), 3)
    hull = np.flatnonzero(nbr.reshape(-1) < 0)
    # Hull half-edge (t, k) runs u -> v with u = vertex k+1; the walk around u starts at t.
    u = flat[3 * (hull // 3) + (hull % 3 + 1) % 3]
    start[u] = hull // 3
    on_hull = np.zeros(n, dtype=bool)
    on_hull[u] = True
    degree = np.bincount(flat, minlength=n)
    voff = np.concatenate([[0], np.cumsum(degree + 2 * on_hull)])
    noff = np.concatenate([[0], np.cumsum(degree + on_hull)])
    return start, on_hull, voff, noff


@njit(cache=True)
def _cell_fans(tri, nbr, start, on_hull, he_ridge, voff, noff):
    """Walk counter-clockwise around every point through the triangle neighbours.

    Inputs: ``tri``, ``nbr`` (nt, 3) int32, ``start`` (n,) int32, ``on_hull`` (n,) bool,
    ``he_ridge`` (3 nt,) int64, ``voff``, ``noff`` (n + 1,) int64 (see :func:`_fan_starts`).
    Returns ``cv`` (voff[-1],) int32, the cell lists (triangle = circumcentre indices, -1 ends
    on the hull); ``nb_pts`` (noff[-1],) int32, the Delaunay neighbours n_0, n_1, ... of each
    point in the same order, the side between c_{j-1} and c_j being the bisector with n_j;
    ``nb_ridges`` (noff[-1],) int64, those sides' ridges; and -1, or a point around which the
    neighbours do not form a fan.
    """
    n = start.shape[0]
    cv = np.empty(voff[n], dtype=np.int32)
    nb_pts = np.empty(noff[n], dtype=np.int32)
    nb_ridges = np.empty(noff[n], dtype=np.int64)
    for i in range(n):
        t0 = start[i]
        if t0 < 0:
            continue
        pos, npos = voff[i], noff[i]
        end = voff[i + 1] - 1 if on_hull[i] else voff[i + 1]
        if on_hull[i]:
            cv[pos] = -1
            pos += 1
        t = t0
        while True:
            k = 0
            while k < 3 and tri[t, k] != i:
                k += 1
            if k == 3 or pos >= end:
                return cv, nb_pts, nb_ridges, i
            cv[pos] = t
            pos += 1
            # Counter-clockwise around i the next triangle is across the side (i, vertex k+2).
            nb_pts[npos] = tri[t, (k + 1) % 3]
            nb_ridges[npos] = he_ridge[3 * t + (k + 2) % 3]
            npos += 1
            nxt = nbr[t, (k + 1) % 3]
            if nxt < 0:
                if not on_hull[i]:
                    return cv, nb_pts, nb_ridges, i
                nb_pts[npos] = tri[t, (k + 2) % 3]
                nb_ridges[npos] = he_ridge[3 * t + (k + 1) % 3]
                npos += 1
                cv[pos] = -1
                pos += 1
                break
            if nxt == t0:
                break
            t = nxt
        if pos != voff[i + 1] or npos != noff[i + 1]:
            return cv, nb_pts, nb_ridges, i
    return cv, nb_pts, nb_ridges, -1


# --------------------------------------------------------------------------- clipping


@njit(cache=True)
def _overlaps(poly, e, x0, y0, x1, y1):
    """Whether the bounding box of polygon side ``e`` meets the box [x0, x1] x [y0, y1]."""
    k = poly.shape[0]
    ax, ay, bx, by = poly[e, 0], poly[e, 1], poly[(e + 1) % k, 0], poly[(e + 1) % k, 1]
    return min(ax, bx) <= x1 and max(ax, bx) >= x0 and min(ay, by) <= y1 and max(ay, by) >= y0


@njit(cache=True)
def _inside(x, y, poly):
    """Even-odd ray casting; the half-open test in y counts a vertex on the ray once."""
    k = poly.shape[0]
    inside = False
    for e in range(k):
        x0, y0 = poly[e, 0], poly[e, 1]
        x1, y1 = poly[(e + 1) % k, 0], poly[(e + 1) % k, 1]
        if (y0 > y) != (y1 > y) and x0 + (y - y0) * (x1 - x0) / (y1 - y0) > x:
            inside = not inside
    return inside


@njit(cache=True)
def _crossing(poly, e, points, ridge_points, r):
    """Crossing of clip side ``e`` with the bisector of ridge ``r``, and the sides' signs.

    Always computed from the whole side and the ridge's own point order, so every cell and
    ridge that meets this crossing gets bitwise the same coordinates.
    """
    k = poly.shape[0]
    u, v = ridge_points[r, 0], ridge_points[r, 1]
    dx, dy = points[v, 0] - points[u, 0], points[v, 1] - points[u, 1]
    mx, my = 0.5 * (points[u, 0] + points[v, 0]), 0.5 * (points[u, 1] + points[v, 1])
    x0, y0 = poly[e, 0], poly[e, 1]
    x1, y1 = poly[(e + 1) % k, 0], poly[(e + 1) % k, 1]
    s0 = dx * (x0 - mx) + dy * (y0 - my)
    s1 = dx * (x1 - mx) + dy * (y1 - my)
    lam = 0.5 if s0 == s1 else min(max(s0 / (s0 - s1), 0.0), 1.0)
    return x0 + lam * (x1 - x0), y0 + lam * (y1 - y0), s0, s1


@njit(cache=True)
def _reserve(xy, lab, used, extra):
    """Return buffers (c, 2) float64 and (c, w) int64 keeping ``used`` rows, room for ``extra``."""
    if used + extra <= lab.shape[0]:
        return xy, lab
    cap = max(2 * lab.shape[0], used + extra)
    xy2, lab2 = np.empty((cap, 2)), np.empty((cap, lab.shape[1]), dtype=np.int64)
    for s in range(used):
        _copy_row(xy2, lab2, s, xy, lab, s)
    return xy2, lab2


@njit(cache=True)
def _copy_row(dst_xy, dst_lab, d, src_xy, src_lab, s):
    """Copy row ``s`` of a (coordinates, labels) buffer pair to row ``d`` of another."""
    dst_xy[d, 0], dst_xy[d, 1] = src_xy[s, 0], src_xy[s, 1]
    for c in range(min(dst_lab.shape[1], src_lab.shape[1])):
        dst_lab[d, c] = src_lab[s, c]


@njit(cache=True)
def _fan_triangle(j1, j2, x, y, cv, first, m, closed, centres):
    """Name the meeting point of bisectors j1 and j2 of a cell by its Delaunay triangle.

    The vertex between sides j and j+1 of the cell is its fan triangle j (``cv[first + j]``,
    ``m`` of them; the sides of a closed cell wrap around).  Non-consecutive sides meet on the
    cell only through zero-length ridges of cocircular points; the nearest circumcentre is then
    the same point.
    """
    nh = m if closed else m + 1
    if j2 == j1 + 1 or (closed and j2 == 0 and j1 == nh - 1):
        return cv[first + j1]
    if j1 == j2 + 1 or (closed and j1 == 0 and j2 == nh - 1):
        return cv[first + j2]
    best, best_d = cv[first], np.inf
    for s in range(first, first + m):
        d = (centres[cv[s], 0] - x) ** 2 + (centres[cv[s], 1] - y) ** 2
        if d < best_d:
            best, best_d = cv[s], d
    return best


@njit(cache=True)
def _tidy(wxy, wlab, cnt):
    """Drop repeated vertices and zero-width spikes from the first ``cnt`` rows, in place.

    ``wxy`` (c, 2) float64 and ``wlab`` (c, 5) int64 (kind, a, b, support kind, support id, the
    support being the line the side to the next vertex lies on).  A clip side through a Voronoi
    vertex repeats it; a non-convex region leaves spikes out along one line and back, whose tip
    has the same support in and out (as has a vertex inside a straight run): dropping it merges
    the two sides.  A removal can expose another, so repeat.  Returns the new count.
    """
    drop = np.zeros(cnt, dtype=np.bool_)
    changed = True
    while changed and cnt >= 3:
        changed = False
        for phase in range(2):
            for s in range(cnt):
                if phase == 0:
                    # Of two equal vertices keep the second: its support is the real side.
                    o = s + 1 if s + 1 < cnt else 0
                    same = wlab[o, 0] == wlab[s, 0] and wlab[o, 1] == wlab[s, 1]
                    drop[s] = same and wlab[o, 2] == wlab[s, 2]
                else:
                    o = s - 1 if s > 0 else cnt - 1
                    drop[s] = wlab[o, 3] == wlab[s, 3] and wlab[o, 4] == wlab[s, 4]
            kept = 0
            for s in range(cnt):
                if not drop[s]:
                    _copy_row(wxy, wlab, kept, wxy, wlab, s)
                    kept += 1
            changed = changed or kept < cnt
            cnt = kept
            if cnt < 3:
                break
    return cnt


@njit(cache=True)
def _clip_cells(points, centres, poly, voff, cv, noff, nb_pts, nb_ridges, ridge_points):
    """Clip every cell to the polygon (Sutherland-Hodgman, the cell's half-planes as window).

    Returns ``counts`` (n,) int64, the number of vertices of each clipped cell; ``lab``
    (sum(counts), 3) int64, their labels (kind, a, b) cell after cell (see ``_TRI``); ``xy``
    (sum(counts), 2) float64, their coordinates.
    """
    n, k = points.shape[0], poly.shape[0]
    counts = np.zeros(n, dtype=np.int64)
    lab = np.empty((4 * (n + k), 3), dtype=np.int64)
    xy = np.empty((4 * (n + k), 2))
    used = 0
    # Working polygon: coordinates, and (kind, a, b, support kind, support id) where the
    # support is what the side from this vertex to the next lies on.
    wxy, wlab = np.empty((2 * k + 8, 2)), np.empty((2 * k + 8, 5), dtype=np.int64)
    nxy, nlab = np.empty_like(wxy), np.empty_like(wlab)
    for i in range(n):
        v0, v1 = voff[i], voff[i + 1]
        if v0 == v1:
            continue
        closed = cv[v0] >= 0
        first = v0 if closed else v0 + 1
        m = v1 - first if closed else v1 - first - 1
        if closed:
            x0, y0, x1, y1 = np.inf, np.inf, -np.inf, -np.inf
            for s in range(v0, v1):
                cx, cy = centres[cv[s], 0], centres[cv[s], 1]
                x0, y0, x1, y1 = min(x0, cx), min(y0, cy), max(x1, cx), max(y1, cy)
            touches = False
            for e in range(k):
                if _overlaps(poly, e, x0, y0, x1, y1):
                    touches = True
                    break
            if not touches:
                # Off the clip boundary the cell is wholly in or out, like its generator.
                if _inside(points[i, 0], points[i, 1], poly):
                    xy, lab = _reserve(xy, lab, used, m)
                    for s in range(v0, v1):
                        lab[used, 0], lab[used, 1], lab[used, 2] = _TRI, cv[s], 0
                        xy[used, 0], xy[used, 1] = centres[cv[s], 0], centres[cv[s], 1]
                        used += 1
                    counts[i] = m
                continue
        for c in range(k):
            wxy[c, 0], wxy[c, 1] = poly[c, 0], poly[c, 1]
            wlab[c, 0], wlab[c, 1], wlab[c, 2], wlab[c, 3], wlab[c, 4] = _CORNER, c, 0, _ON_CLIP, c
        cnt = k
        h0, nh = noff[i], noff[i + 1] - noff[i]
        for j in range(nh):
            q, r = nb_pts[h0 + j], nb_ridges[h0 + j]
            dx, dy = points[q, 0] - points[i, 0], points[q, 1] - points[i, 1]
            mx, my = 0.5 * (points[q, 0] + points[i, 0]), 0.5 * (points[q, 1] + points[i, 1])
            nxy, nlab = _reserve(nxy, nlab, 0, 2 * cnt)  # each side yields at most two
            out = 0
            for s in range(cnt):
                s2 = s + 1 if s + 1 < cnt else 0
                ax, ay, bx, by = wxy[s, 0], wxy[s, 1], wxy[s2, 0], wxy[s2, 1]
                sa = dx * (ax - mx) + dy * (ay - my)
                sb = dx * (bx - mx) + dy * (by - my)
                a_in, b_in = sa <= 0.0, sb <= 0.0
                if a_in:
                    _copy_row(nxy, nlab, out, wxy, wlab, s)
                    out += 1
                if a_in != b_in:
                    if wlab[s, 3] == _ON_CLIP:
                        x, y, _, _ = _crossing(poly, wlab[s, 4], points, ridge_points, r)
                        nlab[out, 0], nlab[out, 1], nlab[out, 2] = _CROSS, wlab[s, 4], r
                    else:
                        lam = sa / (sa - sb)
                        x, y = ax + lam * (bx - ax), ay + lam * (by - ay)
                        # Two bisectors meet: a Voronoi vertex, named once clipping is done.
                        nlab[out, 0], nlab[out, 1], nlab[out, 2] = _TRI, wlab[s, 4], j
                    nxy[out, 0], nxy[out, 1] = x, y
                    if a_in:
                        nlab[out, 3], nlab[out, 4] = _ON_BISECTOR, j
                    else:
                        nlab[out, 3], nlab[out, 4] = wlab[s, 3], wlab[s, 4]
                    out += 1
            wxy, nxy, wlab, nlab, cnt = nxy, wxy, nlab, wlab, out
            if cnt == 0:
                break
        if cnt < 3:
            continue
        for s in range(cnt):
            if wlab[s, 0] == _TRI:
                wlab[s, 1] = _fan_triangle(
                    wlab[s, 1], wlab[s, 2], wxy[s, 0], wxy[s, 1], cv, first, m, closed, centres
                )
                wlab[s, 2] = 0
                wxy[s, 0], wxy[s, 1] = centres[wlab[s, 1], 0], centres[wlab[s, 1], 1]
        cnt = _tidy(wxy, wlab, cnt)
        if cnt >= 3:
            xy, lab = _reserve(xy, lab, used, cnt)
            for s in range(cnt):
                _copy_row(xy, lab, used + s, wxy, wlab, s)
            counts[i] = cnt
            used += cnt
    return counts, lab[:used], xy[:used]


@njit(cache=True)
def _clip_ridges(points, centres, poly, ridge_points, ridge_vertices):
    """Cut every ridge (segment or ray) to the pieces inside the polygon.

    Returns ``piece_ridge`` (p,) int64, the ridge of each piece (in ridge order, then along the
    ridge); ``lab`` (2 p, 3) int64, start and end label (kind, a, b) of each piece; ``xy``
    (2 p, 2) float64, their coordinates.
    """
    k, nr = poly.shape[0], ridge_points.shape[0]
    piece_ridge = np.empty(nr, dtype=np.int64)
    lab = np.empty((2 * nr, 3), dtype=np.int64)
    xy = np.empty((2 * nr, 2))
    pieces = 0
    lam_buf, side_buf = np.empty(k), np.empty(k, dtype=np.int64)
    for r in range(nr):
        t0, t1 = ridge_vertices[r, 0], ridge_vertices[r, 1]
        ax, ay = centres[t0, 0], centres[t0, 1]
        if t1 >= 0:
            dx, dy, lam_max = centres[t1, 0] - ax, centres[t1, 1] - ay, 1.0
            x0, x1 = min(ax, ax + dx), max(ax, ax + dx)
            y0, y1 = min(ay, ay + dy), max(ay, ay + dy)
        else:
            u, v = ridge_points[r, 0], ridge_points[r, 1]
            # Outward normal of hull edge u -> v (the outside is on its right).
            dx, dy, lam_max = points[v, 1] - points[u, 1], points[u, 0] - points[v, 0], np.inf
            x0, x1 = (-np.inf if dx < 0 else ax), (np.inf if dx > 0 else ax)
            y0, y1 = (-np.inf if dy < 0 else ay), (np.inf if dy > 0 else ay)
        dd = dx * dx + dy * dy
        nc = 0
        for e in range(k):
            if dd == 0.0 or not _overlaps(poly, e, x0, y0, x1, y1):
                continue
            x, y, s0, s1 = _crossing(poly, e, points, ridge_points, r)
            # Half-open in the side's end signs: a clip corner on the bisector counts once.
            if (s0 <= 0.0 < s1) or (s1 <= 0.0 < s0):
                lam = ((x - ax) * dx + (y - ay) * dy) / dd
                if 0.0 <= lam <= lam_max:
                    c = nc
                    while c > 0 and lam_buf[c - 1] > lam:
                        lam_buf[c], side_buf[c] = lam_buf[c - 1], side_buf[c - 1]
                        c -= 1
                    lam_buf[c], side_buf[c] = lam, e
                    nc += 1
        inside = _inside(ax, ay, poly)
        xy, lab = _reserve(xy, lab, 2 * pieces, 2 * (nc + 1))
        if piece_ridge.shape[0] < pieces + nc + 1:
            grown = np.empty(2 * (pieces + nc + 1), dtype=np.int64)
            for c in range(pieces):
                grown[c] = piece_ridge[c]
            piece_ridge = grown
        skind, sa, sb, sx, sy = _TRI, t0, 0, ax, ay
        for c in range(nc + 1):
            if c < nc:
                e = side_buf[c]
                ekind, ea, eb = _CROSS, e, r
                ex, ey, _, _ = _crossing(poly, e, points, ridge_points, r)
            elif t1 >= 0:
                ekind, ea, eb, ex, ey = _TRI, t1, 0, centres[t1, 0], centres[t1, 1]
            else:
                break  # a ray ends outside a bounded region
            if inside:
                piece_ridge[pieces] = r
                row = 2 * pieces
                lab[row, 0], lab[row, 1], lab[row, 2] = skind, sa, sb
                lab[row + 1, 0], lab[row + 1, 1], lab[row + 1, 2] = ekind, ea, eb
                xy[row, 0], xy[row, 1], xy[row + 1, 0], xy[row + 1, 1] = sx, sy, ex, ey
                pieces += 1
            skind, sa, sb, sx, sy = ekind, ea, eb, ex, ey
            inside = not inside
    return piece_ridge[:pieces], lab[: 2 * pieces], xy[: 2 * pieces]
