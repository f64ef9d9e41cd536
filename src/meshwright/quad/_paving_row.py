"""Numba kernels of a paving row's geometry (:mod:`meshwright.quad.paving`, Blacker and
Stephenson 1991, steps 1 and 3): angles, node classes, row depth, the provisional new
edges the row adjustment measures, the new paving boundary and its relaxation, and the
bisectors of every paving node that the joints look along, the seams' candidates and
the check that seams and joints leave every directed paving-boundary edge once.

A row costs one call of each kernel around one call of the size field (the kernel of
its new nodes and quads, ``row_nodes``, and of its tucks and wedges, ``adjust_row``, are
in :mod:`meshwright.quad._paving_kernel`), instead of some sixty small NumPy calls.
Everything here is floating point: the geometry a row is built from, not a topological
decision (the row's exact check is ``check_row``).

Array layout: a paving boundary's coordinates ``p`` (n, 2) float64 in order, its region
on the left (node i's neighbours are i - 1 and i + 1, cyclic); node ids (n,) int64;
several boundaries as one id array with offsets ``off`` (k + 1,) int64.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["edges_once", "front_bisectors", "recent_nodes", "row_classes", "row_finish", "row_prepare", "sharp_nodes"]


@njit(inline="always")
def _interior(nx, ny, px, py):
    """Interior angle in (0, 2 pi] at a node whose next neighbour lies at (nx, ny) and whose
    previous one at (px, py) from it (the region on the left)."""
    a = np.arctan2(nx * py - ny * px, nx * px + ny * py)
    if a <= 0.0:
        a += 2.0 * np.pi
    return a


@njit(cache=True)
def row_classes(deg, end, corner, reversal):
    """Node classes from interior angles in degrees (step 1; see
    :func:`meshwright.quad.paving.node_classes`): 0 row end below ``end``, 1 side below
    ``corner``, 3 corner below ``reversal``, 5 reversal; of two neighbouring row ends the
    sharper one (the first in a tie) keeps its class.  The row ends are taken sharpest
    first by repeated scans (few per row; no sort to compile)."""
    n = deg.shape[0]
    m = np.empty(n, dtype=np.int64)
    ne = 0
    for i in range(n):
        a = deg[i]
        m[i] = 0 if a < end else (1 if a < corner else (3 if a < reversal else 5))
        if m[i] == 0:
            ne += 1
    if ne > 1:
        keep = np.zeros(n, dtype=np.bool_)
        done = np.zeros(n, dtype=np.bool_)
        for _ in range(ne):
            pick = -1
            for i in range(n):
                if m[i] == 0 and not done[i] and (pick < 0 or deg[i] < deg[pick]):
                    pick = i
            done[pick] = True
            if not keep[(pick - 1) % n] and not keep[(pick + 1) % n]:
                keep[pick] = True
        for i in range(n):
            if m[i] == 0 and not keep[i]:
                m[i] = 1
    return m


@njit(cache=True)
def row_prepare(p, h, scale, end, corner, reversal):
    """Steps 1 and 3 of a row before the size field is asked again: each paving node's
    interior angle, class, row depth and outgoing edge direction, and the midpoints and
    lengths of the edges between the provisional new nodes (on the bisectors, as a row of
    side nodes would place them) for the row adjustment's running surplus.

    Parameters
    ----------
    p : (n, 2) float64
        The paving boundary's nodes in order, region on the left.
    h : (n,) float64
        The size field at those nodes.
    scale : (n,) float64
        Factor on the row depth (lowered by repairs).
    end, corner, reversal : float
        The class thresholds in degrees (:func:`row_classes`).

    Returns
    -------
    ang : (n,) float64
        Interior angles in radians, in (0, 2 pi].
    deg : (n,) float64
        The same in degrees.
    m : (n,) int64
        Classes (:func:`row_classes`).
    depth : (n,) float64
        The size kept within [1/2, 2] of the mean of the two edges at the node, averaged
        (1/4, 1/2, 1/4) along the row, times ``scale``.
    th0 : (n,) float64
        Direction of the edge to the next node.
    mid : (n, 2) float64
        Midpoint of the provisional new edge from node i's new node to node i + 1's.
    plen : (n,) float64
        Its length.
    """
    n = p.shape[0]
    ang = np.empty(n)
    deg = np.empty(n)
    th0 = np.empty(n)
    le = np.empty(n)
    for i in range(n):
        nx = p[(i + 1) % n, 0] - p[i, 0]
        ny = p[(i + 1) % n, 1] - p[i, 1]
        px = p[(i - 1) % n, 0] - p[i, 0]
        py = p[(i - 1) % n, 1] - p[i, 1]
        a = _interior(nx, ny, px, py)
        ang[i] = a
        deg[i] = a * (180.0 / np.pi)
        th0[i] = np.arctan2(ny, nx)
        le[i] = np.hypot(nx, ny)
    d = np.empty(n)
    for i in range(n):
        lm = 0.5 * (le[i] + le[(i - 1) % n])
        d[i] = min(max(h[i], 0.5 * lm), 2.0 * lm)
    depth = np.empty(n)
    for i in range(n):
        depth[i] = 0.25 * (d[(i - 1) % n] + 2.0 * d[i] + d[(i + 1) % n]) * scale[i]
    prov = np.empty((n, 2))
    for i in range(n):
        th = th0[i] + 0.5 * ang[i]
        r = depth[i] / max(np.sin(0.5 * ang[i]), 0.5)
        prov[i, 0] = p[i, 0] + r * np.cos(th)
        prov[i, 1] = p[i, 1] + r * np.sin(th)
    mid = np.empty((n, 2))
    plen = np.empty(n)
    for i in range(n):
        j = (i + 1) % n
        mid[i, 0] = 0.5 * (prov[i, 0] + prov[j, 0])
        mid[i, 1] = 0.5 * (prov[i, 1] + prov[j, 1])
        plen[i] = np.hypot(prov[j, 0] - prov[i, 0], prov[j, 1] - prov[i, 1])
    return ang, deg, row_classes(deg, end, corner, reversal), depth, th0, mid, plen


@njit(cache=True)
def row_finish(xy, quads, front, n0, relax):
    """Step 3's end: the new paving boundary from :func:`row_nodes`' spokes (a node
    repeated by merged spokes kept once where consecutive), refused (None) when it has
    fewer than two nodes, an odd count, or a quad has a repeated corner; on a boundary
    of more than six nodes the new nodes (``xy``, ids from ``n0``) relax ``relax``
    Jacobi sweeps along the row, tangentially (corners keep their place, the row its
    depth).  ``xy`` is changed in place; returns the new boundary."""
    k = front.shape[0]
    out = np.empty(k, dtype=np.int64)
    m = 0
    for i in range(k):
        if k <= 1 or front[i] != front[(i - 1) % k]:
            out[m] = front[i]
            m += 1
    if m < 2 or m % 2:
        return None
    for c in range(quads.shape[0]):
        for a in range(4):
            for b in range(a + 1, 4):
                if quads[c, a] == quads[c, b]:
                    return None
    f = out[:m]
    if m > 6:
        c = np.empty((m, 2))
        for _ in range(relax):
            for i in range(m):
                c[i, 0] = xy[f[i] - n0, 0]
                c[i, 1] = xy[f[i] - n0, 1]
            for i in range(m):
                nx, ny = c[(i + 1) % m, 0], c[(i + 1) % m, 1]
                px, py = c[(i - 1) % m, 0], c[(i - 1) % m, 1]
                tx = nx - px
                ty = ny - py
                tn = max(np.hypot(tx, ty), 1e-300)
                tx /= tn
                ty /= tn
                lx = 0.25 * (px + nx - 2.0 * c[i, 0])
                ly = 0.25 * (py + ny - 2.0 * c[i, 1])
                s = lx * tx + ly * ty
                xy[f[i] - n0, 0] = c[i, 0] + s * tx
                xy[f[i] - n0, 1] = c[i, 1] + s * ty
    return f.copy()


@njit(cache=True)
def front_bisectors(pts, ids, off):
    """Unit bisector into the unmeshed region at every slot of several paving
    boundaries (``ids[off[k]:off[k + 1]]`` is boundary k): the direction of the edge to
    the next node turned by half the interior angle.  Returns (m, 2) float64."""
    out = np.empty((ids.shape[0], 2))
    for k in range(off.shape[0] - 1):
        s = off[k]
        n = off[k + 1] - s
        for i in range(n):
            v = ids[s + i]
            w = ids[s + (i + 1) % n]
            u = ids[s + (i - 1) % n]
            nx = pts[w, 0] - pts[v, 0]
            ny = pts[w, 1] - pts[v, 1]
            px = pts[u, 0] - pts[v, 0]
            py = pts[u, 1] - pts[v, 1]
            th = np.arctan2(ny, nx) + 0.5 * _interior(nx, ny, px, py)
            out[s + i, 0] = np.cos(th)
            out[s + i, 1] = np.sin(th)
    return out


@njit(cache=True)
def sharp_nodes(pts, front, n_fixed, below):
    """Positions along the paving boundary ``front`` (node ids) of its floating nodes
    (ids from ``n_fixed`` on) whose interior angle is below ``below`` degrees, sharpest
    first (ties in boundary order; an insertion sort: there are few): the seams'
    candidates.  Returns (j,) int64."""
    n = front.shape[0]
    deg = np.empty(n)
    pick = np.empty(n, dtype=np.int64)
    j = 0
    for i in range(n):
        v = front[i]
        w = front[(i + 1) % n]
        u = front[(i - 1) % n]
        nx = pts[w, 0] - pts[v, 0]
        ny = pts[w, 1] - pts[v, 1]
        px = pts[u, 0] - pts[v, 0]
        py = pts[u, 1] - pts[v, 1]
        a = _interior(nx, ny, px, py) * (180.0 / np.pi)
        if a < below and v >= n_fixed:
            t = j
            while t > 0 and deg[t - 1] > a:
                deg[t] = deg[t - 1]
                pick[t] = pick[t - 1]
                t -= 1
            deg[t] = a
            pick[t] = i
            j += 1
    return pick[:j].copy()


@njit(cache=True)
def edges_once(ids, off):
    """Whether every directed edge of several paving boundaries (``ids[off[k]:off[k + 1]]``
    is boundary k, cyclic) occurs once and none joins a node to itself: what a seam or
    joint must leave.  The edges are grouped by their first node (a counting sort), and
    each group's ends compared pairwise (a node is on few paving boundaries)."""
    m = ids.shape[0]
    if m == 0:
        return True
    top = 0
    for i in range(m):
        top = max(top, ids[i])
    ptr = np.zeros(top + 2, dtype=np.int64)
    for i in range(m):
        ptr[ids[i] + 1] += 1
    for v in range(top + 1):
        ptr[v + 1] += ptr[v]
    fill = ptr[:-1].copy()
    dest = np.empty(m, dtype=np.int64)
    for k in range(off.shape[0] - 1):
        s = off[k]
        n = off[k + 1] - s
        for i in range(n):
            a = ids[s + i]
            b = ids[s + (i + 1) % n]
            if a == b:
                return False
            dest[fill[a]] = b
            fill[a] += 1
    for v in range(top + 1):
        for x in range(ptr[v], ptr[v + 1]):
            for y in range(x + 1, ptr[v + 1]):
                if dest[x] == dest[y]:
                    return False
    return True


