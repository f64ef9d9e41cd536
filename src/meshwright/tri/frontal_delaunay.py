r"""Combined Delaunay + advancing front: frontal Delaunay point placement (chapter 18.3).

Sources: J.-D. Müller, P. L. Roe and H. Deconinck, "A frontal approach for internal node
generation in Delaunay triangulations", Int. J. Numer. Meth. Fluids 17, 1993 (chapter 18.3:
nodes created by advancing-front rules from the front of accepted triangles, inserted by
Delaunay insertion, the background size taken from the boundary triangulation);
S. Rebay, "Efficient unstructured mesh generation by means of Delaunay triangulation and
Bowyer-Watson algorithm", J. Comput. Phys. 106, 1993 (the point on the perpendicular
bisector of a front edge, and the order: worst triangle first).

Procedure
---------
Start from the classified constrained Delaunay triangulation of the boundary points
(:mod:`meshwright.tri.cdt`); the size ``h`` is the user's field or, as in 18.3, the
background interpolated from the boundary triangulation itself (Weatherill's ``dP``).
A triangle is *accepted* when its circumradius is at most ``ACCEPT`` times that of the
equilateral triangle of side h, ``R <= ACCEPT h / sqrt(3)``.  The *front* is the set of
edges between an accepted triangle (or the domain boundary) and a triangle that is not;
the non-accepted triangles on it wait in a queue keyed by ``R sqrt(3) / h``, largest first
(a bucket queue from which a destroyed triangle's entry is deleted,
:mod:`meshwright.tri._frontal_queue`).  Repeatedly:

1. the worst waiting front triangle proposes the point X on the perpendicular bisector of
   its front edge AB (the longest, if several), on its own side, such that ABX has
   circumradius ``rho = clamp(h / sqrt(3), |AB| / 2, R_t)``, i.e. at the distance
   ``rho + sqrt(rho^2 - |AB|^2 / 4)`` from the midpoint of AB: an equilateral element of
   size h where room allows, never beyond the triangle's own circumcentre::

                     X   <- ideal point, |MX| = rho + sqrt(rho^2 - p^2)
                    / \
                   /   \      not accepted
                  /     \
             A --M------- B   front edge (length 2p)
               accepted / boundary

2. X is inserted by constrained Delaunay insertion unless it falls outside the domain or
   within ``SPACING h`` of a vertex, in which case the triangle is accepted as it is;
3. the new triangles around X are accepted or queued, and so are their neighbours that the
   front now reaches.

Müller, Roe and Deconinck insert a whole row of such points at once; inserting them one at
a time, worst first (Rebay's order), measured a mean radius ratio of 0.98-0.99 against 0.92
for rows on the benchmark disk, for the same node-placement rule.  Termination: each point
is at least ``SPACING min(h)`` from every vertex, so a bounded domain holds finitely many;
``max_points`` caps them all the same.

Sizes are evaluated inside the kernel on a background grid
(:func:`meshwright.sizing.background.interpolate_walk`): the given
:class:`~meshwright.sizing.BackgroundGrid`, a uniform one for a constant, or for any other
field a grid sampled at the vertices of a Delaunay refinement to ``SAMPLE`` times the size.
Each vertex keeps a background triangle at or near it, and a size query for a triangle or
a front edge walks from its vertex's: the queue jumps about the whole front, and walks from
the previous query crossed the graded sample, or left it across a hole into a bucket scan
(7x the kernel's time on the graded NACA 0012 of ``benchmarks/quality2d.py``).

Scaffold
--------
Points inserted in frontal order land next to triangles that span the whole unmeshed
interior (the Delaunay triangulation of the front's vertices): their circumcircles reach
far ahead of the front, so cavities are long, and front vertices have a large degree, so
the disc searches around a proposed point are long too.  So the interior is first filled
with a removable *scaffold*, inserted in Hilbert order where its points keep
``SCAFFOLD / 2`` h from every vertex (none when there are fewer than ``MIN_SCAFFOLD``
candidates: the front is short and the mesh stays the one without).  The candidates are,
for a uniform or given background grid, the centres of the leaves of a quadtree whose cells
are at most ``SCAFFOLD`` times the local size; for any other size field, the vertices of
its sample (a refinement to ``SAMPLE`` h, so about the same spacing) off the boundary,
whose sizes are known: locating a quadtree's cells one by one in a strongly graded sample
(the NACA 0012 far field: 1e-3 at the wall, 1 in the far field, thousands of sample
triangles per bucket near the wall, the airfoil's inside refined by the wall's size for
nothing) cost 1.0 s of a 20k-triangle mesh.  Triangles with a scaffold
vertex are never accepted and wait in the queue before all others, as the long triangles
do without a scaffold; the front deletes a scaffold vertex when it proposes a point within
``CLEAR`` h of it (vertex removal, :mod:`meshwright.tri._scaffold`), so no scaffold vertex
is left in the mesh.  Measured on the benchmark disk (289k triangles) with the binary heap
it was 1.4-1.9x faster; since the bucket queue (:mod:`meshwright.tri._frontal_queue`, which
pops no destroyed triangle) it saves no time (disk at n = 1256 and 2512 within noise), and it
stays because a strongly graded far field gets better elements with it (NACA 0012, wall 1e-3
to 1 over 10 chords: mean radius ratio 0.9324 against 0.9287 without, min angle 19.8 against
16.3 degrees; the cause is not isolated).  (The replay that motivated it, the final points re-inserted in
frontal order, 2.2 s against 0.43 s in Hilbert order, is dominated by the replay's walk
from the previous point, which the method does not pay: it walks from the front triangle.)

Stretching
----------
A background grid with one stretching s and direction alpha everywhere (chapter 18.2's
transformation ``T = R(alpha) diag(1/s, 1) R(-alpha)`` is then a constant) is honoured by
meshing in the space mapped by ``T``, where the wanted elements are equilateral of side
delta: the constrained Delaunay triangulation of the mapped boundary is rebuilt there
(Delaunay is not affine invariant), its regions are taken from the plane's
(:mod:`meshwright.tri._mapped`), the method runs isotropically, and the new points are
mapped back (the boundary points keep their given coordinates; every inside triangle's
orientation is checked exactly in the plane).  The mesh is Delaunay in the mapped space, so
no planar refinement pass may follow (``min_angle`` and area bounds are refused there).
A varying stretching is refused (``method="front"`` follows it element by element).

State: the :class:`ConstrainedTriangulation`'s two bundles (``state``, ``constraints``) and
the method's ``FrontalState``, layout in :mod:`meshwright.tri._frontal_kernel`.
"""

