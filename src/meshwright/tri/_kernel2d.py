r"""Flat-array kernel of 2-D incremental Delaunay insertion, shared by Bowyer and Watson.

Both algorithms of the chapter (Watson 1981, section 18.1.1; Bowyer 1981, section 18.1.2)
insert one point at a time: find every triangle whose circumdisk contains the new point
(the *cavity*, Watson's insertion polygon, Bowyer's deleted Voronoi vertices), delete them,
and join the new point to the cavity boundary.  They differ only in the conflict test and in
what is stored per triangle, so this module holds everything else and calls the conflict test
of :mod:`meshwright.tri.bowyer` or of :mod:`meshwright.tri.watson` (with Watson's circle
bookkeeping).  The algorithm is chosen by the per-triangle circle array: an empty ``circ``
runs Bowyer, a sized one runs Watson (a branch on an array length, predicted perfectly).

The state bundle: :class:`TriState`
----------------------------------
Every kernel entry takes the whole state as ONE argument, a :class:`TriState` (a
``typing.NamedTuple`` of flat arrays, which Numba types as a tuple, defined with the status
codes, header slots, :func:`new_state` and :func:`grow` in :mod:`meshwright.tri._state2d` and
re-exported here), and scalar header values live in its int64 ``meta`` array.  Each field
read is an atomic reference-count pair, so the entries are thin wrappers over bodies taking
the unpacked arrays (``_walk``, ``_grow``, ``_fan``, :func:`insert_arrays`), which per-point
loops call with arrays read once (and borrowed, :mod:`meshwright.core.borrowed`).  A kernel
that finds an array too small returns ``NEED_SPACE`` *before* modifying anything (the cavity scratch ``work`` is found short only while the cavity grows:
then only ``work`` and ``meta[M_SHORT_WORK] = 1`` have been written), and :func:`grow`, on the
Python side, returns a new bundle with doubled arrays (``state._replace(...)``); inside a
kernel loop :func:`meshwright.tri._build2d.make_room` does the same.  Method-specific arrays go in a bundle of the
method's own (``CdtState`` of :mod:`meshwright.tri._encroach`, ``RefineState`` of
:mod:`meshwright.tri.ruppert`, ...), never into loose argument lists.

Layout (``cap`` triangle slots, ``ntri = meta[M_NTRI]`` in use), in field order
------------------------------------------------------------------------
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
``meta`` (8,) int64             ``[M_NTRI]`` slots in use, ``[M_LAST]`` a recent triangle,
                                ``[M_RNG]`` xorshift state of the walk (:mod:`meshwright.core.rng`),
                                ``[M_SPLIT_*]`` the constrained edge the pending fan splits,
                                ``[M_NV]`` vertices in use (rows of ``pts``),
                                ``[M_SHORT_WORK]`` 1 when ``work`` must double.
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
1. Locate: visibility walk (:func:`walk`, the one walk of the 2-D kernels; it can also stop
   at constrained edges) (Devillers, Pion & Teillaud 2002, "Walking in a triangulation",
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

One compiled copy of the insertion body: :func:`insert_arrays` holds the only inlined cavity
growth and fan, and every single-point insertion calls it: the Delaunay build's loop,
the frontal kernel, Delaunay refinement's new points (``I_SCREEN``: the cavity is screened
for encroached subsegments before the fan) and :func:`split_edge` (``I_SPLIT``: both
triangles of the edge seed the cavity).  Refinement's loop and the split had their own
inlined copies, each typed and lowered again on the first run (about 4 s and 3 s of the
first refinement's compile, 2026-12-03).  Walk, cavity and fan as three separate calls per
point instead cost 12-30 % of the Delaunay, refinement and frontal run times (alternating
processes, 2026-12-02), so they stay inlined inside :func:`insert_arrays`; the rare paths
call: :func:`flip` (Sloan's recovery, the split's Lawson flips) and the split's
conflict test.  Both algorithms share one inlined exact test (:func:`_conflict`: Watson's
distance filter, then :func:`meshwright.tri.bowyer.conflict`).  Helpers only kernels call
are compiled without Python wrappers (:mod:`meshwright.core.jit`).

Hot-path rules: no allocation and no Python objects inside ``insert_vertex``; arrays that may
be too small make it return ``NEED_SPACE`` *before* anything is modified, and
:func:`grow` grows them by doubling.  Memory locality: the caller stores the points in
insertion order (BRIO), so vertices that are close in space are close in ``pts``; ``rank``
keeps the perturbation keys of that build valid after the vertices are renumbered.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.borrowed import borrowed
from meshwright.core.flat import GHOST, back3, index3, next3, prev3
from meshwright.core.geom2d import orient_filtered
from meshwright.core.jit import inner
from meshwright.core.predicates import orient2d
from meshwright.core.rng import xorshift32
from meshwright.tri import bowyer, watson
from meshwright.tri._diametral import encroaches
from meshwright.tri._state2d import (
    BROKEN,
    DUP_BASE,
    M_LAST,
    M_NTRI,
    M_NV,
    M_RNG,
    M_SHORT_WORK,
    M_SPLIT_A,
    M_SPLIT_B,
    M_SPLIT_C,
    NEED_SPACE,
    TriState,
    grow,
    new_state,
)

__all__ = [
    "GHOST", "NEED_SPACE", "BROKEN", "DUP_BASE", "REFUSED_BASE", "I_WALK", "I_SCREEN", "I_SPLIT", "M_NTRI", "M_LAST", "M_RNG", "M_SPLIT_A",
    "M_SPLIT_B", "M_SPLIT_C", "M_NV", "M_SHORT_WORK", "TriState", "new_state", "grow", "walk",
    "insert_vertex", "insert_arrays", "split_edge", "flip", "on_constraint",
]

# insert_arrays' modes, and its refusals REFUSED_BASE - ncav: below every duplicate code
# DUP_BASE - w (vertex ids are int32, cavities far smaller than 2**40).
I_WALK = 0
I_SCREEN = 1
I_SPLIT = 2
REFUSED_BASE = -(1 << 62)


@njit(inline="always")
def _vslot(u, vmark):
    """Scratch index of vertex u; GHOST uses the last entry."""
    return u if u >= 0 else vmark.shape[0] - 1


@njit(inline="always")
def _fan_slot(j, ncav, ntri, work):
    """Triangle slot of fan triangle j: cavity slots first, then two appended slots."""
    return work[j] if j < ncav else ntri + (j - ncav)


@inner
def _fan_shift(u, w):
    """Rotation that keeps GHOST at vertex 2: conceptual vertex k is stored at (k + s) % 3."""
    if w == GHOST:
        return 1
    if u == GHOST:
        return 2
    return 0


@njit(inline="always")
def _conflict(pts, tri, circ, rank, t, v, px, py):
    """Conflict of triangle t with the new point: Watson's filter first if circles are kept,
    then the one copy of the exact test that serves both algorithms.

    Takes arrays, not the bundle: it runs once per cavity neighbour, and every field read
    from a bundle costs a reference-count pair where the loop runs (measured: 20 % of a
    Delaunay build), so per-iteration helpers get the fields their caller read once.
    """
    if circ.shape[0] > 0:
        f = watson.filter_sign(tri, circ, t, px, py)
        if f != 0:
            return f > 0
    return bowyer.conflict(pts, tri, rank, t, v, px, py)


@inner
def _conflict_call(pts, tri, circ, rank, t, v, px, py):
    """:func:`_conflict` as a call, for the rare Lawson flips of a split (a third inlined copy
    of the exact test is not worth its compile time there)."""
    return _conflict(pts, tri, circ, rank, t, v, px, py)


@njit(inline="always")
def walk(s, t, px, py, blocked):
    """Stochastic visibility walk from triangle t towards the point p.

    Devillers, Pion & Teillaud (2002): from each triangle, step across an edge that p lies
    strictly beyond, trying the edges from a pseudo-random one (``meta[M_RNG]``, the
    xorshift of :mod:`meshwright.core.rng`) and never straight back, so the walk ends also in
    a triangulation that is not Delaunay.

    Parameters
    ----------
    s : TriState
        Its ``meta[M_RNG]`` advances.
    t : int
        Start triangle (finite or ghost).
    px, py : float
    blocked : bool
        Stop at constrained edges (``s.cons``) instead of crossing them.

    Returns
    -------
    (int, int)
        ``(t_end, -1)``: a finite triangle whose closure contains p, or a ghost triangle
        whose hull edge has p strictly on its outer side; or, when ``blocked``, ``(t_end, h)``
        with every edge of finite ``t_end`` that p lies strictly beyond constrained, h one of
        them (the subsegment hiding p).
    """
    return _walk(s.pts, s.tri, s.nbr, s.cons, s.meta, t, px, py, blocked)


@njit(inline="always")
def _walk(pts, tri, nbr, cons, meta, t, px, py, blocked):
    """:func:`walk` over the unpacked bundle (the form the per-point loops inline)."""
    if tri[3 * t + 2] == GHOST:
        t = nbr[3 * t + 2]
    came = -1
    hit = -1
    r = meta[M_RNG]
    while True:
        r = xorshift32(r)
        k = r % 3
        base = 3 * t
        nxt = -1
        hit = -1
        for _ in range(3):
            n = nbr[base + k]
            if n != came:
                a = tri[base + next3(k)]
                b = tri[base + prev3(k)]
                if orient_filtered(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], px, py) < 0.0:
                    if not blocked or cons[base + k] == 0:
                        nxt = n
                        break
                    hit = base + k
            k = next3(k)
        if nxt < 0:
            break
        came = t
        t = nxt
        if tri[3 * t + 2] == GHOST:
            hit = -1
            break
    meta[M_RNG] = r
    return t, hit


@njit(inline="always")
def _short(pts, tri, nbr, circ, cons, meta, vmark):
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
def _grow(pts, tri, nbr, circ, rank, cons, meta, work, v, seed0, seed1):
    """Breadth-first cavity from ``seed0`` (and ``seed1`` across the split edge, if >= 0).

    A constrained edge (``cons`` non-zero) is never crossed: it always bounds the cavity, which
    makes the cavity the constrained-Delaunay one.  Returns the number of cavity triangles,
    ``NEED_SPACE`` (``meta[M_SHORT_WORK]`` set) or ``BROKEN``; ``work`` holds the cavity and
    its boundary (module docstring).
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
                    meta[M_SHORT_WORK] = 1
                    return NEED_SPACE
                work[ncav] = n
                work[cap + ncav] = c
                ncav += 1
            else:
                if nb == cap:
                    meta[M_SHORT_WORK] = 1
                    return NEED_SPACE
                n3 = 3 * n
                j = 0 if nbr[n3] == c else (1 if nbr[n3 + 1] == c else 2)
                o = bo + 3 * nb
                work[o] = tri[base + next3(k)]
                work[o + 1] = tri[base + prev3(k)]
                work[o + 2] = n3 + j
                nb += 1
    if nb != ncav + 2:
        return BROKEN
    return ncav


