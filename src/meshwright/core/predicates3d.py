"""Robust 3-D predicates with exact signs: orientation, in-sphere, and in-sphere under SoS.

Split from :mod:`meshwright.core.predicates` (which re-exports every name here, so
``from meshwright.core.predicates import orient3d`` keeps working); the sign contracts, the
exactness range and the symbolic perturbation are documented there and hold unchanged.

Sources
-------
* J. R. Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast Robust Geometric
  Predicates", Discrete & Computational Geometry 18(3):305-363, 1997: the stage-A filters
  with ``o3derrboundA`` / ``isperrboundA`` and the exact fallback in expansion arithmetic
  (:mod:`meshwright.core.expansion`).
* M. Joldes, J.-M. Muller, V. Popescu, "Tight and rigorous error bounds for basic building
  blocks of double-word arithmetic", ACM TOMS 44(2), 2017: the double-word stage
  :func:`insphere_dd`.
* H. Edelsbrunner and E. P. Mücke, "Simulation of Simplicity", ACM TOG 9(1):66-104, 1990,
  and O. Devillers and M. Teillaud, Computational Geometry 44(3):160-168, 2011: the
  perturbation of the lifted coordinate in :func:`insphere_sos`.

Invariants
----------
* ``orient3d(a, b, c, d) > 0`` iff ``det[b - a, c - a, d - a] > 0`` (CGAL's convention, the
  opposite sign of Shewchuk's C code); ``insphere(a, b, c, d, e) > 0`` iff e is strictly
  inside the sphere through a, b, c, d when ``orient3d(a, b, c, d) > 0``.  The sign is
  exact, exact degeneracies return ``0.0``; the magnitude is approximate.
* All kernels are ``@njit(cache=True)`` over scalars, except :func:`orient3d_batch`, which
  takes ``points`` (n, 3) float64 and ``tets`` (m, 4) int32 or int64.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from meshwright.core.exact_stages2d import (
    DD_ERRBOUND,
    _dw_add,
    _dw_minor,
    _dw_mul,
    _two_diff,
)
from meshwright.core.expansion import (
    EPSILON,
    MAX_EXPANSION_LENGTH,
    diff_into,
    estimate,
    expansion_sum,
    mul_small,
)
from meshwright.core.predicates import _minor2, _rank_desc, _square_times

__all__ = [
    "ISP_ERRBOUND_A",
    "O3D_ERRBOUND_A",
    "insphere",
    "insphere_dd",
    "insphere_sos",
    "insphere_stage_a",
    "orient3d",
    "orient3d_batch",
    "orient3d_stage_a",
]

# A-priori relative forward error bounds of the stage-A evaluations (Shewchuk 1997, Sec. 4),
# as in meshwright.core.predicates.
O3D_ERRBOUND_A = (7.0 + 56.0 * EPSILON) * EPSILON
ISP_ERRBOUND_A = (16.0 + 224.0 * EPSILON) * EPSILON

# Capacity of the largest exact-stage regions of insphere: combinatorially a lift times a
# 3x3 minor has up to 3 * 16 * 192 = 9216 components, but no nonoverlapping expansion of
# doubles can exceed MAX_EXPANSION_LENGTH (one bit position per component).
_CAP = MAX_EXPANSION_LENGTH
# Slot of the xy-minor of the ascending pair (q, r) of insphere's four points, at 4q + r.
_PAIR_SLOT = (-1, 0, 1, 2, -1, -1, 3, 4, -1, -1, -1, 5, -1, -1, -1, -1)


# ----------------------------------------------------------------------------------------
# orient3d
# ----------------------------------------------------------------------------------------
@nb.njit(cache=True)
def _orient3d_exact(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz):
    """Exact ``det[b - a, c - a, d - a]`` as an expansion, rounded.

    Computed as ``-det[a - d, b - d, c - d]`` expanded along z (Shewchuk's form, negated):
    differences 2, xy-minors 16, ``z * minor`` 64, the sum of three 192.
    """
    # Regions (offsets): differences 0 (p - d at 6p: x, y, z), minor 18, t1 34, t2 42,
    # scratch 50 (64), term 114 (64), two accumulators 178 and 370 (192 each).
    w = np.empty(562)
    nd = (
        diff_into(ax, dx, w, 0),
        diff_into(ay, dy, w, 2),
        diff_into(az, dz, w, 4),
        diff_into(bx, dx, w, 6),
        diff_into(by, dy, w, 8),
        diff_into(bz, dz, w, 10),
        diff_into(cx, dx, w, 12),
        diff_into(cy, dy, w, 14),
        diff_into(cz, dz, w, 16),
    )
    acc = 178
    nxt = 370
    n = 0
    for p in range(3):
        q = (p + 1) % 3
        r = (p + 2) % 3
        m = _minor2(
            w, 6 * q, nd[3 * q], 6 * r + 2, nd[3 * r + 1], 6 * r, nd[3 * r],
            6 * q + 2, nd[3 * q + 1], 18, 34, 42, 50,
        )
        # The minus sign turns Shewchuk's determinant into ours.
        k = mul_small(w, 18, m, 6 * p + 4, nd[3 * p + 2], -1.0, 114, 50)
        n = expansion_sum(w, acc, n, 114, k, 1.0, nxt)
        acc, nxt = nxt, acc
    return estimate(w, acc, n)


@nb.njit(cache=True)
def orient3d_stage_a(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz):
    """Shewchuk's stage-A orient3d filter: ``(det, err)``, the floating-point determinant in
    Shewchuk's sign (the negative of :func:`orient3d`) and its a-priori error bound.

    ``|det| > err`` proves the sign of ``det``; otherwise only the exact predicate decides.
    Inlined into :func:`orient3d` and the 3-D kernels, so all evaluate the one proven expression.
    """
    adx = ax - dx
    bdx = bx - dx
    cdx = cx - dx
    ady = ay - dy
    bdy = by - dy
    cdy = cy - dy
    adz = az - dz
    bdz = bz - dz
    cdz = cz - dz

    bdxcdy = bdx * cdy
    cdxbdy = cdx * bdy
    cdxady = cdx * ady
    adxcdy = adx * cdy
    adxbdy = adx * bdy
    bdxady = bdx * ady

    # Shewchuk's evaluation order (the one his error bound is proven for) of
    # det[a-d, b-d, c-d] = -det[b-a, c-a, d-a].
    det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady)
    permanent = (
        (abs(bdxcdy) + abs(cdxbdy)) * abs(adz)
        + (abs(cdxady) + abs(adxcdy)) * abs(bdz)
        + (abs(adxbdy) + abs(bdxady)) * abs(cdz)
    )
    return det, O3D_ERRBOUND_A * permanent


@nb.njit(cache=True)
def orient3d(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz):
    """Orientation of four points in space, with exact sign (CGAL convention).

    Parameters
    ----------
    ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz : float
        Coordinates of a, b, c, d.

    Returns
    -------
    float
        Positive iff ``det[b - a, c - a, d - a] > 0``: the tetrahedron abcd has positive
        volume, i.e. d lies on the side of plane abc from which a, b, c look
        counter-clockwise.  Exactly 0.0 if coplanar.  The magnitude approximates six times
        the signed volume.  NOTE: this is the negative of Shewchuk's C ``orient3d``.
    """
    det, errbound = orient3d_stage_a(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz)
    if det > errbound or -det > errbound:
        return -det
    return _orient3d_exact(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz)


# ----------------------------------------------------------------------------------------
# insphere
# ----------------------------------------------------------------------------------------
@nb.njit(cache=True)
def _insphere_exact(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz, ex, ey, ez):
    """Exact lifted 4x4 determinant relative to e (our sign), as an expansion, rounded.

    Shewchuk's ``det4[p - e | |p - e|**2]`` expanded along the lift column is
    ``sum_s (-1)**(s+1) lift_s M_s`` (s = 0..3, ``M_s`` the xyz-determinant of the other three
    points in order); ours is its negative.  Lengths: differences 2, xy-minors 16,
    ``M_s`` 192, ``x * M_s`` 768, ``x * (x * M_s)`` 3072; beyond that :data:`_CAP` applies.
    """
    # Regions (offsets): differences 0 (p - e at 6p: x, y, z), six xy-minors 24 (16 each),
    # t1 120, t2 128, z * minor 136 (64), two M_s accumulators 200 and 392 (192 each),
    # x * M_s 584 (768), scratch 1352 (3072), then five regions of _CAP: x-square,
    # two lift-term accumulators, two determinant accumulators.
    sq = 4424
    w = np.empty(sq + 5 * _CAP)
    nd = (
        diff_into(ax, ex, w, 0),
        diff_into(ay, ey, w, 2),
        diff_into(az, ez, w, 4),
        diff_into(bx, ex, w, 6),
        diff_into(by, ey, w, 8),
        diff_into(bz, ez, w, 10),
        diff_into(cx, ex, w, 12),
        diff_into(cy, ey, w, 14),
        diff_into(cz, ez, w, 16),
        diff_into(dx, ex, w, 18),
        diff_into(dy, ey, w, 20),
        diff_into(dz, ez, w, 22),
    )
    # xy-minors [p, q] = p_x q_y - q_x p_y for the 6 pairs p < q, in lexicographic order,
    # computed once and shared by the four xyz-minors.
    n01 = _minor2(w, 0, nd[0], 8, nd[4], 6, nd[3], 2, nd[1], 24, 120, 128, 1352)
    n02 = _minor2(w, 0, nd[0], 14, nd[7], 12, nd[6], 2, nd[1], 40, 120, 128, 1352)
    n03 = _minor2(w, 0, nd[0], 20, nd[10], 18, nd[9], 2, nd[1], 56, 120, 128, 1352)
    n12 = _minor2(w, 6, nd[3], 14, nd[7], 12, nd[6], 8, nd[4], 72, 120, 128, 1352)
    n13 = _minor2(w, 6, nd[3], 20, nd[10], 18, nd[9], 8, nd[4], 88, 120, 128, 1352)
    n23 = _minor2(w, 12, nd[6], 20, nd[10], 18, nd[9], 14, nd[7], 104, 120, 128, 1352)
    n2 = (n01, n02, n03, n12, n13, n23)

    acc = sq + 3 * _CAP
    nxt = sq + 4 * _CAP
    n = 0
    for s in range(4):
        # Rows other than s, ascending: (p0, p1, p2).
        p0 = 1 if s == 0 else 0
        p1 = 2 if s <= 1 else 1
        p2 = 2 if s == 3 else 3
        # M_s = det(p0, p1, p2) = p0_z [p1, p2] - p1_z [p0, p2] + p2_z [p0, p1]; every pair
        # here is ascending, so the stored minors apply as they are.
        m3 = 200
        m3n = 392
        k3 = 0
        for j in range(3):
            if j == 0:
                p, q, r, sg = p0, p1, p2, 1.0
            elif j == 1:
                p, q, r, sg = p1, p0, p2, -1.0
            else:
                p, q, r, sg = p2, p0, p1, 1.0
            sl = _PAIR_SLOT[q * 4 + r]
            kz = mul_small(w, 24 + 16 * sl, n2[sl], 6 * p + 4, nd[3 * p + 2], sg, 136, 1352)
            k3 = expansion_sum(w, m3, k3, 136, kz, 1.0, m3n)
            m3, m3n = m3n, m3
        # lift_s * M_s = sum over coordinates x of x * (x * M_s).
        lt = sq + _CAP
        ltn = sq + 2 * _CAP
        kl = 0
        for c in range(3):
            kx = _square_times(w, m3, k3, 6 * s + 2 * c, nd[3 * s + c], sq, 584, 1352)
            kl = expansion_sum(w, lt, kl, sq, kx, 1.0, ltn)
            lt, ltn = ltn, lt
        sign = 1.0 if s % 2 == 0 else -1.0
        n = expansion_sum(w, acc, n, lt, kl, sign, nxt)
        acc, nxt = nxt, acc
    return estimate(w, acc, n)


@nb.njit(cache=True)
def insphere_stage_a(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz, ex, ey, ez):
    """Shewchuk's stage-A in-sphere filter: ``(det, err)``, the floating-point determinant in
    Shewchuk's sign (the negative of :func:`insphere`) and its a-priori error bound.

    ``|det| > err`` proves the sign of ``det``; otherwise only the exact predicate decides.
    Inlined into :func:`insphere` and the 3-D kernels, so all evaluate the one proven expression.
    """
    aex = ax - ex
    bex = bx - ex
    cex = cx - ex
    dex = dx - ex
    aey = ay - ey
    bey = by - ey
    cey = cy - ey
    dey = dy - ey
    aez = az - ez
    bez = bz - ez
    cez = cz - ez
    dez = dz - ez

    aexbey = aex * bey
    bexaey = bex * aey
    ab = aexbey - bexaey
    bexcey = bex * cey
    cexbey = cex * bey
    bc = bexcey - cexbey
    cexdey = cex * dey
    dexcey = dex * cey
    cd = cexdey - dexcey
    dexaey = dex * aey
    aexdey = aex * dey
    da = dexaey - aexdey
    aexcey = aex * cey
    cexaey = cex * aey
    ac = aexcey - cexaey
    bexdey = bex * dey
    dexbey = dex * bey
    bd = bexdey - dexbey

    abc = aez * bc - bez * ac + cez * ab
    bcd = bez * cd - cez * bd + dez * bc
    cda = cez * da + dez * ac + aez * cd
    dab = dez * ab + aez * bd + bez * da

    alift = aex * aex + aey * aey + aez * aez
    blift = bex * bex + bey * bey + bez * bez
    clift = cex * cex + cey * cey + cez * cez
    dlift = dex * dex + dey * dey + dez * dez

    # Shewchuk's determinant (positive inside for his orientation); ours is its negative.
    det = (dlift * abc - clift * dab) + (blift * cda - alift * bcd)

    aezp = abs(aez)
    bezp = abs(bez)
    cezp = abs(cez)
    dezp = abs(dez)
    p_ab = abs(aexbey) + abs(bexaey)
    p_bc = abs(bexcey) + abs(cexbey)
    p_cd = abs(cexdey) + abs(dexcey)
    p_da = abs(dexaey) + abs(aexdey)
    p_ac = abs(aexcey) + abs(cexaey)
    p_bd = abs(bexdey) + abs(dexbey)
    permanent = (
        (p_cd * bezp + p_bd * cezp + p_bc * dezp) * alift
        + (p_da * cezp + p_ac * dezp + p_cd * aezp) * blift
        + (p_ab * dezp + p_bd * aezp + p_da * bezp) * clift
        + (p_bc * aezp + p_ac * bezp + p_ab * cezp) * dlift
    )
    return det, ISP_ERRBOUND_A * permanent


@nb.njit(cache=True)
def insphere_dd(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz, ex, ey, ez):
    """Stage D of :func:`insphere`: ``(det, proven)``, Shewchuk's determinant (the negative
    of ours) evaluated in double-word arithmetic from the exact differences.

    Points rounded onto a sphere (a surface mesh's vertices) are nearly cospherical: the
    stage-A filter fails for almost every in-sphere test of their Delaunay tetrahedralization
    (97 % on a level-5 icosphere, ``|det|`` a median 0.07 of its bound), while about 106
    bits decide nearly all of them; the expansions (about 20 us a call) are left for the
    exactly cospherical and the nearly so within ``2**-100`` of the permanent.

    Error bound, as for ``incircle``'s stage D (:mod:`meshwright.core.exact_stages2d`,
    Joldes, Muller and Popescu 2017): every double-word operation returns its exact result on
    its computed inputs times ``(1 + d)``, ``|d| <= 5u**2``; a monomial of the determinant
    passes at most eight of them (product and difference of an xy-minor, z times minor, two
    sums of the 3x3 minor, lift times minor, two of the final sums), so the computed value
    is within ``((1 + 5u**2)**8 - 1) P <= 40.01 u**2 P`` of the exact one, P the permanent.
    P is evaluated from the rounded differences in plain doubles, less than ``1 + 20u`` below
    the exact permanent; ``|det| > 64 u**2 P`` (``DD_ERRBOUND``) proves the sign.  In the
    predicates' exactness range no double-word component underflows or overflows (degree 5:
    components stay within ``[2**-846, 2**1013]``).
    """
    aex, aexl = _two_diff(ax, ex)
    aey, aeyl = _two_diff(ay, ey)
    aez, aezl = _two_diff(az, ez)
    bex, bexl = _two_diff(bx, ex)
    bey, beyl = _two_diff(by, ey)
    bez, bezl = _two_diff(bz, ez)
    cex, cexl = _two_diff(cx, ex)
    cey, ceyl = _two_diff(cy, ey)
    cez, cezl = _two_diff(cz, ez)
    dex, dexl = _two_diff(dx, ex)
    dey, deyl = _two_diff(dy, ey)
    dez, dezl = _two_diff(dz, ez)
    # xy-minors, as in insphere_stage_a
    abh, abl = _dw_minor(aex, aexl, bey, beyl, bex, bexl, aey, aeyl)
    bch, bcl = _dw_minor(bex, bexl, cey, ceyl, cex, cexl, bey, beyl)
    cdh, cdl = _dw_minor(cex, cexl, dey, deyl, dex, dexl, cey, ceyl)
    dah, dal = _dw_minor(dex, dexl, aey, aeyl, aex, aexl, dey, deyl)
    ach, acl = _dw_minor(aex, aexl, cey, ceyl, cex, cexl, aey, aeyl)
    bdh, bdl = _dw_minor(bex, bexl, dey, deyl, dex, dexl, bey, beyl)
    # 3x3 minors: abc = aez bc - bez ac + cez ab, and so on
    abch, abcl = _dw_sum3(aez, aezl, bch, bcl, -bez, -bezl, ach, acl, cez, cezl, abh, abl)
    bcdh, bcdl = _dw_sum3(bez, bezl, cdh, cdl, -cez, -cezl, bdh, bdl, dez, dezl, bch, bcl)
    cdah, cdal = _dw_sum3(cez, cezl, dah, dal, dez, dezl, ach, acl, aez, aezl, cdh, cdl)
    dabh, dabl = _dw_sum3(dez, dezl, abh, abl, aez, aezl, bdh, bdl, bez, bezl, dah, dal)
    alh, all_ = _dw_lift3(aex, aexl, aey, aeyl, aez, aezl)
    blh, bll = _dw_lift3(bex, bexl, bey, beyl, bez, bezl)
    clh, cll = _dw_lift3(cex, cexl, cey, ceyl, cez, cezl)
    dlh, dll = _dw_lift3(dex, dexl, dey, deyl, dez, dezl)
    # (dlift abc - clift dab) + (blift cda - alift bcd)
    uh, ul = _dw_minor(dlh, dll, abch, abcl, clh, cll, dabh, dabl)
    vh, vl = _dw_minor(blh, bll, cdah, cdal, alh, all_, bcdh, bcdl)
    deth, _ = _dw_add(uh, ul, vh, vl)
    aezp = abs(aez)
    bezp = abs(bez)
    cezp = abs(cez)
    dezp = abs(dez)
    p_ab = abs(aex * bey) + abs(bex * aey)
    p_bc = abs(bex * cey) + abs(cex * bey)
    p_cd = abs(cex * dey) + abs(dex * cey)
    p_da = abs(dex * aey) + abs(aex * dey)
    p_ac = abs(aex * cey) + abs(cex * aey)
    p_bd = abs(bex * dey) + abs(dex * bey)
    permanent = (
        (p_cd * bezp + p_bd * cezp + p_bc * dezp) * (aex * aex + aey * aey + aez * aez)
        + (p_da * cezp + p_ac * dezp + p_cd * aezp) * (bex * bex + bey * bey + bez * bez)
        + (p_ab * dezp + p_bd * aezp + p_da * bezp) * (cex * cex + cey * cey + cez * cez)
        + (p_bc * aezp + p_ac * bezp + p_ab * cezp) * (dex * dex + dey * dey + dez * dez)
    )
    return deth, abs(deth) > DD_ERRBOUND * permanent


@nb.njit(cache=True)
def _dw_sum3(ph, pl, qh, ql, rh, rl, sh, sl, th, tl, uh, ul):
    """Double-word ``p q + r s + t u`` (summed left to right)."""
    xh, xl = _dw_mul(ph, pl, qh, ql)
    yh, yl = _dw_mul(rh, rl, sh, sl)
    zh, zl = _dw_mul(th, tl, uh, ul)
    xh, xl = _dw_add(xh, xl, yh, yl)
    return _dw_add(xh, xl, zh, zl)


@nb.njit(cache=True)
def _dw_lift3(xh, xl, yh, yl, zh, zl):
    """Double-word ``x**2 + y**2 + z**2``."""
    uh, ul = _dw_mul(xh, xl, xh, xl)
    vh, vl = _dw_mul(yh, yl, yh, yl)
    wh, wl = _dw_mul(zh, zl, zh, zl)
    uh, ul = _dw_add(uh, ul, vh, vl)
    return _dw_add(uh, ul, wh, wl)


@nb.njit(cache=True)
def insphere(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz, ex, ey, ez):
    """In-sphere test with exact sign (CGAL convention, matching :func:`orient3d`).

    Parameters
    ----------
    ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz : float
        Four points defining a sphere.
    ex, ey, ez : float
        Query point.

    Returns
    -------
    float
        Positive if e is strictly inside the sphere through a, b, c, d and
        ``orient3d(a, b, c, d) > 0`` (negative if outside); the sign flips when
        ``orient3d(a, b, c, d) < 0``.  Exactly 0.0 if the five points are cospherical (or
        a, b, c, d coplanar and e on their circle).  NOTE: the negative of Shewchuk's C
        ``insphere``.
    """
    det, errbound = insphere_stage_a(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz, ex, ey, ez)
    if det > errbound or -det > errbound:
        return -det
    det, proven = insphere_dd(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz, ex, ey, ez)
    if proven:
        return -det
    return _insphere_exact(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz, ex, ey, ez)



@nb.njit(cache=True)
def insphere_sos(
    ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz, ex, ey, ez, ia, ib, ic, id, ie
):
    """In-sphere test under symbolic perturbation of the lifted coordinate.

    Parameters
    ----------
    ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz, ex, ey, ez : float
        As in :func:`insphere`.
    ia, ib, ic, id, ie : int
        Distinct global indices of a, b, c, d, e.

    Returns
    -------
    int
        ``+1`` or ``-1``: the sign of :func:`insphere` when nonzero, otherwise the sign for
        the perturbed lifts (larger index, larger perturbation).  Returns 0 only when every
        cofactor consulted vanishes, which needs a, b, c, d coplanar (otherwise the cofactor
        of e, ``-orient3d(a, b, c, d)``, decides).  Alternating in its five points.
    """
    det = insphere(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz, ex, ey, ez)
    if det > 0.0:
        return 1
    if det < 0.0:
        return -1
    for r in range(5):
        if _rank_desc(ia, ib, ic, id, ie, 0) == r:
            o = orient3d(ex, ey, ez, bx, by, bz, cx, cy, cz, dx, dy, dz)
        elif _rank_desc(ia, ib, ic, id, ie, 1) == r:
            o = orient3d(ax, ay, az, ex, ey, ez, cx, cy, cz, dx, dy, dz)
        elif _rank_desc(ia, ib, ic, id, ie, 2) == r:
            o = orient3d(ax, ay, az, bx, by, bz, ex, ey, ez, dx, dy, dz)
        elif _rank_desc(ia, ib, ic, id, ie, 3) == r:
            o = orient3d(ax, ay, az, bx, by, bz, cx, cy, cz, ex, ey, ez)
        else:
            o = -orient3d(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz)
        if o > 0.0:
            return 1
        if o < 0.0:
            return -1
    return 0


# ----------------------------------------------------------------------------------------
# batch helper
# ----------------------------------------------------------------------------------------
@nb.njit(cache=True)
def orient3d_batch(points, tets):
    """Evaluate :func:`orient3d` for every tetrahedron.

    Parameters
    ----------
    points : (n, 3) float64
    tets : (m, 4) int32 or int64
        Vertex indices into ``points``.

    Returns
    -------
    (m,) float64
        ``orient3d`` of each tetrahedron's vertices in the given order (positive volume > 0).
    """
    m = tets.shape[0]
    out = np.empty(m)
    for t in range(m):
        i = tets[t, 0]
        j = tets[t, 1]
        k = tets[t, 2]
        q = tets[t, 3]
        out[t] = orient3d(
            points[i, 0], points[i, 1], points[i, 2],
            points[j, 0], points[j, 1], points[j, 2],
            points[k, 0], points[k, 1], points[k, 2],
            points[q, 0], points[q, 1], points[q, 2],
        )
    return out
