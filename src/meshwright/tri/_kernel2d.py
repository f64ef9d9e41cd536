r"""Flat-array kernel of 2-D incremental Delaunay insertion, shared by Bowyer and Watson.

Both algorithms of the chapter (Watson 1981, section 18.1.1; Bowyer 1981, section 18.1.2)
insert one point at a time: find every triangle whose circumdisk contains the new point
(the *cavity*, Watson's insertion polygon, Bowyer's deleted Voronoi vertices), delete them,
and join the new point to the cavity boundary.  They differ only in the conflict test and in
what is stored per triangle, so this module holds everything else and calls the conflict test
of :mod:`meshwright.tri.bowyer` or of :mod:`meshwright.tri.watson` (with Watson's circle
bookkeeping).  The algorithm is chosen by the per-triangle circle array: an empty ``circ``
runs Bowyer, a sized one runs Watson (a branch on an array length, predicted perfectly).

Flat layout (``cap`` triangle slots, ``ntri = meta[M_NTRI]`` in use)
------------------------------------------------------------------
``pts``  (rows, 2) float64      vertex coordinates; vertex ids are row numbers.
``tri``  (3 cap,) int32         ``tri[3t + k]`` vertex k of triangle t, counter-clockwise.
``nbr``  (3 cap,) int32         ``nbr[3t + k]`` triangle across the edge opposite vertex k,
                                the edge from ``tri[3t + (k+1)%3]`` to ``tri[3t + (k+2)%3]``.
``circ`` (4 cap,) float32       Watson's circumcircles (:mod:`meshwright.tri.watson`);
                                empty for Bowyer.
``rank`` (r,) int32             symbolic-perturbation key of vertex v: ``rank[v]`` for v < r,
                                v itself beyond (empty: the key is the vertex id).
``cons`` (3 cap,) int32         constrained Delaunay only (else empty): per half-edge, the
                                constraint id + 1, 0 on a free edge; kept equal on both
                                sides.  A cavity never crosses a constrained edge.
``meta`` (6,) int64             ``[M_NTRI]`` slots in use, ``[M_LAST]`` a recent triangle,
                                ``[M_RNG]`` xorshift state of the walk, ``[M_SPLIT_*]`` the
                                constrained edge the pending fan splits.
``work`` (5 w,) int32           cavity scratch: w cavity triangles, w BFS parents, w boundary
                                edges of three ints (start vertex, end vertex, outer half-edge).
``vmark`` (>= rows + 1,) int32  per-vertex scratch of the fan; the last entry stands for GHOST.

Superstructure: the symbolic vertex at infinity
----------------------------------------------
The chapter's enclosing superstructure is replaced by its limit, one vertex ``GHOST = -1`` at
infinity.  Every convex-hull edge ``a -> b`` (outside on its left) carries a *ghost triangle*
``(a, b, GHOST)``, always stored with GHOST as vertex 2, so the triangles (finite and ghost)
tile a sphere: every ``nbr`` entry is a valid triangle, no triangle is ever lost on removal
and removing the superstructure is dropping the ghosts.  A point p conflicts with a ghost
``(a, b, GHOST)`` iff ``orient2d(a, b, p) > 0`` (p strictly outside the hull edge) or p lies
strictly inside the segment ab.  With n >= 3 vertices not all collinear there are exactly
``2n - 2`` triangles, ``2n - h - 2`` finite and ``h`` ghosts for h hull vertices (collinear
hull points included), so preallocating ``2n`` slots never overflows.

Insertion of vertex v
---------------------
1. Locate: visibility walk (Devillers, Pion & Teillaud 2002, "Walking in a triangulation",
   Int. J. Found. Comput. Sci. 13(2)) from a recent triangle with exact ``orient2d``,
   remembering the triangle it came from and starting at a pseudo-random edge (stochastic
   walk, so it terminates also in non-Delaunay triangulations).  It stops in a finite
   triangle holding v in its closure (a duplicate vertex is detected there) or in a ghost
   triangle whose hull edge v sees.  Either one conflicts with v.
2. Cavity: breadth-first growth over neighbours that conflict.  The cavity is a triangulated
   disk with every vertex on its boundary, so its dual graph is a tree: skipping the BFS
   parent is enough to visit each cavity triangle once.  A non-conflicting neighbour gives a
   boundary edge.  A disk of m triangles has m + 2 boundary edges; anything else means the
   predicate and the triangulation disagree and is reported (``BROKEN``).
3. Fan: boundary edge ``u -> w`` (counter-clockwise around the cavity) gets the new triangle
   ``(u, w, v)``.  The first m reuse the cavity slots, the last two are appended; the outer
   neighbour's back pointer is redirected, and consecutive fan triangles are linked through
   ``vmark[u]`` = the fan triangle whose boundary edge starts at u::

          w2 ______ w1                 w2 ______ w1
            /\    /\                     \  |  /
           /  \  /  \      cavity         \ | /    fan: (u, w, v) for each
       w3 /____\/____\ w0  ------>   w3 ---- v ---- w0    boundary edge u -> w
          \    /\ v  /                    / | \
           \  /  \  /                    /  |  \
            \/____\/                  w4 ___|___ w5
          w4        w5

   A fan triangle touching GHOST is rotated so that GHOST is vertex 2 again.

Hot-path rules: no allocation and no Python objects inside ``insert_vertex``; arrays that may
be too small make it return ``NEED_SPACE`` *before* anything is modified, and
:func:`make_room` grows them by doubling.  Memory locality: the caller stores the points in
insertion order (BRIO), so vertices that are close in space are close in ``pts``; ``rank``
keeps the perturbation keys of that build valid after the vertices are renumbered.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.flat import GHOST, grown
from meshwright.core.predicates import CCW_ERRBOUND_A, orient2d
from meshwright.tri import bowyer, watson

__all__ = [
    "GHOST",
    "NEED_SPACE",
    "BROKEN",
    "DUP_BASE",
    "M_NTRI",
    "M_LAST",
    "M_RNG",
    "M_SPLIT_A",
    "M_SPLIT_B",
    "M_SPLIT_C",
    "new_meta",
    "new_work",
    "walk",
    "cavity",
    "fan",
    "insert_vertex",
    "split_edge",
    "make_room",
    "insert_batch",
    "locate_points",
]

# insert_vertex status: >= 0 is a new triangle incident to v; otherwise one of these, and a
# status <= DUP_BASE means v coincides with vertex DUP_BASE - status (nothing was changed).
NEED_SPACE = -1
BROKEN = -2
DUP_BASE = -3
# meta slots
M_NTRI = 0
M_LAST = 1
M_RNG = 2
M_SPLIT_A = 3  # the constrained edge a-b (id + 1 in M_SPLIT_C, 0: none) the next fan splits
M_SPLIT_B = 4
M_SPLIT_C = 5
_META_LEN = 6
_WORK_INIT = 64  # initial cavity capacity; doubled on demand


def new_meta(seed: int) -> np.ndarray:
    """Fresh kernel header: no triangles, walk start 0, walk RNG state from ``seed``.

    Returns
    -------
    (6,) int64
    """
    meta = np.zeros(_META_LEN, dtype=np.int64)
    meta[M_RNG] = (int(seed) * 2654435761 + 1) % 0xFFFFFFFF or 1  # xorshift state must not be 0
    return meta


def new_work() -> np.ndarray:
    """Fresh cavity scratch of the initial capacity: (5 w,) int32."""
    return np.empty(5 * _WORK_INIT, dtype=np.int32)


@njit(inline="always")
def _next(k):
    return 0 if k == 2 else k + 1


@njit(inline="always")
def _prev(k):
    return 2 if k == 0 else k - 1


@njit(inline="always")
def _vslot(u, vmark):
    """Scratch index of vertex u; GHOST uses the last entry."""
    return u if u >= 0 else vmark.shape[0] - 1


@njit(inline="always")
def _fan_slot(j, ncav, ntri, work):
    """Triangle slot of fan triangle j: cavity slots first, then two appended slots."""
    return work[j] if j < ncav else ntri + (j - ncav)


@njit(inline="always")
def _fan_shift(u, w):
    """Rotation that keeps GHOST at vertex 2: conceptual vertex k is stored at (k + s) % 3."""
    if w == GHOST:
        return 1
    if u == GHOST:
        return 2
    return 0


@njit(inline="always")
def _orient(ax, ay, bx, by, cx, cy):
    """``orient2d`` with Shewchuk's stage-A filter inlined; the exact predicate only if unsure."""
    left = (ax - cx) * (by - cy)
    right = (ay - cy) * (bx - cx)
    det = left - right
    err = CCW_ERRBOUND_A * (abs(left) + abs(right))
    if det > err or -det > err:
        return det
    return orient2d(ax, ay, bx, by, cx, cy)


