"""Max-min pattern search on the worst quads' free nodes (optimisation-based smoothing).

Where the guarded Laplacian (:mod:`meshwright.quad.smoothing`) stalls beside a sliver (the
average of a node's neighbours does not open its corner), each free node of a quad whose
smallest corner sine is below a floor tries moves in 16 directions at three step lengths
and takes the one that raises the smallest corner sine of its quads most: a derivative-free
max-min search, the local form of the optimisation-based smoothing of Freitag and
Plassmann ("Local optimization-based simplicial mesh untangling and improvement", Int. J.
Numer. Meth. Eng. 49, 2000) with the corner sine (the scaled Jacobian) as the quality.
A move never lowers a star's minimum, so no quad inverts.  Paving's cleanup (step 8,
:mod:`meshwright.quad.paving`) and the pairing methods' finish
(:mod:`meshwright.quad._pairing_finish`) run it.

Array layout: points (n, 2) float64; quads (q, 4) int64 counter-clockwise; ``fixed`` (n,)
bool.  Kernels in :mod:`meshwright.quad._polish_kernel`.
"""

from __future__ import annotations

import numpy as np

from meshwright.quad import _polish_kernel as pk

__all__ = ["may_be_below", "polish"]


def may_be_below(xy, quads, floor: float) -> bool:
    """Whether a quad of ``quads`` (q, 4) int64 over ``xy`` (n, 2) float64 may have a
    corner sine below ``floor`` > 0 (False only when every quad is clearly above: one
    pass of products, no square root; :func:`~meshwright.quad._polish_kernel.may_be_below`)."""
    return bool(pk.may_be_below(xy, quads, float(floor)))


def polish(xy, quads, fixed, floor: float, rounds: int):
    """Cleanup of the worst corners: every free node of a quad whose smallest corner
    sine is below ``floor`` tries moves in 16 directions at three step lengths (a
    quarter, an eighth and a sixteenth of its shortest edge) and takes the one that
    raises the smallest corner sine of its quads most (a max-min pattern search, as
    optimisation-based smoothing does where the Laplacian stalls; a move never lowers
    that minimum, so no quad inverts).

    Parameters
    ----------
    xy : (n, 2) float64
        Not modified.
    quads : (q, 4) int
        Counter-clockwise; strictly convex, or bent ones to open (a bent quad's smallest
        sine is not above zero, and no move lowers a star's smallest sine).
    fixed : (n,) bool
        Nodes that never move.
    floor : float
        Quads below this smallest corner sine are worked on.
    rounds : int
        Passes.

    Returns
    -------
    (n, 2) float64
    """
    p = np.array(xy, dtype=np.float64)
    q = np.ascontiguousarray(quads, dtype=np.int64)
    cell_ptr, cell_idx = pk.vertex_cells(q, len(p))
    ang = np.arange(16) * (np.pi / 8.0)
    dirs = np.ascontiguousarray(np.column_stack([np.cos(ang), np.sin(ang)]))
    steps = np.array([0.25, 0.125, 0.0625])
    fixed = np.ascontiguousarray(fixed, dtype=np.bool_)
    return pk.polish_rounds(p, q, cell_ptr, cell_idx, fixed, float(floor), int(rounds), dirs, steps)
