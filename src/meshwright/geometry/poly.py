"""Triangle ``.poly`` files as :class:`~meshwright.geometry.Domain` objects.

The file is parsed by :func:`meshwright.geometry.poly_format.parse_poly` (the one parser
of the format, shared with :mod:`meshwright.io`; grammar, Triangle's rules and errors are
documented there) and written by :func:`~meshwright.geometry.poly_format.write_poly_file`.

Triangle (J. R. Shewchuk, 1996) treats every segment as a constraint and removes the
triangles reachable from a hole seed or from the outside without crossing a segment.
:func:`read_poly` rebuilds that meaning as loops: the segment graph is split into faces
(half-edges sorted by angle around each vertex, faces oriented by their signed area, both
decided exactly: ``orient2d`` and rational sums, floats only as a filter); a face holding
a hole seed is a hole, faces enclosed by segments and holding no seed are domain;
segments between domain and
non-domain form the loops (as :class:`~meshwright.geometry.curves.Polyline` curves keeping
the segment markers, 0 turned into 1 on the boundary as Triangle does), segments inside
the domain become interior constraints and segments outside it are dropped.  Vertices on
no segment become interior points when they lie inside the domain.  Vertex attributes and
markers are not kept.  Regional attributes are kept as the Domain's
``region_attributes``; an integral one is also the region's marker (non-integral ones get
marker 0).  Segments that close no boundary (none, open chains, or every enclosed face a
hole) are closed as Triangle's ``-c`` closes them, by the edges of the vertices' convex
hull (marker 1 where no segment lies), and the Domain is flagged ``open_boundary``.
Before the faces are found, a vertex lying on a segment splits it and crossing segments
are split at their intersection, as Triangle does (:mod:`meshwright.geometry._junctions`);
overlapping segments stay an error.
"""

from __future__ import annotations

from fractions import Fraction
from functools import cmp_to_key
from os import PathLike
from pathlib import Path

import numpy as np

from meshwright.core.errors import GeometryError, InputError, fmt_point
from meshwright.core.predicates import orient2d, orient2d_batch
from meshwright.geometry._discretize import unique_rows
from meshwright.geometry._junctions import planarize
from meshwright.geometry._kernels import (
    INSIDE,
    classify_points,
    find_bad_pairs,
    parity_by_label,
    trace_chains,
)
from meshwright.geometry.curves import Polyline
from meshwright.geometry.domain import Discretization, Domain
from meshwright.geometry.poly_format import PolyData, parse_poly, write_poly_file

__all__ = ["read_poly", "write_poly"]

_JUNCTION_ROUNDS = 64  # rounds of junction splits (a crossing's rounded point may meet another segment)
_JUNCTION_PAIRS = 4096  # offending pairs resolved per round


def _angular_order(xy: np.ndarray, org: np.ndarray, dst: np.ndarray) -> np.ndarray:
    """Half-edges sorted by origin, then counter-clockwise by direction from the +x axis.

    The order decides which faces the segments bound, so it is exact: a direction's half
    plane (angles in [0, pi) or [pi, 2 pi)) comes from the signs of its coordinate
    differences, which floating-point subtraction always gets right, and the order within
    a half from ``orient2d``.  ``arctan2`` only gives the first guess: it ties or swaps
    directions closer than its rounding (about 1e-16 rad), so every origin whose
    neighbouring half-edges the exact test finds out of order is sorted again with it.

    Parameters
    ----------
    xy : (n, 2) float64
    org, dst : (2m,) int64
        Origin and head of every half-edge; no two half-edges from one origin share a
        direction (overlapping segments are rejected before).

    Returns
    -------
    (2m,) int64
        Half-edge indices in that order.
    """
    d = xy[dst] - xy[org]
    lower = (d[:, 1] < 0) | ((d[:, 1] == 0) & (d[:, 0] < 0))
    guess = np.arctan2(d[:, 1], d[:, 0])
    guess = np.where(lower & (guess > 0), guess - 2 * np.pi, guess)  # pi itself leads its half
    order = np.lexsort((guess, lower, org))
    a, b = order[:-1], order[1:]
    same = np.flatnonzero((org[a] == org[b]) & (lower[a] == lower[b]))
    if len(same):
        tri = np.column_stack([org[a[same]], dst[a[same]], dst[b[same]]])
        wrong = same[orient2d_batch(xy, tri) <= 0]
        for o in np.unique(org[a[wrong]]):
            fan = np.flatnonzero(org[order] == o)
            order[fan] = sorted(order[fan], key=cmp_to_key(lambda e, f: _ccw_compare(xy, org, dst, lower, e, f)))
    return order


