"""Watson's algorithm (chapter 18.1.1): triangle list plus a running list of circumcircles.

Source: D. F. Watson, "Computing the n-dimensional Delaunay tessellation with application to
Voronoi polytopes", The Computer Journal 24(2):167-172, 1981 (chapter 18.1.1, Figures
18.1.3 and 18.1.5).

Data structure
--------------
Watson keeps the list of triangles (node triplets) and, for each, its circumcentre and
circumradius, and decides whether a new point deletes a triangle by comparing its distance
from the circumcentre with the radius.  Here, next to the kernel's ``tri``/``nbr``
(:mod:`meshwright.tri._kernel2d`), one float32 record of four per triangle slot::

    circ[4t], circ[4t+1]     circumcentre c of finite triangle t (float32)
    circ[4t+2], circ[4t+3]   certified bounds lo <= ... <= hi for the squared radius test

16 bytes per triangle: the circle list costs about 32 bytes per point.

Conflict test (a floating-point filter with a rigorous error bound)
-------------------------------------------------------------------
``d2 = |p - c|**2`` in float64; ``d2 < lo`` proves p strictly inside the circumcircle,
``d2 > hi`` proves it strictly outside, anything between is decided by Bowyer's exact test
(:func:`meshwright.tri.bowyer.conflict`, ``incircle_sos`` on the three vertices).  Ghost
triangles always use the exact ghost rule.  Because the filter only answers when the exact
sign is certain and nonzero, every decision equals Bowyer's and both algorithms build the
*same* triangulation (same insertion order, same walk, same slots).

Bound (eps = 2**-53).  The centre is computed relative to vertex a,
``u = (cy' B - by' C, bx' C - cx' B) / (2 D)`` with ``b' = b - a``, ``c' = c - a``,
``B = |b'|**2``, ``C = |c'|**2``, ``D = bx' cy' - by' cx'``.  Forward error analysis gives
``|dN| <= 8 eps P`` for each numerator (P its permanent) and ``|dD| <= 5 eps Q`` (Q the
permanent of D); when ``|D| > 4 |dD|`` the computed u is within
``4/3 (|dN| / (2|D|) + (|dD| / |D| + 3 eps) |u|)`` of the exact one per coordinate (otherwise
the triangle is always sent to the exact test).  Rounding ``a + u`` to the stored float32
centre c adds at most ``2**-23 |c| + 1e-44`` per coordinate; the sum of all this is Delta.
For the true centre C and any p, ``|p - C|**2 - R**2 = |p - c|**2 - |a - c|**2 + 2 (c - C).(p - a)``;
with ``|p - a| <= |p - c| + |a - c|`` and ``2 sqrt(d2 r2) <= d2 + r2`` the last term is at most
``eta (d2 + 3 r2)`` with ``eta = Delta / sqrt(r2)``, ``r2 = fl(|a - c|**2)``.  With
``tau = 1.01 eta + 16 eps`` (rounding of d2, r2 and of this arithmetic) the bounds are
``lo = r2 (1 - 3 tau) / (1 + tau)`` and ``hi = r2 (1 + 3 tau) / (1 - tau)``, rounded outwards to
float32 (a factor ``1 -+ 2**-20``; lo capped at 1e37 and raised to 0 below 1e-36, hi raised to
1e-36 and to +inf above 1e37).  Triangles with ``tau > 0.05`` or a non-finite centre keep
``lo = -1, hi = +inf`` and always go to the exact test: the filter degrades to Bowyer, never
to a wrong answer.  Coordinates far from the origin relative to the point spacing (beyond
about 1e5 spacings) make tau large for that reason.

Search
------
The chapter's step 3 scans *all* triangles for those whose circumdisk contains the new point,
O(n) per point.  Here the deleted triangles form a connected cavity around the triangle that
contains the point, so a walk locates that triangle and the cavity grows from it over
neighbours (:func:`meshwright.tri._kernel2d.insert_vertex`): the same set, found in time
proportional to its size.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.flat import GHOST
from meshwright.core.geom2d import circumcentre_offset
from meshwright.tri import bowyer

__all__ = ["circle", "conflict", "filter_sign"]

_EPS = 2.0**-53
_EPS32 = 2.0**-23  # relative rounding to the stored float32 centre, with margin
_TINY32 = 1e-44  # absolute rounding of float32 subnormals
_F32_OUT = 2.0**-20  # outward rounding margin of the float32 bounds
_F32_TINY = 1e-36  # below this, float32 rounding is not relative any more
_F32_HUGE = 1e37  # float32 range ends at 3.4e38: lo is capped here, larger hi becomes +inf


@njit(cache=True, inline="always")
def conflict(pts, tri, circ, rank, t, v, px, py):
    """Whether triangle t's circumdisk contains the new point v: distance filter, exact fallback.

    Parameters
    ----------
    pts : (rows, 2) float64
    tri : (3 cap,) int32
    circ : (4 cap,) float32
        Circle records ``(cx, cy, lo, hi)``.
    rank : (r,) int32
        Perturbation keys, for the exact fallback.
    t : int
        Triangle (finite or ghost).
    v : int
        The new vertex, ``pts[v] == (px, py)``.
    px, py : float

    Returns
    -------
    bool
        Always the value of :func:`meshwright.tri.bowyer.conflict`.
    """
    f = filter_sign(tri, circ, t, px, py)
    if f != 0:
        return f > 0
    return bowyer.conflict(pts, tri, rank, t, v, px, py)


@njit(inline="always")
def filter_sign(tri, circ, t, px, py):
    """The distance filter alone: +1 proven inside triangle t's circumdisk, -1 outside, 0 unsure.

    The insertion kernel runs it before the one inlined copy of
    :func:`meshwright.tri.bowyer.conflict` that serves both algorithms (a second copy inlined
    through :func:`conflict` cost first-run compile time for nothing).

    Parameters
    ----------
    tri : (3 cap,) int32
    circ : (4 cap,) float32
        Circle records ``(cx, cy, lo, hi)``.
    t : int
        Triangle; ghosts are always unsure (their rule is exact, :mod:`meshwright.tri.bowyer`).
    px, py : float

    Returns
    -------
    int
    """
    if tri[3 * t + 2] == GHOST:
        return 0
    c4 = 4 * t
    dx = px - np.float64(circ[c4])
    dy = py - np.float64(circ[c4 + 1])
    d2 = dx * dx + dy * dy
    if d2 < circ[c4 + 2]:
        return 1
    if d2 > circ[c4 + 3]:
        return -1
    return 0


@njit(cache=True)
def circle(pts, tri, circ, t):
    """Store the circumcentre and certified squared-radius bounds of a new triangle t.

    Parameters
    ----------
    pts : (rows, 2) float64
    tri : (3 cap,) int32
    circ : (4 cap,) float32
        Output: ``circ[4t : 4t+4] = (cx, cy, lo, hi)``; ``lo = -1, hi = inf`` sends every test
        to the exact predicate.
    t : int
        Triangle; ghosts are skipped.
    """
    b3 = 3 * t
    if tri[b3 + 2] == GHOST:
        return
    c4 = 4 * t
    a = tri[b3]
    b = tri[b3 + 1]
    c = tri[b3 + 2]
    ax = pts[a, 0]
    ay = pts[a, 1]
    bx = pts[b, 0] - ax
    by = pts[b, 1] - ay
    cx = pts[c, 0] - ax
    cy = pts[c, 1] - ay
    bb = bx * bx + by * by
    cc = cx * cx + cy * cy
    d = bx * cy - by * cx
    dd = 5.0 * _EPS * (abs(bx * cy) + abs(by * cx))
    circ[c4] = 0.0
    circ[c4 + 1] = 0.0
    circ[c4 + 2] = -1.0
    circ[c4 + 3] = np.inf
    if not abs(d) > 4.0 * dd:
        return
    inv = 0.5 / d
    ux, uy = circumcentre_offset(bx, by, cx, cy)
    beta = dd / abs(d) + 3.0 * _EPS
    ex = (8.0 * _EPS * (abs(cy) * bb + abs(by) * cc) * abs(inv) + beta * abs(ux)) * (4.0 / 3.0)
    ey = (8.0 * _EPS * (abs(bx) * cc + abs(cx) * bb) * abs(inv) + beta * abs(uy)) * (4.0 / 3.0)
    ox32 = np.float32(ax + ux)
    oy32 = np.float32(ay + uy)
    ox = np.float64(ox32)
    oy = np.float64(oy32)
    if not (abs(ox) < np.inf and abs(oy) < np.inf):
        return
    rx = ax - ox
    ry = ay - oy
    r2 = rx * rx + ry * ry
    if not (r2 > 0.0 and r2 < np.inf):
        return
    delta = ex + ey + _EPS32 * (abs(ox) + abs(oy)) + 2.0 * _TINY32
    tau = 1.01 * delta / np.sqrt(r2) + 16.0 * _EPS
    if not tau <= 0.05:
        return
    lo = r2 * (1.0 - 3.0 * tau) / (1.0 + tau) * (1.0 - _F32_OUT)
    hi = r2 * (1.0 + 3.0 * tau) / (1.0 - tau) * (1.0 + _F32_OUT)
    circ[c4] = ox32
    circ[c4 + 1] = oy32
    circ[c4 + 2] = 0.0 if lo < _F32_TINY else min(lo, _F32_HUGE)
    circ[c4 + 3] = np.inf if hi > _F32_HUGE else max(hi, _F32_TINY)
