"""Spring-analogy (Laplacian) mesh smoothing with sliding boundary nodes.

Source: chapter 18.2 "Mesh Smoothing" (Spradley 1999; the C++ listing of Figure 18.2.5).
Each edge is a spring; the force on node i is

    f_i = c * sum_{j in N(i)} (x_j - x_i)

and an explicit time step moves it by ``dx_i = dt / ns_i * f_i`` where ``ns_i = |N(i)|``.
With ``relax = c * dt`` a pass moves every free node a fraction ``relax`` of the way to the
centroid of its neighbours (``relax = 1`` is the classic Laplacian smoother).  5-10 passes
are usually enough, as the chapter says.

Safeguards (what users of Triangle/Gmsh expect of a smoother, beyond the chapter):

* A move is accepted only if every incident triangle stays strictly counter-clockwise
  (exact ``orient2d``) and the worst radius ratio among them does not decrease; otherwise the
  step is halved, up to ``MAX_HALVINGS`` times, and then skipped.  So smoothing can never
  invert an element or worsen the worst element around a node.
* Boundary nodes "slide along the boundaries but do not leave them": the displacement is
  projected onto the boundary tangent (from the two neighbouring boundary nodes) and the
  result is snapped back onto the true curve by a caller-supplied projection.  Corner nodes
  (``fixed``) never move.

Array layout
------------
points    : (n, 2) float64, modified copy returned
triangles : (m, 3) int32 counter-clockwise
adjacency : CSR ``(offsets (n+1,) int64, indices int32)``: node neighbours, and node -> incident
            triangles, built once by :func:`node_adjacency`.

Invariants: node count and connectivity never change; every accepted move keeps all incident
triangles positively oriented.
"""

from __future__ import annotations

import numbers
from typing import Callable

import numpy as np
from numba import njit

from meshwright.core.errors import InputError
from meshwright.core.predicates import orient2d
from meshwright.core.topology import boundary_edges_of
from meshwright.core.validate_input import as_cells, as_exact_points, as_node_indices, check_count

__all__ = ["smooth", "node_adjacency", "incident_rows", "incident_triangles"]

MAX_HALVINGS = 4


