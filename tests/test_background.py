"""Background grid (chapter 18.2): interpolation of delta, s, alpha; transformation; files."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import meshwright as mw
from meshwright.core.errors import FormatError, InputError, SizeError
from meshwright.sizing import BackgroundGrid, as_size_field

SQUARE = [(0, 0), (1, 0), (1, 1), (0, 1)]
HALVES = [(0, 1, 2), (0, 2, 3)]


def test_linear_fields_are_reproduced_exactly():
    rng = np.random.default_rng(0)
    pts = rng.random((60, 2))
    tri = mw.delaunay(pts).triangles
    f = lambda p: 1.0 + 2.0 * p[:, 0] + 3.0 * p[:, 1]  # noqa: E731
    bg = BackgroundGrid(pts, tri, f(pts))
    q = rng.random((500, 2)) * 0.5 + 0.25
    inside = mw.delaunay(pts).locate(q) >= 0
    assert np.allclose(bg(q[inside]), f(q[inside]), rtol=1e-12)


def test_outside_takes_the_nearest_point():
    bg = BackgroundGrid(SQUARE, HALVES, [1, 2, 3, 4])
    got = bg(np.array([[-1.0, 0.5], [2.0, 2.0], [0.5, -3.0]]))
    assert np.allclose(got, [2.5, 3.0, 1.5])


def _nearest_edge_values(pts, delta, x, y, atol=1e-12):
    """Exact oracle: the linear interpolations of delta along the triangle's edges nearest
    (x, y), in rationals: every edge within ``atol`` of the least distance (a point within
    rounding of two edges of a needle may take either)."""
    import math
    from fractions import Fraction as F

    cand = []
    for u, w in ((0, 1), (1, 2), (2, 0)):
        ux, uy, wx, wy = F(pts[u][0]), F(pts[u][1]), F(pts[w][0]), F(pts[w][1])
        ex, ey = wx - ux, wy - uy
        f = min(F(1), max(F(0), ((F(x) - ux) * ex + (F(y) - uy) * ey) / (ex * ex + ey * ey)))
        d2 = (ux + f * ex - F(x)) ** 2 + (uy + f * ey - F(y)) ** 2
        cand.append((math.sqrt(d2), float((1 - f) * F(delta[u]) + f * F(delta[w]))))
    least = min(d for d, _ in cand)
    return [v for d, v in cand if d <= least + atol]


def test_outside_a_needle_interpolates_along_its_nearest_edge():
    # A needle met by the stress harness (seed 1701, the chapter's background of a boundary
    # with a tiny feature): long sides of 13, a short one of 2e-5, coordinates near 70.  The
    # barycentric coordinates of the nearest point, divided by its tiny area, came out at
    # (-10.2, 0, 11.2): a size of -0.4 from nodal sizes 6.6-13.4.
    pts = np.array([[70.63561065751219, 15.310125055742597], [70.46272388581933, 2.0723100669390107],
                    [70.63561039747951, 15.310105145228587]])
    delta = np.array([7.30772771, 13.43360089, 6.61947195])
    bg = BackgroundGrid(pts, [(0, 1, 2)], delta)
    rng = np.random.default_rng(3)
    q = np.vstack([[70.63560775944069, 15.309903152505834],
                   pts[2] + rng.normal(0.0, 3e-4, (40, 2)), pts[0] + rng.normal(0.0, 3e-4, (40, 2))])
    got = bg(q)
    assert (got >= delta.min()).all() and (got <= delta.max()).all()
    inside = mw.delaunay(np.vstack([pts, pts.mean(axis=0)])).locate(q) >= 0  # not ours to judge
    for (x, y), h in zip(q[~inside], got[~inside]):
        near = _nearest_edge_values(pts, delta, x, y)
        assert min(near) * (1 - 1e-9) <= h <= max(near) * (1 + 1e-9)


def test_direction_is_an_axis():
    # 170 and 10 degrees are 20 degrees apart as axes: the midpoint is 0, not 90.
    bg = BackgroundGrid(SQUARE, HALVES, 1.0, 2.0, np.radians([170, 10, 10, 170]))
    _, s, alpha = bg.metric(np.array([[0.5, 0.0]]))
    assert s[0] == pytest.approx(2.0)
    assert alpha[0] == pytest.approx(0.0, abs=1e-12)


@settings(deadline=None)
@given(st.floats(1.0, 10.0), st.floats(-math.pi, math.pi))
def test_transform_makes_stretched_elements_unit(s, alpha):
    bg = BackgroundGrid.uniform((0, 0, 1, 1), 0.1, s, alpha)
    t = bg.transform(np.array([[0.5, 0.5]]))[0]
    along = np.array([math.cos(alpha), math.sin(alpha)]) * s * 0.1
    across = np.array([-math.sin(alpha), math.cos(alpha)]) * 0.1
    assert np.linalg.norm(t @ along) == pytest.approx(0.1, rel=1e-9)
    assert np.linalg.norm(t @ across) == pytest.approx(0.1, rel=1e-9)


def test_is_a_size_field_and_meshes_follow_it(tmp_path):
    bg = BackgroundGrid([(-1.2, -1.2), (1.2, -1.2), (1.2, 1.2), (-1.2, 1.2)], HALVES, [0.05, 0.3, 0.3, 0.3])
    assert as_size_field(bg) is bg
    mesh = mw.triangulate(mw.geometry.circle(), size=bg, method="frontal-delaunay")
    mesh.validate()
    p = mesh.points[mesh.cells["triangle"]]
    cen = p.mean(axis=1)
    edge = np.hypot(*(p[:, 1] - p[:, 0]).T)
    fine = edge[(cen[:, 0] < -0.5) & (cen[:, 1] < -0.5)].mean()
    coarse = edge[(cen[:, 0] > 0.5) & (cen[:, 1] > 0.5)].mean()
    assert coarse > 2.0 * fine


def test_file_round_trip_and_cli(tmp_path, capsys):
    bg = BackgroundGrid(SQUARE, HALVES, [0.1, 0.2, 0.3, 0.4], [1, 2, 3, 4], np.radians([0, 30, 60, 90]))
    path = tmp_path / "bg.txt"
    bg.write(path)
    back = BackgroundGrid.read(path)
    q = np.random.default_rng(1).random((50, 2))
    for a, b in zip(bg.metric(q), back.metric(q)):
        assert np.allclose(a, b, rtol=1e-12, atol=1e-14)
    from meshwright.cli import main

    out = tmp_path / "m.vtu"
    big = BackgroundGrid.uniform((-1, -1, 1, 1), 0.1)
    big.write(path)
    assert main(["mesh", "circle", "-o", str(out), "--background", str(path)]) == 0
    assert out.exists()


def test_from_boundary_uses_point_distribution():
    pts = np.array(SQUARE, dtype=float) * 2
    segs = [(0, 1), (1, 2), (2, 3), (3, 0)]
    bg = BackgroundGrid.from_boundary(pts, segs, HALVES)
    assert np.allclose(bg(pts), 2.0)


def test_bad_input_is_named(tmp_path):
    with pytest.raises(SizeError, match="delta at node 2"):
        BackgroundGrid(SQUARE, HALVES, [1, 1, 0, 1])
    with pytest.raises(SizeError, match="stretch"):
        BackgroundGrid(SQUARE, HALVES, 1.0, 0.5)
    with pytest.raises(InputError, match="counter-clockwise"):
        BackgroundGrid(SQUARE, [(0, 2, 1)], 1.0)
    with pytest.raises(InputError):
        BackgroundGrid(SQUARE, [(0, 1, 7)], 1.0)
    bad = tmp_path / "bad.txt"
    bad.write_text("not a grid\n")
    with pytest.raises(FormatError):
        BackgroundGrid.read(bad)


# ---------------------------------------------------------------------------- spacing along curves
def _segment_lengths(disc):
    """Lengths of the discretisation's segments along x and along y (axis-parallel domains)."""
    d = np.diff(disc.points[disc.segments], axis=1)[:, 0]
    length = np.hypot(d[:, 0], d[:, 1])
    horizontal = np.abs(d[:, 1]) < 1e-12 * length
    return length[horizontal], length[~horizontal]


