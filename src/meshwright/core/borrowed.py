r"""Borrowed array views for Numba kernels: the same arrays without their reference count.

Why (numba 0.68; measured on the frontal and refinement kernels, issue 13): Numba's IR-level inlining
(``@njit(inline="always")``) binds every argument of the inlined helper to a new variable,
and a new variable holding an array is an ``NRT_incref`` of its meminfo where it is bound
and an ``NRT_decref`` where it dies.  When the helper's body branches (a short-circuit
``and``, an ``if``, a loop), the decrefs land in other basic blocks than the incref, and
Numba's reference-count pruning (per block, diamond, fan-out patterns) leaves the pairs in
place: every call of such a helper in a loop costs two atomic read-modify-writes per array
argument.  A plain ``@njit`` helper that LLVM inlines costs the same (the callee increfs
its arguments).  In the frontal kernel these pairs were about 20 % of the run's samples;
in Delaunay refinement's loop, where every new vertex hands the three bundles to its
helpers, about 45 % of the CPU time (``benchmarks/README.md``).  The minimal case::

    @njit(inline="always")
    def inside(t, tri, reg):
        return t >= 0 and tri[3 * t + 2] != -1 and reg[t] >= 0

    @njit
    def count(tri, reg, nbr):          # 13.7 ns per iteration, 5 incref / 7 decref sites
        c = 0
        for i in range(nbr.shape[0]):
            if inside(nbr[i], tri, reg):
                c += 1
        return c

and the same loop over ``borrowed(tri)``, ``borrowed(reg)``: 1.5 ns per iteration, no
reference-count call left (the meminfo is a null constant, so LLVM drops the calls;
``NRT_incref`` / ``NRT_decref`` of a null meminfo return at once where it is not known).

:func:`borrowed` returns its argument, an array or a (named) tuple of arrays and scalars
(nested tuples too), with every array's meminfo set to null; data, shape, strides and
parent are kept.  Contract: a borrowed view does not own its memory, so it must not
outlive the reference it was made from — make views of a kernel's arguments (the caller
keeps them alive for the whole call), never of an array the kernel allocates, and never
return or store one.
"""

from __future__ import annotations

from numba.core import cgutils, types
from numba.core.errors import TypingError
from numba.extending import intrinsic

__all__ = ["borrowed"]


def _check(ty) -> None:
    if isinstance(ty, types.Array):
        return
    if isinstance(ty, types.BaseTuple):
        for member in ty:
            _check(member)
        return
    if isinstance(ty, (types.Number, types.Boolean, types.NoneType)):
        return
    raise TypingError(f"borrowed: arrays, numbers and tuples of them only, got {ty}")


def _strip(context, builder, ty, value):
    """``value`` of type ``ty`` with a null meminfo in every array it holds."""
    if isinstance(ty, types.Array):
        ary = context.make_array(ty)(context, builder, value)
        ary.meminfo = cgutils.get_null_value(ary.meminfo.type)
        return ary._getvalue()
    if isinstance(ty, types.BaseTuple):
        out = value
        for i, member in enumerate(ty):
            item = _strip(context, builder, member, builder.extract_value(value, i))
            out = builder.insert_value(out, item, i)
        return out
    return value


@intrinsic
def borrowed(typingctx, value):
    """``value`` (an array or a tuple of arrays and scalars) with no reference counting:
    see the module docstring for when it is safe."""
    _check(value)

    def codegen(context, builder, sig, args):
        return _strip(context, builder, sig.args[0], args[0])

    return value(value), codegen
