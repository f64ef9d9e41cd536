"""Quality-guarded Laplacian smoothing of quad-dominant meshes (shared by the quad methods).

Each free vertex moves towards the mean of its edge neighbours (Gauss-Seidel sweeps, the
plain Laplacian of Herrmann 1976 as used by every chapter 18.5 method after its
topology is fixed); a move is kept only if the smallest corner sine (the scaled Jacobian
of quads, the sine of the angle for triangles) over the cells around the vertex does not
fall, else half the move is tried, else the vertex stays.  This is the "smart" Laplacian
of Canann, Tristano and Staten (IMR 1998): it never inverts a cell and never lowers the
mesh's minimum scaled Jacobian, so a valid mesh stays valid.  Vertices on ``line`` cells
(the boundary and interior segments) are fixed, which keeps them on their true curves.

:func:`smooth_sliding` is the same guard with boundary vertices sliding along their true
curves (the pairing's enhancement smoothing, 18.5.1): a sliding vertex's Laplacian step is
projected onto the chord of its two boundary neighbours and put back on its curve by the
caller's projection, and every move is also checked exactly: no strictly convex corner
around the vertex (a triangle's: counter-clockwise) may stop being one by exact
``orient2d``, and reflex corners are ranked by how far they fold, so relaxed,
tangled or flat cells open over several moves and never close again.  A vertex of a bad
star that no Laplacian step may move tries the centroid of the star's kernel, the convex
region where all its corners are convex (the local untangling of Freitag and Plassmann,
IJNME 2000): the pairing's cells split from flat triangles under a size jump of 1e-4
are opened that way.

Array layout: points (n, 2) float64; cells (m, 4) int32, a triangle padded with -1 in
column 3, counter-clockwise; vertex-to-cell and vertex-to-neighbour tables in CSR form
(``ptr`` (n + 1,) int64, ``idx`` int32), built in one linear pass (:func:`cell_tables`).
The index tables are int32 and the guard is written out in the sweep (:func:`_sweep`), not
called: a visit reads its star from half the bytes, passes no array structs to a call (the
disk's sweeps took about 40 % less time than with a called guard) and takes no reference
counts on arrays (an inlined guard took some eighteen per trial, half the sweep's time).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.errors import InputError
from meshwright.core.predicates import CCW_ERRBOUND_A, orient2d
from meshwright.core.validate_input import check_count

__all__ = ["UNTANGLE", "cell_tables", "smooth_cells", "smooth_sliding"]

UNTANGLE = 0.01  # smooth_sliding: a star this flat or folded whose Laplacian steps fail tries its kernel


@njit(cache=True)
def _corner_table(points, cells, exact):
    """Quality of every corner, (m, 4) float64: ``cs[c, k]`` of corner k of cell c (unused
    slot of a triangle: 1), its sine, or with ``exact`` :func:`_measure_xy`'s; with
    ``exact`` also every corner's exact convexity, (m, 4) int8: ``cv[c, k]`` 1 when
    strictly convex (exact ``orient2d``, through :func:`_measure_xy`'s filter on the same cross
    product), else 0 (unused slot: 1); without it ``cv`` is (0, 4).  Returns (cs, cv)."""
    m = cells.shape[0]
    cs = np.ones((m, 4))
    cv = np.ones((m if exact else 0, 4), np.int8)
    for c in range(m):
        # The cell's corners read once (not three times, once per corner that holds them);
        # a triangle's fourth is its first, unused.
        quad = cells[c, 3] >= 0
        i0 = cells[c, 0]
        i1 = cells[c, 1]
        i2 = cells[c, 2]
        i3 = cells[c, 3] if quad else i0
        x0, y0 = points[i0, 0], points[i0, 1]
        x1, y1 = points[i1, 0], points[i1, 1]
        x2, y2 = points[i2, 0], points[i2, 1]
        x3, y3 = points[i3, 0], points[i3, 1]
        # Corner k between its previous and next corner (a triangle's corner 0 follows
        # corner 2 and its corner 2 precedes corner 0).
        if quad:
            s0, k0 = _quality(exact, x3, y3, x0, y0, x1, y1)
            s2, k2 = _quality(exact, x1, y1, x2, y2, x3, y3)
            s3, k3 = _quality(exact, x2, y2, x3, y3, x0, y0)
            cs[c, 3] = s3
            if exact:
                cv[c, 3] = k3
        else:
            s0, k0 = _quality(exact, x2, y2, x0, y0, x1, y1)
            s2, k2 = _quality(exact, x1, y1, x2, y2, x0, y0)
        s1, k1 = _quality(exact, x0, y0, x1, y1, x2, y2)
        cs[c, 0] = s0
        cs[c, 1] = s1
        cs[c, 2] = s2
        if exact:
            cv[c, 0] = k0
            cv[c, 1] = k1
            cv[c, 2] = k2
    return cs, cv


@njit(inline="always")
def _quality(exact, ax, ay, bx, by, dx, dy):
    """Corner b's entry of :func:`_corner_table`: its sine and 1, or with ``exact``
    :func:`_measure_xy`'s quality and exact convexity (1 or 0)."""
    if exact:
        sn, ok = _measure_xy(ax, ay, bx, by, dx, dy)
        return sn, 1 if ok else 0
    sn, _, _ = _cross_xy(ax, ay, bx, by, dx, dy)
    return sn, 1


