"""The frontal Delaunay method's bucket queue (:mod:`meshwright.tri._frontal_queue`, over
:mod:`meshwright.core.bucket_queue`'s slot queue).

Oracles: a Python dict of the queued slots and their ratios; the order is checked by its
properties (largest first to one bucket's width, newest first among equal ratios), not by
recomputing buckets."""

from __future__ import annotations

import numpy as np
import pytest

from meshwright.core.bucket_queue import Q_LO, Q_N, sq_pop, sq_push, sq_remove
from meshwright.tri._frontal_queue import NB, OCTAVES, PER_OCTAVE, fq_bucket, new_frontal_queue


def _push(q, t, ratio):
    qhead, qnext, qprev, qbin, qhdr = q
    if qbin[t] < 0:
        sq_push(t, fq_bucket(ratio), qhead, qnext, qprev, qbin, qhdr)


def test_distinct_octaves_pop_largest_first():
    q = new_frontal_queue(64)
    ratios = {t: 2.0 ** (t % 20) * 1.5 for t in range(20)}
    for t in np.random.default_rng(3).permutation(20):
        _push(q, int(t), ratios[int(t)])
    out = [int(sq_pop(*q)) for _ in range(20)]
    assert [ratios[t] for t in out] == sorted(ratios.values(), reverse=True)
    assert q[4][Q_N] == 0 and (q[3] == -1).all()


def test_equal_ratios_pop_newest_first():
    q = new_frontal_queue(16)
    for t in (5, 2, 9, 7):
        _push(q, t, 1.7)
    assert [int(sq_pop(*q)) for _ in range(4)] == [7, 9, 2, 5]


def test_ratios_outside_the_range_share_the_end_buckets():
    assert fq_bucket(0.3) == fq_bucket(0.999) == NB - 1
    assert fq_bucket(2.0**OCTAVES) == fq_bucket(1e30) == 0
    assert fq_bucket(1.0) == NB - 1 and fq_bucket(2.0) == NB - 1 - PER_OCTAVE


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_random_pushes_removals_and_pops(seed):
    rng = np.random.default_rng(seed)
    cap = 300
    q = new_frontal_queue(cap)
    held = {}  # slot -> (ratio, push order)
    order = 0
    for _ in range(4000):
        op = rng.random()
        if op < 0.5:
            t = int(rng.integers(cap))
            if t not in held:
                r = float(np.exp(rng.uniform(-1.0, 12.0)))
                _push(q, t, r)
                held[t] = (r, order)
                order += 1
        elif op < 0.75 and held:
            t = int(rng.choice(list(held)))
            sq_remove(t, *q)
            sq_remove(t, *q)  # a second removal is a no-op
            del held[t]
        elif held:
            t = int(sq_pop(*q))
            assert t in held
            r, k = held.pop(t)
            rest = np.array([v[0] for v in held.values()] or [0.0])
            # Largest first, to within one bucket (at most 1 / PER_OCTAVE of the ratio);
            # ratios below 1 all tie.
            assert (rest <= max(r, 1.0) * (1.0 + 1.0 / PER_OCTAVE)).all()
            # Newest first among the ones at exactly the same ratio.
            assert all(v[1] < k for v in held.values() if v[0] == r)
        assert q[4][Q_N] == len(held)
        assert sorted(np.flatnonzero(q[3] >= 0).tolist()) == sorted(held)
    # The lists are consistent: walking every bucket finds exactly the queued slots.
    qhead, qnext, qprev, _, qhdr = q
    seen = []
    for b in range(NB):
        t, prev = qhead[b], -1
        while t >= 0:
            assert qprev[t] == prev
            seen.append(int(t))
            prev, t = t, qnext[t]
        if qhead[b] >= 0:
            assert b >= qhdr[Q_LO]
    assert sorted(seen) == sorted(held)
