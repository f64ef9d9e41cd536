"""tetrahedralize on the surfaces a seeded fuzz (scripts/fuzz_tet.py) found failing (issue 11).

Each reproducer in ``tests/data/tet_fuzz`` is a surface and the keyword arguments it failed
with: coarse rotated spheres with a size, where flat tets on the surface made size splits
cascade and refinement starved ("did not finish in 400 rounds"), and extruded star polygons
whose wall midpoints coincided with earlier vertices or whose recovery cascaded to the guard;
``extruded_crease170`` is fuzz case 46 (seed 7), two walls meeting at a 170 degree crease,
whose recovery cascade failed before refinement moved into the queue kernel (and whose
sliver stage then took 14 s of vertex moves for tets exempt from the radius-edge bound);
``extruded_notch_shells`` is fuzz case 40 (seed 22), a thin notch whose two bottom edges'
midpoint splits made each other missing until the guard (concentric shells fixed it).
``tet_sharp_notch.npz`` (seed 21 case 18, a 6.46-degree notch) is refused with the edge and angle.
Oracles are the test's own: volumes by numpy triple products against the divergence theorem
on the input faces, areas per marker, exact rational in-circle tests for the Lawson flips.
"""

import ast
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

import meshwright as mw
from meshwright.geometry import Surface
from meshwright.tet.recovery import lawson, unique_edges

DATA = Path(__file__).parent / "data" / "tet_fuzz"
CASES = sorted(p.stem for p in DATA.glob("*.npz"))


def _load(name):
    d = np.load(DATA / f"{name}.npz")
    return Surface(d["points"], d["triangles"]), ast.literal_eval(str(d["kw"]))


def _tet_volumes(points, tets):
    p = points[tets]
    return np.einsum("ij,ij->i", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])) / 6.0


def _areas(points, faces):
    p = points[faces]
    return 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)


def test_reproducers_are_there():
    assert len(CASES) >= 5


@pytest.mark.parametrize("name", CASES)
def test_fuzz_reproducer_meshes(name):
    surf, kw = _load(name)
    mesh = mw.tetrahedralize(surf, **kw)
    mesh.validate()
    vol = _tet_volumes(mesh.points, mesh.cells["tetra"])
    assert (vol > 0).all()
    p = surf.points[surf.triangles]
    enclosed = np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6.0
    assert vol.sum() == pytest.approx(enclosed, rel=1e-12)
    out = _areas(mesh.points, mesh.cells["triangle"])
    inp = _areas(surf.points, surf.triangles)
    marks = mesh.cell_data["marker"]["triangle"]
    for m in np.unique(surf.markers):
        assert out[marks == m].sum() == pytest.approx(inp[surf.markers == m].sum(), rel=1e-12)
    # refinement happened: the size bound was honoured somewhere inside
    assert mesh.n_points > surf.n_points


def _incircle_exact(a, b, c, d):
    """Sign of d inside the circle of a, b, c (counter-clockwise), by rationals."""
    rows = []
    for q in (a, b, c):
        x, y = Fraction(q[0]) - Fraction(d[0]), Fraction(q[1]) - Fraction(d[1])
        rows.append((x, y, x * x + y * y))
    (a1, a2, a3), (b1, b2, b3), (c1, c2, c3) = rows
    det = a1 * (b2 * c3 - b3 * c2) - a2 * (b1 * c3 - b3 * c1) + a3 * (b1 * c2 - b2 * c1)
    return (det > 0) - (det < 0)


def _orient_exact(a, b, c):
    det = (Fraction(b[0]) - Fraction(a[0])) * (Fraction(c[1]) - Fraction(a[1])) - (Fraction(b[1]) - Fraction(a[1])) * (Fraction(c[0]) - Fraction(a[0]))
    return (det > 0) - (det < 0)


