"""The Numba decorator of kernel-internal helpers: compiled without the Python-callable wrappers.

Why (numba 0.68, measured for issue 13's first-run compile): every ``@njit`` function
compiles, besides its own body, a CPython wrapper (unboxing each argument from a Python
object, boxing the result, raising the error) and a C-callable wrapper, both lowered and
optimised by LLVM and written to the cache, even when the function is only ever called
from other kernels.  On a helper taking five arrays that is half its compile time
(0.112 -> 0.058 s CPU each, cached; a scalar helper 0.048 -> 0.026 s).  A helper that
only kernels call needs neither: :func:`inner` compiles it with Numba's
``no_cpython_wrapper`` and ``no_cfunc_wrapper`` options (and ``cache=True``); its callers
link its LLVM code as with any ``@njit`` callee, so the run time is the same.

Contract: a function decorated with :func:`inner` is called only from inside ``@njit``
code; anything a test or a Python module calls stays plain ``@njit(cache=True)``.  Its
dispatcher has no Python entry point (calling the compiled code from the interpreter would
crash it), so the dispatcher's class is :class:`InnerDispatcher`, whose ``__call__`` raises
a ``TypeError`` naming the function instead; kernels reach the compiled code directly, as
with any ``@njit`` callee.
"""

from __future__ import annotations

from numba import njit
from numba.core.registry import CPUDispatcher

from meshwright.core import fast_inline

__all__ = ["InnerDispatcher", "inner"]

# Every kernel module imports this one before its first compile: patch the IR inliner then.
fast_inline.install()

_OPTIONS = {"cache": True, "no_cpython_wrapper": True, "no_cfunc_wrapper": True}


class InnerDispatcher(CPUDispatcher):
    """The dispatcher of an :func:`inner` function: typed and compiled as any ``@njit``
    callee, but a call from Python raises instead of entering code that has no entry point."""

    def __call__(self, *args, **kwargs):
        raise TypeError(
            f"{self.py_func.__module__}.{self.py_func.__qualname__} is a kernel-only helper "
            "(meshwright.core.jit.inner): call it from @njit code"
        )


def _kernel_only(dispatcher):
    dispatcher.__class__ = InnerDispatcher
    return dispatcher


def inner(signature=None):
    """Decorator: ``@inner`` or ``@inner("int64(int64, ...)")`` (an explicit signature, compiled
    at import), a kernel-only ``@njit(cache=True)`` without the Python-callable wrappers."""
    if callable(signature):
        return _kernel_only(njit(**_OPTIONS)(signature))
    if signature is None:
        return lambda fn: _kernel_only(njit(**_OPTIONS)(fn))
    return lambda fn: _kernel_only(njit(signature, **_OPTIONS)(fn))
