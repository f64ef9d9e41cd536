"""Small helpers shared by the subcommand modules (output, quality table, plotting)."""

from __future__ import annotations

import time
from pathlib import Path


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
