"""Closure, joining and cleanup of paving boundaries (steps 2, 7 and 8 of
:mod:`meshwright.quad.paving`).

Blacker and Stephenson (1991) close a paving boundary of six or fewer nodes by templates,
connect paving boundaries that meet and clean the mesh up at the end.  This module holds
those pieces (and the paving boundaries' geometry: :func:`boundary_loops`,
:func:`loop_angles`, :func:`signed_area`, :func:`encloses`):

* :func:`closure_quads`: the four- and six-node templates (one quad; two quads along a
  long diagonal or three around a centre node, the valid one with the best smallest
  corner sine);
* :func:`close_loop`: a paving boundary of more nodes is cut by chords, node to node, with
  nodes at the local size on the chord so that both parts stay even, until every part
  takes a template; the chord chosen leaves the widest smallest angle beside it; a part of
  up to :data:`STAR_MAX` nodes that no chord can cut is closed around one centre node
  (:func:`star_quads`);
* :func:`bridge`: a paving boundary around a hole's paving boundary is joined to it by one
  such chord (its nodes appear on both sides of the chord, so the joined boundary has
  ``n_outer + n_hole + 2 k + 2`` nodes: even), after which :func:`close_loop` can close it;
* :func:`facing_order`: the pairs of paving nodes the paver tries to join, closest first;
* :func:`fill_voids`: the region left between stopped paving boundaries, meshed by
  advancing-front triangles paired into quads (18.5.1, :mod:`meshwright.quad.pairing`),
  the front's spacing never above that of the void's own boundary nodes (chapter 18.3's
  background), so it grows from a stopped row's short edges instead of fanning onto them;

Every chord is checked against every paving-boundary edge by the exact crossing kernel
(:func:`meshwright.quad._paving_kernel.row_crossings`); every quad of a template is
strictly convex by exact ``orient2d``.

Array layout: points (n, 2) float64; a paving boundary is a (k,) int64 array of node ids
with its region on the left; quads (q, 4) int64 counter-clockwise; new nodes are numbered
from ``len(xy)`` on, in the order of the returned coordinate block.
"""

from __future__ import annotations

import numpy as np

from meshwright.core.errors import MeshingError
from meshwright.quad import _paving_kernel as pk
from meshwright.quad import _paving_long as pl
from meshwright.quad import _paving_row as pr
from meshwright.quad.enhancement import enhance, nonconvex, unpair_nonconvex
from meshwright.quad.pairing import pair_triangles
from meshwright.quad.smoothing import smooth_cells
from meshwright.sizing.background import BackgroundGrid
from meshwright.sizing.field import as_size_field

__all__ = [
    "area_kept",
    "boundary_loops",
    "bridge",
    "clear_after_merge",
    "close_loop",
    "closure_quads",
    "consistent",
    "convex",
    "despike",
    "edges_of",
    "encloses",
    "facing_order",
    "fill_voids",
    "front_slots",
    "loop_angles",
    "min_sine",
    "shift_next",
    "shift_prev",
    "signed_area",
    "star_quads",
]

CHORD_MIN_ANGLE = 35.0  # degrees: a chord leaves no angle sharper than this beside it
CHORD_REACH = 4.0  # sizes: chords up to this long are tried first
CHORD_TRIES = 48  # best-scored chords tested for crossings before giving up on a part
VOID_SMOOTH = 8  # guarded Laplacian sweeps of the void fill before non-convex pairs are cut back
STAR_MAX = 12  # a part of up to this many nodes no chord can cut is closed around a centre node
SERPENTINE = 16  # cells per side of the grid that orders the void fill's size queries
LONG_LOOP = 200  # loops above this many nodes are closed by the kernel of _paving_long (near chords only)


