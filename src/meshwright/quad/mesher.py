"""``quadrangulate``: one entry point from a domain to a boundary-conforming quad mesh.

Section 18.5 of the reference text builds quadrilaterals three ways; each is a method of
:data:`QUAD_METHODS` (the CLI's ``meshwright quad --method`` choices), one module per
method:

* ``quadtree``: Yerry and Shephard's modified quadtree (1984, 18.5.3),
  :mod:`meshwright.quad.quadtree`;
* ``pairing``: advancing-front triangles paired into quads (Zhu et al. 1991, 18.5.1),
  :mod:`meshwright.quad.pairing`;
* ``zhu``: the same with the chapter's own front, which makes the two triangles of every
  quad together and keeps every sub-front even (:mod:`meshwright.quad.zhu`);
* ``paving``: rows of quads laid inward from the boundaries (Blacker and Stephenson
  1991, 18.5.2), :mod:`meshwright.quad.paving`.

Pipeline::

    Domain, size --door (every argument checked against the method's QuadMethod)-->
        method(job) -> QuadFill --all-quad finish (below)--> optional smoothing --> Mesh

Method contract
---------------
A method is a :class:`QuadMethod` entry whose ``build`` is ``build(job: QuadJob) ->
QuadFill``.  The job carries the checked request: ``domain`` (a validated
:class:`~meshwright.geometry.Domain`), ``field`` (a :class:`~meshwright.sizing.SizeField`,
or None only with ``size="boundary"`` on a domain carrying no size: only methods
declaring ``needs_size=False`` see None), ``all_quad``, ``smooth`` (the passes the mesher
will run on the finished mesh, for information; 0 unless the method declares ``smooths``),
``max_points`` (cap on vertices of the returned fill), ``seed`` (an
int or a ``numpy.random.Generator``, from :func:`meshwright.core.validate_input.check_seed`)
and ``progress`` (True only for methods declaring ``reports_progress``).  The fill is:

==============  =============  ==========================================================
field           array          meaning
==============  =============  ==========================================================
points          (n, 2) f8      every vertex, C-contiguous
quads           (m, 4) i4      counter-clockwise, strictly convex unless the method says
triangles       (t, 3) i4      counter-clockwise leftovers, ``(0, 3)`` when none
lines           (k, 2) i4      boundary and interior-segment edges, domain on the left
                               of boundary edges
line_markers    (k,) i4        the segment markers (as ``triangulate`` gives)
line_curves     (k,) i4        index into ``domain.curves`` of the curve each line
                               discretises (every boundary vertex lies on its curve)
==============  =============  ==========================================================

A method that cannot finish raises a :class:`~meshwright.core.errors.MeshingError`
naming the cap or the stuck front; it never returns a broken fill.  The mesher checks
every finished cell by the exact ``orient2d`` before returning (triangles strictly
counter-clockwise, quads simple and counter-clockwise:
:func:`meshwright.core.validate_quad.simple_ccw_quads`) and raises a ``MeshingError``
naming the method and the first bad cell otherwise.

All-quad guarantee
------------------
With ``all_quad=True`` a fill that still has triangles is finished by one midpoint split
of every element (:func:`meshwright.quad.subdivide.split_all`): a triangle becomes three
quads and a quad four, edge midpoints shared so the mesh stays conforming, boundary
midpoints placed on their true curves.  The split halves the spacing, so a method that
knows it will leave triangles builds at twice the size when ``job.all_quad`` is set
(the quadtree does).  ``all_quad=False`` returns the fill as it is: quad-dominant, with
its triangles in a ``"triangle"`` block (``len(mesh.triangles)`` says how many).

Smoothing
---------
``smooth=N`` (methods declaring ``smooths``) runs N sweeps of the shared guarded
Laplacian (:func:`meshwright.quad.smoothing.smooth_cells`) on the finished mesh: boundary
and segment vertices stay on their curves, and no move lowers the smallest corner sine
around a vertex, so the mesh stays valid and its minimum scaled Jacobian never falls.
"""

from __future__ import annotations

from typing import Callable, NamedTuple

import numpy as np

from meshwright.core.errors import InputError, MeshingError
from meshwright.core.mesh import Mesh
from meshwright.core.validate_input import check_count, check_flag, check_seed
from meshwright.geometry.domain import Domain
from meshwright.sizing.field import SizeField
from meshwright.tri.mesher import DEFAULT_MAX_POINTS, _check_work, _domain_and_field

__all__ = ["QUAD_METHODS", "QuadMethod", "QuadJob", "QuadFill", "quadrangulate"]