@njit(inline="always")
def _conflict(pts, tri, circ, rank, t, v, px, py):
    """Conflict of triangle t with the new point: Watson's filter if circles are kept."""
    if circ.shape[0] > 0:
        return watson.conflict(pts, tri, circ, rank, t, v, px, py)
    return bowyer.conflict(pts, tri, rank, t, v, px, py)


@njit(inline="always")
def walk(pts, tri, nbr, meta, t, px, py):
    """Stochastic visibility walk from triangle t towards the point p.

    Parameters
    ----------
    pts : (rows, 2) float64
    tri, nbr : (3 cap,) int32
    meta : (6,) int64
        Its ``M_RNG`` entry advances.
    t : int
        Start triangle (finite or ghost).
    px, py : float

    Returns
    -------
    int
        A finite triangle whose closure contains p, or a ghost triangle whose hull edge has
        p strictly on its outer side.
    """
    if tri[3 * t + 2] == GHOST:
        t = nbr[3 * t + 2]
    came = -1
    r = meta[M_RNG]
    while True:
        r ^= (r << 13) & 0xFFFFFFFF
        r ^= r >> 17
        r ^= (r << 5) & 0xFFFFFFFF
        k = r % 3
        base = 3 * t
        nxt = -1
        for _ in range(3):
            n = nbr[base + k]
            if n != came:
                a = tri[base + _next(k)]
                b = tri[base + _prev(k)]
                if _orient(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], px, py) < 0.0:
                    nxt = n
                    break
            k = _next(k)
        if nxt < 0:
            break
        came = t
        t = nxt
        if tri[3 * t + 2] == GHOST:
            break
    meta[M_RNG] = r
    return t


