"""Domain decomposition for distributed meshing: straight cuts balanced by the size-field integral.

Sources: L. Linardakis and N. Chrisochoides, "Delaunay decoupling method for parallel guaranteed
quality planar mesh refinement", SIAM J. Sci. Comput. 27(4), 2006, and "Graded Delaunay
decoupling method for parallel guaranteed quality planar mesh generation", SIAM J. Sci. Comput.
30(4), 2008 (separators meeting the boundary at angles of at least 60 degrees, the input
condition of Ruppert's guarantee, and discretised before meshing so that parts mesh with no
communication); D. Morozov and T. Peterka, "Efficient Delaunay tessellation through k-d tree
decomposition", SC16 (recursive bisection balanced by the work, not by width).

Algorithm
---------
1. The domain's boundary is discretised once (``Domain.discretize``); its vertices and segments
   start the *skeleton*, the points every part shares by global id.
2. The cost of a region is ``kappa * 4 / sqrt(3) * integral(1 / h^2)`` triangles (``kappa`` =
   :data:`KAPPA`, measured for ``method="delaunay"``), integrated on a grid of samples of the
   bounding box.
3. Recursive bisection (an explicit stack, no recursion): a convex cell (:mod:`.cells`) holding
   ``k`` parts is cut by a line into cells of ``j`` and ``k - j`` parts (the :data:`_SPLITS`
   splits nearest halves).  Candidate positions lie within the first of
   :data:`BALANCE_WINDOWS` of the balanced cost that holds one (the cumulative cost of a
   column of samples counted at its far edge); a candidate is admissible when every crossing
   with a boundary chord makes an angle of at least :data:`MIN_CUT_ANGLE` with it, no boundary
   vertex (nor interior point, nor end of an earlier cut) lies closer than the first of
   :data:`VERTEX_CLEARANCES` (times ``h``) to the line, and each end inside the domain meets
   the earlier cut it ends on at :data:`MIN_CUT_ANGLE` or more; in each window the preferred
   clearance is tried before the accepted one.  Axis-parallel lines are tried first (the
   longer axis first); when none lies within :data:`_OBLIQUE_TRIGGER` of its balance, lines
   at every 15 degrees are tried too and the better-balanced admissible cut wins (a line
   crosses a circle at >= 60 degrees only within half its radius of the centre, so the rim
   between the axes needs radial-ish cuts).  Without any admissible cut the best-scoring
   axis-parallel candidate is taken and its angle reported.  The sides of a cut that ended
   off balance get the part counts nearest their costs.
4. Crossings split boundary chords: on straight curves on the line, on curved ones at the
   curve parameter found by bisection, so every skeleton point lies on its true curve (an
   axis-parallel cut's coordinate is set exactly).
5. Each cut is broken at its crossings and at the ends of the later cuts that meet it
   (junctions, recorded when they are made); the pieces inside the domain are discretised by
   the boundary's own 1-D placer (:func:`meshwright.geometry._discretize.place_params`) and
   become *interface* segments with global ids, oriented with the part on their left.

Layout of the result (:class:`Decomposition`): skeleton points ``(n, 2)`` float64 and their
markers; skeleton segments ``(m, 2)`` int64 with ``kind`` (0 loop, 1 interior constraint, 2
interface), ``left``/``right`` parts (-1 where none), markers, curve ids (-1 for interfaces)
and curve parameters; cells ``(p, 4)`` float64, the bounding box ``(x0, y0, x1, y1)`` of each
part's convex cell; predicted triangles per part; cuts ``(c, 8)`` ``(nx, ny, c, xa, ya, xb,
yb, smallest crossing angle)``: the line ``xy . (nx, ny) == c`` from ``(xa, ya)`` to ``(xb,
yb)``.

Invariants: every skeleton segment lies in exactly one part (kind 0, 1) or on the common edge of
two parts (kind 2); segments of kind 0 and 2 run with their ``left`` part on their left; no two
skeleton points coincide.
"""

from __future__ import annotations

import itertools
import math
from typing import NamedTuple

import numpy as np

from meshwright.core.errors import InputError, MeshingError
from meshwright.distributed.cells import (
    AXES,
    along,
    box,
    clip,
    contains,
    direction,
    line_ends,
    proj,
    segment_angle,
)
from meshwright.geometry._discretize import place_params
from meshwright.geometry._kernels import INSIDE, classify_points
from meshwright.geometry.curves import Line, Polyline
from meshwright.sizing.field import SizeField

__all__ = ["KAPPA", "MIN_CUT_ANGLE", "Decomposition", "PartPSLG", "decompose_domain", "part_pslg"]

