"""Shape enhancement of paired quads (Zhu et al. 1991, chapter 18.5.1) and their smoothing.

Source: J. Z. Zhu, O. C. Zienkiewicz, E. Hinton and J. Wu, "A new approach to the
development of automatic quadrilateral mesh generation", Int. J. Numer. Meth. Eng. 32,
1991: node elimination, element elimination and diagonal swapping (the kernels in
:mod:`meshwright.quad._enhance_kernel`), followed by the chapter's Laplacian smoothing
(18.2) with boundary nodes sliding on their curves
(:func:`meshwright.quad.smoothing.smooth_sliding`): a move is accepted only if the
smallest corner sine around the node does not fall and every quad strictly convex before
it stays so (exact ``orient2d``).  After it, a node that never moves with a corner wider
than 150 degrees between its only two quads has the free node across their common side
turned towards the bisector of its angle, when that raises the worst scaled Jacobian
around it (:func:`meshwright.quad._enhance_kernel.balance_corners`; a reflex input corner
the smoothing left split 172 / 110 degrees).

Passes after the first examine only the quads next to the previous pass's changes (the
kernel's ``dirty`` flags), which decides exactly as a pass over every quad.

Invariants: every quad an operation or a move produces is strictly convex by exact
``orient2d``; boundary nodes (and segment and interior-point nodes) are never removed, and
move only along their true curves; a quad that stays non-convex is cut back into two
counter-clockwise triangles (:func:`unpair_nonconvex`).

Array layout: points (n, 2) float64; quads (q, 4) and triangles (t, 3) int32
counter-clockwise; lines (k, 2) int32 with (k,) curve indices into ``Domain.curves``.
"""

from __future__ import annotations

import numpy as np

from meshwright.core.errors import InputError, MeshingError, fmt_point
from meshwright.core.predicates import orient2d_batch
from meshwright.core.validate_input import as_cells, as_points, check_count
from meshwright.geometry.curves import Line, Parametric, Polyline
from meshwright.geometry.domain import Domain
from meshwright.quad import _enhance_kernel as ek
from meshwright.quad._pairing_kernel import nonconvex_quads
from meshwright.quad.smoothing import smooth_sliding

__all__ = [
    "ACCEPT",
    "ENHANCE_PASSES",
    "ENHANCE_SETTLE",
    "ENHANCE_SMOOTH",
    "SWAP_GAIN",
    "enhance",
    "min_scaled_jacobian",
    "nonconvex",
    "resplit_leftovers",
    "smooth_quads",
    "unpair_nonconvex",
]

ENHANCE_PASSES = 8  # cap on enhancement passes (each stops early when nothing changes)
ENHANCE_SMOOTH = 5  # Laplacian passes of the enhancement (and again after a split) ...
ENHANCE_SETTLE = 1e-2  # ... after the first, only where a node moved more than this times an edge
ACCEPT = 0.4  # element elimination may lower the local worst scaled Jacobian, but not below this
SWAP_GAIN = 0.02  # a diagonal swap must raise the pair's worst scaled Jacobian by more than this
RESPLIT_BELOW = 0.2  # a left-over triangle and a quad are re-split only under this worst corner sine
RESPLIT_PASSES = 4  # cap on re-splitting passes (each stops early when nothing changes)


