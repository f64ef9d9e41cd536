"""Ready-made domains: polygons, rectangles, circles, ellipses, NACA sections, far fields.

* NACA 4-digit sections follow I. H. Abbott and A. E. von Doenhoff, *Theory of Wing
  Sections*, Dover, 1959, section 6.4: thickness
  ``y_t = 5 t (0.2969 sqrt(x) - 0.1260 x - 0.3516 x^2 + 0.2843 x^3 - 0.1015 x^4)`` laid
  off normal to the camber line; replacing 0.1015 by 0.1036 closes the trailing edge.
  The section is a single :class:`~meshwright.geometry.curves.Parametric` curve of the
  cosine-spaced parameter ``u`` with ``x = cos^2(u / 2)`` (``u = 0``: trailing edge, upper
  surface for ``u < pi``), which removes the ``sqrt(x)`` singularity at the leading edge, so
  refinement and smoothing stay on the true surface.
* ``circles`` is the "triangulation around circles" case and ``naca0012`` the "triangulation
  around airfoil" case of figure 18.1.7 of the reference text; ``three_element_airfoil``
  (slat, main element and flap) is the configuration of figure 18.3.1 (Müller, Roe and
  Deconinck, 1993), here built from NACA sections.

Angles: curve parameters are radians; ``aoa`` (angle of attack) is in degrees, positive
nose up, i.e. a clockwise rotation about the leading edge.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np

from meshwright.core.errors import GeometryError, InputError
from meshwright.geometry.curves import Arc, Curve, Line, Parametric, Polyline
from meshwright.geometry.domain import Domain
from meshwright.sizing.boundary import gradation
from meshwright.sizing.field import as_size_field

__all__ = [
    "WALL",
    "FARFIELD",
    "polygon",
    "rectangle",
    "circle",
    "ellipse",
    "ellipse_loop",
    "annulus",
    "circles",
    "naca_loop",
    "naca",
    "three_element_loops",
    "three_element_airfoil",
    "airfoil_in_farfield",
    "from_shapely",
    "BUILTIN_DOMAINS",
    "builtin",
]

WALL = 1  # boundary marker of solid walls (airfoil surfaces)
FARFIELD = 2  # boundary marker of far-field boundaries

_THICKNESS = (0.2969, 0.1260, 0.3516, 0.2843)
_LAST_OPEN, _LAST_CLOSED = 0.1015, 0.1036


def _loop_markers(markers, nloops: int) -> list:
    if markers is None or np.isscalar(markers):
        return [markers] * nloops
    if len(markers) != nloops:
        raise InputError(f"markers needs one entry per loop ({nloops}), got {len(markers)}")
    return list(markers)


def polygon(outer, holes=(), segments=(), markers=None, points=None, regions=()) -> Domain:
    """Domain bounded by polygons.

    Parameters
    ----------
    outer : (n, 2) array_like
        Vertices of the outer polygon (any orientation; a repeated first vertex is dropped).
    holes : sequence of (n_i, 2) array_like
        Hole polygons.
    segments : sequence of (k, 2) array_like
        Interior constraint polylines.
    markers : int, or sequence with one entry per loop (outer first)
        Each entry an int or one marker per polygon edge (edge i joins vertex i to i + 1).
    points, regions
        As for :class:`Domain`.
    """
    loops = [outer, *holes]
    mk = _loop_markers(markers, len(loops))
    curves = []
    for i, (lp, m) in enumerate(zip(loops, mk)):
        p = np.asarray(lp, dtype=np.float64)
        if p.ndim != 2 or p.shape[1] != 2:
            raise InputError(f"loop {i} must be an (n, 2) vertex array, got shape {p.shape}")
        if len(p) > 1 and np.array_equal(p[0], p[-1]):
            p = p[:-1]
        if len(p) < 3:
            raise GeometryError(f"loop {i} has {len(p)} vertices; a polygon needs at least 3")
        scalar = m is None or np.isscalar(m)
        curves.append(Polyline(p, None if scalar else m, closed=True, marker=m if scalar else None))
    return Domain(curves[0], curves[1:], segments=segments, points=points, regions=regions)


def rectangle(x0: float, y0: float, x1: float, y1: float, markers=None) -> Domain:
    """Axis-aligned rectangle ``[x0, x1] x [y0, y1]``; ``markers`` (bottom, right, top, left)."""
    if not (x1 > x0 and y1 > y0):
        raise GeometryError(f"rectangle needs x0 < x1 and y0 < y1, got ({x0}, {y0}, {x1}, {y1})")
    return Domain(_box_loop(x0, y0, x1, y1, markers))


def _box_loop(x0, y0, x1, y1, markers=None) -> list[Curve]:
    c = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
    mk = _loop_markers(markers, 4)
    return [Line(c[i], c[(i + 1) % 4], mk[i]) for i in range(4)]


def circle(center=(0.0, 0.0), radius: float = 1.0, marker: int | None = None) -> Domain:
    """Disc bounded by one full-circle :class:`Arc`."""
    return Domain(Arc(center, radius, 0.0, 2.0 * math.pi, marker))


def ellipse_loop(
    center=(0.0, 0.0), a: float = 2.0, b: float = 1.0, rotation: float = 0.0, marker=None
) -> list[Curve]:
    """Loop of one :class:`Parametric` ellipse, the ``a`` axis turned by ``rotation`` radians."""
    if not (a > 0 and b > 0):
        raise GeometryError(f"ellipse semi-axes must be positive, got {a!r}, {b!r}")
    cx, cy = float(center[0]), float(center[1])
    cr, sr = math.cos(rotation), math.sin(rotation)

    def ellipse_xy(t):
        x, y = a * np.cos(t), b * np.sin(t)
        return np.column_stack([cx + cr * x - sr * y, cy + sr * x + cr * y])

    return [Parametric(ellipse_xy, 0.0, 2.0 * math.pi, marker)]


def ellipse(
    center=(0.0, 0.0), a: float = 2.0, b: float = 1.0, rotation: float = 0.0, marker=None
) -> Domain:
    """Ellipse with semi-axes ``a`` and ``b``, the ``a`` axis turned by ``rotation`` radians."""
    return Domain(ellipse_loop(center, a, b, rotation, marker))


def annulus(center=(0.0, 0.0), r_inner: float = 0.5, r_outer: float = 1.0) -> Domain:
    """Ring between two concentric circles (inner marker 2, outer marker 1)."""
    if not (0 < r_inner < r_outer):
        raise GeometryError(f"annulus needs 0 < r_inner < r_outer, got {r_inner}, {r_outer}")
    return Domain(
        Arc(center, r_outer, 0.0, 2.0 * math.pi, 1), [Arc(center, r_inner, 0.0, 2.0 * math.pi, 2)]
    )


def circles(
    centers=((1.0, 1.5), (2.4, 2.0), (2.9, 0.9)),
    radii=(0.5, 0.35, 0.3),
    box=(0.0, 0.0, 4.0, 3.0),
) -> Domain:
    """Circular holes in a rectangle (figure 18.1.7a); box marker 1, circle ``k`` marker ``k + 2``."""
    c = np.asarray(centers, dtype=np.float64).reshape(-1, 2)
    r = np.broadcast_to(np.asarray(radii, dtype=np.float64), (len(c),))
    holes = [Arc(ci, ri, 0.0, 2.0 * math.pi, k + 2) for k, (ci, ri) in enumerate(zip(c, r))]
    return Domain(_box_loop(*box, markers=1), holes)


def _naca_code(code) -> tuple[float, float, float]:
    digits = str(code).upper().replace("NACA", "").strip()
    if len(digits) != 4 or not digits.isdigit():
        raise InputError(f"NACA code must have 4 digits (e.g. '2412'), got {code!r}")
    m, p, t = int(digits[0]) / 100.0, int(digits[1]) / 10.0, int(digits[2:]) / 100.0
    if t == 0.0:
        raise GeometryError(f"NACA {digits} has zero thickness")
    if (m == 0.0) != (p == 0.0):
        raise GeometryError(
            f"NACA {digits}: camber and its position must both be zero or both non-zero"
        )
    return m, p, t


def _naca_func(m: float, p: float, t: float, closed_te: bool) -> Callable:
    a0, a1, a2, a3 = _THICKNESS
    a4 = _LAST_CLOSED if closed_te else _LAST_OPEN

    def naca_xy(u):
        c = np.cos(0.5 * u)  # > 0 on the upper surface, < 0 on the lower
        x = c * c
        ac = np.abs(c)
        ys = 5.0 * t * (a0 * c - ac * c * (a1 + x * (a2 - x * (a3 - x * a4))))
        if m == 0.0:
            return np.column_stack([x, ys])
        fore = x < p
        yc = np.where(
            fore,
            m / p**2 * (2 * p * x - x * x),
            m / (1 - p) ** 2 * ((1 - 2 * p) + 2 * p * x - x * x),
        )
        slope = np.where(fore, 2 * m / p**2 * (p - x), 2 * m / (1 - p) ** 2 * (p - x))
        th = np.arctan(slope)
        return np.column_stack([x - ys * np.sin(th), yc + ys * np.cos(th)])

    return naca_xy


def naca_loop(
    code="0012",
    chord: float = 1.0,
    aoa: float = 0.0,
    origin=(0.0, 0.0),
    closed_te: bool = True,
    n: int | None = None,
    marker: int | None = WALL,
) -> list[Curve]:
    """Loop of a NACA 4-digit section, leading edge at ``origin``.

    Parameters
    ----------
    code : str or int
        Four digits ``MPTT``: camber ``M``% at ``P``/10 of the chord, thickness ``TT``%.
    chord : float
    aoa : float
        Angle of attack in degrees, positive nose up (clockwise about the leading edge).
    origin : (2,) float
        Leading-edge position.
    closed_te : bool
        Sharp trailing edge (coefficient -0.1036) or the original blunt one (-0.1015,
        closed by a straight :class:`Line`).
    n : int, optional
        When given, a :class:`Polyline` through ``n`` cosine-spaced points per surface
        instead of the exact parametric curve (classic coordinate tables).
    marker : int
        Boundary marker (default :data:`WALL`).

    Returns
    -------
    list of Curve
        Counter-clockwise, starting at the trailing edge along the upper surface.
    """
    m, p, t = _naca_code(code)
    if not (np.isfinite(chord) and chord > 0):
        raise GeometryError(f"chord must be positive, got {chord!r}")
    f = _naca_func(m, p, t, closed_te)
    a = math.radians(aoa)
    rot = chord * np.array([[math.cos(a), math.sin(a)], [-math.sin(a), math.cos(a)]])
    off = np.asarray(origin, dtype=np.float64)
    if n is not None:
        if int(n) < 3:
            raise InputError(f"n must be at least 3 points per surface, got {n!r}")
        u = np.linspace(0.0, 2.0 * math.pi, 2 * int(n) - 1)
        pts = f(u[:-1] if closed_te else u) @ rot.T + off
        return [Polyline(pts, closed=True, marker=marker)]
    surf = Parametric(lambda u: f(u) @ rot.T + off, 0.0, 2.0 * math.pi, marker)
    if closed_te:
        return [surf]
    return [surf, Line(surf.end, surf.start, marker)]


def naca(
    code="0012", chord: float = 1.0, aoa: float = 0.0, closed_te: bool = True, n: int | None = None
) -> Domain:
    """The inside of a NACA 4-digit section (see :func:`naca_loop`)."""
    return Domain(naca_loop(code, chord, aoa, closed_te=closed_te, n=n))


# Slat, main element and flap: (code, chord, aoa in degrees, leading-edge position).
_THREE_ELEMENT = (
    ("4412", 0.16, -25.0, (-0.152, -0.035)),
    ("2412", 1.00, 0.0, (0.0, 0.0)),
    ("4412", 0.30, 30.0, (0.965, -0.06)),
)


def three_element_loops(closed_te: bool = True) -> list[list[Curve]]:
    """Slat, main element and flap loops (figure 18.3.1), disjoint, marker :data:`WALL`."""
    return [naca_loop(c, ch, a, o, closed_te) for c, ch, a, o in _THREE_ELEMENT]


def airfoil_in_farfield(
    airfoil="0012",
    radius: float = 10.0,
    shape: str = "circle",
    center=None,
    size=None,
) -> Domain:
    """Airfoil element(s) as holes in a far field (marker :data:`FARFIELD`).

    Parameters
    ----------
    airfoil : str, Domain or sequence of loops
        A NACA code, a Domain whose outer loop is the section, or loops (each a Curve or a
        sequence of Curves) for multi-element configurations.
    radius : float
        Far-field radius (half-width for ``shape="rectangle"``) in the airfoil's units.
    shape : {"circle", "rectangle"}
    center : (2,) float, optional
        Far-field centre; defaults to the middle of the airfoil's bounding box.
    size : optional
        Suggested size stored on the domain.
    """
    if isinstance(airfoil, Domain):
        if len(airfoil.loops) != 1:
            raise GeometryError("airfoil_in_farfield needs a Domain without holes")
        loops = [list(airfoil.loops[0])]
    elif isinstance(airfoil, (str, int)):
        loops = [naca_loop(airfoil)]
    elif isinstance(airfoil, Sequence):
        loops = [[lp] if isinstance(lp, Curve) else list(lp) for lp in airfoil]
    else:
        raise InputError(
            f"airfoil must be a NACA code, a Domain or loops, got {type(airfoil).__name__}"
        )
    pts = np.concatenate([c.evaluate(c.fine_params()) for lp in loops for c in lp])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    c = 0.5 * (lo + hi) if center is None else np.asarray(center, dtype=np.float64)
    if not (np.isfinite(radius) and radius > 0):
        raise GeometryError(f"far-field radius must be positive, got {radius!r}")
    if shape == "circle":
        outer = [Arc(c, radius, 0.0, 2.0 * math.pi, FARFIELD)]
    elif shape == "rectangle":
        outer = _box_loop(c[0] - radius, c[1] - radius, c[0] + radius, c[1] + radius, FARFIELD)
    else:
        raise InputError(f"shape must be 'circle' or 'rectangle', got {shape!r}")
    return Domain(outer, loops, size=size)


def _airfoil_size(loops, h_wall: float, growth: float, hmax: float):
    pts = np.concatenate([c.evaluate(c.fine_params()) for lp in loops for c in lp])
    return gradation(pts, h_wall, growth, hmax)


def three_element_airfoil(
    radius: float = 10.0, shape: str = "circle", closed_te: bool = True
) -> Domain:
    """Slat, main element and flap in a far field (figure 18.3.1), with a graded size."""
    loops = three_element_loops(closed_te)
    return airfoil_in_farfield(
        loops, radius, shape, size=_airfoil_size(loops, 0.01, 1.25, radius / 4)
    )


def from_shapely(geom) -> Domain:
    """Domain from a shapely ``Polygon`` (or a ``MultiPolygon`` with one part).

    Raises
    ------
    ImportError
        If shapely is not installed (it is an optional dependency).
    """
    try:
        from shapely.geometry import MultiPolygon, Polygon
    except ImportError as exc:
        raise ImportError(
            "from_shapely needs the optional dependency shapely: pip install shapely"
        ) from exc
    if isinstance(geom, MultiPolygon):
        if len(geom.geoms) != 1:
            raise GeometryError(
                f"a Domain has one outer loop; the MultiPolygon has {len(geom.geoms)} parts"
            )
        geom = geom.geoms[0]
    if not isinstance(geom, Polygon):
        raise InputError(f"from_shapely needs a Polygon, got {type(geom).__name__}")
    if geom.is_empty:
        raise GeometryError("the shapely Polygon is empty")
    return polygon(
        np.asarray(geom.exterior.coords)[:, :2],
        [np.asarray(r.coords)[:, :2] for r in geom.interiors],
    )


def _naca0012() -> Domain:
    loops = [naca_loop("0012")]
    return airfoil_in_farfield(loops, 10.0, size=_airfoil_size(loops, 0.01, 1.25, 2.5))


def _with_size(d: Domain, size: float) -> Domain:
    d.size = as_size_field(size)
    return d


# Name -> zero-argument factory; the CLI takes its choices from the keys.
BUILTIN_DOMAINS: dict[str, Callable[[], Domain]] = {
    "rectangle": lambda: _with_size(rectangle(0.0, 0.0, 2.0, 1.0), 0.1),
    "l-shape": lambda: _with_size(
        polygon([(-1, -1), (0, -1), (0, 0), (1, 0), (1, 1), (-1, 1)]), 0.1
    ),
    "circle": lambda: _with_size(circle(), 0.1),
    "ellipse": lambda: _with_size(ellipse(), 0.15),
    "annulus": lambda: _with_size(annulus(), 0.08),
    "circles": lambda: _with_size(circles(), 0.15),
    "naca0012": _naca0012,
    "three-element": three_element_airfoil,
}


def builtin(name: str) -> Domain:
    """Build the registered domain ``name`` (see :data:`BUILTIN_DOMAINS`); it carries a size."""
    try:
        factory = BUILTIN_DOMAINS[name]
    except KeyError:
        raise InputError(
            f"unknown domain {name!r}; choose from {sorted(BUILTIN_DOMAINS)}"
        ) from None
    return factory()
