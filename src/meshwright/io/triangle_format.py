"""Shewchuk's Triangle file sets (``.node``, ``.ele``, ``.poly``; TetGen's 3-D ``.node`` /
``.ele`` too) as :class:`~meshwright.core.mesh.Mesh` objects.

Source: J. R. Shewchuk, "Triangle: Engineering a 2D Quality Mesh Generator and Delaunay
Triangulator" (1996), file formats at https://www.cs.cmu.edu/~quake/triangle.html.
``.node`` and ``.poly`` are parsed and written by :mod:`meshwright.geometry.poly_format`,
the one implementation of those formats (a ``.poly`` describes a domain, so geometry owns
it and this layer, above geometry, builds meshes from it); :func:`read_node` and
:func:`read_poly` are its parsers.  This module adds the element file::

    .ele    <#elements> <nodes per element (3, or 4 for TetGen)> <#attributes>
            <element #> <v0> <v1> <v2> [v3] [attributes]

read with the same :class:`~meshwright.geometry.poly_format.Records` (comments, blank
lines, file-and-line errors); its vertex references use the numbering of the ``.node``.

Mapping to :class:`~meshwright.core.mesh.Mesh` data (see ``core/mesh.py``): vertex markers
are ``point_data["marker"]``, vertex attributes ``point_data["attributes"]`` (n, a);
a single integer-valued element attribute is ``cell_data["marker"][cell_type]`` (region
marker), anything else ``cell_data["attributes"][cell_type]`` (m, a); ``.poly`` segments
are ``line`` cells with ``cell_data["marker"]["line"]`` (0 when the file has none).
"""

from __future__ import annotations

from pathlib import Path
from typing import NamedTuple

import numpy as np

from meshwright.core.errors import FormatError, InputError
from meshwright.core.mesh import Mesh
from meshwright.geometry.poly_format import NodeData, PolyData, Records, write_node_file, write_poly_file
from meshwright.geometry.poly_format import parse_node as read_node
from meshwright.geometry.poly_format import parse_poly as read_poly

__all__ = [
    "NodeData",
    "EleData",
    "PolyData",
    "read_node",
    "read_ele",
    "read_poly",
    "read_triangle",
    "write_triangle",
    "TRIANGLE_SUFFIXES",
]

TRIANGLE_SUFFIXES = (".node", ".ele", ".poly")


class EleData(NamedTuple):
    """Contents of an ``.ele`` file.

    Attributes
    ----------
    cells : (m, k) int32
        0-based vertex indices, k = 3 (triangles) or 4 (tetrahedra).
    attributes : (m, a) float64
    """

    cells: np.ndarray
    attributes: np.ndarray


def _indices(rec: Records, values, linenos, first_index: int, n_points: int | None, what: str) -> np.ndarray:
    """Convert 1-based or 0-based vertex references to 0-based int32, checking the range."""
    idx = rec.integers(values, linenos, f"{what} vertex indices") - first_index
    upper = n_points if n_points is not None else np.iinfo(np.int32).max
    bad = np.flatnonzero(np.any((idx < 0) | (idx >= upper), axis=1))
    if len(bad):
        i = int(bad[0])
        lo, hi = first_index, first_index + upper - 1
        raise rec.error(
            int(linenos[i]), f"{what} refers to vertex {(idx[i] + first_index).tolist()} outside {lo}..{hi}"
        )
    return idx.astype(np.int32)


