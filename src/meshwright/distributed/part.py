"""Meshing one part on a worker: Delaunay refinement with frozen interfaces, resumed after rounds.

Source: L. Linardakis and N. Chrisochoides, "Delaunay decoupling method for parallel
guaranteed quality planar mesh refinement", SIAM J. Sci. Comput. 27(4), 2006: with the
separators discretised beforehand, every part is meshed by the serial refinement (here
:func:`meshwright.tri.ruppert.refine` on :func:`meshwright.tri.cdt.cdt_build`, the path of
:func:`meshwright.triangulate`).  The part's interface segments are boundary segments of its
planar straight-line graph (domain on their left), told apart by ``PartPSLG.interface``, and
*frozen*: refinement never splits them itself but reports the subsegments it needed split
(``ct.held``).  A. Chernikov and N. Chrisochoides, "Parallel 2D constrained Delaunay mesh
generation", ACM TOMS 34(1), 2008: such a split becomes a message to the neighbour, which
makes the same split (:mod:`meshwright.distributed.exchange`).

Splits of an interface: a held subsegment ``a-b`` is split at ``0.5 * (P[a] + P[b])``, the
serial refinement's midpoint.  Both ends of every interface subsegment lie at dyadic
fractions of their skeleton segment ``s`` (counted from its end with the smaller skeleton id,
which both parts know), so a split point is named by ``(s, f)`` with ``f`` a
:class:`fractions.Fraction`, and its coordinates, computed from the same two points by the
same formula, are the same bits in both parts.  The part makes the splits it needs itself
(:func:`_settle`: refine, split what is held, refine again, until nothing is held) and
reports them; a neighbour makes them in the next round (:func:`resume_part`), which may need
more: rounds end when both sides of every interface hold the same points.

Invariants: a part never splits an interface subsegment except at its midpoint; every vertex
on an interface has a name (``PartState.names``); a state handed to a task is never modified.

State between rounds (:class:`PartState`): the triangulation stays on its worker as a Dask
future (``__sizeof__`` gives its bytes, so Dask counts it against the worker's memory and
may spill it); a resume works on a copy, so a task Dask runs again (lost worker) starts from
the same state and the output does not depend on it.  After the last round
:func:`write_part_state` numbers the part's vertices (global ids: skeleton ids, the split
points' ids, then ``offset + j`` for own vertex ``j``) and writes its piece.

Layout of a written piece (:class:`PartMesh`): ``points`` (q, 2) float64 the part's own
vertices (not on the skeleton), ``triangles`` (t, 3) and ``lines`` (l, 2) int64 global ids.
"""

from __future__ import annotations

import copy
import time
from fractions import Fraction
from typing import NamedTuple

import numpy as np
from numba import njit

from meshwright.core.errors import MeshingError
from meshwright.distributed.writer import write_part
from meshwright.geometry.curves import Line
from meshwright.tri.cdt import SegmentCurves, cdt_build
from meshwright.tri.ruppert import refine, split_subsegment

__all__ = [
    "INTERFACE_CURVE", "MAX_LOCAL_SPLITS", "PartMesh", "PartReport", "PartState", "PartSummary", "min_angle_of",
    "part_mesh", "report_of", "resume_part", "start_part", "write_part_state",
]

INTERFACE_CURVE = Line((0.0, 0.0), (1.0, 0.0))  # straight: interface splits are midpoints
# Refine / split passes in one task: each pass halves every held subsegment once, so this
# bounds the depth of splitting an interface below its skeleton spacing (2^-64: far below
# double precision; reaching it means refinement cannot settle).
MAX_LOCAL_SPLITS = 64


class PartMesh(NamedTuple):
    """One part's piece as written (module docstring).

    Attributes
    ----------
    index : int
    points : (q, 2) float64
    triangles : (t, 3) int64
    triangle_markers : (t,) int32
    lines : (l, 2) int64
        Loop and constraint subsegments (not interfaces), counter-clockwise around the domain.
    line_markers : (l,) int32
    point_markers : (q,) int32
        Largest marker of the lines at each own vertex (0 inside).
    """

    index: int
    points: np.ndarray
    triangles: np.ndarray
    triangle_markers: np.ndarray
    lines: np.ndarray
    line_markers: np.ndarray
    point_markers: np.ndarray