KAPPA = 1.60  # triangles over the equilateral count of integral(1/h^2), Delaunay refinement at 30 degrees
MIN_CUT_ANGLE = 60.0  # degrees: Ruppert's input condition (and MADD's Phi_0)
VERTEX_CLEARANCES = (0.25, 0.1)  # in units of h: how near a cut may pass a boundary vertex (preferred, accepted)
TANGENT_CLEARANCE = 1.0  # in units of h: vertices of chords the cut does not cross
JUNCTION_CLEARANCE = 1.0  # in units of h: how near a cut may pass the end of another (unless it meets it)
BALANCE_WINDOWS = (0.03, 0.06, 0.1)  # fractions of a cell's cost a cut may move to find a good position
INTERFACE_SPACING = 0.75  # of h: interfaces a little finer than h rarely need splits (measured)
INTERFACE_GROWTH = 0.5  # how fast the interface spacing grows away from a boundary crossing
_CANDIDATES = 81
_QUERY_BLOCK = 256  # size queries per block of the interface spacing (consecutive: near each other)
_GOOD_ENOUGH = 0.005  # a cut this near its balance (fraction of the cell's cost) is taken at once
_SPLITS = 5  # splits k = j + (k - j) of a cell tried, nearest halves first
_SNAP = 1e-9  # of the padding (1 % of the domain's extent): ends of cuts this near are one point
_OBLIQUE_TRIGGER = 0.01  # an axis-parallel cut further than this from its balance: try oblique lines too
_OBLIQUE = tuple(direction(-1, math.radians(a)) for a in range(15, 180, 15) if a != 90)
_BISECTIONS = 80
_EQUILATERAL = 4.0 / math.sqrt(3.0)

KIND_LOOP, KIND_CONSTRAINT, KIND_INTERFACE = 0, 1, 2


class Decomposition(NamedTuple):
    """A domain cut into parts, with its skeleton (see the module docstring for the layout).

    Attributes
    ----------
    points : (n, 2) float64
        Skeleton points: boundary vertices, cut crossings, interface vertices, interior points.
    point_markers : (n,) int32
        Largest boundary marker of the loop/constraint segments at each point (0 elsewhere).
    segments : (m, 2) int64
        Skeleton segments as point ids.
    kind : (m,) int8
        0 loop, 1 interior constraint, 2 interface.
    left, right : (m,) int32
        Part on the left (the one holding kind 0 and 1 segments), part on the right (kind 2), or -1.
    markers : (m,) int32
        Boundary markers (0 on interfaces).
    curve : (m,) int32
        ``Domain.curves`` index, -1 on interfaces.
    params : (m, 2) float64
        Curve parameters of the ends (0, 1 on interfaces).
    interior : (q,) int64
        Skeleton ids of the domain's interior points.
    interior_part : (q,) int32
    cells : (p, 4) float64
        ``(x0, y0, x1, y1)``: bounding box of each part's convex cell.
    predicted : (p,) float64
        Predicted triangles per part.
    cuts : (c, 8) float64
        ``(nx, ny, c, xa, ya, xb, yb, smallest crossing angle in degrees)`` (180 without
        crossings): the line ``xy . (nx, ny) == c`` between its ends in its cell.
    """

    points: np.ndarray
    point_markers: np.ndarray
    segments: np.ndarray
    kind: np.ndarray
    left: np.ndarray
    right: np.ndarray
    markers: np.ndarray
    curve: np.ndarray
    params: np.ndarray
    interior: np.ndarray
    interior_part: np.ndarray
    cells: np.ndarray
    predicted: np.ndarray
    cuts: np.ndarray

    @property
    def n_parts(self) -> int:
        return len(self.cells)

    @property
    def min_cut_angle(self) -> float:
        """Smallest angle between a cut and a boundary chord it crosses (degrees)."""
        return float(self.cuts[:, 7].min()) if len(self.cuts) else 180.0

    @property
    def imbalance(self) -> float:
        """Largest predicted part cost over the mean."""
        return float(self.predicted.max() / self.predicted.mean())


class PartPSLG(NamedTuple):
    """What one part meshes: a planar straight-line graph over skeleton points.

    Attributes
    ----------
    index : int
    gids : (k,) int64
        Skeleton id of each local point.
    points : (k, 2) float64
    segments : (s, 2) int32
        Local point ids, oriented with the part on the left (loops, interfaces).
    sides : (s,) int8
        +1 (domain on the left), 0 for interior constraints.
    markers : (s,) int32
    curve : (s,) int32
        ``Domain.curves`` index; interfaces point past the domain's curves (a straight dummy).
    params : (s, 2) float64
    skeleton_segment : (s,) int64
        Skeleton segment id of each segment.
    interface : (s,) bool
    """

    index: int
    gids: np.ndarray
    points: np.ndarray
    segments: np.ndarray
    sides: np.ndarray
    markers: np.ndarray
    curve: np.ndarray
    params: np.ndarray
    skeleton_segment: np.ndarray
    interface: np.ndarray


def _sample_grid(dom_segments, bbox, field, n_samples: int):
    """Centres of a uniform grid over ``bbox`` inside the domain, their cost weights, their
    grid indices (n, 2) int64 and the grid's coordinates ``(xs, ys)``."""
    x0, y0, x1, y1 = bbox
    w, h = x1 - x0, y1 - y0
    step = math.sqrt(w * h / n_samples)
    nx, ny = max(8, math.ceil(w / step)), max(8, math.ceil(h / step))
    xs = x0 + (np.arange(nx) + 0.5) * (w / nx)
    ys = y0 + (np.arange(ny) + 0.5) * (h / ny)
    ij = np.stack(np.meshgrid(np.arange(nx), np.arange(ny)), axis=-1).reshape(-1, 2)
    xy = np.ascontiguousarray(np.column_stack([xs[ij[:, 0]], ys[ij[:, 1]]]))
    inside = classify_points(xy, *dom_segments) == INSIDE
    xy, ij = xy[inside], ij[inside]
    hv = field(xy)
    return xy, (w / nx) * (h / ny) / (hv * hv), ij, (xs, ys)


