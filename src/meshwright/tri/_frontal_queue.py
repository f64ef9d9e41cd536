r"""The frontal Delaunay method's queue of waiting front triangles: a bucket queue over
triangle slots, largest ``R sqrt(3) / h`` first, from which a triangle's entry is deleted
when the triangle is.

Sources: R. B. Dial, "Algorithm 360: shortest-path forest with topological ordering",
Comm. ACM 12(11), 1969 (one list per integer priority, served in order); the lists are
doubly linked so that an entry leaves in O(1), as in a doubly linked bucket structure.

Why not :mod:`meshwright.core.heap`: a binary heap cannot delete an entry it does not
hold at its top, so the entries of triangles an insertion destroyed stayed queued and were
recognised only when popped: on the benchmark disk (289k triangles) 188,208 of 345,251
pops (54.5 %) were such stale entries, each a root-to-leaf sift and a read of a slot that
had been rewritten since.  Here each triangle slot holds at most one entry, the slot
itself, and the method deletes it wherever it rewrites or frees the slot (classifying a
new triangle, moving a triangle into a freed slot), so every pop is a live triangle.

Priorities are quantised: the bucket of ratio r is its position on a log2 scale with
``PER_OCTAVE`` steps per doubling (piecewise linear in the mantissa, so monotone in r),
the largest first; inside a bucket the newest entry is served first.  Ratios below 1 share
the last bucket and ratios of ``2**OCTAVES`` and more the first (scaffold triangles wait
with a lift of 1e3, ``frontal_delaunay.LIFT``, about 2**10).

Layout (``NB`` buckets; per triangle slot arrays of the slot capacity)::

    qhead (NB,)   int32  newest slot of bucket b, -1 when empty
    qnext (cap,)  int32  next older slot of the same bucket (-1 ends), while queued
    qprev (cap,)  int32  next newer slot of the same bucket (-1: the slot is the head)
    qbin  (cap,)  int32  bucket of the slot's entry, -1 when the slot is not queued
    qhdr  (2,)    int64  [Q_N] entries queued, [Q_LO] no bucket below it is non-empty
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["NB", "Q_LO", "Q_N", "fq_bucket", "fq_pop", "fq_push", "fq_remove", "new_frontal_queue"]

PER_OCTAVE = 256  # buckets per doubling of the ratio: ties within 0.2-0.4 %
OCTAVES = 24
NB = PER_OCTAVE * OCTAVES
Q_N = 0
Q_LO = 1


def new_frontal_queue(slots: int):
    """Empty queue arrays ``(qhead, qnext, qprev, qbin, qhdr)`` for ``slots`` triangle slots."""
    qhdr = np.zeros(2, dtype=np.int64)
    qhdr[Q_LO] = NB
    return (
        np.full(NB, -1, dtype=np.int32), np.empty(slots, dtype=np.int32), np.empty(slots, dtype=np.int32),
        np.full(slots, -1, dtype=np.int32), qhdr,
    )


@njit(inline="always")
def fq_bucket(ratio):
    """The bucket of a positive ``ratio`` (float): 0 for the largest ratios, ``NB - 1`` for
    those below 1."""
    m, e = math.frexp(ratio)  # ratio = m 2**e, 0.5 <= m < 1
    level = (e - 1) * PER_OCTAVE + int((2.0 * m - 1.0) * PER_OCTAVE)
    return NB - 1 - min(max(level, 0), NB - 1)


@njit(inline="always")
def fq_push(t, b, qhead, qnext, qprev, qbin, qhdr):
    """Queue slot t (not queued: ``qbin[t] < 0``) in bucket b."""
    h = qhead[b]
    qnext[t] = h
    qprev[t] = -1
    if h >= 0:
        qprev[h] = t
    qhead[b] = t
    qbin[t] = b
    qhdr[Q_N] += 1
    if b < qhdr[Q_LO]:
        qhdr[Q_LO] = b


@njit(inline="always")
def fq_remove(t, qhead, qnext, qprev, qbin, qhdr):
    """Take slot t's entry out of the queue, if it has one."""
    b = qbin[t]
    if b < 0:
        return
    n = qnext[t]
    p = qprev[t]
    if p >= 0:
        qnext[p] = n
    else:
        qhead[b] = n
    if n >= 0:
        qprev[n] = p
    qbin[t] = -1
    qhdr[Q_N] -= 1


@njit(inline="always")
def fq_pop(qhead, qnext, qprev, qbin, qhdr):
    """Remove and return the newest slot of the first non-empty bucket (``qhdr[Q_N] > 0``)."""
    b = qhdr[Q_LO]
    while qhead[b] < 0:
        b += 1
    qhdr[Q_LO] = b
    t = qhead[b]
    fq_remove(t, qhead, qnext, qprev, qbin, qhdr)
    return t
