"""Tests of the 3-D Delaunay kernel (meshwright.tet) and the dimension dispatch of meshwright.delaunay.

The oracle is independent of the library: coordinates are turned into exact integers (every
float is a dyadic rational, so one common power of two makes them all integers) and the
orientation and in-sphere determinants are evaluated in Python integers over numpy object
arrays.  Validity of a tetrahedralization of the convex hull is checked as: every tet
positively oriented, neighbour links symmetric and across a shared face, boundary faces
forming a closed oriented surface with every point on or inside each of their planes, every
input point a vertex, and the empty-sphere property on every interior face (strict for points
in general position, non-strict where the input has cospherical points).  scipy (Qhull) is
the independent peer on random inputs.
"""

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import meshwright as mw
from meshwright.core.errors import DegenerateInputError, DuplicatePointError, InputError, MeshwrightError
from meshwright.tet import TET_ALGORITHMS, Tetrahedralization, delaunay3d

FACES = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]])


# ----------------------------------------------------------------------------- exact oracle
def _as_int(points):
    """(n, 3) object array of Python ints equal to ``points * 2**k`` exactly, for one k."""
    fr = [Fraction(float(x)) for x in np.asarray(points, dtype=np.float64).ravel()]
    den = max(f.denominator for f in fr)
    return np.array([f.numerator * (den // f.denominator) for f in fr], dtype=object).reshape(-1, 3)


def _det3(a, b, c):
    return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])


def _orient(P, a, b, c, d):
    """Exact det[b - a, c - a, d - a] for index arrays (vectorised over object arrays)."""
    A = P[a]
    return _det3((P[b] - A).T, (P[c] - A).T, (P[d] - A).T)


def _insphere(P, a, b, c, d, e):
    """Exact sign-carrying in-sphere value: > 0 iff e strictly inside the sphere of positive abcd."""
    E = P[e]
    rows = []
    for v in (a, b, c, d):
        q = P[v] - E
        rows.append((q[:, 0], q[:, 1], q[:, 2], q[:, 0] * q[:, 0] + q[:, 1] * q[:, 1] + q[:, 2] * q[:, 2]))
    (a0, a1, a2, a3), (b0, b1, b2, b3), (c0, c1, c2, c3), (d0, d1, d2, d3) = rows

    def m3(x, y, z):
        return _det3(x, y, z)

    # The lifted determinant is negative for a point inside a positively oriented tet's sphere.
    det = -(
        -a3 * m3((b0, b1, b2), (c0, c1, c2), (d0, d1, d2))
        + b3 * m3((a0, a1, a2), (c0, c1, c2), (d0, d1, d2))
        - c3 * m3((a0, a1, a2), (b0, b1, b2), (d0, d1, d2))
        + d3 * m3((a0, a1, a2), (b0, b1, b2), (c0, c1, c2))
    )
    return det


def test_oracle_calibration():
    # The regular corner tet of the unit cube: its centroid is inside, a far point outside.
    P = _as_int(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0.25, 0.25, 0.25], [3, 3, 3]]))
    a, b, c, d = (np.array([i]) for i in range(4))
    assert _orient(P, a, b, c, d)[0] > 0
    assert _insphere(P, a, b, c, d, np.array([4]))[0] > 0
    assert _insphere(P, a, b, c, d, np.array([5]))[0] < 0
    assert _insphere(P, a, b, c, d, np.array([1]))[0] == 0


