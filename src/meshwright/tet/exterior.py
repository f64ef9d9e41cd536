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

Refinement only inserts points (every new tet has a new vertex; the old tets it keeps are the
same solids) and only splits subfaces, so a component's label never changes:
:func:`carry_labels` takes the old tets' labels from the previous classification and floods
them into the new tets across unprotected faces, instead of a new search over every tet.

Arrays: ``tets``, ``nbr`` (nt, 4) int32 as in :mod:`meshwright.tet.recovery`; ``barrier``
(nt, 4) bool, true on both sides of every subface.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.errors import GeometryError, fmt_point

__all__ = ["carry_labels", "classify", "components", "depths", "solid_part"]


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


@njit(cache=True)
def carry_labels(tets, nbr, barrier, nv0, src, barrier0, solid0, region0, vmax0, seeded):
    """Labels of a tetrahedralization that grew from a classified one by insertions.

    Parameters
    ----------
    tets, nbr : (nt, 4) int32
    barrier : (nt, 4) bool
    nv0 : int
        Vertices at the previous classification: a tet with a vertex ``>= nv0`` is new, the
        others were tets then.
    src : (nt,) int32
        Each old tet's index then (:meth:`Tetrahedralization.tracked`).
    barrier0 : (nt0, 4) bool
        The barrier flags then.  An old tet with a face whose protection changed since
        (a subface flip: recovery's Lawson flips, unflatten's) is labelled afresh, as new
        tets are: the flat tet four coplanar subface corners make changes sides.
    solid0, region0, vmax0 : (nt0,) bool, int32, float64
        The previous classification (:func:`classify`).
    seeded : bool
        Hole or region seeds were given.  Without seeds a new tet with an unprotected hull
        face is outside (depth 0: void, region 0, no bound), as :func:`classify` finds; the
        outside between a convex surface and its hull is often new tets only.

    Returns
    -------
    ok : bool
        False when a fresh tet is reached from no old one across unprotected faces, or when
        a fresh tet and a tet across one of its unprotected faces got different labels (the
        caller then runs :func:`classify`).  Two other tets sharing a face shared it before,
        protected or not as now, so their labels agree already.
    solid, region, vmax : (nt,) as in :func:`classify`
    fresh : (k,) int64
        The new and re-protected tets, ascending.
    """
    nt = tets.shape[0]
    nt0 = solid0.shape[0]
    solid = np.zeros(nt, dtype=np.bool_)
    region = np.zeros(nt, dtype=np.int32)
    vmax = np.full(nt, np.inf)
    known = np.zeros(nt, dtype=np.bool_)
    fresh = np.empty(nt, dtype=np.int64)
    nn = 0
    for t in range(nt):
        new = False
        for k in range(4):
            if tets[t, k] >= nv0:
                new = True
        s = src[t]
        if not new:
            if s < 0 or s >= nt0:
                return False, solid, region, vmax, fresh[:0].copy()
            for k in range(4):
                if barrier[t, k] != barrier0[s, k]:
                    new = True
        if new:
            fresh[nn] = t
            nn += 1
            continue
        solid[t] = solid0[s]
        region[t] = region0[s]
        vmax[t] = vmax0[s]
        known[t] = True
    # flood: fresh tets take the label of a labelled tet across an unprotected face
    queue = np.empty(max(nn, 1), dtype=np.int64)
    tail = 0
    for i in range(nn):
        t = fresh[i]
        for k in range(4):
            u = nbr[t, k]
            if barrier[t, k]:
                continue
            if u >= 0 and known[u]:
                solid[t] = solid[u]
                region[t] = region[u]
                vmax[t] = vmax[u]
            elif u >= 0 or seeded:
                continue
            known[t] = True
            queue[tail] = t
            tail += 1
            break
    head = 0
    while head < tail:
        t = queue[head]
        head += 1
        for k in range(4):
            u = nbr[t, k]
            if barrier[t, k] or u < 0 or known[u]:
                continue
            solid[u] = solid[t]
            region[u] = region[t]
            vmax[u] = vmax[t]
            known[u] = True
            queue[tail] = u
            tail += 1
    for i in range(nn):
        if not known[fresh[i]]:
            return False, solid, region, vmax, fresh[:nn].copy()
    # a label is one per component: unprotected neighbours must agree
    for i in range(nn):
        t = fresh[i]
        for k in range(4):
            u = nbr[t, k]
            if barrier[t, k] or u < 0:
                continue
            if solid[u] != solid[t] or region[u] != region[t] or vmax[u] != vmax[t]:
                return False, solid, region, vmax, fresh[:nn].copy()
    return True, solid, region, vmax, fresh[:nn].copy()


@njit(cache=True)
def solid_part(tets, nbr, barrier, solid, nv):
    """The solid tets as a mesh of their own, in one pass (NumPy's masks, gathers and
    cumulative sums over every tet were a tenth of the level-5 sphere's last stage).

    Parameters
    ----------
    tets, nbr : (nt, 4) int32
    barrier : (nt, 4) bool
    solid : (nt,) bool
    nv : int
        Vertices of ``tets``.

    Returns
    -------
    used : (nv,) bool
        The vertices of solid tets.
    newid : (nv,) int32
        Their new numbers (in the old order), -1 for the others.
    cells : (m, 4) int32
        The solid tets in their order, renumbered.
    neighbors : (m, 4) int32
        Across face k among the solid tets, -1 where the tet across is not solid.
    locked : (m, 4) bool
        ``barrier`` of the solid tets.
    """
    nt = tets.shape[0]
    newt = np.full(nt, -1, dtype=np.int32)
    used = np.zeros(nv, dtype=np.bool_)
    m = 0
    for t in range(nt):
        if solid[t]:
            newt[t] = m
            m += 1
            for k in range(4):
                used[tets[t, k]] = True
    newid = np.full(nv, -1, dtype=np.int32)
    c = 0
    for v in range(nv):
        if used[v]:
            newid[v] = c
            c += 1
    cells = np.empty((m, 4), dtype=np.int32)
    neighbors = np.empty((m, 4), dtype=np.int32)
    locked = np.empty((m, 4), dtype=np.bool_)
    for t in range(nt):
        i = newt[t]
        if i < 0:
            continue
        for k in range(4):
            cells[i, k] = newid[tets[t, k]]
            u = nbr[t, k]
            neighbors[i, k] = newt[u] if u >= 0 else -1
            locked[i, k] = barrier[t, k]
    return used, newid, cells, neighbors, locked
