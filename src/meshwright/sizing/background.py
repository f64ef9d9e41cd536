r"""Background grid of chapter 18.2 (spacing delta, stretching s and direction alpha per node),
and its 3-D counterpart of chapter 18.4.2 step 1 (spacing delta on a mesh of tetrahedra).

Sources: J. Peraire, M. Vahdati, K. Morgan and O. C. Zienkiewicz, "Adaptive remeshing for
compressible flow computations", J. Comput. Phys. 72, 1987 (the background mesh of the
advancing-front method); J. Peraire, J. Peiro and K. Morgan, "Adaptive remeshing for
three-dimensional compressible flow computations", J. Comput. Phys. 103, 1992 (the same on
tetrahedra); chapters 18.2 and 18.4.2 of the reference text.

A background grid is a triangulation (2-D) or tetrahedralization (3-D) covering the domain
with values at each node, interpolated linearly inside each background simplex.  In 2-D the
values are the spacing ``delta``, the stretching ``s >= 1`` and the stretching direction
``alpha``.  An element generated at a point has length ``s * delta`` along ``alpha`` and
``delta`` across it; the chapter maps the plane by the local transformation
``T = R(alpha) diag(1/s, 1) R(-alpha)`` (rotate alpha onto x1, scale x1 by 1/s, rotate back),
in which those elements are equilateral of side delta: :meth:`BackgroundGrid.transform`
returns it.  In 3-D the grid is isotropic: ``delta`` only (stretching in 3-D would need a
direction frame per node, which no 3-D method here honours, so the constructor refuses it).

Directions are axes (alpha and alpha + pi are the same stretching), so they are
interpolated as the doubled-angle vector ``(cos 2 alpha, sin 2 alpha)``, whose angle is
halved afterwards; interpolating the angles themselves would turn 179 and 1 degrees into 90.

Outside the background simplices (the grid should cover the domain, but a boundary point
may sit on a curve just beyond the chord of a background edge, or a surface point just
beyond a background face) the values of the nearest point of the nearest simplex are used.

Layout: ``points`` (n, d) float64, ``cells`` (m, d + 1) int32 (counter-clockwise triangles,
positively oriented tetrahedra: ``orient3d > 0``), ``delta``, ``stretch``, ``direction``
(n,) float64; point location by the uniform bucket grid of :mod:`meshwright.sizing._buckets`
(CSR ``start`` (cubes + 1,) int64, ``items`` int32, about two simplices per cube) and walks
across the face neighbours (``core.mesh.build_neighbors`` / ``build_neighbors_tet``: a
background whose simplices overlap or share a face three times is refused); the 3-D kernels
are in :mod:`meshwright.sizing._background3d`.

File format (:meth:`BackgroundGrid.read` / :meth:`BackgroundGrid.write`), plain text, ``#``
comments; 2-D::

    meshwright-background 1
    n m
    x y delta stretch direction_degrees      (n lines)
    i j k                                    (m lines, 0-based, counter-clockwise)

3-D (a third number on the count line gives the dimension)::

    meshwright-background 1
    n m 3
    x y z delta                              (n lines)
    i j k l                                  (m lines, 0-based, orient3d > 0)
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numba import njit

from meshwright.core.errors import FormatError, InputError, SizeError, ValidationError
from meshwright.core.mesh import build_neighbors, build_neighbors_tet
from meshwright.sizing._background3d import interpolate3d
from meshwright.sizing._buckets import bucket_grid, bucket_shape
from meshwright.sizing.boundary import point_distribution
from meshwright.sizing.field import SizeField, fmt_point, unit_tangents

__all__ = ["BackgroundGrid", "interpolate_one", "interpolate_walk"]

_MAGIC = "meshwright-background 1"


@njit(inline="always")
def _barycentric(pts, tris, t, x, y):
    ax = pts[tris[t, 0], 0]
    ay = pts[tris[t, 0], 1]
    bx = pts[tris[t, 1], 0]
    by = pts[tris[t, 1], 1]
    cx = pts[tris[t, 2], 0]
    cy = pts[tris[t, 2], 1]
    det = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    l1 = ((x - ax) * (cy - ay) - (y - ay) * (cx - ax)) / det
    l2 = ((bx - ax) * (y - ay) - (by - ay) * (x - ax)) / det
    return 1.0 - l1 - l2, l1, l2


@njit(cache=True)
def _weights(pts, tris, start, items, x0, y0, cell, nx, ny, x, y):
    """Background triangle and barycentric weights ``(t, w0, w1, w2)`` for the point (x, y).

    The containing triangle is searched in the query's cell; a point in no triangle takes
    the weights of the nearest point of the nearest triangle, searched in growing rings:
    that point's position along its edge, so the weights stay a convex combination (the
    barycentric coordinates of a point on an edge of a needle, divided by its tiny area,
    could be anything).
    """
    ci = min(nx - 1, max(0, int((x - x0) / cell)))
    cj = min(ny - 1, max(0, int((y - y0) / cell)))
    best = -1
    best_d2 = np.inf
    best_e = 0
    best_s = 0.0
    ring = 0
    found_ring = -1
    while ring <= max(nx, ny):
        for j in range(max(0, cj - ring), min(ny, cj + ring + 1)):
            for i in range(max(0, ci - ring), min(nx, ci + ring + 1)):
                if max(abs(i - ci), abs(j - cj)) != ring:
                    continue
                c = j * nx + i
                for s in range(start[c], start[c + 1]):
                    t = items[s]
                    w0, w1, w2 = _barycentric(pts, tris, t, x, y)
                    if min(w0, w1, w2) >= 0.0:
                        best, best_d2, best_e = t, 0.0, -1
                        continue
                    for e in range(3):
                        u = tris[t, (e + 1) % 3]
                        w = tris[t, (e + 2) % 3]
                        ex = pts[w, 0] - pts[u, 0]
                        ey = pts[w, 1] - pts[u, 1]
                        den = ex * ex + ey * ey
                        f = 0.0 if den == 0.0 else min(1.0, max(0.0, ((x - pts[u, 0]) * ex + (y - pts[u, 1]) * ey) / den))
                        d2 = (pts[u, 0] + f * ex - x) ** 2 + (pts[u, 1] + f * ey - y) ** 2
                        if d2 < best_d2:
                            best, best_d2, best_e, best_s = t, d2, e, f
        if best >= 0 and found_ring < 0:
            found_ring = ring
        # Once something is found, one more ring covers every nearer candidate.
        if best_d2 == 0.0 or (found_ring >= 0 and ring > found_ring):
            break
        ring += 1
    if best_e < 0:
        w0, w1, w2 = _barycentric(pts, tris, best, x, y)
        return best, w0, w1, w2
    # Weight 1 - f on the edge's first vertex, f on its second, none on the opposite one.
    w0 = 0.0 if best_e == 0 else (1.0 - best_s if best_e == 2 else best_s)
    w1 = 0.0 if best_e == 1 else (1.0 - best_s if best_e == 0 else best_s)
    w2 = 0.0 if best_e == 2 else (1.0 - best_s if best_e == 1 else best_s)
    return best, w0, w1, w2


@njit(cache=True)
def interpolate_walk(pts, tris, nbr, start, items, x0, y0, cell, nx, ny, values, col, hint, x, y):
    """:func:`interpolate_one` walking from the triangle ``hint[0]`` (updated), for queries
    that move a little at a time (a front): O(distance) instead of a bucket scan, which a
    graded background (many small triangles in one bucket) makes slow.  A walk that leaves
    the grid (across a hole or a concave side) falls back to the bucket scan, whose triangle
    becomes the hint, so that the next query near (x, y) walks from there."""
    t = hint[0]
    if t < 0 or t >= tris.shape[0]:
        t = 0
    for step in range(4096):
        n = -2  # no edge with the query on its outer side: t contains it
        for j in range(3):
            e = (j + step) % 3
            u = tris[t, (e + 1) % 3]
            w = tris[t, (e + 2) % 3]
            side = (pts[w, 0] - pts[u, 0]) * (y - pts[u, 1]) - (pts[w, 1] - pts[u, 1]) * (x - pts[u, 0])
            if side < 0.0:
                n = nbr[t, e]
                break
        if n == -2:
            hint[0] = t
            w0, w1, w2 = _barycentric(pts, tris, t, x, y)
            return w0 * values[tris[t, 0], col] + w1 * values[tris[t, 1], col] + w2 * values[tris[t, 2], col]
        if n < 0:
            break
        t = n
    t, w0, w1, w2 = _weights(pts, tris, start, items, x0, y0, cell, nx, ny, x, y)
    hint[0] = t
    return w0 * values[tris[t, 0], col] + w1 * values[tris[t, 1], col] + w2 * values[tris[t, 2], col]


@njit(cache=True)
def interpolate_one(pts, tris, start, items, x0, y0, cell, nx, ny, x, y, values, col):
    """Linear interpolation of column ``col`` of ``values`` (n, k) at one point (x, y);
    kernels that need sizes inside their loops call this directly."""
    t, w0, w1, w2 = _weights(pts, tris, start, items, x0, y0, cell, nx, ny, x, y)
    return w0 * values[tris[t, 0], col] + w1 * values[tris[t, 1], col] + w2 * values[tris[t, 2], col]


@njit(cache=True)
def _interpolate(pts, tris, start, items, x0, y0, cell, nx, ny, xy, values):
    """Linear interpolation of ``values`` (n, k) at ``xy`` (q, 2); returns (q, k)."""
    q = xy.shape[0]
    k = values.shape[1]
    out = np.empty((q, k))
    for p in range(q):
        t, w0, w1, w2 = _weights(pts, tris, start, items, x0, y0, cell, nx, ny, xy[p, 0], xy[p, 1])
        for c in range(k):
            out[p, c] = w0 * values[tris[t, 0], c] + w1 * values[tris[t, 1], c] + w2 * values[tris[t, 2], c]
    return out



def _area2(pts: np.ndarray, tris: np.ndarray) -> np.ndarray:
    """(m,) float64: twice the signed area of each triangle."""
    a, b, c = pts[tris[:, 0]], pts[tris[:, 1]], pts[tris[:, 2]]
    return (b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0]


def _volume6(pts: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """(m,) float64: six times the signed volume of each tetrahedron."""
    a = pts[tets[:, 0]]
    return np.einsum("mi,mi->m", pts[tets[:, 1]] - a, np.cross(pts[tets[:, 2]] - a, pts[tets[:, 3]] - a))


def _measure(pts: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Twice the area (2-D) or six times the volume (3-D) of each simplex, signed."""
    return _area2(pts, cells) if pts.shape[1] == 2 else _volume6(pts, cells)