def read_ele(path, first_index: int | None = None, n_points: int | None = None) -> EleData:
    """Read a Triangle ``.ele`` (3 nodes) or TetGen ``.ele`` (4 nodes) file.

    Parameters
    ----------
    path : str or Path
    first_index : {0, 1}, optional
        Numbering of the vertices (that of the ``.node`` file).  Default: the number of
        the first element, which Triangle and TetGen give the same base.
    n_points : int, optional
        Number of vertices, to check the range of the references.

    Returns
    -------
    EleData

    Raises
    ------
    InputError
        ``first_index`` not None, 0 or 1; ``n_points`` not None or a non-negative int.
    FormatError
        Missing, unreadable or non-UTF-8 file, malformed or truncated record, unsupported
        nodes per element (second-order elements), a vertex reference out of range.
    """
    if first_index is not None and (first_index not in (0, 1) or isinstance(first_index, bool)):
        raise InputError(f"first_index must be None, 0 or 1, got {first_index!r}")
    if n_points is not None and (not isinstance(n_points, (int, np.integer)) or n_points < 0):
        raise InputError(f"n_points must be None or a non-negative int, got {n_points!r}")
    rec = Records(path)
    line, (n, k, n_attr) = rec.header("the .ele header", ("#elements", "nodes per element", "#attributes"), (3, 0))
    if k not in (3, 4):
        raise rec.error(line, f"{k} nodes per element are not supported (3 or 4; no second order)")
    names = ("element #",) + ("vertex",) * k + ("attribute",) * n_attr
    values, linenos = rec.table(n, "element", names, 1 + k, line)
    numbers = rec.integers(values[:, :1], linenos, "element numbers")[:, 0]
    base = first_index
    if base is None:
        base = int(numbers[0]) if len(numbers) else 0
        if base not in (0, 1):
            raise rec.error(int(linenos[0]), f"the first element must be numbered 0 or 1, got {base}")
    cells = _indices(rec, values[:, 1 : 1 + k], linenos, base, n_points, "element")
    rec.finish()
    return EleData(cells, np.ascontiguousarray(values[:, 1 + k :]))


def _stem(path) -> str:
    """``path`` without a Triangle suffix, as a string: Triangle's names carry dots of
    their own (``A.1.node`` is iteration 1 of ``A``), which ``Path.with_suffix`` would eat."""
    path = Path(path)
    return str(path.with_suffix("")) if path.suffix in TRIANGLE_SUFFIXES else str(path)


def _cell_attributes(attributes: np.ndarray) -> tuple[str, np.ndarray] | None:
    """Map element attributes to a cell_data entry: one integer column is a marker."""
    if attributes.shape[1] == 0:
        return None
    if attributes.shape[1] == 1 and np.all(attributes == np.round(attributes)):
        return "marker", attributes[:, 0].astype(np.int32)
    return "attributes", attributes


def _segment_markers(poly: PolyData) -> np.ndarray:
    if poly.segment_markers is None:
        return np.zeros(len(poly.segments), np.int32)
    return poly.segment_markers


def read_triangle(path) -> Mesh:
    """Read a Triangle / TetGen file set into a :class:`~meshwright.core.mesh.Mesh`.

    ``path`` may name the ``.node``, ``.ele`` or ``.poly`` file or the common stem.  A
    ``.poly`` path alone gives its vertices and segments (``line`` cells).  Otherwise the
    ``.node`` and, if present, ``.ele`` are read; the segments of a ``.poly`` of the same
    name that lists its vertices in that ``.node`` (vertex count 0) become ``line`` cells.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    Mesh

    Raises
    ------
    FormatError
        Any file of the set missing (the ``.node``), unreadable or malformed, naming the
        file and line.
    """
    path = Path(path)
    stem = _stem(path)
    if path.suffix == ".poly":
        poly = read_poly(path)
        point_data = {} if poly.vertex_markers is None else {"marker": poly.vertex_markers}
        if poly.vertex_attributes.shape[1]:
            point_data["attributes"] = poly.vertex_attributes
        return Mesh(
            poly.vertices,
            {"line": poly.segments},
            point_data=point_data,
            cell_data={"marker": {"line": _segment_markers(poly)}},
        )
    node = read_node(Path(stem + ".node"))
    cells: dict[str, np.ndarray] = {}
    cell_data: dict[str, dict[str, np.ndarray]] = {}
    ele_path = Path(stem + ".ele")
    if ele_path.exists():
        ele = read_ele(ele_path, node.first_index, len(node.points))
        cell_type = "triangle" if ele.cells.shape[1] == 3 else "tetra"
        if cell_type == "tetra" and node.points.shape[1] != 3:
            raise FormatError(f"{ele_path}: 4-node elements need a 3-D .node file")
        cells[cell_type] = ele.cells
        entry = _cell_attributes(ele.attributes)
        if entry is not None:
            cell_data[entry[0]] = {cell_type: entry[1]}
    poly_path = Path(stem + ".poly")
    if poly_path.exists() and node.points.shape[1] == 2 and Records(poly_path).peek_first_field() == "0":
        poly = read_poly(poly_path)
        cells["line"] = poly.segments
        cell_data.setdefault("marker", {})["line"] = _segment_markers(poly)
    point_data = {}
    if node.markers is not None:
        point_data["marker"] = node.markers
    if node.attributes.shape[1]:
        point_data["attributes"] = node.attributes
    return Mesh(node.points, cells, point_data=point_data, cell_data=cell_data)


