"""The cheap exact stages of orient2d / incircle (core/exact_stages2d.py) against Fraction arithmetic.

Every stage may decline (``proven`` false) but must never claim a wrong sign; on the inputs
each stage exists for (grids for stage E, rounded points on a circle for stage D) it must
also decide, or the fast path would silently never run.  The oracle is exact rational
arithmetic on the lifted 4x4 / homogeneous 3x3 determinants, sharing no code with the
stages or with the expansion arithmetic.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numba import njit

from meshwright.core.exact_stages2d import incircle_dd, incircle_eft, orient2d_eft
from meshwright.core.predicates import incircle, incircle_sos, orient2d


@njit(cache=True)
def _stages(q):
    """Run every stage on each row ``(ax, ay, bx, by, cx, cy, dx, dy)`` of q."""
    m = q.shape[0]
    out = np.empty((m, 6))
    for i in range(m):
        ax, ay, bx, by, cx, cy, dx, dy = q[i, 0], q[i, 1], q[i, 2], q[i, 3], q[i, 4], q[i, 5], q[i, 6], q[i, 7]
        e, pe = incircle_eft(ax, ay, bx, by, cx, cy, dx, dy)
        d, pd = incircle_dd(ax, ay, bx, by, cx, cy, dx, dy)
        o, po = orient2d_eft(ax, ay, bx, by, cx, cy)
        out[i, 0] = e
        out[i, 1] = 1.0 if pe else 0.0
        out[i, 2] = d
        out[i, 3] = 1.0 if pd else 0.0
        out[i, 4] = o
        out[i, 5] = 1.0 if po else 0.0
    return out


def sgn(x) -> int:
    return int(x > 0) - int(x < 0)


def det(rows) -> Fraction:
    """Determinant by Laplace expansion along the first row (small matrices only)."""
    if len(rows) == 1:
        return rows[0][0]
    total = Fraction(0)
    for j, v in enumerate(rows[0]):
        if v:
            minor = [r[:j] + r[j + 1 :] for r in rows[1:]]
            total += (-1) ** j * v * det(minor)
    return total


def ref_orient(a, b, c) -> int:
    return sgn(det([[Fraction(p[0]), Fraction(p[1]), Fraction(1)] for p in (a, b, c)]))


def ref_incircle(pts) -> int:
    """Sign of the lifted determinant det[x, y, x**2 + y**2, 1]: positive when d is inside ccw a, b, c."""
    return sgn(_lifted_value(pts, (0, 0, 0, 0)))


def test_oracle_convention():
    a, b, c = (1.0, 0.0), (0.0, 1.0), (-1.0, 0.0)
    assert ref_orient(a, b, c) == 1
    assert ref_incircle((a, b, c, (0.0, 0.0))) == 1
    assert ref_incircle((a, b, c, (3.0, 0.0))) == -1
    assert ref_incircle((a, b, c, (0.0, -1.0))) == 0


def check_rows(q: np.ndarray) -> np.ndarray:
    """Assert every proven stage's sign on the rows of q; return the proven flags (m, 3)."""
    out = _stages(np.ascontiguousarray(q, dtype=np.float64))
    for row, r in zip(q, out):
        pts = [tuple(row[2 * i : 2 * i + 2]) for i in range(4)]
        exact_ic = ref_incircle(pts)
        exact_o = ref_orient(*pts[:3])
        if r[1]:
            assert sgn(r[0]) == exact_ic, (row.tolist(), "stage E incircle")
        if r[3]:
            assert sgn(r[2]) == exact_ic, (row.tolist(), "stage D incircle")
            assert exact_ic != 0
        if r[5]:
            assert sgn(r[4]) == exact_o, (row.tolist(), "stage E orient2d")
        assert sgn(incircle(*row)) == exact_ic, row.tolist()
        assert sgn(orient2d(*row[:6])) == exact_o, row.tolist()
    return out[:, [1, 3, 5]] > 0


def grid_rows(rng, m, scale=1.0, offset=0.0):
    """Four points of a small integer grid (many cocircular and collinear), scaled."""
    g = rng.integers(-4, 5, size=(m, 8)).astype(float)
    base = rng.integers(-1000, 1000, size=(m, 1)).astype(float)
    return (g + base) * scale + offset


@pytest.mark.parametrize("scale", [1.0, 2.0**-30, 2.0**40, 0.25])
def test_grid_inputs_decided_by_stage_e(scale):
    rng = np.random.default_rng(1)
    q = grid_rows(rng, 400, scale)
    proven = check_rows(q)
    assert proven[:, 0].all() and proven[:, 2].all()
    exact = [ref_incircle([tuple(r[2 * i : 2 * i + 2]) for i in range(4)]) for r in q]
    assert exact.count(0) > 20  # degenerate cases are really exercised