def enhance(points, quads, boundary, triangles=None, passes=ENHANCE_PASSES):
    """Node elimination, element elimination and diagonal swapping (step 8's enhancement).

    Parameters
    ----------
    points : (n, 2) float64
        Not modified.
    quads : (q, 4) int32
        Strictly convex, counter-clockwise.
    boundary : (n,) bool
        Nodes on the boundary or on interior segments: never moved or removed.
    triangles : (t, 3) int32, optional
        Left-over triangles; their nodes are not touched.
    passes : int
        Cap on passes.

    Returns
    -------
    points : (n, 2) float64
        A copy (element elimination moves nodes).
    quads : (q', 4) int32
    kept : (q',) int64
        Row of ``quads`` (input) each output quad continues.
    counts : tuple of int
        Node eliminations, element eliminations, diagonal swaps.

    Raises
    ------
    InputError
        Points not (n, 2) finite, a quad or triangle row out of range (named),
        ``boundary`` not an (n,) bool array, ``passes`` not a count.
    """
    xy = as_points(points, "points", copy=True)
    qd = as_cells(quads, "quads", 4, len(xy)).copy()
    b = np.asarray(boundary)
    if b.shape != (len(xy),) or b.dtype != bool:
        raise InputError(f"boundary must be a ({len(xy)},) bool array, got {b.dtype} of shape {b.shape}")
    passes = check_count(passes, "passes")
    alive = np.ones(len(qd), dtype=np.int8)
    bnd = b.astype(np.int8)
    tri_node = np.zeros(len(xy), dtype=np.int8)
    if triangles is not None:
        tri_node[as_cells(triangles, "triangles", 3, len(xy)).ravel()] = 1
    total = np.zeros(3, dtype=np.int64)
    dirty = np.ones(len(qd), dtype=np.int8)
    for _ in range(passes):
        off, idx = ek.node_quads(qd, alive, len(xy))
        got = ek.enhance_pass(xy, qd, alive, bnd, off, idx, tri_node, ACCEPT, SWAP_GAIN, dirty)
        total += np.asarray(got)
        if sum(got) == 0:
            break
    kept = np.flatnonzero(alive == 1)
    return xy, qd[kept], kept, tuple(int(c) for c in total)


def resplit_leftovers(points, quads, triangles, boundary, lines, passes=RESPLIT_PASSES):
    """Left-over triangles re-split with a quad beside them (before the chord refinement),
    and low quads swapped across sides between two boundary nodes.

    A triangle and the quad across one of its interior sides form a pentagon; where the
    pair's worst corner sine is under :data:`RESPLIT_BELOW`, it is re-split along the
    pentagon diagonal that raises it most (by more than :data:`SWAP_GAIN`), judged over
    the triangle's three sides (:func:`meshwright.quad._enhance_kernel.resplit_pass`).
    The chord refinement keeps a triangle's corners as corners of its quads, so a sliver
    triangle at fixed nodes would leave slivers no smoothing opens.  Then a quad with a
    corner between three boundary nodes under the same bound (one the smoothing cannot
    open) swaps a side between two boundary nodes that is not a line with the quad
    across it, when the better other diagonal of their hexagon gains as much
    (:func:`meshwright.quad._enhance_kernel.swap_low_pass`): :func:`enhance` swaps only
    sides with a free node, as it has no lines to tell a side across the domain from an
    interior segment.  No node moves.
    Meant for the pairing's left-overs twice: after :func:`enhance`, and after
    :func:`unpair_nonconvex` (a quad the smoothing left non-convex is cut back along the
    diagonal that makes both triangles counter-clockwise, however thin).

    Parameters
    ----------
    points : (n, 2) float64
    quads : (q, 4) int32
        Strictly convex, counter-clockwise; not modified.
    triangles : (t, 3) int32
        Counter-clockwise; not modified.
    boundary : (n,) bool
        Nodes on the boundary or on interior segments (or fixed): no new quad has a
        corner wider than 150 degrees between three of them.
    lines : (k, 2) int
        Boundary and interior-segment edges: never crossed (an interior segment has
        quads on both sides).
    passes : int
        Cap on passes.

    Returns
    -------
    quads : (q, 4) int32
        Same rows, some re-cut: every new one strictly convex (exact).
    triangles : (t, 3) int32
        Same rows, some moved: every one counter-clockwise (exact).
    count : int
        Pairs re-split and quads swapped.

    Raises
    ------
    InputError
        Points not (n, 2) finite, a row out of range, ``boundary`` not (n,) bool,
        ``passes`` not a count.
    """
    xy = as_points(points, "points")
    qd = np.ascontiguousarray(as_cells(quads, "quads", 4, len(xy)), dtype=np.int32).copy()
    td = np.ascontiguousarray(as_cells(triangles, "triangles", 3, len(xy)), dtype=np.int32).copy()
    b = np.asarray(boundary)
    if b.shape != (len(xy),) or b.dtype != bool:
        raise InputError(f"boundary must be a ({len(xy)},) bool array, got {b.dtype} of shape {b.shape}")
    passes = check_count(passes, "passes")
    ln = as_cells(lines, "lines", 2, len(xy)).astype(np.int64)
    total = 0
    if not len(qd):
        return qd, td, total
    bnd = b.astype(np.int8)
    ends = np.concatenate([ln, ln[:, ::-1]])
    order = np.argsort(ends[:, 0], kind="stable")
    loff = np.searchsorted(ends[order, 0], np.arange(len(xy) + 1)).astype(np.int64)
    lidx = ends[order, 1]
    alive = np.ones(len(qd), dtype=np.int8)
    for _ in range(passes):
        off, idx = ek.node_quads(qd, alive, len(xy))
        got = ek.resplit_pass(xy, qd, td, bnd, off, idx, loff, lidx, RESPLIT_BELOW, SWAP_GAIN) if len(td) else 0
        if got:
            off, idx = ek.node_quads(qd, alive, len(xy))
        got += ek.swap_low_pass(xy, qd, bnd, off, idx, loff, lidx, RESPLIT_BELOW, SWAP_GAIN)
        total += got
        if got == 0:
            break
    return qd, td, total


