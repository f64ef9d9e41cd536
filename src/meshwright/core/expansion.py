"""Exact floating-point expansion arithmetic (Numba kernels over one flat float64 workspace).

Source: J. R. Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast Robust
Geometric Predicates", Discrete & Computational Geometry 18(3):305-363, 1997.  The
error-free transformations (Two-Sum, Two-Product via Dekker's split) and the expansion
algorithms (Fast-Expansion-Sum, Scale-Expansion, both with zero elimination) follow
Sections 2.5-2.8 of that paper; this is an independent implementation.

Invariants
----------
* An *expansion* is ``w[o : o + n]`` inside a workspace array ``w``: float64 components of
  strictly increasing magnitude, pairwise nonoverlapping (in fact strongly nonoverlapping),
  none of them zero.  Its value is the exact real sum of the components; ``n == 0`` is zero.
  Routines take ``(w, offset, length)`` rather than array slices because a Numba slice costs
  a reference-count round trip, which dominated the exact stage's running time.
* Consequently the sign of an expansion is the sign of its last component.  The last
  component alone can be a poor approximation of the value (when it has few significant
  bits); :func:`estimate` sums the components for a good one with the same exact sign.
* Every routine here requires IEEE-754 double precision with round-to-nearest-even and no
  fused multiply-add contraction (Numba's default, i.e. ``fastmath`` off; an explicit
  :func:`fma` is a single correctly rounded operation and fine) and is exact only
  while no intermediate overflows or underflows (see :mod:`meshwright.core.predicates` for a
  sufficient condition on coordinates); ``split`` needs ``|x| < 2**996``.
* An output region must not overlap any input region of the same call.

Length bounds used to size regions: ``diff_into`` gives <= 2 components; scaling an
``n``-component expansion gives <= 2n; summing gives <= m + n; multiplying by a factor of
<= 2 components gives <= 4n.  Independently, nonoverlapping components occupy disjoint
ranges of the 2098 bit positions 2**-1074 .. 2**1023, so no expansion ever exceeds
:data:`MAX_EXPANSION_LENGTH` components.
"""

from __future__ import annotations

import numba as nb
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

__all__ = [
    "EPSILON",
    "SPLITTER",
    "MAX_EXPANSION_LENGTH",
    "two_sum",
    "two_diff",
    "split",
    "two_product",
    "fma",
    "diff_into",
    "expansion_sum",
    "scale_expansion",
    "mul_small",
    "estimate",
]

#: Half an ulp of 1.0 (unit roundoff for round-to-nearest), the ``epsilon`` of Shewchuk 1997.
EPSILON = 2.0**-53
#: ``2**ceil(53/2) + 1``: Dekker's constant that splits a double into two 26-bit halves.
SPLITTER = 2.0**27 + 1.0
#: Hard cap on the length of any nonoverlapping float64 expansion (one bit position each).
MAX_EXPANSION_LENGTH = 2098


# Offsets are almost always constants at the call sites; without an explicit signature Numba
# would compile a separate literal-typed specialisation for every call site (minutes of
# compile time), hence the signatures on the expansion routines below.  The four error-free
# transformations are plain @njit over scalars: LLVM inlines them into their callers, and
# Numba's IR inlining of their many call sites only cost first-run compile time.
@nb.njit(cache=True)
def two_sum(a, b):
    """Return ``(x, y)`` with ``x = fl(a + b)`` and ``x + y = a + b`` exactly (Knuth).

    Parameters
    ----------
    a, b : float
        Any finite doubles; no ordering of magnitudes is required.

    Returns
    -------
    x, y : float
        Rounded sum and its roundoff error; ``|y| <= ulp(x) / 2``.
    """
    x = a + b
    b_virtual = x - a
    a_virtual = x - b_virtual
    return x, (a - a_virtual) + (b - b_virtual)


@nb.njit(cache=True)
def two_diff(a, b):
    """Return ``(x, y)`` with ``x = fl(a - b)`` and ``x + y = a - b`` exactly.

    Parameters
    ----------
    a, b : float

    Returns
    -------
    x, y : float
        Rounded difference and its roundoff error.
    """
    x = a - b
    b_virtual = a - x
    a_virtual = x + b_virtual
    return x, (a - a_virtual) + (b_virtual - b)


