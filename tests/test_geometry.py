"""Tests of meshwright.geometry: curves, Domain validation and discretisation, shapes, files."""

from __future__ import annotations

import json
import math
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from meshwright.core.errors import FormatError, GeometryError, InputError
from meshwright.geometry import (
    BUILTIN_DOMAINS,
    Arc,
    Domain,
    Line,
    Parametric,
    Polyline,
    Spline,
    airfoil_in_farfield,
    annulus,
    builtin,
    circle,
    circles,
    domain_from_dict,
    domain_to_dict,
    ellipse,
    from_shapely,
    load_domain,
    naca,
    naca_loop,
    polygon,
    read_poly,
    rectangle,
    save_domain,
    three_element_loops,
    write_poly,
)
from meshwright.geometry._kernels import find_bad_pairs, nearest_segment

TWO_PI = 2 * math.pi


def shoelace(p):
    x, y = np.asarray(p, dtype=float).T
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def loop_area(loop):
    return sum(c.signed_area() for c in loop)


def seg_lengths(disc):
    d = disc.points[disc.segments[:, 1]] - disc.points[disc.segments[:, 0]]
    return np.hypot(d[:, 0], d[:, 1])


def assert_valid_pslg(disc):
    assert len(find_bad_pairs(disc.points, disc.segments.astype(np.int64), 1)) == 0
    assert len(np.unique(disc.points, axis=0)) == len(disc.points)


def min_distance(a, b):
    idx, f = nearest_segment(a, b[:-1], b[1:])
    q = b[:-1][idx] * (1 - f[:, None]) + b[1:][idx] * f[:, None]
    return np.hypot(*(a - q).T).min()


def star(n, rng_angles, rng_radii):
    ang = (np.arange(n) + 0.8 * np.asarray(rng_angles)) * TWO_PI / n
    r = np.asarray(rng_radii)
    return np.column_stack([r * np.cos(ang), r * np.sin(ang)])


# ---------------------------------------------------------------------------------------
# curves
# ---------------------------------------------------------------------------------------
class TestCurves:
    def test_line(self):
        c = Line((0, 0), (3, 4), marker=5)
        assert c.length == 5.0
        np.testing.assert_array_equal(c.evaluate([0, 1]), [[0, 0], [3, 4]])
        np.testing.assert_allclose(c.t_at_length([2.5]), [0.5])
        np.testing.assert_allclose(c.project([[3, 0], [10, 10]]), [9 / 25, 1.0])
        assert c.reversed().start.tolist() == [3, 4]
        assert c.segment_markers([0.0], [1.0], 1).tolist() == [5]

    def test_arc_closed_forms(self):
        c = Arc((1, 2), 2.0, 0.0, -math.pi)  # clockwise half circle
        assert c.length == pytest.approx(2 * math.pi)
        np.testing.assert_allclose(c.end, [-1, 2], atol=1e-15)
        t = c.t_at_length([math.pi])
        np.testing.assert_allclose(c.evaluate(t), [[1, 0]], atol=1e-15)
        np.testing.assert_allclose(c.project([[1, -5]]), [-math.pi / 2])
        # A point outside the sweep projects to the nearer end.
        np.testing.assert_allclose(c.project([[4, 2.1]]), [0.0])
        np.testing.assert_allclose(c.midpoint_param([0.0], [-math.pi]), [-math.pi / 2])
        assert c.min_segments == 2

    def test_arc_signed_area_full_circle(self):
        c = Arc((3, -1), 0.5, 0.0, TWO_PI)
        assert c.signed_area() == pytest.approx(math.pi * 0.25, rel=1e-14)
        assert c.reversed().signed_area() == pytest.approx(-math.pi * 0.25, rel=1e-14)

    def test_arc_projection_hint_at_seam(self):
        c = Arc((0, 0), 1.0, 0.0, TWO_PI)
        q = np.array([[1.0, -1e-3]])
        assert c.project(q, t_near=[6.2])[0] == pytest.approx(TWO_PI - 1e-3, abs=1e-9)
        assert c.project(q, t_near=[0.1])[0] == 0.0

    def test_arc_transform(self):
        c = Arc((0, 0), 1.0, 0.0, math.pi / 2)
        rot = np.array([[0.0, -2.0], [2.0, 0.0]])  # rotate 90 degrees, scale 2
        r = c.transformed(rot, (1, 1))
        assert isinstance(r, Arc) and r.radius == pytest.approx(2.0)
        np.testing.assert_allclose(
            r.evaluate([r.t0, r.t1]), c.evaluate([0, math.pi / 2]) @ rot.T + 1, atol=1e-14
        )
        mirror = c.transformed(np.diag([1.0, -1.0]))
        np.testing.assert_allclose(mirror.end, [0, -1], atol=1e-15)
        squash = c.transformed(np.diag([2.0, 1.0]))
        assert isinstance(squash, Parametric)
        np.testing.assert_allclose(squash.end, [0, 1], atol=1e-15)

    def test_polyline(self):
        c = Polyline([(0, 0), (1, 0), (1, 2)], markers=[3, 4])
        assert c.length == 3.0
        np.testing.assert_allclose(c.evaluate([0.5, 1.5]), [[0.5, 0], [1, 1]])
        np.testing.assert_allclose(c.t_at_length([0.5, 2.0]), [0.5, 1.5])
        np.testing.assert_allclose(c.project([[2, 1], [0.3, -1]]), [1.5, 0.3])
        np.testing.assert_allclose(c.project([[2, 1]], t_near=[1.9]), [1.5])
        assert c.segment_markers([0.0, 1.0], [0.5, 2.0], 1).tolist() == [3, 4]
        r = c.reversed()
        assert r.markers.tolist() == [4, 3] and r.start.tolist() == [1, 2]

    def test_parametric_circle_tables(self):
        c = Parametric(lambda t: np.column_stack([2 * np.cos(t), 2 * np.sin(t)]), 0.0, TWO_PI)
        assert c.min_segments == 3
        assert c.length == pytest.approx(4 * math.pi, rel=1e-9)
        assert c.signed_area() == pytest.approx(4 * math.pi, rel=1e-9)
        t = np.array([0.3, 2.0, 5.0])
        np.testing.assert_allclose(c.t_at_length(c.arclength(t)), t, atol=1e-6)
        np.testing.assert_allclose(c.project(c.evaluate(t) * 1.1), t, atol=1e-8)
        assert c.reversed().signed_area() == pytest.approx(-4 * math.pi, rel=1e-9)

    def test_parametric_rejects_bad_func(self):
        with pytest.raises(InputError, match="shape"):
            Parametric(lambda t: t, 0.0, 1.0)
        with pytest.raises(GeometryError, match="t0 < t1"):
            Parametric(lambda t: np.column_stack([t, t]), 1.0, 0.0)

    def test_spline_interpolates(self):
        p = np.array([(0, 0), (1, 1), (2, 0), (3, 1)], dtype=float)
        s = Spline(p)
        np.testing.assert_allclose(s.evaluate(np.arange(4.0)), p, atol=1e-12)
        closed = Spline(p, closed=True)
        np.testing.assert_allclose(closed.evaluate([4.0]), p[:1], atol=1e-12)
        back = closed.reversed()
        np.testing.assert_allclose(back.evaluate([0.0, 1.0]), p[[0, 3]], atol=1e-12)
        assert back.signed_area() == pytest.approx(-closed.signed_area(), rel=1e-9)
        with pytest.raises(GeometryError, match="coincide"):
            Spline([(0, 0), (0, 0), (1, 1)])

    def test_bad_curves(self):
        with pytest.raises(GeometryError, match="zero length"):
            Line((1, 1), (1, 1))
        with pytest.raises(GeometryError, match="radius"):
            Arc((0, 0), -1.0, 0, 1)
        with pytest.raises(GeometryError, match="sweep"):
            Arc((0, 0), 1.0, 0, 7)
        with pytest.raises(GeometryError, match="non-finite"):
            Line((0, np.nan), (1, 1))


