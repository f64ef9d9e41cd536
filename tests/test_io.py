"""File I/O: round trips through meshio formats and Triangle files, point files, malformed input."""

import re
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from meshwright.core.errors import FormatError, InputError
from meshwright.core.mesh import Mesh
from meshwright.geometry.poly_format import write_node_file, write_poly_file
from meshwright.io import read, read_ele, read_node, read_points, read_poly, write, write_triangle
from meshwright.io.triangle_format import read_area, read_edge, read_neigh


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


# ---------------------------------------------------------------------------- Triangle formats


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


DATA = Path(__file__).parent / "data"


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
        "3\n1 0.5 0.5 3 0.1\n2 2.5 2.5 4\n3 2.5 0.5 5 0\n"
    )
    poly = read_poly(path)
    assert poly.first_index == 1 and poly.vertex_path == path
    assert poly.vertices.shape == (8, 2) and poly.vertex_attributes.shape == (8, 1)
    assert poly.vertex_markers.tolist() == [1] * 4 + [2] * 4
    assert poly.segments[0].tolist() == [0, 1] and poly.segments[-1].tolist() == [7, 4]
    assert poly.segments.dtype == np.int32
    assert poly.segment_markers.tolist() == [10] * 4 + [20] * 4
    assert poly.segment_lines.tolist() == list(range(12, 20))
    np.testing.assert_array_equal(poly.holes, [[1.5, 1.5]])
    # Triangle: a region without an area bound takes its attribute as the bound; 0 is none.
    np.testing.assert_array_equal(poly.regions, [[0.5, 0.5, 3, 0.1], [2.5, 2.5, 4, 4], [2.5, 0.5, 5, -1]])
    lines = read(path)  # a .poly read as a mesh: vertices and segments
    assert lines.lines.shape == (8, 2) and lines.cell_data["marker"]["line"][4] == 20
    assert lines.point_data["attributes"].shape == (8, 1)


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


def test_triangle_lexical_rules(tmp_path):
    """Comments anywhere, blank lines, tabs, CRLF, a BOM, Fortran numbers, header defaults,
    omitted trailing attributes and markers (0), as Triangle reads them."""
    path = tmp_path / "lex.poly"
    text = (
        "\ufeff# header with only the count: dimension 2, no attributes, no markers\r\n"
        "3\r\n"
        "\r\n"
        "  1\t0.000000E+00   -.000000E+00   # first vertex\r\n"
        "  2\t0.418893E+02   -.5E-1\r\n"
        "# a comment line between records\r\n"
        "  3\t1e0 2.\r\n"
        "3  # segments, no marker count\r\n"
        "1 1 2\r\n2 2 3\r\n3 3 1\r\n"
        "0"
    )
    path.write_bytes(text.encode("utf-8"))
    poly = read_poly(path)
    np.testing.assert_array_equal(poly.vertices, [[0.0, -0.0], [41.8893, -0.05], [1.0, 2.0]])
    assert poly.vertex_markers is None and poly.segment_markers is None
    assert poly.vertex_attributes.shape == (3, 0) and poly.regions.shape == (0, 4)
    assert poly.vertex_lines.tolist() == [4, 5, 7]
    node = tmp_path / "short.node"
    node.write_text("2 2 2 1\n1 0 0 7.5\n2 1 0 1.5 2.5 9\n")  # trailing fields omitted on line 2
    data = read_node(node)
    np.testing.assert_array_equal(data.attributes, [[7.5, 0.0], [1.5, 2.5]])
    assert data.markers.tolist() == [0, 9]