def test_unit_squares_are_exact_zero():
    rng = np.random.default_rng(2)
    x0 = rng.integers(0, 10**6, 200).astype(float)
    y0 = rng.integers(0, 10**6, 200).astype(float)
    q = np.column_stack([x0, y0, x0 + 1, y0, x0 + 1, y0 + 1, x0, y0 + 1])
    out = _stages(q)
    assert (out[:, 1] == 1).all() and (out[:, 0] == 0).all()
    assert (np.array([incircle(*r) for r in q]) == 0).all()


def circle_rows(rng, m, spread):
    t = rng.random((m, 1)) * 2 * np.pi + np.sort(rng.random((m, 4)), axis=1) * spread
    return np.column_stack([np.cos(t[:, 0]), np.sin(t[:, 0]), np.cos(t[:, 1]), np.sin(t[:, 1]),
                            np.cos(t[:, 2]), np.sin(t[:, 2]), np.cos(t[:, 3]), np.sin(t[:, 3])])


@pytest.mark.parametrize("spread", [6.0, 1.0, 1e-3])
def test_rounded_circle_points_decided_by_stage_d(spread):
    rng = np.random.default_rng(3)
    q = circle_rows(rng, 300, spread)
    proven = check_rows(q)
    assert proven[:, 1].mean() > 0.95


def test_one_ulp_perturbations():
    rng = np.random.default_rng(4)
    q = grid_rows(rng, 300, 1.0)
    # Cocircular and collinear quadruples, then one coordinate moved by one ulp either way.
    for i in range(q.shape[0]):
        j = rng.integers(0, 8)
        q[i, j] = np.nextafter(q[i, j], np.inf if rng.random() < 0.5 else -np.inf)
    check_rows(q)
    sq = np.array([[0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0]] * 16)
    for k in range(16):
        sq[k, k % 8] = np.nextafter(sq[k, k % 8], np.inf if k < 8 else -np.inf)
    check_rows(sq)


def test_inexact_differences():
    rng = np.random.default_rng(5)
    base = rng.random((300, 8)) * np.array([1.0, 1e-9, 1e6, 1.0, 3.0, 1e-3, 7.0, 1e9])
    check_rows(base)
    tiny = 1.0 + rng.integers(-3, 4, (300, 8)) * 2.0**-52
    check_rows(tiny)


finite = st.floats(min_value=-1e3, max_value=1e3, allow_nan=False, allow_infinity=False, allow_subnormal=False)
small_ints = st.integers(-20, 20).map(float)


@settings(max_examples=300, deadline=None)
@given(st.lists(finite | small_ints, min_size=8, max_size=8))
def test_random_rows_match_fraction(v):
    v = [0.0 if (x != 0.0 and abs(x) < 2.0**-100) else x for x in v]
    check_rows(np.array([v]))


def ref_incircle_sos(pts, idx) -> int:
    """Perturbed sign: the lift of point i raised by eps**(N - idx[i]), eps -> 0+."""
    s = ref_incircle(pts)
    if s:
        return s
    for i in sorted(range(4), key=lambda k: -idx[k]):
        # The lifted determinant is linear in each lift: its derivative is a difference.
        extra = [0, 0, 0, 0]
        extra[i] = 1
        d1 = _lifted_value(pts, extra) - _lifted_value(pts, (0, 0, 0, 0))
        if d1:
            return sgn(d1)
    return 0


def _lifted_value(pts, extra) -> Fraction:
    rows = []
    for p, e in zip(pts, extra):
        x, y = Fraction(p[0]), Fraction(p[1])
        rows.append([x, y, x * x + y * y + e, Fraction(1)])
    return det(rows)


@pytest.mark.parametrize("seed", range(4))
def test_incircle_sos_on_grids_matches_perturbed_fraction(seed):
    rng = np.random.default_rng(10 + seed)
    q = grid_rows(rng, 150, 1.0)
    for row in q:
        pts = [tuple(row[2 * i : 2 * i + 2]) for i in range(4)]
        if ref_orient(*pts[:3]) == 0 or len(set(pts)) < 4:
            continue
        idx = [int(k) for k in rng.choice(100, 4, replace=False)]
        assert incircle_sos(*row, *idx) == ref_incircle_sos(pts, idx), (row.tolist(), idx)
