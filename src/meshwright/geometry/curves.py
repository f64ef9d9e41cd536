"""Boundary curves that stay true curves through discretisation, refinement and smoothing.

A domain boundary is a chain of curves.  Meshing never works on a frozen polygon: the
discretiser places points *on* each curve, refinement splits a boundary segment at
:meth:`Curve.midpoint_param` of its two end parameters, and smoothing slides boundary nodes
with :meth:`Curve.project`, so the mesh converges to the true boundary (the "algebraic
equations for each boundary" of the advancing-front recipe, chapter 18.2 of the reference
text; Thompson, Soni and Weatherill, *Handbook of Grid Generation*, CRC Press, 1999).

Parametrisations
----------------
=============  ====================================================================
``Line``       ``t`` in ``[0, 1]``; exact end points
``Arc``        ``t`` is the polar angle in radians from ``theta0`` to ``theta1``; it
               decreases along the curve when the sweep is negative (clockwise)
``Polyline``   ``t`` in ``[0, n - 1]``; vertex ``i`` at ``t = i`` (exact), linear between
``Parametric`` the user's ``t`` in ``[t0, t1]`` with ``t0 < t1``
``Spline``     centripetal Catmull-Rom (Yuksel, Schaefer and Keyser, "Parameterization
               and applications of Catmull-Rom curves", Computer-Aided Design 43(7),
               2011); control point ``i`` at ``t = i``
=============  ====================================================================

Curves without a closed form (``Parametric``, ``Spline``) keep an adaptive table of
parameters refined until the chordal deviation is below 1e-4 of the length; arc length on
that table is Romberg-extrapolated from chords at the table, half and quarter steps, and
:meth:`Curve.project` refines the nearest table point by golden-section search on the true
curve.

All methods take and return arrays: parameters ``(k,)`` float64, points ``(k, 2)`` float64.
"""

from __future__ import annotations

import copy
import math
from abc import ABC, abstractmethod

import numpy as np

from meshwright.core.errors import GeometryError, InputError, fmt_point
from meshwright.geometry._kernels import nearest_segment

__all__ = ["Curve", "Line", "Arc", "Polyline", "Parametric", "Spline"]

_TWO_PI = 2.0 * math.pi
_GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0
_ARC_FINE_STEP = _TWO_PI / 256  # sagitta below 8e-5 of the radius
_TABLE_TOL = 1e-4  # chordal deviation of parametric tables, relative to the length
_TABLE_MAX = 16385


def _params(t) -> np.ndarray:
    return np.atleast_1d(np.asarray(t, dtype=np.float64)).ravel()


def _xy(xy) -> np.ndarray:
    a = np.asarray(xy, dtype=np.float64)
    if a.ndim == 1:
        a = a.reshape(1, -1)
    if a.ndim != 2 or a.shape[1] != 2:
        raise InputError(f"points must have shape (k, 2), got {np.shape(xy)}")
    return a


def _point(p, what: str) -> np.ndarray:
    a = np.asarray(p, dtype=np.float64).ravel()
    if a.shape != (2,):
        raise InputError(f"{what} must be a 2-D point, got {p!r}")
    if not np.all(np.isfinite(a)):
        raise GeometryError(f"{what} has non-finite coordinates {fmt_point(a)}")
    return a


def _affine(matrix, offset) -> tuple[np.ndarray, np.ndarray]:
    a = np.asarray(matrix, dtype=np.float64)
    b = np.asarray(offset, dtype=np.float64).ravel()
    if a.shape != (2, 2) or b.shape != (2,) or not (np.isfinite(a).all() and np.isfinite(b).all()):
        raise InputError("transform needs a finite (2, 2) matrix and a finite (2,) offset")
    if np.linalg.det(a) == 0.0:
        raise GeometryError("transform matrix is singular")
    return a, b


def _chain_area(p: np.ndarray) -> float:
    """Contribution ``1/2 sum(x_i y_{i+1} - x_{i+1} y_i)`` of an open chain of points."""
    return 0.5 * float(np.sum(p[:-1, 0] * p[1:, 1] - p[1:, 0] * p[:-1, 1]))