# ---------------------------------------------------------------------------------------
# shapes
# ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", sorted(BUILTIN_DOMAINS))
def test_builtin_domains_valid_and_oriented(name):
    d = builtin(name)
    assert d.size is not None
    assert loop_area(d.loops[0]) > 0
    for lp, depth in zip(d.loops[1:], d.loop_depth[1:]):
        assert (loop_area(lp) < 0) == (depth % 2 == 1)
    disc = d.discretize()
    assert_valid_pslg(disc)
    assert len(disc.holes) == int(np.sum(d.loop_depth % 2 == 1))
    assert d.contains(disc.holes).sum() == 0


def test_builtin_unknown_name():
    with pytest.raises(InputError, match="circle"):
        builtin("nope")


def test_areas():
    assert circle((1, 1), 2.0).area() == pytest.approx(4 * math.pi, rel=1e-14)
    assert rectangle(0, 0, 2, 3).area() == 6.0
    assert annulus((0, 0), 0.5, 1.0).area() == pytest.approx(0.75 * math.pi, rel=1e-14)
    assert ellipse((0, 0), 3.0, 1.0, rotation=0.4).area() == pytest.approx(3 * math.pi, rel=1e-9)
    c = circles()
    assert c.area() == pytest.approx(12 - math.pi * (0.25 + 0.35**2 + 0.09), rel=1e-14)


def test_naca0012_thickness_and_area():
    d = naca("0012")
    surf = d.curves[0]
    u = np.linspace(0.0, math.pi, 20001)
    upper = surf.evaluate(u)
    i = np.argmax(upper[:, 1])
    assert 2 * upper[i, 1] == pytest.approx(0.12, abs=2e-5)
    assert upper[i, 0] == pytest.approx(0.30, abs=0.01)
    # Closed form: 10 t (2/3 a0 - a1/2 - a2/3 + a3/4 - a4/5) with a4 = 0.1036.
    exact = 1.2 * (2 / 3 * 0.2969 - 0.1260 / 2 - 0.3516 / 3 + 0.2843 / 4 - 0.1036 / 5)
    assert d.area() == pytest.approx(exact, rel=1e-8)
    np.testing.assert_allclose(surf.start, [1, 0], atol=1e-15)


def test_naca_variants():
    blunt = naca("2412", closed_te=False)
    assert isinstance(blunt.loops[0][1], Line)
    te = blunt.loops[0][1]
    assert te.length == pytest.approx(2 * 5 * 0.12 * 0.0021, rel=0.05)
    table = naca("2412", n=60)
    assert isinstance(table.curves[0], Polyline) and len(table.curves[0].points) == 119
    assert table.area() == pytest.approx(naca("2412").area(), rel=1e-3)
    tilted = naca_loop("0012", chord=2.0, aoa=10.0)[0]
    te = tilted.evaluate([0.0])[0]
    np.testing.assert_allclose(
        te, 2 * np.array([math.cos(0.1745329), -math.sin(0.1745329)]), atol=1e-6
    )
    with pytest.raises(InputError, match="4 digits"):
        naca("12")
    with pytest.raises(GeometryError, match="zero thickness"):
        naca("0000")


def test_naca_discretisation_on_true_surface():
    d = naca("4412")
    disc = d.discretize(0.02)
    surf = d.curves[0]
    np.testing.assert_allclose(
        surf.evaluate(disc.segment_params[:, 0]), disc.points[disc.segments[:, 0]], atol=1e-15
    )
    t, xy = d.project(
        disc.segment_curve, disc.points[disc.segments[:, 0]] + 1e-4, disc.segment_params[:, 0]
    )
    assert np.abs(t - disc.segment_params[:, 0]).max() < 0.01