def _random_pslg(draw, n_max=12):
    finite = st.floats(allow_nan=False, allow_infinity=False)
    n = draw(st.integers(1, n_max))
    n_attr = draw(st.integers(0, 2))
    points = np.array(draw(st.lists(st.tuples(finite, finite), min_size=n, max_size=n)), dtype=np.float64)
    attributes = np.array(draw(st.lists(st.lists(finite, min_size=n_attr, max_size=n_attr), min_size=n, max_size=n)))
    marker = st.integers(-(2**31) + 1, 2**31 - 1)
    markers = np.array(draw(st.lists(marker, min_size=n, max_size=n))) if draw(st.booleans()) else None
    s = draw(st.integers(0, 10))
    segments = np.array(draw(st.lists(st.tuples(st.integers(0, n - 1), st.integers(0, n - 1)), min_size=s, max_size=s)))
    segment_markers = np.array(draw(st.lists(marker, min_size=s, max_size=s))) if draw(st.booleans()) else None
    holes = np.array(draw(st.lists(st.tuples(finite, finite), max_size=3))).reshape(-1, 2)
    area = st.one_of(st.just(-1.0), st.floats(min_value=1e-300, max_value=1e300))
    regions = np.array(draw(st.lists(st.tuples(finite, finite, finite, area), max_size=3))).reshape(-1, 4)
    return points, attributes.reshape(n, n_attr), markers, segments.reshape(s, 2), segment_markers, holes, regions


@settings(max_examples=60, deadline=None)
@given(data=st.data(), first_index=st.sampled_from([0, 1]), own_vertices=st.booleans())
def test_poly_arrays_round_trip_exactly(data, first_index, own_vertices):
    points, attributes, markers, segments, segment_markers, holes, regions = _random_pslg(data.draw)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "r.1.poly"
        vertex_kw = {"points": points, "point_attributes": attributes, "point_markers": markers}
        if not own_vertices:
            write_node_file(Path(tmp) / "r.1.node", points, attributes, markers, first_index)
            vertex_kw = {}
        write_poly_file(path, segments, segment_markers, holes, regions, first_index=first_index, **vertex_kw)
        poly = read_poly(path)
    assert poly.first_index == first_index
    np.testing.assert_array_equal(poly.vertices, points)
    np.testing.assert_array_equal(poly.vertex_attributes, attributes)
    if markers is None:
        assert poly.vertex_markers is None
    else:
        np.testing.assert_array_equal(poly.vertex_markers, markers)
    np.testing.assert_array_equal(poly.segments, segments)
    if segment_markers is None:
        assert poly.segment_markers is None
    else:
        np.testing.assert_array_equal(poly.segment_markers, segment_markers)
    np.testing.assert_array_equal(poly.holes, holes)
    np.testing.assert_array_equal(poly.regions, regions)


def test_node_file_3d_round_trip(tmp_path):
    pts = np.random.default_rng(3).normal(size=(5, 3))
    write_node_file(tmp_path / "t.node", pts, first_index=0)
    node = read_node(tmp_path / "t.node")
    np.testing.assert_array_equal(node.points, pts)
    assert node.first_index == 0 and node.markers is None


def test_writers_check_their_arguments(tmp_path):
    with pytest.raises(InputError, match="first_index must be 0 or 1"):
        write_node_file(tmp_path / "a.node", np.zeros((2, 2)), first_index=2)
    with pytest.raises(InputError, match=r"points row 1 is not finite"):
        write_node_file(tmp_path / "a.node", [[0, 0], [np.nan, 1]])
    with pytest.raises(InputError, match=r"segments row 0 must be integers in 0\.\.1"):
        write_poly_file(tmp_path / "a.poly", [[0, 2]], points=[[0, 0], [1, 0]])
    with pytest.raises(InputError, match=r"markers row 0 must be integers"):
        write_node_file(tmp_path / "a.node", [[0, 0]], markers=[0.5])
    with pytest.raises(InputError, match="need points"):
        write_poly_file(tmp_path / "a.poly", [[0, 1]], point_markers=[1, 1])
    with pytest.raises(InputError, match="first_index"):
        write_triangle(marked_square(), tmp_path / "m.node", first_index=True)


POLY3 = "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n"  # three vertices numbered from 1 (lines 1-4)
SEG3 = "3 0\n1 1 2\n2 2 3\n3 3 1\n"  # lines 5-8