def _romberg(coarse, half, quarter):
    """Extrapolate O(h^2) + O(h^4) errors away from results at steps h, h/2, h/4."""
    r1 = (4.0 * half - coarse) / 3.0
    r2 = (4.0 * quarter - half) / 3.0
    return (16.0 * r2 - r1) / 15.0


class Curve(ABC):
    """Base class of boundary curves.

    Attributes
    ----------
    t0, t1 : float
        Parameters of the start and end point.
    marker : int or None
        Boundary marker given to every segment discretising the curve (None: the domain's
        default, 1 on loops and 0 on interior constraints).
    min_segments : int
        Fewest segments per piece of the curve that keep its polygon faithful.
    exact_ends : bool
        Whether ``start``/``end`` are the user's exact coordinates (preferred at corners).
    """

    t0: float
    t1: float
    marker: int | None = None
    min_segments: int = 1
    exact_ends: bool = False

    @abstractmethod
    def evaluate(self, t) -> np.ndarray:
        """Points at parameters ``t`` (k,), shape (k, 2) float64."""

    @property
    def start(self) -> np.ndarray:
        """First point, shape (2,)."""
        return self.evaluate(self.t0)[0]

    @property
    def end(self) -> np.ndarray:
        """Last point, shape (2,)."""
        return self.evaluate(self.t1)[0]

    @property
    def length(self) -> float:
        """Total arc length."""
        return float(self.arclength(self.t1)[0])

    def arclength(self, t) -> np.ndarray:
        """Arc length from the start to parameters ``t`` (k,), shape (k,)."""
        tt, ss = self._table()
        return np.interp(_params(t), tt, ss)

    def t_at_length(self, s) -> np.ndarray:
        """Parameters at arc lengths ``s`` (k,) from the start, shape (k,)."""
        tt, ss = self._table()
        return np.interp(_params(s), ss, tt)

    def midpoint_param(self, ta, tb) -> np.ndarray:
        """Parameter halfway in arc length between ``ta`` and ``tb`` (each (k,)), shape (k,)."""
        return self.t_at_length(0.5 * (self.arclength(ta) + self.arclength(tb)))

    @abstractmethod
    def project(self, xy, t_near=None) -> np.ndarray:
        """Parameters of the closest curve points to ``xy`` (k, 2), shape (k,).

        ``t_near`` (k,) are parameters the answers should be close to (a boundary node's
        current parameter): they restrict the search to a neighbourhood, so a node near
        a thin trailing edge is not snapped onto the opposite surface.
        """

    @abstractmethod
    def signed_area(self) -> float:
        """``1/2 * integral(x dy - y dx)`` along the curve; summed over a loop: its area."""

    @abstractmethod
    def reversed(self) -> Curve:
        """The same curve traversed backwards (a new object)."""

    @abstractmethod
    def transformed(self, matrix, offset=(0.0, 0.0)) -> Curve:
        """The image under ``x -> matrix @ x + offset`` (a new object)."""

    def with_marker(self, marker: int | None) -> Curve:
        """A copy with another boundary marker."""
        c = copy.copy(self)
        c.marker = None if marker is None else int(marker)
        return c

    # -- hooks used by Domain ------------------------------------------------------------
    def fine_params(self) -> np.ndarray:
        """Parameters of a polyline resolving the curve's shape, ordered along it."""
        return self._table()[0]

    def breaks(self) -> np.ndarray:
        """Parameters that must be vertices of any discretisation, ordered along the curve."""
        return np.array([self.t0, self.t1])

    def piece_index(self, t) -> np.ndarray:
        """Index of the piece (between consecutive breaks) holding each parameter."""
        return np.zeros(len(_params(t)), dtype=np.int64)

    def segment_markers(self, ta, tb, default: int) -> np.ndarray:
        """Markers (m,) int32 of segments between parameters ``ta`` and ``tb``."""
        m = self.marker if self.marker is not None else default
        return np.full(len(_params(ta)), m, dtype=np.int32)

    def _table(self) -> tuple[np.ndarray, np.ndarray]:
        """Fine arc-length table ``(t, s)``, both (k,) float64: chords of 1025 samples.

        Curves with an exact arc length (lines, arcs, polylines) override the methods that
        use it; curved ones refine it adaptively.
        """
        t = np.linspace(self.t0, self.t1, 1025)
        p = self.evaluate(t)
        s = np.concatenate([[0.0], np.cumsum(np.hypot(*(p[1:] - p[:-1]).T))])
        return t, s


