"""``meshwright tet SURFACE -o OUT``: quality tetrahedral mesh of a closed surface (18.4).

SURFACE is a surface file (STL, OBJ, PLY, OFF, VTK/VTU, Gmsh .msh through meshio; TetGen
``.smesh``, 3-D ``.poly``, ``.node`` + ``.face``) read by
:func:`meshwright.geometry.surface_io.read_surface`, or the name of a built-in solid
(:data:`meshwright.tet.builtin_surfaces.BUILTIN_SURFACES`).
The method choices come from :data:`meshwright.tet.TET_METHODS`.  ``--hole`` and
``--region`` seeds override the even-odd rule for what is solid, as in TetGen.
``--no-refine`` stops after boundary recovery and exterior removal (TetGen's ``-p``
without ``-q``).  The picture (``--plot``) shows the boundary surface, a clipped cut
through the volume and the dihedral-angle histogram.
"""

from __future__ import annotations

from pathlib import Path

from meshwright.cli._common import Timer, add_max_points_argument, add_output_arguments, emit_mesh
from meshwright.core.errors import FormatError, InputError
from meshwright.geometry.surface_io import read_surface
from meshwright.tet import TET_METHODS, tetrahedralize
from meshwright.tet.builtin_surfaces import BUILTIN_SURFACES
from meshwright.tet.mesher import SLIVER_MODES

NAME = "tet"
HELP = "quality tetrahedral mesh of a closed surface file or a built-in solid"


def add_arguments(parser) -> None:
    parser.add_argument(
        "surface",
        metavar="SURFACE",
        help="a closed surface file (.stl .obj .ply .off .vtk .vtu .msh .smesh .poly .node) "
        f"or a built-in solid: {', '.join(sorted(BUILTIN_SURFACES))}",
    )
    parser.add_argument(
        "--size",
        type=float,
        metavar="H",
        help="target edge length (default: none, the tets grade from the surface by shape alone)",
    )
    parser.add_argument(
        "--radius-edge",
        type=float,
        metavar="RHO",
        help="bound on a tet's circumradius / shortest edge (default 2.0; TetGen's -q)",
    )
    parser.add_argument(
        "--no-refine",
        action="store_true",
        help="no quality refinement: boundary recovery and exterior removal only (TetGen's -p without -q)",
    )
    parser.add_argument("--max-volume", type=float, metavar="V", help="largest tet volume (TetGen's -a)")
    parser.add_argument(
        "--min-dihedral",
        type=float,
        metavar="D",
        help="tets with a smaller dihedral angle (degrees, in (0, 20]) are split too",
    )
    parser.add_argument(
        "--slivers",
        choices=SLIVER_MODES,
        default="remove",
        help="remove slivers (flips and vertex moves; default) or keep the refined mesh as it is",
    )
    parser.add_argument(
        "--method",
        choices=sorted(TET_METHODS),
        default="delaunay",
        help="interior points: " + "; ".join(f"{m.name}: {m.summary}" for m in TET_METHODS.values()),
    )
    parser.add_argument("--smooth", type=int, default=0, metavar="N", help="spring-analogy smoothing passes")
    parser.add_argument(
        "--hole",
        nargs=3,
        type=float,
        action="append",
        metavar=("X", "Y", "Z"),
        help="a point inside a hole: the space around it stays empty (repeatable)",
    )
    parser.add_argument(
        "--region",
        nargs=5,
        type=float,
        action="append",
        metavar=("X", "Y", "Z", "ID", "V"),
        help="a region seed: its tets get region ID and volume bound V (V <= 0: none; repeatable)",
    )
    add_max_points_argument(parser)
    parser.add_argument("--seed", type=int, default=0, help="seed of the randomized insertion order")
    parser.add_argument("--progress", action="store_true", help="show a progress bar on stderr")
    add_output_arguments(parser)


def load_surface(spec: str):
    """The SURFACE argument: a built-in solid's name (passed on as is) or a Surface read from a file.

    Raises
    ------
    FormatError
        ``spec`` is neither a built-in name nor an existing file (the reader raises its own
        ``FormatError`` for an unknown or malformed file).
    """
    if spec in BUILTIN_SURFACES:
        return spec
    path = Path(spec)
    if not path.is_file():
        raise FormatError(f"{spec}: no such file, and not a built-in solid ({', '.join(sorted(BUILTIN_SURFACES))})")
    return read_surface(path)


def _region_rows(regions) -> list:
    """``--region`` values as ``(x, y, z, id, max_volume)`` seed rows; the id must be an integer."""
    rows = []
    for x, y, z, rid, vol in regions or ():
        if not float(rid).is_integer():
            raise InputError(f"--region {x:g} {y:g} {z:g} {rid:g} {vol:g}: the region id must be an integer")
        rows.append((x, y, z, rid, vol))
    return rows


def run(args) -> int:
    if args.no_refine and args.radius_edge is not None:
        raise InputError(f"--no-refine and --radius-edge {args.radius_edge:g} are mutually exclusive")
    surface = load_surface(args.surface)
    options = {"radius_edge": None} if args.no_refine else {}
    if args.radius_edge is not None:
        options["radius_edge"] = args.radius_edge
    if args.max_points is not None:
        options["max_points"] = args.max_points
    with Timer() as t:
        mesh = tetrahedralize(
            surface,
            args.size,
            max_volume=args.max_volume,
            min_dihedral=args.min_dihedral,
            holes=[tuple(h) for h in args.hole or ()],
            regions=_region_rows(args.region),
            slivers=args.slivers,
            method=args.method,
            smooth=args.smooth,
            seed=args.seed,
            progress=args.progress,
            **options,
        )
    print(f"{args.method}: {len(mesh.tetra)} tetrahedra in {t.elapsed:.3f} s")
    emit_mesh(mesh, args, "tet")
    return 0