def _crossing(curves, pts, seg, curve, params, s: int, d, c: float):
    """The point where skeleton segment ``s`` crosses the cut ``(d, c)`` and its curve parameter."""
    a, b = pts[seg[s, 0]], pts[seg[s, 1]]
    ta, tb = params[s]
    cv = curves[curve[s]]
    pa, pb = float(proj(a, d)), float(proj(b, d))
    f = (c - pa) / (pb - pa)
    if isinstance(cv, (Line, Polyline)):
        p = a + f * (b - a)
        t = ta + f * (tb - ta)
    else:
        # Bisection on the curve parameter: the chord's ends straddle the line, so does the curve.
        lo, hi = ta, tb
        slo = pa - c
        for _ in range(_BISECTIONS):
            mid = 0.5 * (lo + hi)
            v = float(proj(cv.evaluate(np.array([mid]))[0], d)) - c
            if v == 0.0:
                lo = hi = mid
                break
            if (v < 0.0) == (slo < 0.0):
                lo, slo = mid, v
            else:
                hi = mid
        t = 0.5 * (lo + hi)
        p = cv.evaluate(np.array([t]))[0]
    p = np.array(p, dtype=np.float64)
    if d[0] >= 0:
        p[d[0]] = c
    return p, t


def _scores(pts, seg, segs_in, verts, vh, clearance, exy, eh, d, cs: np.ndarray):
    """``(scores, smallest angles)`` (each (k,)) of the cuts ``(d, cs[j])``: a score
    >= 1 is admissible.

    ``verts`` (v,) sorted are the skeleton points the cut must keep clear of (the ends of the
    cell's segments, interior points), ``vh`` (v,) the size there: the ends of the chords a
    cut crosses by ``clearance * vh``, any other by :data:`TANGENT_CLEARANCE` ``* vh``, so that
    a cut never runs along a curve it does not cross (a thin sliver of domain between them).
    ``exy`` (e, 2) are the ends of earlier cuts on the cell's edges, which a cut either meets
    exactly (a cross junction) or passes at :data:`JUNCTION_CLEARANCE` ``h`` (``eh`` (e,)) at
    least, so that no interface piece between two junctions is short.  All candidates are
    scored at once (arrays of k by the segments and vertices near them: a segment that
    straddles none of them cannot be crossed, and a vertex farther than ``vh`` from all of them
    scores >= 1, so leaving both out changes no admissible set and no score below 1)."""
    k = len(cs)
    lo, hi = cs.min(), cs.max()
    ends = seg[segs_in]
    a, b = proj(pts[ends[:, 0]], d), proj(pts[ends[:, 1]], d)
    near = (np.maximum(a, b) > lo) & (np.minimum(a, b) < hi)
    segs_in, ends, a, b = segs_in[near], ends[near], a[near], b[near]
    cross = (a[None, :] - cs[:, None]) * (b[None, :] - cs[:, None]) < 0.0
    seg_angle = segment_angle(pts[ends[:, 1]] - pts[ends[:, 0]], d[2])
    angle = np.where(cross, seg_angle[None, :], 180.0).min(axis=1) if len(segs_in) else np.full(k, 180.0)
    clear = np.full(k, np.inf)
    coord = proj(pts[verts], d)
    reach = max(TANGENT_CLEARANCE, *VERTEX_CLEARANCES) * vh
    keep = (coord > lo - reach) & (coord < hi + reach)
    if keep.any():
        slot = np.full(len(verts), -1, dtype=np.int64)
        slot[keep] = np.arange(int(keep.sum()))
        pos = slot[np.searchsorted(verts, ends)]
        crossed = np.zeros((k, int(keep.sum()) + 1), dtype=bool)  # column -1: ends left out
        rows, cols = np.nonzero(cross)
        crossed[rows, pos[cols, 0]] = True
        crossed[rows, pos[cols, 1]] = True
        factor = np.where(crossed[:, :-1], clearance, TANGENT_CLEARANCE) * vh[keep][None, :]
        clear = (np.abs(coord[keep][None, :] - cs[:, None]) / factor).min(axis=1)
    if len(exy):
        de = np.abs(proj(exy, d)[None, :] - cs[:, None])
        clear = np.minimum(clear, np.where(de == 0.0, np.inf, de / (JUNCTION_CLEARANCE * eh[None, :])).min(axis=1))
    return np.minimum(clear, angle / MIN_CUT_ANGLE), angle


class _Skeleton:
    """Growing skeleton arrays during the bisection (client side, O(boundary))."""

    def __init__(self, disc, dom):
        self.pts = disc.points.copy()
        self.seg = disc.segments.astype(np.int64)
        self.markers = disc.segment_markers.astype(np.int32)
        self.curve = disc.segment_curve.astype(np.int32)
        self.params = disc.segment_params.copy()
        self.kind = np.where(dom.curve_loop[self.curve] >= 0, KIND_LOOP, KIND_CONSTRAINT).astype(np.int8)

    def split(self, curves, segs, d, c: float) -> tuple[np.ndarray, np.ndarray]:
        """Split segments ``segs`` at the cut ``(d, c)``; returns the new point ids and segment ids."""
        new_p, new_s = [], []
        for s in segs.tolist():
            p, t = _crossing(curves, self.pts, self.seg, self.curve, self.params, s, d, c)
            pid = len(self.pts)
            self.pts = np.vstack([self.pts, p[None]])
            b = int(self.seg[s, 1])
            tb = self.params[s, 1]
            self.seg[s, 1] = pid
            self.params[s, 1] = t
            sid = len(self.seg)
            self.seg = np.vstack([self.seg, [[pid, b]]])
            self.params = np.vstack([self.params, [[t, tb]]])
            self.markers = np.append(self.markers, self.markers[s])
            self.curve = np.append(self.curve, self.curve[s])
            self.kind = np.append(self.kind, self.kind[s])
            new_p.append(pid)
            new_s.append(sid)
        return np.array(new_p, dtype=np.int64), np.array(new_s, dtype=np.int64)


