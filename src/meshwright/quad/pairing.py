r"""Quadrilaterals by pairing advancing-front triangles (chapter 18.5.1, Zhu et al. 1991).

Source: J. Z. Zhu, O. C. Zienkiewicz, E. Hinton and J. Wu, "A new approach to the
development of automatic quadrilateral mesh generation", Int. J. Numer. Meth. Eng. 32,
1991, as summarised in section 18.5.1 of the reference chapter: an even number of
boundary nodes, two triangles sharing a side combined into one quadrilateral as the front
advances, then shape enhancement (node elimination, element elimination, diagonal
swapping, side elimination) and smoothing.

What this module does (and what it does not)
--------------------------------------------
This is the *frontal pairing* route: the advancing front of 18.2
(:func:`meshwright.tri.front.advancing_front`, spacing, stretching and direction from the
size field or background grid exactly as there) makes its triangles first, numbered in
the order the front made them, and the pairing then walks them in that order.  The front's
own finishing (diagonal swaps and a Laplacian, ``advancing_front(finish=False)``) is
skipped: the enhancement and the quad smoothing below reshape the quads themselves.

1. **Even boundaries.**  Every loop gets an even number of boundary nodes: a loop whose
   discretisation is odd gets one node on its longest segment, on the true curve (the
   segment's arc-length midpoint), and up to :data:`RESPACE` nodes on each side along the
   same curve piece are spaced evenly again, so the front meets no half-length segment
   (it would close a sliver there).  With ``fixed_boundary=True`` the discretisation is
   kept and an odd loop raises :class:`~meshwright.quad.parity.ParityError` naming it; without it the triangle
   front grades the boundary first (``advancing_front(grade=True)``: a segment longer
   than ``GRADE`` sizes of its finer end is halved towards it, an even number of new
   nodes per segment, and faces keep shortest-first order while sizes are evaluated), so a
   size jump along the boundary does not close in slivers.  Even loops make the
   triangle count of the domain even (``t = 2 n_inside + n_boundary - 2 + 2 holes``), the
   necessary condition for pairing every triangle.  A given size is graded from boundary
   points spaced closer than it, and ``size="boundary"``'s background capped, as
   :func:`meshwright.triangulate` does (:mod:`meshwright.quad._pairing_finish`): a front
   from close boundary vertices at a coarse size closes in fans no pair can take (two
   boundary sides at a corner of nearly 180 degrees), which only chords could finish
   (Zhu's front, which grades its boundary at size jumps itself, keeps the boundary
   discretised at the given size, and its ``size="boundary"`` background uncapped).
   Before pairing, an ear of the front
   (a triangle on two boundary sides) wider than :data:`FLAT_ANGLE` has its third side
   flipped, or split at its midpoint when the flip is not convex, since no pair could
   take it.
2. **Pairing in front order** (:func:`~meshwright.quad._pairing_kernel.greedy_pairs`): the
   first unpaired triangle ABC (the chapter's step 2) is combined with the neighbour across
   one of its sides (steps 5-6, 8) that has no other partner left, else with the one
   making the best quadrilateral.  Strictly convex pairs (exact ``orient2d`` at both new
   corners) whose scaled Jacobian reaches a bound come first; the bound is lowered in
   steps (:data:`PAIR_BOUNDS`) down to plain convexity, and a last round admits, as the
   chapter does before enhancement, pairs with a corner of 180 degrees or more (step 5
   below repairs or reverts them).  No round pairs across a boundary or interior segment,
   or leaves a boundary node in one quad at a corner wider than 150 degrees, nor a
   segment's fixed node between its segment and the side to another fixed segment node
   or interior point (no later step moves either).
3. **Side elimination** of left-over triangles
   (:func:`~meshwright.quad._pairing_kernel.augment`): an unpaired triangle and another
   one reached through an alternating chain of pairs exchange partners along the chain, so
   both end paired (each exchange removes a diagonal and inserts another; breadth first,
   :data:`MAX_VISIT` triangles per search, Edmonds' blossoms shrunk).  Triangles still
   unpaired then *walk*: the diagonal between one and a paired neighbour is flipped, the
   two new triangles paired, the neighbour's old partner freed, and the search repeated
   (at most :data:`MAX_WALKS` rounds, :data:`STALE_WALKS` without progress, or
   :data:`DOMAIN_STALE_WALKS` in :func:`pair_domain`).  If triangles
   are still left, a second attempt splits them at their centroids (:data:`CENTRE_ROUNDS`:
   a boundary fan's nodes get a second interior side) and pairs again; it is kept when
   it pairs everything with a scaled Jacobian of at least :data:`CENTRE_KEEP`.  This is the
   global counterpart of the chapter's sub-front parity rule (steps 3, 5(c) and 6), which
   keeps every sub-front even so that no triangle is stranded.
4. **Shape enhancement** (:func:`meshwright.quad.enhancement.enhance`, up to
   ``ENHANCE_PASSES`` passes): node elimination (an interior node in two quads: they
   become one), element elimination (a quad between two interior nodes of three quads
   each: the two nodes merge at their midpoint, the quad disappears), diagonal swapping
   (two quads sharing a side: the side moves to the hexagon diagonal with the better worst
   scaled Jacobian).  Every result is strictly convex by exact ``orient2d``.
5. **Smoothing** (``ENHANCE_SMOOTH`` passes, :func:`meshwright.quad.enhancement.smooth_quads`,
   part of the enhancement whatever ``quadrangulate``'s ``smooth``, which adds the shared
   smoother's sweeps afterwards): the chapter's Laplacian (:func:`meshwright.tri.smoothing.smooth`) over the four corner
   triangles of every quad, so a move is accepted only if every quad stays strictly
   convex; boundary nodes slide on their true curves (``smooth_boundary=True``; on
   parametric curves by Newton steps in the curve parameter) or stay fixed; after
   the first pass only nodes whose neighbourhood still moves are visited
   (:data:`~meshwright.quad.enhancement.ENHANCE_SETTLE`); curve joints, polygon
   corners and interior points never move.  The
   nodes of a non-convex quad move only to make it convex; a quad still non-convex after
   smoothing is cut back into two triangles (``PairingReport.reverted``).
6. **All-quad route**: triangles that are still unpaired (a face of the domain cut off
   by interior segments with an odd count, a boundary fan the pairing cannot take, a
   quad cut back in step 5) are finished, when ``all_quad=True``, by chord refinement
   (:func:`meshwright.quad.chords.chord_split`): each side of a left-over triangle starts
   a chord through the quads beyond it to the boundary or to another triangle; crossed sides get their
   midpoints (on the true curves for boundary sides), each crossed quad splits in two (in
   four where chords cross), each triangle into three quads; the result conforms, and is
   smoothed again around the chords (:data:`CHORD_RINGS` rings of nodes).  Unlike one midpoint split of every element
   (:func:`meshwright.quad.subdivide.split_all`), only the quads on the chords change.
   With ``all_quad=False`` the quad-dominant mesh is returned and :class:`PairingReport`
   counts the triangles left.
7. **Polish**: where a quad has a corner sine under ``POLISH_BELOW``, paving's max-min
   pattern search (:func:`meshwright.quad._paving_close.polish`) moves the free nodes of
   such quads (not line nodes, fixed points, or left-over triangles' nodes), never
   lowering the smallest corner sine around a node: the Laplacian stalls beside slivers.

With ``front="pairs"`` (method ``"zhu"``) the chapter's own front makes the triangles two
at a time, every sub-front even (steps 1-9, :mod:`meshwright.quad.zhu`), and steps 2-3
only pair what it left to the triangle front.  The chapter does not define its four enhancement operations; "side elimination" is read
here as the removal of the side between two unpaired triangles (step 3) and the others
as in Zhu et al.'s names.

Array layout: points (n, 2) float64; triangles (t, 3) and quads (q, 4) int32
counter-clockwise; the kernel's flat arrays in :mod:`meshwright.quad._pairing_kernel`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from meshwright.core.errors import InputError, MeshingError, fmt_point
from meshwright.core.predicates import orient2d_batch
from meshwright.core.quality import triangle_quality
from meshwright.core.validate_input import (
    as_cells,
    as_points,
    check_count,
    check_flag,
    check_seed,
)
from meshwright.geometry.curves import Parametric, Polyline
from meshwright.geometry.domain import Domain
from meshwright.quad import _pairing_kernel as pk
from meshwright.quad._pairing_finish import boundary_background, given_size, polish_fill
from meshwright.quad.chords import chord_split_candidates
from meshwright.quad.parity import make_loops_even
from meshwright.quad.zhu import zhu_front
from meshwright.quad.enhancement import (
    ENHANCE_SMOOTH,
    _fixed_nodes,
    enhance,
    min_scaled_jacobian,
    resplit_leftovers,
    smooth_quads,
    unpair_nonconvex,
)
from meshwright.sizing.background import BackgroundGrid
from meshwright.sizing.field import as_size_field
from meshwright.tri.cdt import SegmentCurves, cdt_build
from meshwright.tri.front import advancing_front

__all__ = [
    "CENTRE_KEEP", "CENTRE_ROUNDS", "CHORD_RINGS", "DOMAIN_EARLY_VISIT", "DOMAIN_STALE_WALKS", "EARLY_VISIT",
    "FLAT_ANGLE", "FRONTS", "MAX_VISIT", "MAX_WALKS", "PAIR_BOUNDS", "STALE_WALKS", "PairingReport",
    "pair_domain", "pair_triangles", "pairing_fill",
]

PAIR_BOUNDS = (0.5, 0.3, 0.0, -1.0)  # scaled-Jacobian floors of the pairing rounds; 0: strictly convex; < 0: any
MAX_VISIT = 4096  # triangles one alternating-chain search may enter (last round)
EARLY_VISIT = 64  # ... in the rounds before the last
# ... in pair_domain: 64 left the h=0.01 disk six triangles for the chords, 256 pairs them all
# and raises the airfoils' min scaled Jacobian; paving's void fill (pair_triangles) keeps 64,
# its three-element airfoil fell from 50.1 to 42.8 degrees with 256.
DOMAIN_EARLY_VISIT = 256
MAX_WALKS = 64  # rounds of moving unpaired triangles by diagonal flips
STALE_WALKS = 8  # ... stopped after this many rounds without fewer unpaired triangles
# ... in pair_domain: over the domains of benchmarks/quad_domains.py no walk gained after two
# stale rounds there, and each costs a full chain search (about 0.09 s on the h=0.01 disk,
# eight of them 13 % of its time); paving's void fill (pair_triangles) keeps STALE_WALKS,
# its angles on the three-element airfoil fell from 49.2 to 46.2 degrees with two.
DOMAIN_STALE_WALKS = 2
CENTRE_ROUNDS = 2  # rounds of splitting the still unpaired triangles at their centroids (second attempt)
CENTRE_KEEP = 0.3  # ... kept only if it pairs everything with a scaled Jacobian of at least this
FLAT_ANGLE = 150.0  # degrees: an ear of the front flatter than this is flipped open before pairing
EAR_FLOOR = 1e-6  # ... or split open, unless a triangle of the split is flatter than this (radius ratio 2r/R)
FRONTS = ("pairs", "triangles")  # pair_domain's fronts: Zhu's pair by pair, or triangles then matching
CHORD_RINGS = 2  # rings of nodes around a chord refinement's new nodes smoothed again


class PairingReport(NamedTuple):
    """What the pairing did.

    Attributes
    ----------
    nodes_added : tuple of int
        Loops that received one node to make their count even.
    triangles : int
        Triangles the advancing front made.
    paired : int
        Quads formed by pairing (greedy and alternating chains).
    chains : int
        Pairs gained along alternating chains (side elimination).
    left_over : int
        Triangles left unpaired after pairing.
    reverted : int
        Quads that enhancement and smoothing left non-convex, cut back into two
        triangles each.
    eliminated : tuple of int
        Node eliminations, element eliminations and diagonal swaps.
    split : bool
        Whether the all-quad route refined along chords
        (:func:`meshwright.quad.chords.chord_split`).
    triangles_left : int
        Triangles in the returned mesh (0 when ``all_quad``).
    """

    nodes_added: tuple
    triangles: int
    paired: int
    chains: int
    left_over: int
    reverted: int
    eliminated: tuple
    split: bool
    triangles_left: int


def _neighbours(tris: np.ndarray, bkey: np.ndarray, n: int) -> np.ndarray:
    """(t, 3) int32 neighbours with -1 across the blocked edges (sorted keys ``min * n + max``)."""
    nbr, bad = pk.dual_neighbours(np.ascontiguousarray(tris, dtype=np.int32).ravel(), n, bkey)
    if bad >= 0:
        raise MeshingError(
            f"triangle {bad} {tris[bad].tolist()} shares an edge with more than one triangle, or traverses it in "
            "the same direction as its neighbour; the triangles to pair must be a consistently oriented mesh"
        )
    return nbr.reshape(-1, 3)


def _walk_left_overs(tris, nbr, mate, raw, rng, qmin) -> np.ndarray:
    """Move every unpaired triangle t one pair further: flip the diagonal between t and a
    paired neighbour s (their union an allowed quad: a raw score ``raw`` of at least
    ``qmin`` >= 0, :func:`~meshwright.quad._pairing_kernel.side_scores`), pair the two new
    triangles and free s's old partner; ``tris`` and ``nbr`` are updated in place, ``raw``
    is not (the caller rescores the flipped triangles).  Each walking triangle tries its
    sides in a random order from ``rng`` (:func:`~meshwright.quad._pairing_kernel.walk_flips`).
    Returns the triangles flipped, (2 flips,) int64."""
    # One random order per unpaired triangle is drawn ahead in one call (the rows of
    # Generator.permuted, as many permutation(3) calls would give them), the generator is
    # set back and then advances by the rows the walk used only, so its state and the
    # walk's orders are those of one permutation(3) call per walking triangle.  The walk
    # itself is compiled: in Python it cost 1.7 ms over the disk's six walks.
    rows = int((mate < 0).sum())
    state = rng.bit_generator.state
    order = rng.permuted(np.tile(np.arange(3, dtype=np.int64), (rows, 1)), axis=1)
    flipped, used = pk.walk_flips(tris, nbr, mate, raw, order, float(qmin))
    rng.bit_generator.state = state
    rng.permuted(np.tile(np.arange(3, dtype=np.int64), (int(used), 1)), axis=1)
    return flipped


def _open_ears(xy, tris, nbr, mate):
    """Open every unpaired (``mate``) triangle with two boundary sides and a corner between
    them wider than ``FLAT_ANGLE`` (a sliver the front closed along the boundary): no pair
    could take it, and any quad on it would keep that corner.  Its third side is flipped when the union
    with the neighbour is strictly convex, else split at its midpoint (both triangles in
    two, the ear vertex then joined to the interior); every new triangle is checked
    counter-clockwise by exact ``orient2d``.

    Returns
    -------
    xy : (n', 2) float64
        ``xy`` with the midpoints appended.
    tris : (t', 3) int32
        Changed in place; split triangles' second halves appended.
    changed : int
    """
    # Column by column in int8: a row sum over the (t, 3) mask cost 0.8 ms on the disk's
    # 72,184 triangles (which have no ear), this 0.1 ms.
    ears = np.flatnonzero(((nbr[:, 0] < 0).view(np.int8) + (nbr[:, 1] < 0).view(np.int8)
                           + (nbr[:, 2] < 0).view(np.int8)) == 2)
    new_xy, new_tris = [], []
    changed = 0
    for t in ears.tolist():
        if (nbr[t] == -2).any() or mate[t] >= 0:
            continue
        k = int(np.flatnonzero(nbr[t] >= 0)[0])
        s = int(nbr[t, k])
        if mate[s] >= 0:
            continue
        a, b, c = (int(v) for v in (tris[t, k], tris[t, (k + 1) % 3], tris[t, (k + 2) % 3]))
        u, w = xy[b] - xy[a], xy[c] - xy[a]
        if (nbr[s] < 0).sum() >= 2 or np.degrees(np.arctan2(u[0] * w[1] - u[1] * w[0], u @ w)) < FLAT_ANGLE:
            continue
        d = int(tris[s][nbr[s] == t][0])
        if (orient2d_batch(xy, np.array([[a, b, d], [d, c, a]])) > 0.0).all():
            tris[t] = (a, b, d)
            tris[s] = (a, d, c)
        else:
            m = len(xy) + len(new_xy)
            trial = np.vstack([xy[[a, b, c, d]], 0.5 * (xy[b] + xy[c])])
            # Local indices: a 0, b 1, c 2, d 3, m 4.
            parts = np.array([[0, 1, 4], [0, 4, 2], [2, 4, 3], [4, 1, 3]])
            if (orient2d_batch(trial, parts) <= 0.0).any():
                continue
            if triangle_quality(trial, parts)["radius_ratio"].min() < EAR_FLOOR:
                continue
            new_xy.append(trial[4])
            tris[t] = (a, b, m)
            tris[s] = (c, m, d)
            new_tris += [(a, m, c), (m, b, d)]
        # Keep the table true for the next ears: both triangles' sides changed.
        nbr[t] = nbr[s] = -2
        changed += 1
    if new_xy:
        xy = np.ascontiguousarray(np.vstack([xy, np.asarray(new_xy)]))
        tris = np.ascontiguousarray(np.vstack([tris, np.asarray(new_tris, dtype=np.int32)]))
    return xy, tris, changed


def _split_left_overs(xy, tris, mate):
    """Split every unpaired triangle at its centroid into three (all counter-clockwise by
    exact ``orient2d``, else left as it is): a triangle of a boundary fan, isolated because
    every pair would leave a boundary node in one quad at a flat corner, gives its boundary
    nodes a second interior side.  Two triangles more keep the count's parity.  Returns
    (xy, tris, mate, the triangles cut (k,) int64); the i-th cut triangle keeps its first
    part, its second and third are appended at ``t + i`` and ``t + k + i``."""
    left = np.flatnonzero(mate < 0)
    t = tris[left].astype(np.int64)
    m = len(left)
    corners = xy[t]
    centre = corners.mean(axis=1)
    # The orientation tests read the left-overs' corners and centres only (local indices:
    # corner j of left-over i at 3 i + j, its centre at 3 m + i), not a copy of every point.
    trial = np.concatenate([corners.reshape(-1, 2), centre])
    own = 3 * np.arange(m)
    ok = np.ones(m, dtype=bool)
    for k in range(3):
        ok &= orient2d_batch(trial, np.column_stack([own + k, own + (k + 1) % 3, 3 * m + np.arange(m)])) > 0.0
    if not ok.any():
        return xy, tris, mate, np.zeros(0, dtype=np.int64)
    # Renumber the kept centres so the points stay contiguous.
    kept = int(ok.sum())
    g = len(xy) + np.arange(kept)
    t = t[ok]
    xy = np.ascontiguousarray(np.vstack([xy, centre[ok]]))
    out = np.empty((len(tris) + 2 * kept, 3), dtype=np.int32)
    out[: len(tris)] = tris
    for k, rows in enumerate((left[ok], len(tris) + np.arange(kept), len(tris) + kept + np.arange(kept))):
        out[rows] = np.column_stack([t[:, k], t[:, (k + 1) % 3], g])
    mate = np.concatenate([mate, np.full(2 * kept, -1, dtype=np.int32)])
    return xy, out, mate, left[ok].astype(np.int64)


def pair_triangles(
    points, triangles, blocked=None, bounds=PAIR_BOUNDS, max_visit=MAX_VISIT, walks=MAX_WALKS, seed=0, centres=0,
):
    """Pair triangles sharing a side into strictly convex quads, in the triangles' order.

    Parameters
    ----------
    points : (n, 2) float64
    triangles : (t, 3) int32
        Counter-clockwise, in the order the front made them.
    blocked : (b, 2) int, optional
        Edges no pair may cross (boundary and interior segments).
    bounds : sequence of float
        Scaled-Jacobian floors, one greedy round and one chain round per entry.
    max_visit : int
        Triangles one alternating-chain search may enter.
    walks : int
        Rounds of moving the unpaired triangles by a diagonal flip
        (:func:`_walk_left_overs`), each followed by a chain round at the last bound;
        :data:`STALE_WALKS` rounds without progress end them.
    seed : int
        Randomness of which side a walk takes.
    centres : int
        Rounds of splitting the triangles still unpaired at their centroids
        (:func:`_split_left_overs`), each followed by a greedy and a chain round.

    Returns
    -------
    quads : (q, 4) int32
        Counter-clockwise; the pair (t, s) with t made first gives quad ``(a, b, d, c)``,
        t = (a, b, c) and d the vertex of s across b c.
    first : (q,) int64
        The first triangle of each pair.
    left : (l,) int64
        Triangles left unpaired.
    triangles : (t, 3) int32
        The triangles after the ear openings and the walks' flips (``left`` indexes them).
    chains : int
        Pairs gained along alternating chains.
    points : (n', 2) float64
        ``points`` with the nodes that opened flat ears appended (:func:`_open_ears`).

    Raises
    ------
    InputError
        Points not (n, 2) finite, a triangle or blocked edge out of range (its row named)
        or a triangle not counter-clockwise, ``bounds`` empty or not numbers,
        ``max_visit`` / ``walks`` not counts.
    """
    xy = as_points(points, "points")
    n = len(xy)
    tris = as_cells(triangles, "triangles", 3, n).copy()
    o = orient2d_batch(xy, tris)
    if (o <= 0.0).any():
        t = int(np.flatnonzero(o <= 0.0)[0])
        raise InputError(f"triangle {t} {tris[t].tolist()} is not counter-clockwise (exact orient2d)")
    blocked = as_cells(np.zeros((0, 2), dtype=np.int32) if blocked is None else blocked, "blocked", 2, n)
    try:
        bounds = tuple(float(q) for q in bounds)
    except (TypeError, ValueError):
        raise InputError(f"bounds must be a sequence of numbers, got {bounds!r}") from None
    if not bounds or not all(np.isfinite(bounds)):
        raise InputError(f"bounds must be a non-empty sequence of finite numbers, got {bounds!r}")
    max_visit = check_count(max_visit, "max_visit", 1)
    walks = check_count(walks, "walks")
    centres = check_count(centres, "centres")
    bkey = np.zeros(0, dtype=np.int64)
    if len(blocked):
        key = np.sort(blocked.astype(np.int64), axis=1)
        bkey = np.unique(key[:, 0] * n + key[:, 1])
    st = _pair_rounds(xy, tris, bkey, n, bounds, max_visit, walks, seed)
    st = _centre_rounds(st, bkey, n, bounds[-1], max_visit, centres)
    return _quads_of(st)


class _PairState(NamedTuple):
    """Where a pairing stands: points, triangles, neighbours (when the pair front left
    nothing to pair, only the pairs' shared sides, :func:`~meshwright.quad._pairing_kernel.mate_sides`:
    no chain round reads them), partners, chain gains, the raw side scores of the triangles (:func:`~meshwright.quad._pairing_kernel.side_scores`)
    and the chain searches' work arrays (:func:`~meshwright.quad._pairing_kernel.augment_scratch`,
    at rest, with rows to spare for the centroid splits), the nodes that never move (the scores' ``pinned``)."""

    xy: np.ndarray
    tris: np.ndarray
    nbr: np.ndarray
    mate: np.ndarray
    chains: int
    raw: np.ndarray
    scratch: tuple | None
    pinned: np.ndarray | None


def _pair_rounds(
    xy, tris, bkey, n, bounds, max_visit, walks, seed, stale_walks=STALE_WALKS, early_visit=EARLY_VISIT, mate=None,
    pinned=None,
) -> _PairState:
    """Ears opened, greedy and chain rounds per bound (searches of ``early_visit``
    triangles before the last), then the walks (steps 1-3), stopped after ``stale_walks``
    rounds without fewer unpaired triangles; ``mate`` (t,) int32, the pairs made already
    (the pair front's), is completed in place (nothing to do when it pairs everything);
    ``pinned`` (n,) bool, the nodes that never move (None: none), for the flat-corner rule
    (:func:`~meshwright.quad._pairing_kernel.side_scores`)."""
    mate = np.full(len(tris), -1, dtype=np.int32) if mate is None else mate
    if (mate >= 0).all():
        # Nothing to pair: the quads need only each pair's shared side, not the whole
        # neighbour table (the pair front's disk h=0.01: 2.6 ms).
        shared = pk.mate_sides(tris.ravel(), mate, n, bkey).reshape(-1, 3)
        return _PairState(xy, tris, shared, mate, 0, None, None, pinned)
    nbr = _neighbours(tris, bkey, n)
    xy, tris, changed = _open_ears(xy, tris, nbr, mate)
    if changed:
        nbr = _neighbours(tris, bkey, n)
        # A split ear appends two triangles: unpaired, as the table's other free entries.
        mate = np.concatenate([mate, np.full(len(tris) - len(mate), -1, dtype=np.int32)])
    chains = 0
    raw = pk.side_scores(xy, tris.ravel(), nbr.ravel(), pinned)
    # Rows to spare for the centroid splits' new triangles (two per left-over and round),
    # so _centre_rounds need not allocate and fill the O(triangles) arrays again.
    scratch = pk.augment_scratch(len(tris), 64 + len(tris) // 256)
    for i, q in enumerate(bounds):
        pk.greedy_pairs(raw, nbr.ravel(), mate, float(q))
        # Early rounds only mend locally: a triangle with no partner at a high bound would
        # search its whole component in vain; the last round searches far.
        visit = int(max_visit) if i == len(bounds) - 1 else min(int(max_visit), int(early_visit))
        chains += int(pk.augment(raw, nbr.ravel(), mate, float(q), visit, scratch))
    rng = np.random.default_rng(seed)
    best, stale = int((mate < 0).sum()), 0
    for _ in range(walks):
        if best == 0 or stale >= stale_walks:
            break
        flipped = _walk_left_overs(tris, nbr, mate, raw, rng, max(float(bounds[-1]), 0.0))
        if not len(flipped):
            break
        pk.rescore(raw, xy, tris.ravel(), nbr.ravel(), flipped, pinned)
        # Every chain round since the last bound's was at bounds[-1], and only the flips
        # changed sides and partners: the search table is refilled around them alone.
        chains += int(pk.augment_changed(raw, nbr.ravel(), mate, float(bounds[-1]), int(max_visit), scratch, flipped))
        left = int((mate < 0).sum())
        best, stale = (left, 0) if left < best else (best, stale + 1)
    return _PairState(xy, tris, nbr, mate, chains, raw, scratch, pinned)


def _centre_rounds(st: _PairState, bkey, n, qmin, max_visit, centres) -> _PairState:
    """Up to ``centres`` rounds of centroid splits of the unpaired triangles, each followed
    by a greedy and a chain round at ``qmin``.

    ``st.scratch``'s search table must hold ``st``'s last chain round at ``qmin`` (as
    :func:`_pair_rounds` leaves it at its last bound): a round refills only the rows around
    its cut triangles (:func:`~meshwright.quad._pairing_kernel.augment_changed`).  ``st``'s
    arrays are not modified, but its table then holds the centred rows: a chain round on
    ``st`` afterwards must refill every row (``augment``)."""
    xy, tris, nbr, mate, chains, raw, scratch = st[:7]
    for _ in range(centres):
        if not (mate < 0).any():
            break
        # The split returns new arrays, so the rounds below never write into st's; the
        # neighbours and scores change only around the cut triangles.
        nt = len(tris)
        xy, tris, mate, cut = _split_left_overs(xy, tris, mate)
        if not len(cut):
            break
        nbr = pk.split_neighbours(nbr.ravel(), cut, nt).reshape(-1, 3)
        raw = np.concatenate([raw, np.empty(3 * (len(tris) - nt))])
        parts = np.concatenate([cut, nt + np.arange(len(tris) - nt, dtype=np.int64)])
        pk.rescore(raw, xy, tris.ravel(), nbr.ravel(), parts, st.pinned)
        # The parts and the left-overs not cut: the only triangles the greedy pass can pair
        # (with each other or with a neighbour), so the rows that change lie around them.
        free = np.flatnonzero(mate < 0)
        pk.greedy_pairs(raw, nbr.ravel(), mate, float(qmin))
        if scratch is None or len(scratch[0]) < len(tris):
            scratch = pk.augment_scratch(len(tris), 64 + len(tris) // 256)
            chains += int(pk.augment(raw, nbr.ravel(), mate, float(qmin), int(max_visit), scratch))
        else:
            chains += int(pk.augment_changed(raw, nbr.ravel(), mate, float(qmin), int(max_visit), scratch, free))
    return _PairState(xy, tris, nbr, mate, chains, raw, scratch, st.pinned)


def _quads_of(st: _PairState):
    """:func:`pair_triangles`'s results from a pairing state."""
    xy, tris, nbr, mate, chains = st[:5]
    # Quad (a, b, d, c): t = (a, b, c) with a opposite the shared side, d the partner's third vertex.
    quads, first = pk.pair_quads(np.ascontiguousarray(tris).ravel(), np.ascontiguousarray(nbr).ravel(), mate)
    return quads, first, np.flatnonzero(mate < 0), tris, chains, xy


def pair_domain(
    domain: Domain,
    field=None,
    *,
    all_quad: bool = True,
    smooth: int = ENHANCE_SMOOTH,
    smooth_boundary: bool = True,
    fixed_boundary: bool = False,
    seed=0,
    max_points: int | None = None,
    front: str = "triangles",
):
    """Quadrilateral fill of ``domain`` by pairing advancing-front triangles (18.5.1).

    Parameters
    ----------
    domain : Domain
        Validated (the caller's door, :func:`meshwright.quadrangulate`).
    field : SizeField or BackgroundGrid, optional
        Spacing (a background grid also gives stretching s and direction alpha); None:
        chapter 18.3's background from the boundary nodes, as ``triangulate``'s front.
    all_quad : bool
        Refine along chords when triangles remain (module docstring, step 6).
    smooth : int
        Laplacian passes after the enhancement (and again after a split); 0 for none.
    smooth_boundary : bool
        Boundary nodes slide on their curves while smoothing; False keeps them fixed.
    fixed_boundary : bool
        Keep the discretisation's boundary nodes: an odd loop is an error, and the
        front does not grade the boundary (``advancing_front(grade=...)``).
    seed : int or numpy.random.Generator
        Randomness of the constrained triangulation and of the left-over walks.
    max_points : int, optional
        Cap on vertices (the front's nodes, and the chord refinement's).
    front : {"triangles", "pairs"}
        ``"triangles"``: the triangle front, then the matching of steps 2-3;
        ``"pairs"``: Zhu's pair-by-pair front (:func:`meshwright.quad.zhu.zhu_front`),
        the matching only for the triangles it leaves.

    Returns
    -------
    QuadFill
        See :mod:`meshwright.quad.mesher`; ``triangles`` is empty when ``all_quad``.
    PairingReport

    Raises
    ------
    InputError
        An argument of the wrong type or range (named).
    ParityError
        An odd loop with ``fixed_boundary=True`` (the loop named).
    MeshingError
        The front could not close (the face named), a cap was hit, or the result failed
        its own exact check (the quad named).
    """
    from meshwright.quad.mesher import QuadFill

    if not isinstance(domain, Domain):
        raise InputError(f"domain must be a meshwright.geometry.Domain, got {type(domain).__name__}")
    field = None if field is None else as_size_field(field)
    all_quad = check_flag(all_quad, "all_quad")
    smooth_boundary = check_flag(smooth_boundary, "smooth_boundary")
    fixed_boundary = check_flag(fixed_boundary, "fixed_boundary")
    passes = check_count(smooth, "smooth (passes)")
    seed = check_seed(seed)
    cap = np.iinfo(np.int32).max if max_points is None else check_count(max_points, "max_points", 4)
    if front not in FRONTS:
        raise InputError(f"front must be one of {', '.join(map(repr, FRONTS))}, got {front!r}")
    # Zhu's front grades its own boundary at size jumps (zhu_front(grade=...)): the
    # boundary discretised again with the graded size left slivers beside them there
    # (stress 72 / 96 / 110: 0.30 / 0.17 / 0.30 -> 0.05 / 0.06 / 0.05), so it keeps the
    # boundary discretised at the given size.
    field, disc = given_size(domain, field, fixed_boundary or front == "pairs")
    disc, added = make_loops_even(domain, disc, fixed_boundary)
    curves = SegmentCurves.from_domain(domain, disc)
    ct = cdt_build(disc.points, disc.segments, seed=seed, curves=curves)
    sides = np.where(domain.curve_loop[disc.segment_curve] >= 0, 1, 0)
    regions = [(x, y, int(m)) if a <= 0 else (x, y, int(m), float(a)) for x, y, m, a in disc.regions]
    ct.classify(segment_sides=sides, holes=disc.holes, regions=regions)
    if field is None:
        # Chapter 18.3's background, as triangulate's front takes it: the triangulated
        # boundary nodes with their point distribution function (capped for the triangle
        # front, as triangulate caps it).
        field = boundary_background(ct) if front == "triangles" else BackgroundGrid.from_boundary(
            ct.points, ct.segments()[0], ct.triangles(False)
        )
    if front == "pairs":
        # Graded like the triangle front below: a coarse boundary segment beside a size
        # jump's fine pieces would close on a node near its fine end (a sliver).
        pts, tris, zpairs, _ = zhu_front(ct, field, max_points=cap, grade=not fixed_boundary)
    else:
        pts, tris, zpairs = *advancing_front(ct, field, max_points=cap, finish=False, grade=not fixed_boundary), np.zeros((0, 2), np.int64)
    base = ct.to_mesh(segment_markers=disc.segment_markers, fill=(pts, tris))
    # The mesh keeps the front's triangle order; recover each line's curve.
    used = np.zeros(len(pts), dtype=bool)
    used[tris.ravel()] = True
    newid = np.cumsum(used) - 1
    edges, ids = ct.segments()
    keep = used[edges[:, 0]] & used[edges[:, 1]]
    n = base.n_points
    ekey = np.sort(newid[edges[keep]], axis=1)
    ekey = ekey[:, 0] * n + ekey[:, 1]
    lines = base.cells["line"]
    lkey = np.sort(lines.astype(np.int64), axis=1)
    lkey = lkey[:, 0] * n + lkey[:, 1]
    order = np.argsort(ekey)
    line_curve = disc.segment_curve[ids[keep]][order][np.searchsorted(ekey, lkey, sorter=order)].astype(np.int32)
    line_marker = base.cell_data["marker"]["line"].astype(np.int32)
    xy = base.points
    n_free = len(domain.points)
    fixed_pts = newid[ct.index_map[len(disc.points) - n_free :]] if n_free else np.zeros(0, dtype=np.int64)

    # Where the discretisation put each boundary node on its curve: the enhancement's
    # sliding starts from that parameter instead of searching the curve for it.  A node at
    # the seam of a closed parametric curve (parameter t0 or t1) stays, as at a joint of two
    # curves: a step from it leaves the curve's parameter range on one side.
    starts = ct.index_map[disc.segments[:, 0]]
    on = used[starts]
    node_t = np.full(n, np.nan)
    node_t[newid[starts[on]]] = disc.segment_params[on, 0]
    span = np.array([(c.t0, c.t1) if isinstance(c, Parametric) else (np.nan, np.nan) for c in domain.curves])
    ta, sc = disc.segment_params[:, 0], disc.segment_curve
    seam = on & ((ta == span[sc, 0]) | (ta == span[sc, 1]))
    # A polyline's vertices (integer parameters) are input vertices and stay, even where
    # they are collinear with their neighbours (a point the domain moved into a segment):
    # the smoother fixes only corners it sees bent.
    poly = np.array([isinstance(c, Polyline) for c in domain.curves], dtype=bool)
    ends = ct.index_map[disc.segments[:, 1]]
    tb = disc.segment_params[:, 1]
    vert_a = on & poly[sc] & (ta == np.floor(ta))
    vert_b = used[ends] & poly[sc] & (tb == np.floor(tb))
    fixed_pts = np.concatenate([fixed_pts, newid[starts[seam | vert_a]], newid[ends[vert_b]]]).astype(np.int64)

    # The Mesh has checked its cells (int32, C-contiguous, nodes in range) and points
    # (finite float64): no second check of 72,184 triangles (1.5 ms on the disk).
    tri_in = base.cells["triangle"].copy()
    lkey = np.sort(lines.astype(np.int64), axis=1)
    bkey = np.unique(lkey[:, 0] * n + lkey[:, 1])
    mate = np.full(len(tri_in), -1, dtype=np.int32)
    mate[zpairs[:, 0]], mate[zpairs[:, 1]] = zpairs[:, 1], zpairs[:, 0]
    # Interior segments' and points' nodes the smoothing never moves (ends, polyline
    # vertices, the points): a flat corner between such a node's segment and the side to
    # another one (two nearly collinear segments a size apart) stays flat, so no pair may
    # form it.  Loop nodes are left out: on a thin loop domain under a size jump
    # (stress-pairing-7df4e2241e4e) their refusals left fans no chord split made convex.
    # A domain of loops alone pins nothing (no NumPy pass over its nodes: the benchmarks).
    loop = domain.curve_loop[line_curve] >= 0
    pinned = None
    if n_free or not loop.all():
        pinned = _fixed_nodes(xy, lines, line_curve, domain, fixed_pts)[0]
        if not smooth_boundary:
            pinned[lines.ravel()] = True
        pinned[lines[loop].ravel()] = False
    paired = _pair_rounds(
        xy, tri_in, bkey, n, PAIR_BOUNDS, MAX_VISIT, MAX_WALKS, seed, DOMAIN_STALE_WALKS,
        DOMAIN_EARLY_VISIT, mate, pinned,
    )

    def attempt(st):
        """Enhance, smooth and revert a pairing: (xy, quads, left-over triangles, report fields)."""
        quads, first, left, t3, chains, pts = _quads_of(st)
        lt = t3[left]
        bnd = np.zeros(len(pts), dtype=bool)
        bnd[lines.ravel()] = True
        bnd[fixed_pts] = True
        pts, quads, _, counts = enhance(pts, quads, bnd, lt)
        # The chords keep a left-over triangle's corners, and a quad's corner between
        # three boundary nodes stays as the smoothing finds it: both are re-split first
        # (the enhancement helper's measurements, 5927685 / 0267ab3).
        bnd = np.zeros(len(pts), dtype=bool)
        bnd[lines.ravel()] = True
        bnd[fixed_pts] = True
        quads, lt, _ = resplit_leftovers(pts, quads, lt, bnd, lines)
        params = np.concatenate([node_t, np.full(len(pts) - n, np.nan)])
        pts = smooth_quads(pts, quads, lt, lines, line_curve, domain, fixed_pts, passes, smooth_boundary, params)
        n_quads = len(quads)
        # Almost always every quad is convex: the compiled check spares unpair_nonconvex's
        # NumPy one (2 ms on the disk h=0.01), which would find nothing to cut.
        reverted = 0
        if len(pk.nonconvex_quads(pts, quads)):
            quads, lt = unpair_nonconvex(pts, quads, lt)
            reverted = n_quads - len(quads)
            # A quad cut back into two triangles along its only valid diagonal, however thin.
            quads, lt, _ = resplit_leftovers(pts, quads, lt, bnd, lines)
        return pts, quads, lt, (len(t3), len(first), chains, len(left), reverted, counts)

    chosen = None
    if all_quad and (paired.mate < 0).any():
        # Left-overs (mostly boundary fans): try them split at their centroids, continuing
        # from the same pairing, and keep that if it needs no chords and stays well shaped
        # (a centre pairing that still leaves triangles is not enhanced).  Only then is the
        # plain pairing enhanced: attempt() does not modify its state, and a pairing with
        # no left-over has nothing to split, so the choice is the one made after it.
        centred = _centre_rounds(paired, bkey, n, PAIR_BOUNDS[-1], MAX_VISIT, CENTRE_ROUNDS)
        if not (centred.mate < 0).any():
            xy2, quads2, lt2, stats2 = attempt(centred)
            if not len(lt2) and len(quads2) and min_scaled_jacobian(xy2, quads2) >= CENTRE_KEEP:
                chosen = xy2, quads2, lt2, stats2
    xy, quads, lt, stats = attempt(paired) if chosen is None else chosen
    xy, quads, lt, lines, remap = pk.compact_nodes(
        xy, *(np.ascontiguousarray(b, dtype=np.int32) for b in (quads, lt.reshape(-1, 3), lines))
    )
    fixed_pts = remap[fixed_pts]
    node_t = np.concatenate([node_t, np.full(len(remap) - n, np.nan)])[remap >= 0]
    fill = QuadFill(xy, quads, lt, lines, line_marker, line_curve)
    split = bool(all_quad and len(lt))
    if split:
        n_before = len(fill.points)

        def settle(f):
            """Smooth a chord refinement around its new nodes.

            The refinement appends its nodes: the old indices, interior points included,
            stay valid.  Only the quads on the chords changed; the rest was smoothed
            already, so the new nodes and two rings of nodes around them move."""
            near = np.zeros(len(f.points), dtype=bool)
            near[n_before:] = True
            near = pk.grow_rings(np.ascontiguousarray(f.quads, dtype=np.int32), near, CHORD_RINGS)
            moved = smooth_quads(
                f.points, f.quads, f.triangles, f.lines, f.line_curves, domain,
                np.concatenate([fixed_pts, np.flatnonzero(~near)]), passes, smooth_boundary,
                np.concatenate([node_t, np.full(len(f.points) - n_before, np.nan)]),
            )
            return f._replace(points=np.ascontiguousarray(moved))

        # A bent plain split is often opened by the smoothing (a free node moves); the
        # re-cut one (cells too flat to split cut otherwise) is kept where the plain one
        # stays bent or smooths to a worse shape.
        plain, recut = chord_split_candidates(fill, domain, cap)
        fill = settle(plain)
        if recut is not None:
            other = settle(recut)
            if not len(pk.nonconvex_quads(other.points, other.quads)) and (
                len(pk.nonconvex_quads(fill.points, fill.quads))
                or min_scaled_jacobian(other.points, other.quads) > min_scaled_jacobian(fill.points, fill.quads)
            ):
                fill = other
    fill = polish_fill(fill, fixed_pts, domain if smooth_boundary else None)
    _check(fill.points, fill.quads, fill.triangles)
    n_tri, n_pairs, chains, n_left, reverted, counts = stats
    report = PairingReport(added, n_tri, n_pairs, chains, n_left, reverted, counts, split, len(fill.triangles))
    return fill, report


def pairing_fill(job, front="triangles"):
    """``QUAD_METHODS["pairing"]`` / ``["zhu"]``: :func:`pair_domain` on a checked :class:`QuadJob`.

    The method's own smoothing (``ENHANCE_SMOOTH`` passes, boundary nodes sliding on
    their curves) is part of its shape enhancement and always runs, since the relaxed
    pairs need it to open; ``job.smooth`` sweeps of the shared smoother follow in the
    mesher (:func:`meshwright.quadrangulate`).
    """
    return pair_domain(
        job.domain, job.field, all_quad=job.all_quad, smooth=ENHANCE_SMOOTH, seed=job.seed,
        max_points=job.max_points, front=front,
    )[0]


def _check(xy, quads, tris) -> None:
    """Exact last check: every quad strictly convex, every triangle counter-clockwise."""
    bad = pk.nonconvex_quads(xy, quads)
    if len(bad):
        q = int(bad[0])
        raise MeshingError(
            f"pairing produced a non-convex quad {q} with corners "
            + ", ".join(fmt_point(xy[v]) for v in quads[q])
        )
    if len(tris):
        o = orient2d_batch(xy, tris)
        if (o <= 0.0).any():
            t = int(np.flatnonzero(o <= 0.0)[0])
            raise MeshingError(f"pairing left an inverted triangle {t} at {fmt_point(xy[tris[t]].mean(axis=0))}")
