"""Numba kernels of :mod:`meshwright.quad.enhancement`: the quad shape enhancement of 18.5.1.

Source: J. Z. Zhu, O. C. Zienkiewicz, E. Hinton and J. Wu, "A new approach to the
development of automatic quadrilateral mesh generation", Int. J. Numer. Meth. Eng. 32,
1991: node elimination, element elimination and diagonal swapping after the pairing.

Array layout
------------
xy     : (n, 2) float64 node coordinates.
quad   : (m, 4) int32 counter-clockwise quadrilaterals; ``alive`` (m,) int8.
bnd    : (n,) int8, 1 for a node on the boundary, on an interior segment or given as an
         interior point (never moved or removed by the enhancement).
csr    : node -> incident quads, ``(off (n+1,) int64, idx int32)`` (:func:`node_quads`),
         rebuilt by the caller before every enhancement pass.

Invariants: whether a quadrilateral after an operation is strictly convex is an exact
``orient2d`` (through :func:`~meshwright.quad._pairing_kernel.quad_ok`); the scaled Jacobian
and the 150-degree rule at boundary nodes are quality rules in floating point, applied only
among valid choices.  An operation touches only quads not touched before in the same pass,
so the node -> quad table stays true for every quad an operation reads.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.quad._pairing_kernel import corner_flat, corner_ok, quad_ok, quad_sj

__all__ = ["balance_corners", "enhance_pass", "node_quads", "resplit_pass", "swap_low_pass"]


@njit(cache=True)
def _local_min(xy, quad, alive, off, idx, v, skip, sub_from, sub_to):
    """Smallest scaled Jacobian of the live quads around v (except ``skip``), with node
    ``sub_from`` read as ``sub_to``; -1 when one of them would not be strictly convex."""
    worst = 1.0
    for s in range(off[v], off[v + 1]):
        q = idx[s]
        if q == skip or alive[q] == 0:
            continue
        a, b, c, d = quad[q, 0], quad[q, 1], quad[q, 2], quad[q, 3]
        if a == sub_from:
            a = sub_to
        if b == sub_from:
            b = sub_to
        if c == sub_from:
            c = sub_to
        if d == sub_from:
            d = sub_to
        if not quad_ok(xy, a, b, c, d):
            return -1.0
        sj = quad_sj(xy, a, b, c, d)
        if sj < worst:
            worst = sj
    return worst


@njit(inline="always")
def _live_count(alive, off, idx, v):
    count = 0
    for s in range(off[v], off[v + 1]):
        if alive[idx[s]] != 0:
            count += 1
    return count


@njit(inline="always")
def _lock_star(off, idx, lock, v):
    for s in range(off[v], off[v + 1]):
        lock[idx[s]] = 1


@njit(inline="always")
def _position(quad, q, v):
    for k in range(4):
        if quad[q, k] == v:
            return k
    return -1


@njit(cache=True)
def _node_elimination(xy, quad, alive, bnd, off, idx, lock, tri_node, wake):
    """Interior nodes in exactly two quads (doublets): the two quads become one, unless it
    would be non-convex or leave a boundary node in one quad at a flat corner.  Only nodes
    flagged in ``wake`` (n,) int8 (a dirty quad in their star) are examined."""
    done = 0
    n = xy.shape[0]
    for v in range(n):
        if wake[v] == 0 or bnd[v] != 0 or tri_node[v] != 0:
            continue
        # The star's locks and live quads read in place, not through inlined helpers: an
        # inlined function's array argument costs reference counts on every pass
        # through it.
        q1 = -1
        q2 = -1
        count = 0
        busy = False
        for s in range(off[v], off[v + 1]):
            busy |= lock[idx[s]] != 0
            if alive[idx[s]] != 0:
                count += 1
                if q1 < 0:
                    q1 = idx[s]
                else:
                    q2 = idx[s]
        if busy or count != 2:
            continue
        i = (quad[q1, 1] == v) * 1 + (quad[q1, 2] == v) * 2 + (quad[q1, 3] == v) * 3
        # int64 corners, as every other caller passes them: an int32 quad would compile
        # quad_ok, quad_sj and corner_flat once more each (issue 13, first-run compile).
        a, b, c = np.int64(quad[q1, (i + 1) % 4]), np.int64(quad[q1, (i + 2) % 4]), np.int64(quad[q1, (i + 3) % 4])
        j = (quad[q2, 1] == v) * 1 + (quad[q2, 2] == v) * 2 + (quad[q2, 3] == v) * 3
        if quad[q2, (j + 1) % 4] != c or quad[q2, (j + 3) % 4] != a:
            continue
        d = np.int64(quad[q2, (j + 2) % 4])
        if not quad_ok(xy, a, b, c, d) or _flat_boundary_corner(xy, bnd, a, b, c, d):
            continue
        _lock_star(off, idx, lock, v)
        quad[q1, 0], quad[q1, 1], quad[q1, 2], quad[q1, 3] = a, b, c, d
        alive[q2] = 0
        done += 1
    return done


@njit(cache=True)
def _element_elimination(xy, quad, alive, bnd, off, idx, lock, tri_node, accept, dirty):
    """Quads whose opposite nodes a, c are interior and in three quads each (diamonds):
    a and c merge at their midpoint and the quad disappears."""
    done = 0
    none = np.int64(-1)  # typed: literal -1 arguments would compile _local_min once per pattern
    for q in range(quad.shape[0]):
        if alive[q] == 0 or lock[q] != 0 or dirty[q] == 0:
            continue
        for r in range(2):
            a = quad[q, r]
            c = quad[q, r + 2]
            if bnd[a] != 0 or bnd[c] != 0 or tri_node[a] != 0 or tri_node[c] != 0:
                continue
            if off[a + 1] - off[a] != 3 or off[c + 1] - off[c] != 3:
                continue
            b = quad[q, r + 1]
            d = quad[q, (r + 3) % 4]
            # Live quads and locks counted in place (see _node_elimination).
            live_b = 0
            for s in range(off[b], off[b + 1]):
                live_b += alive[idx[s]] != 0
            live_d = 0
            for s in range(off[d], off[d + 1]):
                live_d += alive[idx[s]] != 0
            if live_b < 3 or live_d < 3:
                continue
            busy = False
            for s in range(off[a], off[a + 1]):
                busy |= lock[idx[s]] != 0
            for s in range(off[c], off[c + 1]):
                busy |= lock[idx[s]] != 0
            if busy:
                continue
            old = min(_local_min(xy, quad, alive, off, idx, a, none, none, none),
                      _local_min(xy, quad, alive, off, idx, c, none, none, none))
            ax, ay = xy[a, 0], xy[a, 1]
            xy[a, 0] = 0.5 * (ax + xy[c, 0])
            xy[a, 1] = 0.5 * (ay + xy[c, 1])
            new = min(_local_min(xy, quad, alive, off, idx, a, q, none, none),
                      _local_min(xy, quad, alive, off, idx, c, q, np.int64(c), np.int64(a)))
            if new <= 0.0 or new < min(old, accept):
                xy[a, 0], xy[a, 1] = ax, ay
                continue
            _lock_star(off, idx, lock, a)
            _lock_star(off, idx, lock, c)
            for s in range(off[c], off[c + 1]):
                p = idx[s]
                for k in range(4):
                    if quad[p, k] == c:
                        quad[p, k] = a
            alive[q] = 0
            done += 1
            break
    return done


@njit(inline="always")
def _flat_boundary_corner(xy, bnd, a, b, c, d):
    """Whether quad (a, b, c, d) has a corner between two boundary nodes, itself on the
    boundary, wider than 150 degrees (a boundary node left in one quad)."""
    v = (a, b, c, d)
    for k in range(4):
        p = v[(k + 3) % 4]
        q = v[k]
        r = v[(k + 1) % 4]
        if bnd[p] != 0 and bnd[q] != 0 and bnd[r] != 0 and corner_flat(xy, p, q, r):
            return True
    return False


@njit(inline="always")
def _quad_sj_xy(ax, ay, bx, by, cx, cy, dx, dy):
    """:func:`~meshwright.quad._pairing_kernel.quad_sj` of quad (a, b, c, d) from its
    coordinates, bit for bit: the same differences, square roots and quotients per
    corner, written out for the four corners (no call, no tuple read at a run-time index);
    the product of a corner's two side lengths is the same in either order.  Coordinates,
    not an array: an inlined function's array argument costs reference counts on every
    pass through it."""
    l3 = np.sqrt((dx - ax) ** 2 + (dy - ay) ** 2)
    l0 = np.sqrt((bx - ax) ** 2 + (by - ay) ** 2)
    l1 = np.sqrt((cx - bx) ** 2 + (cy - by) ** 2)
    l2 = np.sqrt((dx - cx) ** 2 + (dy - cy) ** 2)
    # From 1 down, as quad_sj (a sine may round above 1).
    return min(1.0, _cross_over(dx, dy, ax, ay, bx, by, l0 * l3), _cross_over(ax, ay, bx, by, cx, cy, l1 * l0),
               _cross_over(bx, by, cx, cy, dx, dy, l2 * l1), _cross_over(cx, cy, dx, dy, ax, ay, l3 * l2))


@njit(inline="always")
def _cross_over(px, py, qx, qy, rx, ry, den):
    """Cross product of corner q (q->r, q->p) over ``den``, the product of its two side
    lengths (0 when it is 0): quad_sj's corner sine."""
    ux = rx - qx
    uy = ry - qy
    wx = px - qx
    wy = py - qy
    return (ux * wy - uy * wx) / den if den > 0.0 else 0.0


