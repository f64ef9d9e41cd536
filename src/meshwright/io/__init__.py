"""Mesh and point-set files, one format per module (meshio style).

* :mod:`~meshwright.io.meshio_io`: every meshio format (``.vtu``, ``.vtk``, ``.msh``,
  ``.xdmf``, ``.off``, ``.mesh``, ...);
* :mod:`~meshwright.io.triangle_format`: Triangle / TetGen ``.node``, ``.ele``, ``.poly``,
  and Triangle's ``.edge``, ``.neigh``, ``.area`` as arrays
  (``.node`` and ``.poly`` parsed by :mod:`meshwright.geometry.poly_format`, the one parser
  of those formats, which :func:`meshwright.geometry.read_poly` uses too);
* :mod:`~meshwright.io.points`: point sets (``.txt``, ``.csv``, ``.xyz``, ``.npy``, ``.node``).

:func:`read` and :func:`write` pick the module from the extension (or ``file_format``:
``"triangle"`` or any meshio format name).  Missing, unreadable, corrupt, truncated or
non-UTF-8 files raise :class:`~meshwright.core.errors.FormatError` naming the file and, for
the Triangle and point formats, the line.
"""

from __future__ import annotations

from pathlib import Path

from meshwright.io import meshio_io
from meshwright.io.points import read_points
from meshwright.io.triangle_format import (
    TRIANGLE_SUFFIXES,
    read_area,
    read_edge,
    read_ele,
    read_neigh,
    read_node,
    read_poly,
    read_triangle,
    write_triangle,
)

__all__ = [
    "read",
    "write",
    "read_points",
    "read_node",
    "read_ele",
    "read_edge",
    "read_neigh",
    "read_area",
    "read_poly",
    "read_triangle",
    "write_triangle",
]


def _is_triangle(path: Path, file_format: str | None) -> bool:
    if file_format is not None:
        return file_format == "triangle"
    return path.suffix.lower() in TRIANGLE_SUFFIXES


def read(path, file_format: str | None = None, dim: int | None = None):
    """Read a mesh file into a :class:`~meshwright.core.mesh.Mesh`.

    Parameters
    ----------
    path : str or Path
    file_format : str, optional
        ``"triangle"`` or a meshio format name; default from the extension.
    dim : {2, 3}, optional
        meshio formats only: force the spatial dimension (default: drop an all-zero z).

    Returns
    -------
    Mesh
    """
    path = Path(path)
    if _is_triangle(path, file_format):
        return read_triangle(path)
    return meshio_io.read(path, file_format=file_format, dim=dim)


def write(mesh, path, file_format: str | None = None, **kwargs) -> None:
    """Write a :class:`~meshwright.core.mesh.Mesh`; the format follows the extension.

    Parameters
    ----------
    mesh : Mesh
    path : str or Path
        ``.node`` / ``.ele`` / ``.poly`` write the Triangle file set of that stem
        (see :func:`write_triangle`); any other extension goes through meshio.
    file_format : str, optional
        ``"triangle"`` or a meshio writer name (``"gmsh22"``, ``"gmsh"``, ``"vtu"``, ...).
    **kwargs
        Passed to the writer (e.g. ``binary=True`` for Gmsh, ``first_index=0`` for Triangle).
    """
    path = Path(path)
    if _is_triangle(path, file_format):
        write_triangle(mesh, path, **kwargs)
    else:
        meshio_io.write(mesh, path, file_format=file_format, **kwargs)
