"""Diametral-circle encroachment (exact), below the insertion kernel.

p encroaches the segment ab iff ``(a - p) . (b - p) < 0``: p lies strictly inside the circle
with diameter ab (Ruppert 1995; Shewchuk 2002).  The test lives here, not in
:mod:`meshwright.tri._encroach`, because the insertion kernel
(:func:`meshwright.tri._kernel2d.insert_arrays`) screens a refinement point's cavity with it,
and ``_encroach`` imports that kernel.
"""

from __future__ import annotations

import numpy as np

from meshwright.core.expansion import diff_into, estimate, expansion_sum, mul_small
from meshwright.core.jit import inner
from meshwright.core.predicates import CCW_ERRBOUND_A

__all__ = ["encroaches"]


@inner
def _dot_exact(ax, ay, bx, by, px, py):
    """``(a - p) . (b - p)`` rounded from its exact expansion (so its sign is exact)."""
    # Regions: four differences at 0..8, the two products at 8 and 16, scratch at 24,
    # the sum at 32 (each product has at most 8 components).
    w = np.empty(48)
    n1 = diff_into(ax, px, w, 0)
    n2 = diff_into(ay, py, w, 2)
    n3 = diff_into(bx, px, w, 4)
    n4 = diff_into(by, py, w, 6)
    m1 = mul_small(w, 0, n1, 4, n3, 1.0, 8, 24)
    m2 = mul_small(w, 2, n2, 6, n4, 1.0, 16, 24)
    n = expansion_sum(w, 8, m1, 16, m2, 1.0, 32)
    return estimate(w, 32, n)


@inner
def encroaches(ax, ay, bx, by, px, py):
    """Whether p lies strictly inside the diametral circle of ab (exact).

    Parameters
    ----------
    ax, ay, bx, by, px, py : float64

    Returns
    -------
    bool
        ``(a - p) . (b - p) < 0``.
    """
    l = (ax - px) * (bx - px)
    r = (ay - py) * (by - py)
    d = l + r
    bound = CCW_ERRBOUND_A * (abs(l) + abs(r))
    if d > bound:
        return False
    if d < -bound:
        return True
    return _dot_exact(ax, ay, bx, by, px, py) < 0.0
