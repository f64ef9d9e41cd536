"""Start and finish of a 3-D kernel build: first tetrahedra, slot compaction, relabelling.

Helpers of :class:`meshwright.tet.tetrahedralization.Tetrahedralization` around the insertion
kernel (:mod:`meshwright.tet._kernel3d`, whose module docstring gives the flat layout):
:func:`find_start` chooses four non-coplanar points, :func:`init_tets` builds given finite
tets (one, or the chapter's five box tets) with ghosts on their free faces, and after the
insertions :func:`compact` puts finite tets first, ghosts next and drops freed slots, and
:func:`relabel` renumbers vertices.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.flat import GHOST, TET_FACES
from meshwright.core.predicates import orient2d, orient3d
from meshwright.tet import watson
from meshwright.tet._kernel3d import DELETED, M_LAST, M_NFREE, M_NTET

__all__ = ["find_start", "init_tets", "compact", "relabel"]


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


@njit(cache=True)
def compact(tet, nbr, sph, meta):
    """Finite tets to slots ``[0, nt)``, ghosts to ``[nt, ng)``, freed slots dropped.

    Neighbour links and ``meta[M_LAST]`` follow; ``meta[M_NTET] = ng`` afterwards.  In place
    (one int32 per slot of scratch).

    Returns
    -------
    int
        nt, the number of finite tets.
    """
    ntet = meta[M_NTET]
    newid = np.empty(ntet, dtype=np.int32)
    nt = 0
    for t in range(ntet):
        if tet[4 * t + 3] >= 0:
            newid[t] = nt
            nt += 1
    ng = nt
    for t in range(ntet):
        if tet[4 * t + 3] == GHOST:
            newid[t] = ng
            ng += 1
    nd = ng
    for t in range(ntet):
        if tet[4 * t + 3] == DELETED:
            newid[t] = nd
            nd += 1
    for t in range(ntet):
        if tet[4 * t + 3] != DELETED:
            for k in range(4):
                nbr[4 * t + k] = newid[nbr[4 * t + k]]
    last = meta[M_LAST]
    meta[M_LAST] = newid[last] if 0 <= last < ntet and newid[last] < nt else 0
    keep = sph.shape[0] > 0
    for i in range(ntet):
        while newid[i] != i:
            j = newid[i]
            for k in range(4):
                x = tet[4 * i + k]
                tet[4 * i + k] = tet[4 * j + k]
                tet[4 * j + k] = x
                y = nbr[4 * i + k]
                nbr[4 * i + k] = nbr[4 * j + k]
                nbr[4 * j + k] = y
            if keep:
                for k in range(watson.RECORD):
                    z = sph[watson.RECORD * i + k]
                    sph[watson.RECORD * i + k] = sph[watson.RECORD * j + k]
                    sph[watson.RECORD * j + k] = z
            newid[i] = newid[j]
            newid[j] = j
    meta[M_NTET] = ng
    meta[M_NFREE] = 0
    return nt


@njit(cache=True)
def relabel(tet, ntet, newid):
    """Replace every non-ghost vertex id v in slots ``[0, ntet)`` by ``newid[v]``."""
    for i in range(4 * ntet):
        v = tet[i]
        if v >= 0:
            tet[i] = newid[v]