@njit(cache=True)
def _star_min(cs, cells, cell_ptr, cell_idx, v):
    """Smallest corner sine over the cells around ``v``, read from the flat corner table
    ``cs`` (4 m,) with the flat cells (4 m,), and the corner holding it (``4 * cell +
    corner``; -1 when no sine is below 1)."""
    worst = 1.0
    at = -1
    for t in range(cell_ptr[v], cell_ptr[v + 1]):
        c = 4 * np.int64(cell_idx[t])
        nv = 4 if cells[c + 3] >= 0 else 3
        for k in range(nv):
            if cs[c + k] < worst:
                worst = cs[c + k]
                at = c + k
    return worst, at


@njit(inline="always")
def _cross_xy(ax, ay, bx, by, dx, dy):
    """Sine, floating cross product and its error scale at corner b (between b->d and b->a).

    The cross product is computed with exactly the operations of ``orient2d(d, a, b)``'s
    filter, so ``cross >= CCW_ERRBOUND_A * scale`` (Shewchuk 1997) certifies that the
    exact ``orient2d(a, b, d)`` (the same determinant, cyclically permuted) is positive.
    The sine is ``cross / sqrt(|u|^2 |w|^2)`` (-1 for a degenerate corner); the corner
    table and every guard test compute it here, so they agree bit for bit.  Coordinates,
    not an array and indices: an inlined function's array argument costs reference
    counts on every pass through it.
    """
    ux = dx - bx
    uy = dy - by
    wx = ax - bx
    wy = ay - by
    left = ux * wy
    right = uy * wx
    cross = left - right
    den = np.sqrt((ux * ux + uy * uy) * (wx * wx + wy * wy))
    return (cross / den if den > 0.0 else -1.0), cross, abs(left) + abs(right)


@njit(inline="always")
def _measure_xy(ax, ay, bx, by, dx, dy):
    """Quality of corner b (between b->d and b->a) for the exact guard, and whether it is
    strictly convex (exact).  A strictly convex corner's quality is its sine; a corner that
    is not gets a value that falls with the angle over the whole reflex range: its sine
    from 180 to 270 degrees (0 to -1), then ``-2 + |sine|`` up to 360 (-1 to -2); a
    degenerate corner -2.  The sine alone would rank a corner of 359 degrees, almost
    folded, with one of 181, so a guard that lets reflex corners stay (a relaxed quad
    opening over several moves) could fold one; the convexity is the exact one, since near
    0 or 360 degrees the floating cross product's sign cannot tell the two apart."""
    sn, cross, scale = _cross_xy(ax, ay, bx, by, dx, dy)
    if (cross > 0.0 and cross >= CCW_ERRBOUND_A * scale) or orient2d(ax, ay, bx, by, dx, dy) > 0.0:
        return sn, True
    ux = dx - bx
    uy = dy - by
    wx = ax - bx
    wy = ay - by
    den = np.sqrt((ux * ux + uy * uy) * (wx * wx + wy * wy))
    if den == 0.0:
        return -2.0, False
    if ux * wx + uy * wy <= 0.0:
        return min(sn, 0.0), False
    return -2.0 + abs(sn), False