class Line(Curve):
    """Straight segment from ``p0`` to ``p1`` with ``t`` in ``[0, 1]``."""

    exact_ends = True

    def __init__(self, p0, p1, marker: int | None = None):
        self.p0 = _point(p0, "Line start")
        self.p1 = _point(p1, "Line end")
        if np.array_equal(self.p0, self.p1):
            raise GeometryError(f"Line has zero length at {fmt_point(self.p0)}")
        self.t0, self.t1 = 0.0, 1.0
        self.marker = None if marker is None else int(marker)

    def __repr__(self) -> str:
        return f"Line({fmt_point(self.p0)}, {fmt_point(self.p1)}, marker={self.marker})"

    def evaluate(self, t) -> np.ndarray:
        t = _params(t)[:, None]
        # (1 - t) p0 + t p1 reproduces both end points exactly.
        return (1.0 - t) * self.p0 + t * self.p1

    @property
    def start(self) -> np.ndarray:
        return self.p0.copy()

    @property
    def end(self) -> np.ndarray:
        return self.p1.copy()

    @property
    def length(self) -> float:
        return float(np.hypot(*(self.p1 - self.p0)))

    def arclength(self, t) -> np.ndarray:
        return _params(t) * self.length

    def t_at_length(self, s) -> np.ndarray:
        return _params(s) / self.length

    def midpoint_param(self, ta, tb) -> np.ndarray:
        return 0.5 * (_params(ta) + _params(tb))

    def project(self, xy, t_near=None) -> np.ndarray:
        d = self.p1 - self.p0
        return np.clip((_xy(xy) - self.p0) @ d / (d @ d), 0.0, 1.0)

    def signed_area(self) -> float:
        return 0.5 * float(self.p0[0] * self.p1[1] - self.p1[0] * self.p0[1])

    def reversed(self) -> Line:
        return Line(self.p1, self.p0, self.marker)

    def transformed(self, matrix, offset=(0.0, 0.0)) -> Line:
        a, b = _affine(matrix, offset)
        return Line(a @ self.p0 + b, a @ self.p1 + b, self.marker)

    def fine_params(self) -> np.ndarray:
        return np.array([0.0, 1.0])


