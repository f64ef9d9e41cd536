r"""Constrained Delaunay triangulation of a planar straight-line graph, exterior removal.

API (stable; :mod:`meshwright.tri.mesher` and :mod:`meshwright.tri.weatherill` build on it)
-------------------------------------------------------------------------------------------
``cdt_build(points, segments=None, segment_ids=None, seed=0, *, conforming=False,
curves=None, duplicates="merge") -> ConstrainedTriangulation``

``ConstrainedTriangulation``
    ``classify(segment_sides=None, holes=None, regions=None) -> self``  exterior and regions
    ``close_hull(segment_id=-1) -> self``     constrain the free convex-hull edges
    ``insert_point(x, y) -> int``, ``insert_points(xy) -> (k,) int32``  constrained insertion
    ``split_segment(a, b, xy=None) -> int``   split subsegment ab (default: its split point)
    ``reserve(rows=0, slots=0)`` / ``shrink() -> self``   grow / trim the arrays' spare room
    ``points`` (nv, 2), ``index_map`` (n,), ``triangles(inside=True)`` (nt, 3),
    ``neighbors(inside=True)`` (nt, 3), ``triangle_markers(inside=True)`` (nt,),
    ``segments() -> (edges (k, 2), ids (k,))``, ``to_mesh(segment_markers=None) -> Mesh``

``SegmentCurves(curves, segment_curve, segment_params)`` / ``SegmentCurves.from_domain(domain,
discretization)``: the true curve of each input segment, so that every split point lies on it
(arcs are evaluated inside the Numba loop, other curves in Python).  ``curves`` may also be a
callable ``(segment_id, xy_a, xy_b) -> xy_split``.  :func:`meshwright.tri.ruppert.refine`
takes a ``ConstrainedTriangulation``.

Segment ids: ``segment_ids[i]`` (default i) labels input segment i; every subsegment carries
the id of its segment, ``to_mesh`` maps ids to markers through ``segment_markers[id]``, and
``segment_sides`` / ``SegmentCurves`` are indexed by input segment.

Sources
-------
Points are inserted by the Delaunay kernel (:mod:`meshwright.tri._kernel2d`, BRIO order);
segments are then recovered by edge flips (S. W. Sloan, "A fast algorithm for generating
constrained Delaunay triangulations", Computers & Structures 47(3), 1993) in
:func:`meshwright.tri.sloan.recover_segments`: the crossing edges are collected by a walk
along the segment and flipped from a queue, then the new edges are made locally Delaunay.
A segment passing exactly through a vertex (exact ``orient2d == 0``, between its ends) is cut
there.  Constrained edges are marked per half-edge in ``cons`` (``piece + 1``), which the
kernel respects on every later insertion (a cavity never crosses a constrained edge).

Exterior removal (chapter 18.1.2 of the reference text): boundary loops run with the domain
on their left (outer loops counter-clockwise, holes clockwise), so the triangle on the domain
side of a boundary segment is known from the sign of the cross product of the segment
direction with the vector to its apex.  ``classify`` (kernels in :mod:`meshwright.tri._classify`)
seeds those triangles and floods across free edges (and across interior constraints without a
side); anything not reached, the
superstructure (ghost triangles) included, is exterior.  Without sides, the flood starts from
the ghost triangles instead (Triangle's convention) and hole seeds eat inwards.  Region seeds
``(x, y, marker[, max_area])`` flood their region.  Triangles are flagged, never deleted::

      ghost  |  exterior   *=====*   domain (left of the loop)      *===* constrained edge
             |             loop a->b

Invariants: every input segment is a union of constrained edges; every free edge is locally
constrained-Delaunay (exact ``incircle_sos`` with the build's perturbation keys); ``vtri[v]``
is a triangle of vertex v; ``treg`` is -1 on ghosts and exterior triangles, 0 inside, r + 1 in
region r.

State: two documented bundles, all that methods built on the class use: ``state``, the
insertion kernel's :class:`~meshwright.tri._kernel2d.TriState` (``tri``/``nbr``/``cons``,
finite and ghost slots interleaved), and ``constraints``, the constrained layer's
:class:`~meshwright.tri._encroach.CdtState`.  They grow only through
:meth:`ConstrainedTriangulation.reserve` (arrays taken before may then be stale).
"""

from __future__ import annotations

import numpy as np

from meshwright.core.errors import GeometryError, InputError, MeshingError, fmt_point
from meshwright.core.flat import GHOST
from meshwright.tri import _encroach as enc
from meshwright.tri._build2d import locate_points
from meshwright.tri._classify import FLOOD_LEAK, FLOOD_OK, classify_sides, flood
from meshwright.tri._kernel2d import M_NTRI, M_NV, grow
from meshwright.tri.sloan import recover_segments
from meshwright.tri.triangulation import Triangulation

