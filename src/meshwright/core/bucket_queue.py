r"""A bucket queue over flat arrays: small integer priorities, newest first inside a bucket.

Sources: R. B. Dial, "Algorithm 360: shortest-path forest with topological ordering",
Comm. ACM 12(11), 1969 (one list per integer priority, the lowest non-empty served first);
J. R. Shewchuk, Triangle (1996), whose bad-triangle queue is such a structure (4096 lists,
FIFO inside each).  Against a binary heap (:mod:`meshwright.core.heap`) a push or pop
touches one or two entries instead of a root-to-leaf path, which matters when the queue
holds a large part of a mesh and that path misses the cache at every level.  Inside a
bucket the newest entry is served first (a stack, unlike Triangle): Delaunay refinement
then works where it just worked, on data still in the cache (measured in
``benchmarks/README.md``).

Layout (``nb`` buckets, ``cap`` entries, payload rows of ``w`` ints)::

    head (nb,)     int32  newest entry of bucket b, -1 when the bucket is empty
    nxt  (cap,)    int32  next older entry of the same bucket, or next free entry; -1 ends
    val  (cap, w)  int32  payload row of each entry (the caller's)
    hdr  (4,)      int64  [Q_N] entries queued, [Q_FREE] first free entry (-1: none),
                          [Q_LO] no bucket below it is non-empty, [Q_USED] entries ever handed out

Invariants: bucket b's entries run from ``head[b]`` along ``nxt``, newest first; every entry
below ``hdr[Q_USED]`` is queued or on the free list; ``hdr[Q_USED] <= cap``.  Neither
function checks capacity: a push needs ``hdr[Q_N] < cap`` (then ``hdr[Q_USED] < cap`` or a
free entry exists), which callers reserve before a step as for their other arrays; ``nxt``
and ``val`` grow by copying (:func:`meshwright.core.flat.grown_rows`).

Usage: ``e = bq_push(head, nxt, hdr, b)``, then write ``val[e, :]``; to pop,
``e = bq_pop(head, nxt, hdr)`` (``hdr[Q_N] > 0``) and read ``val[e, :]`` before the next
push, which may reuse the entry.

**Slot queue** (``sq_*``): the same buckets, but the entries are the caller's own slots
(say triangle slots), at most one each and no payload, doubly linked so that a slot's
entry leaves in O(1) when the slot is rewritten; a heap cannot delete an entry below its
top, so its stale entries are popped and skipped instead (frontal Delaunay: 54.5 % of its
pops on the benchmark disk).  Layout, ``cap`` the slot capacity::

    head (nb,)   int32  newest slot of bucket b, -1 when empty
    nxt  (cap,)  int32  next older slot of the same bucket (-1 ends), while queued
    prv  (cap,)  int32  next newer slot of the same bucket (-1: the slot is the head)
    sbin (cap,)  int32  bucket of the slot's entry, -1 when the slot is not queued
    hdr  (4,)    int64  [Q_N] and [Q_LO] as above ([Q_FREE], [Q_USED] unused)

``nxt``, ``prv`` and ``sbin`` grow with the slots (``sbin`` filled with -1).
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = [
    "Q_FREE", "Q_LO", "Q_N", "Q_USED", "bq_pop", "bq_push", "new_queue", "new_slot_queue", "sq_pop", "sq_push",
    "sq_remove",
]

Q_N = 0
Q_FREE = 1
Q_LO = 2
Q_USED = 3


def new_queue(nb: int, cap: int, w: int):
    """Empty queue arrays ``(head (nb,) int32, nxt (cap,) int32, val (cap, w) int32, hdr (4,) int64)``."""
    hdr = np.zeros(4, dtype=np.int64)
    hdr[Q_FREE] = -1
    hdr[Q_LO] = nb
    return np.full(nb, -1, dtype=np.int32), np.empty(cap, dtype=np.int32), np.empty((cap, w), dtype=np.int32), hdr


@njit(inline="always")
def bq_push(head, nxt, hdr, b):
    """Add a new entry to bucket b (``0 <= b < nb``); return it for the payload write.

    Parameters
    ----------
    head : (nb,) int32
    nxt : (cap,) int32
    hdr : (4,) int64
    b : int

    Returns
    -------
    int
        The entry (a free one if any, the most recently freed first); the caller writes
        ``val[e, :]``.
    """
    e = hdr[Q_FREE]
    if e >= 0:
        hdr[Q_FREE] = nxt[e]
    else:
        e = hdr[Q_USED]
        hdr[Q_USED] = e + 1
    nxt[e] = head[b]
    head[b] = e
    hdr[Q_N] += 1
    hdr[Q_LO] = min(hdr[Q_LO], b)
    return e


@njit(inline="always")
def bq_pop(head, nxt, hdr):
    """Remove the newest entry of the lowest non-empty bucket (``hdr[Q_N] > 0``); return it.

    The entry goes to the free list; its payload stays readable until the next push.
    """
    b = hdr[Q_LO]
    while head[b] < 0:
        b += 1
    e = head[b]
    head[b] = nxt[e]
    hdr[Q_LO] = b
    hdr[Q_N] -= 1
    nxt[e] = hdr[Q_FREE]
    hdr[Q_FREE] = e
    if hdr[Q_N] == 0:
        hdr[Q_LO] = head.shape[0]
    return e


def new_slot_queue(nb: int, cap: int):
    """Empty slot-queue arrays ``(head (nb,), nxt (cap,), prv (cap,), sbin (cap,))`` int32 and
    ``hdr (4,)`` int64."""
    hdr = np.zeros(4, dtype=np.int64)
    hdr[Q_LO] = nb
    return (
        np.full(nb, -1, dtype=np.int32), np.empty(cap, dtype=np.int32), np.empty(cap, dtype=np.int32),
        np.full(cap, -1, dtype=np.int32), hdr,
    )


@njit(inline="always")
def sq_push(t, b, head, nxt, prv, sbin, hdr):
    """Queue slot t (not queued: ``sbin[t] < 0``) in bucket b."""
    h = head[b]
    nxt[t] = h
    prv[t] = -1
    if h >= 0:
        prv[h] = t
    head[b] = t
    sbin[t] = b
    hdr[Q_N] += 1
    if b < hdr[Q_LO]:
        hdr[Q_LO] = b


@njit(inline="always")
def sq_remove(t, head, nxt, prv, sbin, hdr):
    """Take slot t's entry out of the queue, if it has one."""
    b = sbin[t]
    if b < 0:
        return
    n = nxt[t]
    p = prv[t]
    if p >= 0:
        nxt[p] = n
    else:
        head[b] = n
    if n >= 0:
        prv[n] = p
    sbin[t] = -1
    hdr[Q_N] -= 1


@njit(inline="always")
def sq_pop(head, nxt, prv, sbin, hdr):
    """Remove and return the newest slot of the lowest non-empty bucket (``hdr[Q_N] > 0``)."""
    b = hdr[Q_LO]
    while head[b] < 0:
        b += 1
    hdr[Q_LO] = b
    t = head[b]
    sq_remove(t, head, nxt, prv, sbin, hdr)
    return t
