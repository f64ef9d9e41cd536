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

The queue itself is :mod:`meshwright.core.bucket_queue`'s slot queue (``sq_push``,
``sq_remove``, ``sq_pop``: the slots' arrays ``qhead (NB,)``, ``qnext``, ``qprev``, ``qbin``
``(cap,)`` int32 and ``qhdr (4,)`` int64); this module gives its buckets.
"""

from __future__ import annotations

import math

from numba import njit

from meshwright.core.bucket_queue import new_slot_queue

__all__ = ["NB", "OCTAVES", "PER_OCTAVE", "fq_bucket", "new_frontal_queue"]

PER_OCTAVE = 256  # buckets per doubling of the ratio: ties within 0.2-0.4 %
OCTAVES = 24
NB = PER_OCTAVE * OCTAVES


def new_frontal_queue(slots: int):
    """Empty queue arrays ``(qhead, qnext, qprev, qbin, qhdr)`` for ``slots`` triangle slots."""
    return new_slot_queue(NB, slots)


@njit(inline="always")
def fq_bucket(ratio):
    """The bucket of a positive ``ratio`` (float): 0 for the largest ratios, ``NB - 1`` for
    those below 1."""
    m, e = math.frexp(ratio)  # ratio = m 2**e, 0.5 <= m < 1
    level = (e - 1) * PER_OCTAVE + int((2.0 * m - 1.0) * PER_OCTAVE)
    return NB - 1 - min(max(level, 0), NB - 1)
