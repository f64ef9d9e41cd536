"""Max-min pattern search on the worst quads' free nodes (optimisation-based smoothing).

Where the guarded Laplacian (:mod:`meshwright.quad.smoothing`) stalls beside a sliver (the
average of a node's neighbours does not open its corner), each free node of a quad whose
smallest corner sine is below a floor tries moves in 16 directions at three step lengths
and takes the one that raises the smallest corner sine of its quads most: a derivative-free
max-min search, the local form of the optimisation-based smoothing of Freitag and
Plassmann ("Local optimization-based simplicial mesh untangling and improvement", Int. J.
Numer. Meth. Eng. 49, 2000) with the corner sine (the scaled Jacobian) as the quality.
A move never lowers a star's minimum, so no quad inverts.  A line node that is no
input vertex, on a straight curve (:func:`line_sliders`), searches along its line instead,
towards either line neighbour: the domain does not change.  Paving's cleanup (step 8,
:mod:`meshwright.quad.paving`) and the pairing methods' finish
(:mod:`meshwright.quad._pairing_finish`) run it.

Array layout: points (n, 2) float64; quads (q, 4) int64 counter-clockwise; ``fixed`` (n,)
bool.  Kernels in :mod:`meshwright.quad._polish_kernel`.
"""

from __future__ import annotations

import numpy as np

from meshwright.quad import _polish_kernel as pk

__all__ = ["line_sliders", "may_be_below", "polish"]

SLIDE_STEPS = (0.5, 0.25, 0.125, 0.0625)  # a sliding node's trials, times its shorter line edge


def may_be_below(xy, quads, floor: float) -> bool:
    """Whether a quad of ``quads`` (q, 4) int64 over ``xy`` (n, 2) float64 may have a
    corner sine below ``floor`` > 0 (False only when every quad is clearly above: one
    pass of products, no square root; :func:`~meshwright.quad._polish_kernel.may_be_below`)."""
    return bool(pk.may_be_below(xy, quads, float(floor)))


def line_sliders(n: int, lines, line_curves, domain, keep):
    """(n, 2) int64: for each node that may slide along its straight line piece, its two
    line neighbours; -1 elsewhere.  Such a node is on exactly two lines, both of one
    :class:`~meshwright.geometry.curves.Line` or
    :class:`~meshwright.geometry.curves.Polyline` curve, and is not in ``keep`` (the
    input vertices: polyline vertices, curve ends where one curve is a loop, given
    points).  Its neighbours are then on the same straight piece (a polyline's vertices
    are in ``keep``), so a point between it and one of them is on the domain's boundary
    or segment: the move changes no input.  Curved (parametric) lines do not slide."""
    from meshwright.geometry.curves import Line, Polyline

    slide = np.full((n, 2), -1, dtype=np.int64)
    lines = np.asarray(lines, dtype=np.int64).reshape(-1, 2)
    if not len(lines):
        return slide
    straight = np.array([isinstance(c, (Line, Polyline)) for c in domain.curves], dtype=bool)
    curve = np.asarray(line_curves, dtype=np.int64)
    deg = np.bincount(lines.ravel(), minlength=n)
    # A node on a curved line, or on lines of two curves, is marked off.
    lo = np.full(n, np.iinfo(np.int64).max)
    hi = np.full(n, -1)
    np.minimum.at(lo, lines.ravel(), np.repeat(curve, 2))
    np.maximum.at(hi, lines.ravel(), np.repeat(curve, 2))
    ok = (deg == 2) & (lo == hi) & (hi >= 0)
    ok &= straight[np.where(hi >= 0, hi, 0)]
    ok[np.asarray(keep, dtype=np.int64)] = False
    ends = lines.ravel()
    other = lines[:, ::-1].ravel()
    order = np.argsort(ends, kind="stable")
    ends, other = ends[order], other[order]
    first = np.searchsorted(ends, np.arange(n))
    v = np.flatnonzero(ok)
    slide[v, 0] = other[first[v]]
    slide[v, 1] = other[first[v] + 1]
    # Two lines between the same two nodes (a loop of two lines) give no piece to slide on.
    slide[v[slide[v, 0] == slide[v, 1]]] = -1
    return slide


def polish(xy, quads, fixed, floor: float, rounds: int, slide=None):
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
    slide : (n, 2) int, optional
        From :func:`line_sliders`: a node with line neighbours there (and not
        ``fixed``) moves only towards one of them, by :data:`SLIDE_STEPS` times its
        shorter line edge, with the same max-min choice.

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
    if slide is None:
        slide = np.full((len(p), 2), -1, dtype=np.int64)
    slide = np.ascontiguousarray(slide, dtype=np.int64)
    return pk.polish_rounds(
        p, q, cell_ptr, cell_idx, fixed, float(floor), int(rounds), dirs, steps, slide, np.array(SLIDE_STEPS)
    )