@njit(inline="always")
def _short_of_space(pts, tri, nbr, cons, circ, meta, vmark):
    """Whether one more insertion (two more slots) could overflow an array."""
    need = 3 * (meta[M_NTRI] + 2)
    return (
        need > tri.shape[0]
        or need > nbr.shape[0]
        or (cons.shape[0] > 0 and need > cons.shape[0])
        or (circ.shape[0] > 0 and 4 * (meta[M_NTRI] + 2) > circ.shape[0])
        or vmark.shape[0] <= pts.shape[0]
    )


@njit(inline="always")
def _grow_cavity(v, seed0, seed1, pts, tri, nbr, cons, circ, rank, work):
    """Breadth-first cavity from ``seed0`` (and ``seed1`` across the split edge, if >= 0).

    A constrained edge (``cons`` non-zero) is never crossed: it always bounds the cavity, which
    makes the cavity the constrained-Delaunay one.  Returns the number of cavity triangles,
    ``NEED_SPACE`` or ``BROKEN``; ``work`` holds the cavity and its boundary.
    """
    px = pts[v, 0]
    py = pts[v, 1]
    cap = work.shape[0] // 5
    bo = 2 * cap
    constrained = cons.shape[0] > 0
    work[0] = seed0
    work[cap] = seed1
    ncav = 1
    if seed1 >= 0:
        work[1] = seed1
        work[cap + 1] = seed0
        ncav = 2
    nb = 0
    i = 0
    while i < ncav:
        c = work[i]
        parent = work[cap + i]
        i += 1
        base = 3 * c
        for k in range(3):
            n = nbr[base + k]
            if n == parent:
                continue
            if (not (constrained and cons[base + k] != 0)) and _conflict(pts, tri, circ, rank, n, v, px, py):
                if ncav == cap:
                    return NEED_SPACE
                work[ncav] = n
                work[cap + ncav] = c
                ncav += 1
            else:
                if nb == cap:
                    return NEED_SPACE
                n3 = 3 * n
                j = 0 if nbr[n3] == c else (1 if nbr[n3 + 1] == c else 2)
                o = bo + 3 * nb
                work[o] = tri[base + _next(k)]
                work[o + 1] = tri[base + _prev(k)]
                work[o + 2] = n3 + j
                nb += 1
    if nb != ncav + 2:
        return BROKEN
    return ncav