def _junction_scores(cell, ctx, d, cs: np.ndarray, angles: bool) -> np.ndarray:
    """Scores (k,) of the cuts ``(d, cs[j])`` at their ends on earlier cuts (junctions), >= 1
    where admissible; infinite where no end is a junction.

    A junction inside the domain is an input angle of the parts around it, so the cuts must
    meet at :data:`MIN_CUT_ANGLE` or more (checked when ``angles``: with axis-parallel cuts
    only, every junction is a right angle).  And a junction must keep
    :data:`JUNCTION_CLEARANCE` ``h`` from where the earlier cut crosses the boundary, inside
    the domain or out: one between a chord and its curve (the cuts cross the curve, pieces are
    kept by their midpoints against the chords) would leave a sliver of interface poking out
    of the domain.  Elsewhere the earlier cut keeps its own clearance from the boundary."""
    poly, labels = cell
    cut_dirs, dom_segments, crossings = ctx
    out = np.full(len(cs), np.inf)
    xy, lab = line_ends(poly, labels, d, cs)
    need = lab >= 0
    if not need.any():
        return out
    rows, cols = np.nonzero(need)
    e = np.ascontiguousarray(xy[rows, cols])
    on = lab[rows, cols]
    if angles:
        inside = classify_points(e, *dom_segments) == INSIDE
        t_other = np.array([cut_dirs[q][2] for q in on.tolist()]).reshape(-1, 2)
        ang = np.degrees(np.arccos(np.clip(np.abs(t_other @ d[2]), 0.0, 1.0)))
        np.minimum.at(out, rows[inside], ang[inside] / MIN_CUT_ANGLE)
    for q in np.unique(on).tolist():
        x, hx = crossings[q]
        if not len(x):
            continue
        sel = on == q
        gap = np.hypot(e[sel, 0, None] - x[None, :, 0], e[sel, 1, None] - x[None, :, 1]) / (JUNCTION_CLEARANCE * hx)
        np.minimum.at(out, rows[sel], gap.min(axis=1))
    return out


def _cumulative(cell, grid, weights, dirs=None) -> list:
    """``[(direction, coordinates, cumulative cost)]`` of a cell's samples along each of
    ``dirs`` (default the two axes, the longer extent first); see :func:`_choose_cut`."""
    poly, _ = cell
    x0, y0 = poly.min(axis=0)
    x1, y1 = poly.max(axis=0)
    if dirs is None:
        dirs = AXES if (x1 - x0) >= (y1 - y0) else AXES[::-1]
    out = []
    ij, axes_xy, xy = grid
    for d in dirs:
        axis = d[0]
        if axis >= 0:
            # Cumulative cost at each distinct sample coordinate, interpolated in between, so
            # that candidates are not tied to the sample grid (gaps between boundary vertices
            # are finer than it where h is small).  The cost of a column is all reached at its
            # far edge, not at its centre (there, every cut would leave up to a column's cost
            # off its lower side).
            n_axis = len(axes_xy[axis])
            present = np.bincount(ij[:, axis], minlength=n_axis) > 0
            coord = axes_xy[axis][present] + 0.5 * (axes_xy[axis][1] - axes_xy[axis][0])
            cum = np.cumsum(np.bincount(ij[:, axis], weights, minlength=n_axis)[present])
        else:
            s = proj(xy, d)
            order = np.argsort(s, kind="stable")
            coord, cum = s[order], np.cumsum(weights[order])
        out.append((d, coord, cum))
    return out