__all__ = ["ConstrainedTriangulation", "SegmentCurves", "cdt_build"]



# ---------------------------------------------------------------------------- curves
class SegmentCurves:
    """True curve of each input segment, for split points on curved boundaries.

    Parameters
    ----------
    curves : sequence of Curve
        E.g. ``Domain.curves``; :class:`~meshwright.geometry.curves.Arc` is evaluated in
        the Numba loop, ``Line``/``Polyline`` are straight, anything else is called back
        (``midpoint_param`` and ``evaluate``).
    segment_curve : (m,) int
        Curve of each input segment (``Discretization.segment_curve``).
    segment_params : (m, 2) float64
        Curve parameters of each segment's end points (``Discretization.segment_params``).
    """

    def __init__(self, curves, segment_curve, segment_params):
        from meshwright.geometry.curves import Arc, Line, Polyline

        self.curves = tuple(curves)
        self.segment_curve = np.asarray(segment_curve, dtype=np.int64).ravel()
        self.segment_params = np.asarray(segment_params, dtype=np.float64).reshape(-1, 2)
        m = len(self.segment_curve)
        if self.segment_params.shape[0] != m:
            raise InputError(f"segment_params has {self.segment_params.shape[0]} rows for {m} segments")
        if m and (self.segment_curve.min() < 0 or self.segment_curve.max() >= len(self.curves)):
            raise InputError(f"segment_curve holds indices outside [0, {len(self.curves)})")
        self.kind = np.full(m, enc.KIND_CURVE, dtype=np.int8)
        self.data = np.zeros((m, 5))
        self.data[:, 3:] = self.segment_params
        for cid, c in enumerate(self.curves):
            rows = self.segment_curve == cid
            if isinstance(c, (Line, Polyline)):
                self.kind[rows] = enc.KIND_STRAIGHT
            elif isinstance(c, Arc):
                self.kind[rows] = enc.KIND_ARC
                self.data[rows, :3] = (c.center[0], c.center[1], c.radius)

    @classmethod
    def from_domain(cls, domain, discretization) -> SegmentCurves:
        """Curves of a :class:`~meshwright.geometry.Domain` and its ``discretize()`` result."""
        return cls(domain.curves, discretization.segment_curve, discretization.segment_params)

    def split(self, row: int, ta: float, tb: float) -> tuple[float, float, float]:
        """Split point ``(x, y, t)`` halfway in arc length between parameters ta and tb."""
        c = self.curves[self.segment_curve[row]]
        t = float(c.midpoint_param(np.array([ta]), np.array([tb]))[0])
        x, y = c.evaluate(np.array([t]))[0]
        return float(x), float(y), t

    def project(self, row: int, xy) -> float:
        """Curve parameter of the point of input segment ``row``'s curve nearest ``xy``."""
        c = self.curves[self.segment_curve[row]]
        lo, hi = sorted(self.segment_params[row])
        return float(np.clip(c.project(np.reshape(xy, (1, 2)))[0], lo, hi))


