"""``core.borrowed``: array views without reference counting, for Numba kernels.

The oracle is NumPy itself: a kernel writing through borrowed views must change the caller's
arrays exactly as the same writes done in NumPy, nested tuples keep their members and
scalars, and a type the view cannot take is a typing error.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pytest
from numba import njit
from numba.core.errors import TypingError

from meshwright.core.borrowed import borrowed


class _Pair(NamedTuple):
    a: np.ndarray
    b: np.ndarray


@njit(inline="always")
def _bump(i, a, b):
    if a[i] > 0:
        b[i] += a[i]
    else:
        b[i] -= 1.0


@njit
def _kernel(p, scale):
    q = borrowed(p)
    a, b = q
    for i in range(a.shape[0]):
        _bump(i, a, b)
    nested = borrowed(((a, scale), b))
    nested[0][0][0] = nested[0][1]
    return b.sum()


def test_writes_through_views_reach_the_callers_arrays():
    rng = np.random.default_rng(3)
    a = rng.normal(size=50)
    b = rng.normal(size=50)
    want_b = np.where(a > 0, b + a, b - 1.0)
    want_a = a.copy()
    want_a[0] = 7.5
    p = _Pair(a, b)
    total = _kernel(p, 7.5)
    assert np.array_equal(p.b, want_b)
    assert np.array_equal(p.a, want_a)
    assert total == pytest.approx(want_b.sum(), rel=1e-15)


def test_strided_and_2d_views_keep_shape_and_strides():
    @njit
    def first_column_sum(x):
        y = borrowed(x)
        s = 0.0
        for i in range(y.shape[0]):
            s += y[i, 0]
        return s, y.shape[0], y.shape[1]

    x = np.arange(24.0).reshape(6, 4)[::2, 1:]
    s, n, m = first_column_sum(x)
    assert (n, m) == x.shape
    assert s == x[:, 0].sum()


def test_a_list_is_refused():
    @njit
    def bad(x):
        return borrowed(x)

    with pytest.raises(TypingError, match="borrowed"):
        bad([np.zeros(2)])