def nonconvex(xy: np.ndarray, quads: np.ndarray) -> np.ndarray:
    """Indices (k,) int64 of quads with a corner that is not strictly convex (exact orient2d):
    :func:`meshwright.quad._pairing_kernel.nonconvex_quads` on the layouts pairing passes it."""
    return nonconvex_quads(np.ascontiguousarray(xy, dtype=np.float64), np.ascontiguousarray(quads, dtype=np.int32))


def unpair_nonconvex(xy, quads, tris):
    """Quads that enhancement and smoothing left non-convex go back to two triangles each,
    cut along the diagonal that makes both counter-clockwise (exact ``orient2d``; a simple
    quadrilateral always has one).  Returns (quads, triangles)."""
    bad = nonconvex(xy, quads)
    if not len(bad):
        return quads, tris
    q = quads[bad].astype(np.int64)
    cut02 = np.concatenate([q[:, [0, 1, 2]], q[:, [0, 2, 3]]])
    cut13 = np.concatenate([q[:, [1, 2, 3]], q[:, [1, 3, 0]]])
    m = len(q)
    o02 = orient2d_batch(xy, cut02)
    o13 = orient2d_batch(xy, cut13)
    use02 = (o02[:m] > 0.0) & (o02[m:] > 0.0)
    use13 = (o13[:m] > 0.0) & (o13[m:] > 0.0)
    if not (use02 | use13).all():
        i = int(bad[np.flatnonzero(~(use02 | use13))[0]])
        raise MeshingError(
            f"pairing left quad {i} with corners {', '.join(fmt_point(xy[v]) for v in quads[i])} that no diagonal splits"
        )
    halves = np.where(np.concatenate([use02, use02])[:, None], cut02, cut13)
    keep = np.ones(len(quads), dtype=bool)
    keep[bad] = False
    return quads[keep], np.concatenate([np.asarray(tris, dtype=np.int32).reshape(-1, 3), halves.astype(np.int32)])


def min_scaled_jacobian(xy, quads) -> float:
    """Smallest scaled Jacobian over ``quads`` (a quality rule, floating point)."""
    q = np.asarray(quads, dtype=np.int64)
    worst = 1.0
    for k in range(4):
        p, c, n = xy[q[:, (k + 3) % 4]], xy[q[:, k]], xy[q[:, (k + 1) % 4]]
        u, w = n - c, p - c
        sine = (u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0]) / (np.hypot(*u.T) * np.hypot(*w.T))
        worst = min(worst, float(sine.min()))
    return worst


def _fixed_nodes(xy, lines, line_curve, domain: Domain, n_interior_fixed) -> np.ndarray:
    """(n,) bool: nodes smoothing never moves: where two curves meet, polygon corners, given points."""
    n = len(xy)
    lo = np.full(n, np.iinfo(np.int64).max)
    hi = np.full(n, -1)
    np.minimum.at(lo, lines.ravel(), np.repeat(line_curve, 2))
    np.maximum.at(hi, lines.ravel(), np.repeat(line_curve, 2))
    fixed = (hi >= 0) & (lo != hi)
    straight = np.array([isinstance(c, (Line, Polyline)) for c in domain.curves], dtype=bool)
    e = lines[straight[line_curve]]
    nxt = np.full(n, -1)
    prv = np.full(n, -1)
    nxt[e[:, 0]] = e[:, 1]
    prv[e[:, 1]] = e[:, 0]
    mid = np.flatnonzero((nxt >= 0) & (prv >= 0))
    fixed[mid] |= orient2d_batch(xy, np.column_stack([prv[mid], mid, nxt[mid]])) != 0.0
    fixed[n_interior_fixed] = True
    return fixed, np.where(hi >= 0, hi, 0)


