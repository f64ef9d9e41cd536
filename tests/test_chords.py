"""Chord refinement's boundary midpoints from the lines' curve parameters
(``chord_split(..., line_params=...)``, as paving passes its discretisation's
``segment_params``).  The oracles are plain trigonometry on the unit circle."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

from meshwright.core.errors import InputError
from meshwright.geometry import circle, polygon
from meshwright.quad.chords import chord_split, chord_split_candidates
from meshwright.quad.mesher import QuadFill


def _fan(angles):
    """Triangles (centre, rim i, rim i + 1) under unit-circle rim nodes at ``angles``
    (increasing, radians); the rim sides are the lines, on curve 0."""
    rim = np.column_stack([np.cos(angles), np.sin(angles)])
    xy = np.vstack([[0.0, 0.0], rim])
    k = len(angles)
    tris = np.column_stack([np.zeros(k - 1), np.arange(1, k), np.arange(2, k + 1)]).astype(np.int32)
    lines = np.column_stack([np.arange(1, k), np.arange(2, k + 1)]).astype(np.int32)
    return QuadFill(xy, np.zeros((0, 4), np.int32), tris, lines, np.ones(k - 1, np.int32), np.zeros(k - 1, np.int32))


def test_split_lines_take_the_arc_midpoint_of_their_parameters():
    angles = np.array([0.1, 0.35, 0.9, 1.2])
    fill = _fan(angles)
    params = np.column_stack([angles[:-1], angles[1:]])
    out = chord_split(fill, circle(), 100, line_params=params)
    assert len(out.triangles) == 0 and len(out.quads) == 3 * len(fill.triangles)
    # Every line is split: its new node is the second end of its first half.
    assert len(out.lines) == 2 * len(fill.lines)
    mids = out.points[out.lines[0::2, 1]]
    half = 0.5 * (angles[:-1] + angles[1:])
    for (x, y), t in zip(mids.tolist(), half.tolist()):
        assert x == pytest.approx(math.cos(t), abs=1e-14)
        assert y == pytest.approx(math.sin(t), abs=1e-14)
    # The same cells and lines as the projecting route, and the same points up to its
    # search tolerance.
    ref = chord_split(fill, circle(), 100)
    assert np.array_equal(ref.quads, out.quads) and np.array_equal(ref.lines, out.lines)
    assert np.abs(ref.points - out.points).max() < 1e-6


def test_line_params_are_checked_at_the_door():
    fill = _fan(np.array([0.0, 0.5, 1.0]))
    for bad in (np.zeros((1, 2)), np.zeros((2, 3)), np.array([[0.0, 0.5], [0.5, np.nan]])):
        with pytest.raises(InputError, match="line_params"):
            chord_split(fill, circle(), 100, line_params=bad)


def _orient(p, q, r) -> Fraction:
    """Exact orientation of three float points (rational arithmetic)."""
    (px, py), (qx, qy), (rx, ry) = ([Fraction(float(c)) for c in v] for v in (p, q, r))
    return (qx - px) * (ry - py) - (qy - py) * (rx - px)


def _assert_convex_and_conforming(out, fill):
    """Every quad strictly convex (exact), no triangle, every quad side shared by exactly two
    quads or lying on exactly one line, and the lines' chain covering the old lines."""
    assert len(out.triangles) == 0
    xy = out.points
    sides = {}
    for q in out.quads.tolist():
        for k in range(4):
            assert _orient(xy[q[k - 1]], xy[q[k]], xy[q[(k + 1) % 4]]) > 0, f"quad {q} bent at {q[k]}"
            sides[(q[k], q[(k + 1) % 4])] = sides.get((q[k], q[(k + 1) % 4]), 0) + 1
    lines = {tuple(sorted(e)) for e in out.lines.tolist()}
    for (a, b), count in sides.items():
        assert count == 1
        assert ((b, a) in sides) != ((min(a, b), max(a, b)) in lines), f"side {a}-{b}"
    assert len(lines) == len(out.lines) >= len(fill.lines)


def _flat_ear():
    """A pentagon whose bottom vertex 1 lies one float step below the line of its
    neighbours: the triangle (0, 1, 2) is counter-clockwise with a height under the
    coordinates' spacing, so its centroid rounds onto its long side."""
    xy = np.array([[0.0, 3.0], [0.5, np.nextafter(3.0, 0.0)], [1.0, 3.0], [1.0, 4.0], [0.0, 4.0]])
    tris = np.array([[0, 1, 2], [0, 2, 4], [2, 3, 4]], np.int32)
    lines = np.array([[0, 1], [1, 2], [2, 3], [3, 4], [4, 0]], np.int32)
    return QuadFill(xy, np.zeros((0, 4), np.int32), tris, lines, np.ones(5, np.int32), np.zeros(5, np.int32))