@njit(cache=True)
def _sweep(points, cells, cell_ptr, cell_idx, nbr_ptr, nbr_idx, free, cur, nxt, settle, cs, cv, slot, old, box, nodes,
           full, half):
    """One Gauss-Seidel guarded sweep in place; returns (moves kept, whether one woke its
    neighbours).

    With ``nodes`` empty, every free vertex (with ``settle > 0`` only those awake in
    ``cur``) tries the full step towards its neighbours' mean, then the half step, then,
    with ``cv`` and ``box`` given and a star whose worst corner is below ``UNTANGLE``,
    its kernel's centroid (:func:`_kernel_target`; ``box``: its (4, k) scratch): a
    Laplacian step seldom opens a reflex or flat corner.  A kept move of more than ``settle`` times the
    vertex's distance to its first neighbour wakes it and its neighbours for the rest of
    this sweep (``cur``) and the next (``nxt``).  Else vertex ``nodes[s]`` tries
    ``full[s]``, then ``half[s]`` (the sliding vertices' projected steps), and wakes
    nothing.

    The guard: a trial is kept if every corner quality that moving the vertex changes is
    at least the star's smallest before the move (``before``, read from the corner table
    ``cs`` by :func:`_star_min`; the corners opposite the vertex in its quads keep their
    sides and are not tested) and, with ``cv`` (the exact guard; None: sines only),
    every corner of the star that was strictly convex (``cv``, (m, 4) int8) still is by
    exact ``orient2d``, certified from the same cross products where the filter allows.
    The qualities are sines, or with ``cv`` :func:`_measure_xy`'s: a reflex corner may stay reflex, no better than the
    star's worst was, so a relaxed or tangled quad opens over several moves of its
    vertices (one move rarely makes a quad with two bad corners convex at once, and a rule
    that asked for it kept every such star still), while no convex corner ever turns.  A
    refused move almost always fails at the star's worst corner (``worst``), so that
    corner, if the move changes it, is tested first.  The walk of the star stops at the
    first cell that fails; the new values are kept in ``old`` and their corners in
    ``slot`` (``4 * cell + corner``, shifted left by one, lowest bit: convex), and written
    to ``cs`` (and ``cv``) once every test passed.  A quad's three corners are formed
    together from the four sides they share, without a loop to find the vertex in it.

    The guard, the neighbours' mean and the wake-up are written out here, not inlined
    functions: an inlined function's array arguments are new references, counted
    (atomically) on every pass through it, and a guard with several exits kept them,
    some eighteen counts per trial, half the sweep's time on the disk.  ``cv`` and
    ``box`` None are pruned at compile time (``is None`` tests of arguments): the
    sines-only specialisation compiles neither the exact tests nor the kernel's clipping.
    """
    interior = nodes.shape[0] == 0
    # Flat views: an index is a shift and an add, no row stride read from the array (spilled).
    P = points.reshape(-1)
    C = cells.reshape(-1)
    S = cs.reshape(-1)
    if cv is not None:
        V = cv.reshape(-1)
    kept = 0
    woke = False
    for it in range(points.shape[0] if interior else nodes.shape[0]):
        tx = 0.0
        ty = 0.0
        if interior:
            v = np.int64(it)
            if not free[v] or nbr_ptr[v + 1] == nbr_ptr[v]:
                continue
            if settle > 0.0 and cur[v] == 0:
                continue
            for t in range(nbr_ptr[v], nbr_ptr[v + 1]):
                tx += P[2 * nbr_idx[t]]
                ty += P[2 * nbr_idx[t] + 1]
            k = nbr_ptr[v + 1] - nbr_ptr[v]
            tx = tx / k
            ty = ty / k
        else:
            v = nodes[it]
        x0 = P[2 * v]
        y0 = P[2 * v + 1]
        # A refused trial puts v back exactly, so every trial shares one ``before``.
        before, worst = _star_min(S, C, cell_ptr, cell_idx, v)
        moved = False
        for trial in range(3):
            if trial < 2:
                if interior:
                    step = 1.0 if trial == 0 else 0.5
                    px = x0 + step * (tx - x0)
                    py = y0 + step * (ty - y0)
                elif trial == 0:
                    px = full[it, 0]
                    py = full[it, 1]
                else:
                    px = half[it, 0]
                    py = half[it, 1]
            else:
                # ``box`` None (the sines-only sweeps) prunes the kernel trial at compile
                # time: that specialisation does not compile the clipping (first call).
                if box is None or cv is None:
                    break
                if not interior or before >= UNTANGLE:
                    break
                found, px, py = _kernel_target(points, cells, cell_ptr, cell_idx, v, box[0], box[1], box[2], box[3])
                if not found:
                    break
            P[2 * v] = px
            P[2 * v + 1] = py
            ok = True
            if worst >= 0:
                c = worst >> 2
                k = worst & 3
                nv = 4 if C[4 * c + 3] >= 0 else 3
                if nv == 3 or C[4 * c + ((k + 2) & 3)] != v:
                    a = C[4 * c + (k - 1 if k > 0 else nv - 1)]
                    b = C[4 * c + k]
                    d = C[4 * c + (k + 1 if k + 1 < nv else 0)]
                    if cv is not None:
                        sn, convex = _measure_xy(P[2 * a], P[2 * a + 1], P[2 * b], P[2 * b + 1],
                                                 P[2 * d], P[2 * d + 1])
                        ok = not (sn < before or (cv[c, k] == 1 and not convex))
                    else:
                        sn, _, _ = _cross_xy(P[2 * a], P[2 * a + 1], P[2 * b], P[2 * b + 1],
                                             P[2 * d], P[2 * d + 1])
                        ok = not sn < before
            i = 0
            if ok:
                for t in range(cell_ptr[v], cell_ptr[v + 1]):
                    c = cell_idx[t]
                    if C[4 * c + 3] < 0:
                        for k in range(3):
                            a = C[4 * c + (k - 1 if k > 0 else 2)]
                            b = C[4 * c + k]
                            d = C[4 * c + (k + 1 if k < 2 else 0)]
                            convex = True
                            if cv is not None:
                                sn, convex = _measure_xy(P[2 * a], P[2 * a + 1], P[2 * b], P[2 * b + 1],
                                                         P[2 * d], P[2 * d + 1])
                                if not convex and cv[c, k] == 1:
                                    ok = False
                            else:
                                sn, _, _ = _cross_xy(P[2 * a], P[2 * a + 1], P[2 * b], P[2 * b + 1],
                                                     P[2 * d], P[2 * d + 1])
                            if sn < before:
                                ok = False
                            if not ok:
                                break
                            slot[i] = 2 * (4 * c + k) + (1 if convex else 0)
                            old[i] = sn
                            i += 1
                        if not ok:
                            break
                        continue
                    # v's place in the quad without a data-dependent loop exit, then its
                    # three corners that v changes from the four sides they share (v->q,
                    # v->p, q->o, p->o).  A side read backwards is negated, which changes
                    # no magnitude: the sines and cross products are _cross_xy's, bit for bit.
                    kv = (C[4 * c + 1] == v) * 1 + (C[4 * c + 2] == v) * 2 + (C[4 * c + 3] == v) * 3
                    kq = (kv + 1) & 3
                    kp = (kv + 3) & 3
                    q = C[4 * c + kq]
                    o = C[4 * c + ((kv + 2) & 3)]
                    p = C[4 * c + kp]
                    aqx = P[2 * q] - px
                    aqy = P[2 * q + 1] - py
                    apx = P[2 * p] - px
                    apy = P[2 * p + 1] - py
                    qox = P[2 * o] - P[2 * q]
                    qoy = P[2 * o + 1] - P[2 * q + 1]
                    pox = P[2 * o] - P[2 * p]
                    poy = P[2 * o + 1] - P[2 * p + 1]
                    lq = aqx * aqx + aqy * aqy
                    lp = apx * apx + apy * apy
                    l0 = aqx * apy
                    r0 = aqy * apx
                    l1 = -(qox * aqy)
                    r1 = -(qoy * aqx)
                    l2 = -(apx * poy)
                    r2 = -(apy * pox)
                    cr0 = l0 - r0
                    cr1 = l1 - r1
                    cr2 = l2 - r2
                    d0 = np.sqrt(lq * lp)
                    d1 = np.sqrt((qox * qox + qoy * qoy) * lq)
                    d2 = np.sqrt(lp * (pox * pox + poy * poy))
                    s0 = cr0 / d0 if d0 > 0.0 else -1.0
                    s1 = cr1 / d1 if d1 > 0.0 else -1.0
                    s2 = cr2 / d2 if d2 > 0.0 else -1.0
                    b0 = 1
                    b1 = 1
                    b2 = 1
                    if cv is not None:
                        if not (cr0 > 0.0 and cr0 >= CCW_ERRBOUND_A * (abs(l0) + abs(r0))):
                            s0, ok0 = _measure_xy(P[2 * p], P[2 * p + 1], px, py, P[2 * q], P[2 * q + 1])
                            b0 = 1 if ok0 else 0
                        if not (cr1 > 0.0 and cr1 >= CCW_ERRBOUND_A * (abs(l1) + abs(r1))):
                            s1, ok1 = _measure_xy(px, py, P[2 * q], P[2 * q + 1], P[2 * o], P[2 * o + 1])
                            b1 = 1 if ok1 else 0
                        if not (cr2 > 0.0 and cr2 >= CCW_ERRBOUND_A * (abs(l2) + abs(r2))):
                            s2, ok2 = _measure_xy(P[2 * o], P[2 * o + 1], P[2 * p], P[2 * p + 1], px, py)
                            b2 = 1 if ok2 else 0
                        if (b0 == 0 and cv[c, kv] == 1) or (b1 == 0 and cv[c, kq] == 1) or (b2 == 0 and cv[c, kp] == 1):
                            ok = False
                            break
                    if s0 < before or s1 < before or s2 < before:
                        ok = False
                        break
                    slot[i] = 2 * (4 * c + kv) + b0
                    slot[i + 1] = 2 * (4 * c + kq) + b1
                    slot[i + 2] = 2 * (4 * c + kp) + b2
                    old[i] = s0
                    old[i + 1] = s1
                    old[i + 2] = s2
                    i += 3
            if ok:
                for j in range(i):
                    sc = slot[j] >> 1
                    S[sc] = old[j]
                    if cv is not None:
                        V[sc] = slot[j] & 1
                moved = True
                break
            P[2 * v] = x0
            P[2 * v + 1] = y0
        if not moved:
            continue
        kept += 1
        if interior and settle > 0.0:
            w = nbr_idx[nbr_ptr[v]]
            ref = (P[2 * w] - x0) ** 2 + (P[2 * w + 1] - y0) ** 2
            shift = (P[2 * v] - x0) ** 2 + (P[2 * v + 1] - y0) ** 2
            if shift > settle * settle * ref:
                woke = True
                cur[v] = 1
                nxt[v] = 1
                for t in range(nbr_ptr[v], nbr_ptr[v + 1]):
                    cur[nbr_idx[t]] = 1
                    nxt[nbr_idx[t]] = 1
    return kept, woke