from __future__ import annotations

import copy
import math

import numpy as np

from meshwright.core.errors import InputError, MeshingError
from meshwright.core.flat import grown_rows
from meshwright.core.spatial_sort import hilbert_order
from meshwright.sizing.background import BackgroundGrid
from meshwright.sizing.field import as_size_field
from meshwright.tri import _frontal_kernel as fk
from meshwright.tri._frontal_queue import new_frontal_queue
from meshwright.tri._kernel2d import M_NTRI, M_NV
from meshwright.tri._mapped import transfer_regions
from meshwright.tri._refine_caps import estimate
from meshwright.tri._scaffold import SCRATCH

__all__ = ["ACCEPT", "CLEAR", "SAMPLE", "SCAFFOLD", "SPACING", "frontal_delaunay", "scaffold_points", "stretching"]

ACCEPT = 1.4  # R <= ACCEPT * h / sqrt(3): the triangle is of the right size
SPACING = 0.7  # a new point keeps this fraction of h away from every vertex
SAMPLE = 3.0  # a general size field is sampled on a mesh this many times coarser
SCAFFOLD = 4.0  # scaffold cells are at most this many times the local size
CLEAR = 1.0  # a proposed point removes the scaffold vertices within this many h
MIN_SCAFFOLD = 1000  # fewer scaffold cells than this: no scaffold (the front is short)
LIFT = 1e3  # queue-key lift of a triangle with a scaffold vertex: it waits before all others
_MAX_LEVELS = 40  # quadtree levels of the scaffold (cells of 2**-40 of the box)
_MAX_ROOT_LEVELS = 10  # a thin box gets up to 2**10 roots along its longer side