@pytest.mark.parametrize(
    "files, pattern",
    [
        ({"x.poly": "3 2 0 0\n1 0 0\n2 1 zero\n3 0 1\n"}, r"x\.poly, line 3: vertex y: 'zero' is not a finite number"),
        ({"x.poly": "3 2 0 0\n1 0 0\n2 nan 0\n3 0 1\n"}, r"x\.poly, line 3: vertex x: 'nan' is not a finite"),
        ({"x.poly": POLY3 + SEG3 + "1\n1 inf 0\n"}, r"x\.poly, line 10: hole x: 'inf' is not a finite"),
        ({"x.poly": POLY3 + SEG3 + "0\n1\n1 0.2 0.2 1 NaN\n"}, r"x\.poly, line 11: region maximum area: 'NaN'"),
        ({"x.poly": POLY3 + "3 0\n1 1 2\n2 2 1.5\n3 3 1\n"}, r"x\.poly, line 7: segment endpoints must be integers"),
        ({"x.poly": POLY3 + "3 1\n1 1 2 a\n"}, r"x\.poly, line 6: segment boundary marker: 'a'"),
        ({"x.poly": POLY3 + "3 0\n1 1 2\n2 2 9\n3 3 1\n"}, r"x\.poly, line 7: segment endpoints 2 9 outside the vertex numbers, 1\.\.3"),
        ({"x.poly": POLY3 + "1 0\n1 0 2\n"}, r"x\.poly, line 6: segment endpoints 0 2 outside .* 1\.\.3"),
        # counts that disagree with the records
        ({"x.poly": "3 2 0 0\n1 0 0\n2 1 0\n"}, r"x\.poly, line 3: unexpected end of file: line 1 declares 3 vertices, found 2"),
        ({"x.poly": "2 2 0 0\n1 0 0\n2 1 0\n3 0 1\n" + SEG3}, r"x\.poly, line 4: expected the segment header '<#segments> <#boundary markers>', got '3 0 1'"),
        ({"x.poly": POLY3 + SEG3 + "0\n0\n7\n"}, r"x\.poly, line 11: unexpected content after the last section: '7'"),
        ({"x.poly": POLY3 + "4 0\n1 1 2\n2 2 3\n3 3 1\n0\n"}, r"x\.poly, line 9: a segment line holds 3 fields"),
        ({"x.poly": "-3 2 0 0\n"}, r"x\.poly, line 1: the \.poly vertex header: #vertices must be a non-negative integer, got '-3'"),
        # truncated files
        ({"x.poly": "3 2 0 0\n1 0 0\n2 1 0\n3 0"}, r"x\.poly, line 4: a vertex line holds 3 fields .*got 2: '3 0'"),
        ({"x.poly": POLY3 + SEG3}, r"x\.poly, line 8: unexpected end of file, expected the hole header"),
        ({"x.poly": ""}, r"x\.poly, line 1: unexpected end of file, expected the \.poly vertex header"),
        ({"x.poly": "# only a comment\n\n"}, r"x\.poly, line 2: unexpected end of file"),
        # numbering, dimension, marker counts, field counts
        ({"x.poly": "2 2 0 0\n2 0 0\n3 1 0\n"}, r"x\.poly, line 2: the first vertex must be numbered 0 or 1, got 2"),
        ({"x.poly": "2 2 0 0\n1 0 0\n3 1 0\n"}, r"x\.poly, line 3: vertex numbered 3, expected 2"),
        ({"x.poly": "2 2 0 0\n1 0 0\n2.5 1 0\n"}, r"x\.poly, line 3: vertex numbers must be integers"),
        ({"x.poly": "3 3 0 0\n"}, r"x\.poly, line 1: dimension must be 2, got 3"),
        ({"x.poly": "3 2 0 2\n"}, r"x\.poly, line 1: number of vertex boundary markers must be 0 or 1, got 2"),
        ({"x.poly": POLY3 + "3 2\n"}, r"x\.poly, line 5: number of segment boundary markers must be 0 or 1"),
        ({"x.poly": "3 2 0 0\n1 0 0 7\n"}, r"x\.poly, line 2: a vertex line holds 3 fields"),
        ({"x.poly": POLY3 + SEG3 + "0\n1\n1 0.5 0.5\n"}, r"x\.poly, line 11: a region line holds 4 to 5 fields"),
        ({"x.poly": POLY3 + SEG3 + "1 2\n"}, r"x\.poly, line 9: expected the hole header '<#holes>', got '1 2'"),
        # non-UTF-8 bytes
        ({"x.poly": b"3 2 0 0\n1 0 0\n2 1 \xff0\n3 0 1\n"}, r"x\.poly, line 3: not UTF-8 text \(byte 0xff\)"),
        # vertices in the companion .node
        ({"x.poly": "0 2 0 0\n" + SEG3 + "0\n"}, r"x\.poly, line 1: 0 vertices declared, so they must be in x\.node next to it, which does not exist"),
        ({"x.poly": "0 2 0 0\n" + SEG3 + "0\n", "x.node": "0 2 0 0\n"}, r"x\.node, line 1: declares 0 vertices, but x\.poly \(line 1\) reads its vertices from this file"),
        ({"x.poly": "0 2 0 0\n" + SEG3 + "0\n", "x.node": "3 3 0 0\n"}, r"x\.node, line 1: dimension must be 2, got 3"),
        ({"x.poly": "0 2 0 0\n" + SEG3 + "0\n", "x.node": b"# caf\xe9\n3 2 0 0\n"}, r"x\.node, line 1: not UTF-8"),
        ({"x.poly": "0 2 0 0\n" + SEG3 + "0\n", "x.node": "3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n"}, r"x\.poly, line 4: segment endpoints 2 3 outside the vertex numbers of x\.node, 0\.\.2"),
        ({"x.poly": "0 2 0 0\n" + SEG3 + "0\n", "x.node": "3 2 0 0\n1 0 0\n2 1 0\n"}, r"x\.node, line 3: unexpected end of file: line 1 declares 3 vertices, found 2"),
        # element files
        ({"x.node": POLY3, "x.ele": "1 3 0\n1 1 2 9\n"}, r"x\.ele, line 2: element refers to vertex \[1, 2, 9\] outside 1\.\.3"),
        ({"x.node": POLY3, "x.ele": "1 6 0\n1 1 2 3 4 5 6\n"}, r"x\.ele, line 1: 6 nodes per element are not supported"),
        ({"x.node": POLY3, "x.ele": "2 3 0\n1 1 2 3\n"}, r"x\.ele, line 2: unexpected end of file: line 1 declares 2 elements, found 1"),
        ({"x.node": "3 2 0 0\n1 0 0\n2 1 0\n3 0 1 1\n"}, r"x\.node, line 4: a vertex line holds 3 fields"),
    ],
)
def test_malformed_triangle_files_name_file_and_line(tmp_path, files, pattern):
    for name, content in files.items():
        (tmp_path / name).write_bytes(content if isinstance(content, bytes) else content.encode())
    target = tmp_path / ("x.poly" if "x.poly" in files else "x.ele" if "x.ele" in files else "x.node")
    with pytest.raises(FormatError, match=pattern):
        read(target)