def _choose_cut(sk, cell, grid, weights, segs_in, verts, vh, exy, eh, frac, windows=BALANCE_WINDOWS, dirs=None,
                ctx=None):
    """Best cut of a cell: ``(direction, c, angle)`` (see the module docstring, step 3).

    ``cell`` is ``(polygon, labels)`` (:mod:`.cells`); ``grid`` is ``(indices (n, 2), (xs,
    ys), xy (n, 2))`` of the cell's samples (:func:`_sample_grid`).  ``dirs``: the directions
    tried, default the two axes, the longer extent first, or what :func:`_cumulative` made of
    them.  ``ctx`` is ``(cut directions, dom_segments, crossings)``: the cut's ends on earlier
    cuts are scored by :func:`_junction_scores` (their angles where the cell has an oblique
    edge or ``d`` is oblique).
    With ``windows`` shorter than :data:`BALANCE_WINDOWS`, None when no candidate is
    admissible."""
    poly, labels = cell
    x0, y0 = poly.min(axis=0)
    x1, y1 = poly.max(axis=0)
    sorted_dirs = dirs if isinstance(dirs, list) else _cumulative(cell, grid, weights, dirs)
    cut_dirs = ctx[0]
    oblique_cell = any(cut_dirs[e][0] < 0 for e in labels[labels >= 0].tolist())
    total = weights.sum()
    best = None
    strict = len(windows) < len(BALANCE_WINDOWS)
    found = None  # strict: (relative deviation from the balance, direction, c, angle) of the best admissible
    for clearance, window in [(q, w) for w in windows for q in VERTEX_CLEARANCES]:
        for d, coord, cum in sorted_dirs:
            extent = proj(poly, d)
            lo_cell, hi_cell = extent.min(), extent.max()
            targets = frac * total + np.linspace(-window, window, _CANDIDATES) * total
            # Nearest the balance first.
            targets = targets[np.argsort(np.abs(targets - frac * total), kind="stable")]
            cs = np.interp(targets, cum, coord) if len(coord) > 1 else np.full(len(targets), 0.5 * (lo_cell + hi_cell))
            dev = np.abs(targets - frac * total)
            if len(exy) and len(coord) > 1:
                # Cross junctions first: the coordinates of earlier cut ends within the window.
                at = np.unique(proj(exy, d))
                cost = np.abs(np.interp(at, coord, cum) - frac * total)
                at = at[cost <= window * total]
                order = np.argsort(cost[cost <= window * total], kind="stable")
                cs = np.concatenate([at[order], cs])
                dev = np.concatenate([np.sort(cost[cost <= window * total]), dev])
            inside = (lo_cell < cs) & (cs < hi_cell)
            cs, dev = cs[inside], dev[inside]
            if not len(cs):
                continue
            score, angle = _scores(sk.pts, sk.seg, segs_in, verts, vh, clearance, exy, eh, d, cs)
            score = np.minimum(score, _junction_scores(cell, ctx, d, cs, d[0] < 0 or oblique_cell))
            ok = np.flatnonzero(score >= 1.0)
            if len(ok) and strict:
                j = ok[np.argmin(dev[ok])]
                dv = float(dev[j] / total)
                if dv <= _GOOD_ENOUGH:
                    # In the usual order (longer axis, preferred clearance, junctions) when balanced.
                    j = ok[0] if dev[ok[0]] <= _GOOD_ENOUGH * total else j
                    return float(dev[j] / total), d, float(cs[j]), float(angle[j])
                if found is None or dv < found[0]:
                    found = (dv, d, float(cs[j]), float(angle[j]))
                continue
            if len(ok):
                return d, float(cs[ok[0]]), float(angle[ok[0]])
            j = int(np.argmax(score))
            if best is None or score[j] > best[0]:
                best = (float(score[j]), d, float(cs[j]), float(angle[j]))
    if strict:
        return found
    if best is None or best[0] <= 0.0:
        raise MeshingError(
            f"cannot place a cut in the cell ({x0:.6g}, {y0:.6g}) - ({x1:.6g}, {y1:.6g}): "
            "every candidate passes through a boundary vertex; use fewer parts"
        )
    return best[1], best[2], best[3]