@pytest.mark.parametrize(
    "dom",
    [mw.geometry.polygon([(0, 0), (4, 0), (4, 1), (0, 1)]), mw.geometry.rectangle(0.0, 0.0, 4.0, 1.0)],
    ids=["polygon", "rectangle"],
)
@pytest.mark.parametrize("direction, along_x, along_y", [(0.0, 0.2, 0.05), (math.pi / 2, 0.05, 0.2)])
def test_boundary_spacing_follows_the_stretching(dom, direction, along_x, along_y):
    bg = BackgroundGrid.uniform(dom.bbox, delta=0.05, stretch=4, direction=direction)
    hx, hy = _segment_lengths(dom.discretize(bg))
    assert hx.mean() == pytest.approx(along_x, rel=0.1)
    assert hy.mean() == pytest.approx(along_y, rel=0.1)
    # Polygon corners must not leak one side's direction into the other's spacing.
    assert hx.std() < 0.05 * hx.mean() and hy.std() < 0.05 * hy.mean()


def test_along_matches_the_metric_formula():
    delta, s, alpha = 0.05, 4.0, math.radians(30)
    bg = BackgroundGrid.uniform((0, 0, 1, 1), delta, s, alpha)
    angles = np.radians([0.0, 30.0, 75.0, 120.0, 210.0])
    tau = np.column_stack([np.cos(angles), np.sin(angles)])
    xy = np.random.default_rng(2).random((len(angles), 2))
    r = np.array([[math.cos(alpha), -math.sin(alpha)], [math.sin(alpha), math.cos(alpha)]])
    t = r @ np.diag([1 / s, 1.0]) @ r.T
    m = t @ t / delta**2
    want = 1.0 / np.sqrt(np.einsum("ni,ij,nj->n", tau, m, tau))
    # Tangent length is irrelevant.
    got = bg.along(xy, 3.0 * tau)
    assert np.allclose(got, want, rtol=1e-12)
    assert got[1] == pytest.approx(s * delta, rel=1e-12)
    assert got[3] == pytest.approx(delta, rel=1e-12)
    assert got[4] == pytest.approx(s * delta, rel=1e-12)
    assert bg.along(xy[:1], np.zeros((1, 2)))[0] == pytest.approx(delta, rel=1e-12)


