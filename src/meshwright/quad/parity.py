"""Even boundary node counts (chapter 18.5.1, step 1; 18.5.2's paving boundaries likewise).

A loop of quadrilaterals needs an even number of boundary nodes (J. Z. Zhu, O. C.
Zienkiewicz, E. Hinton and J. Wu, Int. J. Numer. Meth. Eng. 32, 1991; T. D. Blacker and
M. B. Stephenson, Int. J. Numer. Meth. Eng. 32, 1991).  :func:`make_loops_even` gives every
odd loop of a discretisation one node, on its longest segment at the arc-length midpoint of
the true curve, and spaces up to :data:`RESPACE` neighbours on each side evenly again so the
two half segments leave no sliver for the front; with the boundary fixed it raises
:class:`ParityError` naming the loop.  Shared by pairing, Zhu's front and paving.

Array layout: a :class:`~meshwright.geometry.domain.Discretization` in and out (points
(n, 2) float64, segments (m, 2) int32 in loop order, per-segment markers, curves and
curve parameters (m, 2) float64).
"""

from __future__ import annotations

import numpy as np

from meshwright.core.errors import GeometryError, InputError, fmt_point
from meshwright.core.validate_input import check_flag
from meshwright.geometry.domain import Discretization, Domain

__all__ = ["RESPACE", "ParityError", "make_loops_even"]

RESPACE = 6  # segments on each side of a parity split spaced evenly again


class ParityError(GeometryError):
    """A loop has an odd number of boundary nodes and its nodes may not change."""


def _loop_name(li: int) -> str:
    return "outer loop (loop 0)" if li == 0 else f"hole {li - 1} (loop {li})"


def _split_and_respace(domain: Domain, disc, r: int):
    """``disc`` with segment ``r`` split at its arc-length midpoint and the nodes of up to
    :data:`RESPACE` segments on each side (same curve piece) spaced evenly in arc length,
    so the two half segments leave no sliver for the front.  Curve ends and polyline
    corners never move; returns a new Discretization."""
    p = disc.points.copy()
    seg = disc.segments.astype(np.int64)
    c = int(disc.segment_curve[r])
    curve = domain.curves[c]
    ta, tb = disc.segment_params[r]
    tm = float(curve.midpoint_param(np.array([ta]), np.array([tb]))[0])
    n_loop = int(seg[domain.curve_loop[disc.segment_curve] >= 0].max()) + 1
    seg[seg >= n_loop] += 1
    u, w = seg[r]
    seg = np.concatenate([seg[:r], [[u, n_loop], [n_loop, w]], seg[r + 1 :]])
    p = np.concatenate([p[:n_loop], curve.evaluate(np.array([tm])), p[n_loop:]])
    par = np.concatenate([disc.segment_params[:r], [[ta, tm], [tm, tb]], disc.segment_params[r + 1 :]])
    dup = np.concatenate([np.arange(r + 1), np.arange(r, len(disc.segments))])
    curve_of = disc.segment_curve[dup]
    piece = curve.piece_index(par.mean(axis=1))
    same = (curve_of == c) & (piece == piece[r])
    lo, hi = r, r + 1
    while lo > 0 and r - lo < RESPACE and same[lo - 1] and seg[lo - 1, 1] == seg[lo, 0]:
        lo -= 1
    while hi < len(seg) - 1 and hi - r - 1 < RESPACE and same[hi + 1] and seg[hi + 1, 0] == seg[hi, 1]:
        hi += 1
    if hi > lo + 1:
        ends = curve.arclength(np.array([par[lo, 0], par[hi, 1]]))
        t_new = curve.t_at_length(np.linspace(ends[0], ends[1], hi - lo + 2)[1:-1])
        nodes = seg[lo + 1 : hi + 1, 0]
        p[nodes] = curve.evaluate(t_new)
        par[lo + 1 : hi + 1, 0] = t_new
        par[lo:hi, 1] = t_new
    pm = np.concatenate([disc.point_markers[:n_loop], [disc.segment_markers[r]], disc.point_markers[n_loop:]])
    return disc._replace(
        points=np.ascontiguousarray(p),
        segments=seg.astype(np.int32),
        segment_markers=disc.segment_markers[dup],
        segment_curve=curve_of,
        segment_params=par,
        point_markers=pm.astype(np.int32),
    )


def make_loops_even(domain: Domain, disc, fixed_boundary: bool = False):
    """Give every loop an even number of boundary nodes (step 1).

    A loop with an odd count gets one node: its longest segment is split at its
    arc-length midpoint on the true curve, and its neighbours on the same curve piece
    are spaced evenly again (:func:`_split_and_respace`).

    Parameters
    ----------
    domain : Domain
    disc : Discretization
        ``domain.discretize(...)``.
    fixed_boundary : bool
        Refuse to add nodes: an odd loop raises :class:`ParityError`.

    Returns
    -------
    Discretization
        With every loop even (``disc`` itself when nothing changed).
    tuple of int
        The loops that received a node.

    Raises
    ------
    InputError
        ``domain`` / ``disc`` of the wrong type, ``fixed_boundary`` not a bool.
    ParityError
        An odd loop with ``fixed_boundary=True`` (the loop and its first node named).
    """
    if not isinstance(domain, Domain):
        raise InputError(f"domain must be a meshwright.geometry.Domain, got {type(domain).__name__}")
    if not isinstance(disc, Discretization):
        raise InputError(f"disc must be the Discretization of domain.discretize(), got {type(disc).__name__}")
    fixed_boundary = check_flag(fixed_boundary, "fixed_boundary")
    added = []
    for li in range(len(domain.loops)):
        rows = np.flatnonzero(domain.curve_loop[disc.segment_curve] == li)
        if len(rows) % 2 == 0:
            continue
        e = disc.segments[rows]
        p = disc.points
        if fixed_boundary:
            raise ParityError(
                f"{_loop_name(li)} has {len(rows)} boundary nodes, an odd number, and fixed_boundary=True forbids "
                f"adding one (its first node is at {fmt_point(p[e[0, 0]])}); a loop of quadrilaterals needs an even count"
            )
        length = np.hypot(*(p[e[:, 1]] - p[e[:, 0]]).T)
        disc = _split_and_respace(domain, disc, int(rows[int(np.argmax(length))]))
        added.append(li)
    return disc, tuple(added)