def _ccw_compare(xy, org, dst, lower, e: int, f: int) -> int:
    """-1 when half-edge ``e`` comes before ``f`` counter-clockwise around their origin."""
    if lower[e] != lower[f]:
        return -1 if lower[f] else 1
    o, p, q = xy[org[e]], xy[dst[e]], xy[dst[f]]
    turn = orient2d(o[0], o[1], p[0], p[1], q[0], q[1])
    return -1 if turn > 0 else (1 if turn < 0 else 0)


def _faces(xy: np.ndarray, seg: np.ndarray):
    """Faces of a planar segment graph; half-edge ``e < m`` is ``seg[e]``, ``e + m`` its twin.

    Returns the face of each half-edge (faces to the left, bounded ones counter-clockwise),
    each face's signed area (float), whether it is positive (exact), and the half-edges'
    origins and heads.
    """
    m = len(seg)
    org = np.concatenate([seg[:, 0], seg[:, 1]])
    dst = np.concatenate([seg[:, 1], seg[:, 0]])
    order = _angular_order(xy, org, dst)
    pos = np.empty(2 * m, dtype=np.int64)
    pos[order] = np.arange(2 * m)
    deg = np.bincount(org, minlength=len(xy))
    first = np.concatenate([[0], np.cumsum(deg)])[:-1]
    twin = (np.arange(2 * m) + m) % (2 * m)
    # Next half-edge of the face: the one clockwise-before the twin around the head vertex.
    v = dst
    nxt = order[first[v] + (pos[twin] - first[v] - 1) % deg[v]]
    label = np.arange(2 * m)
    jump = nxt.copy()
    for _ in range(int(np.ceil(np.log2(2 * m))) + 1):
        label = np.minimum(label, label[jump])
        jump = jump[jump]
    _, face = np.unique(label, return_inverse=True)
    cross = xy[org, 0] * xy[dst, 1] - xy[dst, 0] * xy[org, 1]
    area = 0.5 * np.bincount(face, cross)
    # Bounded faces are the counter-clockwise ones: a topological decision, so the sign of
    # the float shoelace sum is trusted only above its rounding error bound (each term
    # errs by at most 2u|term|, the sum of k terms by (k - 1)u more); faces below it are
    # summed again in exact rationals.
    size = np.bincount(face, minlength=len(area))
    magnitude = np.bincount(face, np.abs(xy[org, 0] * xy[dst, 1]) + np.abs(xy[dst, 0] * xy[org, 1]))
    bound = (size + 2) * 2.0**-52 * magnitude
    positive = area > 0
    for f in np.flatnonzero(np.abs(area) <= bound):
        he = np.flatnonzero(face == f)
        exact = sum(
            Fraction(xy[o, 0]) * Fraction(xy[t, 1]) - Fraction(xy[t, 0]) * Fraction(xy[o, 1])
            for o, t in zip(org[he].tolist(), dst[he].tolist())
        )
        positive[f] = exact > 0
    return face, area, positive, org, dst


def _regions(data: PolyData) -> tuple[list[tuple[float, float, int, float | None]], list[float]]:
    """Region seeds of ``data`` as :class:`Domain` regions and their regional attributes.

    An integral attribute is also the region's marker; any other gets marker 0 and lives
    on as the attribute alone.
    """
    out, attributes = [], []
    for x, y, attribute, area in data.regions:
        integral = attribute == round(attribute) and abs(attribute) <= np.iinfo(np.int32).max
        out.append((float(x), float(y), int(attribute) if integral else 0, float(area) if area > 0 else None))
        attributes.append(float(attribute))
    return out, attributes


def _hull_edges(xy: np.ndarray) -> np.ndarray:
    """(k, 2) int64 edges of the convex hull of distinct points, counter-clockwise.

    Andrew's monotone chain (A. M. Andrew, "Another efficient algorithm for convex hulls in
    two dimensions", 1979) with exact turns (``orient2d``); a point on a hull edge stays a
    hull vertex (only strict right turns are popped), as Triangle's ``-c`` keeps it.
    """
    order = np.lexsort((xy[:, 1], xy[:, 0])).tolist()

    def chain(idx):
        out = []
        for i in idx:
            while len(out) >= 2 and orient2d(*xy[out[-2]], *xy[out[-1]], *xy[i]) < 0:
                out.pop()
            out.append(i)
        return out

    loop = chain(order)[:-1] + chain(order[::-1])[:-1]
    if len(set(loop)) < max(len(loop), 3):
        # Collinear points: both chains run along the same line; no hull encloses area.
        return np.zeros((0, 2), dtype=np.int64)
    return np.column_stack([loop, np.roll(loop, -1)]).astype(np.int64)