def check_delaunay(T, points, strict=True):
    """Exact validity of T as the Delaunay tetrahedralization of the hull of ``points``."""
    tets = np.asarray(T.tetrahedra)
    nbr = np.asarray(T.neighbors)
    hull = np.asarray(T.hull)
    pts = np.asarray(T.points)
    nt = len(tets)
    assert tets.dtype == np.int32 and nbr.dtype == np.int32 and hull.dtype == np.int32
    assert tets.shape == nbr.shape == (nt, 4) and hull.shape[1] == 3
    P = _as_int(pts)
    # orientation
    assert all(_orient(P, tets[:, 0], tets[:, 1], tets[:, 2], tets[:, 3]) > 0)
    # every distinct input point is a vertex
    assert np.array_equal(np.unique(tets), np.arange(len(pts)))
    assert len(np.unique(np.asarray(points), axis=0)) == len(pts)
    # neighbour links: symmetric, across the same face
    t, k = np.nonzero(nbr >= 0)
    u = nbr[t, k]
    face = np.sort(tets[t[:, None], FACES[k]], axis=1)
    back = (nbr[u] == t[:, None])
    assert np.all(back.sum(axis=1) == 1)
    j = back.argmax(axis=1)
    assert np.array_equal(face, np.sort(tets[u[:, None], FACES[j]], axis=1))
    # boundary = hull faces, a closed oriented surface, every point on or inside each plane
    bt, bk = np.nonzero(nbr < 0)
    assert len(hull) == len(bt)
    assert np.array_equal(np.sort(hull, axis=1)[np.lexsort(np.sort(hull, axis=1).T)],
                          np.sort(tets[bt[:, None], FACES[bk]], axis=1)[np.lexsort(np.sort(tets[bt[:, None], FACES[bk]], axis=1).T)])
    edges = np.concatenate([hull[:, [0, 1]], hull[:, [1, 2]], hull[:, [2, 0]]])
    fwd = {tuple(e) for e in edges.tolist()}
    assert len(fwd) == len(edges) and all((b, a) in fwd for a, b in fwd)
    n = len(pts)
    for f in hull:
        o = _orient(P, np.full(n, f[0]), np.full(n, f[1]), np.full(n, f[2]), np.arange(n))
        assert all(o <= 0)
    # empty spheres on every interior face (each pair once)
    once = t < u
    t, k, u, j = t[once], k[once], u[once], j[once]
    far = tets[u, j]
    s = _insphere(P, tets[t, 0], tets[t, 1], tets[t, 2], tets[t, 3], far)
    assert all(s < 0) if strict else all(s <= 0)
    return True


def tet_set(T):
    return {tuple(x) for x in np.sort(np.asarray(T.tetrahedra), axis=1).tolist()}


def _lattice(k, offset=0.0, scale=1.0):
    g = np.stack(np.meshgrid(*[np.arange(k, dtype=float)] * 3, indexing="ij"), -1).reshape(-1, 3)
    return g * scale + offset


# ----------------------------------------------------------------------------- cross-checks
@pytest.mark.parametrize("algorithm", sorted(TET_ALGORITHMS))
@pytest.mark.parametrize("n, seed", [(5, 0), (60, 1), (700, 2)])
def test_random_points_match_scipy(algorithm, n, seed):
    spatial = pytest.importorskip("scipy.spatial")
    pts = np.random.default_rng(seed).random((n, 3))
    T = delaunay3d(pts, algorithm=algorithm, seed=seed)
    check_delaunay(T, pts)
    assert tet_set(T) == {tuple(x) for x in np.sort(spatial.Delaunay(pts).simplices, axis=1).tolist()}


def test_public_door_dispatches_on_dimension():
    pts3 = np.random.default_rng(4).random((40, 3))
    T = mw.delaunay(pts3, algorithm="watson", seed=3)
    assert isinstance(T, Tetrahedralization) and T.algorithm == "watson"
    assert isinstance(mw.delaunay(pts3[:, :2]), mw.Triangulation)
    assert set(TET_ALGORITHMS) == set(mw.DELAUNAY_ALGORITHMS)
    with pytest.raises(InputError, match="3-D points only"):
        mw.delaunay(pts3[:, :2], superstructure="box")


