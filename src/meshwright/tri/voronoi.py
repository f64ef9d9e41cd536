"""Voronoi diagram (Dirichlet tessellation) read off a Delaunay triangulation.

The Voronoi polygon of an input point ``P_i`` is the region nearer to ``P_i`` than to any other
input point (Voronoi, 1908); the polygons together tile the plane, the Dirichlet tessellation
(Dirichlet, 1850), and joining the points whose polygons share a side gives the Delaunay
triangulation (chapter 18.1, Figure 18.1.1a).  Following Bowyer (1981; chapter 18.1.2,
Figure 18.1.8) every Voronoi vertex is stored with its *forming points*, the three points of a
Delaunay triangle whose circumcentre it is, and its *neighbouring vertices*, the circumcentres of
the three adjacent triangles (-1, Bowyer's 0, where the Voronoi edge runs to infinity).  The
diagram is therefore a relabelling of a :class:`~meshwright.tri.triangulation.Triangulation`,
built in O(n) by vectorised NumPy and ``@njit`` walks; no topological decision is taken here
(the exact ``orient2d`` only checks a supplied triangulation and a clip polygon at the door).

Circumcentres are computed in floating point relative to the first vertex, and recomputed in
exact rationals (then rounded once) for the rare triangle whose float area may have lost more
than half its bits or whose float centre is not finite, so a triangle that is exactly
non-degenerate never yields an infinite or NaN Voronoi vertex, however thin.  Inside the
predicates' coordinate range (checked at the door, :mod:`meshwright.core.validate_input`)
every exact circumcentre is a finite double: coordinates are then multiples of ``2**-200`` of
magnitude at most ``2**200``, so twice a nonzero area is at least ``2**-400`` and the centre is
within ``2**1005`` of the origin.

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
it; a cell that misses the region is empty.  New vertices are clip corners and the crossings of
clip sides with bisectors, each stored once and shared by the cells and ridges that meet it.
Ridges are clipped too (a ridge crossing a non-convex region may give several rows with the
same ``ridge_points``); no ``-1`` remains.  The algorithm (Sutherland-Hodgman with the convex
cell as the window), its invariants and its limitation on non-convex regions are in
:mod:`meshwright.tri.voronoi_clip`.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import numpy as np
from numba import njit

from meshwright.core.errors import DegenerateInputError, InputError, fmt_point
from meshwright.core.predicates import orient2d
from meshwright.core.validate_input import as_exact_points, check_seed
from meshwright.tri.triangulation import delaunay
from meshwright.tri.voronoi_clip import clip_diagram, clip_region

__all__ = ["Voronoi", "voronoi"]

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
    seed : int or numpy.random.Generator
        Seed of the Delaunay insertion order (used for points only; checked always).

    Returns
    -------
    Voronoi

    Raises
    ------
    InputError
        Malformed points (shape, NaN/inf, a nonzero coordinate outside the exact predicates'
        range ``[2**-148, 2**200]`` in magnitude), triangulation arrays (a point index out of
        range, a triangle that is not strictly counter-clockwise) or clip box.
    GeometryError
        The clip polygon has fewer than 3 distinct vertices or is not simple.
    DegenerateInputError
        Fewer than three points or all collinear (no triangle).
    """
    poly = None if clip is None else clip_region(clip)
    seed = check_seed(seed)
    points, tri, nbr = _delaunay_arrays(points_or_triangulation, seed)
    n = len(points)
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
        vertices, ridge_points, ridge_vertices, voff, cv = clip_diagram(
            points, centres, poly, ridge_points, ridge_vertices, voff, cv, noff, nb_pts, nb_ridges
        )
        directions = np.zeros((len(ridge_points), 2))
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


def _delaunay_arrays(obj, seed: int):
    """Return ``points`` (n, 2) float64, ``triangles`` and ``neighbors`` (nt, 3) int32."""
    supplied = hasattr(obj, "triangles") and hasattr(obj, "neighbors")
    if supplied:
        points, tri = as_exact_points(obj.points, copy=True), np.ascontiguousarray(obj.triangles, dtype=np.int32)
    else:
        points = as_exact_points(obj, copy=True)
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
    if supplied:
        t = _first_not_ccw(points, tri)
        if t >= 0:
            corners = ", ".join(f"{i} {fmt_point(points[i])}" for i in tri[t].tolist())
            raise InputError(
                f"triangle {t} is not strictly counter-clockwise (exact orient2d <= 0): points {corners}"
            )
    return points, tri, nbr


@njit(cache=True)
def _first_not_ccw(points, tri):
    """Index of the first triangle of (nt, 3) int32 ``tri`` that is not strictly ccw, else -1."""
    for t in range(tri.shape[0]):
        a, b, c = tri[t, 0], tri[t, 1], tri[t, 2]
        if orient2d(points[a, 0], points[a, 1], points[b, 0], points[b, 1], points[c, 0], points[c, 1]) <= 0.0:
            return t
    return -1


# --------------------------------------------------------------------------- the dual


# The float area keeps at least half its bits where |D| > 2**-26 * permanent (its error is
# below 4 eps = 2**-51 of the permanent); only thinner triangles take the exact path.
_SURE_AREA = 2.0**-26


def _circumcentres(points: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """Return the circumcentre of every (strictly counter-clockwise) triangle, (nt, 2) float64.

    Computed relative to the first vertex, so that the result does not lose digits to large
    absolute coordinates.  The float area ``D = b x c`` (with ``b``, ``c`` the rounded edge
    vectors) errs by less than ``4 eps (|bx cy| + |by cx|)``; where ``|D|`` is not above
    ``_SURE_AREA`` times that permanent, or the float centre is not finite, the centre is
    recomputed exactly (:func:`_exact_circumcentre`).
    """
    a = points[tri[:, 0]]
    b = points[tri[:, 1]] - a
    c = points[tri[:, 2]] - a
    b2 = b[:, 0] ** 2 + b[:, 1] ** 2
    c2 = c[:, 0] ** 2 + c[:, 1] ** 2
    bc, cb = b[:, 0] * c[:, 1], b[:, 1] * c[:, 0]
    d = 2.0 * (bc - cb)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        ux = (c[:, 1] * b2 - b[:, 1] * c2) / d
        uy = (b[:, 0] * c2 - c[:, 0] * b2) / d
        centres = a + np.stack([ux, uy], axis=1)
    doubtful = ~(np.abs(bc - cb) > _SURE_AREA * (np.abs(bc) + np.abs(cb)))
    doubtful |= ~np.isfinite(centres).all(axis=1)
    for t in np.flatnonzero(doubtful):
        centres[t] = _exact_circumcentre(points[tri[t]])
    return centres


def _exact_circumcentre(abc: np.ndarray) -> tuple[float, float]:
    """Circumcentre of the triangle with corners ``abc`` (3, 2) float64, rounded once.

    Exact rational arithmetic on the float inputs; the caller guarantees a nonzero exact area
    (triangles checked counter-clockwise by ``orient2d``, or built by ``delaunay``).
    """
    (ax, ay), (bx, by), (cx, cy) = ((Fraction(float(x)), Fraction(float(y))) for x, y in abc)
    bx, by, cx, cy = bx - ax, by - ay, cx - ax, cy - ay
    b2, c2 = bx * bx + by * by, cx * cx + cy * cy
    d = 2 * (bx * cy - by * cx)
    return float(ax + (cy * b2 - by * c2) / d), float(ay + (bx * c2 - cx * b2) / d)


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
