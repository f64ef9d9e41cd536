"""``triangulate``: one entry point from a domain to a boundary-conforming triangle mesh.

Pipeline (every method of the 2-D chapter sections shares its ends)::

    Domain --discretize(size)--> PSLG --cdt_build--> constrained Delaunay triangulation
        --classify (18.1.2: exterior, holes, regions)--> point placement by ``method``
        --to_mesh (markers)--> optional spring-analogy smoothing (18.2) --> Mesh

Point placement methods (:data:`MESH_METHODS`, the CLI's ``--method`` choices):

* ``delaunay``: guaranteed-quality Delaunay refinement (Ruppert 1995 with Üngör's
  off-centres, :mod:`meshwright.tri.ruppert`), minimum angle and size field honoured;
* ``weatherill``: the chapter's automatic point generation (Weatherill 1992, 18.1.3,
  :mod:`meshwright.tri.weatherill`) driven by the boundary point distribution function
  ``dP`` (capped by the size field if one is given);
* ``frontal-delaunay``: advancing-front points inserted by the Delaunay kernel (18.3,
  :mod:`meshwright.tri.frontal_delaunay`);
* ``front``: the advancing-front method itself (18.2, :mod:`meshwright.tri.front`): its
  triangles replace the constrained triangulation's, and a background grid's stretching
  and direction shape them.

Without a size (and none carried by the domain) every method but ``delaunay`` follows
the default size of :func:`_default_size` (issue 14): the local feature size of the
domain's polygon (Ruppert 1995, :mod:`meshwright.sizing.lfs`), graded, capped at half the
domain's extent, with curves sized by their turning and area bounds graded in, so that
short features get small elements and long segments are split.  ``delaunay`` takes none:
Delaunay refinement grades its meshes by the local feature size by itself (its registry
entry's ``grades_itself``).  ``size="boundary"`` names the chapter's own mode instead: the
boundary as the domain discretises it, Weatherill's ``dP`` from it (18.1.3), and for
``frontal-delaunay`` and ``front`` the chapter's background, the triangulated boundary
nodes with their point distribution function (18.3).

Grading from the boundary (``grading=g``, default :data:`DEFAULT_GRADING` = 1.2;
:data:`RELAXED_GRADING` = 1.1 where ``front`` and ``frontal-delaunay`` relax their mesh;
none for ``delaunay``, whose refinement grades by itself): where the
discretised boundary is finer than the size (polygon vertices given closer, curves split
for their turning, a fine wall), every method follows ``h(x) = min(size(x), min_i (dP_i +
(g - 1) |x - x_i|))`` over the boundary points ``x_i`` with their spacing ``dP_i``
(those whose spacing is below :data:`~meshwright.sizing.boundary.FINER` times the size: :func:`~meshwright.sizing.gradation`,
the Lipschitz limit ``|grad h| <= g - 1`` of Persson 2006), so elements grow from the boundary spacing to ``size`` instead of
jumping; ``size`` stays the upper bound.  The boundary is discretised again with the
graded size, so that straight pieces next to finer given vertices grade as well.  This is
Gmsh's default
``Mesh.MeshSizeExtendFromBoundary = 1`` done as a gradation limit, and ``grading=None`` is
its ``0``: the size exactly as given.  The chapter's background of ``size="boundary"`` is
capped the same way (its linear interpolation of ``dP`` may grow as fast as the boundary
spacing jumps); the default size is the local feature size graded by ``g`` (it starts from
the boundary's features already), so it needs no cap and ``grading=None`` is refused with
it; a stretched background grid is the user's own drawing and is used as given.

What each method honours is declared in its registry entry (:class:`MeshMethod`), and
:func:`triangulate` checks every argument against it before any work: ``min_angle`` up to
``max_min_angle`` (Delaunay refinement natively; Weatherill and frontal Delaunay by a final
Delaunay refinement pass on their points; the advancing front, which makes its own
triangles, not at all), ``progress`` where the method reports it, and the method's own
options (Weatherill's ``alpha``).  A parameter a method cannot honour is an error, never
dropped.  Region seeds' area bounds are honoured as ``max_area`` is, and their float
attributes come back per triangle (``cell_data["region_attribute"]``) when they say more
than the markers.  A domain whose
segments close no boundary (``Domain.open_boundary``) is meshed only with
``convex_hull=True``, which every method declares it honours.  The work is capped:
``max_points`` bounds every method, and a size or area bound that would need more points
than the cap is refused before the boundary is discretised.

Smoothing keeps boundary nodes on their true curves: each boundary node slides along the
curve of its segments (projected with :meth:`Domain.project`); nodes where two curves meet
and the domain's interior points never move.
"""

from __future__ import annotations

