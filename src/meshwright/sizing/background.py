r"""Background grid of chapter 18.2: spacing delta, stretching s and direction alpha per node.

Source: J. Peraire, M. Vahdati, K. Morgan and O. C. Zienkiewicz, "Adaptive remeshing for
compressible flow computations", J. Comput. Phys. 72, 1987 (the background mesh of the
advancing-front method); chapter 18.2 of the reference text.

A background grid is a triangulation covering the domain with three values at each node:
the spacing ``delta``, the stretching ``s >= 1`` and the stretching direction ``alpha``.
Inside a background triangle the values are interpolated linearly.  An element generated
at a point has length ``s * delta`` along ``alpha`` and ``delta`` across it; the chapter
maps the plane by the local transformation ``T = R(alpha) diag(1/s, 1) R(-alpha)`` (rotate
alpha onto x1, scale x1 by 1/s, rotate back), in which those elements are equilateral of
side delta: :meth:`BackgroundGrid.transform` returns it.

Directions are axes (alpha and alpha + pi are the same stretching), so they are
interpolated as the doubled-angle vector ``(cos 2 alpha, sin 2 alpha)``, whose angle is
halved afterwards; interpolating the angles themselves would turn 179 and 1 degrees into 90.

Outside the background triangles (the grid should cover the domain, but a boundary point
may sit on a curve just beyond the chord of a background edge) the values of the nearest
point of the nearest triangle are used.

Layout: ``points`` (n, 2) float64, ``triangles`` (m, 3) int32 counter-clockwise, ``delta``,
``stretch``, ``direction`` (n,) float64; point location by a uniform bucket grid over the
triangles' bounding boxes in CSR form (``start`` (cells + 1,) int64, ``items`` int32), about
two triangles per cell.

File format (:meth:`BackgroundGrid.read` / :meth:`BackgroundGrid.write`), plain text::

    meshwright-background 1
    n m
    x y delta stretch direction_degrees      (n lines)
    i j k                                    (m lines, 0-based, counter-clockwise)
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numba import njit

from meshwright.core.errors import FormatError, InputError, SizeError
from meshwright.core.geom2d import closest_on_segment
from meshwright.sizing.boundary import point_distribution
from meshwright.sizing.field import SizeField, fmt_point, unit_tangents

__all__ = ["BackgroundGrid", "interpolate_one", "interpolate_walk"]

_MAGIC = "meshwright-background 1"


@njit(inline="always")
def _cell_range(pts, tris, t, x0, y0, cell, nx, ny):
    """Cells (i0, i1, j0, j1) touched by the bounding box of triangle t."""
    lo_x = min(pts[tris[t, 0], 0], pts[tris[t, 1], 0], pts[tris[t, 2], 0])
    hi_x = max(pts[tris[t, 0], 0], pts[tris[t, 1], 0], pts[tris[t, 2], 0])
    lo_y = min(pts[tris[t, 0], 1], pts[tris[t, 1], 1], pts[tris[t, 2], 1])
    hi_y = max(pts[tris[t, 0], 1], pts[tris[t, 1], 1], pts[tris[t, 2], 1])
    i0 = min(nx - 1, max(0, int((lo_x - x0) / cell)))
    i1 = min(nx - 1, max(0, int((hi_x - x0) / cell)))
    j0 = min(ny - 1, max(0, int((lo_y - y0) / cell)))
    j1 = min(ny - 1, max(0, int((hi_y - y0) / cell)))
    return i0, i1, j0, j1


@njit(cache=True)
def _bucket_grid(pts, tris, x0, y0, cell, nx, ny):
    """CSR lists ``(start, items)`` of the triangles whose bounding box touches each cell."""
    m = tris.shape[0]
    start = np.zeros(nx * ny + 1, dtype=np.int64)
    for t in range(m):
        i0, i1, j0, j1 = _cell_range(pts, tris, t, x0, y0, cell, nx, ny)
        for j in range(j0, j1 + 1):
            for i in range(i0, i1 + 1):
                start[j * nx + i + 1] += 1
    for c in range(nx * ny):
        start[c + 1] += start[c]
    items = np.empty(start[nx * ny], dtype=np.int32)
    fill = start[:-1].copy()
    for t in range(m):
        i0, i1, j0, j1 = _cell_range(pts, tris, t, x0, y0, cell, nx, ny)
        for j in range(j0, j1 + 1):
            for i in range(i0, i1 + 1):
                c = j * nx + i
                items[fill[c]] = t
                fill[c] += 1
    return start, items


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
    the weights of the nearest point of the nearest triangle, searched in growing rings.
    """
    ci = min(nx - 1, max(0, int((x - x0) / cell)))
    cj = min(ny - 1, max(0, int((y - y0) / cell)))
    best = -1
    best_d2 = np.inf
    bx_ = x
    by_ = y
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
                        best, best_d2, bx_, by_ = t, 0.0, x, y
                        continue
                    for e in range(3):
                        u = tris[t, (e + 1) % 3]
                        w = tris[t, (e + 2) % 3]
                        cx, cy = closest_on_segment(pts[u, 0], pts[u, 1], pts[w, 0], pts[w, 1], x, y)
                        d2 = (cx - x) ** 2 + (cy - y) ** 2
                        if d2 < best_d2:
                            best, best_d2, bx_, by_ = t, d2, cx, cy
        if best >= 0 and found_ring < 0:
            found_ring = ring
        # Once something is found, one more ring covers every nearer candidate.
        if best_d2 == 0.0 or (found_ring >= 0 and ring > found_ring):
            break
        ring += 1
    w0, w1, w2 = _barycentric(pts, tris, best, bx_, by_)
    return best, w0, w1, w2