def _background(ct, field, max_points) -> tuple[BackgroundGrid, np.ndarray | None]:
    """A background grid giving ``field`` (see the module docstring), and for a sampled
    field the scaffold candidates it yields: the sample's vertices off the boundary, in
    Hilbert order (None for a given or uniform grid).  ``max_points`` (or None) caps the
    sample as it caps the method: refinement's default cap, from the size alone, is short
    where the boundary needs many more vertices than the size (a needle's sides matched
    to each other, ``tests/test_refine_chains.py``)."""
    if isinstance(field, BackgroundGrid):
        return field, None
    p = ct.points
    lo, hi = p.min(axis=0), p.max(axis=0)
    if field.constant is not None:
        return BackgroundGrid.uniform((lo[0], lo[1], hi[0], hi[1]), field.constant), None
    from meshwright.tri.ruppert import refine

    sample = copy.deepcopy(ct)
    refine(sample, min_angle=20.0, size=lambda xy: SAMPLE * field(xy), max_points=max_points)
    # The inside triangles cover the domain.
    grid = BackgroundGrid.on_triangulation(sample.points, sample.triangles(True), field(sample.points))
    nv = sample.n_points
    off = np.arange(ct.n_points, nv)
    off = off[sample.constraints.vseg[ct.n_points:nv] < 0]
    xy = np.ascontiguousarray(sample.points[off])
    return grid, np.ascontiguousarray(xy[hilbert_order(xy)]) if len(xy) else xy


def scaffold_points(bg: BackgroundGrid, lo, hi, limit: int) -> np.ndarray:
    """Centres of the leaves of a quadtree over the box ``lo``-``hi`` whose cells are at
    most ``SCAFFOLD`` times the spacing of ``bg`` at their centre, in Hilbert order.

    The roots are squares of the longer side over ``2**k``, the smallest ``k <= 10`` for
    which the shorter side is at least that (one root for a box of aspect ratio below 2):
    a square root over a thin box would spend almost all its leaves outside it.

    Parameters
    ----------
    bg : BackgroundGrid
        2-D; its ``delta`` is the size h.
    lo, hi : (2,) float64
        Box of the domain.
    limit : int
        Most leaves wanted; a finer tree stops refining (its leaves are then coarser).

    Returns
    -------
    (k, 2) float64
        The candidates, each moved off its cell's centre by a fixed fraction of the cell
        (a lattice's exactly cocircular quadruples would send every in-circle test of the
        insertions and removals to the exact stage).
    """
    wx, wy = float(hi[0] - lo[0]), float(hi[1] - lo[1])
    side = max(wx, wy)
    if not side > 0.0:
        return np.zeros((0, 2))
    k = 0
    while k < _MAX_ROOT_LEVELS and side / 2 ** (k + 1) >= min(wx, wy):
        k += 1
    side /= 2**k
    nx, ny = max(1, math.ceil(wx / side)), max(1, math.ceil(wy / side))
    if nx * ny > limit:
        return np.zeros((0, 2))
    gx, gy = np.meshgrid(lo[0] + side * (np.arange(nx) + 0.5), lo[1] + side * (np.arange(ny) + 0.5))
    centres = np.column_stack([gx.ravel(), gy.ravel()])
    leaves = []
    half = 0.5 * side
    count = 0
    for _ in range(_MAX_LEVELS):
        h = bg.metric(centres)[0]
        split = 2.0 * half > SCAFFOLD * h
        if count + 4 * int(split.sum()) > limit:
            split[:] = False
        leaves.append((centres[~split], half))
        count += int((~split).sum())
        if not split.any():
            break
        c = centres[split]
        half *= 0.5
        centres = np.concatenate(
            [c + (-half, -half), c + (half, -half), c + (-half, half), c + (half, half)]
        )
    pts = np.concatenate([p for p, _ in leaves]) if leaves else np.zeros((0, 2))
    if len(pts) == 0:
        return pts
    size = np.concatenate([np.full(len(p), r) for p, r in leaves])
    i = np.arange(len(pts))
    # Weyl-sequence offsets: deterministic, no random state.
    pts = pts + (np.stack([(i * 0.6180339887) % 1.0, (i * 0.7548776662) % 1.0], axis=1) - 0.5)[:, :] * (
        0.2 * size[:, None]
    )
    return np.ascontiguousarray(pts[hilbert_order(pts)])


