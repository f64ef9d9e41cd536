"""Mesh data model: construction, validate() on good and defective meshes, neighbours, quality."""

import re

import numpy as np
import pytest

from meshwright.core.errors import InputError, ValidationError
from meshwright.core.mesh import Mesh, build_neighbors, build_neighbors_tet, check_neighbors
from meshwright.core.quality import QualityReport

# --------------------------------------------------------------------------- builders


def square_grid(n=4):
    """Unit square, n x n squares each split into two ccw triangles; boundary lines marked 1..4."""
    x, y = np.meshgrid(np.linspace(0, 1, n + 1), np.linspace(0, 1, n + 1))
    pts = np.column_stack([x.ravel(), y.ravel()])
    idx = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel(), idx[1:, :-1].ravel()
    tri = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    lines = np.concatenate(
        [
            np.column_stack([idx[0, :-1], idx[0, 1:]]),
            np.column_stack([idx[:-1, -1], idx[1:, -1]]),
            np.column_stack([idx[-1, 1:], idx[-1, :-1]]),
            np.column_stack([idx[1:, 0], idx[:-1, 0]]),
        ]
    )
    markers = np.repeat(np.arange(1, 5), n).astype(np.int32)
    return pts, tri, lines, markers, idx


def quad_grid(nx=3, ny=2):
    x, y = np.meshgrid(np.linspace(0, 1.5, nx + 1), np.linspace(0, 1, ny + 1))
    pts = np.column_stack([x.ravel(), y.ravel()])
    idx = np.arange((nx + 1) * (ny + 1)).reshape(ny + 1, nx + 1)
    quads = np.column_stack([idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel(), idx[1:, :-1].ravel()])
    return pts, quads


CUBE = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)
CUBE_6 = np.array([[0, 1, 2, 6], [0, 2, 3, 6], [0, 3, 7, 6], [0, 7, 4, 6], [0, 4, 5, 6], [0, 5, 1, 6]])
CUBE_5 = np.array([[0, 1, 3, 4], [1, 2, 3, 6], [1, 5, 4, 6], [3, 6, 4, 7], [1, 3, 4, 6]])


def positive(points, tets):
    """Swap two vertices of every negatively oriented tetrahedron (test helper)."""
    p = points[tets]
    neg = np.linalg.det(p[:, 1:] - p[:, :1]) < 0
    tets = tets.copy()
    tets[neg, 0], tets[neg, 1] = tets[neg, 1], tets[neg, 0].copy()
    return tets


TWO = (np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]), np.array([[0, 1, 2], [0, 2, 3]]))


def raises(match, mesh, **kw):
    with pytest.raises(ValidationError, match=match) as info:
        mesh.validate(**kw)
    return str(info.value)


# ------------------------------------------------------------------------- construction


def test_construction_coerces_and_exposes_blocks():
    pts, tri = TWO
    mesh = Mesh(pts.tolist(), {"triangle": tri.astype(np.int64)})
    assert mesh.points.dtype == np.float64 and mesh.points.flags.c_contiguous
    assert mesh.triangles.dtype == np.int32 and mesh.triangles.shape == (2, 3)
    assert mesh.quads.shape == (0, 4) and mesh.tetra.shape == (0, 4) and mesh.lines.shape == (0, 2)
    assert mesh.dim == 2 and mesh.n_points == 4 and mesh.n_cells == 2
    assert "n_points=4" in repr(mesh) and "triangle: 2" in repr(mesh)
    assert Mesh(pts, [("triangle", tri)]).n_cells == 2


@pytest.mark.parametrize(
    "kwargs, pattern",
    [
        (dict(points=np.zeros((3, 4)), cells={}), r"shape \(n, 2\) or \(n, 3\)"),
        (dict(points=[[0, 0], [1, np.nan], [0, 1]], cells={}), r"point 1 has a non-finite"),
        (dict(points=TWO[0], cells={"triangle": [[0, 1, 7]]}), r"triangle 0 \(vertices 0, 1, 7\) references a vertex"),
        (dict(points=TWO[0], cells={"triangle": [[0, 1, -1]]}), r"triangle 0"),
        (dict(points=TWO[0], cells={"polygon": [[0, 1, 2]]}), r"unknown cell type 'polygon'"),
        (dict(points=TWO[0], cells={"triangle": [[0.0, 1.0, 2.0]]}), r"must hold integers"),
        (dict(points=TWO[0], cells={"triangle": [[0, 1]]}), r"shape \(m, 3\)"),
        (dict(points=TWO[0], cells={"tetra": [[0, 1, 2, 3]]}), r"tetra cells need 3-D points"),
        (dict(points=TWO[0], cells={"triangle": TWO[1]}, point_data={"h": [1.0]}), r"point_data\['h'\]"),
        (
            dict(points=TWO[0], cells={"triangle": TWO[1]}, cell_data={"marker": {"triangle": [1]}}),
            r"cell_data\['marker'\]\['triangle'\] has shape \(1,\)",
        ),
        (
            dict(points=TWO[0], cells={"triangle": TWO[1]}, cell_data={"marker": {"line": [1]}}),
            r"no such cells",
        ),
    ],
)
def test_construction_rejects_bad_input(kwargs, pattern):
    with pytest.raises(InputError, match=pattern):
        Mesh(**kwargs)