@pytest.mark.parametrize(
    "name, pts, strict",
    [
        ("lattice 10^3", _lattice(10), False),
        ("lattice 6^3 offset 1e9", _lattice(6, offset=1e9), False),
        ("lattice 6^3 scaled 2^30", _lattice(6, scale=2.0**30), False),
        ("lattice 6^3 scaled 2^-30", _lattice(6, scale=2.0**-30), False),
        ("random offset 1e9", 1e9 + np.random.default_rng(5).random((300, 3)), True),
    ],
)
def test_degenerate_families_are_exactly_delaunay_and_watson_equals_bowyer(name, pts, strict):
    B = delaunay3d(pts, algorithm="bowyer", seed=1)
    check_delaunay(B, pts, strict=strict)
    W = delaunay3d(pts, algorithm="watson", seed=1)
    assert tet_set(W) == tet_set(B)


@pytest.mark.parametrize("scale", [2.0**-140, 2.0**190])
def test_exact_at_both_ends_of_the_coordinate_range(scale):
    # Lattice points scaled so every nonzero coordinate stays in [2**-148, 2**200]; Watson's
    # float32 spheres underflow or overflow there and must fall back to the exact test.
    cells = np.random.default_rng(3).permutation(32**3)[:150]
    pts = np.column_stack([cells // 1024 + 1, (cells // 32) % 32 + 1, cells % 32 + 1]) / 32.0 * scale
    B = delaunay3d(pts, seed=0)
    check_delaunay(B, pts, strict=False)
    assert tet_set(delaunay3d(pts, algorithm="watson", seed=0)) == tet_set(B)


def test_lattice_15_cubed():
    pts = _lattice(15)
    T = delaunay3d(pts, seed=2)
    check_delaunay(T, pts, strict=False)
    # The hull of the lattice is its cube: 6 faces of 14 x 14 squares, two triangles each.
    assert len(T.hull) == 6 * 14 * 14 * 2


def _sphere_points():
    """Every integer point on the sphere x^2 + y^2 + z^2 = 21^2 (exactly cospherical)."""
    r = 21
    g = np.arange(-r, r + 1)
    x, y, z = np.meshgrid(g, g, g, indexing="ij")
    on = x * x + y * y + z * z == r * r
    return np.column_stack([x[on], y[on], z[on]]).astype(float)


def test_points_on_one_sphere():
    pts = _sphere_points()
    assert len(pts) > 100
    B = delaunay3d(pts, seed=3)
    check_delaunay(B, pts, strict=False)
    assert tet_set(delaunay3d(pts, algorithm="watson", seed=3)) == tet_set(B)
    # With the centre and a few interior points added, still valid.
    more = np.vstack([pts, [[0.0, 0.0, 0.0], [1.0, 2.0, 3.0], [-5.0, 4.0, 0.0]]])
    check_delaunay(delaunay3d(more, seed=4), more, strict=False)
    # The centre inserted last empties every tet (a cavity larger than its boundary: freed
    # slots, and every scratch array grown on the way).
    B.insert([0.0, 0.0, 0.0])
    check_delaunay(B, np.vstack([pts, [[0.0, 0.0, 0.0]]]), strict=False)
    assert len(B.tetrahedra) == len(B.hull)


def test_coplanar_subsets_and_points_on_hull_faces():
    rng = np.random.default_rng(6)
    plane = np.column_stack([rng.integers(0, 8, 120), rng.integers(0, 8, 120), np.zeros(120)]).astype(float)
    top = plane + [0, 0, 7]
    side = np.column_stack([rng.integers(0, 8, 60), np.zeros(60), rng.integers(0, 8, 60)]).astype(float)
    inner = rng.integers(1, 7, (40, 3)).astype(float)
    pts = np.unique(np.vstack([plane, top, side, inner]), axis=0)
    pts = pts[rng.permutation(len(pts))]
    for alg in TET_ALGORITHMS:
        T = delaunay3d(pts, algorithm=alg, seed=7)
        check_delaunay(T, pts, strict=False)


def test_seeds_give_valid_results_on_degenerate_input():
    pts = _lattice(5)
    for seed in range(3):
        check_delaunay(delaunay3d(pts, seed=seed), pts, strict=False)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(*[st.integers(0, 3)] * 3), min_size=4, max_size=40), st.integers(0, 3))