def read_poly(path) -> Domain:
    """Read a Triangle ``.poly`` file as a :class:`Domain`.

    Parameters
    ----------
    path : str or Path
        The ``.poly`` file; with 0 vertices declared, its vertices are read from the
        ``.node`` file of the same base name.

    Returns
    -------
    Domain

    Raises
    ------
    InputError
        ``path`` is not a str or path.
    FormatError
        Missing, unreadable or malformed file (message names file and line; see
        :func:`~meshwright.geometry.poly_format.parse_poly`).
    GeometryError
        Overlapping segments, touching loops, or nothing enclosed even by the convex hull
        (message names the file and the segments' lines).
    """
    if not isinstance(path, (str, PathLike)):
        raise InputError(f"read_poly needs a file path, got {type(path).__name__}")
    path = Path(path)
    data = parse_poly(path)
    xy, seg0, marks, holes = data.vertices, data.segments, data.segment_markers, data.holes
    slines = data.segment_lines
    regions, attributes = _regions(data)
    verts, inv = unique_rows(xy)
    seg = inv[seg0]
    zero = np.flatnonzero(seg[:, 0] == seg[:, 1])
    if len(zero):
        raise GeometryError(f"{path}, line {slines[zero[0]]}: segment has zero length")
    key = np.sort(seg, axis=1)
    _, first, count = np.unique(key, axis=0, return_index=True, return_counts=True)
    if (count > 1).any():
        dup = np.flatnonzero((key == key[first[np.flatnonzero(count > 1)[0]]]).all(axis=1))
        raise GeometryError(
            f"{path}, line {slines[dup[1]]}: segment duplicates the one on line {slines[dup[0]]}"
        )
    verts, seg, marks, slines = _planar(verts, seg, marks, slines, path)
    found = _loops(verts, seg, marks, holes, path) if len(seg) >= 3 else None
    open_boundary = found is None
    if open_boundary:
        # Triangle's -c: the convex hull closes what the segments leave open; its edges
        # that are no segment carry marker 1.
        hull = _hull_edges(verts)
        new = hull[~np.isin(_edge_keys(hull, len(verts)), _edge_keys(seg, len(verts)))]
        seg = np.concatenate([seg, new])
        if marks is not None:
            marks = np.concatenate([marks, np.ones(len(new), dtype=marks.dtype)])
        bad = find_bad_pairs(verts, seg, 1)
        if len(bad):
            s = bad[0, 0] if bad[0, 0] < len(slines) else bad[0, 1]
            raise GeometryError(
                f"{path}, line {slines[s]}: segment overlaps the convex hull that closes the open segments "
                "(split it at the vertices on it)"
            )
        found = _loops(verts, seg, marks, holes, path) if len(hull) else None
        if found is None:
            raise GeometryError(f"{path}: the vertices and segments enclose no region outside the holes")
    loops, constraints, boundary = found
    used = np.zeros(len(verts), dtype=bool)
    used[seg.ravel()] = True
    iso = verts[~used]
    if len(iso):
        b = np.flatnonzero(boundary)
        where = classify_points(iso, verts[seg[b, 0]], verts[seg[b, 1]])
        iso = iso[where != 0]
    try:
        return Domain(
            loops[0], loops[1:], segments=constraints, points=iso, regions=regions,
            region_attributes=attributes, open_boundary=open_boundary,
        )
    except GeometryError as exc:
        raise GeometryError(f"{path}: {exc}") from exc


def _planar(verts, seg, marks, slines, path: Path):
    """The segment graph split at its junctions (:func:`~meshwright.geometry._junctions.planarize`):
    vertices lying on segments and crossing segments, as Triangle splits them."""
    for _ in range(_JUNCTION_ROUNDS):
        bad = find_bad_pairs(verts, seg, _JUNCTION_PAIRS)
        if not len(bad):
            return verts, seg, marks, slines
        verts, seg, parent, culprit = planarize(verts, seg, bad)
        if culprit >= 0:
            s, t = bad[culprit]
            raise GeometryError(f"{path}: segments on lines {slines[s]} and {slines[t]} overlap or intersect")
        marks = None if marks is None else marks[parent]
        slines = np.asarray(slines)[parent]
    raise GeometryError(
        f"{path}: segment junctions still need splits after {_JUNCTION_ROUNDS} rounds of up to {_JUNCTION_PAIRS}"
    )


def _edge_keys(seg: np.ndarray, n: int) -> np.ndarray:
    """(m,) int64: one key per undirected edge."""
    return np.minimum(seg[:, 0], seg[:, 1]).astype(np.int64) * n + np.maximum(seg[:, 0], seg[:, 1])


