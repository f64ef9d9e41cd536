"""``meshwright quad INPUT -o OUT``: quadrilateral mesh of a domain (section 18.5).

INPUT is a Triangle ``.poly`` file, a JSON geometry file or the name of a built-in domain,
as for ``meshwright mesh``.  The method choices come from
:data:`meshwright.quad.QUAD_METHODS`.  The mesh is all-quad unless ``--mixed`` is given
(then the method's leftover triangles stay and their count is printed).
"""

from __future__ import annotations

import sys

from meshwright.cli._common import Timer, add_convex_hull_argument, add_input_argument, add_max_points_argument
from meshwright.cli._common import add_output_arguments, emit_mesh
from meshwright.cli.mesh import load_input, size_value
from meshwright.quad import QUAD_METHODS, quadrangulate

NAME = "quad"
HELP = "quadrilateral mesh (all-quad by default) of a .poly file, a JSON geometry file or a built-in domain"


def add_arguments(parser) -> None:
    add_input_argument(parser)
    parser.add_argument(
        "--size",
        type=size_value,
        metavar="H",
        help="target quad edge length, or 'boundary' for the spacing of the boundary alone (default: the "
        "domain's own, else its local feature size)",
    )
    parser.add_argument(
        "--method",
        choices=sorted(QUAD_METHODS),
        default="quadtree",
        help="quad method: " + "; ".join(f"{m.name}: {m.summary}" for m in QUAD_METHODS.values()),
    )
    parser.add_argument(
        "--mixed",
        action="store_true",
        help="keep the method's leftover triangles (quad-dominant) instead of finishing all-quad",
    )
    parser.add_argument(
        "--smooth",
        type=int,
        default=0,
        metavar="N",
        help="smoothing passes (methods that smooth: "
        + (", ".join(m.name for m in QUAD_METHODS.values() if m.smooths) or "none yet")
        + ")",
    )
    add_max_points_argument(parser)
    parser.add_argument("--seed", type=int, default=0, help="seed of the methods' randomness")
    add_convex_hull_argument(parser)
    add_output_arguments(parser)


def run(args) -> int:
    domain = load_input(args.input)
    with Timer() as t:
        mesh = quadrangulate(
            domain,
            args.size,
            method=args.method,
            all_quad=not args.mixed,
            smooth=args.smooth,
            max_points=args.max_points,
            seed=args.seed,
            convex_hull=args.convex_hull,
            progress=sys.stderr.isatty() and QUAD_METHODS[args.method].reports_progress,
        )
    tris = len(mesh.triangles)
    left = f", {tris} triangles left" if args.mixed else ""
    print(f"{args.method}: {len(mesh.quads)} quads{left} in {t.elapsed:.3f} s")
    emit_mesh(mesh, args, "quad")
    return 0
