"""``meshwright demo [DIR]``: mesh built-in examples and write .vtu files and .png pictures.

The demo reproduces chapter 18.1's circle example (Figure 18.1.5): points on a circle
and inside it, triangulated by Bowyer's and Watson's algorithms, with the Voronoi
diagram of the same points (Figure 18.1.1).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from meshwright.cli._common import Timer
from meshwright.tri import delaunay
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
    return 0