class Arc(Curve):
    """Circular arc ``center + radius * (cos t, sin t)`` for ``t`` from ``theta0`` to ``theta1``.

    The sweep ``theta1 - theta0`` is signed (negative: clockwise) with ``0 < |sweep| <= 2 pi``;
    a full circle is ``Arc(c, r, a, a + 2 pi)``.  Angles are in radians.
    """

    def __init__(
        self, center, radius: float, theta0: float, theta1: float, marker: int | None = None
    ):
        self.center = _point(center, "Arc center")
        self.radius = float(radius)
        self.t0, self.t1 = float(theta0), float(theta1)
        if not (np.isfinite(self.radius) and self.radius > 0.0):
            raise GeometryError(f"Arc at {fmt_point(self.center)} needs a positive radius, got {radius}")
        sweep = self.t1 - self.t0
        if not np.isfinite(sweep) or sweep == 0.0 or abs(sweep) > _TWO_PI * (1.0 + 1e-12):
            raise GeometryError(
                f"Arc at {fmt_point(self.center)}: sweep theta1 - theta0 = {sweep:.17g} must be "
                "non-zero and at most 2 pi in magnitude"
            )
        self.sweep = sweep
        self.min_segments = max(1, math.ceil(abs(sweep) / (0.5 * math.pi) - 1e-9))
        self.marker = None if marker is None else int(marker)

    def __repr__(self) -> str:
        return (
            f"Arc({fmt_point(self.center)}, {self.radius}, {self.t0}, {self.t1}, marker={self.marker})"
        )

    def evaluate(self, t) -> np.ndarray:
        t = _params(t)
        return self.center + self.radius * np.column_stack([np.cos(t), np.sin(t)])

    @property
    def length(self) -> float:
        return self.radius * abs(self.sweep)

    def arclength(self, t) -> np.ndarray:
        return self.radius * np.abs(_params(t) - self.t0)

    def t_at_length(self, s) -> np.ndarray:
        return self.t0 + np.sign(self.sweep) * _params(s) / self.radius

    def midpoint_param(self, ta, tb) -> np.ndarray:
        return 0.5 * (_params(ta) + _params(tb))

    def project(self, xy, t_near=None) -> np.ndarray:
        d = _xy(xy) - self.center
        sgn = math.copysign(1.0, self.sweep)
        u = np.mod(sgn * (np.arctan2(d[:, 1], d[:, 0]) - self.t0), _TWO_PI)
        span = abs(self.sweep)
        if t_near is None:
            # Outside the sweep: the nearer end point (compare the angular gaps).
            u = np.where(u <= span, u, np.where(u - span < _TWO_PI - u, span, 0.0))
        else:
            # Of the 2 pi-shifted candidates, the one (clamped to the sweep) nearest t_near.
            un = sgn * (_params(t_near) - self.t0)
            cand = np.clip(u[:, None] + np.array([-_TWO_PI, 0.0, _TWO_PI]), 0.0, span)
            u = cand[np.arange(len(u)), np.argmin(np.abs(cand - un[:, None]), axis=1)]
        return self.t0 + sgn * u

    def signed_area(self) -> float:
        cx, cy = self.center
        r = self.radius
        s0, s1 = math.sin(self.t0), math.sin(self.t1)
        c0, c1 = math.cos(self.t0), math.cos(self.t1)
        return 0.5 * (r * r * self.sweep + r * (cx * (s1 - s0) - cy * (c1 - c0)))

    def reversed(self) -> Arc:
        return Arc(self.center, self.radius, self.t1, self.t0, self.marker)

    def transformed(self, matrix, offset=(0.0, 0.0)) -> Curve:
        a, b = _affine(matrix, offset)
        scale = math.sqrt(abs(np.linalg.det(a)))
        if not np.allclose(
            a.T @ a, scale * scale * np.eye(2), rtol=1e-12, atol=1e-14 * scale * scale
        ):
            arc = self
            return Parametric(
                lambda u: arc.evaluate(arc.t0 + u * arc.sweep) @ a.T + b, 0.0, 1.0, self.marker
            )
        alpha = math.atan2(a[1, 0], a[0, 0])
        if np.linalg.det(a) > 0:
            th0, th1 = self.t0 + alpha, self.t1 + alpha
        else:
            # A reflection maps angle t to alpha - t.
            th0, th1 = alpha - self.t0, alpha - self.t1
        return Arc(a @ self.center + b, scale * self.radius, th0, th1, self.marker)

    def fine_params(self) -> np.ndarray:
        k = max(4, math.ceil(abs(self.sweep) / _ARC_FINE_STEP))
        return np.linspace(self.t0, self.t1, k + 1)


