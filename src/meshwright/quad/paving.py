r"""All-quad meshes by paving (chapter 18.5.2, Blacker and Stephenson 1991).

Source: T. D. Blacker and M. B. Stephenson, "Paving: a new approach to automated
quadrilateral mesh generation", Int. J. Numer. Meth. Eng. 32, 1991, as summarised in
section 18.5.2 of the reference chapter: rows of quadrilaterals laid one layer at a time
inward from the *paving boundaries* (the exterior one counter-clockwise, the interior ones
clockwise, so the unmeshed region is always on their left), every paving boundary kept
with an even number of nodes.  Node classes and thresholds follow the description of
FASTQ in ``design-notes-quads.md`` (section 3); nothing is copied from it.

Steps, as the chapter numbers them
----------------------------------
0. **Even boundaries.**  Every loop of the discretised domain gets an even node count
   (:func:`meshwright.quad.parity.make_loops_even`: one node on the longest segment, on
   the true curve); with ``fixed_boundary=True`` an odd loop raises
   :class:`~meshwright.quad.parity.ParityError` naming the loop.  Rows, tucks, wedges,
   seams, joints and closures change counts by even numbers: no triangle is needed.
1. **Row choice.**  Each paving node gets its interior angle (from the edge to the next
   node, counter-clockwise to the edge to the previous one) and a class: *row end*
   (angle below :data:`END_ANGLE`: the row turns there, one quad takes both of its
   sides), *side* (below :data:`CORNER_ANGLE`: one new node on the bisector), *corner*
   (below :data:`REVERSAL_ANGLE`: three new nodes, one extra quad) or *reversal* (five
   new nodes, two extra quads).  Two row ends are never neighbours; the row is the whole
   paving boundary, between its row ends.
2. **Closure.**  A paving boundary of six or fewer nodes is closed by a template (four
   nodes one quad; six nodes two quads or three around a centre node); one of up to
   :data:`SPLIT_MAX` nodes whose row fails is first cut by chords until every part takes
   a template (:mod:`meshwright.quad._paving_close`).
3. **Row generation.**  New nodes at the row depth (the size field at the node, kept
   within ``[1/2, 2]`` of the neighbouring edge lengths and averaged along the row):
   a side node's on its bisector, a corner's and a reversal's on spokes that split its
   angle evenly (the diagonal ones making rhombi), a row end's neighbours sharing one
   node on the end's bisector; quads between the old and the new nodes.  The new nodes
   relax :data:`ROW_RELAX` times along the row (tangentially: corners stay) and form the
   new paving boundary.
4. **Smoothing.**  After each row, the guarded Laplacian (:mod:`meshwright.quad.smoothing`)
   on the floating nodes of the two previous rows (after its first sweep only where
   nodes still move, :data:`ROW_SETTLE`).
5. **Seams.**  A floating paving node sharper than :data:`SEAM_ANGLE` is closed: its two
   neighbours merge at their midpoint if every quad around stays strictly convex, no
   front edge moves across another, the boundary's region only shrinks and the node
   merged away lies on no other paving boundary (a joint's node lies on two).
6. **Row adjustment.**  Along the row, the predicted new edge lengths are compared with
   the size field; their running surplus places *tucks* (a floating side node becomes a
   row end: two nodes fewer) and *wedges* (a floating side node becomes a corner: two
   more) whenever the surplus passes :data:`TUCK_AT` edges, at least :data:`ADJUST_GAP`
   nodes apart.
7. **Intersection.**  A row is accepted only if every new quad is strictly convex, no new
   edge meets a paving-boundary edge or another new edge, and no paving node lies in a
   new quad (exact ``orient2d``, :mod:`meshwright.quad._paving_kernel`); failing nodes
   get a shallower row (up to :data:`REPAIRS` times), then the paving boundary stops.
   After every round, paving nodes closer than :data:`CONNECT` times the size and facing
   each other are joined: two paving boundaries become one, one that meets itself splits
   in two even ones, and seams zip the narrow angles beside the joint (no joint or seam
   moves an edge across another).  At the end, stopped boundaries around stopped holes
   are bridged to them by chords; a thin or small region is closed by chords and
   templates.  *Simplification*: what is left (large regions between stopped fronts) is
   filled by the pairing method of 18.5.1 (pairing and shape enhancement of
   :mod:`meshwright.quad.pairing`) on the size field capped by the spacing of the void's
   own boundary nodes (rows keep their boundary's spacing while the field grows away from
   the walls; at the field's size the front fanned thin, unpairable triangles onto the
   stopped rows), as unconstrained paving (Staten et al. 2005) fills its voids after the
   rows; :class:`PavingReport` counts those quads.
8. **Cleanup.**  Triangles the pairing of a void could not pair are finished by chord
   refinement (:func:`meshwright.quad.chords.chord_split`, quads along the chords split);
   then :data:`FINAL_SMOOTH` sweeps of the guarded Laplacian (after the first, only
   where nodes still move: :data:`SETTLE`), and a max-min pattern
   search (:mod:`meshwright.quad.polish`) moves the free nodes of every quad with a corner sine
   below :data:`POLISH_BELOW` (all-quad fills only: it does not look at triangles), up to
   :data:`MEND_ROUNDS` passes more while a quad the chord split bent is still not convex.

*Interior segments, points and regions.*  A segment that meets a loop, or has many pieces,
is a *hard line* (FASTQ): the paving boundaries are the face cycles of the loops and those
pieces, each run once each way (:mod:`meshwright.quad._paving_hard`; no seam drops such a
slit, no closure leaves a flat corner), so rows grow from both sides; its nodes never move.
Short free segments (their few-node slit fronts fail closures) and interior points are
*obstacles* (:mod:`meshwright.quad._paving_obstacles`): a row whose quads come within the
size of one is refused (the boundary stops), no closure takes a region holding one, and the
void fill takes them as constraints and nodes.  A hard-line paving that loses a piece
(checked) is redone with obstacles; where nothing was paved, or that fails, the pairing
method's fill of the whole domain is the void fill.  Region markers: the mesher's flood
fill over the line cells.  Domains with none of these take the path above, node for node.

Invariants: every paving boundary has an even node count and the unmeshed region on its
left; every quad committed is strictly convex by exact ``orient2d``; no paving-boundary
edge crosses another.  Every loop is capped: rounds of rows (:data:`MAX_ROUNDS` plus the
domain's diagonal over its smallest spacing, or ``max_rounds``), repairs per row, seams
per row, joints per round, chords per closure and the number of points (``max_points``);
the rounds cap raises :class:`~meshwright.core.errors.MeshingError` naming the stuck
paving boundary (the loop it grew from, its length and first node), ``max_points`` names
itself.  The other caps end their step, and what is left goes to the void fill.

Implementation: a row is built by kernels over the boundary's node arrays, one call each
around the row's one call of the size field (:mod:`meshwright.quad._paving_row`: ``row_prepare``:
angles, classes, depth and the provisional new edges; ``adjust_row``; ``row_nodes``;
``row_finish``: the new boundary and its relaxation); a row's whole step-7 check (one
call per row, bounded by the row's box), crossing, containment, joint and cleanup
searches are Numba kernels too (:mod:`meshwright.quad._paving_kernel`); closure, joining
and cleanup pieces live in :mod:`meshwright.quad._paving_close`.

Array layout: points (n, 2) float64; quads (q, 4) int32 counter-clockwise; a paving
boundary is an (k,) int64 array of node ids with the unmeshed region on its left.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from meshwright.core.errors import GeometryError, InputError, MeshingError, fmt_point
from meshwright.core.validate_input import check_count, check_flag, check_seed
from meshwright.geometry.domain import Domain
from meshwright.quad import _paving_kernel as pk
from meshwright.quad import _paving_row as pr
from meshwright.quad._paving_close import (
    LONG_LOOP,
    area_kept,
    boundary_loops,
    bridge,
    clear_after_merge,
    close_loop,
    closure_quads,
    consistent,
    convex,
    despike,
    edges_of,
    encloses,
    facing_order,
    fill_voids,
    front_slots,
    min_sine,
    shift_next,
    signed_area,
)
from meshwright.quad._paving_finish import Finish, fill_by_pairing, finish
from meshwright.quad._paving_hard import FLAT, attached_pieces, face_cycles, pieces_two_sided
from meshwright.quad._paving_obstacles import Obstacles
from meshwright.quad.parity import make_loops_even
from meshwright.quad.smoothing import smooth_cells
from meshwright.sizing.field import as_size_field

__all__ = [
    "CONNECT",
    "CORNER_ANGLE",
    "END_ANGLE",
    "FINAL_SMOOTH",
    "MAX_ROUNDS",
    "REVERSAL_ANGLE",
    "SEAM_ANGLE",
    "SETTLE",
    "PavingReport",
    "closure_quads",
    "node_classes",
    "pave_domain",
    "paving_fill",
]

END_ANGLE = 135.0  # degrees: a paving node below this is a row end
CORNER_ANGLE = 225.0  # ... at or above this a corner (three new nodes)
REVERSAL_ANGLE = 315.0  # ... at or above this a reversal (five new nodes)
SEAM_ANGLE = 40.0  # a floating paving node sharper than this is seamed
TUCK_MAX_ANGLE = 179.5  # tucks only at side nodes flatter than this ...
WEDGE_MIN_ANGLE = 185.0  # ... wedges only at side nodes wider than this
ROW_RELAX = 2  # Jacobi sweeps of the new row's nodes along the row
ADJUST_GAP = 4  # nodes between two tucks or wedges of one row, at least
TUCK_AT = 1.6  # edges of running surplus (or shortfall) that place a wedge (or a tuck)
CONNECT = 1.0  # facing paving nodes closer than this times the size are joined
REPAIRS = 4  # retries of a refused row with the depth lowered around its failing nodes
REPAIR_SCALE = 0.7  # ... by this factor each time
THIN = 0.75  # a stopped region thinner than this (area / perimeter / size) is closed by chords
SPLIT_MAX = 80  # paving boundaries up to this many nodes may be closed by chords
MAX_ROUNDS = 64  # rounds of rows beyond the bound from the domain's extent
POLISH_BELOW = 0.8  # quads with a corner sine below this (about 53 degrees) get the max-min cleanup ...
POLISH_ROUNDS = 8  # ... this many passes
MEND_ROUNDS = 32  # ... and up to this many more while a quad is still not convex
FINAL_SMOOTH = 12  # guarded Laplacian sweeps over all floating nodes at the end
ROW_SMOOTH = 4  # ... over the two previous rows after each row
SETTLE = 1e-2  # at the end: after the first sweep, only where a node moved more than this times an edge
ROW_SETTLE = 3e-2  # ... after each row (its nodes are smoothed again after the next row and at the end)


class PavingReport(NamedTuple):
    """What the paving did.

    Attributes
    ----------
    nodes_added : tuple of int
        Loops that received one node to make their count even.
    rows : int
        Rows accepted (all paving boundaries together).
    tucks, wedges, seams, joints, closures : int
        Row adjustments, seams, joints of meeting paving boundaries and closures applied.
    paved : int
        Quads laid by rows, seams and closures.
    voids, filled : int
        Stopped paving boundaries sent to the void fill; quads of the fill (pairing).
    split : bool
        Whether chord refinement finished left-over triangles.
    triangles_left : int
        Triangles in the returned fill (0 when ``all_quad``).
    """

    nodes_added: tuple
    rows: int
    tucks: int
    wedges: int
    seams: int
    joints: int
    closures: int
    paved: int
    voids: int
    filled: int
    split: bool
    triangles_left: int


def _loop_name(li: int) -> str:
    return "outer loop (loop 0)" if li == 0 else f"loop {li}"


def node_classes(angles_deg) -> np.ndarray:
    """New nodes per paving node from its interior angle (step 1).

    Parameters
    ----------
    angles_deg : (k,) float64
        Interior angles in degrees, along a paving boundary.

    Returns
    -------
    (k,) int64
        0 row end, 1 side, 3 corner, 5 reversal; no two row ends are neighbours (the
        sharper one keeps the class).
    """
    return pr.row_classes(np.ascontiguousarray(angles_deg, dtype=np.float64), END_ANGLE, CORNER_ANGLE, REVERSAL_ANGLE)


class _Paver:
    """The paving state: points, quads by round, paving boundaries, counters."""

    def __init__(self, xy, field, cap):
        self.pts = np.array(xy, dtype=np.float64, order="C")
        self.n = len(xy)
        self.n_fixed = len(xy)
        self.field = field
        self.cap = cap
        self.round_of = np.full(len(xy), -1, dtype=np.int64)
        # The size field at each node, NaN until asked and again once the node moves: a
        # graded field costs a search per point, and every row and joint asks it at the
        # paving nodes, which stay where they are until they leave the front.
        self.h = np.full(len(xy), np.nan)
        self.quads: list[np.ndarray] = []
        # Bounds on each block's node ids (kept covering them through merges), so that a
        # merge reads only the blocks that may hold its two nodes.
        self.quad_lo: list[int] = []
        self.quad_hi: list[int] = []
        self.quad_round: list[int] = []
        self.tucks = self.wedges = self.seams = self.closures = self.rows = 0
        self.pending = (0, 0)
        self.joints = 0
        # Parts of partly closed paving boundaries, left to the void fill.
        self.open_parts: list[np.ndarray] = []
        # Obstacles (None without any) and the node bound of hard lines' spikes (despike).
        self.obs, self.keep = None, 0

    def _reserve(self, k: int) -> None:
        """Room for ``k`` nodes beyond ``self.n`` (the arrays doubled when full)."""
        if self.n + k > len(self.pts):
            grow = np.empty((max(2 * len(self.pts), self.n + k), 2))
            grow[: self.n] = self.pts[: self.n]
            self.pts = grow
            self.round_of = np.concatenate([self.round_of, np.full(len(grow) - len(self.round_of), -1)])
            self.h = np.concatenate([self.h, np.full(len(grow) - len(self.h), np.nan)])

    def trial_points(self, p: np.ndarray) -> np.ndarray:
        """The committed nodes followed by candidate nodes ``p`` (not committed): a view
        of the point buffer, so that checking a row copies no old node."""
        self._reserve(len(p))
        self.pts[self.n : self.n + len(p)] = p
        return self.pts[: self.n + len(p)]

    def add_points(self, p: np.ndarray, rnd: int) -> np.ndarray:
        k = len(p)
        if self.n + k > self.cap:
            raise MeshingError(f"paving needs more than max_points = {self.cap} nodes")
        self._reserve(k)
        self.pts[self.n : self.n + k] = p
        self.h[self.n : self.n + k] = np.nan
        self.round_of[self.n : self.n + k] = rnd
        ids = np.arange(self.n, self.n + k, dtype=np.int64)
        self.n += k
        return ids

    @property
    def xy(self) -> np.ndarray:
        return self.pts[: self.n]

    def size_at(self, ids: np.ndarray) -> np.ndarray:
        """The size field at nodes ``ids`` (evaluated only where not known yet)."""
        h = self.h[ids]
        miss = np.isnan(h)
        if miss.any():
            h[miss] = self.field(self.pts[ids[miss]])
            self.h[ids[miss]] = h[miss]
        return h

    def add_quads(self, q: np.ndarray, rnd: int) -> None:
        blk = np.asarray(q, dtype=np.int64).reshape(-1, 4)
        self.quads.append(blk)
        self.quad_lo.append(int(blk.min()) if len(blk) else -1)
        self.quad_hi.append(int(blk.max()) if len(blk) else -1)
        self.quad_round.append(rnd)

    # -- step 1, 3, 6: one row --------------------------------------------------------
    def build_row(self, f: np.ndarray, scale: np.ndarray, calm_only: np.ndarray, memo: dict | None = None):
        """Candidate row on paving boundary ``f`` with the row depth times ``scale`` and no
        tuck or wedge where ``calm_only``: (new node coordinates, quads with new nodes
        numbered from ``self.n``, new paving boundary, depth, the paving node each new
        node grew from); None if it degenerates.  Three kernels around the one call of
        the size field at the provisional new edges
        (:func:`~meshwright.quad._paving_row.row_prepare`, ``adjust_row``,
        ``row_nodes``, ``row_finish``).  ``memo`` (a dict kept over the repairs of one
        row) holds the last attempt's edge midpoints and their sizes: a repair moves the
        midpoints beside the failing nodes only (each depends on its edge's two nodes),
        and only the moved ones ask the size field again."""
        p = self.pts[f]
        ang, deg, m, depth, th0, mid, plen = pr.row_prepare(
            p, self.size_at(f), scale, END_ANGLE, CORNER_ANGLE, REVERSAL_ANGLE
        )
        if memo is not None and "mid" in memo:
            h_mid = memo["h"].copy()
            moved = (mid != memo["mid"]).any(axis=1)
            if moved.any():
                h_mid[moved] = self.field(mid[moved])
        else:
            h_mid = self.field(mid)
        if memo is not None:
            memo["mid"], memo["h"] = mid, h_mid
        # Step 6: tucks and wedges from the running surplus of predicted edge lengths.
        tucks, wedges = pk.adjust_row(
            m, plen / h_mid, calm_only, f >= self.n_fixed, deg, ADJUST_GAP, TUCK_AT, TUCK_MAX_ANGLE,
            WEDGE_MIN_ANGLE,
        )
        self.pending = (tucks, wedges)
        ok, new_xy, q, front, owner = pk.row_nodes(p, f, ang, m, depth, th0, self.n)
        if not ok:
            return None
        # Row smoothing in row_finish: the new nodes relax along the row, which spreads
        # the long and short edges a tuck or wedge leaves over their neighbours.
        front = pr.row_finish(new_xy, q, front, self.n, ROW_RELAX)
        if front is None:
            return None
        return new_xy, q, front, depth, owner

    # -- step 7: checks -----------------------------------------------------------------
    def row_with_repairs(self, f, others):
        """A valid row on ``f`` (steps 1, 3, 6, 7; the check is
        :func:`~meshwright.quad._paving_kernel.check_row`, the other boundaries' edges and
        nodes gathered once), the depth lowered and the adjustments dropped around failing
        nodes up to :data:`REPAIRS` times: (new coordinates, quads, new front) or None."""
        n = len(f)
        scale = np.ones(n)
        calm_only = np.zeros(n, dtype=bool)
        memo: dict = {}
        edges = None
        for _ in range(REPAIRS + 1):
            row = self.build_row(f, scale, calm_only, memo)
            if row is None:
                return None
            new_xy, quads, front, _, owner = row
            if edges is None:
                edges = (*edges_of(others + [f]), np.concatenate(others + [f]) if others else f)
            bad = np.flatnonzero(pk.check_row(self.trial_points(new_xy), f, quads, owner, np.int64(self.n), *edges))
            if not len(bad):
                if self.obs is not None and self.obs.row_refused(self.trial_points(new_xy), quads, self.h, self.n):
                    return None  # no shallower row creeping up to it: the boundary stops
                self.tucks += self.pending[0]
                self.wedges += self.pending[1]
                return new_xy, quads, front
            near = (bad[:, None] + np.arange(-1, 2)[None, :]).ravel() % n
            scale[near] *= REPAIR_SCALE
            calm_only[near] = True
        return None

    # -- step 5: seams --------------------------------------------------------------------
    def seam(self, front: np.ndarray, others, cap: int) -> np.ndarray:
        """Close floating paving nodes sharper than :data:`SEAM_ANGLE` (at most ``cap``);
        no seam moves a paving-boundary edge across another (``others``: the other
        paving boundaries)."""
        front = despike(front, self.keep)
        # A joint leaves its node on two paving boundaries: merged away by a seam of one,
        # it would stay on the other, which then closes over a node no quad around it has
        # any more (a tangled four-node void on a random star).
        shared = np.concatenate(others) if others else np.zeros(0, dtype=np.int64)
        for _ in range(cap):
            if len(front) <= 2:
                return front
            done = False
            for i in pr.sharp_nodes(self.pts, front, self.n_fixed, SEAM_ANGLE).tolist():
                k = len(front)
                a, b = int(front[i - 1]), int(front[(i + 1) % k])
                if a < self.n_fixed or b < self.n_fixed or (shared == b).any():
                    continue
                at = 0.5 * (self.pts[a] + self.pts[b])
                trial = np.delete(front, [i, (i + 1) % k])
                trial = despike(np.where(trial == b, a, trial), self.keep)
                if (
                    consistent([trial] + others)
                    and area_kept(self.xy, front, trial, a, b, at)
                    and clear_after_merge(self.xy, [front] + others, a, b, at)
                    and self._merge(a, b, at)
                ):
                    front = trial
                    self.seams += 1
                    done = True
                    break
            if not done:
                return front
        return front

    def _merge(self, a: int, b: int, at=None) -> bool:
        """Merge node b into a, at ``at`` (default their midpoint), if every quad around
        them stays strictly convex (exact); the paving boundaries are the caller's."""
        blocks = [k for k, (lo, hi) in enumerate(zip(self.quad_lo, self.quad_hi)) if lo <= a <= hi or lo <= b <= hi]
        allq = np.concatenate([self.quads[k] for k in blocks]) if blocks else np.zeros((0, 4), dtype=np.int64)
        touch = np.flatnonzero(((allq == a) | (allq == b)).any(axis=1))
        q = allq[touch].copy()
        q[q == b] = a
        old = self.pts[a].copy()
        self.pts[a] = 0.5 * (self.pts[a] + self.pts[b]) if at is None else at
        self.h[a] = np.nan
        ok = all(len(set(r)) == 4 for r in q.tolist()) and convex(self.xy, q).all()
        if not ok:
            self.pts[a] = old
            return False
        for k in blocks:
            blk = self.quads[k]
            blk[blk == b] = a
            self.quad_lo[k] = min(self.quad_lo[k], a)
            self.quad_hi[k] = max(self.quad_hi[k], a)
        return True

    # -- step 7: paving boundaries that meet -----------------------------------------------
    def connect(self, fronts: list[np.ndarray], cap: int) -> list[np.ndarray]:
        """Join paving nodes that came closer than :data:`CONNECT` times the size while
        facing each other: the two merge (at their midpoint; a permanent node stays), two
        paving boundaries become one (the merged node on it twice) and one boundary that
        meets itself splits into two even ones.  Seams then zip the narrow angles beside
        the joint.  At most ``cap`` joints; returns the new list of boundaries."""
        tried: set[tuple[int, int]] = set()
        attempts = 0
        cand = None
        while attempts < cap and fronts:
            if cand is None:
                # The slots and their candidate pairs, searched again only after a joint
                # (a refused one changes nothing: every check works on copies).
                ids, fid, pos, nrm = front_slots(self.pts, fronts)
                order_u, order_v = facing_order(
                    ids, fid, pos, self.pts[ids], nrm, CONNECT * self.size_at(ids), [len(f) for f in fronts]
                )
                cand = iter(zip(order_u.tolist(), order_v.tolist()))
            pair = next((uv for uv in cand if (int(ids[uv[0]]), int(ids[uv[1]])) not in tried), None)
            if pair is None:
                break
            attempts += 1
            u, v = pair
            a, b = int(ids[u]), int(ids[v])
            tried.add((a, b))
            if b < self.n_fixed:
                a, b, u, v = b, a, v, u
            if b < self.n_fixed:
                continue
            at = self.pts[a].copy() if a < self.n_fixed else 0.5 * (self.pts[a] + self.pts[b])
            fa, fb, i, j = int(fid[u]), int(fid[v]), int(pos[u]), int(pos[v])
            A, B = fronts[fa], fronts[fb]
            if fa != fb:
                joined = np.concatenate([A[:i], [a], B[j + 1 :], B[:j], [a], A[i + 1 :]])
                new = [f for k, f in enumerate(fronts) if k not in (fa, fb)] + [joined]
            else:
                i, j = min(i, j), max(i, j)
                A = np.where(A == b, a, A)
                one = np.concatenate([[a], A[i + 1 : j]])
                two = np.concatenate([[a], A[j + 1 :], A[:i]])
                # Both parts keep a positive area: tested before the new boundaries are
                # built, it turns away most candidates (37 of 39 on the three-element).
                if min(signed_area(self.pts[one]), signed_area(self.pts[two])) <= 0.0:
                    continue
                new = [f for k, f in enumerate(fronts) if k != fa] + [g for g in (one, two) if len(g) > 2]
            new = [np.where(f == b, a, f) for f in new]
            sa, sb = edges_of(fronts)
            gap = np.array([a]), np.array([b])
            if (
                not consistent(new)
                or pk.row_crossings(self.xy, gap[0], gap[1], sa, sb).any()
                or not clear_after_merge(self.xy, fronts, a, b, at)
                or not self._merge(a, b, at)
            ):
                continue
            fronts = new
            self.joints += 1
            cand = None
        return fronts

    # -- step 2: closure of small paving boundaries ---------------------------------------
    def close(self, f, others, rnd, limit=SPLIT_MAX) -> bool:
        """Close paving boundary ``f`` (step 2) by chords and templates
        (:func:`~meshwright.quad._paving_close.close_loop`) when it has at most ``limit``
        nodes and no other paving boundary inside; commits and returns True on success,
        changes nothing otherwise.  A long boundary may close in part: the parts left
        open join :attr:`open_parts` for the void fill (a sliver folded into layers
        leaves a few small parts that no chord or template closes; the void fill of the
        whole boundary cost a minute)."""
        if len(f) > limit or encloses(self.pts, f, others):
            return False
        if self.obs is not None and self.obs.inside(self.xy, f):
            return False
        oa, ob = edges_of(others)
        sizes = self.size_at(np.asarray(f, dtype=np.int64)) if len(f) > LONG_LOOP else None
        done = close_loop(self.xy, f, self.field, oa, ob, 4 * len(f), partial=True, sizes=sizes)
        if done is None:
            return False
        extra, quads, open_parts = done
        if self.keep and len(quads) and min_sine(np.vstack([self.xy, extra]), quads).min() < FLAT:
            return False  # a template on nodes of straight hard lines: the void fill does better
        if len(extra):
            self.add_points(extra, rnd)
        self.add_quads(quads, rnd)
        self.open_parts += open_parts
        self.closures += 1
        return True

    def join_and_close(self, loops, rnd):
        """Step 7 on the stopped paving boundaries: each one around holes' boundaries is
        joined to them by chords (:func:`~meshwright.quad._paving_close.bridge`), and a
        region that is thin (area below :data:`THIN` times its perimeter times the size)
        or small (at most :data:`SPLIT_MAX` nodes) is closed by chords and templates.
        Returns the boundaries left for the void fill."""
        area = [signed_area(self.pts[f]) for f in loops]
        outer = [i for i, a in enumerate(area) if a > 0.0]
        owner = {}
        for h in (i for i, a in enumerate(area) if a <= 0.0):
            around = [i for i in outer if encloses(self.pts, loops[i], [loops[h]])]
            if around:
                owner[h] = min(around, key=lambda i: area[i])
        left = [loops[h] for h, a in enumerate(area) if a <= 0.0 and h not in owner]
        for i in outer:
            holes = [loops[h] for h, o in owner.items() if o == i]
            region = [loops[i]] + holes
            if holes and not self._may_close(region):
                left += region
                continue
            rest = [g for g in loops if not any(g is r for r in region)]
            joined = loops[i]
            for h in holes:
                oa, ob = edges_of([joined] + [g for g in holes] + rest)
                res = bridge(self.xy, joined, h, self.field, oa, ob)
                if res is None:
                    joined = None
                    break
                pts, joined = res
                if len(pts):
                    self.add_points(pts, rnd)
            if joined is not None:
                p = self.pts[joined]
                perimeter = float(np.hypot(*(shift_next(p) - p).T).sum())
                size = float(np.mean(self.size_at(np.asarray(joined, dtype=np.int64))))
                thin = signed_area(p) < THIN * perimeter * size
                if (thin or len(joined) <= SPLIT_MAX) and self.close(joined, rest, rnd, limit=len(joined)):
                    continue
            left += region
        return left

    def thin(self, f) -> bool:
        """Whether the region left of paving boundary ``f`` is thin: its area positive
        (a boundary around its region, not a hole's) and below :data:`THIN` times its
        perimeter times the mean size along it (a strip thinner than about one and a
        half sizes).  The mean is by length (each edge's mean end size times its
        length): by node it was the size of the finely spaced stretches, and a sliver
        whose stretches differ in spacing passed as thick, then spent minutes in rows."""
        p = self.pts[f]
        area = signed_area(p)
        if area <= 0.0:
            return False
        h = self.size_at(f)
        along = np.hypot(*(shift_next(p) - p).T) * (h + shift_next(h))
        return area < THIN * 0.5 * float(along.sum())

    def _may_close(self, region) -> bool:
        """Whether the region bounded by ``region`` (a paving boundary and the holes'
        inside it) may pass :meth:`join_and_close`'s test once bridged: the bridges' nodes
        (two more per hole at least) within :data:`SPLIT_MAX`, or thin with every chord
        as long as the outer boundary's diagonal.  The bridges' chords, searched over
        every pair of nodes, are built only then: the three-element airfoil's void
        (its far field around the stopped rows) never closes, and its bridge cost 6 %
        of the paving."""
        if sum(len(f) for f in region) + 2 * (len(region) - 1) <= SPLIT_MAX:
            return True
        pts = [self.pts[f] for f in region]
        perimeter = sum(float(np.hypot(*(shift_next(p) - p).T).sum()) for p in pts)
        perimeter += 2.0 * (len(region) - 1) * float(np.hypot(*np.ptp(pts[0], axis=0)))
        size = float(np.mean(self.size_at(np.concatenate(region).astype(np.int64, copy=False))))
        return sum(signed_area(p) for p in pts) < THIN * perimeter * size

    # -- step 4: smoothing -----------------------------------------------------------------
    def smooth_recent(self, rnd: int, on_front: np.ndarray) -> None:
        """Guarded Laplacian on the floating nodes of rounds ``rnd - 1`` and ``rnd - 2``."""
        sel = [q for q, r in zip(self.quads, self.quad_round) if r >= rnd - 3]
        if not sel:
            return
        used, local, fixed = pr.recent_nodes(np.concatenate(sel), self.n, self.round_of, on_front, self.n_fixed, rnd)
        if fixed.all():
            return
        self.pts[used] = smooth_cells(self.pts[used], local, np.zeros((0, 3), np.int64), fixed, ROW_SMOOTH, ROW_SETTLE)
        self.h[used[~fixed]] = np.nan


def pave_domain(domain: Domain, field, *, all_quad: bool = True, fixed_boundary: bool = False, seed=0,
                max_points: int | None = None, max_rounds: int | None = None):
    """All-quad fill of ``domain`` by paving (module docstring).

    Parameters
    ----------
    domain : Domain
        Validated; interior segments and points are honoured (module docstring).
    field : number, callable, SizeField or BackgroundGrid
        Size field (the row depth and spacing); isotropic (a stretched background grid
        is refused).
    all_quad : bool
        Finish left-over triangles of the void fill by chord refinement.
    fixed_boundary : bool
        Keep the discretisation's boundary nodes: an odd loop is an error.
    seed : int or numpy.random.Generator
        Randomness of the void fill.
    max_points : int, optional
        Cap on nodes.
    max_rounds : int, optional
        Cap on rounds of rows; default :data:`MAX_ROUNDS` plus the domain's diagonal over
        its smallest boundary spacing.

    Returns
    -------
    QuadFill
    PavingReport

    Raises
    ------
    InputError
        An argument of the wrong type or range (named).
    ParityError
        An odd loop with ``fixed_boundary=True`` (the loop named).
    MeshingError
        A cap was hit (the stuck paving boundary named), or the result failed its own
        exact check.
    """
    if not isinstance(domain, Domain):
        raise InputError(f"domain must be a meshwright.geometry.Domain, got {type(domain).__name__}")
    field = as_size_field(field)
    stretch = np.asarray(getattr(field, "stretch", 1.0), dtype=np.float64)
    if (stretch > 1.0).any():
        raise InputError(
            f"paving lays isotropic rows: a background grid stretched by up to {float(stretch.max()):g} is not "
            "honoured; give an isotropic size, or use method='pairing' for stretched quads"
        )
    all_quad = check_flag(all_quad, "all_quad")
    fixed_boundary = check_flag(fixed_boundary, "fixed_boundary")
    seed = check_seed(seed)
    cap = np.iinfo(np.int32).max if max_points is None else check_count(max_points, "max_points", 4)
    if max_rounds is not None:
        check_count(max_rounds, "max_rounds", 1)
    disc, added = make_loops_even(domain, domain.discretize(field), fixed_boundary)
    loops = boundary_loops(domain, disc)
    if len(disc.points) > cap:
        raise MeshingError(f"the boundary alone has {len(disc.points)} nodes, above max_points = {cap}")
    x0, y0, x1, y1 = domain.bbox
    seg_len = np.hypot(*(disc.points[disc.segments[:, 1]] - disc.points[disc.segments[:, 0]]).T)
    if max_rounds is None:
        rounds = MAX_ROUNDS + int(np.hypot(x1 - x0, y1 - y0) / max(float(seg_len.min()), 1e-300))
    else:
        rounds = check_count(max_rounds, "max_rounds", 1)
    names = [_loop_name(i) for i in range(len(loops))]
    obs = Obstacles.of(domain, disc)
    job = (domain, disc, field, cap, rounds, seed, all_quad)
    if obs is None:
        out = _pave(*job, loops, names, None, None)
        return out[0], PavingReport(added, *out[1])
    hard = attached_pieces(loops, obs.seg_a, obs.seg_b)
    tries = [(loops, names, obs)]
    if hard.any():
        fronts, src = face_cycles(disc.points, loops, obs.seg_a[hard], obs.seg_b[hard])
        tries.insert(0, (fronts, [names[i] if i >= 0 else "a segment cycle" for i in src], obs.only(~hard)))
    out = None
    for starts, named, rows_obs in tries:
        try:
            out = _pave(*job, starts, named, rows_obs, obs)
            break
        except MeshingError:
            pass  # hard lines: a piece lost; obstacles: a quad bent (size jumps): the next way
    out = fill_by_pairing(out, domain, field, all_quad, fixed_boundary, seed, cap)
    return out[0], PavingReport(added, *out[1])


def _pave(domain, disc, field, cap, rounds, seed, all_quad, starts, names, obs, all_obs):
    """Steps 1-8 of :func:`pave_domain` from paving boundaries ``starts`` (``names``), rows
    kept off ``obs``, every piece and point of ``all_obs`` checked on the result: (QuadFill,
    the counts of :class:`PavingReport` after ``nodes_added``)."""
    pv = _Paver(disc.points, field, cap)
    pv.obs = obs
    pv.keep = 0 if all_obs is None else pv.n_fixed
    active = list(zip(starts, names))
    stopped: list[np.ndarray] = []
    for rnd in range(rounds + 1):
        if not active:
            break
        if rnd == rounds:
            f, name = active[0]
            raise MeshingError(
                f"paving: the paving boundary grown from {name} ({len(f)} nodes, first at "
                f"{fmt_point(pv.pts[f[0]])}) is still open after {rounds} rounds of rows"
            )
        nxt = []
        for idx in range(len(active)):
            f, name = active[idx]
            others = [g for g, _ in active[idx + 1 :]] + [g for g, _ in nxt] + stopped
            if len(f) <= 2:
                continue
            if len(f) <= 6:
                if not pv.close(f, others, rnd):
                    stopped.append(f)
                continue
            if rnd == 0 and pv.thin(f):
                # No row fits a domain thinner than about one and a half sizes: the
                # rows' repairs and checks were all wasted (seconds to minutes on the
                # stress harness's slivers); chords close it at once.  Later paving
                # boundaries keep their rows (a thin one stops and is closed at the end).
                if not pv.close(f, others, rnd, limit=len(f)):
                    stopped.append(f)
                continue
            row = pv.row_with_repairs(f, others)
            if row is None:
                if not pv.close(f, others, rnd):
                    stopped.append(f)
                continue
            new_xy, quads, front = row
            pv.add_points(new_xy, rnd)
            pv.add_quads(quads, rnd)
            pv.rows += 1
            front = pv.seam(front, others, len(front))
            if len(front) <= 2:
                continue
            nxt.append((front, name))
        fronts = pv.connect([g for g, _ in nxt] + stopped, 4 * (len(nxt) + len(stopped)) + 64)
        still = {id(g) for g in stopped}
        stopped = [g for g in fronts if id(g) in still]
        named = {id(g): name for g, name in nxt}
        active = []
        for k, g in enumerate(fronts):
            if id(g) not in still:
                g2 = pv.seam(g, fronts[:k] + fronts[k + 1 :], len(g))
                fronts[k] = g2
                active.append((g2, named.get(id(g), "a joined paving boundary")))
        active = [(g, name) for g, name in active if len(g) > 2]
        on_front = np.zeros(pv.n, dtype=bool)
        for g in [g for g, _ in active] + stopped:
            on_front[g] = True
        pv.smooth_recent(rnd, on_front)
    voids = pv.join_and_close([f for f in stopped if len(f) > 2], rounds) + pv.open_parts
    xy = pv.xy.copy()
    quads = np.concatenate(pv.quads) if pv.quads else np.zeros((0, 4), dtype=np.int64)
    paved = len(quads)
    if obs is not None and paved and obs.covered(xy, quads):
        # A seam or joint moved a paved quad onto an obstacle: all to the void fill.
        quads, paved, voids = quads[:0], 0, list(starts)
    tris = np.zeros((0, 3), dtype=np.int64)
    filled = 0
    if voids:
        try:
            xy, fq, tris = fill_voids(xy, voids, field, seed, obs)
        except GeometryError as e:
            # The stopped paving boundaries are this method's own state, not the user's
            # geometry: a failure to triangulate them is a meshing failure.
            raise MeshingError(
                f"paving: the region left between {len(voids)} stopped paving boundaries could not be filled ({e}); "
                "please report it with the domain and size"
            ) from e
        filled = len(fq)
        quads = np.concatenate([quads, fq])
    if all_obs is not None and not pieces_two_sided(quads, tris, all_obs.seg_a, all_obs.seg_b):
        raise MeshingError("paving lost an interior segment piece (not a side of a cell each way)")
    points = np.zeros(0, dtype=np.int64) if all_obs is None else all_obs.points
    rules = Finish(FINAL_SMOOTH, SETTLE, POLISH_BELOW, POLISH_ROUNDS, MEND_ROUNDS)
    fill, split = finish(xy, quads, tris, pv.n_fixed, disc, domain, cap, all_quad, points, rules)
    counts = (pv.rows, pv.tucks, pv.wedges, pv.seams, pv.joints, pv.closures, paved, len(voids), filled, split,
              len(fill.triangles))
    return fill, counts


def paving_fill(job):
    """``QUAD_METHODS["paving"].build``: :func:`pave_domain` on a checked :class:`QuadJob`."""
    return pave_domain(job.domain, job.field, all_quad=job.all_quad, seed=job.seed, max_points=job.max_points)[0]
