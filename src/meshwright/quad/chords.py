"""Chord refinement: a mixed quad-triangle mesh finished with quadrilaterals only.

A *chord* of a quadrilateral mesh is the strip of quads crossed by entering each through
one side and leaving through the opposite one (the dual line of the mesh; in 3-D the
sheets of M. J. Borden, S. E. Benzley and J. F. Shepherd, "Hexahedral sheet extraction",
11th International Meshing Roundtable, 2002).  Splitting every quad of a chord along it,
and every triangle at the chord's ends into three quads, keeps the mesh conforming, so
left-over triangles of a pairing (:mod:`meshwright.quad.pairing`) become quads while only
the quads on their chords change; one midpoint split of every element
(:func:`meshwright.quad.subdivide.split_all`) is the global alternative.

Invariants: every side a chord crosses is split in both its elements (chords are
deterministic: a quad met again in the same direction is the same chord walked from its
other end); a boundary or interior-segment side's midpoint lies on its true curve.

Array layout: a :class:`~meshwright.quad.mesher.QuadFill` in and out (points (n, 2)
float64; quads (m, 4), triangles (t, 3), lines (k, 2) int32 counter-clockwise; line
markers and curves (k,) int32).  Half-edge ``h`` is side ``h % 4`` of quad ``h // 4`` for
``h < 4 m`` and side ``(h - 4 m) % 3`` of triangle ``(h - 4 m) // 3`` beyond.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.errors import InputError, MeshingError
from meshwright.core.predicates import orient2d_batch
from meshwright.core.validate_input import check_count
from meshwright.geometry.domain import Domain
from meshwright.quad._pairing_kernel import nonconvex_quads

__all__ = ["chord_split", "chord_split_candidates"]

MEND_ROUNDS = 8  # rounds of re-cuts of the cells whose split came out non-convex
# A quad crossed once becomes two halves: corners 0-3, then the midpoints of the two sides
# crossed (4: side bit - 1, 5: side bit + 1); rows [bit - 1, half].
_HALVES = np.array([[[0, 4, 5, 3], [4, 1, 2, 5]], [[0, 1, 4, 5], [5, 4, 2, 3]]], dtype=np.int64)


def chord_split(fill, domain: Domain, max_points: int, line_params=None):
    """Finish a mixed fill with quads only, refining along chords from the left-over triangles.

    Every side of a left-over triangle starts a chord: it crosses the quad beyond that side
    to the opposite side, and the next quad, until it meets the boundary (or an interior
    segment's end of the mesh) or another triangle.  Every side a chord crosses gets its
    midpoint (on the true curve for a line), a quad crossed once becomes two, a quad
    crossed both ways four (around its vertex mean), a triangle three (around its
    centroid).  Every split side is split in both its elements, so the result conforms;
    only the quads on the chords change, unlike the global midpoint split.

    Every new quad is checked exactly (``orient2d`` at each corner, on the rounded
    coordinates).  A cell too flat for its split to survive rounding (a quad with a corner
    of almost 180 degrees, a sliver triangle whose height is below the coordinates' spacing)
    is re-cut and the split redone (:func:`_mend`): such a quad becomes two triangles along
    the diagonal through its widest corner, such a triangle is flipped with the cell
    beyond the side facing its widest corner.  Meshes whose split is convex at once are
    unchanged, and so is one that no re-cut makes convex within ``MEND_ROUNDS`` (a node
    next to a line, the line facing its straight angle): its bent quads are returned as
    they came, for the caller's smoothing, which may still open them (a free node moves),
    and its exact check.

    Parameters
    ----------
    fill : QuadFill
    domain : Domain
    max_points : int
    line_params : (k, 2) float64, optional
        Curve parameters of each line's two ends (``Discretization.segment_params`` when
        the lines are the discretisation's segments, in order): a split line's midpoint
        is then the arc-length midpoint of its parameters, without projecting its ends
        back onto the curve (a golden-section search per curve; not exact at a cusp).

    Returns
    -------
    QuadFill
        No triangles.

    Raises
    ------
    InputError
        ``fill`` not a QuadFill, ``domain`` not a Domain, ``max_points`` not a positive int,
        ``line_params`` not finite with one row per line.
    MeshingError
        The refinement would exceed ``max_points``.
    """
    first, mended = chord_split_candidates(fill, domain, max_points, line_params)
    return first if mended is None else mended


def chord_split_candidates(fill, domain: Domain, max_points: int, line_params=None):
    """:func:`chord_split`'s two results: (the plain split, the re-cut one or None).

    The re-cut split is None when the plain one is convex already or no re-cut made it
    convex.  A caller that smooths afterwards can keep whichever smooths better: the
    smoother may open a bent quad by moving a free node (a better shape than a re-cut
    that leaves a sliver), or not.  Same parameters and errors as :func:`chord_split`
    (its arguments checked here).
    """
    from meshwright.quad.mesher import QuadFill

    if not isinstance(fill, QuadFill):
        raise InputError(f"fill must be a meshwright.quad.QuadFill, got {type(fill).__name__}")
    if not isinstance(domain, Domain):
        raise InputError(f"domain must be a meshwright.geometry.Domain, got {type(domain).__name__}")
    max_points = check_count(max_points, "max_points", 1)
    if line_params is not None:
        line_params = np.asarray(line_params, dtype=np.float64)
        if line_params.shape != (len(fill.lines), 2) or not np.isfinite(line_params).all():
            raise InputError(
                f"line_params must be finite with shape ({len(fill.lines)}, 2), one row per line; "
                f"got shape {line_params.shape}"
            )
    first = None
    for _ in range(MEND_ROUNDS):
        out, parent = _split(fill, domain, max_points, line_params)
        bad = nonconvex_quads(out.points, out.quads)
        if not len(bad):
            return (out, None) if first is None else (first, out)
        first = out if first is None else first
        mended = _mend(fill, np.unique(parent[bad]))
        if mended is None:
            break
        fill = fill._replace(quads=mended[0], triangles=mended[1])
    return first, None


def _split(fill, domain: Domain, max_points: int, line_params):
    """One chord refinement of a checked fill: (QuadFill, parent) with ``parent`` (q,) int64
    the cell each new quad came from (``i < m`` quad ``i``, ``m + j`` triangle ``j``)."""
    from meshwright.quad.subdivide import curve_midpoints

    xy = fill.points
    n = len(xy)
    quads = np.ascontiguousarray(fill.quads, dtype=np.int32)
    tris = np.ascontiguousarray(fill.triangles, dtype=np.int32)
    split, crossed, starts, ends = _chord_walk(quads, tris, n)
    # Only the split sides get a key: one node per side, numbered in key order.
    hs = np.flatnonzero(split)
    key = np.minimum(starts[hs], ends[hs]) * n + np.maximum(starts[hs], ends[hs])
    uniq, which = np.unique(key, return_inverse=True)
    both = np.flatnonzero(crossed == 3)
    total = n + len(uniq) + len(both) + len(tris)
    if total > max_points:
        raise MeshingError(f"the chord refinement needs {total} vertices, above max_points = {max_points}")
    mid = 0.5 * (xy[uniq // n] + xy[uniq % n])
    lines = fill.lines.astype(np.int64)
    lkey = np.minimum(lines[:, 0], lines[:, 1]) * n + np.maximum(lines[:, 0], lines[:, 1])
    # uniq is sorted: one search finds both whether a line is split and its midpoint
    # (np.isin sorted both arrays again, 0.6 ms of the disk's split).
    pos = np.searchsorted(uniq, lkey)
    lsplit = uniq[np.minimum(pos, len(uniq) - 1)] == lkey if len(uniq) else np.zeros(len(lkey), dtype=bool)
    lmid = pos[lsplit]
    on_curve = fill.line_curves[lsplit] >= 0
    if on_curve.any():
        curves = fill.line_curves[lsplit][on_curve]
        if line_params is None:
            ends_l = lines[lsplit][on_curve]
            mid[lmid[on_curve]] = curve_midpoints(domain, curves, xy[ends_l[:, 0]], xy[ends_l[:, 1]])
        else:
            ta, tb = line_params[lsplit][on_curve].T
            mid[lmid[on_curve]] = domain.split(curves, ta, tb)[1]
    node = np.full(len(split), -1, dtype=np.int64)
    node[hs] = n + which.ravel()
    centres = np.concatenate([xy[quads[both]].mean(axis=1), xy[tris].mean(axis=1)])
    out, parent = _chord_cells(quads, tris, node, crossed, n + len(uniq))
    # Each split line becomes (u, mid) and (mid, w), in the lines' order.
    reps = np.where(lsplit, 2, 1)
    at = np.cumsum(reps) - reps
    new_lines = np.empty((int(reps.sum()), 2), dtype=np.int64)
    new_lines[at, 0] = lines[:, 0]
    new_lines[at, 1] = lines[:, 1]
    new_lines[at[lsplit], 1] = n + lmid
    new_lines[at[lsplit] + 1, 0] = n + lmid
    new_lines[at[lsplit] + 1, 1] = lines[lsplit, 1]
    split_fill = fill._replace(
        points=np.ascontiguousarray(np.concatenate([xy, mid, centres])),
        quads=out,
        triangles=np.zeros((0, 3), dtype=np.int32),
        lines=new_lines.astype(np.int32),
        line_markers=np.repeat(fill.line_markers, reps).astype(np.int32),
        line_curves=np.repeat(fill.line_curves, reps).astype(np.int32),
    )
    return split_fill, parent


def _corners(xy, cell):
    """(sine, cosine) of each corner of a polygon (quality rules, floating point): the
    widest corner (smallest cosine) is the re-cut's choice, the smallest sine (the scaled
    Jacobian) ranks the options; the exact checks decide whether a cut is valid."""
    p = xy[cell]
    u = np.roll(p, -1, axis=0) - p
    w = np.roll(p, 1, axis=0) - p
    norm = np.hypot(*u.T) * np.hypot(*w.T)
    return (u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0]) / norm, (u * w).sum(axis=1) / norm


def _mend(fill, parents):
    """Re-cut the cells (``parents``, :func:`_split` numbering) whose split was non-convex.

    A quad becomes two triangles along the diagonal through its widest corner (the
    diagonal that halves the almost straight angle; the other one would leave it in a
    sliver).  A triangle is flipped with the cell beyond the side facing its widest
    corner, unless that side is a line: with a triangle into two triangles across the
    other diagonal, with a quad (a pentagon) into a quad and a triangle by a diagonal
    from that corner, the better shaped of the two.  Every new cell is checked exactly
    (strictly convex quads, counter-clockwise triangles); a cell touched already this
    round waits for the next.  Rare: a Python loop over the few cells, each neighbour
    found by a scan of the arrays.  Returns
    (quads, triangles) int32, or None when no cell could be re-cut.
    """
    xy = fill.points
    quads = fill.quads.astype(np.int64)
    tris = fill.triangles.astype(np.int64)
    m = len(quads)
    lines = fill.lines.astype(np.int64)
    q_next = quads[:, [1, 2, 3, 0]]
    t_next = tris[:, [1, 2, 0]]
    gone = np.zeros(m + len(tris), dtype=bool)
    new_quads, new_tris = [], []

    def beyond(a, b):
        """The cell whose side runs from b to a (the twin of a -> b), -1 if none."""
        hit = np.flatnonzero(((quads == b) & (q_next == a)).any(axis=1))
        if len(hit):
            return int(hit[0])
        hit = np.flatnonzero(((tris == b) & (t_next == a)).any(axis=1))
        return m + int(hit[0]) if len(hit) else -1

    def is_line(a, b):
        return bool((((lines[:, 0] == a) & (lines[:, 1] == b)) | ((lines[:, 0] == b) & (lines[:, 1] == a))).any())

    def ccw(*cells):
        o = orient2d_batch(xy, np.array(cells, dtype=np.int64))
        return bool((o > 0.0).all())

    def convex(q):
        return ccw(*([q[(k + 3) % 4], q[k], q[(k + 1) % 4]] for k in range(4)))

    for p in map(int, parents):
        if gone[p]:
            continue
        if p < m:
            q = quads[p].tolist()
            k = int(np.argmin(_corners(xy, q)[1]))
            for d in (k, (k + 1) % 4):
                a, b, c, e = (q[(d + i) % 4] for i in range(4))
                if ccw([a, b, c], [a, c, e]):
                    gone[p] = True
                    new_tris += [[a, b, c], [a, c, e]]
                    break
            continue
        t = tris[p - m].tolist()
        k = int(np.argmin(_corners(xy, t)[1]))
        c, a, b = t[k], t[(k + 1) % 3], t[(k + 2) % 3]
        o = beyond(a, b)
        if o < 0 or gone[o] or is_line(a, b):
            continue
        if o >= m:
            x = next(v for v in tris[o - m].tolist() if v != a and v != b)
            if ccw([c, a, x], [c, x, b]):
                gone[[p, o]] = True
                new_tris += [[c, a, x], [c, x, b]]
            continue
        r = quads[o].tolist()
        s = r.index(b)
        x, y = r[(s + 2) % 4], r[(s + 3) % 4]
        options = [([c, x, y, b], [c, a, x]), ([c, a, x, y], [c, y, b])]
        options = [(qq, tt) for qq, tt in options if convex(qq) and ccw(tt)]
        if options:
            qq, tt = max(options, key=lambda ct: min(_corners(xy, ct[0])[0].min(), _corners(xy, ct[1])[0].min()))
            gone[[p, o]] = True
            new_quads.append(qq)
            new_tris.append(tt)
    if not gone.any():
        return None
    return (
        np.concatenate([quads[~gone[:m]], np.array(new_quads, dtype=np.int64).reshape(-1, 4)]).astype(np.int32),
        np.concatenate([tris[~gone[m:]], np.array(new_tris, dtype=np.int64).reshape(-1, 3)]).astype(np.int32),
    )


@njit(cache=True)
def _chord_walk(quads, tris, n):
    """Walk the chords from every triangle side; returns (split, crossed, starts, ends).

    Half-edge ``h`` runs from ``starts[h]`` to ``ends[h]`` (both (4 m + 3 t,) int64, the
    module's half-edge order, from ``quads`` (m, 4) and ``tris`` (t, 3) int32); its twin, the
    half-edge of the same side in the other cell,
    runs the other way and is looked up, only for the sides the chords reach, among the
    half-edges leaving ``ends[h]`` (a table by start vertex, ``n`` vertices: no sort).
    ``split`` (4 m + 3 t,) bool marks the half-edges whose side gets a midpoint;
    ``crossed`` (m,) int8 has bit 0 set for a quad whose sides 0 and 2 are split, bit 1
    for sides 1 and 3.  A chord stops at a side with no twin (a line), at a triangle, or
    at a quad it crossed already in the same direction (the same chord walked from its
    other end): every step sets a new bit, so all the walks together take at most 2 m
    steps.
    """
    m = quads.shape[0]
    starts = np.empty(4 * m + 3 * tris.shape[0], np.int64)
    ends = np.empty_like(starts)
    for q in range(m):
        for k in range(4):
            starts[4 * q + k] = quads[q, k]
            ends[4 * q + k] = quads[q, (k + 1) & 3]
    for j in range(tris.shape[0]):
        for k in range(3):
            starts[4 * m + 3 * j + k] = tris[j, k]
            ends[4 * m + 3 * j + k] = tris[j, k + 1 if k < 2 else 0]
    nh = starts.shape[0]
    ptr = np.zeros(n + 1, np.int64)
    for h in range(nh):
        ptr[starts[h] + 1] += 1
    for v in range(n):
        ptr[v + 1] += ptr[v]
    fill = ptr[:-1].copy()
    out_of = np.empty(nh, np.int64)
    for h in range(nh):
        out_of[fill[starts[h]]] = h
        fill[starts[h]] += 1
    crossed = np.zeros(m, np.int8)
    split = np.zeros(nh, np.bool_)
    for h in range(4 * m, nh):
        split[h] = True
        at = h
        while True:
            o = -1
            for j in range(ptr[ends[at]], ptr[ends[at] + 1]):
                if ends[out_of[j]] == starts[at]:
                    o = out_of[j]
                    break
            if not 0 <= o < 4 * m:
                break
            q = o >> 2
            k = o & 3
            bit = 1 << (k & 1)
            if crossed[q] & bit:
                break  # the same chord, walked from its other end
            crossed[q] |= bit
            split[o] = True
            at = 4 * q + ((k + 2) & 3)
            split[at] = True
        if o >= 0:
            split[o] = True
    return split, crossed, starts, ends


@njit(cache=True)
def _chord_cells(quads, tris, node, crossed, first_centre):
    """The split's quads (k, 4) int32 and the cell each came from (k,) int64.

    ``node`` (4 m + 3 t,) int64 is the midpoint of each half-edge's side (-1 where not
    split); the centres are numbered from ``first_centre``, the quads crossed both ways
    first, then the triangles.  In this order: the quads not crossed; those crossed once
    between sides 0 and 2, as (v0, m0, m2, v3) then (m0, v1, v2, m2); those crossed between
    sides 1 and 3, as (v0, v1, m1, m3) then (m3, m1, v2, v3); then for k = 0 .. 3 corner
    k's quad (v_k, m_k, centre, m_{k-1}) of every quad crossed both ways, and for k = 0 .. 2
    that of every triangle.
    """
    m = quads.shape[0]
    t = tris.shape[0]
    count = np.zeros(4, np.int64)
    for q in range(m):
        count[crossed[q]] += 1
    total = count[0] + 2 * count[1] + 2 * count[2] + 4 * count[3] + 3 * t
    out = np.empty((total, 4), np.int32)
    parent = np.empty(total, np.int64)
    i = 0
    for q in range(m):
        if crossed[q] == 0:
            # Entry by entry: a row assignment (out[i] = quads[q]) costs 1.5 s of compile.
            for k in range(4):
                out[i, k] = quads[q, k]
            parent[i] = q
            i += 1
    for bit in range(1, 3):
        for half in range(2):
            for q in range(m):
                if crossed[q] != bit:
                    continue
                # Crossed once: the two midpoints (sides bit - 1 and bit + 1) as entries 4
                # and 5 after the corners, placed by the half's pattern.
                for k in range(4):
                    j = _HALVES[bit - 1, half, k]
                    out[i, k] = quads[q, j] if j < 4 else node[4 * q + bit - 1 + 2 * (j - 4)]
                parent[i] = q
                i += 1
    for k in range(4):
        c = first_centre
        for q in range(m):
            if crossed[q] != 3:
                continue
            out[i, 0] = quads[q, k]
            out[i, 1] = node[4 * q + k]
            out[i, 2] = c
            out[i, 3] = node[4 * q + (k + 3) % 4]
            parent[i] = q
            c += 1
            i += 1
    for k in range(3):
        c = first_centre + count[3]
        for j in range(t):
            out[i, 0] = tris[j, k]
            out[i, 1] = node[4 * m + 3 * j + k]
            out[i, 2] = c
            out[i, 3] = node[4 * m + 3 * j + (k + 2) % 3]
            parent[i] = m + j
            c += 1
            i += 1
    return out, parent