VALID_POLY = (
    "# square with a square hole\n4 2 1 1\n1 0 0 0.5 1\n2 3 0 0.5 1\n3 3 3 0.5 1\n4 0 3 0.5 1\n"
    "4 1\n1 1 2 7\n2 2 3 7\n3 3 4 7\n4 4 1 7\n1\n1 1.5 1.5\n1\n1 0.5 0.5 2 0.25\n"
)


@settings(max_examples=300, deadline=None)
@given(data=st.data())
def test_corrupted_poly_files_raise_only_format_errors(data):
    """Whatever damage a file takes (cut, bytes replaced or inserted, lines dropped), reading
    it returns data or raises FormatError naming the file, never another exception."""
    raw = bytearray(VALID_POLY.encode())
    for _ in range(data.draw(st.integers(1, 3))):
        kind = data.draw(st.sampled_from(["cut", "replace", "insert", "drop line"]))
        at = data.draw(st.integers(0, len(raw) - 1)) if raw else 0
        if kind == "cut":
            raw = raw[:at]
        elif kind == "replace" and raw:
            raw[at] = data.draw(st.integers(0, 255))
        elif kind == "insert":
            raw[at:at] = data.draw(st.binary(min_size=1, max_size=4))
        else:
            lines = raw.split(b"\n")
            del lines[data.draw(st.integers(0, len(lines) - 1))]
            raw = bytearray(b"\n".join(lines))
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "c.poly"
        path.write_bytes(bytes(raw))
        try:
            read_poly(path)
        except FormatError as exc:
            assert str(exc).startswith(f"{path}")


