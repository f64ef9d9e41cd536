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

Contract: a function decorated with :func:`inner` must never be called from Python (the
dispatcher has no entry point to call: the interpreter crashes).  Use it only for helpers
that every caller calls from inside ``@njit`` code; anything a test or a Python module calls
stays plain ``@njit(cache=True)``.
"""

from __future__ import annotations

from numba import njit

__all__ = ["inner"]

_OPTIONS = {"cache": True, "no_cpython_wrapper": True, "no_cfunc_wrapper": True}


def inner(signature=None):
    """Decorator: ``@inner`` or ``@inner("int64(int64, ...)")`` (an explicit signature, compiled
    at import), a kernel-only ``@njit(cache=True)`` without the Python-callable wrappers."""
    if callable(signature):
        return njit(**_OPTIONS)(signature)
    if signature is None:
        return njit(**_OPTIONS)
    return njit(signature, **_OPTIONS)
