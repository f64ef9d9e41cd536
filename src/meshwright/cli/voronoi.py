"""``meshwright voronoi IN``: Voronoi diagram (Dirichlet tessellation) of a point file."""

from __future__ import annotations

import numpy as np

from meshwright.cli._common import Timer, ensure_parent
from meshwright.core.errors import FormatError, InputError
from meshwright.io import read_points
from meshwright.tri.voronoi import voronoi

NAME = "voronoi"
HELP = "Voronoi diagram of a point set, optionally clipped to a box"


def add_arguments(parser) -> None:
    parser.add_argument("input", help="point file: .txt/.csv/.xyz, .npy or Triangle .node")
    parser.add_argument(
        "--clip",
        nargs=4,
        type=float,
        metavar=("XMIN", "YMIN", "XMAX", "YMAX"),
        help="clip every cell to this box (all cells then bounded)",
    )
    parser.add_argument(
        "-o",
        "--output",
        help="write the Voronoi ridges as line cells (.vtu, .vtk, .msh, ...)",
    )
    parser.add_argument("--plot", metavar="PNG", help="draw Delaunay + Voronoi (chapter Figure 18.1.1)")


def ridge_mesh(vor):
    """Return the finite ridges of a Voronoi diagram as a line :class:`~meshwright.Mesh`."""
    from meshwright.core.mesh import Mesh

    rv = vor.ridge_vertices
    finite = (rv >= 0).all(axis=1)
    lines = rv[finite]
    used = np.unique(lines)
    renum = np.full(len(vor.vertices), -1, dtype=np.int64)
    renum[used] = np.arange(len(used))
    return Mesh(vor.vertices[used], {"line": renum[lines].astype(np.int32)})


def run(args) -> int:
    points = read_points(args.input)
    if points.shape[1] != 2:
        raise FormatError(f"{args.input}: {points.shape[1]} coordinates per point; the Voronoi diagram is 2-D (x y)")
    clip = tuple(args.clip) if args.clip else None
    if clip is not None and not (np.isfinite(clip).all() and clip[0] < clip[2] and clip[1] < clip[3]):
        raise InputError(f"--clip box {clip} must be finite with XMIN < XMAX and YMIN < YMAX")
    with Timer() as t:
        vor = voronoi(points, clip=clip)
    n_bounded = int(np.count_nonzero(vor.bounded))
    print(
        f"voronoi: {len(vor.points)} cells ({n_bounded} bounded), {len(vor.vertices)} vertices, "
        f"{len(vor.ridge_points)} ridges in {t.elapsed:.3f} s"
    )
    if args.output:
        ridge_mesh(vor).write(str(ensure_parent(args.output)))
        print(f"wrote {args.output}")
    if args.plot:
        from meshwright.plot.voronoi_plot import plot_voronoi

        plot_voronoi(vor, path=str(ensure_parent(args.plot)))
        print(f"wrote {args.plot}")
    return 0