def test_small_integer_sets_are_exactly_delaunay(cells, seed):
    # Points of a 4 x 4 x 4 lattice, with repeats: every degeneracy at once (coincident,
    # collinear, coplanar and cospherical points, points on hull faces and edges).
    pts = np.array(cells, dtype=float)
    try:
        B = delaunay3d(pts, seed=seed)
    except DegenerateInputError:
        flat = pts - pts[0]
        assert np.linalg.matrix_rank(flat) < 3  # only when no tetrahedron exists
        return
    check_delaunay(B, np.unique(pts, axis=0), strict=False)
    assert np.array_equal(B.points[B.index_map], pts)
    assert tet_set(delaunay3d(pts, algorithm="watson", seed=seed)) == tet_set(B)


# ----------------------------------------------------------------------------- incremental
def test_insert_equals_batch_in_general_position():
    pts = np.random.default_rng(8).random((400, 3))
    batch = delaunay3d(pts, seed=0)
    inc = delaunay3d(pts[:50], seed=1)
    ids = inc.insert(pts[50:300])
    assert np.array_equal(ids, np.arange(50, 300))
    for p in pts[300:320]:
        inc.insert(p)
    inc.insert(pts[320:])
    assert tet_set(inc) == tet_set(batch)
    check_delaunay(inc, pts)


def test_insert_outside_the_hull_and_on_a_lattice():
    pts = _lattice(4)
    T = delaunay3d(pts, seed=0)
    new = np.array([[5.0, 1.0, 1.0], [1.5, 1.5, 1.5], [3.0, 3.0, 0.0], [-1.0, -1.0, -1.0]])
    ids = T.insert(new)
    assert np.array_equal(ids, [64, 65, 3 * 16 + 3 * 4, 66])  # (3, 3, 0) is lattice vertex 60
    check_delaunay(T, np.vstack([pts, new]), strict=False)


def test_duplicates_merge_and_reject():
    pts = np.random.default_rng(9).random((30, 3))
    dup = np.vstack([pts, pts[[3, 7]], pts[3]])
    T = delaunay3d(dup, seed=0)
    assert len(T.points) == 30
    assert np.array_equal(T.index_map, np.concatenate([np.arange(30), [3, 7, 3]]))
    check_delaunay(T, pts)
    with pytest.raises(DuplicatePointError, match="coincident points: 3 and 30"):
        delaunay3d(dup, duplicates="reject")
    assert np.array_equal(T.insert(np.vstack([pts[5], [0.5, 0.5, 0.5], [0.5, 0.5, 0.5]])), [5, 30, 30])


def test_duplicates_within_a_lattice_keep_the_first():
    pts = _lattice(4)
    dup = np.vstack([pts, pts[::-1]])
    T = delaunay3d(dup, seed=5)
    assert np.array_equal(T.index_map, np.concatenate([np.arange(64), np.arange(64)[::-1]]))
    check_delaunay(T, pts, strict=False)


def test_locate():
    pts = np.random.default_rng(10).random((300, 3))
    T = delaunay3d(pts, seed=0)
    q = np.random.default_rng(11).random((200, 3)) * 1.2 - 0.1
    found = T.locate(q)
    assert found.dtype == np.int32 and found.shape == (200,)
    P = _as_int(np.vstack([T.points, q]))
    n = len(T.points)
    tets = np.asarray(T.tetrahedra)
    ins = found >= 0
    qi = np.arange(n, n + len(q))[ins]
    tt = tets[found[ins]]
    for k in range(4):
        f = FACES[k]
        assert all(_orient(P, tt[:, f[0]], tt[:, f[1]], tt[:, f[2]], qi) <= 0)
    # a query reported outside lies strictly outside some hull face's plane
    for i in np.flatnonzero(~ins):
        h = np.asarray(T.hull)
        o = _orient(P, h[:, 0], h[:, 1], h[:, 2], np.full(len(h), n + i))
        assert any(o > 0)
    assert T.locate(T.points[17]) >= 0 and T.locate([5.0, 5.0, 5.0]) == -1


