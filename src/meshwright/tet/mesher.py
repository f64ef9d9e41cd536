"""``tetrahedralize``: quality tetrahedral meshes of closed surfaces (chapter 18.4.1).

The 3-D counterpart of :func:`meshwright.triangulate`, what TetGen's ``-pq`` does::

    surface (validated) --Delaunay of its vertices (Bowyer, ghost hull)-->
    --boundary recovery (Steiner points on missing faces, tet/recovery.py)-->
    --exterior removal (flood fill across unprotected faces, tet/exterior.py)-->
    --interior points (Delaunay refinement at circumcentres, tet/refine3d.py)-->
    --sliver removal (flips and vertex moves, tet/slivers.py)--> Mesh

Every stage keeps the tetrahedralization Delaunay until sliver removal (whose flips keep
every boundary and interface face), so the result's boundary faces are exactly the
recovered subfaces of the input faces.

``TET_METHODS`` maps method names to :class:`TetMethod` records; the CLI offers its keys.
"""

from __future__ import annotations

import os
import warnings
from typing import Callable, NamedTuple

import numpy as np

from meshwright.core.errors import GeometryError, InputError, MeshingError, SliverWarning
from meshwright.core.flat import TET_FACES
from meshwright.core.hugepages import small_pages
from meshwright.core.mesh import Mesh
from meshwright.core.predicates import orient2d, orient3d_batch
from meshwright.core.validate_input import (
    check_count,
    check_flag,
    check_positive,
    check_seed,
)
from meshwright.tet.exterior import carry_labels, classify, solid_part
from meshwright.tet.recovery import (
    SplitOrigins,
    _longest,
    bisect_marked,
    dominant_axes,
    insert_new,
    raise_cap,
    recover,
    unique_edges,
)
from meshwright.tet.refine3d import (
    SIZE_FACTOR,
    bad_solid,
    circumspheres,
    crease_caps,
    flag_counts,
    refine_in_queue,
    select_points,
)
from meshwright.tet.tetrahedralization import Tetrahedralization

__all__ = ["REFINE_ROUNDS", "SLIVER_MODES", "TET_METHODS", "TetMethod", "tetrahedralize"]

SLIVER_MODES = ("remove", "keep")
REFINE_ROUNDS = 400  # refinement rounds; the mesh roughly doubles in a few rounds
GUARD = 2.0**-12  # shortest splittable edge, relative to the shortest input edge
# Quality refinement splits no subface edge shorter than FLOOR times the shortest edge of its
# input face, and tets with an edge shorter than EXEMPT times the input's shortest edge are
# exempt from the radius-edge bound: near acute input angles (a wing's trailing-edge wedge)
# encroachment would otherwise cascade to round-off.  Size and volume bounds are not limited
# by either.  Measured on the level-4 sphere (radius-edge 1.414, 85k tets): exemption at
# 1.0 left 53 tets above the bound, at 0.25 two (1.43); 0.25 everywhere took minutes on the
# wing.
FLOOR = 1.0
EXEMPT = 0.25  # the exemption's edge length, relative to the shortest input edge
MIN_RADIUS_EDGE = 1.0
SIZE_SPLIT = 0.5  # a size bound splits subface edges down to SIZE_SPLIT times the size
# Refinement aims at MARGIN times the radius-edge bound: sliver flips and moves may raise a
# tet's ratio a little (2.05 measured for a bound of 2 refined exactly).
MARGIN = 0.95
SLIVER_RATIO = 0.12
SLIVER_RATIO_MAX = 0.24
UNFLATTEN_PASSES = 8  # flat tets moved out per round; one pass settles each tet
SLIVER_PASSES = 4  # flip + move passes per threshold: 4 and 10 gave the same sphere quality; moves near exempt tets crawl on


class TetMethod(NamedTuple):
    """A volume method of :func:`tetrahedralize`.

    Attributes
    ----------
    name : str
    summary : str
        One line for ``--help``.
    run : callable
        ``run(job) -> Mesh``.
    """

    name: str
    summary: str
    run: Callable


class _Job(NamedTuple):
    points: np.ndarray
    faces: np.ndarray
    markers: np.ndarray
    field: Callable | None
    max_volume: float
    radius_edge: float | None
    min_dihedral: float | None
    holes: np.ndarray
    regions: np.ndarray
    slivers: str
    smooth: int
    max_points: int
    seed: object
    progress: bool


def _as_surface(surface):
    """A validated :class:`meshwright.geometry.surface.Surface` from what the caller gave."""
    from meshwright.geometry.surface import Surface

    if isinstance(surface, Surface):
        surf = surface
    elif isinstance(surface, Mesh):
        surf = Surface.from_mesh(surface)
    elif isinstance(surface, (str, os.PathLike)):
        if os.path.exists(surface):
            from meshwright.geometry.surface_io import read_surface

            surf = read_surface(surface)
        else:
            from meshwright.tet.builtin_surfaces import builtin_surface

            surf = builtin_surface(str(surface))
    elif isinstance(surface, tuple) and len(surface) == 2:
        surf = Surface(surface[0], surface[1])
    else:
        raise InputError(
            f"surface must be a geometry.Surface, a 3-D Mesh with triangle cells, a (points, triangles) "
            f"pair, a file path or a built-in name; got {type(surface).__name__}"
        )
    surf.validate()
    return surf


