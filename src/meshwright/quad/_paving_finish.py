"""The last steps of :func:`meshwright.quad.paving.pave_domain` (step 8): numbering,
chord refinement of left-over triangles, smoothing, the max-min cleanup and the exact
convexity check.

Array layout: points (n, 2) float64; quads (q, 4) and triangles (t, 3) int64 in, a
:class:`~meshwright.quad.mesher.QuadFill` out.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from meshwright.core.errors import MeshingError, fmt_point
from meshwright.quad._paving_close import convex
from meshwright.quad.polish import line_sliders, may_be_below, polish
from meshwright.quad.smoothing import smooth_cells

__all__ = ["TRY_PAIRING_BELOW", "Finish", "fill_by_pairing", "finish"]

TRY_PAIRING_BELOW = 0.2  # a paved constrained mesh with a smaller unforced corner sine is compared with pairing's


class Finish(NamedTuple):
    """The cleanup's rules (the constants of :mod:`meshwright.quad.paving`)."""

    smooth: int
    settle: float
    polish_below: float
    polish_rounds: int
    mend_rounds: int


def finish(xy, quads, tris, n_fixed: int, disc, domain, cap: int, all_quad: bool, points, rules: Finish):
    """The fill of the paved and void-filled cells: unused nodes dropped (the first
    ``n_fixed``, the discretisation's, kept), left-over triangles split along chords when
    ``all_quad``, then smoothing and cleanup with the lines' nodes and ``points`` (node ids
    of the interior points) fixed.  Returns (QuadFill, whether chords were split).

    Raises
    ------
    MeshingError
        A quad still not strictly convex after the cleanup (its corners named).
    """
    from meshwright.quad.chords import chord_split
    from meshwright.quad.mesher import QuadFill

    lines = disc.segments.astype(np.int32)
    used = np.zeros(len(xy), dtype=bool)
    used[quads.ravel()] = True
    used[tris.ravel()] = True
    used[:n_fixed] = True
    newid = np.cumsum(used) - 1
    xy = np.ascontiguousarray(xy[used])
    quads = newid[quads].astype(np.int32)
    tris = newid[tris].astype(np.int32)
    fill = QuadFill(xy, quads, tris, lines, disc.segment_markers.astype(np.int32), disc.segment_curve.astype(np.int32))
    split = bool(all_quad and len(tris))
    if split:
        # The lines are the discretisation's segments in order: their curve parameters
        # give the split lines' midpoints without projecting their ends.
        fill = chord_split(fill, domain, cap, disc.segment_params)
    fixed = np.zeros(len(fill.points), dtype=bool)
    fixed[fill.lines.ravel()] = True
    # The interior points are nodes of no line: they stay where the domain has them.
    fixed[newid[points]] = True
    moved = smooth_cells(fill.points, fill.quads, fill.triangles, fixed, rules.smooth, rules.settle)
    pinned, slide = fixed, None
    if not len(fill.triangles) and may_be_below(moved, fill.quads, rules.polish_below):
        # Line nodes that are no input vertex slide along their straight piece in the
        # polish.  With no quad below the floor the polish would move nothing: the
        # benchmarks' meshes skip the sliders' NumPy setup.
        keep = _input_vertices(disc, domain, newid[points])
        slide = line_sliders(len(fill.points), fill.lines, fill.line_curves, domain, keep)
        pinned = fixed & (slide[:, 0] < 0)
        moved = polish(moved, fill.quads, pinned, rules.polish_below, rules.polish_rounds, slide)
    fill = fill._replace(points=np.ascontiguousarray(moved))
    bad = np.flatnonzero(~convex(fill.points, fill.quads))
    if len(bad) and not len(fill.triangles):
        # The chord split may leave bent quads that the smoothing and the first passes
        # do not open (15 on a sliver under a size jump, one left at the end); each pass
        # only raises a star's smallest sine, so more passes open them.
        fill = fill._replace(points=polish(fill.points, fill.quads, pinned, rules.polish_below, rules.mend_rounds, slide))
        bad = np.flatnonzero(~convex(fill.points, fill.quads))
    if len(bad):
        c = int(bad[0])
        raise MeshingError(
            "paving produced a non-convex quad with corners "
            + ", ".join(fmt_point(fill.points[v]) for v in fill.quads[c])
        )
    return fill, split


