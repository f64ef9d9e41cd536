r"""Cheap exact stages of ``orient2d`` and ``incircle`` between the stage-A filter and the expansions.

When Shewchuk's stage-A filter cannot decide a sign, :mod:`meshwright.core.predicates` runs
these stages before its full expansion arithmetic; each either proves the exact sign or
says it cannot, so the predicates stay exact whatever the input.

Sources
-------
* J. R. Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast Robust Geometric
  Predicates", Discrete & Computational Geometry 18(3):305-363, 1997: the stage-A filter,
  error-free transformations, the forward error analysis of the determinant.
* M. Joldes, J.-M. Muller and V. Popescu, "Tight and rigorous error bounds for basic
  building blocks of double-word arithmetic", ACM Transactions on Mathematical Software
  44(2), article 15, 2017: AccurateDWPlusDW (their Algorithm 6, relative error
  <= 3u**2 / (1 - 4u)) and DWTimesDW3 (Algorithm 12, with FMA, relative error <= 5u**2).

Stage E: error-free evaluation
------------------------------
Degenerate inputs of the kind meshes meet (grids, points with few significant bits) make
every operation of the determinant exact: each difference, product, lift and minor is
checked with an error-free transformation (``two_diff``/``two_sum`` tails, the product's
tail ``fma(a, b, -a * b)``), and if every tail is zero the computed value *is* the exact
determinant, except for the last addition, whose rounding keeps the sign and maps zero to
zero.  Cost: about three times stage A, no memory.  Exactly zero determinants, the common
case on a grid, are proven here instead of by the expansions.

Stage D: double-word filter (``incircle`` only)
-----------------------------------------------
Near-degenerate inputs whose operations are not exact (points on a circle whose
coordinates are rounded cosines) need more precision but rarely exactness.  The
determinant is evaluated from the exact differences (``two_diff``: hi + lo) in double-word
arithmetic (about 106 bits).  Every double-word operation returns its exact result on its
computed inputs times ``(1 + d)`` with ``|d| <= k = 5u**2`` (u = 2**-53; Joldes et al.),
and every monomial of the determinant passes at most seven such operations (product,
minor, square, lift, lift times minor, two sums), so the computed value differs from the
exact one by at most ``((1 + k)**7 - 1) P <= 35.01 u**2 P``, with P the permanent (sum of
the monomials' absolute values).  P is evaluated from the rounded differences in plain
doubles, less than ``1 + 12u`` below the exact one; the filter accepts
``|det| > 64 u**2 P``, which covers both.  Exactness range: the predicates' (every nonzero
coordinate of magnitude in ``[2**-148, 2**200]``), where no double-word component
underflows or overflows.

Return convention: every stage returns ``(value, proven)``; ``value`` has the exact sign
of the determinant when ``proven`` is true and is meaningless otherwise.  All functions
are plain compiled calls over scalars (:func:`meshwright.core.jit.inner`: kernels call
them, Python never does): no arrays, so no reference counts to save, and LLVM
inlines them where it pays; Numba's IR inlining (``inline="always"``) of these forty-odd
call sites tripled the predicates' compile time.
"""

from __future__ import annotations

from meshwright.core.expansion import EPSILON, fma
from meshwright.core.jit import inner

__all__ = ["orient2d_eft", "incircle_eft", "incircle_dd", "DD_ERRBOUND"]

#: Stage D's acceptance bound, relative to the permanent (see the module docstring).
DD_ERRBOUND = 64.0 * EPSILON * EPSILON


@inner
def _two_diff(a, b):
    """``(x, y)``: ``x = fl(a - b)``, ``x + y = a - b`` exactly (Knuth; a plain call, see below)."""
    x = a - b
    bv = a - x
    av = x + bv
    return x, (a - av) + (bv - b)


@inner
def _two_sum(a, b):
    """``(x, y)``: ``x = fl(a + b)``, ``x + y = a + b`` exactly (Knuth; a plain call, see below)."""
    x = a + b
    bv = x - a
    av = x - bv
    return x, (a - av) + (b - bv)


@inner
def orient2d_eft(ax, ay, bx, by, cx, cy):
    """Stage E of ``orient2d``: ``(det, proven)``, ``det`` of ``(a-c)x (b-c)y - (a-c)y (b-c)x``.

    Proven when the four differences and both products are exact; the final subtraction of
    two exact values is then correctly signed (zero iff they are equal).
    """
    acx, e1 = _two_diff(ax, cx)
    bcy, e2 = _two_diff(by, cy)
    acy, e3 = _two_diff(ay, cy)
    bcx, e4 = _two_diff(bx, cx)
    left = acx * bcy
    right = acy * bcx
    e5 = fma(acx, bcy, -left)
    e6 = fma(acy, bcx, -right)
    proven = (abs(e1) + abs(e2) + abs(e3) + abs(e4) + abs(e5) + abs(e6)) == 0.0
    return left - right, proven


@inner
def _exact_product(a, b):
    """``(a * b, |error|)``: the rounded product and the magnitude of its rounding error."""
    p = a * b
    return p, abs(fma(a, b, -p))


