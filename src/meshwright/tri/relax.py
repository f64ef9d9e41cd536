r"""Mesh relaxation: valence-driven diagonal swaps alternated with guarded smoothing.

Source: D. A. Field and W. H. Frey, "Mesh relaxation: a new technique for improving
triangulations", Int. J. Numer. Meth. Eng. 31, 1991: a node of a good triangle mesh has
six neighbours (a boundary node, one more than its interior angle holds 60-degree
corners); a diagonal whose swap brings the four nodes of its quadrilateral closer to their
ideal valences is swapped, and Laplacian smoothing then evens the shapes the swaps leave.
Gmsh smooths its 2-D meshes once by default (``Mesh.Smoothing = 1``) for the same reason.

Why: where the size grades, or two fronts meet, a frontal method leaves nodes of five and
seven neighbours side by side.  Smoothing alone cannot mend that (it moves nodes, not
edges: on ``benchmarks/grading2d.py``'s domains frontal Delaunay's mean radius ratio
stops at 0.965-0.967 however many passes run, and the triangulation stays Delaunay, so
Delaunay swaps do nothing either); the valence swaps change the connectivity first.

The swap, with t = (c, x, y) and u = (d, y, x) counter-clockwise::

          y                 y
         /|\               / \
        / | \             / u'\
       c t|u d    -->    c-----d
        \ | /             \ t'/
         \|/               \ /
          x                 x

t' = (c, x, d) reuses t's slot and u' = (c, d, y) u's; each keeps its region, and an edge
on a line (boundary or interior segment) or between two regions is never swapped (its
neighbour entry is -1 in ``nbr``).

A swap is made when both new triangles are strictly counter-clockwise (exact
``orient2d``: the quadrilateral is strictly convex) and either the valence defect
``sum |deg - ideal|`` of the four nodes drops and the pair's worst radius ratio stays above
``KEEP`` times what it was, or the defect stays and the worst radius ratio rises (the
max-min swap).  Each swap lowers the defect or, at equal defect, raises a pair's worst
ratio, and ``max_passes`` caps the passes all the same.

Array layout: points (n, 2) float64; tri (m, 3) int32 counter-clockwise, rewritten in
place; nbr (m, 3) int32, ``nbr[t, k]`` the triangle across the edge opposite corner k, -1
where none or locked, rewritten with it; ideal (n,) int32 valences.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.errors import InputError
from meshwright.core.predicates import orient2d
from meshwright.core.validate_input import as_cells, as_exact_points, as_node_indices, check_count
from meshwright.tri.smoothing import incident_rows, incident_triangles, smooth_nodes

__all__ = ["relax", "relax_mesh", "KEEP", "ROUGH", "ROUNDS", "SWAP_PASSES", "SMOOTH_PASSES"]

KEEP = 0.5  # a valence swap may lower its pair's worst radius ratio to this fraction
SWAP_PASSES = 8  # passes of swapping per round at most
SMOOTH_PASSES = 3  # guarded smoothing passes after each round's swaps
ROUNDS = 2  # rounds of swaps + smoothing
ROUGH = 0.98  # triangles under this radius ratio have their nodes smoothed, as swapped ones do


@njit(inline="always")
def _ratio(ax, ay, bx, by, cx, cy):
    """2r/R of a triangle (1 equilateral, 0 flat or clockwise); geometric, not topological.

    :func:`meshwright.tri.smoothing._radius_ratio`'s formula with ``sqrt`` for ``hypot``:
    called from the swaps and the rough test, the shared one made the whole relaxed
    frontal-delaunay disk of ``benchmarks/quality2d.py`` 0.255-0.264 -> 0.269-0.271 s CPU
    (same hour); the smoother keeps ``hypot``, whose last bits its front meshes depend on.
    """
    la = np.sqrt((bx - cx) ** 2 + (by - cy) ** 2)
    lb = np.sqrt((cx - ax) ** 2 + (cy - ay) ** 2)
    lc = np.sqrt((ax - bx) ** 2 + (ay - by) ** 2)
    area2 = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    if area2 <= 0.0:
        return 0.0
    return 4.0 * area2 * area2 / ((la + lb + lc) * la * lb * lc)


@njit(cache=True)
def ideal_valence(pts, tri, bnode):
    """Ideal number of neighbours per node, (n,) int32: 6 inside; at a boundary node
    (``bnode`` (n,) bool) one more than the 60-degree corners its interior angle holds, at
    least 2; and the current valence, (n,) int32."""
    n = pts.shape[0]
    angle = np.zeros(n)
    deg = np.zeros(n, dtype=np.int32)
    for t in range(tri.shape[0]):
        for k in range(3):
            o = tri[t, k]
            deg[o] += 1
            if bnode[o]:
                a = tri[t, (k + 1) % 3]
                b = tri[t, (k + 2) % 3]
                ux, uy = pts[a, 0] - pts[o, 0], pts[a, 1] - pts[o, 1]
                vx, vy = pts[b, 0] - pts[o, 0], pts[b, 1] - pts[o, 1]
                angle[o] += np.arctan2(abs(ux * vy - uy * vx), ux * vx + uy * vy)
    ideal = np.full(n, 6, dtype=np.int32)
    for v in range(n):
        if bnode[v]:
            deg[v] += 1  # a fan of k triangles has k + 1 neighbours
            ideal[v] = max(2, int(np.rint(angle[v] / (np.pi / 3.0))) + 1)
    return ideal, deg


@njit(cache=True)
def rough(pts, tri, hit, rows, below):
    """(m,) bool: the triangles ``hit`` (m,) int8 by a swap, and those of ``rows`` (k,)
    int32 under radius ratio ``below`` (only these changed shape since the last look)."""
    out = hit != 0
    for i in range(rows.shape[0]):
        t = rows[i]
        a, b, c = tri[t, 0], tri[t, 1], tri[t, 2]
        if _ratio(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[c, 0], pts[c, 1]) < below:
            out[t] = True
    return out


@njit(cache=True)
def neighbours(tri, off, inc, marker):
    """``nbr`` (m, 3) int32 across each edge (-1: none, or a triangle of another
    ``marker``), from the node -> triangle CSR ``off``/``inc``
    (:func:`meshwright.tri.smoothing.incident_triangles`), and the nodes on an edge with
    no triangle beyond it, (n,) bool.

    Each directed edge x -> z of a triangle is matched at its start x: its twin z -> x
    lies in a triangle of x's star in which z precedes x.  Not
    :func:`meshwright.core.mesh.build_neighbors`: that one validates by sorting every facet
    (63-110 ms on a 289k-triangle disk against 22 ms here, the star CSR being needed anyway)
    and knows no markers.
    """
    m = tri.shape[0]
    n = off.shape[0] - 1
    nbr = np.full((m, 3), -1, dtype=np.int32)
    bnode = np.zeros(n, dtype=np.bool_)
    width = 0
    for x in range(n):
        width = max(width, off[x + 1] - off[x])
    # Per star, the corner before x and the one after it in each triangle, read once (the
    # twin search reads the first width times).
    before = np.empty(width, dtype=np.int64)
    after = np.empty(width, dtype=np.int64)
    slot = np.empty(width, dtype=np.int64)
    for x in range(n):
        lo = off[x]
        d = off[x + 1] - lo
        for j in range(d):
            t = inc[lo + j]
            c = 0
            while tri[t, c] != x:
                c += 1
            before[j] = tri[t, (c + 2) % 3]
            after[j] = tri[t, (c + 1) % 3]
            slot[j] = (c + 2) % 3
        for j in range(d):
            t = inc[lo + j]
            z = after[j]
            found = -1
            for jj in range(d):
                if before[jj] == z:
                    found = inc[lo + jj]
                    break
            if found < 0:
                bnode[x] = True
                bnode[z] = True
            elif marker[found] == marker[t]:
                nbr[t, slot[j]] = found
    return nbr, bnode


@njit(cache=True)
def lock(tri, nbr, off, inc, edges):
    """Set to -1 the entries of ``nbr`` across ``edges`` (k, 2): never swapped."""
    for e in range(edges.shape[0]):
        a, b = edges[e, 0], edges[e, 1]
        for j in range(off[a], off[a + 1]):
            t = inc[j]
            for k in range(3):
                x = tri[t, (k + 1) % 3]
                y = tri[t, (k + 2) % 3]
                if (x == a and y == b) or (x == b and y == a):
                    nbr[t, k] = -1


@njit(inline="always")
def _repoint(nbr, w, old, new):
    """Make triangle w's entry that pointed at ``old`` point at ``new``."""
    if w >= 0:
        for j in range(3):
            if nbr[w, j] == old:
                nbr[w, j] = new