def decompose_domain(dom, field, parts: int, samples_per_part: int = 1024) -> Decomposition:
    """Cut ``dom`` into ``parts`` parts for the size field ``field`` (module docstring).

    Parameters
    ----------
    dom : Domain
        Without region seeds (checked by the caller).
    field : SizeField
    parts : int
        At least 1.
    samples_per_part : int
        Cost samples per part (at least 16,384 in all, at most 1,048,576).

    Returns
    -------
    Decomposition

    Raises
    ------
    MeshingError
        No cut position avoids the boundary vertices of a cell.
    """
    disc = dom.discretize(field)
    curves = dom.curves
    sk = _Skeleton(disc, dom)
    loops = np.flatnonzero(sk.kind == KIND_LOOP)
    dom_segments = (sk.pts[sk.seg[loops, 0]], sk.pts[sk.seg[loops, 1]])
    bx0, by0, bx1, by1 = dom.bbox
    pad = 0.01 * max(bx1 - bx0, by1 - by0)
    root = (bx0 - pad, by0 - pad, bx1 + pad, by1 + pad)
    n_samples = int(np.clip(parts * samples_per_part, 16_384, 1_048_576))
    samples, weights, ij, axes_xy = _sample_grid(dom_segments, dom.bbox, field, n_samples)
    n_interior = len(dom.points)
    interior = np.arange(len(disc.points) - n_interior, len(disc.points), dtype=np.int64)

    cells = np.zeros((parts, 4))
    cost = np.zeros(parts)
    seg_part = np.full(len(sk.seg), -1, dtype=np.int64)
    interior_part = np.zeros(n_interior, dtype=np.int32)
    # tree rows: (axis, nx, ny, c, node_lo_child, node_hi_child); leaves are -1 - part.
    cuts, dirs, tree, ends = [], [], [], []
    cut_points, junctions = [], []  # per cut: its boundary crossings (ids), the ends of later cuts on it
    crossings = []  # per cut: its boundary crossings (q, 2) and the size there
    ctx = (dirs, dom_segments, crossings)
    stack = [(box(*root), parts, 0, np.arange(len(samples)), np.arange(len(sk.seg)), np.arange(n_interior), -1, 0)]
    while stack:
        cell, k, first, smp, segs_in, ints_in, parent, side = stack.pop()
        poly, labels = cell
        if k == 1:
            cells[first] = (*poly.min(axis=0), *poly.max(axis=0))
            cost[first] = weights[smp].sum()
            seg_part[segs_in] = first
            interior_part[ints_in] = first
            node = -1 - first
        else:
            verts = np.unique(np.concatenate([sk.seg[segs_in].ravel(), interior[ints_in]]))
            vh = field(sk.pts[verts]) if len(verts) else np.zeros(0)
            exy = np.array(ends, dtype=np.float64).reshape(-1, 2)
            # Ends of cuts in cells already done that lie on this cell's edges, inside the domain.
            exy = exy[contains(poly, exy)] if len(exy) else exy
            if len(exy):
                exy = exy[classify_points(np.ascontiguousarray(exy), *dom_segments) == INSIDE]
            eh = field(exy) if len(exy) else np.zeros(0)
            grid = (ij[smp], axes_xy, samples[smp])
            w = weights[smp]
            cut, excess, kl = _best_split(sk, cell, grid, w, segs_in, verts, vh, exy, eh, k, None, ctx)
            if cut is None or excess > _OBLIQUE_TRIGGER:
                # No axis-parallel cut near its balance (a curved boundary met below 60 degrees
                # wherever the balance puts the line): lines at other angles.
                got = _best_split(sk, cell, grid, w, segs_in, verts, vh, exy, eh, k, _OBLIQUE, ctx)
                if got[0] is not None and got[1] < excess:
                    cut, excess, kl = got
            if cut is None:
                kl = k // 2
                cut = _choose_cut(sk, cell, grid, w, segs_in, verts, vh, exy, eh, kl / k, ctx=ctx)
            d, c, angle = cut
            below = proj(samples[smp], d) < c
            # A cut pushed off balance by the angle and clearance rules: hand its sides the
            # part counts nearest their costs (the leaves then balance again).
            share = float(w[below].sum() / w.sum())
            if abs(share - kl / k) > BALANCE_WINDOWS[0]:
                kl = int(np.clip(round(share * k), 1, k - 1))
            a, b = proj(sk.pts[sk.seg[segs_in, 0]], d), proj(sk.pts[sk.seg[segs_in, 1]], d)
            crossing = segs_in[(a - c) * (b - c) < 0.0]
            new_p, new_s = sk.split(curves, crossing, d, c)
            segs_in = np.concatenate([segs_in, new_s])
            seg_part = np.append(seg_part, np.full(len(new_s), -1))
            mid = 0.5 * (proj(sk.pts[sk.seg[segs_in, 0]], d) + proj(sk.pts[sk.seg[segs_in, 1]], d))
            node = len(tree)
            lo_cell, hi_cell, cut_ends = clip(poly, labels, d, c, node)
            if ends:
                # A cut placed through an earlier cut's end computes that point again with its
                # own rounding where either is oblique: snap it, so the junction is one point.
                known = np.array(ends, dtype=np.float64)
                for xy, _ in cut_ends:
                    gap = np.hypot(known[:, 0] - xy[0], known[:, 1] - xy[1])
                    j = int(np.argmin(gap))
                    if 0.0 < gap[j] <= _SNAP * pad:
                        for half, _ in (lo_cell, hi_cell):
                            half[(half[:, 0] == xy[0]) & (half[:, 1] == xy[1])] = known[j]
                        xy[:] = known[j]
            tree.append([d[0], d[1][0], d[1][1], c, 0, 0])
            (pa, _), (pb, _) = cut_ends
            cuts.append((d[1][0], d[1][1], c, *pa, *pb, angle))
            dirs.append(d)
            cut_points.append(new_p)
            cross_xy = sk.pts[new_p]
            crossings.append((cross_xy, field(cross_xy) if len(new_p) else np.zeros(0)))
            junctions.append([])
            for xy, lab in cut_ends:
                ends.append(xy)
                if lab >= 0:
                    junctions[lab].append(xy)
            ib = proj(sk.pts[interior[ints_in]], d) < c
            stack.append((hi_cell, k - kl, first + kl, smp[~below], segs_in[mid > c], ints_in[~ib], node, 1))
            stack.append((lo_cell, kl, first, smp[below], segs_in[mid < c], ints_in[ib], node, 0))
        if parent >= 0:
            tree[parent][4 + side] = node
    tree = np.array(tree, dtype=np.float64).reshape(-1, 6)
    cuts = np.array(cuts, dtype=np.float64).reshape(-1, 8)
    if len(sk.seg) and (seg_part < 0).any():
        s = int(np.flatnonzero(seg_part < 0)[0])
        raise MeshingError(f"skeleton segment {s} fell in no part (a cut along it)")
    cut_lines = (dirs, cut_points, junctions)
    return _interfaces(dom, field, sk, seg_part, cells, cost, cuts, cut_lines, tree, interior, interior_part,
                       dom_segments)


