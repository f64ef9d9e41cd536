"""Mesh relaxation (Field and Frey 1991): valence swaps and guarded smoothing.

Oracles: the neighbour table against :func:`meshwright.core.mesh.build_neighbors` (facet
matching by sorting, another code path); validity by :meth:`Mesh.validate`, exact rational
orientation of every triangle and the shoelace area sum; the lines, regions and fixed nodes
by direct comparison with the input.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import meshwright as mw
from meshwright import geometry as g
from meshwright.core.errors import InputError
from meshwright.core.mesh import build_neighbors
from meshwright.core.topology import boundary_edges_of, edges_of
from meshwright.sizing import BackgroundGrid
from meshwright.tri.relax import ideal_valence, neighbours, relax
from meshwright.tri.smoothing import incident_triangles


def _delaunay(seed: int, n: int):
    rng = np.random.default_rng(seed)
    pts = rng.random((n, 2))
    tri = mw.delaunay(pts).triangles.astype(np.int32)
    return pts, tri


def _area(pts, tri):
    a, b, c = pts[tri[:, 0]], pts[tri[:, 1]], pts[tri[:, 2]]
    return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


def _ccw_exact(pts, tri) -> bool:
    for a, b, c in tri.tolist():
        (ax, ay), (bx, by), (cx, cy) = (map(Fraction, pts[v]) for v in (a, b, c))
        if (bx - ax) * (cy - ay) - (by - ay) * (cx - ax) <= 0:
            return False
    return True


def _ratio(pts, tri):
    a, b, c = pts[tri[:, 0]], pts[tri[:, 1]], pts[tri[:, 2]]
    la, lb, lc = (np.linalg.norm(u - v, axis=1) for u, v in ((b, c), (c, a), (a, b)))
    return 16.0 * _area(pts, tri) ** 2 / ((la + lb + lc) * la * lb * lc)


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 10_000), st.integers(4, 300))
def test_neighbours_match_facet_matching(seed, n):
    pts, tri = _delaunay(seed, n)
    off, inc = incident_triangles(tri, n)
    nbr, bnode = neighbours(tri, off, inc, np.zeros(len(tri), dtype=np.int64))
    assert np.array_equal(nbr, build_neighbors(tri))
    expect = np.zeros(n, dtype=bool)
    expect[boundary_edges_of(tri).ravel()] = True
    assert np.array_equal(bnode, expect)


def test_neighbours_stop_at_a_marker_change():
    pts, tri = _delaunay(3, 200)
    marker = (pts[tri].mean(axis=1)[:, 0] > 0.5).astype(np.int64)
    off, inc = incident_triangles(tri, len(pts))
    nbr, _ = neighbours(tri, off, inc, marker)
    full = build_neighbors(tri)
    across = (full >= 0) & (marker[np.maximum(full, 0)] != marker[:, None])
    assert np.array_equal(nbr, np.where(across, -1, full))


def test_ideal_valence_inside_and_on_a_straight_boundary():
    # A regular grid of right triangles: interior nodes have six neighbours.
    k = 6
    xs, ys = np.meshgrid(np.arange(k), np.arange(k))
    pts = np.column_stack([xs.ravel(), ys.ravel()]).astype(float)
    tri = []
    for i in range(k - 1):
        for j in range(k - 1):
            a, b, c, d = i * k + j, i * k + j + 1, (i + 1) * k + j + 1, (i + 1) * k + j
            tri += [[a, b, c], [a, c, d]]
    tri = np.array(tri, dtype=np.int32)
    bnode = np.zeros(len(pts), dtype=bool)
    bnode[boundary_edges_of(tri).ravel()] = True
    ideal, deg = ideal_valence(pts, tri, bnode)
    inner = ~bnode
    assert (ideal[inner] == 6).all() and (deg[inner] == 6).all()
    side = bnode & (pts[:, 0] > 0) & (pts[:, 0] < k - 1) & (pts[:, 1] == 0)
    assert (ideal[side] == 4).all()  # a straight boundary: three 60-degree corners


@settings(max_examples=20, deadline=None)
@given(st.integers(0, 10_000), st.integers(10, 400))
def test_relax_keeps_a_valid_mesh_its_boundary_and_locked_edges(seed, n):
    pts, tri = _delaunay(seed, n)
    rng = np.random.default_rng(seed + 1)
    inner = edges_of(tri)
    locked = inner[rng.random(len(inner)) < 0.1]
    fixed = rng.random(n) < 0.1
    xy, out = relax(pts, tri, locked, fixed=fixed)
    assert out.shape == tri.shape and out.dtype == np.int32
    assert _ccw_exact(xy, out)
    assert np.isclose(_area(xy, out).sum(), _area(pts, tri).sum(), rtol=1e-12)
    have = {tuple(e) for e in edges_of(out).tolist()}
    assert {tuple(e) for e in np.sort(locked, axis=1).tolist()} <= have
    b0 = {tuple(e) for e in np.sort(boundary_edges_of(tri), axis=1).tolist()}
    assert b0 == {tuple(e) for e in np.sort(boundary_edges_of(out), axis=1).tolist()}
    still = fixed.copy()
    still[boundary_edges_of(tri).ravel()] = True
    still[locked.ravel()] = True
    assert np.array_equal(xy[still], pts[still])
    mw.Mesh(xy, {"triangle": out}).validate()


def test_relax_mends_valences_and_raises_quality_on_a_graded_mesh():
    t = np.linspace(0.0, 2.0 * np.pi, 40, endpoint=False)
    ring = np.column_stack([np.cos(t), np.sin(t)])
    holes = [c + 0.08 * ring for c in ((0.3, 0.3), (0.7, 0.4), (0.45, 0.75))]
    dom = g.polygon([(0, 0), (1, 0), (1, 1), (0, 1)], holes=holes)
    m = mw.triangulate(dom, 0.06, method="frontal-delaunay", relax=False)
    pts, tri = m.points, m.cells["triangle"]
    xy, out = relax(pts, tri, m.cells["line"])
    bnode = np.zeros(len(pts), dtype=bool)
    bnode[boundary_edges_of(tri).ravel()] = True

    def defect(p, t):
        ideal, deg = ideal_valence(p, t, bnode)
        return np.abs(deg - ideal).sum()

    assert defect(xy, out) < defect(pts, tri)
    assert _ratio(xy, out).mean() > _ratio(pts, tri).mean() + 0.01
    assert _ratio(xy, out).min() > 0.5 * _ratio(pts, tri).min()


def test_triangulate_relaxes_frontal_delaunay_by_default_and_keeps_regions():
    dom = g.polygon([(0, 0), (2, 0), (2, 1), (0, 1)], segments=[[(1, 0), (1, 1)]],
                    regions=[(0.5, 0.5, 7, None), (1.5, 0.5, 9, None)])
    plain = mw.triangulate(dom, 0.1, method="frontal-delaunay", relax=False)
    m = mw.triangulate(dom, 0.1, method="frontal-delaunay")
    m.validate()
    assert len(m.cells["triangle"]) == len(plain.cells["triangle"])
    assert np.array_equal(m.cells["line"], plain.cells["line"])
    centre = m.points[m.cells["triangle"]].mean(axis=1)
    marks = m.cell_data["marker"]["triangle"]
    assert (marks[centre[:, 0] < 1] == 7).all() and (marks[centre[:, 0] > 1] == 9).all()
    assert not np.array_equal(m.cells["triangle"], plain.cells["triangle"]) or not np.array_equal(m.points, plain.points)


@pytest.mark.parametrize(
    "kw",
    [dict(relax="yes"), dict(relax=1.0), dict(relax=True, min_angle=20.0), dict(relax=True, max_area=0.01),
     dict(relax=True, conforming=True)],
)
def test_triangulate_door_refuses_relax_it_cannot_honour(kw):
    with pytest.raises(InputError, match="relax"):
        mw.triangulate("circle", 0.2, method="frontal-delaunay", **kw)


def test_relax_refused_under_a_stretched_background_and_off_by_default_there():
    bg = BackgroundGrid.uniform((-1.5, -1.5, 1.5, 1.5), 0.1, stretch=3.0, direction=0.0)
    with pytest.raises(InputError, match="stretched"):
        mw.triangulate("circle", bg, method="frontal-delaunay", relax=True)
    m = mw.triangulate("circle", bg, method="frontal-delaunay")
    plain = mw.triangulate("circle", bg, method="frontal-delaunay", relax=False)
    assert np.array_equal(m.cells["triangle"], plain.cells["triangle"]) and np.array_equal(m.points, plain.points)


def test_relax_door():
    pts, tri = _delaunay(1, 30)
    with pytest.raises(InputError):
        relax(pts, tri, rounds=-1)
    with pytest.raises(InputError, match="markers"):
        relax(pts, tri, markers=np.zeros(3))
    with pytest.raises(InputError):
        relax(pts, tri[:, :2])
    xy, out = relax(pts, tri, rounds=0)
    assert np.array_equal(xy, pts) and np.array_equal(out, tri)


def test_the_front_relaxes_by_default_and_keeps_its_lines():
    dom = g.polygon([(0, 0), (1, 0), (1, 1), (0, 1)], holes=[[(0.4, 0.4), (0.6, 0.4), (0.6, 0.6), (0.4, 0.6)]])
    plain = mw.triangulate(dom, 0.08, method="front", relax=False)
    m = mw.triangulate(dom, 0.08, method="front")
    m.validate()
    assert np.array_equal(m.cells["line"], plain.cells["line"])
    assert len(m.cells["triangle"]) == len(plain.cells["triangle"])
    bnd = np.unique(plain.cells["line"])
    assert np.array_equal(m.points[bnd], plain.points[bnd])
    # What a swap promises is a smaller valence defect, not a higher mean ratio (a coarse mesh
    # like this one may lose 1e-4 of it): the defect must fall.
    bnode = np.zeros(len(m.points), dtype=bool)
    bnode[bnd] = True

    def defect(mesh):
        ideal, deg = ideal_valence(mesh.points, mesh.cells["triangle"].astype(np.int32), bnode)
        return np.abs(deg - ideal).sum()

    assert defect(m) < defect(plain)