def test_lawson_flips_subfaces_to_the_planar_delaunay_triangulation():
    rng = np.random.default_rng(3)
    # one input face on the plane z = 0.25 x + 0.5 y (dominant axis z), random points inside
    xy = np.vstack([[0, 0], [4, 0], [0, 4], rng.random((40, 2)) * 1.9 + 0.05])
    pts = np.c_[xy, 0.25 * xy[:, 0] + 0.5 * xy[:, 1]]
    # scipy's planar Delaunay triangulation, spoiled by flipping interior edges the wrong way
    scipy_spatial = pytest.importorskip("scipy.spatial")
    tri = scipy_spatial.Delaunay(xy).simplices.astype(np.int32)
    faces = tri.copy()
    axis = np.array([2], dtype=np.int64)
    parent = np.zeros(faces.shape[0], dtype=np.int32)
    for f in range(faces.shape[0]):
        if _orient_exact(*xy[faces[f]]) < 0:
            faces[f] = faces[f, ::-1]
    spoiled = 0
    for f in range(0, faces.shape[0], 2):
        for g in range(faces.shape[0]):
            shared = set(faces[f]) & set(faces[g])
            if g == f or len(shared) != 2:
                continue
            r = int(next(v for v in faces[f] if v not in shared))
            s = int(next(v for v in faces[g] if v not in shared))
            k = list(faces[f]).index(r)
            p, q = int(faces[f, (k + 1) % 3]), int(faces[f, (k + 2) % 3])
            if _orient_exact(xy[r], xy[p], xy[s]) > 0 and _orient_exact(xy[r], xy[s], xy[q]) > 0:
                faces[f] = (r, p, s)
                faces[g] = (r, s, q)
                spoiled += 1
            break
    assert spoiled > 3
    lawson(pts, faces, parent, np.array([[0, 1, 2]], dtype=np.int32), np.full((len(pts), 2), -1, dtype=np.int32), axis)
    # every interior edge is locally Delaunay, every face still counter-clockwise
    for f in range(faces.shape[0]):
        assert _orient_exact(*xy[faces[f]]) > 0
    edges, fe = unique_edges(faces)
    for e in range(edges.shape[0]):
        fs = np.flatnonzero((fe == e).any(axis=1))
        if fs.size != 2:
            continue
        f, g = fs
        s = next(v for v in faces[g] if v not in faces[f])
        assert _incircle_exact(*xy[faces[f]], xy[s]) <= 0
    assert _areas(pts, faces).sum() == pytest.approx(_areas(pts, tri).sum(), rel=1e-12)


def _sliver_ratios(points, tets):
    """a = r_in / R per tet: r_in = 3 V / (sum of face areas), R from the circumcentre solved
    by numpy (this test's own formulas)."""
    p = points[tets]
    v = np.abs(_tet_volumes(points, tets))
    faces = ((1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2))
    area = sum(0.5 * np.linalg.norm(np.cross(p[:, b] - p[:, a], p[:, c] - p[:, a]), axis=1) for a, b, c in faces)
    r_in = 3.0 * v / area
    e = p[:, 1:] - p[:, :1]  # (m, 3, 3): edge vectors from vertex 0
    rhs = 0.5 * np.einsum("mij,mij->mi", e, e)
    x = np.linalg.solve(e, rhs[..., None])[..., 0]  # circumcentre relative to vertex 0
    return r_in / np.linalg.norm(x, axis=1)


def test_slivers_left_after_removal_are_announced():
    """Where the sliver stage leaves chapter slivers (a < 0.01), tetrahedralize says how many
    (SliverWarning); where it leaves none it stays silent."""
    import warnings

    surf, kw = _load("extruded_crease170")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        mesh = mw.tetrahedralize(surf, **kw)
    left = int(np.count_nonzero(_sliver_ratios(mesh.points, mesh.cells["tetra"]) < 0.01))
    said = [w for w in caught if issubclass(w.category, mw.SliverWarning)]
    if left:
        assert len(said) == 1 and f"{left} tets" in str(said[0].message)
        assert said[0].filename == __file__  # points at the caller
    else:
        assert not said
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        mesh = mw.tetrahedralize(mw.geometry.sphere(level=2), 0.3)
    assert (_sliver_ratios(mesh.points, mesh.cells["tetra"]) >= 0.01).all()
    assert not [w for w in caught if issubclass(w.category, mw.SliverWarning)]


