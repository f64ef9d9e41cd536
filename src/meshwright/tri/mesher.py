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

Without a size, ``frontal-delaunay`` and ``front`` take the chapter's background: the
triangulated boundary nodes with their point distribution function (18.3).

Smoothing keeps boundary nodes on their true curves: each boundary node slides along the
curve of its segments (projected with :meth:`Domain.project`); nodes where two curves meet
and the domain's interior points never move.
"""

from __future__ import annotations

from typing import Callable, NamedTuple

import numpy as np

from meshwright.core.errors import InputError
from meshwright.core.mesh import Mesh
from meshwright.core.predicates import orient2d_batch
from meshwright.geometry.curves import Line, Polyline
from meshwright.geometry.domain import Discretization, Domain
from meshwright.geometry.shapes import builtin, polygon
from meshwright.sizing.background import BackgroundGrid
from meshwright.sizing.boundary import point_distribution
from meshwright.sizing.field import SizeField, as_size_field
from meshwright.tri.cdt import ConstrainedTriangulation, SegmentCurves, cdt_build
from meshwright.tri.front import advancing_front
from meshwright.tri.frontal_delaunay import frontal_delaunay
from meshwright.tri.ruppert import conform, refine
from meshwright.tri.smoothing import smooth as smooth_points
from meshwright.tri.weatherill import DEFAULT_ALPHA, weatherill

__all__ = ["MESH_METHODS", "MeshMethod", "triangulate"]


class _Job(NamedTuple):
    """What a point-placement method gets: the classified CDT and the request."""

    ct: ConstrainedTriangulation
    disc: Discretization
    field: SizeField | None
    min_angle: float
    max_area: float | None
    progress: bool


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
    """

    name: str
    summary: str
    place: Callable[[_Job], tuple | None]


def _place_delaunay(job: _Job) -> None:
    if not job.progress:
        refine(job.ct, min_angle=job.min_angle, size=job.field, max_area=job.max_area)
        return
    from tqdm import tqdm

    with tqdm(desc="Delaunay refinement", unit=" vertices", leave=False) as bar:

        def report(n: int) -> None:
            bar.update(n - bar.n)

        refine(job.ct, min_angle=job.min_angle, size=job.field, max_area=job.max_area, progress=report)


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
            DEFAULT_ALPHA,
            size=job.field,
            callback=None if bar is None else (lambda p, acc, n: bar.update(1)),
        )
    finally:
        if bar is not None:
            bar.close()
    if job.max_area is not None:
        # A hard area bound still holds: refine by area only (no angle criterion).
        refine(ct, min_angle=0.0, max_area=job.max_area)


def _background(job: _Job):
    """The size field, or chapter 18.3's background: the triangulated boundary nodes with
    their point distribution function, interpolated linearly."""
    if job.field is not None:
        return job.field
    ct = job.ct
    return BackgroundGrid.from_boundary(ct.points, ct.index_map[job.disc.segments], ct.triangles(False))


def _place_frontal(job: _Job) -> None:
    frontal_delaunay(job.ct, _background(job))
    if job.max_area is not None:
        refine(job.ct, min_angle=0.0, max_area=job.max_area)


def _place_front(job: _Job) -> tuple:
    field = _background(job)
    bar = None
    if job.progress:
        from tqdm import tqdm

        bar = tqdm(desc="advancing front", unit=" nodes", leave=False)
    try:
        return advancing_front(
            job.ct, field, max_area=job.max_area, progress=None if bar is None else (lambda n: bar.update(n - bar.n))
        )
    finally:
        if bar is not None:
            bar.close()


MESH_METHODS: dict[str, MeshMethod] = {
    m.name: m
    for m in (
        MeshMethod("delaunay", "guaranteed-quality Delaunay refinement (Ruppert, off-centres)", _place_delaunay),
        MeshMethod("weatherill", "Weatherill's automatic point generation (chapter 18.1.3)", _place_weatherill),
        MeshMethod("frontal-delaunay", "frontal Delaunay: advancing-front points, Delaunay insertion (18.3)", _place_frontal),
        MeshMethod("front", "advancing front with stretched background grids (18.2)", _place_front),
    )
}


def _as_domain(domain) -> Domain:
    if isinstance(domain, Domain):
        return domain
    if isinstance(domain, str):
        return builtin(domain)
    arr = np.asarray(domain, dtype=np.float64)
    if arr.ndim == 2 and arr.shape[1] == 2:
        return polygon(arr)
    raise InputError(
        f"domain must be a meshwright.geometry.Domain, a built-in name or an (n, 2) polygon, got {type(domain).__name__}"
    )


def _regions(disc: Discretization) -> list[tuple]:
    out = []
    for x, y, marker, area in disc.regions:
        out.append((x, y, int(marker)) if area <= 0 else (x, y, int(marker), float(area)))
    return out


def _polyline_corners(points: np.ndarray, edges: np.ndarray, curve: np.ndarray, domain: Domain) -> np.ndarray:
    """(n,) bool: nodes where a straight curve (a Polyline's vertex) turns; exact test."""
    straight = np.array([isinstance(c, (Line, Polyline)) for c in domain.curves], dtype=bool)
    e = edges[straight[curve]]
    nxt = np.full(len(points), -1)
    prv = np.full(len(points), -1)
    nxt[e[:, 0]] = e[:, 1]
    prv[e[:, 1]] = e[:, 0]
    out = np.zeros(len(points), dtype=bool)
    mid = np.flatnonzero((nxt >= 0) & (prv >= 0))
    out[mid] = orient2d_batch(points, np.column_stack([prv[mid], mid, nxt[mid]])) != 0.0
    return out