from typing import Callable, NamedTuple

import math
import numbers
import os
from pathlib import Path

import numpy as np

from meshwright.core.errors import GeometryError, InputError, SizeError
from meshwright.core.mesh import Mesh
from meshwright.core.validate_input import check_count, check_flag, check_positive, check_seed
from meshwright.geometry.curves import Line, Polyline
from meshwright.geometry.domain import Discretization, Domain
from meshwright.geometry.shapes import BUILTIN_DOMAINS, builtin, polygon
from meshwright.sizing.background import BackgroundGrid
from meshwright.sizing.boundary import boundary_size, graded_from_boundary, gradation, is_stretched, point_distribution
from meshwright.sizing.field import SizeField, as_size_field
from meshwright.sizing.lfs import DEFAULT_CAP, DEFAULT_GROWTH, lfs_field, turning_size
from meshwright.tri.cdt import ConstrainedTriangulation, SegmentCurves, cdt_build
from meshwright.tri.front import advancing_front
from meshwright.tri.frontal_delaunay import frontal_delaunay, stretching
from meshwright.tri._postprocess import input_nodes, region_data, relax_domain, relax_flag, smooth_mesh
from meshwright.tri.relax import relax_mesh
from meshwright.tri.ruppert import conform, refine
from meshwright.tri.weatherill import DEFAULT_ALPHA, weatherill

__all__ = [
    "MESH_METHODS", "MeshMethod", "triangulate", "DEFAULT_MAX_POINTS", "RUPPERT_MAX_ANGLE", "BOUNDARY_SIZE",
    "DEFAULT_GRADING", "GRADING_AUTO", "RELAXED_GRADING",
]

DEFAULT_MAX_POINTS = 100_000_000  # vertices; about 20 GB of kernel arrays, far beyond a 2-D mesh anyone waits for
RUPPERT_MAX_ANGLE = 33.8  # degrees: where Delaunay refinement with off-centres still terminates in practice
BOUNDARY_SIZE = "boundary"  # the named size: the chapter's spacing from the boundary alone
TURN_PER_ELEMENT = math.pi / 16  # radians a curve turns along one element of the default size
_AREA_SOURCES = 2_000_000  # most sources the default size spreads over area-bounded regions
DEFAULT_GRADING = DEFAULT_GROWTH  # g of the grading from the boundary: |grad h| <= g - 1, as the default size's
# The relaxing methods' g where they relax (their registry entries, _auto_grading): frontal
# points keep their shape only as well as the size varies across a triangle.
# benchmarks/grading2d.py's four domains, mean radius ratio relaxed at g = 1.2 -> 1.1,
# front / frontal-delaunay: holes30 0.9635 -> 0.9758 /
# 0.9712 -> 0.9778 (Gmsh Frontal-Delaunay 0.9750), slit 0.9744 -> 0.9789 / 0.9686 -> 0.9794
# (0.9729), radii and naca up 0.009-0.012 (already above Gmsh's), for 1.4-2.5x the triangles
# (up to Gmsh's count, but 2.1x Gmsh's on the naca's wide far field).  Relaxation cannot
# buy it instead: on holes30 more swap rounds and smoothing passes over every node gained
# under 0.001.  A size given already graded (no boundary spacing under FINER times it)
# meshes as before.
RELAXED_GRADING = 1.1
# grading's default (_auto_grading): DEFAULT_GRADING, or the registry entry's where the mesh is
# relaxed, for the methods that place points by a size, none for a method that grades itself
# (Delaunay refinement follows the local feature size by its own splits; a graded field only
# adds 1.5-3.5x the triangles there and a Python size callback).
GRADING_AUTO = "auto"


class _Job(NamedTuple):
    """What a point-placement method gets: the classified CDT and the checked request."""

    ct: ConstrainedTriangulation
    disc: Discretization
    field: SizeField | None
    min_angle: float
    max_area: float | None
    progress: bool
    max_points: int
    alpha: float
    grading: float | None


