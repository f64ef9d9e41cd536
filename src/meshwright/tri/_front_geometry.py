r"""Geometry of the 2-D advancing front (:mod:`meshwright.tri._front_kernel`): the exact
tests that decide whether a triangle may be added, and the metric measures that rank the
candidate apexes.

Topological decisions use :func:`meshwright.core.predicates.orient2d` only: a point's
side of a line (:func:`_orient`), two segments meeting (:func:`_meets`), a node hidden
behind a face (:func:`_behind`).  Lengths and qualities in the metric are plain floating
point (:func:`_to_metric`, :func:`_seg_dist2`, :func:`_quality`): they order candidates
and keep clearances, and never decide validity.  Every function is compiled into its
caller (the triangle front and Zhu's pair front).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.predicates import orient2d

_Q = 4.0 * np.sqrt(3.0)


@njit(inline="always")
def _orient(pts, a, b, c):
    return orient2d(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[c, 0], pts[c, 1])


@njit(inline="always")
def _between(pts, p, a, b):
    """Collinear p lies on the closed segment ab."""
    return (
        min(pts[a, 0], pts[b, 0]) <= pts[p, 0] <= max(pts[a, 0], pts[b, 0])
        and min(pts[a, 1], pts[b, 1]) <= pts[p, 1] <= max(pts[a, 1], pts[b, 1])
    )


@njit(cache=True)
def _meets(pts, p, q, r, s):
    """Segments pq and rs share a point other than a common endpoint (exact)."""
    if p == r or p == s or q == r or q == s:
        # A shared corner: an overlap would put the other end on the segment, which the
        # node-in-triangle test catches.
        return False
    o1 = _orient(pts, p, q, r)
    o2 = _orient(pts, p, q, s)
    if (o1 > 0.0 and o2 > 0.0) or (o1 < 0.0 and o2 < 0.0):
        return False
    o3 = _orient(pts, r, s, p)
    o4 = _orient(pts, r, s, q)
    if (o3 > 0.0 and o4 > 0.0) or (o3 < 0.0 and o4 < 0.0):
        return False
    if o1 == 0.0 and o2 == 0.0:
        return _between(pts, r, p, q) or _between(pts, s, p, q) or _between(pts, p, r, s) or _between(pts, q, r, s)
    return True


@njit(inline="always")
def _to_metric(l11, l21, l22, dx, dy):
    """x' = L^T x, where M = L L^T (Cholesky): |x'| is the metric length of x."""
    return l11 * dx + l21 * dy, l22 * dy


@njit(inline="always")
def _seg_dist2(ux, uy, vx, vy):
    """Squared distance from the origin to segment uv (compared with a squared bound: no
    square root, and no libm call, per node and candidate)."""
    ex = vx - ux
    ey = vy - uy
    den = ex * ex + ey * ey
    t = 0.0 if den == 0.0 else min(1.0, max(0.0, -(ux * ex + uy * ey) / den))
    wx = ux + t * ex
    wy = uy + t * ey
    return wx * wx + wy * wy


@njit(inline="always")
def _boxes_meet(pts, qbox, g, p, q):
    """Whether the closed box of segment pq meets item g's box (exact comparisons)."""
    return not (
        qbox[g, 2] < min(pts[p, 0], pts[q, 0])
        or qbox[g, 0] > max(pts[p, 0], pts[q, 0])
        or qbox[g, 3] < min(pts[p, 1], pts[q, 1])
        or qbox[g, 1] > max(pts[p, 1], pts[q, 1])
    )


@njit(inline="always")
def _behind(pts, a, b, p, v):
    """Node v lies behind face a -> b as seen from point p (exact): p strictly left of the
    face, v strictly right of it and in the closed wedge at p spanned by a and b, so the
    segment p v meets the face.  A front face's left side is unmeshed and its right side
    meshed or outside the domain, so every way from p to v passes a or b."""
    return (
        _orient(pts, a, b, p) > 0.0
        and _orient(pts, a, b, v) < 0.0
        and _orient(pts, p, a, v) >= 0.0
        and _orient(pts, p, b, v) <= 0.0
    )


@njit(inline="always")
def _quality(ax, ay, bx, by, cx, cy):
    """4 sqrt(3) area / sum of squared edges: 1 for an equilateral triangle."""
    area = 0.5 * ((bx - ax) * (cy - ay) - (by - ay) * (cx - ax))
    s = (bx - ax) ** 2 + (by - ay) ** 2 + (cx - bx) ** 2 + (cy - by) ** 2 + (ax - cx) ** 2 + (ay - cy) ** 2
    return _Q * area / s if s > 0.0 else 0.0
