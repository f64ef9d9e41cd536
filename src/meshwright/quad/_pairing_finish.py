"""The size :func:`meshwright.quad.pairing.pair_domain` meshes with, and its last polish.

* :func:`given_size`: a given size graded from the boundary points spaced closer than it,
  as :func:`meshwright.triangulate` grades it (:data:`GRADING`).  A triangle front from
  close boundary vertices at a coarse size closes in fans no pair can take (two boundary
  sides at a corner of nearly 180 degrees), which only chords could finish.
* :func:`boundary_background`: ``size="boundary"``'s background (chapter 18.3: the
  triangulated boundary nodes with their point distribution function), capped the same
  way where it grows faster than the grading allows.
* :func:`polish_fill`: paving's max-min pattern search
  (:func:`meshwright.quad._paving_close.polish`) on the free nodes of the quads with a
  corner sine under :data:`POLISH_BELOW`: the enhancement's Laplacian stalls beside
  slivers, and a chord refinement is smoothed only around its chords.

Quality rules in floating point; the polish never lowers the smallest corner sine around
a node, so no quad inverts (the caller's exact check follows).
"""

from __future__ import annotations

import numpy as np

from meshwright.quad.polish import line_sliders, may_be_below, polish
from meshwright.sizing.background import BackgroundGrid
from meshwright.sizing.boundary import boundary_size, graded_from_boundary

__all__ = ["GRADING", "POLISH_BELOW", "POLISH_ROUNDS", "boundary_background", "given_size", "polish_fill"]

POLISH_BELOW = 0.3  # quads with a corner sine below this (about 17.5 degrees) get the max-min search ...
POLISH_ROUNDS = 40  # ... up to this many passes (it stops at a pass that moves nothing)
GRADING = 1.2  # the size grows from finer boundary spacing by at most GRADING - 1 per unit length


def given_size(domain, field, keep_boundary: bool):
    """(field, discretisation): ``field`` graded from the boundary points of its
    discretisation spaced closer than it (:func:`~meshwright.sizing.boundary.graded_from_boundary`), and the boundary
    discretised again with the graded size unless ``keep_boundary``; ``field`` and its
    discretisation where nothing is finer, or for None."""
    disc = domain.discretize(field)
    graded = graded_from_boundary(field, disc.points, disc.segments, GRADING)
    if graded is field or keep_boundary:
        return graded, disc
    return graded, domain.discretize(graded)


def boundary_background(ct):
    """Chapter 18.3's background of the classified triangulation ``ct``, capped by the
    grading from its boundary nodes (:func:`~meshwright.sizing.boundary_size`) where its
    slope exceeds ``GRADING - 1`` (:func:`_steepest`): its linear interpolation between
    nodes far apart grows as fast as the boundary spacing jumps."""
    edges = ct.segments()[0]
    grid = BackgroundGrid.from_boundary(ct.points, edges, ct.triangles(False))
    if _steepest(grid) <= GRADING - 1.0:
        return grid
    return boundary_size(ct.points, edges, GRADING, base=grid)


def _steepest(grid) -> float:
    """Largest slope of a background grid's size over its triangles.  The size is linear
    on each and the triangles cover the convex hull of its nodes (slivers aside), so it
    grows by at most this per unit length from any node: at most ``GRADING - 1``, a cap
    graded from the nodes cannot bind, and the front keeps the compiled interpolation
    instead of a callback."""
    p, t, d = grid.points, grid.triangles, grid.delta
    if not len(t):
        return 0.0
    a, b, c = t[:, 0], t[:, 1], t[:, 2]
    u, w = p[b] - p[a], p[c] - p[a]
    fu, fw = d[b] - d[a], d[c] - d[a]
    det = u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0]
    return float(np.hypot((fu * w[:, 1] - fw * u[:, 1]) / det, (u[:, 0] * fw - w[:, 0] * fu) / det).max())


def polish_fill(fill, fixed_pts, domain=None):
    """``fill`` (a :class:`~meshwright.quad.mesher.QuadFill`) with the free nodes of its
    quads below :data:`POLISH_BELOW` moved by the max-min search; the nodes ``fixed_pts``
    (the input vertices) and the nodes of left-over triangles (the search reads quads
    only) stay, and line nodes stay too unless ``domain`` is given: then a line node of
    a straight curve slides along it (:func:`~meshwright.quad.polish.line_sliders`).
    Skipped, at the cost of one pass of products, when no quad may be below
    (:func:`~meshwright.quad.polish.may_be_below`)."""
    quads = np.ascontiguousarray(fill.quads, dtype=np.int64)
    if not len(quads) or not may_be_below(fill.points, quads, POLISH_BELOW):
        return fill
    fixed = np.zeros(len(fill.points), dtype=bool)
    fixed[fill.lines.ravel()] = True
    fixed[fixed_pts] = True
    slide = None
    if domain is not None:
        slide = line_sliders(len(fill.points), fill.lines, fill.line_curves, domain, fixed_pts)
        fixed[slide[:, 0] >= 0] = False
    fixed[fill.triangles.ravel()] = True
    return fill._replace(points=polish(fill.points, quads, fixed, POLISH_BELOW, POLISH_ROUNDS, slide))