# ---------------------------------------------------------------------------- the class
class ConstrainedTriangulation:
    """Constrained Delaunay triangulation with per-triangle inside/region flags.

    Built by :func:`cdt_build`; see the module docstring for the API and invariants.

    Attributes
    ----------
    index_map : (n,) int32
        Vertex of each input point (coincident points share one).
    segment_ids : (m,) int32
        Id of each input segment.
    input_segments : (m, 2) int32
        Input segments as vertex pairs.
    curves : SegmentCurves, callable or None
        Where split points of each segment lie (see :func:`cdt_build`).
    classified : bool
        Whether :meth:`classify` ran (else every finite triangle counts as inside).
    state : TriState
        The insertion kernel's bundle (:mod:`meshwright.tri._kernel2d`), with ``cons``.
    constraints : CdtState
        The constrained layer's bundle (:mod:`meshwright.tri._encroach`).
    held : tuple of ((k, 2) int32, (k,) int32)
        Subsegments of frozen segments that the last :func:`~meshwright.tri.ruppert.refine`
        left unsplit although refinement needed them split (along their segment's
        direction, as :meth:`segments`), and their segment ids; empty without ``frozen``.
    """

    def __init__(self, tr: Triangulation, segments: np.ndarray, segment_ids: np.ndarray, curves):
        nv = len(tr.points)
        rows = max(16, 2 * nv)
        t = tr.state
        pts = np.empty((rows, 2))
        pts[:nv] = t.pts[:nv]
        slots = t.tri.shape[0] // 3
        # The Triangulation's arrays become this one's: it is not used again.
        self.state = t._replace(
            pts=pts, cons=np.zeros(3 * slots, dtype=np.int32), circ=np.empty(0, dtype=np.float32),
            vmark=np.empty(rows + 1, dtype=np.int32),
        )
        self.state.meta[M_NV] = nv
        ntri = int(t.meta[M_NTRI])
        m = len(segments)
        seg = np.empty((m + 16, 2), dtype=np.int32)
        seg[:m] = segments
        seg_in = np.empty(m + 16, dtype=np.int32)
        seg_in[:m] = np.arange(m)
        self.constraints = enc.CdtState(
            vtri=np.empty(rows, dtype=np.int32), treg=np.zeros(slots, dtype=np.int32),
            vseg=np.full(rows, -1, dtype=np.int32), vpar=np.zeros(rows), vacute=np.zeros(rows, dtype=np.int8),
            seg=seg, seg_in=seg_in, pkind=np.zeros(0, dtype=np.int8), pdat=np.zeros((0, 5)),
            rarea=np.array([np.inf]),
        )
        c = self.constraints
        enc.link_vertices(self.state.tri, ntri, c.vtri)
        c.treg[:ntri][self.state.tri[2 : 3 * ntri : 3] == GHOST] = -1
        self.index_map = tr.index_map
        self.input_segments = segments
        self.segment_ids = segment_ids
        self.curves = curves
        self.classified = False
        self.held = (np.zeros((0, 2), dtype=np.int32), np.zeros(0, dtype=np.int32))
        self._rmarker = np.zeros(1, dtype=np.int32)
        self._np = m
        self._hull_id = -1
        self._recover(np.arange(m - 1, -1, -1, dtype=np.int32))

    # ------------------------------------------------------------------ building
    def _recover(self, todo: np.ndarray) -> None:
        """Recover pieces ``todo`` (processed last to first) as constrained edges."""
        ntri = int(self.state.meta[M_NTRI])
        elist = np.empty(2 * (3 * ntri // 2 + 3), dtype=np.int32)
        nlist = np.empty_like(elist)
        rs = np.array([self._np, len(todo), -1, -1], dtype=np.int64)
        todo = np.concatenate([todo, np.empty(len(todo) + 16, dtype=np.int32)])
        while True:
            code = recover_segments(self.state, self.constraints, todo, rs, elist, nlist)
            self._np = int(rs[0])
            if code == 0:
                return
            if code == 1:
                self._grow_pieces(max(16, self.constraints.seg.shape[0]))
                todo = np.concatenate([todo, np.empty(max(16, len(todo)), dtype=np.int32)])
                continue
            self._raise_crossing(int(rs[2]), int(rs[3]))

    def _grow_pieces(self, more: int) -> None:
        c = self.constraints
        self.constraints = c._replace(
            seg=np.concatenate([c.seg, np.empty((more, 2), dtype=np.int32)]),
            seg_in=np.concatenate([c.seg_in, np.empty(more, dtype=np.int32)]),
        )

    def _raise_crossing(self, p: int, h: int) -> None:
        i = int(self.constraints.seg_in[p])
        a, b = self.input_segments[i] if i >= 0 else self.constraints.seg[p]
        what = f"segment {i} from {fmt_point(self.state.pts[a])} to {fmt_point(self.state.pts[b])}"
        if h < 0:
            raise MeshingError(f"cannot trace {what} through the triangulation")
        q = int(self.state.cons[h]) - 1
        j = int(self.constraints.seg_in[q])
        u, w = self.state.tri[h - h % 3 + (h % 3 + 1) % 3], self.state.tri[h - h % 3 + (h % 3 + 2) % 3]
        c, d = self.input_segments[j] if j >= 0 else self.constraints.seg[q]
        pts = self.state.pts
        other = f"segment {j} from {fmt_point(pts[c])} to {fmt_point(pts[d])}" if j >= 0 else "a hull segment"
        raise GeometryError(
            f"{what} intersects {other} (it crosses its piece {fmt_point(self.state.pts[u])}-{fmt_point(self.state.pts[w])})"
        )

    def refresh_pieces(self) -> None:
        """Set ``constraints.pkind`` / ``pdat`` of every piece from :attr:`curves`.

        Kernels that split subsegments read them; call after :attr:`curves` or the pieces
        change (the refinement and insertion entries do).  Pieces with no known curve are
        straight.
        """
        n = self._np
        kind = np.zeros(n, dtype=np.int8)
        data = np.zeros((n, 5))
        c = self.constraints
        if isinstance(self.curves, SegmentCurves):
            rows = c.seg_in[:n]
            ok = (rows >= 0) & (rows < len(self.curves.kind))
            ok[ok] &= (c.seg[:n][ok] == self.input_segments[rows[ok]]).all(axis=1)
            kind[ok] = self.curves.kind[rows[ok]]
            data[ok] = self.curves.data[rows[ok]]
        elif callable(self.curves):
            kind[c.seg_in[:n] >= 0] = enc.KIND_CURVE
        self.constraints = c._replace(pkind=kind, pdat=data)

    def mark_acute(self) -> None:
        """Flag (``constraints.vacute``) input vertices where two pieces meet below 60 degrees."""
        seg = self.constraints.seg[: self._np]
        if not len(seg):
            return
        d = self.state.pts[seg[:, 1]] - self.state.pts[seg[:, 0]]
        verts = np.concatenate([seg[:, 0], seg[:, 1]])
        ang = np.concatenate([np.arctan2(d[:, 1], d[:, 0]), np.arctan2(-d[:, 1], -d[:, 0])])
        order = np.lexsort((ang, verts))
        v, a = verts[order], ang[order]
        first = np.r_[True, v[1:] != v[:-1]]
        gap = np.diff(a, append=np.inf)
        gap[np.r_[~first[1:], False] == False] = np.inf  # noqa: E712 - last of each group
        start = np.flatnonzero(first)
        last = np.r_[start[1:], len(v)] - 1
        wrap = 2.0 * np.pi - (a[last] - a[start])
        wrap[last == start] = np.inf
        small = np.minimum(np.minimum.reduceat(gap, start), wrap) < np.pi / 3.0
        self.constraints.vacute[v[start[small]]] = 1

    # ------------------------------------------------------------------ growth
    def reserve(self, rows: int = 0, slots: int = 0) -> None:
        """Grow both bundles (doubling) to ``rows`` vertices and ``slots`` triangle slots.

        With no arguments, makes the room one more insertion needs, the cavity scratch
        included when a kernel asked for it; what a kernel returning ``NEED_SPACE`` /
        ``R_ROOM`` needs.  Arrays taken from :attr:`state` or :attr:`constraints` before the
        call may be stale after it.
        """
        self.state = grow(self.state, rows, slots)
        s = self.state
        self.constraints = enc.grow(self.constraints, s.pts.shape[0], s.tri.shape[0] // 3)

    def shrink(self) -> ConstrainedTriangulation:
        """Release the spare room: every array trimmed to the vertices, triangle slots and
        pieces in use (copies, so the larger arrays are freed).

        For a triangulation kept between calls (the distributed mesher keeps each part's
        between exchange rounds): refinement reserves room toward its size field's estimate,
        up to twice what it uses.  Nothing a kernel decides depends on the room, so a later
        insertion or refinement gives the same triangles, growing the arrays again by doubling.
        Arrays taken from :attr:`state` or :attr:`constraints` before the call are stale after it.
        """
        s, c = self.state, self.constraints
        nv, ntri, npc = int(s.meta[M_NV]), int(s.meta[M_NTRI]), self._np
        self.state = s._replace(
            pts=s.pts[:nv].copy(), tri=s.tri[: 3 * ntri].copy(), nbr=s.nbr[: 3 * ntri].copy(),
            cons=s.cons[: 3 * ntri].copy(), circ=s.circ[: 4 * ntri].copy(),
            vmark=np.empty(nv + 1, dtype=np.int32),
        )
        self.constraints = c._replace(
            vtri=c.vtri[:nv].copy(), vseg=c.vseg[:nv].copy(), vpar=c.vpar[:nv].copy(),
            vacute=c.vacute[:nv].copy(), treg=c.treg[:ntri].copy(), seg=c.seg[:npc].copy(),
            seg_in=c.seg_in[:npc].copy(),
        )
        return self

    # ------------------------------------------------------------------ classification
    def classify(self, segment_sides=None, holes=None, regions=None) -> ConstrainedTriangulation:
        """Flag exterior triangles and assign regions (chapter 18.1.2 exterior removal).

        Parameters
        ----------
        segment_sides : (m,) array_like of int, optional
            Per input segment: +1 the domain lies left of it (as in a discretised loop), -1
            right, 0 unknown or an interior constraint.  Without any nonzero side, every
            triangle that can be reached from outside the convex hull without crossing a
            segment is exterior (Triangle's convention).
        holes : (h, 2) array_like of float, optional
            Seeds: the region around each (bounded by segments) is exterior.
        regions : sequence of (x, y, marker) or (x, y, marker, max_area)
            Seeds: the region around each gets ``marker`` (and a maximum triangle area that
            :func:`meshwright.tri.ruppert.refine` honours).

        Returns
        -------
        ConstrainedTriangulation
            ``self``.

        Raises
        ------
        GeometryError
            A boundary is open (the domain side of a segment reaches infinity), sides are
            inconsistent, or a region seed lies outside the domain.
        """
        m = len(self.input_segments)
        sides = np.zeros(m, dtype=np.int8) if segment_sides is None else np.sign(
            np.asarray(segment_sides, dtype=np.int64).ravel()
        ).astype(np.int8)
        if sides.shape != (m,):
            raise InputError(f"segment_sides must have one entry per segment ({m}), got {sides.shape}")
        rows = self.constraints.seg_in[: self._np]
        # Hull pieces run with the inside on their left (see close_hull).
        pside = np.ones(self._np, dtype=np.int8)
        pside[rows >= 0] = sides[rows[rows >= 0]]
        ntri = int(self.state.meta[M_NTRI])
        stack = np.empty(ntri, dtype=np.int32)
        info = np.zeros(2, dtype=np.int64)
        code = classify_sides(self.state, self.constraints, pside, ntri, stack, info)
        if code != FLOOD_OK:
            self._raise_flood(code, info)
        self.constraints = self.constraints._replace(rarea=np.array([np.inf]))
        self._rmarker = np.zeros(1, dtype=np.int32)
        if holes is not None and len(holes):
            for t in self.locate(holes, "hole"):
                if t >= 0 and self.constraints.treg[t] >= 0:
                    self.constraints.treg[t] = -1
                    stack[0] = t
                    flood(stack, 1, -1, 0, self.state, self.constraints, pside, False)
        if regions is not None and len(regions):
            self._regions(regions, stack, pside)
        self.classified = True
        return self

    def _raise_flood(self, code: int, info) -> None:
        p, t = int(info[0]), int(info[1])
        tri = self.state.tri[3 * t : 3 * t + 3]
        where = fmt_point(self.state.pts[tri[tri >= 0]].mean(axis=0))
        if code == FLOOD_LEAK:
            raise GeometryError(
                f"the domain is not closed: its inside reaches the convex hull near {where} "
                "without crossing a boundary segment (an open loop, or segment_sides missing)"
            )
        if p < 0:
            raise GeometryError(f"segment sides are inconsistent near {where}")
        i = int(self.constraints.seg_in[p])
        a, b = self.constraints.seg[p]
        raise GeometryError(
            f"segment {i} from {fmt_point(self.state.pts[a])} to {fmt_point(self.state.pts[b])} has the domain on both "
            f"sides near {where}: loops are oriented inconsistently (outer ccw, holes cw) or cross"
        )

    def locate(self, xy, what: str = "query") -> np.ndarray:
        """Triangle slot (of :attr:`state`) holding each point, -1 outside the convex hull.

        Parameters
        ----------
        xy : (m, 2) array_like of float64
        what : str
            What the points are, for the error message.

        Returns
        -------
        (m,) int32
            Slots, flagged in ``constraints.treg`` (inside, exterior, region).
        """
        q = np.ascontiguousarray(np.asarray(xy, dtype=np.float64).reshape(-1, 2))
        if not np.isfinite(q).all():
            raise InputError(f"{what} points must be finite")
        return locate_points(self.state._replace(meta=self.state.meta.copy()), q)

    def inside_slots(self) -> np.ndarray:
        """(ntri,) bool over the kernel's triangle slots: finite and inside the domain.

        Slot order is the order of :meth:`triangles`; kernels that walk the flat arrays
        (``_tri``, ``_nbr``) use it to stay inside.
        """
        return self._mask(True)

    def _regions(self, regions, stack, pside) -> None:
        rows = [tuple(r) for r in regions]
        if any(len(r) not in (3, 4) for r in rows):
            raise InputError("regions must be rows (x, y, marker) or (x, y, marker, max_area)")
        xy = np.array([r[:2] for r in rows], dtype=np.float64)
        area = [np.inf if len(r) < 4 or r[3] is None or r[3] < 0 else float(r[3]) for r in rows]
        self._rmarker = np.array([0] + [int(r[2]) for r in rows], dtype=np.int32)
        self.constraints = self.constraints._replace(rarea=np.array([np.inf] + area))
        for i, t in enumerate(self.locate(xy, "region")):
            if t < 0 or self.constraints.treg[t] < 0:
                raise GeometryError(f"region {i} seed {fmt_point(xy[i])} lies outside the domain")
            self.constraints.treg[t] = i + 1
            stack[0] = t
            flood(stack, 1, i + 1, 0, self.state, self.constraints, pside, False)

    def close_hull(self, segment_id: int = -1) -> ConstrainedTriangulation:
        """Constrain every free convex-hull edge as a new segment piece with id ``segment_id``.

        Makes the convex hull the boundary of a point set (Triangle without ``-p``); such
        pieces get marker 1 in :meth:`to_mesh`.  Returns ``self``.
        """
        ntri = int(self.state.meta[M_NTRI])
        ghosts = np.flatnonzero(self.state.tri[2 : 3 * ntri : 3] == GHOST)
        h = 3 * ghosts + 2
        free = h[self.state.cons[h] == 0]
        if not len(free):
            return self
        k = len(free)
        if self._np + k > self.constraints.seg.shape[0]:
            self._grow_pieces(k + 16)
        g = free // 3
        piece = np.arange(self._np, self._np + k, dtype=np.int32)
        # Ghost (a, b, GHOST) holds hull edge a -> b with the outside on its left.
        self.constraints.seg[piece] = np.column_stack([self.state.tri[3 * g + 1], self.state.tri[3 * g]])
        self.constraints.seg_in[piece] = -1
        self._hull_id = int(segment_id)
        self.state.cons[free] = piece + 1
        twin = 3 * self.state.nbr[free]
        back = np.select(
            [self.state.nbr[twin] == g, self.state.nbr[twin + 1] == g], [twin, twin + 1], twin + 2
        )
        self.state.cons[back] = piece + 1
        self._np += k
        return self

    # ------------------------------------------------------------------ insertion
    def insert_point(self, x: float, y: float) -> int:
        """Insert one point (constrained Delaunay insertion); return its vertex id.

        A point on a subsegment splits it (both halves keep its id); a point equal to a
        vertex returns that vertex.  New triangles inherit the flag of the region they fill.
        """
        return int(self.insert_points(np.array([[x, y]], dtype=np.float64))[0])

    def insert_points(self, xy) -> np.ndarray:
        """Insert points in the given order; return the vertex of each, (k,) int32.

        Parameters
        ----------
        xy : (k, 2) array_like of float64
            Finite points (outside the convex hull they become exterior triangles).
        """
        q = np.ascontiguousarray(np.asarray(xy, dtype=np.float64).reshape(-1, 2))
        if not np.isfinite(q).all():
            raise InputError(f"point {int(np.flatnonzero(~np.isfinite(q).all(axis=1))[0])} is not finite")
        out = np.empty(len(q), dtype=np.int32)
        self.refresh_pieces()
        i = 0
        while i < len(q):
            batch = min(len(q) - i, 1 << 20)
            self.reserve(self.n_points + batch + 1, int(self.state.meta[M_NTRI]) + 2 * batch + 2)
            i, code = enc.insert_points(q, i, out, self.state, self.constraints)
            if code == enc.R_BROKEN:
                raise MeshingError(f"inserting point {i} at {fmt_point(q[i])} met an inconsistent cavity")
        return out

    def split_segment(self, a: int, b: int, xy=None) -> int:
        """Split subsegment ab (vertex ids) at ``xy``, by default at its split point.

        The default point is the midpoint, on the true curve when :attr:`curves` knows it
        (see :func:`meshwright.tri.ruppert.refine` for the rules); ``xy`` must lie on ab or,
        for a curved segment, inside one of its two triangles.  Returns the new vertex.
        """
        from meshwright.tri.ruppert import split_subsegment

        return split_subsegment(self, int(a), int(b), xy)

    # ------------------------------------------------------------------ outputs
    @property
    def points(self) -> np.ndarray:
        """(nv, 2) float64 vertex coordinates (read-only view)."""
        view = self.state.pts[: self.n_points]
        view.flags.writeable = False
        return view

    @property
    def n_points(self) -> int:
        """Number of vertices."""
        return int(self.state.meta[M_NV])

    def _mask(self, inside: bool) -> np.ndarray:
        ntri = int(self.state.meta[M_NTRI])
        finite = self.state.tri[2 : 3 * ntri : 3] != GHOST
        return finite & (self.constraints.treg[:ntri] >= 0) if inside else finite

    def triangles(self, inside: bool = True) -> np.ndarray:
        """(nt, 3) int32 counter-clockwise triangles: inside the domain, or all finite ones."""
        ntri = int(self.state.meta[M_NTRI])
        return self.state.tri[: 3 * ntri].reshape(ntri, 3)[self._mask(inside)]  # a copy: boolean index

    def neighbors(self, inside: bool = True) -> np.ndarray:
        """(nt, 3) int32: across the edge opposite vertex k, -1 where none is selected."""
        ntri = int(self.state.meta[M_NTRI])
        mask = self._mask(inside)
        newid = np.where(mask, np.cumsum(mask) - 1, -1).astype(np.int32)
        return newid[self.state.nbr[: 3 * ntri].reshape(ntri, 3)[mask]]

    def triangle_markers(self, inside: bool = True) -> np.ndarray:
        """(nt,) int32 region marker of each triangle (0 outside every region seed)."""
        ntri = int(self.state.meta[M_NTRI])
        mask = self._mask(inside)
        if len(self._rmarker) == 1:
            return np.zeros(int(np.count_nonzero(mask)), dtype=np.int32)
        return self._rmarker[np.maximum(self.constraints.treg[:ntri][mask], 0)]

    def _piece_ids(self) -> np.ndarray:
        rows = self.constraints.seg_in[: self._np]
        ids = np.full(self._np, self._hull_id, dtype=np.int32)
        ids[rows >= 0] = self.segment_ids[rows[rows >= 0]]
        return ids

    def _constrained(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Constrained half-edges: (h (k,), start (k,), end (k,)), both directions."""
        ntri = int(self.state.meta[M_NTRI])
        h = np.flatnonzero(self.state.cons[: 3 * ntri] != 0)
        base = h - h % 3
        return h, self.state.tri[base + (h % 3 + 1) % 3], self.state.tri[base + (h % 3 + 2) % 3]

    def segments(self) -> tuple[np.ndarray, np.ndarray]:
        """All subsegments, each once along its segment's direction.

        Returns
        -------
        edges : (k, 2) int32
        ids : (k,) int32
            Segment id of each.
        """
        h, u, w = self._constrained()
        p = self.state.cons[h] - 1
        d = self.state.pts[self.constraints.seg[p, 1]] - self.state.pts[self.constraints.seg[p, 0]]
        along = ((self.state.pts[w] - self.state.pts[u]) * d).sum(axis=1) > 0.0
        return np.column_stack([u, w])[along].astype(np.int32), self._piece_ids()[p[along]]

    def to_mesh(self, segment_markers=None, fill=None):
        """The inside triangles as a :class:`~meshwright.core.mesh.Mesh`.

        Parameters
        ----------
        segment_markers : (s,) array_like of int, optional
            Boundary marker of each segment id (``segment_markers[id]``); pieces added by
            :meth:`close_hull` get 1.  Default: 1 on boundary subsegments (domain on one
            side only), 0 on interior constraints.
        fill : tuple of ((n, 2) float64, (t, 3) int32), optional
            Another triangulation of the inside with the same subsegments, on this
            triangulation's vertices followed by new ones (an advancing front's output):
            its triangles replace the inside ones, each taking the region marker of the
            triangle holding its centroid.

        Returns
        -------
        Mesh
            Used vertices only (renumbered); ``"triangle"`` cells with region markers in
            ``cell_data["marker"]["triangle"]``; ``"line"`` cells for every subsegment that
            touches the domain (boundary ones counter-clockwise around it) with
            ``cell_data["marker"]["line"]``; ``point_data["marker"]``, the largest marker of
            the lines at each vertex (0 inside).
        """
        from meshwright.core.mesh import Mesh

        if fill is None:
            pts, tris, tmarks = self.state.pts[: self.n_points], self.triangles(True), self.triangle_markers(True)
        else:
            pts, tris = fill
            if len(self._rmarker) > 1:
                slots = self.locate(pts[tris].mean(axis=1), "centroid")
                tmarks = self._rmarker[np.maximum(self.constraints.treg[slots], 0)]
            else:
                tmarks = np.zeros(len(tris), dtype=np.int32)
        used = np.zeros(len(pts), dtype=bool)
        used[tris.ravel()] = True
        # Usually every vertex is used (refinement leaves none outside): no renumbering then.
        every = bool(used.all())
        newid = None if every else np.cumsum(used, dtype=np.int64).astype(np.int32) - 1
        h, u, w = self._constrained()
        tin = self.constraints.treg[h // 3] >= 0
        tin &= self.state.tri[3 * (h // 3) + 2] != GHOST
        n = self.state.nbr[h]
        nin = (self.constraints.treg[n] >= 0) & (self.state.tri[3 * n + 2] != GHOST)
        p = self.state.cons[h] - 1
        d = self.state.pts[self.constraints.seg[p, 1]] - self.state.pts[self.constraints.seg[p, 0]]
        along = ((self.state.pts[w] - self.state.pts[u]) * d).sum(axis=1) > 0.0
        # Boundary subsegments from their inside triangle (ccw around the domain), interior
        # ones once, along their segment.
        keep = (tin & ~nin) | (tin & nin & along)
        lines = np.column_stack([u, w])[keep]
        ids = self._piece_ids()[p[keep]]
        if segment_markers is None:
            marks = np.where(nin[keep], 0, 1).astype(np.int32)
        else:
            sm = np.asarray(segment_markers, dtype=np.int32).ravel()
            if len(ids) and ids.max() >= len(sm):
                raise InputError(f"segment_markers has {len(sm)} entries; segment id {int(ids.max())} needs more")
            marks = np.where(ids >= 0, sm[np.maximum(ids, 0)], 1).astype(np.int32)
        pmark = np.zeros(len(pts), dtype=np.int32)
        if len(lines):
            np.maximum.at(pmark, lines[:, 0], marks)
            np.maximum.at(pmark, lines[:, 1], marks)
        lines = lines.reshape(-1, 2)
        if every:
            return Mesh(
                pts.copy(), {"triangle": tris, "line": lines}, point_data={"marker": pmark},
                cell_data={"marker": {"triangle": tmarks, "line": marks}},
            )
        return Mesh(
            pts[used],
            {"triangle": newid[tris], "line": newid[lines]},
            point_data={"marker": pmark[used]},
            cell_data={"marker": {"triangle": tmarks, "line": marks}},
        )

    def __repr__(self) -> str:
        return (
            f"ConstrainedTriangulation({self.n_points} points, {len(self.triangles(True))} inside triangles, "
            f"{len(self.input_segments)} segments, classified={self.classified})"
        )


def _coerce_segments(segments, segment_ids, n: int) -> tuple[np.ndarray, np.ndarray]:
    seg = np.zeros((0, 2), dtype=np.int64) if segments is None else np.asarray(segments)
    if seg.size == 0:
        seg = seg.reshape(0, 2)
    if seg.ndim != 2 or seg.shape[1] != 2 or not np.issubdtype(seg.dtype, np.integer):
        raise InputError(f"segments must be an (m, 2) integer array, got shape {seg.shape} {seg.dtype}")
    bad = np.flatnonzero(((seg < 0) | (seg >= n)).any(axis=1))
    if len(bad):
        raise InputError(f"segment {bad[0]} {seg[bad[0]].tolist()} refers to a point outside [0, {n})")
    m = len(seg)
    ids = np.arange(m, dtype=np.int32) if segment_ids is None else np.asarray(segment_ids)
    if ids.shape != (m,) or not np.issubdtype(ids.dtype, np.integer):
        raise InputError(f"segment_ids must be (m,) integers with m = {m}, got {ids.shape} {ids.dtype}")
    if m and ids.min() < 0:
        raise InputError(f"segment_ids must be >= 0; segment {int(np.argmin(ids))} has {int(ids.min())}")
    return seg.astype(np.int32), ids.astype(np.int32)


def cdt_build(points, segments=None, segment_ids=None, seed=0, *, conforming=False, curves=None, duplicates="merge"):
    """Constrained (or conforming) Delaunay triangulation of points and segments.

    Parameters
    ----------
    points : (n, 2) array_like of float64
        At least three distinct, finite, not all collinear points.
    segments : (m, 2) array_like of int, optional
        Point index pairs that must appear as (unions of) edges.
    segment_ids : (m,) array_like of int, optional
        Non-negative id of each segment (default ``arange(m)``), carried by its subsegments.
    seed : int or numpy.random.Generator
        Randomness of the insertion order and of the walks.
    conforming : bool
        Split segments (at midpoints, on the true curve when ``curves`` knows it; at
        power-of-two shells next to small input angles) until every one of them is a union
        of Delaunay edges: the result is a true Delaunay triangulation.
    curves : SegmentCurves or callable, optional
        True curve of each input segment (see :class:`SegmentCurves`); a callable is called
        as ``curves(segment_id, xy_a, xy_b) -> xy`` for every split.
    duplicates : {"merge", "reject"}
        Coincident points: merged (see ``index_map``) or rejected.

    Returns
    -------
    ConstrainedTriangulation
        Not yet classified: every finite triangle counts as inside until :meth:`classify`.

    Raises
    ------
    InputError, DegenerateInputError, DuplicatePointError
        Malformed input (from :class:`~meshwright.tri.Triangulation` for the points).
    GeometryError
        Two segments intersect other than at a shared end point (both named), or a segment
        has zero length after merging coincident points.
    """
    tr = Triangulation(points, algorithm="bowyer", duplicates=duplicates, seed=seed)
    seg, ids = _coerce_segments(segments, segment_ids, len(tr.index_map))
    seg = tr.index_map[seg]
    zero = np.flatnonzero(seg[:, 0] == seg[:, 1])
    if len(zero):
        i = zero[0]
        raise GeometryError(f"segment {i} has zero length: both ends at {fmt_point(tr.points[seg[i, 0]])}")
    if curves is not None and not (isinstance(curves, SegmentCurves) or callable(curves)):
        raise InputError("curves must be a SegmentCurves or a callable (segment_id, xy_a, xy_b) -> xy")
    if isinstance(curves, SegmentCurves) and len(curves.kind) != len(seg):
        raise InputError(f"curves describe {len(curves.kind)} segments, but {len(seg)} were given")
    ct = ConstrainedTriangulation(tr, seg, ids, curves)
    if conforming:
        from meshwright.tri.ruppert import conform

        conform(ct)
    return ct