@nb.njit(cache=True)
def split(a):
    """Split ``a`` into ``hi + lo`` with each half fitting in 26 significant bits (Dekker).

    Parameters
    ----------
    a : float
        ``|a| < 2**996`` so that ``SPLITTER * a`` cannot overflow.

    Returns
    -------
    hi, lo : float
        Nonoverlapping halves with ``hi + lo == a`` exactly.
    """
    c = SPLITTER * a
    big = c - a
    hi = c - big
    return hi, a - hi


@nb.njit(cache=True)
def two_product(a, b):
    """Return ``(x, y)`` with ``x = fl(a * b)`` and ``x + y = a * b`` exactly (Dekker/Veltkamp).

    Parameters
    ----------
    a, b : float

    Returns
    -------
    x, y : float
        Rounded product and its roundoff error (exact barring underflow of ``y``).
    """
    x = a * b
    ahi, alo = split(a)
    bhi, blo = split(b)
    # Peel the exactly representable partial products off x, largest first, so every
    # subtraction below is exact and the remainder is precisely the rounding error.
    err = x - ahi * bhi
    err = err - alo * bhi
    err = err - ahi * blo
    return x, alo * blo - err


@intrinsic
def fma(typingctx, a, b, c):
    """``a * b + c`` with one rounding (LLVM's ``llvm.fma.f64``; a library call where the CPU
    has no fused multiply-add, still correctly rounded).

    ``p = a * b; e = fma(a, b, -p)`` is Two-Product in two operations: ``p + e == a * b``
    exactly (barring underflow of ``e``), and ``e == 0`` iff the product ``a * b`` is exact.

    Parameters
    ----------
    a, b, c : float

    Returns
    -------
    float
    """
    if not all(isinstance(x, types.Float) for x in (a, b, c)):
        return None
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        args = [context.cast(builder, v, t, types.float64) for v, t in zip(args, signature.args)]
        d = ir.DoubleType()
        fn = builder.module.declare_intrinsic("llvm.fma", [d], ir.FunctionType(d, [d, d, d]))
        return builder.call(fn, args)

    return sig, codegen


@nb.njit("int64(float64, float64, float64[::1], int64)", cache=True)
def diff_into(a, b, w, ho):
    """Write the exact difference ``a - b`` as an expansion of <= 2 components at ``w[ho:]``.

    Parameters
    ----------
    a, b : float
    w : float64 array
        Workspace.
    ho : int
        Output offset (2 slots).

    Returns
    -------
    int
        Length (0, 1 or 2).
    """
    x, y = two_diff(a, b)
    n = 0
    if y != 0.0:
        w[ho] = y
        n += 1
    if x != 0.0:
        w[ho + n] = x
        n += 1
    return n


@nb.njit("int64(float64[::1], int64, int64, int64, int64, float64, int64)", cache=True)
def expansion_sum(w, eo, elen, fo, flen, fsign, ho):
    """Write the expansion ``e + fsign * f`` at ``w[ho:]`` and return its length.

    Merge-then-accumulate (Shewchuk's Fast-Expansion-Sum) with zero elimination.  Two-Sum is
    used for every step, including the first where Fast-Two-Sum would do: this removes one
    precondition to get wrong at the price of three flops per component.

    Parameters
    ----------
    w : float64 array
        Workspace holding both inputs and the output.
    eo, elen : int
        Offset and length of ``e``.
    fo, flen : int
        Offset and length of ``f``.
    fsign : float
        ``1.0`` or ``-1.0``; negation is exact, so subtraction comes for free.
    ho : int
        Output offset; ``elen + flen`` slots, overlapping neither input.

    Returns
    -------
    int
        Length of the zero-eliminated result (0 means the sum is exactly zero).
    """
    if elen == 0 or flen == 0:
        # Copy the nonempty one, still dropping zeros so the output invariant holds even
        # for a caller-built input such as a lone 0.0.
        hlen = 0
        for j in range(flen):
            if w[fo + j] != 0.0:
                w[ho + hlen] = fsign * w[fo + j]
                hlen += 1
        for i in range(elen):
            if w[eo + i] != 0.0:
                w[ho + hlen] = w[eo + i]
                hlen += 1
        return hlen
    i = 0
    j = 0
    # Feed components in nondecreasing magnitude order; that is what makes the running
    # roundoff terms come out nonoverlapping and increasing.
    enow = w[eo]
    fnow = fsign * w[fo]
    if abs(fnow) < abs(enow):
        q = fnow
        j = 1
    else:
        q = enow
        i = 1
    hlen = 0
    while i < elen or j < flen:
        if j >= flen:
            g = w[eo + i]
            i += 1
        elif i >= elen:
            g = fsign * w[fo + j]
            j += 1
        else:
            enow = w[eo + i]
            fnow = w[fo + j]
            if abs(enow) <= abs(fnow):
                g = enow
                i += 1
            else:
                g = fsign * fnow
                j += 1
        q, hh = two_sum(q, g)
        if hh != 0.0:
            w[ho + hlen] = hh
            hlen += 1
    if q != 0.0:
        w[ho + hlen] = q
        hlen += 1
    return hlen


