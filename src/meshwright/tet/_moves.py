"""Vertex-move kernels of sliver removal, over flat tetrahedron arrays.

Source: the chapter's "node point D is moved" (section 18.1.1, after Cavendish, Field and
Frey, 1985), done as a search over a few candidate positions (towards the ideal apex over
the opposite face, away from that face, towards the star's centroid) refined by a compass
search, keeping every tet of the vertex's star positive (exact ``orient3d``).

Layout and quality measure as in :mod:`meshwright.tet._flips` (``tet[4*t + k]``, dead slot
``tet[4*t] == -1``; the sliver ratio ``a = r_in / R_circ`` with the radius-edge term of
:func:`meshwright.tet._flips._quality_xyz`).  Invariants: a move changes one vertex's
coordinates and no connectivity; every tet of its star stays positive and the star gets no
more slivers than it had.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.flat import TET_FACES
from meshwright.tet._flips import C_MOVES, C_REMOVED_MOVE, C_WORK, _orient, _tet_ratio

__all__ = ["move_pass", "vertex_stars"]

# Rounds of the compass search that refines a vertex move, and its directions: the six
# axes and the eight cube diagonals (more than the axes, so that the search does not
# stall on the kinks of the max-min objective where no axis direction helps).
_SEARCH_ROUNDS = 8
_DIRS = np.array(
    [[i, j, k] for i in (-1, 0, 1) for j in (-1, 0, 1) for k in (-1, 0, 1) if abs(i) + abs(j) + abs(k) in (1, 3)],
    dtype=np.float64,
)
_DIRS /= np.sqrt((_DIRS**2).sum(axis=1))[:, None]
# Star evaluations one vertex's search may make: the current position, the 13 candidates,
# the compass rounds (each direction and both normals), and the count before / after a move.
_POSITIONS = 1 + 13 + _SEARCH_ROUNDS * (_DIRS.shape[0] + 2) + 2


@njit(cache=True)
def vertex_stars(tet, ntet, nv):
    """Compressed lists of the live slots around each vertex.

    Returns
    -------
    first : (nv + 1,) int64
    slots : (4 * live,) int64
        The tets of vertex v are ``slots[first[v]:first[v + 1]]``.
    """
    first = np.zeros(nv + 1, np.int64)
    for t in range(ntet):
        if tet[4 * t] >= 0:
            for k in range(4):
                first[tet[4 * t + k] + 1] += 1
    for v in range(nv):
        first[v + 1] += first[v]
    fill = first[:-1].copy()
    slots = np.empty(first[nv], np.int64)
    for t in range(ntet):
        if tet[4 * t] >= 0:
            for k in range(4):
                v = tet[4 * t + k]
                slots[fill[v]] = t
                fill[v] += 1
    return first, slots


@njit(cache=True)
def _star_worst(pts, tet, first, slots, v, x, y, z, threshold, floor, bound):
    """Smallest ratio and sliver count of v's star with v placed at (x, y, z).

    A call, not inlined: move_pass evaluates it at five places, and five inlined copies of
    the star loop (with the ratio and exact orientation code) made move_pass the third most
    expensive kernel to compile.

    Returns -inf as soon as a tet's float ratio is <= ``floor`` (the position cannot
    win, so the exact tests are skipped) or a tet would not be positive (exact
    ``orient3d``, run only once every float ratio has passed).
    """
    ox, oy, oz = pts[v, 0], pts[v, 1], pts[v, 2]
    pts[v, 0] = x
    pts[v, 1] = y
    pts[v, 2] = z
    worst = np.inf
    bad = 0
    for i in range(first[v], first[v + 1]):
        r = _tet_ratio(pts, tet, slots[i], bound)
        if r <= floor:
            worst = -np.inf
            break
        worst = min(worst, r)
        if r < threshold:
            bad += 1
    if worst > -np.inf:
        for i in range(first[v], first[v + 1]):
            t = slots[i]
            if not _orient(pts, tet[4 * t], tet[4 * t + 1], tet[4 * t + 2], tet[4 * t + 3]) > 0.0:
                worst = -np.inf
                break
    pts[v, 0] = ox
    pts[v, 1] = oy
    pts[v, 2] = oz
    return worst, bad


@njit(cache=True)
def move_pass(pts, tet, ratios, ntet, cand, threshold, movable, counters, bound, budget):
    """Move one vertex of every slot of ``cand`` that is still a sliver, when that helps.

    For each movable vertex v of the sliver, candidate positions are tried: towards the
    apex of the ideal tet on the opposite face (1/8 .. all the way), straight away from
    that face (1/32 .. 1/4 of its mean edge), and towards the centroid of v's star
    (1/4 .. all the way); a compass search refines the best of them.  A position counts
    only if every tet of v's star stays positive (exact ``orient3d``) and the star has
    no more slivers than before; the one with the best smallest ratio over the star wins
    if that beats the current one.  ``pts`` is updated in place.

    Each vertex tried costs :data:`_POSITIONS` times its star's size in work units
    (``counters[C_WORK]``, an upper bound on the star tets the search evaluates); the pass
    stops before a sliver once the units reach ``budget``, so the stage's move work stays
    proportional to what the caller allows (a mesh with most tets slivers took 20 minutes).

    Parameters
    ----------
    pts : (n, 3) float64
    tet : (>= 4 ntet,) int32
    ratios : (>= ntet,) float64
        Sliver ratios of the slots (:func:`meshwright.tet._flips.all_ratios`); those of a
        moved vertex's star are recomputed.
    ntet : int
    cand : (c,) int64
        Slots to try, worst first.
    threshold : float
    movable : (n,) bool
    counters : (N_COUNTERS,) int64
        Incremented: ``C_MOVES``, ``C_REMOVED_MOVE`` (slivers of the star before
        minus after; a move never adds slivers to the star) and ``C_WORK``.
    bound : (2,) float64
        As for :func:`meshwright.tet._flips.flip_pass`.
    budget : int
        Work units after which the pass stops.

    Returns
    -------
    moved : int
        Vertices moved.
    stopped : bool
        The pass stopped at ``budget`` with candidates left.
    """
    nv = pts.shape[0]
    first, slots = vertex_stars(tet, ntet, nv)
    cands = np.empty((13, 3))
    moved = 0
    for ci in range(cand.shape[0]):
        t = cand[ci]
        if tet[4 * t] < 0 or not _tet_ratio(pts, tet, t, bound) < threshold:
            continue
        if counters[C_WORK] >= budget:
            return moved, True
        best_gain = 0.0
        best_v = -1
        best_x = 0.0
        best_y = 0.0
        best_z = 0.0
        for k in range(4):
            v = np.int64(tet[4 * t + k])  # int64 as best_v: one specialisation of _star_worst
            if not movable[v]:
                continue
            px, py, pz = pts[v, 0], pts[v, 1], pts[v, 2]
            counters[C_WORK] += _POSITIONS * (first[v + 1] - first[v])
            q0, bad0 = _star_worst(pts, tet, first, slots, v, px, py, pz, threshold, -np.inf, bound)
            a = tet[4 * t + TET_FACES[k, 0]]
            b = tet[4 * t + TET_FACES[k, 1]]
            c = tet[4 * t + TET_FACES[k, 2]]
            # Inward normal of the face opposite v (its outward normal points away from v).
            e1x, e1y, e1z = pts[b, 0] - pts[a, 0], pts[b, 1] - pts[a, 1], pts[b, 2] - pts[a, 2]
            e2x, e2y, e2z = pts[c, 0] - pts[a, 0], pts[c, 1] - pts[a, 1], pts[c, 2] - pts[a, 2]
            nx = -(e1y * e2z - e1z * e2y)
            ny = -(e1z * e2x - e1x * e2z)
            nz = -(e1x * e2y - e1y * e2x)
            nn = np.sqrt(nx * nx + ny * ny + nz * nz)
            if nn == 0.0:
                continue
            nx, ny, nz = nx / nn, ny / nn, nz / nn
            h = 0.0
            for i in range(3):
                x0 = a if i == 0 else (b if i == 1 else c)
                x1 = b if i == 0 else (c if i == 1 else a)
                dx, dy, dz = pts[x1, 0] - pts[x0, 0], pts[x1, 1] - pts[x0, 1], pts[x1, 2] - pts[x0, 2]
                h += np.sqrt(dx * dx + dy * dy + dz * dz) / 3.0
            gx = (pts[a, 0] + pts[b, 0] + pts[c, 0]) / 3.0
            gy = (pts[a, 1] + pts[b, 1] + pts[c, 1]) / 3.0
            gz = (pts[a, 2] + pts[b, 2] + pts[c, 2]) / 3.0
            apex = np.sqrt(2.0 / 3.0) * h  # height of the regular tet on an equilateral face
            ix, iy, iz = gx + apex * nx, gy + apex * ny, gz + apex * nz
            sx = 0.0
            sy = 0.0
            sz = 0.0
            ns = 0
            for i in range(first[v], first[v + 1]):
                st = slots[i]
                for j in range(4):
                    w = tet[4 * st + j]
                    if w != v:
                        sx += pts[w, 0]
                        sy += pts[w, 1]
                        sz += pts[w, 2]
                        ns += 1
            sx, sy, sz = sx / ns, sy / ns, sz / ns
            nc = 0
            for f in (0.125, 0.25, 0.5, 0.75, 1.0):
                cands[nc, 0] = px + f * (ix - px)
                cands[nc, 1] = py + f * (iy - py)
                cands[nc, 2] = pz + f * (iz - pz)
                nc += 1
            for f in (0.03125, 0.0625, 0.125, 0.25):
                cands[nc, 0] = px + f * h * nx
                cands[nc, 1] = py + f * h * ny
                cands[nc, 2] = pz + f * h * nz
                nc += 1
            for f in (0.25, 0.5, 0.75, 1.0):
                cands[nc, 0] = px + f * (sx - px)
                cands[nc, 1] = py + f * (sy - py)
                cands[nc, 2] = pz + f * (sz - pz)
                nc += 1
            qv = q0
            xv, yv, zv = px, py, pz
            for i in range(nc):
                q, bad = _star_worst(pts, tet, first, slots, v, cands[i, 0], cands[i, 1], cands[i, 2], threshold, qv, bound)
                if q > qv and bad <= bad0:
                    qv = q
                    xv, yv, zv = cands[i, 0], cands[i, 1], cands[i, 2]
            # Compass search from the best candidate along _DIRS and the face normal,
            # halving the step after a round without gain.
            step = 0.125 * h
            for _ in range(_SEARCH_ROUNDS):
                gained = False
                for dxn in range(_DIRS.shape[0] + 2):
                    if dxn < _DIRS.shape[0]:
                        ax, ay, az = _DIRS[dxn, 0], _DIRS[dxn, 1], _DIRS[dxn, 2]
                    else:
                        sign = 1.0 if dxn == _DIRS.shape[0] else -1.0
                        ax, ay, az = sign * nx, sign * ny, sign * nz
                    cx, cy, cz = xv + step * ax, yv + step * ay, zv + step * az
                    q, bad = _star_worst(pts, tet, first, slots, v, cx, cy, cz, threshold, qv, bound)
                    if q > qv and bad <= bad0:
                        qv = q
                        xv, yv, zv = cx, cy, cz
                        gained = True
                if not gained:
                    step *= 0.5
            if qv - q0 > best_gain:
                best_gain = qv - q0
                best_v = v
                best_x, best_y, best_z = xv, yv, zv
        if best_v < 0:
            continue
        _, before = _star_worst(
            pts, tet, first, slots, best_v, pts[best_v, 0], pts[best_v, 1], pts[best_v, 2], threshold, -np.inf, bound
        )
        _, after = _star_worst(pts, tet, first, slots, best_v, best_x, best_y, best_z, threshold, -np.inf, bound)
        pts[best_v, 0] = best_x
        pts[best_v, 1] = best_y
        pts[best_v, 2] = best_z
        for i in range(first[best_v], first[best_v + 1]):
            ratios[slots[i]] = _tet_ratio(pts, tet, slots[i], bound)
        counters[C_MOVES] += 1
        counters[C_REMOVED_MOVE] += before - after
        moved += 1
    return moved, False