def _smooth_mesh(mesh: Mesh, ct: ConstrainedTriangulation, domain: Domain, disc: Discretization, passes: int) -> Mesh:
    """Spring-analogy smoothing of ``mesh`` (made by ``ct.to_mesh``) with sliding boundary nodes."""
    tris_ct = ct.triangles(True)
    used = np.zeros(ct.n_points, dtype=bool)
    used[tris_ct.ravel()] = True
    newid = np.cumsum(used) - 1  # the renumbering of ConstrainedTriangulation.to_mesh
    edges, ids = ct.segments()
    keep = used[edges[:, 0]] & used[edges[:, 1]]
    edges, curve = newid[edges[keep]], disc.segment_curve[ids[keep]]
    n = mesh.n_points
    lo = np.full(n, np.iinfo(np.int64).max)
    hi = np.full(n, -1)
    np.minimum.at(lo, edges.ravel(), np.repeat(curve, 2))
    np.maximum.at(hi, edges.ravel(), np.repeat(curve, 2))
    fixed = (hi >= 0) & (lo != hi)  # where two curves meet: a corner of the true boundary
    fixed |= _polyline_corners(mesh.points, edges, curve, domain)
    npts = len(domain.points)
    if npts:
        inner = ct.index_map[len(disc.points) - npts :]
        fixed[newid[inner[used[inner]]]] = True
    vcurve = np.where(hi >= 0, hi, 0)

    def project(nodes, xy):
        return domain.project(vcurve[nodes], xy)[1]

    xy = smooth_points(mesh.points, mesh.cells["triangle"], edges, passes=passes, fixed=fixed, project=project)
    return Mesh(xy, mesh.cells, point_data=mesh.point_data, cell_data=mesh.cell_data)


def triangulate(
    domain,
    size=None,
    *,
    min_angle: float = 30.0,
    method: str = "delaunay",
    smooth: int = 0,
    max_area: float | None = None,
    seed: int = 0,
    progress: bool = False,
    conforming: bool = False,
) -> Mesh:
    """Boundary-conforming quality triangle mesh of a 2-D domain.

    Parameters
    ----------
    domain : Domain, str or (n, 2) array_like
        What to mesh: a domain, the name of a built-in one
        (:data:`meshwright.geometry.BUILTIN_DOMAINS`), or the vertex loop of a polygon.  Curved boundaries stay
        curves: every boundary point lies on the true curve.
    size : number, callable or SizeField, optional
        Target edge length ``h(x)`` (boundary spacing and interior size); default: the
        domain's own size, or else the boundary as given with sizes grown from it.
    min_angle : float
        Smallest angle in degrees for ``method="delaunay"`` (up to ~33; angles next to
        smaller input angles are left alone).  0 refines by size only.
    method : str
        A key of :data:`MESH_METHODS`.
    smooth : int
        Spring-analogy smoothing passes afterwards (chapter 18.2); 0 for none.
    max_area : float, optional
        Largest triangle area (region seeds may lower it locally).  ``method="front"``
        honours it through the spacing (``MAX_AREA_SIDE`` times the side of the
        equilateral triangle of that area, boundary segments split to it), so a few
        closing triangles may exceed it (by less than twice); the Delaunay methods refine
        until it holds exactly.
    seed : int
        Randomness of the insertion order (results are reproducible for a seed).
    progress : bool
        Show a progress bar for long runs.
    conforming : bool
        Also split segments until every triangle is Delaunay (not only constrained
        Delaunay), like Triangle's ``-D``.  With ``method="front"`` the front's points
        are then connected by the Delaunay kernel instead of by the front.

    Returns
    -------
    Mesh
        ``"triangle"`` cells (counter-clockwise, region markers in
        ``cell_data["marker"]["triangle"]``), ``"line"`` cells on the boundary and interior
        segments with their segment markers, ``point_data["marker"]``.

    Raises
    ------
    GeometryError
        Invalid geometry (named loops, segments, coordinates).
    InputError
        Unknown method, bad parameters.
    MeshingError
        A cap on points or steps was hit.
    """
    if method not in MESH_METHODS:
        raise InputError(f"unknown method {method!r}; choose one of {', '.join(sorted(MESH_METHODS))}")
    if int(smooth) < 0:
        raise InputError(f"smooth must be a non-negative number of passes, got {smooth!r}")
    dom = _as_domain(domain)
    field = None
    if size is not None:
        field = as_size_field(size)
    elif dom.size is not None:
        field = dom.size
    disc = dom.discretize(field)
    curves = SegmentCurves.from_domain(dom, disc)
    ct = cdt_build(disc.points, disc.segments, seed=seed, curves=curves)
    sides = np.where(dom.curve_loop[disc.segment_curve] >= 0, 1, 0)
    ct.classify(segment_sides=sides, holes=disc.holes, regions=_regions(disc))
    fill = MESH_METHODS[method].place(_Job(ct, disc, field, float(min_angle), max_area, bool(progress)))
    if fill is not None and conforming:
        # A Delaunay mesh was asked for: the method's points, connected by the kernel.
        ct.insert_points(fill[0][ct.n_points :])
        fill = None
    if conforming:
        conform(ct)
    mesh = ct.to_mesh(segment_markers=disc.segment_markers, fill=fill)
    if smooth:
        mesh = _smooth_mesh(mesh, ct, dom, disc, int(smooth))
    return mesh
