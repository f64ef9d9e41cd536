"""The graded size field's cone minimum (``sizing.boundary._cone_min``) is exact.

``gradation(points, sizes, g, hmax, base)(q)`` must equal, bit for bit, the brute-force
``min(hmax, base(q), min_i h_i + (g - 1) sqrt(dx_i^2 + dy_i^2))`` written here in plain
NumPy (the same three operations per source, no shared code): on random sources, on a
graded wall (a cosine-spaced airfoil-like loop, queries in raster and in random order, so
the search's warm start from the previous query is both useful and useless), on thin
source sets (the grid's thin-box path), on queries far outside the sources' box, where
the cap decides, and on coincident sources.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from meshwright.sizing import gradation


def brute(src, h, slope, q, upper):
    """min(upper, min_i h_i + slope sqrt(dx^2 + dy^2)), in chunks of queries."""
    out = np.empty(len(q))
    for a in range(0, len(q), 512):
        ex = q[a : a + 512, None, 0] - src[None, :, 0]
        ey = q[a : a + 512, None, 1] - src[None, :, 1]
        out[a : a + 512] = np.minimum(upper[a : a + 512], (h[None, :] + slope * np.sqrt(ex * ex + ey * ey)).min(axis=1))
    return out


def wall(k):
    """A closed cosine-spaced loop of 2 k points round a thin symmetric section, with the
    spacing at each point as its size."""
    x = 0.5 * (1.0 - np.cos(np.linspace(0.0, math.pi, k + 1)))
    y = 0.6 * (0.2969 * np.sqrt(x) - 0.1260 * x - 0.3516 * x**2 + 0.2843 * x**3 - 0.1015 * x**4)
    pts = np.concatenate([np.column_stack([x, -y]), np.column_stack([x[::-1], y[::-1]])[1:-1]])
    ln = np.hypot(*(np.roll(pts, -1, axis=0) - pts).T)
    return pts, 0.5 * (ln + np.roll(ln, 1))


def raster(x0, y0, x1, y1, n):
    xs, ys = np.meshgrid(np.linspace(x0, x1, n), np.linspace(y0, y1, n))
    return np.column_stack([xs.ravel(), ys.ravel()])


@pytest.mark.parametrize("growth", [1.05, 1.2, 2.0])
@pytest.mark.parametrize("hmax", [None, 0.3])
def test_graded_wall_is_the_exact_minimum(growth, hmax):
    src, h = wall(120)
    f = gradation(src, h, growth, hmax)
    rng = np.random.default_rng(1)
    q = np.concatenate([raster(-1, -1, 2, 1, 90), rng.uniform(-3, 4, (4000, 2)),
                        0.5 * (src[1:] + src[:-1]) + rng.normal(0, 1e-4, (len(src) - 1, 2))])
    upper = np.full(len(q), np.inf if hmax is None else hmax)
    for qq, uu in ((q, upper), (q[rng.permutation(len(q))], upper)):
        want = brute(src, h, growth - 1.0, qq, uu)
        assert np.array_equal(f(qq), want)


@pytest.mark.parametrize("n", [1, 2, 7, 300, 3000])
def test_random_sources_are_the_exact_minimum(n):
    rng = np.random.default_rng(n)
    src = rng.uniform(-1, 1, (n, 2)) * 10.0 ** rng.uniform(-3, 3)
    h = 10.0 ** rng.uniform(-6, -1, n)
    scale = float(np.abs(src).max()) + 1e-300
    q = np.concatenate([rng.uniform(-1.5, 1.5, (3000, 2)) * scale, rng.uniform(-1e4, 1e4, (200, 2)) * scale, src])
    f = gradation(src, h, 1.2, None)
    assert np.array_equal(f(q), brute(src, h, 1.2 - 1.0, q, np.full(len(q), np.inf)))


def test_cap_and_base_decide_far_away():
    src, h = wall(60)
    base = 0.05
    f = gradation(src, h, 1.2, 1.0, base=lambda xy: np.full(len(xy), base))
    q = np.concatenate([raster(-50, -50, 50, 50, 40), raster(-0.2, -0.2, 1.2, 0.2, 40)])
    want = brute(src, h, 1.2 - 1.0, q, np.full(len(q), base))
    got = f(q)
    assert np.array_equal(got, want)
    assert (got == base).mean() > 0.5 and (got < base).any()


@pytest.mark.parametrize("aspect", [1e-2, 1e-4, 0.0])
def test_thin_and_flat_source_sets(aspect):
    rng = np.random.default_rng(3)
    t = np.sort(rng.random(400))
    src = np.column_stack([t, aspect * rng.random(400)])
    h = 1e-3 + 1e-2 * rng.random(400)
    q = np.concatenate([np.column_stack([np.linspace(-0.1, 1.1, 2000), np.full(2000, 0.5 * aspect)]),
                        rng.uniform(-0.5, 1.5, (2000, 2))])
    f = gradation(src, h, 1.3, None)
    assert np.array_equal(f(q), brute(src, h, 1.3 - 1.0, q, np.full(len(q), np.inf)))


def test_coincident_sources_take_the_smaller_size():
    src = np.array([[0.5, 0.5]] * 5 + [[0.0, 0.0], [1.0, 1.0]])
    h = np.array([0.3, 0.1, 0.2, 0.05, 0.4, 0.2, 0.2])
    q = raster(-1, -1, 2, 2, 50)
    f = gradation(src, h, 1.5, None)
    assert np.array_equal(f(q), brute(src, h, 1.5 - 1.0, q, np.full(len(q), np.inf)))


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 80), st.floats(1.0, 3.0), st.floats(-8, 8))
def test_hypothesis_exact_minimum(seed, n, growth, log_scale):
    rng = np.random.default_rng(seed)
    s = 10.0**log_scale
    src = (rng.uniform(-1, 1, (n, 2)) + rng.uniform(-1e3, 1e3, 2)) * s
    h = s * 10.0 ** rng.uniform(-4, 0, n)
    q = np.concatenate([src.mean(axis=0) + rng.normal(0, 2, (300, 2)) * s, src + rng.normal(0, 1e-3, (n, 2)) * s])
    hmax = float(s * rng.uniform(0.1, 2))
    f = gradation(src, h, growth, hmax)
    assert np.array_equal(f(q), brute(src, h, growth - 1.0, q, np.full(len(q), hmax)))
