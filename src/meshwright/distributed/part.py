"""Meshing one part on a worker: the serial Delaunay refinement with interfaces as boundary.

Source: L. Linardakis and N. Chrisochoides, "Delaunay decoupling method for parallel
guaranteed quality planar mesh refinement", SIAM J. Sci. Comput. 27(4), 2006: with the
separators discretised beforehand, every part is meshed by the unmodified serial refinement
(here :func:`meshwright.tri.ruppert.refine` on :func:`meshwright.tri.cdt.cdt_build`, the path
of :func:`meshwright.triangulate`).  The part's interface segments are ordinary boundary
segments of its planar straight-line graph (domain on their left), told apart by
``PartPSLG.interface``.  When refinement splits one of them, the mesh is not kept: the new
points on the interface are returned as a *split request* (A. Chernikov and N. Chrisochoides,
"Parallel 2D constrained Delaunay mesh generation", ACM TOMS 34(1), 2008: the split becomes a
message to the neighbour), which :mod:`meshwright.distributed.exchange` turns into the same
split on both sides.

One task per part (:func:`mesh_part`): mesh, write the piece, return a :class:`PartSummary`
(counts, requests, times: a few hundred bytes), so the client never waits on a second task
per part and no mesh stays in a worker's memory; the piece on the shared file system is the
part's state, and a part that meshes again in an exchange round overwrites it.

Layout of a part's mesh (:class:`PartMesh`): ``points`` (q, 2) float64 are the part's own
vertices (not on the skeleton); ``triangles`` and ``lines`` are (t, 3) and (l, 2) int64
*references*: a skeleton id ``g >= 0`` or ``-1 - j`` for own vertex ``j``, so that global
numbering (:mod:`meshwright.distributed.numbering`) needs no coordinates.  The piece is
written with these references; :func:`meshwright.distributed.writer.resolve_pieces` turns
them into global ids once the prefix sums are known.
"""

from __future__ import annotations

import math
import time
from typing import NamedTuple

import numpy as np

from meshwright.distributed.writer import write_part
from meshwright.geometry.curves import Line
from meshwright.tri.cdt import SegmentCurves, cdt_build
from meshwright.tri.ruppert import refine

__all__ = ["INTERFACE_CURVE", "PartMesh", "PartSummary", "build_part", "mesh_part"]

INTERFACE_CURVE = Line((0.0, 0.0), (1.0, 0.0))  # straight: interface splits are midpoints


class PartMesh(NamedTuple):
    """One part's mesh (module docstring), or its split requests when ``requests`` is not empty.

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
    requests : tuple of (int, (k, 2) float64)
        Skeleton interface segment and the points refinement put on it.
    min_angle : float
        Smallest triangle angle, degrees.
    seconds : float
        Time of the meshing task.
    """

    index: int
    points: np.ndarray
    triangles: np.ndarray
    triangle_markers: np.ndarray
    lines: np.ndarray
    line_markers: np.ndarray
    point_markers: np.ndarray
    requests: tuple
    min_angle: float
    seconds: float


class PartSummary(NamedTuple):
    """What the client fetches of a part: counts, requests and times, no mesh arrays.

    Attributes
    ----------
    index : int
    n_points, n_triangles, n_lines : int
        Own vertices, triangles and boundary lines of the piece (0 with requests).
    requests : tuple of (int, (k, 2) float64)
        As :class:`PartMesh`; no piece was written when not empty.
    min_angle : float
    seconds : float
        Meshing time.
    write_seconds : float
        Time writing the piece.
    path : str
        The piece ("" when not written).
    cpu_seconds : float
        CPU time of the task's thread (meshing and writing): what the part costs on a core
        of its own, whatever else the machine runs.
    peak_rss : int
        The worker process's peak resident memory so far, bytes (0 where the platform does
        not report it): checked against the worker's memory limit.
    """

    index: int
    n_points: int
    n_triangles: int
    n_lines: int
    requests: tuple
    min_angle: float
    seconds: float
    write_seconds: float
    path: str
    cpu_seconds: float
    peak_rss: int


def _peak_rss() -> int:
    """Peak resident memory of this process in bytes (``ru_maxrss`` is KiB on Linux); 0 without it."""
    try:
        import resource
    except ImportError:
        return 0
    return int(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss) * 1024