def serpentine(xy, k: int = SERPENTINE):
    """Order of points ``xy`` (m, 2) along the rows of a k by k grid of their box,
    alternate rows backwards (a stable sort by cell): consecutive points are near each
    other, for searches that start from the last answer (a kernel,
    :func:`~meshwright.quad._paving_kernel.serpentine_order`: the NumPy version's dozen
    calls cost a millisecond per three-element void fill)."""
    return pk.serpentine_order(np.ascontiguousarray(xy, dtype=np.float64), int(k))


def shift_next(a: np.ndarray) -> np.ndarray:
    """``a`` with row i holding row i + 1 (cyclic): ``np.roll(a, -1, axis=0)`` without its
    per-call overhead, which the per-row paving calls thousands of times."""
    return np.concatenate((a[1:], a[:1]))


def shift_prev(a: np.ndarray) -> np.ndarray:
    """``a`` with row i holding row i - 1 (cyclic): ``np.roll(a, 1, axis=0)``."""
    return np.concatenate((a[-1:], a[:-1]))


def loop_angles(xy: np.ndarray) -> np.ndarray:
    """Interior angles (radians, in (0, 2 pi]) of a closed node sequence with the region on
    its left: from the edge to the next node counter-clockwise to the edge to the previous."""
    en = shift_next(xy) - xy
    ep = shift_prev(xy) - xy
    a = np.arctan2(en[:, 0] * ep[:, 1] - en[:, 1] * ep[:, 0], (en * ep).sum(axis=1))
    return np.where(a <= 0.0, a + 2.0 * np.pi, a)


def signed_area(xy: np.ndarray) -> float:
    """Shoelace area of a closed node sequence (positive counter-clockwise)."""
    x, y = xy[:, 0], xy[:, 1]
    return 0.5 * float((x * shift_next(y) - shift_next(x) * y).sum())


def min_sine(xy: np.ndarray, quads: np.ndarray) -> np.ndarray:
    """Smallest corner sine of each quad (floating point; a quality rule)."""
    q = np.asarray(quads, dtype=np.int64)
    worst = np.full(len(q), 1.0)
    for k in range(4):
        u = xy[q[:, (k + 1) % 4]] - xy[q[:, k]]
        w = xy[q[:, (k + 3) % 4]] - xy[q[:, k]]
        den = np.hypot(*u.T) * np.hypot(*w.T)
        s = np.where(den > 0.0, (u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0]) / np.where(den > 0.0, den, 1.0), -1.0)
        worst = np.minimum(worst, s)
    return worst


def convex(xy: np.ndarray, quads: np.ndarray) -> np.ndarray:
    """(q,) bool: strictly convex and counter-clockwise (exact orient2d at all corners)."""
    q = np.ascontiguousarray(np.asarray(quads, dtype=np.int64).reshape(-1, 4))
    return pk.convex_quads(np.ascontiguousarray(xy, dtype=np.float64), q)


def edges_of(fronts) -> tuple[np.ndarray, np.ndarray]:
    """All edges of a list of paving boundaries, as two (m,) int64 end arrays."""
    if not fronts:
        z = np.zeros(0, dtype=np.int64)
        return z, z
    return np.concatenate(fronts), np.concatenate([shift_next(f) for f in fronts])


def closure_quads(xy, loop):
    """Template closure of a paving boundary of four or six nodes.

    Parameters
    ----------
    xy : (n, 2) float64
    loop : (k,) int
        Node ids, region on the left, k in {4, 6}.

    Returns
    -------
    quads : (q, 4) int64 or None
        The valid template (strictly convex quads) with the best smallest corner sine; for
        six nodes a centre node, when chosen, has id ``len(xy)``.  None when none is valid.
    centre : (2,) float64 or None
        The centre node's coordinates when the centre template was chosen.
    """
    f = np.asarray(loop, dtype=np.int64)
    if len(f) == 4:
        q = f[None, :]
        return (q, None) if convex(xy, q).all() else (None, None)
    if len(f) != 6 or len(np.unique(f)) != 6:
        return None, None
    best, best_q, centre = -np.inf, None, None
    for s in range(3):
        r = np.roll(f, -s)
        q = np.array([[r[0], r[1], r[2], r[3]], [r[3], r[4], r[5], r[0]]])
        if convex(xy, q).all():
            w = float(min_sine(xy, q).min())
            if w > best:
                best, best_q, centre = w, q, None
    c = xy[f].mean(axis=0)
    trial = np.vstack([xy, c])
    g = len(xy)
    for s in range(2):
        r = np.roll(f, -s)
        q = np.array([[g, r[0], r[1], r[2]], [g, r[2], r[3], r[4]], [g, r[4], r[5], r[0]]])
        if convex(trial, q).all():
            w = float(min_sine(trial, q).min())
            if w > best:
                best, best_q, centre = w, q, c
    return best_q, centre


