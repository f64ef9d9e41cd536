"""Removal of exterior and void tetrahedra by a flood fill across unprotected faces (18.4.1).

The chapter removes the tets whose centroids lie outside the surface.  A centroid test can be
fooled (a flat tet on a concave boundary has its centroid on the wrong side within
round-off); a flood fill cannot: the recovered subfaces (:mod:`meshwright.tet.recovery`) are
*barriers*, every set of tets connected through non-barrier faces is one *component*, and a
component's *depth* is the least number of barriers crossed on a path from the outside (the
hull's far side is depth 0).  By default a component is solid when its depth is odd, the
even-odd rule a ray-parity point-in-solid test gives: a box surface holding a sphere surface
meshes the space between them, and two boxes sharing a face (an interface) are both depth 1.
Seeds override it, as in TetGen: a hole seed makes its component void, a region seed makes
it solid with the seed's id and volume bound.

Arrays: ``tets``, ``nbr`` (nt, 4) int32 as in :mod:`meshwright.tet.recovery`; ``barrier``
(nt, 4) bool, true on both sides of every subface.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.errors import GeometryError, fmt_point

__all__ = ["components", "depths", "classify"]


@njit(cache=True)
def components(nbr, barrier):
    """Connected components of tets through non-barrier faces.

    Parameters
    ----------
    nbr : (nt, 4) int32
    barrier : (nt, 4) bool

    Returns
    -------
    comp : (nt,) int32
        Component of each tet, numbered in order of their lowest tet.
    count : int
    """
    nt = nbr.shape[0]
    comp = np.full(nt, -1, dtype=np.int32)
    queue = np.empty(nt, dtype=np.int32)
    nc = 0
    for s in range(nt):
        if comp[s] >= 0:
            continue
        comp[s] = nc
        head = 0
        tail = 1
        queue[0] = s
        while head < tail:
            t = queue[head]
            head += 1
            for k in range(4):
                if barrier[t, k]:
                    continue
                u = nbr[t, k]
                if u >= 0 and comp[u] < 0:
                    comp[u] = nc
                    queue[tail] = u
                    tail += 1
        nc += 1
    return comp, nc


def depths(nbr: np.ndarray, barrier: np.ndarray, comp: np.ndarray, count: int) -> np.ndarray:
    """Least number of barriers between each component and the outside; (count,) int64.

    A breadth-first search on the component graph: the outside reaches a component at cost 0
    through a hull face that is no barrier, 1 through a barrier on the hull; components meet
    only across barriers (cost 1).  One Numba pass (:func:`_depths`): its NumPy form (pairs of
    components sorted by np.unique) was a third of each classification.
    """
    return _depths(nbr, barrier, comp, count)


@njit(cache=True)
def _depths(nbr, barrier, comp, count):
    nt = nbr.shape[0]
    unset = np.iinfo(np.int64).max // 2
    depth = np.full(count, unset, dtype=np.int64)
    # interior barrier faces as component pairs, both ways
    m = 0
    for t in range(nt):
        for k in range(4):
            if barrier[t, k] and nbr[t, k] >= 0:
                m += 1
    a = np.empty(m, dtype=np.int64)
    b = np.empty(m, dtype=np.int64)
    m = 0
    for t in range(nt):
        for k in range(4):
            u = nbr[t, k]
            if u < 0:
                c = comp[t]
                w = 1 if barrier[t, k] else 0
                if w < depth[c]:
                    depth[c] = w
            elif barrier[t, k]:
                a[m] = comp[t]
                b[m] = comp[u]
                m += 1
    # unit weights: settle level by level; a level that reaches nothing new ends the search
    level = 0
    while level <= count:
        reached = False
        for i in range(m):
            if depth[a[i]] == level and depth[b[i]] > level + 1:
                depth[b[i]] = level + 1
                reached = True
        if not reached:
            more = False
            for c in range(count):
                if depth[c] > level and depth[c] < unset:
                    more = True
                    break
            if not more:
                break
        level += 1
    return depth


@njit(cache=True)
def _lowest(tets, comp, count):
    """Lowest vertex of each component's tets; (count,) int64."""
    lowest = np.full(count, np.iinfo(np.int64).max, dtype=np.int64)
    for t in range(tets.shape[0]):
        c = comp[t]
        for k in range(4):
            v = np.int64(tets[t, k])
            if v < lowest[c]:
                lowest[c] = v
    return lowest


def classify(tz, barrier: np.ndarray, holes: np.ndarray, regions: np.ndarray):
    """Solid components and their region ids and volume bounds.

    Parameters
    ----------
    tz : Tetrahedralization
    barrier : (nt, 4) bool
    holes : (h, 3) float64
        Hole seeds: their components are void.
    regions : (r, 5) float64
        ``(x, y, z, id, max_volume)`` region seeds (``max_volume <= 0``: no bound).

    Returns
    -------
    solid : (nt,) bool
    region : (nt,) int32
        Region id of each solid tet: the seed's, else 0 when seeds are given, else 1, 2, ...
        over the unseeded solid components in order of their lowest vertex (input order).
    max_volume : (nt,) float64
        Volume bound of each tet's region (inf: none).
    """
    tets = tz.tetrahedra
    nbr = tz.neighbors
    comp, count = components(nbr, barrier)
    depth = depths(nbr, barrier, comp, count)
    solid_c = depth % 2 == 1
    rid = np.zeros(count, dtype=np.int32)
    vmax = np.full(count, np.inf)
    seeded = np.zeros(count, dtype=bool)
    for what, seeds in (("hole", holes), ("region", regions)):
        if len(seeds) == 0:
            continue
        loc = np.atleast_1d(tz.locate(np.ascontiguousarray(seeds[:, :3])))
        for i, t in enumerate(loc):
            if t < 0:
                raise GeometryError(f"{what} seed {i} {fmt_point(seeds[i, :3])} lies outside the surface's hull")
            c = comp[t]
            if what == "hole":
                solid_c[c] = False
                seeded[c] = True
            else:
                solid_c[c] = True
                seeded[c] = True
                rid[c] = int(seeds[i, 3])
                if seeds[i, 4] > 0:
                    vmax[c] = seeds[i, 4]
    if len(regions) == 0:
        lowest = _lowest(tets, comp, count)
        unseeded = np.flatnonzero(solid_c & ~seeded)
        order = unseeded[np.argsort(lowest[unseeded], kind="stable")]
        rid[order] = np.arange(1, order.size + 1, dtype=np.int32)
    return solid_c[comp], rid[comp], vmax[comp]
