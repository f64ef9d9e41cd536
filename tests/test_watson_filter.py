"""Watson's certified circle filter (meshwright.tri.watson): it decides, it is right, it steps aside.

``watson.circle`` stores per triangle a float32 centre and bounds ``lo <= |p - c|**2 <= hi``
of the uncertain band; ``watson.conflict`` answers from the record when ``d2 < lo`` (inside)
or ``d2 > hi`` (outside) and falls through to Bowyer's exact test otherwise.  These tests
call both public kernels on crafted one-triangle inputs and judge them by an exact-rational
in-circle determinant (``fractions.Fraction``, no shared code):

* on random triangles and queries the record decides almost every query, and every decision
  it makes is the exact answer (a filter that never decides, or decides wrongly, fails);
* ``conflict`` really answers from the record (a deliberately false record changes its
  answer) and equals the exact answer with the true record;
* on exactly cocircular inputs (lattice squares, Pythagorean circles) the record must not
  decide: the exact, perturbed path is taken, and ``conflict`` equals Bowyer's test;
* ill-conditioned triangles get the "always exact" record ``lo = -1, hi = inf``.
"""

from fractions import Fraction

import numpy as np
import pytest

from meshwright.tri import bowyer, watson


def _incircle_exact(a, b, c, d):
    """Sign of the in-circle determinant in exact rationals: +1 when d is inside ccw abc."""
    rows = []
    for p in (a, b, c):
        x, y = Fraction(float(p[0])) - Fraction(float(d[0])), Fraction(float(p[1])) - Fraction(float(d[1]))
        rows.append((x, y, x * x + y * y))
    (ax, ay, al), (bx, by, bl), (cx, cy, cl) = rows
    det = al * (bx * cy - by * cx) - bl * (ax * cy - ay * cx) + cl * (ax * by - ay * bx)
    return (det > 0) - (det < 0)


def _orient_exact(a, b, c):
    ax, ay, bx, by, cx, cy = (Fraction(float(v)) for v in (*a, *b, *c))
    det = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    return (det > 0) - (det < 0)


def _setup(a, b, c, d):
    """One ccw triangle (slot 0) and the query as vertex 3, with its circle record."""
    pts = np.ascontiguousarray(np.array([a, b, c, d], dtype=np.float64))
    tri = np.array([0, 1, 2], dtype=np.int32)
    circ = np.zeros(4, dtype=np.float32)
    rank = np.arange(4, dtype=np.int32)
    watson.circle(pts, tri, circ, 0)
    return pts, tri, circ, rank


def _record_says(circ, px, py):
    """What the record alone decides for the query (the documented contract): +1, -1 or 0."""
    dx = px - np.float64(circ[0])
    dy = py - np.float64(circ[1])
    d2 = dx * dx + dy * dy
    if d2 < np.float64(circ[2]):
        return 1
    if d2 > np.float64(circ[3]):
        return -1
    return 0


def _random_case(rng, scale, offset):
    while True:
        a, b, c = offset + scale * rng.random((3, 2))
        o = _orient_exact(a, b, c)
        if o != 0:
            break
    if o < 0:
        b, c = c, b
    # Queries around the circumcircle, out to twice its radius.
    m = np.array([[b[0] - a[0], b[1] - a[1]], [c[0] - a[0], c[1] - a[1]]])
    rhs = 0.5 * np.array([m[0] @ m[0], m[1] @ m[1]])
    centre = a + np.linalg.solve(m, rhs)
    r = np.hypot(*(centre - a))
    d = centre + 2 * r * (2 * rng.random(2) - 1)
    return a, b, c, d