class MeshMethod(NamedTuple):
    """A point-placement method of :func:`triangulate`.

    Attributes
    ----------
    name : str
    summary : str
        One line for ``--help``.
    place : callable
        ``place(job)`` adds points to ``job.ct`` in place and returns None, or returns its
        own triangulation of the inside ``(points (n, 2) float64, triangles (t, 3) int32)``
        on ``job.ct``'s vertices followed by new ones (see ``ConstrainedTriangulation.to_mesh``).
    max_min_angle : float
        Largest ``min_angle`` (degrees) the method guarantees; 0 when it honours none.
    default_min_angle : float
        ``min_angle`` used when the caller gives None.
    reports_progress : bool
        Whether ``progress=True`` shows a bar for this method.
    options : tuple of str
        Keyword options of :func:`triangulate` only this method takes (``"alpha"``).
    convex_hull : bool
        Whether the method meshes the convex hull of an open set of segments
        (``convex_hull=True``, Triangle's ``-c``).
    grades_itself : bool
        Whether the method's own point placement follows the local feature size, so that
        without a size it takes none (Delaunay refinement: Ruppert 1995 proves its meshes
        graded by the lfs); the others get :func:`_default_size`.
    relaxes : bool
        Whether :func:`triangulate` relaxes the method's mesh by default
        (:mod:`meshwright.tri.relax`: where no bound is asked for and the size is isotropic).
    grading : float
        Growth factor ``g`` of the grading from the boundary under ``grading="auto"`` where
        the mesh is relaxed (:data:`DEFAULT_GRADING`; :data:`RELAXED_GRADING` for the
        relaxing methods, whose mean shape follows how fast the size grows); a mesh not
        relaxed grades at :data:`DEFAULT_GRADING`, and one that ``grades_itself`` not at all.
    """

    name: str
    summary: str
    place: Callable[[_Job], tuple | None]
    max_min_angle: float
    default_min_angle: float
    reports_progress: bool
    options: tuple[str, ...] = ()
    convex_hull: bool = True
    grades_itself: bool = False
    relaxes: bool = False
    grading: float = DEFAULT_GRADING


def _place_delaunay(job: _Job) -> None:
    kw = dict(min_angle=job.min_angle, size=job.field, max_area=job.max_area, max_points=job.max_points)
    if not job.progress:
        refine(job.ct, **kw)
        return
    from tqdm import tqdm

    with tqdm(desc="Delaunay refinement", unit=" vertices", leave=False) as bar:

        def report(n: int) -> None:
            bar.update(n - bar.n)

        refine(job.ct, progress=report, **kw)


def _finish(job: _Job) -> None:
    """The angle and area bounds (global and regional) of a point-placement method without
    its own: a Delaunay refinement pass on its points (by angle and area only; its spacing
    already holds)."""
    if job.min_angle > 0.0 or job.max_area is not None or (job.disc.regions[:, 3] > 0).any():
        refine(job.ct, min_angle=job.min_angle, max_area=job.max_area, max_points=job.max_points)


def _place_weatherill(job: _Job) -> None:
    ct, disc = job.ct, job.disc
    dp_in = point_distribution(disc.points, disc.segments)
    # dP of each vertex of the CDT: coincident input points share a vertex.
    dp = np.full(ct.n_points, np.nan)
    dp[ct.index_map] = dp_in
    lonely = ~np.isfinite(dp)
    if lonely.any():
        # Interior points on no segment: the mean dP of the boundary stands in.
        dp[lonely] = np.nanmean(dp_in) if np.isfinite(dp_in).any() else 1.0
    bar = None
    if job.progress:
        from tqdm import tqdm

        bar = tqdm(desc="weatherill passes", unit="pass", leave=False)
    try:
        weatherill(
            ct,
            dp,
            job.alpha,
            size=job.field if job.field is not None else _boundary_cap(job),
            max_points=job.max_points,
            callback=None if bar is None else (lambda p, acc, n: bar.update(1)),
        )
    finally:
        if bar is not None:
            bar.close()
    _finish(job)


def _boundary_cap(job: _Job, base=None) -> SizeField | None:
    """``base`` graded from the boundary (:func:`~meshwright.sizing.boundary_size`), or the grading alone for a
    method without a size; None when ``grading=None`` leaves it as it is."""
    if job.grading is None:
        return base
    return boundary_size(job.disc.points, job.disc.segments, job.grading, base=base)


def _background(job: _Job):
    """The size field, or chapter 18.3's background: the triangulated boundary nodes with
    their point distribution function, interpolated linearly, graded from the boundary."""
    if job.field is not None:
        return job.field
    ct = job.ct
    bg = BackgroundGrid.from_boundary(ct.points, ct.index_map[job.disc.segments], ct.triangles(False))
    return _boundary_cap(job, bg)


def _place_frontal(job: _Job) -> None:
    field = _background(job)
    if stretching(field) is not None and (job.min_angle > 0.0 or job.max_area is not None
                                          or (job.disc.regions[:, 3] > 0).any()):
        raise InputError("frontal-delaunay under a stretched background grid honours no min_angle or area bound "
                         "(a Delaunay refinement pass in the plane would undo the stretching)")
    frontal_delaunay(job.ct, field, max_points=job.max_points)
    _finish(job)