def test_projection_hint_keeps_surface_at_trailing_edge():
    surf = naca_loop("0012")[0]
    t_lower = 2 * math.pi - 0.05  # lower surface just before the trailing edge
    p = surf.evaluate([t_lower]) + [0.0, 0.0004]  # nudged towards the upper surface
    assert surf.project(p, t_near=[t_lower])[0] > math.pi


def test_three_element_pieces_disjoint():
    loops = three_element_loops()
    pts = [np.concatenate([c.evaluate(c.fine_params()) for c in lp]) for lp in loops]
    for i in range(3):
        for j in range(i + 1, 3):
            assert min_distance(pts[i], pts[j]) > 0.01
    d = airfoil_in_farfield(loops, 5.0, shape="rectangle")
    assert len(d.loops) == 4 and (d.loop_depth[1:] == 1).all()
    assert d.area() == pytest.approx(100 - sum(abs(loop_area(lp)) for lp in loops), rel=1e-12)


def test_polygon_markers_and_constraints():
    d = polygon(
        [(0, 0), (2, 0), (2, 2), (0, 2)],
        holes=[[(0.5, 0.5), (0.5, 1.0), (1.0, 1.0), (1.0, 0.5)]],
        segments=[[(1.5, 0.2), (1.5, 1.8)]],
        markers=[[1, 2, 3, 4], 7],
        points=[(1.8, 1.8)],
        regions=[(0.2, 0.2, 9, 0.01)],
    )
    disc = d.discretize()
    assert len(disc.points) == 4 + 4 + 2 + 1
    assert sorted(disc.segment_markers.tolist()) == [0, 1, 2, 3, 4, 7, 7, 7, 7]
    assert disc.regions.tolist() == [[0.2, 0.2, 9.0, 0.01]]
    assert disc.point_markers[-1] == 0
    np.testing.assert_array_equal(disc.points[:4], [(0, 0), (2, 0), (2, 2), (0, 2)])


def test_from_shapely_missing(monkeypatch):
    monkeypatch.setitem(sys.modules, "shapely", None)
    monkeypatch.setitem(sys.modules, "shapely.geometry", None)
    with pytest.raises(ImportError, match="pip install shapely"):
        from_shapely(object())


def test_from_shapely():
    geometry = pytest.importorskip("shapely.geometry")
    poly = geometry.Polygon([(0, 0), (3, 0), (3, 3), (0, 3)], [[(1, 1), (2, 1), (2, 2), (1, 2)]])
    d = from_shapely(poly)
    assert d.area() == pytest.approx(8.0)
    assert len(d.holes) == 1


# ---------------------------------------------------------------------------------------
# discretisation
# ---------------------------------------------------------------------------------------
def test_discretize_constant_size_on_circle():
    d = circle((0.5, -1), 1.0)
    disc = d.discretize(0.05)
    ln = seg_lengths(disc)
    assert ln.min() > 0.05 / 1.3 and ln.max() < 0.05 * 1.3
    r = np.hypot(disc.points[:, 0] - 0.5, disc.points[:, 1] + 1)
    np.testing.assert_allclose(r, 1.0, atol=1e-14)
    assert len(disc.segments) == round(TWO_PI / 0.05)
    assert_valid_pslg(disc)


def test_discretize_graded_size():
    d = rectangle(0, 0, 4, 1)

    def h(xy):
        return 0.02 + 0.1 * xy[:, 0]

    disc = d.discretize(h)
    mid = 0.5 * (disc.points[disc.segments[:, 0]] + disc.points[disc.segments[:, 1]])
    ratio = seg_lengths(disc) / h(mid)
    assert ratio.min() > 0.75 and ratio.max() < 1.33
    # Corners are vertices, shared by the neighbouring sides.
    for corner in [(0, 0), (4, 0), (4, 1), (0, 1)]:
        assert (disc.points == corner).all(axis=1).sum() == 1


def test_discretize_split_stays_on_curve():
    d = ellipse((0, 0), 2.0, 1.0)
    disc = d.discretize(0.2)
    t, xy = d.split(disc.segment_curve, disc.segment_params[:, 0], disc.segment_params[:, 1])
    np.testing.assert_allclose((xy[:, 0] / 2) ** 2 + xy[:, 1] ** 2, 1.0, atol=1e-12)
    lo = np.minimum(disc.segment_params[:, 0], disc.segment_params[:, 1])
    hi = np.maximum(disc.segment_params[:, 0], disc.segment_params[:, 1])
    assert ((t > lo) & (t < hi)).all()


def test_discretize_refines_coarse_conflicts():
    # A small hole close to the circle is cut off by the 4-segment coarse polygon.
    d = Domain(
        Arc((0, 0), 1.0, 0.0, TWO_PI), [[(0.97, -0.01), (0.99, -0.01), (0.99, 0.01), (0.97, 0.01)]]
    )
    disc = d.discretize()
    assert_valid_pslg(disc)
    assert len(disc.segments) > 8
    hole = disc.holes[0]
    assert 0.97 < hole[0] < 0.99


def test_discretize_without_size_keeps_polygon():
    p = [(0, 0), (1, 0), (1, 1), (0.5, 1.5), (0, 1)]
    disc = polygon(p).discretize()
    np.testing.assert_array_equal(disc.points, p)
    assert disc.segments.dtype == np.int32 and disc.segment_markers.tolist() == [1] * 5


