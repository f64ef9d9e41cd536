"""``meshwright tet`` and the tetrahedral mesh picture (plot/tet_plot.py)."""

from collections import Counter
from fractions import Fraction

import numpy as np
import pytest

from meshwright.core.errors import InputError
from meshwright.core.mesh import Mesh
from meshwright.plot.tet_plot import clipped_faces, plot_tet_mesh

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def assert_png(path):
    data = path.read_bytes()
    assert data[:8] == PNG_MAGIC and len(data) > 2000


def cube_grid(n=3):
    """n^3 unit cubes of side 1/n, six tets each (around the main diagonal), positive."""
    g = np.linspace(0.0, 1.0, n + 1)
    pts = np.stack(np.meshgrid(g, g, g, indexing="ij"), -1).reshape(-1, 3)
    idx = np.arange((n + 1) ** 3).reshape(n + 1, n + 1, n + 1)
    corner = [idx[i : i + n, j : j + n, k : k + n].ravel() for i in (0, 1) for j in (0, 1) for k in (0, 1)]
    c = dict(zip([(i, j, k) for i in (0, 1) for j in (0, 1) for k in (0, 1)], corner))
    paths = [((1, 0, 0), (1, 1, 0)), ((1, 0, 0), (1, 0, 1)), ((0, 1, 0), (1, 1, 0)), ((0, 1, 0), (0, 1, 1)),
             ((0, 0, 1), (1, 0, 1)), ((0, 0, 1), (0, 1, 1))]  # fmt: skip
    tets = np.concatenate([np.column_stack([c[(0, 0, 0)], c[a], c[b], c[(1, 1, 1)]]) for a, b in paths])
    p = pts[tets]
    neg = np.einsum("mi,mi->m", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])) < 0
    tets[neg, 0], tets[neg, 1] = tets[neg, 1], tets[neg, 0].copy()
    return Mesh(pts, {"tetra": tets})


def det3(a, b, c, d):
    """Exact orientation determinant det[b-a, c-a, d-a] over rationals."""
    u, v, w = ([Fraction(float(x)) - Fraction(float(y)) for x, y in zip(p, a)] for p in (b, c, d))
    return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0])


@pytest.mark.parametrize("normal", [(1.0, 0.0, 0.0), (0.3, -1.0, 0.2)])
def test_clipped_faces_are_the_faces_of_the_kept_tets_seen_once(normal):
    mesh = cube_grid(3)
    origin = np.array([0.5, 0.45, 0.5])
    faces, owner, on_cut = clipped_faces(mesh, cut=(origin, normal))
    tets = mesh.tetra
    # Oracle: the kept tets by their centroid in exact arithmetic, their faces counted by vertex set.
    n = [Fraction(x) for x in normal]
    o = [Fraction(float(x)) for x in origin]

    def kept(t):
        cen = [sum(Fraction(float(mesh.points[v][i])) for v in t) / 4 for i in range(3)]
        return sum((cen[i] - o[i]) * n[i] for i in range(3)) <= 0

    keep = [kept(t) for t in tets]
    def faces_of(t):
        return [frozenset(int(v) for v in t if v != t[k]) for k in range(4)]

    all_faces = Counter(f for t in tets for f in faces_of(t))
    kept_faces = Counter(f for t, kp in zip(tets, keep) if kp for f in faces_of(t))
    expected = {f for f, count in kept_faces.items() if count == 1}
    got = [frozenset(int(v) for v in f) for f in faces]
    assert len(got) == len(set(got)) and set(got) == expected
    assert 0 < sum(keep) < len(tets)
    for f, t, cut in zip(faces, owner, on_cut):
        assert keep[t]
        assert cut == (all_faces[frozenset(int(v) for v in f)] == 2)
        apex = next(v for v in tets[t] if v not in f)
        # Outward: the owner's fourth vertex lies behind the face.
        assert det3(*(mesh.points[v] for v in (*f, apex))) < 0


