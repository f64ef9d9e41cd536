"""Numba kernels of the paving method (:mod:`meshwright.quad.paving`): the row checks.

A candidate row of quads (Blacker and Stephenson 1991, step 3) is accepted only if none of
its new edges crosses or touches an edge of any paving boundary or another new edge, and no
node of a paving boundary lies inside or on one of its new quads (step 7's intersection
check); every sign is the exact ``orient2d``; :func:`check_row` runs the whole check of
one row (its new edges found, the crossings, the quads' convexity and the nodes inside
them, the culprits traced back to the paving nodes they grew from) in one call;
:func:`row_nodes` builds a row's nodes and quads and :func:`adjust_row` its tucks and
wedges.  :func:`facing_pairs` finds the paving nodes close enough to be joined (a quality
rule, floating point); the cleanup's pattern search is :mod:`meshwright.quad.polish`.

Array layout: ``pts`` (n, 2) float64; segments as two (m,) int64 end arrays ``sa``, ``sb``
(node ids into ``pts``); quads (q, 4) int64 counter-clockwise; node lists (k,) int64.
:func:`row_crossings` sweeps the segments sorted along one axis, so each query visits only
segments whose range there can overlap its own; a row's own check searches a uniform grid
of them instead (:func:`~meshwright.quad._paving_grid.grid_crossings`, the same answer).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.flat import lower_bound
from meshwright.core.predicates import orient2d
from meshwright.quad._paving_grid import grid_crossings, grid_nodes_in_quads, segments_meet
from meshwright.sizing.background import interpolate_walk

__all__ = [
    "adjust_row", "check_row", "convex_quads", "corner_min_sine", "facing_pairs", "row_crossings", "row_nodes",
    "serpentine_order", "sweep_axis", "walk_spacing",
]


RUNGS = 4  # committed nodes a new node of a row notes its rungs from (check_row)
FEW = 8  # row_crossings tests up to this many segments against every one, unsorted


@njit
def sweep_axis(pts, sa, sb):
    """0 (x) or 1 (y): the longer side of the bounding box of the segments ``sa[j] - sb[j]``
    (or of nodes, ``sa`` = ``sb``), along which a sweep separates them best (a sliver
    along y sorted by x put every segment in each query's window)."""
    x0 = np.inf
    x1 = -np.inf
    y0 = np.inf
    y1 = -np.inf
    for j in range(sa.shape[0]):
        for v in (sa[j], sb[j]):
            x0 = min(x0, pts[v, 0])
            x1 = max(x1, pts[v, 0])
            y0 = min(y0, pts[v, 1])
            y1 = max(y1, pts[v, 1])
    return 0 if x1 - x0 >= y1 - y0 else 1


@njit(cache=True)
def row_crossings(pts, na, nb, sa, sb):
    """(k,) bool: which new segments ``(na[i], nb[i])`` meet a segment of ``sa, sb``
    (closed segments, exact) other than at a shared end node.

    ``sa, sb`` holds every paving-boundary edge and the new segments themselves.  The
    segments are swept along the longer axis of their box in classes of extent (each
    class up to twice its shortest, its own sorted list and window): with one window
    as wide as the longest segment, a few long boundary edges beside a sliver's
    200,000 short ones put thousands of segments in every query's window (a row's check
    took 23 s).  The answer does not depend on the classes.
    """
    m = sa.shape[0]
    bad = np.zeros(na.shape[0], dtype=np.bool_)
    if m == 0:
        return bad
    if na.shape[0] <= FEW:
        # A seam's or joint's few edges: each tests every segment's box, where the sort
        # below cost more than the tests (the same answer).
        for i in range(na.shape[0]):
            a = na[i]
            b = nb[i]
            q0 = min(pts[a, 0], pts[b, 0])
            q1 = max(pts[a, 0], pts[b, 0])
            r0 = min(pts[a, 1], pts[b, 1])
            r1 = max(pts[a, 1], pts[b, 1])
            for j in range(m):
                u = sa[j]
                d = sb[j]
                if u == a or u == b or d == a or d == b:
                    continue
                if max(pts[u, 0], pts[d, 0]) < q0 or min(pts[u, 0], pts[d, 0]) > q1:
                    continue
                if max(pts[u, 1], pts[d, 1]) < r0 or min(pts[u, 1], pts[d, 1]) > r1:
                    continue
                if segments_meet(pts, a, b, u, d):
                    bad[i] = True
                    break
        return bad
    ax = sweep_axis(pts, sa, sb)
    bx = 1 - ax
    lo = np.empty(m)
    ext = np.empty(m)
    for j in range(m):
        a0 = pts[sa[j], ax]
        a1 = pts[sb[j], ax]
        lo[j] = min(a0, a1)
        ext[j] = abs(a1 - a0)
    # Class 0: extent up to 8 times the mean; class c: up to 2**c times that (a
    # handful of classes: a base at the smallest extent made thirty on a row, whose
    # searches cost more than its windows; a median cost a sort).
    base = 8.0 * ext.mean()
    cls = np.zeros(m, dtype=np.int64)
    nclass = 1
    if base > 0.0:
        for j in range(m):
            if ext[j] > base:
                cls[j] = min(int(np.ceil(np.log2(ext[j] / base))), 2000)
                nclass = max(nclass, cls[j] + 1)
    # Sorted by (class, low end): one sort by the low end, then a stable counting
    # sort by class; each class's slice and widest extent (empty classes stay empty).
    order0 = np.argsort(lo)
    starts = np.zeros(nclass + 1, dtype=np.int64)
    span = np.zeros(nclass)
    for j in range(m):
        starts[cls[j] + 1] += 1
        span[cls[j]] = max(span[cls[j]], ext[j])
    for c in range(nclass):
        starts[c + 1] += starts[c]
    fill = starts[:nclass].copy()
    order = np.empty(m, dtype=np.int64)
    key = np.empty(m)
    for t in range(m):
        j = order0[t]
        order[fill[cls[j]]] = j
        key[fill[cls[j]]] = lo[j]
        fill[cls[j]] += 1
    for i in range(na.shape[0]):
        a = na[i]
        b = nb[i]
        q0 = min(pts[a, ax], pts[b, ax])
        q1 = max(pts[a, ax], pts[b, ax])
        r0 = min(pts[a, bx], pts[b, bx])
        r1 = max(pts[a, bx], pts[b, bx])
        for c in range(nclass):
            if bad[i]:
                break
            k = lower_bound(key, starts[c], starts[c + 1], q0 - span[c])
            while k < starts[c + 1] and key[k] <= q1:
                j = order[k]
                k += 1
                u = sa[j]
                d = sb[j]
                if u == a or u == b or d == a or d == b:
                    continue
                if max(pts[u, ax], pts[d, ax]) < q0:
                    continue
                if min(pts[u, bx], pts[d, bx]) > r1 or max(pts[u, bx], pts[d, bx]) < r0:
                    continue
                if segments_meet(pts, a, b, u, d):
                    bad[i] = True
                    break
    return bad


@njit(cache=True)
def check_row(pts, f, quads, owner, n_old, sa, sb, nodes):
    """Step 7 on a candidate row: which paving nodes its failing quads and edges trace to.

    Parameters
    ----------
    pts : (n, 2) float64
        Committed nodes (ids below ``n_old``) followed by the row's new nodes.
    f : (k,) int64
        The paving boundary the row grows from.
    quads : (q, 4) int64
        The row's quads, counter-clockwise.
    owner : (n - n_old,) int64
        The index into ``f`` each new node grew from.
    n_old : int
        Number of committed nodes.
    sa, sb : (m,) int64
        Edges of every paving boundary, ``f``'s included.
    nodes : (r,) int64
        The nodes of every paving boundary (repeats allowed).

    Returns
    -------
    (k,) bool
        Paving nodes (indices into ``f``) that are corners of a quad that is not strictly
        convex or holds a paving node, or ends of a new edge that meets another new edge or
        a paving-boundary edge, or grew such a new node; all False when the row is valid.

    Notes
    -----
    The grid kernels of :mod:`meshwright.quad._paving_grid` are compiled into this one,
    and Numba's cache checks only this file's stamp: a cached copy keeps their old code
    until this file changes too.
    """
    nq = quads.shape[0]
    big = pts.shape[0]
    k = f.shape[0]
    # The row's edges with a new end: row_nodes builds every edge between two committed
    # nodes from two consecutive nodes of f (the paving boundary's own, not checked).  A
    # rung (committed node to new node) between two quads comes once each way: the new
    # to committed copy is left out when the other was seen (each new node notes up to
    # RUNGS committed nodes it is reached from), which takes a third of the queries and
    # of the edges they search.  Other edges shared by two quads stay listed twice: a
    # copy shares both ends with the other, which the crossing test skips, so no sort is
    # needed (a sort and np.unique here cost seconds of first-run compile).
    rung_n = np.zeros(big - n_old, dtype=np.int64)
    rung = np.empty((big - n_old, RUNGS), dtype=np.int64)
    for c in range(nq):
        for e in range(4):
            a = quads[c, e]
            b = quads[c, (e + 1) % 4]
            if a < n_old <= b and rung_n[b - n_old] < RUNGS:
                rung[b - n_old, rung_n[b - n_old]] = a
                rung_n[b - n_old] += 1
    na = np.empty(4 * nq, dtype=np.int64)
    nb = np.empty(4 * nq, dtype=np.int64)
    ne = 0
    for c in range(nq):
        for e in range(4):
            a = quads[c, e]
            b = quads[c, (e + 1) % 4]
            if a < n_old and b < n_old:
                continue
            if b < n_old <= a:
                twin = False
                for r in range(rung_n[a - n_old]):
                    twin = twin or rung[a - n_old, r] == b
                if twin:
                    continue
            na[ne] = a
            nb[ne] = b
            ne += 1
    # Only edges and nodes that reach the row's bounding box can meet it: a row around
    # one airfoil skips the far field's long edges, which would coarsen the grid of
    # :func:`~meshwright.quad._paving_grid.grid_crossings` and the nodes' sorted sweep.
    x0 = np.inf
    x1 = -np.inf
    y0 = np.inf
    y1 = -np.inf
    for c in range(nq):
        for e in range(4):
            v = quads[c, e]
            x0 = min(x0, pts[v, 0])
            x1 = max(x1, pts[v, 0])
            y0 = min(y0, pts[v, 1])
            y1 = max(y1, pts[v, 1])
    ms = sa.shape[0]
    ea = np.empty(ms + ne, dtype=np.int64)
    eb = np.empty(ms + ne, dtype=np.int64)
    me = 0
    for j in range(ms):
        a = sa[j]
        b = sb[j]
        if max(pts[a, 0], pts[b, 0]) < x0 or min(pts[a, 0], pts[b, 0]) > x1:
            continue
        if max(pts[a, 1], pts[b, 1]) < y0 or min(pts[a, 1], pts[b, 1]) > y1:
            continue
        ea[me] = a
        eb[me] = b
        me += 1
    for j in range(ne):
        ea[me + j] = na[j]
        eb[me + j] = nb[j]
    near = np.empty(nodes.shape[0], dtype=np.int64)
    mn = 0
    for j in range(nodes.shape[0]):
        v = nodes[j]
        if x0 <= pts[v, 0] <= x1 and y0 <= pts[v, 1] <= y1:
            near[mn] = v
            mn += 1
    cross = grid_crossings(pts, na[:ne], nb[:ne], ea[: me + ne], eb[: me + ne])
    inside = grid_nodes_in_quads(pts, quads, near[:mn])
    # Culprit nodes: new ones flag the paving node they grew from, committed ones
    # themselves (a stamp over the committed nodes; f may hold a node twice).
    hit = np.zeros(big, dtype=np.bool_)
    for c in range(nq):
        fail = inside[c]
        for e in range(4):
            if fail:
                break
            a = quads[c, (e + 3) % 4]
            b = quads[c, e]
            d = quads[c, (e + 1) % 4]
            if orient2d(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[d, 0], pts[d, 1]) <= 0.0:
                fail = True
        if fail:
            for e in range(4):
                hit[quads[c, e]] = True
    for i in range(ne):
        if cross[i]:
            hit[na[i]] = True
            hit[nb[i]] = True
    bad = np.zeros(k, dtype=np.bool_)
    for v in range(n_old, big):
        if hit[v]:
            bad[owner[v - n_old]] = True
    for i in range(k):
        if hit[f[i]]:
            bad[i] = True
    return bad


@njit(cache=True)
def facing_pairs(p, nrm, reach, ids, fid, pos, size, out_u, out_v, out_d):
    """Pairs of paving-node slots closer than both their ``reach``, facing each other
    (bisectors ``nrm`` opposed by more than ``acos(0.3)`` and each node in front of the
    other), other than one node twice, and on one paving boundary (``fid``, ``pos``
    along it, ``size`` its length) only more than three steps and an even number apart.
    Writes up to ``len(out_u)`` pairs (u < v) and their distances; returns how many
    there are in all (a quality rule, floating point)."""
    n = p.shape[0]
    order = np.argsort(p[:, 0])
    xs = p[order, 0]
    cnt = 0
    for a in range(n):
        u = order[a]
        # A pair is closer than both reaches, so u's own bounds the window (one long
        # reach in the far field would otherwise widen every node's).
        k = lower_bound(xs, np.int64(0), xs.shape[0], p[u, 0] - reach[u])
        while k < n and xs[k] <= p[u, 0] + reach[u]:
            v = order[k]
            k += 1
            if v <= u or ids[u] == ids[v]:
                continue
            dx = p[v, 0] - p[u, 0]
            dy = p[v, 1] - p[u, 1]
            d = np.sqrt(dx * dx + dy * dy)
            if d >= min(reach[u], reach[v]):
                continue
            if nrm[u, 0] * nrm[v, 0] + nrm[u, 1] * nrm[v, 1] >= -0.3:
                continue
            if dx * nrm[u, 0] + dy * nrm[u, 1] <= 0.0 or dx * nrm[v, 0] + dy * nrm[v, 1] >= 0.0:
                continue
            if fid[u] == fid[v]:
                gap = abs(pos[u] - pos[v])
                gap = min(gap, size[u] - gap)
                if gap <= 3 or gap % 2:
                    continue
            if cnt < out_u.shape[0]:
                out_u[cnt] = u
                out_v[cnt] = v
                out_d[cnt] = d
            cnt += 1
    return cnt


@njit
def corner_min_sine(p, a, b, c, d):
    """Smallest corner sine of quad a b c d (floating point, a quality rule), computed as
    :func:`~meshwright.quad._paving_close.min_sine` computes it (the same rounding: which quads
    are below a floor is the same); -1 at a corner with a zero-length side."""
    v = (a, b, c, d)
    worst = 1.0
    for k in range(4):
        u = v[(k + 3) % 4]
        w = v[k]
        z = v[(k + 1) % 4]
        ux = p[z, 0] - p[w, 0]
        uy = p[z, 1] - p[w, 1]
        wx = p[u, 0] - p[w, 0]
        wy = p[u, 1] - p[w, 1]
        den = np.hypot(ux, uy) * np.hypot(wx, wy)
        s = (ux * wy - uy * wx) / den if den > 0.0 else -1.0
        worst = min(worst, s)
    return worst


@njit(cache=True)
def convex_quads(pts, q):
    """(q,) bool: which quads (q, 4) int64 are strictly convex and counter-clockwise
    (exact ``orient2d`` > 0 at every corner; in one call, not four gathered batches)."""
    out = np.ones(q.shape[0], dtype=np.bool_)
    for c in range(q.shape[0]):
        for k in range(4):
            a = q[c, k]
            b = q[c, (k + 1) % 4]
            d = q[c, (k + 2) % 4]
            if not orient2d(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[d, 0], pts[d, 1]) > 0.0:
                out[c] = False
                break
    return out


@njit(cache=True)
def serpentine_order(xy, k):
    """:func:`meshwright.quad._paving_close.serpentine` in one call: the order of points
    ``xy`` (m, 2) float64 along the rows of a k by k grid of their box, alternate rows
    backwards, by a counting sort of the cells (stable: input order within a cell).  The
    cells are computed as NumPy computes them there, so the order is the same."""
    m = xy.shape[0]
    out = np.arange(m)
    if m < 2:
        return out
    lox = xy[0, 0]
    hix = xy[0, 0]
    loy = xy[0, 1]
    hiy = xy[0, 1]
    for i in range(1, m):
        lox = min(lox, xy[i, 0])
        hix = max(hix, xy[i, 0])
        loy = min(loy, xy[i, 1])
        hiy = max(hiy, xy[i, 1])
    ext = max(hix - lox, hiy - loy)
    if not ext > 0.0:
        return out
    key = np.empty(m, dtype=np.int64)
    count = np.zeros(k * k + 1, dtype=np.int64)
    for i in range(m):
        cx = min(int(k * ((xy[i, 0] - lox) / ext)), k - 1)
        cy = min(int(k * ((xy[i, 1] - loy) / ext)), k - 1)
        key[i] = cy * k + (cx if cy % 2 == 0 else k - 1 - cx)
        count[key[i] + 1] += 1
    for c in range(k * k):
        count[c + 1] += count[c]
    for i in range(m):
        out[count[key[i]]] = i
        count[key[i]] += 1
    return out


@njit(cache=True)
def walk_spacing(pts, tris, nbr, start, items, x0, y0, cell, nx, ny, values, hint, xy):
    """A 2-D background grid's spacing (column 0 of ``values``) at ``xy`` (k, 2), each
    query walking from the triangle the previous one ended in (``hint`` (1,) int64,
    updated; :func:`meshwright.sizing.background.interpolate_walk` with the grid's
    ``kernel_args()``).  The void fill's front asks its new nodes in creation order, a
    step apart, where the grid's own bucket scan searched buckets crowded by the void
    triangulation's long triangles.  Returns (k,) float64."""
    out = np.empty(xy.shape[0])
    for k in range(xy.shape[0]):
        out[k] = interpolate_walk(pts, tris, nbr, start, items, x0, y0, cell, nx, ny, values, 0, hint, xy[k, 0], xy[k, 1])
    return out


@njit(cache=True)
def adjust_row(m, rho, calm_only, floating, deg, gap, tuck_at, tuck_max, wedge_min):
    """Tucks (class 0) and wedges (class 3) of one row from the running surplus of
    predicted edge lengths ``rho - 1`` over each run of side nodes (class 1), step 6;
    ``m`` (n,) int64 is changed in place.  A node qualifies only with side neighbours,
    ``calm_only`` unset, floating, and ``gap`` nodes after the previous change.
    Returns (tucks, wedges)."""
    n = m.shape[0]
    c = 0.0
    tucks = 0
    wedges = 0
    last = -gap
    for i in range(n):
        if m[i] != 1:
            c = 0.0
            continue
        c += rho[i] - 1.0
        calm = m[(i - 1) % n] == 1 and m[(i + 1) % n] == 1 and not calm_only[i] and i - last >= gap
        if c <= -tuck_at and calm and floating[i] and deg[i] < tuck_max:
            m[i] = 0
            c += 2.0
            tucks += 1
            last = i
        elif c >= tuck_at and calm and floating[i] and deg[i] > wedge_min:
            m[i] = 3
            c -= 2.0
            wedges += 1
            last = i
    return tucks, wedges


@njit(inline="always")
def _find(parent, x):
    while parent[x] != x:
        parent[x] = parent[parent[x]]
        x = parent[x]
    return x


@njit(cache=True)
def row_nodes(p, f, ang, m, depth, th0, n0):
    """New nodes and quads of one row on the paving boundary ``f`` (step 3).

    Node i of class ``m[i]`` = 1 (side) grows one node on its bisector, ``depth[i] /
    max(sin(ang/2), 1/2)`` away; class 3 or 5 (corner, reversal) a fan of ``m[i]`` nodes
    (every second one at the diagonal's length); class 0 (row end) none: the last node
    of its previous neighbour and the first of its next one merge (union-find) into one
    node at the mean of the bisector points of the row ends merged into it (each
    ``depth / sin(ang/2)`` inside, at most ``1.5 depth``).  New nodes are numbered from
    ``n0`` in the order of their union-find roots.

    Parameters
    ----------
    p : (n, 2) float64
        The paving nodes' coordinates, in ``f``'s order.
    f : (n,) int64
        The paving boundary's node ids.
    ang, depth, th0 : (n,) float64
        Interior angle, row depth and direction of the outgoing edge at each node.
    m : (n,) int64
        Node classes (0, 1, 3, 5).
    n0 : int
        Id of the first new node.

    Returns
    -------
    ok : bool
        False when the row degenerates (no new node, or a row end beside another).
    xy : (k, 2) float64
        New nodes.
    quads : (q, 4) int64
        The row's quads, counter-clockwise.
    front : (s,) int64
        The new nodes along the row, one entry per spoke (merged ones repeated).
    owner : (k,) int64
        The paving node (index into ``f``) each new node grew from.
    """
    n = f.shape[0]
    off = np.zeros(n + 1, dtype=np.int64)
    for i in range(n):
        off[i + 1] = off[i] + m[i]
    k = off[n]
    empty = np.zeros((0, 2))
    if k == 0:
        return False, empty, np.zeros((0, 4), dtype=np.int64), np.zeros(0, dtype=np.int64), np.zeros(0, np.int64)
    for i in range(n):
        if m[i] == 0 and (m[(i - 1) % n] == 0 or m[(i + 1) % n] == 0):
            return False, empty, np.zeros((0, 4), dtype=np.int64), np.zeros(0, dtype=np.int64), np.zeros(0, np.int64)
    coords = np.empty((k, 2))
    own = np.empty(k, dtype=np.int64)
    spoke = np.empty(k, dtype=np.int64)  # spoke[off[i] + s]: new-node slot of spoke s of node i
    nc = 0
    for i in range(n):
        mi = m[i]
        if mi == 0:
            continue
        a = ang[i]
        d = depth[i]
        if mi == 1:
            t = th0[i] + 0.5 * a
            r = d / max(np.sin(0.5 * a), 0.5)
            coords[nc, 0] = p[i, 0] + r * np.cos(t)
            coords[nc, 1] = p[i, 1] + r * np.sin(t)
            own[nc] = i
            spoke[off[i]] = nc
            nc += 1
            continue
        sig = a / ((mi + 1) // 2 + 1)
        for j in range((mi + 1) // 2):
            t = th0[i] + sig * (j + 1)
            spoke[off[i] + mi - 1 - 2 * j] = nc
            coords[nc, 0] = p[i, 0] + d * np.cos(t)
            coords[nc, 1] = p[i, 1] + d * np.sin(t)
            own[nc] = i
            nc += 1
        for j in range((mi - 1) // 2):
            t = th0[i] + sig * (j + 1.5)
            spoke[off[i] + mi - 2 - 2 * j] = nc
            r = 2.0 * d * np.cos(0.5 * sig)
            coords[nc, 0] = p[i, 0] + r * np.cos(t)
            coords[nc, 1] = p[i, 1] + r * np.sin(t)
            own[nc] = i
            nc += 1
    parent = np.arange(k)
    acc = np.zeros((k, 2))
    cnt = np.zeros(k)
    for e in range(n):
        if m[e] != 0:
            continue
        a_ = (e - 1) % n
        b_ = (e + 1) % n
        t = th0[e] + 0.5 * ang[e]
        r = min(depth[e] / max(np.sin(0.5 * ang[e]), 1e-3), 1.5 * depth[e])
        u = _find(parent, spoke[off[a_ + 1] - 1])
        w = _find(parent, spoke[off[b_]])
        if u != w:
            parent[w] = u
            acc[u, 0] += acc[w, 0]
            acc[u, 1] += acc[w, 1]
            cnt[u] += cnt[w]
        acc[u, 0] += p[e, 0] + r * np.cos(t)
        acc[u, 1] += p[e, 1] + r * np.sin(t)
        cnt[u] += 1.0
        own[u] = e
    lab = np.full(k, -1, dtype=np.int64)
    root = np.empty(k, dtype=np.int64)
    for x in range(k):
        root[x] = _find(parent, x)
        lab[root[x]] = 0
    nk = 0
    for x in range(k):
        if lab[x] == 0:
            lab[x] = n0 + nk
            nk += 1
    xy = np.empty((nk, 2))
    owner = np.empty(nk, dtype=np.int64)
    for x in range(k):
        if root[x] == x:
            r = lab[x] - n0
            if cnt[x] > 0.0:
                xy[r, 0] = acc[x, 0] / cnt[x]
                xy[r, 1] = acc[x, 1] / cnt[x]
            else:
                xy[r, 0] = coords[x, 0]
                xy[r, 1] = coords[x, 1]
            owner[r] = own[x]
    quads = np.empty((2 * n + k, 4), dtype=np.int64)
    nq = 0
    for i in range(n):
        j = (i + 1) % n
        if m[i] != 0 and m[j] != 0:
            quads[nq, 0] = f[i]
            quads[nq, 1] = f[j]
            quads[nq, 2] = lab[root[spoke[off[j]]]]
            quads[nq, 3] = lab[root[spoke[off[i + 1] - 1]]]
            nq += 1
        for s in range(0, m[i] - 2, 2):
            quads[nq, 0] = f[i]
            quads[nq, 1] = lab[root[spoke[off[i] + s + 2]]]
            quads[nq, 2] = lab[root[spoke[off[i] + s + 1]]]
            quads[nq, 3] = lab[root[spoke[off[i] + s]]]
            nq += 1
    for e in range(n):
        if m[e] == 0:
            a_ = (e - 1) % n
            quads[nq, 0] = f[a_]
            quads[nq, 1] = f[e]
            quads[nq, 2] = f[(e + 1) % n]
            quads[nq, 3] = lab[root[spoke[off[a_ + 1] - 1]]]
            nq += 1
    front = np.empty(k, dtype=np.int64)
    for x in range(k):
        front[x] = lab[root[spoke[x]]]
    return True, xy, quads[:nq].copy(), front, owner