class QuadJob(NamedTuple):
    """The checked request a method's ``build`` gets (see the module docstring)."""

    domain: Domain
    field: SizeField | None
    all_quad: bool
    smooth: int
    max_points: int
    seed: object
    progress: bool


class QuadFill(NamedTuple):
    """What a method returns (array layout in the module docstring)."""

    points: np.ndarray
    quads: np.ndarray
    triangles: np.ndarray
    lines: np.ndarray
    line_markers: np.ndarray
    line_curves: np.ndarray


class QuadMethod(NamedTuple):
    """A quad method of :func:`quadrangulate`.

    Attributes
    ----------
    name : str
    summary : str
        One line for ``--help``.
    build : callable
        ``build(job: QuadJob) -> QuadFill``.
    needs_size : bool
        The method needs a size field (from the caller, the domain or the default).
    smooths : bool
        The method honours ``smooth > 0``: the mesher runs the shared smoother on its
        finished mesh (module docstring).
    reports_progress : bool
        Whether ``progress=True`` shows a bar for this method.
    segments : bool
        The method honours the domain's interior segments (constraints).
    points : bool
        The method honours the domain's interior points.
    regions : bool
        The method honours the domain's region seeds: the mesher gives every cell the
        marker of its region (:func:`meshwright.quad.regions.region_markers`, a flood
        fill stopped by the line cells, so the method must honour ``segments``).  Area
        bounds of regions are refused for every method.
    """

    name: str
    summary: str
    build: Callable[[QuadJob], QuadFill]
    needs_size: bool
    smooths: bool
    reports_progress: bool
    segments: bool
    points: bool
    regions: bool


def _quadtree(job: QuadJob) -> QuadFill:
    from meshwright.quad.quadtree import quadtree_fill

    return quadtree_fill(job)


def _pairing(job: QuadJob) -> QuadFill:
    from meshwright.quad.pairing import pairing_fill

    return pairing_fill(job)


def _zhu(job: QuadJob) -> QuadFill:
    from meshwright.quad.pairing import pairing_fill

    return pairing_fill(job, front="pairs")


def _paving(job: QuadJob) -> QuadFill:
    from meshwright.quad.paving import paving_fill

    return paving_fill(job)


QUAD_METHODS: dict[str, QuadMethod] = {
    m.name: m
    for m in (
        QuadMethod(
            "quadtree", "modified quadtree with a boundary layer of split triangles (Yerry-Shephard, 18.5.3)",
            _quadtree, needs_size=False, smooths=True, reports_progress=False, segments=True, points=True,
            regions=True,
        ),
        QuadMethod(
            "pairing", "advancing-front triangles paired into quads, then shape enhancement (Zhu et al., 18.5.1)",
            _pairing, needs_size=False, smooths=True, reports_progress=False, segments=True, points=True,
            regions=True,
        ),
        QuadMethod(
            "zhu", "pairs made two triangles at a time by the advancing front, every sub-front even, then shape "
            "enhancement (Zhu et al., 18.5.1 steps 1-9)",
            _zhu, needs_size=False, smooths=True, reports_progress=False, segments=True, points=True,
            regions=True,
        ),
        QuadMethod(
            "paving", "rows of quads paved inward from the boundaries, voids paired (Blacker-Stephenson, 18.5.2)",
            _paving, needs_size=True, smooths=True, reports_progress=False, segments=True, points=True,
            regions=True,
        ),
    )
}


def _check_domain(m: QuadMethod, dom: Domain) -> None:
    """Refuse domain features the method cannot honour (named)."""
    if dom.constraints and not m.segments:
        raise InputError(f"method {m.name!r} does not honour interior segments; the domain has {len(dom.constraints)}")
    if len(dom.points) and not m.points:
        p = dom.points[0]
        raise InputError(
            f"method {m.name!r} does not honour interior points; the domain has {len(dom.points)} "
            f"(the first at ({p[0]:.17g}, {p[1]:.17g}))"
        )
    if dom.regions and not m.regions:
        r = dom.regions[0]
        raise InputError(
            f"method {m.name!r} does not honour region seeds; the domain has {len(dom.regions)} "
            f"(the first at ({r[0]:.17g}, {r[1]:.17g}), marker {r[2]})"
        )
    for i, r in enumerate(dom.regions):
        if len(r) > 3 and r[3] is not None:
            raise InputError(
                f"region {i} at ({r[0]:.17g}, {r[1]:.17g}) has max_area {r[3]!r}: quadrangulate honours "
                "region markers, not area bounds; give a size field instead"
            )


