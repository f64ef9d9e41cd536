"""Sliver removal (chapter 18.1.1): hand-built flips (Figure 18.1.4's case, 2-3, 4-4) and
real Delaunay meshes from scipy's Qhull (random, near-cospherical, jittered lattice).

Oracles independent of the code under test: volumes by numpy determinants, r/R by
core.quality (a separate implementation from the kernels'), hull faces as sets."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from meshwright.core.errors import InputError
from meshwright.core.mesh import Mesh
from meshwright.tet.slivers import LEFT_REASONS, remove_slivers

spatial = pytest.importorskip("scipy.spatial")


def positive(points, tets):
    p = points[tets]
    neg = np.linalg.det(p[:, 1:] - p[:, :1]) < 0
    tets = np.array(tets).copy()
    tets[neg, 0], tets[neg, 1] = tets[neg, 1], tets[neg, 0].copy()
    return tets


def volume(mesh):
    p = mesh.points[mesh.tetra]
    return np.linalg.det(p[:, 1:] - p[:, :1]).sum() / 6.0


def ratio(mesh):
    return mesh.quality()["tetra"]["sliver_ratio"]


def hull_set(mesh):
    return {tuple(sorted(f)) for f in mesh.boundary_facets().tolist()}


def check_result(before, after, report):
    after.validate()
    assert volume(after) == pytest.approx(volume(before), rel=1e-12)
    assert report.found - report.removed_by_flip - report.removed_by_move + report.created == report.left
    assert report.left == int(np.count_nonzero(ratio(after) < report.threshold))
    assert sum(report.left_reasons.values()) == report.left
    assert ratio(after).min() >= ratio(before).min()
    if not report.moves:
        np.testing.assert_array_equal(after.points, before.points)
        assert hull_set(after) == hull_set(before)


def test_figure_18_1_4_sliver_between_two_tets_sharing_e():
    # Edge BD along z; A, C, E around it.  ABCD is flat (all four points within 0.02 of
    # the plane y = 0); its neighbours ABDE and BCDE share E: {ABCD, ABDE, BCDE} -> {ABCE, ACDE}.
    A, B, C, D, E = [1, 0, 0], [0, 0, -1], [-1, 0.02, 0], [0, 0, 1], [0, -1, 0]
    pts = np.array([A, B, C, D, E], float)
    a, b, c, d, e = range(5)
    mesh = Mesh(pts, {"tetra": positive(pts, np.array([[a, b, c, d], [a, b, d, e], [b, c, d, e]]))})
    assert ratio(mesh)[0] < 0.01
    out, report = remove_slivers(mesh)
    check_result(mesh, out, report)
    assert {tuple(sorted(t)) for t in out.tetra.tolist()} == {(a, b, c, e), (a, c, d, e)}
    assert report.flips["3-2"] == 1 and report.found == 1 and report.removed_by_flip == 1 and report.left == 0
    assert ratio(out).min() > 0.1


def test_two_three_flip_removes_a_cap():
    # d just above the centre of triangle abc, e far below: 2 tets -> 3 around edge de.
    s = np.sqrt(3) / 2
    pts = np.array([[1, 0, 0], [-0.5, s, 0], [-0.5, -s, 0], [0, 0, 0.01], [0, 0, -1]])
    mesh = Mesh(pts, {"tetra": positive(pts, np.array([[0, 1, 2, 3], [0, 1, 2, 4]]))})
    out, report = remove_slivers(mesh)
    check_result(mesh, out, report)
    assert report.flips["2-3"] == 1 and len(out.tetra) == 3
    assert all(3 in t and 4 in t for t in out.tetra.tolist())
    assert ratio(out).min() > 10 * ratio(mesh).min()


def test_four_four_flip_around_an_edge_of_degree_four():
    # Ring of four around the z axis; w0 and w1 are almost opposite, so tet (p, q, w0, w1) is a sliver.
    ang = np.radians([0.0, 178.5, 240.0, 300.0])
    ring = np.column_stack([np.cos(ang), np.sin(ang), np.zeros(4)])
    pts = np.vstack([[[0, 0, -1], [0, 0, 1]], ring])
    tets = positive(pts, np.array([[0, 1, 2 + i, 2 + (i + 1) % 4] for i in range(4)]))
    mesh = Mesh(pts, {"tetra": tets})
    assert np.count_nonzero(ratio(mesh) < 0.01) == 1
    out, report = remove_slivers(mesh)
    check_result(mesh, out, report)
    assert report.flips["4-4"] == 1 and len(out.tetra) == 4
    assert not any(0 in t and 1 in t for t in out.tetra.tolist())  # the edge pq is gone
    assert report.left == 0


def test_flip_keeps_locked_faces_edges_and_regions():
    A, B, C, D, E = [1, 0, 0], [0, 0, -1], [-1, 0.02, 0], [0, 0, 1], [0, -1, 0]
    pts = np.array([A, B, C, D, E], float)
    tets = positive(pts, np.array([[0, 1, 2, 3], [0, 1, 3, 4], [1, 2, 3, 4]]))
    base = Mesh(pts, {"tetra": tets})
    for extra in ({"line": [[1, 3]]}, {"triangle": [[1, 3, 4]]}):
        mesh = Mesh(pts, {"tetra": tets, **extra})
        out, report = remove_slivers(mesh)
        assert report.flips["3-2"] == 0 and report.left == 1
        assert report.left_reasons["boundary"] == 1
        np.testing.assert_array_equal(np.sort(out.tetra, axis=1), np.sort(base.tetra, axis=1))
    regions = Mesh(pts, {"tetra": tets}, cell_data={"marker": {"tetra": [1, 1, 2]}})
    out, report = remove_slivers(regions)
    assert report.left == 1 and len(out.tetra) == 3
    np.testing.assert_array_equal(out.cell_data["marker"]["tetra"], [1, 1, 2])
    same = Mesh(pts, {"tetra": tets}, cell_data={"marker": {"tetra": [5, 5, 5]}})
    out, report = remove_slivers(same)
    assert report.left == 0 and out.cell_data["marker"]["tetra"].tolist() == [5, 5]


def scipy_mesh(pts):
    return Mesh(pts, {"tetra": positive(pts, spatial.Delaunay(pts).simplices)})


def random_points(n=600, seed=0):
    return np.random.default_rng(seed).random((n, 3))


def sphere_points(n=400, seed=1):
    rng = np.random.default_rng(seed)
    v = rng.normal(size=(n, 3))
    shell = v / np.linalg.norm(v, axis=1)[:, None] * (1 + 1e-3 * rng.random((n, 1)))
    # A few interior points so that some vertices may move.
    inner = rng.normal(size=(n // 4, 3))
    inner = inner / np.linalg.norm(inner, axis=1)[:, None] * rng.uniform(0.2, 0.8, (n // 4, 1))
    return np.vstack([shell, inner])


def lattice_points(k=7, seed=2):
    g = np.stack(np.meshgrid(*[np.arange(k, dtype=float)] * 3, indexing="ij"), axis=-1).reshape(-1, 3)
    return g + 1e-3 * np.random.default_rng(seed).standard_normal(g.shape)


@pytest.mark.parametrize("make", [random_points, sphere_points, lattice_points])
def test_real_delaunay_meshes(make):
    mesh = scipy_mesh(make())
    before = int(np.count_nonzero(ratio(mesh) < 0.01))
    assert before > 0  # slivers are common in these families
    out, report = remove_slivers(mesh)
    check_result(mesh, out, report)
    assert report.found == before
    assert report.left < before
    moved = np.flatnonzero(np.any(out.points != mesh.points, axis=1))
    boundary = np.unique(mesh.boundary_facets())
    assert not np.isin(moved, boundary).any()
    # Flips keep the hull; moves only touch interior vertices, so the hull faces are the same.
    assert hull_set(out) == hull_set(mesh)
    assert set(report.left_reasons) == set(LEFT_REASONS)


def test_lattice_without_moves_uses_flips_only():
    mesh = scipy_mesh(lattice_points(6))
    out, report = remove_slivers(mesh, move_points=False)
    check_result(mesh, out, report)
    assert report.moves == 0 and report.removed_by_move == 0
    assert sum(report.flips.values()) > 0 and report.left < report.found
    assert report.left_reasons["no_improving_move"] == 0
    # Every left sliver is explained by its vertices: all on the boundary, or not movable.
    assert report.left_reasons["boundary"] + report.left_reasons["not_movable"] == report.left


def test_threshold_one_third_flags_everything_and_still_returns_a_valid_mesh():
    mesh = scipy_mesh(random_points(150, seed=5))
    out, report = remove_slivers(mesh, threshold=1 / 3, max_iter=3)
    check_result(mesh, out, report)
    assert report.found == len(mesh.tetra)
    assert "removed by flip" in str(report)


def test_arguments_are_checked():
    mesh = scipy_mesh(random_points(40, seed=3))
    with pytest.raises(InputError, match="threshold must lie"):
        remove_slivers(mesh, threshold=0.5)
    with pytest.raises(InputError, match="threshold must be a number"):
        remove_slivers(mesh, threshold="0.1")
    with pytest.raises(InputError, match="max_iter"):
        remove_slivers(mesh, max_iter=0)
    with pytest.raises(InputError, match="move_points"):
        remove_slivers(mesh, move_points=1)
    with pytest.raises(InputError, match="movable given with move_points=False"):
        remove_slivers(mesh, move_points=False, movable=np.zeros(40, bool))
    with pytest.raises(InputError, match=r"movable must be a \(40,\) bool"):
        remove_slivers(mesh, movable=np.zeros(39, bool))
    v = int(mesh.boundary_facets()[0, 0])
    with pytest.raises(InputError, match=f"movable marks vertex {v} "):
        remove_slivers(mesh, movable=np.arange(40) == v)
    with pytest.raises(InputError, match="3-D mesh with tetra"):
        remove_slivers(Mesh(np.eye(3)[:, :2], {"triangle": [[0, 1, 2]]}))
    with pytest.raises(InputError, match="cell_data 'q'"):
        remove_slivers(Mesh(mesh.points, {"tetra": mesh.tetra}, cell_data={"q": {"tetra": np.zeros(len(mesh.tetra))}}))
    with pytest.raises(InputError, match="must be a meshwright Mesh"):
        remove_slivers(mesh.tetra)
    with pytest.raises(InputError, match="radius_edge must be finite and at least"):
        remove_slivers(mesh, radius_edge=0.5)
    with pytest.raises(InputError, match="radius_edge must be a number"):
        remove_slivers(mesh, radius_edge="2")


def test_radius_edge_cap_is_not_exceeded_by_flips_or_moves():
    mesh = scipy_mesh(random_points(300, seed=11))
    p = mesh.points[mesh.tetra]
    u, v, w = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0], p[:, 3] - p[:, 0]
    det = np.einsum("ij,ij->i", u, np.cross(v, w))

    def radius_edge(points, tets):
        q = points[tets]
        a, b, c = q[:, 1] - q[:, 0], q[:, 2] - q[:, 0], q[:, 3] - q[:, 0]
        d = np.einsum("ij,ij->i", a, np.cross(b, c))
        o = (np.einsum("ij,ij->i", a, a)[:, None] * np.cross(b, c) + np.einsum("ij,ij->i", b, b)[:, None] * np.cross(c, a)
             + np.einsum("ij,ij->i", c, c)[:, None] * np.cross(a, b)) / (2 * d[:, None])
        e = np.stack([np.linalg.norm(q[:, i] - q[:, j], axis=1) for i, j in ((0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3))], 1)
        return np.linalg.norm(o, axis=1) / e.min(axis=1)

    assert (det > 0).all()
    before = radius_edge(mesh.points, mesh.tetra)
    bound = float(np.quantile(before, 0.9))
    free, _ = remove_slivers(mesh, threshold=0.2, max_iter=4)
    capped, report = remove_slivers(mesh, threshold=0.2, max_iter=4, radius_edge=bound)
    check_result(mesh, capped, report)
    # no operation lifts a tet over the bound: tets over it after the stage are at most as
    # many as before (those the stage could not repair), and fewer than without the cap
    over = int((radius_edge(capped.points, capped.tetra) > bound).sum())
    assert over <= int((before > bound).sum())
    assert over <= int((radius_edge(free.points, free.tetra) > bound).sum())


def test_on_meshwright_delaunay_of_points_on_a_sphere():
    import meshwright as mw

    rng = np.random.default_rng(4)
    v = rng.normal(size=(300, 3))
    pts = np.vstack([v / np.linalg.norm(v, axis=1)[:, None], 0.5 * rng.random((60, 3)) - 0.25])
    mesh = mw.delaunay(pts).to_mesh()
    mesh.validate(check_delaunay=True)
    out, report = remove_slivers(mesh)
    check_result(mesh, out, report)
    assert report.found > 0 and report.left < report.found
    assert hull_set(out) == hull_set(mesh)


def test_only_the_vertices_of_the_mask_move_and_the_input_is_untouched():
    mesh = scipy_mesh(lattice_points(6, seed=3))
    points, tets = mesh.points.copy(), mesh.tetra.copy()
    interior = np.ones(mesh.n_points, bool)
    interior[np.unique(mesh.boundary_facets())] = False
    mask = interior & (np.arange(mesh.n_points) % 2 == 0)
    out, report = remove_slivers(mesh, movable=mask)
    check_result(mesh, out, report)
    moved = np.any(out.points != mesh.points, axis=1)
    assert report.moves > 0 and moved.any() and not (moved & ~mask).any()
    np.testing.assert_array_equal(mesh.points, points)
    np.testing.assert_array_equal(mesh.tetra, tets)


@settings(max_examples=25, deadline=None)
@given(
    st.integers(0, 2**32 - 1),
    st.integers(20, 200),
    st.sampled_from(["uniform", "flat", "lattice"]),
    st.floats(0.005, 1 / 3),
    st.booleans(),
)
def test_any_delaunay_mesh_stays_valid(seed, n, kind, threshold, move_points):
    rng = np.random.default_rng(seed)
    if kind == "uniform":
        pts = rng.random((n, 3))
    elif kind == "flat":  # a thin slab: slivers everywhere
        pts = rng.random((n, 3)) * [1, 1, 0.05]
    else:
        k = max(3, round(n ** (1 / 3)))
        pts = lattice_points(k, seed=seed)
    mesh = scipy_mesh(pts)
    out, report = remove_slivers(mesh, threshold=threshold, move_points=move_points, max_iter=10)
    check_result(mesh, out, report)
    assert hull_set(out) == hull_set(mesh)
