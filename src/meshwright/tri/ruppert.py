r"""Guaranteed-quality Delaunay refinement (Ruppert / Chew with off-centres) of a CDT.

Sources: J. Ruppert, "A Delaunay refinement algorithm for quality 2-dimensional mesh
generation", J. Algorithms 18(3):548-585, 1995; J. R. Shewchuk, "Delaunay refinement
algorithms for triangular mesh generation", Comput. Geom. 22:21-74, 2002 (concentric
shells and the rule that leaves triangles at small input angles alone, both as implemented
in Triangle); A. Üngör, "Off-centers: a new type of Steiner points for computing
size-optimal quality-guaranteed Delaunay triangulations", LATIN 2004 (with Triangle's
constant 0.475 for the off-centre distance).

Algorithm (:func:`refine_loop`, one Numba loop over flat arrays)
--------------------------------------------------------------
1. Queue every encroached subsegment (its diametral circle holds the apex of an inside
   triangle, exact test) and every bad inside triangle: smallest angle below ``min_angle``,
   or area above ``max_area`` / its region's maximum / the area of the equilateral triangle
   of side ``h`` (the size field at its circumcentre).
2. While subsegments are queued, split them: at the midpoint (on the true curve), or at a
   power-of-two distance from an acute input vertex (concentric shells)::

        a *========m========* b          a *====*====*====* b
          \       /|\       /    split       \   /|\  |  /|   new triangles around m;
           \ t   / | \  n  /   ------>        \ / | \ | / |   the halves a-m, m-b keep
            \   /  |  \   /                   ...           the segment's id

3. Else pop a bad triangle with the shortest shortest edge (queue below; stale entries are
   recognised by their vertices) and compute its off-centre (circumcentre when nearer).
   Walk there; a subsegment hiding the point from the triangle is split instead; a point
   in the diametral circle of a subsegment on its cavity boundary is rejected and those
   subsegments are split instead (the triangle is requeued).  Otherwise insert it: the
   cavity never crosses a constrained edge.
4. Every new triangle is examined as in 1.  Triangles whose shortest edge joins two segments
   meeting at a small input angle, at equal distance from the apex, are left alone; a
   vertex of one such segment as far from the apex as an end of a subsegment of the other
   does not encroach it (shell vertices, whose rounding would otherwise decide).  A
   straight segment here is the input segment as drawn, however finely the boundary was
   cut into pieces (:func:`chains`): on a thin domain the pieces meet only at the apex.
   A curve's pieces count one by one, as cut.

State: the insertion kernel's ``TriState`` ``s``, the constrained layer's ``CdtState`` ``c``
(:mod:`meshwright.tri._encroach`) and this method's :class:`RefineState` ``r`` (layout in
:mod:`meshwright.tri._refine_state`, with the per-triangle tests of step 1), each one kernel
argument.

Frozen segments (``refine(frozen=ids)``, for the distributed mesher's interfaces): a
subsegment of one is never split.  Where step 2 or 3 would split it, it is recorded in
``held`` and the triangle that needed it is dropped; the caller splits the agreed
subsegments and calls again, and the new run's step 1 finds what was dropped.

Priority queue (:mod:`meshwright.core.bucket_queue`): one bucket per half power of two of
the squared shortest edge, shortest first (Triangle's order), newest first inside a bucket
(Triangle: oldest first; newest first works where the loop just worked, in the cache, and
measured as good a mesh).  A binary heap on the smallest angle before it missed the cache
on its root-to-leaf paths with most of the mesh queued (``benchmarks/README.md``).  Sizes
from a Python callable are evaluated in batches: new triangles wait in ``pend`` with their
circumcentres, and the loop returns when nothing else is left.  Curves that are not arcs
are evaluated in Python one split at a time.

Termination: guaranteed by Ruppert's and Shewchuk's analyses for ``min_angle`` up to about
20.7 degrees and practical (as in Triangle) up to about 33.8 degrees; ``max_points`` and
``max_steps`` caps raise :class:`~meshwright.core.errors.MeshingError` naming the cap and the
place where the loop was working.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.borrowed import borrowed
from meshwright.core.bucket_queue import Q_N, bq_pop, new_queue
from meshwright.core.errors import GeometryError, InputError, MeshingError
from meshwright.core.flat import GHOST, grown_rows, next3, prev3
from meshwright.sizing.field import as_size_field
from meshwright.tri._encroach import R_BROKEN, R_DONE, R_ROOM, edge_of, encroaches, param_of, room_of, set_flags, split_point
from meshwright.tri._kernel2d import (
    BROKEN, DUP_BASE, I_SCREEN, M_NTRI, M_NV, NEED_SPACE, REFUSED_BASE, _on_constraint, _walk, insert_arrays, split_edge,
)
from meshwright.tri._refine_caps import Caps
from meshwright.tri._refine_state import (
    EQUILATERAL, MODE_CONFORM, MODE_RUPPERT, P_AMAX, P_CT, P_CX, P_CY, P_LEN, P_OFF, P_SIN2, P_TA, P_TB, P_WX, P_WY, QB,
    S_CREADY, S_HN, S_LEN, S_MAXPTS, S_MAXSTEPS, S_MODE, S_NIN, S_PN, S_QN, S_REQ_A, S_REQ_B, S_REQ_P, S_SIZED,
    S_SKIPPED, S_STEPS, RefineState, apply_sizes, examine, hold_subsegment, push_seg, requeue, steiner_point,
)

__all__ = ["refine", "conform", "split_subsegment", "RefineState"]

# statuses of refine_loop besides R_DONE, R_ROOM, R_BROKEN
R_SIZES = 2
R_CURVE = 3
R_CAP_POINTS = 4
R_CAP_STEPS = 5
R_OFF_CURVE = 7
_GROWTH = 8  # largest factor one grow of the bundles may take toward the estimate


@njit(inline="always")
def _short(rows, slots, wcap, meta, qnext, qhdr, sq, pend, held, st):
    """Whether some array lacks room for one more step (one insertion and its queue pushes);
    ``rows, slots`` from :func:`meshwright.tri._encroach.room_of`, ``wcap`` the cavity room."""
    return (
        meta[M_NV] + 1 > rows
        or meta[M_NTRI] + 2 > slots
        or qhdr[Q_N] + wcap + 1 > qnext.shape[0]
        or 2 * (st[S_QN] + 3 * wcap + 3) > sq.shape[0]
        or 4 * (st[S_PN] + wcap + 1) > pend.shape[0]
        or 2 * (st[S_HN] + 3 * wcap + 3) > held.shape[0]
    )


@njit(inline="always")
def _new_vertex(v, tn, piece, tpar, a, b, fl, fr, f0, s, c, r):
    """Record a new vertex v (on ``piece`` at parameter ``tpar``, or -1) and queue its star."""
    c.vseg[v] = piece
    c.vpar[v] = tpar
    c.vacute[v] = 0
    s.meta[M_NV] = v + 1
    set_flags(v, tn, a, b, fl, fr, f0, s, c)
    examine(v, tn, s, c, r)


@njit(cache=True, nogil=True)
def refine_loop(s, c, r):
    """Run Delaunay refinement (or conforming splits) until done or Python is needed.

    Parameters
    ----------
    s : TriState
    c : CdtState
    r : RefineState
        The three bundles of the module docstring.  Every return leaves them consistent, so
        calling again (after growing them on ``R_ROOM``) continues.

    Returns
    -------
    int
        ``R_DONE``; ``R_ROOM`` (grow the bundles); ``R_SIZES`` (evaluate the size field at
        ``pcen``, call :func:`apply_sizes`); ``R_CURVE`` (put the split point of subsegment
        ``st[S_REQ_A], st[S_REQ_B]`` of piece ``st[S_REQ_P]``, between parameters
        ``prm[P_TA], prm[P_TB]``, in ``prm[P_CX:P_CT + 1]`` and set ``st[S_CREADY]``);
        ``R_CAP_POINTS`` / ``R_CAP_STEPS`` (a cap was hit near ``prm[P_WX], prm[P_WY]``);
        ``R_BROKEN`` (inconsistent cavity); ``R_OFF_CURVE`` (the split point of the requested
        subsegment lies neither on it nor inside its two triangles).
    """
    # Every array once, here, and the array forms of walk / cavity / fan below (the bundle
    # forms read the fields again per point).
    s, c, r = borrowed(s), borrowed(c), borrowed(r)
    pts, tri, nbr, circ, rank, cons, meta, work, vmark = s
    vtri, treg = c.vtri, c.treg
    qhead, qnext, qval, qhdr, sq, pend, _, st, prm, fz, held, _ = r
    rows, slots = room_of(s, c)
    wcap = work.shape[0] // 5
    screen = np.int64(I_SCREEN)  # a variable, not a literal: insert_arrays keeps one signature
    while True:
        nv = meta[M_NV]
        if _short(rows, slots, wcap, meta, qnext, qhdr, sq, pend, held, st):
            return R_ROOM
        if st[S_QN] > 0:
            q = st[S_QN] - 1
            a = sq[2 * q]
            b = sq[2 * q + 1]
            h = edge_of(np.int64(a), np.int64(b), tri, nbr, vtri)  # one signature with Python's calls
            if h < 0 or cons[h] == 0:
                st[S_QN] = q  # split or freed meanwhile
                continue
            p = cons[h] - 1
            x, y, tpar, ok = split_point(p, a, b, s, c)
            if not ok:
                if st[S_CREADY] == 0 or st[S_REQ_A] != a or st[S_REQ_B] != b:
                    st[S_REQ_A] = a
                    st[S_REQ_B] = b
                    st[S_REQ_P] = p
                    prm[P_TA] = param_of(p, a, c.seg, c.pdat, c.vpar)
                    prm[P_TB] = param_of(p, b, c.seg, c.pdat, c.vpar)
                    return R_CURVE
                x = prm[P_CX]
                y = prm[P_CY]
                tpar = prm[P_CT]
            prm[P_WX] = x
            prm[P_WY] = y
            st[S_STEPS] += 1
            if st[S_STEPS] > st[S_MAXSTEPS]:
                return R_CAP_STEPS
            if nv >= st[S_MAXPTS]:
                return R_CAP_POINTS
            pts[nv, 0] = x
            pts[nv, 1] = y
            fl = treg[h // 3]
            fr = treg[nbr[h]]
            tn = split_edge(nv, h, s)
            if tn == NEED_SPACE:
                st[S_STEPS] -= 1
                return R_ROOM
            if tn < 0:
                st[S_REQ_A] = a
                st[S_REQ_B] = b
                st[S_REQ_P] = p
                return R_OFF_CURVE
            st[S_CREADY] = 0
            st[S_QN] = q
            f0 = 0
        elif qhdr[Q_N] > 0:
            e = bq_pop(qhead, qnext, qhdr)
            t = qval[e, 0]
            stale = t >= meta[M_NTRI] or tri[3 * t] != qval[e, 1] or tri[3 * t + 1] != qval[e, 2]
            stale = stale or tri[3 * t + 2] != qval[e, 3]
            if stale or treg[t] < 0:
                continue
            st[S_STEPS] += 1
            x, y = steiner_point(t, pts, tri, prm[P_OFF])
            prm[P_WX] = x
            prm[P_WY] = y
            if st[S_STEPS] > st[S_MAXSTEPS]:
                # Requeued: a caller that raises the cap continues where the loop stopped.
                requeue(t, pts, tri, qhead, qnext, qval, qhdr)
                return R_CAP_STEPS
            t0, hb = _walk(pts, tri, nbr, cons, meta, t, x, y, True)
            if hb < 0 and tri[3 * t0 + 2] != GHOST:
                hb = _on_constraint(pts, tri, cons, t0, x, y)
            if hb >= 0:
                # Hidden behind, or on, a subsegment: split that one first (a frozen one
                # waits for the caller; so does t, dropped until the next run examines it).
                u = tri[next3(hb % 3) + hb - hb % 3]
                w = tri[prev3(hb % 3) + hb - hb % 3]
                if not hold_subsegment(u, w, hb, cons, fz, held, st):
                    push_seg(u, w, sq, st)
                    requeue(t, pts, tri, qhead, qnext, qval, qhdr)
                continue
            if tri[3 * t0 + 2] == GHOST or treg[t0] < 0:
                st[S_SKIPPED] += 1  # unreachable without crossing a segment: cannot happen
                continue
            if nv >= st[S_MAXPTS]:
                requeue(t, pts, tri, qhead, qnext, qval, qhdr)
                return R_CAP_POINTS
            pts[nv, 0] = x
            pts[nv, 1] = y
            f0 = treg[t0]
            # The insertion kernel's compiled copy (shared with every per-point insertion:
            # an inlined cavity and fan here took about 4 s of the first run's compile),
            # which refuses a point inside the diametral circle of a subsegment on its
            # cavity boundary (the only subsegments it can encroach).
            tn = insert_arrays(pts, tri, nbr, circ, rank, cons, meta, work, vmark, nv, t0, screen)
            if tn == NEED_SPACE:
                requeue(t, pts, tri, qhead, qnext, qval, qhdr)
                return R_ROOM
            if tn == BROKEN:
                return R_BROKEN
            if tn <= REFUSED_BASE:
                # Refused: split the encroached subsegments instead (the cavity is in work).
                bo = 2 * (work.shape[0] // 5)
                enc = False
                for j in range(REFUSED_BASE - tn + 2):
                    o = bo + 3 * j
                    if cons[work[o + 2]] != 0:
                        u = work[o]
                        w = work[o + 1]
                        if encroaches(pts[u, 0], pts[u, 1], pts[w, 0], pts[w, 1], x, y):
                            if not hold_subsegment(u, w, work[o + 2], cons, fz, held, st):
                                push_seg(u, w, sq, st)
                                enc = True
                if enc:
                    requeue(t, pts, tri, qhead, qnext, qval, qhdr)
                continue
            if tn <= DUP_BASE:
                st[S_SKIPPED] += 1
                continue
            p, tpar, a, b, fl, fr = -1, 0.0, -1, -1, 0, 0
        elif st[S_PN] > 0:
            return R_SIZES
        else:
            return R_DONE
        # One inlined copy for a subsegment's split point and an off-centre (each copy is
        # typed and lowered again on the first run: issue 13).
        _new_vertex(nv, tn, p, tpar, a, b, fl, fr, f0, s, c, r)


@njit(cache=True, nogil=True)
def _split_at(v, h, s, c):
    """Split the subsegment of half-edge h at ``pts[v]`` and flag the new triangles."""
    a = s.tri[3 * (h // 3) + next3(h % 3)]
    b = s.tri[3 * (h // 3) + prev3(h % 3)]
    fl = c.treg[h // 3]
    fr = c.treg[s.nbr[h]]
    tn = split_edge(v, h, s)
    if tn >= 0:
        set_flags(v, tn, a, b, fl, fr, 0, s, c)
    return tn


# ---------------------------------------------------------------------------- driver
def chains(ct) -> np.ndarray:
    """The chain of each piece of ``ct`` and the chain's end vertices (``RefineState.pcor``).

    A chain is the stretch of one straight input segment (a
    :class:`~meshwright.geometry.curves.Line`, or one edge of a
    :class:`~meshwright.geometry.curves.Polyline`: its parameters lie between two consecutive integers, as
    ``ct.curves``, a :class:`~meshwright.tri.cdt.SegmentCurves`, tells) between two
    vertices where other pieces meet it: the pieces of that stretch, however finely the
    boundary was cut, and the two vertices that bound an odd number of them.  A piece of
    any other curve, a piece without curve data, and the pieces of a stretch that is not
    one open path stay their own chains, ending at their own vertices.

    Only straight segments: the small-angle rules' premise is two straight segments at
    the input angle, so that vertices equally far from the apex face each other across
    the wedge.  On a curve that holds only piece by piece (a closed NACA section's upper
    and lower surfaces are equally far from its trailing edge along the whole chord), and
    a curve's data does not say where it has a corner (the trailing edge is where that
    closed curve starts and ends).

    Returns
    -------
    (P, 3) int32
        Chain id, end vertex, end vertex.
    """
    from meshwright.geometry.curves import Line, Polyline
    from meshwright.tri.cdt import SegmentCurves

    n = ct._np
    seg = ct.constraints.seg[:n].astype(np.int64)
    out = np.empty((n, 3), dtype=np.int32)
    out[:, 0] = np.arange(n)
    out[:, 1:] = seg
    curves = ct.curves
    rows = ct.constraints.seg_in[:n].astype(np.int64)
    # Curve data that does not cover every input segment (replaced by refine(curves=...)
    # with fewer rows) tells nothing safe: pieces stay their own chains.
    if not isinstance(curves, SegmentCurves) or n == 0 or rows.max() < 0 or rows.max() >= len(curves.segment_curve):
        return out
    kind = np.array([isinstance(cv, Polyline) + 2 * isinstance(cv, Line) for cv in curves.curves], dtype=np.int64)
    ok = rows >= 0
    ok[ok] = kind[curves.segment_curve[rows[ok]]] > 0
    ok = np.flatnonzero(ok)
    if not len(ok):
        return out
    # The input segments (rows) of these pieces along each straight segment, in the order
    # of their curve parameters.
    used = np.unique(rows[ok])
    cid = curves.segment_curve[used].astype(np.int64)
    mid = curves.segment_params[used].mean(axis=1)
    edge = np.where(kind[cid] == 1, np.floor(mid), 0.0).astype(np.int64)
    order = np.lexsort((mid, edge, cid))
    used, cid, edge = used[order], cid[order], edge[order]
    ends = ct.input_segments[used].astype(np.int64)
    # A new stretch starts with each straight segment, and after a vertex where other
    # pieces meet it (more than its two) or that two consecutive rows do not share.
    degree = np.bincount(seg.ravel(), minlength=int(seg.max()) + 1)
    a, b = ends[:-1], ends[1:]
    shared = np.where((a[:, 1] == b[:, 0]) | (a[:, 1] == b[:, 1]), a[:, 1], a[:, 0])
    joined = (shared == b[:, 0]) | (shared == b[:, 1])
    cut = np.ones(len(used), dtype=bool)
    cut[1:] = (cid[1:] != cid[:-1]) | (edge[1:] != edge[:-1]) | ~joined | (degree[shared] != 2)
    stretch = np.cumsum(cut) - 1
    by_row = np.argsort(used)
    chain = stretch[by_row[np.searchsorted(used, rows[ok], sorter=by_row)]]
    # Ends: the vertices of an odd number of the chain's pieces.
    pairs = np.column_stack([np.concatenate([chain, chain]), np.concatenate([seg[ok, 0], seg[ok, 1]])])
    ev, count = np.unique(pairs, axis=0, return_counts=True)
    ev = ev[count % 2 == 1]
    two = np.bincount(ev[:, 0], minlength=int(chain.max()) + 1) == 2
    # ev is sorted by chain, then vertex: the two ends of a chain are adjacent rows.
    ev = ev[two[ev[:, 0]]].reshape(-1, 2, 2)
    first = np.full(len(two), -1, dtype=np.int64)
    last = np.full(len(two), -1, dtype=np.int64)
    first[ev[:, 0, 0]] = ev[:, 0, 1]
    last[ev[:, 0, 0]] = ev[:, 1, 1]
    use = two[chain]
    out[ok[use], 0] = n + chain[use]
    out[ok[use], 1] = first[chain[use]]
    out[ok[use], 2] = last[chain[use]]
    return out


class _Run:
    """The :class:`RefineState` of one refinement run on a ConstrainedTriangulation ``ct``."""

    def __init__(
        self, ct, mode: int, sin2: float, amax: float, off: float, sized: bool, max_points: int, max_steps: int,
        frozen=None,
    ):
        self.ct = ct
        ct.refresh_pieces()
        ct.mark_acute()
        rows = ct.constraints.seg_in[: ct._np]
        fz = np.zeros(len(rows), dtype=np.uint8)
        if frozen is not None and len(frozen):
            inner = rows >= 0
            fz[inner] = np.isin(ct.segment_ids[rows[inner]], frozen)
        st = np.zeros(S_LEN, dtype=np.int64)
        st[S_MODE] = mode
        st[S_SIZED] = int(sized)
        st[S_MAXPTS] = max_points
        st[S_MAXSTEPS] = max_steps
        st[S_NIN] = ct.n_points
        prm = np.zeros(P_LEN)
        prm[P_SIN2] = sin2
        prm[P_AMAX] = amax
        prm[P_OFF] = off
        cap = 2 * int(ct.state.meta[M_NTRI]) + 1024
        self.r = RefineState(
            *new_queue(QB, cap, 4), np.empty(2 * (3 * cap), dtype=np.int32),
            np.empty(4 * cap, dtype=np.int32), np.empty(2 * cap), st, prm, fz, np.empty(2 * (3 * cap), dtype=np.int32),
            chains(ct),
        )

    def seed(self) -> None:
        examine(-1, 0, self.ct.state, self.ct.constraints, self.r)

    def grow(self, estimate: int) -> None:
        """Double whatever :func:`refine_loop` found short (``estimate``: expected vertices)."""
        ct, r = self.ct, self.r
        st = r.st
        nv = ct.n_points
        ntri = int(ct.state.meta[M_NTRI])
        # Straight to the estimate, but at most _GROWTH times the present size: the estimate
        # may be far too high (size ratios of 1e4), and each grow copies every array, so
        # doubling from the boundary (8 grows for a 460k-triangle disk) cost 15 % of the run.
        rows = max(nv + 2, min(estimate, _GROWTH * nv + 2))
        slots = max(ntri + 4, min(2 * estimate + 8, _GROWTH * ntri + 4))
        ct.reserve(rows, slots)
        wcap = ct.state.work.shape[0] // 5
        sq = grown_rows(r.sq, 2 * (int(st[S_QN]) + 3 * wcap + 3))
        pend = grown_rows(r.pend, 4 * (int(st[S_PN]) + wcap + 1))
        held = grown_rows(r.held, 2 * (int(st[S_HN]) + 3 * wcap + 3))
        self.r = r._replace(sq=sq, pend=pend, pcen=grown_rows(r.pcen, len(pend) // 2), held=held)
        # The queue holds up to about one entry per triangle slot.
        self._grow_queue(max(wcap + 1, slots - int(r.qhdr[Q_N])))

    def _grow_queue(self, more: int) -> None:
        """Room for ``more`` pushes on the bad-triangle queue."""
        r = self.r
        qnext = grown_rows(r.qnext, int(r.qhdr[Q_N]) + more)
        if qnext is not r.qnext:
            self.r = r._replace(qnext=qnext, qval=grown_rows(r.qval, len(qnext)))

    def curve_point(self) -> None:
        """Answer an ``R_CURVE`` request: the split point on a curve known only to Python."""
        ct, st, prm = self.ct, self.r.st, self.r.prm
        pts = ct.state.pts
        a, b, p = int(st[S_REQ_A]), int(st[S_REQ_B]), int(st[S_REQ_P])
        row = int(ct.constraints.seg_in[p])
        if callable(ct.curves) and not hasattr(ct.curves, "split"):
            xy = np.asarray(ct.curves(int(ct.segment_ids[row]), pts[a].copy(), pts[b].copy()), dtype=np.float64)
            if xy.shape != (2,) or not np.isfinite(xy).all():
                raise InputError(f"curves({int(ct.segment_ids[row])}, ...) must return a finite (2,) point, got {xy!r}")
            x, y, t = float(xy[0]), float(xy[1]), 0.0
        else:
            ta, tb = float(prm[P_TA]), float(prm[P_TB])
            # Vertices inserted on a curved segment by hand have no parameter yet.
            ta = ct.curves.project(row, pts[a]) if np.isnan(ta) else ta
            tb = ct.curves.project(row, pts[b]) if np.isnan(tb) else tb
            x, y, t = ct.curves.split(row, ta, tb)
        prm[P_CX], prm[P_CY], prm[P_CT] = x, y, t
        st[S_CREADY] = 1

    def run(self, size, estimate: int, what: str, progress=None, caps: Caps | None = None) -> None:
        """Call the loop until it is done, serving its requests; raise on caps and errors.

        ``progress(n_vertices)`` is called whenever the loop hands control back to Python;
        ``caps`` may raise a default cap when it is reached (:mod:`._refine_caps`).
        """
        ct = self.ct
        while True:
            code = refine_loop(ct.state, ct.constraints, self.r)
            st = self.r.st
            if progress is not None:
                progress(ct.n_points)
            if code == R_DONE:
                return
            if code == R_ROOM:
                self.grow(estimate)
            elif code == R_SIZES:
                pn = int(st[S_PN])
                h = size(self.r.pcen[: 2 * pn].reshape(pn, 2))
                # Every waiting triangle may go to the queue.
                self._grow_queue(pn + 1)
                apply_sizes(h, ct.state, self.r)
            elif code == R_CURVE:
                self.curve_point()
            elif code == R_CAP_POINTS and caps is not None and caps.relax(ct):
                st[S_MAXPTS] = caps.max_points
            elif code == R_CAP_STEPS and caps is not None and caps.more_steps(ct):
                st[S_MAXSTEPS] = caps.max_steps
            else:
                self._fail(code, what)

    def _fail(self, code: int, what: str) -> None:
        ct, st, prm = self.ct, self.r.st, self.r.prm
        pts = ct.state.pts
        where = f"({prm[P_WX]:.17g}, {prm[P_WY]:.17g})"
        done = ct.n_points
        if code == R_CAP_POINTS:
            raise MeshingError(
                f"{what}: max_points={int(st[S_MAXPTS])} reached while working near {where}; "
                "raise max_points, or coarsen the size / relax min_angle"
            )
        if code == R_CAP_STEPS:
            raise MeshingError(
                f"{what}: max_steps={int(st[S_MAXSTEPS])} reached with {done} vertices while working "
                f"near {where}; the input may have features the angle bound cannot resolve"
            )
        if code == R_OFF_CURVE:
            a, b, p = int(st[S_REQ_A]), int(st[S_REQ_B]), int(st[S_REQ_P])
            raise GeometryError(
                f"{what}: subsegment ({pts[a, 0]:.17g}, {pts[a, 1]:.17g})-({pts[b, 0]:.17g}, {pts[b, 1]:.17g}) of segment "
                f"{int(ct.constraints.seg_in[p])} cannot be split at {where}: the point is neither on it nor "
                "inside its two triangles (a vertex lies between the chord and the true curve)"
            )
        raise MeshingError(f"{what}: inserting a vertex near {where} met an inconsistent cavity")


def refine(
    ct, *, min_angle: float = 30.0, size=None, max_area=None, max_points=None, max_steps=None,
    offcenters: bool = True, curves=None, progress=None, frozen=None,
):
    """Guaranteed-quality Delaunay refinement of a constrained triangulation, in place.

    Parameters
    ----------
    ct : ConstrainedTriangulation
        From :func:`meshwright.tri.cdt.cdt_build`; classified first if it was not (free
        convex-hull edges bounding the inside become segments, :meth:`close_hull`).
    min_angle : float
        Smallest angle wanted, degrees in ``[0, 60)``; 0 refines by size only.  Up to about
        33.8 terminates in practice; angles next to smaller input angles are left alone.
    size : number, callable or SizeField, optional
        Local edge length h(x): a triangle is split while its area exceeds that of the
        equilateral triangle of side h at its circumcentre.
    max_area : float, optional
        Largest triangle area (region seeds of :meth:`classify` may lower it locally).
    max_points : int, optional
        Cap on the number of vertices; default ``nv + 50 nv + 4 * estimate + 1000`` with the
        estimate from ``size`` / ``max_area``, raised once to the local-feature-size estimate
        when reached (:mod:`meshwright.tri._refine_caps`).
    max_steps : int, optional
        Cap on loop steps (default ``20 * min(max_points, nv + 50 nv + 4 * estimate + 1000)``,
        so a stalled loop stops early even under a large ``max_points``; raised when reached
        while the run keeps inserting vertices).
    offcenters : bool
        Insert Üngör's off-centres instead of circumcentres where nearer (fewer vertices).
    curves : SegmentCurves or callable, optional
        Replaces ``ct.curves`` (true curve of each segment for the split points).
    progress : callable, optional
        ``progress(n_vertices)``, called now and then (progress bars).
    frozen : (f,) array_like of int, optional
        Ids of segments refinement must not split (the interfaces of a decomposed domain:
        their splits are agreed with the neighbouring part first).  A subsegment of one that
        an encroachment would split is recorded in ``ct.held`` instead, and the triangles
        that waited for it are left as they are; split the agreed subsegments
        (:func:`split_subsegment`) and call ``refine`` again to finish them.

    Returns
    -------
    ConstrainedTriangulation
        ``ct``, refined (everywhere when ``ct.held`` is empty).

    Raises
    ------
    MeshingError
        A cap was hit (the message names it and where the loop was working).
    GeometryError
        A curved segment cannot be split on its curve.
    """
    if not (0.0 <= float(min_angle) < 60.0):
        raise InputError(f"min_angle must be in [0, 60) degrees, got {min_angle!r}")
    if max_area is not None and not (np.isfinite(max_area) and max_area > 0.0):
        raise InputError(f"max_area must be positive and finite, got {max_area!r}")
    if frozen is not None:
        frozen = np.asarray(frozen)
        if frozen.ndim != 1 or (frozen.size and frozen.dtype.kind not in "iu"):
            raise InputError(f"frozen must be a 1-D array of segment ids, got shape {frozen.shape} dtype {frozen.dtype}")
    if curves is not None:
        ct.curves = curves
    if not ct.classified:
        ct.classify()
    _close_open_hull(ct)
    field = None if size is None else as_size_field(size)
    amax = np.inf if max_area is None else float(max_area)
    if field is not None and field.constant is not None:
        amax = min(amax, EQUILATERAL * field.constant**2)
    theta = np.radians(float(min_angle))
    sin2 = np.sin(theta) ** 2
    off = 0.475 * np.sqrt((1.0 + np.cos(theta)) / (1.0 - np.cos(theta))) if offcenters and theta > 0 else 0.0
    caps = Caps(ct, amax, field, max_points, max_steps)
    sized = field is not None and field.constant is None
    run = _Run(ct, MODE_RUPPERT, sin2, amax, off, sized, caps.max_points, caps.max_steps, frozen)
    run.seed()
    run.run(field, caps.room, "refine", progress, caps)
    ct.held = _held(ct, run.r)
    return ct


def _held(ct, r: RefineState) -> tuple[np.ndarray, np.ndarray]:
    """The distinct subsegments the run held (``ct.held``), as :meth:`segments` gives them."""
    pairs = r.held[: 2 * int(r.st[S_HN])].reshape(-1, 2).astype(np.int64)
    edges, ids = ct.segments()
    if not len(pairs):
        return edges[:0], ids[:0]
    n = ct.n_points

    def key(e):
        return np.minimum(e[:, 0], e[:, 1]).astype(np.int64) * n + np.maximum(e[:, 0], e[:, 1])

    keep = np.isin(key(edges), key(pairs))
    return edges[keep], ids[keep]


def _close_open_hull(ct) -> None:
    """Constrain free hull edges whose inner triangle is inside (they bound the domain)."""
    s = ct.state
    ntri = int(s.meta[M_NTRI])
    g = np.flatnonzero(s.tri[2 : 3 * ntri : 3] == GHOST)
    h = 3 * g + 2
    inner = s.nbr[h]
    if np.any((s.cons[h] == 0) & (ct.constraints.treg[inner] >= 0)):
        ct.close_hull()


def conform(ct) -> None:
    """Split subsegments until each is locally Delaunay: a conforming Delaunay triangulation.

    Split points as in :func:`refine` (midpoints on the true curve, shells at acute input
    vertices); no triangle is refined.
    """
    nv = ct.n_points
    run = _Run(ct, MODE_CONFORM, 0.0, np.inf, 0.0, False, 50 * nv + 1000, 1000 * nv + 10000)
    run.seed()
    run.run(None, 2 * nv, "conforming Delaunay")


def split_subsegment(ct, a: int, b: int, xy=None) -> int:
    """Split subsegment ab of ``ct`` at ``xy`` or at its split point; return the new vertex."""
    s, c = ct.state, ct.constraints
    h = int(edge_of(a, b, s.tri, s.nbr, c.vtri)) if 0 <= min(a, b) and max(a, b) < ct.n_points else -1
    if h < 0 or s.cons[h] == 0:
        raise InputError(f"vertices {a} and {b} are not the ends of a subsegment")
    run = _Run(ct, MODE_CONFORM, 0.0, np.inf, 0.0, False, 2**31 - 16, 1)
    c = ct.constraints
    p = int(s.cons[h]) - 1
    row = int(c.seg_in[p])
    if xy is None:
        x, y, t, ok = split_point(p, a, b, s, c)
        if not ok:
            st, prm = run.r.st, run.r.prm
            st[S_REQ_A], st[S_REQ_B], st[S_REQ_P] = a, b, p
            prm[P_TA] = param_of(p, a, c.seg, c.pdat, c.vpar)
            prm[P_TB] = param_of(p, b, c.seg, c.pdat, c.vpar)
            run.curve_point()
            x, y, t = prm[P_CX], prm[P_CY], prm[P_CT]
    else:
        x, y = (float(c) for c in np.asarray(xy, dtype=np.float64).ravel()[:2])
        t = ct.curves.project(row, (x, y)) if hasattr(ct.curves, "project") and row >= 0 else np.nan
    v = ct.n_points
    ct.reserve(v + 1, int(ct.state.meta[M_NTRI]) + 2)
    ct.state.pts[v] = x, y
    while True:
        tn = _split_at(v, h, ct.state, ct.constraints)
        if tn != NEED_SPACE:
            break
        ct.reserve(v + 1, int(ct.state.meta[M_NTRI]) + 2)
    if tn < 0:
        raise GeometryError(
            f"subsegment {a}-{b} cannot be split at ({x:.17g}, {y:.17g}): the point is neither on it "
            "nor inside one of its two triangles"
        )
    c = ct.constraints
    c.vseg[v], c.vpar[v], c.vacute[v] = p, t, 0
    ct.state.meta[M_NV] = v + 1
    return v