@pytest.mark.parametrize("scale, offset", [(1.0, 0.0), (1e-3, 0.0), (1.0, 1e3), (1e6, -5e6)])
def test_filter_decides_most_random_queries_and_is_right(scale, offset):
    rng = np.random.default_rng(7)
    decided = 0
    trials = 600
    for _ in range(trials):
        a, b, c, d = _random_case(rng, scale, offset)
        pts, tri, circ, rank = _setup(a, b, c, d)
        exact = _incircle_exact(a, b, c, d)
        says = _record_says(circ, d[0], d[1])
        if says:
            decided += 1
            assert says == exact, (a, b, c, d, circ)
        if exact:
            assert watson.conflict(pts, tri, circ, rank, 0, 3, d[0], d[1]) == (exact > 0)
    # Random queries are rarely near the circle: the filter must answer nearly all of them.
    assert decided >= 0.95 * trials


def test_conflict_answers_from_the_record():
    a, b, c = (0.0, 0.0), (1.0, 0.0), (0.0, 1.0)
    far, near = (5.0, 5.0), (0.25, 0.25)
    assert _incircle_exact(a, b, c, far) < 0 < _incircle_exact(a, b, c, near)
    pts, tri, circ, rank = _setup(a, b, c, far)
    assert _record_says(circ, *far) == -1
    assert not watson.conflict(pts, tri, circ, rank, 0, 3, *far)
    # A false record that claims every point is inside: the filter's answer is used.
    circ[2], circ[3] = np.float32(1e30), np.float32(np.inf)
    assert watson.conflict(pts, tri, circ, rank, 0, 3, *far)
    # The "always exact" record: the exact answer again.
    circ[2], circ[3] = np.float32(-1.0), np.float32(np.inf)
    assert not watson.conflict(pts, tri, circ, rank, 0, 3, *far)
    pts, tri, circ, rank = _setup(a, b, c, near)
    assert _record_says(circ, *near) == 1 and watson.conflict(pts, tri, circ, rank, 0, 3, *near)
    circ[2], circ[3] = np.float32(-1.0), np.float32(0.0)  # claims every point is outside
    assert not watson.conflict(pts, tri, circ, rank, 0, 3, *near)


def _cocircular_cases():
    cases = []
    for off in (0.0, 1e6, -2.0**30):
        for h in (1.0, 0.5, 2.0**-20, 3.0):
            x, y = off + 7 * h, off - 3 * h
            # A lattice square: the fourth corner is exactly on the circle of the other three.
            cases.append(((x, y), (x + h, y), (x + h, y + h), (x, y + h)))
            cases.append(((x, y), (x + h, y + h), (x, y + h), (x + h, y)))
    circle5 = [(5, 0), (4, 3), (3, 4), (0, 5), (-3, 4), (-4, 3), (-5, 0), (-4, -3), (0, -5), (3, -4)]
    for i in range(len(circle5) - 3):
        cases.append(tuple(circle5[i : i + 4]))
    return cases


@pytest.mark.parametrize("a, b, c, d", _cocircular_cases())
def test_cocircular_queries_take_the_exact_path(a, b, c, d):
    assert _orient_exact(a, b, c) > 0 and _incircle_exact(a, b, c, d) == 0
    pts, tri, circ, rank = _setup(a, b, c, d)
    assert _record_says(circ, d[0], d[1]) == 0
    got = watson.conflict(pts, tri, circ, rank, 0, 3, float(d[0]), float(d[1]))
    assert got == bowyer.conflict(pts, tri, rank, 0, 3, float(d[0]), float(d[1]))


@pytest.mark.parametrize(
    "a, b, c",
    [
        ((0.0, 0.0), (1.0, 1.0), (1.0, 1.0 + 2.0**-49)),  # the float area has no correct digit
        ((0.0, 0.0), (1.0, 1.0 - 2.0**-52), (1.0 + 2.0**-52, 1.0)),  # float area exactly 0
    ],
)
def test_ill_conditioned_record_always_defers(a, b, c):
    assert _orient_exact(a, b, c) > 0
    for d in [(0.5, -1.0), (1.0, 1.0 + 2.0**-50), (-3.0, 4.0)]:
        pts, tri, circ, rank = _setup(a, b, c, d)
        assert circ[2] == -1.0 and circ[3] == np.inf
        exact = _incircle_exact(a, b, c, d)
        if exact:
            assert watson.conflict(pts, tri, circ, rank, 0, 3, *d) == (exact > 0)