def _min_angle(xy: np.ndarray, tris: np.ndarray) -> float:
    """Smallest angle (degrees) of triangles ``tris`` (t, 3) over points ``xy`` (n, 2)."""
    if len(tris) == 0:
        return 180.0
    p = xy[tris]
    e = np.roll(p, -1, axis=1) - p
    length = np.hypot(e[..., 0], e[..., 1])
    prev = np.roll(e, 1, axis=1)
    cross = np.abs(prev[..., 0] * e[..., 1] - prev[..., 1] * e[..., 0])
    dot = -(prev * e).sum(axis=2)
    return float(np.degrees(np.arctan2(cross, dot)).min()) if length.size else 180.0


def mesh_part(pslg, curves, field, min_angle: float, seed: int, max_points: int, path: str) -> PartSummary:
    """Mesh one part and write its piece (module docstring): the whole work of one task.

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
    path : str
        Where the piece goes (:func:`meshwright.distributed.writer.part_path`).

    Returns
    -------
    PartSummary
        With non-empty ``requests`` (and nothing written) when refinement split an interface.
    """
    cpu0 = time.thread_time()
    pm = build_part(pslg, curves, field, min_angle, seed, max_points)
    if pm.requests:
        return PartSummary(
            pm.index, 0, 0, 0, pm.requests, pm.min_angle, pm.seconds, 0.0, "", time.thread_time() - cpu0,
            _peak_rss(),
        )
    t0 = time.perf_counter()
    write_part(pm, path)
    return PartSummary(
        pm.index, len(pm.points), len(pm.triangles), len(pm.lines), (), pm.min_angle, pm.seconds,
        time.perf_counter() - t0, str(path), time.thread_time() - cpu0, _peak_rss(),
    )


def build_part(pslg, curves, field, min_angle: float, seed: int, max_points: int) -> PartMesh:
    """The mesh of one part, or its split requests (parameters as :func:`mesh_part`).

    Returns
    -------
    PartMesh
        Empty arrays and non-empty ``requests`` when refinement split an interface.
    """
    t0 = time.perf_counter()
    sc = SegmentCurves(tuple(curves) + (INTERFACE_CURVE,), pslg.curve, pslg.params)
    ct = cdt_build(pslg.points, pslg.segments, seed=seed, curves=sc)
    ct.classify(segment_sides=pslg.sides)
    refine(ct, min_angle=min_angle, size=field, max_points=max_points)
    edges, ids = ct.segments()
    xy = ct.points
    iface = pslg.interface[ids]
    counts = np.bincount(ids[iface], minlength=len(pslg.segments))
    split = np.flatnonzero(counts > 1)
    if len(split):
        requests = []
        for j in split.tolist():
            e = edges[ids == j]
            inner = np.setdiff1d(e.ravel(), ct.index_map[pslg.segments[j]])
            requests.append((int(pslg.skeleton_segment[j]), xy[inner].copy()))
        empty = np.zeros((0, 3), dtype=np.int64)
        return PartMesh(
            pslg.index, np.zeros((0, 2)), empty, np.zeros(0, dtype=np.int32), np.zeros((0, 2), dtype=np.int64),
            np.zeros(0, dtype=np.int32), np.zeros(0, dtype=np.int32), tuple(requests), math.nan,
            time.perf_counter() - t0,
        )
    tris = ct.triangles(True)
    gid = np.full(ct.n_points, -1, dtype=np.int64)
    gid[ct.index_map] = pslg.gids
    used = np.zeros(ct.n_points, dtype=bool)
    used[tris.ravel()] = True
    own = used & (gid < 0)
    ref = np.where(gid >= 0, gid, -1 - (np.cumsum(own) - 1))
    keep = ~iface
    lines = edges[keep]
    lmark = pslg.markers[ids[keep]].astype(np.int32)
    pmark = np.zeros(ct.n_points, dtype=np.int32)
    if len(lines):
        np.maximum.at(pmark, lines[:, 0], lmark)
        np.maximum.at(pmark, lines[:, 1], lmark)
    return PartMesh(
        index=pslg.index,
        points=np.ascontiguousarray(xy[own]),
        triangles=ref[tris],
        triangle_markers=ct.triangle_markers(True).astype(np.int32),
        lines=ref[lines].reshape(-1, 2),
        line_markers=lmark,
        point_markers=pmark[own],
        requests=(),
        min_angle=_min_angle(xy, tris),
        seconds=time.perf_counter() - t0,
    )