def test_discretize_orientation_normalised():
    cw = [(0, 0), (0, 1), (1, 1), (1, 0)]
    d = polygon(cw, holes=[[(0.4, 0.4), (0.6, 0.4), (0.6, 0.6), (0.4, 0.6)]])
    disc = d.discretize()
    outer = disc.points[:4]
    hole = disc.points[4:8]
    assert shoelace(outer) > 0 and shoelace(hole) < 0


def test_contains():
    d = annulus((0, 0), 0.5, 1.0)
    q = np.array([[0, 0], [0.75, 0], [1.5, 0], [0, -0.9], [1.0, 0.0]])
    assert d.contains(q).tolist() == [False, True, False, True, False]
    assert d.contains(q, boundary=True).tolist() == [False, True, False, True, True]


# ---------------------------------------------------------------------------------------
# validation
# ---------------------------------------------------------------------------------------
SQUARE = [(0, 0), (4, 0), (4, 4), (0, 4)]


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (
            {"outer": [(0, 0), (2, 2), (2, 0), (0, 2)]},
            r"outer loop \(loop 0\) curve 0 segment \d .* intersects",
        ),
        ({"outer": SQUARE, "holes": [[(0, 0), (1, 1), (1, 0.5)]]}, "touch at"),
        (
            {"outer": SQUARE, "holes": [[(3, 1), (5, 1), (5, 2), (3, 2)]]},
            r"hole 0 \(loop 1\).*intersects|intersects.*hole 0",
        ),
        ({"outer": SQUARE, "holes": [[(5, 5), (6, 5), (6, 6)]]}, "hole 0 .*outside the outer loop"),
        (
            {
                "outer": SQUARE,
                "holes": [[(1, 1), (3, 1), (3, 3), (1, 3)], [(1.5, 1.5), (2, 1.5), (2, 2)]],
            },
            "island",
        ),
        (
            {"outer": [(0, 0), (1, 0), (1, 0), (1, 1)]},
            r"segment 1 \(1, 0\)-\(1, 0\) has zero length",
        ),
        (
            {"outer": [(0, 0), (2, 0), (1, 1), (2, 2), (0, 2), (1, 1)]},
            r"passes twice through \(1, 1\)",
        ),
        ({"outer": [(0, 0), (1, np.nan), (1, 1)]}, "non-finite"),
        ({"outer": SQUARE, "points": [(5, 5)]}, r"interior point 0 at \(5, 5\)"),
        ({"outer": SQUARE, "points": [(4, 2)]}, "on a boundary"),
        ({"outer": SQUARE, "points": [(1, 1), (1, 1)]}, "interior points 0 and 1 coincide"),
        ({"outer": SQUARE, "regions": [(-1, 1, 2, None)]}, "region 0 seed"),
        ({"outer": SQUARE, "regions": [(1, 1, 2, -3.0)]}, "max_area"),
        ({"outer": SQUARE, "segments": [[(5, 5), (6, 6)]]}, "constraint 0 lies outside"),
        (
            {"outer": SQUARE, "segments": [[(1, 1), (5, 1)]]},
            "constraint 0 .*intersects|intersects.*constraint 0",
        ),
    ],
)
def test_validation_errors(kwargs, match):
    kw = dict(kwargs)
    outer = kw.pop("outer")
    holes = kw.pop("holes", ())
    with pytest.raises(GeometryError, match=match):
        Domain(outer, holes, **kw)


def test_fewer_than_three_vertices():
    with pytest.raises(GeometryError, match="at least 3"):
        polygon([(0, 0), (1, 0)])
    with pytest.raises(GeometryError, match="outer loop .* has 2 vertices"):
        Domain([Line((0, 0), (1, 0)), Line((1, 0), (0, 0))])


def test_open_and_broken_loops():
    with pytest.raises(
        GeometryError, match=r"outer loop \(loop 0\) is open: curve 2 ends at \(0, 0.5\)"
    ):
        Domain([Line((0, 0), (1, 0)), Line((1, 0), (1, 1)), Line((1, 1), (0, 0.5))])
    with pytest.raises(GeometryError, match="is broken: curve 0 ends at"):
        Domain([Line((0, 0), (1, 0)), Line((1, 0.1), (1, 1)), Line((1, 1), (0, 0))])


def test_parametric_nan_names_loop_and_curve():
    bad = Parametric(
        lambda t: np.column_stack([np.cos(t), np.where((t > 2.5) & (t < 2.9), np.nan, np.sin(t))]),
        0.0,
        3.0,
    )
    with pytest.raises(GeometryError, match=r"hole 0 \(loop 1\) curve 0: .*non-finite"):
        Domain(SQUARE, [[bad.transformed(np.eye(2) * 0.5, (2, 2)), Line((1, 2), (2.5, 2))]])


def test_island_with_region_is_meshed():
    d = Domain(
        SQUARE,
        [[(1, 1), (3, 1), (3, 3), (1, 3)], [(1.5, 1.5), (2.5, 1.5), (2.5, 2.5), (1.5, 2.5)]],
        regions=[(2, 2, 5, None)],
    )
    assert d.loop_depth.tolist() == [0, 1, 2]
    assert d.area() == pytest.approx(16 - 4 + 1)
    assert loop_area(d.loops[2]) > 0
    assert d.contains([[2, 2], [1.2, 2], [0.5, 0.5]]).tolist() == [True, False, True]
    seed = d.holes[0]
    assert 1 < seed[0] < 3 and not (1.5 <= seed[0] <= 2.5 and 1.5 <= seed[1] <= 2.5)


