"""Tests of meshwright.core.spatial_sort: Hilbert order and BRIO."""

import numpy as np
import pytest

from meshwright.core.errors import InputError
from meshwright.core.spatial_sort import brio_order, hilbert_keys, hilbert_order


def _is_permutation(order, n):
    return order.shape == (n,) and np.array_equal(np.sort(order), np.arange(n))


def _mean_step(points, order):
    return np.linalg.norm(np.diff(points[order], axis=0), axis=1).mean()


def test_hilbert_keys_visit_every_cell_once_along_adjacent_cells():
    # On a full 2**b x 2**b grid the keys are a bijection onto range(4**b) and consecutive
    # keys belong to edge-adjacent cells: the defining property of the Hilbert curve.
    b = 4
    k = 1 << b
    x, y = np.meshgrid(np.arange(k, dtype=float), np.arange(k, dtype=float))
    pts = np.column_stack([x.ravel(), y.ravel()])
    keys = hilbert_keys(pts, b)
    assert np.array_equal(np.sort(keys), np.arange(k * k))
    path = pts[np.argsort(keys)]
    steps = np.abs(np.diff(path, axis=0)).sum(axis=1)
    assert np.all(steps == 1.0)
    assert tuple(path[0]) == (0.0, 0.0) and tuple(path[-1]) == (k - 1.0, 0.0)


@pytest.mark.parametrize("n", [0, 1, 2, 17, 1000])
def test_hilbert_order_is_permutation(n):
    pts = np.random.default_rng(n).random((n, 2))
    assert _is_permutation(hilbert_order(pts), n)


def test_hilbert_order_degenerate_extent_and_ties_keep_input_order():
    pts = np.zeros((5, 2))
    assert np.array_equal(hilbert_order(pts), np.arange(5))
    line = np.column_stack([np.arange(6.0)[::-1], np.full(6, 3.0)])
    assert _is_permutation(hilbert_order(line), 6)


def test_hilbert_order_locality():
    pts = np.random.default_rng(1).random((20000, 2))
    sorted_step = _mean_step(pts, hilbert_order(pts))
    random_step = _mean_step(pts, np.arange(len(pts)))
    # Consecutive points along the curve are about 1/sqrt(n) apart, random ones about 0.5.
    assert sorted_step < 0.02 < 0.4 < random_step


def test_brio_permutation_and_determinism():
    pts = np.random.default_rng(2).random((5000, 2))
    a = brio_order(pts, np.random.default_rng(7))
    b = brio_order(pts, np.random.default_rng(7))
    c = brio_order(pts, np.random.default_rng(8))
    assert _is_permutation(a, len(pts))
    assert np.array_equal(a, b)
    assert not np.array_equal(a, c)


def test_brio_rounds_are_hilbert_sorted_and_growing():
    pts = np.random.default_rng(3).random((40000, 2))
    order = brio_order(pts, np.random.default_rng(0), min_round=100)
    keys = hilbert_keys(pts, 16)[order]
    # Round boundaries are where the Hilbert key drops; each round is sorted.
    starts = np.flatnonzero(np.diff(keys) < 0) + 1
    sizes = np.diff(np.concatenate([[0], starts, [len(pts)]]))
    assert 5 <= len(sizes) <= 12
    assert sizes[-1] > 0.4 * len(pts) and sizes[-2] > 0.15 * len(pts)
    # The whole order is still local except at the few round boundaries.
    assert _mean_step(pts, order) < 0.05


def test_brio_small_inputs():
    for n in range(0, 5):
        pts = np.random.default_rng(n).random((n, 2))
        assert _is_permutation(brio_order(pts, np.random.default_rng(0)), n)


def test_bits_validated():
    with pytest.raises(InputError, match="bits"):
        hilbert_order(np.zeros((3, 2)), bits=40)