@nb.njit("int64(float64[::1], int64, int64, float64, int64)", cache=True)
def scale_expansion(w, eo, elen, b, ho):
    """Write the expansion ``b * e`` at ``w[ho:]`` and return its length (Scale-Expansion).

    Parameters
    ----------
    w : float64 array
    eo, elen : int
        Offset and length of ``e``.
    b : float
    ho : int
        Output offset; ``2 * elen`` slots, not overlapping ``e``.

    Returns
    -------
    int
        Length of the zero-eliminated result.
    """
    if elen == 0 or b == 0.0:
        return 0
    q, hh = two_product(w[eo], b)
    hlen = 0
    if hh != 0.0:
        w[ho] = hh
        hlen += 1
    for i in range(1, elen):
        p_hi, p_lo = two_product(w[eo + i], b)
        s, hh = two_sum(q, p_lo)
        if hh != 0.0:
            w[ho + hlen] = hh
            hlen += 1
        q, hh = two_sum(p_hi, s)
        if hh != 0.0:
            w[ho + hlen] = hh
            hlen += 1
    if q != 0.0:
        w[ho + hlen] = q
        hlen += 1
    return hlen


@nb.njit("int64(float64[::1], int64, int64, int64, int64, float64, int64, int64)", cache=True)
def mul_small(w, eo, elen, do, dlen, fsign, ho, so):
    """Write ``fsign * e * d`` at ``w[ho:]`` where ``d`` has at most two components.

    Every factor in the predicates' exact stages is either a coordinate difference (at most
    two components) or built from them, so products are formed as one or two
    Scale-Expansions and at most one merge, never a long-by-long product.

    Parameters
    ----------
    w : float64 array
    eo, elen : int
        Offset and length of ``e``.
    do, dlen : int
        Offset and length (0, 1 or 2) of ``d``.
    fsign : float
        ``1.0`` or ``-1.0``.
    ho : int
        Output offset; ``2 * elen * dlen`` slots.
    so : int
        Scratch offset; ``4 * elen`` slots.  No region may overlap another.

    Returns
    -------
    int
        Length of the product.
    """
    if dlen == 0:
        return 0
    if dlen == 1:
        return scale_expansion(w, eo, elen, fsign * w[do], ho)
    n1 = scale_expansion(w, eo, elen, fsign * w[do], so)
    n2 = scale_expansion(w, eo, elen, fsign * w[do + 1], so + 2 * elen)
    return expansion_sum(w, so, n1, so + 2 * elen, n2, 1.0, ho)


@nb.njit("float64(float64[::1], int64, int64)", cache=True)
def estimate(w, eo, elen):
    """Return a floating-point approximation of ``e`` whose sign is the exact sign.

    The components are summed smallest first (relative error a few ulps).  In the corner
    case where that rounded sum disagrees in sign with the most significant component (a
    near-total cancellation that rounding pushed over the edge), the component is returned.

    Parameters
    ----------
    w : float64 array
    eo, elen : int
        Offset and length of ``e``.

    Returns
    -------
    float
    """
    if elen == 0:
        return 0.0
    s = 0.0
    for i in range(elen):
        s += w[eo + i]
    t = w[eo + elen - 1]
    if (s > 0.0) != (t > 0.0) or s == 0.0:
        return t
    return s
