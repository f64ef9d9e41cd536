"""Command-line interface: ``meshwright <subcommand> ...``.

One module per subcommand (meshio style).  Each module exposes ``NAME``, ``HELP``,
``add_arguments(parser)`` and ``run(args) -> int``; :data:`SUBCOMMANDS` lists them in
the order ``--help`` shows.  Choices of algorithms come from the method registries of
the library, never from hand-copied lists.

A user mistake never prints a traceback: the library raises a
:class:`~meshwright.core.errors.MeshwrightError` naming the culprit for every bad input,
and :func:`main` turns it (and any ``OSError``: a missing or unreadable file) into one line
on stderr.  Exit status: 0 success; 2 bad arguments or input (argparse's usage errors
included); 1 a method that could not finish (:class:`MeshingError`, a cap hit) or a mesh
that fails validation.
"""

from __future__ import annotations

import argparse
import sys

from meshwright.cli import delaunay as _delaunay
from meshwright.cli import demo as _demo
from meshwright.cli import mesh as _mesh
from meshwright.cli import quad as _quad
from meshwright.cli import tet as _tet
from meshwright.cli import voronoi as _voronoi
from meshwright.core.errors import MeshingError, MeshwrightError, ValidationError

__all__ = ["main", "build_parser", "SUBCOMMANDS", "EXIT_FAILED", "EXIT_USAGE"]

EXIT_FAILED = 1  # the input was fine, the method could not finish
EXIT_USAGE = 2  # bad arguments or input, as argparse's own usage errors

SUBCOMMANDS = (_delaunay, _voronoi, _mesh, _quad, _tet, _demo)


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
    """Run the command line; return the process exit status (see the module docstring)."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if not hasattr(args, "_run"):
        parser.print_help()
        return EXIT_USAGE
    try:
        return int(args._run(args) or 0)
    except (MeshingError, ValidationError) as exc:
        _report(args.command, exc)
        return EXIT_FAILED
    except (MeshwrightError, OSError) as exc:
        _report(args.command, exc)
        return EXIT_USAGE


def _report(command: str, exc: Exception) -> None:
    """One line on stderr; an OSError names its file (``strerror: filename``)."""
    if isinstance(exc, OSError) and exc.filename is not None:
        text = f"{exc.filename}: {exc.strerror or exc}"
    else:
        text = " ".join(str(exc).split())
    print(f"meshwright {command}: error: {text}", file=sys.stderr)
