"""File I/O: round trips through meshio formats and Triangle files, point files, malformed input."""

import re

import numpy as np
import pytest

from meshwright.core.errors import FormatError
from meshwright.core.mesh import Mesh
from meshwright.io import read, read_ele, read_node, read_points, read_poly, write, write_triangle


def marked_square(n=3):
    """n x n grid of the unit square: region markers 1 | 2, boundary line markers 1..4, point markers."""
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
    regions = np.where(pts[tri].mean(axis=1)[:, 0] < 0.5, 1, 2).astype(np.int32)
    on_boundary = ((pts == 0) | (pts == 1)).any(axis=1).astype(np.int32)
    return Mesh(
        pts,
        {"triangle": tri, "line": lines},
        point_data={"marker": on_boundary},
        cell_data={"marker": {"triangle": regions, "line": np.repeat(np.arange(1, 5), n).astype(np.int32)}},
    )


def tet_cube():
    pts = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)
    tets = np.array([[0, 1, 2, 6], [0, 2, 3, 6], [0, 3, 7, 6], [0, 7, 4, 6], [0, 4, 5, 6], [0, 5, 1, 6]])
    return Mesh(pts, {"tetra": tets}, cell_data={"marker": {"tetra": np.arange(6, dtype=np.int32)}})


def assert_same(a: Mesh, b: Mesh):
    np.testing.assert_array_equal(a.points, b.points)
    assert list(a.cells) == list(b.cells)
    for t in a.cells:
        np.testing.assert_array_equal(a.cells[t], b.cells[t])
        np.testing.assert_array_equal(a.cell_data["marker"][t], b.cell_data["marker"][t])
        assert b.cell_data["marker"][t].dtype == np.int32


def assert_same_up_to_order(a: Mesh, b: Mesh):
    """Same cells (as vertex coordinates, in cell order) with the same markers, in any order."""
    assert sorted(a.cells) == sorted(b.cells)
    for t in a.cells:
        rows = [
            np.column_stack([m.points[m.cells[t]].reshape(len(m.cells[t]), -1), m.cell_data["marker"][t]])
            for m in (a, b)
        ]
        ra, rb = (r[np.lexsort(r.T[::-1])] for r in rows)
        np.testing.assert_array_equal(ra, rb)


@pytest.mark.parametrize(
    "name, kwargs",
    [("m.vtu", {}), ("m.vtk", {}), ("m.msh", {}), ("m.msh", {"file_format": "gmsh"}), ("m.mesh", {})],
    ids=["vtu", "vtk", "msh22", "msh41", "medit"],
)
def test_meshio_round_trip_keeps_points_cells_markers(tmp_path, name, kwargs):
    mesh = marked_square()
    mesh.point_data["h"] = mesh.points[:, 0] * 2.0
    path = tmp_path / name
    mesh.write(path, **kwargs)
    back = read(path)
    assert back.dim == 2  # the z = 0 padding is stripped
    back.validate()
    if kwargs.get("file_format") == "gmsh":  # Gmsh 4.1 groups the cells by entity = marker
        assert_same_up_to_order(mesh, back)
        np.testing.assert_array_equal(back.points, mesh.points)
    else:
        assert_same(mesh, back)
    if name != "m.mesh":  # Medit keeps one integer per point only
        np.testing.assert_allclose(back.point_data["h"], mesh.point_data["h"])


def test_gmsh22_is_ascii_with_physical_tags(tmp_path):
    path = tmp_path / "m.msh"
    write(marked_square(), path)
    text = path.read_text()
    assert text.startswith("$MeshFormat\n2.2 0 8")
    # element line: number, type 1 (line), 2 tags, physical 1, geometrical 1, nodes
    assert re.search(r"\n\d+ 1 2 1 1 1 2\n", text)


def test_3d_tetra_round_trips(tmp_path):
    mesh = tet_cube()
    for name in ("t.vtu", "t.msh"):
        mesh.write(tmp_path / name)
        back = read(tmp_path / name)
        assert back.dim == 3
        assert_same(mesh, back)
    # A flat 3-D mesh stays 3-D when asked.
    flat = Mesh(np.column_stack([marked_square().points, np.zeros(16)]), {"triangle": marked_square().triangles})
    flat.write(tmp_path / "flat.vtu")
    assert read(tmp_path / "flat.vtu").dim == 2
    assert read(tmp_path / "flat.vtu", dim=3).dim == 3


def test_quad_mesh_round_trip(tmp_path):
    pts = np.array([[0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1.0]])
    mesh = Mesh(pts, {"quad": [[0, 1, 4, 3], [1, 2, 5, 4]]}, cell_data={"marker": {"quad": np.int32([7, 8])}})
    mesh.write(tmp_path / "q.vtu")
    assert_same(mesh, read(tmp_path / "q.vtu"))