class PartReport(NamedTuple):
    """What the client fetches of a part after a round: a few hundred bytes, no mesh arrays.

    Attributes
    ----------
    index : int
    splits : tuple of (int, Fraction)
        Interface points this task created, ``(skeleton segment, fraction)``.
    xy : (k, 2) float64
        Their coordinates.
    n_own : int
        Own vertices of the part's mesh so far (used by a triangle, not on the skeleton).
    n_triangles : int
    seconds, cpu_seconds : float
        Wall time of the task, and CPU time of its thread (what the part costs on a core of
        its own, whatever else the machine runs).
    peak_rss : int
        The worker process's peak resident memory so far, bytes (0 where not reported).
    state_bytes : int
        Bytes of the :class:`PartState` kept on the worker.
    """

    index: int
    splits: tuple
    xy: np.ndarray
    n_own: int
    n_triangles: int
    seconds: float
    cpu_seconds: float
    peak_rss: int
    state_bytes: int


class PartSummary(NamedTuple):
    """A written piece: what :func:`meshwright.distributed.writer.write_mesh` needs, and times.

    Attributes
    ----------
    index, n_points, n_triangles, n_lines : int
        Own vertices, triangles and boundary lines of the piece.
    min_angle : float
        Smallest triangle angle, degrees.
    seconds, cpu_seconds : float
        Wall and thread CPU time of the writing task.
    path : str
    peak_rss : int
    """

    index: int
    n_points: int
    n_triangles: int
    n_lines: int
    min_angle: float
    seconds: float
    cpu_seconds: float
    path: str
    peak_rss: int


class PartState:
    """A part between rounds: its triangulation and the names of its interface split points.

    Attributes
    ----------
    pslg : PartPSLG
    ct : ConstrainedTriangulation
    field : SizeField
    min_angle : float
    max_points : int
    frozen : (f,) int64
        Its interface segments (pslg rows, the CDT's segment ids).
    names : dict
        ``(s, Fraction) -> vertex`` for every vertex on an interface, ends included.
    report : PartReport
        Of the task that made this state (None until it is set).
    """

    def __init__(self, pslg, ct, field, min_angle: float, max_points: int):
        self.pslg, self.ct, self.field = pslg, ct, field
        self.min_angle, self.max_points = float(min_angle), int(max_points)
        self.frozen = np.flatnonzero(pslg.interface).astype(np.int64)
        self.names = {}
        self.report = None
        # Fractions run from the end with the smaller skeleton id: both parts name a point alike.
        for j in self.frozen.tolist():
            s = int(pslg.skeleton_segment[j])
            u, w = (int(v) for v in pslg.segments[j])
            if pslg.gids[u] > pslg.gids[w]:
                u, w = w, u
            self.names[(s, Fraction(0))] = int(ct.index_map[u])
            self.names[(s, Fraction(1))] = int(ct.index_map[w])

    def __sizeof__(self) -> int:
        s, c = self.ct.state, self.ct.constraints
        arrays = tuple(s) + tuple(c) + tuple(self.pslg[1:])
        return int(sum(a.nbytes for a in arrays if isinstance(a, np.ndarray))) + 64 * len(self.names)


def _peak_rss() -> int:
    """Peak resident memory of this process in bytes (``ru_maxrss`` is KiB on Linux); 0 without it."""
    try:
        import resource
    except ImportError:
        return 0
    return int(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss) * 1024