@njit(cache=True)
def valence_swaps(pts, tri, nbr, ideal, deg, hit, first, max_passes, keep):
    """Swap diagonals by the module's rule until a pass swaps nothing or ``max_passes``
    have run; ``deg`` (n,) int32 is kept current and ``hit`` (m,) int8 set to 1 at both
    rows of every swap.  The first pass visits the triangles ``first`` (k,) int32, a later
    one only those a swap of the pass before touched and their neighbours.  Returns the
    number of swaps."""
    m = tri.shape[0]
    todo = np.empty(m, dtype=np.int32)
    ntodo = first.shape[0]
    todo[:ntodo] = first
    mark = np.zeros(m, dtype=np.int32)  # pass number + 1 that queued the triangle
    nxt = np.empty(m, dtype=np.int32)
    swaps = 0
    for it in range(max_passes):
        nn = 0
        for i in range(ntodo):
            t = todo[i]
            if deg[tri[t, 0]] == ideal[tri[t, 0]] and deg[tri[t, 1]] == ideal[tri[t, 1]] and \
                    deg[tri[t, 2]] == ideal[tri[t, 2]]:
                # A swap adds one to c's valence and takes one from x's and y's: with all
                # three at their ideal, the defect rises by 3 and falls by at most 1 at d.
                continue
            for k in range(3):
                u = nbr[t, k]
                if u < 0:  # none or locked
                    continue
                c = tri[t, k]
                x = tri[t, (k + 1) % 3]
                y = tri[t, (k + 2) % 3]
                kk = 0
                while nbr[u, kk] != t:
                    kk += 1
                d = tri[u, kk]
                old = (abs(deg[c] - ideal[c]) + abs(deg[d] - ideal[d]) + abs(deg[x] - ideal[x])
                       + abs(deg[y] - ideal[y]))
                new = (abs(deg[c] + 1 - ideal[c]) + abs(deg[d] + 1 - ideal[d]) + abs(deg[x] - 1 - ideal[x])
                       + abs(deg[y] - 1 - ideal[y]))
                if new > old:
                    continue
                cx, cy, dx, dy = pts[c, 0], pts[c, 1], pts[d, 0], pts[d, 1]
                xx, xy, yx, yy = pts[x, 0], pts[x, 1], pts[y, 0], pts[y, 1]
                q_old = min(_ratio(cx, cy, xx, xy, yx, yy), _ratio(dx, dy, yx, yy, xx, xy))
                q_new = min(_ratio(cx, cy, xx, xy, dx, dy), _ratio(cx, cy, dx, dy, yx, yy))
                if new < old:
                    if q_new <= keep * q_old:
                        continue
                elif q_new <= q_old:
                    continue
                if orient2d(cx, cy, xx, xy, dx, dy) <= 0.0 or orient2d(cx, cy, dx, dy, yx, yy) <= 0.0:
                    continue
                a = nbr[t, (k + 1) % 3]  # across y-c
                b = nbr[t, (k + 2) % 3]  # across c-x
                cc = nbr[u, (kk + 1) % 3]  # across x-d
                dd = nbr[u, (kk + 2) % 3]  # across d-y
                tri[t, 0], tri[t, 1], tri[t, 2] = c, x, d
                nbr[t, 0], nbr[t, 1], nbr[t, 2] = cc, u, b
                tri[u, 0], tri[u, 1], tri[u, 2] = c, d, y
                nbr[u, 0], nbr[u, 1], nbr[u, 2] = dd, a, t
                _repoint(nbr, cc, u, t)
                _repoint(nbr, a, t, u)
                deg[c] += 1
                deg[d] += 1
                deg[x] -= 1
                deg[y] -= 1
                hit[t] = 1
                hit[u] = 1
                swaps += 1
                for w in (t, u, a, b, cc, dd):
                    if w >= 0 and mark[w] != it + 1:
                        mark[w] = it + 1
                        nxt[nn] = w
                        nn += 1
                break  # t changed: its other edges wait for the next pass
        if nn == 0:
            break
        todo, nxt = nxt, todo
        ntodo = nn
    return swaps