@njit(cache=True)
def recent_nodes(q, n, round_of, on_front, n_fixed, rnd):
    """The nodes of quads ``q`` (k, 4) int64 over ``n`` nodes, numbered locally for the row
    smoothing of round ``rnd`` (step 4): ``used`` (m,) int64 ascending (the sweeps'
    order), ``local`` (k, 4) int64 the quads in those numbers, ``fixed`` (m,) bool every
    node but the floating ones of rounds ``rnd - 1`` and ``rnd - 2`` (``round_of``) off
    the paving boundaries (``on_front``).  One call for what took a dozen NumPy calls per
    row (a byte table of the used nodes read back in order, not a sort)."""
    mark = np.zeros(n, dtype=np.bool_)
    for c in range(q.shape[0]):
        for k in range(4):
            mark[q[c, k]] = True
    lut = np.empty(n, dtype=np.int64)
    m = 0
    for v in range(n):
        if mark[v]:
            lut[v] = m
            m += 1
    used = np.empty(m, dtype=np.int64)
    fixed = np.empty(m, dtype=np.bool_)
    for v in range(n):
        if mark[v]:
            i = lut[v]
            used[i] = v
            ro = round_of[v]
            fixed[i] = not (v >= n_fixed and rnd - 2 <= ro <= rnd - 1 and not on_front[v])
    local = np.empty((q.shape[0], 4), dtype=np.int64)
    for c in range(q.shape[0]):
        for k in range(4):
            local[c, k] = lut[q[c, k]]
    return used, local, fixed