# ---------------------------------------------------------------------------- good meshes


def test_two_triangles_and_grid_validate():
    Mesh(*TWO[:1], {"triangle": TWO[1]}).validate(check_delaunay=True)
    pts, tri, lines, markers, _ = square_grid(6)
    mesh = Mesh(pts, {"triangle": tri, "line": lines}, cell_data={"marker": {"line": markers}})
    mesh.validate(check_delaunay=True)  # every diagonal is cocircular: exact incircle == 0 passes
    assert mesh.area() == pytest.approx(1.0)


def test_interior_line_cells_are_allowed():
    pts, tri, lines, _, idx = square_grid(2)
    interior = np.array([[idx[1, 0], idx[1, 1]], [idx[1, 1], idx[1, 2]]])
    Mesh(pts, {"triangle": tri, "line": np.concatenate([lines, interior])}).validate()


def test_quad_grid_and_mixed_mesh_validate():
    pts, quads = quad_grid()
    mesh = Mesh(pts, {"quad": quads})
    mesh.validate()
    assert mesh.area() == pytest.approx(1.5)
    # Split the last quad into two triangles: a conforming mixed mesh.
    q = quads[-1]
    mixed = Mesh(pts, {"quad": quads[:-1], "triangle": [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]})
    mixed.validate()


@pytest.mark.parametrize("tets", [CUBE_5, CUBE_6], ids=["5 tets", "6 tets"])
def test_tet_cubes_validate(tets):
    tets = positive(CUBE, tets)
    mesh = Mesh(CUBE, {"tetra": tets})
    mesh.validate()
    assert mesh.volume() == pytest.approx(1.0)
    faces = mesh.boundary_facets()
    assert len(faces) == 12
    # Boundary faces of a volume mesh may be given as triangle cells.
    Mesh(CUBE, {"tetra": tets, "triangle": faces}).validate()


def test_hexahedra_validate():
    pts = np.concatenate([CUBE, CUBE[4:] + [0, 0, 1]])
    hexes = np.array([[0, 1, 2, 3, 4, 5, 6, 7], [4, 5, 6, 7, 8, 9, 10, 11]])
    mesh = Mesh(pts, {"hexahedron": hexes})
    mesh.validate()
    assert mesh.volume() == pytest.approx(2.0)


def test_closed_surface_in_3d_needs_no_boundary():
    tets = positive(CUBE, CUBE_6)
    faces = Mesh(CUBE, {"tetra": tets}).boundary_facets()
    Mesh(CUBE, {"triangle": faces}).validate()


# ----------------------------------------------------------------------------- defects


def test_flipped_triangle_is_named():
    pts, tri, *_ = square_grid(3)
    tri = tri.copy()
    tri[5] = tri[5][[0, 2, 1]]
    msg = raises(r"triangle 5 \(vertices", Mesh(pts, {"triangle": tri}))
    assert "inverted" in msg and "1 such cells" in msg


def test_degenerate_triangle_is_named():
    pts = np.array([[0, 0], [1, 0], [2, 0], [1, 1.0]])
    msg = raises(r"triangle 1 \(vertices 0, 1, 2\)", Mesh(pts, {"triangle": [[0, 1, 3], [0, 1, 2], [1, 2, 3]]}))
    assert "degenerate" in msg


def test_dangling_vertex():
    pts = np.vstack([TWO[0], [[5.0, 5.0]]])
    raises(r"vertex 4 at \(5\.0, 5\.0\) is not used", Mesh(pts, {"triangle": TWO[1]}))


def test_duplicate_vertex():
    # Two triangles meeting along x = 1 without sharing vertex indices.
    pts = np.array([[0, 0], [1, 0], [1, 1], [1, 0], [2, 0], [1, 1.0]])
    raises(r"vertices 1 and 3 have identical coordinates \(1\.0, 0\.0\)", Mesh(pts, {"triangle": [[0, 1, 2], [3, 4, 5]]}))


def test_repeated_vertex_in_cell():
    pts, tri = TWO
    raises(r"triangle 1 \(vertices 0, 2, 0\) repeats vertex 0", Mesh(pts, {"triangle": [[0, 1, 2], [0, 2, 0], [0, 2, 3]]}))


