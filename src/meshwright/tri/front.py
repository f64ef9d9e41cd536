r"""Advancing-front triangulation (chapter 18.2), stretched through the background grid.

Sources: S. H. Lo, "A new mesh generation scheme for arbitrary planar domains", Int. J.
Numer. Meth. Eng. 21, 1985; J. Peraire, M. Vahdati, K. Morgan and O. C. Zienkiewicz,
"Adaptive remeshing for compressible flow computations", J. Comput. Phys. 72, 1987 (the
background grid of spacing delta, stretching s and direction alpha, the ideal point and the
candidate search); R. Löhner and P. Parikh, "Generation of three-dimensional unstructured
grids by the advancing-front method", Int. J. Numer. Meth. Fluids 8, 1988 (search
structures, back-off).

Procedure (the numbered steps of 18.2)
--------------------------------------
1. The background grid gives, at every node, the metric ``M = T^2 / delta^2`` of the
   chapter's local transformation ``T = R(alpha) diag(1/s, 1) R(-alpha)``: in the space
   ``x' = L^T x`` (``M = L L^T``) the wanted triangles are equilateral of unit side.  A size
   field without stretching gives ``M = I / h^2``.
2.-3. The initial front is the boundary of the classified constrained triangulation of the
   boundary points: every segment with the domain on its left (outer loops counter-clockwise,
   holes clockwise, both sides of an interior segment), and every input point on no segment
   as a free point that the front must reach.
4. The next face is the shortest one (a binary heap): small elements advance first, so
   large ones never cross regions of small ones.
5. For face AB, in the metric of its ends: (a) the ideal point P makes an equilateral
   triangle of unit side, the sides kept within [0.55, 2] face lengths; (b) the front nodes
   within ``CLOSE rho`` of P, left of AB, are tried first, nearest first, if their triangle
   has quality ``GOOD`` and sides below ``LONG rho``; then P itself if it keeps ``CLEAR_NODE
   rho`` from every node and ``CLEAR_FACE rho`` from every face, those behind AB seen from P
   excepted (exact orientations; the way to them passes A or B, rho away: a sharp corner
   at A or B puts its neighbour there); then the other nodes of the search box, best
   triangle first; (c) a candidate is taken only if the triangle crosses no front face and
   contains no front node (exact tests, see
   :mod:`meshwright.tri._front_kernel`), and, as a quality rule, its new sides keep
   ``CLEAR_EDGE rho`` from every other node.
6.-8. The triangle is added; each of its two new sides either closes the front face lying on
   it or joins the front; the face AB leaves the front.
9. Repeat until the front is empty.
10. Clean-up (Löhner and Parikh 1988; Peraire et al. 1987 smooth and swap likewise): the
    diagonals of the finished mesh are swapped where that raises the smaller angle of the
    two triangles on them, measured in the metric (``SWAP_PASSES`` passes at most, a swap
    must gain ``SWAP_GAIN`` radians), input segments never; then, for an isotropic size,
    ``SMOOTH_PASSES`` passes of the chapter's guarded spring-analogy smoothing
    (:mod:`meshwright.tri.smoothing`: no triangle inverted, the worst radius ratio around a
    node never lowered) move the generated nodes, input vertices fixed, and the swaps run
    once more.  Where two fronts meet, or the size still grades, the front closes with a
    node chosen for validity rather than shape; this step repairs those triangles (issue
    13: on graded domains the smallest angle rose from 14-19 to 29-31 degrees).  A
    stretched background is swapped in its metric but not smoothed (the Laplacian is
    isotropic).

A face with no valid candidate is postponed (``MAX_DEFER`` times, behind every ordinary
face).  Its last try searches four times as far, and to the far ends of every face the box
meets (a gap narrower than the spacing closes with a long segment's ends), and ends with a
round that asks validity only.  If it still fails, the triangles around its ends (one ring,
then two, then three) are removed and their region re-opened (back-off).  A face that fails after three rings, or more
than ``max_backoff`` back-offs in all, raises :class:`MeshingError` naming the face.

Sizes: nodes carry their metric, evaluated in batches (the field is a Python callable): a
face whose end is a node made since the last evaluation waits, and the field is evaluated
when only waiting faces are left, ``SYNC_EVERY`` nodes are new, or (``grade=True``) the
shortest ready face is more than ``WAIT_RATIO`` (:mod:`meshwright.tri._front_kernel`) times
as long as a waiting one: the shortest-first order then holds across the waits too (without it, at a
size jump, a coarse face advanced while the fine faces beside it waited and they closed on
its far node in a fan of slivers).  Every face is thus advanced with the exact metric of
its ends; a uniform metric needs no evaluation at all.

Array layout: :mod:`meshwright.tri._front_kernel`.  Output: the constrained triangulation's
vertices followed by the generated nodes (``points`` (n, 2) float64) and counter-clockwise
``triangles`` (t, 3) int32 covering exactly the domain.
"""