def test_missing_and_unreadable_triangle_files(tmp_path):
    with pytest.raises(FormatError, match=r"nothing\.poly: no such file"):
        read_poly(tmp_path / "nothing.poly")
    (tmp_path / "dir.poly").mkdir()
    with pytest.raises(FormatError, match=r"dir\.poly: cannot read"):
        read_poly(tmp_path / "dir.poly")
    with pytest.raises(FormatError, match=r"a\.node: no such file"):
        read(tmp_path / "a.ele")


def test_zero_vertex_poly_reads_its_node_file(tmp_path):
    (tmp_path / "sq.node").write_text("# four corners\n4 2 1 1\n1 0 0 9 1\n2 1 0 9 1\n3 1 1 9 2\n4 0 1 9 2\n")
    (tmp_path / "sq.poly").write_text("0 2 0 0\n4 1\n1 1 2 5\n2 2 3 5\n3 3 4 6\n4 4 1 6\n0\n")
    poly = read_poly(tmp_path / "sq.poly")
    assert poly.vertex_path == tmp_path / "sq.node" and poly.first_index == 1
    np.testing.assert_array_equal(poly.vertices, [[0, 0], [1, 0], [1, 1], [0, 1]])
    assert poly.vertex_markers.tolist() == [1, 1, 2, 2] and poly.vertex_attributes.tolist() == [[9]] * 4
    assert poly.segments.tolist() == [[0, 1], [1, 2], [2, 3], [3, 0]]
    assert poly.vertex_lines.tolist() == [3, 4, 5, 6] and poly.segment_lines.tolist() == [3, 4, 5, 6]
    mesh = read(tmp_path / "sq.node")  # the .poly's segments become line cells of the .node set
    assert mesh.lines.tolist() == poly.segments.tolist() and mesh.cell_data["marker"]["line"].tolist() == [5, 5, 6, 6]


def test_zero_vertex_poly_beside_zero_vertex_node_is_an_error_not_a_loop(tmp_path, capsys):
    (tmp_path / "z.poly").write_text("0 2 0 0\n0 0\n0\n")
    (tmp_path / "z.node").write_text("0 2 0 0\n")
    with pytest.raises(FormatError, match=r"z\.node, line 1: declares 0 vertices"):
        read_poly(tmp_path / "z.poly")
    with pytest.raises(FormatError, match=r"z\.node, line 1: declares 0 vertices"):
        read(tmp_path / "z.poly")
    # A path that names the .node itself cannot defer to itself either.
    with pytest.raises(FormatError, match=r"z\.node, line 1: 0 vertices declared, .* which is this very file"):
        read_poly(tmp_path / "z.node")
    # The command line reports it without a traceback.
    from meshwright.cli import main

    assert main(["mesh", str(tmp_path / "z.poly"), "-o", str(tmp_path / "z.vtu")]) != 0
    err = capsys.readouterr().err
    assert "z.node, line 1: declares 0 vertices" in err and "Traceback" not in err


def test_triangle_set_names_with_dots(tmp_path):
    """Triangle names iteration k of ``A`` ``A.k.node``: the stem keeps its own dots."""
    mesh = marked_square(2)
    written = write_triangle(mesh, tmp_path / "sq.1.node")
    assert [p.name for p in written] == ["sq.1.node", "sq.1.ele", "sq.1.poly"]
    (tmp_path / "sq.node").write_text("1 2 0 0\n1 5 5\n")  # a decoy the old stem handling read
    back = read(tmp_path / "sq.1.ele")
    assert_same(mesh, back)