def test_isotropic_along_is_the_size():
    xy = np.random.default_rng(3).random((40, 2))
    tau = np.random.default_rng(4).normal(size=(40, 2))
    tau[0] = 0.0
    for field in (
        as_size_field(0.1),
        as_size_field(lambda p: 0.01 + p[:, 0] ** 2),
        BackgroundGrid(SQUARE, HALVES, [0.1, 0.2, 0.3, 0.4]),
    ):
        assert np.array_equal(field.along(xy, tau), field(xy))
    with pytest.raises(InputError, match="tangents"):
        as_size_field(0.1).along(xy, tau[:5])
    tau[7] = np.nan
    with pytest.raises(InputError, match="tangent 7"):
        as_size_field(0.1).along(xy, tau)


def test_single_point_tables_and_arcs_do_not_break_along():
    # A circle (one arc, no corners) under a stretched grid: still a valid polygon, finer
    # where the boundary runs across the stretching.
    bg = BackgroundGrid.uniform((-1, -1, 1, 1), 0.05, 3.0, 0.0)
    disc = mw.geometry.circle().discretize(bg)
    p = disc.points[disc.segments]
    mid = p.mean(axis=1)
    length = np.hypot(*(p[:, 1] - p[:, 0]).T)
    top = length[np.abs(mid[:, 1]) > 0.95].mean()  # tangent ~ x: stretched
    side = length[np.abs(mid[:, 0]) > 0.95].mean()  # tangent ~ y: across
    assert top == pytest.approx(0.15, rel=0.15)
    assert side == pytest.approx(0.05, rel=0.15)
    from meshwright.geometry._discretize import _curve_queries

    one = np.array([[0.5, 0.5]])
    xy, tan, corners = _curve_queries(mw.geometry.Line((0, 0), (1, 0)), np.array([0.0]), one)
    assert np.array_equal(xy, one) and np.array_equal(tan, np.zeros((1, 2))) and len(corners) == 0
    assert bg.along(xy, tan)[0] == pytest.approx(0.05)