@njit(inline="always")
def _mark_split(h, tri, cons, meta):
    """Remember constrained half-edge h (a -> b) as the one the next fan splits."""
    t3 = h - h % 3
    meta[M_SPLIT_A] = tri[t3 + next3(h % 3)]
    meta[M_SPLIT_B] = tri[t3 + prev3(h % 3)]
    meta[M_SPLIT_C] = cons[h]


@njit(inline="always")
def on_constraint(t, px, py, s):
    """A constrained half-edge of finite triangle t through p (p in its closure), or -1."""
    return _on_constraint(s.pts, s.tri, s.cons, t, px, py)


@njit(inline="always")
def _on_constraint(pts, tri, cons, t, px, py):
    """:func:`on_constraint` over the unpacked bundle."""
    for k in range(3):
        h = 3 * t + k
        if cons[h] != 0:
            a = tri[3 * t + next3(k)]
            b = tri[3 * t + prev3(k)]
            if orient2d(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], px, py) == 0.0:
                return h
    return -1


@njit(inline="always")
def _cavity_seed(pts, tri, nbr, cons, meta, v, t0):
    """The second seed of v's cavity from triangle t0, which contains it: -1, or the triangle
    across the constrained edge of t0 that v lies exactly on (the edge is then recorded as
    the one the fan splits, its two halves keeping the constraint); or ``DUP_BASE - w`` when
    v coincides with vertex w.

    t0 is a finite triangle whose closure holds v, or a ghost whose hull edge v sees (what
    :func:`walk` returns); any other constrained edge bounds the cavity.  Modifies only
    ``meta``'s split record.
    """
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
            h = _on_constraint(pts, tri, cons, t0, px, py)
            if h >= 0:
                _mark_split(h, tri, cons, meta)
                seed1 = nbr[h]
    return seed1


