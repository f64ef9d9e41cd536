"""Float cell data (``region_attribute``, as ``triangulate`` gives la.poly's regions) through
every format that can hold it (Gmsh 2.2 and 4.1, VTU, VTK, XDMF), the warning of those that
cannot, and Triangle's ``.ele`` / ``.poly`` carrying it as Triangle's ``-A`` writes it.

Oracles: attributes computed here from coordinates, ``.ele`` columns split by hand, and
Triangle (the ``triangle`` package) loading the written files and re-meshing the ``.poly``.
"""

import warnings
from pathlib import Path

import numpy as np
import pytest
from test_io import marked_square

from meshwright.core.mesh import Mesh
from meshwright.io import read, read_poly, write_triangle
from meshwright.io.meshio_io import DataLossWarning

def with_region_attribute(mesh: Mesh, lines: bool = True) -> Mesh:
    """``mesh`` plus a float64 ``region_attribute``: 0.05 + the centroid's x on triangles
    (not integral: implied marker 0), 0.0 on the lines (as ``triangulate`` gives)."""
    tri = mesh.triangles
    data = {"triangle": 0.05 + mesh.points[tri].mean(axis=1)[:, 0]}
    if lines:
        data["line"] = np.zeros(len(mesh.lines))
    cell_data = {**mesh.cell_data, "region_attribute": data}
    return Mesh(mesh.points, mesh.cells, point_data=mesh.point_data, cell_data=cell_data)


def cell_rows(mesh: Mesh, cell_type: str) -> np.ndarray:
    """Cells as (vertex coordinates, marker, region attribute) rows, sorted: equal for two
    meshes exactly when they hold the same cells with the same data, in any order."""
    cells = mesh.cells[cell_type]
    rows = np.column_stack(
        [
            mesh.points[cells].reshape(len(cells), -1),
            mesh.cell_data["marker"][cell_type],
            mesh.cell_data["region_attribute"][cell_type],
        ]
    )
    return rows[np.lexsort(rows.T[::-1])]


CELL_DATA_CASES = [
    ("m.msh", {}),
    ("m.msh", {"binary": True}),
    ("m.msh", {"file_format": "gmsh"}),
    ("m.msh", {"file_format": "gmsh", "binary": True}),
    ("m.vtu", {}),
    ("m.vtk", {}),
    ("m.xdmf", {}),
]
CELL_DATA_IDS = ["msh22", "msh22-binary", "msh41", "msh41-binary", "vtu", "vtk", "xdmf"]


@pytest.mark.parametrize("name, kwargs", CELL_DATA_CASES, ids=CELL_DATA_IDS)
def test_markers_and_float_cell_data_round_trip(tmp_path, name, kwargs):
    """Two cell blocks, two region markers and a float region attribute: meshio 5.3's own
    Gmsh 2.2 reader cannot split such ElementData (issue 14's follow-up)."""
    if name.endswith(".xdmf"):
        pytest.importorskip("h5py")
    mesh = with_region_attribute(marked_square())
    path = tmp_path / name
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # these formats keep the data: no DataLossWarning
        mesh.write(path, **kwargs)
    back = read(path)
    back.validate()
    assert sorted(back.cell_data) == ["marker", "region_attribute"]
    for t in ("triangle", "line"):
        assert back.cell_data["region_attribute"][t].dtype == np.float64
        np.testing.assert_array_equal(cell_rows(back, t), cell_rows(mesh, t))
    if kwargs.get("file_format") != "gmsh":  # only Gmsh 4.1 regroups the cells by marker
        expected = 0.05 + back.points[back.triangles].mean(axis=1)[:, 0]
        np.testing.assert_array_equal(back.cell_data["region_attribute"]["triangle"], expected)


@pytest.mark.parametrize("kwargs", [{}, {"file_format": "gmsh"}], ids=["msh22", "msh41"])
def test_float_cell_data_missing_on_a_block_reads_back_as_nan(tmp_path, kwargs):
    mesh = with_region_attribute(marked_square(), lines=False)
    mesh.write(tmp_path / "m.msh", **kwargs)
    back = read(tmp_path / "m.msh")
    assert np.isnan(back.cell_data["region_attribute"]["line"]).all()
    assert not np.isnan(back.cell_data["region_attribute"]["triangle"]).any()


def test_la_region_attributes_round_trip_through_gmsh(tmp_path):
    """la.poly (the triangle package's example: float regional attributes, markers 0 and 3)
    meshed, written as Gmsh 2.2 and 4.1, reads back with the same attributes."""
    triangle = pytest.importorskip("triangle")
    folder = Path(triangle.__file__).parent / "data"
    if not (folder / "la.poly").is_file():
        pytest.skip("the triangle package ships no example files")
    import meshwright as mw

    la = mw.triangulate(mw.geometry.read_poly(folder / "la.poly"))
    assert len(np.unique(la.cell_data["marker"]["triangle"])) > 1
    for kwargs in ({}, {"file_format": "gmsh"}):
        la.write(tmp_path / "la.msh", **kwargs)
        back = read(tmp_path / "la.msh")
        for t in ("triangle", "line"):
            np.testing.assert_array_equal(cell_rows(back, t), cell_rows(la, t))


