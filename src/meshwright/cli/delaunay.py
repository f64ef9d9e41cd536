"""``meshwright delaunay IN -o OUT``: Delaunay triangulation (2-D) or tetrahedralization (3-D) of a point file.

Three columns whose z values are not all equal give a tetrahedralization (``tetra`` cells,
``--plot`` draws the hull); two columns, or a constant third one, the 2-D triangulation.
"""

from __future__ import annotations

import numpy as np

from meshwright.cli._common import Timer, add_output_arguments, emit_mesh
from meshwright.core.errors import InputError
from meshwright.io import read_points
from meshwright.tet import SUPERSTRUCTURES, delaunay3d
from meshwright.tri import DELAUNAY_ALGORITHMS, delaunay

NAME = "delaunay"
HELP = "Delaunay triangulation (x y) or tetrahedralization (x y z) of a point set (.txt, .csv, .xyz, .npy or Triangle .node)"


def add_arguments(parser) -> None:
    parser.add_argument(
        "input", help="point file: .txt/.csv/.xyz (x y or x y z per line), .npy (n, 2) or (n, 3), or Triangle .node"
    )
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
    parser.add_argument(
        "--superstructure",
        choices=SUPERSTRUCTURES,
        default="ghost",
        help="3-D only: vertex at infinity (convex hull) or the chapter's eight-point box (hull tets lost)",
    )
    add_output_arguments(parser)


def run(args) -> int:
    points = read_points(args.input)
    if points.shape[1] == 3 and np.any(points[:, 2] != points[0, 2]):
        with Timer() as t:
            tet = delaunay3d(
                points, algorithm=args.algorithm, duplicates=args.duplicates, seed=args.seed,
                superstructure=args.superstructure,
            )
        print(f"{args.algorithm}: {len(tet.points)} points -> {len(tet.tetrahedra)} tetrahedra in {t.elapsed:.3f} s")
        emit_mesh(tet.to_mesh(), args, "delaunay")
        return 0
    if args.superstructure != "ghost":
        raise InputError("--superstructure box needs 3-D points (x y z with z not constant)")
    points = points[:, :2]
    with Timer() as t:
        tri = delaunay(points, algorithm=args.algorithm, duplicates=args.duplicates, seed=args.seed)
    print(f"{args.algorithm}: {len(tri.points)} points -> {len(tri.triangles)} triangles in {t.elapsed:.3f} s")
    emit_mesh(tri.to_mesh(), args, "delaunay")
    return 0