def relax(
    points: np.ndarray,
    triangles: np.ndarray,
    locked_edges: np.ndarray | None = None,
    *,
    markers: np.ndarray | None = None,
    fixed: np.ndarray | None = None,
    rounds: int = ROUNDS,
) -> tuple[np.ndarray, np.ndarray]:
    """Relax a triangle mesh: valence swaps, then guarded smoothing, ``rounds`` times.

    Parameters
    ----------
    points : (n, 2) float64
        Node coordinates (not modified).
    triangles : (m, 3) int32
        Counter-clockwise triangles (not modified), conforming (each edge shared by at most
        two triangles, in opposite directions).
    locked_edges : (k, 2) int, optional
        Edges never swapped: interior segments (the boundary never is).
    markers : (m,) int, optional
        Region of each triangle: an edge between two regions is never swapped.
    fixed : (k,) int or (n,) bool, optional
        Nodes that never move.  Boundary nodes and the ends of locked edges never move
        either (the relaxation keeps every line exactly as given).
    rounds : int
        Rounds of swaps and smoothing (0: the mesh as given).

    Returns
    -------
    points : (n, 2) float64
        Relaxed coordinates.
    triangles : (m, 3) int32
        The swapped connectivity, counter-clockwise; row t keeps row t's region (a swap
        rewrites two triangles of one region in their own rows).

    Raises
    ------
    InputError
        Points or connectivity malformed (:mod:`meshwright.core.validate_input`), markers
        not one integer per triangle, ``rounds`` not a non-negative int.
    """
    xy = as_exact_points(points, "points", copy=True)
    n = len(xy)
    tri = np.array(as_cells(triangles, "triangles", 3, n), dtype=np.int32, order="C")
    locked = np.zeros((0, 2), dtype=np.int32) if locked_edges is None else as_cells(locked_edges, "locked_edges", 2, n)
    if markers is None:
        marker = np.zeros(len(tri), dtype=np.int32)
    else:
        marker = np.asarray(markers)
        if marker.shape != (len(tri),) or not np.issubdtype(marker.dtype, np.integer):
            raise InputError(f"markers must be one integer per triangle, shape ({len(tri)},), got "
                             f"{marker.dtype} {marker.shape}")
        marker = marker.astype(np.int64)
    hold = np.zeros(n, dtype=bool)
    hold[as_node_indices(fixed, n)] = True
    rounds = check_count(rounds, "rounds")
    if not len(tri) or not rounds:
        return xy, tri
    off, inc = incident_triangles(tri, n)
    nbr, bnode = neighbours(tri, off, inc, marker)
    lock(tri, nbr, off, inc, np.ascontiguousarray(locked, dtype=np.int64))
    hold |= bnode
    hold[locked.ravel()] = True
    first = np.arange(len(tri), dtype=np.int32)
    for _ in range(rounds):
        ideal, deg = ideal_valence(xy, tri, bnode)
        hit = np.zeros(len(tri), dtype=np.int8)
        if not valence_swaps(xy, tri, nbr, ideal, deg, hit, first, SWAP_PASSES, KEEP):
            break
        # Only the triangles around moved nodes changed shape: the next round starts there.
        first = _smooth_near(xy, tri, rough(xy, tri, hit, first, ROUGH), hold)
    return xy, tri