def _place_front(job: _Job) -> tuple:
    field = _background(job)
    bar = None
    if job.progress:
        from tqdm import tqdm

        bar = tqdm(desc="advancing front", unit=" nodes", leave=False)
    try:
        return advancing_front(
            job.ct,
            field,
            max_area=job.max_area,
            max_points=job.max_points,
            progress=None if bar is None else (lambda n: bar.update(n - bar.n)),
        )
    finally:
        if bar is not None:
            bar.close()


MESH_METHODS: dict[str, MeshMethod] = {
    m.name: m
    for m in (
        MeshMethod(
            "delaunay", "guaranteed-quality Delaunay refinement (Ruppert, off-centres)", _place_delaunay,
            RUPPERT_MAX_ANGLE, 30.0, True, grades_itself=True,
        ),
        MeshMethod(
            "weatherill", "Weatherill's automatic point generation (chapter 18.1.3)", _place_weatherill,
            RUPPERT_MAX_ANGLE, 0.0, True, ("alpha",),
        ),
        MeshMethod(
            "frontal-delaunay", "frontal Delaunay: advancing-front points, Delaunay insertion (18.3)", _place_frontal,
            RUPPERT_MAX_ANGLE, 0.0, False, relaxes=True, grading=RELAXED_GRADING,
        ),
        MeshMethod(
            "front", "advancing front with stretched background grids (18.2)", _place_front, 0.0, 0.0, True,
            relaxes=True, grading=RELAXED_GRADING,
        ),
    )
}


def _as_domain(domain) -> Domain:
    """The Domain named by ``triangulate``'s first argument (see its docstring)."""
    if isinstance(domain, Domain):
        return domain
    if isinstance(domain, str) and domain in BUILTIN_DOMAINS:
        return builtin(domain)
    if isinstance(domain, (str, os.PathLike)):
        path = Path(domain)
        suffix = path.suffix.lower()
        if not path.is_file() or suffix not in (".json", ".poly"):
            raise InputError(
                f"domain {str(domain)!r} is neither a built-in domain ({', '.join(sorted(BUILTIN_DOMAINS))}) "
                "nor an existing .json or .poly file"
            )
        from meshwright.geometry import load_domain, read_poly

        return load_domain(path) if suffix == ".json" else read_poly(path)
    try:
        arr = np.asarray(domain, dtype=np.float64)
    except (TypeError, ValueError):
        arr = None
    if arr is not None and arr.ndim == 2 and arr.shape[1] == 2:
        return polygon(arr)
    raise InputError(
        "domain must be a meshwright.geometry.Domain, a built-in name, a .json/.poly path or an (n, 2) "
        f"polygon, got {type(domain).__name__}" + ("" if arr is None else f" of shape {arr.shape}")
    )


def _min_angle(m: MeshMethod, min_angle) -> float:
    """``min_angle`` checked against what ``m`` honours (None: the method's default)."""
    if min_angle is None:
        return m.default_min_angle
    if isinstance(min_angle, bool) or not isinstance(min_angle, numbers.Real) or not math.isfinite(min_angle):
        raise InputError(f"min_angle must be a finite number of degrees, got {min_angle!r}")
    a = float(min_angle)
    if a < 0.0:
        raise InputError(f"min_angle must be >= 0 degrees, got {a!r}")
    if a > 0.0 and m.max_min_angle == 0.0:
        raise InputError(
            f"method {m.name!r} cannot honour min_angle={a:g}: it makes its own triangles without an angle "
            "bound; leave min_angle None (or 0), or use a method that refines by angle "
            f"({', '.join(k for k, v in MESH_METHODS.items() if v.max_min_angle > 0)})"
        )
    if a > m.max_min_angle:
        raise InputError(
            f"min_angle={a:g} is above what method {m.name!r} can honour ({m.max_min_angle:g} degrees: "
            "Delaunay refinement may not terminate beyond it)"
        )
    return a


def _check_work(dom: Domain, field: SizeField | None, max_area: float | None, cap: int) -> None:
    """Refuse, before discretising, a size or area bound that needs more than ``cap`` points.

    The estimate is a low one (so nothing feasible is refused): the boundary points
    :meth:`Domain.estimate_boundary_points` places, plus for a uniform size half the
    vertices of equilateral triangles of that side, or for ``max_area`` a quarter of
    area / max_area (triangles of at most that area, about two per vertex, the advancing
    front's closing triangles up to twice it).
    """
    area = abs(dom.area())
    boundary = 0.0 if field is None else dom.estimate_boundary_points(field)
    interior = 0.0
    what = []
    if field is not None:
        what.append(f"size {field.constant:g}" if field.constant is not None else f"size field {field.name}")
        if field.constant is not None and not isinstance(field, BackgroundGrid):
            # Divided twice, not squared: a size near 1e154 must not overflow a float.
            interior = area / math.sqrt(3.0) / field.constant / field.constant
    if max_area is not None:
        what.append(f"max_area {max_area:g}")
        interior = max(interior, area / (4.0 * max_area))
    need = boundary + interior
    if need > cap:
        x0, y0, x1, y1 = dom.bbox
        raise SizeError(
            f"{' and '.join(what)} would need about {need:.3g} points ({boundary:.3g} on the boundary) "
            f"on a domain of extent {x1 - x0:.3g} x {y1 - y0:.3g} (boundary length {dom.boundary_length():.3g}, "
            f"area {area:.3g}), above max_points = {cap}; coarsen it or raise max_points"
        )


