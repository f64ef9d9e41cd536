r"""Flat-array helpers shared by the ``@njit`` kernels: capacity growth, the ghost sentinel.

Kernels keep their data in flat, preallocated NumPy arrays (``tri[3*t + k]``,
``nbr[3*t + k]``, ...) and a count of used entries.  When a kernel may outgrow its
preallocated bound (points inserted into an existing structure), it calls :func:`grown`
to obtain a larger copy; amortised over the insertions the copying costs O(1) each.

Invariant: ``grown(a, need)`` returns ``a`` itself when it is already large enough, so
callers can write ``a = grown(a, need)`` unconditionally.

Triangle index helpers: :func:`index3` and :func:`back3` take arrays and are
``inline="always"`` (a call would cost an array reference-count pair); :func:`next3` and
:func:`prev3` take a scalar and are plain compiled calls (kernel-only, without the Python
wrappers: :mod:`meshwright.core.jit`): LLVM inlines them at every call site anyway, while
Numba's IR inlining of their hundreds of call sites cost seconds of first-run compile (see
``benchmarks/compile2d.py``).  Edge k of triangle t
runs from ``tri[3t + next3(k)]`` to ``tri[3t + prev3(k)]``; ``nbr[3t + k]`` lies across it.

``GHOST = -1`` is the vertex id of the symbolic vertex at infinity in connectivity arrays
(ghost triangles close the convex hull; see :mod:`meshwright.tri._kernel2d`).

Tetrahedra (4 slots per tet, ``tet[4*t + k]``) are positively oriented,
``orient3d(v0, v1, v2, v3) > 0`` (v3 on the side of plane v0 v1 v2 that its normal
``(v1 - v0) x (v2 - v0)`` points to), and ``nbr[4*t + k]`` is the tet across the face
opposite vertex k.  ``TET_FACES[k]`` lists the local vertices of that face in the order
whose right-hand normal points *out* of the tet (counter-clockwise seen from outside)::

              v3
             /|\          face 0: v1 v2 v3     face 2: v0 v1 v3
            / | \         face 1: v0 v3 v2     face 3: v0 v2 v1
          v0--|--v2
            \ | /
             \|/
              v1
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.jit import inner

__all__ = ["GHOST", "TET_FACES", "grown", "grown_rows", "next3", "prev3", "index3", "back3", "lower_bound"]

GHOST = -1

# Outward-oriented faces of a positively oriented tet, by the local vertex they are opposite.
TET_FACES = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]], dtype=np.int64)


@njit(cache=True)
def grown(a, need):
    """Return ``a`` if it holds at least ``need`` entries, else a doubled copy.

    Parameters
    ----------
    a : (m,) array of any dtype
        Flat array whose first entries are in use.
    need : int
        Required length.

    Returns
    -------
    (max(m, need, 2m),) array of ``a.dtype``
        ``a`` itself, or a new array whose first ``m`` entries are those of ``a``; the rest
        are uninitialised.
    """
    m = a.shape[0]
    if need <= m:
        return a
    out = np.empty(max(need, 2 * m), dtype=a.dtype)
    # An element loop, not ``out[:m] = a``: the slice assignment's broadcasting checks cost
    # about 3 s of cold compile (their error-message string handling) on the first call.
    for i in range(m):
        out[i] = a[i]
    return out


def grown_rows(a: np.ndarray, need: int, fill=None) -> np.ndarray:
    """Python-side :func:`grown` for arrays of any rank (rows are the first axis).

    Parameters
    ----------
    a : (m, ...) array
    need : int
        Required number of rows.
    fill : scalar, optional
        Value of the new rows (default: uninitialised).

    Returns
    -------
    (max(m, need, 2m), ...) array of ``a.dtype``
        ``a`` itself when it already has ``need`` rows, else a copy with the first ``m`` rows
        of ``a``.
    """
    m = a.shape[0]
    if need <= m:
        return a
    shape = (max(need, 2 * m),) + a.shape[1:]
    out = np.empty(shape, dtype=a.dtype) if fill is None else np.full(shape, fill, dtype=a.dtype)
    out[:m] = a
    return out


@inner
def next3(k):
    """``(k + 1) % 3`` without a division."""
    return 0 if k == 2 else k + 1


@inner
def prev3(k):
    """``(k + 2) % 3`` without a division."""
    return 2 if k == 0 else k - 1


@njit(inline="always")
def index3(tri, t, v):
    """Position (0, 1, 2) of vertex v in triangle t of ``tri`` (3 cap,); 2 if absent."""
    return 0 if tri[3 * t] == v else (1 if tri[3 * t + 1] == v else 2)


@njit(inline="always")
def back3(nbr, n, t):
    """Position of the link back to triangle t in its neighbour n: ``nbr[3n + back3] == t``."""
    return 0 if nbr[3 * n] == t else (1 if nbr[3 * n + 1] == t else 2)


@inner
def lower_bound(xs, lo, hi, x):
    """First index in ``[lo, hi)`` of sorted ``xs`` whose entry is not below ``x`` (``hi``
    when none): ``np.searchsorted``'s left side on a slice, written out (the generic one
    cost each kernel calling it about a second of first-run compile)."""
    while lo < hi:
        mid = (lo + hi) // 2
        if xs[mid] < x:
            lo = mid + 1
        else:
            hi = mid
    return lo
