"""``meshwright mesh INPUT -o OUT``: quality triangle mesh of a domain.

INPUT is a Triangle ``.poly`` file, a JSON geometry file (schema in
:mod:`meshwright.geometry.spec`) or the name of a built-in domain
(:data:`meshwright.geometry.BUILTIN_DOMAINS`).  The method choices come from
:data:`meshwright.tri.MESH_METHODS`.  The output format follows the extension of OUT:
any meshio format, or Triangle ``.node``/``.ele``.

``--stretch S [--direction DEG]`` meshes with a uniform stretched background grid over the
domain's bounding box (chapter 18.2): spacing ``S * H`` along DEG and ``H`` across it,
``H`` being ``--size``.  Boundary spacing follows it for every method.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

from meshwright.cli._common import Timer, add_convex_hull_argument, add_input_argument, add_max_points_argument
from meshwright.cli._common import add_output_arguments, emit_mesh
from meshwright.core.errors import FormatError, InputError, SizeError
from meshwright.geometry import BUILTIN_DOMAINS, builtin, load_domain, read_poly
from meshwright.sizing import BackgroundGrid
from meshwright.tri import MESH_METHODS, triangulate
from meshwright.tri.mesher import BOUNDARY_SIZE, DEFAULT_GRADING, GRADING_AUTO, RELAXED_GRADING
from meshwright.tri.weatherill import DEFAULT_ALPHA

NAME = "mesh"
HELP = "quality triangle mesh of a .poly file, a JSON geometry file or a built-in domain"


def add_arguments(parser) -> None:
    add_input_argument(parser)
    parser.add_argument(
        "--size",
        type=size_value,
        metavar="H",
        help="target edge length, or 'boundary' for the chapter's spacing from the boundary alone "
        "(default: the domain's own, else its local feature size; delaunay grades by itself)",
    )
    parser.add_argument(
        "--background",
        metavar="FILE",
        help="background grid giving the spacing (format in meshwright.sizing.background); overrides --size",
    )
    parser.add_argument(
        "--stretch",
        type=float,
        metavar="S",
        help="uniform stretched background (18.2): spacing S*H along --direction, H across; "
        "S >= 1, needs --size H; excludes --background",
    )
    parser.add_argument(
        "--direction",
        type=float,
        metavar="DEG",
        help="stretching direction in degrees from the x axis (default 0; only with --stretch)",
    )
    parser.add_argument(
        "--min-angle",
        type=float,
        metavar="A",
        help="minimum angle in degrees; default per method: "
        + ", ".join(
            f"{m.name} {m.default_min_angle:g} (up to {m.max_min_angle:g})" if m.max_min_angle else f"{m.name} none"
            for m in MESH_METHODS.values()
        ),
    )
    parser.add_argument(
        "--method",
        choices=sorted(MESH_METHODS),
        default="delaunay",
        help="point placement: " + "; ".join(f"{m.name}: {m.summary}" for m in MESH_METHODS.values()),
    )
    grading = parser.add_mutually_exclusive_group()
    grading.add_argument(
        "--grading", type=grading_value, default=GRADING_AUTO, metavar="G",
        help=f"growth of the size away from a boundary finer than it, G >= 1 (default {DEFAULT_GRADING:g}; "
        f"{RELAXED_GRADING:g} for front and frontal-delaunay when they relax; none for the delaunay method, "
        "which grades by itself; Gmsh's Mesh.MeshSizeExtendFromBoundary)",
    )
    grading.add_argument(
        "--no-grading", dest="grading", action="store_const", const=None,
        help="follow --size exactly as given, not graded from the boundary (needs --size)",
    )
    relax = parser.add_mutually_exclusive_group()
    relax.add_argument(
        "--relax", dest="relax", action="store_const", const=True, default=None,
        help="valence swaps and smoothing afterwards (default: on for the methods that relax, when no bound is given)",
    )
    relax.add_argument("--no-relax", dest="relax", action="store_const", const=False, help="the method's mesh as made")
    parser.add_argument("--smooth", type=int, default=0, metavar="N", help="spring-analogy smoothing passes")
    parser.add_argument("--max-area", type=float, metavar="A", help="largest triangle area")
    add_max_points_argument(parser)
    parser.add_argument(
        "--alpha",
        type=float,
        metavar="ALPHA",
        help=f"Weatherill's density coefficient (--method weatherill only; default {DEFAULT_ALPHA}): smaller is denser",
    )
    parser.add_argument(
        "--conforming", action="store_true", help="split segments until every triangle is Delaunay (Triangle's -D)"
    )
    add_convex_hull_argument(parser)
    parser.add_argument("--seed", type=int, default=0, help="seed of the randomized insertion order")
    parser.add_argument(
        "--workers", type=int, metavar="N",
        help="mesh in parts on N local Dask worker processes (meshwright.distributed; -o OUT.xdmf, delaunay only)",
    )
    parser.add_argument("--scheduler", metavar="ADDRESS", help="as --workers, on the Dask cluster at ADDRESS")
    add_output_arguments(parser)


def load_input(spec: str):
    """Domain named by the INPUT argument: a built-in name, a .poly file or a JSON file.

    Raises
    ------
    FormatError
        If ``spec`` is neither a built-in name nor an existing file of a known kind.
    """
    if spec in BUILTIN_DOMAINS:
        return builtin(spec)
    path = Path(spec)
    if not path.exists():
        raise FormatError(
            f"{spec}: no such file, and not a built-in domain ({', '.join(sorted(BUILTIN_DOMAINS))})"
        )
    suffix = path.suffix.lower()
    if suffix not in (".poly", ".json"):
        raise FormatError(f"{spec}: unknown input kind {suffix!r}; expected .poly or .json")
    try:
        return read_poly(path) if suffix == ".poly" else load_domain(path)
    except UnicodeDecodeError as exc:
        raise FormatError(f"{spec}: not UTF-8 text (byte {exc.start}: {exc.reason})") from exc


def stretched_background(domain, size, stretch, direction):
    """Uniform background grid over ``domain.bbox`` from the ``--size/--stretch/--direction`` values.

    Parameters
    ----------
    domain : Domain
    size : float or None
        Spacing ``delta`` across the stretching (``--size``).
    stretch : float
        Stretching ``s >= 1`` (``--stretch``).
    direction : float or None
        Stretching direction in degrees (``--direction``); None means 0.

    Returns
    -------
    BackgroundGrid

    Raises
    ------
    InputError
        ``--size`` missing, or a non-finite ``--direction``.
    SizeError
        ``--size`` not positive or ``--stretch`` below 1 (or not finite).
    """
    if size is None:
        raise InputError(f"--stretch {stretch:g} needs --size H: the spacing across the stretching")
    if not (math.isfinite(size) and size > 0.0):
        raise SizeError(f"--size must be positive and finite, got {size!r}")
    if not (math.isfinite(stretch) and stretch >= 1.0):
        raise SizeError(f"--stretch must be a finite number >= 1, got {stretch!r}")
    deg = 0.0 if direction is None else direction
    if not math.isfinite(deg):
        raise InputError(f"--direction must be a finite angle in degrees, got {direction!r}")
    return BackgroundGrid.uniform(domain.bbox, size, stretch=stretch, direction=math.radians(deg))


def grading_value(text: str):
    """``--grading``: a growth factor, or ``auto`` (:data:`~meshwright.tri.mesher.GRADING_AUTO`)."""
    if text == GRADING_AUTO:
        return text
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a growth factor >= 1 or {GRADING_AUTO!r}, got {text!r}") from None


def size_value(text: str):
    """``--size``: a number, or the named size ``boundary`` (:data:`~meshwright.tri.mesher.BOUNDARY_SIZE`)."""
    if text == BOUNDARY_SIZE:
        return text
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number or {BOUNDARY_SIZE!r}, got {text!r}") from None


def _size_option(args, domain):
    """The size argument of :func:`triangulate` chosen by ``--size/--background/--stretch``."""
    if args.stretch is None:
        if args.direction is not None:
            raise InputError(f"--direction {args.direction:g} needs --stretch S")
        if not args.background:
            return args.size
        try:
            return BackgroundGrid.read(args.background)
        except UnicodeDecodeError as exc:
            raise FormatError(f"{args.background}: not UTF-8 text (byte {exc.start}: {exc.reason})") from exc
    if args.background:
        raise InputError(
            f"--background {args.background} and --stretch {args.stretch:g} are mutually exclusive: "
            "the background grid file carries its own stretching"
        )
    if args.size == BOUNDARY_SIZE:
        raise InputError(f"--stretch {args.stretch:g} needs --size H, a number: the spacing across the stretching")
    return stretched_background(domain, args.size, args.stretch, args.direction)


def _run_distributed(args, domain, size) -> int:
    """``--workers`` / ``--scheduler``: :func:`meshwright.distributed.triangulate` writes the XDMF itself."""
    from meshwright.distributed import local_cluster
    from meshwright.distributed import triangulate as distributed_triangulate

    if args.workers is not None and args.scheduler:
        raise InputError("--workers and --scheduler are mutually exclusive: local processes or a cluster")
    unsupported = [
        flag for flag, on in (
            ("--smooth", args.smooth), ("--max-area", args.max_area is not None), ("--conforming", args.conforming),
            ("--convex-hull", args.convex_hull), ("--alpha", args.alpha is not None), ("--plot", args.plot),
            ("--quality", args.quality), ("--grading", args.grading not in (GRADING_AUTO, None)),
            ("--relax", args.relax),
        ) if on
    ]
    if unsupported:
        raise InputError(f"{', '.join(unsupported)} cannot be honoured by distributed meshing (--workers/--scheduler)")
    if not args.output or Path(args.output).suffix.lower() != ".xdmf":
        raise InputError(f"distributed meshing writes XDMF: give -o OUT.xdmf (got {args.output!r})")
    if args.workers is not None and args.workers < 1:
        raise InputError(f"--workers must be >= 1, got {args.workers}")
    client = args.scheduler or local_cluster(args.workers)
    try:
        with Timer() as t:
            dm = distributed_triangulate(
                domain, size, client=client, min_angle=args.min_angle, method=args.method, seed=args.seed,
                out=args.output, max_points=args.max_points,
            )
    finally:
        if not isinstance(client, str):
            client.close()
    s = dm.stats
    print(
        f"{args.method}: {dm.n_cells} triangles in {t.elapsed:.3f} s on {s['workers']} workers "
        f"({s['parts']} parts, {s['rounds']} exchange rounds, imbalance {s['imbalance']:.3f} per part, "
        f"{s['worker_imbalance']:.3f} per worker)"
    )
    if s["memory_limit"]:
        print(f"peak worker memory {s['peak_rss'] / 2**20:.0f} MiB of its {s['memory_limit'] / 2**20:.0f} MiB limit")
    print(f"wrote {', '.join(dm.files[:2])} and {len(dm.files) - 2} part files")
    return 0


def run(args) -> int:
    domain = load_input(args.input)
    size = _size_option(args, domain)
    if args.workers is not None or args.scheduler:
        return _run_distributed(args, domain, size)
    with Timer() as t:
        mesh = triangulate(
            domain,
            size,
            min_angle=args.min_angle,
            method=args.method,
            smooth=args.smooth,
            max_area=args.max_area,
            seed=args.seed,
            conforming=args.conforming,
            convex_hull=args.convex_hull,
            max_points=args.max_points,
            alpha=args.alpha,
            grading=args.grading,
            relax=args.relax,
            # A bar only helps a person watching a terminal; logs stay clean.  Methods that
            # report no progress would refuse progress=True.
            progress=sys.stderr.isatty() and MESH_METHODS[args.method].reports_progress,
        )
    print(f"{args.method}: {len(mesh.cells['triangle'])} triangles in {t.elapsed:.3f} s")
    emit_mesh(mesh, args, "mesh")
    return 0