def test_shell_points_split_at_powers_of_two_around_input_vertices():
    from meshwright.tet.recovery import shell_points

    rng = np.random.default_rng(5)
    pts = rng.normal(size=(40, 3))
    e = np.array([[i, 20 + i] for i in range(20)] + [[25, 3], [30, 31], [2, 7]], dtype=np.int32)
    out = shell_points(pts, e, 20)  # vertices 0-19 are input vertices
    for (a, b), p in zip(e, out):
        if (a < 20) == (b < 20):  # both or neither an input vertex: the midpoint
            np.testing.assert_array_equal(p, 0.5 * (pts[a] + pts[b]))
            continue
        apex, other = (a, b) if a < 20 else (b, a)
        r = float(np.linalg.norm(p - pts[apex]))
        length = float(np.linalg.norm(pts[other] - pts[apex]))
        assert abs(np.log2(r) - round(np.log2(r))) < 1e-12
        assert 0.5 / np.sqrt(2) - 1e-12 <= r / length <= 1 / np.sqrt(2) + 1e-12
        assert np.linalg.norm(np.cross(p - pts[apex], pts[other] - pts[apex])) < 1e-12 * length**2


def test_shell_points_match_radii_on_edges_at_a_small_angle():
    # Two edges from vertex 0 at 6 degrees, of unequal lengths: after the first split the
    # pieces at vertex 0 are split at the same radii on both, so neither edge's split point
    # lies in the diametral ball of the other's piece (what cascaded with midpoints)
    from meshwright.tet.recovery import shell_points

    t = np.radians(6.0)
    pts = np.array([[0, 0, 0], [0.3, 0, 0], [0.25 * np.cos(t), 0.25 * np.sin(t), 0]])
    radii = {1: [], 2: []}
    for end in (1, 2):
        q = pts.copy()
        far = end
        for _ in range(12):
            p = shell_points(q, np.array([[0, far]], dtype=np.int32), 3)[0]
            q = np.vstack([q, p])
            far = q.shape[0] - 1
            radii[end].append(float(np.linalg.norm(p)))
    np.testing.assert_allclose(radii[1][1:], radii[2][1:], rtol=1e-12)
    # the first split of an edge between two input vertices is its midpoint
    np.testing.assert_allclose([radii[1][0], radii[2][0]], [0.15, 0.125], rtol=1e-12)
    np.testing.assert_allclose(radii[1][1:], 2.0 ** -np.arange(4, 15), rtol=1e-12)


def test_sharp_dihedral_notch_is_refused_naming_the_edge_and_angle():
    # Fuzz seed 21 case 18: an extruded star with a notch whose two walls meet at 6.46
    # degrees along a vertical edge; recovery cascades there to the guard.  The error names
    # that input edge and the angle (the test's own: the bottom edges' directions at the notch)
    d = np.load(Path(__file__).parent / "data" / "tet_sharp_notch.npz")
    surf, kw = Surface(d["points"], d["triangles"]), ast.literal_eval(str(d["kw"]))
    apex = np.array([0.0061692134356062054, 0.55185985030770301, 0.0])
    i = int(np.argmin(np.linalg.norm(surf.points - apex, axis=1)))
    bottom = surf.triangles[(surf.points[surf.triangles][:, :, 2] == 0).all(axis=1)]
    ends = {int(v) for t in bottom for k, v in enumerate(t) if t[(k + 1) % 3] == i or t[(k - 1) % 3] == i}
    rim = [v for v in ends if sum(((t == i).any() and (t == v).any()) for t in bottom) == 1]
    u, w = (surf.points[v] - surf.points[i] for v in rim)
    angle = np.degrees(np.arccos(u @ w / np.linalg.norm(u) / np.linalg.norm(w)))
    assert 6.4 < angle < 6.5
    with pytest.raises(mw.MeshingError, match=rf"meet at {angle:.2f} degrees") as info:
        mw.tetrahedralize(surf, **kw)
    assert "(0.0061692134356062054, 0.55185985030770301, 0)" in str(info.value)
