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

and the files Triangle writes beside it, read into arrays by :func:`read_edge`,
:func:`read_neigh` and :func:`read_area`::

    .edge   <#edges> <#boundary markers (0 or 1)>
            <edge #> <endpoint> <endpoint> [marker]    a Voronoi ray (.v.edge) reads
            <edge #> <endpoint> -1 <dx> <dy>           (no markers in ray files)
    .neigh  <#triangles> <#neighbours per triangle (3)>
            <triangle #> <n0> <n1> <n2>                 n_k opposite corner k, -1 = none
    .area   <#triangles>
            <triangle #> <maximum area>                 <= 0: no constraint

all read with the same :class:`~meshwright.geometry.poly_format.Records` (comments,
blank lines, file-and-line errors); vertex and triangle references use the numbering of
the ``.node`` (the first record's number when not given).

Mapping to :class:`~meshwright.core.mesh.Mesh` data (see ``core/mesh.py``): vertex markers
are ``point_data["marker"]``, vertex attributes ``point_data["attributes"]`` (n, a);
a single integer-valued element attribute is ``cell_data["marker"][cell_type]`` (region
marker), anything else ``cell_data["attributes"][cell_type]`` (m, a); ``.poly`` segments
are ``line`` cells with ``cell_data["marker"]["line"]`` (0 when the file has none).
"""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import NamedTuple

import numpy as np

from meshwright.core.errors import FormatError, InputError
from meshwright.core.mesh import Mesh
from meshwright.geometry.poly_format import NodeData, PolyData, Records, write_node_file, write_poly_file
from meshwright.geometry.poly_format import parse_node as read_node
from meshwright.geometry.poly_format import parse_poly as read_poly
from meshwright.io.meshio_io import DataLossWarning

__all__ = [
    "NodeData",
    "EleData",
    "PolyData",
    "read_node",
    "read_ele",
    "EdgeData",
    "read_edge",
    "read_neigh",
    "read_area",
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


def _check_base(first_index) -> None:
    if first_index is not None and (first_index not in (0, 1) or isinstance(first_index, bool)):
        raise InputError(f"first_index must be None, 0 or 1, got {first_index!r}")


def _check_count(value, name: str) -> None:
    if value is not None and (isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 0):
        raise InputError(f"{name} must be None or a non-negative int, got {value!r}")


def _base(rec: Records, numbers: np.ndarray, linenos: np.ndarray, first_index: int | None, what: str) -> int:
    """The given numbering, or that of the first record (0 or 1)."""
    if first_index is not None:
        return first_index
    base = int(numbers[0]) if len(numbers) else 0
    if base not in (0, 1):
        raise rec.error(int(linenos[0]), f"the first {what} must be numbered 0 or 1, got {base}")
    return base


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
    _check_base(first_index)
    _check_count(n_points, "n_points")
    rec = Records(path)
    line, (n, k, n_attr) = rec.header("the .ele header", ("#elements", "nodes per element", "#attributes"), (3, 0))
    if k not in (3, 4):
        raise rec.error(line, f"{k} nodes per element are not supported (3 or 4; no second order)")
    names = ("element #",) + ("vertex",) * k + ("attribute",) * n_attr
    values, linenos = rec.table(n, "element", names, 1 + k, line)
    numbers = rec.integers(values[:, :1], linenos, "element numbers")[:, 0]
    base = _base(rec, numbers, linenos, first_index, "element")
    cells = _indices(rec, values[:, 1 : 1 + k], linenos, base, n_points, "element")
    rec.finish()
    return EleData(cells, np.ascontiguousarray(values[:, 1 + k :]))


class EdgeData(NamedTuple):
    """Contents of an ``.edge`` file.

    Attributes
    ----------
    edges : (e, 2) int32
        0-based vertex indices; the second is -1 for a Voronoi ray.
    markers : (e,) int32 or None
        None when the header declares no boundary markers.
    directions : (e, 2) float64
        Direction of each ray, zeros for finite edges.
    """

    edges: np.ndarray
    markers: np.ndarray | None
    directions: np.ndarray


def read_edge(path, first_index: int | None = None, n_points: int | None = None) -> EdgeData:
    """Read a Triangle ``.edge`` file (Voronoi ``.v.edge`` rays included).

    Parameters
    ----------
    path : str or Path
    first_index : {0, 1}, optional
        Numbering of the vertices; default: the number of the first edge.
    n_points : int, optional
        Number of vertices, to check the range of the references.

    Returns
    -------
    EdgeData

    Raises
    ------
    InputError
        Bad ``first_index`` or ``n_points``.
    FormatError
        Missing, unreadable or malformed file, a ray in a file with markers or without its
        direction, a vertex reference out of range: naming file and line.
    """
    _check_base(first_index)
    _check_count(n_points, "n_points")
    rec = Records(path)
    line, (n, n_markers) = rec.header("the .edge header", ("#edges", "#boundary markers"), (0,))
    if n_markers not in (0, 1):
        raise rec.error(line, f"number of edge boundary markers must be 0 or 1, got {n_markers}")
    tail = ("boundary marker",) if n_markers else ("direction x", "direction y")
    start = rec.pos
    values, linenos = rec.table(n, "edge", ("edge #", "endpoint", "endpoint") + tail, 3, line)
    widths = np.fromiter((len(f) for _, f in rec.items[start : rec.pos]), dtype=np.int64, count=len(linenos))
    numbers = rec.integers(values[:, :1], linenos, "edge numbers")[:, 0]
    base = _base(rec, numbers, linenos, first_index, "edge")
    ends = rec.integers(values[:, 1:3], linenos, "edge endpoints")
    ray = ends[:, 1] == -1
    bad = np.flatnonzero(ray & (widths != 5) | ~ray & (widths > 3 + n_markers))
    if len(bad):
        i = int(bad[0])
        expected = "a ray line (b = -1) holds '<edge #> <a> -1 <dx> <dy>' in a file without markers"
        if not ray[i]:
            expected = f"an edge line holds 3 to {3 + n_markers} fields"
        raise rec.error(int(linenos[i]), f"{expected}, got {widths[i]} fields")
    finite = ends.copy()
    finite[ray, 1] = base  # a valid stand-in for the range check
    edges = _indices(rec, finite, linenos, base, n_points, "edge")
    edges[ray, 1] = -1
    markers = None
    if n_markers:
        markers = rec.integers(values[:, 3:4], linenos, "edge boundary markers")[:, 0].astype(np.int32)
    directions = np.zeros((len(edges), 2))
    if not n_markers:
        directions[ray] = values[ray, 3:5]
    rec.finish()
    return EdgeData(edges, markers, directions)


def read_neigh(path, first_index: int | None = None, n_triangles: int | None = None) -> np.ndarray:
    """Read a Triangle ``.neigh`` file.

    Parameters
    ----------
    path : str or Path
    first_index : {0, 1}, optional
        Numbering of the triangles; default: the number of the first record.
    n_triangles : int, optional
        Number of triangles (that of the ``.ele``): the record count must agree, and
        every neighbour lie in range.

    Returns
    -------
    (m, 3) int32
        0-based neighbour of each triangle across the edge opposite corner k; -1 = none
        (the layout of ``Triangulation.neighbors``).

    Raises
    ------
    InputError
        Bad ``first_index`` or ``n_triangles``.
    FormatError
        Missing, unreadable or malformed file, a count other than ``n_triangles``, a
        neighbour out of range: naming file and line.
    """
    _check_base(first_index)
    _check_count(n_triangles, "n_triangles")
    rec = Records(path)
    line, (n, k) = rec.header("the .neigh header", ("#triangles", "#neighbours per triangle"), (3,))
    if k != 3:
        raise rec.error(line, f"triangles have 3 neighbours, the header declares {k}")
    if n_triangles is not None and n != n_triangles:
        raise rec.error(line, f"{n} triangles declared, the .ele has {n_triangles}")
    values, linenos = rec.table(n, "triangle", ("triangle #", "neighbour", "neighbour", "neighbour"), 4, line)
    numbers = rec.integers(values[:, :1], linenos, "triangle numbers")[:, 0]
    base = _base(rec, numbers, linenos, first_index, "triangle")
    raw = rec.integers(values[:, 1:4], linenos, "neighbours")
    none = raw == -1
    upper = n if n_triangles is None else n_triangles
    idx = raw - base
    bad = np.flatnonzero(np.any(~none & ((idx < 0) | (idx >= upper)), axis=1))
    if len(bad):
        i = int(bad[0])
        raise rec.error(
            int(linenos[i]), f"neighbours {raw[i].tolist()} outside {base}..{base + upper - 1} (or -1 for none)"
        )
    rec.finish()
    return np.where(none, -1, idx).astype(np.int32)


def read_area(path, n_triangles: int | None = None) -> np.ndarray:
    """Read a Triangle ``.area`` file (a maximum area per triangle, for refinement).

    Parameters
    ----------
    path : str or Path
    n_triangles : int, optional
        Number of triangles (that of the ``.ele``): the record count must agree.

    Returns
    -------
    (m,) float64
        Maximum area of each triangle; -1 where unconstrained (<= 0 in the file).

    Raises
    ------
    InputError
        Bad ``n_triangles``.
    FormatError
        Missing, unreadable or malformed file, a non-finite area, a count other than
        ``n_triangles``: naming file and line.
    """
    _check_count(n_triangles, "n_triangles")
    rec = Records(path)
    line, (n,) = rec.header("the .area header", ("#triangles",), ())
    if n_triangles is not None and n != n_triangles:
        raise rec.error(line, f"{n} triangles declared, the .ele has {n_triangles}")
    values, linenos = rec.table(n, "triangle", ("triangle #", "maximum area"), 2, line)
    rec.integers(values[:, :1], linenos, "triangle numbers")
    rec.finish()
    area = np.ascontiguousarray(values[:, 1])
    area[area <= 0] = -1.0
    return area


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
        with marker 1) as segments, no holes, and one region point per region attribute.
        The ``.ele`` attribute column and the region points hold, as Triangle's ``-A``
        writes them, ``cell_data["region_attribute"]`` when the mesh has it (float64),
        else the region markers, else ``cell_data["attributes"]``; markers that the float
        attributes do not imply (integral attribute = marker, else 0) are left out with a
        :class:`~meshwright.io.meshio_io.DataLossWarning`.  Read back, a single float
        column is ``cell_data["attributes"]`` (m, 1).

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


def _region_attribute(mesh: Mesh, path: Path) -> np.ndarray | None:
    """The triangles' float region attributes, or None; warns when the markers they leave out
    are not those the attributes imply (integral attribute = marker, else 0, as read_poly)."""
    attribute = mesh.cell_data.get("region_attribute", {}).get("triangle")
    if attribute is None:
        return None
    attribute = np.asarray(attribute, dtype=np.float64).reshape(-1)
    marker = mesh.cell_data.get("marker", {}).get("triangle")
    implied = np.where(attribute == np.round(attribute), attribute, 0.0)
    if marker is not None and not np.array_equal(np.asarray(marker), implied):
        warnings.warn(
            f"{path}: the .ele and .poly hold one region attribute per triangle, written from "
            f'cell_data["region_attribute"]; the triangle markers, not implied by it, are left out',
            DataLossWarning,
            stacklevel=4,
        )
    return attribute


def _write_ele(mesh: Mesh, element_type: str, path: Path, first_index: int) -> Path:
    elements = mesh.cells_of(element_type)
    m, k = elements.shape
    # Triangle's -A writes the regional attribute: a float region attribute comes first,
    # then the region marker, then any other attributes.
    attr = _region_attribute(mesh, path) if element_type == "triangle" else None
    integral = False
    if attr is None:
        attr = mesh.cell_data.get("marker", {}).get(element_type)
        integral = attr is not None
    if attr is None:
        attr = mesh.cell_data.get("attributes", {}).get(element_type)
    attr = np.zeros((m, 0)) if attr is None else np.asarray(attr, dtype=np.float64).reshape(m, -1)
    numbers = np.arange(first_index, first_index + m)
    rows = np.column_stack([numbers, elements + first_index, attr]).astype(np.float64)
    # Integers stay exact through float64: every one is below 2**31.
    fmt = ["%d"] * (1 + k) + ["%d" if integral else "%.17g"] * attr.shape[1]
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
    # One region point (a triangle's centroid) per piece that Triangle's -A floods from
    # one point, with its attribute (the float one when present, else the marker), so that
    # re-meshing the .poly with -A restores them; two separate regions of one value each
    # need a point.
    regions = np.zeros((0, 4))
    region_value = mesh.cell_data.get("region_attribute", {}).get("triangle")
    if region_value is None:
        region_value = mesh.cell_data.get("marker", {}).get("triangle")
    if region_value is not None and len(region_value):
        region_value = np.asarray(region_value, dtype=np.float64).reshape(-1)
        piece = _region_pieces(mesh.triangles, region_value, segments, len(mesh.points), path)
        first = np.unique(piece, return_index=True)[1]
        centroids = mesh.points[mesh.triangles[first]].mean(axis=1)
        regions = np.column_stack([centroids, region_value[first], -np.ones(len(first))])
    return write_poly_file(path, segments, seg_markers, None, regions, first_index=first_index)


def _region_pieces(triangles: np.ndarray, values: np.ndarray, segments: np.ndarray, n_points: int, path) -> np.ndarray:
    """Label the triangles by connected piece: triangles sharing an edge that is no segment
    and carrying equal values are in one piece.

    Parameters
    ----------
    triangles : (m, 3) int
    values : (m,) float64
    segments : (s, 2) int
        Edges that separate pieces.
    n_points : int
    path : Path
        The file being written, for the error message.

    Returns
    -------
    (m,) int64
        The smallest triangle index of each triangle's piece.
    """
    m = len(triangles)
    edges = np.sort(np.asarray(triangles)[:, [1, 2, 2, 0, 0, 1]].reshape(-1, 2), axis=1).astype(np.int64)
    keys = edges[:, 0] * n_points + edges[:, 1]
    order = np.argsort(keys, kind="stable")
    keys, owner = keys[order], np.repeat(np.arange(m), 3)[order]
    shared = np.flatnonzero(keys[1:] == keys[:-1])
    a, b = owner[shared], owner[shared + 1]
    seg = np.sort(np.asarray(segments, dtype=np.int64).reshape(-1, 2), axis=1)
    keep = ~np.isin(keys[shared], seg[:, 0] * n_points + seg[:, 1]) & (values[a] == values[b])
    a, b = a[keep], b[keep]
    label = np.arange(m)
    # Hook the larger root of every edge whose ends differ to the smaller, then jump the
    # pointers to their roots; each round removes a root, so m rounds suffice, and
    # pointers only point to smaller indices, so log2(m) + 1 jumps reach the roots.
    for _ in range(m + 1):
        la, lb = label[a], label[b]
        if np.array_equal(la, lb):
            return label
        np.minimum.at(label, np.maximum(la, lb), np.minimum(la, lb))
        for _ in range(m.bit_length() + 1):
            jumped = label[label]
            if np.array_equal(jumped, label):
                break
            label = jumped
    raise FormatError(f"{path}: labelling the regions of {m} triangles did not converge")
