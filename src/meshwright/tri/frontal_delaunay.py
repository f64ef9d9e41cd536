r"""Combined Delaunay + advancing front: frontal Delaunay point placement (chapter 18.3).

Sources: J.-D. Müller, P. L. Roe and H. Deconinck, "A frontal approach for internal node
generation in Delaunay triangulations", Int. J. Numer. Meth. Fluids 17, 1993 (chapter 18.3:
nodes created by advancing-front rules, a row at a time, inserted by Delaunay insertion);
S. Rebay, "Efficient unstructured mesh generation by means of Delaunay triangulation and
Bowyer-Watson algorithm", J. Comput. Phys. 106, 1993 (the point on the perpendicular
bisector of a front edge).

Procedure
---------
Start from the classified constrained Delaunay triangulation of the boundary points
(:mod:`meshwright.tri.cdt`); the size ``h`` is the user's field or, as in 18.3, the
background interpolated from the boundary triangulation itself (Weatherill's ``dP``).
A triangle is *accepted* when its circumradius is at most ``ACCEPT`` times that of the
equilateral triangle of side h, ``R <= ACCEPT h / sqrt(3)``.  The *front* is the set of
edges between an accepted triangle (or the domain boundary) and a triangle that is not.
One row:

1. every non-accepted triangle with a front edge AB proposes the point X on the
   perpendicular bisector of AB, on its own side, such that ABX has circumradius
   ``rho = clamp(h / sqrt(3), |AB| / 2, R_t)`` (Rebay), i.e. at the distance
   ``rho + sqrt(rho^2 - |AB|^2 / 4)`` from the midpoint of AB: an equilateral element of
   size h where room allows, never beyond the triangle's own circumcentre::

                     X   <- ideal point, |MX| = rho + sqrt(rho^2 - p^2)
                    / \
                   /   \      not accepted
                  /     \
             A --M------- B   front edge (length 2p)
               accepted / boundary

2. proposals closer than ``SPACING h`` to a vertex or to an earlier proposal of the same
   row are dropped (the disk search of :mod:`meshwright.tri.weatherill`), and so are those
   that do not fall inside the domain;
3. the rest are inserted (Hilbert order) by constrained Delaunay insertion.

Rows repeat until no triangle is left unaccepted or no proposal survives.  Termination:
accepted proposals are at least ``SPACING min(h)`` from every vertex, so a bounded domain
holds finitely many; ``max_rows`` caps the loop all the same.

Array layout: the kernel's flat ``tri``/``nbr`` (3 cap,) int32 of the
:class:`ConstrainedTriangulation`, ``inside`` (ntri,) bool over its slots, and ``acc``
(3 cap,) int32, the vertex triple of the triangle accepted in each slot (a slot reused by a
later insertion no longer matches, so only new triangles are examined: a row costs time in
proportion to the front, not to the mesh).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.errors import MeshingError
from meshwright.core.spatial_sort import hilbert_order
from meshwright.sizing.field import as_size_field
from meshwright.tri._kernel2d import walk
from meshwright.tri.weatherill import select_spaced

__all__ = ["frontal_delaunay", "ACCEPT", "SPACING"]

ACCEPT = 1.4  # R <= ACCEPT * h / sqrt(3): the triangle is of the right size
SPACING = 0.7  # a proposal keeps this fraction of h away from vertices and other proposals
_SQRT3 = np.sqrt(3.0)


@njit(inline="always")
def _settled(t, tri, acc):
    """Whether slot t still holds the triangle that was accepted there."""
    return acc[3 * t] == tri[3 * t] and acc[3 * t + 1] == tri[3 * t + 1] and acc[3 * t + 2] == tri[3 * t + 2]


@njit(cache=True)
def _waiting(pts, tri, inside, acc):
    """Inside slots not (or no longer) accepted, with circumcentres and circumradii.

    Accepted triangles are remembered by their vertex triple in ``acc`` (3 cap,) int32, so a
    slot reused by a later insertion counts as new.  Returns ``(slots (k,) int64,
    centres (k, 2) float64, radii (k,) float64)``.
    """
    nt = inside.shape[0]
    slots = np.empty(nt, dtype=np.int64)
    k = 0
    for t in range(nt):
        if inside[t] and not _settled(t, tri, acc):
            slots[k] = t
            k += 1
    cen = np.empty((k, 2))
    rad = np.empty(k)
    for i in range(k):
        t = slots[i]
        ax = pts[tri[3 * t], 0]
        ay = pts[tri[3 * t], 1]
        bx = pts[tri[3 * t + 1], 0] - ax
        by = pts[tri[3 * t + 1], 1] - ay
        cx = pts[tri[3 * t + 2], 0] - ax
        cy = pts[tri[3 * t + 2], 1] - ay
        d = 2.0 * (bx * cy - by * cx)
        b2 = bx * bx + by * by
        c2 = cx * cx + cy * cy
        ux = (cy * b2 - by * c2) / d
        uy = (bx * c2 - cx * b2) / d
        cen[i, 0] = ax + ux
        cen[i, 1] = ay + uy
        rad[i] = np.sqrt(ux * ux + uy * uy)
    return slots[:k], cen, rad


@njit(cache=True)
def _proposals(pts, tri, nbr, inside, acc, slots, rad, h, accept):
    """Accept the waiting triangles of the right size; propose points for the others.

    Returns
    -------
    xy : (k, 2) float64
        Ideal points.
    hx : (k,) float64
        Size at the proposing triangle (the spacing radius uses it).
    src : (k,) int64
        The proposing slot.
    n_waiting : int
        Triangles still not accepted.
    """
    m = slots.shape[0]
    for i in range(m):
        t = slots[i]
        if rad[i] <= accept * h[i] / _SQRT3:
            acc[3 * t] = tri[3 * t]
            acc[3 * t + 1] = tri[3 * t + 1]
            acc[3 * t + 2] = tri[3 * t + 2]
    xy = np.empty((m, 2))
    hx = np.empty(m)
    src = np.empty(m, dtype=np.int64)
    k = 0
    waiting = 0
    for i in range(m):
        t = slots[i]
        if _settled(t, tri, acc):
            continue
        waiting += 1
        # The front edge: toward an accepted neighbour or the boundary; the longest such.
        best = -1
        blen = -1.0
        for e in range(3):
            n = nbr[3 * t + e]
            if inside[n] and not _settled(n, tri, acc):
                continue
            a = tri[3 * t + (e + 1) % 3]
            b = tri[3 * t + (e + 2) % 3]
            ln = np.hypot(pts[b, 0] - pts[a, 0], pts[b, 1] - pts[a, 1])
            if ln > blen:
                blen = ln
                best = e
        if best < 0:
            continue
        a = tri[3 * t + (best + 1) % 3]
        b = tri[3 * t + (best + 2) % 3]
        mx = 0.5 * (pts[a, 0] + pts[b, 0])
        my = 0.5 * (pts[a, 1] + pts[b, 1])
        p = 0.5 * blen
        # Inward unit normal of a -> b (the triangle lies to its left).
        nx = -(pts[b, 1] - pts[a, 1]) / blen
        ny = (pts[b, 0] - pts[a, 0]) / blen
        rho = min(max(h[i] / _SQRT3, p), rad[i])
        d = rho + np.sqrt(max(rho * rho - p * p, 0.0))
        xy[k, 0] = mx + d * nx
        xy[k, 1] = my + d * ny
        hx[k] = h[i]
        src[k] = t
        k += 1
    return xy[:k], hx[:k], src[:k], waiting


@njit(cache=True)
def _locate_near(pts, tri, nbr, meta, src, xy):
    """Slot holding each proposal, walking from the triangle that proposed it (a step away)."""
    out = np.empty(xy.shape[0], dtype=np.int64)
    for i in range(xy.shape[0]):
        out[i] = walk(pts, tri, nbr, meta, src[i], xy[i, 0], xy[i, 1])
    return out


def frontal_delaunay(ct, size, *, max_rows: int = 10_000, max_points: int | None = None) -> None:
    """Fill a classified constrained triangulation with frontal points, in place.

    Parameters
    ----------
    ct : ConstrainedTriangulation
        From :func:`meshwright.tri.cdt.cdt_build`, exterior removed by ``classify``.
    size : number, callable or SizeField
        Target edge length h(x).
    max_rows : int
        Cap on the rows.
    max_points : int, optional
        Cap on the number of vertices.

    Raises
    ------
    MeshingError
        A cap was hit (the message names it).
    """
    field = as_size_field(size)
    cap = np.iinfo(np.int32).max if max_points is None else int(max_points)
    acc = np.full(len(ct._tri), -2, dtype=np.int32)  # no triple matches: nothing accepted yet
    for _ in range(int(max_rows)):
        if len(acc) < len(ct._tri):
            acc = np.concatenate([acc, np.full(len(ct._tri) - len(acc), -2, dtype=np.int32)])
        pts, inside = ct.points, ct.inside_slots()
        slots, cen, rad = _waiting(pts, ct._tri, inside, acc)
        if len(slots) == 0:
            return
        xy, hx, src, waiting = _proposals(pts, ct._tri, ct._nbr, inside, acc, slots, rad, field(cen), ACCEPT)
        if waiting == 0 or len(xy) == 0:
            return
        # Spacing: the disk search walks the triangulation from each proposal's triangle.
        host = _locate_near(pts, ct._tri, ct._nbr, ct._meta.copy(), src, xy)
        keep = inside[host]
        xy, hx, host = xy[keep], hx[keep], host[keep]
        accepted = select_spaced(pts, ct._tri, ct._nbr, inside, xy, host, SPACING * hx)
        if not accepted.any():
            return
        new = xy[accepted]
        if ct.n_points + len(new) > cap:
            raise MeshingError(
                f"frontal Delaunay would add {len(new)} points to {ct.n_points}, above max_points = {cap}"
            )
        ct.insert_points(new[hilbert_order(new)])
    raise MeshingError(f"frontal Delaunay still added points after max_rows = {max_rows} rows")
