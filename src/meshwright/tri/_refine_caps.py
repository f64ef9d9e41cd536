r"""Default caps of Delaunay refinement (:mod:`meshwright.tri.ruppert`): how many vertices a
mesh needs, estimated from the size bounds and, where those undercount, from the local
feature size.

Sources: J. Ruppert, "A Delaunay refinement algorithm for quality 2-dimensional mesh
generation", J. Algorithms 18(3):548-585, 1995, and J. R. Shewchuk, "Delaunay refinement
algorithms for triangular mesh generation", Comput. Geom. 22:21-74, 2002: the vertices of a
refined mesh number within a constant factor of :math:`\int dA / \mathrm{lfs}(x)^2`, the
edges being graded by the local feature size wherever it is below the size asked for.

Two estimates, both sums over the inside triangles of ``area / (area of the equilateral
triangle of side h)`` with ``h`` the smallest of the sizes at the corners and the centroid
(an upper bound on the count where ``h`` is smooth):

* the **size estimate**, before the run, with ``h`` the caller's size field (``max_area``
  and region bounds included).  It counts what the size needs, not what the angle bound
  needs: a polygon of aspect ratio 1e4 or a 1e-6 feature needs far more vertices than its
  area over ``h^2``;
* the **lfs estimate**, with ``h = min(size, lfs)`` and the lfs of the input graph
  (:func:`meshwright.sizing.lfs.lfs_field`, scale 1, graded), summed over the *current*
  triangles (small by then, so the sum resolves the lfs).  It is computed only when a
  default cap is reached, once per run.

Default caps, from an estimate ``est`` and the ``nv`` input vertices: points
``nv + 50 nv + 4 est + 1000``, steps ``20 min(points cap, that)``.  A cap the caller gave
is honoured exactly.  When the default point cap is reached, :meth:`Caps.relax` recomputes
it once from the lfs estimate: the loop continues if it grew (the loop requeues the
triangle it stopped at), and the cap's error stands otherwise.

The default step cap follows the run's progress instead of an estimate
(:meth:`Caps.more_steps`): reached, it becomes ``20 min(points cap, expected + inserted)``
with ``inserted`` the vertices the run has added, granted only when that is at least
:data:`GRANT` above the old cap (:data:`GRANT_POINTS` more vertices).  A run that keeps
inserting is bounded by the point cap alone; one that stalls (steps without insertions)
stops within ``20 x`` its insertions plus the first estimate.  Progress costs nothing to
measure, where the lfs estimate of a thin domain samples millions of segment points (a
polygon of aspect 1e4: 7.4e6 samples, 13 s, for a steps cap the progress rule raises for
free); the estimate is also far above the count there (3.4e8 against 693k vertices), so it
bounded nothing.

Arrays: the :class:`~meshwright.tri.cdt.ConstrainedTriangulation`'s ``points`` (n, 2)
float64 and its inside ``triangles`` (t, 3) int32; the input graph of the lfs is the first
``nv`` points with the pieces ``constraints.seg`` (p, 2) int32 as they were when the run
started.
"""

from __future__ import annotations

import numpy as np

from meshwright.core.errors import MeshwrightError
from meshwright.tri._kernel2d import M_NTRI

__all__ = ["Caps", "estimate"]

_EQUILATERAL = np.sqrt(3.0) / 4.0  # area of the equilateral triangle of side 1
_INT_CAP = 2**31 - 16
STEPS_PER_POINT = 20  # loop steps a run may take per vertex it needs
GRANT = 1.05  # a step grant raises the cap by this factor at least ...
GRANT_POINTS = 64  # ... and by this many vertices' steps: few trips back to Python


def estimate(ct, amax: float, h=None) -> float:
    """Vertices a mesh of ``ct``'s inside triangles needs under the area bound ``amax``
    (regions' bounds included) and the size ``h``, roughly (area / bound).

    Parameters
    ----------
    ct : ConstrainedTriangulation
    amax : float
        Global area bound (inf: none).
    h : callable, optional
        ``h(xy (k, 2) float64) -> (k,) float64``, the local edge length.

    Returns
    -------
    float
    """
    tris = ct.triangles(True)
    if not len(tris):
        return 0.0
    p = ct.points
    a, b, c = p[tris[:, 0]], p[tris[:, 1]], p[tris[:, 2]]
    area = 0.5 * np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
    ntri = int(ct.state.meta[M_NTRI])
    reg = ct.constraints.treg[:ntri][ct.inside_slots()]
    bound = np.minimum(amax, ct.constraints.rarea[np.maximum(reg, 0)])
    if h is not None:
        hh = np.minimum(np.minimum(h(a), h(b)), np.minimum(h(c), h((a + b + c) / 3.0)))
        bound = np.minimum(bound, _EQUILATERAL * hh * hh)
    return float(np.sum(area / bound))


def _expected(nv: int, est: float) -> int:
    return int(min(nv + 50 * nv + 4 * est + 1000, _INT_CAP))


class Caps:
    """The point and step caps of one refinement run (module docstring).

    Parameters
    ----------
    ct : ConstrainedTriangulation
        Before the run.
    amax : float
        Global area bound (inf: none).
    field : SizeField, optional
        The size.
    max_points, max_steps : int, optional
        The caller's caps (None: the default).

    Attributes
    ----------
    max_points, max_steps : int
        The caps now.
    room : int
        Vertices to reserve room for when the run first grows its arrays.
    """

    def __init__(self, ct, amax: float, field, max_points=None, max_steps=None):
        self.nv = ct.n_points
        # The input graph, recovered lazily from these (the run only appends rows).
        self.pieces = ct.constraints.seg[: ct._np].copy()
        self.amax = amax
        self.field = field
        self.free_points = max_points is None
        self.free_steps = max_steps is None
        est = estimate(ct, amax, None if field is None or field.constant is not None else field)
        expected = _expected(self.nv, est)
        self.max_points = expected if max_points is None else int(max_points)
        # The estimate-based bound also bounds the steps under a caller's generous
        # max_points (triangulate passes 10**8): a stalled loop must not run billions of steps.
        self.expected = expected
        steps = STEPS_PER_POINT * min(self.max_points, expected)
        self.max_steps = steps if max_steps is None else int(max_steps)
        self.room = int(min(self.max_points, self.nv + 1.2 * est + 16))
        self.relaxed = not self.free_points

    def more_steps(self, ct) -> bool:
        """The default step cap was reached: raise it if the run has been inserting
        (module docstring); whether it grew."""
        if not self.free_steps:
            return False
        inserted = ct.n_points - self.nv
        steps = min(STEPS_PER_POINT * min(self.max_points, self.expected + inserted), _INT_CAP)
        if steps < max(GRANT * self.max_steps, self.max_steps + STEPS_PER_POINT * GRANT_POINTS):
            return False
        self.max_steps = steps
        return True

    def relax(self, ct) -> bool:
        """Once per run: raise the default point cap to the lfs estimate; whether it grew."""
        if self.relaxed:
            return False
        self.relaxed = True
        from meshwright.sizing.lfs import lfs_field

        pts = np.ascontiguousarray(ct.points[: self.nv])
        try:
            lfs = lfs_field(pts, self.pieces, scale=1.0)
        except MeshwrightError:
            return False  # a graph the lfs does not take (too many samples): the cap's error stands
        field = self.field
        h = lfs if field is None else (lambda xy: np.minimum(lfs(xy), field(xy)))
        expected = _expected(self.nv, estimate(ct, self.amax, h))
        if expected <= self.max_points:
            return False
        self.max_points = self.expected = expected
        return True