@settings(max_examples=40, deadline=None)
@given(
    n=st.integers(8, 40),
    data=st.data(),
    reverse=st.booleans(),
)
def test_random_star_polygons(n, data, reverse):
    # tiny jitters flushed to zero: a coordinate like 1e-308 beside 1.0 lies outside the
    # predicates' exact range and is refused at the door (tests/test_doors.py)
    jitter = [j if j > 1e-30 else 0.0 for j in data.draw(st.lists(st.floats(0, 1), min_size=n, max_size=n))]
    radii = data.draw(st.lists(st.floats(0.2, 1.0), min_size=n, max_size=n))
    p = star(n, jitter, radii)
    if reverse:
        p = p[::-1]
    hole = np.array([(-0.05, -0.05), (-0.05, 0.05), (0.05, 0.05), (0.05, -0.05)])
    d = polygon(p, holes=[hole])
    assert loop_area(d.loops[0]) > 0 and loop_area(d.loops[1]) < 0
    assert d.area() == pytest.approx(abs(shoelace(p)) - 0.01, rel=1e-12, abs=1e-14)
    disc = d.discretize()
    assert len(disc.points) == n + 4
    assert d.contains(disc.holes).tolist() == [False]
    assert d.contains([[0.1, 0.0]]).tolist() == [True]


def test_large_polygon_validates_quickly():
    rng = np.random.default_rng(1)
    n = 100_000
    ang = np.arange(n) * TWO_PI / n
    p = star(n, rng.random(n), 1.0 + 0.1 * np.sin(5 * ang) + 1e-4 * rng.random(n))
    d = polygon(p)
    assert d.area() == pytest.approx(shoelace(p), rel=1e-12)
    with pytest.raises(GeometryError, match="intersects"):
        q = p.copy()
        q[10] *= -2.0  # a spike through the opposite side
        polygon(q)


def brute_force_pairs(pts, seg):
    from meshwright.geometry._kernels import _pair_is_bad

    x, y = pts[:, 0].copy(), pts[:, 1].copy()
    return {
        (i, j)
        for i in range(len(seg))
        for j in range(i + 1, len(seg))
        if _pair_is_bad(x, y, seg[i, 0], seg[i, 1], seg[j, 0], seg[j, 1])
    }


@pytest.mark.parametrize("seed", range(4))
def test_grid_finds_every_bad_pair(seed):
    rng = np.random.default_rng(seed)
    # Snapped coordinates give touching, collinear-overlapping and shared-vertex cases.
    pts = np.unique(np.round(rng.random((60, 2)) * 8) / 8, axis=0)
    seg = rng.integers(0, len(pts), (120, 2))
    seg = seg[seg[:, 0] != seg[:, 1]].astype(np.int64)
    got = {tuple(p) for p in find_bad_pairs(pts, seg, 10**6).tolist()}
    assert got == brute_force_pairs(pts, seg)


def test_classify_points_matches_brute_force():
    from meshwright.geometry._kernels import classify_points, parity_by_label

    rng = np.random.default_rng(7)
    ang = np.sort(rng.random(50)) * TWO_PI
    poly = np.column_stack([np.cos(ang), np.sin(ang)]) * (0.5 + rng.random(50))[:, None]
    poly = np.round(poly * 16) / 16
    q = np.round((rng.random((3000, 2)) * 3 - 1.5) * 32) / 32  # many on edges and vertices
    a, b = poly, np.roll(poly, -1, axis=0)
    fast = classify_points(q, a, b)
    slow = parity_by_label(q, a, b, np.zeros(len(a), dtype=np.int64), 1)[:, 0]
    assert (fast == slow).all() and (fast == 2).any() and (fast == 1).any()


# ---------------------------------------------------------------------------------------
# files
# ---------------------------------------------------------------------------------------
POLY = """# square with a hole, an interior and a dangling segment, a region
9 2 0 1
{b0} 0 0 5
{b1} 4 0 0
{b2} 4 4 0
{b3} 0 4 0
{b4} 1 1 0
{b5} 2 1 0
{b6} 2 2 0
{b7} 1 2 0
{b8} 3 3 0
10 1
1 {b0} {b1} 7
2 {b1} {b2} 0
3 {b2} {b3} 0
4 {b3} {b0} 0
5 {b4} {b5} 0
6 {b5} {b6} 0
7 {b6} {b7} 0
8 {b7} {b4} 0
9 {b1} {b6} 3
10 {b8} {b2} 0
1
1 1.5 1.5
1
1 0.5 3 4 0.1
"""


@pytest.mark.parametrize("base", [0, 1])
def test_read_poly(tmp_path, base):
    f = tmp_path / "a.poly"
    f.write_text(POLY.format(**{f"b{i}": i + base for i in range(9)}))
    d = read_poly(f)
    assert d.area() == pytest.approx(15.0)
    assert len(d.loops) == 2 and len(d.constraints) == 2
    assert d.regions == ((0.5, 3.0, 4, 0.1),)
    disc = d.discretize()
    assert sorted(disc.segment_markers.tolist()) == [0, 1, 1, 1, 1, 1, 1, 1, 3, 7]


def test_poly_round_trip(tmp_path):
    d = polygon(
        [(0, 0), (3, 0), (3, 2), (0, 2)],
        holes=[[(1, 0.5), (2, 0.5), (2, 1.5), (1, 1.5)]],
        segments=[[(2.5, 0.5), (2.5, 1.5)]],
        markers=[[1, 2, 3, 4], 6],
        points=[(0.5, 1.0)],
        regions=[(0.2, 0.2, 3, 0.05)],
    )
    f = tmp_path / "r.poly"
    write_poly(f, d)
    e = read_poly(f)
    a, b = d.discretize(), e.discretize()
    assert e.area() == pytest.approx(d.area())
    assert sorted(a.segment_markers.tolist()) == sorted(b.segment_markers.tolist())
    assert e.points.tolist() == [[0.5, 1.0]]
    assert e.regions == d.regions
    assert len(e.holes) == 1 and len(e.constraints) == 1