def test_edge_shared_by_three_triangles():
    pts = np.array([[0, 0], [1, 0], [0.5, 1], [0.5, -1], [0.5, -0.5]])
    tri = [[0, 1, 2], [1, 0, 3], [1, 0, 4]]
    msg = raises(r"edge \(0, 1\) is shared by 3 cells", Mesh(pts, {"triangle": tri}))
    assert all(f"triangle {i}" in msg for i in range(3))


def test_neighbour_on_the_same_side():
    # Both triangles are counter-clockwise but lie on the same side of edge 0-1.
    pts = np.array([[0, 0], [1, 0], [0.5, 1], [0.5, 0.5]])
    msg = raises(r"same direction", Mesh(pts, {"triangle": [[0, 1, 2], [0, 1, 3]]}))
    assert "triangle 0" in msg and "triangle 1" in msg and "(0, 1)" in msg


def test_misoriented_surface_triangle_in_3d():
    tets = positive(CUBE, CUBE_6)
    faces = Mesh(CUBE, {"tetra": tets}).boundary_facets()
    faces[3] = faces[3][[0, 2, 1]]
    msg = raises(r"same direction", Mesh(CUBE, {"triangle": faces}))
    assert "triangle 3" in msg


def test_line_that_is_not_an_edge():
    pts, tri = TWO
    raises(r"line 0 \(vertices 1, 3\) is not an edge", Mesh(pts, {"triangle": tri, "line": [[1, 3]]}))


def test_check_delaunay_names_the_bad_edge():
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.3]])
    good = Mesh(pts, {"triangle": [[0, 1, 2], [0, 2, 3]]})
    good.validate(check_delaunay=True)
    bad = Mesh(pts, {"triangle": [[0, 1, 3], [1, 2, 3]]})
    bad.validate()  # valid, just not Delaunay
    msg = raises(r"edge \((1, 3|3, 1)\) .* not locally Delaunay", bad, check_delaunay=True)
    assert re.search(r"vertex [02] at", msg)
    # The same edge as a constraint (an interior line cell): constrained Delaunay passes.
    Mesh(pts, {"triangle": bad.triangles, "line": [[3, 1]]}).validate(check_delaunay=True)


def test_flipped_and_shared_tetra():
    tets = positive(CUBE, CUBE_5)
    flipped = tets.copy()
    flipped[2] = flipped[2][[1, 0, 2, 3]]
    raises(r"tetra 2 \(vertices .*\) .* inverted", Mesh(CUBE, {"tetra": flipped}))
    # A sixth tetra duplicating the central one's face (1, 3, 4) on its inner side.
    pts = np.vstack([CUBE, [[0.4, 0.4, 0.4]]])
    extra = positive(pts, np.array([[1, 3, 4, 8]]))
    msg = raises(r"face \(1, 3, 4\) is shared by 3 cells", Mesh(pts, {"tetra": np.vstack([tets, extra])}))
    assert "tetra 5" in msg


def test_inverted_hexahedron_and_bad_quads():
    hexes = np.array([[4, 5, 6, 7, 0, 1, 2, 3]])  # top and bottom swapped: inside out
    raises(r"hexahedron 0 .* inverted \(negative volume at corner 0", Mesh(CUBE, {"hexahedron": hexes}))
    pts = np.array([[0, 0], [1, 0], [1, 1], [0, 1.0]])
    raises(r"quad 0 \(vertices 0, 3, 2, 1\) .* inverted", Mesh(pts, {"quad": [[0, 3, 2, 1]]}))
    # A dart (non-convex quad) has a negative corner even though it is counter-clockwise.
    pts[2] = [0.3, 0.3]
    raises(r"quad 0 \(vertices 0, 1, 2, 3\) .* at corner 2", Mesh(pts, {"quad": [[0, 1, 2, 3]]}))


# -------------------------------------------------------------------------- neighbours


def test_build_and_check_neighbors():
    pts, tri, *_ = square_grid(5)
    nbr = build_neighbors(tri)
    assert nbr.dtype == np.int32 and nbr.shape == tri.shape
    check_neighbors(tri, nbr)
    # The edge opposite vertex k is shared with the neighbour across it.
    t, k = np.argwhere(nbr >= 0)[0]
    shared = {tri[t, (k + 1) % 3], tri[t, (k + 2) % 3]}
    assert shared <= set(tri[nbr[t, k]])
    assert np.count_nonzero(nbr < 0) == 4 * 5  # boundary edges
    broken = nbr.copy()
    broken[t, k] = (nbr[t, k] + 1) % len(tri)
    with pytest.raises(ValidationError, match=rf"triangle {t} slot {k}"):
        check_neighbors(tri, broken)
    with pytest.raises(ValidationError, match="same direction"):
        build_neighbors(np.array([[0, 1, 2], [0, 1, 3]]))


