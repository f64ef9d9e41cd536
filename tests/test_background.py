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