@njit(inline="always")
def _sine(px, py, qx, qy, rx, ry):
    """Sine of corner q between q->r and q->p as :func:`_sj_above` forms it (0 when a
    side is degenerate)."""
    ux = rx - qx
    uy = ry - qy
    wx = px - qx
    wy = py - qy
    lu = np.sqrt(ux * ux + uy * uy)
    lw = np.sqrt(wx * wx + wy * wy)
    return (ux * wy - uy * wx) / (lu * lw) if lu * lw > 0.0 else 0.0


# A call, not inlined IR (two call sites; see quad_sj's note in _pairing_kernel).
@njit
def _sj_above(xy, a, b, c, d, bound):
    """Whether :func:`~meshwright.quad._pairing_kernel.quad_sj` of quad (a, b, c, d) (at
    most 1) exceeds ``bound``: the same corner sines, bit for bit, stopping at the first
    one that does not."""
    if bound >= 1.0:
        return False
    v = (a, b, c, d)
    for k in range(4):
        p = v[(k + 3) % 4]
        q = v[k]
        r = v[(k + 1) % 4]
        if not _sine(xy[p, 0], xy[p, 1], xy[q, 0], xy[q, 1], xy[r, 0], xy[r, 1]) > bound:
            return False
    return True


@njit(cache=True)
def _diagonal_swap(xy, quad, alive, bnd, off, idx, lock, gain, dirty):
    """Two quads sharing a side form a hexagon; the side moves to the hexagon diagonal that
    gives the best pair when its worst scaled Jacobian gains more than ``gain``.

    Cost (decisions as testing every side of every examined quad in full): no node moves
    in this stage and a swapped pair is locked, so a quad's scaled Jacobian is computed
    once (``sjt``, the minimum over the same four corner sines whichever corner its
    listing starts at); a candidate pair's scaled Jacobian is computed only when both
    its quads pass :func:`_sj_above` the best so far, and its exact convexity and
    flat-corner tests only after that (a conjunction, in another order); and a
    side refused from one quad is not tested again from the quad across it, which would
    see the same hexagon and refuse it (``refused``: the partner it was refused with).
    """
    done = 0
    h = np.empty(6, dtype=np.int64)
    # Filled by loops: np.full would be one more overload to compile on the first call.
    sjt = np.empty(quad.shape[0])
    refused = np.empty(4 * quad.shape[0], dtype=np.int32)
    for q in range(quad.shape[0]):
        sjt[q] = np.nan
        for k in range(4):
            refused[4 * q + k] = -1
    for q1 in range(quad.shape[0]):
        if alive[q1] == 0 or lock[q1] != 0 or dirty[q1] == 0:
            continue
        for k in range(4):
            u = quad[q1, k]
            v = quad[q1, (k + 1) % 4]
            if bnd[u] != 0 and bnd[v] != 0:
                continue  # possibly a boundary side: only interior sides are swapped
            # (Quads searched in place, not through _position: an inlined function's
            # array argument costs reference counts on every pass through it.)
            q2 = -1
            for s in range(off[u], off[u + 1]):
                p = idx[s]
                if p != q1 and alive[p] != 0 and (quad[p, 0] == v or quad[p, 1] == v or quad[p, 2] == v
                                                  or quad[p, 3] == v):
                    q2 = p
            if q2 < 0 or lock[q2] != 0 or refused[4 * q1 + k] == q2:
                continue
            j = (quad[q2, 1] == u) * 1 + (quad[q2, 2] == u) * 2 + (quad[q2, 3] == u) * 3
            if quad[q2, (j + 3) % 4] != v:
                continue  # q2 must run v -> u
            # Hexagon counter-clockwise: u, c, d, v, a, b with q1 = (u, v, a, b), q2 = (v, u, c, d).
            h[0] = u
            h[1] = quad[q2, (j + 1) % 4]
            h[2] = quad[q2, (j + 2) % 4]
            h[3] = v
            h[4] = quad[q1, (k + 2) % 4]
            h[5] = quad[q1, (k + 3) % 4]
            # Each quad's scaled Jacobian once per stage (``sjt``: NaN = not yet).
            for r in (q2, q1):
                if np.isnan(sjt[r]):
                    a, b, c, d = quad[r, 0], quad[r, 1], quad[r, 2], quad[r, 3]
                    sjt[r] = _quad_sj_xy(xy[a, 0], xy[a, 1], xy[b, 0], xy[b, 1], xy[c, 0], xy[c, 1], xy[d, 0], xy[d, 1])
            old = min(sjt[q2], sjt[q1])
            best = old + gain
            pick = -1
            # Either new diagonal leaves u and v each in one quad, at the hexagon's whole
            # corner there (b, u, c and d, v, a, the same sines in both pairs): unless both
            # exceed the bound, no pair can (at a valence-4 node that corner is flat, so
            # most sides stop here instead of at two or four quads' corners).
            far = 3
            if best < 1.0 and _sine(xy[h[5], 0], xy[h[5], 1], xy[u, 0], xy[u, 1], xy[h[1], 0], xy[h[1], 1]) > best:
                if _sine(xy[h[2], 0], xy[h[2], 1], xy[v, 0], xy[v, 1], xy[h[4], 0], xy[h[4], 1]) > best:
                    far = 1
            for r in range(far, 3):
                p0, p1, p2, p3 = h[r], h[r + 1], h[r + 2], h[(r + 3) % 6]
                s0, s1, s2, s3 = h[(r + 3) % 6], h[(r + 4) % 6], h[(r + 5) % 6], h[r]
                if not (_sj_above(xy, p0, p1, p2, p3, best) and _sj_above(xy, s0, s1, s2, s3, best)):
                    continue
                val = min(quad_sj(xy, p0, p1, p2, p3), quad_sj(xy, s0, s1, s2, s3))
                if not (quad_ok(xy, p0, p1, p2, p3) and quad_ok(xy, s0, s1, s2, s3)):
                    continue
                if _flat_boundary_corner(xy, bnd, p0, p1, p2, p3) or _flat_boundary_corner(xy, bnd, s0, s1, s2, s3):
                    continue
                best = val
                pick = r
            if pick < 0:
                if q2 > q1:
                    refused[4 * q2 + (j + 3) % 4] = q1
                continue
            r = pick
            quad[q1, 0], quad[q1, 1], quad[q1, 2], quad[q1, 3] = h[r], h[r + 1], h[r + 2], h[(r + 3) % 6]
            quad[q2, 0], quad[q2, 1], quad[q2, 2], quad[q2, 3] = h[(r + 3) % 6], h[(r + 4) % 6], h[(r + 5) % 6], h[r]
            lock[q1] = 1
            lock[q2] = 1
            done += 1
            break
    return done