def test_build_neighbors_tet():
    tets = positive(CUBE, CUBE_5)
    nbr = build_neighbors_tet(tets)
    check_neighbors(tets, nbr)
    assert sorted(nbr[4].tolist()) == [0, 1, 2, 3]  # the central tetra touches the four corners
    assert np.count_nonzero(nbr >= 0) == 8


def _python_calls(func):
    """Number of Python and C function calls ``func()`` makes (a profile hook, no timing).

    The garbage collector is off while it counts: a collection falling inside ``func`` can run
    finalizers of unrelated objects, whose calls are not ``func``'s work (the likely cause of a
    clean-clone run that counted 303 against 299 calls once)."""
    import gc
    import sys

    calls = 0

    def hook(frame, event, arg):
        nonlocal calls
        calls += event in ("call", "c_call")

    gc.collect()
    gc.disable()
    sys.setprofile(hook)
    try:
        func()
    finally:
        sys.setprofile(None)
        gc.enable()
    return calls


def test_validate_is_vectorised_on_a_large_grid():
    # Vectorised means the interpreter's work does not grow with the mesh: validate and
    # build_neighbors make the same number of calls on 50 triangles as on 800, and on 45 000
    # as on 61 250 (NumPy sorts small facet sets, a compiled counting sort large ones).
    for small, large in [(Mesh(pts, {"triangle": tri}) for pts, tri, *_ in map(square_grid, n)) for n in ((5, 20), (150, 175))]:
        small.validate()  # compile the predicates first
        large.validate()
        assert _python_calls(large.validate) == _python_calls(small.validate)
        tri_small, tri_large = small.cells["triangle"], large.cells["triangle"]
        assert _python_calls(lambda: build_neighbors(tri_large)) == _python_calls(lambda: build_neighbors(tri_small))
    # The large grid is really checked: one reversed triangle is found.
    bad = tri_large.copy()
    bad[22_222] = bad[22_222, ::-1]
    with pytest.raises(ValidationError):
        Mesh(large.points, {"triangle": bad}).validate()


# ------------------------------------------------------------------------------ quality


def test_quality_equilateral_and_right_isosceles():
    pts = np.array([[0, 0], [1, 0], [0.5, np.sqrt(3) / 2], [0, -1.0]])
    mesh = Mesh(pts, {"triangle": [[0, 1, 2], [0, 3, 1]]})
    q = mesh.quality()["triangle"]
    np.testing.assert_allclose(q["min_angle"], [60, 45])
    np.testing.assert_allclose(q["max_angle"], [60, 90])
    np.testing.assert_allclose(q["radius_ratio"], [1.0, 2 * (np.sqrt(2) - 1)])
    np.testing.assert_allclose(q["edge_ratio"], [1.0, np.sqrt(2)])
    np.testing.assert_allclose(q["area"], [np.sqrt(3) / 4, 0.5])


def test_quality_regular_tetra_and_rectangle():
    reg = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1.0]])
    tet = positive(reg, np.array([[0, 1, 2, 3]]))
    q = Mesh(reg, {"tetra": tet}).quality()["tetra"]
    np.testing.assert_allclose(q["radius_ratio"], 1.0)
    np.testing.assert_allclose(q["min_dihedral"], np.degrees(np.arccos(1 / 3)))
    np.testing.assert_allclose(q["volume"], 8 / 3)
    pts, quads = quad_grid(1, 1)
    q = Mesh(pts, {"quad": quads}).quality()["quad"]
    np.testing.assert_allclose([q["min_angle"][0], q["max_angle"][0]], [90, 90])
    np.testing.assert_allclose([q["scaled_jacobian"][0], q["edge_ratio"][0], q["area"][0]], [1.0, 1.5, 1.5])


def test_quality_report_summary_and_table():
    pts, tri, *_ = square_grid(4)
    report = Mesh(pts, {"triangle": tri}).quality()
    assert isinstance(report, QualityReport) and "triangle" in report
    stats = report.summary()["triangle"]["min_angle"]
    assert list(stats) == ["min", "p1", "p5", "p50", "mean", "max"]
    assert stats["min"] == pytest.approx(45.0) and stats["max"] == pytest.approx(45.0)
    table = report.table()
    assert table == str(report)
    lines = table.splitlines()
    assert lines[0] == "triangle (32 cells)" and "radius_ratio" in table and "min_angle [deg]" in table
    assert len({len(line) for line in lines[1:]}) == 1  # aligned columns
    assert Mesh(pts, {"line": [[0, 1]]}).quality().table() == "no elements with quality measures"
