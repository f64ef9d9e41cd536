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
the non-accepted triangles on it wait in a heap keyed by ``R sqrt(3) / h``.  Repeatedly:

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

State: the :class:`ConstrainedTriangulation`'s two bundles (``state``, ``constraints``) and
the method's ``FrontalState``, layout in :mod:`meshwright.tri._frontal_kernel`.
"""

from __future__ import annotations

import copy

import numpy as np

from meshwright.core.errors import MeshingError
from meshwright.sizing.background import BackgroundGrid
from meshwright.sizing.field import as_size_field
from meshwright.core.flat import grown_rows
from meshwright.tri import _frontal_kernel as fk
from meshwright.tri._kernel2d import M_NTRI

__all__ = ["frontal_delaunay", "ACCEPT", "SPACING", "SAMPLE"]

ACCEPT = 1.4  # R <= ACCEPT * h / sqrt(3): the triangle is of the right size
SPACING = 0.7  # a new point keeps this fraction of h away from every vertex
SAMPLE = 3.0  # a general size field is sampled on a mesh this many times coarser


def _background(ct, field) -> BackgroundGrid:
    """A background grid giving ``field`` (see the module docstring)."""
    if isinstance(field, BackgroundGrid):
        return field
    p = ct.points
    lo, hi = p.min(axis=0), p.max(axis=0)
    if field.constant is not None:
        return BackgroundGrid.uniform((lo[0], lo[1], hi[0], hi[1]), field.constant)
    from meshwright.tri.ruppert import refine

    sample = copy.deepcopy(ct)
    refine(sample, min_angle=20.0, size=lambda xy: SAMPLE * field(xy))
    # The inside triangles cover the domain.
    return BackgroundGrid.on_triangulation(sample.points, sample.triangles(True), field(sample.points))


def frontal_delaunay(ct, size, *, max_points: int | None = None) -> None:
    """Fill a classified constrained triangulation with frontal points, in place.

    Parameters
    ----------
    ct : ConstrainedTriangulation
        From :func:`meshwright.tri.cdt.cdt_build`, exterior removed by ``classify``.
    size : number, callable or SizeField
        Target edge length h(x).
    max_points : int, optional
        Cap on the number of vertices.

    Raises
    ------
    MeshingError
        The cap was hit, or an insertion met an inconsistent cavity (the message names it).
    """
    field = as_size_field(size)
    bg = _background(ct, field).kernel_args() + (np.zeros(1, dtype=np.int64),)  # last: the walk's hint
    par = np.zeros(fk.P_LEN)
    par[fk.P_ACCEPT] = ACCEPT
    par[fk.P_SPACING] = SPACING
    par[fk.P_MAX_POINTS] = np.iinfo(np.int32).max if max_points is None else int(max_points)
    par[fk.P_CONST] = field.constant if field.constant is not None else 0.0
    slots = len(ct.constraints.treg)
    hcap = max(1024, slots)
    f = fk.FrontalState(
        acc=np.full(3 * slots, -2, dtype=np.int32),  # no triple matches: nothing accepted yet
        ratio=np.zeros(slots), hkey=np.empty(hcap), htri=np.empty((hcap, 4), dtype=np.int32),
        stamp=np.zeros(slots, dtype=np.int64), fmeta=np.zeros(fk.FM_LEN, dtype=np.int64), par=par,
    )
    fk.start(ct.state, ct.constraints, f, bg)
    ct.refresh_pieces()
    while True:
        code = fk.run(ct.state, ct.constraints, f, bg)
        if code == fk.F_DONE:
            return
        if code == fk.F_POINTS:
            raise MeshingError(f"frontal Delaunay reached max_points = {int(par[fk.P_MAX_POINTS])} vertices")
        if code == fk.F_BROKEN:
            raise MeshingError(f"frontal Delaunay: an insertion met an inconsistent cavity ({ct.n_points} vertices)")
        # Room: the triangulation, the per-slot arrays, the heap.
        ct.reserve(ct.n_points + 1024, int(ct.state.meta[M_NTRI]) + 2048)
        slots = len(ct.constraints.treg)
        hkey = f.hkey
        if int(f.fmeta[fk.FM_HN]) + fk.HEAP_ROOM > len(hkey):
            hkey = grown_rows(hkey, 2 * len(hkey))
        f = f._replace(
            acc=grown_rows(f.acc, 3 * slots, -2), stamp=grown_rows(f.stamp, slots, 0),
            ratio=grown_rows(f.ratio, slots, 0.0), hkey=hkey, htri=grown_rows(f.htri, len(hkey)),
        )
