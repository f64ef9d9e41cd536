r"""Inline floating-point 2-D geometry for the ``@njit`` kernels (constructions, not predicates).

Everything here *constructs* (a circumcentre, a closest point) in floating point; no
topological decision may rest on it: those use the exact predicates of
:mod:`meshwright.core.predicates`, which :func:`orient_filtered` only fronts with Shewchuk's
stage-A filter (J. R. Shewchuk, "Adaptive precision floating-point arithmetic and fast robust
geometric predicates", Discrete Comput. Geom. 18, 1997), returning the exact sign whenever
the filter cannot certify it.

Circumcentres are computed relative to the first vertex (the classical formula, e.g.
Shewchuk's Triangle), which keeps the rounding error relative to the triangle's size::

    u = b - a,  w = c - a,  d = 2 (u x w)
    centre = a + ( w_y |u|^2 - u_y |w|^2 ,  u_x |w|^2 - w_x |u|^2 ) / d

The functions over scalars are plain ``@njit``: they are called once per triangle or per
step of a hot loop, where LLVM inlines them (checked on the insertion kernel's machine code);
Numba's IR inlining (``inline="always"``) would only add first-run compile time.  Those only
kernels call (:func:`orient_filtered`, :func:`circumcentre_offset`) are compiled without the
Python wrappers (:mod:`meshwright.core.jit`).
:func:`corners` takes arrays and stays ``inline="always"``: a call would cost a
reference-count pair per array.

:func:`off_centre`: A. Üngör, "Off-centers: a new type of Steiner points for computing
size-optimal quality-guaranteed Delaunay triangulations", LATIN 2004.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.jit import inner
from meshwright.core.predicates import CCW_ERRBOUND_A, orient2d

__all__ = [
    "corners", "orient_filtered", "circumcentre_offset", "circumcentre", "circumcircle", "off_centre",
    "closest_on_segment", "segment_dist2",
]


@njit(inline="always")
def corners(pts, tri, t):
    """Coordinates ``(ax, ay, bx, by, cx, cy)`` of the vertices of flat triangle slot t."""
    a = tri[3 * t]
    b = tri[3 * t + 1]
    c = tri[3 * t + 2]
    return pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[c, 0], pts[c, 1]


@inner
def orient_filtered(ax, ay, bx, by, cx, cy):
    """``orient2d`` with its stage-A filter inlined: same sign, exact predicate only if unsure."""
    left = (ax - cx) * (by - cy)
    right = (ay - cy) * (bx - cx)
    det = left - right
    err = CCW_ERRBOUND_A * (abs(left) + abs(right))
    if det > err or -det > err:
        return det
    return orient2d(ax, ay, bx, by, cx, cy)


@inner
def circumcentre_offset(ux, uy, wx, wy):
    """Circumcentre of the triangle (0, 0), u, w, relative to the origin (u x w != 0)."""
    uu = ux * ux + uy * uy
    ww = wx * wx + wy * wy
    inv = 0.5 / (ux * wy - uy * wx)
    return (wy * uu - uy * ww) * inv, (ux * ww - wx * uu) * inv


@njit(cache=True)
def circumcentre(ax, ay, bx, by, cx, cy):
    """Circumcentre of a non-degenerate triangle abc, computed relative to a."""
    ox, oy = circumcentre_offset(bx - ax, by - ay, cx - ax, cy - ay)
    return ax + ox, ay + oy


@njit(cache=True)
def circumcircle(ax, ay, bx, by, cx, cy):
    """Circumcentre and circumradius ``(x, y, r)`` of a non-degenerate triangle abc."""
    ox, oy = circumcentre_offset(bx - ax, by - ay, cx - ax, cy - ay)
    return ax + ox, ay + oy, np.hypot(ox, oy)


@njit(cache=True)
def off_centre(ax, ay, bx, by, cx, cy, off):
    """Üngör's off-centre of the counter-clockwise triangle abc, or its circumcentre if nearer.

    On the bisector of the shortest edge pq, at ``off * |pq|`` from its midpoint towards the
    third vertex (the apex of the isosceles triangle on pq whose apex angle is the quality
    bound); the circumcentre when that is nearer to pq, or when ``off <= 0``.
    """
    ox, oy = circumcentre(ax, ay, bx, by, cx, cy)
    if off <= 0.0:
        return ox, oy
    l0 = (cx - bx) ** 2 + (cy - by) ** 2
    l1 = (ax - cx) ** 2 + (ay - cy) ** 2
    l2 = (bx - ax) ** 2 + (by - ay) ** 2
    if l0 <= l1 and l0 <= l2:
        px, py, qx, qy = bx, by, cx, cy
    elif l1 <= l2:
        px, py, qx, qy = cx, cy, ax, ay
    else:
        px, py, qx, qy = ax, ay, bx, by
    # Left normal of p -> q points into the counter-clockwise triangle.
    fx = 0.5 * (px + qx) - off * (qy - py)
    fy = 0.5 * (py + qy) + off * (qx - px)
    if (fx - px) ** 2 + (fy - py) ** 2 < (ox - px) ** 2 + (oy - py) ** 2:
        return fx, fy
    return ox, oy


@njit(cache=True)
def closest_on_segment(ax, ay, bx, by, x, y):
    """Point of the segment ab nearest (x, y) (a when a == b)."""
    ex = bx - ax
    ey = by - ay
    den = ex * ex + ey * ey
    u = 0.0 if den == 0.0 else min(1.0, max(0.0, ((x - ax) * ex + (y - ay) * ey) / den))
    return ax + u * ex, ay + u * ey


@njit(cache=True)
def segment_dist2(ax, ay, bx, by, x, y):
    """Squared distance from (x, y) to the segment ab: the test of the disc searches that
    flood the triangles a disc reaches (an edge farther than r keeps the disc out)."""
    cx, cy = closest_on_segment(ax, ay, bx, by, x, y)
    return (cx - x) ** 2 + (cy - y) ** 2