@njit(cache=True)
def node_quads(quad, alive, n):
    """CSR node -> live quads by a counting sort (each node's quads in increasing order):
    ``(off (n+1,) int64, idx int32)`` of ``quad`` (m, 4) int32 and ``alive`` (m,) int8."""
    off = np.zeros(n + 1, dtype=np.int64)
    for q in range(quad.shape[0]):
        if alive[q] != 0:
            for k in range(4):
                off[quad[q, k] + 1] += 1
    for v in range(n):
        off[v + 1] += off[v]
    fill = off[:-1].copy()
    idx = np.empty(off[n], dtype=np.int32)
    for q in range(quad.shape[0]):
        if alive[q] != 0:
            for k in range(4):
                v = quad[q, k]
                idx[fill[v]] = q
                fill[v] += 1
    return off, idx


@njit(cache=True)
def enhance_pass(xy, quad, alive, bnd, off, idx, tri_node, accept, gain, dirty):
    """One pass of node elimination, element elimination and diagonal swapping.

    ``tri_node`` (n,) int8 flags nodes of left-over triangles, which no operation touches.
    Only quads flagged in ``dirty`` (q,) int8 (and nodes with one in their star) are
    examined; on return ``dirty`` flags the quads with a node in a quad this pass changed,
    the only ones whose operations can decide otherwise in the next pass (every test
    reads the stars and positions of the quad's own nodes, and an operation changes only
    the quads it locks; a refused one leaves no trace), so a pass with ``dirty`` decides
    exactly as a pass over every quad.  Returns (doublets removed, diamonds collapsed,
    sides swapped).
    """
    lock = np.zeros(quad.shape[0], dtype=np.int8)
    # Nodes with a dirty quad in their star, flagged from the quads' rows before any
    # operation (the star is the live quads of the table): a pass after the first then
    # reads each node's star only near the changes, not all of them.
    wake = np.zeros(xy.shape[0], dtype=np.int8)
    for q in range(quad.shape[0]):
        if dirty[q] != 0 and alive[q] != 0:
            for k in range(4):
                wake[quad[q, k]] = 1
    n1 = _node_elimination(xy, quad, alive, bnd, off, idx, lock, tri_node, wake)
    n2 = _element_elimination(xy, quad, alive, bnd, off, idx, lock, tri_node, accept, dirty)
    n3 = _diagonal_swap(xy, quad, alive, bnd, off, idx, lock, gain, dirty)
    touched = np.zeros(xy.shape[0], dtype=np.int8)
    for q in range(quad.shape[0]):
        if lock[q] != 0:
            for k in range(4):
                touched[quad[q, k]] = 1
    for q in range(quad.shape[0]):
        dirty[q] = 0
        if alive[q] != 0:
            for k in range(4):
                if touched[quad[q, k]] != 0:
                    dirty[q] = 1
                    break
    return n1, n2, n3