def test_hilbert_keys_3d_visit_every_cell_once_along_adjacent_cells():
    # On a full 2**b cube grid the 3-D keys are a bijection onto range(8**b) and consecutive
    # keys belong to face-adjacent cells.
    b = 3
    k = 1 << b
    g = np.stack(np.meshgrid(*[np.arange(k, dtype=float)] * 3, indexing="ij"), -1).reshape(-1, 3)
    keys = hilbert_keys(g, b)
    assert np.array_equal(np.sort(keys), np.arange(k**3))
    path = g[np.argsort(keys)]
    assert np.all(np.abs(np.diff(path, axis=0)).sum(axis=1) == 1.0)
    assert tuple(path[0]) == (0.0, 0.0, 0.0)


def test_brio_order_3d_is_a_local_permutation():
    pts = np.random.default_rng(2).random((20000, 3))
    order = brio_order(pts, np.random.default_rng(0))
    assert _is_permutation(order, len(pts))
    last = order[len(pts) // 2 :]  # the last round is Hilbert-sorted: short steps
    assert _mean_step(pts, last) < 0.25 * _mean_step(pts, np.arange(len(pts)))
    assert _is_permutation(hilbert_order(pts), len(pts))


@pytest.mark.parametrize("bad", [np.zeros((3, 4)), np.zeros(5)])
def test_spatial_sort_rejects_other_shapes(bad):
    with pytest.raises(InputError, match="shape"):
        brio_order(bad, np.random.default_rng(0))


def test_3d_bits_limit():
    with pytest.raises(InputError, match="bits"):
        hilbert_order(np.zeros((3, 3)), bits=20)


def _reference_keys(pts, bits):
    """Per-level Hilbert index in plain Python (the textbook rotate-and-reflect loop)."""
    lo = pts.min(axis=0)
    ext = pts.max(axis=0) - lo
    side = 1 << bits
    out = []
    for px, py in pts:
        x = min(int((px - lo[0]) * (side / ext[0] if ext[0] else 0.0)), side - 1)
        y = min(int((py - lo[1]) * (side / ext[1] if ext[1] else 0.0)), side - 1)
        d = 0
        s = side >> 1
        while s:
            rx = 1 if x & s else 0
            ry = 1 if y & s else 0
            d += s * s * ((3 * rx) ^ ry)
            if ry == 0:
                if rx == 1:
                    x ^= s - 1
                    y ^= s - 1
                x, y = y, x
            s >>= 1
        out.append(d)
    return np.array(out, dtype=np.int64)


@pytest.mark.parametrize("bits", [1, 2, 3, 4, 5, 6, 7, 9, 16, 26])
def test_table_driven_keys_match_per_level_reference(bits):
    rng = np.random.default_rng(bits)
    for pts in (rng.random((300, 2)), rng.integers(0, 9, (300, 2)).astype(float)):
        assert np.array_equal(hilbert_keys(pts, bits), _reference_keys(pts, bits))


@pytest.mark.parametrize("n", [2, 3, 1000, 50000])
def test_orders_equal_stable_argsort(n):
    rng = np.random.default_rng(n)
    # Few distinct cells: many equal keys, whose input order must survive.
    pts = rng.integers(0, 7, (n, 2)).astype(float)
    assert np.array_equal(hilbert_order(pts, 3), np.argsort(hilbert_keys(pts, 3), kind="stable"))
    pts = rng.random((n, 2))
    keys = hilbert_keys(pts, 16)
    assert np.array_equal(hilbert_order(pts), np.argsort(keys, kind="stable"))
    # BRIO: the same composite (round, key) order as a stable argsort would give.
    a = brio_order(pts, np.random.default_rng(3))
    rounds = max(1, int(np.floor(np.log2(max(n, 1) / 128))) + 1)
    if rounds > 1:
        back = np.minimum(np.random.default_rng(3).geometric(0.5, size=n), rounds)
        keys = keys | ((rounds - back) << 32)
    assert np.array_equal(a, np.argsort(keys, kind="stable"))