def test_xdmf_needs_h5py_or_round_trips(tmp_path):
    mesh = marked_square()
    try:
        import h5py  # noqa: F401
    except ImportError:
        with pytest.raises(FormatError, match="h5py"):
            mesh.write(tmp_path / "m.xdmf")
        return
    mesh.write(tmp_path / "m.xdmf")
    assert_same(mesh, read(tmp_path / "m.xdmf"))


@pytest.mark.parametrize("first_index", [0, 1])
def test_triangle_files_round_trip(tmp_path, first_index):
    mesh = marked_square()
    written = write_triangle(mesh, tmp_path / "sq.node", first_index=first_index)
    assert [p.suffix for p in written] == [".node", ".ele", ".poly"]
    assert (tmp_path / "sq.node").read_text().splitlines()[2].split()[0] == str(first_index)
    back = read(tmp_path / "sq.ele")
    assert_same(mesh, back)
    np.testing.assert_array_equal(back.point_data["marker"], mesh.point_data["marker"])
    poly = read_poly(tmp_path / "sq.poly")
    np.testing.assert_array_equal(poly.segments, mesh.lines)
    np.testing.assert_array_equal(poly.segment_markers, mesh.cell_data["marker"]["line"])
    assert poly.holes.shape == (0, 2)
    assert poly.regions[:, 2].tolist() == [1.0, 2.0] and np.all(poly.regions[:, 3] < 0)


def test_tetgen_node_ele_round_trip(tmp_path):
    mesh = tet_cube()
    assert [p.suffix for p in write_triangle(mesh, tmp_path / "cube")] == [".node", ".ele"]
    assert_same(mesh, read(tmp_path / "cube.node"))


def test_read_poly_raw_with_own_vertices(tmp_path):
    path = tmp_path / "box.poly"
    path.write_text(
        "# a square with a square hole, 1-based\n"
        "8 2 1 1\n"
        "1 0 0 0.5 1\n2 3 0 0.5 1\n3 3 3 0.5 1\n4 0 3 0.5 1\n"
        "5 1 1 0 2\n6 2 1 0 2\n7 2 2 0 2\n8 1 2 0 2\n"
        "8 1\n"
        "1 1 2 10\n2 2 3 10\n3 3 4 10\n4 4 1 10\n"
        "5 5 6 20\n6 6 7 20\n7 7 8 20\n8 8 5 20\n"
        "1\n1 1.5 1.5\n"
        "2\n1 0.5 0.5 3 0.1\n2 2.5 2.5 4\n"
    )
    poly = read_poly(path)
    assert poly.vertices.shape == (8, 2) and poly.vertex_attributes.shape == (8, 1)
    assert poly.vertex_markers.tolist() == [1] * 4 + [2] * 4
    assert poly.segments[0].tolist() == [0, 1] and poly.segments[-1].tolist() == [7, 4]
    assert poly.segment_markers.tolist() == [10] * 4 + [20] * 4
    np.testing.assert_array_equal(poly.holes, [[1.5, 1.5]])
    np.testing.assert_array_equal(poly.regions, [[0.5, 0.5, 3, 0.1], [2.5, 2.5, 4, -1]])
    lines = read(path)  # a .poly read as a mesh: vertices and segments
    assert lines.lines.shape == (8, 2) and lines.cell_data["marker"]["line"][4] == 20


def test_read_node_attributes_and_markers(tmp_path):
    path = tmp_path / "p.node"
    path.write_text("3 2 2 1\n0 0.0 0.0 1.5 2.5 1\n1 1.0 0.0 3.5 4.5 0\n2 0.0 1.0 5.5 6.5 1 # comment\n")
    node = read_node(path)
    assert node.first_index == 0 and node.markers.tolist() == [1, 0, 1]
    np.testing.assert_array_equal(node.attributes, [[1.5, 2.5], [3.5, 4.5], [5.5, 6.5]])
    ele = tmp_path / "p.ele"
    ele.write_text("1 3 1\n0 0 1 2 0.25\n")
    mesh = read(path)
    np.testing.assert_array_equal(mesh.cell_data["attributes"]["triangle"], [[0.25]])  # not integral: no marker
    assert read_ele(ele).cells.tolist() == [[0, 1, 2]]