@njit(cache=True)
def balance_corners(xy, quad, alive, bnd, tri_node, off, idx):
    """Fixed nodes in exactly two quads with a corner wider than 150 degrees
    (:func:`~meshwright.quad._pairing_kernel.corner_flat`): the free node m across their
    common side turns about the fixed node towards the bisector of the two quads' angle
    there (at its distance from it) if every quad around m stays strictly convex (exact)
    and their worst scaled Jacobian rises.  Returns the number of nodes moved.

    A reflex input corner covered by two quads is split between them by where m is; the
    Laplacian smoothing moves m towards its neighbours' centroid, not towards the
    bisector, and the corner never moves (letter_a.poly at h = 0.5: corners of 167 and
    114 degrees at its 281-degree notch, 172 after smoothing, scaled Jacobian 0.145).
    The guarded smoothing that follows lets no move lower the worst corner sine around
    m again.  ``off``, ``idx``: the node -> quad table of the current quads.
    """
    done = 0
    none = np.int64(-1)
    for v in range(xy.shape[0]):
        if bnd[v] == 0 or tri_node[v] != 0 or _live_count(alive, off, idx, v) != 2:
            continue
        q1 = -1
        q2 = -1
        for s in range(off[v], off[v + 1]):
            if alive[idx[s]] != 0:
                if q1 < 0:
                    q1 = idx[s]
                else:
                    q2 = idx[s]
        i1 = _position(quad, q1, v)
        i2 = _position(quad, q2, v)
        # Counter-clockwise quads: the angle at v sweeps from its next node to its previous
        # one.  Order them so that q1's previous node is q2's next: m, their common node.
        if quad[q1, (i1 + 3) % 4] != quad[q2, (i2 + 1) % 4]:
            q1, q2, i1, i2 = q2, q1, i2, i1
        m = quad[q1, (i1 + 3) % 4]
        if m != quad[q2, (i2 + 1) % 4] or bnd[m] != 0 or tri_node[m] != 0:
            continue
        a = quad[q1, (i1 + 1) % 4]
        b = quad[q2, (i2 + 3) % 4]
        if not (corner_flat(xy, np.int64(m), v, np.int64(a)) or corner_flat(xy, np.int64(b), v, np.int64(m))):
            continue
        # Angles at v counter-clockwise from its side to a: m at t1, b at t1 + t2.
        ax = xy[a, 0] - xy[v, 0]
        ay = xy[a, 1] - xy[v, 1]
        mx = xy[m, 0] - xy[v, 0]
        my = xy[m, 1] - xy[v, 1]
        bx = xy[b, 0] - xy[v, 0]
        by = xy[b, 1] - xy[v, 1]
        t1 = np.arctan2(ax * my - ay * mx, ax * mx + ay * my) % (2.0 * np.pi)
        t2 = np.arctan2(mx * by - my * bx, mx * bx + my * by) % (2.0 * np.pi)
        la = np.sqrt(ax * ax + ay * ay)
        lm = np.sqrt(mx * mx + my * my)
        if la == 0.0:
            continue
        old = _local_min(xy, quad, alive, off, idx, m, none, none, none)
        ox = xy[m, 0]
        oy = xy[m, 1]
        # The bisector, or a half or a quarter of the way there when the whole turn would
        # fold a quad of m's star: the first that raises the star's worst scaled Jacobian.
        better = False
        for k in range(3):
            turn = t1 + (0.5 * (t1 + t2) - t1) / (1 << k)
            c = np.cos(turn)
            sn = np.sin(turn)
            xy[m, 0] = xy[v, 0] + lm * (c * ax - sn * ay) / la
            xy[m, 1] = xy[v, 1] + lm * (sn * ax + c * ay) / la
            if _local_min(xy, quad, alive, off, idx, m, none, none, none) > old:
                better = True
                break
        if not better:
            xy[m, 0] = ox
            xy[m, 1] = oy
            continue
        done += 1
    return done