def test_poly_with_node_file_and_circle(tmp_path):
    d = circle((0, 0), 1.0)
    f = tmp_path / "c.poly"
    write_poly(f, d, size=0.1)
    lines = f.read_text().splitlines()
    nv = int(lines[1].split()[0])
    (tmp_path / "c.node").write_text("\n".join(lines[1 : 2 + nv]) + "\n")
    (tmp_path / "c.poly").write_text("0 2 0 1\n" + "\n".join(lines[2 + nv :]) + "\n")
    e = read_poly(f)
    assert e.area() == pytest.approx(
        d.discretize(0.1).points.shape[0] * 0.5 * math.sin(TWO_PI / nv)
    )


@pytest.mark.parametrize(
    "text, match, err",
    [
        ("3 2 0 0\n1 0 0\n2 1 x\n", r"x\.poly, line 3: vertex y: 'x' is not a finite number", FormatError),
        ("2 2 0 0\n1 0 0\n3 1 0\n", r"x\.poly, line 3: vertex numbered 3, expected 2", FormatError),
        (
            "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n2 0\n1 1 2\n2 2 9\n",
            r"x\.poly, line 7: segment endpoints 2 9 outside the vertex numbers, 1\.\.3",
            FormatError,
        ),
        (
            "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n2 0\n1 1 2\n2 2 3\n",
            r"x\.poly, line 7: unexpected end of file, expected the hole header",
            FormatError,
        ),
        (
            "4 2 0 0\n1 0 0\n2 1 1\n3 1 0\n4 0 1\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n",
            "segments on lines 7 and 9 intersect",
            GeometryError,
        ),
        (
            "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 1 0\n4 0\n1 1 2\n2 2 3\n3 3 1\n4 2 4\n0\n",
            r"x\.poly, line 10: segment has zero length",
            GeometryError,
        ),
    ],
)
def test_poly_errors(tmp_path, text, match, err):
    f = tmp_path / "x.poly"
    f.write_text(text)
    with pytest.raises(err, match=match):
        read_poly(f)


def test_poly_zero_vertices_twice_is_an_error_not_a_recursion(tmp_path):
    (tmp_path / "z.poly").write_text("0 2 0 0\n3 0\n1 1 2\n2 2 3\n3 3 1\n0\n")
    with pytest.raises(FormatError, match=r"z\.poly, line 1: 0 vertices declared, so they must be in z\.node"):
        read_poly(tmp_path / "z.poly")
    (tmp_path / "z.node").write_text("# deferring again would loop\n0 2 0 0\n")
    with pytest.raises(FormatError, match=r"z\.node, line 2: declares 0 vertices, but z\.poly \(line 1\)"):
        read_poly(tmp_path / "z.poly")


def test_poly_arguments_checked(tmp_path):
    with pytest.raises(InputError, match="file path, got int"):
        read_poly(3)
    with pytest.raises(InputError, match="Domain or a Discretization, got str"):
        write_poly(tmp_path / "a.poly", "circle")
    with pytest.raises(InputError, match="already discretised"):
        write_poly(tmp_path / "a.poly", circle((0, 0), 1.0).discretize(0.5), size=0.1)
    with pytest.raises(InputError, match="first_index must be 0 or 1"):
        write_poly(tmp_path / "a.poly", circle((0, 0), 1.0), first_index=2)


@pytest.mark.parametrize("first_index", [0, 1])
def test_poly_round_trip_first_index(tmp_path, first_index):
    d = polygon([(0, 0), (2, 0), (2, 1), (0, 1)], holes=[[(0.5, 0.25), (1.5, 0.25), (1.0, 0.75)]])
    f = tmp_path / "t.poly"
    write_poly(f, d, first_index=first_index)
    assert f.read_text().splitlines()[2].split()[0] == str(first_index)
    e = read_poly(f)
    np.testing.assert_array_equal(e.discretize().points, d.discretize().points)
    assert e.area() == d.area()


@settings(max_examples=150, deadline=None)
@given(data=st.data())
def test_damaged_poly_files_raise_meshwright_errors_only(data):
    """A damaged .poly (bytes replaced, a line dropped) gives a Domain or a FormatError /
    GeometryError naming the file, never a raw exception."""
    import tempfile
    from pathlib import Path

    from meshwright.core.errors import MeshwrightError

    lines = POLY.format(**{f"b{i}": i + 1 for i in range(9)}).encode().split(b"\n")
    if data.draw(st.booleans()):
        del lines[data.draw(st.integers(0, len(lines) - 1))]
    raw = bytearray(b"\n".join(lines))
    for _ in range(data.draw(st.integers(0, 2))):
        raw[data.draw(st.integers(0, len(raw) - 1))] = data.draw(st.sampled_from(b"0123456789 .-#\nx\xff"))
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "d.poly"
        path.write_bytes(bytes(raw))
        try:
            read_poly(path)
        except (FormatError, GeometryError) as exc:
            assert str(exc).startswith(str(path))
        except MeshwrightError as exc:
            pytest.fail(f"{type(exc).__name__} without the file name: {exc}")


