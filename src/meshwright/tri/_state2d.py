"""The state bundle of the 2-D insertion kernel: :class:`TriState`, its status codes and header slots.

Split from :mod:`meshwright.tri._kernel2d` (which re-exports every name here, and whose
module docstring gives the layout of each array and the growth contract): the Python side
of the bundle, building a fresh one (:func:`new_state`) and growing one by doubling
(:func:`grow`); the kernels that walk, carve cavities and fan live there.

Invariants: arrays are never resized in place (a grown bundle holds new arrays, the used
parts copied, new constraint entries 0); scalar header values live in the int64 ``meta``
array at the ``M_*`` slots; optional parts are empty arrays of the right dtype (Bowyer:
``circ`` (0,) float32; unconstrained: ``cons`` (0,) int32), so one compiled signature serves
every use.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from meshwright.core.flat import grown_rows
from meshwright.core.rng import seed_state

__all__ = [
    "BROKEN", "DUP_BASE", "M_LAST", "M_NTRI", "M_NV", "M_RNG", "M_SHORT_WORK", "M_SPLIT_A", "M_SPLIT_B",
    "M_SPLIT_C", "NEED_SPACE", "TriState", "grow", "new_state",
]

# insert_vertex status: >= 0 is a new triangle incident to v; otherwise one of these, and a
# status <= DUP_BASE means v coincides with vertex DUP_BASE - status (nothing was changed).
NEED_SPACE = -1
BROKEN = -2
DUP_BASE = -3
# meta slots
M_NTRI = 0
M_LAST = 1
M_RNG = 2
M_SPLIT_A = 3  # the constrained edge a-b (id + 1 in M_SPLIT_C, 0: none) the next fan splits
M_SPLIT_B = 4
M_SPLIT_C = 5
M_NV = 6
M_SHORT_WORK = 7
_META_LEN = 8
_WORK_INIT = 64  # initial cavity capacity; doubled on demand


class TriState(NamedTuple):
    """State of the 2-D insertion kernel, passed whole to every kernel function.

    Fields in this order (shapes and meaning in the module docstring):
    ``pts`` (rows, 2) float64, ``tri`` / ``nbr`` (3 cap,) int32, ``circ`` (4 cap,) float32 or
    (0,), ``rank`` (r,) int32, ``cons`` (3 cap,) int32 or (0,), ``meta`` (8,) int64, ``work``
    (5 w,) int32, ``vmark`` (>= rows + 1,) int32.  Grown copies come from :func:`grow` (Python)
    or :func:`make_room` (inside a kernel); the arrays are never resized in place.
    """

    pts: np.ndarray
    tri: np.ndarray
    nbr: np.ndarray
    circ: np.ndarray
    rank: np.ndarray
    cons: np.ndarray
    meta: np.ndarray
    work: np.ndarray
    vmark: np.ndarray


def new_state(pts: np.ndarray, slots: int, seed: int, *, circles: bool = False, constrained: bool = False,
              rank: np.ndarray | None = None) -> TriState:
    """A fresh bundle over the point rows ``pts`` with ``slots`` triangle slots, none in use.

    Parameters
    ----------
    pts : (rows, 2) float64
        Vertex coordinates (the bundle keeps this array); ``meta[M_NV]`` starts at 0.
    slots : int
        Triangle slots to preallocate (``2 n`` suffice for n vertices).
    seed : int
        Seed of the walk's xorshift state.
    circles : bool
        Keep Watson's circle records (``circ`` of 4 slots per triangle) or not (Bowyer).
    constrained : bool
        Keep per-half-edge constraints (``cons``) or not.
    rank : (r,) int32, optional
        Perturbation keys (default: empty, the key is the vertex id).
    """
    meta = np.zeros(_META_LEN, dtype=np.int64)
    meta[M_RNG] = seed_state(seed)
    return TriState(
        pts,
        np.empty(3 * slots, dtype=np.int32),
        np.empty(3 * slots, dtype=np.int32),
        np.empty(4 * slots if circles else 0, dtype=np.float32),
        np.empty(0, dtype=np.int32) if rank is None else rank,
        np.zeros(3 * slots if constrained else 0, dtype=np.int32),
        meta,
        np.empty(5 * _WORK_INIT, dtype=np.int32),
        np.empty(pts.shape[0] + 1, dtype=np.int32),
    )


def grow(s: TriState, rows: int = 0, slots: int = 0) -> TriState:
    """Bundle with room for ``rows`` vertices and ``slots`` triangle slots (doubling), and with
    the cavity scratch doubled if the kernel asked for it (``meta[M_SHORT_WORK]``).

    Returns ``s`` itself when nothing is short; otherwise ``s._replace(...)`` of grown copies
    (the used part copied, new constraint entries 0).  Call it after ``NEED_SPACE``: with no
    arguments it makes room for one more insertion.
    """
    ntri = int(s.meta[M_NTRI])
    rows = max(rows, int(s.meta[M_NV]) + 1)
    slots = max(slots, ntri + 2)
    new = {}
    if rows > s.pts.shape[0]:
        new["pts"] = grown_rows(s.pts, rows)
    prows = new["pts"].shape[0] if "pts" in new else s.pts.shape[0]
    if s.vmark.shape[0] <= prows:
        new["vmark"] = np.empty(prows + 1, dtype=np.int32)
    if 3 * slots > s.tri.shape[0]:
        cap = max(slots, 2 * (s.tri.shape[0] // 3))
        new["tri"] = grown_rows(s.tri, 3 * cap)
        new["nbr"] = grown_rows(s.nbr, 3 * cap)
        if s.cons.shape[0] > 0:
            new["cons"] = grown_rows(s.cons, 3 * cap, 0)
        if s.circ.shape[0] > 0:
            new["circ"] = grown_rows(s.circ, 4 * cap)
    if s.meta[M_SHORT_WORK]:
        s.meta[M_SHORT_WORK] = 0
        new["work"] = np.empty(2 * s.work.shape[0], dtype=np.int32)
    return s._replace(**new) if new else s