def _regions(disc: Discretization) -> list[tuple]:
    """Region seeds for ``classify``, region i marked i + 1 so that every triangle names
    its region (see :func:`meshwright.tri._postprocess.region_data`)."""
    out = []
    for i, (x, y, _, area) in enumerate(disc.regions):
        out.append((x, y, i + 1) if area <= 0 else (x, y, i + 1, float(area)))
    return out


def _domain_and_field(
    domain, size, convex_hull: bool, max_area: float | None = None, grades_itself: bool = False, check=None,
    growth: float | None = DEFAULT_GROWTH,
) -> tuple[Domain, SizeField | None]:
    """The domain argument as a :class:`Domain` and the size field to mesh it with: ``size``
    when given; for None the domain's own, else :func:`_default_size` (``max_area``,
    ``grades_itself`` and ``growth`` passed on); for ``"boundary"`` the domain's own or None
    (the boundary's spacing alone).  ``check(domain)``, if given, runs on the domain before
    any default size is built.  Raises as :func:`_as_domain`,
    :func:`~meshwright.sizing.field.as_size_field`, :func:`_check_open` and ``check``, and
    :class:`InputError` for ``growth=None`` (no grading) with the default size, which is
    graded by construction.
    """
    if isinstance(size, str):
        if size != BOUNDARY_SIZE:
            raise SizeError(f"size {size!r} is no named size; the only one is {BOUNDARY_SIZE!r}")
        field = None
    else:
        field = None if size is None else as_size_field(size)
    dom = _as_domain(domain)
    _check_open(dom, convex_hull)
    if check is not None:
        check(dom)
    if field is None:
        field = dom.size
    if field is None and size is None:
        if growth is None:
            raise InputError(
                "grading=None meshes a given size exactly as given, but no size was given: the default size "
                f"(the local feature size) is graded by construction; give a size, or a grading factor >= 1 "
                f"(default {DEFAULT_GRADING:g})"
            )
        field = _default_size(dom, max_area, grades_itself, growth)
    return dom, field


def _default_size(dom: Domain, max_area: float | None, grades_itself: bool, growth: float = DEFAULT_GROWTH
                  ) -> SizeField | None:
    """The size used when neither the caller nor the domain gives one (issue 14): the local
    feature size of the domain's own discretisation (polygon vertices as given,
    :func:`~meshwright.sizing.lfs.lfs_field`), with curved pieces sized by their turning
    (:data:`TURN_PER_ELEMENT` radians per element along their fine polylines) and area
    bounds graded in (:func:`_area_sources`), all graded by ``growth``.  For a method that
    ``grades_itself`` only the curves' turning, graded as the rest (None for a polygon): its
    refinement sees the polygon, not the curves it stands for."""
    xy, h = [], []
    for c in dom.curves:
        if not isinstance(c, (Line, Polyline)):
            p = c.evaluate(c.fine_params())
            if len(p) >= 3:
                xy.append(p[1:-1])
                h.append(turning_size(p, TURN_PER_ELEMENT))
    if grades_itself:
        if not xy:
            return None
        xy, h = np.concatenate(xy), np.concatenate(h)
        x0, y0, x1, y1 = dom.bbox
        hmax = DEFAULT_CAP * max(x1 - x0, y1 - y0)
        return gradation(xy, np.minimum(h, hmax), growth, hmax)
    disc = dom.discretize(None)
    area = _area_sources(dom, disc, max_area)
    if area is not None:
        xy.append(area[0])
        h.append(area[1])
    extra = None
    if xy:
        xy, h = np.concatenate(xy), np.concatenate(h)
        extra = (xy[np.isfinite(h)], h[np.isfinite(h)])
    return lfs_field(disc.points, disc.segments, growth=growth, extra=extra)