def star_quads(xy, loop):
    """Closure of an even paving boundary by one centre node: quads ``(c, f[2i], f[2i+1],
    f[2i+2])`` (or shifted by one node), the centre at the nodes' mean or at the polygon's
    centroid, whichever valid choice has the best smallest corner sine.

    Returns
    -------
    (quads (k/2, 4) int64 with the centre id ``len(xy)``, centre (2,)) or (None, None)
    """
    f = np.asarray(loop, dtype=np.int64)
    if len(f) % 2 or len(np.unique(f)) != len(f):
        return None, None
    p = xy[f]
    a = signed_area(p)
    if a <= 0.0:
        return None, None
    cross = p[:, 0] * shift_next(p[:, 1]) - shift_next(p[:, 0]) * p[:, 1]
    centroid = ((p + shift_next(p)) * cross[:, None]).sum(axis=0) / (6.0 * a)
    g = len(xy)
    best, pick = -np.inf, (None, None)
    for c in (p.mean(axis=0), centroid):
        trial = np.vstack([xy, c])
        for s in range(2):
            r = np.roll(f, -s)
            q = np.column_stack([np.full(len(f) // 2, g), r[0::2], r[1::2], shift_next(r[0::2])])
            if convex(trial, q).all():
                w = float(min_sine(trial, q).min())
                if w > best:
                    best, pick = w, (q, c)
    return pick


def _chord_nodes(length, h, parity):
    """Nodes on chords of the given lengths at sizes ``h``: the count nearest
    ``length / h - 1`` whose parity is ``parity`` (None: any)."""
    ideal = length / h - 1.0
    k = np.maximum(0, np.rint(ideal)).astype(np.int64)
    if parity is not None:
        wrong = (k % 2) != parity
        k = np.where(wrong, np.where((ideal >= k) | (k == 0), k + 1, k - 1), k)
    return k


def _split_angles(d, th_i, ang_i, th_j, ang_j):
    """Smallest of the four angles a chord ``d`` (from i to j) leaves beside it (degrees)."""
    ai = (np.degrees(np.arctan2(d[:, 1], d[:, 0])) - th_i) % 360.0
    aj = (np.degrees(np.arctan2(-d[:, 1], -d[:, 0])) - th_j) % 360.0
    return np.minimum(np.minimum(ai, ang_i - ai), np.minimum(aj, ang_j - aj))


def _first_clear(xy, p_i, p_j, a_ids, b_ids, ks, order, oa, ob):
    """The first candidate (in ``order``) whose chord, with its nodes, meets no edge of
    ``oa, ob``: (index, chord node coordinates, chain of ids) or None."""
    base = len(xy)
    for c in order[:CHORD_TRIES].tolist():
        k = int(ks[c])
        t = np.arange(1, k + 1) / (k + 1)
        pts = p_i[c] + t[:, None] * (p_j[c] - p_i[c])[None, :]
        ids = base + np.arange(k, dtype=np.int64)
        chain = np.concatenate([[a_ids[c]], ids, [b_ids[c]]])
        trial = np.vstack([xy, pts]) if k else xy
        ca, cb = chain[:-1], chain[1:]
        if not pk.row_crossings(trial, ca, cb, np.concatenate([oa, ca]), np.concatenate([ob, cb])).any():
            return c, pts, ids
    return None


def _size_where_allowed(field, a, b, split):
    """The size at the midpoints of the chords ``a`` to ``b`` that leave no angle below
    :data:`CHORD_MIN_ANGLE` (infinite elsewhere: :func:`_ranked` never picks those): a
    graded field costs a search per point, and a bridge asks it for every pair of nodes."""
    ok = split >= CHORD_MIN_ANGLE
    h = np.full(len(split), np.inf)
    if ok.any():
        h[ok] = field(0.5 * (a[ok] + b[ok]))
    return h


def _ranked(split, length, h, k):
    """Candidate chords, best first, or None: the smallest angle each leaves beside it,
    less penalties for a spacing off the size and for every node on it (short chords
    first, so a thin region is cut straight across); only chords within
    :data:`CHORD_REACH` sizes when there are any, none leaving an angle below
    :data:`CHORD_MIN_ANGLE`."""
    score = split - 45.0 * np.abs(length / ((k + 1) * h) - 1.0) - 15.0 * k
    ok = split >= CHORD_MIN_ANGLE
    near = ok & (length <= CHORD_REACH * h)
    pick = np.flatnonzero(near if near.any() else ok)
    if not len(pick):
        return None
    return pick[np.argsort(-score[pick], kind="stable")]


def _geometry(xy, g):
    p = xy[g]
    ang = np.degrees(loop_angles(p))
    th = np.degrees(np.arctan2(*(shift_next(p) - p)[:, ::-1].T))
    return p, ang, th


def _best_chord(xy, g, field, oa, ob):
    """Chord of loop ``g`` with the best score: (chord nodes (k, 2), part, part) or None."""
    n = len(g)
    p, ang, th = _geometry(xy, g)
    i, j = np.triu_indices(n, 2)
    keep = ~((i == 0) & (j == n - 1)) & (g[i] != g[j])
    i, j = i[keep], j[keep]
    d = p[j] - p[i]
    length = np.hypot(*d.T)
    split = _split_angles(d, th[i], ang[i], th[j], ang[j])
    h = _size_where_allowed(field, p[i], p[j], split)
    k = _chord_nodes(length, h, parity=((j - i + 1) % 2))
    order = _ranked(split, length, h, k)
    if order is None:
        return None
    hit = _first_clear(xy, p[i], p[j], g[i], g[j], k, order, np.concatenate([oa, g]), np.concatenate([ob, shift_next(g)]))
    if hit is None:
        return None
    c, pts, ids = hit
    a, b = int(i[c]), int(j[c])
    return pts, np.concatenate([g[a : b + 1], ids[::-1]]), np.concatenate([g[b:], g[: a + 1], ids])


def close_loop(xy, loop, field, oa, ob, max_parts: int, partial: bool = False, sizes=None):
    """Close a paving boundary by chords and templates.

    Parameters
    ----------
    xy : (n, 2) float64
    loop : (k,) int
        Even, region on the left, no other paving boundary inside.
    field : SizeField
        Size of the chord nodes' spacing.
    oa, ob : (m,) int64
        Edges of the other paving boundaries (chords may not meet them).
    max_parts : int
        Cap on chords and templates.
    partial : bool
        A loop above :data:`LONG_LOOP` nodes may close in part: the parts that no chord,
        template or centre node closes are returned open (for the void fill) while the
        others close.  Smaller loops close whole or not at all.
    sizes : (k,) float64, optional
        The field at the loop's nodes where the caller knows it already (a loop above
        :data:`LONG_LOOP` nodes asks the field there only; a sliver's thin test has
        just asked it at the same nodes).

    Returns
    -------
    (new coordinates (j, 2), quads (q, 4) int64, open parts) or None
        New nodes numbered from ``len(xy)``; the open parts a list of (r,) int64 node
        ids (region on the left; empty unless ``partial``); None when nothing closes, or
        some part does not and ``partial`` is False.
    """
    if len(loop) > LONG_LOOP:
        done = _close_long(xy, np.asarray(loop, dtype=np.int64), field, oa, ob, max_parts, sizes)
        if done is None or (done[2] and not partial):
            return None
        return done
    extra: list[np.ndarray] = []
    quads: list[np.ndarray] = []
    todo = [np.asarray(loop, dtype=np.int64)]
    for _ in range(max_parts):
        if not todo:
            break
        g = todo.pop()
        cur = np.vstack([xy] + extra) if extra else xy
        if len(g) <= 6:
            q, centre = closure_quads(cur, g)
            if q is None:
                return None
            if centre is not None:
                extra.append(centre[None, :])
            quads.append(q)
            continue
        parts = _best_chord(cur, g, field, oa, ob)
        if parts is None:
            q, centre = star_quads(cur, g) if len(g) <= STAR_MAX else (None, None)
            if q is None:
                return None
            extra.append(centre[None, :])
            quads.append(q)
            continue
        pts, a, b = parts
        if len(pts):
            extra.append(pts)
        todo += [a, b]
    if todo or not quads:
        return None
    return (np.vstack(extra) if extra else np.zeros((0, 2))), np.concatenate(quads), []


def _close_long(xy, loop, field, oa, ob, max_parts, sizes=None):
    """:func:`close_loop` of a loop above :data:`LONG_LOOP` nodes, in one kernel
    (:func:`meshwright.quad._paving_long.close_long`: near chords only, long parts cut
    near their middle, the size asked at the loop's nodes only, or ``sizes`` there);
    the open parts as global ids; None when no quad closes."""
    n = len(loop)
    room = n + 4 * n + 64
    P = np.empty((room, 2))
    P[:n] = xy[loop]
    H = np.empty(room)
    H[:n] = field(P[:n]) if sizes is None else sizes
    lo, hi = P[:n].min(axis=0), P[:n].max(axis=0)
    if len(oa):
        e = np.column_stack([xy[oa], xy[ob]])
        near = (np.maximum(e[:, 0], e[:, 2]) >= lo[0]) & (np.minimum(e[:, 0], e[:, 2]) <= hi[0])
        near &= (np.maximum(e[:, 1], e[:, 3]) >= lo[1]) & (np.minimum(e[:, 1], e[:, 3]) <= hi[1])
        other = np.ascontiguousarray(e[near])
    else:
        other = np.zeros((0, 4))
    q, used, open_ids, open_ptr = pl.close_long(
        P, H, n, other, CHORD_MIN_ANGLE, CHORD_REACH, CHORD_TRIES, STAR_MAX, max_parts
    )
    if not len(q):
        return None
    ids = np.concatenate([loop, len(xy) + np.arange(used - n, dtype=np.int64)])
    open_parts = [ids[open_ids[a:b]] for a, b in zip(open_ptr[:-1].tolist(), open_ptr[1:].tolist())]
    return P[n:used].copy(), ids[q], open_parts


def bridge(xy, outer, hole, field, oa, ob):
    """Join a hole's paving boundary to the one around it by the best chord.

    Parameters
    ----------
    xy : (n, 2) float64
    outer, hole : (k,) int64
        Paving boundaries, regions on their left; ``hole`` inside ``outer``.
    field : SizeField
    oa, ob : (m,) int64
        Every paving-boundary edge (the chord may meet none).

    Returns
    -------
    (chord node coordinates (j, 2), joined boundary) or None
    """
    pa, anga, tha = _geometry(xy, outer)
    pb, angb, thb = _geometry(xy, hole)
    i, j = np.divmod(np.arange(len(outer) * len(hole)), len(hole))
    d = pb[j] - pa[i]
    length = np.hypot(*d.T)
    split = _split_angles(d, tha[i], anga[i], thb[j], angb[j])
    h = _size_where_allowed(field, pa[i], pb[j], split)
    k = _chord_nodes(length, h, None)
    order = _ranked(split, length, h, k)
    if order is None:
        return None
    hit = _first_clear(xy, pa[i], pb[j], outer[i], hole[j], k, order, oa, ob)
    if hit is None:
        return None
    c, pts, ids = hit
    a, b = int(i[c]), int(j[c])
    joined = np.concatenate([outer[: a + 1], ids, hole[b:], hole[: b + 1], ids[::-1], outer[a:]])
    return pts, joined


def facing_order(ids, fid, pos, p, nrm, reach, sizes):
    """Every pair (u, v) of paving-node slots (node ``ids``, boundary ``fid``, position
    ``pos`` along it, coordinates ``p``, unit bisectors ``nrm`` into the unmeshed region)
    closer than both their ``reach``, facing each other, not near neighbours along one
    boundary (and an even distance apart there, so both parts stay even), closest first
    (ties in the kernel's order): two (j,) int64 arrays
    (:func:`meshwright.quad._paving_kernel.facing_pairs`).  The paver tries them in
    this order until one joint holds, without searching again after a refused one."""
    size = np.asarray(sizes, dtype=np.int64)[fid]
    room = 64
    for _ in range(64):
        u = np.empty(room, dtype=np.int64)
        v = np.empty(room, dtype=np.int64)
        d = np.empty(room)
        cnt = pk.facing_pairs(p, nrm, reach, ids, fid, pos, size, u, v, d)
        if cnt <= room:
            break
        room = 2 * cnt
    order = np.argsort(d[:cnt], kind="stable")
    return u[order], v[order]


def fill_voids(xy, voids, field, seed, obstacles=None):
    """Quads (and left-over triangles) of the region bounded by the stopped paving
    boundaries, by advancing-front triangles paired and enhanced (18.5.1); node ids of
    ``xy``, new nodes appended.  ``obstacles``
    (:class:`~meshwright.quad._paving_obstacles.Obstacles`, optional): interior segment
    pieces and points inside the voids, which become constraints and nodes of the
    triangulation (no pair crosses a piece).  Returns (xy, quads, triangles)."""
    from meshwright.tri.cdt import cdt_build
    from meshwright.tri.front import advancing_front

    ring = np.concatenate(voids).astype(np.int64, copy=False)
    if obstacles is None:
        nodes = np.unique(ring)
    else:
        nodes = np.unique(np.concatenate([ring, obstacles.seg_a, obstacles.seg_b, obstacles.points]))
    # Each void's edges in order, numbered by rank among the nodes (a dict and a pair
    # per edge in Python cost 0.2 s on a sliver's 2,000 open parts).
    seg = np.searchsorted(nodes, np.column_stack([ring, np.concatenate([shift_next(f) for f in voids])]))
    # An edge a paving boundary runs both ways (a slit left by joints and seams) has the
    # region on both sides: one copy, as a constraint with no side.
    n = len(nodes)
    fwd = seg[:, 0] * n + seg[:, 1]
    slit = np.isin(seg[:, 1] * n + seg[:, 0], fwd)
    keep = ~slit | (seg[:, 0] < seg[:, 1])
    seg, sides = seg[keep], np.where(slit[keep], 0, 1)
    if obstacles is not None and len(obstacles.seg_a):
        # Interior segment pieces: constraints with the region on both sides.
        inner = np.searchsorted(nodes, np.column_stack([obstacles.seg_a, obstacles.seg_b]))
        seg, sides = np.concatenate([seg, inner]), np.concatenate([sides, np.zeros(len(inner), dtype=sides.dtype)])
    ct = cdt_build(xy[nodes], seg, seed=seed)
    ct.classify(segment_sides=sides)
    # Rows keep their boundary's spacing while the field may grow away from the walls:
    # a front at the field's size would fan thin triangles onto a stopped row's short
    # edges, which no pairing takes.  The spacing of the void's own boundary nodes
    # (chapter 18.3's background), where smaller, lets the front grow from it instead.
    # Only the void's own triangles: the front asks inside it, and the hull's triangles
    # between the open parts of a folded sliver (1,400 parts) crowded the grid's buckets
    # (0.4 s of bucketing; same values on quad2d and the paving reproducers).
    bg = BackgroundGrid.from_boundary(ct.points, ct.segments()[0], ct.triangles(True))
    # Located by walking from the last query's triangle: the grid's bucket scan searched
    # buckets crowded by this triangulation's long triangles (same values).
    grid, hint = bg.kernel_args(), np.zeros(1, dtype=np.int64)

    def capped(p):
        # Asked in a serpentine order over a grid of the batch's box: the front's new
        # nodes come in face order, jumping across the void, and both the walk and the
        # graded field's search start from the last query (half the walk's cost on the
        # three-element airfoil; each value is the same in any order).
        q = np.ascontiguousarray(p, dtype=np.float64)
        order = serpentine(q)
        ahead = np.ascontiguousarray(q[order])
        out = np.empty(len(q))
        out[order] = np.minimum(field(ahead), pk.walk_spacing(*grid, hint, ahead))
        return out

    pts, tris = advancing_front(ct, as_size_field(capped), finish=False)
    # Back to global ids: the triangulation's own vertices, then the front's new nodes.
    n_ct = ct.n_points
    glob = np.empty(n_ct, dtype=np.int64)
    glob[ct.index_map] = nodes
    blocked = np.empty_like(seg)
    blocked[:] = ct.index_map[seg]
    quads, _, left, t3, _, pts2 = pair_triangles(pts, tris, blocked, seed=seed)
    bnd = np.zeros(len(pts2), dtype=bool)
    bnd[:n_ct] = True
    pts2, quads, _, _ = enhance(pts2, quads, bnd, t3[left])
    # The pairing's last round admits non-convex pairs: the guarded smoother opens most
    # (a move never lowers the smallest corner sine around a node), the rest go back to
    # two triangles each.  A reflex corner already holds its quad's smallest sine, so the
    # guard may let a node pass over the other diagonal too, leaving a quad that no
    # diagonal splits (thin and tiny voids): then the smoothing is redone with every
    # non-convex pair held as its two triangles, which the guard keeps counter-clockwise.
    held = pts2
    pts2 = smooth_cells(held, quads, t3[left], bnd, VOID_SMOOTH)
    try:
        quads, lt = unpair_nonconvex(pts2, quads, t3[left])
    except MeshingError:
        bent = nonconvex(held, quads)
        halves = unpair_nonconvex(held, quads[bent], t3[left])[1]
        pts2 = smooth_cells(held, np.delete(quads, bent, axis=0), halves, bnd, VOID_SMOOTH)
        quads, lt = unpair_nonconvex(pts2, quads, t3[left])
    extra = pts2[n_ct:]
    m = np.concatenate([glob, len(xy) + np.arange(len(extra))])
    return np.vstack([xy, extra]), m[quads], m[lt]


def encloses(xy, f, others) -> bool:
    """Whether the first node of another paving boundary lies inside the polygon ``f``
    (crossing count; then ``f`` alone does not bound its region)."""
    p = xy[f]
    q = shift_next(p)
    for g in others:
        x, y = xy[g[0]]
        up = (p[:, 1] <= y) != (q[:, 1] <= y)
        t = (y - p[:, 1]) / np.where(up, q[:, 1] - p[:, 1], 1.0)
        if (up & (p[:, 0] + t * (q[:, 0] - p[:, 0]) > x)).sum() % 2:
            return True
    return False


def boundary_loops(domain, disc) -> list[np.ndarray]:
    """Each loop's nodes in order, the domain on the left: the paving boundaries of a
    :class:`~meshwright.geometry.Domain` and its ``Discretization``."""
    loops = []
    seg = disc.segments.astype(np.int64)
    loop_of = domain.curve_loop[disc.segment_curve]
    for li in range(len(domain.loops)):
        s = seg[loop_of == li]
        if (s[1:, 0] == s[:-1, 1]).all() and s[-1, 1] == s[0, 0]:
            # Segments already in order (the discretisation's own order): the walk
            # below would give their first ends, at a dict lookup per node (0.5 s on a
            # sliver's 90k nodes).
            loops.append(s[:, 0].copy())
            continue
        nxt = dict(zip(s[:, 0].tolist(), s[:, 1].tolist()))
        start = int(s[0, 0])
        order = [start]
        v = nxt[start]
        while v != start and len(order) <= len(s):
            order.append(v)
            v = nxt[v]
        loops.append(np.asarray(order, dtype=np.int64))
    return loops


def consistent(fronts) -> bool:
    """Every directed paving-boundary edge once, none from a node to itself: what a seam
    or joint must leave (two nodes merged next to each other elsewhere would not)."""
    if not fronts:
        return True
    off = np.concatenate([[0], np.cumsum([len(f) for f in fronts])]).astype(np.int64)
    return bool(pr.edges_once(np.concatenate(fronts).astype(np.int64, copy=False), off))


def despike(front: np.ndarray, keep: int = 0) -> np.ndarray:
    """Drop the spikes ``x, y, x`` of a paving boundary: the edge x y, zipped by seams or
    joints, has quads on both sides and is no front any more (two nodes fewer: the count
    stays even).  A spike between two nodes below ``keep`` stays: an interior segment's
    piece that the paving boundary runs both ways (a hard line) has no quad yet."""
    f = front
    for _ in range(len(front)):
        if len(f) <= 2:
            return f
        hit = np.flatnonzero(shift_prev(f) == shift_next(f))
        if keep:
            hit = hit[(f[hit] >= keep) | (shift_prev(f)[hit] >= keep)]
        if not len(hit):
            return f
        i = int(hit[0])
        f = np.delete(f, [i, (i + 1) % len(f)])
    return f


def front_slots(pts, fronts):
    """Every slot of a list of paving boundaries: node ids, boundary index, position
    along it (all (m,) int64) and the unit bisector into the unmeshed region (m, 2)."""
    ids = np.concatenate(fronts).astype(np.int64, copy=False)
    size = np.array([len(f) for f in fronts], dtype=np.int64)
    off = np.concatenate([[0], np.cumsum(size)])
    fid = np.repeat(np.arange(len(fronts), dtype=np.int64), size)
    pos = np.arange(len(ids), dtype=np.int64) - off[fid]
    return ids, fid, pos, pr.front_bisectors(pts, ids, off)


def area_kept(xy, front, trial, a, b, at) -> bool:
    """A seam only removes region: the signed area of the paving boundary does not
    grow, and a boundary around its region (positive area) keeps a positive one
    unless it closed (two nodes or fewer); a quality rule up to round-off."""
    before = signed_area(xy[front])
    moved = xy[trial]
    moved[(trial == a) | (trial == b)] = at
    after = signed_area(moved) if len(trial) > 2 else 0.0
    # Zipped slits have zero area: round-off is no change.
    tol = 1e-9 * float(np.ptp(xy[front], axis=0).max()) ** 2
    return after <= before + tol and (before <= tol or after > -tol or len(trial) <= 2)

def clear_after_merge(xy, fronts, a, b, at) -> bool:
    """No paving-boundary edge at node a or b, moved to ``at``, meets another
    paving-boundary edge (exact).  ``xy`` is changed during the test and restored."""
    sa, sb = edges_of(fronts)
    sa = np.where(sa == b, a, sa)
    sb = np.where(sb == b, a, sb)
    mine = (sa == a) | (sb == a)
    keep = sa != sb
    # Node b is on no edge any more: only a moves, in place and back (a copy of every
    # point per trial cost more than the test).
    old = xy[a].copy()
    xy[a] = at
    try:
        return not pk.row_crossings(xy, sa[mine & keep], sb[mine & keep], sa[keep], sb[keep]).any()
    finally:
        xy[a] = old