def _check_cells(method: str, points: np.ndarray, quads: np.ndarray, triangles: np.ndarray) -> None:
    """The door out: no inverted, flat or self-intersecting cell leaves :func:`quadrangulate`."""
    from meshwright.core.predicates import orient2d_batch
    from meshwright.core.validate_quad import simple_ccw_quads

    bad = np.flatnonzero(~simple_ccw_quads(points, quads))
    what, block = "quad", quads
    if not len(bad) and len(triangles):
        bad = np.flatnonzero(np.asarray(orient2d_batch(points, np.ascontiguousarray(triangles, np.int64))) <= 0)
        what, block = "triangle", triangles
    if len(bad):
        c = int(bad[0])
        where = ", ".join(f"({points[v, 0]:.17g}, {points[v, 1]:.17g})" for v in block[c])
        raise MeshingError(
            f"method {method!r} produced an inverted or self-intersecting {what} {c} at {where} "
            f"({len(bad)} such cells); please report it with the domain and size"
        )


def _close_voids(method: str, points: np.ndarray, quads: np.ndarray, triangles: np.ndarray,
                 lines: np.ndarray) -> np.ndarray:
    """The cover check: every edge that bounds the cells on one side only must be a line cell.

    A method may leave a void inside the domain (paving's closure missed a four-node loop);
    a four-node void that is a strictly convex quad gets that quad (the paving closure
    template for four nodes), any other raises :class:`MeshingError` naming the loop, so no
    mesh with a hole the domain does not have leaves :func:`quadrangulate`.  A line cell that
    is no cell's edge (a boundary or segment piece the cells cut across) raises too.  Returns
    ``quads``, with the closing quads appended.
    """
    from meshwright.core.validate_quad import one_sided_edges, simple_ccw_quads

    n = np.int64(len(points))
    one_sided, orphan = one_sided_edges(len(points), quads, triangles, lines)
    if len(orphan):
        u, v = lines[orphan[0]]
        raise MeshingError(
            f"method {method!r} left the line ({points[u, 0]:.17g}, {points[u, 1]:.17g}) - "
            f"({points[v, 0]:.17g}, {points[v, 1]:.17g}) off every cell ({len(orphan)} such lines); "
            "please report it with the domain and size"
        )
    ln = lines.astype(np.int64)
    line_keys = np.concatenate([ln[:, 0] * n + ln[:, 1], ln[:, 1] * n + ln[:, 0]])
    extra = one_sided[~np.isin(one_sided[:, 0] * n + one_sided[:, 1], line_keys)]
    if not len(extra):
        return quads
    succ = {int(u): int(v) for u, v in extra}
    closing = []
    while succ:
        start, _ = succ.popitem()
        loop = [start]
        v = _
        while v != start and v in succ and len(loop) <= len(extra):
            loop.append(v)
            v = succ.pop(v)
        # The cells run counter-clockwise around themselves, so clockwise around the void.
        quad = np.array(loop[::-1], dtype=quads.dtype).reshape(1, -1)
        if v != start or quad.shape[1] != 4 or not simple_ccw_quads(points, quad)[0]:
            where = ", ".join(f"({points[w, 0]:.17g}, {points[w, 1]:.17g})" for w in loop[:8])
            raise MeshingError(
                f"method {method!r} left a void of {len(loop)} edges inside the domain at {where}; "
                "please report it with the domain and size"
            )
        closing.append(quad)
    return np.concatenate([quads] + closing)


