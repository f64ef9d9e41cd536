"""``meshwright delaunay IN -o OUT``: Delaunay triangulation of a point file."""

from __future__ import annotations

from meshwright.cli._common import Timer, add_output_arguments, emit_mesh
from meshwright.io import read_points
from meshwright.tri import DELAUNAY_ALGORITHMS, delaunay

NAME = "delaunay"
HELP = "Delaunay triangulation of a point set (.txt, .csv, .xyz, .npy or Triangle .node)"


def add_arguments(parser) -> None:
    parser.add_argument("input", help="point file: .txt/.csv/.xyz (x y per line), .npy (n, 2) or Triangle .node")
    parser.add_argument(
        "-a",
        "--algorithm",
        choices=sorted(DELAUNAY_ALGORITHMS),
        default="bowyer",
        help="insertion algorithm (chapter 18.1.1 Watson, 18.1.2 Bowyer)",
    )
    parser.add_argument(
        "--duplicates",
        choices=("merge", "reject"),
        default="merge",
        help="what to do with coincident input points",
    )
    parser.add_argument("--seed", type=int, default=0, help="seed of the randomized insertion order")
    add_output_arguments(parser)


def run(args) -> int:
    points = read_points(args.input)[:, :2]
    with Timer() as t:
        tri = delaunay(points, algorithm=args.algorithm, duplicates=args.duplicates, seed=args.seed)
    print(f"{args.algorithm}: {len(tri.points)} points -> {len(tri.triangles)} triangles in {t.elapsed:.3f} s")
    emit_mesh(tri.to_mesh(), args, "delaunay")
    return 0
