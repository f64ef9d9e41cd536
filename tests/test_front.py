"""Advancing front (chapter 18.2): the loose quadtree under it, stretched elements, closure.

The domain suite of ``test_triangulate.py`` runs every registered method, ``front``
included; here are the properties specific to the front: elements shaped by the background
grid's s and alpha, free points reached, the back-off path, caps and errors.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_triangulate import _shoelace, check

import meshwright as mw
from meshwright import geometry as g
from meshwright.core.errors import MeshingError
from meshwright.core.spatial.loose_quadtree import STACK_PER_LEVEL, qt_insert, qt_new, qt_query
from meshwright.sizing import BackgroundGrid
from meshwright.tri import _front_kernel as fk
from meshwright.tri import front as F
from meshwright.tri.cdt import cdt_build

# ---------------------------------------------------------------------------- quadtree
boxes = st.lists(
    st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(0, 0.5), st.floats(0, 0.5)), min_size=1, max_size=60
)


@settings(deadline=None, max_examples=60)
@given(boxes, boxes, st.integers(0, 2**31 - 1))
def test_quadtree_query_matches_brute_force(items, queries, seed):
    qbox = np.array([(x, y, x + w, y + h) for x, y, w, h in items])
    n = len(qbox)
    qgeo, qmeta, qchild, qhead = qt_new((-1, -1, 1.5, 1.5), 1e-3, nodes=64 * n + 64)
    qnext = np.empty(n, dtype=np.int32)
    for i in range(n):
        qt_insert(i, qgeo, qmeta, qchild, qhead, qnext, qbox)
    alive = np.ones(n, dtype=np.int8)
    alive[np.random.default_rng(seed).random(n) < 0.3] = 0  # lazily deleted items
    out = np.empty(n + 1, dtype=np.int32)
    depth = int(qmeta[1])
    stack = np.empty(STACK_PER_LEVEL * (depth + 2), dtype=np.int64)
    fstack = np.empty((len(stack), 3))
    for x, y, w, h in queries:
        k = qt_query(x, y, x + w, y + h, qgeo, qchild, qhead, qnext, qbox, alive, out, stack, fstack)
        meet = (qbox[:, 2] >= x) & (qbox[:, 0] <= x + w) & (qbox[:, 3] >= y) & (qbox[:, 1] <= y + h)
        assert sorted(out[:k].tolist()) == np.flatnonzero(meet & (alive == 1)).tolist()


def test_quadtree_reports_overflow():
    qbox = np.array([[0.1 * i, 0.0, 0.1 * i + 0.05, 0.05] for i in range(10)])
    qgeo, qmeta, qchild, qhead = qt_new((0, 0, 1, 1), 0.01)
    qnext = np.empty(10, dtype=np.int32)
    for i in range(10):
        qt_insert(i, qgeo, qmeta, qchild, qhead, qnext, qbox)
    out = np.empty(3, dtype=np.int32)
    stack = np.empty(STACK_PER_LEVEL * (int(qmeta[1]) + 2), dtype=np.int64)
    k = qt_query(-1, -1, 2, 2, qgeo, qchild, qhead, qnext, qbox, np.ones(10, dtype=np.int8), out, stack,
                 np.empty((len(stack), 3)))
    assert k == 10


# ---------------------------------------------------------------------------- stretching
def _principal(mesh):
    """Per triangle: aspect ratio and major-axis direction (degrees in [0, 180)) of its vertices."""
    p = mesh.points[mesh.cells["triangle"]]
    d = p - p.mean(axis=1, keepdims=True)
    w, v = np.linalg.eigh(np.einsum("tki,tkj->tij", d, d))
    return np.sqrt(w[:, 1] / w[:, 0]), np.degrees(np.arctan2(v[:, 1, 1], v[:, 0, 1])) % 180.0


@pytest.mark.parametrize("stretch, degrees", [(4.0, 30.0), (2.5, 100.0)])
def test_stretched_elements_measure_s_delta_along_alpha(stretch, degrees):
    dom = g.polygon([(0, 0), (4, 0), (4, 1), (0, 1)])
    delta = 0.05
    bg = BackgroundGrid.uniform(dom.bbox, delta, stretch=stretch, direction=math.radians(degrees))
    mesh = mw.triangulate(dom, bg, method="front")
    check(mesh, dom, straight=True)
    aspect, direction = _principal(mesh)
    # An equilateral triangle of side delta in the chapter's transformed space is, in the
    # plane, s times longer along alpha than across it.
    assert np.median(aspect) == pytest.approx(stretch, rel=0.1)
    off = np.abs((direction - degrees + 90.0) % 180.0 - 90.0)
    assert np.median(off) < 3.0
    # Edge lengths in the transformed space: delta (1 after dividing by delta).
    T = bg.transform(np.zeros((1, 2)))[0]
    p = mesh.points[mesh.cells["triangle"]]
    edges = (p[:, [1, 2, 0]] - p) @ T.T / delta
    lengths = np.hypot(edges[..., 0], edges[..., 1])
    assert np.median(lengths) == pytest.approx(1.0, rel=0.1)
    # In that space the triangles are nearly equilateral.
    mapped = mw.Mesh(mesh.points @ T.T, {"triangle": mesh.cells["triangle"]})
    assert mapped.quality().summary()["triangle"]["radius_ratio"]["mean"] > 0.9


def test_isotropic_front_is_nearly_equilateral_and_follows_size():
    dom = g.circle()
    mesh = mw.triangulate(dom, 0.05, method="front")
    check(mesh, dom)
    q = mesh.quality().summary()["triangle"]
    assert q["radius_ratio"]["mean"] > 0.97
    assert q["min_angle"]["min"] > 15.0
    p = mesh.points[mesh.cells["triangle"]]
    lengths = np.hypot(*(p - p[:, [1, 2, 0]]).transpose(2, 0, 1))
    assert np.median(lengths) == pytest.approx(0.05, rel=0.05)


def test_graded_size_ratio_above_1e4():
    # Three-element airfoil, size from the boundary background (chapter 18.3's default).
    mesh = mw.triangulate("three-element", method="front")
    mesh.validate()
    area = mesh.quality()["triangle"]["area"]
    assert np.sqrt(area.max() / area.min()) > 100.0


# ---------------------------------------------------------------------------- domains
def test_coarse_boundary_with_a_size_jump_closes():
    # Seven boundary points (a 3-point airfoil in a 4-point far field), the chapter's
    # default background from them: spacing 14 at the far field, 0.7 at the airfoil.  The
    # last front loop is a long thin triangle whose third node lies far from every search box.
    dom = g.airfoil_in_farfield("0012")
    mesh = mw.triangulate(dom, method="front")
    mesh.validate()
    assert mesh.area() == pytest.approx(_shoelace(mesh.points, mesh.boundary_facets()), rel=1e-12)


def test_hole_in_a_gap_narrower_than_the_spacing_closes():
    # A diamond hole 0.05 from a long outer segment, spacing from the boundary (0.17 at the
    # hole, 0.85 at the outer vertices): the gap closes only with the far ends of that
    # segment, outside every ordinary search box.
    outer = [(-0.588, 0.442), (-0.592, 0.289), (-0.821, 0.139), (-0.081, -0.693), (0.008, -0.785),
             (0.831, -0.351), (0.771, -0.069)]
    r = 0.12063938427325001
    dom = g.polygon(outer, holes=[[(r, 0.0), (0.0, -r), (-r, 0.0), (0.0, r)]])
    mesh = mw.triangulate(dom, method="front")
    check(mesh, dom, straight=True)


def test_free_points_are_reached():
    inner = np.array([(0.3, 0.3), (0.7, 0.35), (0.5, 0.71)])
    dom = g.polygon([(0, 0), (1, 0), (1, 1), (0, 1)], points=inner)
    mesh = mw.triangulate(dom, 0.1, method="front")
    check(mesh, dom, straight=True)
    for q in inner:
        assert np.any(np.all(mesh.points == q, axis=1))


@pytest.mark.parametrize("degrees", [1.0, 5.0, 20.0])
def test_small_input_angles_close(degrees):
    t = math.radians(degrees)
    dom = g.polygon([(0, 0), (1, 0), (math.cos(t), math.sin(t)), (-0.5, 0.5)])
    mesh = mw.triangulate(dom, 0.05, method="front")
    check(mesh, dom, straight=True)


def test_regions_keep_markers():
    outer = [(0, 0), (1, 0), (2, 0), (2, 1), (1, 1), (0, 1)]
    dom = g.polygon(outer, segments=[np.array([(1, 0), (1, 1)])], regions=[(0.5, 0.5, 7, None), (1.5, 0.5, 9, None)])
    mesh = mw.triangulate(dom, size=0.1, method="front")
    check(mesh, dom, straight=True)
    tm = mesh.cell_data["marker"]["triangle"]
    cen = mesh.points[mesh.cells["triangle"]].mean(axis=1)
    assert (tm[cen[:, 0] < 1] == 7).all() and (tm[cen[:, 0] > 1] == 9).all()


def test_max_area_bounds_the_spacing():
    # The front honours an area bound through the spacing (boundary included): nearly every
    # triangle is below it and closing triangles exceed it by less than twice.
    mesh = mw.triangulate("circle", method="front", max_area=0.002)
    check(mesh, g.circle())
    area = mesh.quality()["triangle"]["area"]
    assert np.mean(area <= 0.002) > 0.95 and area.max() < 2 * 0.002
    edges = mesh.points[mesh.cells["line"]]
    assert np.hypot(*(edges[:, 1] - edges[:, 0]).T).max() <= F.MAX_AREA_SIDE * math.sqrt(4 * 0.002 / math.sqrt(3))


def test_region_area_bounds_through_the_spacing():
    outer = [(0, 0), (2, 0), (2, 1), (0, 1)]
    inner = np.array([(0.25, 0.25), (0.75, 0.25), (0.75, 0.75), (0.25, 0.75), (0.25, 0.25)])
    dom = g.polygon(outer, segments=[inner], regions=[(0.5, 0.5, 7, 0.001), (1.5, 0.5, 9, None)])
    mesh = mw.triangulate(dom, size=0.2, method="front")
    check(mesh, dom, straight=True)
    cen = mesh.points[mesh.cells["triangle"]].mean(axis=1)
    box = (np.abs(cen[:, 0] - 0.5) < 0.25) & (np.abs(cen[:, 1] - 0.5) < 0.25)
    tm = mesh.cell_data["marker"]["triangle"]
    assert (tm[box] == 7).all() and (tm[~box] == 9).all()
    area = mesh.quality()["triangle"]["area"]
    assert np.mean(area[box] <= 0.001) > 0.95 and area[box].max() < 2 * 0.001
    # Outside the bounded region the size 0.2 takes over: far larger triangles.
    assert area[~box].max() > 5 * 0.001


def test_smoothing_after_front_keeps_validity():
    dom = g.circle()
    raw = mw.triangulate(dom, 0.1, method="front")
    smooth = mw.triangulate(dom, 0.1, method="front", smooth=5)
    check(smooth, dom)
    # The smoother's guarantee: the worst radius ratio never falls (the front has smoothed
    # its own nodes already, so the smallest angle may move either way).
    worst = [m.quality().summary()["triangle"]["radius_ratio"]["min"] for m in (smooth, raw)]
    assert worst[0] >= worst[1] - 1e-9


# ---------------------------------------------------------------------------- closure
def _square_ct(h=0.1):
    dom = g.polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    disc = dom.discretize(h)
    ct = cdt_build(disc.points, disc.segments)
    ct.classify(segment_sides=np.ones(len(disc.segments), dtype=int))
    return ct, dom


def _mesh_of(ct, fill):
    return ct.to_mesh(fill=fill)


def test_backoff_reopens_the_front_and_the_mesh_still_closes(monkeypatch):
    """Remove triangles mid-run (the back-off), then let the front finish: still a valid mesh."""
    ct, dom = _square_ct()
    monkeypatch.setattr(F, "SYNC_EVERY", 20)
    calls = {"n": 0}
    real = F._Front.advance

    def advance(self, par):
        code = real(self, par)
        if code == fk.R_SYNC and calls["n"] < 3:
            calls["n"] += 1
            fs = self.fs
            live = np.flatnonzero(fs.falive[: fs.meta[fk.M_NF]] == 1)
            live = live[fs.face[live, 0] != fs.face[live, 1]]
            before = int((fs.talive[: fs.meta[fk.M_NT]] == 1).sum())
            tbuf = np.empty(fk.BACKOFF_TRIS * fk.MAX_LEVEL, dtype=np.int32)
            vbuf = np.empty(3 * len(tbuf) + 2, dtype=np.int32)
            removed = fk._backoff(int(live[-1]), 2, fs, tbuf, vbuf)
            assert removed > 0
            assert int((fs.talive[: fs.meta[fk.M_NT]] == 1).sum()) == before - removed
        return code

    monkeypatch.setattr(F._Front, "advance", advance)
    # A varying size, so that the kernel stops for the field (where the test steps in).
    fill = F.advancing_front(ct, lambda xy: 0.08 + 0.04 * xy[:, 0])
    assert calls["n"] == 3
    check(_mesh_of(ct, fill), dom, straight=True)


def test_stuck_face_raises_naming_it(monkeypatch):
    # No new points (none keeps clear of the nodes) and a search box too small to see any
    # node but the next one along the front: a straight side cannot advance.
    ct, _ = _square_ct()
    monkeypatch.setattr(F, "SEARCH", 1e-9)
    monkeypatch.setattr(F, "CLEAR_NODE", 1e9)
    with pytest.raises(MeshingError, match=r"no valid triangle on front face \(.*\) -> \(.*\) after 0 back-offs"):
        F.advancing_front(ct, 0.1, max_backoff=0)


def test_point_cap_raises():
    ct, _ = _square_ct()
    with pytest.raises(MeshingError, match="max_points"):
        F.advancing_front(ct, 0.01, max_points=100)


@settings(deadline=None, max_examples=25)
@given(st.floats(0.03, 0.3), st.floats(1.0, 6.0), st.floats(0.0, 180.0))
def test_hypothesis_stretched_annulus(h, stretch, degrees):
    dom = g.polygon(
        [(np.cos(t) * 1.0, np.sin(t) * 1.0) for t in np.linspace(0, 2 * np.pi, 24, endpoint=False)],
        holes=[[(np.cos(t) * 0.4, -np.sin(t) * 0.4) for t in np.linspace(0, 2 * np.pi, 12, endpoint=False)]],
    )
    bg = BackgroundGrid.uniform(dom.bbox, h, stretch=stretch, direction=math.radians(degrees))
    mesh = mw.triangulate(dom, bg, method="front")
    check(mesh, dom, straight=True)


def test_cli_front_with_stretch(tmp_path):
    from meshwright.cli import main

    out = tmp_path / "r.vtu"
    assert main(["mesh", "rectangle", "-o", str(out), "--method", "front", "--size", "0.05", "--stretch", "3",
                 "--direction", "45"]) == 0
    mesh = mw.read(out)
    aspect, _ = _principal(mesh)
    assert np.median(aspect) == pytest.approx(3.0, rel=0.15)


def test_demo_writes_every_mesh_and_picture(tmp_path):
    from meshwright.cli import main

    assert main(["demo", str(tmp_path)]) == 0
    for stem in ("naca0012-front", "three-element-frontal-delaunay", "naca0012-delaunay"):
        assert (tmp_path / f"{stem}.vtu").exists() and (tmp_path / f"{stem}.png").exists()
        mw.read(tmp_path / f"{stem}.vtu").validate()
    for stem in ("three-element-quad-quadtree", "naca0012-quad-pairing"):
        assert (tmp_path / f"{stem}.vtu").exists() and (tmp_path / f"{stem}.png").exists()
        mesh = mw.read(tmp_path / f"{stem}.vtu")
        mesh.validate()
        assert len(mesh.cells["quad"]) > 0 and len(mesh.cells.get("triangle", ())) == 0


def test_demo_first_run_notice_reads_numba_cache_state(tmp_path, monkeypatch, capsys):
    """The notice appears exactly when the insertion kernel has no cache index on disk."""
    from meshwright.cli import demo

    mw.delaunay(np.random.default_rng(0).random((20, 2)))  # compiles or loads: the index exists
    assert demo.kernels_cached()
    monkeypatch.setattr(demo, "kernels_cached", lambda: False)
    monkeypatch.setattr(demo, "mesh_solids", lambda out: None)
    monkeypatch.setattr(demo, "triangulate", lambda *a, **k: (_ for _ in ()).throw(KeyboardInterrupt))
    with pytest.raises(KeyboardInterrupt):
        demo.run(type("A", (), {"directory": str(tmp_path), "seed": 0})())
    out = capsys.readouterr().out
    assert out.startswith("First run: Numba compiles")
    assert "circle (bowyer) ..." in out and "naca0012 (delaunay) ..." in out