def test_hand_written_example_files():
    """Files in tests/data written by hand in Triangle's formats; expected values typed in."""
    a = read_poly(DATA / "letter_a.poly")
    assert a.first_index == 1 and a.vertices.shape == (11, 2) and a.segment_markers is None
    np.testing.assert_allclose(a.vertex_attributes[:, 0], np.arange(1, 12) / 10)
    assert a.segments[7].tolist() == [7, 0] and a.segments[10].tolist() == [10, 8]
    np.testing.assert_array_equal(a.holes, [[2.0, 2.5]])
    ring = read_poly(DATA / "ring.poly")
    assert ring.vertex_path.name == "ring.node" and ring.first_index == 0
    assert ring.vertex_markers.tolist() == [1] * 12 + [2] * 4
    np.testing.assert_allclose(ring.vertices[3], [0.0, 2.0], atol=1e-6)
    assert ring.segments[16].tolist() == [0, 14] and ring.segment_markers[16] == 0
    np.testing.assert_array_equal(ring.regions, [[0.0, 1.25, 1, 0.05], [0.0, -1.25, 2, -1]])
    spiral = read_node(DATA / "spiral.node")
    assert spiral.points.shape == (15, 2) and spiral.first_index == 1 and spiral.markers is None
    np.testing.assert_array_equal(spiral.points[1], [0.2953, 0.3721])


def _triangle_data_dir():
    triangle = pytest.importorskip("triangle")
    data = Path(triangle.__file__).parent / "data"
    if not data.is_dir():
        pytest.skip("the triangle package ships no example files")
    return triangle, data


TRIANGLE_POLY = ["A", "box", "double_hex", "double_hex2", "double_hex3", "face", "la", "square_circle_hole"]
TRIANGLE_SETS = ["A.1", "box.4", "double_hex3.1", "face.1", "la.1", "greenland", "spiral.q.1"]


@pytest.mark.parametrize("name", TRIANGLE_POLY)
def test_triangle_example_poly_files_read_like_triangle_py(name):
    """Every .poly file that ships with Triangle parses; the triangle package's own reader is
    the oracle for vertices, segments, markers and holes."""
    triangle, data = _triangle_data_dir()
    poly = read_poly(data / f"{name}.poly")
    ref = triangle.load(str(data), name)
    np.testing.assert_array_equal(poly.vertices, ref["vertices"])
    np.testing.assert_array_equal(poly.segments, ref["segments"])
    if "segment_markers" in ref:
        np.testing.assert_array_equal(poly.segment_markers, ref["segment_markers"][:, 0])
    np.testing.assert_array_equal(poly.holes, ref.get("holes", np.zeros((0, 2))))


def test_voronoi_edge_file_with_rays_reads_like_triangle_py():
    triangle, data = _triangle_data_dir()
    edge = read_edge(data / "diamond_02_00009.1.v.edge")
    ref = triangle.load(str(data), "diamond_02_00009.1.v")
    ray = edge.edges[:, 1] == -1
    np.testing.assert_array_equal(edge.edges[~ray], ref["edges"])
    np.testing.assert_array_equal(edge.edges[ray, 0], ref["ray_origins"][:, 0])
    np.testing.assert_array_equal(edge.directions[ray], ref["ray_directions"])
    assert edge.markers is None and not edge.directions[~ray].any()


def test_area_file_of_triangle():
    _, data = _triangle_data_dir()
    area = read_area(data / "bbox.1.area", n_triangles=12)
    assert area.tolist() == [-1, -1, 0.02] + [-1] * 9


def test_neigh_file_round_trip_with_triangle():
    """Triangle's neighbours (written to a .neigh here) read back; neighbour k lies across
    the edge opposite corner k."""
    triangle = pytest.importorskip("triangle")
    pts = np.random.default_rng(5).random((30, 2))
    out = triangle.triangulate({"vertices": pts}, "n")
    tri, nbr = out["triangles"], out["neighbors"]
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "d.1.neigh"
        rows = "\n".join(f"{t + 1} " + " ".join(str(n + 1 if n >= 0 else -1) for n in row) for t, row in enumerate(nbr))
        path.write_text(f"# neighbours\n{len(tri)} 3\n{rows}\n")
        got = read_neigh(path, n_triangles=len(tri))
    np.testing.assert_array_equal(got, nbr)
    for t in range(len(tri)):
        for k in range(3):
            if got[t, k] >= 0:
                assert set(tri[t]) - {tri[t, k]} <= set(tri[got[t, k]])


