"""``core.fast_inline``: Numba's IR inlining without its repeated work gives the same code.

A kernel whose ``inline="always"`` helpers nest (a multi-block helper inlined at several
sites, itself inlining another) is compiled in two fresh processes with empty caches, one
with Numba's stock inliner (``MESHWRIGHT_STOCK_INLINING=1``) and one with the patched one:
the machine code must be the same instruction for instruction, and the results equal to
plain Python arithmetic.  Also the kernels of the first ``delaunay`` call.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from meshwright.core import fast_inline

CHILD = r"""
import hashlib, json, re, sys
import numpy as np
from numba import njit
from meshwright.core import fast_inline, jit  # noqa: F401  (jit installs the patch)

if sys.argv[2] == "ours":
    fast_inline.SCOPE.append("__main__")  # this script's helpers take the patched path

@njit(inline="always")
def _leaf(a, i):
    s = 0.0
    for k in range(i):
        if a[k] > 0.0:
            s += a[k]
        else:
            s -= 2.0 * a[k]
    return s

@njit(inline="always")
def _mid(a, i, j):
    x = _leaf(a, i)
    if x > 3.0:
        x = x - _leaf(a, j)
    while x > 10.0:
        x *= 0.5
    return x

@njit
def kernel(a):
    t = 0.0
    for i in range(a.shape[0]):
        t += _mid(a, i, i // 2) + _mid(a, a.shape[0] - i, 1) + _leaf(a, i)
    return t

a = np.array([1.5, -2.0, 4.0, 0.25, -0.5, 8.0])
value = kernel(a)
fns = [kernel]
if sys.argv[1] == "delaunay":
    import meshwright as mw
    from meshwright.tri import _kernel2d, _build2d
    mw.delaunay(np.random.default_rng(0).random((200, 2)))
    fns += [_kernel2d.insert_arrays, _build2d.insert_batch]
digests = {}
for fn in fns:
    for sig in fn.signatures:
        lines = [re.sub(r"_ZN\S+", "SYM", l) for l in fn.inspect_asm(sig).splitlines()
                 if l.strip() and not l.strip().startswith(("#", ".file", ".ident", ".loc"))]
        digests[f"{fn.py_func.__name__}{sig}"] = hashlib.md5("\n".join(lines).encode()).hexdigest()
kept = sum(1 for key in fast_inline._UNTYPED if key[0].__module__ == "__main__")
print(json.dumps({"installed": fast_inline.installed(), "value": value, "asm": digests, "kept": kept}))
"""


def _leaf(a, i):
    return sum(x if x > 0.0 else -2.0 * x for x in a[:i])


def _mid(a, i, j):
    x = _leaf(a, i)
    if x > 3.0:
        x = x - _leaf(a, j)
    while x > 10.0:
        x *= 0.5
    return x


def _compile(tmp_path, stock: bool, what: str, scope: str = "ours") -> dict:
    cache = tmp_path / (("stock" if stock else "fast") + scope)
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache), MESHWRIGHT_STOCK_INLINING="1" if stock else "0")
    res = subprocess.run(
        [sys.executable, "-c", CHILD, what, scope], capture_output=True, text=True, env=env, timeout=600, check=False
    )
    assert res.returncode == 0, res.stderr[-3000:]
    return json.loads(res.stdout.strip().splitlines()[-1])


@pytest.mark.skipif(not fast_inline.installed(), reason="this Numba's inliner is not the one the patch knows")
@pytest.mark.parametrize("what", ["nested", "delaunay"])
def test_patched_inlining_compiles_the_same_machine_code(tmp_path, what):
    stock = _compile(tmp_path, True, what)
    fast = _compile(tmp_path, False, what)
    assert not stock["installed"] and fast["installed"]
    a = [1.5, -2.0, 4.0, 0.25, -0.5, 8.0]
    n = len(a)
    expected = sum(_mid(a, i, i // 2) + _mid(a, n - i, 1) + _leaf(a, i) for i in range(n))
    assert stock["value"] == pytest.approx(expected, rel=1e-12)
    assert fast["value"] == stock["value"]
    assert len(fast["asm"]) >= (3 if what == "delaunay" else 1)
    assert fast["asm"] == stock["asm"]


@pytest.mark.skipif(not fast_inline.installed(), reason="this Numba's inliner is not the one the patch knows")
def test_functions_outside_the_scope_are_inlined_by_numba_itself(tmp_path):
    """A user's own helpers (here ``__main__``'s, outside ``SCOPE``) go through the stock
    inliner: no IR of theirs is kept, and the code is the stock code."""
    stock = _compile(tmp_path, True, "nested", "user")
    fast = _compile(tmp_path, False, "nested", "user")
    assert fast["installed"] and fast["kept"] == 0
    assert fast["asm"] == stock["asm"] and fast["value"] == stock["value"]
