"""Numba's IR inlining (``@njit(inline="always")``) without its repeated work: same IR, less compile.

Why (numba 0.68, issue 13's first-run compile): every ``inline="always"`` call site runs
:meth:`numba.core.inline_closurecall.InlineWorker.inline_function`, which

1. runs the callee's whole untyped pipeline again (bytecode analysis, interpretation, the
   untyped passes, and with them the IR inlining of the callee's own ``inline="always"``
   callees: a nest of inlined helpers is rebuilt at every transitive call site), and
2. copies the result twice (``inline_ir``'s ``copy_ir``: once to mutate, once to return),
   each block by its own ``copy.deepcopy``.  Every block refers to the function's one
   ``Scope``, which holds every variable of the function, so each block's copy copies all
   the variables again: quadratic in the callee's size.

Over every 2-D method in one process, IR inlining was 35 of 183 s of ``numba:compile``
(``benchmarks/compile2d.py --profile``, load 3); the frontal kernel's ``_drop`` spent 7.6 of
its 11 s there.  The same defects are reported upstream (numba issues 8989 and 9204,
numba-cuda issue 688).

What :func:`install` changes, and why the inlined IR stays the same:

* the callee's untyped IR is computed once per (function, flags, contexts, pipeline) and
  kept: ``inline_ir`` copies it before any mutation, so the kept IR is never modified and
  every call site receives what a fresh run would have built (the untyped pipeline does
  not depend on the call site; the interpreter is deterministic);
* ``copy_ir``'s per-block deep copies share one memo per copied function, as a single
  ``copy.deepcopy`` of the block dictionary would: one copy of the scope and of each
  variable instead of one per block.  Blocks of the original share their scope and their
  variables; the copies now do too.

Nothing in the typed pipeline, the lowering or the code changes, and Numba's compile cache
is unaffected (it keys on the source, not on how the IR was built).  Only functions of the
modules named in :data:`SCOPE` (meshwright's) take the patched path: a user's own
``inline="always"`` functions are inlined by Numba's stock code, since keeping a callee's IR
would freeze the globals it read at its first inlining (a user redefining a global between
two compilations expects the new value; meshwright's kernels read module constants only).
The patch is not installed where the methods it replaces differ from the ones it was
written against, or where ``MESHWRIGHT_STOCK_INLINING=1`` is set (for A/B measurements and
as a way out).
"""

from __future__ import annotations

import copy
import inspect
import os
import types

__all__ = ["SCOPE", "install", "installed"]

# Module name prefixes whose inline="always" functions take the patched path.
SCOPE = ["meshwright."]

_STATE = {"installed": False}
# (function, flags, typing context, target context, pipeline) -> the callee's untyped IR.
_UNTYPED: dict = {}


class _SharedMemoCopy:
    """Stands in for the ``copy`` module inside ``inline_ir``: a block's deep copy uses the
    memo of its scope while one ``inline_ir`` call runs (``memos`` is not ``None``)."""

    memos = None

    def __getattr__(self, name):
        return getattr(copy, name)

    def deepcopy(self, x, memo=None):
        if memo is None and self.memos is not None and isinstance(x, self.block_type):
            memo = self.memos.setdefault(id(x.scope), {})
        return copy.deepcopy(x, memo)


def installed() -> bool:
    """Whether :func:`install` patched Numba's inliner in this process."""
    return _STATE["installed"]


def _expected(worker) -> bool:
    """The inliner has the methods and signatures this module was written against."""
    want = {
        "inline_ir": ["self", "caller_ir", "block", "i", "callee_ir", "callee_freevars", "arg_typs"],
        "inline_function": ["self", "caller_ir", "block", "i", "function", "arg_typs"],
        "run_untyped_passes": ["self", "func", "enable_ssa"],
    }
    for name, params in want.items():
        fn = getattr(worker, name, None)
        if not isinstance(fn, types.FunctionType) or list(inspect.signature(fn).parameters) != params:
            return False
    nested = [c for c in worker.inline_ir.__code__.co_consts if isinstance(c, types.CodeType)]
    return any(c.co_name == "copy_ir" and "deepcopy" in c.co_names for c in nested)


def install() -> bool:
    """Patch Numba's IR inliner once per process (module docstring); whether it is patched."""
    if _STATE["installed"]:
        return True
    if os.environ.get("MESHWRIGHT_STOCK_INLINING", "") == "1":
        return False
    try:
        from numba.core import inline_closurecall, ir
    except ImportError:
        return False
    worker = inline_closurecall.InlineWorker
    if not _expected(worker):
        return False

    shim = _SharedMemoCopy()
    shim.block_type = ir.Block
    stock_inline_ir = worker.inline_ir
    globals_ = dict(stock_inline_ir.__globals__, copy=shim)
    shared_memo_inline_ir = types.FunctionType(
        stock_inline_ir.__code__, globals_, stock_inline_ir.__name__,
        stock_inline_ir.__defaults__, stock_inline_ir.__closure__,
    )

    def inline_ir(self, caller_ir, block, i, callee_ir, callee_freevars, arg_typs=None):
        saved = shim.memos
        shim.memos = {}
        try:
            return shared_memo_inline_ir(self, caller_ir, block, i, callee_ir, callee_freevars, arg_typs)
        finally:
            shim.memos = saved

    stock_inline_function = worker.inline_function

    def inline_function(self, caller_ir, block, i, function, arg_typs=None):
        if not (getattr(function, "__module__", None) or "").startswith(tuple(SCOPE)):
            return stock_inline_function(self, caller_ir, block, i, function, arg_typs)
        if self.locals:
            callee_ir = self.run_untyped_passes(function)
        else:
            # run_untyped_passes sets this flag on the shared flags before it runs.
            self.flags.enable_ssa = False
            key = (function, repr(self.flags), self.typingctx, self.targetctx, self._compiler_pipeline)
            callee_ir = _UNTYPED.get(key)
            if callee_ir is None:
                callee_ir = self.run_untyped_passes(function)
                _UNTYPED[key] = callee_ir
        return inline_ir(self, caller_ir, block, i, callee_ir, function.__code__.co_freevars, arg_typs=arg_typs)

    inline_function.__doc__ = stock_inline_function.__doc__
    worker.inline_function = inline_function
    _STATE["installed"] = True
    return True
