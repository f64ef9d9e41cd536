"""Bowyer's algorithm (chapter 18.1.2): Delaunay triangulation as a graph of Voronoi vertices.

Source: A. Bowyer, "Computing Dirichlet tessellations", The Computer Journal 24(2):162-166,
1981 (chapter 18.1.2, Figure 18.1.8).

Data structure
--------------
Bowyer describes the tessellation by two lists per Voronoi vertex: its three *forming points*
(the Delaunay triangle whose circumcentre it is) and its three *neighbouring Voronoi vertices*
(the adjacent triangles, 0 where the Voronoi edge runs to infinity).  These are exactly the
flat kernel arrays of :mod:`meshwright.tri._kernel2d`::

    Voronoi vertex t:  forming points  tri[3t : 3t+3]   (counter-clockwise)
                       neighbours      nbr[3t : 3t+3]   (nbr[3t+k] shares the two forming
                                                         points other than tri[3t+k])

Bowyer's "0" neighbours are ghost triangles at the symbolic vertex at infinity, so his
initial superstructure (step 1) is never built and never has to be removed.

Steps 2-9 of the chapter map onto :func:`meshwright.tri._kernel2d.insert_vertex`:
step 3 (vertices whose circumcircle holds the new point) is the cavity search, decided by
:func:`conflict` below, the exact in-circle predicate of the forming points; steps 4-7
(contiguous points, surviving neighbours, new forming points, new neighbour pairs) are the fan
with its per-vertex scratch; step 8 (overwrite the deleted vertices' entries) is the reuse of
cavity slots.  Nothing per triangle is stored besides ``tri``/``nbr``: the kernel runs Bowyer
when its per-triangle circle arrays ``cen``/``rad`` are empty.

Ghost rule: a point p conflicts with the ghost triangle ``(a, b, GHOST)`` iff
``orient2d(a, b, p) > 0`` (strictly outside the hull edge) or p is collinear with a, b and
strictly between them: the limit of the circumdisk of ``(a, b, x)`` as x goes to infinity
beyond the edge, with the open segment ab included so a point on a hull edge splits it.

Invariant: after every insertion each finite triangle's circumdisk holds no vertex in its
interior under the symbolic perturbation of :func:`meshwright.core.predicates.incircle_sos`
(cocircular points resolved by a fixed key per vertex, its insertion rank in the bulk build),
which makes the result unique.  The in-circle determinant is first evaluated with
Shewchuk's stage-A error bound inlined; the exact, perturbed predicate runs only when that
filter cannot decide.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.flat import GHOST
from meshwright.core.geom2d import orient_filtered
from meshwright.core.predicates import incircle_sos, incircle_stage_a

__all__ = ["ghost_conflict", "conflict"]


@njit(cache=True, inline="always")
def ghost_conflict(pts, a, b, px, py):
    """Conflict of p with the ghost triangle ``(a, b, GHOST)``: p beyond hull edge a -> b.

    Parameters
    ----------
    pts : (rows, 2) float64
    a, b : int
        Hull edge, outside on its left.
    px, py : float
        The new point.

    Returns
    -------
    bool
        ``orient2d(a, b, p) > 0``, or p collinear and strictly between a and b.
    """
    ax = pts[a, 0]
    ay = pts[a, 1]
    bx = pts[b, 0]
    by = pts[b, 1]
    o = orient_filtered(ax, ay, bx, by, px, py)
    if o != 0.0:
        return o > 0.0
    if ax != bx:
        return (ax < px < bx) or (bx < px < ax)
    return (ay < py < by) or (by < py < ay)


@njit(inline="always")
def _key(rank, v):
    """Perturbation key of vertex v: ``rank[v]`` if listed, else v (int64 whatever the index
    type, so the predicates compile once)."""
    return np.int64(rank[v]) if v < rank.shape[0] else np.int64(v)


@njit(cache=True, inline="always")
def conflict(pts, tri, rank, t, v, px, py):
    """Whether the Voronoi vertex t is deleted by the new point v (exact, perturbed).

    Parameters
    ----------
    pts : (rows, 2) float64
    tri : (3 cap,) int32
    rank : (r,) int32
        Perturbation keys of the vertices (see :mod:`meshwright.tri._kernel2d`).
    t : int
        Triangle (finite or ghost).
    v : int
        The new vertex, ``pts[v] == (px, py)``.
    px, py : float

    Returns
    -------
    bool
        ``incircle_sos(a, b, c, v) > 0`` for a finite triangle, the ghost rule otherwise.
    """
    b3 = 3 * t
    a = tri[b3]
    b = tri[b3 + 1]
    c = tri[b3 + 2]
    if c == GHOST:
        return ghost_conflict(pts, a, b, px, py)
    ax = pts[a, 0]
    ay = pts[a, 1]
    bx = pts[b, 0]
    by = pts[b, 1]
    cx = pts[c, 0]
    cy = pts[c, 1]
    # Shewchuk's stage-A filter of the in-circle determinant, inlined; exact only if unsure.
    det, err = incircle_stage_a(ax, ay, bx, by, cx, cy, px, py)
    if det > err:
        return True
    if -det > err:
        return False
    ka = _key(rank, a)
    kb = _key(rank, b)
    kc = _key(rank, c)
    kv = _key(rank, v)
    return incircle_sos(ax, ay, bx, by, cx, cy, px, py, ka, kb, kc, kv) > 0