# -------------------------------------------------------------------------- writing


def write_triangle(mesh: Mesh, path, first_index: int = 1) -> list[Path]:
    """Write a mesh as Triangle (2-D) or TetGen (3-D) ``.node`` / ``.ele`` / ``.poly`` files.

    Parameters
    ----------
    mesh : Mesh
        Triangles (2-D) or tetrahedra (3-D), optional ``line`` cells.
    path : str or Path
        Any of the three file names or their common stem.
    first_index : {0, 1}
        Number of the first vertex and element (Triangle's default is 1).

    Returns
    -------
    list of Path
        The files written: ``.node`` always; ``.ele`` when there are elements; ``.poly``
        for 2-D meshes, listing the ``line`` cells (or, without any, the boundary edges
        with marker 1) as segments, no holes, and one region point per region marker.

    Raises
    ------
    InputError
        ``mesh`` not a Mesh, ``first_index`` not 0 or 1.
    FormatError
        Cell types the files cannot store (2-D: only line and triangle; 3-D: only tetra).
    """
    if not isinstance(mesh, Mesh):
        raise InputError(f"write_triangle needs a Mesh, got {type(mesh).__name__}")
    if first_index not in (0, 1) or isinstance(first_index, bool):
        raise InputError(f"first_index must be 0 or 1, got {first_index!r}")
    stem = _stem(path)
    n, dim = mesh.points.shape
    storable = ("line", "triangle") if dim == 2 else ("tetra",)
    unsupported = [t for t, c in mesh.cells.items() if len(c) and t not in storable]
    if unsupported:
        raise FormatError(
            f"{stem}: {dim}-D Triangle/TetGen files cannot store {', '.join(unsupported)} cells "
            f"(only {', '.join(storable)})"
        )
    attributes = mesh.point_data.get("attributes")
    written = [
        write_node_file(
            Path(stem + ".node"),
            mesh.points,
            None if attributes is None else np.asarray(attributes).reshape(n, -1),
            mesh.point_data.get("marker"),
            first_index,
        )
    ]
    element_type = "triangle" if dim == 2 else "tetra"
    elements = mesh.cells_of(element_type)
    if len(elements):
        written.append(_write_ele(mesh, element_type, Path(stem + ".ele"), first_index))
    if dim == 2:
        written.append(_write_poly(mesh, Path(stem + ".poly"), first_index))
    return written


def _write_ele(mesh: Mesh, element_type: str, path: Path, first_index: int) -> Path:
    elements = mesh.cells_of(element_type)
    m, k = elements.shape
    marker = mesh.cell_data.get("marker", {}).get(element_type)
    attr = marker if marker is not None else mesh.cell_data.get("attributes", {}).get(element_type)
    attr = np.zeros((m, 0)) if attr is None else np.asarray(attr, dtype=np.float64).reshape(m, -1)
    numbers = np.arange(first_index, first_index + m)
    rows = np.column_stack([numbers, elements + first_index, attr]).astype(np.float64)
    # Integers stay exact through float64: every one is below 2**31.
    fmt = ["%d"] * (1 + k) + ["%d" if marker is not None else "%.17g"] * attr.shape[1]
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(f"# {element_type} elements: index vertices [attributes]\n{m} {k} {attr.shape[1]}\n")
        np.savetxt(fh, rows, fmt=fmt, delimiter=" ")
    return path


def _write_poly(mesh: Mesh, path: Path, first_index: int) -> Path:
    """The segments of a 2-D mesh as a ``.poly`` whose vertices are in the ``.node``."""
    segments = mesh.lines
    seg_markers = mesh.cell_data.get("marker", {}).get("line")
    if not len(segments) and len(mesh.triangles):
        segments = mesh.boundary_facets()
        seg_markers = np.ones(len(segments), np.int32)
    if seg_markers is None:
        seg_markers = np.zeros(len(segments), np.int32)
    # One region point (a triangle centroid) per region marker, so that re-meshing the
    # .poly with Triangle's -A restores the region attributes.
    regions = np.zeros((0, 4))
    region_marker = mesh.cell_data.get("marker", {}).get("triangle")
    if region_marker is not None and len(region_marker):
        values, first = np.unique(region_marker, return_index=True)
        centroids = mesh.points[mesh.triangles[first]].mean(axis=1)
        regions = np.column_stack([centroids, values, -np.ones(len(values))])
    return write_poly_file(path, segments, seg_markers, None, regions, first_index=first_index)
