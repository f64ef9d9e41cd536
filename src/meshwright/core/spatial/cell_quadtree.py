r"""Quadtree of axis-aligned boxes split over at most four cells (range queries for fronts).

A loose quadtree (:mod:`meshwright.core.spatial.loose_quadtree`) stores each box in one
node whose *loose* cell (twice the cell) holds it, so a query meets the loose cells of
about four nodes on every level, however small it is: on a graded front 41 node visits
for 4 faces.  Here each box is stored in every cell it meets on the level whose cells are
at least ``SPLIT`` times as wide as the box (at most two cells per axis), so a query meets
only the cells its own box meets: one per level down to the deepest cell holding the
whole query box, reached without any geometric test by following the cell's bits from
the root; below it, the cells of that subtree that meet the box.  An item met in several
of the query's cells is reported by one of them only, the cell holding the lower-left
corner of the intersection of the two boxes (items split over the cells they meet as in
the MX-CIF and PMR quadtrees of H. Samet, "Foundations of multidimensional and metric
data structures", 2006; the reporting rule is the usual one for grids whose items span
several cells).

Cells are addressed by integers: a coordinate x maps to ``ix = floor((x - ox) s)``
clamped to ``[0, 2**D)`` (D the depth, ``s = 2**D / side``) and the cell of level l
holding it is ``ix >> (D - l)``.  The map is monotone, so an item whose real box meets the
query box has an integer box meeting the query's, and the rule above reports it exactly
once; the exact real comparison then decides.  Items outside the root square are clamped
to its border cells, which only costs time.

Deletion is lazy: the caller clears ``alive[i]`` and a query passing a cell unlinks the
item's entry there (each of its up to four entries on its own).  Nodes are never freed.

Array layout::

    qgeo   (3,)  float64   ox, oy (root square's lower-left corner), s (cells per unit
                           on level D)
    qmeta  (3,)  int64     [nodes in use, nodes one insertion may create, depth D]
    qchild (4 cap,) int32  child q of node n at 4 n + q (q = east + 2 north), -1 none
    qhead  (cap,) int32    first entry of node n's list, -1 none
    qnext  (4 items,) int32  entry 4 i + k is item i's k-th cell; next entry, -1 end
    qcell  (items, 2) int64  integer lower-left corner (ix, iy) of each item's box
    qbox   (items, 4) float64  (xmin, ymin, xmax, ymax)
    alive  (items,) int8   owned by the caller; 0 = deleted

A query scans a depth-first stack: ``stack`` (k,) int64 node ids and ``fstack`` (k, 3)
float64 the node's cell (shift D - level, i, j), integers exact in float64; ``k >=
STACK_PER_LEVEL * (qmeta[Q_DEPTH] + 2)`` rows suffice (three siblings per level and one).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.jit import inner
from meshwright.core.spatial._nodes import child_of

__all__ = ["Q_NODES", "Q_ROOM", "Q_DEPTH", "STACK_PER_LEVEL", "MAX_DEPTH", "SPLIT", "ct_new", "ct_insert", "ct_query"]

Q_NODES = 0
Q_ROOM = 1
Q_DEPTH = 2
STACK_PER_LEVEL = 4  # rows per level: more than the 3 D + 1 a query stacks
MAX_DEPTH = 30  # integer cells below 2**30 per axis (finer items share the finest cells)
# An item's cells are at least SPLIT times as wide as its box.  Wider cells hold more items
# (more entries scanned), narrower ones split more items and add levels to pass; a front's
# query (pairing, three-element x0.5) cost 408 / 263 / 212 / 352 ns with SPLIT 1 / 2 / 4 / 8
# (the loose quadtree 630-710 ns), insertion 87 / 56 / 40 / 72 ns (loose 64-69 ns).
SPLIT = 4


def ct_new(bbox, finest: float, nodes: int = 1024):
    """Empty tree over ``bbox = (xmin, ymin, xmax, ymax)`` with cells down to ``finest``.

    Returns ``(qgeo, qmeta, qchild, qhead)``; the item arrays (``qnext`` of four entries per
    item, ``qcell``, ``qbox``) belong to the caller.
    """
    x0, y0, x1, y1 = (float(v) for v in bbox)
    half = 0.5 * max(x1 - x0, y1 - y0)
    half = half * 1.01 + 1e-300 if half > 0.0 else 1.0
    depth = int(np.clip(np.ceil(np.log2(2.0 * half / max(float(finest), 1e-300))), 1, MAX_DEPTH))
    qgeo = np.array([0.5 * (x0 + x1) - half, 0.5 * (y0 + y1) - half, 2.0**depth / (2.0 * half)])
    # Each of an item's (at most four) cells may need a new node on every level.
    qmeta = np.array([1, 4 * (depth + 1), depth], dtype=np.int64)
    qchild = np.full(4 * max(nodes, 1), -1, dtype=np.int32)
    qhead = np.full(max(nodes, 1), -1, dtype=np.int32)
    return qgeo, qmeta, qchild, qhead


@inner
def _icoord(v, o, s, top):
    """Integer cell coordinate on the finest level of real coordinate v (monotone in v); a
    compiled call over scalars only (LLVM inlines it), not Numba IR inlining at the eight
    call sites: about 1 s less first-run compile of the front (comp helper's A/B)."""
    t = np.floor((v - o) * s)
    if t < 0.0:
        return np.int64(0)
    if t > top:
        return np.int64(top)
    return np.int64(t)


@njit(inline="always")
def ct_insert(item, qgeo, qmeta, qchild, qhead, qnext, qcell, qbox):
    """Link ``item`` (its box already in ``qbox[item]``) into every cell its box meets on its
    level.

    The caller guarantees room for ``qmeta[Q_ROOM]`` more nodes (``qhead`` length) and four
    entries per item in ``qnext``.
    """
    depth = qmeta[Q_DEPTH]
    top = float((1 << depth) - 1)
    ix0 = _icoord(qbox[item, 0], qgeo[0], qgeo[2], top)
    iy0 = _icoord(qbox[item, 1], qgeo[1], qgeo[2], top)
    ix1 = _icoord(qbox[item, 2], qgeo[0], qgeo[2], top)
    iy1 = _icoord(qbox[item, 3], qgeo[1], qgeo[2], top)
    qcell[item, 0] = ix0
    qcell[item, 1] = iy0
    # Cells 2**sh wide, sh the least with 2**sh >= SPLIT * span: the box meets at most two
    # per axis, and a second one with odds at most 1 / SPLIT.
    span = max(ix1 - ix0, iy1 - iy0)
    sh = 0
    while (np.int64(1) << sh) < SPLIT * span:
        sh += 1
    level = depth - sh
    k = 0
    for cx in range(ix0 >> sh, (ix1 >> sh) + 1):
        for cy in range(iy0 >> sh, (iy1 >> sh) + 1):
            node = 0
            for t in range(level - 1, -1, -1):
                node = child_of(node, ((cx >> t) & 1) + 2 * ((cy >> t) & 1), qmeta, qchild, qhead)
            e = 4 * item + k
            qnext[e] = qhead[node]
            qhead[node] = e
            k += 1


@njit(inline="always")
def _scan(node, sh, cx, cy, qx0, qy0, x0, y0, x1, y1, qhead, qnext, qcell, qbox, alive, out, k):
    """Report node's items meeting the box from this cell only when it holds the lower-left
    corner of the intersection (module docstring); unlink dead entries.  Returns the new
    count."""
    cap = out.shape[0]
    prev = -1
    e = qhead[node]
    while e >= 0:
        nxt = qnext[e]
        it = e >> 2
        if alive[it] == 0:
            if prev < 0:
                qhead[node] = nxt
            else:
                qnext[prev] = nxt
        else:
            # One test without short-circuits: a query scans about 28 entries to report 4
            # (pairing's disk), and each of five unpredictable branches cost more than the
            # comparisons (10 % of the front's run).  The item is written at the next slot
            # either way and counted only on a hit.
            hit = (
                ((max(qcell[it, 0], qx0) >> sh) == cx)
                & ((max(qcell[it, 1], qy0) >> sh) == cy)
                & (qbox[it, 2] >= x0) & (qbox[it, 0] <= x1) & (qbox[it, 3] >= y0) & (qbox[it, 1] <= y1)
            )
            if k < cap:
                out[k] = it
            k += np.int64(hit)
            prev = e
        e = nxt
    return k


@njit(inline="always")
def ct_query(x0, y0, x1, y1, qgeo, qmeta, qchild, qhead, qnext, qcell, qbox, alive, out, stack, fstack):
    """Items whose box meets ``[x0, x1] x [y0, y1]`` (closed), each once, written to ``out``.

    Dead items met on the way are unlinked.  ``stack`` and ``fstack`` are scratch (module
    docstring).

    Returns
    -------
    int
        The number of items found; when it exceeds ``len(out)`` only the first
        ``len(out)`` were written and the caller must retry with a larger ``out``.
    """
    depth = qmeta[Q_DEPTH]
    top = float((1 << depth) - 1)
    qx0 = _icoord(x0, qgeo[0], qgeo[2], top)
    qy0 = _icoord(y0, qgeo[1], qgeo[2], top)
    qx1 = _icoord(x1, qgeo[0], qgeo[2], top)
    qy1 = _icoord(y1, qgeo[1], qgeo[2], top)
    # The deepest level whose one cell holds the whole query box: above and at it the
    # query meets one cell per level, the path of the box's common leading bits.
    diff = (qx0 ^ qx1) | (qy0 ^ qy1)
    sh0 = 0
    while diff >> sh0:
        sh0 += 1
    k = 0
    node = 0
    for t in range(depth - 1, sh0 - 1, -1):
        k = _scan(node, t + 1, qx0 >> (t + 1), qy0 >> (t + 1), qx0, qy0, x0, y0, x1, y1,
                  qhead, qnext, qcell, qbox, alive, out, k)
        node = qchild[4 * node + ((qx0 >> t) & 1) + 2 * ((qy0 >> t) & 1)]
        if node < 0:
            return k
    top_ = 1
    stack[0] = node
    fstack[0, 0] = sh0
    fstack[0, 1] = qx0 >> sh0
    fstack[0, 2] = qy0 >> sh0
    while top_ > 0:
        top_ -= 1
        node = stack[top_]
        sh = np.int64(fstack[top_, 0])
        cx = np.int64(fstack[top_, 1])
        cy = np.int64(fstack[top_, 2])
        k = _scan(node, sh, cx, cy, qx0, qy0, x0, y0, x1, y1, qhead, qnext, qcell, qbox, alive, out, k)
        if sh == 0:
            continue
        sc = sh - 1
        for q in range(4):
            child = qchild[4 * node + q]
            if child < 0:
                continue
            ccx = 2 * cx + (q & 1)
            ccy = 2 * cy + (q >> 1)
            if ccx < (qx0 >> sc) or ccx > (qx1 >> sc) or ccy < (qy0 >> sc) or ccy > (qy1 >> sc):
                continue
            stack[top_] = child
            fstack[top_, 0] = sc
            fstack[top_, 1] = ccx
            fstack[top_, 2] = ccy
            top_ += 1
    return k