@njit(cache=True, nogil=True)
def _largest_cosine(pts, tri):
    """Largest cosine of a triangle's smallest angle over triangles ``tri`` (3 t,) int32 of
    ``pts`` (n, 2) float64: that angle is opposite the shortest side ``a``, ``cos = (b^2 + c^2 -
    a^2) / (2 b c)`` from the squared sides alone."""
    worst = -1.0
    for t in range(tri.shape[0] // 3):
        u, v, w = tri[3 * t], tri[3 * t + 1], tri[3 * t + 2]
        a2 = (pts[v, 0] - pts[u, 0]) ** 2 + (pts[v, 1] - pts[u, 1]) ** 2
        b2 = (pts[w, 0] - pts[v, 0]) ** 2 + (pts[w, 1] - pts[v, 1]) ** 2
        c2 = (pts[u, 0] - pts[w, 0]) ** 2 + (pts[u, 1] - pts[w, 1]) ** 2
        m = min(a2, b2, c2)
        cos = (a2 + b2 + c2 - 2.0 * m) / (2.0 * np.sqrt(a2 * b2 * c2 / m))
        worst = max(worst, cos)
    return worst


def min_angle_of(points: np.ndarray, triangles: np.ndarray) -> float:
    """Smallest angle (degrees) of ``triangles`` (t, 3) int over ``points`` (n, 2) float64."""
    if len(triangles) == 0:
        return 180.0
    tri = np.ascontiguousarray(triangles, dtype=np.int32).ravel()
    return float(np.degrees(np.arccos(min(1.0, _largest_cosine(np.ascontiguousarray(points), tri)))))


def _split(st: PartState, s: int, fa: Fraction, fb: Fraction, xy) -> Fraction:
    """Split the interface subsegment between names ``(s, fa)`` and ``(s, fb)`` at ``xy``."""
    f = (fa + fb) / 2
    v = split_subsegment(st.ct, st.names[(s, fa)], st.names[(s, fb)], xy)
    st.names[(s, f)] = int(v)
    return f


def _settle(st: PartState, made: list) -> None:
    """Refine with the interfaces frozen, split what was held, until nothing is held.

    Appends ``(s, Fraction)`` of every split made to ``made``.
    """
    # A vertex where two interface segments meet has a name on each: look up by segment.
    frac = {(k[0], v): k[1] for k, v in st.names.items()}
    for _ in range(MAX_LOCAL_SPLITS):
        refine(st.ct, min_angle=st.min_angle, size=st.field, max_points=st.max_points, frozen=st.frozen)
        edges, ids = st.ct.held
        if len(edges) == 0:
            return
        for (a, b), j in zip(edges.tolist(), ids.tolist()):
            s = int(st.pslg.skeleton_segment[j])
            # Read the points anew: a split may have moved them to larger arrays.
            pts = st.ct.points
            f = _split(st, s, frac[(s, a)], frac[(s, b)], 0.5 * (pts[a] + pts[b]))
            frac[(s, st.names[(s, f)])] = f
            made.append((s, f))
    x, y = st.ct.points[a]
    raise MeshingError(
        f"part {st.pslg.index}: refinement still needs interface splits after {MAX_LOCAL_SPLITS} passes "
        f"(near ({x:.17g}, {y:.17g})): the size field cannot be met along the cut"
    )


def _report(st: PartState, made: list, t0: float, cpu0: float) -> PartReport:
    ct = st.ct
    xy = np.array([ct.points[st.names[k]] for k in made], dtype=np.float64).reshape(-1, 2)
    tris = ct.triangles(True)
    # Own vertices: used by a triangle, neither skeleton points nor interface splits.
    own = np.zeros(ct.n_points, dtype=bool)
    own[tris.ravel()] = True
    own[ct.index_map] = False
    own[np.fromiter(st.names.values(), dtype=np.int64, count=len(st.names))] = False
    return PartReport(
        st.pslg.index, tuple(made), xy, int(np.count_nonzero(own)), len(tris), time.perf_counter() - t0,
        time.thread_time() - cpu0, _peak_rss(), st.__sizeof__(),
    )


def start_part(pslg, curves, field, min_angle: float, seed: int, max_points: int) -> PartState:
    """Round 0 of one part: build its CDT and refine it with the interfaces frozen.

    Parameters
    ----------
    pslg : PartPSLG
    curves : tuple of Curve
        ``Domain.curves``; interfaces use :data:`INTERFACE_CURVE`, appended here.
    field : SizeField
    min_angle : float
        Degrees.
    seed : int
        Insertion order of this part (derived from the run's seed and the part index).
    max_points : int
        Cap on the part's vertices.

    Returns
    -------
    PartState
        With ``report`` (:class:`PartReport`) set: what :func:`report_of` hands the client.
    """
    t0, cpu0 = time.perf_counter(), time.thread_time()
    sc = SegmentCurves(tuple(curves) + (INTERFACE_CURVE,), pslg.curve, pslg.params)
    ct = cdt_build(pslg.points, pslg.segments, seed=seed, curves=sc)
    ct.classify(segment_sides=pslg.sides)
    st = PartState(pslg, ct, field, min_angle, max_points)
    made = []
    _settle(st, made)
    # Kept on the worker until the pieces are written: without the refinement's spare room.
    st.ct.shrink()
    st.report = _report(st, made, t0, cpu0)
    return st


def resume_part(state: PartState, splits) -> PartState:
    """A later round: make the neighbours' splits on this part's interfaces, then settle again.

    Parameters
    ----------
    state : PartState
        Not modified (a copy is resumed).
    splits : sequence of (int, Fraction, float, float)
        ``(s, f, x, y)``: skeleton segment, fraction and coordinates of each split point this
        part lacks, shallowest first (so both ends of each are already vertices).

    Returns
    -------
    PartState
        With a new ``report``.

    Raises
    ------
    MeshingError
        A split point whose coordinates differ from this part's midpoint (the two sides
        would not match), or no settling within :data:`MAX_LOCAL_SPLITS` passes.
    """
    t0, cpu0 = time.perf_counter(), time.thread_time()
    # The size field and the graph are only read: shared, not copied (the memo maps them to themselves).
    st = copy.deepcopy(state, {id(state.field): state.field, id(state.pslg): state.pslg})
    for s, f, x, y in splits:
        half = Fraction(1, f.denominator)
        fa, fb = f - half, f + half
        pa, pb = st.ct.points[st.names[(s, fa)]], st.ct.points[st.names[(s, fb)]]
        mid = 0.5 * (pa + pb)
        if mid[0] != x or mid[1] != y:
            raise MeshingError(
                f"part {st.pslg.index}: split point ({x!r}, {y!r}) of skeleton segment {s} at {f} is not the "
                f"midpoint ({mid[0]!r}, {mid[1]!r}) of its subsegment here"
            )
        _split(st, s, fa, fb, mid)
    made = []
    _settle(st, made)
    # Kept on the worker until the pieces are written: without the refinement's spare room.
    st.ct.shrink()
    st.report = _report(st, made, t0, cpu0)
    return st


def report_of(state: PartState) -> PartReport:
    """The small report of a state (a task of its own: the state stays on its worker)."""
    return state.report


def part_mesh(state: PartState, split_ids: dict, offset: int) -> PartMesh:
    """The part's mesh with global vertex ids (module docstring).

    Parameters
    ----------
    state : PartState
    split_ids : dict
        ``(s, Fraction) -> global id`` of the interface split points (of this part's segments).
    offset : int
        Global id of the part's first own vertex.
    """
    st, ct, pslg = state, state.ct, state.pslg
    tris = ct.triangles(True)
    gid = np.full(ct.n_points, -1, dtype=np.int64)
    gid[ct.index_map] = pslg.gids
    for key, v in st.names.items():
        if key[1] not in (0, 1):
            gid[v] = split_ids[key]
    used = np.zeros(ct.n_points, dtype=bool)
    used[tris.ravel()] = True
    own = used & (gid < 0)
    gid[own] = offset + np.arange(np.count_nonzero(own), dtype=np.int64)
    edges, ids = ct.segments()
    keep = ~pslg.interface[ids]
    lines = edges[keep]
    lmark = pslg.markers[ids[keep]].astype(np.int32)
    pmark = np.zeros(ct.n_points, dtype=np.int32)
    if len(lines):
        np.maximum.at(pmark, lines[:, 0], lmark)
        np.maximum.at(pmark, lines[:, 1], lmark)
    return PartMesh(
        index=pslg.index,
        points=np.ascontiguousarray(ct.points[own]),
        triangles=gid[tris],
        triangle_markers=ct.triangle_markers(True).astype(np.int32),
        lines=gid[lines].reshape(-1, 2),
        line_markers=lmark,
        point_markers=pmark[own],
    )


def write_part_state(state: PartState, split_ids: dict, offset: int, path: str) -> PartSummary:
    """Number the part's vertices and write its piece (the last task of a part).

    Parameters
    ----------
    state : PartState
    split_ids : dict
        As :func:`part_mesh`.
    offset : int
    path : str
        Where the piece goes (:func:`meshwright.distributed.writer.part_path`).

    Returns
    -------
    PartSummary
    """
    t0, cpu0 = time.perf_counter(), time.thread_time()
    pm, angle = part_mesh(state, split_ids, offset), min_angle_of(state.ct.points, state.ct.triangles(True))
    write_part(pm, path)
    return PartSummary(
        pm.index, len(pm.points), len(pm.triangles), len(pm.lines), angle, time.perf_counter() - t0,
        time.thread_time() - cpu0, str(path), _peak_rss(),
    )

