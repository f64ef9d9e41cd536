"""Argument checks shared by the public doors: point arrays, the predicates' coordinate range,
connectivity arrays, counts, seeds and positive numbers.

Every public function checks all its arguments before any work (docs/ARCHITECTURE.md); the
checks that several doors need live here, so each is written once and every door names the
culprit the same way (:func:`meshwright.core.errors.fmt_point`).

Coordinate range
----------------
The predicates of :mod:`meshwright.core.predicates` decide exactly only while none of their
intermediate products overflows or underflows.  Their documented sufficient condition is that
every nonzero coordinate has magnitude in ``[COORD_MIN, COORD_MAX] = [2**-148, 2**200]``
(about 2.8e-45 .. 1.6e60); zero is always allowed.  :func:`check_coordinate_range` enforces it
at the doors of ``delaunay``, ``voronoi``, ``triangulate`` (the domain) and ``smooth``.

The doors check rather than rescale.  Multiplying by a power of two is exact in binary
floating point, so a door could move a tiny or huge point set into the range and scale its
results back; but every derived quantity (Voronoi vertices, areas, sizes, later insertions
and location queries) would then have to follow the same factor, and a point set whose
magnitudes span more than ``2**348`` would still not fit.  A clear error naming the point is
simpler and leaves the choice of units to the caller: multiply the coordinates by ``2**k``
yourself (exact), mesh, and divide the result by the same ``2**k`` (exact again).
"""

from __future__ import annotations

import numbers

import numpy as np

from meshwright.core.errors import InputError, SizeError, fmt_point

__all__ = [
    "as_node_indices",
    "COORD_MIN",
    "COORD_MAX",
    "as_points",
    "as_exact_points",
    "as_cells",
    "check_coordinate_range",
    "check_count",
    "check_flag",
    "check_positive",
    "check_seed",
]

COORD_MIN = 2.0**-148
COORD_MAX = 2.0**200


def as_points(points, what: str = "points", dim: int = 2, *, copy: bool = False) -> np.ndarray:
    """The one point coercer: C-contiguous ``(n, dim)`` float64 with finite coordinates.

    Parameters
    ----------
    points : (n, dim) array_like of float
    what : str
        Name of the argument in error messages.
    dim : int
        Required number of columns.
    copy : bool
        Always return a new array (otherwise not copied when already C-contiguous float64).

    Returns
    -------
    (n, dim) float64, C-contiguous

    Raises
    ------
    InputError
        Not numeric, wrong shape, or a NaN/infinite coordinate (the first such point named
        with its index and coordinates).
    """
    try:
        arr = np.array(points, dtype=np.float64, order="C", copy=True) if copy else np.ascontiguousarray(
            points, dtype=np.float64
        )
    except (TypeError, ValueError) as exc:
        raise InputError(f"{what} must be an (n, {dim}) array of numbers: {exc}") from exc
    if arr.ndim != 2 or arr.shape[1] != dim:
        raise InputError(f"{what} must have shape (n, {dim}), got {arr.shape}")
    # One flat test first: the row-wise reduction that names the culprit costs several
    # times more and is needed only when there is one.
    if not np.isfinite(arr).all():
        bad = np.flatnonzero(~np.isfinite(arr).all(axis=1))
        raise InputError(f"{what}: point {bad[0]} is not finite: {fmt_point(arr[bad[0]])}")
    return arr


def as_exact_points(points, what: str = "points", dim: int = 2, *, copy: bool = False) -> np.ndarray:
    """:func:`as_points` (same arguments, same result) followed by :func:`check_coordinate_range`:
    the coercer of the doors whose points feed the exact predicates.

    Raises
    ------
    InputError
        As :func:`as_points` and :func:`check_coordinate_range`, naming the first bad point.
    """
    arr = as_points(points, what, dim, copy=copy)
    check_coordinate_range(arr, what)
    return arr


def as_cells(arr, what: str, width: int, n: int) -> np.ndarray:
    """Connectivity argument: a (k, width) integer array of node indices in ``[0, n)``.

    Parameters
    ----------
    arr : (k, width) array_like of int
        The cells (triangles, quads, edges ...); an empty array gives ``(0, width)``.
    what : str
        The argument's name, for the message.
    width : int
        Nodes per cell.
    n : int
        Number of nodes.

    Returns
    -------
    (k, width) int32 ndarray
        C-contiguous; a copy only where the input was not already int32 and contiguous.

    Raises
    ------
    InputError
        Naming ``what``: a non-integer dtype (bool included), a wrong shape, or the first row
        that refers to a node outside ``[0, n)``.
    """
    a = np.asarray(arr)
    if a.size == 0:
        return np.zeros((0, width), dtype=np.int32)
    if a.dtype == bool or not np.issubdtype(a.dtype, np.integer):
        raise InputError(f"{what} must be an integer array of node indices, got dtype {a.dtype}")
    if a.ndim != 2 or a.shape[1] != width:
        raise InputError(f"{what} must have shape (k, {width}), got {a.shape}")
    if a.min() < 0 or a.max() >= n:
        bad = np.flatnonzero(((a < 0) | (a >= n)).any(axis=1))
        raise InputError(f"{what} row {bad[0]} {a[bad[0]].tolist()} refers to a node outside [0, {n})")
    return np.ascontiguousarray(a, dtype=np.int32)