def _nodes_and_cells(points, cells, dim: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Coerce and check a background's points (n, d) and simplices (m, d + 1), orientation aside.

    ``dim`` None takes d from the points (2 or 3).
    """
    pts = np.ascontiguousarray(np.asarray(points, dtype=np.float64))
    d = dim
    if d is None:
        d = pts.shape[1] if pts.ndim == 2 and pts.shape[1] in (2, 3) else 0
    if pts.ndim != 2 or pts.shape[1] != d or len(pts) < d + 1:
        want = f"(n >= {d + 1}, {d})" if d else "(n >= 3, 2) or (n >= 4, 3)"
        raise InputError(f"background points must have shape {want}, got {pts.shape}")
    bad = np.flatnonzero(~np.isfinite(pts).all(axis=1))
    if len(bad):
        raise InputError(f"background node {bad[0]} has non-finite coordinates {pts[bad[0]].tolist()}")
    c = np.asarray(cells)
    what = "triangles" if d == 2 else "tetrahedra"
    if c.ndim != 2 or c.shape[1] != d + 1 or len(c) == 0 or not np.issubdtype(c.dtype, np.integer):
        raise InputError(f"background {what} must be an (m >= 1, {d + 1}) integer array, got {c.shape} {c.dtype}")
    if c.min() < 0 or c.max() >= len(pts):
        raise InputError(f"background {what} refer to nodes outside [0, {len(pts)})")
    return pts, np.ascontiguousarray(c, dtype=np.int32)


def _per_node(value, n: int, name: str) -> np.ndarray:
    v = np.asarray(value, dtype=np.float64)
    if v.ndim == 0:
        v = np.full(n, float(v))
    if v.shape != (n,):
        raise InputError(f"background {name} must be a scalar or have one value per node ({n}), got shape {v.shape}")
    return np.ascontiguousarray(v)


class BackgroundGrid(SizeField):
    """Spacing on a background triangulation (2-D: with stretching) or tetrahedralization (3-D).

    Usable wherever a size is accepted (``size=BackgroundGrid(...)``): as a size field it
    gives delta at (k, d) points, and in 2-D :meth:`along` gives the direction-aware spacing
    along a curve, which boundary discretisation uses (``s * delta`` along alpha, ``delta``
    across it).  The dimension is the points' (:attr:`dim`).

    Parameters
    ----------
    points : (n, 2) or (n, 3) array_like of float64
    cells : (m, 3) or (m, 4) array_like of int
        Counter-clockwise triangles (2-D) or positively oriented tetrahedra (3-D,
        ``orient3d > 0``) covering the domain.
    delta : float or (n,) array_like
        Spacing, positive.
    stretch : float or (n,) array_like, optional
        2-D only: stretching s >= 1 (element length s * delta along the direction); default 1.
    direction : float or (n,) array_like, optional
        2-D only: stretching direction alpha in radians, from the x axis; default 0.

    Attributes
    ----------
    dim : int
    points : (n, dim) float64
    cells : (m, dim + 1) int32
        Also :attr:`triangles` (2-D) or :attr:`tetrahedra` (3-D).
    delta, stretch, direction : (n,) float64
        In 3-D ``stretch`` is all ones and ``direction`` all zeros (isotropic).

    Raises
    ------
    InputError
        Wrong shapes, indices out of range, non-finite coordinates, a triangle that is not
        counter-clockwise or a tetrahedron not positively oriented, simplices that overlap
        across a shared face or a face shared by three (all named); ``stretch`` or
        ``direction`` given in 3-D.
    SizeError
        A spacing that is not positive or a stretching below 1 (node and value named).
    """

    def __init__(self, points, cells, delta, stretch=None, direction=None):
        pts, cells = _nodes_and_cells(points, cells)
        dim = pts.shape[1]
        if dim == 3 and (stretch is not None or direction is not None):
            raise InputError(
                "a 3-D background grid is isotropic (delta only): stretch and direction are 2-D, "
                f"got stretch={stretch!r}, direction={direction!r}"
            )
        measure = _measure(pts, cells)
        flat = np.flatnonzero(measure <= 0.0)
        if len(flat):
            t = flat[0]
            raise InputError(
                f"background triangle {t} {cells[t].tolist()} is not counter-clockwise "
                f"(twice its signed area is {measure[t]!r})"
                if dim == 2
                else f"background tetrahedron {t} {cells[t].tolist()} is not positively oriented "
                f"(six times its signed volume is {measure[t]!r})"
            )
        n = len(pts)
        d = _per_node(delta, n, "delta")
        s = _per_node(1.0 if stretch is None else stretch, n, "stretch")
        al = _per_node(0.0 if direction is None else direction, n, "direction")
        for name, v, ok in (("delta", d, d > 0.0), ("stretch", s, s >= 1.0), ("direction", al, np.isfinite(al))):
            bad = np.flatnonzero(~(ok & np.isfinite(v)))
            if len(bad):
                raise SizeError(
                    f"background {name} at node {bad[0]} {fmt_point(pts[bad[0]])} is {float(v[bad[0]])!r}; "
                    + ("it must be positive" if name == "delta" else "it must be >= 1" if name == "stretch" else "")
                )
        self.dim = dim
        self.points, self.cells = pts, cells
        if dim == 2:
            self.triangles = cells
            # Interpolated columns: delta, s, cos 2 alpha, sin 2 alpha.
            self._values = np.ascontiguousarray(np.column_stack([d, s, np.cos(2 * al), np.sin(2 * al)]))
        else:
            self.tetrahedra = cells
            self._values = np.ascontiguousarray(d[:, None])
        self.delta, self.stretch, self.direction = d, s, al
        lo, self._cell, dims = bucket_shape(pts, len(cells))
        self._lo, self._dims = lo, dims
        self._start, self._items = bucket_grid(pts, cells, lo, self._cell, dims)
        try:
            self._nbr = (build_neighbors if dim == 2 else build_neighbors_tet)(cells)
        except ValidationError as exc:
            raise InputError(f"background grid: {exc}") from exc
        constant = float(d[0]) if np.all(d == d[0]) else None
        super().__init__(self._spacing, constant=constant, name="background grid", dim=dim)

    def __repr__(self) -> str:
        what = "triangles" if self.dim == 2 else "tetrahedra"
        return f"BackgroundGrid({len(self.points)} nodes, {len(self.cells)} {what})"

    def _grid(self) -> tuple:
        """Lower corner, cube side and cubes per axis as the kernels take them (scalars)."""
        return (*(float(v) for v in self._lo), self._cell, *(int(v) for v in self._dims))

    def _interp(self, xy) -> np.ndarray:
        q = np.ascontiguousarray(np.asarray(xy, dtype=np.float64).reshape(-1, self.dim))
        if self.dim == 3:
            return interpolate3d(*self.kernel_args(), q)
        return _interpolate(self.points, self.cells, self._start, self._items, *self._grid(), q, self._values)

    def kernel_args(self) -> tuple:
        """The grid as the walking interpolation kernels take it.

        2-D: ``(points, triangles, neighbours, start, items, x0, y0, cell, nx, ny, values)``
        for :func:`interpolate_walk` (``values`` columns: delta, s, cos 2 alpha, sin 2 alpha).
        3-D: ``(points, tetrahedra, neighbours, start, items, x0, y0, z0, cell, nx, ny, nz,
        values)``, the leading arguments of every kernel of
        :mod:`meshwright.sizing._background3d` (``interpolate3d_one(*args, col, x, y, z)``,
        ``interpolate3d_walk(*args, col, hint, x, y, z)``; ``values`` column 0: delta).
        """
        return (self.points, self.cells, self._nbr, self._start, self._items, *self._grid(), self._values)

    def _spacing(self, xy) -> np.ndarray:
        return self._interp(xy)[:, 0]

    def _planar(self, what: str) -> None:
        if self.dim != 2:
            raise InputError(f"BackgroundGrid.{what} is 2-D (stretching); this grid is {self.dim}-D and isotropic")

    def metric(self, xy) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Interpolated ``(delta, stretch, direction)`` at ``xy`` (k, 2), each (k,) float64.

        ``direction`` is in radians, in (-pi/2, pi/2].  2-D only (InputError in 3-D).
        """
        self._planar("metric")
        v = self._interp(xy)
        return v[:, 0], v[:, 1], 0.5 * np.arctan2(v[:, 3], v[:, 2])

    def along(self, xy, tangents) -> np.ndarray:
        r"""Spacing wanted along a curve through ``xy`` (n, d) with ``tangents`` (n, d).

        With ``delta``, ``s``, ``alpha`` interpolated at each point and ``tau`` the unit
        tangent, the spacing is :math:`1 / \sqrt{\tau^T M \tau}` for the metric
        :math:`M = T^2 / \delta^2`, ``T`` as in :meth:`transform`: ``s * delta`` along
        alpha, ``delta`` across it, the radius of that ellipse in between.  Because ``T`` is
        symmetric, :math:`\tau^T M \tau = |T \tau|^2 / \delta^2
        = (1 - c^2 (1 - 1/s^2)) / \delta^2` with :math:`c = \cos(\angle(\tau, \alpha))`,
        which is what is evaluated (exactly ``delta`` where ``s = 1``, and so everywhere in
        3-D).

        Parameters
        ----------
        xy : (n, d) array_like of float64
        tangents : (n, d) array_like of float64
            Any nonzero length; a zero tangent gets ``delta``.

        Returns
        -------
        (n,) float64
            Positive, finite spacings.

        Raises
        ------
        InputError
            Mismatched shapes or a non-finite tangent (its index named).
        """
        tau, _ = unit_tangents(xy, tangents, self.dim)
        if np.all(self.stretch == 1.0):
            # Keeps an unstretched grid bit-for-bit equal to its isotropic size field.
            return self(xy)
        d, s, al = self.metric(xy)
        if self.constant is not None:
            # The size field's exact constant, not the interpolation's rounding of it.
            d = np.full(len(d), self.constant)
        # Interpolating values >= 1 can round a hair below 1.
        s = np.maximum(s, 1.0)
        c = tau[:, 0] * np.cos(al) + tau[:, 1] * np.sin(al)
        # A zero tangent has c = 0 and so gets delta.
        return d / np.sqrt(1.0 - c * c * (1.0 - 1.0 / (s * s)))

    def transform(self, xy) -> np.ndarray:
        """The chapter's local transformation at ``xy`` (k, 2): (k, 2, 2) float64 matrices.

        ``T = R(alpha) diag(1/s, 1) R(-alpha)``: a vector of length ``s * delta`` along alpha
        and one of length ``delta`` across it both map to length ``delta``.  2-D only
        (InputError in 3-D).
        """
        self._planar("transform")
        _, s, al = self.metric(xy)
        c, sn = np.cos(al), np.sin(al)
        # R diag(1/s, 1) R^T expanded.
        t = np.empty((len(s), 2, 2))
        t[:, 0, 0] = c * c / s + sn * sn
        t[:, 0, 1] = c * sn / s - c * sn
        t[:, 1, 0] = t[:, 0, 1]
        t[:, 1, 1] = sn * sn / s + c * c
        return t

    # ------------------------------------------------------------------ constructors
    @classmethod
    def uniform(cls, bbox, delta: float, stretch: float | None = None, direction: float | None = None) -> BackgroundGrid:
        """Uniform values on a box enlarged by 10 % per side: two triangles or six tetrahedra.

        Parameters
        ----------
        bbox : sequence of 4 or 6 floats, or (2, d) array_like
            ``(xmin, ymin, xmax, ymax)`` (2-D) or ``(xmin, ymin, zmin, xmax, ymax, zmax)``
            (3-D); a ``[lo, hi]`` pair of corners (a ``bbox`` attribute) reads the same.
        delta : float
        stretch, direction : float, optional
            2-D only, as in the constructor.

        Raises
        ------
        InputError
            A box that is not 4 or 6 numbers, empty or non-finite; stretching in 3-D.
        SizeError
            As the constructor.
        """
        try:
            box = np.asarray(bbox, dtype=np.float64).ravel()
        except (TypeError, ValueError) as exc:
            raise InputError(f"bbox must be 4 (2-D) or 6 (3-D) numbers, got {bbox!r}") from exc
        if box.size not in (4, 6) or not np.isfinite(box).all():
            raise InputError(f"bbox must be 4 (2-D) or 6 (3-D) finite numbers, got {bbox!r}")
        d = box.size // 2
        lo, hi = box[:d], box[d:]
        if not (hi > lo).all():
            names = "xmin < xmax and ymin < ymax" + (" and zmin < zmax" if d == 3 else "")
            raise InputError(f"bbox must have {names}, got {bbox}")
        margin = 0.1 * (hi - lo)
        lo, hi = lo - margin, hi + margin
        if d == 2:
            (x0, y0), (x1, y1) = lo, hi
            pts = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
            return cls(pts, [(0, 1, 2), (0, 2, 3)], delta, stretch, direction)
        # Corner b has bit k set where it sits at hi along axis k; Kuhn's six tetrahedra run
        # from corner 0 to corner 7 along the edges of the cube, one per order of the axes.
        bits = np.arange(8)[:, None] >> np.arange(3) & 1
        pts = np.where(bits == 1, hi, lo)
        tets = []
        for a, b in ((0, 1), (0, 2), (1, 0), (1, 2), (2, 0), (2, 1)):
            tets.append((0, 1 << a, (1 << a) | (1 << b), 7))
        tets = np.array(tets, dtype=np.int32)
        backwards = _volume6(pts, tets) < 0.0
        tets[backwards] = tets[backwards][:, [0, 1, 3, 2]]
        return cls(pts, tets, delta, stretch, direction)

    @classmethod
    def from_boundary(cls, points, segments, triangles) -> BackgroundGrid:
        """Chapter 18.3's background: the triangulated boundary nodes with Weatherill's dP (2-D).

        Parameters
        ----------
        points : (n, 2) float64
            Boundary nodes.
        segments : (m, 2) int
            Boundary segments (dP is their mean length at each node).
        triangles : (t, 3) int
            A triangulation of ``points`` (e.g. their Delaunay triangulation).
        """
        pts, triangles = _nodes_and_cells(points, triangles, 2)
        dp = point_distribution(pts, segments)
        lonely = ~np.isfinite(dp)
        if lonely.all():
            raise SizeError("a background from the boundary needs at least one segment")
        dp[lonely] = np.nanmean(dp)
        return cls.on_triangulation(pts, triangles, dp)

    @classmethod
    def on_triangulation(cls, points, triangles, delta) -> BackgroundGrid:
        """Spacing ``delta`` (n,) on a mesh's triangles (points (n, 2)), its slivers left out.

        A triangulation built with exact predicates may hold triangles that are exactly
        counter-clockwise yet whose floating-point area rounds to zero; they carry nothing to
        interpolate, so they are dropped instead of rejected.
        """
        pts, tris = _nodes_and_cells(points, triangles, 2)
        return cls(pts, tris[_area2(pts, tris) > 0.0], delta)

    @classmethod
    def on_tetrahedra(cls, points, tetrahedra, delta) -> BackgroundGrid:
        """Spacing ``delta`` (n,) on a mesh's tetrahedra (points (n, 3)), its slivers left out.

        As :meth:`on_triangulation`: tetrahedra that are exactly positive but whose
        floating-point volume rounds to zero (or below) are dropped instead of rejected.

        Parameters
        ----------
        points : (n, 3) array_like of float64
        tetrahedra : (m, 4) array_like of int
            Positively oriented (``orient3d > 0``), e.g. ``delaunay(points).tetrahedra``.
        delta : float or (n,) array_like
        """
        pts, tets = _nodes_and_cells(points, tetrahedra, 3)
        return cls(pts, tets[_volume6(pts, tets) > 0.0], delta)

    # ------------------------------------------------------------------ files
    def write(self, path) -> None:
        """Write the grid in the plain-text format of the module docstring."""
        if self.dim == 2:
            lines = [_MAGIC, f"{len(self.points)} {len(self.cells)}"]
            lines += [
                f"{x!r} {y!r} {d!r} {s!r} {float(np.degrees(a))!r}"
                for (x, y), d, s, a in zip(self.points.tolist(), self.delta.tolist(), self.stretch.tolist(), self.direction.tolist())
            ]
        else:
            lines = [_MAGIC, f"{len(self.points)} {len(self.cells)} 3"]
            lines += [f"{x!r} {y!r} {z!r} {d!r}" for (x, y, z), d in zip(self.points.tolist(), self.delta.tolist())]
        lines += [" ".join(str(v) for v in row) for row in self.cells.tolist()]
        Path(path).write_text("\n".join(lines) + "\n")

    @classmethod
    def read(cls, path) -> BackgroundGrid:
        """Read a grid written by :meth:`write` (or by hand in that format), 2-D or 3-D.

        Raises
        ------
        FormatError
            Wrong header, counts, dimension or numbers (file named).
        """
        text = Path(path).read_text().splitlines()
        rows = [ln.split("#", 1)[0].strip() for ln in text]
        rows = [r for r in rows if r]
        if not rows or rows[0] != _MAGIC:
            raise FormatError(f"{path}: first line must be {_MAGIC!r}")
        try:
            counts = [int(v) for v in rows[1].split()]
            if len(counts) not in (2, 3):
                raise ValueError(f"count line {rows[1]!r} must be 'n m' or 'n m dim'")
            n, m, dim = (*counts, 2) if len(counts) == 2 else counts
            if dim not in (2, 3):
                raise ValueError(f"dimension {dim} on the count line must be 2 or 3")
            nodes = np.array([[float(v) for v in r.split()] for r in rows[2 : 2 + n]])
            cells = np.array([[int(v) for v in r.split()] for r in rows[2 + n : 2 + n + m]])
        except (ValueError, IndexError) as exc:
            raise FormatError(f"{path}: malformed background grid ({exc})") from exc
        width = 5 if dim == 2 else 4
        what = "triangle lines of 3" if dim == 2 else "tetrahedron lines of 4"
        if nodes.shape != (n, width) or cells.shape != (m, dim + 1):
            raise FormatError(
                f"{path}: expected {n} node lines of {width} numbers and {m} {what} indices, "
                f"got {nodes.shape} and {cells.shape}"
            )
        if dim == 3:
            return cls(nodes[:, :3], cells, nodes[:, 3])
        return cls(nodes[:, :2], cells, nodes[:, 2], nodes[:, 3], np.radians(nodes[:, 4]))