def test_poly_faces_exact_for_directions_closer_than_arctan2_resolves(tmp_path):
    """Two segments leave (0, 0) 4e-19 rad apart (arctan2 ties them) and bound a sliver
    face of area 1/2 whose float shoelace sum rounds to 0: the half-edge order around each
    vertex and the faces' orientations must still be the exact ones."""
    from fractions import Fraction

    from meshwright.geometry.poly import _angular_order, _faces

    a = 2**30
    xy = np.array([(0, 0), (a, a + 1), (a + 1, a + 2), (0, 2 * a), (2 * a, 0)], dtype=np.float64)
    seg = np.array([(0, 1), (0, 2), (1, 2), (1, 3), (0, 3), (0, 4), (4, 2)])
    org = np.concatenate([seg[:, 0], seg[:, 1]])
    dst = np.concatenate([seg[:, 1], seg[:, 0]])

    def before(e, f):  # counter-clockwise from the +x axis, in rationals
        u = [Fraction(xy[dst[e], k]) - Fraction(xy[org[e], k]) for k in (0, 1)]
        v = [Fraction(xy[dst[f], k]) - Fraction(xy[org[f], k]) for k in (0, 1)]
        hu, hv = (w[1] < 0 or (w[1] == 0 and w[0] < 0) for w in (u, v))
        return hu < hv or (hu == hv and u[0] * v[1] - u[1] * v[0] > 0)

    order = _angular_order(xy, org, dst).tolist()
    assert order == sorted(order, key=lambda e: (org[e], sum(before(f, e) for f in range(len(org)) if org[f] == org[e])))
    face, area, positive, _, _ = _faces(xy, seg)
    sliver = face[1]  # half-edge 0 -> 2 runs along the sliver (0, 0), b, a
    assert area[sliver] == 0.0 and positive[sliver]  # the float sum loses it, the exact test not
    assert positive.sum() == 3 and len(positive) == 4


def _fraction_area(points, triangles):
    """Exact total area of triangles (absolute values), with rationals."""
    from fractions import Fraction

    p = [(Fraction(x), Fraction(y)) for x, y in np.asarray(points, dtype=float).tolist()]
    total = Fraction(0)
    for a, b, c in np.asarray(triangles).tolist():
        (ax, ay), (bx, by), (cx, cy) = p[a], p[b], p[c]
        total += abs((bx - ax) * (cy - ay) - (by - ay) * (cx - ax)) / 2
    return total


@pytest.mark.parametrize("name", ["A", "double_hex", "double_hex2", "double_hex3", "face", "square_circle_hole"])
def test_read_poly_triangle_examples_enclose_triangles_area(name):
    """Each closed example .poly that ships with Triangle becomes a Domain whose area is that
    of Triangle's own constrained triangulation of the file (``p``), summed exactly."""
    triangle = pytest.importorskip("triangle")
    from pathlib import Path

    path = Path(triangle.__file__).parent / "data" / f"{name}.poly"
    if not path.is_file():
        pytest.skip("the triangle package ships no example files")
    ref = triangle.triangulate(triangle.get_data(name), "p")
    d = read_poly(path)
    assert d.area() == pytest.approx(float(_fraction_area(ref["vertices"], ref["triangles"])), rel=1e-12)


def test_json_round_trip(tmp_path):
    outer = [
        Line((0, 0), (2, 0), marker=3),
        Arc((2, 1), 1.0, -math.pi / 2, math.pi / 2, marker=4),
        Polyline([(2, 2), (1, 2.5), (0, 2)], markers=[5, 6]),
        Line((0, 2), (0, 0)),
    ]
    d = Domain(
        outer,
        [Spline([(0.5, 0.5), (1.0, 0.4), (1.2, 1.0), (0.6, 1.2)], closed=True, marker=9)],
        segments=[[Line((1.5, 0.2), (1.5, 1.5))]],
        points=[(2.5, 1.0)],
        regions=[(0.2, 0.2, 1, None)],
        size=0.1,
    )
    f = tmp_path / "d.json"
    save_domain(d, f)
    e = load_domain(f)
    assert e.area() == pytest.approx(d.area(), rel=1e-12)
    assert e.size.constant == 0.1
    a, b = d.discretize(), e.discretize()
    np.testing.assert_allclose(a.points, b.points, atol=1e-12)
    assert a.segment_markers.tolist() == b.segment_markers.tolist()
    assert domain_to_dict(e) == domain_to_dict(d)


def test_json_schema_shapes():
    d = domain_from_dict(
        {
            "outer": {"circle": {"center": [0, 0], "radius": 10}, "marker": 2},
            "holes": [
                {"naca": "0012", "aoa": 5},
                {"polygon": [[3, 3], [4, 3], [4, 4]], "markers": [7, 8, 9]},
                {"ellipse": {"center": [-4, 0], "a": 1, "b": 0.5}},
                {
                    "curves": [
                        {
                            "arc": {"center": [0, -5], "radius": 1, "theta0": 0, "theta1": 360},
                            "degrees": True,
                        }
                    ]
                },
            ],
        }
    )
    assert d.area() == pytest.approx(
        100 * math.pi - naca("0012").area() - 0.5 - 0.5 * math.pi - math.pi, rel=1e-8
    )


@pytest.mark.parametrize(
    "obj, match",
    [
        ({"outer": [[0, 0], [1, 0], [0, 1]], "hole": []}, r"unknown key\(s\) \['hole'\]"),
        ({"holes": []}, "missing 'outer'"),
        (
            {"outer": {"curves": [{"line": [[0, 0], [1, 0]], "colour": 1}]}},
            r"outer.curves\[0\]: unknown key",
        ),
        (
            {"outer": {"curves": [{"arc": {"center": [0, 0], "radius": 1, "theta0": 0}}]}},
            "missing 'theta1'",
        ),
        ({"outer": {"square": 1}}, "a loop needs one of"),
        ({"outer": [[0, 0], [1, 0], [0, 1]], "version": 2}, "version"),
    ],
)
def test_json_errors(obj, match):
    with pytest.raises(FormatError, match=match):
        domain_from_dict(obj)


def test_json_file_errors(tmp_path):
    f = tmp_path / "bad.json"
    f.write_text('{"outer": [[0, 0],\n [1, 0]\n')
    with pytest.raises(FormatError, match=r"bad.json:\d+:\d+: invalid JSON"):
        load_domain(f)
    f.write_text(json.dumps({"outer": [[0, 0], [1, 1], [1, 0], [0, 1]]}))
    with pytest.raises(GeometryError, match="bad.json: outer loop"):
        load_domain(f)
    with pytest.raises(InputError, match="Parametric"):
        domain_to_dict(naca("0012"))