def test_plot_tet_mesh_three_panels_and_png(tmp_path):
    mesh = cube_grid(4)
    faces = mesh.boundary_facets()
    markers = np.where(mesh.points[faces].mean(axis=1)[:, 2] > 0.999, 2, 1)
    marked = Mesh(mesh.points, {"tetra": mesh.tetra, "triangle": faces}, cell_data={"marker": {"triangle": markers}})
    path = tmp_path / "tet.png"
    fig = plot_tet_mesh(marked, path, title="cube", measure="radius_ratio")
    surf, cut, hist = fig.axes[:3]
    assert surf.name == "3d" and cut.name == "3d" and hist.name == "rectilinear"
    assert [t.get_text() for t in surf.get_legend().get_texts()] == ["marker 1", "marker 2"]
    # One collection per 3-D panel (matplotlib depth-sorts within a collection only).
    assert len(surf.collections) == 1 and len(surf.collections[0].get_paths()) == len(faces)
    assert len(cut.collections) == 1
    assert "10 deg" in [t.get_text() for t in hist.get_legend().get_texts()]
    assert fig._suptitle.get_text() == "cube"
    assert_png(path)


def test_plot_tet_mesh_of_a_delaunay_mesh_and_mesh_plot_dispatch(tmp_path):
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from meshwright import delaunay

    mesh = delaunay(np.random.default_rng(3).random((200, 3))).to_mesh()
    fig = plot_tet_mesh(mesh)
    assert isinstance(fig.canvas, FigureCanvasAgg) and len(fig.axes) == 4  # 3 panels + colour bar
    ax = mesh.plot(path=tmp_path / "m.png")
    assert ax.name == "3d" and len(ax.figure.axes) == 4
    assert_png(tmp_path / "m.png")


def test_plot_tet_mesh_refuses_bad_arguments():
    mesh = cube_grid(1)
    with pytest.raises(InputError, match="needs a 3-D mesh with tetra"):
        plot_tet_mesh(Mesh(np.zeros((3, 2)) + [[0, 0], [1, 0], [0, 1]], {"triangle": [[0, 1, 2]]}))
    with pytest.raises(InputError, match="no quality measure 'min_angle'"):
        plot_tet_mesh(mesh, measure="min_angle")
    with pytest.raises(InputError, match="nonzero"):
        plot_tet_mesh(mesh, cut=((0, 0, 0), (0, 0, 0)))
    with pytest.raises(InputError, match="two 3-vectors"):
        clipped_faces(mesh, cut=((0, 0), (1, 0, 0)))
    with pytest.raises(InputError, match="finite"):
        clipped_faces(mesh, cut=((0, 0, np.nan), (1, 0, 0)))
    with pytest.raises(InputError, match="bins must be"):
        plot_tet_mesh(mesh, bins=0)
    with pytest.raises(InputError, match="must be a meshwright Mesh"):
        plot_tet_mesh("mesh.vtu")


# ---------------------------------------------------------------------------- the CLI


def icosahedron_file(path, drop_face=False):
    """A unit icosahedron (outward faces) written by meshio, optionally with a face missing."""
    meshio = pytest.importorskip("meshio")
    t = (1.0 + 5.0**0.5) / 2.0
    pts = np.array([[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
                    [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]], float)  # fmt: skip
    pts /= np.linalg.norm(pts, axis=1)[:, None]
    faces = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4],
                      [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8],
                      [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]])  # fmt: skip
    if drop_face:
        faces = faces[1:]
    meshio.write_points_cells(str(path), pts, [("triangle", faces)])
    return pts, faces


def enclosed_volume(pts, faces):
    """Volume inside outward faces: the sum of det[a, b, c] / 6 (exact rationals)."""
    total = Fraction(0)
    for f in faces:
        total += det3(np.zeros(3), *(pts[v] for v in f))
    return total / 6


def one_error_line(capsys):
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("meshwright tet: error:"), err
    return err[0]


def test_cli_tet_meshes_a_surface_file_and_writes_mesh_plot_quality(tmp_path, capsys):
    from meshwright import read
    from meshwright.cli import main

    pts, faces = icosahedron_file(tmp_path / "ico.stl")
    out, png = tmp_path / "ico.vtu", tmp_path / "ico.png"
    argv = ["tet", str(tmp_path / "ico.stl"), "-o", str(out), "--size", "0.4", "--radius-edge", "1.6"]
    assert main([*argv, "--quality", "--plot", str(png), "--seed", "3"]) == 0
    text = capsys.readouterr().out
    assert "tetrahedra in" in text and "min_dihedral" in text and f"wrote {png}" in text
    assert_png(png)
    mesh = read(out)
    assert mesh.dim == 3 and len(mesh.tetra) > 20
    vol = mesh.quality()["tetra"]["volume"]
    assert (vol > 0).all()
    assert vol.sum() == pytest.approx(float(enclosed_volume(pts, faces)), rel=1e-9)


