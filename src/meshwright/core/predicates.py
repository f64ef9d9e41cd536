"""Robust geometric predicates with exact signs: orientation, in-circle, in-sphere, SoS.

The 2-D predicates and the expansion helpers they share with 3-D live here; the 3-D ones
(``orient3d``, ``insphere``, their filters, ``insphere_sos``, ``orient3d_batch``) are in
:mod:`meshwright.core.predicates3d` and importable from this module too (loaded on first use).

Sources
-------
* J. R. Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast Robust Geometric
  Predicates", Discrete & Computational Geometry 18(3):305-363, 1997.  Floating-point
  filters with his a-priori forward error bounds (``ccwerrboundA``, ``iccerrboundA``,
  ``o3derrboundA``, ``isperrboundA``), exact fallback in expansion arithmetic
  (:mod:`meshwright.core.expansion`).
* H. Edelsbrunner and E. P. Mücke, "Simulation of Simplicity: A Technique to Cope with
  Degenerate Cases in Geometric Algorithms", ACM Transactions on Graphics 9(1):66-104, 1990.
* O. Devillers and M. Teillaud, "Perturbations for Delaunay and weighted Delaunay 3D
  triangulations", Computational Geometry 44(3):160-168, 2011: perturbing only the lifted
  coordinate ``|p|**2`` leaves every orientation unperturbed and still yields a Delaunay
  triangulation of the unperturbed points.

Sign contracts
--------------
The **sign** is exact; the magnitude is only an approximation.

* ``orient2d(a, b, c) > 0``  iff a, b, c are counter-clockwise;
  it approximates ``det[b - a, c - a]`` (twice the signed area).
* ``incircle(a, b, c, d) > 0`` iff d is strictly inside the circle through a, b, c when a, b, c
  are counter-clockwise; the sign flips when a, b, c are clockwise (Shewchuk's convention).
  It is alternating in all four arguments.
* ``orient3d(a, b, c, d) > 0`` iff ``det[b - a, c - a, d - a] > 0`` (positive tetrahedron
  volume, CGAL's convention).  **This is the OPPOSITE sign of Shewchuk's C orient3d**, which
  is positive when d lies *below* the plane of counter-clockwise a, b, c.
* ``insphere(a, b, c, d, e) > 0`` iff e is strictly inside the sphere through a, b, c, d when
  ``orient3d(a, b, c, d) > 0`` (so also the opposite sign of Shewchuk's C insphere).
  It is alternating in all five arguments.

Exactness holds for finite inputs whose intermediate products neither overflow nor underflow.
A sufficient condition for all four predicates: every nonzero coordinate has magnitude in
``[2**-148, 2**200]`` (about 2.8e-45 .. 1.6e60).  Then all coordinates are multiples of
``2**-200``, so every nonzero expansion component (a multiple of the product of at most five
such granules) stays above ``2**-1000``, and degree-5 terms stay below ``2**1013``.  NaN/inf
inputs give unspecified results.

Invariants
----------
* Two stages.  The filter evaluates the determinant in plain doubles in Shewchuk's order and
  returns it when ``|det|`` exceeds ``errbound * permanent``; it allocates nothing.  Otherwise
  the exact stage recomputes the determinant from exact coordinate differences (two-component
  expansions) and returns the exact value rounded to a double, never flipping its sign.
  Between the two, ``orient2d`` and ``incircle`` run the cheap exact stages of
  :mod:`meshwright.core.exact_stages2d`: an error-free evaluation that proves the sign (and
  exact zeros) when every operation is exact (grids), and, for ``incircle``, a double-word
  filter for near-degenerate inputs (points on a circle); ``insphere`` runs the same
  double-word filter (:func:`insphere_dd`) before its expansions (points on a sphere).
  Shewchuk's stages B/C are not implemented.
* Exactly degenerate inputs return exactly ``0.0``; the SoS variants return ``0`` only in the
  documented fully degenerate cases.
* All kernels are ``@njit(cache=True)`` and take scalars (batch helpers take arrays).

Symbolic perturbation
---------------------
``incircle_sos`` / ``insphere_sos`` evaluate the predicate on lifted points
``(p, |p|**2 + delta_i)`` where the point with global index ``i`` gets ``delta_i = eps**(N - i)``
for an infinitesimal ``eps > 0`` (``N`` larger than every index), so a larger index means a
larger perturbation.  The lifted determinant is linear in the lift column, so on an exact zero
its sign is the sign of the lift-column cofactor of the largest-index point, then of the next
largest if that cofactor vanishes, and so on.  Those cofactors are unperturbed orientations;
raising a point's lift moves it *outside*, so for the query point the cofactor sign is
``-orient(a, b, c[, d])`` and for any other point it is the orientation with the query point
put in that point's place.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from meshwright.core.exact_stages2d import incircle_dd, incircle_eft, orient2d_eft
from meshwright.core.expansion import (
    EPSILON,
    diff_into,
    estimate,
    expansion_sum,
    mul_small,
)
from meshwright.core.jit import inner

__all__ = [  # the 3-D names come from predicates3d through __getattr__ below
    "CCW_ERRBOUND_A",
    "ICC_ERRBOUND_A",
    "ISP_ERRBOUND_A",  # noqa: F822
    "O3D_ERRBOUND_A",  # noqa: F822
    "incircle",
    "incircle_sos",
    "incircle_stage_a",
    "insphere",  # noqa: F822
    "insphere_dd",  # noqa: F822
    "insphere_sos",  # noqa: F822
    "insphere_stage_a",  # noqa: F822
    "orient2d",
    "orient2d_batch",
    "orient3d",  # noqa: F822
    "orient3d_batch",  # noqa: F822
    "orient3d_stage_a",  # noqa: F822
]

# A-priori relative forward error bounds of the plain floating-point evaluations below
# (Shewchuk 1997, Sec. 4): |computed - exact| <= bound * permanent, where the permanent is the
# same expression with every product replaced by its absolute value.
CCW_ERRBOUND_A = (3.0 + 16.0 * EPSILON) * EPSILON
ICC_ERRBOUND_A = (10.0 + 96.0 * EPSILON) * EPSILON


# Helpers that take constant offsets carry explicit signatures so that Numba does not compile
# one literal-typed specialisation per call site.
@inner("int64(float64[::1], " + ", ".join(["int64"] * 12) + ")")
def _minor2(w, pxo, npx, qyo, nqy, qxo, nqx, pyo, npy, ho, t1, t2, so):
    """``w[ho:] = px * qy - qx * py`` for factors of <= 2 components: <= 8 + 8 = 16.

    ``t1``, ``t2`` are 8-slot and ``so`` an 8-slot scratch region.
    """
    n1 = mul_small(w, pxo, npx, qyo, nqy, 1.0, t1, so)
    n2 = mul_small(w, qxo, nqx, pyo, npy, 1.0, t2, so)
    return expansion_sum(w, t1, n1, t2, n2, -1.0, ho)


@inner("int64(float64[::1], int64, int64, int64, int64, int64, int64, int64)")
def _square_times(w, mo, mlen, xo, nx, ho, to, so):
    """``w[ho:] = x * (x * m)``: <= 16 mlen slots at ``ho``, 4 mlen at ``to``, 16 mlen at ``so``.

    Scaling twice by the short difference beats forming ``x**2`` and multiplying two long
    expansions: no merge grows beyond the final length.
    """
    n = mul_small(w, mo, mlen, xo, nx, 1.0, to, so)
    return mul_small(w, to, n, xo, nx, 1.0, ho, so)


# ----------------------------------------------------------------------------------------
# orient2d
# ----------------------------------------------------------------------------------------
@nb.njit(cache=True)
def _orient2d_exact(ax, ay, bx, by, cx, cy):
    """Exact ``(a-c)x (b-c)y - (a-c)y (b-c)x`` as an expansion, rounded."""
    # Regions: 4 differences (2 each) at 0..8, products at 8 and 16, scratch at 24,
    # result (<= 16) at 32.
    w = np.empty(48)
    nacx = diff_into(ax, cx, w, 0)
    nacy = diff_into(ay, cy, w, 2)
    nbcx = diff_into(bx, cx, w, 4)
    nbcy = diff_into(by, cy, w, 6)
    n = _minor2(w, 0, nacx, 6, nbcy, 4, nbcx, 2, nacy, 32, 8, 16, 24)
    return estimate(w, 32, n)


@nb.njit(cache=True)
def orient2d(ax, ay, bx, by, cx, cy):
    """Orientation of three points in the plane, with exact sign.

    Parameters
    ----------
    ax, ay, bx, by, cx, cy : float
        Coordinates of a, b, c.

    Returns
    -------
    float
        Positive if a, b, c are counter-clockwise, negative if clockwise, exactly 0.0 if
        collinear.  The magnitude approximates twice the signed triangle area.
    """
    detleft = (ax - cx) * (by - cy)
    detright = (ay - cy) * (bx - cx)
    det = detleft - detright
    # If the two products have opposite signs (or one is zero), the subtraction cannot
    # cancel and the sign of det is already the sign of the exact value.
    if detleft > 0.0:
        if detright <= 0.0:
            return det
        detsum = detleft + detright
    elif detleft < 0.0:
        if detright >= 0.0:
            return det
        detsum = -detleft - detright
    else:
        return det
    errbound = CCW_ERRBOUND_A * detsum
    if det >= errbound or -det >= errbound:
        return det
    det, proven = orient2d_eft(ax, ay, bx, by, cx, cy)
    if proven:
        return det
    return _orient2d_exact(ax, ay, bx, by, cx, cy)


# ----------------------------------------------------------------------------------------
# incircle
# ----------------------------------------------------------------------------------------
@nb.njit(cache=True)
def _incircle_exact(ax, ay, bx, by, cx, cy, dx, dy):
    """Exact lifted 3x3 determinant relative to d, as an expansion, rounded.

    ``det = sum_p |p - d|**2 * minor_p`` over p = a, b, c with ``minor_p`` the 2x2
    determinant of the cyclic successors of p.  Lengths: differences 2, minor 16,
    ``x * (x * minor)`` 256, one lifted term 512, the sum of three 1536.
    """
    # Regions (offsets): differences 0 (p - d at 4p: x, then y), minor 12, t1 28, t2 36,
    # x * minor 44 (64), scratch 108 (256), x-square 364 (256), y-square 620 (256),
    # term 876 (512), two accumulators 1388 and 2924 (1536 each).
    w = np.empty(4460)
    nd = (
        diff_into(ax, dx, w, 0),
        diff_into(ay, dy, w, 2),
        diff_into(bx, dx, w, 4),
        diff_into(by, dy, w, 6),
        diff_into(cx, dx, w, 8),
        diff_into(cy, dy, w, 10),
    )
    acc = 1388
    nxt = 2924
    n = 0
    for p in range(3):
        q = (p + 1) % 3
        r = (p + 2) % 3
        m = _minor2(
            w, 4 * q, nd[2 * q], 4 * r + 2, nd[2 * r + 1], 4 * r, nd[2 * r],
            4 * q + 2, nd[2 * q + 1], 12, 28, 36, 108,
        )
        nx = _square_times(w, 12, m, 4 * p, nd[2 * p], 364, 44, 108)
        ny = _square_times(w, 12, m, 4 * p + 2, nd[2 * p + 1], 620, 44, 108)
        k = expansion_sum(w, 364, nx, 620, ny, 1.0, 876)
        n = expansion_sum(w, acc, n, 876, k, 1.0, nxt)
        acc, nxt = nxt, acc
    return estimate(w, acc, n)


@inner
def incircle_stage_a(ax, ay, bx, by, cx, cy, dx, dy):
    """Shewchuk's stage-A in-circle filter: ``(det, err)``, the floating-point determinant
    (the sign of :func:`incircle`) and its a-priori error bound.

    ``|det| > err`` proves the sign of ``det``; otherwise only the exact predicate decides.
    Inlined into :func:`incircle` and the kernels that filter before the perturbed
    predicate, so all of them evaluate the one proven expression.
    """
    adx = ax - dx
    bdx = bx - dx
    cdx = cx - dx
    ady = ay - dy
    bdy = by - dy
    cdy = cy - dy

    bdxcdy = bdx * cdy
    cdxbdy = cdx * bdy
    alift = adx * adx + ady * ady

    cdxady = cdx * ady
    adxcdy = adx * cdy
    blift = bdx * bdx + bdy * bdy

    adxbdy = adx * bdy
    bdxady = bdx * ady
    clift = cdx * cdx + cdy * cdy

    det = alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy) + clift * (adxbdy - bdxady)
    permanent = (
        (abs(bdxcdy) + abs(cdxbdy)) * alift
        + (abs(cdxady) + abs(adxcdy)) * blift
        + (abs(adxbdy) + abs(bdxady)) * clift
    )
    return det, ICC_ERRBOUND_A * permanent


@nb.njit(cache=True)
def incircle(ax, ay, bx, by, cx, cy, dx, dy):
    """In-circle test with exact sign.

    Parameters
    ----------
    ax, ay, bx, by, cx, cy : float
        Three points defining a circle.
    dx, dy : float
        Query point.

    Returns
    -------
    float
        Positive if d is strictly inside the circle through a, b, c and a, b, c are
        counter-clockwise (negative if outside); the sign flips if a, b, c are clockwise.
        Exactly 0.0 if the four points are cocircular (or a, b, c collinear and d on the line).
    """
    det, errbound = incircle_stage_a(ax, ay, bx, by, cx, cy, dx, dy)
    if det > errbound or -det > errbound:
        return det
    det, proven = incircle_eft(ax, ay, bx, by, cx, cy, dx, dy)
    if proven:
        return det
    det, proven = incircle_dd(ax, ay, bx, by, cx, cy, dx, dy)
    if proven:
        return det
    return _incircle_exact(ax, ay, bx, by, cx, cy, dx, dy)


# ----------------------------------------------------------------------------------------
# symbolic perturbation of the lifted coordinate
# ----------------------------------------------------------------------------------------
@inner("int64(int64, int64, int64, int64, int64, int64)")
def _rank_desc(i0, i1, i2, i3, i4, k):
    """Position (0-based, 0 = largest index) of argument ``k`` among the given indices.

    Ties, which the contract excludes, are broken by argument position so the order is
    still total and the result deterministic.
    """
    idx = (i0, i1, i2, i3, i4)
    me = idx[k]
    r = 0
    for j in range(5):
        if j != k and (idx[j] > me or (idx[j] == me and j < k)):
            r += 1
    return r


@nb.njit(cache=True)
def incircle_sos(ax, ay, bx, by, cx, cy, dx, dy, ia, ib, ic, id):
    """In-circle test under symbolic perturbation of the lifted coordinate; never 0 in practice.

    Parameters
    ----------
    ax, ay, bx, by, cx, cy, dx, dy : float
        As in :func:`incircle`.
    ia, ib, ic, id : int
        Distinct global indices of a, b, c, d; they define the perturbation.

    Returns
    -------
    int
        ``+1`` or ``-1``: the sign of :func:`incircle` when it is nonzero, otherwise the sign
        for the perturbed lifts ``|p|**2 + eps**(N - index)`` (larger index, larger
        perturbation).  Returns 0 only when every cofactor consulted vanishes, which needs
        a, b, c collinear (otherwise the cofactor of d, ``-orient2d(a, b, c)``, decides).
        Like :func:`incircle`, it is alternating: swapping two points together with their
        indices flips the result.
    """
    det = incircle(ax, ay, bx, by, cx, cy, dx, dy)
    if det > 0.0:
        return 1
    if det < 0.0:
        return -1
    if id > ia and id > ib and id > ic:
        # The query point's cofactor comes first: what an insertion kernel meets, the new
        # vertex having the largest key, decided by one orientation.
        o = orient2d(ax, ay, bx, by, cx, cy)
        if o > 0.0:
            return -1
        if o < 0.0:
            return 1
    # Lowest sentinel for the unused fifth slot so it never outranks a real point.
    lowest = min(min(ia, ib), min(ic, id)) - 1
    for r in range(4):
        if _rank_desc(ia, ib, ic, id, lowest, 0) == r:
            o = orient2d(dx, dy, bx, by, cx, cy)
        elif _rank_desc(ia, ib, ic, id, lowest, 1) == r:
            o = orient2d(ax, ay, dx, dy, cx, cy)
        elif _rank_desc(ia, ib, ic, id, lowest, 2) == r:
            o = orient2d(ax, ay, bx, by, dx, dy)
        else:
            o = -orient2d(ax, ay, bx, by, cx, cy)
        if o > 0.0:
            return 1
        if o < 0.0:
            return -1
    return 0


# ----------------------------------------------------------------------------------------
# batch helpers
# ----------------------------------------------------------------------------------------
@nb.njit(cache=True)
def orient2d_batch(points, tri):
    """Evaluate :func:`orient2d` for every triangle.

    Parameters
    ----------
    points : (n, 2) float64
    tri : (m, 3) int32 or int64
        Vertex indices into ``points``.

    Returns
    -------
    (m,) float64
        ``orient2d`` of each triangle's vertices in the given order (positive = ccw).
    """
    m = tri.shape[0]
    out = np.empty(m)
    for t in range(m):
        i = tri[t, 0]
        j = tri[t, 1]
        k = tri[t, 2]
        out[t] = orient2d(
            points[i, 0], points[i, 1], points[j, 0], points[j, 1], points[k, 0], points[k, 1]
        )
    return out


# The 3-D predicates live in meshwright.core.predicates3d (built on the helpers above); their
# names stay importable from here, loaded on first use so that 2-D code never imports them.
_NAMES_3D = frozenset(
    ("orient3d", "insphere", "orient3d_stage_a", "insphere_stage_a", "insphere_dd", "insphere_sos",
     "orient3d_batch", "O3D_ERRBOUND_A", "ISP_ERRBOUND_A", "_orient3d_exact", "_insphere_exact")
)


def __getattr__(name: str):
    """The 3-D names of :mod:`meshwright.core.predicates3d`, imported on first access."""
    if name in _NAMES_3D:
        from meshwright.core import predicates3d

        return getattr(predicates3d, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
