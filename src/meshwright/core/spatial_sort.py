"""Spatial sorting of 2-D and 3-D points: Hilbert-curve order and biased randomized insertion order.

Incremental Delaunay insertion is fast when consecutive points are close (the point
location walk is short and the touched triangles are still in cache) and robustly fast
when the order is random (expected O(n log n) total cavity work).  BRIO gets both.

Sources
-------
* D. Hilbert, "Über die stetige Abbildung einer Linie auf ein Flächenstück",
  Mathematische Annalen 38:459-460, 1891: the space-filling curve.
* J. Skilling, "Programming the Hilbert curve", AIP Conference Proceedings 707:381-387,
  2004: the transpose form of the d-dimensional curve, used for 3-D points.
* N. Amenta, S. Choi and G. Rote, "Incremental constructions con BRIO", Proc. 19th ACM
  Symposium on Computational Geometry, 211-219, 2003: biased randomized insertion order.

Hilbert order
-------------
Each coordinate is quantised to ``bits`` bits on the bounding box of the points (each axis
scaled separately), and the cell index along the Hilbert curve of order ``bits`` is computed
iteratively, from the most significant bit down: at every level the quadrant ``(rx, ry)``
selects one of four sub-squares, visited in the order::

      ry=1 | 1 | 2 |      quadrant index q = (3 rx) xor ry
           +---+---+      the curve enters at (0, 0) and leaves at (2**bits - 1, 0);
      ry=0 | 0 | 3 |      quadrants 0 and 3 are transposed (3 also mirrored)
             rx=0 rx=1    so that the sub-curves join end to end.

In 3-D each axis is quantised the same way and Skilling's algorithm turns the cell
coordinates into the "transposed" Hilbert index (inverse undo of the excess work, Gray
encoding), whose bits interleaved from the most significant down are the index along the
curve; consecutive indices are face-adjacent cells.  The 2-D keys are unchanged.

The 2-D keys are computed four levels at a time from a 1024-entry table of the curve's
four states (transpose, mirror: they commute, so their compositions are four).  The
permutation is a stable LSD radix sort of the keys (digits of at most 12 bits, passes over
a constant digit skipped), so equal cells keep their input order.

BRIO
----
Every point falls independently into round ``r`` with probability ``2**-(R - r)`` (the last
round ``R - 1`` takes about half the points, the one before a quarter, ...); rounds smaller
than ``min_round`` points are merged into round 0.  Rounds are inserted one after the other,
each in Hilbert order.  Sorting once by the composite key ``(round, hilbert)`` gives the whole
order in one sort.

Arrays
------
points : (n, 2) or (n, 3) float64, finite.  Keys : (n,) int64 in ``[0, 2**(d bits))``.
Permutations : (n,) int64, ``points[order]`` is the sorted sequence.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.jit import inner

__all__ = ["hilbert_keys", "hilbert_order", "brio_order"]

_MAX_BITS = 26  # 2 * 26 key bits plus the round number still fit in an int64
_MAX_BITS_3D = 19  # 3 * 19 key bits plus the round number still fit in an int64


@njit(cache=True)
def _hilbert_keys_3d(points, bits):
    """Hilbert index of every 3-D point (Skilling's transpose algorithm), see the module docstring."""
    n = points.shape[0]
    keys = np.zeros(n, dtype=np.int64)
    if n == 0:
        return keys
    lo = np.empty(3)
    hi = np.empty(3)
    for a in range(3):
        lo[a] = points[0, a]
        hi[a] = points[0, a]
    for i in range(1, n):
        for a in range(3):
            lo[a] = min(lo[a], points[i, a])
            hi[a] = max(hi[a], points[i, a])
    side = 1 << bits
    top = side - 1
    sc = np.empty(3)
    for a in range(3):
        sc[a] = 0.0 if hi[a] == lo[a] else side / (hi[a] - lo[a])
    x = np.empty(3, dtype=np.int64)
    for i in range(n):
        for a in range(3):
            x[a] = min(np.int64((points[i, a] - lo[a]) * sc[a]), top)
        q = np.int64(1) << (bits - 1)
        while q > 1:
            p = q - 1
            for a in range(3):
                if x[a] & q:
                    x[0] ^= p
                else:
                    t = (x[0] ^ x[a]) & p
                    x[0] ^= t
                    x[a] ^= t
            q >>= 1
        x[1] ^= x[0]
        x[2] ^= x[1]
        t = np.int64(0)
        q = np.int64(1) << (bits - 1)
        while q > 1:
            if x[2] & q:
                t ^= q - 1
            q >>= 1
        for a in range(3):
            x[a] ^= t
        d = np.int64(0)
        for b in range(bits - 1, -1, -1):
            for a in range(3):
                d = (d << 1) | ((x[a] >> b) & 1)
        keys[i] = d
    return keys


@inner
def _hilbert_step(state, rx, ry):
    """One level of the 2-D curve: ``(quadrant index, next state)`` for the raw cell bits.

    ``state`` records the transform the coarser levels applied to the lower bits: bit 0 a
    transpose, bit 1 a mirror of both axes.  The two commute and are involutions, so the
    composition of all of them is one of these four states.
    """
    if state & 1:
        rx, ry = ry, rx
    if state & 2:
        rx ^= 1
        ry ^= 1
    if ry == 0:
        state ^= 1
        if rx == 1:
            state ^= 2
    return (3 * rx) ^ ry, state


@inner
def _hilbert_table():
    """Four levels at once: entry ``256 state + 16 x4 + y4`` is ``(8 key bits << 2) | next state``."""
    lut = np.empty(1024, dtype=np.int64)
    for st in range(4):
        for xc in range(16):
            for yc in range(16):
                s = st
                d = 0
                for lv in range(3, -1, -1):
                    q, s = _hilbert_step(s, (xc >> lv) & 1, (yc >> lv) & 1)
                    d = (d << 2) | q
                lut[256 * st + 16 * xc + yc] = (d << 2) | s
    return lut


def hilbert_keys(points, bits):
    """Hilbert-curve index of every point, quantised on the points' bounding box.

    Parameters
    ----------
    points : (n, 2) or (n, 3) float64
        Finite coordinates.
    bits : int
        Quantisation bits per axis, 1 to 26 (2-D) or 19 (3-D).

    Returns
    -------
    (n,) int64
        Index of each point's cell along the Hilbert curve of order ``bits``.
    """
    # Dispatched here, not in a kernel: a 2-D user never compiles the 3-D keys.
    if points.shape[1] == 3:
        return _hilbert_keys_3d(points, bits)
    return _hilbert_keys_2d(points, bits)


@njit(cache=True)
def _hilbert_keys_2d(points, bits):
    """:func:`hilbert_keys` of (n, 2) points."""
    n = points.shape[0]
    keys = np.zeros(n, dtype=np.int64)
    if n == 0:
        return keys
    xmin = points[0, 0]
    xmax = xmin
    ymin = points[0, 1]
    ymax = ymin
    for i in range(1, n):
        x = points[i, 0]
        y = points[i, 1]
        xmin = min(xmin, x)
        xmax = max(xmax, x)
        ymin = min(ymin, y)
        ymax = max(ymax, y)
    side = 1 << bits
    top = side - 1
    # Cells of width extent / 2**bits; the maximum falls on the boundary and is clamped.
    sx = 0.0 if xmax == xmin else side / (xmax - xmin)
    sy = 0.0 if ymax == ymin else side / (ymax - ymin)
    lut = _hilbert_table()
    lead = bits % 4
    for i in range(n):
        x = min(np.int64((points[i, 0] - xmin) * sx), top)
        y = min(np.int64((points[i, 1] - ymin) * sy), top)
        d = np.int64(0)
        state = np.int64(0)
        for lv in range(bits - 1, bits - 1 - lead, -1):
            q, state = _hilbert_step(state, (x >> lv) & 1, (y >> lv) & 1)
            d = (d << 2) | q
        # The remaining levels four at a time: a quarter of the branchy per-level steps.
        for c in range(bits - lead - 4, -1, -4):
            e = lut[256 * state + 16 * ((x >> c) & 15) + ((y >> c) & 15)]
            d = (d << 8) | (e >> 2)
            state = e & 3
        keys[i] = d
    return keys


@njit(cache=True)
def _radix_order(keys):
    """Stable argsort of non-negative int64 keys: LSD radix sort, equal digits of <= 12 bits.

    Same permutation as ``np.argsort(keys, kind="stable")``; a pass whose digit is the same
    for every key is skipped.  Scratch: two int64 key arrays and two index arrays.
    """
    n = keys.shape[0]
    idx = np.arange(n)
    if n < 2:
        return idx
    # Loops, not ``keys.max()`` / ``cnt.max()``: numpy's reductions add about a second of
    # cold compile to the first Delaunay call.
    top = 0
    for i in range(n):
        top = max(top, keys[i])
    nbits = 0
    while (top >> nbits) > 0:
        nbits += 1
    passes = max(1, (nbits + 11) // 12)
    dbits = (nbits + passes - 1) // passes
    mask = (1 << dbits) - 1
    k = keys.copy()
    k2 = np.empty(n, dtype=np.int64)
    idx2 = np.empty(n, dtype=np.int64)
    cnt = np.empty(mask + 1, dtype=np.int64)
    for p in range(passes):
        shift = p * dbits
        for b in range(mask + 1):
            cnt[b] = 0
        for i in range(n):
            cnt[(k[i] >> shift) & mask] += 1
        full = False
        for b in range(mask + 1):
            full = full or cnt[b] == n
        if full:
            continue
        total = 0
        for b in range(mask + 1):
            c = cnt[b]
            cnt[b] = total
            total += c
        for i in range(n):
            x = k[i]
            j = cnt[(x >> shift) & mask]
            cnt[(x >> shift) & mask] = j + 1
            k2[j] = x
            idx2[j] = idx[i]
        k, k2 = k2, k
        idx, idx2 = idx2, idx
    return idx


def _check(points, bits: int) -> tuple[np.ndarray, int]:
    """The points as (n, 2) or (n, 3) float64 and ``bits`` checked for their dimension."""
    from meshwright.core.errors import InputError

    pts = np.ascontiguousarray(points, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] not in (2, 3):
        raise InputError(f"points must have shape (n, 2) or (n, 3), got {pts.shape}")
    top = _MAX_BITS if pts.shape[1] == 2 else _MAX_BITS_3D
    bits = int(bits)
    if not 1 <= bits <= top:
        raise InputError(f"bits must be in 1..{top} for {pts.shape[1]}-D points, got {bits}")
    return pts, bits


def hilbert_order(points, bits: int = 16) -> np.ndarray:
    """Permutation sorting the points along a Hilbert curve over their bounding box.

    Parameters
    ----------
    points : (n, 2) or (n, 3) array_like of float64
        Finite coordinates.
    bits : int, optional
        Quantisation bits per axis (1 to 26 in 2-D, 19 in 3-D); points in one cell keep
        their input order.

    Returns
    -------
    (n,) int64
        ``points[order]`` follows the curve.
    """
    pts, bits = _check(points, bits)
    return _radix_order(hilbert_keys(pts, bits))


def brio_order(points, rng: np.random.Generator, min_round: int = 128, bits: int = 16) -> np.ndarray:
    """Biased randomized insertion order (Amenta, Choi & Rote 2003), rounds Hilbert-sorted.

    Parameters
    ----------
    points : (n, 2) or (n, 3) array_like of float64
        Finite coordinates.
    rng : numpy.random.Generator
        Source of the random round assignment; the order is a function of its state.
    min_round : int, optional
        Rounds expected to hold fewer points are merged into the first round.
    bits : int, optional
        Hilbert quantisation bits per axis (1 to 26 in 2-D, 19 in 3-D).

    Returns
    -------
    (n,) int64
        Insertion order: a permutation of ``range(n)``.
    """
    pts, bits = _check(points, bits)
    n = pts.shape[0]
    keys = hilbert_keys(pts, bits)
    rounds = max(1, int(np.floor(np.log2(max(n, 1) / max(int(min_round), 1)))) + 1)
    if rounds > 1:
        # geometric(1/2) = 1 with probability 1/2 (last round), 2 with 1/4, ...
        back = np.minimum(rng.geometric(0.5, size=n), rounds)
        keys |= (rounds - back) << (pts.shape[1] * bits)
        del back
    return _radix_order(keys)