@njit(cache=True)
def _sweeps(points, cells, cell_ptr, cell_idx, nbr_ptr, nbr_idx, free, passes, settle):
    """Gauss-Seidel guarded Laplacian sweeps (:func:`_sweep`, sines only) in place;
    returns the moves kept.

    With ``settle > 0`` a vertex is visited again only while it or an edge neighbour
    moved, in this sweep or the last, by more than ``settle`` times the vertex's distance
    to its first neighbour; 0 visits every free vertex in every sweep.  The active set is
    kept as wake flags, set around each such move for this sweep and the next (the
    vertices of the previous sweep's moves and their neighbours, joined by this sweep's
    as they come), so a skipped vertex costs one byte read.  The sine of every
    corner is kept in a table (:func:`_corner_table`), brought up to
    date with each kept move from the sines its test computed: a visit reads its star's
    smallest sine instead of computing it.
    """
    n = points.shape[0]
    kept = 0
    cur = np.ones(n, np.int8)
    nxt = np.zeros(n, np.int8)
    cs, _ = _corner_table(points, cells, np.bool_(False))
    most = 0
    for v in range(n):
        most = max(most, cell_ptr[v + 1] - cell_ptr[v])
    slot = np.empty(4 * most + 1, np.int64)
    old = np.empty(4 * most + 1)
    none = np.empty(0, np.int64)
    steps = np.empty((0, 2))
    for _ in range(passes):
        got, woke = _sweep(points, cells, cell_ptr, cell_idx, nbr_ptr, nbr_idx, free, cur, nxt, settle, cs, None, slot,
                           old, None, none, steps, steps)
        kept += got
        if settle > 0.0 and not woke:
            break  # nothing is awake: every later sweep would visit no vertex
        cur, nxt = nxt, cur
        nxt[:] = 0
    return kept

