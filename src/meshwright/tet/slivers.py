"""Sliver identification and removal in tetrahedral meshes (chapter section 18.1.1).

A sliver is a tetrahedron whose faces are fine triangles but whose volume is almost
zero: four points near a common circle (Figure 18.1.4a).  Delaunay tetrahedralizations
are full of them, since the empty-sphere criterion does not mind a flat tet whose
circumsphere is empty.  The chapter (after Cavendish, Field and Frey, 1985) flags a
tet when ``a = r_in / R_circ < 0.01`` (1/3 for the regular tet) and removes it either
by a flip, when two of its neighbours share a vertex E ({ABDE, BCDE} -> {ABCE, ACDE}),
or by moving one of its vertices.

:func:`remove_slivers` does that with the general flips of which the chapter's is a
special case (see :mod:`meshwright.tet._flips` for sketches): the chapter's flip is the
3-2 flip that removes the sliver's edge BD when the two neighbours across the faces at
BD share the apex E; with it come the 2-3 flip across any interior face, the 4-4 flip
and edge removal on rings of up to 7 tets.  A flip is applied only if it raises the
smallest sliver ratio of the tets it replaces.  Slivers no flip improves get the vertex
move: a vertex the caller allows to move is placed where the worst tet of its star is
best, among a few candidate positions (the apex of the ideal tet on the opposite face,
away from that face, towards the star's centroid), keeping every tet positive.  Flip
passes and move passes alternate until nothing changes or ``max_iter`` passes.

Invariants: every flip replaces tets by others filling the same polyhedron, so the
boundary faces (hull faces of a Delaunay mesh), faces of ``triangle`` cells, edges of
``line`` cells and borders between regions (``cell_data["marker"]["tetra"]``) are
kept; every new tet and every tet of a moved vertex's star is checked positive with the
exact ``orient3d``; the result passes :meth:`Mesh.validate` (checked before returning).
The result is in general no longer Delaunay.

Arrays: the mesh's ``tetra`` block (m, 4) int32 positively oriented is copied into flat
``tet[4*t + k]`` / ``nbr[4*t + k]`` arrays (:mod:`meshwright.core.flat` layout) for the
kernels; the returned mesh has compact (m', 4) int32 tetra and moved float64 points.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from meshwright.core.errors import InputError, MeshingError, ValidationError
from meshwright.core.flat import TET_FACES
from meshwright.core.mesh import Mesh, build_neighbors_tet
from meshwright.core.validate_cells import _rows_in
from meshwright.tet import _flips, _moves

__all__ = ["LEFT_REASONS", "SliverReport", "remove_slivers"]

# Why a sliver is left.  Every left sliver also had no improving flip in the last pass.
LEFT_REASONS = {
    "boundary": "it has a face on the boundary surface, which no flip may change, or all four vertices lie "
    "on the boundary or on constrained cells, so none may move",
    "not_movable": "its vertices off the boundary are not movable (move_points=False or the movable mask)",
    "no_improving_move": "moves of its movable vertices did not lift it above the threshold",
    "iteration_cap": "max_iter passes ran out while the number of slivers was still falling",
    "work_cap": "the vertex moves used up their work budget (MOVE_WORK per tet of the input)",
}

# Passes without fewer slivers after which the loop stops (moves can creep on forever).
_STALL_PASSES = 3
# Work budget of the vertex moves: MOVE_WORK star-tet evaluations (the move pass's
# ``C_WORK`` units) per tet of the input, plus MOVE_WORK_MIN, so that small meshes are never
# stopped; past it the moves stop and the mesh is kept as it is (valid, every flip and move
# an improvement).  Measured: about 4e7 units a second; the level-4 sphere's moves use 3
# units per tet, the fuzz reproducer extruded_crease170 2,800 (8e7 in all, 28,850 tets, 18 %
# of them slivers), the 300-point random Delaunay at threshold 0.2 (tests) 2.3e7 in all;
# the star prism of fuzz seed 11 case 95 (476k tets, 63 % slivers) about 5e9 (minutes).
MOVE_WORK = 4_000
MOVE_WORK_MIN = 50_000_000
_RING_NAMES = {3: "3-2", 4: "4-4", 5: "5-6", 6: "6-8", 7: "7-10"}
_ROWS, _START, _COUNT = _flips.ring_tables()


@dataclass(frozen=True)
class SliverReport:
    """What :func:`remove_slivers` did.

    ``found - removed_by_flip - removed_by_move + created == left``.  Every operation
    counts the net change of the number of slivers among the tets it touches: a flip
    raises their worst ratio but may leave more of them below the threshold
    (``created``); a move never adds slivers to its vertex's star.

    Attributes
    ----------
    threshold : float
        The sliver ratio ``a = r_in / R_circ`` below which a tet is a sliver.
    found : int
        Slivers in the input mesh.
    removed_by_flip, removed_by_move, created, left : int
    left_reasons : dict of str to int
        Reason (keys of :data:`LEFT_REASONS`) -> number of slivers left for it.
    left_cells : (left,) int64
        Indices of the left slivers in the returned mesh's ``tetra`` block.
    flips : dict of str to int
        Flips applied by kind: ``"2-3"``, ``"3-2"``, ``"4-4"``, ``"5-6"``, ``"6-8"``, ``"7-10"``.
    moves : int
        Vertex moves applied.
    iterations : int
        Flip + move passes run.
    min_ratio_before, min_ratio_after : float
        Smallest sliver ratio of the input and of the result.
    """

    threshold: float
    found: int
    removed_by_flip: int
    removed_by_move: int
    created: int
    left: int
    left_reasons: dict[str, int] = field(default_factory=dict)
    left_cells: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    flips: dict[str, int] = field(default_factory=dict)
    moves: int = 0
    iterations: int = 0
    min_ratio_before: float = float("nan")
    min_ratio_after: float = float("nan")

    def __str__(self) -> str:
        flips = ", ".join(f"{k}: {v}" for k, v in self.flips.items() if v) or "none"
        reasons = ", ".join(f"{k}: {v}" for k, v in self.left_reasons.items() if v) or "none"
        return (
            f"slivers (r/R < {self.threshold:g}): found {self.found}, removed by flip {self.removed_by_flip}, "
            f"by move {self.removed_by_move}, created {self.created}, left {self.left} ({reasons}); "
            f"flips {flips}; moves {self.moves}; {self.iterations} passes; "
            f"min r/R {self.min_ratio_before:.3g} -> {self.min_ratio_after:.3g}"
        )


def _check_args(mesh, threshold, move_points, movable, max_iter):
    if not isinstance(mesh, Mesh):
        raise InputError(f"mesh must be a meshwright Mesh, got {type(mesh).__name__}")
    if mesh.dim != 3 or not len(mesh.tetra):
        raise InputError(f"remove_slivers needs a 3-D mesh with tetra cells, got {mesh!r}")
    if len(mesh.hexahedra) or len(mesh.quads):
        raise InputError("remove_slivers handles tetra meshes (with triangle, line and vertex cells); this one has hexahedra or quads")
    if isinstance(threshold, bool) or not isinstance(threshold, (int, float, np.floating, np.integer)):
        raise InputError(f"threshold must be a number, got {threshold!r}")
    if not 0.0 < float(threshold) <= 1.0 / 3.0:
        raise InputError(f"threshold must lie in (0, 1/3] (1/3 is the regular tet's r/R), got {threshold!r}")
    if not isinstance(move_points, (bool, np.bool_)):
        raise InputError(f"move_points must be True or False, got {move_points!r}")
    if isinstance(max_iter, bool) or not isinstance(max_iter, (int, np.integer)) or max_iter < 1:
        raise InputError(f"max_iter must be a positive integer, got {max_iter!r}")
    extra = sorted(name for name, blocks in mesh.cell_data.items() if "tetra" in blocks and name != "marker")
    if extra:
        raise InputError(
            f"cell_data {', '.join(map(repr, extra))} on tetra cannot follow flips (only 'marker' regions can); drop it first"
        )
    if movable is not None:
        if not move_points:
            raise InputError("movable given with move_points=False: say which one you mean")
        arr = np.asarray(movable)
        if arr.dtype != np.bool_ or arr.shape != (mesh.n_points,):
            raise InputError(f"movable must be a ({mesh.n_points},) bool array, got {arr.dtype} {arr.shape}")


def _check_radius_edge(radius_edge) -> float:
    """The radius-edge cap of the kernels (0.0: none) from ``radius_edge``, checked."""
    if radius_edge is None:
        return 0.0
    if isinstance(radius_edge, bool) or not isinstance(radius_edge, (int, float, np.floating, np.integer)):
        raise InputError(f"radius_edge must be a number or None, got {radius_edge!r}")
    if not np.isfinite(radius_edge) or float(radius_edge) < np.sqrt(6.0) / 4.0:
        raise InputError(f"radius_edge must be finite and at least sqrt(6)/4 = 0.612 (the regular tet's), got {radius_edge!r}")
    return float(radius_edge)


def _fixed_vertices(mesh: Mesh, neighbors: np.ndarray | None = None) -> np.ndarray:
    """Vertices that never move: on the boundary surface or on a triangle, line or vertex cell.

    ``neighbors`` (m, 4) int32 of the tetra block, when known, gives the boundary faces
    (-1 slots) without sorting every face of the mesh.
    """
    fixed = np.zeros(mesh.n_points, bool)
    if neighbors is None:
        fixed[mesh.boundary_facets().ravel()] = True
    else:
        # the boundary slots first: gathering every tet's four faces was a (m, 4, 3) temporary
        t, k = np.nonzero(neighbors < 0)
        fixed[mesh.tetra[t[:, None], TET_FACES[k]].ravel()] = True
    for cell_type in ("triangle", "line", "vertex"):
        fixed[mesh.cells_of(cell_type).ravel()] = True
    return fixed


def remove_slivers(mesh: Mesh, threshold: float = 0.01, move_points: bool = True, movable=None, max_iter: int = 50, radius_edge=None):
    """Remove slivers (r_in / R_circ < threshold) by flips and vertex moves (section 18.1.1).

    Parameters
    ----------
    mesh : Mesh
        Valid 3-D mesh of positively oriented ``tetra`` cells, optionally with
        ``triangle`` (faces), ``line`` (edges) and ``vertex`` cells, which are kept, and
        region markers ``cell_data["marker"]["tetra"]``, which flips do not mix.
    threshold : float
        Sliver ratio below which a tet is a sliver, in (0, 1/3]; the chapter's 0.01.
    move_points : bool
        Allow the chapter's vertex move for slivers no flip improves.
    movable : (n,) bool array, optional
        Which vertices may move.  Default (with ``move_points``): every vertex not on
        the boundary surface and not on a triangle, line or vertex cell.  So for a
        Delaunay tetrahedralization of a point set, where every point is input, the
        interior input points *do* move by default: pass ``move_points=False`` (or a
        mask) to keep the input points where they are.  Boundary and constrained
        vertices never move; marking one movable is an error.
    max_iter : int
        Cap on the flip + move passes; the loop also stops when a pass changes nothing,
        when three passes in a row did not lower the number of slivers, or when the vertex
        moves have used :data:`MOVE_WORK` star-tet evaluations per input tet and
        :data:`MOVE_WORK_MIN` more (the slivers left are then reported under
        ``"work_cap"``; the mesh is valid and every flip and move made was an improvement).
    radius_edge : float, optional
        A radius-edge bound B (circumradius over shortest edge, at least the regular tet's
        sqrt(6)/4) the flips and moves keep: a tet with R / l_min > B counts with the
        quality ``a (B l_min / R)**2 / 2`` instead of ``a``, so an operation that would lift a
        tet over B is refused like one making a sliver, and tets already over it are
        treated (and reported) as slivers.  ``tetrahedralize`` passes its bound.

    Returns
    -------
    mesh : Mesh
        New mesh (the input is not modified): same points, moved ones changed, same
        point data, new tetra block with its markers, other blocks unchanged.
    report : SliverReport

    Raises
    ------
    InputError
        A bad argument (named), or tetra cell data other than ``"marker"``.
    ValidationError
        The input mesh is not valid (as :meth:`Mesh.validate` says).
    MeshingError
        An internal inconsistency (a bug): no broken mesh is ever returned.
    """
    _check_args(mesh, threshold, move_points, movable, max_iter)
    cap = _check_radius_edge(radius_edge)
    mesh.validate()
    return remove_slivers_of_valid(mesh, float(threshold), move_points, movable, max_iter, cap)


def remove_slivers_of_valid(
    mesh: Mesh,
    threshold: float,
    move_points: bool,
    movable,
    max_iter: int,
    cap: float,
    exempt: float = 0.0,
    neighbors: np.ndarray | None = None,
    locked: np.ndarray | None = None,
):
    """:func:`remove_slivers` after its door: ``mesh`` already valid and the arguments checked
    (``cap`` the radius-edge bound, 0.0 for none; tets with an edge shorter than ``exempt``
    are not held to it).  ``tetrahedralize`` calls it on the mesh it
    has just built: validating it again cost 16 % of the level-4 sphere.  The result is
    validated all the same.

    ``neighbors`` (m, 4) int32 (across the face opposite vertex k, -1 on the boundary) and
    ``locked`` (m, 4) bool (faces that are ``triangle`` cells) of the tetra block, when the
    caller has them from its tetrahedralization: finding them again by sorting every face
    of the mesh was a fifth of the level-5 sphere's time.
    """
    cap = np.array([cap, exempt * exempt])
    n = mesh.n_points
    fixed = _fixed_vertices(mesh, neighbors)
    if movable is None:
        movable = ~fixed if move_points else np.zeros(n, bool)
    else:
        movable = np.asarray(movable, dtype=bool).copy()
        bad = np.flatnonzero(movable & fixed)
        if len(bad):
            v = int(bad[0])
            raise InputError(
                f"movable marks vertex {v} at {tuple(float(x) for x in mesh.points[v])}, which lies on the boundary "
                f"surface or a constrained cell ({len(bad)} such vertices): those never move"
            )

    tet, nbr, lock, region, ekeys = _flat_state(mesh, neighbors, locked)
    free = np.zeros(len(region), np.int64)
    nfree, ntet = 0, len(mesh.tetra)
    pts = mesh.points.copy()

    counters = np.zeros(_flips.N_COUNTERS, np.int64)
    # one whole-mesh pass: the flips and moves keep the ratios of what they change
    ratios = np.full(len(region), np.inf)
    ratios[:ntet] = _flips.all_ratios(pts, tet, ntet, cap)
    found = int(np.count_nonzero(ratios[:ntet] < threshold))
    min_before = float(ratios[:ntet].min())
    budget = MOVE_WORK * ntet + MOVE_WORK_MIN
    capped = False
    out_of_work = False
    iterations = 0
    fewest, stalled = found, 0
    any_movable = bool(movable.any())
    for it in range(max_iter):
        cand = np.flatnonzero(ratios[:ntet] < threshold)
        if not len(cand):
            break
        cand = cand[np.argsort(ratios[cand], kind="stable")].astype(np.int64)
        iterations += 1
        tet, nbr, lock, region, ratios, free, ntet, nfree, flips, ok = _flips.flip_pass(
            pts, tet, nbr, lock, region, ratios, ntet, free, nfree, cand, threshold, ekeys, n, _ROWS, _START, _COUNT, counters, cap
        )
        if not ok:
            raise MeshingError("sliver flip produced a face that matches no neighbour (internal error)")
        moved = 0
        if any_movable:
            cand = np.flatnonzero(ratios[:ntet] < threshold)
            cand = cand[np.argsort(ratios[cand], kind="stable")].astype(np.int64)
            moved, out_of_work = _moves.move_pass(pts, tet, ratios, ntet, cand, threshold, movable, counters, cap, budget)
        n_slivers = int(np.count_nonzero(ratios[:ntet] < threshold))
        if n_slivers < fewest:
            fewest, stalled = n_slivers, 0
        else:
            stalled += 1
        if flips + moved == 0 or stalled == _STALL_PASSES or out_of_work:
            break
        if it == max_iter - 1 and n_slivers:
            capped = True

    alive = tet[: 4 * ntet].reshape(ntet, 4)[:, 0] >= 0
    new_tets = tet[: 4 * ntet].reshape(ntet, 4)[alive].copy()
    cells = {t: c for t, c in mesh.cells.items() if t != "tetra"}
    cells["tetra"] = new_tets
    cell_data = {name: {t: v for t, v in blocks.items() if t != "tetra"} for name, blocks in mesh.cell_data.items()}
    if "tetra" in mesh.cell_data.get("marker", {}):
        cell_data["marker"]["tetra"] = region[:ntet][alive].copy()
    out = Mesh(pts, cells, point_data=dict(mesh.point_data), cell_data={k: v for k, v in cell_data.items() if v})
    try:
        out.validate()
    except ValidationError as exc:
        raise MeshingError(f"sliver removal produced an invalid mesh (internal error): {exc}") from exc

    final = ratios[:ntet][alive]
    left_cells = np.flatnonzero(final < threshold)
    on_surface = (nbr[: 4 * ntet].reshape(ntet, 4)[np.flatnonzero(alive)[left_cells]] < 0).any(axis=1)
    reasons = _left_reasons(new_tets, left_cells, on_surface, fixed, movable, capped, out_of_work)
    flips_by_kind = {"2-3": int(counters[_flips.C_23])}
    flips_by_kind.update({name: int(counters[_flips.C_RING + size]) for size, name in _RING_NAMES.items()})
    report = SliverReport(
        threshold=threshold,
        found=found,
        removed_by_flip=int(counters[_flips.C_REMOVED_FLIP]),
        removed_by_move=int(counters[_flips.C_REMOVED_MOVE]),
        created=int(counters[_flips.C_CREATED]),
        left=len(left_cells),
        left_reasons=reasons,
        left_cells=left_cells.astype(np.int64),
        flips=flips_by_kind,
        moves=int(counters[_flips.C_MOVES]),
        iterations=iterations,
        min_ratio_before=min_before,
        min_ratio_after=float(final.min()),
    )
    return out, report


def _flat_state(mesh: Mesh, nb: np.ndarray | None = None, locked: np.ndarray | None = None):
    """Flat kernel arrays of the tetra block, with room for twice as many tets.

    ``nb`` (m, 4) int32 neighbours and ``locked`` (m, 4) bool ``triangle`` faces, when the
    caller knows them; found by sorting the faces otherwise.

    Returns
    -------
    tet, nbr : (4 cap,) int32
        Vertices and neighbours (-1 = boundary; unused slots -1).
    lock : (4 cap,) uint8
        1 on faces between two regions and on faces that are ``triangle`` cells.
    region : (cap,) int32
        ``cell_data["marker"]["tetra"]``, or 0.
    ekeys : (e,) int64
        Sorted ``min * n + max`` of the ``line`` cells (edges no flip may remove).
    """
    n = mesh.n_points
    tets = np.ascontiguousarray(mesh.tetra, dtype=np.int32)
    m = len(tets)
    cap = 2 * m + 16
    tet = np.full(4 * cap, -1, np.int32)
    tet[: 4 * m] = tets.ravel()
    nbr = np.full(4 * cap, -1, np.int32)
    if nb is None:
        nb = build_neighbors_tet(tets)
    nbr[: 4 * m] = nb.ravel()
    region = np.zeros(cap, np.int32)
    markers = mesh.cell_data.get("marker", {}).get("tetra")
    if markers is not None:
        region[:m] = np.asarray(markers, dtype=np.int32)
    lock = np.zeros(4 * cap, np.uint8)
    lock[: 4 * m] = ((nb >= 0) & (region[np.maximum(nb, 0)] != region[:m, None])).ravel()
    faces = mesh.cells_of("triangle")
    if locked is not None:
        lock[: 4 * m] |= locked.ravel().astype(np.uint8)
    elif len(faces):
        lock[: 4 * m] |= _rows_in(tets[:, TET_FACES].reshape(-1, 3), faces, n).astype(np.uint8)
    lines = np.sort(mesh.cells_of("line").astype(np.int64), axis=1)
    ekeys = np.unique(lines[:, 0] * n + lines[:, 1]) if len(lines) else np.zeros(0, np.int64)
    return tet, nbr, lock, region, ekeys


def _left_reasons(tets, left, on_surface, fixed, movable, capped, out_of_work=False) -> dict[str, int]:
    """Count the left slivers by reason (see LEFT_REASONS), first matching reason wins;
    ``on_surface`` (left,) bool: which of them have a boundary face."""
    reasons = dict.fromkeys(LEFT_REASONS, 0)
    if out_of_work:
        reasons["work_cap"] = len(left)
        return reasons
    if capped:
        reasons["iteration_cap"] = len(left)
        return reasons
    rows = tets[left]
    boundary = on_surface | fixed[rows].all(axis=1)
    can_move = movable[rows].any(axis=1)
    reasons["boundary"] = int(np.count_nonzero(boundary))
    reasons["no_improving_move"] = int(np.count_nonzero(~boundary & can_move))
    reasons["not_movable"] = int(np.count_nonzero(~boundary & ~can_move))
    return reasons