def _best_split(sk, cell, grid, w, segs_in, verts, vh, exy, eh, k: int, dirs, ctx):
    """``(cut, excess, parts on the lower side)`` of the best admissible cut of a cell of ``k``
    parts in ``dirs`` (:func:`_choose_cut`), or ``(None, inf, None)``.

    Halves first, then the other splits of k by distance from halves: an admissible cut
    within the tightest window at 1 : 3 beats one pushed 10 % off balance at 1 : 1 (cuts meet a
    circle at >= 60 degrees only within half its radius of the centre).  Scored by the heavier
    side's cost per part over the mean; wider windows only when no split has an admissible
    cut in a narrower one."""
    cut, excess, kl = None, np.inf, None
    dirs = _cumulative(cell, grid, w, dirs)
    for window in BALANCE_WINDOWS:
        for j in sorted(range(1, k), key=lambda j: (abs(2 * j - k), j))[:_SPLITS]:
            got = _choose_cut(sk, cell, grid, w, segs_in, verts, vh, exy, eh, j / k, (window,), dirs, ctx)
            if got is not None:
                ex = got[0] / min(j / k, 1.0 - j / k)
                if ex < excess:
                    cut, excess, kl = got[1:], ex, j
                if excess <= _GOOD_ENOUGH:
                    break
        if cut is not None:
            break
    return cut, excess, kl


def _interface_size(field, ends: np.ndarray, end_sizes: np.ndarray) -> SizeField:
    """Spacing along the cut pieces: :data:`INTERFACE_SPACING` ``h``, graded down (by
    :data:`INTERFACE_GROWTH` per unit length) to the shorter boundary chord at every point
    ``ends`` (e, 2) where a cut crosses the boundary (``end_sizes`` (e,)).  Refinement splits an
    interface whose end segment is much longer than the boundary chord beside it (the
    corner's triangle is bad), so matching them keeps parts from requesting splits in the
    common case.  One field for all pieces, so that they are placed in one call."""

    def h(xy):
        out = INTERFACE_SPACING * field(xy)
        if not len(ends):
            return out
        for lo in range(0, len(xy), _QUERY_BLOCK):
            q, o = xy[lo : lo + _QUERY_BLOCK], out[lo : lo + _QUERY_BLOCK]
            # Crossings farther than this from the block's box cannot lower any of its sizes.
            reach = (o.max() - end_sizes.min()) / INTERFACE_GROWTH
            sel = np.flatnonzero(
                (ends[:, 0] >= q[:, 0].min() - reach) & (ends[:, 0] <= q[:, 0].max() + reach)
                & (ends[:, 1] >= q[:, 1].min() - reach) & (ends[:, 1] <= q[:, 1].max() + reach)
            )
            if len(sel):
                d = np.hypot(q[:, 0, None] - ends[None, sel, 0], q[:, 1, None] - ends[None, sel, 1])
                np.minimum(o, (end_sizes[None, sel] + INTERFACE_GROWTH * d).min(axis=1), out=o)
        return out

    return SizeField(h, name="interface spacing")


def _leaf(tree: np.ndarray, xy: np.ndarray, on_cut: int, side: int) -> int:
    """Part holding point ``xy``; at node ``on_cut`` (whose line holds ``xy``) go to ``side``."""
    if len(tree) == 0:
        return 0
    node = 0
    while node >= 0:
        axis, nx, ny, c, lo, hi = tree[node]
        if node == on_cut:
            up = side == 1
        else:
            up = float(proj(xy, (int(axis), (nx, ny), None))) > c
        node = int(hi if up else lo)
    return -1 - node