@njit(cache=True)
def _tables(cells, n):
    """Vertex -> cells and vertex -> edge neighbours (deduplicated), both CSR, in O(cells).

    A vertex's neighbours come in the order of its cells, each cell's next corner before
    its previous one, each neighbour at its first appearance (the Laplacian's mean sums
    them in that order)."""
    m = cells.shape[0]
    cell_ptr = np.zeros(n + 1, np.int64)
    for c in range(m):
        for k in range(4):
            if cells[c, k] >= 0:
                cell_ptr[cells[c, k] + 1] += 1
    for v in range(n):
        cell_ptr[v + 1] += cell_ptr[v]
    fill = cell_ptr[:-1].copy()
    cell_idx = np.empty(cell_ptr[n], np.int32)
    # Each entry's two candidate neighbours (next corner, previous corner) are written
    # beside it here, while the cell is at hand, so that the deduplication below reads
    # them in order instead of going back to the cells at random.
    pair = np.empty(2 * cell_ptr[n], np.int32)
    for c in range(m):
        last = 3 if cells[c, 3] >= 0 else 2
        for k in range(last + 1):
            v = cells[c, k]
            f = fill[v]
            cell_idx[f] = c
            pair[2 * f] = cells[c, k + 1 if k < last else 0]
            pair[2 * f + 1] = cells[c, k - 1 if k > 0 else last]
            fill[v] = f + 1
    # A stamp drops the repeats.
    stamp = np.full(n, -1, np.int32)
    nbr_ptr = np.zeros(n + 1, np.int64)
    nbr_idx = np.empty(2 * cell_ptr[n], np.int32)
    top = 0
    for v in range(n):
        for s in range(2 * cell_ptr[v], 2 * cell_ptr[v + 1]):
            w = pair[s]
            if stamp[w] != v:
                stamp[w] = v
                nbr_idx[top] = w
                top += 1
        nbr_ptr[v + 1] = top
    return cell_ptr, cell_idx, nbr_ptr, nbr_idx[:top].copy()


