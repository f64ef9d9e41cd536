"""Stage D of insphere (core/predicates.insphere_dd) against exact rational arithmetic.

The oracle is the 4x4 lifted determinant in ``fractions.Fraction`` (rows ``p - e`` and
``|p - e|**2``), which is Shewchuk's in-sphere determinant, the value ``insphere_dd``
approximates: a proven result must have its sign, on random, nearly cospherical (points
rounded onto a sphere), exactly cospherical (integer points on a sphere, where it must
not claim a proof) and 1-ulp perturbed inputs.
"""

from fractions import Fraction

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from meshwright.core.predicates import insphere, insphere_dd


def _det(m):
    """Exact determinant of a square list of Fractions (Laplace expansion on the first row)."""
    if len(m) == 1:
        return m[0][0]
    return sum((-1) ** j * m[0][j] * _det([row[:j] + row[j + 1 :] for row in m[1:]]) for j in range(len(m)) if m[0][j])


def _oracle(pts):
    """Sign of det[p - e | |p - e|^2] over p = a, b, c, d (e the fifth point), exactly."""
    e = [Fraction(v) for v in pts[4]]
    rows = []
    for p in pts[:4]:
        d = [Fraction(v) - w for v, w in zip(p, e)]
        rows.append(d + [sum(x * x for x in d)])
    v = _det(rows)
    return (v > 0) - (v < 0)


def _check(pts):
    """(proven, agrees) for one 5-point input; insphere's own sign is checked too."""
    flat = [float(v) for p in pts for v in p]
    det, proven = insphere_dd(*flat)
    truth = _oracle(pts)
    s = insphere(*flat)
    assert ((s < 0) - (s > 0)) == truth  # insphere is the negative of Shewchuk's determinant
    if proven:
        assert (det > 0) - (det < 0) == truth
    return proven


# the predicates are exact for nonzero magnitudes in [2**-148, 2**200] (core/predicates.py)
coord = st.floats(-1e3, 1e3, allow_nan=False, allow_infinity=False, width=64).filter(lambda x: x == 0.0 or abs(x) >= 2.0**-148)


@settings(max_examples=300, deadline=None)
@given(st.lists(st.tuples(coord, coord, coord), min_size=5, max_size=5))
def test_random_points(pts):
    _check(pts)


def test_points_rounded_onto_a_sphere_are_decided():
    rng = np.random.default_rng(3)
    proven = 0
    cases = 300
    for i in range(cases):
        center = rng.uniform(-10, 10, 3)
        radius = 10.0 ** rng.uniform(-3, 2)
        # five nearby points, as in a surface mesh's Delaunay tetrahedralization, or spread
        v = rng.normal(size=(5, 3)) if i % 2 else np.array([0.0, 0.0, 1.0]) + 0.05 * rng.normal(size=(5, 3))
        pts = center + radius * v / np.linalg.norm(v, axis=1)[:, None]
        proven += _check(pts.tolist())
    assert proven >= 0.9 * cases  # the stage decides what stage A cannot, almost always


def test_exactly_cospherical_points_are_not_claimed():
    # integer points on the sphere of radius 25 (3-4-12-... triples), shifted and scaled by
    # powers of two (exact): the determinant is exactly zero
    sphere = [(0, 0, 25), (7, 0, 24), (0, 15, 20), (12, 16, 15), (-20, 0, 15), (9, 12, 20), (-16, -12, 15), (24, 7, 0)]
    rng = np.random.default_rng(5)
    for _ in range(60):
        idx = rng.choice(len(sphere), 5, replace=False)
        scale = 2.0 ** int(rng.integers(-30, 30))
        shift = float(rng.integers(-1000, 1000)) / 8.0
        pts = [[shift + scale * c for c in sphere[i]] for i in idx]
        assert _oracle(pts) == 0
        _, proven = insphere_dd(*[float(v) for p in pts for v in p])
        assert not proven
        assert insphere(*[float(v) for p in pts for v in p]) == 0.0


def test_one_ulp_off_a_sphere():
    sphere = [(0.0, 0.0, 25.0), (7.0, 0.0, 24.0), (0.0, 15.0, 20.0), (12.0, 16.0, 15.0), (-20.0, 0.0, 15.0)]
    decided = 0
    for j in range(5):
        for c in range(3):
            for direction in (np.inf, -np.inf):
                if sphere[j][c] == 0.0:
                    continue  # the next float after 0 is subnormal: outside the exactness range
                pts = [list(p) for p in sphere]
                pts[j][c] = float(np.nextafter(pts[j][c], direction))
                assert _oracle(pts) != 0
                decided += _check(pts)
    assert decided >= 20