def node_adjacency(triangles: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Return node-to-node and node-to-triangle adjacency in CSR form.

    Parameters
    ----------
    triangles : (m, 3) int32
    n : int
        Number of nodes.

    Returns
    -------
    nbr_offsets : (n + 1,) int64
    nbr_indices : (k,) int32
        Distinct neighbours of node i are ``nbr_indices[nbr_offsets[i]:nbr_offsets[i+1]]``.
    tri_offsets : (n + 1,) int64
    tri_indices : (3m,) int32
        Triangles incident to node i.
    """
    tri = np.ascontiguousarray(triangles, dtype=np.int64)
    tri_offsets, tri_indices = incident_triangles(tri, n)
    nbr_offsets, nbr_indices = _star_neighbours(tri, tri_offsets, tri_indices, np.ones(n, dtype=np.bool_))
    return nbr_offsets, nbr_indices, tri_offsets, tri_indices


@njit(cache=True)
def incident_rows(tri, rows, n):
    """Node -> triangle CSR of the triangles ``rows`` (k,) int32 ascending of ``tri``
    (m, 3) int, n nodes: offsets (n + 1,) int64 and triangle ids (3k,) int32, each node's
    ascending; complete for a node all of whose triangles are listed.  A counting sort (a
    stable argsort of the corners gave the same, 0.09 s of a 289k-triangle mesh's
    set-up); reads k rows, not m (relaxation's rounds list a few thousand)."""
    offsets = np.zeros(n + 1, dtype=np.int64)
    for i in range(rows.shape[0]):
        t = rows[i]
        for k in range(3):
            offsets[tri[t, k] + 1] += 1
    for v in range(n):
        offsets[v + 1] += offsets[v]
    fill = offsets[:-1].copy()
    out = np.empty(3 * rows.shape[0], dtype=np.int32)
    for i in range(rows.shape[0]):
        t = rows[i]
        for k in range(3):
            v = tri[t, k]
            out[fill[v]] = t
            fill[v] += 1
    return offsets, out


@njit(cache=True)
def incident_triangles(tri, n):
    """:func:`incident_rows` of every triangle of ``tri`` (m, 3) int."""
    return incident_rows(tri, np.arange(tri.shape[0], dtype=np.int32), n)


@njit(cache=True)
def _star_neighbours(tri, tri_offsets, tri_indices, want):
    """Distinct neighbours of every node with ``want`` (n,) bool, ascending, from its
    triangle star (CSR; the other nodes' runs are empty).

    One pass over the stars with a stamp array: linear, where deduplicating the 6m directed
    edges by ``np.unique`` sorted them (0.45 s of a 40k-quad pairing's 1.5 s).  Ascending
    order per node, as that sort gave, so sums over neighbours keep their order.
    """
    n = want.shape[0]
    stamp = np.full(n, -1, dtype=np.int64)
    offsets = np.zeros(n + 1, dtype=np.int64)
    out = np.empty(2 * tri_indices.shape[0], dtype=np.int32)
    k = 0
    for v in range(n):
        start = k
        if not want[v]:
            offsets[v + 1] = k
            continue
        for j in range(tri_offsets[v], tri_offsets[v + 1]):
            t = tri_indices[j]
            for c in range(3):
                u = tri[t, c]
                if u != v and stamp[u] != v:
                    stamp[u] = v
                    # Insertion into the sorted run: stars hold about six neighbours.
                    i = k
                    while i > start and out[i - 1] > u:
                        out[i] = out[i - 1]
                        i -= 1
                    out[i] = u
                    k += 1
        offsets[v + 1] = k
    return offsets, out[:k].copy()


@njit(cache=True)
def _radius_ratio(ax, ay, bx, by, cx, cy):
    """2r/R of a triangle (1 for equilateral, 0 for degenerate); geometric, not topological."""
    la = np.hypot(bx - cx, by - cy)
    lb = np.hypot(cx - ax, cy - ay)
    lc = np.hypot(ax - bx, ay - by)
    area2 = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    if area2 <= 0.0:
        return 0.0
    s = la + lb + lc
    # r = area / s_half, R = la lb lc / (4 area)  =>  2r/R = 8 area^2 / (s_half la lb lc)
    return 4.0 * area2 * area2 / (s * la * lb * lc)


# The guard's float filter: _radius_ratio with sqrt for hypot (a third of the price) is
# within a few units in the last place of it wherever every squared edge is a normal float
# well inside the range and the ratio is not tiny; FILTER is far above that error, so a
# ratio more than FILTER (relative) from the bound decides the comparison as hypot's would.
FILTER = 1e-12
UNSURE = -2.0  # the filter's ratio: outside its safe range, ask _radius_ratio
_TINY = 1e-200  # ratios under this are left to _radius_ratio (underflow in the products)
_SAFE_LO = 1e-290  # squared edges outside [_SAFE_LO, _SAFE_HI]: sqrt's error is not bounded
_SAFE_HI = 1e290


@njit(inline="always")
def _filter_ratio(ax, ay, bx, by, cx, cy):
    """:func:`_radius_ratio` by sqrt, or :data:`UNSURE` where the filter's bound may not hold
    (0.0 where area2 <= 0, as there)."""
    a2 = (bx - cx) ** 2 + (by - cy) ** 2
    b2 = (cx - ax) ** 2 + (cy - ay) ** 2
    c2 = (ax - bx) ** 2 + (ay - by) ** 2
    if min(a2, b2, c2) < _SAFE_LO or max(a2, b2, c2) > _SAFE_HI:
        return UNSURE
    area2 = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    if area2 <= 0.0:
        return 0.0
    la = np.sqrt(a2)
    lb = np.sqrt(b2)
    lc = np.sqrt(c2)
    r = 4.0 * area2 * area2 / ((la + lb + lc) * la * lb * lc)
    if r < _TINY:
        return UNSURE
    return r


@njit(cache=True)
def _worst_around(xy, tris, tri_offsets, tri_indices, i, px, py):
    """Worst radius ratio of the triangles around node ``i`` if it sat at (px, py).

    Returns -1.0 if any incident triangle would not be strictly counter-clockwise.  Corners
    are read as scalars: a per-triangle scratch array was a heap allocation per visit, most
    of a pass's time.
    """
    worst = 1.0
    for s in range(tri_offsets[i], tri_offsets[i + 1]):
        t = tri_indices[s]
        u, v, w = tris[t, 0], tris[t, 1], tris[t, 2]
        ax, ay, bx, by, cx, cy = xy[u, 0], xy[u, 1], xy[v, 0], xy[v, 1], xy[w, 0], xy[w, 1]
        if u == i:
            ax, ay = px, py
        elif v == i:
            bx, by = px, py
        else:
            cx, cy = px, py
        if orient2d(ax, ay, bx, by, cx, cy) <= 0.0:
            return -1.0
        q = _radius_ratio(ax, ay, bx, by, cx, cy)
        if q < worst:
            worst = q
    return worst


@njit(cache=True)
def _spring_step(xy, nbr_offsets, nbr_indices, i, relax):
    """Displacement ``dt/ns_i * f_i`` of node i under the spring forces of its neighbours."""
    ns = nbr_offsets[i + 1] - nbr_offsets[i]
    fx = 0.0
    fy = 0.0
    for s in range(nbr_offsets[i], nbr_offsets[i + 1]):
        j = nbr_indices[s]
        fx += xy[j, 0] - xy[i, 0]
        fy += xy[j, 1] - xy[i, 1]
    return relax * fx / max(ns, 1), relax * fy / max(ns, 1)


@njit(cache=True)
def _smooth_interior(xy, tris, nbr_offsets, nbr_indices, tri_offsets, tri_indices, kind, relax, q, known, hint):
    """One Gauss-Seidel pass over the free interior nodes; returns how many moved.

    The decisions are :func:`_worst_around`'s, before and after, bit for bit: a move is taken
    exactly when every triangle of the star stays strictly counter-clockwise (exact) with a
    radius ratio (:func:`_radius_ratio`, hypot) positive and not below the star's worst
    before.  Cheaper: ``q`` (m,) float64 caches each triangle's filter ratio
    (:func:`_filter_ratio`; -1.0 not strictly counter-clockwise) at the current coordinates,
    valid where ``known`` (m,) bool, so a node's worst before is read, not recomputed; a trial
    compares filter ratios and asks hypot's only when the two sides are within
    :data:`FILTER` (then for the star's worst before, too); it stops at its first refusing
    triangle, and ``hint`` (n,) int64 (kept across passes) names the slot of a node's star
    that refused last, asked first next time (a move is taken only when every triangle
    agrees, so the order decides nothing); an accepted trial writes its values back.  A star
    with an unsure ratio takes :func:`_worst_around`'s way for the visit.
    """
    width = 0
    for i in range(xy.shape[0]):
        width = max(width, tri_offsets[i + 1] - tri_offsets[i])
    trial = np.empty(width)
    moved = 0
    for i in range(xy.shape[0]):
        if kind[i] != 0 or nbr_offsets[i + 1] == nbr_offsets[i]:
            continue
        ns = nbr_offsets[i + 1] - nbr_offsets[i]
        fx = 0.0
        fy = 0.0
        x0 = xy[i, 0]
        y0 = xy[i, 1]
        for s in range(nbr_offsets[i], nbr_offsets[i + 1]):
            j = nbr_indices[s]
            fx += xy[j, 0] - x0
            fy += xy[j, 1] - y0
        dx = relax * fx / max(ns, 1)
        dy = relax * fy / max(ns, 1)
        before = 1.0
        for s in range(tri_offsets[i], tri_offsets[i + 1]):
            t = tri_indices[s]
            if not known[t]:
                u, v, w = tris[t, 0], tris[t, 1], tris[t, 2]
                ax, ay, bx, by, cx, cy = xy[u, 0], xy[u, 1], xy[v, 0], xy[v, 1], xy[w, 0], xy[w, 1]
                if orient2d(ax, ay, bx, by, cx, cy) <= 0.0:
                    q[t] = -1.0
                else:
                    q[t] = _filter_ratio(ax, ay, bx, by, cx, cy)
                known[t] = True
            if q[t] < before:
                before = q[t]
        if before == UNSURE or 0.0 < before < _TINY:
            # Outside the filter's range: hypot's ratios for the whole visit.
            exact = _worst_around(xy, tris, tri_offsets, tri_indices, i, x0, y0)
            for _ in range(MAX_HALVINGS + 1):
                after = _worst_around(xy, tris, tri_offsets, tri_indices, i, x0 + dx, y0 + dy)
                if after >= exact and after > 0.0:
                    xy[i, 0] = x0 + dx
                    xy[i, 1] = y0 + dy
                    for s in range(tri_offsets[i], tri_offsets[i + 1]):
                        known[tri_indices[s]] = False
                    moved += 1
                    break
                dx *= 0.5
                dy *= 0.5
            continue
        exact = 2.0  # hypot's worst before, computed at the first close call
        lo = before * (1.0 - FILTER)
        hi = before * (1.0 + FILTER)
        lo_s = tri_offsets[i]
        d = tri_offsets[i + 1] - lo_s
        start = hint[i]  # a triangle that refused once often refuses again
        if start >= d:
            start = 0
        for _ in range(MAX_HALVINGS + 1):
            px = x0 + dx
            py = y0 + dy
            ok = True
            for jj in range(d):
                k = jj + start
                if k >= d:
                    k -= d
                t = tri_indices[lo_s + k]
                u, v, w = tris[t, 0], tris[t, 1], tris[t, 2]
                ax, ay, bx, by, cx, cy = xy[u, 0], xy[u, 1], xy[v, 0], xy[v, 1], xy[w, 0], xy[w, 1]
                if u == i:
                    ax, ay = px, py
                elif v == i:
                    bx, by = px, py
                else:
                    cx, cy = px, py
                if orient2d(ax, ay, bx, by, cx, cy) <= 0.0:
                    ok = False
                    start = k
                    break
                r = _filter_ratio(ax, ay, bx, by, cx, cy)
                if r == 0.0 or (before > 0.0 and r < lo):
                    ok = False  # hypot's ratio is 0.0 too, or below the bound
                    start = k
                    break
                if r == UNSURE or (before > 0.0 and r <= hi):
                    if exact == 2.0:
                        exact = _worst_around(xy, tris, tri_offsets, tri_indices, i, x0, y0)
                    rh = _radius_ratio(ax, ay, bx, by, cx, cy)
                    if rh < exact or rh <= 0.0:
                        ok = False
                        start = k
                        break
                trial[k] = r
            hint[i] = start
            if ok:
                xy[i, 0] = px
                xy[i, 1] = py
                k = 0
                for s in range(tri_offsets[i], tri_offsets[i + 1]):
                    t = tri_indices[s]
                    q[t] = trial[k]
                    known[t] = True
                    k += 1
                moved += 1
                break
            dx *= 0.5
            dy *= 0.5
    return moved


@njit(cache=True)
def _sliding_steps(xy, nbr_offsets, nbr_indices, nodes, tangent, relax):
    """Spring displacements of sliding nodes projected onto their boundary tangents, (k, 2)."""
    out = np.empty((nodes.shape[0], 2))
    for s in range(nodes.shape[0]):
        i = nodes[s]
        dx, dy = _spring_step(xy, nbr_offsets, nbr_indices, i, relax)
        d = dx * tangent[i, 0] + dy * tangent[i, 1]
        out[s, 0] = d * tangent[i, 0]
        out[s, 1] = d * tangent[i, 1]
    return out


@njit(cache=True)
def _try_moves(xy, nodes, targets, tris, tri_offsets, tri_indices, known):
    """Move each node to its target if validity holds and its worst element does not get worse.

    Returns a boolean mask of the accepted moves; the moved nodes' triangles are marked not
    ``known`` in :func:`_smooth_interior`'s cache.
    """
    ok = np.zeros(nodes.shape[0], dtype=np.bool_)
    for s in range(nodes.shape[0]):
        i = nodes[s]
        before = _worst_around(xy, tris, tri_offsets, tri_indices, i, xy[i, 0], xy[i, 1])
        after = _worst_around(xy, tris, tri_offsets, tri_indices, i, targets[s, 0], targets[s, 1])
        if after > 0.0 and after >= before:
            xy[i, 0] = targets[s, 0]
            xy[i, 1] = targets[s, 1]
            ok[s] = True
            for j in range(tri_offsets[i], tri_offsets[i + 1]):
                known[tri_indices[j]] = False
    return ok


def _boundary_neighbours(boundary_edges: np.ndarray, n: int) -> np.ndarray:
    """(n, 2) int64: the two boundary neighbours of every node on exactly two boundary edges, else -1."""
    e = np.asarray(boundary_edges, dtype=np.int64)
    owner = np.concatenate([e[:, 0], e[:, 1]])
    other = np.concatenate([e[:, 1], e[:, 0]])
    order = np.argsort(owner, kind="stable")
    owner, other = owner[order], other[order]
    degree = np.bincount(owner, minlength=n)
    start = np.concatenate([[0], np.cumsum(degree)[:-1]])
    out = np.full((n, 2), -1, dtype=np.int64)
    two = np.flatnonzero(degree == 2)
    out[two, 0] = other[start[two]]
    out[two, 1] = other[start[two] + 1]
    return out


@njit(cache=True)
def _fix_corners(xy, bnbr, kind):
    """Fix sliding nodes whose two boundary neighbours are not exactly collinear with them."""
    for i in range(xy.shape[0]):
        if kind[i] != 1:
            continue
        u = bnbr[i, 0]
        v = bnbr[i, 1]
        if orient2d(xy[u, 0], xy[u, 1], xy[i, 0], xy[i, 1], xy[v, 0], xy[v, 1]) != 0.0:
            kind[i] = 2


def _boundary_tangents(points: np.ndarray, bnbr: np.ndarray, on_boundary: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit tangents at boundary nodes: the chord between their two boundary neighbours.

    Returns ``(kind, tangent)``: kind 1 (sliding) for nodes with exactly two boundary
    neighbours, 2 (fixed) for other boundary nodes (chain ends, junctions), 0 elsewhere.
    The chord is independent of the edges' directions.
    """
    n = len(points)
    kind = np.zeros(n, dtype=np.int8)
    tangent = np.zeros((n, 2))
    kind[on_boundary] = 2
    two = np.flatnonzero(bnbr[:, 0] >= 0)
    chord = points[bnbr[two, 1]] - points[bnbr[two, 0]]
    norm = np.hypot(chord[:, 0], chord[:, 1])
    ok = norm > 0.0
    kind[two[ok]] = 1
    tangent[two[ok]] = chord[ok] / norm[ok][:, None]
    return kind, tangent


def smooth(
    points: np.ndarray,
    triangles: np.ndarray,
    boundary_edges: np.ndarray | None = None,
    *,
    passes: int = 10,
    relax: float = 1.0,
    fixed: np.ndarray | None = None,
    project: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None,
) -> np.ndarray:
    """Smooth a triangle mesh with the chapter's spring-analogy Laplacian.

    Parameters
    ----------
    points : (n, 2) float64
        Node coordinates (not modified; a smoothed copy is returned).
    triangles : (m, 3) int32
        Counter-clockwise triangles.
    boundary_edges : (b, 2) int32, optional
        Edges on the domain boundary (and interior constraints).  Their nodes slide along
        the boundary; nodes where the boundary turns a corner should be listed in ``fixed``.
        Default: the edges used by exactly one triangle.
    passes : int
        Number of smoothing passes (time steps), 5-10 suffice.
    relax : float
        ``c * dt`` of the spring analogy, in (0, 1]; 1 moves a node to its neighbours' centroid.
    fixed : (k,) int or (n,) bool, optional
        Nodes that never move (corners, user points).
    project : callable, optional
        ``project(nodes (k,) int64, xy (k, 2) float64) -> (k, 2) float64`` putting boundary
        nodes back onto their true curve after each pass.  Without it, sliding nodes move
        only along straight boundary stretches (nodes whose two boundary edges are not
        collinear are fixed), so they never leave a polygonal boundary.

    Returns
    -------
    (n, 2) float64
        Smoothed coordinates.  Connectivity is unchanged; no triangle is inverted and the
        worst radius ratio around every node is never decreased by a move.

    Raises
    ------
    InputError
        Points not (n, 2), NaN/infinite or outside the predicates' exact range
        (:mod:`meshwright.core.validate_input`); connectivity (``triangles``,
        ``boundary_edges``, ``fixed``) not integer or referring to a node outside
        ``[0, n)`` (the row is named); ``passes`` not a non-negative int; ``relax`` outside
        (0, 1]; ``project`` not callable.
    """
    xy = as_exact_points(points, "points", copy=True)
    n = len(xy)
    tris = as_cells(triangles, "triangles", 3, n)
    passes = check_count(passes, "passes")
    if isinstance(relax, bool) or not isinstance(relax, numbers.Real) or not 0.0 < float(relax) <= 1.0:
        raise InputError(f"relax = c*dt must be a number in (0, 1], got {relax!r}")
    relax = float(relax)
    if project is not None and not callable(project):
        raise InputError(f"project must be callable project(nodes, xy) -> xy, got {type(project).__name__}")
    fixed_nodes = as_node_indices(fixed, n)
    if boundary_edges is None:
        boundary_edges = boundary_edges_of(tris)
    boundary_edges = as_cells(boundary_edges, "boundary_edges", 2, n)
    bnbr = _boundary_neighbours(boundary_edges, n)
    on_boundary = np.zeros(n, dtype=bool)
    on_boundary[boundary_edges.ravel()] = True
    kind, tangent = _boundary_tangents(xy, bnbr, on_boundary)
    if project is None:
        # Without the true curve, only nodes on straight stretches may slide.
        _fix_corners(xy, bnbr, kind)
    kind[fixed_nodes] = 2
    nbr_offsets, nbr_indices, tri_offsets, tri_indices = node_adjacency(tris, n)
    sliding = np.flatnonzero(kind == 1).astype(np.int64)
    if project is None:
        def project(nodes, xy_new):
            return xy_new

    q = np.empty(len(tris))
    known = np.zeros(len(tris), dtype=bool)
    hint = np.zeros(len(xy), dtype=np.int64)
    for _ in range(passes):
        moved = _smooth_interior(xy, tris, nbr_offsets, nbr_indices, tri_offsets, tri_indices, kind, relax, q, known, hint)
        if len(sliding):
            # Sliding nodes only ever jump to projected (on-curve) positions; a refused
            # move is retried at half the step and finally skipped, so none leaves its curve.
            steps = _sliding_steps(xy, nbr_offsets, nbr_indices, sliding, tangent, relax)
            pending = np.arange(len(sliding))
            for _ in range(MAX_HALVINGS + 1):
                nodes = sliding[pending]
                targets = np.ascontiguousarray(project(nodes, xy[nodes] + steps[pending]), dtype=np.float64)
                accepted = _try_moves(xy, nodes, targets, tris, tri_offsets, tri_indices, known)
                moved += int(accepted.sum())
                pending = pending[~accepted]
                if len(pending) == 0:
                    break
                steps[pending] *= 0.5
            tangent = _boundary_tangents(xy, bnbr, on_boundary)[1]
        if moved == 0:
            break
    return xy


def smooth_nodes(xy: np.ndarray, tris: np.ndarray, tri_offsets: np.ndarray, tri_indices: np.ndarray,
                 free: np.ndarray, passes: int) -> None:
    """Guarded smoothing (:func:`smooth`'s interior passes, ``relax`` 1) of the ``free``
    (n,) bool nodes of a mesh, all others fixed, in place; for callers that checked their
    arrays (:func:`meshwright.tri.relax.relax`).

    The same moves as :func:`smooth` of the sub-mesh of the free nodes' stars, renumbered in
    ascending order, with no boundary edges and every other node fixed: a free node's star
    and its neighbours (ascending) are the same there, and so is the order of the visits.
    Without the sub-mesh's extraction, unique and checks, which were most of a relaxation
    round's set-up.

    Parameters
    ----------
    xy : (n, 2) float64
        Coordinates, moved in place.
    tris : (m, 3) int32
        Counter-clockwise triangles.
    tri_offsets, tri_indices : (n + 1,) int64, (k,) int32
        Node -> triangle CSR of ``tris`` (:func:`incident_triangles`), each node's
        ascending; complete for every free node (the others' runs are not read).
    free : (n,) bool
        Nodes that may move.
    passes : int
        Passes at most (fewer when one moves nothing).
    """
    nbr_offsets, nbr_indices = _star_neighbours(tris, tri_offsets, tri_indices, free)
    kind = np.where(free, 0, 2).astype(np.int8)
    q = np.empty(len(tris))
    known = np.zeros(len(tris), dtype=bool)
    hint = np.zeros(len(xy), dtype=np.int64)
    for _ in range(passes):
        if not _smooth_interior(xy, tris, nbr_offsets, nbr_indices, tri_offsets, tri_indices, kind, 1.0, q, known, hint):
            break
