"""``core.jit.inner``: kernel-only helpers compiled without the Python-callable wrappers.

A kernel calling an ``inner`` helper gets the helper's result (checked against plain
Python arithmetic, also with an explicit signature), and a call from Python raises a
``TypeError`` naming the helper instead of entering code without an entry point (which
crashed the interpreter before the dispatcher class was set).
"""

from __future__ import annotations

import numpy as np
import pytest
from numba import njit

from meshwright.core.jit import InnerDispatcher, inner
from meshwright.core.flat import next3


@inner
def _twice_plus(a, i):
    return 2.0 * a[i] + 1.0


@inner("int64(int64, int64)")
def _mix(x, y):
    return 3 * x - y


@njit(cache=True)
def _kernel(a, x, y):
    s = 0.0
    for i in range(a.shape[0]):
        s += _twice_plus(a, i)
    return s, _mix(x, y)


def test_kernels_call_inner_helpers():
    a = np.array([0.5, -2.0, 7.25])
    s, m = _kernel(a, 11, 4)
    assert s == sum(2.0 * v + 1.0 for v in a.tolist())
    assert m == 3 * 11 - 4


@pytest.mark.parametrize("fn, args", [(_twice_plus, (np.ones(2), 0)), (_mix, (1, 2)), (next3, (1,))])
def test_a_call_from_python_raises_and_names_the_helper(fn, args):
    assert isinstance(fn, InnerDispatcher)
    with pytest.raises(TypeError, match=fn.py_func.__qualname__ + ".*kernel-only"):
        fn(*args)
