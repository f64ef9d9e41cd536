"""Bowyer's algorithm in 3-D (chapter 18.1.2, 18.4.1): the exact conflict test of a tetrahedron.

Source: A. Bowyer, "Computing Dirichlet tessellations", The Computer Journal 24(2):162-166,
1981 (chapter 18.1.2; the chapter's 3-D procedure is section 18.4.1).

Data structure
--------------
Bowyer's Voronoi vertices in 3-D are the circumcentres of the Delaunay tetrahedra; their
four *forming points* and four *neighbouring Voronoi vertices* are exactly the flat kernel
arrays of :mod:`meshwright.tet._kernel3d`::

    Voronoi vertex t:  forming points  tet[4t : 4t+4]   (positively oriented)
                       neighbours      nbr[4t : 4t+4]   (nbr[4t+k] shares the three forming
                                                         points other than tet[4t+k])

Bowyer's neighbours "at infinity" are ghost tetrahedra ``(a, b, c, GHOST)`` on the hull faces
(GHOST always stored as vertex 3), so no superstructure has to be built or removed.  The
cavity search of the kernel (walk, then breadth first over neighbours) is the chapter's tree
search for the set S; this module decides membership in S.

Conflict rules (exact, under symbolic perturbation)
---------------------------------------------------
* Finite tet ``(a, b, c, d)``: ``insphere_sos(a, b, c, d, p) > 0``, keys from ``rank``
  (Shewchuk's stage-A filter inlined; the exact, perturbed predicate only when unsure).
* Ghost ``(a, b, c, GHOST)``, hull face ``a b c`` with its normal pointing out of the hull:
  the limit of the circumballs through a, b, c whose centre runs to infinity outside the
  face.  p conflicts iff ``orient3d(a, b, c, p) > 0`` (strictly outside the face's plane), or
  p lies in that plane and inside the circumcircle of a b c.  That circle is the trace of
  the circumsphere of the finite tet across the face on the plane, and under the lifted
  perturbation the in-plane decision does not depend on the fourth vertex, so the coplanar
  case is decided by the finite neighbour's own test.  The ghost and the finite tet then
  always agree for a coplanar p, which keeps the hull convex and the cavity star-shaped
  (a point on a hull face, or coplanar and inside its circle, removes the face).

Invariant: after every insertion no vertex lies inside the circumball of a finite tet under
the symbolic perturbation of :func:`meshwright.core.predicates.insphere_sos` (cospherical
points resolved by a fixed key per vertex), which makes the result unique.
"""

from __future__ import annotations

from numba import njit

from meshwright.core.flat import GHOST
from meshwright.core.predicates import insphere_sos, insphere_stage_a, orient3d

__all__ = ["conflict", "finite_conflict", "key"]


@njit(inline="always")
def key(rank, v):
    """Perturbation key of vertex v: ``rank[v]`` if listed, else v."""
    return rank[v] if v < rank.shape[0] else v


@njit(inline="always")
def vertex0(tet, t):
    """Vertex 0 of tet t, also while the kernel marks t as a cavity member (``-2 - v``)."""
    a = tet[4 * t]
    return a if a >= 0 else -2 - a


@njit(inline="always")
def finite_conflict(pts, tet, rank, t, v, px, py, pz):
    """Whether p = pts[v] lies inside the circumball of the finite tet t (exact, perturbed).

    Parameters
    ----------
    pts : (rows, 3) float64
    tet : (4 cap,) int32
    rank : (r,) int32
        Perturbation keys (see :mod:`meshwright.tet._kernel3d`).
    t, v : int
        A finite tet and the new vertex.
    px, py, pz : float
        ``pts[v]``.

    Returns
    -------
    bool
        ``insphere_sos(a, b, c, d, p) > 0``.
    """
    b4 = 4 * t
    a = vertex0(tet, t)
    b = tet[b4 + 1]
    c = tet[b4 + 2]
    d = tet[b4 + 3]
    ax = pts[a, 0]
    ay = pts[a, 1]
    az = pts[a, 2]
    bx = pts[b, 0]
    by = pts[b, 1]
    bz = pts[b, 2]
    cx = pts[c, 0]
    cy = pts[c, 1]
    cz = pts[c, 2]
    dx = pts[d, 0]
    dy = pts[d, 1]
    dz = pts[d, 2]
    # Shewchuk's stage-A filter of the in-sphere determinant (his sign; ours is its negative).
    det, err = insphere_stage_a(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz, px, py, pz)
    if det > err:
        return False
    if -det > err:
        return True
    return (
        insphere_sos(
            ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz, px, py, pz,
            key(rank, a), key(rank, b), key(rank, c), key(rank, d), key(rank, v),
        )
        > 0
    )


@njit(inline="always")
def conflict(pts, tet, nbr, rank, t, v, px, py, pz):
    """Whether tet t (finite or ghost) is deleted by the new vertex v (exact, perturbed).

    Parameters
    ----------
    pts : (rows, 3) float64
    tet, nbr : (4 cap,) int32
    rank : (r,) int32
    t, v : int
    px, py, pz : float
        ``pts[v]``.

    Returns
    -------
    bool
        :func:`finite_conflict` for a finite tet; the ghost rule of the module docstring
        for a ghost.
    """
    if tet[4 * t + 3] == GHOST:
        a = vertex0(tet, t)
        b = tet[4 * t + 1]
        c = tet[4 * t + 2]
        o = orient3d(pts[a, 0], pts[a, 1], pts[a, 2], pts[b, 0], pts[b, 1], pts[b, 2],
                     pts[c, 0], pts[c, 1], pts[c, 2], px, py, pz)
        if o != 0.0:
            return o > 0.0
        t = nbr[4 * t + 3]  # coplanar: the finite tet across the hull face decides
    return finite_conflict(pts, tet, rank, t, v, px, py, pz)
