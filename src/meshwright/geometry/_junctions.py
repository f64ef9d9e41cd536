r"""Junctions of a domain's straight pieces: vertices on segments, crossing constraints.

A planar straight-line graph as users write it (Triangle's ``.poly`` files, hand-made
domains) often has an interior segment ending in the middle of a boundary segment (a
T-junction), an interior point on a segment, or two interior segments crossing.  Triangle
accepts all three (J. R. Shewchuk, "Triangle: Engineering a 2D Quality Mesh Generator and
Delaunay Triangulator", 1996: a vertex met while a segment is inserted splits it there, and
a segment crossing an existing one is split at their intersection).  This module decides
the same splits for a :class:`~meshwright.geometry.domain.Domain` before it is validated:

* a vertex of a constraint, or an interior point, lying *exactly* (exact ``orient2d`` = 0)
  strictly inside a straight segment of a loop or a constraint splits that segment there;
* a loop vertex lying exactly inside a straight constraint segment splits the constraint;
* two straight constraint segments crossing at one interior point are both split at their
  intersection, rounded to the nearest floating-point coordinates (as Triangle does; the
  pieces then bend by at most half a unit in the last place).  Exact splits go first: a
  round that has any exact split (an end or a point on a segment) defers the crossings, so
  that a point lying exactly on a segment splits it before a rounded crossing bends it;
* anything else stays an error naming both segments: loops touching or crossing each other
  or themselves, a constraint crossing a loop (it would leave the domain), collinear
  overlaps, and junctions on curved pieces (an arc or spline cannot be split exactly).

Only :class:`~meshwright.geometry.curves.Line` and
:class:`~meshwright.geometry.curves.Polyline` pieces are split; a split Polyline keeps its
vertices and gains the new ones (each new segment keeps its parent's marker), a split Line
becomes a chain of Lines with its marker.

Arrays: the domain's fine assembly (``points`` (n, 2) float64, ``segments`` (m, 2) int64,
``seg_curve`` and ``seg_local`` (m,) int64: the curve of each segment and the segment's
index within it, which for straight pieces is the piece's edge index).
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np

from meshwright.core.predicates import orient2d
from meshwright.geometry._kernels import ON_BOUNDARY, classify_points
from meshwright.geometry.curves import Line, Polyline

__all__ = ["apply_splits", "junction_splits", "planarize", "point_splits"]


def _orient(a, b, c) -> int:
    v = orient2d(float(a[0]), float(a[1]), float(b[0]), float(b[1]), float(c[0]), float(c[1]))
    return (v > 0) - (v < 0)


def _strictly_inside(a, b, p) -> bool:
    """For ``p`` collinear with segment ``ab``: whether it lies strictly between a and b."""
    k = 0 if a[0] != b[0] else 1
    lo, hi = min(a[k], b[k]), max(a[k], b[k])
    return bool(lo < p[k] < hi)


def _crossing(a0, a1, b0, b1):
    """Intersection of two properly crossing segments, rounded to the nearest doubles."""
    ax, ay, bx, by = (Fraction(float(v)) for v in (a0[0], a0[1], a1[0], a1[1]))
    cx, cy, dx, dy = (Fraction(float(v)) for v in (b0[0], b0[1], b1[0], b1[1]))
    den = (bx - ax) * (dy - cy) - (by - ay) * (dx - cx)
    t = ((cx - ax) * (dy - cy) - (cy - ay) * (dx - cx)) / den
    return np.array([float(ax + t * (bx - ax)), float(ay + t * (by - ay))])


def _resolve(a0, a1, b0, b1):
    """Splits resolving one offending pair of segments a0-a1 (0) and b0-b1 (1).

    Returns a list of ``(which, point, kind)`` with ``kind`` "end" (an end point of the
    other segment lies strictly inside it) or "cross" (a proper crossing, rounded), or
    None when no split resolves the pair (a collinear overlap, a rounded crossing landing
    on an end point).
    """
    o = [_orient(a0, a1, b0), _orient(a0, a1, b1), _orient(b0, b1, a0), _orient(b0, b1, a1)]
    if o == [0, 0, 0, 0]:
        return None
    out = []
    for p, side, host in ((b0, o[0], 0), (b1, o[1], 0), (a0, o[2], 1), (a1, o[3], 1)):
        h0, h1 = (a0, a1) if host == 0 else (b0, b1)
        if side == 0 and _strictly_inside(h0, h1, p):
            out.append((host, p, "end"))
    if out:
        return out
    if o[0] * o[1] < 0 and o[2] * o[3] < 0:
        x = _crossing(a0, a1, b0, b1)
        if any(np.array_equal(x, q) for q in (a0, a1, b0, b1)):
            return None
        return [(0, x, "cross"), (1, x, "cross")]
    return None


def junction_splits(points, segments, seg_curve, seg_local, curves, is_loop, pairs):
    """Splits resolving a domain's offending segment pairs, or the first pair none resolves.

    Exact splits go first: when any pair has an end inside the other segment, only those
    splits are returned and the crossings wait for a later round.

    Parameters
    ----------
    points : (n, 2) float64
    segments : (m, 2) int64
    seg_curve, seg_local : (m,) int64
        Curve of each segment and its edge index within that curve.
    curves : sequence of Curve
    is_loop : (C,) bool
        Whether each curve belongs to a loop (else to a constraint).
    pairs : (p, 2) int64
        Offending segment pairs (``find_bad_pairs``).

    Returns
    -------
    splits : dict
        ``{(curve, edge): [point (2,) float64, ...]}``, the points at which to split each
        straight edge: the exact splits (ends inside segments) when there are any, else
        the crossings.
    rounded : bool
        Whether ``splits`` are crossings (rounded points).
    culprit : int
        Index into ``pairs`` of the first pair no split resolves, or -1.
    """
    splits: dict = {"end": {}, "cross": {}}
    for k, pair in enumerate(pairs):
        ends = [points[segments[s, 0]] for s in pair] + [points[segments[s, 1]] for s in pair]
        found = _resolve(ends[0], ends[2], ends[1], ends[3])
        if found is None:
            return {}, False, k
        loops = [bool(is_loop[seg_curve[s]]) for s in pair]
        for which, p, kind in found:
            s = pair[which]
            straight = isinstance(curves[int(seg_curve[s])], (Line, Polyline))
            # Loops may not meet loops, and a constraint crossing a loop leaves the domain.
            if not straight or (kind == "end" and all(loops)) or (kind == "cross" and any(loops)):
                return {}, False, k
            key = (int(seg_curve[s]), int(seg_local[s]))
            splits[kind].setdefault(key, []).append(np.asarray(p, dtype=np.float64))
    return (splits["end"], False, -1) if splits["end"] else (splits["cross"], bool(splits["cross"]), -1)


def planarize(points, segments, pairs):
    """Split the segments of a raw graph at its junctions (a ``.poly`` file's, before its
    loops are found): vertices on segments and crossings, as Triangle does.

    Parameters
    ----------
    points : (n, 2) float64
        Distinct vertices.
    segments : (m, 2) int64
    pairs : (p, 2) int64
        Offending segment pairs (``find_bad_pairs``).

    Returns
    -------
    points : (n', 2) float64
        ``points`` followed by the crossings.
    segments : (m', 2) int64
        The split segments, each piece in its parent's direction.
    parent : (m',) int64
        Input segment of each piece.
    culprit : int
        Index into ``pairs`` of the first pair no split resolves (then the other outputs
        are the inputs), or -1.
    """
    found_cuts: dict = {"end": {}, "cross": {}}
    for k, (s, t) in enumerate(pairs):
        found = _resolve(points[segments[s, 0]], points[segments[s, 1]], points[segments[t, 0]], points[segments[t, 1]])
        if found is None:
            return points, segments, np.arange(len(segments)), k
        for which, p, kind in found:
            found_cuts[kind].setdefault(int((s, t)[which]), []).append(np.asarray(p, dtype=np.float64))
    # Exact cuts first: a crossing waits for a round without any (module docstring).
    cuts = found_cuts["end"] or found_cuts["cross"]
    index = {tuple(p): i for i, p in enumerate(points.tolist())}
    extra = []
    out, parent = [], []
    for s in range(len(segments)):
        a, b = int(segments[s, 0]), int(segments[s, 1])
        chain = [a]
        if s in cuts:
            for p in _split_points(points[a], points[b], cuts[s]):
                key = (float(p[0]), float(p[1]))
                if key not in index:
                    index[key] = len(points) + len(extra)
                    extra.append(p)
                chain.append(index[key])
        chain.append(b)
        out.extend(zip(chain[:-1], chain[1:]))
        parent.extend([s] * (len(chain) - 1))
    pts = np.concatenate([points, np.array(extra).reshape(-1, 2)]) if extra else points
    return pts, np.array(out, dtype=np.int64).reshape(-1, 2), np.array(parent, dtype=np.int64), -1


def point_splits(points, segments, seg_curve, seg_local, curves, xy):
    """Interior points lying exactly on a segment: the splits, and which points they absorb.

    Parameters
    ----------
    points : (n, 2) float64
    segments : (m, 2) int64
    seg_curve, seg_local : (m,) int64
    curves : sequence of Curve
    xy : (k, 2) float64
        The domain's interior points.

    Returns
    -------
    splits : dict
        As :func:`junction_splits`.
    keep : (k,) bool
        False for the points that are (or become) vertices of a segment.
    culprit : int
        Index into ``xy`` of a point on a curved piece (no exact split), or -1.
    """
    splits: dict = {}
    keep = np.ones(len(xy), dtype=bool)
    if not len(xy):
        return splits, keep, -1
    a, b = points[segments[:, 0]], points[segments[:, 1]]
    ok = np.isfinite(xy).all(axis=1)
    on = np.zeros(len(xy), dtype=bool)
    on[ok] = classify_points(xy[ok], a, b) == ON_BOUNDARY
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    for i in np.flatnonzero(on):
        p = xy[i]
        if ((points == p).all(axis=1)).any():
            keep[i] = False
            continue
        cand = np.flatnonzero((lo <= p).all(axis=1) & (p <= hi).all(axis=1))
        hosts = [int(s) for s in cand if _orient(a[s], b[s], p) == 0 and _strictly_inside(a[s], b[s], p)]
        if not hosts:
            continue
        if not all(isinstance(curves[int(seg_curve[s])], (Line, Polyline)) for s in hosts):
            return {}, keep, int(i)
        keep[i] = False
        for s in hosts:
            splits.setdefault((int(seg_curve[s]), int(seg_local[s])), []).append(np.asarray(p, dtype=np.float64))
    return splits, keep, -1


def _split_points(p0, p1, extra):
    """``extra`` points on segment p0-p1, distinct, ordered from p0 to p1."""
    d = p1 - p0
    uniq = np.unique(np.array(extra).reshape(-1, 2), axis=0)
    order = np.argsort((uniq - p0) @ d, kind="stable")
    return uniq[order]


def apply_splits(chains, first_curve, splits):
    """Chains of curves with the split edges replaced.

    Parameters
    ----------
    chains : sequence of tuple of Curve
        Loops then constraints, in the domain's curve order.
    first_curve : sequence of int
        Global index of each chain's first curve.
    splits : dict
        ``{(curve, edge): [points]}`` from :func:`junction_splits` / :func:`point_splits`.

    Returns
    -------
    list of tuple of Curve
    """
    out = []
    for chain, c0 in zip(chains, first_curve):
        new = []
        for j, c in enumerate(chain):
            cid = c0 + j
            edges = sorted(e for (cc, e) in splits if cc == cid)
            if not edges:
                new.append(c)
            elif isinstance(c, Line):
                pts = [c.p0, *_split_points(c.p0, c.p1, splits[(cid, 0)]), c.p1]
                new.extend(Line(p, q, c.marker) for p, q in zip(pts[:-1], pts[1:]))
            else:
                verts, marks = [c.points[0]], []
                for e in range(len(c.points) - 1):
                    inner = _split_points(c.points[e], c.points[e + 1], splits[(cid, e)]) if (cid, e) in splits else []
                    verts.extend(inner)
                    verts.append(c.points[e + 1])
                    if c.markers is not None:
                        marks.extend([c.markers[e]] * (len(inner) + 1))
                new.append(Polyline(np.array(verts), None if c.markers is None else np.array(marks), marker=c.marker))
        out.append(tuple(new))
    return out