class Polyline(Curve):
    """Chain of straight segments through ``points`` (n, 2); vertex ``i`` at ``t = i``.

    Every vertex is kept in any discretisation (vertices are corners).  ``closed=True``
    adds the segment back to the first point.  ``markers`` (one per segment) override
    ``marker``.
    """

    exact_ends = True

    def __init__(self, points, markers=None, closed: bool = False, marker: int | None = None):
        p = np.array(points, dtype=np.float64)
        if p.ndim != 2 or p.shape[1] != 2:
            raise InputError(f"Polyline points must have shape (n, 2), got {np.shape(points)}")
        bad = np.flatnonzero(~np.isfinite(p).all(axis=1))
        if len(bad):
            raise GeometryError(
                f"Polyline vertex {bad[0]} has non-finite coordinates {fmt_point(p[bad[0]])}"
            )
        if closed:
            if len(p) > 1 and np.array_equal(p[0], p[-1]):
                p = p[:-1]
            p = np.vstack([p, p[:1]])
        if len(p) < 2:
            raise GeometryError(f"Polyline needs at least 2 vertices, got {len(p)}")
        self.points = np.ascontiguousarray(p)
        ne = len(p) - 1
        if markers is not None:
            markers = np.asarray(markers, dtype=np.int32).ravel()
            if markers.shape != (ne,):
                raise InputError(f"Polyline has {ne} segments but {markers.size} markers")
        self.markers = markers
        self.marker = None if marker is None else int(marker)
        self.t0, self.t1 = 0.0, float(ne)
        seg = np.diff(p, axis=0)
        self._seg_len = np.hypot(seg[:, 0], seg[:, 1])
        self._cum = np.concatenate([[0.0], np.cumsum(self._seg_len)])

    def __repr__(self) -> str:
        return f"Polyline(<{len(self.points)} vertices>, marker={self.marker})"

    def _edge(self, t: np.ndarray) -> np.ndarray:
        return np.clip(np.floor(t).astype(np.int64), 0, len(self.points) - 2)

    def evaluate(self, t) -> np.ndarray:
        t = _params(t)
        i = self._edge(t)
        f = (t - i)[:, None]
        return (1.0 - f) * self.points[i] + f * self.points[i + 1]

    @property
    def start(self) -> np.ndarray:
        return self.points[0].copy()

    @property
    def end(self) -> np.ndarray:
        return self.points[-1].copy()

    @property
    def length(self) -> float:
        return float(self._cum[-1])

    def arclength(self, t) -> np.ndarray:
        t = _params(t)
        i = self._edge(t)
        return self._cum[i] + (t - i) * self._seg_len[i]

    def t_at_length(self, s) -> np.ndarray:
        s = _params(s)
        i = np.clip(np.searchsorted(self._cum, s, side="right") - 1, 0, len(self._seg_len) - 1)
        ln = self._seg_len[i]
        safe = np.where(ln > 0, ln, 1.0)
        return i + np.clip(np.where(ln > 0, (s - self._cum[i]) / safe, 0.0), 0.0, 1.0)

    def project(self, xy, t_near=None) -> np.ndarray:
        q = _xy(xy)
        if t_near is None:
            idx, frac = nearest_segment(q, self.points[:-1], self.points[1:])
            return idx + frac
        ne = len(self.points) - 1
        cand = np.clip(self._edge(_params(t_near))[:, None] + np.arange(-2, 3), 0, ne - 1)
        a = self.points[cand]
        d = self.points[cand + 1] - a
        dd = np.einsum("kjc,kjc->kj", d, d)
        f = np.clip(
            np.einsum("kjc,kjc->kj", q[:, None, :] - a, d) / np.where(dd > 0, dd, 1.0), 0, 1
        )
        dist = np.sum((a + f[..., None] * d - q[:, None, :]) ** 2, axis=2)
        j = np.argmin(dist, axis=1)
        rows = np.arange(len(q))
        return cand[rows, j] + f[rows, j]

    def signed_area(self) -> float:
        return _chain_area(self.points)

    def reversed(self) -> Polyline:
        mk = None if self.markers is None else self.markers[::-1]
        return Polyline(self.points[::-1], mk, marker=self.marker)

    def transformed(self, matrix, offset=(0.0, 0.0)) -> Polyline:
        a, b = _affine(matrix, offset)
        return Polyline(self.points @ a.T + b, self.markers, marker=self.marker)

    def with_marker(self, marker: int | None) -> Polyline:
        return Polyline(self.points, None, marker=marker)

    def fine_params(self) -> np.ndarray:
        return np.arange(len(self.points), dtype=np.float64)

    def breaks(self) -> np.ndarray:
        return self.fine_params()

    def piece_index(self, t) -> np.ndarray:
        return self._edge(_params(t))

    def segment_markers(self, ta, tb, default: int) -> np.ndarray:
        if self.markers is None:
            return super().segment_markers(ta, tb, default)
        return self.markers[self._edge(0.5 * (_params(ta) + _params(tb)))].astype(np.int32)