def _grading(grading) -> float | str | None:
    """``grading`` checked: None, ``"auto"``, or a finite growth factor >= 1 (as a float)."""
    if grading is None or (isinstance(grading, str) and grading == GRADING_AUTO):
        return grading
    if isinstance(grading, bool) or not isinstance(grading, numbers.Real) or not math.isfinite(grading):
        raise InputError(f"grading must be None, {GRADING_AUTO!r} or a finite growth factor >= 1, got {grading!r}")
    if grading < 1.0:
        raise InputError(
            f"grading must be a growth factor >= 1 (the size grows by at most grading - 1 per unit length "
            f"away from the boundary), got {grading!r}"
        )
    return float(grading)


def _auto_grading(m: MeshMethod, relax: bool | None, dom: Domain) -> float | None:
    """``grading="auto"``: None for a method that grades itself; the registry entry's
    ``grading`` where the method's mesh is relaxed (``relax`` from :func:`relax_flag` not
    False and no region with an area bound: the default without bounds); else
    :data:`DEFAULT_GRADING`, since where a bound sets the spacing the mesh stays as the
    bound made it (on la.poly's regional bounds, ``size="boundary"``, the front's closing
    triangles reach 2.15x their bound at g = 1.1 against 1.98x at 1.2)."""
    if m.grades_itself:
        return None
    if relax is False or any(r[3] is not None and r[3] > 0 for r in dom.regions):
        return DEFAULT_GRADING
    return m.grading


def _area_sources(dom: Domain, disc: Discretization, max_area: float | None):
    """Sources of the default size where an area bound (``max_area``, a region's) applies:
    points spread over every bounded triangle of the boundary's constrained triangulation,
    at most the side of the equilateral triangle of the bound apart, with that side as
    their size, so that the size the methods follow already grades into each bound
    instead of meeting it as a jump.  None without any bound."""
    if max_area is None and not (disc.regions[:, 3] > 0).any():
        return None
    ct = _classified_cdt(dom, disc, 0)
    bound = np.concatenate([[np.inf], np.where(disc.regions[:, 3] > 0, disc.regions[:, 3], np.inf)])
    bound = bound[ct.triangle_markers(True)]
    if max_area is not None:
        bound = np.minimum(bound, max_area)
    tris = ct.points[ct.triangles(True)[np.isfinite(bound)]]
    side = np.sqrt(4.0 / math.sqrt(3.0) * bound[np.isfinite(bound)])
    longest = np.hypot(*(tris - np.roll(tris, 1, axis=1)).transpose(2, 0, 1)).max(axis=1)
    # A bound far below the domain's size is refused later (_check_work): until then the
    # lattices stay within _AREA_SOURCES points.
    spread = max(1.0, math.sqrt(float(np.sum((longest / side + 1.0) ** 2)) / _AREA_SOURCES))
    counts = np.maximum(1, np.ceil(longest / (spread * side))).astype(np.int64)
    xy, h = [], []
    for k in np.unique(counts).tolist():
        i, j = np.triu_indices(k + 1)
        w = np.column_stack([k - j, j - i, i]) / k  # barycentric lattice, corners included
        xy.append(np.einsum("lc,tcd->tld", w, tris[counts == k]).reshape(-1, 2))
        h.append(np.repeat(side[counts == k], len(w)))
    return np.concatenate(xy), np.concatenate(h)


def _classified_cdt(dom: Domain, disc: Discretization, seed) -> ConstrainedTriangulation:
    """The constrained triangulation of ``disc`` with exterior, holes and regions flagged."""
    ct = cdt_build(disc.points, disc.segments, seed=seed, curves=SegmentCurves.from_domain(dom, disc))
    sides = np.where(dom.curve_loop[disc.segment_curve] >= 0, 1, 0)
    ct.classify(segment_sides=sides, holes=disc.holes, regions=_regions(disc))
    return ct


def _check_open(dom: Domain, convex_hull: bool) -> None:
    """Refuse an open boundary without ``convex_hull``, and ``convex_hull`` on a non-convex loop.

    A domain whose segments close no boundary (``Domain.open_boundary``) carries the convex
    hull of its vertices as its outer loop; meshing it is what Triangle's ``-c`` does, so it
    is done only when asked for.
    """
    if dom.open_boundary and not convex_hull:
        raise GeometryError(
            "the boundary is open: the segments enclose no region (Triangle returns no triangles here); "
            "pass convex_hull=True (CLI --convex-hull) to mesh the convex hull of the input, as Triangle's -c"
        )
    if convex_hull and not dom.open_boundary and not dom.outer_is_convex():
        raise InputError(
            "convex_hull=True meshes the convex hull of an open set of segments; this domain's outer loop is "
            "given and not convex, so its hull would change the domain: call it with convex_hull=False"
        )

