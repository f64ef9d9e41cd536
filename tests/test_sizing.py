"""Tests of meshwright.sizing: size-field validation, Weatherill's dP and gradation."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from meshwright.core.errors import InputError, SizeError
from meshwright.sizing import (
    SizeField,
    as_size_field,
    boundary_size,
    gradation,
    minimum,
    point_distribution,
)

XY = np.array([[0.0, 0.0], [1.0, 2.0], [-3.0, 0.5]])


def test_constant():
    f = as_size_field(0.25)
    assert f.constant == 0.25
    np.testing.assert_array_equal(f(XY), [0.25] * 3)
    assert as_size_field(f) is f


@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan, math.inf, True, "0.1", None])
def test_bad_constants(bad):
    with pytest.raises(SizeError):
        as_size_field(bad)


def test_callable_and_object():
    f = as_size_field(lambda xy: 1.0 + xy[:, 0] ** 2)
    np.testing.assert_allclose(f(XY), [1.0, 2.0, 10.0])

    class Field:
        def __call__(self, xy):
            return 0.5

    np.testing.assert_array_equal(as_size_field(Field())(XY), [0.5] * 3)


def test_callable_errors_name_the_point():
    f = as_size_field(lambda xy: xy[:, 0])
    with pytest.raises(SizeError, match=r"h = -3.0 at \(-3, 0.5\)"):
        f(XY[[1, 2]])
    with pytest.raises(SizeError, match="h = nan"):
        as_size_field(lambda xy: np.full(len(xy), np.nan))(XY)
    with pytest.raises(SizeError, match="shape"):
        as_size_field(lambda xy: np.ones((len(xy), 2)))(XY)
    with pytest.raises(InputError, match=r"\(n, 2\)"):
        f(np.zeros(3))


def test_minimum():
    f = minimum(0.5, lambda xy: 0.1 + xy[:, 1])
    np.testing.assert_allclose(f(XY), [0.1, 0.5, 0.5])
    assert minimum(0.3, 0.2).constant == 0.2
    assert isinstance(f, SizeField)


def test_point_distribution_weatherill():
    # dP_i = (|x_{i+1} - x_i| + |x_i - x_{i-1}|) / 2 on a closed loop (chapter 18.1.3).
    rng = np.random.default_rng(3)
    ang = np.sort(rng.random(12)) * 2 * math.pi
    p = np.column_stack([np.cos(ang), np.sin(ang)]) * (1 + rng.random(12)[:, None])
    seg = np.column_stack([np.arange(12), (np.arange(12) + 1) % 12])
    nxt, prv = np.roll(p, -1, axis=0), np.roll(p, 1, axis=0)
    expected = 0.5 * (np.hypot(*(nxt - p).T) + np.hypot(*(p - prv).T))
    np.testing.assert_allclose(point_distribution(p, seg), expected)


def test_point_distribution_isolated_and_errors():
    dp = point_distribution([[0, 0], [2, 0], [5, 5]], [[0, 1]])
    assert dp[:2].tolist() == [2.0, 2.0] and math.isnan(dp[2])
    with pytest.raises(InputError, match="segment indices"):
        point_distribution([[0, 0], [1, 0]], [[0, 2]])


def test_gradation_matches_brute_force():
    rng = np.random.default_rng(0)
    src = rng.random((500, 2))
    h = 0.01 + 0.05 * rng.random(500)
    q = rng.random((2000, 2)) * 3 - 1
    f = gradation(src, h, growth=1.3)
    ref = np.min(
        h[None, :] + 0.3 * np.hypot(q[:, None, 0] - src[:, 0], q[:, None, 1] - src[:, 1]), axis=1
    )
    np.testing.assert_allclose(f(q), ref, rtol=1e-14)


@settings(max_examples=30, deadline=None)
@given(
    st.lists(
        st.tuples(st.floats(-5, 5), st.floats(-5, 5), st.floats(0.01, 2.0)), min_size=1, max_size=30
    ),
    st.floats(1.0, 3.0),
)
def test_gradation_is_lipschitz(sources, growth):
    s = np.array(sources)
    f = gradation(s[:, :2], s[:, 2], growth=growth, hmax=1.5)
    rng = np.random.default_rng(len(sources))
    a, b = rng.random((200, 2)) * 14 - 7, rng.random((200, 2)) * 14 - 7
    ha, hb = f(a), f(b)
    assert (np.abs(ha - hb) <= (growth - 1) * np.hypot(*(a - b).T) + 1e-12).all()
    assert (ha <= 1.5).all() and (f(s[:, :2]) <= s[:, 2] + 1e-15).all()


def test_gradation_options_and_errors():
    f = gradation([[0, 0]], 0.1, growth=2.0, base=lambda xy: 0.5 + 0 * xy[:, 0])
    np.testing.assert_allclose(f(np.array([[0.2, 0], [10, 0]])), [0.3, 0.5])
    assert gradation([[0, 0], [1, 0]], [0.2, 0.3], growth=1.0)(np.array([[9.0, 9.0]]))[0] == 0.2
    with pytest.raises(SizeError, match="growth"):
        gradation([[0, 0]], 0.1, growth=0.5)
    with pytest.raises(SizeError, match=r"source 1 at \(1, 0\)"):
        gradation([[0, 0], [1, 0]], [0.1, -1.0])
    with pytest.raises(SizeError, match="at least one"):
        gradation(np.zeros((0, 2)), 0.1)


def test_boundary_size_reproduces_spacing():
    n = 64
    ang = np.linspace(0, 2 * math.pi, n, endpoint=False)
    p = np.column_stack([np.cos(ang), np.sin(ang)])
    seg = np.column_stack([np.arange(n), (np.arange(n) + 1) % n])
    f = boundary_size(p, seg, growth=1.2)
    side = 2 * math.sin(math.pi / n)
    np.testing.assert_allclose(f(p), side)
    assert f(np.array([[0.0, 0.0]]))[0] == pytest.approx(side + 0.2)