def cell_tables(points, quads, triangles):
    """Padded cells and their vertex tables.

    Parameters
    ----------
    points : (n, 2) float64
    quads : (m, 4) int
    triangles : (t, 3) int

    Returns
    -------
    cells : (m + t, 4) int32
        Quads, then triangles padded with -1.
    cell_ptr, cell_idx : (n + 1,) int64, (4m + 3t,) int32
        Cells around each vertex.
    nbr_ptr, nbr_idx : (n + 1,) int64, (k,) int32
        Edge neighbours of each vertex, each once.
    """
    cells = np.full((len(quads) + len(triangles), 4), -1, np.int32)
    cells[: len(quads)] = quads
    cells[len(quads) :, :3] = triangles
    return (cells, *_tables(cells, len(points)))


@njit(cache=True)
def _clip(px, py, n, qx, qy, a, b, c):
    """Clip the convex polygon ``px``, ``py`` (``n`` vertices, counter-clockwise) to the
    open half-plane ``a x + b y + c > 0`` (Sutherland and Hodgman 1974) into ``qx``, ``qy``;
    returns the new vertex count (0: nothing left)."""
    m = 0
    for i in range(n):
        j = i + 1 if i + 1 < n else 0
        hi = a * px[i] + b * py[i] + c
        hj = a * px[j] + b * py[j] + c
        if hi > 0.0:
            qx[m] = px[i]
            qy[m] = py[i]
            m += 1
        if (hi > 0.0) != (hj > 0.0) and hi != hj:
            t = hi / (hi - hj)
            qx[m] = px[i] + t * (px[j] - px[i])
            qy[m] = py[i] + t * (py[j] - py[i])
            m += 1
    return m


@njit(cache=True)
def _kernel_target(points, cells, cell_ptr, cell_idx, v, px, py, qx, qy):
    """Centroid of the region where every corner of ``v``'s star is convex, and whether
    it is not empty (floating point; the exact guard decides).

    Each corner that moving ``v`` changes is an orientation with ``v`` as one of its three
    points, linear in ``v``: the region is an intersection of half-planes, a convex
    polygon (the feasible set of Freitag and Plassmann's local untangling, IJNME 2000),
    clipped here from the box of the star one half-plane at a time.  Coordinates are taken
    relative to ``v``, whose stars in size jumps of 1e-4 are 1e-7 wide at coordinates of
    hundreds.  ``px``, ``py``, ``qx``, ``qy``: scratch of at least 4 + the star's corners.
    """
    x0 = points[v, 0]
    y0 = points[v, 1]
    lo_x = 0.0
    hi_x = 0.0
    lo_y = 0.0
    hi_y = 0.0
    for t in range(cell_ptr[v], cell_ptr[v + 1]):
        c = cell_idx[t]
        for k in range(4 if cells[c, 3] >= 0 else 3):
            dx = points[cells[c, k], 0] - x0
            dy = points[cells[c, k], 1] - y0
            lo_x = min(lo_x, dx)
            hi_x = max(hi_x, dx)
            lo_y = min(lo_y, dy)
            hi_y = max(hi_y, dy)
    px[0], py[0], px[1], py[1] = lo_x, lo_y, hi_x, lo_y
    px[2], py[2], px[3], py[3] = hi_x, hi_y, lo_x, hi_y
    n = np.int64(4)
    for t in range(cell_ptr[v], cell_ptr[v + 1]):
        c = cell_idx[t]
        nv = 4 if cells[c, 3] >= 0 else 3
        for k in range(nv):
            a = cells[c, k - 1 if k > 0 else nv - 1]
            b = cells[c, k]
            d = cells[c, k + 1 if k + 1 < nv else 0]
            # orient(a, b, d) with v first: orient(v, x, y) = (x - v) x (y - v).
            if b == v:
                x, y = d, a
            elif a == v:
                x, y = b, d
            elif d == v:
                x, y = a, b
            else:
                continue  # the corner opposite v
            xx = points[x, 0] - x0
            xy = points[x, 1] - y0
            yx = points[y, 0] - x0
            yy = points[y, 1] - y0
            # (X - u) x (Y - u) = X x Y + u_x (X_y - Y_y) - u_y (X_x - Y_x)
            n = _clip(px, py, n, qx, qy, xy - yy, yx - xx, xx * yy - xy * yx)
            if n == 0:
                return False, x0, y0
            # A loop, not a slice assignment: that compiles a shape check with string
            # formatting, a second of the first call's compile.
            for j in range(n):
                px[j] = qx[j]
                py[j] = qy[j]
    # Area centroid (the vertex mean when the polygon is too thin to have one).
    area = 0.0
    cx = 0.0
    cy = 0.0
    mx = 0.0
    my = 0.0
    for i in range(n):
        j = i + 1 if i + 1 < n else 0
        w = px[i] * py[j] - px[j] * py[i]
        area += w
        cx += (px[i] + px[j]) * w
        cy += (py[i] + py[j]) * w
        mx += px[i]
        my += py[i]
    if area > 0.0:
        return True, x0 + cx / (3.0 * area), y0 + cy / (3.0 * area)
    return True, x0 + mx / n, y0 + my / n