# ----------------------------------------------------------------------------- superstructure
def test_box_superstructure_loses_hull_tets():
    pts = np.random.default_rng(12).random((400, 3))
    ghost = delaunay3d(pts, seed=0)
    box = delaunay3d(pts, seed=0, superstructure="box")
    gs, bs = tet_set(ghost), tet_set(box)
    assert bs < gs  # a strict subset: hull tets whose circumsphere holds a box point are gone
    # the box result is still a consistent tetrahedralization of its own region
    nb = np.asarray(box.neighbors)
    t, k = np.nonzero(nb >= 0)
    assert np.all((nb[nb[t, k]] == t[:, None]).sum(axis=1) == 1)
    edges = np.concatenate([box.hull[:, [0, 1]], box.hull[:, [1, 2]], box.hull[:, [2, 0]]])
    fwd = {tuple(e) for e in edges.tolist()}
    assert len(fwd) == len(edges) and all((b, a) in fwd for a, b in fwd)
    # insertion inside the box works, outside is refused naming the point
    box.insert([[0.5, 0.5, 0.25]])
    with pytest.raises(InputError, match="point 1 .* not strictly inside the box"):
        box.insert([[0.5, 0.5, 0.5], [10.0, 0.0, 0.0]])
    assert box.locate([0.5, 0.5, 0.25]) >= 0


# ----------------------------------------------------------------------------- mesh and hull
def test_to_mesh_and_hull_orientation():
    pts = np.random.default_rng(13).random((100, 3))
    T = delaunay3d(pts)
    m = T.to_mesh()
    assert m.cells_of("tetra").shape == T.tetrahedra.shape
    m.validate(check_delaunay=True)  # Mesh's own tetra checks, written independently
    delaunay3d(_lattice(4), superstructure="box").to_mesh().validate(check_delaunay=True)
    assert np.array_equal(m.points, T.points)
    # outward hull faces: the hull's signed volume (divergence theorem) equals the tets' volume
    p = T.points
    h = T.hull
    vol_hull = np.einsum("ij,ij->i", p[h[:, 0]], np.cross(p[h[:, 1]], p[h[:, 2]])).sum() / 6
    t = T.tetrahedra
    vol_tets = np.einsum("ij,ij->i", p[t[:, 1]] - p[t[:, 0]], np.cross(p[t[:, 2]] - p[t[:, 0]], p[t[:, 3]] - p[t[:, 0]])).sum() / 6
    assert vol_hull == pytest.approx(vol_tets) and vol_tets > 0
    with pytest.raises(ValueError):
        T.tetrahedra[0, 0] = 1


# ----------------------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    "bad, error, match",
    [
        ([[0, 0, 0], [1, 0, 0], [np.nan, 1, 0], [0, 0, 1]], InputError, "point 2"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, np.inf]], InputError, "point 3"),
        (np.zeros((5, 4)), InputError, "shape"),
        (np.zeros(6), InputError, "shape"),
        ([[0, 0, 0], [1, "x", 0], [0, 1, 0], [0, 0, 1]], InputError, "numbers"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], DegenerateInputError, "at least 4"),
        ([[1, 2, 3]] * 5, DegenerateInputError, "coincide"),
        ([[0, 0, 0], [1, 1, 1], [2, 2, 2], [3, 3, 3], [0, 0, 0]], DegenerateInputError, "collinear"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [5, 7, 0]], DegenerateInputError, "coplanar"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1e-300]], InputError, "range"),
    ],
)
def test_bad_input(bad, error, match):
    with pytest.raises(error, match=match):
        mw.delaunay(bad)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"algorithm": "qhull"}, "algorithm"),
        ({"duplicates": "keep"}, "duplicates"),
        ({"superstructure": "sphere"}, "superstructure"),
        ({"seed": -1}, "seed"),
        ({"seed": 1.5}, "seed"),
    ],
)
def test_bad_options(kwargs, match):
    with pytest.raises(InputError, match=match):
        mw.delaunay(np.random.default_rng(0).random((10, 3)), **kwargs)