@pytest.mark.parametrize("name, dropped", [("m.mesh", "region_attribute"), ("m.off", "marker, region_attribute")])
def test_formats_without_float_cell_data_warn(tmp_path, name, dropped):
    """Medit keeps the marker only, OFF no cell data: the file is written and reads back,
    with a DataLossWarning naming what it left out."""
    mesh = with_region_attribute(marked_square())
    with pytest.warns(DataLossWarning, match=f"cannot store cell data {dropped};"):
        mesh.write(tmp_path / name)
    back = read(tmp_path / name)
    assert "region_attribute" not in back.cell_data
    if name == "m.mesh":
        np.testing.assert_array_equal(back.cell_data["marker"]["triangle"], mesh.cell_data["marker"]["triangle"])


def ele_columns(path: Path) -> np.ndarray:
    """The attribute columns of an .ele, parsed here by splitting lines (not by read_ele)."""
    lines = [ln.split("#")[0].split() for ln in path.read_text().splitlines()]
    lines = [ln for ln in lines if ln]
    n, k, a = (int(v) for v in lines[0])
    return np.array([[float(v) for v in ln[1 + k : 1 + k + a]] for ln in lines[1 : 1 + n]]).reshape(n, a)


def test_ele_holds_the_float_region_attribute(tmp_path):
    """As Triangle's -A: the .ele attribute column is the region attribute, which reads
    back exactly; the .poly has a region point per attribute value."""
    mesh = with_region_attribute(marked_square())
    zeros = {"triangle": np.zeros(len(mesh.triangles), np.int32)}
    implied = Mesh(
        mesh.points, mesh.cells, cell_data={"marker": zeros, "region_attribute": mesh.cell_data["region_attribute"]}
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # markers all 0: implied by the float attributes
        write_triangle(implied, tmp_path / "m.node")
    attribute = mesh.cell_data["region_attribute"]["triangle"]
    np.testing.assert_array_equal(ele_columns(tmp_path / "m.ele"), attribute[:, None])
    np.testing.assert_array_equal(read(tmp_path / "m.node").cell_data["attributes"]["triangle"], attribute[:, None])
    poly = read_poly(tmp_path / "m.poly")
    assert set(poly.regions[:, 2].tolist()) == set(attribute.tolist())
    # Markers 1 | 2 are not implied by non-integral attributes: written without them, said so.
    with pytest.warns(DataLossWarning, match="triangle markers"):
        write_triangle(mesh, tmp_path / "w.node")
    np.testing.assert_array_equal(ele_columns(tmp_path / "w.ele"), attribute[:, None])


def test_la_ele_and_poly_carry_region_attributes_triangle_reads(tmp_path):
    triangle = pytest.importorskip("triangle")
    folder = Path(triangle.__file__).parent / "data"
    if not (folder / "la.poly").is_file():
        pytest.skip("the triangle package ships no example files")
    import meshwright as mw

    la = mw.triangulate(mw.geometry.read_poly(folder / "la.poly"))
    attribute = la.cell_data["region_attribute"]["triangle"]
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # la's markers (3 where the attribute is 3.0) are implied
        la.write(tmp_path / "la.1.node")
    np.testing.assert_array_equal(ele_columns(tmp_path / "la.1.ele"), attribute[:, None])
    np.testing.assert_array_equal(read(tmp_path / "la.1.node").cell_data["attributes"]["triangle"][:, 0], attribute)
    ref = triangle.load(str(tmp_path), "la.1")
    np.testing.assert_array_equal(ref["triangles"], la.triangles)
    np.testing.assert_array_equal(ref["triangle_attributes"][:, 0], attribute)
    # Triangle's -A re-meshing the written .poly gives every attribute the same area as la
    # (its two separate 0.05 regions need a region point each).  The package's loader drops
    # the attribute of 5-field region lines, so the regions are passed as read here.
    poly = read_poly(tmp_path / "la.1.poly")
    assert set(poly.regions[:, 2].tolist()) == {0.0, 0.05, 0.2, 0.4, 0.8, 3.0}  # la.poly's, typed
    regions = np.column_stack([poly.regions[:, :3], np.zeros(len(poly.regions))])
    again = triangle.triangulate({"vertices": ref["vertices"], "segments": poly.segments, "regions": regions}, "pA")
    again_attribute = again["triangle_attributes"][:, 0]

    def areas(points, triangles):
        a, b, c = (points[triangles[:, k]] for k in range(3))
        return 0.5 * np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))

    ours, theirs = areas(la.points, la.triangles), areas(again["vertices"], again["triangles"])
    assert set(again_attribute.tolist()) == set(attribute.tolist())
    for value in set(attribute.tolist()):
        assert theirs[again_attribute == value].sum() == pytest.approx(ours[attribute == value].sum(), rel=1e-12)