@njit(inline="always")
def _mark_split(h, tri, cons, meta):
    """Remember constrained half-edge h (a -> b) as the one the next fan splits."""
    t3 = h - h % 3
    meta[M_SPLIT_A] = tri[t3 + _next(h % 3)]
    meta[M_SPLIT_B] = tri[t3 + _prev(h % 3)]
    meta[M_SPLIT_C] = cons[h]


@njit(inline="always")
def cavity(v, t0, pts, tri, nbr, cons, circ, rank, meta, work, vmark):
    """Cavity of vertex v (coordinates in ``pts[v]``) from triangle t0, which contains it.

    t0 is a finite triangle whose closure holds v, or a ghost whose hull edge v sees (what
    :func:`walk` returns).  When v lies exactly on a constrained edge of t0, the triangle
    across is seeded too and the edge is split by the following :func:`fan` (the two halves
    keep its constraint); any other constrained edge bounds the cavity.

    Parameters
    ----------
    v, t0 : int
    pts : (rows, 2) float64
    tri, nbr : (3 cap,) int32
    cons : (3 cap,) int32 or (0,)
        Constraint id + 1 per half-edge, 0 on free edges; empty: no constraints.
    circ : (4 cap,) float32 or (0,)
    rank : (r,) int32
    meta : (6,) int64
    work : (5 w,) int32
        Output: the cavity triangles and boundary edges (see the module docstring).
    vmark : (>= rows + 1,) int32

    Returns
    -------
    int
        The number of cavity triangles (> 0); or ``NEED_SPACE``, ``BROKEN``, or
        ``DUP_BASE - w`` when v coincides with vertex w.  Nothing is modified but ``work``
        and ``meta``'s split record.
    """
    if _short_of_space(pts, tri, nbr, cons, circ, meta, vmark):
        return NEED_SPACE
    meta[M_SPLIT_C] = 0
    seed1 = -1
    if tri[3 * t0 + 2] != GHOST:
        px = pts[v, 0]
        py = pts[v, 1]
        for k in range(3):
            w = tri[3 * t0 + k]
            if pts[w, 0] == px and pts[w, 1] == py:
                return DUP_BASE - w
        if cons.shape[0] > 0:
            for k in range(3):
                h = 3 * t0 + k
                if cons[h] != 0:
                    a = tri[3 * t0 + _next(k)]
                    b = tri[3 * t0 + _prev(k)]
                    if orient2d(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], px, py) == 0.0:
                        _mark_split(h, tri, cons, meta)
                        seed1 = nbr[h]
                        break
    return _grow_cavity(v, t0, seed1, pts, tri, nbr, cons, circ, rank, work)