class Parametric(Curve):
    """Curve ``func(t)`` for ``t`` in ``[t0, t1]``, ``t0 < t1``.

    ``func`` maps a (k,) float64 array of parameters to a (k, 2) array of points and must
    be smooth between ``t0`` and ``t1`` (put corners at curve ends).
    """

    def __init__(self, func, t0: float, t1: float, marker: int | None = None):
        self.func = func
        self.t0, self.t1 = float(t0), float(t1)
        if not (np.isfinite(self.t0) and np.isfinite(self.t1) and self.t0 < self.t1):
            raise GeometryError(f"Parametric curve needs finite t0 < t1, got [{t0!r}, {t1!r}]")
        self.marker = None if marker is None else int(marker)
        probe = self.evaluate(np.array([self.t0, 0.5 * (self.t0 + self.t1), self.t1]))
        scale = float(np.ptp(probe)) + float(np.abs(probe).max())
        self.min_segments = 3 if np.allclose(probe[0], probe[2], rtol=0, atol=1e-12 * scale) else 2
        self._tab = None

    def __repr__(self) -> str:
        return f"Parametric({getattr(self.func, '__name__', 'func')}, {self.t0}, {self.t1}, marker={self.marker})"

    def evaluate(self, t) -> np.ndarray:
        t = _params(t)
        p = np.asarray(self.func(t), dtype=np.float64)
        if p.shape != (len(t), 2):
            raise InputError(
                f"Parametric func must map (k,) parameters to (k, 2) points; "
                f"got shape {p.shape} for k = {len(t)}"
            )
        bad = np.flatnonzero(~np.isfinite(p).all(axis=1))
        if len(bad):
            raise GeometryError(
                f"Parametric curve gives non-finite point {fmt_point(p[bad[0]])} at t = {float(t[bad[0]]):.17g}"
            )
        return p

    def _table(self) -> tuple[np.ndarray, np.ndarray]:
        if self._tab is None:
            self._tab = self._build_table()
        return self._tab[0], self._tab[1]

    def _build_table(self):
        t = np.linspace(self.t0, self.t1, 129)
        while True:
            p = self.evaluate(t)
            mid = 0.5 * (t[:-1] + t[1:])
            pm = self.evaluate(mid)
            half = np.hypot(*(pm - p[:-1]).T) + np.hypot(*(p[1:] - pm).T)
            total = half.sum()
            dev = np.hypot(*(pm - 0.5 * (p[:-1] + p[1:])).T)
            need = (dev > _TABLE_TOL * total) | (half > total / 128)
            if not need.any() or 2 * len(t) > _TABLE_MAX:
                break
            t = np.sort(np.concatenate([t, mid[need]]))
        # Chord sums and polygon areas converge as even powers of h: Romberg-extrapolate
        # from the table, its midpoints and its quarter points.
        q = np.linspace(0.0, 1.0, 5)[None, :]
        tq = t[:-1, None] + q * (t[1:] - t[:-1])[:, None]
        pq = self.evaluate(tq.ravel()).reshape(len(t) - 1, 5, 2)
        lens = [
            np.hypot(*np.diff(pq[:, ::k], axis=1).transpose(2, 0, 1)).sum(axis=1) for k in (4, 2, 1)
        ]
        seg = _romberg(*lens)
        s = np.concatenate([[0.0], np.cumsum(seg)])
        chains = [np.vstack([pq[:, :-1:k].reshape(-1, 2), pq[-1:, -1]]) for k in (4, 2, 1)]
        area = float(_romberg(*[_chain_area(c) for c in chains]))
        return t, s, area

    def project(self, xy, t_near=None) -> np.ndarray:
        q = _xy(xy)
        tt, _ = self._table()
        pts = self.evaluate(tt)
        last = len(tt) - 1
        if t_near is None:
            j, f = nearest_segment(q, pts[:-1], pts[1:])
            j = j + (f > 0.5)
        else:
            c = np.searchsorted(tt, _params(t_near))
            win = np.clip(c[:, None] + np.arange(-16, 17), 0, last)
            dist = np.sum((pts[win] - q[:, None, :]) ** 2, axis=2)
            j = win[np.arange(len(q)), np.argmin(dist, axis=1)]
        lo = tt[np.clip(j - 1, 0, last)]
        hi = tt[np.clip(j + 1, 0, last)]
        return self._golden(q, lo, hi)

    def _golden(self, q: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """Vectorised golden-section minimisation of the distance to ``q`` on ``[a, b]``."""

        def dist(t):
            return np.sum((self.evaluate(t) - q) ** 2, axis=1)

        c = b - _GOLDEN * (b - a)
        d = a + _GOLDEN * (b - a)
        fc, fd = dist(c), dist(d)
        for _ in range(40):
            left = fc < fd
            a = np.where(left, a, c)
            b = np.where(left, d, b)
            new = np.where(left, b - _GOLDEN * (b - a), a + _GOLDEN * (b - a))
            fn = dist(new)
            c, d = np.where(left, new, d), np.where(left, c, new)
            fc, fd = np.where(left, fn, fd), np.where(left, fc, fn)
        return 0.5 * (a + b)

    def signed_area(self) -> float:
        self._table()
        return float(self._tab[2])

    def reversed(self) -> Parametric:
        f, t0, t1 = self.func, self.t0, self.t1
        return Parametric(lambda t: f(t0 + t1 - t), t0, t1, self.marker)

    def transformed(self, matrix, offset=(0.0, 0.0)) -> Parametric:
        a, b = _affine(matrix, offset)
        f = self.func
        return Parametric(
            lambda t: np.asarray(f(t), dtype=np.float64) @ a.T + b, self.t0, self.t1, self.marker
        )


class Spline(Parametric):
    """Centripetal Catmull-Rom spline interpolating ``points`` (n, 2), C1 and cusp-free.

    Open splines extend the end segments by reflected ghost points; ``closed=True`` wraps
    around (a repeated last point is dropped) and gives a smooth closed curve.
    """

    def __init__(self, points, closed: bool = False, marker: int | None = None):
        p = np.array(points, dtype=np.float64)
        if p.ndim != 2 or p.shape[1] != 2:
            raise InputError(f"Spline points must have shape (n, 2), got {np.shape(points)}")
        if not np.isfinite(p).all():
            raise GeometryError("Spline control points must be finite")
        if closed and len(p) > 1 and np.array_equal(p[0], p[-1]):
            p = p[:-1]
        if len(p) < (3 if closed else 2):
            raise GeometryError(f"Spline needs at least {3 if closed else 2} points, got {len(p)}")
        step = np.diff(np.vstack([p, p[:1]]) if closed else p, axis=0)
        zero = np.flatnonzero(np.hypot(step[:, 0], step[:, 1]) == 0)
        if len(zero):
            raise GeometryError(
                f"Spline control points {zero[0]} and {zero[0] + 1} coincide at {fmt_point(p[zero[0]])}"
            )
        self.points = p
        self.closed = bool(closed)
        if closed:
            ext = np.vstack([p[-1:], p, p[:2]])
        else:
            ext = np.vstack([2 * p[0] - p[1], p, 2 * p[-1] - p[-2]])
        self._ext = ext
        nseg = len(p) if closed else len(p) - 1
        super().__init__(self._eval, 0.0, float(nseg), marker)

    def __repr__(self) -> str:
        return f"Spline(<{len(self.points)} points>, closed={self.closed}, marker={self.marker})"

    def _eval(self, t: np.ndarray) -> np.ndarray:
        nseg = len(self._ext) - 3
        i = np.clip(np.floor(t).astype(np.int64), 0, nseg - 1)
        f = (t - i)[:, None]
        p0, p1, p2, p3 = (self._ext[i + k] for k in range(4))
        # Barry-Goldman pyramid with knot spacing |P_{k+1} - P_k|^(1/2).
        k1 = np.sqrt(np.hypot(*(p1 - p0).T))[:, None]
        k2 = k1 + np.sqrt(np.hypot(*(p2 - p1).T))[:, None]
        k3 = k2 + np.sqrt(np.hypot(*(p3 - p2).T))[:, None]
        u = k1 + f * (k2 - k1)
        a1 = ((k1 - u) * p0 + u * p1) / k1
        a2 = ((k2 - u) * p1 + (u - k1) * p2) / (k2 - k1)
        a3 = ((k3 - u) * p2 + (u - k2) * p3) / (k3 - k2)
        b1 = ((k2 - u) * a1 + u * a2) / k2
        b2 = ((k3 - u) * a2 + (u - k1) * a3) / (k3 - k1)
        return ((k2 - u) * b1 + (u - k1) * b2) / (k2 - k1)

    def reversed(self) -> Spline:
        # A closed spline must still start at its first point.
        back = np.roll(self.points[::-1], 1, axis=0) if self.closed else self.points[::-1]
        return Spline(back, self.closed, self.marker)
