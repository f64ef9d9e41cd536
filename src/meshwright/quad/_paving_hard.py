"""Hard lines: interior segments that meet a loop become paving boundaries (FASTQ style).

An interior segment that ends on a loop (a junction, split there by the domain) is run
by the paving boundary on both of its sides: the paving boundaries are the face cycles of
the plane graph of the loops' edges (domain on their left) and the attached segment
pieces (both ways), so a dangling segment is a slit of its loop (its tip a reversal),
a wall splits its loop in two and a segment cycle bounds a region of its own.  Rows then
grow from the segment as from the boundary, and every piece is a quad edge on both sides.
Segments that meet no loop stay obstacles (:mod:`meshwright.quad._paving_obstacles`).

The turn at each node is decided exactly (``orient2d`` of the edge directions): a cycle
leaves a node along the first edge clockwise from the one it came in by.

Array layout: points (n, 2) float64; loops (k,) int64 node ids, domain on the left;
segment pieces two (m,) int64 end arrays.
"""

from __future__ import annotations

import numpy as np

from numba import njit

from meshwright.core.predicates import orient2d
from meshwright.quad.regions import _components

__all__ = ["FLAT", "FREE_HARD", "attached_pieces", "face_cycles", "pieces_two_sided"]

FREE_HARD = 8  # a segment meeting no loop is a hard line too from this many pieces on
FLAT = 1e-2  # with interior segments, no closure leaves a corner sine below this


def attached_pieces(loops, sa: np.ndarray, sb: np.ndarray) -> np.ndarray:
    """(m,) bool: segment pieces whose connected component (through shared nodes) has a
    node on a loop or at least :data:`FREE_HARD` pieces (a long free segment: rows around
    it as around a hole; a short one, a few pieces, stays an obstacle, whose slit fronts of
    a few nodes the closures do not take)."""
    m = len(sa)
    if not m:
        return np.zeros(0, dtype=bool)
    nodes, inv = np.unique(np.concatenate([sa, sb]), return_inverse=True)
    comp = _components(len(nodes), np.column_stack([inv[:m], inv[m:]]).astype(np.int64))
    hit = np.zeros(len(nodes), dtype=bool)
    hit[comp[np.isin(nodes, np.concatenate(loops))]] = True
    hit |= np.bincount(comp[inv[:m]], minlength=len(nodes)) >= FREE_HARD
    return hit[comp[inv[:m]]]


def _first_clockwise(xy, v: int, u: int, cands) -> int:
    """The target of the first edge out of ``v`` clockwise from the direction ``v -> u``
    (exact); ``u`` itself only when nothing else is there (a segment's tip)."""
    px, py = xy[v]
    ux, uy = xy[u]
    best, best_g = -1, 9
    for w in cands:
        if w == u:
            g = 3
        else:
            o = orient2d(px, py, ux, uy, xy[w, 0], xy[w, 1])
            g = 0 if o < 0.0 else (2 if o > 0.0 else 1)
        if g < best_g:
            best, best_g = w, g
        elif g == best_g and g in (0, 2):
            # Same half-turn: w comes first if it lies counter-clockwise of the best.
            if orient2d(px, py, xy[best, 0], xy[best, 1], xy[w, 0], xy[w, 1]) > 0.0:
                best = w
    return best


@njit(cache=True)
def _cycles(nxt):
    """The cycles of the permutation ``nxt`` of half-edges, each from its smallest
    half-edge: (half-edges in cycle order, (c + 1,) offsets of the c cycles)."""
    n = nxt.shape[0]
    seen = np.zeros(n, dtype=np.bool_)
    seq = np.empty(n, dtype=np.int64)
    bounds = np.zeros(n + 1, dtype=np.int64)
    k = 0
    c = 0
    for s in range(n):
        if seen[s]:
            continue
        h = s
        while not seen[h]:
            seen[h] = True
            seq[k] = h
            k += 1
            h = nxt[h]
        c += 1
        bounds[c] = k
    return seq, bounds[: c + 1]


def face_cycles(xy, loops, sa: np.ndarray, sb: np.ndarray):
    """The paving boundaries of ``loops`` with the segment pieces ``sa``, ``sb`` run on
    both sides (module docstring).

    Returns
    -------
    cycles : list of (k,) int64
        Loops that meet no piece come first, unchanged and in order; then the face
        cycles of the others, each from its first half-edge (the touched loops' edges in
        order, then the pieces forward, then backward).
    source : list of int
        The loop each cycle starts on (-1 for a cycle of segment pieces only).
    """
    ends = np.concatenate([sa, sb])
    touched = [i for i, f in enumerate(loops) if np.isin(f, ends).any()]
    cycles = [f for i, f in enumerate(loops) if i not in touched]
    source = [i for i in range(len(loops)) if i not in touched]
    lp = [np.asarray(loops[i], dtype=np.int64) for i in touched]
    heads = np.concatenate(lp + [sa, sb]).astype(np.int64)
    tails = np.concatenate([np.roll(f, -1) for f in lp] + [sb, sa]).astype(np.int64)
    loop_of = np.repeat(np.asarray(touched, dtype=np.int64), [len(f) for f in lp])
    # Each half-edge's successor: the only edge out of its end, or at a node with more
    # (a junction, a segment's inner node) the first clockwise from the way back.
    order = np.argsort(heads, kind="stable")
    lo = np.searchsorted(heads[order], tails, side="left")
    deg = np.searchsorted(heads[order], tails, side="right") - lo
    nxt = order[np.minimum(lo, len(order) - 1)]
    # Two edges out, one of them back: the other (a segment's inner node), no turn to decide.
    two = np.flatnonzero(deg == 2)
    a, b = order[lo[two]], order[np.minimum(lo[two] + 1, len(order) - 1)]
    back_a, back_b = tails[a] == heads[two], tails[b] == heads[two]
    nxt[two[back_a]] = b[back_a]
    nxt[two[back_b]] = a[back_b]
    decided = deg == 1
    decided[two[back_a | back_b]] = True
    for h in np.flatnonzero(~decided).tolist():
        outs = order[lo[h] : lo[h] + deg[h]]
        w = _first_clockwise(xy, int(tails[h]), int(heads[h]), tails[outs].tolist())
        nxt[h] = outs[tails[outs] == w][0]
    seq, bounds = _cycles(nxt)
    for c in range(len(bounds) - 1):
        hs = seq[bounds[c] : bounds[c + 1]]
        cycles.append(heads[hs])
        source.append(int(loop_of[hs[0]]) if hs[0] < len(loop_of) else -1)
    return cycles, source


def pieces_two_sided(quads: np.ndarray, tris: np.ndarray, sa: np.ndarray, sb: np.ndarray) -> bool:
    """Whether every segment piece is a side of one cell (quad or triangle) each way: an
    edge of the mesh with cells on both sides."""
    if not len(sa):
        return True
    cells = [np.asarray(c, dtype=np.int64) for c in (quads, tris) if len(c)]
    n = int(max([c.max() for c in cells] + [sa.max(), sb.max()])) + 1
    d = np.concatenate([(c * n + np.roll(c, -1, axis=1)).ravel() for c in cells] + [np.zeros(0, dtype=np.int64)])
    want = np.concatenate([sa * n + sb, sb * n + sa])
    d.sort()
    return bool((np.searchsorted(d, want, side="right") - np.searchsorted(d, want, side="left") == 1).all())