def _loops(verts, seg, marks, holes, path: Path):
    """Boundary loops, interior constraints and the boundary-segment mask of a segment
    graph, or None when the segments close no boundary (none, or open chains)."""
    m = len(seg)
    face, area, positive, org, dst = _faces(verts, seg)
    bounded = np.flatnonzero(positive)
    # Smallest bounded face containing each query point (-1: the unbounded exterior).
    he = np.flatnonzero(np.isin(face, bounded))
    lab = np.searchsorted(bounded, face[he])

    def containing(q):
        if len(q) == 0 or len(bounded) == 0:
            return np.full(len(q), -1, dtype=np.int64)
        par = parity_by_label(
            np.ascontiguousarray(q, dtype=np.float64),
            verts[org[he]],
            verts[dst[he]],
            lab,
            len(bounded),
        )
        a = np.where(par == INSIDE, area[bounded][None, :], np.inf)
        best = np.argmin(a, axis=1)
        return np.where(np.isfinite(a[np.arange(len(q)), best]), bounded[best], -1)

    hole_faces = containing(holes)
    # Each component's outer face lies in the face containing one of its vertices.
    outer_faces = np.flatnonzero(~positive)
    _, first_he = np.unique(face, return_index=True)
    probe = verts[org[first_he[outer_faces]]]
    enclosing = np.full(len(area), -1, dtype=np.int64)
    enclosing[outer_faces] = containing(probe)
    enclosing[bounded] = bounded
    inside = np.zeros(len(area) + 1, dtype=bool)  # last entry: the exterior
    inside[bounded] = True
    inside[hole_faces[hole_faces >= 0]] = False
    left = inside[enclosing[face[:m]]]
    right = inside[enclosing[face[m:]]]
    boundary = left != right
    if not boundary.any():
        return None
    bverts = np.bincount(seg[boundary].ravel(), minlength=len(verts))
    touch = np.flatnonzero(bverts > 2)
    if len(touch):
        v = touch[0]
        raise GeometryError(f"{path}: boundary loops touch at vertex {fmt_point(verts[v])}")
    chains = _polylines(verts, seg, marks, np.flatnonzero(boundary), boundary_marks=True)
    if not all(closed for _, closed in chains):
        return None
    # The outer loop encloses the largest area.
    loops = sorted((c for c, _ in chains), key=lambda c: -abs(c.signed_area()))
    constraints = [c for c, _ in _polylines(verts, seg, marks, np.flatnonzero(left & right), False)]
    return loops, constraints, boundary


def _polylines(verts, seg, marks, which, boundary_marks: bool) -> list[tuple[Polyline, bool]]:
    """Chain the segments ``which`` into polylines carrying their markers; flag closed ones."""
    if len(which) == 0:
        return []
    sub = seg[which]
    vseq, eseq, off, closed = trace_chains(len(verts), sub)
    out = []
    for k in range(len(off) - 1):
        e = which[eseq[off[k] : off[k + 1]]]
        v = vseq[off[k] + k : off[k + 1] + k + 1]
        mk = None
        if marks is not None:
            mk = marks[e].copy()
            if boundary_marks:
                mk[mk == 0] = 1
        pts = verts[v[:-1]] if closed[k] else verts[v]
        out.append((Polyline(pts, mk, closed=bool(closed[k])), bool(closed[k])))
    return out


def write_poly(path, domain, size=None, first_index: int = 1) -> None:
    """Write a Domain's discretisation (or a :class:`Discretization`) as a ``.poly`` file.

    Vertices carry their markers, segments theirs; holes and regions follow, each region
    with its attribute (a Domain's ``region_attributes``, a Discretization's markers) and
    area bound.  Coordinates are written with 17 significant digits, so :func:`read_poly`
    reads them back exactly.  A Domain with an open boundary is written with the hull
    segments that close it, as Triangle's ``-c`` writes its output.

    Parameters
    ----------
    path : str or Path
    domain : Domain or Discretization
    size : optional
        Spacing of the discretisation (anything :meth:`Domain.discretize` accepts);
        ignored for a Discretization, so giving both is an error.
    first_index : {0, 1}
        Number of the first vertex (Triangle's default is 1).

    Raises
    ------
    InputError
        ``domain`` of another type, ``size`` with a Discretization, bad ``first_index``.
    """
    if isinstance(domain, Discretization):
        if size is not None:
            raise InputError("size applies to a Domain; a Discretization is already discretised")
        disc = domain
    elif isinstance(domain, Domain):
        disc = domain.discretize(size)
        regions = disc.regions.copy()
        regions[:, 2] = domain.region_attributes
        disc = disc._replace(regions=regions)
    else:
        raise InputError(f"write_poly needs a Domain or a Discretization, got {type(domain).__name__}")
    write_poly_file(
        path,
        disc.segments,
        disc.segment_markers,
        disc.holes,
        disc.regions,
        points=disc.points,
        point_markers=disc.point_markers,
        first_index=first_index,
    )