@pytest.mark.parametrize(
    "name, text, call, pattern",
    [
        ("e.edge", "2 1\n1 1 2 0\n2 1 -1 1 0\n", read_edge, r"e\.edge, line 3: an edge line holds 3 to 4 fields .* got 5"),
        ("e.edge", "1 0\n1 1 -1\n", read_edge, r"e\.edge, line 2: a ray line \(b = -1\)"),
        ("e.edge", "1 0\n1 1 2 7\n", read_edge, r"e\.edge, line 2: an edge line holds 3 to 3 fields, got 4"),
        ("e.edge", "1 0\n1 1 0\n", read_edge, r"e\.edge, line 2: edge refers to vertex \[1, 0\] outside"),
        ("n.neigh", "1 3\n1 2 -1 -1\n", read_neigh, r"n\.neigh, line 2: neighbours \[2, -1, -1\] outside 1\.\.1"),
        ("n.neigh", "1 4\n", read_neigh, r"n\.neigh, line 1: triangles have 3 neighbours"),
        ("a.area", "2\n1 0.5\n2 inf\n", read_area, r"a\.area, line 3: triangle maximum area: 'inf'"),
        ("a.area", "2\n1 0.5\n", read_area, r"a\.area, line 2: unexpected end of file: line 1 declares 2 triangles"),
    ],
)
def test_malformed_edge_neigh_area_files(tmp_path, name, text, call, pattern):
    (tmp_path / name).write_text(text)
    with pytest.raises(FormatError, match=pattern):
        call(tmp_path / name)
    with pytest.raises(InputError, match="must be None"):
        call(tmp_path / name, **({"n_triangles": -1} if call is not read_edge else {"first_index": 2}))


def test_la_regions_read_as_triangle_wrote_them_back():
    """Triangle read la.poly (four-field region lines) and wrote la.1.poly: same regions."""
    _, data = _triangle_data_dir()
    np.testing.assert_array_equal(read_poly(data / "la.poly").regions, read_poly(data / "la.1.poly").regions)


@pytest.mark.parametrize("name", TRIANGLE_SETS)
def test_triangle_example_meshes_read_like_triangle_py(name):
    triangle, data = _triangle_data_dir()
    mesh = read(data / f"{name}.ele")
    ref = triangle.load(str(data), name)
    np.testing.assert_array_equal(mesh.points, ref["vertices"])
    np.testing.assert_array_equal(mesh.triangles, ref["triangles"])
    if "vertex_markers" in ref:
        np.testing.assert_array_equal(mesh.point_data["marker"], ref["vertex_markers"][:, 0])
    if "segments" in ref:
        np.testing.assert_array_equal(mesh.lines, ref["segments"])
    mesh.validate()


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
    with pytest.raises(FormatError, match=r"missing\.vtu: no such file"):
        read(tmp_path / "missing.vtu")
    (tmp_path / "dir.vtu").mkdir()
    with pytest.raises(FormatError, match=r"dir\.vtu: not a regular file"):
        read(tmp_path / "dir.vtu")
    marked_square().write(tmp_path / "ok.vtu")
    with pytest.raises(InputError, match="dim must be None, 2 or 3, got 4"):
        read(tmp_path / "ok.vtu", dim=4)


@pytest.mark.parametrize(
    "name, content",
    [
        ("latin1.vtk", b"# vtk DataFile Version 4.2\ncaf\xe9\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 3 dou\xffble\n"),
        ("cut.off", b"OFF\n# Created by hand\n"),  # meshio 5.3 loops forever on this
        ("cut.ply", b"ply\nformat ascii 1.0\nelement vertex 3\n"),  # and on this
        ("noise.msh", bytes(range(256)) * 4),
        ("empty.vtu", b""),
    ],
)
def test_corrupt_meshio_files_are_format_errors(tmp_path, name, content):
    (tmp_path / name).write_bytes(content)
    with pytest.raises(FormatError, match=re.escape(name) + ": cannot read"):
        read(tmp_path / name)


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