def test_bad_insert_and_locate_arguments():
    T = delaunay3d(np.random.default_rng(14).random((20, 3)))
    with pytest.raises(InputError, match="point 1"):
        T.insert([[0.5, 0.5, 0.5], [np.nan, 0, 0]])
    with pytest.raises(InputError, match="shape"):
        T.insert(np.zeros((2, 2)))
    with pytest.raises(InputError, match="shape"):
        T.locate(np.zeros((2, 4)))
    with pytest.raises(MeshwrightError):
        T.locate("abc")
    assert T.insert(np.empty((0, 3))).shape == (0,)


# ----------------------------------------------------------------------------- command line
def test_cli_tetrahedralizes_xyz_files(tmp_path, capsys):
    from meshwright.cli import main
    from meshwright.io import read

    pts = np.random.default_rng(15).random((50, 3))
    src = tmp_path / "cloud.xyz"
    np.savetxt(src, pts)
    out = tmp_path / "cloud.vtu"
    assert main(["delaunay", str(src), "-o", str(out), "--algorithm", "watson"]) == 0
    assert "tetrahedra" in capsys.readouterr().out
    mesh = read(out)
    assert len(mesh.cells_of("tetra")) == len(delaunay3d(pts, algorithm="watson").tetrahedra)
    assert main(["delaunay", str(src), "--superstructure", "box"]) == 0
    flat = tmp_path / "flat.xyz"
    np.savetxt(flat, np.column_stack([pts[:, :2], np.ones(50)]))
    assert main(["delaunay", str(flat)]) == 0
    assert "triangles" in capsys.readouterr().out
    assert main(["delaunay", str(flat), "--superstructure", "box"]) == 2
    coplanar = tmp_path / "coplanar.xyz"
    ij = np.random.default_rng(16).integers(0, 100, (50, 2))
    np.savetxt(coplanar, np.column_stack([ij, ij[:, 0] + 2 * ij[:, 1]]))  # exactly on one plane
    assert main(["delaunay", str(coplanar)]) == 2
    assert "coplanar" in capsys.readouterr().err


def test_kernel_single_point_entry_and_need_space():
    # insert_vertex asks for room before changing anything, then inserts after grow().
    from meshwright.tet._kernel3d import M_NEED, NEED_SPACE, NEED_VERTS, insert_vertex
    from meshwright.tet._build3d import compact
    from meshwright.tet.tetrahedralization import grow

    pts = np.random.default_rng(17).random((60, 3))
    T = delaunay3d(pts, seed=0)
    s = T._s
    n = len(T.points)
    P = np.vstack([s.pts[:n], [[0.5, 0.5, 0.5]]])
    s = s._replace(pts=P)
    tet_before = s.tet.copy()
    st = insert_vertex(s, n, 0)
    assert st == NEED_SPACE and s.meta[M_NEED] == NEED_VERTS
    assert np.array_equal(s.tet, tet_before)
    s = grow(s)
    st = insert_vertex(s, n, 0)
    assert st >= 0 and n in s.tet[4 * st : 4 * st + 4]
    T._s = s
    T._nv = n + 1
    T._nt = compact(s.tet, s.nbr, s.sph, s.meta)
    T._cache = {}
    assert tet_set(T) == tet_set(delaunay3d(np.vstack([pts, [[0.5, 0.5, 0.5]]]), seed=3))


def test_inconsistent_structure_is_reported_not_corrupted():
    # Vertices moved behind the kernel's back make tets inverted and spheres wrong: the
    # cavity check (Euler count, paired edges) must refuse with an error naming the point,
    # never crash, hang or carry on silently.
    from meshwright.core.errors import MeshingError

    rng = np.random.default_rng(18)
    T = delaunay3d(rng.random((200, 3)), seed=0)
    T._s.pts[rng.choice(200, 20, replace=False)] = rng.random((20, 3))
    with pytest.raises(MeshingError, match=r"inserting point \d+ at \(.*\) met an inconsistent cavity"):
        T.insert(rng.random((200, 3)))