@njit(inline="always")
def fan(v, ncav, pts, tri, nbr, cons, circ, rank, meta, work, vmark):
    """Replace the cavity found by :func:`cavity` with the fan of v; returns a new triangle.

    Each boundary edge keeps its constraint; the fan's inner edges are free, except the two
    halves of a split constrained edge.  Returns a new finite triangle incident to v.
    """
    ntri = meta[M_NTRI]
    cap = work.shape[0] // 5
    bo = 2 * cap
    nb = ncav + 2
    constrained = cons.shape[0] > 0
    sa = meta[M_SPLIT_A]
    sb = meta[M_SPLIT_B]
    sc = meta[M_SPLIT_C] if constrained else 0
    # Write every triangle and its outer link, record where each boundary edge starts.
    for j in range(nb):
        o = bo + 3 * j
        u = work[o]
        w = work[o + 1]
        he = work[o + 2]
        tn = _fan_slot(j, ncav, ntri, work)
        s = _fan_shift(u, w)
        b3 = 3 * tn
        tri[b3 + s] = u
        tri[b3 + (s + 1) % 3] = w
        tri[b3 + (s + 2) % 3] = v
        nbr[b3 + (s + 2) % 3] = he // 3
        nbr[he] = tn
        if constrained:
            cons[b3 + (s + 2) % 3] = cons[he]
            # (u, w, v): the edge w-v is opposite u, the edge v-u opposite w.
            cons[b3 + s] = sc if (sc != 0 and (w == sa or w == sb)) else 0
            cons[b3 + (s + 1) % 3] = sc if (sc != 0 and (u == sa or u == sb)) else 0
        vmark[_vslot(u, vmark)] = j
    # Link each fan triangle (u, w, v) with the one whose boundary edge starts at w.
    result = -1
    for j in range(nb):
        o = bo + 3 * j
        u = work[o]
        w = work[o + 1]
        tn = _fan_slot(j, ncav, ntri, work)
        s = _fan_shift(u, w)
        jn = vmark[_vslot(w, vmark)]
        on = bo + 3 * jn
        tn2 = _fan_slot(jn, ncav, ntri, work)
        s2 = _fan_shift(work[on], work[on + 1])
        nbr[3 * tn + s] = tn2
        nbr[3 * tn2 + (s2 + 1) % 3] = tn
        if circ.shape[0] > 0:
            watson.circle(pts, tri, circ, tn)
        if s == 0:
            result = tn
    meta[M_NTRI] = ntri + 2
    meta[M_LAST] = result
    meta[M_SPLIT_C] = 0
    return result


@njit(cache=True)
def insert_vertex(v, t, pts, tri, nbr, cons, circ, rank, meta, work, vmark):
    """Insert vertex v (row v of ``pts``) by cavity re-triangulation, walking from triangle t.

    This is the single-point entry of the kernel for every method that inserts points into a
    Delaunay triangulation (refinement, segment recovery): write the coordinates into row v of
    ``pts`` first, call, and on ``NEED_SPACE`` call :func:`make_room` and retry.  With
    constraints, the result is the constrained Delaunay triangulation (a point exactly on a
    constrained edge splits it).

    Parameters
    ----------
    v : int
        Vertex to insert; ``pts[v]`` holds its coordinates.
    t : int
        Start triangle of the walk, ``0 <= t < meta[M_NTRI]``.
    pts : (rows, 2) float64
    tri, nbr : (3 cap,) int32
    cons : (3 cap,) int32 or (0,)
        Constraint per half-edge (see :func:`cavity`); empty for a plain triangulation.
    circ : (4 cap,) float32 or (0,)
        Watson's circumcircles; empty for Bowyer.
    rank : (r,) int32
        Perturbation keys (see the module docstring); may be empty.
    meta : (6,) int64
    work : (5 w,) int32
    vmark : (>= rows + 1,) int32

    Returns
    -------
    int
        A new finite triangle incident to v; or ``NEED_SPACE`` (call :func:`make_room`, then
        retry), ``BROKEN`` (inconsistent cavity), or ``DUP_BASE - w`` when v coincides with
        vertex w.  Only success modifies the triangulation.
    """
    if _short_of_space(pts, tri, nbr, cons, circ, meta, vmark):
        return NEED_SPACE
    t0 = walk(pts, tri, nbr, meta, t, pts[v, 0], pts[v, 1])
    ncav = cavity(v, t0, pts, tri, nbr, cons, circ, rank, meta, work, vmark)
    if ncav < 0:
        return ncav
    return fan(v, ncav, pts, tri, nbr, cons, circ, rank, meta, work, vmark)


