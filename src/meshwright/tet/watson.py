"""Watson's algorithm in 3-D (chapter 18.1.1): tetrahedra plus a list of circumspheres.

Source: D. F. Watson, "Computing the n-dimensional Delaunay tessellation with application to
Voronoi polytopes", The Computer Journal 24(2):167-172, 1981 (chapter 18.1.1, whose 3-D
paragraph replaces circumcircles by circumspheres).

Data structure
--------------
Next to the kernel's ``tet``/``nbr`` (:mod:`meshwright.tet._kernel3d`) one float32 record of
five per tet slot::

    sph[5t : 5t+3]     circumcentre c of finite tet t (float32)
    sph[5t+3], [5t+4]  certified bounds lo <= ... <= hi for the squared-distance test

20 bytes per tet, about 140 bytes per point: Watson's sphere list is what makes it heavier
than Bowyer, whose test needs nothing stored.

Conflict test (a floating-point filter with a rigorous error bound)
-------------------------------------------------------------------
``d2 = |p - c|**2`` in float64; ``d2 < lo`` proves p strictly inside the circumsphere,
``d2 > hi`` proves it strictly outside, anything between goes to Bowyer's exact test
(:func:`meshwright.tet.bowyer.conflict`, ``insphere_sos``).  Ghosts always use the exact
ghost rule.  The filter answers only when the exact sign is certain and nonzero, so every
decision equals Bowyer's and both algorithms build the *same* tetrahedralization.

Bound (eps = 2**-53), the 3-D analogue of :mod:`meshwright.tri.watson`.  The centre is
``u = N / (2 D)`` relative to vertex a, with ``b' = b - a`` (likewise c', d'),
``N = |b'|**2 (c' x d') + |c'|**2 (d' x b') + |d'|**2 (b' x c')`` and
``D = det[b', c', d']``.  Counting the rounding of the differences, squares, products and
sums, each numerator component is within ``12 eps P`` of the exact one (P: the same sum with
absolute values) and D within ``8 eps Q`` (Q its permanent); the code uses 24 eps and 16 eps.
When ``|D| > 4 |dD|`` the computed u is within ``4/3 (|dN| / (2|D|) + (|dD| / |D| + 3 eps) |u|)``
per coordinate; otherwise the tet always goes to the exact test.  Rounding ``a + u`` to the
float32 centre c adds ``2**-23 |c| + 1e-44`` per coordinate; the sum over the coordinates is
Delta >= |c - C|.  For the true centre C and any p,
``|p - C|**2 - R**2 = |p - c|**2 - |a - c|**2 + 2 (c - C).(p - a)`` and the last term is at
most ``eta (d2 + 3 r2)``, ``eta = Delta / sqrt(r2)``, ``r2 = fl(|a - c|**2)``.  With
``tau = 1.01 eta + 16 eps`` the bounds are ``lo = r2 (1 - 3 tau) / (1 + tau)`` and
``hi = r2 (1 + 3 tau) / (1 - tau)``, rounded outwards to float32 (factor ``1 -+ 2**-20``; lo
capped at 1e37 and 0 below 1e-36; hi at least 1e-36, +inf above 1e37).  Tets with
``tau > 0.05`` or a non-finite centre keep ``lo = -1, hi = +inf``: the filter degrades to
Bowyer, never to a wrong answer (points far from the origin relative to their spacing, e.g.
a 1e9 offset, take that path).

Search
------
The chapter's step 3 scans every tet; here the deleted tets form a connected cavity around
the tet that contains the point, found by the kernel's walk and breadth-first search, in
time proportional to its size.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.flat import GHOST
from meshwright.tet import bowyer

__all__ = ["conflict", "filter_sign", "sphere", "RECORD"]

RECORD = 5  # float32 entries per tet slot
_EPS = 2.0**-53
_EPS32 = 2.0**-23
_TINY32 = 1e-44
_F32_OUT = 2.0**-20
_F32_TINY = 1e-36
_F32_HUGE = 1e37


@njit(inline="always")
def filter_sign(tet, sph, t, px, py, pz):
    """The distance filter alone: +1 proven inside tet t's circumsphere, -1 outside, 0 unsure.

    Parameters
    ----------
    tet : (4 cap,) int32
    sph : (5 cap,) float32
        Sphere records ``(cx, cy, cz, lo, hi)``.
    t : int
        Tet; ghosts are always unsure (their rule is exact, :mod:`meshwright.tet.bowyer`).
    px, py, pz : float

    Returns
    -------
    int
    """
    if tet[4 * t + 3] == GHOST:
        return 0
    s5 = 5 * t
    dx = px - np.float64(sph[s5])
    dy = py - np.float64(sph[s5 + 1])
    dz = pz - np.float64(sph[s5 + 2])
    d2 = dx * dx + dy * dy + dz * dz
    if d2 < sph[s5 + 3]:
        return 1
    if d2 > sph[s5 + 4]:
        return -1
    return 0


@njit(inline="always")
def conflict(pts, tet, nbr, sph, rank, t, v, px, py, pz):
    """Whether tet t's circumball contains the new point v: distance filter, exact fallback.

    Parameters
    ----------
    pts : (rows, 3) float64
    tet, nbr : (4 cap,) int32
    sph : (5 cap,) float32
    rank : (r,) int32
    t, v : int
    px, py, pz : float
        ``pts[v]``.

    Returns
    -------
    bool
        Always the value of :func:`meshwright.tet.bowyer.conflict`.
    """
    f = filter_sign(tet, sph, t, px, py, pz)
    if f != 0:
        return f > 0
    return bowyer.conflict(pts, tet, nbr, rank, t, v, px, py, pz)


@njit(inline="always")
def sphere(pts, tet, sph, t):
    """Store the circumcentre and certified squared-radius bounds of the new tet t.

    Parameters
    ----------
    pts : (rows, 3) float64
    tet : (4 cap,) int32
    sph : (5 cap,) float32
        Output: ``sph[5t : 5t+5]``; ``lo = -1, hi = inf`` sends every test to the exact
        predicate.  Ghost tets are given that record too.
    t : int
    """
    s5 = 5 * t
    sph[s5] = 0.0
    sph[s5 + 1] = 0.0
    sph[s5 + 2] = 0.0
    sph[s5 + 3] = -1.0
    sph[s5 + 4] = np.inf
    b4 = 4 * t
    d = tet[b4 + 3]
    if d == GHOST:
        return
    a = tet[b4]
    b = tet[b4 + 1]
    c = tet[b4 + 2]
    ax = pts[a, 0]
    ay = pts[a, 1]
    az = pts[a, 2]
    bx = pts[b, 0] - ax
    by = pts[b, 1] - ay
    bz = pts[b, 2] - az
    cx = pts[c, 0] - ax
    cy = pts[c, 1] - ay
    cz = pts[c, 2] - az
    dx = pts[d, 0] - ax
    dy = pts[d, 1] - ay
    dz = pts[d, 2] - az
    bb = bx * bx + by * by + bz * bz
    cc = cx * cx + cy * cy + cz * cz
    dd = dx * dx + dy * dy + dz * dz
    # cross products c' x d', d' x b', b' x c' and their permanents
    cdx1 = cy * dz
    cdx2 = cz * dy
    cdy1 = cz * dx
    cdy2 = cx * dz
    cdz1 = cx * dy
    cdz2 = cy * dx
    dbx1 = dy * bz
    dbx2 = dz * by
    dby1 = dz * bx
    dby2 = dx * bz
    dbz1 = dx * by
    dbz2 = dy * bx
    bcx1 = by * cz
    bcx2 = bz * cy
    bcy1 = bz * cx
    bcy2 = bx * cz
    bcz1 = bx * cy
    bcz2 = by * cx
    det = bx * (cdx1 - cdx2) + by * (cdy1 - cdy2) + bz * (cdz1 - cdz2)
    q = abs(bx) * (abs(cdx1) + abs(cdx2)) + abs(by) * (abs(cdy1) + abs(cdy2)) + abs(bz) * (abs(cdz1) + abs(cdz2))
    ddet = 16.0 * _EPS * q
    if not abs(det) > 4.0 * ddet:
        return
    nx = bb * (cdx1 - cdx2) + cc * (dbx1 - dbx2) + dd * (bcx1 - bcx2)
    ny = bb * (cdy1 - cdy2) + cc * (dby1 - dby2) + dd * (bcy1 - bcy2)
    nz = bb * (cdz1 - cdz2) + cc * (dbz1 - dbz2) + dd * (bcz1 - bcz2)
    px_ = bb * (abs(cdx1) + abs(cdx2)) + cc * (abs(dbx1) + abs(dbx2)) + dd * (abs(bcx1) + abs(bcx2))
    py_ = bb * (abs(cdy1) + abs(cdy2)) + cc * (abs(dby1) + abs(dby2)) + dd * (abs(bcy1) + abs(bcy2))
    pz_ = bb * (abs(cdz1) + abs(cdz2)) + cc * (abs(dbz1) + abs(dbz2)) + dd * (abs(bcz1) + abs(bcz2))
    inv = 0.5 / det
    ux = nx * inv
    uy = ny * inv
    uz = nz * inv
    beta = ddet / abs(det) + 3.0 * _EPS
    ainv = abs(inv)
    ex = (24.0 * _EPS * px_ * ainv + beta * abs(ux)) * (4.0 / 3.0)
    ey = (24.0 * _EPS * py_ * ainv + beta * abs(uy)) * (4.0 / 3.0)
    ez = (24.0 * _EPS * pz_ * ainv + beta * abs(uz)) * (4.0 / 3.0)
    ox32 = np.float32(ax + ux)
    oy32 = np.float32(ay + uy)
    oz32 = np.float32(az + uz)
    ox = np.float64(ox32)
    oy = np.float64(oy32)
    oz = np.float64(oz32)
    if not (abs(ox) < np.inf and abs(oy) < np.inf and abs(oz) < np.inf):
        return
    rx = ax - ox
    ry = ay - oy
    rz = az - oz
    r2 = rx * rx + ry * ry + rz * rz
    if not (r2 > 0.0 and r2 < np.inf):
        return
    delta = ex + ey + ez + _EPS32 * (abs(ox) + abs(oy) + abs(oz)) + 3.0 * _TINY32
    tau = 1.01 * delta / np.sqrt(r2) + 16.0 * _EPS
    if not tau <= 0.05:
        return
    lo = r2 * (1.0 - 3.0 * tau) / (1.0 + tau) * (1.0 - _F32_OUT)
    hi = r2 * (1.0 + 3.0 * tau) / (1.0 - tau) * (1.0 + _F32_OUT)
    sph[s5] = ox32
    sph[s5 + 1] = oy32
    sph[s5 + 2] = oz32
    sph[s5 + 3] = 0.0 if lo < _F32_TINY else min(lo, _F32_HUGE)
    sph[s5 + 4] = np.inf if hi > _F32_HUGE else max(hi, _F32_TINY)
