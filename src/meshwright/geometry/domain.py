"""The :class:`Domain`: what to mesh, as closed loops of true curves plus constraints.

A domain is one outer loop and any number of hole loops, each a chain of
:mod:`~meshwright.geometry.curves` joined end to start.  Loops are accepted in any
orientation and normalised as the Delaunay and advancing-front methods require
(chapter 18.1.2 and figure 18.2.1 of the reference text): the outer boundary
counter-clockwise and the holes clockwise, so the domain always lies to the left of the
boundary.  A loop nested inside a hole is an *island* (meshed again, counter-clockwise) and
must contain a region seed; a hole inside an island is a hole again, and so on.

Optional interior constraints are open or closed chains of curves (material interfaces,
cracks) whose discretisation must appear as mesh edges; interior points must appear as
mesh vertices; region seeds ``(x, y, marker, max_area_or_None)`` label the connected region
holding them (Triangle's regional attributes, J. R. Shewchuk, "Triangle: Engineering a 2D
Quality Mesh Generator and Delaunay Triangulator", 1996).

Validation works on a fine polyline of every curve (``Curve.fine_params``) with exact
predicates (:mod:`meshwright.geometry._kernels`): self-intersecting or touching loops,
loops crossing each other, holes outside the outer loop, islands without a region,
zero-length segments, duplicate points, open loops, loops with fewer than three vertices
and non-finite coordinates all raise :class:`~meshwright.core.errors.GeometryError` naming
the loop, curve, segment and coordinates at fault.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from meshwright.core.errors import GeometryError, InputError, fmt_point
from meshwright.core.predicates import orient2d, orient2d_batch
from meshwright.core.validate_input import check_coordinate_range
from meshwright.geometry._discretize import interior_seed, place_params, unique_rows
from meshwright.geometry._domain_args import as_chain, check_region_attributes, region_row
from meshwright.geometry._junctions import apply_splits, junction_splits, point_splits
from meshwright.geometry._kernels import (
    INSIDE,
    ON_BOUNDARY,
    classify_points,
    find_bad_pairs,
    nearest_segment,
)
from meshwright.geometry.curves import Line, Polyline
from meshwright.sizing.field import as_size_field

__all__ = ["Domain", "Discretization"]

_JOINT_RTOL = 1e-9  # curve ends closer than this (relative to the domain extent) are joined
_MAX_ROUNDS = 16  # doublings of segment counts to make a coarse polygon valid
_REPORT = 64  # offending pairs collected per round
_JUNCTION_ROUNDS = 64  # rounds of junction splits (a crossing's rounded point may meet another segment)
_JUNCTION_PAIRS = 4096  # offending pairs resolved per junction round


class Discretization(NamedTuple):
    """Planar straight-line graph of a discretised :class:`Domain` (Triangle's .poly content).

    Attributes
    ----------
    points : (n, 2) float64
        Loop vertices (loop by loop, along each loop), then constraint vertices, then the
        interior points.
    segments : (m, 2) int32
        Vertex indices; loop segments run with the normalised loops (domain to their left).
    segment_markers : (m,) int32
        Boundary marker of each segment (1 on loops, 0 on constraints unless set).
    segment_curve : (m,) int32
        Index into ``Domain.curves`` of the curve each segment discretises.
    segment_params : (m, 2) float64
        Curve parameters of the segment's two end points: split a segment at
        ``curve.midpoint_param(*segment_params[i])`` to stay on the true curve.
    point_markers : (n,) int32
        Largest marker of the segments at each point; 0 for interior points.
    holes : (h, 2) float64
        One point strictly inside each hole of this polygon.
    regions : (r, 4) float64
        Rows ``(x, y, marker, max_area)``, ``max_area = -1`` when unconstrained.
    """

    points: np.ndarray
    segments: np.ndarray
    segment_markers: np.ndarray
    segment_curve: np.ndarray
    segment_params: np.ndarray
    point_markers: np.ndarray
    holes: np.ndarray
    regions: np.ndarray


class _Assembly(NamedTuple):
    """Raw polyline of all curves before merging coincident vertices."""

    points: np.ndarray  # (N, 2)
    segments: np.ndarray  # (M, 2) int64 into points
    seg_curve: np.ndarray  # (M,) int64
    seg_params: np.ndarray  # (M, 2)
    seg_local: np.ndarray  # (M,) index of the segment within its curve
    point_group: np.ndarray  # (N,) loop index, or -1 - chain index
    seg_slices: dict  # group -> slice of its segments (groups are contiguous)


class Domain:
    """A region of the plane bounded by loops of curves, with optional constraints.

    Parameters
    ----------
    outer : Curve, sequence of Curve, or (n, 2) array
        The outer loop (an array is a polygon's vertices).
    holes : sequence of loops
        Hole loops (islands nested in holes included), same forms as ``outer``.
    segments : sequence
        Interior constraints: each a Curve, a chain of Curves, or an (n, 2) array of
        polyline vertices; a chain whose end meets its start is closed.
    points : (p, 2) array_like, optional
        Interior points that must become mesh vertices.
    regions : sequence of (x, y, marker, max_area_or_None)
        Region seeds: numbers, the marker integral, ``max_area`` positive or None.
    size : optional
        Suggested size (anything :func:`meshwright.sizing.as_size_field` accepts) used
        when a caller gives none, e.g. from a JSON geometry file.
    region_attributes : sequence of float, optional
        One finite number per region (Triangle's regional attribute, copied to every
        triangle of the region as ``cell_data["region_attribute"]``); default: each
        region's marker.
    open_boundary : bool
        True when the input's segments close no boundary and ``outer`` is the convex hull
        of its vertices, added to close it (what :func:`~meshwright.geometry.read_poly`
        builds from such a ``.poly`` file, Triangle's ``-c``); ``triangulate`` meshes such
        a domain only when asked for the convex hull.

    Attributes
    ----------
    loops : tuple of tuple of Curve
        Normalised loops; ``loops[0]`` is the outer one (counter-clockwise).
    loop_depth : (L,) int64
        Nesting depth: 0 outer, odd for holes (clockwise), even >= 2 for islands.
    constraints : tuple of tuple of Curve
    curves : tuple of Curve
        Every curve: loops in order, then constraints; ``segment_curve`` indexes it.
    curve_loop : (C,) int64
        Loop of each curve, -1 for constraint curves.
    points : (p, 2) float64
    regions : tuple of (x, y, marker, max_area_or_None)
    region_attributes : (r,) float64
    open_boundary : bool

    Raises
    ------
    GeometryError
        If the domain is invalid (see :meth:`validate`).
    InputError
        Malformed arguments (a region row of the wrong length or types, named by index), or
        coordinates outside the exact predicates' range
        (:mod:`meshwright.core.validate_input`).
    """

    def __init__(
        self, outer, holes=(), *, segments=(), points=None, regions=(), size=None, region_attributes=None,
        open_boundary=False,
    ):
        self._raw_loops = [as_chain(outer, "outer loop")] + [
            as_chain(h, f"hole {i}") for i, h in enumerate(holes)
        ]
        self.constraints = tuple(as_chain(s, f"segment {i}") for i, s in enumerate(segments))
        try:
            pts = np.zeros((0, 2)) if points is None else np.asarray(points, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise InputError(f"points must be a (p, 2) array of numbers: {exc}") from None
        if pts.ndim != 2 or pts.shape[1] != 2:
            raise InputError(f"points must have shape (p, 2), got {pts.shape}")
        self.points = np.ascontiguousarray(pts.reshape(-1, 2))
        check_coordinate_range(self.points, "interior points")
        if isinstance(regions, (str, bytes)) or not hasattr(regions, "__iter__"):
            raise InputError(f"regions must be a sequence of (x, y, marker[, max_area]) rows, got {regions!r}")
        self.regions = tuple(region_row(r, i) for i, r in enumerate(regions))
        if self.regions:
            check_coordinate_range(np.array([r[:2] for r in self.regions]), "region seeds")
        self.region_attributes = check_region_attributes(region_attributes, self.regions)
        if not isinstance(open_boundary, (bool, np.bool_)):
            raise InputError(f"open_boundary must be True or False, got {open_boundary!r}")
        self.open_boundary = bool(open_boundary)
        self.size = None if size is None else as_size_field(size)
        self.validate()

    def __repr__(self) -> str:
        return (
            f"Domain({len(self.loops)} loops, {len(self.constraints)} constraints, "
            f"{len(self.points)} points, {len(self.regions)} regions, area={self.area():.6g})"
        )

    # -- structure -----------------------------------------------------------------------
    def _set_loops(self, loops) -> None:
        self.loops = tuple(loops)
        self.curves = tuple(c for lp in self.loops for c in lp) + tuple(
            c for ch in self.constraints for c in ch
        )
        groups = [(li, lp) for li, lp in enumerate(self.loops)]
        groups += [(-1 - ci, ch) for ci, ch in enumerate(self.constraints)]
        self._groups = []
        cid = 0
        for g, chain in groups:
            self._groups.append((g, list(range(cid, cid + len(chain)))))
            cid += len(chain)
        self.curve_loop = np.array(
            [li for li, lp in enumerate(self.loops) for _ in lp]
            + [-1] * (cid - sum(map(len, self.loops))),
            dtype=np.int64,
        )

    def _name(self, group: int) -> str:
        if group == 0:
            return "outer loop (loop 0)"
        if group > 0:
            return f"hole {group - 1} (loop {group})"
        return f"constraint {-1 - group}"

    def _join(self, fine_pts: list[np.ndarray]) -> None:
        """Check that curves meet end to start; fix the shared coordinates of each joint."""
        allp = np.concatenate(fine_pts)
        scale = float(np.ptp(allp, axis=0).max()) + float(np.abs(allp).max())
        tol = _JOINT_RTOL * scale
        n = len(self.curves)
        self._jstart = np.empty((n, 2))
        self._jend = np.empty((n, 2))
        self._closed = {}
        for g, cids in self._groups:
            closed = g >= 0
            if not closed:
                gap = fine_pts[cids[-1]][-1] - fine_pts[cids[0]][0]
                closed = bool(np.hypot(*gap) <= tol)
            self._closed[g] = closed
            pairs = list(zip(cids[:-1], cids[1:])) + ([(cids[-1], cids[0])] if closed else [])
            for a, b in pairs:
                pa, pb = fine_pts[a][-1], fine_pts[b][0]
                if np.hypot(*(pa - pb)) > tol:
                    ka, kb = cids.index(a), cids.index(b)
                    what = "is open" if b == cids[0] else "is broken"
                    raise GeometryError(
                        f"{self._name(g)} {what}: curve {ka} ends at {fmt_point(pa)} but curve {kb} "
                        f"starts at {fmt_point(pb)}"
                    )
                # Prefer the user's exact coordinates (lines, polylines) at corners, else
                # the start of the next curve (a closed arc's seam sits at its theta0).
                joint = pb if self.curves[b].exact_ends or not self.curves[a].exact_ends else pa
                self._jend[a] = joint
                self._jstart[b] = joint
            if not closed:
                self._jstart[cids[0]] = fine_pts[cids[0]][0]
                self._jend[cids[-1]] = fine_pts[cids[-1]][-1]

    def _assemble(self, params: list[np.ndarray], pts: list[np.ndarray] | None = None) -> _Assembly:
        """Concatenate curve polylines at ``params`` into raw points and segments."""
        P, S, SC, SP, SL, PG = [], [], [], [], [], []
        offset = 0
        nseg = 0
        slices = {}
        for g, cids in self._groups:
            chunk = []
            for cid in cids:
                t = params[cid]
                p = self.curves[cid].evaluate(t) if pts is None else pts[cid].copy()
                p[0], p[-1] = self._jstart[cid], self._jend[cid]
                chunk.append(p[:-1])
                SC.append(np.full(len(t) - 1, cid, dtype=np.int64))
                SP.append(np.column_stack([t[:-1], t[1:]]))
                SL.append(np.arange(len(t) - 1))
            closed = self._closed[g]
            if not closed:
                chunk.append(self._jend[cids[-1]][None, :])
            p = np.concatenate(chunk)
            k = len(p)
            idx = np.arange(k, dtype=np.int64) + offset
            S.append(
                np.column_stack([idx, np.roll(idx, -1)])
                if closed
                else np.column_stack([idx[:-1], idx[1:]])
            )
            P.append(p)
            PG.append(np.full(k, g, dtype=np.int64))
            slices[g] = slice(nseg, nseg + len(S[-1]))
            nseg += len(S[-1])
            offset += k
        return _Assembly(
            np.concatenate(P),
            np.concatenate(S),
            np.concatenate(SC),
            np.concatenate(SP),
            np.concatenate(SL),
            np.concatenate(PG),
            slices,
        )

    def _describe(self, asm: _Assembly, s: int) -> str:
        cid = int(asm.seg_curve[s])
        g, cids = next((g, cids) for g, cids in self._groups if cid in cids)
        k = cids.index(cid)
        a, b = asm.points[asm.segments[s]]
        return f"{self._name(g)} curve {k} segment {asm.seg_local[s]} {fmt_point(a)}-{fmt_point(b)}"

    # -- validation ----------------------------------------------------------------------
    def validate(self) -> Domain:
        """Check the domain and normalise loop orientation; return ``self``.

        Straight pieces are first split where a constraint ends on (or passes through) a
        segment, where an interior point lies on one and where two constraints cross, as
        Triangle does (:mod:`meshwright.geometry._junctions`); an interior point that is
        or becomes a vertex of a segment leaves :attr:`points`.

        Raises
        ------
        GeometryError
            Open or broken loops, non-finite coordinates, zero-length segments, loops with
            fewer than three vertices, duplicate points, touching or crossing loops,
            constraints crossing a loop or overlapping, junctions on curved pieces, holes
            outside the outer loop, islands (loops nested in holes) without a region seed,
            constraints, points or region seeds outside the domain.
        """
        for _ in range(_JUNCTION_ROUNDS):
            self._set_loops(self._raw_loops)
            if not self._split_junctions():
                break
        else:
            raise GeometryError(
                f"segment junctions still need splits after {_JUNCTION_ROUNDS} rounds of up to {_JUNCTION_PAIRS} "
                "(too many crossings, or crossings whose rounded intersections meet further segments)"
            )
        asm = self._fine
        depth, parent = self._nesting(asm)
        loops = list(self.loops)
        for li in range(len(loops)):
            ccw = self._ccw(asm, li)
            if ccw != (depth[li] % 2 == 0):
                loops[li] = tuple(c.reversed() for c in reversed(loops[li]))
        self._raw_loops = loops
        self._set_loops(loops)
        self.loop_depth = depth
        self._parent = parent
        params = [c.fine_params() for c in self.curves]
        fine_pts = [c.evaluate(t) for c, t in zip(self.curves, params)]
        self._join(fine_pts)
        self._fine = self._assemble(params, fine_pts)
        self._check_contents()
        self._hole_seeds = self._seeds(self._fine)
        return self

    def _split_junctions(self) -> bool:
        """One round of :mod:`._junctions`: whether any piece was split (then check again)."""
        asm, verts, inv = self._fine_checks()
        self._fine = asm
        segs = inv[asm.segments]
        bad = find_bad_pairs(verts, segs, _JUNCTION_PAIRS)
        is_loop = self.curve_loop >= 0
        splits, rounded, culprit = junction_splits(
            verts, segs, asm.seg_curve, asm.seg_local, self.curves, is_loop, bad
        )
        if culprit >= 0:
            s, t = bad[culprit]
            raise GeometryError(f"{self._describe(asm, s)} intersects {self._describe(asm, t)}")
        at, keep, culprit = point_splits(verts, segs, asm.seg_curve, asm.seg_local, self.curves, self.points)
        if culprit >= 0:
            raise GeometryError(
                f"interior point {culprit} at {fmt_point(self.points[culprit])} lies on a curved boundary or constraint"
            )
        if at or not keep.all():
            # Points on segments are exact splits: they go before any rounded crossing.
            splits = at if rounded else {k: splits.get(k, []) + at.get(k, []) for k in {*splits, *at}}
        if not splits and keep.all():
            return False
        first = [cids[0] for _, cids in self._groups]
        chains = apply_splits(list(self.loops) + list(self.constraints), first, splits)
        self._raw_loops = chains[: len(self.loops)]
        self.constraints = tuple(chains[len(self.loops):])
        self.points = np.ascontiguousarray(self.points[keep])
        return True

    def _fine_checks(self):
        params = []
        fine_pts = []
        for g, cids in self._groups:
            for k, cid in enumerate(cids):
                try:
                    t = self.curves[cid].fine_params()
                    p = self.curves[cid].evaluate(t)
                except GeometryError as exc:
                    raise GeometryError(f"{self._name(g)} curve {k}: {exc}") from exc
                params.append(t)
                fine_pts.append(p)
        self._join(fine_pts)
        asm = self._assemble(params, fine_pts)
        check_coordinate_range(asm.points, "domain boundary")
        a, b = asm.points[asm.segments[:, 0]], asm.points[asm.segments[:, 1]]
        zero = np.flatnonzero((a == b).all(axis=1))
        if len(zero):
            s = zero[0]
            raise GeometryError(f"{self._describe(asm, s)} has zero length")
        for g, _ in self._groups:
            if g >= 0:
                n = np.count_nonzero(asm.point_group == g)
                if n < 3:
                    raise GeometryError(
                        f"{self._name(g)} has {n} vertices; a loop needs at least 3"
                    )
        verts, inv = unique_rows(asm.points)
        self._check_shared(asm, verts, inv)
        return asm, verts, inv

    def _check_shared(self, asm: _Assembly, verts: np.ndarray, inv: np.ndarray) -> None:
        """Loops may not share vertices with themselves or with each other."""
        on_loop = asm.point_group >= 0
        idx = np.flatnonzero(on_loop)
        counts = np.bincount(inv[idx], minlength=len(verts))
        dup = np.flatnonzero(counts > 1)
        if len(dup):
            v = dup[0]
            groups = np.unique(asm.point_group[idx[inv[idx] == v]])
            if len(groups) == 1:
                raise GeometryError(
                    f"{self._name(groups[0])} passes twice through {fmt_point(verts[v])} "
                    "(duplicate point or self-touching loop)"
                )
            raise GeometryError(
                f"{self._name(groups[0])} and {self._name(groups[1])} touch at {fmt_point(verts[v])}"
            )

    def _loop_segments(self, asm: _Assembly, groups) -> tuple[np.ndarray, np.ndarray]:
        """End points (m, 2), (m, 2) of the segments of the given loops (or chains)."""
        parts = [asm.segments[asm.seg_slices[int(g)]] for g in groups]
        s = np.concatenate(parts) if parts else np.zeros((0, 2), dtype=np.int64)
        return asm.points[s[:, 0]], asm.points[s[:, 1]]

    def _ccw(self, asm: _Assembly, li: int) -> bool:
        """Exact orientation of a simple loop: the turn at its lexicographically lowest vertex."""
        idx = np.flatnonzero(asm.point_group == li)
        p = asm.points[idx]
        i = int(np.lexsort((p[:, 1], p[:, 0]))[0])
        a, b, c = p[i - 1], p[i], p[(i + 1) % len(p)]
        return orient2d(a[0], a[1], b[0], b[1], c[0], c[1]) > 0.0

    def _nesting(self, asm: _Assembly):
        """Depth and parent of each loop; holes must lie inside the outer loop."""
        nloops = len(self.loops)
        depth = np.zeros(nloops, dtype=np.int64)
        parent = np.full(nloops, -1, dtype=np.int64)
        if nloops == 1:
            return depth, parent
        first = np.array(
            [asm.points[np.flatnonzero(asm.point_group == li)[0]] for li in range(nloops)]
        )
        boxes = np.array(
            [
                np.r_[p.min(0), p.max(0)]
                for p in (asm.points[asm.point_group == li] for li in range(nloops))
            ]
        )
        a, b = self._loop_segments(asm, [0])
        outside = np.flatnonzero(classify_points(first[1:], a, b) != INSIDE)
        if len(outside):
            h = outside[0] + 1
            raise GeometryError(
                f"{self._name(h)} lies outside the outer loop (vertex {fmt_point(first[h])})"
            )
        containers = []
        for j in range(1, nloops):
            q = first[j]
            cand = np.flatnonzero(
                (boxes[:, 0] <= q[0])
                & (q[0] <= boxes[:, 2])
                & (boxes[:, 1] <= q[1])
                & (q[1] <= boxes[:, 3])
            )
            inside = [
                i
                for i in cand
                if i not in (0, j)
                and classify_points(q[None], *self._loop_segments(asm, [i]))[0] == INSIDE
            ]
            containers.append(inside)
            depth[j] = 1 + len(inside)
        for j in range(1, nloops):
            if containers[j - 1]:
                parent[j] = max(containers[j - 1], key=lambda i: depth[i])
            else:
                parent[j] = 0
        for j in np.flatnonzero((depth >= 2) & (depth % 2 == 0)):
            if not self._island_has_region(asm, j, parent):
                raise GeometryError(
                    f"{self._name(j)} lies inside {self._name(parent[j])}: a loop nested in a hole "
                    "is an island and needs a region seed (x, y, marker, max_area) inside it"
                )
        return depth, parent

    def _island_has_region(self, asm, j, parent) -> bool:
        if not self.regions:
            return False
        seeds = np.array([r[:2] for r in self.regions])
        inside = classify_points(seeds, *self._loop_segments(asm, [j])) == INSIDE
        for child in np.flatnonzero(parent == j):
            inside &= classify_points(seeds, *self._loop_segments(asm, [child])) == 0
        return bool(inside.any())

    def _check_contents(self) -> None:
        """Constraints, interior points and region seeds must lie inside the domain."""
        asm = self._fine
        a, b = self._loop_segments(asm, np.arange(len(self.loops)))
        for ci, chain in enumerate(self.constraints):
            g = -1 - ci
            s = np.flatnonzero(asm.point_group[asm.segments[:, 0]] == g)[0]
            mid = 0.5 * (asm.points[asm.segments[s, 0]] + asm.points[asm.segments[s, 1]])
            if classify_points(mid[None], a, b)[0] != INSIDE:
                raise GeometryError(f"{self._name(g)} lies outside the domain (near {fmt_point(mid)})")
        ca, cb = self._loop_segments(asm, [-1 - ci for ci in range(len(self.constraints))])
        if len(self.points):
            bad = np.flatnonzero(~np.isfinite(self.points).all(axis=1))
            if len(bad):
                raise GeometryError(
                    f"interior point {bad[0]} has non-finite coordinates {fmt_point(self.points[bad[0]])}"
                )
            where = classify_points(self.points, a, b)
            on_c = classify_points(self.points, ca, cb) == ON_BOUNDARY
            bad = np.flatnonzero((where != INSIDE) | on_c)
            if len(bad):
                i = bad[0]
                what = "outside the domain" if where[i] == 0 else "on a boundary or constraint"
                raise GeometryError(f"interior point {i} at {fmt_point(self.points[i])} lies {what}")
            _, inv = unique_rows(self.points)
            twice = np.flatnonzero(np.bincount(inv) > 1)
            if len(twice):
                i, j = np.flatnonzero(inv == twice[0])[:2]
                raise GeometryError(
                    f"interior points {i} and {j} coincide at {fmt_point(self.points[i])}"
                )
        if self.regions:
            seeds = np.array([r[:2] for r in self.regions])
            where = classify_points(seeds, a, b)
            on_c = classify_points(seeds, ca, cb) == ON_BOUNDARY
            bad = np.flatnonzero((where != INSIDE) | on_c)
            if len(bad):
                i = bad[0]
                raise GeometryError(
                    f"region {i} seed {fmt_point(seeds[i])} is not strictly inside the domain"
                )

    def _seeds(self, asm: _Assembly) -> np.ndarray:
        out = []
        for j in np.flatnonzero(self.loop_depth % 2 == 1):
            kids = np.flatnonzero(self._parent == j)
            a, b = self._loop_segments(asm, np.r_[j, kids])
            out.append(interior_seed(a, b, self._name(j)))
        return np.array(out, dtype=np.float64).reshape(-1, 2)

    # -- queries -------------------------------------------------------------------------
    @property
    def holes(self) -> np.ndarray:
        """(h, 2) float64: one point strictly inside each hole loop."""
        return self._hole_seeds.copy()

    @property
    def bbox(self) -> tuple[float, float, float, float]:
        """``(xmin, ymin, xmax, ymax)`` of the outer loop's fine polyline."""
        p = self._fine.points[self._fine.point_group == 0]
        return (
            float(p[:, 0].min()),
            float(p[:, 1].min()),
            float(p[:, 0].max()),
            float(p[:, 1].max()),
        )

    def outer_is_convex(self) -> bool:
        """Whether the outer loop (its fine polyline) turns left or goes straight at every
        vertex, exactly (``orient2d``): then it is its own convex hull."""
        p = self._fine.points[self._fine.point_group == 0]
        i = np.arange(len(p))
        turns = orient2d_batch(p, np.column_stack([i - 1, i, (i + 1) % len(p)]) % len(p))
        return bool((turns >= 0).all())

    def area(self) -> float:
        """Area enclosed: exact for lines, arcs and polylines, quadrature for parametric curves."""
        return float(sum(c.signed_area() for lp in self.loops for c in lp))

    def contains(self, xy, boundary: bool = False) -> np.ndarray:
        """Whether points lie in the domain (exact ray casting on the fine polyline).

        Parameters
        ----------
        xy : (k, 2) array_like
        boundary : bool
            Value returned for points on a loop.

        Returns
        -------
        (k,) bool
        """
        q = np.ascontiguousarray(np.asarray(xy, dtype=np.float64).reshape(-1, 2))
        where = classify_points(q, *self._loop_segments(self._fine, np.arange(len(self.loops))))
        return (where == INSIDE) | ((where == ON_BOUNDARY) & boundary)

    def project(self, curve_ids, xy, t_near=None) -> tuple[np.ndarray, np.ndarray]:
        """Closest points on the given curves.

        Parameters
        ----------
        curve_ids : (k,) int
            Indices into :attr:`curves`.
        xy : (k, 2) float64
        t_near : (k,) float64, optional
            Current parameters, keeping each answer near them (see :meth:`Curve.project`).

        Returns
        -------
        t : (k,) float64
        points : (k, 2) float64
        """
        ids = np.asarray(curve_ids, dtype=np.int64).ravel()
        q = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
        t = np.empty(len(ids))
        out = np.empty((len(ids), 2))
        for cid in np.unique(ids):
            m = ids == cid
            near = None if t_near is None else np.asarray(t_near, dtype=np.float64)[m]
            t[m] = self.curves[cid].project(q[m], near)
            out[m] = self.curves[cid].evaluate(t[m])
        return t, out

    def split(self, curve_ids, ta, tb) -> tuple[np.ndarray, np.ndarray]:
        """Arc-length midpoints between parameters ``ta`` and ``tb`` (each (k,)) on curves.

        Returns
        -------
        t : (k,) float64
        points : (k, 2) float64
            On the true curves.
        """
        ids = np.asarray(curve_ids, dtype=np.int64).ravel()
        ta = np.asarray(ta, dtype=np.float64).ravel()
        tb = np.asarray(tb, dtype=np.float64).ravel()
        t = np.empty(len(ids))
        out = np.empty((len(ids), 2))
        for cid in np.unique(ids):
            m = ids == cid
            t[m] = self.curves[cid].midpoint_param(ta[m], tb[m])
            out[m] = self.curves[cid].evaluate(t[m])
        return t, out

    def boundary_length(self) -> float:
        """Total length of the loops and constraints, on their fine polylines (chords, so a
        little short of the true curves)."""
        asm = self._fine
        d = asm.points[asm.segments[:, 1]] - asm.points[asm.segments[:, 0]]
        return float(np.hypot(d[:, 0], d[:, 1]).sum())

    def estimate_boundary_points(self, size) -> float:
        """About how many points :meth:`discretize` places on the curves for ``size``.

        The integral of ``1 / h`` along every fine-polyline chord, with ``h`` the spacing
        along the chord at its midpoint (:meth:`SizeField.along`): cheap whatever the size,
        so callers can refuse a size far below the domain's extent before discretising.

        Parameters
        ----------
        size : number, callable or SizeField

        Returns
        -------
        float
        """
        h = as_size_field(size)
        asm = self._fine
        a, b = asm.points[asm.segments[:, 0]], asm.points[asm.segments[:, 1]]
        d = b - a
        return float(np.sum(np.hypot(d[:, 0], d[:, 1]) / h.along(0.5 * (a + b), d)))

    # -- discretisation ------------------------------------------------------------------
    def discretize(self, size=None) -> Discretization:
        """Place points along every curve so that spacing follows the size field.

        Each curve piece gets ``max(min_segments, round(integral ds / h))`` segments at
        equal increments of ``integral ds / h``; curve ends are shared vertices.  When the
        resulting polygon is invalid (a coarse chord crossing a neighbouring curve, a loop
        reversed, a region seed or interior point cut off), the counts of the curved pieces
        involved are doubled until it is valid.

        Parameters
        ----------
        size : number, callable or SizeField, optional
            Target spacing ``h``; defaults to :attr:`size`, and without either each piece
            gets its minimum count (polygon vertices are kept as given).

        Returns
        -------
        Discretization
        """
        if size is None:
            size = self.size
        h = None if size is None else as_size_field(size)
        factors = np.ones(len(self.curves), dtype=np.int64)
        for _ in range(_MAX_ROUNDS):
            params = place_params(self.curves, h, factors)
            asm = self._assemble(params)
            verts, inv = unique_rows(asm.points)
            culprits = self._conflicts(asm, verts, inv)
            if culprits is None:
                return self._pslg(asm, verts, inv)
            # Straight pieces are exact: only curved ones can be improved.
            curved = [c for c in culprits if not isinstance(self.curves[c], (Line, Polyline))]
            if not curved:
                break
            factors[curved] *= 2
        raise GeometryError(
            "cannot discretise the domain into a valid polygon: curves "
            f"{sorted(set(int(c) for c in culprits))} stay in conflict after {_MAX_ROUNDS} doublings of their "
            "segment counts; the geometry has features below the fine-polyline resolution"
        )

    def _conflicts(self, asm: _Assembly, verts, inv) -> list[int] | None:
        """Curves to refine for the coarse polygon to be valid, or None when it is."""
        segs = inv[asm.segments]
        bad = find_bad_pairs(verts, segs, _REPORT)
        if len(bad):
            return list(np.unique(asm.seg_curve[bad.ravel()]))
        loop_pts = np.flatnonzero(asm.point_group >= 0)
        counts = np.bincount(inv[loop_pts], minlength=len(verts))
        if (counts > 1).any():
            v = np.flatnonzero(counts > 1)
            touching = np.isin(segs, v).any(axis=1)
            return list(np.unique(asm.seg_curve[touching]))
        wrong = [
            li
            for li in range(len(self.loops))
            if self._ccw(asm, li) != (self.loop_depth[li] % 2 == 0)
        ]
        if wrong:
            return [cid for li in wrong for cid in self._groups[li][1]]
        seeds = [self.points] + ([np.array([r[:2] for r in self.regions])] if self.regions else [])
        q = np.concatenate(seeds)
        if len(q):
            a, b = self._loop_segments(asm, np.arange(len(self.loops)))
            lost = q[classify_points(q, a, b) != INSIDE]
            if len(lost):
                # Loop segments come first in the assembly, so indices coincide.
                idx, _ = nearest_segment(lost, a, b)
                return list(np.unique(asm.seg_curve[idx]))
        return None

    def _pslg(self, asm: _Assembly, verts, inv) -> Discretization:
        segs = inv[asm.segments].astype(np.int32)
        markers = np.empty(len(segs), dtype=np.int32)
        for cid, c in enumerate(self.curves):
            m = asm.seg_curve == cid
            default = 1 if self.curve_loop[cid] >= 0 else 0
            markers[m] = c.segment_markers(asm.seg_params[m, 0], asm.seg_params[m, 1], default)
        points = np.concatenate([verts, self.points])
        pmark = np.zeros(len(points), dtype=np.int32)
        np.maximum.at(pmark, segs[:, 0], markers)
        np.maximum.at(pmark, segs[:, 1], markers)
        regions = np.array(
            [(x, y, m, -1.0 if a is None else a) for x, y, m, a in self.regions], dtype=np.float64
        ).reshape(-1, 4)
        return Discretization(
            points=np.ascontiguousarray(points),
            segments=segs,
            segment_markers=markers,
            segment_curve=asm.seg_curve.astype(np.int32),
            segment_params=asm.seg_params,
            point_markers=pmark,
            holes=self._seeds(asm),
            regions=regions,
        )
