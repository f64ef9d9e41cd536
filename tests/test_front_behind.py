"""The front's ideal point and the nodes behind its face (issue 13, stress seed 1801).

A hole with a sharp corner at an end of a long face puts the corner's neighbour just
behind the face, closer to the face's ideal point than ``CLEAR_NODE rho`` in a straight
line.  The front used to refuse the ideal point for it; with nothing else left of the
face, the face failed after three back-offs (four stress reproducers).  Such a node is
reached from the ideal point only around an end of the face, at least rho away, so it no
longer counts.  The oracles below are the tests' own: exact rational crossings and
distances, and the mesh area as a sum of triangle areas.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

import meshwright as mw
from meshwright.core.spatial.loose_quadtree import Q_DEPTH, STACK_PER_LEVEL
from meshwright.tri import _front_kernel as fk
from meshwright.tri import front as F

OUTER = np.array([[-3.0, -2.0], [3.0, -2.0], [3.0, 3.0], [-3.0, 3.0]])


def _sliver_hole(dx, t):
    """Triangle hole (0, 0), (dx, t), (0, 1): its long side x = 0 has the apex just behind it."""
    return np.array([[0.0, 0.0], [dx, t], [0.0, 1.0]])


def _tri_area_sum(points, tris) -> float:
    a, b, c = points[tris[:, 0]], points[tris[:, 1]], points[tris[:, 2]]
    return float(np.sum(0.5 * ((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])))


# Each of these failed before with "no valid triangle on front face (0, 0) -> (0, 1) after
# 3 back-offs" (measured on the previous kernel).
@pytest.mark.parametrize("dx, t", [(0.01, 0.5), (0.01, 0.7), (0.03, 0.5), (0.03, 0.7), (0.08, 0.5)])
def test_sliver_hole_with_boundary_size_meshes(dx, t):
    hole = _sliver_hole(dx, t)
    dom = mw.geometry.polygon(OUTER, holes=[hole])
    mesh = mw.triangulate(dom, "boundary", method="front")
    mesh.validate()
    # The domain's area by its own arithmetic: the box less the triangle (dx * 1 / 2).
    want = 6.0 * 5.0 - 0.5 * dx
    got = _tri_area_sum(mesh.points, mesh.cells["triangle"])
    assert abs(got - want) <= 1e-12 * want
    pts = mesh.points[:, 0] + 1j * mesh.points[:, 1]
    for p in np.concatenate([OUTER, hole]):
        assert np.any(pts == complex(*p))


def _gather_once(points, faces, free):
    """The candidate search of face 0 on a front of unit isotropic metric; returns
    (p_ok, rho, ideal point)."""
    points = np.asarray(points, dtype=np.float64)
    metric = np.tile([1.0, 0.0, 1.0], (len(points), 1))
    fr = F._Front(points, np.asarray(faces, dtype=np.int32), np.asarray(free, dtype=np.int32), metric, 64)
    fs = fr.fs
    par = np.zeros(fk.P_LEN)
    par[fk.P_CLOSE], par[fk.P_SEARCH] = F.CLOSE, F.SEARCH
    par[fk.P_CLEAR_N], par[fk.P_CLEAR_F] = F.CLEAR_NODE, F.CLEAR_FACE
    depth = fs.qmeta[Q_DEPTH]
    stack = np.empty(STACK_PER_LEVEL * (depth + 2), dtype=np.int64)
    fstack = np.empty((STACK_PER_LEVEL * (depth + 2), 3))
    a, b = int(faces[0][0]), int(faces[0][1])
    p = int(fs.meta[fk.M_NP])
    scratch = [np.empty(256, dtype=np.int32) for _ in range(3)] + [np.empty(256)]
    out = fk._gather(a, b, 0, p, -1, False, False, fs, par, np.empty(0, dtype=np.int8), -1, *scratch, stack, fstack)
    return bool(out[4]), float(out[5]), fs.pts[p].copy()


def _q(xy):
    return Fraction(float(xy[0])), Fraction(float(xy[1]))


def _orient(p, q, r) -> Fraction:
    return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])


def _crosses(p, q, r, s) -> bool:
    """Closed segments pq and rs meet, in exact rational arithmetic."""
    return _orient(p, q, r) * _orient(p, q, s) <= 0 and _orient(r, s, p) * _orient(r, s, q) <= 0


def test_node_behind_the_face_does_not_refuse_the_ideal_point():
    # Face a -> b, 2.2 sizes long, domain on its left (x < 0); the hole's apex c lies behind it.
    a, b, c = (0.0, 0.0), (0.0, 2.2), (0.05, 1.5)
    p_ok, rho, ideal = _gather_once([a, b, c], [(0, 1), (1, 2), (2, 0)], [])
    P, A, B, C = _q(ideal), _q(a), _q(b), _q(c)
    clear2 = Fraction(F.CLEAR_NODE * rho) ** 2

    def d2(u, v):
        return (u[0] - v[0]) ** 2 + (u[1] - v[1]) ** 2

    # The old rule's refusal: c is nearer than the clearance in a straight line ...
    assert d2(P, C) < clear2
    # ... but the segment from the ideal point to c passes through the face, and both ways
    # around it (by a or by b) are longer than the clearance.
    assert _orient(A, B, P) > 0 > _orient(A, B, C) and _crosses(P, C, A, B)
    assert min(d2(P, A), d2(P, B)) >= clear2
    assert p_ok


def test_visible_node_still_refuses_the_ideal_point():
    # The same face with a free point left of it, as near to the ideal point as c above.
    a, b, c, v = (0.0, 0.0), (0.0, 2.2), (0.05, 1.5), (-0.3, 1.5)
    p_ok, rho, ideal = _gather_once([a, b, c, v], [(0, 1), (1, 2), (2, 0)], [3])
    P, A, B, V = _q(ideal), _q(a), _q(b), _q(v)
    assert (P[0] - V[0]) ** 2 + (P[1] - V[1]) ** 2 < Fraction(F.CLEAR_NODE * rho) ** 2
    assert not _crosses(P, V, A, B)
    assert not p_ok