def _grown(f: fk.FrontalState, ct) -> fk.FrontalState:
    """``f`` with per-slot and per-row arrays that match ``ct`` (doubling)."""
    slots = len(ct.constraints.treg)
    rows = len(ct.state.pts)
    return f._replace(
        acc=grown_rows(f.acc, slots, 0), stamp=grown_rows(f.stamp, slots, 0), ratio=grown_rows(f.ratio, slots, 0.0),
        qnext=grown_rows(f.qnext, slots), qprev=grown_rows(f.qprev, slots), qbin=grown_rows(f.qbin, slots, -1),
        vflag=grown_rows(f.vflag, rows, 0), free=grown_rows(f.free, rows, 0), vbg=grown_rows(f.vbg, rows, -1),
    )


def _room(ct, f):
    ct.reserve(ct.n_points + 1024, int(ct.state.meta[M_NTRI]) + 2048)
    return _grown(f, ct)


def stretching(size) -> np.ndarray | None:
    """The constant transformation ``T`` (2, 2) of a uniformly stretched background grid.

    Parameters
    ----------
    size : number, callable, SizeField or BackgroundGrid

    Returns
    -------
    (2, 2) float64 or None
        None when ``size`` is not a stretched 2-D background grid.

    Raises
    ------
    InputError
        A background grid whose stretching or direction varies: Delaunay connectivity in
        one transformed space cannot follow a varying one (``method="front"`` can).
    """
    if not isinstance(size, BackgroundGrid) or size.dim != 2 or np.all(size.stretch == 1.0):
        return None
    s, a = size.stretch, size.direction
    c2, s2 = np.cos(2.0 * a), np.sin(2.0 * a)
    if (s != s[0]).any() or (c2 != c2[0]).any() or (s2 != s2[0]).any():
        i = int(np.flatnonzero((s != s[0]) | (c2 != c2[0]) | (s2 != s2[0]))[0])
        raise InputError(
            "frontal-delaunay honours a uniform stretching only (one s and alpha over the background grid); "
            f"node {i} has s = {s[i]:g}, alpha = {np.degrees(a[i]):g} degrees against node 0's s = {s[0]:g}, "
            f"alpha = {np.degrees(a[0]):g}: use method='front' for a varying stretching"
        )
    return size.transform(size.points[:1])[0]