def quadrangulate(
    domain,
    size=None,
    *,
    method: str = "quadtree",
    all_quad: bool = True,
    smooth: int = 0,
    max_points: int | None = None,
    seed: int = 0,
    progress: bool = False,
    convex_hull: bool = False,
) -> Mesh:
    """Boundary-conforming quadrilateral mesh of a 2-D domain.

    Every argument is checked here, before any work, against what the chosen method
    honours (its :class:`QuadMethod` entry); a parameter the method cannot honour is an
    error, never silently dropped.

    Parameters
    ----------
    domain : Domain, str, path or (n, 2) array_like
        As for :func:`meshwright.triangulate`: a domain, a built-in name, a ``.json`` /
        ``.poly`` path or a polygon's vertex loop.
    size : number, callable, SizeField or "boundary", optional
        Target edge length ``h(x)`` of the quads; default: the domain's own size, or else
        its local feature size, graded and capped (as :func:`meshwright.triangulate`).
        ``"boundary"``: the boundary's own spacing, which a method with ``needs_size``
        refuses on a domain carrying no size.
    method : str
        A key of :data:`QUAD_METHODS`.
    all_quad : bool
        Finish by the documented midpoint split if the method leaves triangles (module
        docstring); False returns a quad-dominant mesh with its triangles.
    smooth : int
        Sweeps of the guarded Laplacian smoother on the finished mesh (module docstring);
        only for methods declaring ``smooths`` (0 otherwise).
    max_points : int, optional
        Cap on the mesh's vertices (default
        :data:`meshwright.tri.mesher.DEFAULT_MAX_POINTS`); a size needing more is refused
        at once with a :class:`SizeError`, a method reaching it raises
        :class:`MeshingError`.
    seed : int or numpy.random.Generator
        Randomness of the methods that use any (reproducible for a seed).
    progress : bool
        Show a progress bar; only for methods whose ``reports_progress`` is set.
    convex_hull : bool
        Mesh the convex hull of a domain whose segments close no boundary
        (``Domain.open_boundary``, e.g. Triangle's ``box.poly``), as
        :func:`meshwright.triangulate` does; such a domain is refused without it.

    Returns
    -------
    Mesh
        ``"quad"`` cells (counter-clockwise), ``"triangle"`` cells only with
        ``all_quad=False``, ``"line"`` cells on the boundary and interior segments with
        their segment markers in ``cell_data["marker"]["line"]``; with region seeds in
        the domain, region markers in ``cell_data["marker"]["quad"]`` (and
        ``["triangle"]``), 0 where no seed reaches.

    Raises
    ------
    GeometryError
        Invalid geometry (named loops, segments, coordinates).
    InputError
        Not a domain, unknown method, a parameter of the wrong type or range, or one the
        method cannot honour (interior points, regions, smoothing, progress; named).
    SizeError
        ``size`` zero, negative, NaN or infinite, or needing more than ``max_points``.
    FormatError
        A domain file that cannot be read (the file named).
    MeshingError
        A cap on points or steps was hit, or a cell came out inverted (named).
    """
    if not isinstance(method, str) or method not in QUAD_METHODS:
        raise InputError(f"unknown quad method {method!r}; choose one of {', '.join(sorted(QUAD_METHODS))}")
    m = QUAD_METHODS[method]
    all_quad = check_flag(all_quad, "all_quad")
    progress = check_flag(progress, "progress")
    convex_hull = check_flag(convex_hull, "convex_hull")
    passes = check_count(smooth, "smooth (passes)")
    if passes and not m.smooths:
        raise InputError(f"method {method!r} does not smooth; call it with smooth=0")
    if progress and not m.reports_progress:
        raise InputError(f"method {method!r} reports no progress; call it with progress=False")
    cap = DEFAULT_MAX_POINTS if max_points is None else check_count(max_points, "max_points", 4)
    seed = check_seed(seed)
    dom, field = _domain_and_field(domain, size, convex_hull, check=lambda d: _check_domain(m, d))
    if field is None and m.needs_size:
        raise InputError(f"method {method!r} needs a size: give size=... (the domain carries none)")
    _check_work(dom, field, None, cap)
    fill = m.build(QuadJob(dom, field, all_quad, passes, cap, seed, progress))
    if all_quad and len(fill.triangles):
        from meshwright.quad.subdivide import split_all

        fill = split_all(fill, dom, cap)
    points = fill.points
    if passes:
        from meshwright.quad.smoothing import smooth_cells

        fixed = np.zeros(len(points), dtype=bool)
        fixed[fill.lines.ravel()] = True
        if len(dom.points):
            # The domain's interior points are vertices of methods honouring them: they stay.
            fixed |= (points[:, None, :] == dom.points[None, :, :]).all(axis=2).any(axis=1)
        points = smooth_cells(points, fill.quads, fill.triangles, fixed, passes)
    quads = _close_voids(m.name, points, fill.quads, fill.triangles, fill.lines)
    _check_cells(m.name, points, quads, fill.triangles)
    cells = {"quad": quads}
    if len(fill.triangles):
        cells["triangle"] = fill.triangles
    cells["line"] = fill.lines
    markers = {"line": fill.line_markers}
    if dom.regions:
        from meshwright.quad.regions import region_markers

        markers["quad"], tri_markers = region_markers(points, quads, fill.triangles, fill.lines, dom.regions)
        if len(fill.triangles):
            markers["triangle"] = tri_markers
    return Mesh(points, cells, cell_data={"marker": markers})
