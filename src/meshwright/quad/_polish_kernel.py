"""Numba kernels of the quads' max-min pattern search (:func:`meshwright.quad.polish.polish`):
:func:`polish_rounds` runs the passes, :func:`polish_nodes` one pass over the marked nodes,
:func:`vertex_cells` builds the vertex-to-quad table they read, :func:`may_be_below` says
cheaply whether any quad needs the search.

Quality rules, floating point.  Array layout: points (n, 2) float64; quads (q, 4) int64
counter-clockwise with a vertex-to-quad table in CSR form, ``cell_ptr`` (n + 1,) and
``cell_idx`` (4 q,) int64.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.quad._paving_kernel import corner_min_sine

__all__ = ["may_be_below", "polish_nodes", "polish_rounds", "vertex_cells"]

WIDE = 1.0 + 1e-9  # relative margin of _below's test without the sine's own rounding


@njit
def _quad_min_sine(p, q, c):
    """Smallest corner sine of quad c (:func:`corner_min_sine`)."""
    return corner_min_sine(p, q[c, 0], q[c, 1], q[c, 2], q[c, 3])


@njit
def _clearly_above(p, q, c, f2):
    """Whether every corner of quad c has ``cr^2 >= f2 ll`` (cross product ``cr``,
    squared sides' product ``ll``, ``f2`` the squared floor with the margin :data:`WIDE`):
    then its sine is above the floor whatever the rounding of the sine's own hypot and
    division (errors of a few 1e-16)."""
    for k in range(4):
        u = q[c, (k + 3) % 4]
        w = q[c, k]
        z = q[c, (k + 1) % 4]
        ux = p[z, 0] - p[w, 0]
        uy = p[z, 1] - p[w, 1]
        wx = p[u, 0] - p[w, 0]
        wy = p[u, 1] - p[w, 1]
        cr = ux * wy - uy * wx
        ll = (ux * ux + uy * uy) * (wx * wx + wy * wy)
        if not (cr > 0.0 and 1e-200 < ll < 1e200 and cr * cr >= f2 * ll):
            return False
    return True


@njit
def _below(p, q, c, floor):
    """Whether quad c's smallest corner sine (:func:`_quad_min_sine`) is below ``floor``;
    only a quad not clearly above it (:func:`_clearly_above`) is computed (most quads
    are clearly above, and the hypot of every corner was most of the setup)."""
    if floor > 0.0 and _clearly_above(p, q, c, floor * floor * WIDE):
        return False
    return _quad_min_sine(p, q, c) < floor


@njit
def _sine_at(p, a, b, d, v, x, y):
    """Sine of the corner at b between b->d and b->a, node ``v`` taken at ``(x, y)``."""
    bx = x if b == v else p[b, 0]
    by = y if b == v else p[b, 1]
    ux = (x if d == v else p[d, 0]) - bx
    uy = (y if d == v else p[d, 1]) - by
    wx = (x if a == v else p[a, 0]) - bx
    wy = (y if a == v else p[a, 1]) - by
    den = np.sqrt((ux * ux + uy * uy) * (wx * wx + wy * wy))
    return (ux * wy - uy * wx) / den if den > 0.0 else -1.0


@njit(cache=True)
def polish_nodes(p, q, cell_ptr, cell_idx, nodes, dirs, steps, settled, kind, g, slide, slide_steps):
    """One pass of the max-min pattern search over ``nodes`` in place (see
    :func:`meshwright.quad.polish.polish`): each node takes the move, among
    ``steps`` times its shortest edge along each of ``dirs``, that raises the smallest
    corner sine of its quads most, or stays.  Returns the number of nodes moved.

    ``settled`` (n,) bool, updated: a node whose last visit left it in place, no node
    of its quads having moved since.  Its visit would read the same coordinates and
    stay again, so it is skipped (on a sliver's closure most marked nodes cannot
    improve, and every pass searched them again).

    The corners opposite the node in its quads do not move: while their smallest sine
    is not above the star's, no move can raise the star's minimum and the node is
    skipped; otherwise a trial is compared on the moving corners only, and its test
    stops at the first one not above the best so far (the same choice as comparing the
    whole star's minimum).  The test starts at the corner that stopped the previous
    trial, which mostly stops this one too (about 40 % of the polish's time on the
    three-element airfoil); a trial that passes reads every corner, so the value kept
    does not depend on the order.

    ``kind`` (c,) int64 and ``g`` (c, 5) float64 are scratch for one node's moving
    corners (c at least three per quad of a node): the node is the corner's first
    neighbour (0), its apex (1) or its second neighbour (2), and ``g`` holds what does
    not move: the other two points, or the apex and its fixed side with that side's
    squared length.  The trials read them instead of the quads (a call per trial with
    the point and quad arrays cost Numba's reference counts on each), with the same
    arithmetic as :func:`_sine_at`, so the same values.

    ``slide`` (n, 2) int64: a line node that may move along its straight line piece has
    its two line neighbours there (-1 elsewhere).  Its trials are ``slide_steps`` times
    its shorter line edge towards each neighbour instead of the 2-D pattern: a fraction
    under one of the way to a neighbour on the piece, so it stays on the piece (up to
    the rounding of that point) and never passes a neighbour."""
    moved = 0
    ntry2 = steps.shape[0] * dirs.shape[0]
    nsl = slide_steps.shape[0]
    for i in range(nodes.shape[0]):
        v = nodes[i]
        if settled[v]:
            continue
        settled[v] = True
        x0 = p[v, 0]
        y0 = p[v, 1]
        reach = np.inf
        fixed_min = 1.0
        m = 0
        for t in range(cell_ptr[v], cell_ptr[v + 1]):
            c = cell_idx[t]
            for k in range(4):
                if q[c, k] == v:
                    for o in (1, 3):
                        w = q[c, (k + o) % 4]
                        reach = min(reach, np.hypot(p[w, 0] - x0, p[w, 1] - y0))
                    o2 = (k + 2) % 4
                    fixed_min = min(fixed_min, _sine_at(p, q[c, (o2 + 3) % 4], q[c, o2], q[c, (o2 + 1) % 4], v, x0, y0))
            # The corners that move with v (all but the one opposite it), at b between
            # b -> d and b -> a.
            for k in range(4):
                if q[c, (k + 2) % 4] == v:
                    continue
                a = q[c, (k + 3) % 4]
                b = q[c, k]
                d = q[c, (k + 1) % 4]
                if b != v and (b == slide[v, 0] or b == slide[v, 1]):
                    # A sliding node moves along the side from this corner's apex: the
                    # corner does not change, and its rounding must not pick the move.
                    fixed_min = min(fixed_min, _sine_at(p, a, b, d, v, x0, y0))
                    continue
                if b == v:
                    kind[m] = 1
                    g[m, 0] = p[d, 0]
                    g[m, 1] = p[d, 1]
                    g[m, 2] = p[a, 0]
                    g[m, 3] = p[a, 1]
                elif d == v:
                    kind[m] = 2
                    wx = p[a, 0] - p[b, 0]
                    wy = p[a, 1] - p[b, 1]
                    g[m, 0] = p[b, 0]
                    g[m, 1] = p[b, 1]
                    g[m, 2] = wx
                    g[m, 3] = wy
                    g[m, 4] = wx * wx + wy * wy
                else:
                    kind[m] = 0
                    ux = p[d, 0] - p[b, 0]
                    uy = p[d, 1] - p[b, 1]
                    g[m, 0] = p[b, 0]
                    g[m, 1] = p[b, 1]
                    g[m, 2] = ux
                    g[m, 3] = uy
                    g[m, 4] = ux * ux + uy * uy
                m += 1
        best = -np.inf
        first = 0
        bx = x0
        by = y0
        ntry = ntry2
        line = slide[v, 0] >= 0
        la = lb = short = 1.0
        if line:
            ntry = 2 * nsl
            la = np.hypot(p[slide[v, 0], 0] - x0, p[slide[v, 0], 1] - y0)
            lb = np.hypot(p[slide[v, 1], 0] - x0, p[slide[v, 1], 1] - y0)
            short = min(la, lb)
        # Trial -1 is the node where it is (nothing to beat); then steps by directions.
        for tr in range(-1, ntry):
            if tr < 0:
                x = x0
                y = y0
            elif line:
                s = tr // 2
                side = tr - 2 * s
                w = slide[v, side]
                f = slide_steps[s] * short / (la if side == 0 else lb)
                x = x0 + f * (p[w, 0] - x0)
                y = y0 + f * (p[w, 1] - y0)
            else:
                s = tr // dirs.shape[0]
                e = tr - s * dirs.shape[0]
                x = x0 + steps[s] * reach * dirs[e, 0]
                y = y0 + steps[s] * reach * dirs[e, 1]
            worst = 1.0
            for jj in range(m):
                j = jj + first
                if j >= m:
                    j -= m
                if kind[j] == 1:
                    ux = g[j, 0] - x
                    uy = g[j, 1] - y
                    wx = g[j, 2] - x
                    wy = g[j, 3] - y
                    den = np.sqrt((ux * ux + uy * uy) * (wx * wx + wy * wy))
                elif kind[j] == 2:
                    ux = x - g[j, 0]
                    uy = y - g[j, 1]
                    wx = g[j, 2]
                    wy = g[j, 3]
                    den = np.sqrt((ux * ux + uy * uy) * g[j, 4])
                else:
                    ux = g[j, 2]
                    uy = g[j, 3]
                    wx = x - g[j, 0]
                    wy = y - g[j, 1]
                    den = np.sqrt(g[j, 4] * (wx * wx + wy * wy))
                sn = (ux * wy - uy * wx) / den if den > 0.0 else -1.0
                if sn < worst:
                    worst = sn
                    if worst <= best:
                        first = j
                        break
            if tr < 0:
                best = min(fixed_min, worst)
            elif worst > best:
                best = min(worst, fixed_min)
                bx = x
                by = y
            if fixed_min <= best:
                break
        if bx != x0 or by != y0:
            p[v, 0] = bx
            p[v, 1] = by
            moved += 1
            for t in range(cell_ptr[v], cell_ptr[v + 1]):
                for k in range(4):
                    settled[q[cell_idx[t], k]] = False
    return moved


@njit(cache=True)
def vertex_cells(q, n):
    """The vertex-to-quad table of ``q`` (m, 4) int64 over ``n`` vertices in CSR form, by
    a counting sort: ``cell_ptr`` (n + 1,) int64 and ``cell_idx`` (4 m,) int64, each
    vertex's quads ascending (the order of a stable argsort of ``q.ravel()``, without
    its sort)."""
    m = q.shape[0]
    ptr = np.zeros(n + 1, dtype=np.int64)
    for c in range(m):
        for k in range(4):
            ptr[q[c, k] + 1] += 1
    for v in range(n):
        ptr[v + 1] += ptr[v]
    nxt = ptr[:n].copy()
    idx = np.empty(4 * m, dtype=np.int64)
    for c in range(m):
        for k in range(4):
            v = q[c, k]
            idx[nxt[v]] = c
            nxt[v] += 1
    return ptr, idx


@njit(cache=True)
def polish_rounds(p, q, cell_ptr, cell_idx, fixed, floor, rounds, dirs, steps, slide, slide_steps):
    """The passes of :func:`meshwright.quad.polish.polish` in place: in each, the
    free nodes (sliding ones included, ``slide`` as :func:`polish_nodes` reads it) of the quads whose smallest corner sine is below ``floor``, in ascending
    order, get one :func:`polish_nodes` visit; which quads are below is kept per quad
    (:func:`_below`) and decided again around the nodes that moved.  Stops after ``rounds`` passes or one that
    moves nothing."""
    nq = q.shape[0]
    n = p.shape[0]
    low = np.empty(nq, dtype=np.bool_)
    for c in range(nq):
        low[c] = _below(p, q, c, floor)
    mark = np.zeros(n, dtype=np.bool_)
    settled = np.zeros(n, dtype=np.bool_)
    nodes = np.empty(n, dtype=np.int64)
    before = np.empty((n, 2))
    most = 0
    for v in range(n):
        most = max(most, cell_ptr[v + 1] - cell_ptr[v])
    kind = np.empty(3 * most, dtype=np.int64)
    g = np.empty((3 * most, 5))
    for _ in range(rounds):
        for c in range(nq):
            if low[c]:
                for k in range(4):
                    mark[q[c, k]] = True
        m = 0
        for v in range(n):
            if mark[v]:
                mark[v] = False
                if not fixed[v]:
                    nodes[m] = v
                    before[m, 0] = p[v, 0]
                    before[m, 1] = p[v, 1]
                    m += 1
        if m == 0:
            break
        if polish_nodes(p, q, cell_ptr, cell_idx, nodes[:m], dirs, steps, settled, kind, g, slide, slide_steps) == 0:
            break
        for i in range(m):
            v = nodes[i]
            if p[v, 0] != before[i, 0] or p[v, 1] != before[i, 1]:
                for t in range(cell_ptr[v], cell_ptr[v + 1]):
                    c = cell_idx[t]
                    low[c] = _below(p, q, c, floor)
    return p


@njit(cache=True)
def may_be_below(xy, quads, floor):
    """Whether a quad (q, 4) may have a corner sine below ``floor`` > 0: False only when
    every quad is clearly above it (:func:`_clearly_above`; no hypot: the common case, a
    mesh with no quad to polish, costs one pass of products)."""
    f2 = floor * floor * WIDE
    for i in range(quads.shape[0]):
        if not _clearly_above(xy, quads, i, f2):
            return True
    return False