def triangulate(
    domain,
    size=None,
    *,
    min_angle: float | None = None,
    method: str = "delaunay",
    smooth: int = 0,
    max_area: float | None = None,
    seed: int = 0,
    progress: bool = False,
    conforming: bool = False,
    max_points: int | None = None,
    alpha: float | None = None,
    convex_hull: bool = False,
    grading: float | str | None = GRADING_AUTO,
    relax: bool | None = None,
) -> Mesh:
    """Boundary-conforming quality triangle mesh of a 2-D domain.

    Every argument is checked here, before any work, against what the chosen method
    honours (its :class:`MeshMethod` entry); a parameter the method cannot honour is an
    error, never silently dropped.

    Parameters
    ----------
    domain : Domain, str, path or (n, 2) array_like
        What to mesh: a domain, the name of a built-in one
        (:data:`meshwright.geometry.BUILTIN_DOMAINS`), the path of a JSON geometry
        (:mod:`meshwright.geometry.spec`) or Triangle ``.poly`` file, or the vertex loop of
        a polygon.  Curved boundaries stay curves: every boundary point lies on the true
        curve.  Coordinates must lie in the exact predicates' range
        (:mod:`meshwright.core.validate_input`).
    size : number, callable, SizeField or "boundary", optional
        Target edge length ``h(x)`` (boundary spacing and interior size).  Default: the
        domain's own size, or else the local feature size of the domain, graded and
        capped (module docstring; ``"delaunay"`` refines by its own grading instead).
        ``"boundary"``: the chapter's mode, the boundary as the domain discretises it by
        itself (polygon vertices as given) with sizes grown from its spacing.
    min_angle : float, optional
        Smallest angle in degrees, at most the method's ``max_min_angle``
        (:data:`RUPPERT_MAX_ANGLE` = 33.8; angles next to smaller input angles are left
        alone).  ``"delaunay"`` refines to it natively (default 30); ``"weatherill"`` and
        ``"frontal-delaunay"`` honour it by a final Delaunay refinement pass on their
        points (default None: no angle bound, their own point placement only);
        ``"front"`` cannot honour it (only None or 0).  0 means no angle bound.
    method : str
        A key of :data:`MESH_METHODS`.
    smooth : int
        Spring-analogy smoothing passes afterwards (chapter 18.2); 0 for none.
    max_area : float, optional
        Largest triangle area, positive and finite (region seeds may lower it locally).
        ``method="front"`` honours it through the spacing (``MAX_AREA_SIDE`` times the
        side of the equilateral triangle of that area, boundary segments split to it), so
        a few closing triangles may exceed it (by less than twice); the Delaunay methods
        refine until it holds exactly.
    seed : int or numpy.random.Generator
        Randomness of the insertion order (results are reproducible for a seed); a
        non-negative int.
    progress : bool
        Show a progress bar for long runs; only for methods whose ``reports_progress`` is
        set (``"frontal-delaunay"`` reports none, so True is refused there).
    conforming : bool
        Also split segments until every triangle is Delaunay (not only constrained
        Delaunay), like Triangle's ``-D``.  With ``method="front"`` the front's points
        are then connected by the Delaunay kernel instead of by the front.
    max_points : int, optional
        Cap on the mesh's vertices, passed to every method (default
        :data:`DEFAULT_MAX_POINTS`).  A size or ``max_area`` whose estimated point count
        exceeds it is refused at once with a :class:`SizeError`; a method that reaches it
        raises :class:`MeshingError` naming it.
    alpha : float, optional
        Weatherill's density coefficient (``method="weatherill"`` only; default
        :data:`meshwright.tri.weatherill.DEFAULT_ALPHA` = 0.6): a candidate closer than
        ``alpha dP`` to a node is rejected, so smaller values give more points.
    convex_hull : bool
        Mesh the convex hull of the input (Triangle's ``-c``): needed for a domain whose
        segments close no boundary (``Domain.open_boundary``, e.g. a ``.poly`` file with a
        lone segment on its outer box), whose outer loop is that hull; its segments,
        holes and points are kept.  For a domain with a given outer loop it is accepted
        only when that loop is convex (its own hull).
    grading : float, None or "auto"
        Growth factor ``g >= 1`` of the size away from the boundary.  ``"auto"`` (the
        default): :data:`DEFAULT_GRADING` = 1.2, or the method's registry entry's
        ``grading`` where its mesh is relaxed (:data:`RELAXED_GRADING` = 1.1 for
        ``"front"`` and ``"frontal-delaunay"`` without ``relax=False`` or a bound:
        gentler, for their mean shape), except for a method whose
        registry entry ``grades_itself`` (``"delaunay"``), which follows a given size as
        given since its refinement grades from the boundary by itself (the default size's
        growth stays 1.2 for every method).  Where the boundary is finer than ``size``, the
        size grows from the boundary spacing by at most ``g - 1`` per unit length up to
        ``size`` (module docstring), as Gmsh's ``Mesh.MeshSizeExtendFromBoundary``; it
        also caps the chapter's background of ``size="boundary"``, and without a size it
        is the default size's growth.  None: a given size is followed exactly as given
        (Gmsh's ``MeshSizeExtendFromBoundary = 0``); refused without a size.  A stretched
        background grid is followed as drawn.
    relax : bool, optional
        Mesh relaxation afterwards (:mod:`meshwright.tri.relax`: valence-driven diagonal
        swaps and guarded smoothing of the nodes off the lines; Field and Frey 1991).
        None (the default): on for the methods whose registry entry ``relaxes``
        (``"frontal-delaunay"``, ``"front"``) when no ``min_angle``, area bound, ``conforming`` or
        stretched background is asked for, whose guarantees a swap could break (the mesh
        is then no longer Delaunay); True where that holds, refused where it does not.

    Returns
    -------
    Mesh
        ``"triangle"`` cells (counter-clockwise, region markers in
        ``cell_data["marker"]["triangle"]``, and when some region's attribute is not its
        marker the attributes in ``cell_data["region_attribute"]["triangle"]``, 0 outside
        every region and on the lines),
        ``"line"`` cells on the boundary and interior segments with their segment markers,
        ``point_data["marker"]``.

    Raises
    ------
    GeometryError
        Invalid geometry (named loops, segments, coordinates), or an open boundary
        without ``convex_hull=True``.
    InputError
        Not a domain (its type named), unknown method, a parameter of the wrong type or
        range, or one the method cannot honour (named); ``grading=None`` without a size.
    SizeError
        ``size`` or ``max_area`` zero, negative, NaN or infinite, a string other than
        ``"boundary"``, or needing more than ``max_points`` points (the estimate and the
        cap named).
    FormatError
        A domain file that cannot be read (the file named).
    MeshingError
        A cap on points or steps was hit.
    """
    if not isinstance(method, str) or method not in MESH_METHODS:
        raise InputError(f"unknown method {method!r}; choose one of {', '.join(sorted(MESH_METHODS))}")
    m = MESH_METHODS[method]
    passes = check_count(smooth, "smooth (passes)")
    angle = _min_angle(m, min_angle)
    if max_area is not None:
        max_area = check_positive(max_area, "max_area")
    cap = DEFAULT_MAX_POINTS if max_points is None else check_count(max_points, "max_points", 3)
    if alpha is not None and "alpha" not in m.options:
        raise InputError(f"alpha is an option of method 'weatherill' only; method {method!r} has no use for it")
    alpha = DEFAULT_ALPHA if alpha is None else check_positive(alpha, "alpha", InputError)
    progress = check_flag(progress, "progress")
    conforming = check_flag(conforming, "conforming")
    convex_hull = check_flag(convex_hull, "convex_hull")
    if progress and not m.reports_progress:
        raise InputError(f"method {method!r} reports no progress; call it with progress=False")
    if convex_hull and not m.convex_hull:
        raise InputError(f"method {method!r} cannot mesh the convex hull; call it with convex_hull=False")
    seed = check_seed(seed)
    relax = relax_flag(relax, m, angle, max_area, conforming)
    grading = _grading(grading)
    growth = DEFAULT_GRADING if grading == GRADING_AUTO else grading
    dom, field = _domain_and_field(domain, size, convex_hull, max_area, m.grades_itself, growth=growth)
    if grading == GRADING_AUTO:
        grading = _auto_grading(m, relax, dom)
    _check_work(dom, field, max_area, cap)
    disc = dom.discretize(field)
    given = not (size is None and dom.size is None)
    graded = graded_from_boundary(field, disc.points, disc.segments, grading) if given else field
    if graded is not field:
        # The boundary too: straight pieces next to finer given vertices (a slit's mouth, a
        # hole near the outer wall) are split at the graded size, not at the size.
        field, disc = graded, dom.discretize(graded)
    relax = relax_domain(relax, is_stretched(field), disc)
    ct = _classified_cdt(dom, disc, seed)
    fill = m.place(_Job(ct, disc, field, angle, max_area, bool(progress), cap, alpha, grading))
    if fill is not None and conforming:
        # A Delaunay mesh was asked for: the method's points, connected by the kernel.
        ct.insert_points(fill[0][ct.n_points :])
        fill = None
    if conforming:
        conform(ct)
    mesh = region_data(ct.to_mesh(segment_markers=disc.segment_markers, fill=fill), dom, disc)
    if relax:
        mesh = relax_mesh(mesh, input_nodes(mesh, ct, dom, disc))
    if passes:
        mesh = smooth_mesh(mesh, ct, dom, disc, passes)
    return mesh
