"""The triangle fronts at a size jump of 1e4 on the boundary (issue 12: the rows of slivers
under which pairing and zhu made quads of scaled Jacobian about 1e-4).

Oracles: sizes from the test's own step function and angles from the test's own
formulas, never the front's metric or quality code."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

from meshwright import geometry as g
from meshwright.quad.parity import make_loops_even
from meshwright.quad.zhu import zhu_front
from meshwright.tri import front as F
from meshwright.tri.cdt import SegmentCurves, cdt_build

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))
from stress2d import build  # noqa: E402  (the harness that wrote the reproducers)

H = 0.1
SMALL = 1e-4 * H


def _step(centre, radius=20 * SMALL):
    def size(xy):
        xy = np.asarray(xy, dtype=np.float64)
        d = np.hypot(xy[..., 0] - centre[0], xy[..., 1] - centre[1])
        return np.where(d < radius, SMALL, H)

    return size


def _ct(dom, size, even=False):
    disc = dom.discretize(size)
    if even:
        disc, _ = make_loops_even(dom, disc)
    ct = cdt_build(disc.points, disc.segments, seed=0, curves=SegmentCurves.from_domain(dom, disc))
    # Loop segments have the domain on one side, interior segments on both.
    sides = np.where(dom.curve_loop[disc.segment_curve] >= 0, 1, 0)
    ct.classify(segment_sides=sides, holes=disc.holes)
    return ct


def _min_angles(p, t):
    """Smallest angle of each triangle, degrees, from the law of cosines."""
    x = p[t]
    e = np.stack([np.hypot(*(x[:, (k + 2) % 3] - x[:, (k + 1) % 3]).T) for k in range(3)])  # opposite corner k
    out = []
    for k in range(3):
        a, b, c = e[k], e[(k + 1) % 3], e[(k + 2) % 3]
        out.append(np.degrees(np.arccos(np.clip((b * b + c * c - a * a) / (2 * b * c), -1.0, 1.0))))
    return np.min(out, axis=0)


def _cover_area(p, t):
    x = p[t]
    return 0.5 * np.sum((x[:, 1, 0] - x[:, 0, 0]) * (x[:, 2, 1] - x[:, 0, 1]) - (x[:, 1, 1] - x[:, 0, 1]) * (x[:, 2, 0] - x[:, 0, 0]))


SQUARE = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]


@pytest.mark.parametrize("centre", [(0.5, 0.0), (1.0, 1.0)])
def test_grading_splits_each_segment_an_even_number_of_times(centre):
    size = _step(centre)
    ct = _ct(g.polygon(SQUARE), size)
    before = np.bincount(ct.segments()[1])
    n = F.grade_segments(ct, size)
    edges, ids = ct.segments()
    added = np.bincount(ids, minlength=len(before)) - before
    assert n == added.sum() > 0
    assert (added % 2 == 0).all()
    # Every piece at most GRADE sizes of its finer end (the step's own sizes).
    p = np.asarray(ct.points)
    length = np.hypot(*(p[edges[:, 1]] - p[edges[:, 0]]).T)
    finer = np.minimum(size(p[edges[:, 0]]), size(p[edges[:, 1]]))
    assert (length <= F.GRADE * finer * (1 + 1e-9)).all()
    # The pieces stay on the square's sides.
    on = (np.isclose(p[:, 0], 0) | np.isclose(p[:, 0], 1) | np.isclose(p[:, 1], 0) | np.isclose(p[:, 1], 1))
    assert on[np.unique(edges)].all()


def test_grading_leaves_a_smooth_size_alone():
    size = lambda xy: 0.05 + 0.1 * np.asarray(xy)[..., 0]  # noqa: E731
    ct = _ct(g.polygon(SQUARE), size)
    before = ct.segments()[0].copy()
    assert F.grade_segments(ct, size) == 0
    assert np.array_equal(ct.segments()[0], before)


@pytest.mark.parametrize("centre", [(0.5, 0.0), (1.0, 1.0)])
def test_front_at_a_boundary_size_jump_lays_no_sliver(centre):
    size = _step(centre)
    p, t = F.advancing_front(_ct(g.polygon(SQUARE), size), size, finish=False, grade=True)
    a = _min_angles(p, t)
    # Measured 1.97 / 4.17 degrees (edge / corner; 0.0000 / 0.108 before the fix): no row
    # of flat triangles.
    assert a.min() > 1.0
    assert abs(_cover_area(p, t) - 1.0) < 1e-9
    # The fine region is meshed at its size: triangles of about SMALL inside it.
    near = np.hypot(*(p[t].mean(axis=1) - np.asarray(centre)).T) < 10 * SMALL
    assert near.sum() > 50


def test_pair_front_on_a_stress_domain_with_a_jump():
    """stress-zhu-783f1d2f72a6: a cocircular disc with a 1e-4 size jump at its rim; before
    the fix the triangle front's smallest angle was 0.0055 degrees, the pair front's 0.0000."""
    body = json.loads((ROOT / "tests/regressions/stress-zhu-783f1d2f72a6.json").read_text())
    dom, size, _, _ = build(body["case"], "zhu")
    p, t = F.advancing_front(_ct(dom, size, even=True), size, finish=False, grade=True)
    assert _min_angles(p, t).min() > 10.0  # measured 11.5
    p, t, pairs, _ = zhu_front(_ct(dom, size, even=True), size, grade=True)
    assert _min_angles(p, t).min() > 1.0  # measured 3.84


def _flattest_angle(p, t):
    """Smallest corner angle over the triangles, degrees, by atan2 of the sides' cross and
    dot products (exact enough at 1e-12 degrees, where the law of cosines rounds to 0)."""
    x = p[t]
    out = []
    for k in range(3):
        u = x[:, (k + 1) % 3] - x[:, k]
        v = x[:, (k + 2) % 3] - x[:, k]
        out.append(np.degrees(np.arctan2(np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]), (u * v).sum(axis=1))))
    return float(np.min(out))


def test_pairs_take_no_apex_on_the_line_of_their_base():
    """stress-zhu-6fde022a69d2 graded: pairs fanned from one node over a row of nodes on a
    line (triangles of 1e-9 .. 1e-12 degrees, flat to round-off, each paired into a quad
    with a straight corner).  The pairs' flattest triangle now comes from the domain's tiny
    feature (measured 2.4e-4 degrees), not from a node on the base's line."""
    body = json.loads((ROOT / "tests/regressions/stress-zhu-6fde022a69d2.json").read_text())
    dom, size, _, _ = build(body["case"], "zhu")
    p, t, pairs, _ = zhu_front(_ct(dom, size, even=True), size, grade=True)
    assert _flattest_angle(p, t[pairs.ravel()]) > 1e-5