def _flat_ear_under_a_quad():
    """The same sliver ear with a quad beyond its long side: the flip re-cuts the pentagon
    into a quad and a triangle."""
    ear = _flat_ear()
    return ear._replace(quads=np.array([[0, 2, 3, 4]], np.int32), triangles=ear.triangles[:1])


def _flat_quad():
    """A quad (0, 1, 2, 4) whose corner 1 is the float point nearest the midpoint of 0 and 2
    with a strictly convex turn (orient2d ~1.5e-23 against sides of ~1e-3), between two
    triangles that make both its chords cross it (found by a search: the vertex-mean split
    of this quad comes out non-convex at 1)."""
    p0 = np.array([0.003511821624700257, 0.005950463696325936])
    p2 = np.array([0.00552623758597222, 0.00644532864103966])
    mid = 0.5 * (p0 + p2)
    cands = [
        np.array([mid[0] + i * np.spacing(mid[0]), mid[1] + j * np.spacing(mid[1])])
        for i in range(-3, 4)
        for j in range(-3, 4)
    ]
    p1 = min((c for c in cands if _orient(p0, c, p2) > 0), key=lambda c: _orient(p0, c, p2))
    d = p2 - p0
    nrm = np.array([-d[1], d[0]])
    xy = np.array([p0, p1, p2, p2 + 0.5 * nrm + 0.5 * d, mid + 0.5 * nrm, p0 + 0.5 * nrm - 0.5 * d])
    quads = np.array([[0, 1, 2, 4]], np.int32)
    tris = np.array([[2, 3, 4], [0, 4, 5]], np.int32)
    lines = np.array([[0, 1], [1, 2], [2, 3], [3, 4], [4, 5], [5, 0]], np.int32)
    return QuadFill(xy, quads, tris, lines, np.ones(6, np.int32), np.zeros(6, np.int32))


@pytest.mark.parametrize("make", [_flat_ear, _flat_ear_under_a_quad, _flat_quad])
def test_cells_too_flat_to_split_are_recut_into_convex_quads(make):
    fill = make()
    out = chord_split(fill, polygon(fill.points[: len(fill.lines)].tolist()), 1000)
    _assert_convex_and_conforming(out, fill)



def test_candidates_are_the_bent_plain_split_and_the_recut_one():
    fill = _flat_ear()
    plain, recut = chord_split_candidates(fill, polygon(fill.points.tolist()), 1000)
    xy = plain.points
    bent = [
        q for q in plain.quads.tolist() if any(_orient(xy[q[k - 1]], xy[q[k]], xy[q[(k + 1) % 4]]) <= 0 for k in range(4))
    ]
    assert bent
    _assert_convex_and_conforming(recut, fill)
    # The same ear half a unit deep splits convex at once: no re-cut.
    xy = fill.points.copy()
    xy[1, 1] = 2.5
    deep = fill._replace(points=xy)
    plain, recut = chord_split_candidates(deep, polygon(xy.tolist()), 1000)
    assert recut is None
    _assert_convex_and_conforming(plain, deep)


def test_nonconvex_quads_matches_exact_rational_corners():
    """The chord and pairing checks' exact convexity (``nonconvex_quads``) against cross
    products in rational arithmetic, on quads whose corner at (12, 12) lies between
    (24, 24) and points a few ulps off the line through both (Shewchuk's example, where
    the floating-point cross product gets the sign wrong), or on it."""
    from meshwright.quad._pairing_kernel import nonconvex_quads

    ulp = 2.0**-53
    ij = np.array([(i, j) for i in range(16) for j in range(16)], dtype=np.float64)
    n = len(ij)
    xy = np.vstack([0.5 + ij * ulp, [[12.0, 12.0], [24.0, 24.0], [30.0, 1.0]]])
    rng = np.random.default_rng(7)
    quads = np.column_stack(
        [rng.integers(0, n, 2000), np.full(2000, n), np.full(2000, n + 1), rng.integers(0, n, 2000)]
    ).astype(np.int32)
    quads[1000:, 3] = n + 2

    def strictly_convex(q):
        p = [tuple(Fraction(v) for v in xy[i]) for i in q]
        for k in range(4):
            (ax, ay), (bx, by), (cx, cy) = p[k - 1], p[k], p[(k + 1) % 4]
            if (ax - cx) * (by - cy) - (ay - cy) * (bx - cx) <= 0:
                return False
        return True

    want = [i for i, q in enumerate(quads.tolist()) if not strictly_convex(q)]
    assert 0 < len(want) < len(quads)
    assert nonconvex_quads(xy, quads).tolist() == want