@pytest.mark.parametrize(
    "suffix, text, pattern",
    [
        (".node", "3 2 0 0\n1 0 0\n2 1 zero\n3 0 1\n", r"bad\.node, line 3: cannot parse 'zero'"),
        (".node", "3 2 0 0\n1 0 0\n2 1 0\n", r"unexpected end of file: expected 3 vertex lines"),
        (".node", "2 2 0 0\n1 0 0\n3 1 0\n", r"line 3: vertex numbered 3, expected 2"),
        (".node", "2 4 0 0\n1 0 0\n2 1 0\n", r"line 1: dimension must be 2 or 3"),
        (".node", "2 2 0 0\n1 0 0 7\n2 1 0\n", r"line 2: expected 3 to 3 fields"),
        (".ele", "1 3 0\n1 1 2 9\n", None),
        (".ele", "1 6 0\n1 1 2 3 4 5 6\n", r"line 1: 6 nodes per element are not supported"),
        (".poly", "0 2 0 0\n0 0\n0\n", r"\.node does not exist"),
    ],
)
def test_malformed_triangle_files_name_the_line(tmp_path, suffix, text, pattern):
    path = tmp_path / f"bad{suffix}"
    path.write_text(text)
    if suffix == ".ele":
        (tmp_path / "bad.node").write_text("3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n")
        if pattern is None:
            pattern = r"bad\.ele, line 2: element refers to vertex \[1, 2, 9\] outside 1\.\.3"
    with pytest.raises(FormatError, match=pattern):
        read(path)


def test_write_triangle_rejects_quads(tmp_path):
    pts = np.array([[0, 0], [1, 0], [1, 1], [0, 1.0]])
    with pytest.raises(FormatError, match="cannot store quad"):
        write(Mesh(pts, {"quad": [[0, 1, 2, 3]]}), tmp_path / "q.node")


def test_meshio_errors_become_format_errors(tmp_path):
    bad = tmp_path / "bad.vtu"
    bad.write_text("<VTKFile> not really")
    with pytest.raises(FormatError, match=r"bad\.vtu: cannot read"):
        read(bad)
    with pytest.raises(FormatError, match="unknown file extension"):
        marked_square().write(tmp_path / "m.unknown")
    with pytest.raises(FileNotFoundError):
        read(tmp_path / "missing.vtu")


# ---------------------------------------------------------------------------- point files


def test_read_points_all_formats(tmp_path):
    pts = np.random.default_rng(1).random((20, 2))
    np.save(tmp_path / "p.npy", pts)
    np.testing.assert_array_equal(read_points(tmp_path / "p.npy"), pts)
    (tmp_path / "p.csv").write_text("x,y\n" + "\n".join(f"{x!r},{y!r}" for x, y in pts.tolist()) + "\n")
    np.testing.assert_array_equal(read_points(tmp_path / "p.csv"), pts)
    body = "\n".join(f"{x!r} {y!r}  # point" for x, y in pts.tolist())
    (tmp_path / "p.txt").write_text("# my points\n% matlab-style comment\n\n" + body + "\n")
    np.testing.assert_array_equal(read_points(tmp_path / "p.txt"), pts)
    (tmp_path / "p.xyz").write_text("0 0 1\n1 0 2\n0 1 3\n")
    assert read_points(tmp_path / "p.xyz").shape == (3, 3)
    write_triangle(Mesh(pts, {}), tmp_path / "p.node")
    np.testing.assert_array_equal(read_points(tmp_path / "p.node"), pts)
    out = read_points(tmp_path / "p.csv")
    assert out.dtype == np.float64 and out.flags.c_contiguous


@pytest.mark.parametrize(
    "name, content, pattern",
    [
        ("a.txt", "0 0\n1 0\n1 x\n", r"a\.txt, line 3: cannot parse '1 x'"),
        ("b.csv", "x,y\n0,0\n1,0,0\n", r"b\.csv, line 3: 3 coordinates where earlier lines have 2"),
        ("c.txt", "0 0 0 0\n", r"c\.txt, line 1: expected 2 or 3 coordinates, got 4"),
        ("d.txt", "# nothing\n", r"d\.txt: no points found"),
        ("e.txt", "0 0\nnan 1\n", r"e\.txt: point 1 has a non-finite"),
    ],
)
def test_malformed_point_files(tmp_path, name, content, pattern):
    (tmp_path / name).write_text(content)
    with pytest.raises(FormatError, match=pattern):
        read_points(tmp_path / name)


def test_malformed_npy(tmp_path):
    np.save(tmp_path / "p.npy", np.zeros((4, 5)))
    with pytest.raises(FormatError, match=r"p\.npy: expected a numeric \(n, 2\) or \(n, 3\) array"):
        read_points(tmp_path / "p.npy")
    (tmp_path / "q.npy").write_bytes(b"garbage")
    with pytest.raises(FormatError, match=r"q\.npy: not a readable"):
        read_points(tmp_path / "q.npy")