def test_read_poly_keeps_float_region_attributes(tmp_path):
    """Triangle's regional attribute is a float: kept per region (marker 0 unless it is
    integral); a region line without its fifth field takes the attribute as area bound."""
    f = tmp_path / "r.poly"
    f.write_text(
        "4 2 0 0\n1 0 0\n2 2 0\n3 2 1\n4 0 1\n5 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 2 4\n0\n"
        "2\n1 1.5 0.1 0.25 0.5\n2 0.2 0.8 7\n"
    )
    dom = read_poly(f)
    assert dom.regions == ((1.5, 0.1, 0, 0.5), (0.2, 0.8, 7, 7.0))
    np.testing.assert_array_equal(dom.region_attributes, [0.25, 7.0])
    assert not dom.open_boundary


@pytest.mark.parametrize("bad, match", [([1.0], "1 entries for 2 regions"), ([1.0, float("nan")], "region 1 attribute")])
def test_domain_region_attributes_checked(bad, match):
    square = [(0, 0), (2, 0), (2, 1), (0, 1)]
    regions = [(0.5, 0.5, 1), (1.5, 0.5, 2)]
    with pytest.raises(InputError, match=match):
        Domain(square, segments=[[(1, 0), (1, 1)]], regions=regions, region_attributes=bad)
    np.testing.assert_array_equal(Domain(square, regions=regions).region_attributes, [1.0, 2.0])


def test_read_poly_numbering_numbers_and_comments_agree(tmp_path):
    """The same square with a hole written 1-based and plain, and 0-based with Fortran
    numbers and comments on every line, reads to the same domain."""
    plain = (
        "8 2 0 0\n1 0 0\n2 3 0\n3 3 3\n4 0 3\n5 1 1\n6 2 1\n7 2 2\n8 1 2\n"
        "8 1\n1 1 2 5\n2 2 3 1\n3 3 4 1\n4 4 1 1\n5 5 6 2\n6 6 7 2\n7 7 8 2\n8 8 5 2\n"
        "1\n1 1.5 1.5\n"
    )
    fortran = (
        "# vertices\n8 2 0 0 # count dim attr markers\n"
        "0 0.000000E+00 -.000000E+00 # a\n1 0.300000E+01 0.0E0 # b\n2 .3E1 3.0 #\n3 -0. 0.3E+01\n"
        "4 0.1E+01 1 # hole\n5 2 .1e1\n6 2. 2.\n7 1 2 # last\n"
        "8 1 # segments\n0 0 1 5\n1 1 2 1 # x\n2 2 3 1\n3 3 0 1\n4 4 5 2\n5 5 6 2\n6 6 7 2\n7 7 4 2 #\n"
        "1 # holes\n0 0.15E+01 1.5E0 # seed\n# end\n"
    )
    domains = []
    for name, text in (("plain", plain), ("fortran", fortran)):
        (tmp_path / f"{name}.poly").write_text(text)
        domains.append(read_poly(tmp_path / f"{name}.poly"))
    a, b = (d.discretize() for d in domains)
    for field in ("points", "segments", "segment_markers", "holes"):
        np.testing.assert_array_equal(getattr(a, field), getattr(b, field))
    assert a.points.shape == (8, 2) and sorted(set(a.segment_markers.tolist())) == [1, 2, 5]


def test_read_poly_open_segments_close_with_the_hull(tmp_path):
    """No segments at all, or one lone segment: the convex hull of the vertices closes the
    boundary (marker 1 off the given segments), hull vertices on a hull edge kept."""
    f = tmp_path / "open.poly"
    f.write_text("5 2 0 0\n1 0 0\n2 2 0\n3 2 2\n4 0 2\n5 1 0\n1 1\n1 1 5 4\n0\n")
    dom = read_poly(f)
    assert dom.open_boundary and dom.area() == 4.0
    disc = dom.discretize()
    assert len(disc.points) == 5  # (1, 0) stays a boundary vertex
    mid = disc.points[disc.segments].mean(axis=1)
    np.testing.assert_array_equal(disc.segment_markers[(mid[:, 1] == 0) & (mid[:, 0] < 1)], [4])
    assert (disc.segment_markers[(mid[:, 1] > 0) | (mid[:, 0] > 1)] == 1).all()
    f.write_text("3 2 0 0\n1 0 0\n2 1 0\n3 2 0\n0 0\n0\n")
    with pytest.raises(GeometryError, match="enclose no region"):
        read_poly(f)


@settings(max_examples=40, deadline=None)
@given(pts=st.lists(st.tuples(st.integers(-6, 6), st.integers(-6, 6)), min_size=3, max_size=25, unique=True))
def test_read_poly_hull_of_a_point_set(tmp_path_factory, pts):
    """A .poly with vertices only is closed by their convex hull: scipy's hull area as the
    oracle, every vertex kept (points on a hull edge as boundary vertices)."""
    spatial = pytest.importorskip("scipy.spatial")
    xy = np.array(pts, dtype=np.float64)
    f = tmp_path_factory.mktemp("hull") / "p.poly"
    f.write_text(f"{len(xy)} 2 0 0\n" + "".join(f"{i + 1} {x} {y}\n" for i, (x, y) in enumerate(pts)) + "0 0\n0\n")
    if np.linalg.matrix_rank(xy[1:] - xy[0]) < 2:
        with pytest.raises(GeometryError, match="enclose no region"):
            read_poly(f)
        return
    dom = read_poly(f)
    assert dom.open_boundary
    assert dom.area() == pytest.approx(spatial.ConvexHull(xy).volume, rel=1e-12)
    assert len(dom.discretize().points) == len(xy)