def _input_vertices(disc, domain, points):
    """Node ids the polish never slides: the interior ``points`` and the polylines'
    vertices (the discretisation's nodes at an integer parameter of a polyline; the
    discretisation's nodes keep their ids in the fill)."""
    from meshwright.geometry.curves import Polyline

    poly = np.array([isinstance(c, Polyline) for c in domain.curves], dtype=bool)
    on = poly[disc.segment_curve]
    t = disc.segment_params
    vert = on[:, None] & (t == np.floor(t))
    return np.concatenate([np.asarray(points, dtype=np.int64).ravel(), disc.segments[vert].astype(np.int64)])


def _unforced_min_sine(fill) -> float:
    """The smallest corner sine of ``fill``'s quads over the corners the input does not
    force (a corner between two line cells keeps the input's angle in every fill, so it
    cannot tell two fills apart); ``inf`` when there is none."""
    q = np.asarray(fill.quads, dtype=np.int64)
    if not len(q):
        return np.inf
    n = np.int64(len(fill.points))
    ln = np.asarray(fill.lines, dtype=np.int64).reshape(-1, 2)
    keys = np.concatenate([ln[:, 0] * n + ln[:, 1], ln[:, 1] * n + ln[:, 0]])
    prev, nxt = np.roll(q, 1, axis=1), np.roll(q, -1, axis=1)
    forced = np.isin(q * n + prev, keys) & np.isin(q * n + nxt, keys)
    xy = fill.points
    u, w = xy[nxt] - xy[q], xy[prev] - xy[q]
    cr = u[..., 0] * w[..., 1] - u[..., 1] * w[..., 0]
    sine = cr / np.maximum(np.hypot(u[..., 0], u[..., 1]) * np.hypot(w[..., 0], w[..., 1]), 1e-300)
    return float(sine[~forced].min()) if (~forced).any() else np.inf


def fill_by_pairing(out, domain, field, all_quad: bool, fixed_boundary: bool, seed, cap: int):
    """``out`` (a paving's (QuadFill, counts)), or the pairing method's fill of the whole
    domain where that has the larger smallest corner sine at the corners the input does
    not force and no quad was paved or ``out``'s is under :data:`TRY_PAIRING_BELOW`, or
    where ``out`` is None (the paving failed: a quad bent by the chord split under a size
    jump, which the pairing's re-cut split opens).

    With interior segments or points a row often fits nowhere (a size coarse beside the
    domain's features, an obstacle near every paving boundary: most of the stress
    harness's junction domains), and the whole domain is the void;
    :func:`~meshwright.quad.pairing.pair_domain` (its grading of the boundary, centre
    pairing, chord re-cuts and cleanup; line nodes fixed, as the paving keeps them) is
    the better fill on about half of those (stress seed 15003), the void fill on the rest.
    Counts as those of :class:`~meshwright.quad.paving.PavingReport` after ``nodes_added``.
    """
    from meshwright.quad.pairing import pair_domain

    if out is not None and out[1][6] and _unforced_min_sine(out[0]) >= TRY_PAIRING_BELOW:
        return out
    fill, rep = pair_domain(
        domain, field, all_quad=all_quad, smooth_boundary=False, fixed_boundary=fixed_boundary, seed=seed,
        max_points=cap,
    )
    if out is not None and (not len(fill.quads) or _unforced_min_sine(fill) <= _unforced_min_sine(out[0])):
        return out
    return fill, (0, 0, 0, 0, 0, 0, 0, 1, len(fill.quads), rep.split, len(fill.triangles))
