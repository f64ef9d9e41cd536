"""``meshwright demo [DIR]``: mesh built-in examples and write .vtu files and .png pictures.

The demo reproduces chapter 18.1's circle example (Figure 18.1.5): points on a circle
and inside it, triangulated by Bowyer's and Watson's algorithms, with the Voronoi
diagram of the same points (Figure 18.1.1); then quality meshes of NACA 0012 in a far
field by Delaunay refinement, Weatherill's point generation with smoothing (18.1.3, 18.2)
and the advancing front (18.2), and of the three-element airfoil (Figure 18.3.1) by
Delaunay refinement and by the frontal Delaunay method (18.3); then all-quad meshes
(18.5) of the three-element airfoil by the quadtree (Yerry and Shephard, 18.5.3) and of
NACA 0012 by triangle pairing (Zhu et al., 18.5.1).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from meshwright.cli._common import Timer
from meshwright.geometry import builtin
from meshwright.quad import quadrangulate
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


def run(args) -> int:
    out = Path(args.directory)
    out.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(args.seed)
    points = circle_points(48, 200, rng)

    for algorithm in ("bowyer", "watson"):
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
        with Timer() as t:
            mesh = triangulate(builtin(name), method=method, smooth=smooth)
        stem = out / f"{name}-{method}"
        q = _save_airfoil(mesh, stem, "triangle")
        print(
            f"{name} ({method}{', smoothed' if smooth else ''}): {len(mesh.cells['triangle'])} triangles in "
            f"{t.elapsed:.3f} s, min angle {q['min_angle']['min']:.1f} deg, mean radius ratio "
            f"{q['radius_ratio']['mean']:.3f} -> {stem}.vtu, .png"
        )

    for name, method in (("three-element", "quadtree"), ("naca0012", "pairing")):
        with Timer() as t:
            mesh = quadrangulate(builtin(name), method=method)
        stem = out / f"{name}-quad-{method}"
        q = _save_airfoil(mesh, stem, "quad")
        print(
            f"{name} ({method}, all-quad): {len(mesh.cells['quad'])} quads in {t.elapsed:.3f} s, min scaled "
            f"Jacobian {q['scaled_jacobian']['min']:.3f}, angles {q['min_angle']['min']:.1f} to "
            f"{q['max_angle']['max']:.1f} deg -> {stem}.vtu, .png"
        )
    return 0


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