def smooth_quads(xy, quads, tris, lines, line_curve, domain, fixed_pts, passes, sliding=True, params=None):
    """Laplacian smoothing of a quad-dominant mesh that keeps every quad strictly convex.

    Parameters
    ----------
    xy : (n, 2) float64
        Not modified.
    quads : (q, 4) int32
    tris : (t, 3) int32
    lines : (k, 2) int32
        Boundary and interior-segment edges.
    line_curve : (k,) int
        Curve of each line in ``domain.curves``: its nodes slide on it.
    domain : Domain
    fixed_pts : (j,) int
        Nodes that never move (the domain's interior points); curve joints and polygon
        corners are fixed as well.
    passes : int
    sliding : bool
        False keeps every line node fixed.
    params : (n,) float64, optional
        Curve parameter of each line node where it is known (NaN elsewhere): the
        parameter of the discretisation that placed the node, on its curve
        (``line_curve``), so that sliding on a parametric curve starts from it instead of
        a golden-section search (:class:`_CurveSlider`).

    Returns
    -------
    (n, 2) float64
        New coordinates (``xy`` itself when there is nothing to do).

    Raises
    ------
    InputError
        ``domain`` not a Domain, ``passes`` not a count, connectivity out of range,
        ``params`` not (n,) numbers.
    """
    if not isinstance(domain, Domain):
        raise InputError(f"domain must be a meshwright.geometry.Domain, got {type(domain).__name__}")
    passes = check_count(passes, "passes")
    xy = as_points(xy, "xy")
    lines = as_cells(lines, "lines", 2, len(xy))
    quads = as_cells(quads, "quads", 4, len(xy))
    tris = as_cells(tris, "tris", 3, len(xy))
    line_curve = np.asarray(line_curve, dtype=np.int64)
    if line_curve.shape != (len(lines),) or (len(lines) and not 0 <= line_curve.min() <= line_curve.max() < len(
        domain.curves
    )):
        raise InputError(f"line_curve must give one curve of the domain per line, got shape {line_curve.shape}")
    if params is not None:
        params = np.asarray(params, dtype=np.float64)
        if params.shape != (len(xy),):
            raise InputError(f"params must be ({len(xy)},) float64 (NaN where unknown), got shape {params.shape}")
    if passes == 0 or not len(lines):
        return xy
    fixed, vcurve = _fixed_nodes(xy, lines, line_curve, domain, fixed_pts)
    if not sliding:
        fixed[lines.ravel()] = True

    project = _CurveSlider(domain, vcurve, xy, params)
    tris = np.asarray(tris).reshape(-1, 3)
    out = smooth_sliding(xy, quads, tris, lines, fixed, project, passes, ENHANCE_SETTLE)
    # A node that never moves with a corner wider than 150 degrees between its two quads:
    # the free node across their common side turns towards the bisector
    # (:func:`~meshwright.quad._enhance_kernel.balance_corners`).
    still = (fixed | np.bincount(lines.ravel(), minlength=len(out)).astype(bool)).astype(np.int8)
    tri_node = np.zeros(len(out), dtype=np.int8)
    tri_node[tris.ravel()] = 1
    qd = np.ascontiguousarray(quads, dtype=np.int32)
    alive = np.ones(len(qd), dtype=np.int8)
    off, idx = ek.node_quads(qd, alive, len(out))
    ek.balance_corners(out, qd, alive, still, tri_node, off, idx)
    return out


