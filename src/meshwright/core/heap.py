r"""One binary min-heap over flat arrays, for the kernels' priority queues.

Source: J. W. J. Williams, "Algorithm 232: Heapsort", Comm. ACM 7(6), 1964 (the implicit
binary heap: the children of entry i are 2i + 1 and 2i + 2).

Entry layout (capacity ``cap``, the first ``n`` entries in use; ``n`` is kept by the caller,
in its own int64 header)::

    hkey (cap,)    any ordered dtype   key of entry i (int64 or float64)
    hval (cap, w)  int32               payload row of entry i: w ints the caller chooses
                                       (the advancing front: a face; Ruppert and the frontal
                                       Delaunay method: a triangle slot and its three
                                       vertices, so stale entries are recognised)

Invariant: ``hkey[(i - 1) // 2] <= hkey[i]`` for ``0 < i < n``; the top is entry 0.  Ties
leave the order unspecified (Ruppert's keys carry a sequence number for FIFO order).
Neither function checks capacity: callers reserve room before a step, as every kernel does
for its other arrays.

Usage: ``i = heap_push(hkey, hval, n, key)``, then write the payload ``hval[i, :]`` and
count ``n + 1``; to pop, read ``hkey[0]`` and ``hval[0, :]``, then ``heap_pop(hkey, hval, n)``
and count ``n - 1``.
"""

from __future__ import annotations

from numba import njit

__all__ = ["heap_push", "heap_pop"]


@njit(inline="always")
def _move(hval, src, dst, w):
    """Copy payload row ``src`` to row ``dst``."""
    for j in range(w):
        hval[dst, j] = hval[src, j]


@njit(inline="always")
def heap_push(hkey, hval, n, key):
    """Open the slot of a new entry with ``key`` in a heap of n entries; return it.

    Parameters
    ----------
    hkey : (cap,) int64 or float64
    hval : (cap, w) int32
    n : int
        Entries in use (``n < cap``).
    key : scalar of ``hkey.dtype``

    Returns
    -------
    int
        Slot i with ``hkey[i] = key`` written; the caller writes ``hval[i, :]``.
    """
    w = hval.shape[1]
    i = n
    while i > 0:
        p = (i - 1) >> 1
        if hkey[p] <= key:
            break
        hkey[i] = hkey[p]
        _move(hval, p, i, w)
        i = p
    hkey[i] = key
    return i


@njit(inline="always")
def heap_pop(hkey, hval, n):
    """Remove the top entry of a heap of n > 0 entries (read it first); n - 1 remain.

    Parameters
    ----------
    hkey : (cap,) int64 or float64
    hval : (cap, w) int32
    n : int
        Entries in use before the pop.
    """
    w = hval.shape[1]
    n -= 1
    if n == 0:
        return
    key = hkey[n]
    i = 0
    while True:
        c = 2 * i + 1
        if c >= n:
            break
        if c + 1 < n and hkey[c + 1] < hkey[c]:
            c += 1
        if hkey[c] >= key:
            break
        hkey[i] = hkey[c]
        _move(hval, c, i, w)
        i = c
    hkey[i] = key
    _move(hval, n, i, w)