@inner
def incircle_eft(ax, ay, bx, by, cx, cy, dx, dy):
    """Stage E of ``incircle``: ``(det, proven)`` for the lifted determinant relative to d.

    ``det = alift (bdx cdy - cdx bdy) + blift (cdx ady - adx cdy) + clift (adx bdy - bdx ady)``
    with ``plift = pdx**2 + pdy**2``, the sign convention of :func:`incircle`.
    """
    adx, e1 = _two_diff(ax, dx)
    bdx, e2 = _two_diff(bx, dx)
    cdx, e3 = _two_diff(cx, dx)
    ady, e4 = _two_diff(ay, dy)
    bdy, e5 = _two_diff(by, dy)
    cdy, e6 = _two_diff(cy, dy)
    if (abs(e1) + abs(e2) + abs(e3) + abs(e4) + abs(e5) + abs(e6)) != 0.0:
        return 0.0, False
    bdxcdy, f1 = _exact_product(bdx, cdy)
    cdxbdy, f2 = _exact_product(cdx, bdy)
    cdxady, f3 = _exact_product(cdx, ady)
    adxcdy, f4 = _exact_product(adx, cdy)
    adxbdy, f5 = _exact_product(adx, bdy)
    bdxady, f6 = _exact_product(bdx, ady)
    bc, g1 = _two_diff(bdxcdy, cdxbdy)
    ca, g2 = _two_diff(cdxady, adxcdy)
    ab, g3 = _two_diff(adxbdy, bdxady)
    adx2, h1 = _exact_product(adx, adx)
    ady2, h2 = _exact_product(ady, ady)
    bdx2, h3 = _exact_product(bdx, bdx)
    bdy2, h4 = _exact_product(bdy, bdy)
    cdx2, h5 = _exact_product(cdx, cdx)
    cdy2, h6 = _exact_product(cdy, cdy)
    alift, k1 = _two_sum(adx2, ady2)
    blift, k2 = _two_sum(bdx2, bdy2)
    clift, k3 = _two_sum(cdx2, cdy2)
    ta, m1 = _exact_product(alift, bc)
    tb, m2 = _exact_product(blift, ca)
    tc, m3 = _exact_product(clift, ab)
    s, m4 = _two_sum(ta, tb)
    err = (
        (f1 + f2 + f3 + f4 + f5 + f6)
        + (abs(g1) + abs(g2) + abs(g3))
        + (h1 + h2 + h3 + h4 + h5 + h6)
        + (abs(k1) + abs(k2) + abs(k3))
        + (m1 + m2 + m3 + abs(m4))
    )
    return s + tc, err == 0.0


@inner
def _fast_two_sum(a, b):
    """``(s, t)`` with ``s + t == a + b`` exactly, for ``|a| >= |b|`` or ``a == 0``."""
    s = a + b
    return s, b - (s - a)


@inner
def _dw_add(xh, xl, yh, yl):
    """AccurateDWPlusDW (Joldes, Muller & Popescu 2017, Algorithm 6): relative error <= 3u**2/(1-4u)."""
    sh, sl = _two_sum(xh, yh)
    th, tl = _two_sum(xl, yl)
    c = sl + th
    vh, vl = _fast_two_sum(sh, c)
    w = tl + vl
    return _fast_two_sum(vh, w)


@inner
def _dw_mul(xh, xl, yh, yl):
    """DWTimesDW3 (Joldes, Muller & Popescu 2017, Algorithm 12, FMA): relative error <= 5u**2."""
    ch = xh * yh
    cl1 = fma(xh, yh, -ch)
    tl0 = xl * yl
    tl1 = fma(xh, yl, tl0)
    cl2 = fma(xl, yh, tl1)
    cl3 = cl1 + cl2
    return _fast_two_sum(ch, cl3)


@inner
def _dw_minor(ph, pl, qh, ql, rh, rl, sh, sl):
    """Double-word ``p q - r s``."""
    uh, ul = _dw_mul(ph, pl, qh, ql)
    vh, vl = _dw_mul(rh, rl, sh, sl)
    return _dw_add(uh, ul, -vh, -vl)


@inner
def _dw_lift(xh, xl, yh, yl):
    """Double-word ``x**2 + y**2``."""
    uh, ul = _dw_mul(xh, xl, xh, xl)
    vh, vl = _dw_mul(yh, yl, yh, yl)
    return _dw_add(uh, ul, vh, vl)


@inner
def incircle_dd(ax, ay, bx, by, cx, cy, dx, dy):
    """Stage D of ``incircle``: ``(det, proven)`` from a double-word evaluation.

    The same determinant as :func:`incircle_eft`, evaluated from the exact differences in
    double-word arithmetic; proven when ``|det| > DD_ERRBOUND * permanent`` (module docstring).
    """
    adx, adxl = _two_diff(ax, dx)
    bdx, bdxl = _two_diff(bx, dx)
    cdx, cdxl = _two_diff(cx, dx)
    ady, adyl = _two_diff(ay, dy)
    bdy, bdyl = _two_diff(by, dy)
    cdy, cdyl = _two_diff(cy, dy)
    bch, bcl = _dw_minor(bdx, bdxl, cdy, cdyl, cdx, cdxl, bdy, bdyl)
    cah, cal = _dw_minor(cdx, cdxl, ady, adyl, adx, adxl, cdy, cdyl)
    abh, abl = _dw_minor(adx, adxl, bdy, bdyl, bdx, bdxl, ady, adyl)
    alh, all_ = _dw_lift(adx, adxl, ady, adyl)
    blh, bll = _dw_lift(bdx, bdxl, bdy, bdyl)
    clh, cll = _dw_lift(cdx, cdxl, cdy, cdyl)
    tah, tal = _dw_mul(alh, all_, bch, bcl)
    tbh, tbl = _dw_mul(blh, bll, cah, cal)
    tch, tcl = _dw_mul(clh, cll, abh, abl)
    sh, sl = _dw_add(tah, tal, tbh, tbl)
    deth, _ = _dw_add(sh, sl, tch, tcl)
    permanent = (
        (abs(bdx * cdy) + abs(cdx * bdy)) * (adx * adx + ady * ady)
        + (abs(cdx * ady) + abs(adx * cdy)) * (bdx * bdx + bdy * bdy)
        + (abs(adx * bdy) + abs(bdx * ady)) * (cdx * cdx + cdy * cdy)
    )
    return deth, abs(deth) > DD_ERRBOUND * permanent
