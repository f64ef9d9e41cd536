"""Command-line interface: ``meshwright <subcommand> ...``.

One module per subcommand (meshio style).  Each module exposes ``NAME``, ``HELP``,
``add_arguments(parser)`` and ``run(args) -> int``; :data:`SUBCOMMANDS` lists them in
the order ``--help`` shows.  Choices of algorithms come from the method registries of
the library, never from hand-copied lists.
"""

from __future__ import annotations

import argparse
import sys

from meshwright.cli import delaunay as _delaunay
from meshwright.cli import demo as _demo
from meshwright.cli import mesh as _mesh
from meshwright.cli import voronoi as _voronoi
from meshwright.core.errors import MeshwrightError

__all__ = ["main", "build_parser", "SUBCOMMANDS"]

SUBCOMMANDS = (_delaunay, _voronoi, _mesh, _demo)


def build_parser() -> argparse.ArgumentParser:
    """Return the top-level argument parser with every subcommand attached."""
    from meshwright import __version__

    parser = argparse.ArgumentParser(
        prog="meshwright",
        description="Unstructured grid generation (Delaunay-Voronoi, advancing front, ...).",
    )
    parser.add_argument("--version", action="version", version=f"meshwright {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for module in SUBCOMMANDS:
        p = sub.add_parser(module.NAME, help=module.HELP, description=module.HELP)
        module.add_arguments(p)
        p.set_defaults(_run=module.run)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line; return the process exit status (0 success, 1 error, 2 usage)."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if not hasattr(args, "_run"):
        parser.print_help()
        return 2
    try:
        return int(args._run(args) or 0)
    except MeshwrightError as exc:
        print(f"meshwright {args.command}: error: {exc}", file=sys.stderr)
        return 1
    except OSError as exc:
        print(f"meshwright {args.command}: error: {exc}", file=sys.stderr)
        return 1
