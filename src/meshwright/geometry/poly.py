"""Triangle ``.poly`` files as :class:`~meshwright.geometry.Domain` objects.

Format (J. R. Shewchuk, Triangle documentation, https://www.cs.cmu.edu/~quake/triangle.poly.html)::

    <# vertices> <dimension (2)> <# attributes> <# boundary markers (0 or 1)>
    <vertex #> <x> <y> [attributes] [boundary marker]          (one line per vertex)
    <# segments> <# boundary markers (0 or 1)>
    <segment #> <endpoint> <endpoint> [boundary marker]
    <# holes>
    <hole #> <x> <y>
    [<# regions>
     <region #> <x> <y> <attribute> <maximum area>]

``#`` starts a comment; numbering may start at 0 or 1 (the first vertex decides); with zero
vertices the vertices are read from the ``.node`` file of the same name.

Triangle treats every segment as a constraint and removes the triangles reachable from a
hole seed or from the outside without crossing a segment.  :func:`read_poly` rebuilds that
meaning as loops: the segment graph is split into faces (half-edges sorted by angle around
each vertex); a face holding a hole seed is a hole, faces enclosed by segments and holding
no seed are domain; segments between domain and non-domain form the loops (as
:class:`~meshwright.geometry.curves.Polyline` curves keeping the segment markers, 0 turned
into 1 on the boundary as Triangle does), segments inside the domain become interior
constraints and segments outside it are dropped.  Vertices on no segment become interior
points when they lie inside the domain.  Vertex attributes and markers are not kept.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from meshwright.core.errors import FormatError, GeometryError
from meshwright.geometry._discretize import unique_rows
from meshwright.geometry._kernels import (
    INSIDE,
    classify_points,
    find_bad_pairs,
    parity_by_label,
    trace_chains,
)
from meshwright.geometry.curves import Polyline, _fmt
from meshwright.geometry.domain import Discretization, Domain

__all__ = ["read_poly", "write_poly"]


class _Lines:
    """Non-empty, comment-free lines of a file, with line numbers for error messages."""

    def __init__(self, path: Path):
        self.path = path
        try:
            text = path.read_text()
        except OSError as exc:
            raise FormatError(f"{path}: cannot read ({exc.strerror})") from exc
        self.lines = [
            (i + 1, ln.split("#", 1)[0].split())
            for i, ln in enumerate(text.splitlines())
            if ln.split("#", 1)[0].strip()
        ]
        self.pos = 0

    def more(self) -> bool:
        return self.pos < len(self.lines)

    def next(self, what: str, least: int) -> tuple[int, list[str]]:
        if not self.more():
            raise FormatError(f"{self.path}: unexpected end of file, expected {what}")
        lineno, tok = self.lines[self.pos]
        self.pos += 1
        if len(tok) < least:
            raise FormatError(
                f"{self.path}:{lineno}: expected {what} ({least} fields), got {len(tok)}"
            )
        return lineno, tok

    def numbers(self, what: str, least: int, kind=float) -> tuple[int, list]:
        lineno, tok = self.next(what, least)
        try:
            return lineno, [int(t) if kind is int else float(t) for t in tok]
        except ValueError:
            raise FormatError(
                f"{self.path}:{lineno}: cannot parse {what} from {' '.join(tok)!r}"
            ) from None


def _read_vertices(src: _Lines, path: Path):
    _, head = src.numbers("vertex header '<#vertices> <dim> <#attributes> <#markers>'", 1, int)
    head += [2, 0, 0][len(head) - 1 :]
    nv, dim, nattr, nmark = head[:4]
    if nv == 0:
        node = path.with_suffix(".node")
        if not node.exists():
            raise FormatError(f"{path}: no vertices and no {node.name} next to it")
        return _read_vertices(_Lines(node), node)
    if dim != 2:
        raise FormatError(f"{path}: dimension must be 2, got {dim}")
    xy = np.empty((nv, 2))
    lines = np.empty(nv, dtype=np.int64)
    base = 0
    for k in range(nv):
        lineno, v = src.numbers(f"vertex {k}", 3 + nattr + nmark)
        if k == 0:
            base = int(v[0])
            if base not in (0, 1):
                raise FormatError(
                    f"{path}:{lineno}: vertex numbering must start at 0 or 1, got {v[0]:g}"
                )
        if v[0] != base + k:
            raise FormatError(f"{path}:{lineno}: expected vertex number {base + k}, got {v[0]:g}")
        xy[k] = v[1:3]
        lines[k] = lineno
        if not np.isfinite(xy[k]).all():
            raise FormatError(f"{path}:{lineno}: vertex {v[0]:g} has non-finite coordinates")
    return xy, lines, base


def _read(path: Path):
    src = _Lines(path)
    xy, vlines, base = _read_vertices(src, path)
    _, head = src.numbers("segment header '<#segments> <#markers>'", 1, int)
    nseg, has_mark = head[0], (head[1] if len(head) > 1 else 0)
    seg = np.empty((nseg, 2), dtype=np.int64)
    marks = np.zeros(nseg, dtype=np.int32)
    slines = np.empty(nseg, dtype=np.int64)
    for k in range(nseg):
        lineno, s = src.numbers(f"segment {k}", 3 + (1 if has_mark else 0), int)
        seg[k] = np.array(s[1:3]) - base
        if (seg[k] < 0).any() or (seg[k] >= len(xy)).any():
            raise FormatError(f"{path}:{lineno}: segment {s[0]} refers to a missing vertex")
        if has_mark:
            marks[k] = s[3]
        slines[k] = lineno
    _, head = src.numbers("hole header '<#holes>'", 1, int)
    holes = np.array([src.numbers(f"hole {k}", 3)[1][1:3] for k in range(head[0])]).reshape(-1, 2)
    regions = []
    if src.more():
        _, head = src.numbers("region header '<#regions>'", 1, int)
        for k in range(head[0]):
            lineno, r = src.numbers(f"region {k}", 4)
            if r[3] != int(r[3]):
                raise FormatError(
                    f"{path}:{lineno}: region attribute {r[3]:g} is not an integer marker"
                )
            area = r[4] if len(r) > 4 and r[4] > 0 else None
            regions.append((r[1], r[2], int(r[3]), area))
    return xy, vlines, seg, marks if has_mark else None, slines, holes, regions


def _faces(xy: np.ndarray, seg: np.ndarray):
    """Faces of a planar segment graph; half-edge ``e < m`` is ``seg[e]``, ``e + m`` its twin.

    Returns the face of each half-edge (faces to the left, bounded ones counter-clockwise)
    and each face's signed area.
    """
    m = len(seg)
    org = np.concatenate([seg[:, 0], seg[:, 1]])
    dst = np.concatenate([seg[:, 1], seg[:, 0]])
    d = xy[dst] - xy[org]
    order = np.lexsort((np.arctan2(d[:, 1], d[:, 0]), org))
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
    return face, area, org, dst


def read_poly(path) -> Domain:
    """Read a Triangle ``.poly`` file as a :class:`Domain`.

    Raises
    ------
    FormatError
        Unreadable or malformed file (message names file and line).
    GeometryError
        Crossing segments, touching loops or no enclosed region (message names the file
        and the segments' lines).
    """
    path = Path(path)
    xy, vlines, seg0, marks, slines, holes, regions = _read(path)
    verts, inv = unique_rows(xy)
    seg = inv[seg0]
    zero = np.flatnonzero(seg[:, 0] == seg[:, 1])
    if len(zero):
        raise GeometryError(f"{path}:{slines[zero[0]]}: segment has zero length")
    key = np.sort(seg, axis=1)
    _, first, count = np.unique(key, axis=0, return_index=True, return_counts=True)
    if (count > 1).any():
        dup = np.flatnonzero((key == key[first[np.flatnonzero(count > 1)[0]]]).all(axis=1))
        raise GeometryError(
            f"{path}:{slines[dup[1]]}: segment duplicates the one on line {slines[dup[0]]}"
        )
    bad = find_bad_pairs(verts, seg, 1)
    if len(bad):
        s, t = bad[0]
        raise GeometryError(f"{path}: segments on lines {slines[s]} and {slines[t]} intersect")
    if len(seg) < 3:
        raise GeometryError(f"{path}: segments enclose no region")
    m = len(seg)
    face, area, org, dst = _faces(verts, seg)
    bounded = np.flatnonzero(area > 0)
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
    outer_faces = np.flatnonzero(area <= 0)
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
        raise GeometryError(f"{path}: segments enclose no region outside the holes")
    bverts = np.bincount(seg[boundary].ravel(), minlength=len(verts))
    touch = np.flatnonzero(bverts > 2)
    if len(touch):
        v = touch[0]
        raise GeometryError(f"{path}: boundary loops touch at vertex {_fmt(verts[v])}")
    chains = _polylines(verts, seg, marks, np.flatnonzero(boundary), boundary_marks=True)
    if not all(closed for _, closed in chains):
        raise GeometryError(f"{path}: boundary segments do not form closed loops")
    # The outer loop encloses the largest area.
    loops = sorted((c for c, _ in chains), key=lambda c: -abs(c.signed_area()))
    constraints = [c for c, _ in _polylines(verts, seg, marks, np.flatnonzero(left & right), False)]
    used = np.zeros(len(verts), dtype=bool)
    used[seg.ravel()] = True
    iso = verts[~used]
    if len(iso):
        b = np.flatnonzero(boundary)
        where = classify_points(iso, verts[seg[b, 0]], verts[seg[b, 1]])
        iso = iso[where != 0]
    try:
        return Domain(loops[0], loops[1:], segments=constraints, points=iso, regions=regions)
    except GeometryError as exc:
        raise GeometryError(f"{path}: {exc}") from exc


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


def write_poly(path, domain, size=None, base: int = 1) -> None:
    """Write a Domain's discretisation (or a :class:`Discretization`) as a ``.poly`` file.

    Vertices carry their markers, segments theirs; holes and regions follow.  Coordinates
    are written with 17 significant digits, so :func:`read_poly` reads them back exactly.
    """
    disc = domain if isinstance(domain, Discretization) else domain.discretize(size)
    rows = [f"# written by meshwright\n{len(disc.points)} 2 0 1"]
    rows += [
        f"{i + base} {x:.17g} {y:.17g} {m}"
        for i, ((x, y), m) in enumerate(zip(disc.points, disc.point_markers))
    ]
    rows.append(f"{len(disc.segments)} 1")
    rows += [
        f"{i + base} {a + base} {b + base} {m}"
        for i, ((a, b), m) in enumerate(zip(disc.segments, disc.segment_markers))
    ]
    rows.append(f"{len(disc.holes)}")
    rows += [f"{i + base} {x:.17g} {y:.17g}" for i, (x, y) in enumerate(disc.holes)]
    rows.append(f"{len(disc.regions)}")
    rows += [
        f"{i + base} {x:.17g} {y:.17g} {int(m)} {a:.17g}"
        for i, (x, y, m, a) in enumerate(disc.regions)
    ]
    Path(path).write_text("\n".join(rows) + "\n")