from __future__ import annotations

import numpy as np

from meshwright.core.errors import MeshingError, fmt_point
from meshwright.core.flat import grown_rows
from meshwright.core.spatial.cell_quadtree import Q_DEPTH, Q_NODES, Q_ROOM, ct_new
from meshwright.core.validate_input import check_flag
from meshwright.sizing.field import as_size_field
from meshwright.tri import _front_kernel as fk
from meshwright.tri._front_swap import swap_edges
from meshwright.tri._kernel2d import M_NTRI
from meshwright.tri.smoothing import smooth

__all__ = [
    "advancing_front", "metric_at", "area_cap", "split_long_segments",
    "CLOSE", "SEARCH", "GOOD", "LONG", "CLEAR_NODE", "CLEAR_FACE", "CLEAR_EDGE", "MAX_DEFER", "SYNC_EVERY",
    "MAX_AREA_SIDE", "SWAP_PASSES", "SWAP_GAIN", "SMOOTH_PASSES", "GRADE", "grade_segments",
]

CLOSE = 0.8  # nodes within CLOSE rho (metric) of the ideal point are preferred to it
SEARCH = 0.8  # the candidate search box covers SEARCH rho about the ideal point
GOOD = 0.6  # a close node is taken before the new point only if its triangle is this good
LONG = 1.3  # ... and its new sides are at most LONG rho
CLEAR_NODE = 0.75  # a new point keeps this fraction of rho from every front node
CLEAR_FACE = 0.55  # ... and this from every front face
CLEAR_EDGE = 0.2  # a new side keeps this fraction of rho from every other front node
MAX_DEFER = 2  # postponements of a face before backing off
SYNC_EVERY = 512  # new nodes between two evaluations of the size field
MAX_AREA_SIDE = 0.8  # an area bound A caps the spacing at this fraction of sqrt(4 A / sqrt(3))
SWAP_PASSES = 8  # passes of diagonal swapping over the finished mesh
SWAP_GAIN = 1e-4  # radians a swap must add to the smallest angle of its two triangles
SMOOTH_PASSES = 2  # guarded Laplacian passes over the generated nodes (isotropic sizes only)
GRADE = 2.5  # grade=True: a subsegment longer than this many sizes of its finer end is halved
MAX_GRADE_ROUNDS = 64  # halvings of one piece: a size ratio up to 2**64 along one segment


def metric_at(field, xy, cap=None) -> np.ndarray:
    """Metric ``(m11, m12, m22)`` of the size field at ``xy`` (k, 2); returns (k, 3) float64.

    A :class:`~meshwright.sizing.BackgroundGrid` contributes its stretching (``T^2 /
    delta^2``); any other field the isotropic ``I / h^2``.  ``cap(xy) -> (k,)``, if given,
    bounds the spacing: the metric is scaled so that no element side exceeds it.
    """
    xy = np.ascontiguousarray(xy, dtype=np.float64)
    out = np.empty((len(xy), 3))
    if hasattr(field, "metric"):
        delta, s, al = field.metric(xy)
        c, sn = np.cos(al), np.sin(al)
        inv_s2 = 1.0 / (s * s)
        # T^2 = R diag(1/s^2, 1) R^T.
        out[:, 0] = (c * c * inv_s2 + sn * sn) / delta**2
        out[:, 1] = c * sn * (inv_s2 - 1.0) / delta**2
        out[:, 2] = (sn * sn * inv_s2 + c * c) / delta**2
        longest = s * delta
    else:
        h = field(xy)
        out[:, 0] = 1.0 / h**2
        out[:, 1] = 0.0
        out[:, 2] = out[:, 0]
        longest = h
    if cap is not None:
        out *= np.maximum(1.0, (longest / cap(xy)) ** 2)[:, None]
    return out


