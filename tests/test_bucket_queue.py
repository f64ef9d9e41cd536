"""The bucket queue of Delaunay refinement (core/bucket_queue.py) against a plain Python model.

The oracle is one Python list per bucket, served lowest bucket first, newest entry first;
interleaved pushes and pops, entry reuse through the free list, and growth of the entry
arrays between operations are all checked against it.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from numba import njit

from meshwright.core.bucket_queue import Q_N, Q_USED, bq_pop, bq_push, new_queue
from meshwright.core.flat import grown_rows


@njit
def _push(head, nxt, val, hdr, b, x):
    e = bq_push(head, nxt, hdr, b)
    val[e, 0] = x
    val[e, 1] = -x
    return e


@njit
def _pop(head, nxt, val, hdr):
    e = bq_pop(head, nxt, hdr)
    return val[e, 0], val[e, 1]


_OPS = st.lists(st.one_of(st.integers(0, 15), st.none()), min_size=1, max_size=300)


@settings(max_examples=60, deadline=None)
@given(_OPS)
def test_pops_serve_lowest_bucket_newest_first(ops):
    nb = 16
    head, nxt, val, hdr = new_queue(nb, 2, 2)
    model = [[] for _ in range(nb)]
    count = 0
    for i, b in enumerate(ops):
        if b is None:
            if count == 0:
                continue
            want = next(q for q in model if q).pop()
            got = _pop(head, nxt, val, hdr)
            assert got == (want, -want)
            count -= 1
        else:
            if hdr[Q_N] + 1 > len(nxt):  # the caller's growth contract
                nxt = grown_rows(nxt, int(hdr[Q_N]) + 1)
                val = grown_rows(val, len(nxt))
            _push(head, nxt, val, hdr, b, i)
            model[b].append(i)
            count += 1
        assert hdr[Q_N] == count
        assert hdr[Q_USED] <= len(nxt)
    rest = [x for q in model for x in reversed(q)]
    got = [_pop(head, nxt, val, hdr)[0] for _ in rest]
    assert got == rest
    assert hdr[Q_N] == 0


def test_entries_are_reused_so_storage_stays_at_the_peak_count():
    head, nxt, val, hdr = new_queue(8, 4, 2)
    for r in range(1000):
        for b in (7, 0, 3):
            _push(head, nxt, val, hdr, b, r)
        for _ in range(3):
            _pop(head, nxt, val, hdr)
    assert hdr[Q_USED] == 3 and hdr[Q_N] == 0
    np.testing.assert_array_equal(head, -1)
