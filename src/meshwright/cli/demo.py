"""``meshwright demo [DIR]``: mesh built-in examples and write .vtu files and .png pictures.

The demo reproduces chapter 18.1's circle example (Figure 18.1.5): points on a circle
and inside it, triangulated by Bowyer's and Watson's algorithms, with the Voronoi
diagram of the same points (Figure 18.1.1); then quality meshes of NACA 0012 in a far
field by Delaunay refinement, Weatherill's point generation with smoothing (18.1.3, 18.2)
and the advancing front (18.2), and of the three-element airfoil (Figure 18.3.1) by
Delaunay refinement and by the frontal Delaunay method (18.3); then all-quad meshes
(18.5) of the three-element airfoil by the quadtree (Yerry and Shephard, 18.5.3) and of
NACA 0012 by triangle pairing (Zhu et al., 18.5.1) and by paving (Blacker and Stephenson,
18.5.2); last, quality tetrahedral meshes (18.4)
of a sphere, a box with a spherical cavity and a NACA 0012 wing (the section extruded) in a
box far field (Figure 18.4.1), each drawn as its boundary, a clipped cut and the dihedral
histogram.  Sizes are coarse so that every case takes seconds once compiled.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from meshwright.cli._common import Timer
from meshwright.geometry import builtin, sphere
from meshwright.quad import quadrangulate
from meshwright.tet import tetrahedralize
from meshwright.tet.builtin_surfaces import box_cavity, naca_wing
from meshwright.tri import delaunay, triangulate
from meshwright.tri.voronoi import voronoi

NAME = "demo"
HELP = "mesh the built-in examples into DIR (.vtu meshes and .png pictures)"


def add_arguments(parser) -> None:
    parser.add_argument("directory", nargs="?", default="demo-output", help="output folder (created)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the random interior points")


def circle_points(n_boundary: int, n_interior: int, rng: np.random.Generator) -> np.ndarray:
    """Return ``n_boundary`` points on the unit circle and ``n_interior`` uniform points inside.

    Returns
    -------
    points : (n_boundary + n_interior, 2) float64
    """
    theta = np.linspace(0.0, 2.0 * np.pi, n_boundary, endpoint=False)
    boundary = np.column_stack([np.cos(theta), np.sin(theta)])
    r = 0.95 * np.sqrt(rng.random(n_interior))
    phi = 2.0 * np.pi * rng.random(n_interior)
    interior = np.column_stack([r * np.cos(phi), r * np.sin(phi)])
    return np.ascontiguousarray(np.vstack([boundary, interior]))


def kernels_cached() -> bool:
    """Whether Numba's on-disk cache already holds the 2-D insertion kernel (not a first run).

    Reads the cache index path of ``tri._build2d.insert_batch`` from Numba's dispatcher; where
    this Numba keeps it elsewhere, answers False (the first-run notice is then printed anyway).
    """
    from meshwright.tri import _build2d

    try:
        index = _build2d.insert_batch._cache._cache_file._index_path
    except AttributeError:
        return False
    return Path(index).exists()


def run(args) -> int:
    out = Path(args.directory)
    out.mkdir(parents=True, exist_ok=True)
    if not kernels_cached():
        # A new user's first run spends most of its time compiling: say so once, and name each
        # case before it starts so the wait shows progress (benchmarks/compile2d.py).
        print(
            "First run: Numba compiles each method's kernels when it is first used (a few "
            "minutes in all for this demo); they are cached on disk and later runs start in "
            "seconds.",
            flush=True,
        )
    rng = np.random.default_rng(args.seed)
    points = circle_points(48, 200, rng)

    for algorithm in ("bowyer", "watson"):
        print(f"circle ({algorithm}) ...", flush=True)
        with Timer() as t:
            tri = delaunay(points, algorithm=algorithm)
        mesh = tri.to_mesh()
        mesh.validate(check_delaunay=True)
        path = out / f"circle-delaunay-{algorithm}.vtu"
        mesh.write(str(path))
        print(f"{algorithm}: {len(tri.triangles)} triangles in {t.elapsed:.3f} s -> {path}")

    png = out / "circle-delaunay.png"
    mesh.plot(path=str(png))
    print(f"wrote {png}")

    from meshwright.plot.voronoi_plot import plot_voronoi

    vor = voronoi(tri, clip=(-1.2, -1.2, 1.2, 1.2))
    png = out / "circle-voronoi.png"
    plot_voronoi(vor, path=str(png))
    print(f"wrote {png}")

    for name, method, smooth in (
        ("naca0012", "delaunay", 0),
        ("naca0012", "weatherill", 8),
        ("naca0012", "front", 0),
        ("three-element", "delaunay", 0),
        ("three-element", "frontal-delaunay", 0),
    ):
        print(f"{name} ({method}) ...", flush=True)
        with Timer() as t:
            mesh = triangulate(builtin(name), method=method, smooth=smooth)
        stem = out / f"{name}-{method}"
        q = _save_airfoil(mesh, stem, "triangle")
        print(
            f"{name} ({method}{', smoothed' if smooth else ''}): {len(mesh.cells['triangle'])} triangles in "
            f"{t.elapsed:.3f} s, min angle {q['min_angle']['min']:.1f} deg, mean radius ratio "
            f"{q['radius_ratio']['mean']:.3f} -> {stem}.vtu, .png"
        )

    for name, method in (("three-element", "quadtree"), ("naca0012", "pairing"), ("naca0012", "paving")):
        print(f"{name} ({method}) ...", flush=True)
        with Timer() as t:
            mesh = quadrangulate(builtin(name), method=method)
        stem = out / f"{name}-quad-{method}"
        q = _save_airfoil(mesh, stem, "quad")
        print(
            f"{name} ({method}, all-quad): {len(mesh.cells['quad'])} quads in {t.elapsed:.3f} s, min scaled "
            f"Jacobian {q['scaled_jacobian']['min']:.3f}, angles {q['min_angle']['min']:.1f} to "
            f"{q['max_angle']['max']:.1f} deg -> {stem}.vtu, .png"
        )
    mesh_solids(out)
    return 0


def mesh_solids(out: Path) -> None:
    """Mesh the 3-D cases of :func:`solids` into ``out`` (``NAME-tet.vtu`` and ``.png``)."""
    for name, surface, size in solids():
        print(f"{name} (tetrahedralize) ...", flush=True)
        with Timer() as t:
            mesh = tetrahedralize(surface, size)
        mesh.validate()
        stem = out / f"{name}-tet"
        mesh.write(str(stem.with_suffix(".vtu")))
        mesh.plot(path=str(stem.with_suffix(".png")), title=f"{name}: {len(mesh.tetra)} tetrahedra")
        q = mesh.quality().summary()["tetra"]
        print(
            f"{name} (tetrahedralize): {len(mesh.tetra)} tetrahedra in {t.elapsed:.3f} s, dihedral angles "
            f"{q['min_dihedral']['min']:.1f} to {q['max_dihedral']['max']:.1f} deg, min sliver ratio "
            f"{q['sliver_ratio']['min']:.3f} -> {stem}.vtu, .png"
        )


def solids() -> list:
    """The 3-D demo cases: ``(name, Surface, size)``.

    The built-ins of :mod:`meshwright.tet.builtin_surfaces`: the sphere and the box with a
    spherical cavity from icosahedra subdivided twice, and NACA 0012 of unit chord and span
    in a box far field one chord away (the mesh fills the air around it), its section meshed
    at 0.1 chord and extruded in ten layers.
    """
    return [
        ("sphere", sphere(level=2), 0.25),
        ("box-cavity", box_cavity(level=2), 0.25),
        ("naca-wing", naca_wing(), 0.3),
    ]


def _save_airfoil(mesh, stem: Path, cell_type: str) -> dict:
    """Validate ``mesh``, write ``stem``.vtu and ``stem``.png; the quality summary of ``cell_type``."""
    mesh.validate()
    mesh.write(str(stem.with_suffix(".vtu")))
    _plot_airfoil(mesh, stem.with_suffix(".png"))
    return mesh.quality().summary()[cell_type]


def _plot_airfoil(mesh, path: Path) -> None:
    """Whole mesh beside a close-up of the airfoil."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(12, 6))
    FigureCanvasAgg(fig)
    whole, close = fig.add_subplot(1, 2, 1), fig.add_subplot(1, 2, 2)
    mesh.plot(ax=whole)
    mesh.plot(ax=close)
    close.set_xlim(-0.15, 1.25)
    close.set_ylim(-0.45, 0.45)
    fig.tight_layout()
    fig.savefig(str(path), dpi=130)