@njit(cache=True)
def _slide_trials(points, nbr_ptr, nbr_idx, slide, ends):
    """The sliding vertices' trial positions before projection.

    Each vertex of ``slide`` whose boundary chord (from line neighbour ``ends[s, 0]`` to
    ``ends[s, 1]``) has a length takes its Laplacian step projected on the unit chord;
    returns those vertices twice, (2 k,) int64, the positions at the full step, then at
    the half step, (2 k, 2), and their current positions twice, (2 k, 2) (the projection's
    arguments for both trials at once).  One pass instead of a dozen array operations
    per sweep; the arithmetic is that of the chord's NumPy form, value for value.
    """
    k = 0
    for s in range(slide.shape[0]):
        if np.hypot(points[ends[s, 1], 0] - points[ends[s, 0], 0], points[ends[s, 1], 1] - points[ends[s, 0], 1]) > 0.0:
            k += 1
    nodes = np.empty(2 * k, np.int64)
    xy = np.empty((2 * k, 2))
    at = np.empty((2 * k, 2))
    j = 0
    for s in range(slide.shape[0]):
        cx = points[ends[s, 1], 0] - points[ends[s, 0], 0]
        cy = points[ends[s, 1], 1] - points[ends[s, 0], 1]
        norm = np.hypot(cx, cy)
        if not norm > 0.0:
            continue
        ux = cx / norm
        uy = cy / norm
        v = slide[s]
        fx = 0.0
        fy = 0.0
        for t in range(nbr_ptr[v], nbr_ptr[v + 1]):
            fx += points[nbr_idx[t], 0] - points[v, 0]
            fy += points[nbr_idx[t], 1] - points[v, 1]
        d = (fx * ux + fy * uy) / max(nbr_ptr[v + 1] - nbr_ptr[v], 1)
        sx = d * ux
        sy = d * uy
        nodes[j] = v
        nodes[k + j] = v
        xy[j, 0] = points[v, 0] + sx
        xy[j, 1] = points[v, 1] + sy
        xy[k + j, 0] = points[v, 0] + 0.5 * sx
        xy[k + j, 1] = points[v, 1] + 0.5 * sy
        at[j, 0] = points[v, 0]
        at[j, 1] = points[v, 1]
        at[k + j, 0] = points[v, 0]
        at[k + j, 1] = points[v, 1]
        j += 1
    return nodes, xy, at


def _check_settle(settle) -> float:
    try:
        settle = float(settle)
    except (TypeError, ValueError):
        raise InputError(f"settle must be a number, got {settle!r}") from None
    if not (np.isfinite(settle) and settle >= 0.0):
        raise InputError(f"settle must be finite and >= 0, got {settle!r}")
    return settle


def smooth_cells(points, quads, triangles, fixed, passes: int, settle: float = 0.0) -> np.ndarray:
    """Guarded Laplacian smoothing (module docstring).

    Parameters
    ----------
    points : (n, 2) float64
    quads : (m, 4) int
    triangles : (t, 3) int
        Counter-clockwise cells of a valid mesh.
    fixed : (n,) bool
        Vertices that never move (boundary and interior-segment vertices).
    passes : int
        Gauss-Seidel sweeps (>= 0).
    settle : float
        After the first sweep, skip vertices whose neighbourhood has settled: neither
        the vertex nor an edge neighbour moved by more than ``settle`` times its
        distance to a neighbour in the last sweep (0: every sweep visits every vertex).

    Returns
    -------
    (n, 2) float64
        New coordinates (the input is not modified).

    Raises
    ------
    InputError
        ``passes`` not a count, ``settle`` negative or not finite.
    """
    passes = check_count(passes, "passes")
    settle = _check_settle(settle)
    pts = np.array(points, dtype=np.float64, order="C")
    cells, cell_ptr, cell_idx, nbr_ptr, nbr_idx = cell_tables(pts, quads, triangles)
    free = ~np.asarray(fixed, dtype=bool)
    _sweeps(pts, cells, cell_ptr, cell_idx, nbr_ptr, nbr_idx, free, passes, settle)
    return pts