# ---------------------------------------------------------------------------- CLI --stretch
def test_cli_stretch(tmp_path, capsys):
    from meshwright.cli import main

    out = tmp_path / "tmp.vtu"
    args = ["mesh", "rectangle", "--method", "delaunay", "-o", str(out)]
    assert main([*args, "--size", "0.1", "--stretch", "3", "--direction", "30"]) == 0
    assert out.exists()
    assert "triangle" in mw.read(out).cells
    capsys.readouterr()

    bg = tmp_path / "bg.txt"
    BackgroundGrid.uniform((0, 0, 2, 1), 0.1).write(bg)
    for extra, message in [
        (["--stretch", "3"], "needs --size"),
        (["--size", "0.1", "--direction", "30"], "needs --stretch"),
        (["--size", "0.1", "--stretch", "3", "--background", str(bg)], "mutually exclusive"),
        (["--size", "0.1", "--stretch", "0.5"], "--stretch must be"),
    ]:
        assert main([*args, *extra]) == 2
        assert message in capsys.readouterr().err


def test_cli_stretch_raises_meshwright_errors():
    from meshwright.cli import build_parser
    from meshwright.cli.mesh import run

    parser = build_parser()
    with pytest.raises(InputError, match="needs --size"):
        run(parser.parse_args(["mesh", "rectangle", "--stretch", "3"]))
    with pytest.raises(InputError, match="needs --stretch"):
        run(parser.parse_args(["mesh", "rectangle", "--direction", "30"]))
    with pytest.raises(InputError, match="mutually exclusive"):
        run(parser.parse_args(["mesh", "rectangle", "--size", "0.1", "--stretch", "3", "--background", "bg.txt"]))
    with pytest.raises(SizeError, match="--stretch"):
        run(parser.parse_args(["mesh", "rectangle", "--size", "0.1", "--stretch", "0.5"]))


def test_walk_interpolation_matches_the_bucket_search():
    """interpolate_walk (the frontal kernel's size lookup) gives interpolate_one's value from
    any start triangle, inside the grid and outside it (nearest-point fallback)."""
    from meshwright.sizing.background import interpolate_one, interpolate_walk
    from meshwright.tri import delaunay

    rng = np.random.default_rng(3)
    pts = rng.random((300, 2))
    tri = delaunay(pts)
    bg = BackgroundGrid(tri.points, tri.triangles, 0.01 + rng.random(len(tri.points)))
    args = bg.kernel_args()
    p, t, nbr, start, items, x0, y0, cell, nx, ny, values = args
    hint = np.zeros(1, dtype=np.int64)
    for q in np.vstack([rng.random((200, 2)), rng.uniform(-0.5, 1.5, (50, 2))]):
        hint[0] = rng.integers(0, len(t))
        a = interpolate_walk(p, t, nbr, start, items, x0, y0, cell, nx, ny, values, 0, hint, q[0], q[1])
        b = interpolate_one(p, t, start, items, x0, y0, cell, nx, ny, q[0], q[1], values, 0)
        assert a == pytest.approx(b, rel=1e-12, abs=1e-12)