def _smooth_near(xy, tri, rough, hold) -> np.ndarray:
    """Guarded smoothing (:func:`meshwright.tri.smoothing.smooth_nodes`) of the free nodes
    of the ``rough`` (m,) bool triangles; the other nodes hold.  A mesh that is good almost
    everywhere (a uniform disk: a few hundred swaps among 289k triangles) pays for what
    changed, not for a pass over every node.  ``xy`` is updated in place; returns the rows of
    the triangles with a free corner, (k,) int32 ascending."""
    free = _free_nodes(tri, rough, hold)
    rows = _rows_touching(tri, free)
    if len(rows):
        off, inc = incident_rows(tri, rows, len(xy))
        smooth_nodes(xy, tri, off, inc, free, SMOOTH_PASSES)
    return rows


@njit(cache=True)
def _free_nodes(tri, rough, hold):
    """(n,) bool: the corners of the ``rough`` (m,) bool triangles not in ``hold`` (n,) bool."""
    free = np.zeros(hold.shape[0], dtype=np.bool_)
    for t in range(tri.shape[0]):
        if rough[t]:
            for k in range(3):
                free[tri[t, k]] = True
    for v in range(hold.shape[0]):
        if hold[v]:
            free[v] = False
    return free


@njit(cache=True)
def _rows_touching(tri, free):
    """The triangles with a corner in ``free`` (n,) bool, (k,) int32 ascending."""
    out = np.empty(tri.shape[0], dtype=np.int32)
    k = 0
    for t in range(tri.shape[0]):
        if free[tri[t, 0]] or free[tri[t, 1]] or free[tri[t, 2]]:
            out[k] = t
            k += 1
    return out[:k].copy()


def relax_mesh(mesh, fixed: np.ndarray | None = None, rounds: int = ROUNDS):
    """:func:`relax` of a :class:`~meshwright.core.mesh.Mesh`'s triangles: its ``line``
    cells locked, its triangle markers (``cell_data["marker"]``) kept apart, ``fixed``
    nodes held.  Every per-triangle cell datum stays valid (a swap keeps its two rows'
    region).  Returns a new Mesh with the same cells otherwise."""
    from meshwright.core.mesh import Mesh

    tri = mesh.cells["triangle"]
    marker = mesh.cell_data.get("marker", {}).get("triangle")
    xy, tri = relax(mesh.points, tri, mesh.cells.get("line"), markers=marker, fixed=fixed, rounds=rounds)
    cells = dict(mesh.cells)
    cells["triangle"] = tri
    return Mesh(xy, cells, point_data=mesh.point_data, cell_data=mesh.cell_data)
