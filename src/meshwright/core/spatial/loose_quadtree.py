r"""Loose quadtree of axis-aligned boxes over flat arrays (range queries for advancing fronts).

Source: T. Ulrich, "Loose octrees", Game Programming Gems, 2000; the use in advancing-front
meshing follows R. Löhner, "Applied CFD techniques", Wiley 2001 (ch. 2, search structures
for the front).

Each item (a box ``qbox[i] = (xmin, ymin, xmax, ymax)``) is stored in one node: the deepest
node whose cell contains the centre of the box and whose half-size is at least the box's
half-extent.  A node of half-size H centred at c therefore holds only boxes inside its
*loose* cell ``c +- 2H``, so a query visits a node only when the query box meets that loose
cell.  Items of similar size sit at similar depths, which keeps a query near small
faces from wading through large ones and the reverse: a graded front (sizes over many
orders of magnitude) costs O(log n) per query.

Deletion is lazy: the caller clears ``alive[i]`` and the next query passing through the
node unlinks the item.  Nodes are never freed (a front only shrinks where it has been).

Array layout::

    qgeo   (3,)  float64   root centre x, y and half-size H
    qmeta  (2,)  int64     [nodes in use, depth cap]
    qchild (4 cap,) int32  child q of node n at 4 n + q (q = east + 2 north), -1 none
    qhead  (cap,) int32    first item of node n's list, -1 none
    qnext  (items,) int32  next item in the same node's list, -1 end
    qbox   (items, 4) float64
    alive  (items,) int8   owned by the caller; 0 = deleted

                 +-----+-----+
                 |  2  |  3  |   child quadrant q = (x >= cx) + 2 (y >= cy)
                 +-----c-----+
                 |  0  |  1  |
                 +-----+-----+
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.spatial._nodes import child_of

__all__ = ["Q_NODES", "Q_DEPTH", "qt_new", "qt_insert", "qt_query", "STACK_PER_LEVEL"]

Q_NODES = 0
Q_DEPTH = 1
STACK_PER_LEVEL = 4  # a depth-first query keeps at most 3 siblings per level plus one


def qt_new(bbox, finest: float, nodes: int = 1024):
    """Empty tree over ``bbox = (xmin, ymin, xmax, ymax)`` with cells down to ``finest``.

    Returns ``(qgeo, qmeta, qchild, qhead)``; the item arrays belong to the caller.
    """
    x0, y0, x1, y1 = (float(v) for v in bbox)
    half = 0.5 * max(x1 - x0, y1 - y0)
    half = half * 1.01 + 1e-300 if half > 0.0 else 1.0
    qgeo = np.array([0.5 * (x0 + x1), 0.5 * (y0 + y1), half])
    depth = int(np.clip(np.ceil(np.log2(2.0 * half / max(float(finest), 1e-300))), 1, 48))
    qmeta = np.array([1, depth], dtype=np.int64)
    qchild = np.full(4 * max(nodes, 1), -1, dtype=np.int32)
    qhead = np.full(max(nodes, 1), -1, dtype=np.int32)
    return qgeo, qmeta, qchild, qhead


@njit(inline="always")
def qt_insert(item, qgeo, qmeta, qchild, qhead, qnext, qbox):
    """Link ``item`` (its box already in ``qbox[item]``) into the tree.

    The caller guarantees room for ``qmeta[Q_DEPTH]`` more nodes (``qhead`` length).
    """
    x0 = qbox[item, 0]
    y0 = qbox[item, 1]
    x1 = qbox[item, 2]
    y1 = qbox[item, 3]
    mx = 0.5 * (x0 + x1)
    my = 0.5 * (y0 + y1)
    ext = 0.5 * max(x1 - x0, y1 - y0)
    node = 0
    cx = qgeo[0]
    cy = qgeo[1]
    h = qgeo[2]
    for _ in range(qmeta[Q_DEPTH]):
        hc = 0.5 * h
        if ext > hc:
            break
        east = mx >= cx
        north = my >= cy
        q = (1 if east else 0) + (2 if north else 0)
        cx = cx + hc if east else cx - hc
        cy = cy + hc if north else cy - hc
        h = hc
        node = child_of(node, q, qmeta, qchild, qhead)
    qnext[item] = qhead[node]
    qhead[node] = item


@njit(inline="always")
def qt_query(x0, y0, x1, y1, qgeo, qchild, qhead, qnext, qbox, alive, out, stack, fstack):
    """Items whose box meets ``[x0, x1] x [y0, y1]`` (closed), written to ``out``.

    Dead items met on the way are unlinked.  ``stack`` (k,) int64 and ``fstack`` (k, 3)
    float64 are scratch of at least ``STACK_PER_LEVEL * (depth + 1)`` rows.

    Returns
    -------
    int
        The number of items found; when it exceeds ``len(out)`` only the first
        ``len(out)`` were written and the caller must retry with a larger ``out``.
    """
    cap = out.shape[0]
    k = 0
    top = 1
    stack[0] = 0
    fstack[0, 0] = qgeo[0]
    fstack[0, 1] = qgeo[1]
    fstack[0, 2] = qgeo[2]
    while top > 0:
        top -= 1
        node = stack[top]
        cx = fstack[top, 0]
        cy = fstack[top, 1]
        h = fstack[top, 2]
        prev = -1
        it = qhead[node]
        while it >= 0:
            nxt = qnext[it]
            if alive[it] == 0:
                if prev < 0:
                    qhead[node] = nxt
                else:
                    qnext[prev] = nxt
            else:
                if not (qbox[it, 2] < x0 or qbox[it, 0] > x1 or qbox[it, 3] < y0 or qbox[it, 1] > y1):
                    if k < cap:
                        out[k] = it
                    k += 1
                prev = it
            it = nxt
        # A child's loose cell c +- 2 hc holds every box of its subtree: one that misses
        # the query box is never pushed (the root, loose without bound, is always read).
        hc = 0.5 * h
        reach = 2.0 * hc
        for q in range(4):
            child = qchild[4 * node + q]
            if child >= 0:
                ccx = cx + hc if (q & 1) else cx - hc
                ccy = cy + hc if (q & 2) else cy - hc
                if ccx + reach < x0 or ccx - reach > x1 or ccy + reach < y0 or ccy - reach > y1:
                    continue
                stack[top] = child
                fstack[top, 0] = ccx
                fstack[top, 1] = ccy
                fstack[top, 2] = hc
                top += 1
    return k