def smooth_sliding(points, quads, triangles, lines, fixed, project, passes: int, settle: float = 0.0) -> np.ndarray:
    """Guarded Laplacian with boundary vertices sliding on their curves (module docstring).

    Parameters
    ----------
    points : (n, 2) float64
        Not modified.
    quads : (m, 4) int
    triangles : (t, 3) int
        Counter-clockwise cells; quads may be non-convex (they only get better).
    lines : (k, 2) int
        Boundary and interior-segment edges: their vertices with exactly two line
        neighbours slide, the others stay.
    fixed : (n,) bool
        Vertices that never move (curve joints, polygon corners, given points).
    project : callable
        ``project(nodes (j,) int64, xy (j, 2), at (j, 2)) -> (j, 2)``: trial positions
        ``xy`` of nodes now at ``at`` put on the nodes' curves (the closest points, or a
        step along the curve towards them).
    passes : int
        Sweeps: all free interior vertices (Gauss-Seidel), then all sliding ones.
    settle : float
        As :func:`smooth_cells`: after the first sweep, interior vertices whose
        neighbourhood has settled are skipped (0: none).

    Returns
    -------
    (n, 2) float64
        New coordinates.

    Raises
    ------
    InputError
        ``passes`` not a count, ``settle`` negative or not finite.
    """
    passes = check_count(passes, "passes")
    settle = _check_settle(settle)
    pts = np.array(points, dtype=np.float64, order="C")
    n = len(pts)
    cells, cell_ptr, cell_idx, nbr_ptr, nbr_idx = cell_tables(pts, quads, triangles)
    e = np.asarray(lines, dtype=np.int64).reshape(-1, 2)
    deg = np.bincount(e.ravel(), minlength=n)
    on_line = deg > 0
    free = ~np.asarray(fixed, dtype=bool) & ~on_line
    # The two line neighbours of every vertex of line degree two.
    owner = np.concatenate([e[:, 0], e[:, 1]])
    other = np.concatenate([e[:, 1], e[:, 0]])
    order = np.argsort(owner, kind="stable")
    slide = np.flatnonzero((deg == 2) & ~np.asarray(fixed, dtype=bool))
    # Each sliding vertex's first entry among the sorted owners (a search over the line
    # entries, not a running sum over every vertex).
    head = np.searchsorted(owner[order], slide)
    ends = np.ascontiguousarray(other[order][np.stack([head, head + 1], axis=1)])
    # Sliding vertices count as moved in every sweep: they and their edge neighbours are
    # woken after each (indices gathered once, in NumPy: no kernel to compile for it).
    lens = nbr_ptr[slide + 1] - nbr_ptr[slide]
    first = np.repeat(nbr_ptr[slide] - (np.cumsum(lens) - lens), lens)
    woken = np.concatenate([slide, nbr_idx[first + np.arange(int(lens.sum()))]])
    cur = np.ones(n, np.int8)
    nxt = np.zeros(n, np.int8)
    cs, cv = _corner_table(pts, cells, True)
    slot = np.empty(4 * int(np.diff(cell_ptr).max(initial=0)) + 1, np.int64)
    old = np.empty(len(slot))
    # Clipping one half-plane adds at most one vertex to the box's four.
    box = np.empty((4, len(slot) + 4))
    none = np.empty(0, np.int64)
    steps = np.empty((0, 2))
    for _ in range(passes):
        _sweep(pts, cells, cell_ptr, cell_idx, nbr_ptr, nbr_idx, free, cur, nxt, settle, cs, cv, slot, old, box, none, steps,
               steps)
        cur, nxt = nxt, cur
        nxt[:] = 0
        cur[woken] = 1
        if not len(slide):
            continue
        twice, trial, at = _slide_trials(pts, nbr_ptr, nbr_idx, slide, ends)
        nodes = twice[: len(twice) // 2]
        if not len(nodes):
            continue  # (an empty list would make _sweep an interior sweep)
        # One projection call for both trial steps: on curves given as functions its cost
        # is per call (a vectorised golden-section search), a third of the pairing's time
        # on the three-element airfoil when made twice.
        both = project(twice, trial, at)
        full = np.ascontiguousarray(both[: len(nodes)], dtype=np.float64)
        half = np.ascontiguousarray(both[len(nodes) :], dtype=np.float64)
        _sweep(pts, cells, cell_ptr, cell_idx, nbr_ptr, nbr_idx, free, cur, nxt, settle, cs, cv, slot, old, box, nodes, full,
               half)
    return pts