@njit(inline="always")
def _tri_sine(xy, a, b, c):
    """Smallest corner sine of triangle (a, b, c) (counter-clockwise: all positive)."""
    return min(_sine(xy[c, 0], xy[c, 1], xy[a, 0], xy[a, 1], xy[b, 0], xy[b, 1]),
               _sine(xy[a, 0], xy[a, 1], xy[b, 0], xy[b, 1], xy[c, 0], xy[c, 1]),
               _sine(xy[b, 0], xy[b, 1], xy[c, 0], xy[c, 1], xy[a, 0], xy[a, 1]))


@njit
def _is_line(loff, lidx, u, v):
    """Whether u-v is a line cell (the lines of u in CSR form ``loff`` / ``lidx``)."""
    for s in range(loff[u], loff[u + 1]):
        if lidx[s] == v:
            return True
    return False


@njit(cache=True)
def resplit_pass(xy, quad, tri, bnd, off, idx, loff, lidx, target, gain):
    """One pass of triangle-quad re-splitting: a left-over triangle and a quad across one
    of its sides form a pentagon, which splits into a triangle and a quad in five ways
    (a diagonal from each corner); where the pair's worst corner sine (the triangle's
    three, the quad's four) is under ``target``, the split whose worst corner sine gains
    more than ``gain`` over it, the best over the triangle's three sides, replaces the
    pair.

    The triangle's corners become corners of the quads the chord refinement cuts it
    into, so a sliver triangle leaves slivers there that no smoothing opens when its
    nodes are fixed.  Only triangles and quads not changed before in the pass are read
    (the node -> quad table ``off``, ``idx`` is the pass's start).  Every new triangle is
    counter-clockwise and every new quad strictly convex (exact ``orient2d``), without a
    flat corner between boundary nodes.  A line (``loff``, ``lidx``: node -> the nodes it
    shares a line cell with) is never crossed: an interior segment has quads on both
    sides.  ``quad`` (m, 4) and ``tri`` (t, 3) are modified in place; returns the number
    of pairs re-split.
    """
    done = 0
    lock = np.zeros(quad.shape[0], dtype=np.int8)
    p = np.empty(5, dtype=np.int64)
    best_p = np.empty(5, dtype=np.int64)
    for t in range(tri.shape[0]):
        ts = _tri_sine(xy, tri[t, 0], tri[t, 1], tri[t, 2])
        best = -2.0
        best_q = -1
        best_i = -1
        for e in range(3):
            u = np.int64(tri[t, e])
            v = np.int64(tri[t, (e + 1) % 3])
            w = np.int64(tri[t, (e + 2) % 3])
            if _is_line(loff, lidx, u, v):
                continue
            q = -1
            j = -1
            for s in range(off[v], off[v + 1]):
                r = idx[s]
                for k in range(4):
                    if quad[r, k] == v and quad[r, (k + 1) % 4] == u:
                        q = r
                        j = k
            if q < 0 or lock[q] != 0:
                continue
            x = np.int64(quad[q, (j + 2) % 4])
            y = np.int64(quad[q, (j + 3) % 4])
            old = min(ts, quad_sj(xy, v, u, x, y))
            if old >= target:
                continue
            # Pentagon counter-clockwise: u, x, y, v, w; the present split is i = 3.
            p[0], p[1], p[2], p[3], p[4] = u, x, y, v, w
            floor = max(best, old + gain)
            for i in range(5):
                if i == 3:
                    continue
                a, b, c = p[i], p[(i + 1) % 5], p[(i + 2) % 5]
                d, f = p[(i + 3) % 5], p[(i + 4) % 5]
                if not (_tri_sine(xy, a, b, c) > floor and _sj_above(xy, c, d, f, a, floor)):
                    continue
                if not (corner_ok(xy, a, b, c) and quad_ok(xy, c, d, f, a)):
                    continue
                if _flat_boundary_corner(xy, bnd, c, d, f, a):
                    continue
                floor = min(_tri_sine(xy, a, b, c), quad_sj(xy, c, d, f, a))
                best = floor
                best_q = q
                best_i = i
                for k in range(5):
                    best_p[k] = p[k]
        if best_q < 0:
            continue
        i = best_i
        tri[t, 0], tri[t, 1], tri[t, 2] = best_p[i], best_p[(i + 1) % 5], best_p[(i + 2) % 5]
        q = best_q
        quad[q, 0], quad[q, 1] = best_p[(i + 2) % 5], best_p[(i + 3) % 5]
        quad[q, 2], quad[q, 3] = best_p[(i + 4) % 5], best_p[i]
        lock[q] = 1
        done += 1
    return done


