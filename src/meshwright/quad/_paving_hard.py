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

from meshwright.core.predicates import orient2d

__all__ = ["face_cycles", "pieces_two_sided", "attached_pieces"]


def attached_pieces(loops, sa: np.ndarray, sb: np.ndarray) -> np.ndarray:
    """(m,) bool: segment pieces whose connected component (through shared nodes) has a
    node on a loop."""
    m = len(sa)
    if not m:
        return np.zeros(0, dtype=bool)
    nodes, inv = np.unique(np.concatenate([sa, sb]), return_inverse=True)
    parent = np.arange(len(nodes))

    def root(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for a, b in zip(inv[:m].tolist(), inv[m:].tolist()):
        ra, rb = root(a), root(b)
        if ra != rb:
            parent[max(ra, rb)] = min(ra, rb)
    comp = np.array([root(a) for a in range(len(nodes))])
    on_loop = np.isin(nodes, np.concatenate(loops))
    hit = np.zeros(len(nodes), dtype=bool)
    hit[comp[on_loop]] = True
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


def face_cycles(xy, loops, sa: np.ndarray, sb: np.ndarray):
    """The paving boundaries of ``loops`` with the segment pieces ``sa``, ``sb`` run on
    both sides (module docstring).

    Returns
    -------
    cycles : list of (k,) int64
        Loops that meet no piece come first, unchanged and in order; then the face
        cycles of the others.
    source : list of int
        The loop each cycle starts on (-1 for a cycle of segment pieces only).
    """
    loop_nodes = [set(f.tolist()) for f in loops]
    touched = [i for i, s in enumerate(loop_nodes) if s.intersection(sa.tolist()) or s.intersection(sb.tolist())]
    cycles = [f for i, f in enumerate(loops) if i not in touched]
    source = [i for i in range(len(loops)) if i not in touched]
    heads, tails = [], []
    for i in touched:
        f = loops[i].tolist()
        heads += f
        tails += f[1:] + f[:1]
    n_loop = len(heads)
    heads += sa.tolist() + sb.tolist()
    tails += sb.tolist() + sa.tolist()
    out: dict[int, list[int]] = {}
    for h, a in enumerate(heads):
        out.setdefault(a, []).append(h)
    key = {(a, b): h for h, (a, b) in enumerate(zip(heads, tails))}
    seen = np.zeros(len(heads), dtype=bool)
    for start in range(len(heads)):
        if seen[start]:
            continue
        cyc, h = [], start
        for _ in range(len(heads)):
            seen[h] = True
            u, v = heads[h], tails[h]
            cyc.append(u)
            w = _first_clockwise(xy, v, u, [tails[g] for g in out[v]])
            h = key[(v, w)]
            if h == start:
                break
        cycles.append(np.asarray(cyc, dtype=np.int64))
        src = -1
        if start < n_loop:
            src = next(i for i in touched if heads[start] in loop_nodes[i])
        source.append(src)
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
