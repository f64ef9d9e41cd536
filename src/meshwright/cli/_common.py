"""Small helpers shared by the subcommand modules (input and cap options, output, quality table,
plotting)."""

from __future__ import annotations

import time
from pathlib import Path

from meshwright.geometry import BUILTIN_DOMAINS
from meshwright.tri.mesher import DEFAULT_MAX_POINTS


def add_input_argument(parser) -> None:
    """Attach the positional INPUT (a .poly, a .json geometry or a built-in domain's name)."""
    parser.add_argument(
        "input",
        help=f"a .poly file, a .json geometry file, or a built-in domain: {', '.join(sorted(BUILTIN_DOMAINS))}",
    )


def add_max_points_argument(parser) -> None:
    """Attach ``--max-points``, the cap on a mesh's vertices the 2-D meshers share."""
    parser.add_argument(
        "--max-points",
        type=int,
        metavar="N",
        help=f"cap on the mesh's vertices (default {DEFAULT_MAX_POINTS}); a size needing more is refused at once",
    )


def add_convex_hull_argument(parser) -> None:
    """Attach ``--convex-hull`` (Triangle's -c) the 2-D meshers share."""
    parser.add_argument(
        "--convex-hull",
        action="store_true",
        help="mesh the convex hull of the input, for a .poly whose segments close no boundary (Triangle's -c)",
    )


def add_output_arguments(parser, default_output: str | None = None) -> None:
    """Attach the ``-o/--output``, ``--plot`` and ``--quality`` options every mesher shares."""
    parser.add_argument(
        "-o",
        "--output",
        default=default_output,
        help="output mesh file; the format follows the extension (.vtu, .vtk, .msh, .xdmf, .off, .node, ...)",
    )
    parser.add_argument("--plot", metavar="PNG", help="also draw the mesh into this image file")
    parser.add_argument("--quality", action="store_true", help="print the element-quality table")


def emit_mesh(mesh, args, label: str) -> None:
    """Write, plot and report a finished mesh according to the shared options."""
    if args.output:
        mesh.write(args.output)
        print(f"wrote {args.output}")
    if args.plot:
        mesh.plot(path=args.plot)
        print(f"wrote {args.plot}")
    if args.quality:
        print(mesh.quality().table())
    counts = ", ".join(f"{len(v)} {k}" for k, v in mesh.cells.items())
    print(f"{label}: {mesh.n_points} points, {counts}")


class Timer:
    """Context manager measuring wall time in seconds (``elapsed``)."""

    def __enter__(self):
        self._t0 = time.perf_counter()
        return self

    def __exit__(self, *exc):
        self.elapsed = time.perf_counter() - self._t0
        return False


def ensure_parent(path: str | Path) -> Path:
    """Create the parent folder of ``path`` if needed and return it as a Path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    return path