@njit(inline="always")
def _star_shaped(pts, work, v, ncav):
    """Whether every finite boundary edge of the cavity in ``work`` sees v strictly on its left."""
    bo = 2 * (work.shape[0] // 5)
    px = pts[v, 0]
    py = pts[v, 1]
    for j in range(ncav + 2):
        u = work[bo + 3 * j]
        w = work[bo + 3 * j + 1]
        if u != GHOST and w != GHOST and orient_filtered(pts[u, 0], pts[u, 1], pts[w, 0], pts[w, 1], px, py) <= 0.0:
            return False
    return True


@njit(inline="always")
def _fan(pts, tri, nbr, circ, cons, meta, work, vmark, v, ncav):
    """Replace the cavity in ``work`` (ncav triangles) with the fan of v; returns a new triangle.

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
        sh = _fan_shift(u, w)
        b3 = 3 * tn
        tri[b3 + sh] = u
        tri[b3 + (sh + 1) % 3] = w
        tri[b3 + (sh + 2) % 3] = v
        nbr[b3 + (sh + 2) % 3] = he // 3
        nbr[he] = tn
        if constrained:
            cons[b3 + (sh + 2) % 3] = cons[he]
            # (u, w, v): the edge w-v is opposite u, the edge v-u opposite w.
            cons[b3 + sh] = sc if (sc != 0 and (w == sa or w == sb)) else 0
            cons[b3 + (sh + 1) % 3] = sc if (sc != 0 and (u == sa or u == sb)) else 0
        vmark[_vslot(u, vmark)] = j
    # Link each fan triangle (u, w, v) with the one whose boundary edge starts at w.
    result = np.int64(-1)  # not a literal: see docs/ARCHITECTURE.md, 'literal arguments'
    for j in range(nb):
        o = bo + 3 * j
        u = work[o]
        w = work[o + 1]
        tn = _fan_slot(j, ncav, ntri, work)
        sh = _fan_shift(u, w)
        jn = vmark[_vslot(w, vmark)]
        on = bo + 3 * jn
        tn2 = _fan_slot(jn, ncav, ntri, work)
        s2 = _fan_shift(work[on], work[on + 1])
        nbr[3 * tn + sh] = tn2
        nbr[3 * tn2 + (s2 + 1) % 3] = tn
        if circ.shape[0] > 0:
            watson.circle(pts, tri, circ, tn)
        if sh == 0:
            result = tn
    meta[M_NTRI] = ntri + 2
    meta[M_LAST] = result
    meta[M_SPLIT_C] = 0
    return result


@inner
def insert_arrays(pts, tri, nbr, circ, rank, cons, meta, work, vmark, v, t, mode):
    """:func:`insert_vertex` over the unpacked bundle, for per-point loops.

    A loop that inserts many points unpacks the bundle once (and again after growing it)
    and calls this: every field read of a bundle costs an atomic reference-count pair,
    about 30 per point through the bundle entries.  A call, not inlined: the one compiled
    copy of the cavity and the fan, which Delaunay refinement's loop and :func:`split_edge`
    share through ``mode`` (inlined in each, they were about 4 s and 3 s of the first
    refinement's compile).  Same contract as :func:`insert_vertex`, plus:

    Parameters
    ----------
    mode : int64
        ``I_WALK``: walk from t.  ``I_SCREEN``: t is a finite triangle that holds v off its
        constrained edges (no walk), and v is refused when it encroaches a constrained edge
        of its cavity's boundary (:func:`meshwright.tri._diametral.encroaches`).
        ``I_SPLIT``: t is the half-edge h of a constrained edge that v splits (as
        :func:`split_edge`: both triangles seed the cavity), refused when that cavity is
        not star-shaped from v.  An int64 variable, never a literal (a literal argument
        compiles the kernel once per value).

    Returns
    -------
    int
        As :func:`insert_vertex`; or, refused, ``REFUSED_BASE - ncav`` with the cavity of
        ncav triangles in ``work`` (``REFUSED_BASE`` alone for an inconsistent split cavity)
        and nothing else modified.
    """
    pts, tri, nbr, circ, rank, cons, meta, work, vmark = borrowed((pts, tri, nbr, circ, rank, cons, meta, work, vmark))
    if _short(pts, tri, nbr, circ, cons, meta, vmark):
        return NEED_SPACE
    # One inlined cavity growth for every mode: the seeds first.
    if mode == I_SPLIT:
        _mark_split(t, tri, cons, meta)
        seed0 = t // 3
        seed1 = nbr[t]
    else:
        seed0 = t
        if mode == I_WALK:
            seed0, _ = _walk(pts, tri, nbr, cons, meta, t, pts[v, 0], pts[v, 1], False)
        seed1 = _cavity_seed(pts, tri, nbr, cons, meta, v, seed0)
        if seed1 <= DUP_BASE:
            return seed1
    ncav = _grow(pts, tri, nbr, circ, rank, cons, meta, work, v, seed0, seed1)
    if mode == I_SPLIT:
        if ncav == NEED_SPACE:
            meta[M_SPLIT_C] = 0
            return ncav
        if ncav < 0 or not _star_shaped(pts, work, v, ncav):
            meta[M_SPLIT_C] = 0
            return REFUSED_BASE - max(ncav, 0)
    elif ncav < 0:
        return ncav
    elif mode == I_SCREEN:
        bo = 2 * (work.shape[0] // 5)
        for j in range(ncav + 2):
            o = bo + 3 * j
            if cons[work[o + 2]] != 0:
                u = work[o]
                w = work[o + 1]
                if encroaches(pts[u, 0], pts[u, 1], pts[w, 0], pts[w, 1], pts[v, 0], pts[v, 1]):
                    return REFUSED_BASE - ncav
    return _fan(pts, tri, nbr, circ, cons, meta, work, vmark, v, ncav)


@njit(cache=True, nogil=True)
def insert_vertex(v, t, s):
    """Insert vertex v (row v of ``s.pts``) by cavity re-triangulation, walking from triangle t.

    This is the single-point entry of the kernel for every method that inserts points into a
    Delaunay triangulation (refinement, segment recovery): write the coordinates into row v of
    ``pts`` first, call, and on ``NEED_SPACE`` grow the bundle (:func:`grow`) and retry.
    With constraints, the result is the constrained Delaunay
    triangulation (a point exactly on a constrained edge splits it).

    Parameters
    ----------
    v : int
        Vertex to insert; ``s.pts[v]`` holds its coordinates.
    t : int
        Start triangle of the walk, ``0 <= t < meta[M_NTRI]``.
    s : TriState

    Returns
    -------
    int
        A new finite triangle incident to v; or ``NEED_SPACE`` (grow, then retry), ``BROKEN``
        (inconsistent cavity), or ``DUP_BASE - w`` when v coincides with vertex w.  Only
        success modifies the triangulation.
    """
    pts, tri, nbr, circ, rank, cons, meta, work, vmark = s
    return insert_arrays(pts, tri, nbr, circ, rank, cons, meta, work, vmark, v, t, np.int64(I_WALK))


@njit(cache=True, nogil=True)
def split_edge(v, h, s):
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
        A new finite triangle incident to v; ``NEED_SPACE`` (nothing modified but the cavity
        scratch); or ``BROKEN``: refused, v lies strictly inside neither triangle of the edge,
        and nothing was modified.
    """
    s = borrowed(s)
    pts, tri, nbr, circ, rank, cons, meta, work, vmark = s
    tn = insert_arrays(pts, tri, nbr, circ, rank, cons, meta, work, vmark, v, h, np.int64(I_SPLIT))
    if tn <= REFUSED_BASE:
        return _split_by_flips(v, h, s)
    return tn


@njit(inline="always")
def _inside(pts, t3, tri, px, py):
    """Whether (px, py) lies strictly inside the finite triangle at slot offset t3 (exact)."""
    for k in range(3):
        u = tri[t3 + next3(k)]
        w = tri[t3 + prev3(k)]
        if orient_filtered(pts[u, 0], pts[u, 1], pts[w, 0], pts[w, 1], px, py) <= 0.0:
            return False
    return True


@njit(inline="always")
def _redirect(nbr, t, old, new):
    """In triangle t, make the link that pointed to ``old`` point to ``new``."""
    for m in range(3):
        if nbr[3 * t + m] == old:
            nbr[3 * t + m] = new


@njit(inline="always")
def _set3(a, t, x, y, z):
    a[3 * t] = x
    a[3 * t + 1] = y
    a[3 * t + 2] = z


@njit(inline="always")
def flip(h, s):
    """Flip the edge of half-edge h (see :func:`_flip_body`); returns the second triangle n.

    A call of the one compiled flip (segment recovery and the split's Lawson flips each
    inlined it twice: seconds of first-run compile), h cast to one signature."""
    return _flip_body(np.int64(h), s)


@inner
def _flip_body(h, s):
    r"""Flip the edge of half-edge h (two finite triangles forming a strictly convex quad)::

              p                       p
             / \                     /|\
          B /   \ A                B / | \ A
           /  t  \                  /  |  \
          u ----- w      ----->     u t | n w
           \  n  /                  \  |  /
          C \   / D                C \ | / D
             \ /                     \|/
              q                       q

    t = (p, u, w) with h = u -> w, n = (q, w, u); afterwards t = (p, u, q), n = (q, w, p).
    Constraint flags travel with the outer edges A-D, the new diagonal is free; Watson's
    circles are refreshed.  Returns n.
    """
    s = borrowed(s)
    tri, nbr, cons = s.tri, s.nbr, s.cons
    t = h // 3
    k = h - 3 * t
    n = nbr[h]
    j = back3(nbr, n, t)
    p = tri[3 * t + k]
    u = tri[3 * t + next3(k)]
    w = tri[3 * t + prev3(k)]
    q = tri[3 * n + j]
    ea = nbr[3 * t + next3(k)]  # across w-p
    eb = nbr[3 * t + prev3(k)]  # across p-u
    ec = nbr[3 * n + next3(j)]  # across u-q
    ed = nbr[3 * n + prev3(j)]  # across q-w
    ca = cons[3 * t + next3(k)] if cons.shape[0] > 0 else 0
    cb = cons[3 * t + prev3(k)] if cons.shape[0] > 0 else 0
    cc = cons[3 * n + next3(j)] if cons.shape[0] > 0 else 0
    cd = cons[3 * n + prev3(j)] if cons.shape[0] > 0 else 0
    _set3(tri, t, p, u, q)
    _set3(nbr, t, ec, n, eb)
    _set3(tri, n, q, w, p)
    _set3(nbr, n, ea, t, ed)
    if cons.shape[0] > 0:
        _set3(cons, t, cc, 0, cb)
        _set3(cons, n, ca, 0, cd)
    _redirect(nbr, ec, n, t)
    _redirect(nbr, ea, t, n)
    if s.circ.shape[0] > 0:
        watson.circle(s.pts, tri, s.circ, t)
        watson.circle(s.pts, tri, s.circ, np.int64(n))
    return n


@inner
def _split_by_flips(v, h, s):
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
    keeps both new triangles incident to v, so only v's star changes and cannot fail.

    Returns a new triangle incident to v, or ``BROKEN`` (nothing modified) when v lies
    strictly inside neither triangle.
    """
    pts, tri, nbr, cons, circ, rank = s.pts, s.tri, s.nbr, s.cons, s.circ, s.rank
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
    a = tri[3 * t + next3(h % 3)]
    b = tri[3 * t + prev3(h % 3)]
    ntri = s.meta[M_NTRI]
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
    s.meta[M_NTRI] = ntri + 2
    # Lawson flips over the edges opposite v, pass after pass around v's star until none
    # flips; the star's counter-clockwise order runs across the edge after v.  A flip keeps
    # both triangles in the star, so no stack is needed.
    changed = True
    while changed:
        changed = False
        tt = x
        while True:
            i = index3(tri, tt, v)
            h = 3 * tt + i
            o = nbr[h]
            if cons[h] == 0 and _conflict_call(pts, tri, circ, rank, o, v, px, py):
                # tt = (v, xx, yy), o holds edge yy -> xx and its apex q.
                xx = tri[3 * tt + next3(i)]
                yy = tri[3 * tt + prev3(i)]
                q = tri[3 * o + back3(nbr, o, tt)]
                # Not strictly convex: only an exact cocircularity can get here; no flip.
                if (
                    orient_filtered(px, py, pts[xx, 0], pts[xx, 1], pts[q, 0], pts[q, 1]) > 0.0
                    and orient_filtered(px, py, pts[q, 0], pts[q, 1], pts[yy, 0], pts[yy, 1]) > 0.0
                ):
                    flip(h, s)
                    changed = True
                    i = index3(tri, tt, v)
            tt = nbr[3 * tt + next3(i)]
            if tt == x:
                break
    if circ.shape[0] > 0:
        for i in range(3):
            watson.circle(pts, tri, circ, np.int64(slots[i]))
    s.meta[M_LAST] = x
    return x