@njit(cache=True)
def split_edge(v, h, pts, tri, nbr, cons, circ, rank, meta, work, vmark):
    """Split the constrained edge of half-edge h at vertex v (on it, or on its true curve).

    Both triangles of the edge are in the cavity; the two halves ``a-v`` and ``v-b`` keep the
    edge's constraint.  v may lie off the chord (a rounded midpoint, a split point on a curved
    boundary).  When the two-sided cavity is not star-shaped from v (a sliver of nearly
    collinear vertices across the chord), v is inserted into the one of the two triangles
    that holds it and the constrained Delaunay property is restored by flips
    (:func:`_split_by_flips`).

    Returns
    -------
    int
        A new finite triangle incident to v, ``NEED_SPACE``, or ``BROKEN`` (refused: v lies
        in neither triangle of the edge; nothing was modified).
    """
    if _short_of_space(pts, tri, nbr, cons, circ, meta, vmark):
        return NEED_SPACE
    _mark_split(h, tri, cons, meta)
    ncav = _grow_cavity(v, h // 3, nbr[h], pts, tri, nbr, cons, circ, rank, work)
    if ncav == NEED_SPACE:
        meta[M_SPLIT_C] = 0
        return ncav
    star = ncav > 0
    if star:
        bo = 2 * (work.shape[0] // 5)
        px = pts[v, 0]
        py = pts[v, 1]
        for j in range(ncav + 2):
            u = work[bo + 3 * j]
            w = work[bo + 3 * j + 1]
            if u != GHOST and w != GHOST and _orient(pts[u, 0], pts[u, 1], pts[w, 0], pts[w, 1], px, py) <= 0.0:
                star = False
                break
    if star:
        return fan(v, ncav, pts, tri, nbr, cons, circ, rank, meta, work, vmark)
    meta[M_SPLIT_C] = 0
    return _split_by_flips(v, h, pts, tri, nbr, cons, circ, rank, meta, work)


@njit(inline="always")
def _inside(pts, t3, tri, px, py):
    """Whether (px, py) lies strictly inside the finite triangle at slot offset t3 (exact)."""
    for k in range(3):
        u = tri[t3 + _next(k)]
        w = tri[t3 + _prev(k)]
        if _orient(pts[u, 0], pts[u, 1], pts[w, 0], pts[w, 1], px, py) <= 0.0:
            return False
    return True


@njit(inline="always")
def _redirect(nbr, t, old, new):
    """In triangle t, make the link that pointed to ``old`` point to ``new``."""
    for m in range(3):
        if nbr[3 * t + m] == old:
            nbr[3 * t + m] = new


@njit(cache=True)
def _split_by_flips(v, h, pts, tri, nbr, cons, circ, rank, meta, work):
    r"""Insert v into the triangle of half-edge h's edge that holds it, then flip (Lawson).

    The triangle X = (p0, p1, p2) holding v becomes three, each stored with v first::

              p2                        p2
             /  \                      / | \
            /    \                    / T0 \        T0 = (v, p1, p2) in X's slot
           /  X   \      ----->      / T1|   \      T1 = (v, p2, p0), T2 = (v, p0, p1)
          /    v   \                /  /  v  \ \
        p0 -------- p1             p0 -----T2---- p1

    The split edge a-b loses its constraint and the halves a-v, v-b get it.  Then every edge
    opposite v that is free and not locally Delaunay is flipped (Lawson 1977); each flip
    keeps both new triangles incident to v, so only v's star changes.  Returns a new
    triangle incident to v, or ``BROKEN`` when v lies strictly inside neither triangle.
    """
    px = pts[v, 0]
    py = pts[v, 1]
    t = h // 3
    x = -1
    if _inside(pts, 3 * t, tri, px, py):
        x = t
    else:
        n = nbr[h]
        if tri[3 * n + 2] != GHOST and _inside(pts, 3 * n, tri, px, py):
            x = n
    if x < 0:
        return BROKEN
    constraint = cons[h]
    a = tri[3 * t + _next(h % 3)]
    b = tri[3 * t + _prev(h % 3)]
    ntri = meta[M_NTRI]
    slots = (x, ntri, ntri + 1)
    p = (tri[3 * x], tri[3 * x + 1], tri[3 * x + 2])
    outer = (nbr[3 * x], nbr[3 * x + 1], nbr[3 * x + 2])
    ocons = (cons[3 * x], cons[3 * x + 1], cons[3 * x + 2])
    for i in range(3):
        ti = slots[i]
        pi = p[(i + 1) % 3]
        pj = p[(i + 2) % 3]
        tri[3 * ti] = v
        tri[3 * ti + 1] = pi
        tri[3 * ti + 2] = pj
        nbr[3 * ti] = outer[i]
        nbr[3 * ti + 1] = slots[(i + 1) % 3]
        nbr[3 * ti + 2] = slots[(i + 2) % 3]
        split_here = (pi == a and pj == b) or (pi == b and pj == a)
        cons[3 * ti] = 0 if split_here else ocons[i]
        cons[3 * ti + 1] = constraint if (pj == a or pj == b) else 0
        cons[3 * ti + 2] = constraint if (pi == a or pi == b) else 0
        if split_here:
            o = outer[i]
            for m in range(3):
                if nbr[3 * o + m] == x:
                    cons[3 * o + m] = 0
        if i > 0:
            _redirect(nbr, outer[i], x, ti)
    meta[M_NTRI] = ntri + 2
    # Lawson flips over the edges opposite v; work[] is the stack of triangles to check.
    cap = work.shape[0]
    work[0] = slots[0]
    work[1] = slots[1]
    work[2] = slots[2]
    top = 3
    while top > 0:
        top -= 1
        tt = work[top]
        o = nbr[3 * tt]
        if cons[3 * tt] != 0 or not _conflict(pts, tri, circ, rank, o, v, px, py):
            continue
        # tt = (v, xx, yy), o holds edge yy -> xx and its apex q.
        xx = tri[3 * tt + 1]
        yy = tri[3 * tt + 2]
        j = 0 if nbr[3 * o] == tt else (1 if nbr[3 * o + 1] == tt else 2)
        q = tri[3 * o + j]
        if (
            _orient(px, py, pts[xx, 0], pts[xx, 1], pts[q, 0], pts[q, 1]) <= 0.0
            or _orient(px, py, pts[q, 0], pts[q, 1], pts[yy, 0], pts[yy, 1]) <= 0.0
        ):
            continue  # not strictly convex: only an exact cocircularity can get here
        # o = (q, yy, xx) from q: the edge x-q is opposite yy (next(j)), q-y opposite xx.
        across_xq = nbr[3 * o + _next(j)]
        across_qy = nbr[3 * o + _prev(j)]
        c_xq = cons[3 * o + _next(j)]
        c_qy = cons[3 * o + _prev(j)]
        n_yv = nbr[3 * tt + 1]
        n_vx = nbr[3 * tt + 2]
        c_yv = cons[3 * tt + 1]
        c_vx = cons[3 * tt + 2]
        tri[3 * tt + 2] = q
        nbr[3 * tt] = across_xq
        nbr[3 * tt + 1] = o
        nbr[3 * tt + 2] = n_vx
        cons[3 * tt] = c_xq
        cons[3 * tt + 1] = 0
        cons[3 * tt + 2] = c_vx
        tri[3 * o] = v
        tri[3 * o + 1] = q
        tri[3 * o + 2] = yy
        nbr[3 * o] = across_qy
        nbr[3 * o + 1] = n_yv
        nbr[3 * o + 2] = tt
        cons[3 * o] = c_qy
        cons[3 * o + 1] = c_yv
        cons[3 * o + 2] = 0
        _redirect(nbr, across_xq, o, tt)
        _redirect(nbr, n_yv, tt, o)
        if circ.shape[0] > 0:
            watson.circle(pts, tri, circ, tt)
            watson.circle(pts, tri, circ, o)
        if top + 2 > cap:
            return BROKEN
        work[top] = tt
        work[top + 1] = o
        top += 2
    if circ.shape[0] > 0:
        for i in range(3):
            watson.circle(pts, tri, circ, slots[i])
    meta[M_LAST] = x
    return x


@njit(cache=True)
def make_room(rows, tri, nbr, cons, circ, meta, work, vmark):
    """Grow whichever array made :func:`insert_vertex` return ``NEED_SPACE``.

    Parameters
    ----------
    rows : int
        Rows of the points array the next insertion uses.
    tri, nbr, cons, circ, meta, work, vmark
        Kernel state as in :func:`insert_vertex`.

    Returns
    -------
    tuple
        ``(tri, nbr, cons, circ, work, vmark)``, grown copies or the arrays themselves.
    """
    need = meta[M_NTRI] + 2
    if (
        3 * need > tri.shape[0]
        or 3 * need > nbr.shape[0]
        or (cons.shape[0] > 0 and 3 * need > cons.shape[0])
        or (circ.shape[0] > 0 and 4 * need > circ.shape[0])
    ):
        tri = grown(tri, 3 * need)
        nbr = grown(nbr, 3 * need)
        if cons.shape[0] > 0:
            cons = grown(cons, 3 * need)
        if circ.shape[0] > 0:
            circ = grown(circ, 4 * need)
    elif vmark.shape[0] <= rows:
        vmark = grown(vmark, rows + 1)
    else:
        work = np.empty(2 * work.shape[0], dtype=np.int32)
    return tri, nbr, cons, circ, work, vmark


@njit(cache=True)
def insert_batch(order, start, stop, vbase, pts, tri, nbr, cons, circ, rank, meta, work, vmark, vmap):
    """Insert ``order[start:stop]`` one by one, each walk starting where the last one ended.

    Parameters
    ----------
    order : (m,) int32 or (0,)
        Vertices (rows of ``pts``) in insertion order; empty means vertices start..stop-1.
    start, stop : int
        Positions of ``order`` to insert.
    vbase : int
        ``vmap`` is indexed by ``v - vbase``.
    pts, tri, nbr, cons, circ, rank, meta, work, vmark
        Kernel state as in :func:`insert_vertex`.
    vmap : (m,) int32
        Output: ``vmap[v - vbase] = v`` for an inserted vertex v, else the vertex v coincides
        with.

    Returns
    -------
    tuple
        ``(bad, tri, nbr, cons, circ, work, vmark)``: ``bad`` is -1, or the vertex whose
        insertion found an inconsistent cavity (the triangulation is then unchanged by it and
        the later vertices are not inserted).
    """
    t = meta[M_LAST]
    rows = pts.shape[0]
    for i in range(start, stop):
        v = order[i] if order.shape[0] > 0 else i
        st = insert_vertex(v, t, pts, tri, nbr, cons, circ, rank, meta, work, vmark)
        while st == NEED_SPACE:
            tri, nbr, cons, circ, work, vmark = make_room(rows, tri, nbr, cons, circ, meta, work, vmark)
            st = insert_vertex(v, t, pts, tri, nbr, cons, circ, rank, meta, work, vmark)
        if st >= 0:
            vmap[v - vbase] = v
            t = st
        elif st == BROKEN:
            return v, tri, nbr, cons, circ, work, vmark
        else:
            vmap[v - vbase] = DUP_BASE - st
    return -1, tri, nbr, cons, circ, work, vmark


@njit(cache=True)
def locate_points(pts, tri, nbr, meta, xy):
    """Finite triangle containing each query point (in its closure), -1 outside the hull.

    Parameters
    ----------
    pts : (rows, 2) float64
    tri, nbr : (3 cap,) int32
    meta : (6,) int64
        A copy is advisable: the walk advances its RNG state.
    xy : (m, 2) float64

    Returns
    -------
    (m,) int32
    """
    m = xy.shape[0]
    out = np.empty(m, dtype=np.int32)
    t = meta[M_LAST]
    for i in range(m):
        t = walk(pts, tri, nbr, meta, t, xy[i, 0], xy[i, 1])
        out[i] = -1 if tri[3 * t + 2] == GHOST else t
    return out