def test_cli_tet_meshes_a_builtin_solid_by_name(tmp_path):
    from meshwright import read
    from meshwright.cli import main

    assert main(["tet", "box", "--size", "0.5", "-o", str(tmp_path / "box.vtu")]) == 0
    mesh = read(tmp_path / "box.vtu")
    assert mesh.quality()["tetra"]["volume"].sum() == pytest.approx(1.0, rel=1e-12)
    assert set(np.unique(mesh.cell_data["marker"]["triangle"])) == {1, 2, 3, 4, 5, 6}


def test_cli_tet_options_reach_the_mesher(tmp_path, capsys):
    from meshwright.cli import main

    icosahedron_file(tmp_path / "ico.stl")
    src = str(tmp_path / "ico.stl")
    assert main(["tet", src, "--no-refine"]) == 0
    coarse = int(capsys.readouterr().out.split(": ")[1].split()[0])
    assert main(["tet", src, "--max-volume", "0.01", "--slivers", "keep"]) == 0
    fine = int(capsys.readouterr().out.split(": ")[1].split()[0])
    assert fine > 10 * coarse
    assert main(["tet", src, "--region", "0", "0", "0", "5", "-1", "-o", str(tmp_path / "r.vtu")]) == 0
    from meshwright import read

    assert set(np.unique(read(tmp_path / "r.vtu").cell_data["marker"]["tetra"])) == {5}


@pytest.mark.parametrize(
    "args, words",
    [
        (["missing.stl"], "no such file"),
        (["{ico}", "--size", "-1"], "size"),
        (["{ico}", "--size", "nan"], "size"),
        (["{ico}", "--radius-edge", "0.5"], "radius_edge"),
        (["{ico}", "--max-volume", "0"], "max_volume"),
        (["{ico}", "--smooth", "-2"], "smooth"),
        (["{ico}", "--max-points", "5", "--size", "0.01"], "max_points"),
        (["{ico}", "--no-refine", "--radius-edge", "2"], "mutually exclusive"),
        (["{ico}", "--region", "0", "0", "0", "1.5", "0"], "region id must be an integer"),
        (["{open}"], "open edge"),
    ],
)
def test_cli_tet_bad_input_is_one_line_and_exit_2(tmp_path, capsys, args, words):
    from meshwright.cli import main

    icosahedron_file(tmp_path / "ico.stl")
    icosahedron_file(tmp_path / "open.stl", drop_face=True)
    argv = [a.format(ico=tmp_path / "ico.stl", open=tmp_path / "open.stl") for a in args]
    assert main(["tet", *argv]) == 2
    assert words in one_error_line(capsys)


def test_cli_tet_usage_errors_exit_2(capsys):
    from meshwright.cli import main

    for argv in (["tet"], ["tet", "x.stl", "--slivers", "maybe"], ["tet", "x.stl", "--method", "nope"]):
        with pytest.raises(SystemExit) as info:
            main(argv)
        assert info.value.code == 2
    assert "invalid choice" in capsys.readouterr().err


def test_demo_solids_are_meshed_written_and_drawn(tmp_path, capsys):
    from meshwright import read
    from meshwright.cli.demo import mesh_solids, solids

    mesh_solids(tmp_path)
    assert capsys.readouterr().out.count("(tetrahedralize):") == 3  # one result line per solid
    for name, surface, _ in solids():
        assert_png(tmp_path / f"{name}-tet.png")
        mesh = read(tmp_path / f"{name}-tet.vtu")
        mesh.validate()
        # The tets fill what the input surface encloses: its exact volume, face by face.
        vol = enclosed_volume(surface.points, surface.triangles)
        assert mesh.quality()["tetra"]["volume"].sum() == pytest.approx(float(vol), rel=1e-9)
        got = set(np.unique(mesh.cell_data["marker"]["triangle"]))
        assert got == set(np.unique(surface.markers)), name