def _stretched(ct, grid: BackgroundGrid, T: np.ndarray, max_points, scaffold) -> dict:
    """Frontal Delaunay in the space mapped by ``T`` (:mod:`meshwright.tri._mapped`), in place."""
    from meshwright.core.predicates import orient2d_batch
    from meshwright.tri.cdt import cdt_build

    nb = ct.n_points
    plane = ct.points.copy()
    s, c = ct.state, ct.constraints
    ntri = int(s.meta[M_NTRI])
    tri = s.tri[: 3 * ntri].reshape(-1, 3)
    cons = s.cons[: 3 * ntri].reshape(-1, 3)
    t, k = np.nonzero(cons)
    ids, first = np.unique(cons[t, k] - 1, return_index=True)
    segs = np.column_stack([tri[t[first], (k[first] + 1) % 3], tri[t[first], (k[first] + 2) % 3]])
    mct = cdt_build(plane @ T.T, segs, seed=0)
    ms = mct.state
    mn = int(ms.meta[M_NTRI])
    if mct.n_points != nb or not np.array_equal(mct.index_map, np.arange(nb)):
        raise MeshingError(
            f"frontal Delaunay: the {nb} boundary points do not stay distinct under the stretching "
            f"(s = {grid.stretch[0]:g}); {mct.n_points} vertices after the mapping"
        )
    mcons = ms.cons[: 3 * mn]
    if len(np.unique(mcons[mcons > 0])) != len(segs) or mcons.max(initial=0) > len(segs):
        raise MeshingError("frontal Delaunay: recovering the boundary in the stretched space split a segment")
    bad = transfer_regions(ms.tri, ms.nbr, ms.cons, mn, mct.constraints.treg, s.tri, s.nbr, c.vtri, c.treg)
    if bad >= 0:
        raise MeshingError(f"frontal Delaunay: triangle {bad} of the stretched space has no region")
    mct.classified = True
    mapped = BackgroundGrid(grid.points @ T.T, grid.cells, grid.delta)
    counts = frontal_delaunay(mct, mapped, max_points=max_points, scaffold=scaffold)
    ms = mct.state
    mn = int(ms.meta[M_NTRI])
    nv = mct.n_points
    ms.pts[nb:nv] = ms.pts[nb:nv] @ np.linalg.inv(T).T
    ms.pts[:nb] = plane  # the boundary points exactly as given (on their true curves)
    inside = mct.triangles(True)
    o = orient2d_batch(ms.pts, inside)
    if (o <= 0.0).any():
        i = int(np.flatnonzero(o <= 0.0)[0])
        raise MeshingError(
            f"frontal Delaunay: triangle {inside[i].tolist()} folds over when mapped back from the stretched space"
        )
    # The pieces keep the plane's numbering and curve data; vertex data of the boundary rows too.
    mc = mct.constraints
    back = np.zeros(len(segs) + 1, dtype=np.int32)
    back[1:] = ids + 1
    ms.cons[: 3 * mn] = back[ms.cons[: 3 * mn]]
    vseg, vpar, vacute = mc.vseg.copy(), mc.vpar.copy(), mc.vacute.copy()
    vseg[:nb], vpar[:nb], vacute[:nb] = c.vseg[:nb], c.vpar[:nb], c.vacute[:nb]
    ct.state = ms
    ct.constraints = mc._replace(
        seg=c.seg, seg_in=c.seg_in, pkind=c.pkind, pdat=c.pdat, rarea=c.rarea, vseg=vseg, vpar=vpar, vacute=vacute
    )
    return counts