def area_cap(ct, max_area=None):
    """Spacing bound ``cap(xy) -> (k,)`` from an area bound and the regions' bounds, or None.

    ``MAX_AREA_SIDE`` times the side of the equilateral triangle of the smaller of
    ``max_area`` and the bound of the region holding each point.
    """
    rarea = np.asarray(ct.constraints.rarea, dtype=np.float64)
    glob = np.inf if max_area is None else float(max_area)
    if not np.isfinite(glob) and not np.isfinite(rarea).any():
        return None

    def cap(xy):
        area = np.full(len(xy), glob)
        if np.isfinite(rarea).any():
            slots = ct.locate(xy, "size query")
            area = np.minimum(area, rarea[np.maximum(ct.constraints.treg[slots], 0)])
        return MAX_AREA_SIDE * np.sqrt(4.0 * area / np.sqrt(3.0))

    return cap


def _initial_front(ct):
    """Front faces (k, 2) and free points (j,) of a classified constrained triangulation."""
    s = ct.state
    ntri = int(s.meta[M_NTRI])
    inside = ct.inside_slots()
    tri = s.tri[: 3 * ntri].reshape(ntri, 3)
    nbr = s.nbr[: 3 * ntri].reshape(ntri, 3)
    cons = s.cons[: 3 * ntri].reshape(ntri, 3) != 0
    # Edge k of a counter-clockwise triangle runs (k+1) -> (k+2) with the triangle on its left.
    open_edge = inside[:, None] & (cons | ~inside[np.maximum(nbr, 0)] | (nbr < 0))
    t, k = np.nonzero(open_edge)
    faces = np.column_stack([tri[t, (k + 1) % 3], tri[t, (k + 2) % 3]]).astype(np.int32)
    used = np.zeros(ct.n_points, dtype=bool)
    used[tri[inside].ravel()] = True
    on_front = np.zeros(ct.n_points, dtype=bool)
    on_front[faces.ravel()] = True
    return faces, np.flatnonzero(used & ~on_front).astype(np.int32), used, tri[inside]