def _interfaces(dom, field, sk, seg_part, cells, cost, cuts, cut_lines, tree, interior, interior_part,
                dom_segments):
    """Break the cuts at crossings and junctions and discretise their inside pieces (step 5)."""
    n_b = len(sk.seg)
    key = {}
    pts = [sk.pts]
    n_pts = len(sk.pts)
    for pid in np.unique(sk.seg.ravel()).tolist():
        key[(float(sk.pts[pid, 0]), float(sk.pts[pid, 1]))] = pid

    def point_id(p) -> int:
        nonlocal n_pts
        k = (float(p[0]), float(p[1]))
        if k not in key:
            key[k] = n_pts
            pts.append(np.array([p], dtype=np.float64))
            n_pts += 1
        return key[k]

    # Spacing at a crossing: the shorter boundary chord there (see _interface_size).
    length = np.hypot(*(sk.pts[sk.seg[:, 1]] - sk.pts[sk.seg[:, 0]]).T)
    chord = np.full(len(sk.pts), np.inf)
    np.minimum.at(chord, sk.seg[:, 0], length)
    np.minimum.at(chord, sk.seg[:, 1], length)

    dirs, cut_points, junctions = cut_lines
    pieces = []  # (cut, pa, pb): the cuts broken at crossings and junctions, in order along t
    for ci in range(len(cuts)):
        d = dirs[ci]
        pa, pb = cuts[ci, 3:5], cuts[ci, 5:7]
        lo, hi = float(along(pa, d)), float(along(pb, d))
        # Crossings with the boundary, and the ends of later cuts that meet this one.
        inner = [sk.pts[q] for q in cut_points[ci].tolist()] + [xy for xy in junctions[ci]]
        pos = {lo: pa, hi: pb}
        for xy in inner:
            u = float(along(xy, d))
            if lo < u < hi:
                pos.setdefault(u, xy)
        brk = sorted(pos)
        pieces += [(ci, pos[u], pos[v]) for u, v in itertools.pairwise(brk)]
    mids = np.array([0.5 * (pa + pb) for _, pa, pb in pieces]).reshape(-1, 2)
    inside = classify_points(np.ascontiguousarray(mids), *dom_segments) == INSIDE
    kept = [(piece, mid) for piece, mid, keep in zip(pieces, mids, inside) if keep]
    lines, ends = [], []
    for (ci, pa, pb), _ in kept:
        lines.append(Line(np.array(pa, dtype=np.float64), np.array(pb, dtype=np.float64)))
        ends += [pa, pb]
    ends = np.array(ends, dtype=np.float64).reshape(-1, 2)
    # Boundary crossings among the piece ends: skeleton points with a boundary chord.
    end_ids = np.array([key.get((float(x), float(y)), -1) for x, y in ends.tolist()], dtype=np.int64)
    crossing = end_ids >= 0
    end_sizes = chord[end_ids[crossing]]
    finite = np.isfinite(end_sizes)
    ends_c, key_c = np.unique(ends[crossing][finite], axis=0, return_index=True)
    size_i = _interface_size(field, ends_c, end_sizes[finite][key_c])
    params = place_params(lines, size_i, np.ones(len(lines), dtype=np.int64)) if lines else []
    iseg, ileft, iright = [], [], []
    for ((ci, _, _), mid), line, t in zip(kept, lines, params):
        d = dirs[ci]
        xy = line.evaluate(t)
        if d[0] >= 0:
            xy[:, d[0]] = cuts[ci, 2]
        xy[0], xy[-1] = line.p0, line.p1
        # Inner points are new (a skeleton point on a cut is a break); only the ends are shared.
        inner = np.arange(n_pts, n_pts + len(xy) - 2)
        pts.append(xy[1:-1])
        n_pts += len(inner)
        ids = [point_id(xy[0]), *inner.tolist(), point_id(xy[-1])]
        lower = _leaf(tree, mid, ci, 0)
        upper = _leaf(tree, mid, ci, 1)
        # Oriented with the upper part (xy . n > c) on the left: along (n_y, -n_x), so down a
        # vertical cut and along a horizontal one.
        flip = d[2][0] * d[1][1] - d[2][1] * d[1][0] < 0.0
        for i0, i1 in itertools.pairwise(ids):
            iseg.append((i1, i0) if flip else (i0, i1))
            ileft.append(upper)
            iright.append(lower)
    points = np.concatenate(pts) if len(pts) > 1 else sk.pts
    m_i = len(iseg)
    segments = np.concatenate([sk.seg, np.array(iseg, dtype=np.int64).reshape(-1, 2)])
    kind = np.concatenate([sk.kind, np.full(m_i, KIND_INTERFACE, dtype=np.int8)])
    markers = np.concatenate([sk.markers, np.zeros(m_i, dtype=np.int32)])
    pmark = np.zeros(len(points), dtype=np.int32)
    np.maximum.at(pmark, sk.seg[:, 0], sk.markers)
    np.maximum.at(pmark, sk.seg[:, 1], sk.markers)
    area_h = cost * KAPPA * _EQUILATERAL
    return Decomposition(
        points=np.ascontiguousarray(points),
        point_markers=pmark,
        segments=segments,
        kind=kind,
        left=np.concatenate([seg_part, ileft]).astype(np.int32),
        right=np.concatenate([np.full(n_b, -1), iright]).astype(np.int32),
        markers=markers,
        curve=np.concatenate([sk.curve, np.full(m_i, -1, dtype=np.int32)]),
        params=np.concatenate([sk.params, np.tile([0.0, 1.0], (m_i, 1))]),
        interior=interior,
        interior_part=interior_part,
        cells=cells,
        predicted=area_h,
        cuts=cuts,
    )


def part_pslg(dec: Decomposition, i: int, n_curves: int) -> PartPSLG:
    """The planar straight-line graph of part ``i``: its segments oriented with it on the left.

    Parameters
    ----------
    dec : Decomposition
    i : int
    n_curves : int
        ``len(Domain.curves)``: interface segments get curve id ``n_curves`` (a straight dummy).

    Returns
    -------
    PartPSLG

    Raises
    ------
    InputError
        ``i`` outside ``[0, parts)``.
    """
    if not (0 <= i < dec.n_parts):
        raise InputError(f"part {i} outside [0, {dec.n_parts})")
    own = np.flatnonzero(dec.left == i)
    theirs = np.flatnonzero(dec.right == i)
    sid = np.concatenate([own, theirs])
    seg = np.concatenate([dec.segments[own], dec.segments[theirs][:, ::-1]])
    ints = dec.interior[dec.interior_part == i]
    gids, local = np.unique(np.concatenate([seg.ravel(), ints]), return_inverse=True)
    kind = dec.kind[sid]
    iface = kind == KIND_INTERFACE
    return PartPSLG(
        index=int(i),
        gids=gids.astype(np.int64),
        points=np.ascontiguousarray(dec.points[gids]),
        segments=local[: 2 * len(sid)].reshape(-1, 2).astype(np.int32),
        sides=np.where(kind == KIND_CONSTRAINT, 0, 1).astype(np.int8),
        markers=dec.markers[sid],
        curve=np.where(iface, n_curves, dec.curve[sid]).astype(np.int32),
        params=np.where(iface[:, None], np.array([0.0, 1.0]), dec.params[sid]),
        skeleton_segment=sid.astype(np.int64),
        interface=iface,
    )