def check_coordinate_range(points: np.ndarray, what: str = "points") -> None:
    """Raise unless every nonzero coordinate lies in the predicates' exact range.

    Parameters
    ----------
    points : (n, d) float64
        Finite coordinates (see :func:`as_points`).
    what : str
        Name of the argument in error messages.

    Raises
    ------
    InputError
        Naming the first point with a nonzero coordinate of magnitude below ``COORD_MIN`` or
        above ``COORD_MAX``, and how to rescale.
    """
    a = np.abs(np.asarray(points, dtype=np.float64))
    if a.size == 0:
        return
    bad = ((a != 0.0) & (a < COORD_MIN)) | (a > COORD_MAX)
    if not bad.any():
        return
    i = int(np.flatnonzero(bad.reshape(len(a), -1).any(axis=1))[0])
    raise InputError(
        f"{what}: point {i} {fmt_point(points[i])} has a coordinate outside the exact predicates' "
        f"range (nonzero magnitudes in [2**-148, 2**200], about {COORD_MIN:.2g} .. {COORD_MAX:.2g}); "
        "multiply all coordinates by a power of two (exact) to bring them into it"
    )


def check_count(value, what: str, minimum: int = 0) -> int:
    """An integer argument (not bool, not float) at least ``minimum``; returns it as int.

    Raises
    ------
    InputError
        Naming ``what`` and the value given.
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise InputError(f"{what} must be an integer >= {minimum}, got {value!r} ({type(value).__name__})")
    if int(value) < minimum:
        raise InputError(f"{what} must be an integer >= {minimum}, got {int(value)}")
    return int(value)


def check_flag(value, what: str) -> bool:
    """A boolean argument: ``True``/``False`` or a NumPy bool (not 0/1, not None); returns it as bool.

    Raises
    ------
    InputError
        Naming ``what`` and the value given.
    """
    if not isinstance(value, (bool, np.bool_)):
        raise InputError(f"{what} must be True or False, got {value!r}")
    return bool(value)


def check_seed(seed, what: str = "seed"):
    """A seed for :func:`numpy.random.default_rng`: a non-negative int or a Generator.

    Returns
    -------
    int or numpy.random.Generator

    Raises
    ------
    InputError
        A bool, float, negative or other value.
    """
    if isinstance(seed, np.random.Generator):
        return seed
    if isinstance(seed, bool) or not isinstance(seed, numbers.Integral):
        raise InputError(
            f"{what} must be a non-negative integer or a numpy.random.Generator, got {seed!r} ({type(seed).__name__})"
        )
    if int(seed) < 0:
        raise InputError(f"{what} must be non-negative, got {int(seed)}")
    return int(seed)


def check_positive(value, what: str, error: type = SizeError) -> float:
    """A positive, finite real number (not bool); returns it as float.

    Raises
    ------
    error
        (:class:`SizeError` by default) naming ``what`` and the value: zero, negative, NaN,
        infinite, or not a number.
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise error(f"{what} must be a positive number, got {value!r} ({type(value).__name__})")
    v = float(value)
    if not (np.isfinite(v) and v > 0.0):
        raise error(f"{what} must be positive and finite, got {v!r}")
    return v


def as_node_indices(fixed, n: int, what: str = "fixed") -> np.ndarray:
    """Node indices given as indices or an (n,) bool mask, checked against ``n``.

    Parameters
    ----------
    fixed : None, (k,) array_like of int, or (n,) array_like of bool
    n : int
        Number of nodes.
    what : str
        Argument name for messages.

    Returns
    -------
    (k,) int64
        Empty for None.

    Raises
    ------
    InputError
        A mask of the wrong shape, non-integer indices, an index outside ``[0, n)``.
    """
    if fixed is None:
        return np.zeros(0, dtype=np.int64)
    f = np.asarray(fixed)
    if f.dtype == bool:
        if f.shape != (n,):
            raise InputError(f"{what} as a mask must have shape ({n},), got {f.shape}")
        return np.flatnonzero(f)
    f = f.ravel()
    if f.size and not np.issubdtype(f.dtype, np.integer):
        raise InputError(f"{what} must be node indices (integers) or an (n,) bool mask, got dtype {f.dtype}")
    bad = np.flatnonzero((f < 0) | (f >= n))
    if len(bad):
        raise InputError(f"{what} entry {bad[0]} is node {int(f[bad[0]])}, outside [0, {n})")
    return f.astype(np.int64)
