"""Explicit random state for ``@njit`` kernels: a 32-bit xorshift generator.

Kernels that need cheap pseudo-random choices (the stochastic visibility walks of the 2-D and
3-D Delaunay kernels pick their first edge/face at random so that they terminate in any
triangulation) keep the generator state in an int64 slot of their own state bundle and pass
it explicitly.  Nothing here touches a global seed.

Source: G. Marsaglia, "Xorshift RNGs", Journal of Statistical Software 8(14), 2003 (the
13/17/5 triple of a 32-bit generator).  Invariant: the state lies in ``[1, 2**32)``; zero is
a fixed point and is never produced from a non-zero state.
"""

from __future__ import annotations

from meshwright.core.jit import inner

__all__ = ["seed_state", "xorshift32"]


def seed_state(seed: int) -> int:
    """Non-zero 32-bit xorshift state derived from any integer ``seed``."""
    return (int(seed) * 2654435761 + 1) % 0xFFFFFFFF or 1


@inner
def xorshift32(r):
    """Next state of the 32-bit xorshift generator (also the pseudo-random output).

    Parameters
    ----------
    r : int64
        Current state in ``[1, 2**32)``.

    Returns
    -------
    int64
        Next state in ``[1, 2**32)``.
    """
    r ^= (r << 13) & 0xFFFFFFFF
    r ^= r >> 17
    r ^= (r << 5) & 0xFFFFFFFF
    return r