class _Front:
    """The kernel's :class:`~meshwright.tri._front_kernel.FrontState` and its growth."""

    def __init__(self, points, faces, free, metric, estimate: int):
        n = len(points)
        pcap = max(64, n + 2 * estimate // 3 + 16)
        fcap = max(4 * fk.ROOM_FACES, len(faces) + 2 * len(free) + 3 * estimate)
        tcap = max(64, estimate + 16)
        pts = np.zeros((pcap, 2))
        pts[:n] = points
        met = np.zeros((pcap, 3))
        met[:n] = metric
        lo, hi = points.min(axis=0), points.max(axis=0)
        lens = np.hypot(*(points[faces[:, 1]] - points[faces[:, 0]]).T) if len(faces) else np.ones(1)
        # A small tree that room() grows by doubling (pairing's disk at h = 0.01 used 4,425 of the
        # 1.1 million nodes that 4 per face slot preallocated: 22 MB filled with -1 per run).
        qgeo, qmeta, qchild, qhead = ct_new((lo[0], lo[1], hi[0], hi[1]), 0.25 * float(lens.min()))
        meta = np.zeros(fk.M_LEN, dtype=np.int64)
        meta[fk.M_NP] = n
        meta[fk.M_NIN] = n
        meta[fk.M_SYNC] = n
        self.fs = fk.FrontState(
            pts=pts, met=met, vint=np.full((pcap, 4), -1, dtype=np.int32), face=np.empty((fcap, 4), dtype=np.int32),
            falive=np.zeros(fcap, dtype=np.int8), qbox=np.empty((fcap, 4)), qgeo=qgeo, qmeta=qmeta, qchild=qchild,
            qhead=qhead, qnext=np.empty(4 * fcap, dtype=np.int32), qcell=np.empty((fcap, 2), dtype=np.int64),
            hkey=np.empty(fcap),
            hface=np.empty((fcap, 1), dtype=np.int32), wkey=np.empty(fcap), wface=np.empty(fcap, dtype=np.int32),
            tri=np.empty((tcap, 3), dtype=np.int32), tnext=np.empty((tcap, 3), dtype=np.int32),
            talive=np.zeros(tcap, dtype=np.int8), meta=meta,
        )
        # The initial front in order, ROOM_FACES items at a time: room() before each chunk
        # leaves the quadtree nodes the kernel's own steps are guaranteed (seed_front checks none).
        faces = np.ascontiguousarray(faces, dtype=np.int32).reshape(-1, 2)
        free = np.ascontiguousarray(free, dtype=np.int32)
        for i in range(0, len(faces) + len(free), fk.ROOM_FACES):
            self.room()
            j = i + fk.ROOM_FACES
            fk.seed_front(faces[i:j], free[max(i - len(faces), 0):max(j - len(faces), 0)], self.fs)
        self.scratch = fk.new_scratch(qmeta[Q_DEPTH])

    def room(self) -> None:
        """Grow every array the kernel asked room in (doubling)."""
        fs = self.fs
        m = fs.meta
        new = {}
        need_p = int(m[fk.M_NP]) + 2
        if need_p > len(fs.pts):
            new.update(pts=grown_rows(fs.pts, need_p), met=grown_rows(fs.met, need_p))
            new["vint"] = grown_rows(fs.vint, need_p, -1)
        need_f = int(m[fk.M_NF]) + fk.ROOM_FACES
        if need_f > len(fs.face):
            for name in ("face", "qbox", "qcell", "wkey", "wface"):
                new[name] = grown_rows(getattr(fs, name), need_f)
            new["falive"] = grown_rows(fs.falive, need_f, 0)
            # Four entries per item, one per cell its box may meet.
            new["qnext"] = grown_rows(fs.qnext, 4 * len(new["face"]))
        need_h = int(m[fk.M_NH]) + int(m[fk.M_NW]) + fk.ROOM_FACES
        if need_h > len(fs.hkey):
            new.update(hkey=grown_rows(fs.hkey, need_h), hface=grown_rows(fs.hface, need_h))
        need_t = int(m[fk.M_NT]) + 2
        if need_t > len(fs.tri):
            new.update(tri=grown_rows(fs.tri, need_t), tnext=grown_rows(fs.tnext, need_t))
            new["talive"] = grown_rows(fs.talive, need_t, 0)
        # One spare insertion's nodes: the pair front's kernel asks ROOM_FACES * (Q_ROOM + 1).
        need_q = int(fs.qmeta[Q_NODES]) + fk.ROOM_FACES * (int(fs.qmeta[Q_ROOM]) + 1)
        if need_q > len(fs.qhead):
            # Only the nodes in use are copied and the rest left unset: child_of sets a node's
            # list and children when it makes it, and nearly all of the room stays unused
            # (pairing's three-element: about 3,000 of 58,000 nodes).
            used = int(fs.qmeta[Q_NODES])
            qhead = np.empty(max(need_q, 2 * len(fs.qhead)), dtype=np.int32)
            qhead[:used] = fs.qhead[:used]
            qchild = np.empty(4 * len(qhead), dtype=np.int32)
            qchild[: 4 * used] = fs.qchild[: 4 * used]
            new.update(qhead=qhead, qchild=qchild)
        if new:
            self.fs = fs._replace(**new)

    def advance(self, par) -> int:
        return int(fk.advance(self.fs, par, self.scratch))


def _is_isotropic(field) -> bool:
    """Whether the size field asks for the same spacing in every direction."""
    return not hasattr(field, "metric") or bool(np.all(field.stretch == 1.0))


def _is_uniform(field) -> bool:
    """Whether the metric is the same everywhere (a constant, or a uniform background grid)."""
    if hasattr(field, "metric"):
        return all(np.ptp(v) == 0.0 for v in (field.delta, field.stretch, field.direction))
    return field.constant is not None


def _estimate(points, tris, field, cap) -> int:
    """Triangles a mesh of the given metric needs: metric area / equilateral unit area."""
    a, b, c = points[tris[:, 0]], points[tris[:, 1]], points[tris[:, 2]]
    area = 0.5 * np.abs((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
    m = metric_at(field, (a + b + c) / 3.0, cap)
    det = np.maximum(m[:, 0] * m[:, 2] - m[:, 1] ** 2, 0.0)
    return int(min(1.3 * np.sum(area * np.sqrt(det)) / (np.sqrt(3.0) / 4.0), 2**31 - 1)) + 16


def _adjacency(tris, n: int, segments):
    """Neighbours (t, 3) int32 across the edge opposite each corner (-1: none) and the
    edges lying on input ``segments`` (k, 2), (t, 3) int8."""
    a = tris[:, [1, 2, 0]].ravel().astype(np.int64)
    b = tris[:, [2, 0, 1]].ravel().astype(np.int64)
    key = np.minimum(a, b) * n + np.maximum(a, b)
    order = np.argsort(key, kind="stable")
    same = key[order[1:]] == key[order[:-1]]
    i, j = order[:-1][same], order[1:][same]
    nbr = np.full(len(key), -1, dtype=np.int32)
    nbr[i] = j // 3
    nbr[j] = i // 3
    seg = np.asarray(segments, dtype=np.int64).reshape(-1, 2)
    locked = np.isin(key, np.minimum(seg[:, 0], seg[:, 1]) * n + np.maximum(seg[:, 0], seg[:, 1]))
    return nbr.reshape(-1, 3), locked.astype(np.int8).reshape(-1, 3)


def _halve(ct, too_long, max_rounds: int, what: str):
    """Halve the subsegments of ``ct`` that ``too_long(points, edges)`` ((k, 2) -> (k,) bool)
    selects, round after round (split points on the true curve), until none is selected.

    Returns the splits per segment id, (ids,) int64, and the final (edges, ids) of
    ``ct.segments()``; raises :class:`MeshingError` naming ``what`` if ``max_rounds``
    rounds do not suffice."""
    edges, ids = ct.segments()
    added = np.zeros(int(ids.max()) + 1 if len(ids) else 0, dtype=np.int64)
    for _ in range(max_rounds):
        long = too_long(np.asarray(ct.points), edges)
        if not long.any():
            return added, edges, ids
        for u, w in edges[long].tolist():
            ct.split_segment(u, w)
        added += np.bincount(ids[long], minlength=len(added))
        edges, ids = ct.segments()
    raise MeshingError(f"{what} after {max_rounds} rounds of halving")


def split_long_segments(ct, cap, max_rounds: int = 64) -> int:
    """Split every subsegment of ``ct`` longer than ``cap(midpoint)`` (split points on the true curve).

    Returns the number of splits; raises :class:`MeshingError` if ``max_rounds`` halvings
    do not suffice (a bound far below the geometry's scale).
    """

    def too_long(p, edges):
        a, b = p[edges[:, 0]], p[edges[:, 1]]
        return np.hypot(*(b - a).T) > cap(0.5 * (a + b))

    added, _, _ = _halve(ct, too_long, max_rounds, "segments still longer than the area bound allows")
    return int(added.sum())


def _too_long(pts, edges, field, cap, neighbours):
    """Whether each subsegment (k, 2) is longer than ``GRADE`` sizes of its finer end (its
    metric length in either end's metric above ``GRADE``) or, with ``neighbours``, than
    ``GRADE`` times a subsegment it shares an end with; returns (k,) bool."""
    a, b = pts[edges[:, 0]], pts[edges[:, 1]]
    m = metric_at(field, np.concatenate([a, b]), cap).reshape(2, -1, 3)
    d = b - a
    sq = d[:, 0] ** 2 * m[:, :, 0] + 2.0 * d[:, 0] * d[:, 1] * m[:, :, 1] + d[:, 1] ** 2 * m[:, :, 2]
    long = sq.max(axis=0) > GRADE * GRADE
    if not neighbours:
        return long
    # A piece much longer than a piece it meets (a tiny input feature beside long sides)
    # grades the same way, the discretisation's own lengths standing for the size.
    length = np.hypot(d[:, 0], d[:, 1])
    shortest = np.full(len(pts), np.inf)
    np.minimum.at(shortest, edges[:, 0], length)
    np.minimum.at(shortest, edges[:, 1], length)
    return long | (length > GRADE * np.minimum(shortest[edges[:, 0]], shortest[edges[:, 1]]))


def grade_segments(ct, field, cap=None, neighbours: bool = True) -> int:
    """Halve the subsegments of ``ct`` that are longer than ``GRADE`` sizes of their finer
    end, or than ``GRADE`` times a subsegment they meet.

    Where the size jumps along the boundary (a small-size region, a size field's step), the
    discretisation follows the field faithfully: one segment of the coarse size next to
    the fine ones.  The front cannot lay a good triangle on it: the fine region's graded
    layers put nodes all along it, so it closes on a node near its fine end, a sliver with
    an angle of about fine / coarse radians, and the faces beside it fan in slivers.
    Halving it towards its fine end (at the midpoint, on the true curve where ``ct`` knows
    it) grades the boundary by 2 per piece, as the front grades the interior.  A tiny
    input feature (two vertices 1e-6 of the extent apart) is the same jump with the size
    uniform: the piece beside it is halved towards it until the two are within ``GRADE``
    (2 ``GRADE`` where the parity split below halves a longest piece once more).

    Every segment (id) receives an even number of new vertices, so every loop keeps the
    parity of its node count (the quad pairing needs even loops): an odd count gets one
    more split, at its longest piece.

    Parameters
    ----------
    ct : ConstrainedTriangulation
        Classified; split in place.
    field : SizeField or BackgroundGrid
    cap : callable, optional
        The spacing bound of :func:`area_cap`.
    neighbours : bool
        Also grade by the lengths of meeting pieces (a tiny feature under a uniform size).

    Returns
    -------
    int
        The number of splits.

    Raises
    ------
    MeshingError
        A piece still too long after ``MAX_GRADE_ROUNDS`` halvings (a size going to 0).
    """
    added, edges, ids = _halve(
        ct, lambda p, e: _too_long(p, e, field, cap, neighbours), MAX_GRADE_ROUNDS,
        f"boundary pieces still longer than {GRADE} sizes of their finer end",
    )
    odd = np.flatnonzero(added % 2 == 1)
    if len(odd):
        p = np.asarray(ct.points)
        length = np.hypot(*(p[edges[:, 1]] - p[edges[:, 0]]).T)
        for sid in odd.tolist():
            mine = np.flatnonzero(ids == sid)
            u, w = edges[mine[np.argmax(length[mine])]].tolist()
            ct.split_segment(u, w)
    return int(added.sum()) + len(odd)


def advancing_front(
    ct, size, *, max_area: float | None = None, max_points: int | None = None, max_backoff: int | None = None,
    progress=None, finish: bool = True, grade: bool = False,
):
    """Mesh the inside of a classified constrained triangulation by the advancing front.

    Parameters
    ----------
    ct : ConstrainedTriangulation
        From :func:`meshwright.tri.cdt.cdt_build`, classified; its segments are the
        initial front (split only by ``max_area`` and ``grade``).
    size : number, callable, SizeField or BackgroundGrid
        Spacing; a background grid also gives stretching and direction.
    max_area : float, optional
        Area bound, honoured with the regions' own bounds through the spacing (see
        :func:`area_cap`); subsegments longer than that spacing are split first.  Closing
        triangles may still exceed it: there is no proven factor (on Triangle's la.poly
        1.91x with ``size="boundary"``, 1.88x with ``max_area=0.5`` too, 1.76x with the
        default size, since the clean-up step; 2.49x before it).
    max_points : int, optional
        Cap on the number of nodes.
    max_backoff : int, optional
        Cap on back-offs in all (default: 100 plus one per 1000 estimated triangles).
    progress : callable, optional
        Called with the number of nodes after every batch.
    finish : bool
        Swap diagonals and smooth the nodes after closing (the default); False returns the
        triangles as the front closed them, for a caller that reshapes the mesh itself
        (the quad pairing combines them and smooths the quads).
    grade : bool
        Split the subsegments much longer than the size at their finer end first
        (:func:`grade_segments`: a size jump along the boundary), and keep the
        shortest-first order across the size field's waits (``WAIT_RATIO``); False (the
        default) keeps the boundary and the earlier order, for a caller whose boundary
        must stay as given (paving's void fill, whose angles the new order lowered).

    Returns
    -------
    points : (n, 2) float64
        The triangulation's vertices (``ct.points``) followed by the generated nodes.
    triangles : (t, 3) int32
        Counter-clockwise, covering exactly the inside of ``ct``.

    Raises
    ------
    MeshingError
        A face could not be advanced even after backing off (its ends are named), or a cap
        was hit.
    """
    finish = check_flag(finish, "finish")
    grade = check_flag(grade, "grade")
    field = as_size_field(size)
    cap = area_cap(ct, max_area)
    if cap is not None:
        split_long_segments(ct, cap)
    if grade:
        grade_segments(ct, field, cap)
    faces, free, used, inside_tris = _initial_front(ct)
    pts0 = np.ascontiguousarray(ct.points, dtype=np.float64)
    metric = np.zeros((len(pts0), 3))
    metric[:, 0] = metric[:, 2] = 1.0
    metric[used] = metric_at(field, pts0[used], cap)
    estimate = _estimate(pts0, inside_tris, field, cap)
    point_cap = np.iinfo(np.int32).max if max_points is None else int(max_points)
    fr = _Front(pts0, faces, free, metric, estimate)
    par = np.zeros(fk.P_LEN)
    par[fk.P_CLOSE], par[fk.P_SEARCH] = CLOSE, SEARCH
    par[fk.P_CLEAR_N], par[fk.P_CLEAR_F] = CLEAR_NODE, CLEAR_FACE
    lo, hi = pts0[used].min(axis=0), pts0[used].max(axis=0)
    par[fk.P_DEFER] = 4.0 * float(np.hypot(*(hi - lo))) + 1.0
    par[fk.P_SYNC_EVERY] = SYNC_EVERY
    par[fk.P_MAX_BACKOFF] = 100 + estimate // 1000 if max_backoff is None else int(max_backoff)
    par[fk.P_MAX_DEFER] = MAX_DEFER
    par[fk.P_QMIN] = GOOD
    par[fk.P_CLEAR_E] = CLEAR_EDGE
    par[fk.P_LONG] = LONG
    par[fk.P_MAX_POINTS] = point_cap
    par[fk.P_UNIFORM] = float(np.all(metric[used] == metric[used][0]) and _is_uniform(field) and cap is None)
    # A graded boundary goes with the shortest-first order across the field's waits.
    par[fk.P_WAIT] = fk.WAIT_RATIO if grade else 0.0
    while True:
        code = fr.advance(par)
        fs = fr.fs
        m = fs.meta
        if code == fk.R_ROOM:
            fr.room()
        elif code == fk.R_SYNC:
            lo_i, hi_i = int(m[fk.M_SYNC]), int(m[fk.M_NP])
            fs.met[lo_i:hi_i] = metric_at(field, fs.pts[lo_i:hi_i], cap)
            m[fk.M_SYNC] = hi_i
            if progress is not None:
                progress(hi_i)
        elif code == fk.R_DONE:
            break
        elif code == fk.R_POINTS:
            raise MeshingError(f"the advancing front made {int(m[fk.M_NP])} nodes, above max_points = {point_cap}")
        elif code == fk.R_STUCK:
            f = int(m[fk.M_FAIL])
            a, b = fs.face[f, 0], fs.face[f, 1]
            raise MeshingError(
                f"advancing front: no valid triangle on front face {fmt_point(fs.pts[a])} -> {fmt_point(fs.pts[b])} "
                f"after {int(m[fk.M_BACKOFF])} back-offs (max_backoff = {int(par[fk.P_MAX_BACKOFF])}); "
                "the size field may vary too fast there for the boundary spacing"
            )
        else:
            raise MeshingError(f"advancing front: step cap hit after {int(m[fk.M_STEPS])} steps")
    fs = fr.fs
    nt = int(fs.meta[fk.M_NT])
    tris = np.ascontiguousarray(fs.tri[:nt][fs.talive[:nt] == 1])
    npts = int(fs.meta[fk.M_NP])
    if finish:
        nbr, locked = _adjacency(tris, npts, ct.segments()[0])
        swap_edges(fs.pts, fs.met, tris, nbr, locked, SWAP_PASSES, SWAP_GAIN)
    if finish and _is_isotropic(field):
        fixed = np.zeros(npts, dtype=bool)
        fixed[: len(pts0)] = True
        fs.pts[:npts] = smooth(fs.pts[:npts], tris, ct.segments()[0], passes=SMOOTH_PASSES, fixed=fixed)
        swap_edges(fs.pts, fs.met, tris, nbr, locked, SWAP_PASSES, SWAP_GAIN)
    n0 = len(pts0)
    keep = np.zeros(npts, dtype=bool)
    keep[:n0] = True
    keep[tris.ravel()] = True
    newid = (np.cumsum(keep) - 1).astype(np.int32)
    return fs.pts[:npts][keep].copy(), newid[tris]