class _CurveSlider:
    """``project(nodes, xy, at)`` for :func:`~meshwright.quad.smoothing.smooth_sliding`:
    trial positions ``xy`` of sliding nodes now at ``at``, put on the nodes' curves.

    On lines, arcs and polylines it is the curve's own closest point.  On parametric
    curves (splines, airfoil sections) that is a golden-section search of some forty
    curve evaluations per call; here a node's parameter is found that way once, and each
    trial is then one Newton step of the same minimisation from it,
    ``t' = t + (xy - at) . C'(t) / |C'(t)|^2`` (``C'`` by a central difference), placed
    at ``C(t')``: exactly on the curve, three evaluations per call.  The parameters of
    the last call's trials are remembered, so the node's next position is recognised
    (exact coordinates) and needs no search.  A step that would leave ``[t0, t1]`` (the
    seam of a closed curve) keeps the node where it is.  Nodes whose parameter is given
    (``params``, finite: where the discretisation put them, at ``xy``) start from it, so
    the search runs only for nodes made later (a chord's boundary midpoints): some forty
    curve evaluations per curve and call, a sixth of the pairing's time on the
    three-element airfoil when every node searched.
    """

    SLOTS = 3  # remembered (parameter, point) pairs per node: where it is, and two trials

    def __init__(self, domain: Domain, vcurve: np.ndarray, xy=None, params=None):
        self.domain = domain
        self.vcurve = vcurve
        self.param = np.array([isinstance(c, Parametric) for c in domain.curves], dtype=bool)
        # One (n, SLOTS) table per coordinate: the lookups compare columns, no reductions
        # over axes of length two or three (a quarter of the projection's time).  Only
        # parametric curves read them: without one they are not made (0.8 ms a call on
        # the disk's 40k nodes).
        rows = len(vcurve) if self.param.any() else 0
        self.memo_t = np.full((rows, self.SLOTS), np.nan)
        self.memo_x = np.full((rows, self.SLOTS), np.nan)
        self.memo_y = np.full((rows, self.SLOTS), np.nan)
        if params is not None and rows:
            known = np.isfinite(params)
            self.memo_t[known, 0] = params[known]
            self.memo_x[known, 0] = xy[known, 0]
            self.memo_y[known, 0] = xy[known, 1]

    def __call__(self, nodes, xy, at):
        nodes = np.asarray(nodes, dtype=np.int64)
        cid = self.vcurve[nodes]
        out = np.empty_like(xy)
        par = self.param[cid]
        if (~par).any():
            out[~par] = self.domain.project(cid[~par], xy[~par])[1]
        for c in np.unique(cid[par]).tolist():
            m = np.flatnonzero(cid == c)
            out[m] = self._slide(self.domain.curves[c], nodes[m], xy[m], at[m])
        return out

    def _slide(self, curve, v, xy, at):
        ax, ay = at[:, 0], at[:, 1]
        hit_x, hit_y = self.memo_x[v] == ax[:, None], self.memo_y[v] == ay[:, None]
        known = self.memo_t[v]
        # The first slot holding the node's exact position gives its parameter.
        t = np.full(len(v), np.nan)
        for s in range(self.SLOTS - 1, -1, -1):
            t = np.where(hit_x[:, s] & hit_y[:, s], known[:, s], t)
        miss = np.isnan(t)
        if miss.any():
            t[miss] = curve.project(at[miss])
        lo, hi = curve.t0, curve.t1
        h = 1e-7 * (hi - lo)
        ta, tb = np.maximum(t - h, lo), np.minimum(t + h, hi)
        k = len(t)
        ends = curve.evaluate(np.concatenate([ta, tb]))
        dt = tb - ta
        dcx = (ends[k:, 0] - ends[:k, 0]) / dt
        dcy = (ends[k:, 1] - ends[:k, 1]) / dt
        step = ((xy[:, 0] - ax) * dcx + (xy[:, 1] - ay) * dcy) / np.maximum(dcx * dcx + dcy * dcy, 1e-300)
        t_new = t + step
        inside = (t_new >= lo) & (t_new <= hi)
        t_new = np.where(inside, t_new, t)
        out = curve.evaluate(t_new)
        out[~inside] = at[~inside]
        # Remember where each node is and its trials, in the order the caller gives them.
        order = np.argsort(v, kind="stable")
        first = np.ones(k, dtype=bool)
        first[1:] = v[order][1:] != v[order][:-1]
        start = np.maximum.accumulate(np.where(first, np.arange(k), 0))
        rank = np.empty(k, dtype=np.int64)
        rank[order] = np.arange(k) - start
        self.memo_t[v, 0], self.memo_x[v, 0], self.memo_y[v, 0] = t, ax, ay
        keep = rank + 1 < self.SLOTS
        vk, sk = v[keep], rank[keep] + 1
        self.memo_t[vk, sk] = t_new[keep]
        self.memo_x[vk, sk] = out[keep, 0]
        self.memo_y[vk, sk] = out[keep, 1]
        return out
