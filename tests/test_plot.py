"""Mesh plots render headless into non-empty PNG files."""

import numpy as np
import pytest

from meshwright.core.errors import InputError
from meshwright.core.mesh import Mesh
from meshwright.plot.mesh_plot import plot_mesh, plot_triangulation

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def grid(n=6):
    x, y = np.meshgrid(np.linspace(0, 1, n + 1), np.linspace(0, 1, n + 1))
    pts = np.column_stack([x.ravel(), y.ravel()])
    idx = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel(), idx[1:, :-1].ravel()
    tri = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    lines = np.concatenate([np.column_stack([idx[0, :-1], idx[0, 1:]]), np.column_stack([idx[-1, 1:], idx[-1, :-1]])])
    regions = np.where(pts[tri].mean(axis=1)[:, 0] < 0.5, 1, 2)
    markers = np.repeat([1, 3], n)
    return Mesh(pts, {"triangle": tri, "line": lines}, cell_data={"marker": {"triangle": regions, "line": markers}})


def assert_png(path):
    data = path.read_bytes()
    assert data[:8] == PNG_MAGIC and len(data) > 2000


def test_plot_mesh_writes_png_headless(tmp_path):
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    ax = grid().plot(path=tmp_path / "mesh.png")
    assert isinstance(ax.figure.canvas, FigureCanvasAgg)
    assert ax.get_aspect() == 1.0
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["marker 1", "marker 3"]
    assert_png(tmp_path / "mesh.png")


@pytest.mark.parametrize(
    "kwargs", [{"show_quality": "min_angle"}, {"color_by": "marker"}, {"color_by": np.arange(72.0)}, {"show_points": True}]
)
def test_plot_mesh_colouring(tmp_path, kwargs):
    path = tmp_path / "c.png"
    plot_mesh(grid(), path=path, title="colours", **kwargs)
    assert_png(path)


def test_plot_mesh_quads_and_3d(tmp_path):
    pts = np.array([[0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1.0]])
    plot_mesh(Mesh(pts, {"quad": [[0, 1, 4, 3], [1, 2, 5, 4]]}), path=tmp_path / "q.png")
    assert_png(tmp_path / "q.png")
    cube = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)
    tets = [[0, 1, 2, 6], [0, 2, 3, 6], [0, 3, 7, 6], [0, 7, 4, 6], [0, 4, 5, 6], [0, 5, 1, 6]]
    ax = plot_mesh(Mesh(cube, {"tetra": tets}), path=tmp_path / "t.png")
    assert ax.name == "3d"
    assert_png(tmp_path / "t.png")


def test_plot_into_given_axes_and_triangulation(tmp_path):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure()
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    mesh = grid(3)
    assert plot_mesh(mesh, ax=ax) is ax
    out = plot_triangulation(mesh.points, mesh.triangles, ax=ax, show_points=True, path=tmp_path / "t.png")
    assert out is ax
    assert_png(tmp_path / "t.png")
    ax2 = plot_triangulation(mesh.points, mesh.triangles, values=mesh.quality()["triangle"]["area"], path=tmp_path / "v.png")
    assert ax2 is not ax
    assert_png(tmp_path / "v.png")


def test_plot_large_mesh_draws_one_collection_per_cell_type(tmp_path):
    # What keeps large plots fast: the artists do not grow with the mesh (one PolyCollection
    # of all triangles, one LineCollection of all line cells), as for a small mesh.
    from matplotlib.collections import LineCollection, PolyCollection

    mesh = grid(100)  # 20 000 triangles
    ax = plot_mesh(mesh, path=tmp_path / "big.png", dpi=60)
    assert len(ax.get_children()) == len(plot_mesh(grid(3)).get_children())
    polys = [c for c in ax.collections if isinstance(c, PolyCollection)]
    lines = [c for c in ax.collections if isinstance(c, LineCollection)]
    assert [len(c.get_paths()) for c in polys] == [len(mesh.cells["triangle"])]
    assert sum(len(c.get_segments()) for c in lines) == len(mesh.cells["line"])
    assert not ax.patches and not ax.lines
    assert_png(tmp_path / "big.png")


def test_plot_errors_name_the_option():
    mesh = grid(2)
    with pytest.raises(InputError, match="no quality measure 'volume'"):
        plot_mesh(mesh, show_quality="volume")
    with pytest.raises(InputError, match="not a cell_data name"):
        plot_mesh(mesh, color_by="nope")
    with pytest.raises(InputError, match="not both"):
        plot_mesh(mesh, show_quality="area", color_by="marker")
    with pytest.raises(InputError, match=r"shape \(8,\)"):
        plot_mesh(mesh, color_by=np.zeros(3))
    with pytest.raises(InputError, match=r"triangles must have shape"):
        plot_triangulation(mesh.points, np.zeros((2, 4), int))


def test_plot_tetra_surface_quality_and_histogram(tmp_path):
    from meshwright.plot.mesh_plot import plot_quality_histogram

    pts = np.random.default_rng(0).random((60, 3))
    spatial = pytest.importorskip("scipy.spatial")
    tets = spatial.Delaunay(pts).simplices
    p = pts[tets]
    neg = np.linalg.det(p[:, 1:] - p[:, :1]) < 0
    tets[neg, 0], tets[neg, 1] = tets[neg, 1], tets[neg, 0].copy()
    mesh = Mesh(pts, {"tetra": tets})
    ax = mesh.plot(path=tmp_path / "q.png", show_quality="min_dihedral", title="dihedrals")
    assert ax.name == "3d" and len(ax.figure.axes) == 3  # surface, colour bar, histogram
    assert_png(tmp_path / "q.png")
    hist = plot_quality_histogram(mesh, "sliver_ratio", path=tmp_path / "h.png")
    assert "sliver flag" in [t.get_text() for t in hist.get_legend().get_texts()][0]
    assert_png(tmp_path / "h.png")
    with pytest.raises(InputError, match="no quality measure 'min_angle'"):
        mesh.plot(show_quality="min_angle")
    with pytest.raises(InputError, match="color_by is for 2-D"):
        mesh.plot(color_by="marker")
    with pytest.raises(InputError, match="bins must be"):
        plot_quality_histogram(mesh, bins=0)