def frontal_delaunay(ct, size, *, max_points: int | None = None, scaffold: bool = True) -> dict:
    """Fill a classified constrained triangulation with frontal points, in place.

    Parameters
    ----------
    ct : ConstrainedTriangulation
        From :func:`meshwright.tri.cdt.cdt_build`, exterior removed by ``classify``.
    size : number, callable or SizeField
        Target edge length h(x).
    max_points : int, optional
        Cap on the number of vertices.
    scaffold : bool
        Fill the interior with the removable scaffold first (module docstring); False
        inserts into the bare boundary triangulation (the same mesh quality, slower).

    Returns
    -------
    dict
        Counts: ``added`` frontal points, ``scaffold`` points seeded, ``removed`` and
        ``kept`` (scaffold vertices whose removal was refused, left as ordinary vertices).

    Raises
    ------
    InputError
        ``max_points`` not a positive integer, ``scaffold`` not a bool.
    MeshingError
        The cap was hit, or an insertion met an inconsistent cavity (the message names it).
    """
    if max_points is not None and (isinstance(max_points, bool) or not isinstance(max_points, (int, np.integer))
                                   or max_points < 1):
        raise InputError(f"frontal_delaunay: max_points must be a positive integer, got {max_points!r}")
    if not isinstance(scaffold, (bool, np.bool_)):
        raise InputError(f"frontal_delaunay: scaffold must be True or False, got {scaffold!r}")
    T = stretching(size)
    if T is not None:
        return _stretched(ct, size, T, max_points, scaffold)
    field = as_size_field(size)
    grid, sampled = _background(ct, field, max_points)
    bg = grid.kernel_args() + (np.zeros(1, dtype=np.int64),)  # last: the walk's hint
    par = np.zeros(fk.P_LEN)
    par[fk.P_ACCEPT] = ACCEPT
    par[fk.P_SPACING] = SPACING
    par[fk.P_MAX_POINTS] = np.iinfo(np.int32).max if max_points is None else int(max_points)
    par[fk.P_CONST] = field.constant if field.constant is not None else 0.0
    par[fk.P_CLEAR] = CLEAR
    par[fk.P_SCAF] = SCAFFOLD
    par[fk.P_LIFT] = LIFT
    slots = len(ct.constraints.treg)
    rows = len(ct.state.pts)
    qhead, qnext, qprev, qbin, qhdr = new_frontal_queue(slots)
    f = fk.FrontalState(
        acc=np.zeros(slots, dtype=np.int8), ratio=np.zeros(slots),
        qhead=qhead, qnext=qnext, qprev=qprev, qbin=qbin, qhdr=qhdr,
        stamp=np.zeros(slots, dtype=np.int64), fmeta=np.zeros(fk.FM_LEN, dtype=np.int64), par=par,
        vflag=np.zeros(rows, dtype=np.int8), free=np.zeros(rows, dtype=np.int32),
        scr=np.zeros(SCRATCH, dtype=np.int32), vbg=np.full(rows, -1, dtype=np.int32),
        stack=np.empty(fk.STACK, dtype=np.int32),
    )
    seeded = 0
    if scaffold:
        if sampled is not None:
            xy = sampled
        else:
            p = ct.points
            cap = int(par[fk.P_MAX_POINTS])
            # The tree covers the domain's box, not the domain: a thin domain across its box
            # would grow it far past the points the domain itself needs (its inside triangles'
            # area over h^2), which is all a scaffold of SCAFFOLD h cells can use.
            need = int(min(estimate(ct, np.inf, grid), 1 << 26))
            xy = scaffold_points(grid, p.min(axis=0), p.max(axis=0), min(cap, 1 << 26, 4 * need + 4 * MIN_SCAFFOLD))
        if len(xy) < MIN_SCAFFOLD:
            xy = xy[:0]  # a short front: no long cavities to avoid, same mesh as without
        i = 0
        n0 = ct.n_points
        for _ in range(64 + 2 * len(xy)):
            i, code = fk.seed_scaffold(xy, i, ct.state, ct.constraints, f, bg)
            if code == fk.F_DONE:
                break
            if code == fk.F_BROKEN:
                raise MeshingError(f"frontal Delaunay: scaffold point {i} at {tuple(xy[i])} met an inconsistent cavity")
            f = _room(ct, f)
        seeded = ct.n_points - n0
    fk.start(ct.state, ct.constraints, f, bg)
    ct.refresh_pieces()
    while True:
        code = fk.run(ct.state, ct.constraints, f, bg)
        if code == fk.F_DONE:
            break
        if code == fk.F_POINTS:
            raise MeshingError(f"frontal Delaunay reached max_points = {int(par[fk.P_MAX_POINTS])} vertices")
        if code == fk.F_BROKEN:
            raise MeshingError(f"frontal Delaunay: an insertion met an inconsistent cavity ({ct.n_points} vertices)")
        f = _room(ct, f)
    if int(f.fmeta[fk.FM_NFREE]) > 0:
        # Dead rows of removed scaffold vertices: close them up, with perturbation keys
        # covering every row so that a moved vertex keeps its own (``_scaffold.move_row``).
        nv = int(ct.state.meta[M_NV])
        rank = ct.state.rank
        if len(rank) < nv:
            full = np.arange(nv, dtype=np.int32)
            full[: len(rank)] = rank
            ct.state = ct.state._replace(rank=full)
        if not fk.close_rows(ct.state, ct.constraints, f):
            raise MeshingError("frontal Delaunay: a vertex star did not close while renumbering rows")
    return {
        "added": int(f.fmeta[fk.FM_ADDED]), "scaffold": seeded, "removed": int(f.fmeta[fk.FM_REMOVED]),
        "kept": int(f.fmeta[fk.FM_KEPT]),
    }
