"""Frontal Delaunay (chapter 18.3): the removable scaffold, vertex removal, stretching.

The domain suite of ``test_triangulate.py`` runs every registered method; here are the
properties of this method's design: the scaffold leaves no vertex behind and changes no
mesh property, vertex removal gives the Delaunay triangulation of what is left (checked
against scipy's Qhull and an exact rational in-circle oracle), and a uniformly stretched
background grid shapes the elements as in the advancing front's stretching test.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_front import _principal
from test_triangulate import check

import meshwright as mw
from meshwright import geometry as g
from meshwright.core.errors import InputError
from meshwright.sizing import BackgroundGrid
from meshwright.tri import frontal_delaunay as FD
from meshwright.tri._kernel2d import M_NTRI
from meshwright.tri._scaffold import SCRATCH, move_slot, remove_vertex
from meshwright.tri.cdt import cdt_build


# ---------------------------------------------------------------------------- oracle
def _incircle_exact(a, b, c, d) -> int:
    """Sign of the in-circle determinant in exact rationals (no shared code with the kernel)."""
    rows = []
    for p in (a, b, c):
        x = Fraction(float(p[0])) - Fraction(float(d[0]))
        y = Fraction(float(p[1])) - Fraction(float(d[1]))
        rows.append((x, y, x * x + y * y))
    (a1, a2, a3), (b1, b2, b3), (c1, c2, c3) = rows
    det = a1 * (b2 * c3 - b3 * c2) - a2 * (b1 * c3 - b3 * c1) + a3 * (b1 * c2 - b2 * c1)
    return (det > 0) - (det < 0)


def _orient_exact(a, b, c) -> int:
    det = (Fraction(float(b[0])) - Fraction(float(a[0]))) * (Fraction(float(c[1])) - Fraction(float(a[1]))) - (
        Fraction(float(b[1])) - Fraction(float(a[1]))
    ) * (Fraction(float(c[0])) - Fraction(float(a[0])))
    return (det > 0) - (det < 0)


def _live_triangles(ct):
    """Finite triangles of every slot in use, as vertex triples."""
    return ct.triangles(False)


# ---------------------------------------------------------------------------- vertex removal
@settings(deadline=None, max_examples=25)
@given(st.integers(0, 2**31 - 1), st.integers(8, 60))
def test_removal_gives_the_delaunay_triangulation_of_the_rest(seed, n):
    rng = np.random.default_rng(seed)
    box = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    inner = 0.05 + 0.9 * rng.random((n, 2))
    pts = np.vstack([box, inner])
    ct = cdt_build(pts, np.array([[0, 1], [1, 2], [2, 3], [3, 0]])).classify()
    scr = np.zeros(SCRATCH, dtype=np.int32)
    removed = set()
    for v in rng.permutation(np.arange(4, len(pts)))[: n // 2]:
        k = remove_vertex(int(v), ct.state, ct.constraints, scr)
        assert k >= 3
        removed.add(int(v))
        # Close the two freed slots as the frontal kernel does, through its own helper.
        s, c = ct.state, ct.constraints
        st_ = scr[64:128]
        for fs in sorted((int(st_[k - 2]), int(st_[k - 1])), reverse=True):
            last = int(s.meta[M_NTRI]) - 1
            if fs != last:
                move_slot(last, fs, s.tri, s.nbr, s.cons, c.treg, c.vtri, s.meta)
            s.meta[M_NTRI] = last
    tris = _live_triangles(ct)
    used = set(np.unique(tris).tolist())
    assert used.isdisjoint(removed)
    assert used == set(range(len(pts))) - removed
    p = ct.state.pts
    for a, b, c in tris:
        assert _orient_exact(p[a], p[b], p[c]) > 0
    # Delaunay: no remaining vertex strictly inside any circumcircle (exact rationals).
    keep = sorted(used)
    for a, b, c in tris:
        for w in keep:
            if w not in (a, b, c):
                assert _incircle_exact(p[a], p[b], p[c], p[w]) <= 0
    # The same triangle count as scipy's Qhull on what is left (general position).
    spatial = pytest.importorskip("scipy.spatial")
    assert len(tris) == len(spatial.Delaunay(p[keep]).simplices)


def test_removal_refuses_a_boundary_vertex_and_changes_nothing():
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.5]])
    ct = cdt_build(pts, np.array([[0, 1], [1, 2], [2, 3], [3, 0]])).classify()
    before = ct.state.tri.copy(), ct.state.nbr.copy()
    scr = np.zeros(SCRATCH, dtype=np.int32)
    assert remove_vertex(0, ct.state, ct.constraints, scr) == -1
    assert np.array_equal(ct.state.tri, before[0]) and np.array_equal(ct.state.nbr, before[1])


# ---------------------------------------------------------------------------- the scaffold
def _frontal(dom, size, scaffold):
    from meshwright.tri import mesher

    counts = {}
    orig = mesher.frontal_delaunay

    def spy(ct, sz, **kw):
        counts.update(orig(ct, sz, scaffold=scaffold, **kw))

    mesher.frontal_delaunay = spy
    try:
        mesh = mw.triangulate(dom, size=size, method="frontal-delaunay", relax=False)
    finally:
        mesher.frontal_delaunay = orig
    return mesh, counts


def test_scaffold_leaves_nothing_and_keeps_quality():
    dom = g.circle()
    with_s, counts = _frontal(dom, 0.02, True)
    without, _ = _frontal(dom, 0.02, False)
    check(with_s, dom)
    with_s.validate(check_delaunay=True)
    assert counts["scaffold"] > 100 and counts["removed"] + counts["kept"] == counts["scaffold"]
    assert counts["kept"] <= counts["scaffold"] // 100
    # Every vertex is a boundary or frontal point: as many as the points added.
    assert len(with_s.points) == len(dom.discretize(0.02).points) + counts["added"]
    q1 = with_s.quality().summary()["triangle"]
    q0 = without.quality().summary()["triangle"]
    assert q1["radius_ratio"]["mean"] >= 0.99
    assert q1["radius_ratio"]["mean"] >= q0["radius_ratio"]["mean"] - 0.002
    assert q1["min_angle"]["min"] >= q0["min_angle"]["min"] - 5.0
    assert abs(len(with_s.cells["triangle"]) / len(without.cells["triangle"]) - 1) < 0.03


def test_scaffold_on_a_graded_domain_with_holes():
    dom = g.airfoil_in_farfield("0012", radius=10.0)
    mesh, counts = _frontal(dom, None, True)
    check(mesh, dom)
    assert counts["removed"] + counts["kept"] == counts["scaffold"]


def test_scaffold_points_follow_the_size():
    grid = BackgroundGrid([(0, 0), (4, 0), (4, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)], [0.01, 0.2, 0.2, 0.01])
    xy = FD.scaffold_points(grid, np.array([0.0, 0.0]), np.array([4.0, 1.0]), 10**6)
    assert len(xy) > 0
    left = np.count_nonzero(xy[:, 0] < 0.5)
    right = np.count_nonzero(xy[:, 0] > 3.5)
    assert left > 4 * right
    assert len(FD.scaffold_points(grid, np.array([0.0, 0.0]), np.array([4.0, 1.0]), 50)) <= 50


def test_door_refuses_bad_arguments():
    ct = cdt_build(np.array([[0.0, 0], [1, 0], [0, 1]]), np.array([[0, 1], [1, 2], [2, 0]])).classify()
    with pytest.raises(InputError, match="max_points"):
        FD.frontal_delaunay(ct, 0.1, max_points=0)
    with pytest.raises(InputError, match="scaffold"):
        FD.frontal_delaunay(ct, 0.1, scaffold="yes")


# ---------------------------------------------------------------------------- stretching
@pytest.mark.parametrize("stretch, degrees", [(4.0, 30.0), (2.5, 100.0)])
def test_stretched_elements_measure_s_delta_along_alpha(stretch, degrees):
    dom = g.polygon([(0, 0), (4, 0), (4, 1), (0, 1)])
    delta = 0.05
    bg = BackgroundGrid.uniform(dom.bbox, delta, stretch=stretch, direction=math.radians(degrees))
    mesh = mw.triangulate(dom, bg, method="frontal-delaunay")
    check(mesh, dom, straight=True)
    aspect, direction = _principal(mesh)
    assert np.median(aspect) == pytest.approx(stretch, rel=0.1)
    off = np.abs((direction - degrees + 90.0) % 180.0 - 90.0)
    assert np.median(off) < 3.0
    T = bg.transform(np.zeros((1, 2)))[0]
    p = mesh.points[mesh.cells["triangle"]]
    edges = (p[:, [1, 2, 0]] - p) @ T.T / delta
    assert np.median(np.hypot(edges[..., 0], edges[..., 1])) == pytest.approx(1.0, rel=0.1)
    mapped = mw.Mesh(mesh.points @ T.T, {"triangle": mesh.cells["triangle"]})
    assert mapped.quality().summary()["triangle"]["radius_ratio"]["mean"] > 0.93


def test_stretched_disk_with_a_hole_keeps_its_regions():
    dom = g.polygon(
        [(np.cos(t), np.sin(t)) for t in np.linspace(0, 2 * np.pi, 40, endpoint=False)],
        holes=[[(0.4 * np.cos(t), -0.4 * np.sin(t)) for t in np.linspace(0, 2 * np.pi, 16, endpoint=False)]],
    )
    bg = BackgroundGrid.uniform(dom.bbox, 0.04, stretch=3.0, direction=math.radians(45))
    mesh = mw.triangulate(dom, bg, method="frontal-delaunay")
    check(mesh, dom, straight=True)
    aspect, _ = _principal(mesh)
    assert np.median(aspect) == pytest.approx(3.0, rel=0.15)


def test_varying_stretching_is_refused():
    pts = [(-1.2, -1.2), (1.2, -1.2), (1.2, 1.2), (-1.2, 1.2)]
    bg = BackgroundGrid(pts, [(0, 1, 2), (0, 2, 3)], 0.1, stretch=[1.0, 3.0, 3.0, 3.0])
    with pytest.raises(InputError, match="uniform stretching only.*node 1"):
        mw.triangulate(g.circle(), bg, method="frontal-delaunay")


def test_stretched_refuses_a_planar_refinement_pass():
    dom = g.polygon([(0, 0), (4, 0), (4, 1), (0, 1)])
    bg = BackgroundGrid.uniform(dom.bbox, 0.1, stretch=3.0, direction=0.0)
    with pytest.raises(InputError, match="stretched background grid honours no min_angle"):
        mw.triangulate(dom, bg, method="frontal-delaunay", min_angle=20.0)
