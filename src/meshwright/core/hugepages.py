"""NumPy's transparent-huge-page advice, off while a large mesh is built.

On Linux NumPy advises the kernel to back every array of 4 MiB or more with huge pages
(``madvise(MADV_HUGEPAGE)``).  Where the kernel's THP defrag setting is ``madvise`` (a
common default), the first touch of such a page may compact memory synchronously, and on a
machine whose memory is fragmented those stalls are seconds: the 1e6-tet sphere
(``tetrahedralize``) took 9.2-11.1 s CPU in the first call of a process and 5.1-7.0 s in
later ones, and 5.1-5.6 s every time with the advice off (same machine code, same mesh;
``benchmarks/README.md``, sixth session).  Gmsh and TetGen allocate without the advice.

:func:`small_pages` turns the advice off for the duration of a call and restores NumPy's
setting afterwards; arrays allocated meanwhile (by any thread) get ordinary pages, which
changes only their speed.  Where NumPy lacks the switch it does nothing.
"""

from __future__ import annotations

from contextlib import contextmanager

import numpy as np

__all__ = ["small_pages"]


def _switch():
    core = getattr(np, "_core", None) or getattr(np, "core", None)
    return getattr(getattr(core, "multiarray", None), "_set_madvise_hugepage", None)


@contextmanager
def small_pages():
    """Context in which NumPy does not advise huge pages for new arrays (module docstring)."""
    switch = _switch()
    if switch is None:
        yield
        return
    previous = switch(False)
    try:
        yield
    finally:
        switch(previous)