@njit(cache=True)
def swap_low_pass(xy, quad, bnd, off, idx, loff, lidx, target, gain):
    """One pass of diagonal swapping at quads with a corner between three boundary nodes
    whose sine is under ``target``, across a side between two boundary nodes that is not
    a line (``loff``, ``lidx`` as in :func:`resplit_pass`): the two quads' hexagon takes
    the other diagonal that raises their worst scaled Jacobian by more than ``gain``, the
    better of the two.

    :func:`_diagonal_swap` leaves every side between two boundary nodes alone, since
    without the lines it cannot tell an interior segment from a side across the domain;
    at a reflex input corner next to a fixed node such a side may be the only one whose
    swap opens a corner.  New quads are strictly convex (exact) without a flat corner
    between boundary nodes.  ``quad`` is modified in place; returns the number of swaps.
    """
    done = 0
    lock = np.zeros(quad.shape[0], dtype=np.int8)
    h = np.empty(6, dtype=np.int64)
    for q1 in range(quad.shape[0]):
        if lock[q1] != 0:
            continue
        # Sides between two boundary nodes only: _diagonal_swap has tested every other.
        pairs = 0
        for k in range(4):
            pairs += bnd[quad[q1, k]] != 0 and bnd[quad[q1, (k + 1) % 4]] != 0
        if pairs == 0:
            continue
        # Only a corner between three boundary nodes, which the smoothing cannot open
        # (they stay or slide on their curves), calls for a swap before it.
        rigid = 1.0
        for k in range(4):
            p0 = quad[q1, (k + 3) % 4]
            p1 = quad[q1, k]
            p2 = quad[q1, (k + 1) % 4]
            if bnd[p0] != 0 and bnd[p1] != 0 and bnd[p2] != 0:
                rigid = min(rigid, _sine(xy[p0, 0], xy[p0, 1], xy[p1, 0], xy[p1, 1], xy[p2, 0], xy[p2, 1]))
        if rigid >= target:
            continue
        s1 = quad_sj(xy, np.int64(quad[q1, 0]), np.int64(quad[q1, 1]), np.int64(quad[q1, 2]), np.int64(quad[q1, 3]))
        for k in range(4):
            u = np.int64(quad[q1, k])
            v = np.int64(quad[q1, (k + 1) % 4])
            if bnd[u] == 0 or bnd[v] == 0:
                continue
            if _is_line(loff, lidx, u, v):
                continue
            q2 = -1
            j = -1
            for s in range(off[u], off[u + 1]):
                p = idx[s]
                if p == q1:
                    continue
                for i in range(4):
                    if quad[p, i] == u and quad[p, (i + 3) % 4] == v:
                        q2 = p
                        j = i
            if q2 < 0 or lock[q2] != 0:
                continue
            # Hexagon counter-clockwise: u, c, d, v, a, b with q1 = (u, v, a, b), q2 = (v, u, c, d).
            h[0] = u
            h[1] = quad[q2, (j + 1) % 4]
            h[2] = quad[q2, (j + 2) % 4]
            h[3] = v
            h[4] = quad[q1, (k + 2) % 4]
            h[5] = quad[q1, (k + 3) % 4]
            best = min(s1, quad_sj(xy, h[3], h[0], h[1], h[2])) + gain
            pick = -1
            for r in range(1, 3):
                p0, p1, p2, p3 = h[r], h[r + 1], h[r + 2], h[(r + 3) % 6]
                t0, t1, t2, t3 = h[(r + 3) % 6], h[(r + 4) % 6], h[(r + 5) % 6], h[r]
                if not (_sj_above(xy, p0, p1, p2, p3, best) and _sj_above(xy, t0, t1, t2, t3, best)):
                    continue
                if not (quad_ok(xy, p0, p1, p2, p3) and quad_ok(xy, t0, t1, t2, t3)):
                    continue
                if _flat_boundary_corner(xy, bnd, p0, p1, p2, p3) or _flat_boundary_corner(xy, bnd, t0, t1, t2, t3):
                    continue
                best = min(quad_sj(xy, p0, p1, p2, p3), quad_sj(xy, t0, t1, t2, t3))
                pick = r
            if pick < 0:
                continue
            r = pick
            quad[q1, 0], quad[q1, 1], quad[q1, 2], quad[q1, 3] = h[r], h[r + 1], h[r + 2], h[(r + 3) % 6]
            quad[q2, 0], quad[q2, 1], quad[q2, 2], quad[q2, 3] = h[(r + 3) % 6], h[(r + 4) % 6], h[(r + 5) % 6], h[r]
            lock[q1] = 1
            lock[q2] = 1
            done += 1
            break
    return done