def _seeds(value, width: int, what: str) -> np.ndarray:
    """(k, width) float64 seed rows; region rows of 4 get max_volume 0 (none)."""
    try:
        arr = np.asarray(value if value is not None else (), dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{what} must be rows of {width} numbers (x, y, z{', id, max_volume' if width == 5 else ''}): {exc}") from None
    if arr.size == 0:
        return np.zeros((0, width))
    if arr.ndim == 1:
        arr = arr[None, :]
    if what == "regions" and arr.ndim == 2 and arr.shape[1] == 4:
        arr = np.concatenate([arr, np.zeros((arr.shape[0], 1))], axis=1)
    if arr.ndim != 2 or arr.shape[1] != width:
        raise InputError(f"{what} must be rows of {width} numbers, got shape {arr.shape}")
    if not np.isfinite(arr).all():
        raise InputError(f"{what}: row {int(np.flatnonzero(~np.isfinite(arr).all(axis=1))[0])} is not finite")
    return np.ascontiguousarray(arr)


def tetrahedralize(
    surface,
    size=None,
    *,
    max_volume=None,
    radius_edge=2.0,
    min_dihedral=None,
    holes=(),
    regions=(),
    slivers: str = "remove",
    method: str = "delaunay",
    smooth: int = 0,
    max_points: int = 100_000_000,
    seed=0,
    progress: bool = False,
) -> Mesh:
    """Quality tetrahedral mesh of the solid a closed triangulated surface bounds.

    Parameters
    ----------
    surface : geometry.Surface, Mesh, (points, triangles), str or path
        Closed, consistently oriented surface (several shells allowed), a 3-D mesh with
        ``triangle`` cells, a surface file or a built-in name (``geometry.solids``).
    size : None, float, callable or size field
        Target edge length: a number, ``h(xyz (n, 3)) -> (n,)`` or a 3-D background grid;
        None refines by shape only.
    max_volume : float, optional
        Bound on every tet's volume (region seeds may set their own).
    radius_edge : float or None
        Bound B >= 1 on circumradius / shortest edge of every tet not exempt at a small
        input angle (Shewchuk's guarantee needs B >= 2); None: no quality refinement
        (boundary recovery and exterior removal only, TetGen's ``-p``).
    min_dihedral : float, optional
        Degrees in (0, 20]: sliver removal raises its threshold until no dihedral angle is
        smaller, or raises :class:`MeshingError`; needs ``slivers="remove"``.  Without it, tets
        left with a sliver ratio below 0.01 (the chapter's sliver) give a
        :class:`~meshwright.core.errors.SliverWarning` naming how many.
    holes : (h, 3) array_like
        Hole seeds (their components are void), added to the surface's own.
    regions : (r, 4) or (r, 5) array_like
        ``(x, y, z, id[, max_volume])`` region seeds, added to the surface's own.
    slivers : {"remove", "keep"}
        ``"remove"`` runs :func:`meshwright.tet.remove_slivers` (flips and interior moves;
        the moves stop at a work budget proportional to the mesh, ``slivers.MOVE_WORK``,
        reached only where most tets are slivers).
    method : str
        A key of ``TET_METHODS``.
    smooth : int
        Spring-analogy smoothing passes of the interior vertices (0: none).
    max_points : int
        Cap on the vertices; a surface or size needing more raises :class:`SizeError`.
    seed : int or numpy.random.Generator
    progress : bool
        Show the refinement rounds with tqdm.

    Returns
    -------
    Mesh
        ``tetra`` (k, 4) int32 positively oriented, ``triangle`` (b, 3) int32 boundary and
        interface faces (oriented out of the solid on the boundary), ``cell_data["marker"]``
        with the input face markers (triangles) and region ids (tets).

    Raises
    ------
    GeometryError, InputError, SizeError, MeshingError
    """
    job = _door(surface, size, max_volume, radius_edge, min_dihedral, holes, regions, slivers, method, smooth, max_points, seed, progress)
    with small_pages():  # no huge-page compaction stalls on the large arrays (core/hugepages.py)
        return TET_METHODS[method].run(job)


def _door(surface, size, max_volume, radius_edge, min_dihedral, holes, regions, slivers, method, smooth, max_points, seed, progress) -> _Job:
    """Check every argument before any work; the job the method runs."""
    if method not in TET_METHODS:
        raise InputError(f"unknown method {method!r}; choose from {sorted(TET_METHODS)}")
    if slivers not in SLIVER_MODES:
        raise InputError(f"slivers must be one of {SLIVER_MODES}, got {slivers!r}")
    field = None
    if size is not None:
        from meshwright.sizing import as_size_field

        field = as_size_field(size, dim=3)
    vmax = np.inf if max_volume is None else check_positive(max_volume, "max_volume")
    if radius_edge is not None:
        radius_edge = check_positive(radius_edge, "radius_edge", error=InputError)
        if radius_edge < MIN_RADIUS_EDGE:
            raise InputError(f"radius_edge must be >= {MIN_RADIUS_EDGE} (the regular tet has 0.612), got {radius_edge}")
    if min_dihedral is not None:
        min_dihedral = check_positive(min_dihedral, "min_dihedral", error=InputError)
        if min_dihedral > 20.0:
            raise InputError(f"min_dihedral must be in (0, 20] degrees, got {min_dihedral}")
    if min_dihedral is not None and slivers != "remove":
        raise InputError("min_dihedral needs slivers='remove' (the sliver stage meets it)")
    smooth = check_count(smooth, "smooth")
    max_points = check_count(max_points, "max_points", minimum=4)
    seed = check_seed(seed)
    progress = check_flag(progress, "progress")
    hole_rows = _seeds(holes, 3, "holes")
    region_rows = _seeds(regions, 5, "regions")
    surf = _as_surface(surface)
    if surf.points.shape[0] > max_points:
        raise_cap(max_points, "the surface")
    if field is not None and field.constant is not None:
        # a tet of edge h has volume h^3 / (6 sqrt 2); about 5.5 tets per vertex
        estimate = abs(surf.enclosed_volume()) / (field.constant**3 / (6.0 * np.sqrt(2.0)) * 5.5)
        if estimate > max_points:
            raise_cap(max_points, f"size {field.constant:g} (about {estimate:.3g} vertices)")
    return _Job(
        points=surf.points,
        faces=surf.triangles,
        markers=surf.markers,
        field=field,
        max_volume=vmax,
        radius_edge=radius_edge,
        min_dihedral=min_dihedral,
        holes=np.concatenate([np.reshape(surf.holes, (-1, 3)), hole_rows]),
        regions=np.concatenate([np.reshape(surf.regions, (-1, 5)), region_rows]),
        slivers=slivers,
        smooth=smooth,
        max_points=max_points,
        seed=seed,
        progress=progress,
    )


def _barrier(nt: int, nbr: np.ndarray, where: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Barrier flags (nt, 4) on both sides of every subface, and ``face_of`` (4 nt,) int32 subface ids."""
    face_of = np.full(4 * nt, -1, dtype=np.int32)  # half the bytes of int64: written every round
    face_of[where] = np.arange(where.size, dtype=np.int32)
    t, k = np.divmod(where, 4)
    u = nbr[t, k]
    inner = u >= 0
    # the slot of t in u's neighbours is the face shared with t
    back = np.argmax(nbr[u[inner]] == t[inner, None], axis=1)
    face_of[4 * u[inner] + back] = np.flatnonzero(inner)
    return (face_of >= 0).reshape(nt, 4), face_of


def _run_delaunay(job: _Job) -> Mesh:
    rng = np.random.default_rng(job.seed)
    tz = Tetrahedralization(job.points, seed=rng)
    edges0, _ = unique_edges(job.faces)
    lengths = np.linalg.norm(job.points[edges0[:, 0]] - job.points[edges0[:, 1]], axis=1)
    guard = GUARD * float(lengths.min())
    fp = job.points[job.faces]
    floor = FLOOR * np.linalg.norm(fp - fp[:, [1, 2, 0]], axis=2).min(axis=1)
    axis = dominant_axes(job.points, job.faces)
    origins = SplitOrigins(job.points.shape[0])
    faces, parent, where = recover(tz, job.faces, np.arange(job.faces.shape[0], dtype=np.int32), guard, job.max_points, job.faces, axis, origins, n_apex=job.points.shape[0])
    refine = job.radius_edge is not None or job.field is not None or np.isfinite(job.max_volume) or (job.regions[:, 4] > 0).any()
    bar = None
    if job.progress and refine:
        from tqdm import tqdm

        bar = tqdm(desc="tetrahedralize", unit=" points")
    rounds = 0
    tried = set()
    caps_only = False  # a round for the crease caps alone, after the queue got stuck
    # The round's state (subfaces, classification, circumspheres, bad tets) is kept while
    # the mesh is unchanged: a queue round that inserts nothing hands it to the caps round,
    # and the final mesh takes it, instead of recomputing the same arrays (each a few passes
    # over all tets: 0.2-0.4 s a round at 1e6 tets).  ``changed``: the tetrahedralization or
    # the subfaces changed since the state was computed; ``settled``: its unflatten did not
    # stop at its pass cap (another call would flip on).
    state = None
    changed = True
    kept = set()  # flat tets unflatten moved out: recovery's Lawson flips leave them so
    # The last state's labels and bad tets, carried: the tets that survive keep them, only
    # the new tets are labelled and examined (tz.track / tracked, exterior.carry_labels).
    carry = None
    queue_bound = job.field is None or job.field.constant is not None
    while refine:
        rounds += 1
        if rounds > REFINE_ROUNDS:
            raise MeshingError(f"Delaunay refinement did not finish in {REFINE_ROUNDS} rounds ({tz.points.shape[0]} vertices)")
        if changed:
            faces, where, flat, state, settled, new = _unflatten(job, tz, faces, parent, where, axis, origins, kept, carry)
            barrier, face_of, solid, vmax, region = state
            tets = tz.tetrahedra
            nbr = tz.neighbors
            pts = tz.points
            vbound = np.minimum(vmax, job.max_volume)
            spheres = None  # circumcentres, radii, volumes and reach: for the rounds that need them
            if queue_bound:
                # one pass without the circumcentres: the queue rounds need the bad tets only
                h = job.field.constant if job.field is not None else np.inf
                bound = (
                    SIZE_FACTOR * h if job.field is not None else np.inf,
                    MARGIN * job.radius_edge if job.radius_edge is not None else np.inf, EXEMPT / FLOOR * float(floor.min()),
                )
                if new is None:
                    bad = bad_solid(pts, tets, solid, vbound, *bound)
                else:
                    # a surviving tet is bad exactly when it was: same shape, label and bounds
                    bad = np.sort(np.concatenate([bad_solid(pts, tets, solid, vbound, *bound, among=new), _survivors(tz, new, carry[4], solid)]))
            else:
                spheres = _spheres(job, pts, tets, solid, vbound, EXEMPT / FLOOR * float(floor.min()), guard)
                bad = spheres[4]
            carry = (barrier, solid, region, vmax, bad, pts.shape[0])
            tz.track()
            changed = not settled
        queue_round = bad.size and not caps_only and queue_bound
        # the queue rounds leave crease caps alone (most vanish under refinement: 6,456 at the
        # start of the level-5 sphere, 3 after it), so they are looked for in the other rounds only
        caps, apex = (np.zeros(0, dtype=np.int64), np.zeros((0, 3))) if queue_round else _new_caps(tets, barrier, solid, face_of, parent, pts, tried)
        if bad.size == 0 and flat.size == 0 and caps.size == 0:
            break
        inserted = 0
        if queue_round:
            # one point at a time from a queue (tet/_refine_kernel.py); a callable size
            # field is Python, so it stays with the rounds below
            h = job.field.constant if job.field is not None else np.inf
            inserted, enc, capped = refine_in_queue(
                tz, barrier, solid, np.minimum(vmax, job.max_volume), bad,
                MARGIN * job.radius_edge if job.radius_edge is not None else np.inf, SIZE_FACTOR * h,
                EXEMPT / FLOOR * float(floor.min()), job.max_points, int(rng.integers(1, 2**31)),
            )
            if capped:
                raise_cap(job.max_points, "Delaunay refinement")
            changed |= inserted > 0
            pts = tz.points
            hit, why = _subfaces_of(faces, enc)
            reach_of = np.array([np.inf, max(guard, SIZE_SPLIT * h), guard])
            hit = np.concatenate([hit, flat])
            least = np.concatenate([reach_of[why], np.full(flat.size, np.inf)])
            new_interior = np.zeros((0, 3))
        else:
            # with a queue (spheres None) these rounds propose the caps only: no circumsphere
            # pass over every tet
            if spheres is None:
                order = np.zeros(0, dtype=np.int32)
                target = apex
            else:
                order = bad[np.argsort(-spheres[1][bad], kind="stable")].astype(np.int32)[: 0 if caps_only else bad.size]
                target = np.concatenate([spheres[0][order], apex])
            close = np.concatenate([np.zeros(order.size, dtype=bool), np.ones(caps.size, dtype=bool)])
            order = np.concatenate([order, caps]).astype(np.int32)
            accept, enc = select_points(pts, tets, nbr, barrier, order, target, close, int(rng.integers(1, 2**31)))
            # a subface edge is split down to the tet's reach (size and volume bounds), else to
            # the surface floor (quality, flat tets)
            hit = np.concatenate([face_of[enc[enc >= 0]], flat])
            sel = order[enc >= 0]
            reach = spheres[3][sel] if spheres is not None else _spheres(job, pts, tets[sel], solid[sel], vbound[sel], 0.0, guard)[3]
            least = np.concatenate([reach, np.full(flat.size, np.inf)])
            new_interior = np.ascontiguousarray(target[accept])
        added = 0
        if hit.size:
            edges, face_edges = unique_edges(faces)
            mark = np.zeros(edges.shape[0], dtype=bool)
            for f, r in zip(hit, least):
                e = face_edges[f, _longest(pts, faces, face_edges, f)]
                a, b = edges[e]
                if np.linalg.norm(pts[a] - pts[b]) >= (r if np.isfinite(r) else max(guard, floor[parent[f]])):
                    mark[e] = True
            if mark.any():
                if tz.points.shape[0] + int(mark.sum()) > job.max_points:
                    raise_cap(job.max_points, "Delaunay refinement")
                faces, parent, added, same = bisect_marked(pts, faces, parent, edges, face_edges, mark, lambda p: insert_new(tz, p), origins)
                where = np.where(same >= 0, where[np.maximum(same, 0)], -1)
                changed = True
        if new_interior.shape[0] and added == 0:
            if tz.points.shape[0] + new_interior.shape[0] > job.max_points:
                raise_cap(job.max_points, "Delaunay refinement")
            before = tz.points.shape[0]
            tried.update(tuple(sorted(r)) for r in tets[order[accept & close]].tolist())
            tz.insert(new_interior)
            changed = True
            added += tz.points.shape[0] - before
        added += inserted
        if bar is not None:
            bar.update(added)
        if added == 0 and (caps.size or queue_round) and not caps_only:
            caps_only = True  # the queue left tets it cannot repair (encroachment below the floor)
            continue
        if added == 0:
            break
        caps_only = False
        faces, parent, where = recover(tz, faces, parent, guard, job.max_points, job.faces, axis, origins, kept=kept, hint=where)
        changed = True
    if bar is not None:
        bar.close()
    if changed:
        faces, where, _, state, _, _ = _unflatten(job, tz, faces, parent, where, axis, origins, kept, carry)
    return _to_mesh(job, tz, faces, parent, where, state)


def _survivors(tz, new: np.ndarray, bad0: np.ndarray, solid: np.ndarray) -> np.ndarray:
    """The tets (k,) int64 of ``tz`` that were bad (``bad0``) at the last ``tz.track()`` and
    are still there, solid; ``new`` (c,) int64 are the tets labelled afresh since."""
    src = np.array(tz.tracked(), dtype=np.int64)
    nt0 = int(max(src.max(initial=0), bad0.max(initial=0))) + 1
    src[new] = nt0  # a slot that was never bad
    hit = np.zeros(nt0 + 1, dtype=bool)
    hit[bad0] = True
    return np.flatnonzero(hit[src] & solid)


def _labels(job: _Job, tz, barrier, carry, nv0=None, src=None):
    """``(solid, region, vmax, fresh)`` of the current tets: carried from ``carry`` (the last
    state's barrier, labels, bad tets and vertex count, :func:`carry_labels`) where
    possible, else :func:`classify` (``fresh`` None)."""
    if carry is not None:
        tets = tz.tetrahedra
        ok, solid, region, vmax, new = carry_labels(
            tets, tz.neighbors, barrier, carry[5] if nv0 is None else nv0, tz.tracked() if src is None else src,
            carry[0], carry[1], carry[2], carry[3], len(job.holes) + len(job.regions) > 0,
        )
        if ok:
            return solid, region, vmax, new
    solid, region, vmax = classify(tz, barrier, job.holes, job.regions)
    return solid, region, vmax, None


def _unflatten(job: _Job, tz, faces, parent, where, axis, origins, kept: set, carry=None):
    """Move flat solid tets lying on an input face out of the solid by flipping its subfaces.

    Steiner points on a general plane are off it by round-off, so four nearly cocircular
    points of one input face can make a tet of round-off volume whose four faces are all in
    the tetrahedralization: two of them subfaces, the other two facing the solid.  Such a tet
    is classified solid, has an infinite or huge circumradius (size splits cascade to the
    guard) and no flip or move can repair it.  Taking the tet's other two faces as the
    subfaces (the same input face, the other diagonal of the quadrilateral) puts it on the
    exterior side; the boundary keeps its vertices and its input face.  When the two subfaces
    lie in two different but exactly coplanar input faces (a wall rectangle's two triangles)
    the flip would cross their common input edge: such a tet's first subface is returned to be
    split instead, which breaks the cocircular tie.  The flipped tets' vertex quadruples are
    added to ``kept``, which recovery's Lawson flips leave alone (they flipped every such
    pair back, and each round paid a second classification to flip it again).

    ``carry`` (barrier, solid, region, vmax, bad, nv) holds the last state, which ``tz`` has
    tracked since (:meth:`Tetrahedralization.track`).

    Returns the subfaces (m, 3) int32, their positions ``where`` (m,) int64, the subfaces
    (s,) int64 to split, the barrier flags, ``face_of``, solid flags, volume bounds and region
    ids of the result (:func:`_barrier`, :func:`classify` or :func:`carry_labels`), whether it
    settled (False: it stopped at :data:`UNFLATTEN_PASSES` with flips left, so another call
    may flip more), and the tets (k,) int64 new or re-protected since ``carry`` (None: every
    tet labelled afresh).
    """
    settled = True
    fresh = None
    barrier = None
    for sweep in range(UNFLATTEN_PASSES + 1):
        split = np.zeros(0, dtype=np.int64)
        tets = tz.tetrahedra
        nbr = tz.neighbors
        old_barrier = barrier
        barrier, face_of = _barrier(tets.shape[0], nbr, where)
        if sweep == 0:
            solid, region, vmax, fresh = _labels(job, tz, barrier, carry)
        elif fresh is not None:
            # the flat tets just flipped changed sides (their faces' protection changed):
            # labelled afresh, the others keep theirs
            solid, region, vmax, checked = _labels(job, tz, barrier, (old_barrier, solid, region, vmax), tz.points.shape[0], np.arange(tets.shape[0], dtype=np.int32))
            fresh = None if checked is None else np.union1d(fresh, checked)  # None: classified afresh, so are the bad tets
        else:
            solid, region, vmax = classify(tz, barrier, job.holes, job.regions)
        cand = np.flatnonzero(solid & (flag_counts(barrier) == 2))
        if cand.size == 0:
            break
        slots = np.argsort(~barrier[cand], axis=1, kind="stable")
        f1 = face_of[4 * cand + slots[:, 0]]
        f2 = face_of[4 * cand + slots[:, 1]]
        across = nbr[cand[:, None], slots[:, :2]]
        outside = ~np.where(across >= 0, solid[np.maximum(across, 0)], False).any(axis=1)
        pick = (parent[f1] == parent[f2]) & outside
        other = np.flatnonzero(outside & ~pick)
        split = f1[other[_coplanar(job, parent[f1[other]], parent[f2[other]])]].astype(np.int64)
        if not pick.any() or sweep == UNFLATTEN_PASSES:
            settled = not pick.any()
            break
        faces = faces.copy()
        where = where.copy()
        used = np.zeros(faces.shape[0], dtype=bool)
        flipped = 0
        rim = None
        for i in np.flatnonzero(pick):
            a, b = int(f1[i]), int(f2[i])
            if used[a] or used[b]:
                continue
            used[a] = used[b] = True
            t = int(cand[i])
            out = tets[t, TET_FACES[slots[i, 0]]]
            # the subface runs as the tet's outward face (a rotation of it) or against it
            same = any(np.array_equal(np.roll(out, r), faces[a]) for r in range(3))
            new = [tets[t, TET_FACES[k]][::-1] if same else tets[t, TET_FACES[k]] for k in slots[i, 2:4]]
            # three of the four nearly collinear: a new face would be degenerate in its plane
            ax = axis[parent[a]]
            sign = np.sign(_orient_proj(tz.points, ax, faces[a]))
            if sign == 0 or any(np.sign(_orient_proj(tz.points, ax, tri)) != sign for tri in new):
                continue
            if rim is None:
                rim = _rim(faces, parent, parent[f1[pick]])
            shared = set(faces[a].tolist()) & set(faces[b].tolist())
            other = set(tets[t].tolist()) - shared
            if _on_rim_between(rim, int(parent[a]), job.faces[parent[a]].tolist(), shared, other):
                continue
            ends = origins.view(tz.points.shape[0])
            if any(set(ends[v].tolist()) == other for v in shared):
                continue  # a midpoint of the new diagonal
            for f, k, tri in ((a, slots[i, 2], new[0]), (b, slots[i, 3], new[1])):
                faces[f] = tri
                where[f] = 4 * t + k
            kept.add(tuple(sorted(int(v) for v in tets[t])))
            flipped += 1
        if flipped == 0:
            break
    return faces, where, split, (barrier, face_of, solid, vmax, region), settled, fresh


def _subfaces_of(faces, enc) -> tuple[np.ndarray, np.ndarray]:
    """Subface ids (k,) int64 of the kernel's encroachment records ``enc`` (r, 4) and their
    reasons (k,) int64; records naming no subface are dropped."""
    if enc.shape[0] == 0:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    # sorted vertex triples as keys, found by binary search (a dict of every subface built
    # each round was 80 ms of a level-5 round)
    n = int(max(faces.max(), enc[:, :3].max())) + 1
    fkey = _triple_keys(faces, n)
    ekey = _triple_keys(enc[:, :3], n)
    order = np.argsort(fkey, kind="stable")
    pos = np.minimum(np.searchsorted(fkey[order], ekey), order.size - 1)
    found = fkey[order[pos]] == ekey
    return order[pos[found]].astype(np.int64), enc[found, 3].astype(np.int64)


def _triple_keys(rows: np.ndarray, n: int) -> np.ndarray:
    """One key per row of (k, 3) vertex ids below ``n``: the sorted triple as a base-n number,
    (k,) int64 (exact while n**3 < 2**63, about 2e6 vertices) or a structured row past that."""
    r = np.sort(rows.astype(np.int64), axis=1)
    if n < 2_000_000:
        return (r[:, 0] * n + r[:, 1]) * n + r[:, 2]
    return np.ascontiguousarray(r).view([("a", np.int64), ("b", np.int64), ("c", np.int64)]).ravel()


def _new_caps(tets, barrier, solid, face_of, parent, pts, tried: set):
    """:func:`crease_caps` of this round not proposed before (one apex per cap: an apex that
    did not remove its cap is not tried again), as (c,) int64 tets and (c, 3) apexes."""
    caps, apex = crease_caps(pts, tets, barrier, solid, face_of, parent, SLIVER_RATIO)
    if caps.size and tried:
        fresh = np.array([tuple(sorted(r)) not in tried for r in tets[caps].tolist()], dtype=bool)
        caps, apex = caps[fresh], apex[fresh]
    return caps, apex


def _rim(faces, parent, among) -> set:
    """Subface edges on their input face's boundary, as sorted vertex pairs with the parent.

    Only the input faces ``among`` (k,) are looked at: the set of every face's rim edges,
    built on each unflatten pass, was 46 % of the level-4 sphere's time.
    """
    sel = np.isin(parent, among)
    faces = faces[sel]
    parent = parent[sel]
    a = faces[:, [1, 2, 0]].ravel()
    b = faces[:, [2, 0, 1]].ravel()
    key = np.stack([np.minimum(a, b), np.maximum(a, b), np.repeat(parent, 3)], axis=1)
    uniq, count = np.unique(key, axis=0, return_counts=True)
    return {tuple(r) for r in uniq[count == 1].tolist()}


def _on_rim_between(rim: set, par: int, corners, old: set, new: set) -> bool:
    """Whether a vertex of the old shared edge lies on input face ``par``'s boundary between
    the new diagonal's ends (a Steiner point on an input edge: a new face would be degenerate)."""
    b, d = sorted(int(x) for x in new)
    for v in (int(x) for x in old):
        if v not in corners and (min(v, b), max(v, b), par) in rim and (min(v, d), max(v, d), par) in rim:
            return True
    return False


def _orient_proj(pts, ax: int, tri) -> float:
    """Exact orient2d of triangle ``tri`` projected along coordinate axis ``ax``."""
    i, j = (ax + 1) % 3, (ax + 2) % 3
    a, b, c = pts[tri[0]], pts[tri[1]], pts[tri[2]]
    return orient2d(a[i], a[j], b[i], b[j], c[i], c[j])


def _coplanar(job: _Job, f: np.ndarray, g: np.ndarray) -> np.ndarray:
    """Whether input faces ``f[i]`` and ``g[i]`` ((k,) int) lie exactly in one plane: (k,) bool
    by exact orient3d of f's corners with each corner of g, in one batched call (a Python
    call per pair was 3 % of the level-4 sphere)."""
    quads = np.concatenate([np.repeat(job.faces[f], 3, axis=0), job.faces[g].reshape(-1, 1)], axis=1)
    return (orient3d_batch(job.points, quads) == 0.0).reshape(-1, 3).all(axis=1)


def _spheres(job: _Job, pts, tets, solid, vbound, floor: float, guard: float):
    """Circumcentres (nt, 3), squared radii (nt,), volumes (nt,), ``reach`` (nt,) and bad
    tets (b,) int64 of the round (:func:`circumspheres`, :func:`_bad`)."""
    cc, r2, lmin, vol = circumspheres(pts, tets)
    bad, reach = _bad(job, pts, tets, solid, r2, lmin, vol, vbound, floor, guard)
    return cc, r2, vol, reach, bad


def _bad(job: _Job, pts, tets, solid, r2, lmin, vol, vmax, floor: float, guard: float) -> tuple[np.ndarray, np.ndarray]:
    """Solid tets breaking the radius-edge, size or volume bound, and how far their splits reach.

    Returns (b,) int64 tets and (nt,) float64 ``reach``: the shortest subface edge a tet's
    encroachment may split, where a size or volume bound is broken (the surface floor does
    not stop those splits), inf elsewhere.  A size bound splits subface edges down to
    :data:`SIZE_SPLIT` h only: a flat tet on a nearly flat crease of the surface has a huge
    circumradius whatever its edges, and splitting for it cascaded to the guard.
    """
    cand = np.flatnonzero(solid)
    r = np.sqrt(r2[cand])
    hard_c = vol[cand] > vmax[cand]
    reach_c = np.where(hard_c, guard, np.inf)
    if job.field is not None:
        # a constant size needs no centroids (their gather was most of this function's time)
        h = job.field.constant if job.field.constant is not None else job.field(pts[tets[cand]].mean(axis=1))
        big = r > SIZE_FACTOR * h
        hard_c |= big
        reach_c = np.where(big & ~np.isfinite(reach_c), np.maximum(guard, SIZE_SPLIT * h), reach_c)
    bad = hard_c.copy()
    if job.radius_edge is not None:
        # tets already finer than the surface floor are exempt: near an acute input angle
        # no radius-edge bound is reachable, and splitting there would cascade
        bad |= (r > MARGIN * job.radius_edge * lmin[cand]) & (lmin[cand] >= floor)
    reach = np.full(solid.shape[0], np.inf)
    reach[cand] = reach_c
    return cand[bad], reach


def _to_mesh(job: _Job, tz, faces, parent, where, state) -> Mesh:
    """The solid tets, their boundary and interface faces, markers; validated.  ``state`` is
    :func:`_unflatten`'s classification of the current tetrahedralization."""
    tets = tz.tetrahedra
    nbr = tz.neighbors
    barrier, _, solid, _, region = state
    if not solid.any():
        raise GeometryError("the surface encloses no solid (every component is a hole or outside)")
    t, k = np.divmod(where, 4)
    u = nbr[t, k]
    s_t = solid[t]
    s_u = np.where(u >= 0, solid[np.maximum(u, 0)], False)
    keep = s_t | s_u
    own = np.where(s_t, t, u)[keep]
    # faces of the owner tet opposite the slot, oriented out of it
    slot = np.where(s_t, k, np.argmax(nbr[np.maximum(u, 0)] == t[:, None], axis=1))[keep]
    tri = tets[own[:, None], TET_FACES[slot]]
    interface = (s_t & s_u)[keep]
    tri[interface] = faces[keep][interface]
    used, newid, cells, nb, locked = solid_part(tets, nbr, barrier, solid, tz.points.shape[0])
    mesh = Mesh(
        tz.points[used],
        {"tetra": cells, "triangle": newid[tri]},
        cell_data={"marker": {"tetra": region[solid].astype(np.int32), "triangle": job.markers[parent[keep]].astype(np.int32)}},
    )
    if job.slivers == "remove":
        # the sliver stage validates its result before returning (validating its input too,
        # as remove_slivers does, cost 16 % of the level-4 sphere); it gets the solid tets'
        # neighbours and subfaces from the tetrahedralization instead of sorting faces again
        mesh = _remove_slivers(mesh, job.min_dihedral, job.radius_edge, _exempt_edge(job), nb, locked)
    else:
        mesh.validate()
    if job.smooth:
        from meshwright.tet.smoothing import smooth_tets

        tri = mesh.cells["triangle"]
        pts = smooth_tets(mesh.points, mesh.cells["tetra"], tri, iterations=job.smooth, markers=mesh.cell_data["marker"]["triangle"])
        mesh = Mesh(pts, mesh.cells, cell_data=mesh.cell_data)
        mesh.validate()
    return mesh


def _exempt_edge(job: _Job) -> float:
    """The edge length below which refinement exempts a tet from the radius-edge bound."""
    fp = job.points[job.faces]
    return EXEMPT * float(np.linalg.norm(fp - fp[:, [1, 2, 0]], axis=2).min())


def _remove_slivers(mesh: Mesh, min_dihedral: float | None, radius_edge: float | None, exempt: float, neighbors, locked) -> Mesh:
    """Flips and interior vertex moves (tet/slivers.py) until the dihedral target is met.

    The sliver ratio a = r_in / R threshold starts at :data:`SLIVER_RATIO` (measured: the
    smallest dihedral angle then reaches 10-14 degrees on the test surfaces, where the
    chapter's a < 0.01 leaves 1-3 degrees) and rises while a requested ``min_dihedral`` is
    not met, up to :data:`SLIVER_RATIO_MAX`; a target still unmet raises
    :class:`MeshingError` naming the smallest angle reached.  ``neighbors`` (m, 4) int32 and
    ``locked`` (m, 4) bool (subfaces) describe ``mesh``'s tetra block for the first pass.
    """
    from meshwright.core.quality import tetra_quality
    from meshwright.tet.slivers import remove_slivers_of_valid

    threshold = SLIVER_RATIO
    while True:
        # the mesh is valid by construction (and each result is validated before returning)
        out, report = remove_slivers_of_valid(mesh, threshold, True, None, SLIVER_PASSES, radius_edge or 0.0, exempt, neighbors, locked)
        neighbors = locked = None  # they describe the first pass's input only
        # stopped at the moves' work budget (slivers.MOVE_WORK: most tets slivers, a cascaded
        # refinement): the mesh is kept as the stage left it, as after its other stops
        out_of_work = report.left_reasons.get("work_cap", 0) > 0
        if min_dihedral is None:
            # The stage's ratios never exceed the plain a = r_in / R: only below 0.01 count them.
            if report.min_ratio_after < 0.01:
                _warn_slivers(out, out_of_work)
            return out
        worst = float(tetra_quality(out.points, out.cells["tetra"])["min_dihedral"].min())
        if worst >= min_dihedral:
            return out
        if threshold >= SLIVER_RATIO_MAX or out_of_work:
            raise MeshingError(
                f"min_dihedral={min_dihedral} not reached: sliver removal leaves {worst:.2f} degrees "
                f"(flips and moves up to sliver ratio {threshold:.2f}"
                + (", stopped at the moves' work budget)" if out_of_work else ")")
            )
        mesh = out
        threshold = min(SLIVER_RATIO_MAX, threshold + 0.04)


def _warn_slivers(mesh: Mesh, out_of_work: bool) -> None:
    """A :class:`SliverWarning` naming the tets of ``mesh`` whose sliver ratio a = r_in / R is
    below 0.01, if any (one pass of the sliver kernels' ratio, no radius-edge factor)."""
    from meshwright.tet._flips import all_ratios

    tets = mesh.cells["tetra"]
    a = all_ratios(mesh.points, np.ascontiguousarray(tets, dtype=np.int32).ravel(), len(tets), np.zeros(2))
    flat = int(np.count_nonzero(a < 0.01))
    if flat:
        warnings.warn(
            f"tetrahedralize: {flat} tets keep a sliver ratio r_in / R below 0.01 after sliver removal (smallest "
            f"{float(a.min()):.3g}{', moves stopped at their work budget' if out_of_work else ''}); pass "
            "min_dihedral to make an unmet bound an error",
            SliverWarning,
            stacklevel=6,  # the caller of tetrahedralize (-> _run_delaunay -> _to_mesh -> _remove_slivers -> here)
        )


TET_METHODS = {
    "delaunay": TetMethod(
        "delaunay",
        "Delaunay refinement of the recovered surface (18.4.1): radius-edge bound, size field, sliver removal",
        _run_delaunay,
    ),
}
