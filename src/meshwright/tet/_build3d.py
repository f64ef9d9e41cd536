"""Start and finish of a 3-D kernel build: first tetrahedra, slot compaction, relabelling.

Helpers of :class:`meshwright.tet.tetrahedralization.Tetrahedralization` around the insertion
kernel (:mod:`meshwright.tet._kernel3d`, whose module docstring gives the flat layout):
:func:`find_start` chooses four non-coplanar points, :func:`init_tets` builds given finite
tets (one, or the chapter's five box tets) with ghosts on their free faces, and after the
insertions :func:`compact` puts finite tets first, ghosts next and drops freed slots
(:func:`compact_tagged` also moves a per-slot tag, so a caller can follow the old tets
through the compaction), and :func:`relabel` renumbers vertices.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.flat import GHOST, TET_FACES
from meshwright.core.predicates import orient2d, orient3d
from meshwright.tet import watson
from meshwright.tet._kernel3d import DELETED, M_LAST, M_NFREE, M_NTET

_MARK = -3  # temporary link value while two swapped slots are repaired

__all__ = ["compact", "compact_tagged", "find_start", "first_repeat", "init_tets", "input_order_maps", "relabel", "scatter_rows"]


@njit(cache=True)
def _collinear(pts, a, b, c):
    """Exact collinearity of three points: all three coordinate-plane projections degenerate."""
    return (
        orient2d(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[c, 0], pts[c, 1]) == 0.0
        and orient2d(pts[a, 1], pts[a, 2], pts[b, 1], pts[b, 2], pts[c, 1], pts[c, 2]) == 0.0
        and orient2d(pts[a, 0], pts[a, 2], pts[b, 0], pts[b, 2], pts[c, 0], pts[c, 2]) == 0.0
    )


@njit(cache=True)
def find_start(pts, order):
    """Positions i < j < k in ``order`` of the first tet ``order[0], order[i], order[j], order[k]``.

    Parameters
    ----------
    pts : (rows, 3) float64
    order : (m,) int32 or int64

    Returns
    -------
    tuple of int
        i is the first position whose point differs from ``order[0]``'s, j the first after
        it not collinear with both, k the first after j not coplanar with the three; -1
        where none exists.
    """
    m = order.shape[0]
    a = order[0]
    i = 1
    while i < m and pts[order[i], 0] == pts[a, 0] and pts[order[i], 1] == pts[a, 1] and pts[order[i], 2] == pts[a, 2]:
        i += 1
    if i >= m:
        return -1, -1, -1
    b = order[i]
    j = i + 1
    while j < m and _collinear(pts, a, b, order[j]):
        j += 1
    if j >= m:
        return i, -1, -1
    c = order[j]
    for k in range(j + 1, m):
        d = order[k]
        if orient3d(pts[a, 0], pts[a, 1], pts[a, 2], pts[b, 0], pts[b, 1], pts[b, 2],
                    pts[c, 0], pts[c, 1], pts[c, 2], pts[d, 0], pts[d, 1], pts[d, 2]) != 0.0:
            return i, j, k
    return i, j, -1


def init_tets(pts: np.ndarray, tets: np.ndarray, tet: np.ndarray, nbr: np.ndarray, sph: np.ndarray, meta: np.ndarray) -> None:
    """Write finite tets, oriented positively, and a ghost on each free face, all linked.

    Parameters
    ----------
    pts : (rows, 3) float64
    tets : (m, 4) int
        Finite tets (any orientation, not flat) that form a convex ball, e.g. one tet or
        the five tets of a hexahedron.
    tet, nbr : (4 cap,) int32
        Output: slots ``[0, m + g)`` for the m tets and g ghosts.
    sph : (5 cap,) float32 or (0,)
        Watson's spheres, written when sized.
    meta : (8,) int64
        ``M_NTET`` and ``M_LAST`` are set.
    """
    rows = []
    for q in np.asarray(tets, dtype=np.int64):
        a, b, c, d = (int(x) for x in q)
        o = orient3d(*pts[a], *pts[b], *pts[c], *pts[d])
        rows.append([a, b, c, d] if o > 0 else [b, a, c, d])
    faces = {}
    for t, q in enumerate(rows):
        for k in range(4):
            faces.setdefault(frozenset(q[i] for i in range(4) if i != k), []).append((t, k))
    for t, q in enumerate(list(rows)):
        for k in range(4):
            if len(faces[frozenset(q[i] for i in range(4) if i != k)]) == 1:
                f = [q[int(i)] for i in TET_FACES[k]]
                g = len(rows)
                rows.append([f[0], f[1], f[2], GHOST])
                for kk in range(3):
                    faces.setdefault(frozenset(rows[g][i] for i in range(4) if i != kk), []).append((g, kk))
                faces[frozenset(f)].append((g, 3))
    for group in faces.values():
        (t1, k1), (t2, k2) = group
        nbr[4 * t1 + k1] = t2
        nbr[4 * t2 + k2] = t1
    for t, q in enumerate(rows):
        tet[4 * t : 4 * t + 4] = q
        if sph.shape[0] > 0:
            _sphere(pts, tet, sph, t)
    meta[M_NTET] = len(rows)
    meta[M_LAST] = 0


@njit(cache=True)
def _sphere(pts, tet, sph, t):
    watson.sphere(pts, tet, sph, t)


@njit(inline="always")
def _repoint(nbr, t, skip, old, new):
    """In every neighbour of tet t other than ``skip``, turn the link ``old`` into ``new``."""
    for k in range(4):
        nb = nbr[4 * t + k]
        if nb != skip:
            for m in range(4):
                if nbr[4 * nb + m] == old:
                    nbr[4 * nb + m] = new


@njit(inline="always")
def _swap_slots(tet, nbr, sph, tag, meta, i, j, live_i, live_j):
    """Exchange the tets in slots i and j (and their ``tag`` entries, if any) and repair every
    link to them.

    ``live_x``: whether the tet first in slot x is finite or ghost (a freed slot's links are
    stale and are neither followed nor repaired).  A neighbour of both is repaired through a
    temporary mark so that its two links cannot be confused.
    """
    for k in range(4):
        x = tet[4 * i + k]
        tet[4 * i + k] = tet[4 * j + k]
        tet[4 * j + k] = x
        y = nbr[4 * i + k]
        nbr[4 * i + k] = nbr[4 * j + k]
        nbr[4 * j + k] = y
    if sph.shape[0] > 0:
        for k in range(watson.RECORD):
            z = sph[watson.RECORD * i + k]
            sph[watson.RECORD * i + k] = sph[watson.RECORD * j + k]
            sph[watson.RECORD * j + k] = z
    if tag.shape[0] > 0:
        x = tag[i]
        tag[i] = tag[j]
        tag[j] = x
    # slot i now holds the old j (live_j), slot j the old i (live_i)
    for k in range(4):
        if live_j and nbr[4 * i + k] == i:
            nbr[4 * i + k] = j
        if live_i and nbr[4 * j + k] == j:
            nbr[4 * j + k] = i
    if live_j:
        _repoint(nbr, i, j, j, _MARK)
    if live_i:
        _repoint(nbr, j, i, i, j)
    if live_j:
        _repoint(nbr, i, j, _MARK, i)
    if meta[M_LAST] == i:
        meta[M_LAST] = j
    elif meta[M_LAST] == j:
        meta[M_LAST] = i


@njit(cache=True)
def compact(tet, nbr, sph, meta):
    """Finite tets to slots ``[0, nt)``, ghosts to ``[nt, ng)``, freed slots dropped.

    In place, without scratch: two sweeps from both ends swap misplaced slots
    (:func:`_swap_slots` repairs the links).  ``meta[M_NTET] = ng`` afterwards.

    Returns
    -------
    int
        nt, the number of finite tets.
    """
    return compact_tagged(tet, nbr, sph, np.empty(0, dtype=np.int32), meta)


@njit(cache=True)
def compact_tagged(tet, nbr, sph, tag, meta):
    """:func:`compact`, moving ``tag`` (one int32 per slot, or empty) with the slots.

    A caller that writes ``tag[t] = t`` before inserting and compacting finds in
    ``tag[t]`` afterwards the slot an old tet occupied before (tets created meanwhile hold
    stale values there; they are the tets with a new vertex).
    """
    ntet = meta[M_NTET]
    # sweep 1: finite before the rest; sweep 2: ghosts before freed slots
    bounds = (0, 0)
    nt = 0
    for sweep in range(2):
        i = nt if sweep == 1 else 0
        j = ntet - 1
        while True:
            while i < j and (tet[4 * i + 3] >= 0 if sweep == 0 else tet[4 * i + 3] == GHOST):
                i += 1
            while j > i and not (tet[4 * j + 3] >= 0 if sweep == 0 else tet[4 * j + 3] == GHOST):
                j -= 1
            if i >= j:
                break
            _swap_slots(tet, nbr, sph, tag, meta, i, j, tet[4 * i + 3] != DELETED, True)
        # first slot past the class just gathered
        k = nt if sweep == 1 else 0
        while k < ntet and (tet[4 * k + 3] >= 0 if sweep == 0 else tet[4 * k + 3] == GHOST):
            k += 1
        if sweep == 0:
            nt = k
        else:
            bounds = (nt, k)
    ng = bounds[1]
    last = meta[M_LAST]
    if not (0 <= last < nt):
        meta[M_LAST] = 0
    meta[M_NTET] = ng
    meta[M_NFREE] = 0
    return nt


@njit(cache=True)
def relabel(tet, ntet, newid, base, shift):
    """Replace every vertex id v >= base in slots ``[0, ntet)`` by ``shift + newid[v - base]``."""
    for i in range(4 * ntet):
        v = tet[i]
        if v >= base:
            tet[i] = shift + newid[v - base]


@njit(cache=True)
def input_order_maps(order, vmap, base, rank, index_map):
    """From insertion order to input order, without temporaries.

    Vertex ``base + k`` was the k-th inserted point, input point ``order[k]``, and is renamed
    ``base + order[k]``.  Fills ``rank[base + order[k]] = base + k`` (its perturbation key:
    the insertion rank) and ``index_map[order[k]] = base + order[vmap[k] - base]`` (the
    renamed vertex the point became).
    """
    for k in range(order.shape[0]):
        rank[base + order[k]] = base + k
        index_map[order[k]] = base + order[vmap[k] - base]


@njit(cache=True)
def first_repeat(vmap, base):
    """First k with ``vmap[k] != base + k`` (a point merged into another vertex), or -1."""
    for k in range(vmap.shape[0]):
        if vmap[k] != base + k:
            return k
    return -1


@njit(cache=True)
def scatter_rows(pts, base, order):
    """In place, move row ``base + k`` of ``pts`` to row ``base + order[k]`` (a permutation).

    Follows the permutation's cycles with one row of scratch, so no copy of the points.
    ``order`` is left unchanged (it is negated while a cycle is open, then restored).
    """
    n = order.shape[0]
    for k in range(n):
        if order[k] < 0 or order[k] == k:
            continue
        x = pts[base + k, 0]
        y = pts[base + k, 1]
        z = pts[base + k, 2]
        j = order[k]
        order[k] = -1 - order[k]
        while True:
            tx = pts[base + j, 0]
            ty = pts[base + j, 1]
            tz = pts[base + j, 2]
            pts[base + j, 0] = x
            pts[base + j, 1] = y
            pts[base + j, 2] = z
            x = tx
            y = ty
            z = tz
            if order[j] < 0:
                break
            nj = order[j]
            order[j] = -1 - order[j]
            j = nj
    for k in range(n):
        if order[k] < 0:
            order[k] = -1 - order[k]