# The unit square with a notch at its top side: an input edge 1.4e-6 long between sides of
# 0.4 and 0.6, the size 0.1 everywhere (a stress "tiny" feature, no jump in the size).
NOTCH = [(0, 0), (1, 0), (1, 1), (0.6, 1), (0.6 - 1e-6, 1 - 1e-6), (0, 1)]


def test_a_tiny_feature_grades_the_pieces_beside_it():
    ct = _ct(g.polygon(NOTCH), 0.1)
    before = len(ct.points)
    F.grade_segments(ct, lambda xy: np.full(np.shape(xy)[:-1], 0.1))
    edges, _ = ct.segments()
    p = np.asarray(ct.points)
    length = np.hypot(*(p[edges[:, 1]] - p[edges[:, 0]]).T)
    for v in np.unique(edges):
        at = length[(edges[:, 0] == v) | (edges[:, 1] == v)]
        # Within GRADE, or 2 GRADE where the parity split halved a segment's longest piece.
        assert at.max() <= 2 * F.GRADE * at.min()
    assert length.max() / length.min() > 1e4  # the notch's edge itself is kept
    # About log2(0.1 / 1.4e-6) = 16 halvings on each side of the notch, an even number each.
    assert len(ct.points) - before >= 2 * 16


def test_pairing_at_a_tiny_feature():
    """Before the grading by neighbouring pieces: min scaled Jacobian 1.1e-4 (a fan of
    slivers from the notch); measured 0.370 with it."""
    from meshwright.quad import quadrangulate

    mesh = quadrangulate(g.polygon(NOTCH), 0.1, method="pairing")
    q = mesh.points[mesh.cells["quad"]]
    into = q - np.roll(q, 1, axis=1)
    out = np.roll(q, -1, axis=1) - q
    cross = into[..., 0] * out[..., 1] - into[..., 1] * out[..., 0]
    sj = cross / (np.hypot(into[..., 0], into[..., 1]) * np.hypot(out[..., 0], out[..., 1]))
    assert sj.min() > 0.2