def _neighbours(tris: np.ndarray) -> np.ndarray:
    """(m, 3) int32: the triangle across the edge opposite vertex k, -1 on the border."""
    m = len(tris)
    a = tris[:, [1, 2, 0]].ravel().astype(np.int64)
    b = tris[:, [2, 0, 1]].ravel().astype(np.int64)
    n = int(tris.max()) + 1
    key = a * n + b
    rev = b * n + a
    order = np.argsort(key)
    pos = np.searchsorted(key[order], rev)
    pos = np.minimum(pos, len(key) - 1)
    hit = key[order][pos] == rev
    out = np.full(3 * m, -1, dtype=np.int32)
    out[hit] = (order[pos[hit]] // 3).astype(np.int32)
    return out.reshape(m, 3)


@njit(cache=True)
def interpolate_walk(pts, tris, nbr, start, items, x0, y0, cell, nx, ny, values, col, hint, x, y):
    """:func:`interpolate_one` walking from the triangle ``hint[0]`` (updated), for queries
    that move a little at a time (a front): O(distance) instead of a bucket scan, which a
    graded background (many small triangles in one bucket) makes slow."""
    t = hint[0]
    if t < 0 or t >= tris.shape[0]:
        t = 0
    for step in range(4096):
        moved = False
        for j in range(3):
            e = (j + step) % 3
            u = tris[t, (e + 1) % 3]
            w = tris[t, (e + 2) % 3]
            side = (pts[w, 0] - pts[u, 0]) * (y - pts[u, 1]) - (pts[w, 1] - pts[u, 1]) * (x - pts[u, 0])
            if side < 0.0:
                n = nbr[t, e]
                if n < 0:
                    return interpolate_one(pts, tris, start, items, x0, y0, cell, nx, ny, x, y, values, col)
                t = n
                moved = True
                break
        if not moved:
            hint[0] = t
            w0, w1, w2 = _barycentric(pts, tris, t, x, y)
            return w0 * values[tris[t, 0], col] + w1 * values[tris[t, 1], col] + w2 * values[tris[t, 2], col]
    return interpolate_one(pts, tris, start, items, x0, y0, cell, nx, ny, x, y, values, col)


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


def _per_node(value, n: int, name: str) -> np.ndarray:
    v = np.asarray(value, dtype=np.float64)
    if v.ndim == 0:
        v = np.full(n, float(v))
    if v.shape != (n,):
        raise InputError(f"background {name} must be a scalar or have one value per node ({n}), got shape {v.shape}")
    return np.ascontiguousarray(v)


class BackgroundGrid(SizeField):
    """Spacing delta, stretching s and direction alpha on a background triangulation.

    Usable wherever a size is accepted (``size=BackgroundGrid(...)``): as a size field it
    gives delta, and :meth:`along` gives the direction-aware spacing along a curve, which
    boundary discretisation uses (``s * delta`` along alpha, ``delta`` across it).

    Parameters
    ----------
    points : (n, 2) array_like of float64
    triangles : (m, 3) array_like of int
        Counter-clockwise triangles covering the domain.
    delta : float or (n,) array_like
        Spacing, positive.
    stretch : float or (n,) array_like
        Stretching s >= 1 (element length s * delta along the direction).
    direction : float or (n,) array_like
        Stretching direction alpha in radians, from the x axis.

    Raises
    ------
    InputError
        Wrong shapes, indices out of range, non-finite coordinates, a triangle that is not
        counter-clockwise (all named).
    SizeError
        A spacing that is not positive or a stretching below 1 (node and value named).
    """

    def __init__(self, points, triangles, delta, stretch=1.0, direction=0.0):
        pts = np.ascontiguousarray(np.asarray(points, dtype=np.float64))
        if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 3:
            raise InputError(f"background points must have shape (n >= 3, 2), got {pts.shape}")
        bad = np.flatnonzero(~np.isfinite(pts).all(axis=1))
        if len(bad):
            raise InputError(f"background node {bad[0]} has non-finite coordinates {pts[bad[0]].tolist()}")
        tris = np.asarray(triangles)
        if tris.ndim != 2 or tris.shape[1] != 3 or len(tris) == 0 or not np.issubdtype(tris.dtype, np.integer):
            raise InputError(f"background triangles must be an (m >= 1, 3) integer array, got {tris.shape} {tris.dtype}")
        if tris.min() < 0 or tris.max() >= len(pts):
            raise InputError(f"background triangles refer to nodes outside [0, {len(pts)})")
        tris = np.ascontiguousarray(tris, dtype=np.int32)
        area2 = _area2(pts, tris)
        flat = np.flatnonzero(area2 <= 0.0)
        if len(flat):
            raise InputError(
                f"background triangle {flat[0]} {tris[flat[0]].tolist()} is not counter-clockwise "
                f"(twice its signed area is {area2[flat[0]]!r})"
            )
        n = len(pts)
        d = _per_node(delta, n, "delta")
        s = _per_node(stretch, n, "stretch")
        al = _per_node(direction, n, "direction")
        for name, v, ok in (("delta", d, d > 0.0), ("stretch", s, s >= 1.0), ("direction", al, np.isfinite(al))):
            bad = np.flatnonzero(~(ok & np.isfinite(v)))
            if len(bad):
                raise SizeError(
                    f"background {name} at node {bad[0]} {fmt_point(pts[bad[0]])} is {float(v[bad[0]])!r}; "
                    + ("it must be positive" if name == "delta" else "it must be >= 1" if name == "stretch" else "")
                )
        self.points, self.triangles = pts, tris
        self.delta, self.stretch, self.direction = d, s, al
        # Interpolated columns: delta, s, cos 2 alpha, sin 2 alpha.
        self._values = np.ascontiguousarray(np.column_stack([d, s, np.cos(2 * al), np.sin(2 * al)]))
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        ext = float(max(hi - lo))
        cells = max(1, int(np.sqrt(len(tris) / 2.0)))
        self._cell = ext / cells if ext > 0 else 1.0
        self._nx = max(1, int(np.ceil((hi[0] - lo[0]) / self._cell)) + 1)
        self._ny = max(1, int(np.ceil((hi[1] - lo[1]) / self._cell)) + 1)
        self._x0, self._y0 = float(lo[0]), float(lo[1])
        self._start, self._items = _bucket_grid(pts, tris, self._x0, self._y0, self._cell, self._nx, self._ny)
        self._nbr = _neighbours(tris)
        constant = float(d[0]) if np.all(d == d[0]) else None
        super().__init__(self._spacing, constant=constant, name="background grid")

    def __repr__(self) -> str:
        return f"BackgroundGrid({len(self.points)} nodes, {len(self.triangles)} triangles)"

    def _interp(self, xy) -> np.ndarray:
        q = np.ascontiguousarray(np.asarray(xy, dtype=np.float64).reshape(-1, 2))
        return _interpolate(
            self.points, self.triangles, self._start, self._items, self._x0, self._y0, self._cell,
            self._nx, self._ny, q, self._values,
        )

    def kernel_args(self) -> tuple:
        """``(points, triangles, neighbours, start, items, x0, y0, cell, nx, ny, values)``: the
        grid as :func:`interpolate_walk` takes it (``values`` columns: delta, s, cos 2 alpha,
        sin 2 alpha)."""
        return (
            self.points, self.triangles, self._nbr, self._start, self._items, self._x0, self._y0, self._cell,
            self._nx, self._ny, self._values,
        )

    def _spacing(self, xy) -> np.ndarray:
        return self._interp(xy)[:, 0]

    def metric(self, xy) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Interpolated ``(delta, stretch, direction)`` at ``xy`` (k, 2), each (k,) float64.

        ``direction`` is in radians, in (-pi/2, pi/2].
        """
        v = self._interp(xy)
        return v[:, 0], v[:, 1], 0.5 * np.arctan2(v[:, 3], v[:, 2])

    def along(self, xy, tangents) -> np.ndarray:
        r"""Spacing wanted along a curve through ``xy`` (n, 2) with ``tangents`` (n, 2).

        With ``delta``, ``s``, ``alpha`` interpolated at each point and ``tau`` the unit
        tangent, the spacing is :math:`1 / \sqrt{\tau^T M \tau}` for the metric
        :math:`M = T^2 / \delta^2`, ``T`` as in :meth:`transform`: ``s * delta`` along
        alpha, ``delta`` across it, the radius of that ellipse in between.  Because ``T`` is
        symmetric, :math:`\tau^T M \tau = |T \tau|^2 / \delta^2
        = (1 - c^2 (1 - 1/s^2)) / \delta^2` with :math:`c = \cos(\angle(\tau, \alpha))`,
        which is what is evaluated (exactly ``delta`` where ``s = 1``).

        Parameters
        ----------
        xy : (n, 2) array_like of float64
        tangents : (n, 2) array_like of float64
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
        tau, _ = unit_tangents(xy, tangents)
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
        and one of length ``delta`` across it both map to length ``delta``.
        """
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
    def uniform(cls, bbox, delta: float, stretch: float = 1.0, direction: float = 0.0) -> BackgroundGrid:
        """Uniform values on two triangles covering ``bbox = (xmin, ymin, xmax, ymax)`` enlarged by 10 %."""
        x0, y0, x1, y1 = (float(v) for v in bbox)
        if not (x1 > x0 and y1 > y0):
            raise InputError(f"bbox must have xmin < xmax and ymin < ymax, got {bbox}")
        mx, my = 0.1 * (x1 - x0), 0.1 * (y1 - y0)
        pts = [(x0 - mx, y0 - my), (x1 + mx, y0 - my), (x1 + mx, y1 + my), (x0 - mx, y1 + my)]
        return cls(pts, [(0, 1, 2), (0, 2, 3)], delta, stretch, direction)

    @classmethod
    def from_boundary(cls, points, segments, triangles) -> BackgroundGrid:
        """Chapter 18.3's background: the triangulated boundary nodes with Weatherill's dP.

        Parameters
        ----------
        points : (n, 2) float64
            Boundary nodes.
        segments : (m, 2) int
            Boundary segments (dP is their mean length at each node).
        triangles : (t, 3) int
            A triangulation of ``points`` (e.g. their Delaunay triangulation).
        """
        dp = point_distribution(points, segments)
        lonely = ~np.isfinite(dp)
        if lonely.all():
            raise SizeError("a background from the boundary needs at least one segment")
        dp[lonely] = np.nanmean(dp)
        return cls.on_triangulation(points, triangles, dp)

    @classmethod
    def on_triangulation(cls, points, triangles, delta) -> BackgroundGrid:
        """Spacing ``delta`` (n,) on a mesh's triangles, its slivers left out.

        A triangulation built with exact predicates may hold triangles that are exactly
        counter-clockwise yet whose floating-point area rounds to zero; they carry nothing to
        interpolate, so they are dropped instead of rejected.
        """
        pts = np.asarray(points, dtype=np.float64)
        tris = np.asarray(triangles)
        return cls(pts, tris[_area2(pts, tris) > 0.0], delta)

    # ------------------------------------------------------------------ files
    def write(self, path) -> None:
        """Write the grid in the plain-text format of the module docstring."""
        lines = [_MAGIC, f"{len(self.points)} {len(self.triangles)}"]
        lines += [
            f"{x!r} {y!r} {d!r} {s!r} {float(np.degrees(a))!r}"
            for (x, y), d, s, a in zip(self.points.tolist(), self.delta.tolist(), self.stretch.tolist(), self.direction.tolist())
        ]
        lines += [f"{i} {j} {k}" for i, j, k in self.triangles.tolist()]
        Path(path).write_text("\n".join(lines) + "\n")

    @classmethod
    def read(cls, path) -> BackgroundGrid:
        """Read a grid written by :meth:`write` (or by hand in that format).

        Raises
        ------
        FormatError
            Wrong header, counts or numbers (the line is named).
        """
        text = Path(path).read_text().splitlines()
        rows = [ln.split("#", 1)[0].strip() for ln in text]
        rows = [r for r in rows if r]
        if not rows or rows[0] != _MAGIC:
            raise FormatError(f"{path}: first line must be {_MAGIC!r}")
        try:
            n, m = (int(v) for v in rows[1].split())
            nodes = np.array([[float(v) for v in r.split()] for r in rows[2 : 2 + n]])
            tris = np.array([[int(v) for v in r.split()] for r in rows[2 + n : 2 + n + m]])
        except (ValueError, IndexError) as exc:
            raise FormatError(f"{path}: malformed background grid ({exc})") from exc
        if nodes.shape != (n, 5) or tris.shape != (m, 3):
            raise FormatError(
                f"{path}: expected {n} node lines of 5 numbers and {m} triangle lines of 3 indices, "
                f"got {nodes.shape} and {tris.shape}"
            )
        return cls(nodes[:, :2], tris, nodes[:, 2], nodes[:, 3], np.radians(nodes[:, 4]))
