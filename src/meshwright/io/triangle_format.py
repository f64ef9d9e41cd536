"""Shewchuk's Triangle file formats: ``.node``, ``.ele`` and ``.poly`` (TetGen's 3-D
``.node`` / ``.ele`` too).

Format summary (https://www.cs.cmu.edu/~quake/triangle.html); ``#`` starts a comment,
blank lines are skipped, vertices are numbered from 0 or 1 and every file of a set
uses the numbering of its ``.node`` file:

* ``.node``: ``<#vertices> <dim> <#attributes> <#markers 0|1>`` then
  ``<i> <x> <y> [z] [attributes...] [marker]`` per vertex.
* ``.ele``: ``<#elements> <nodes per element> <#attributes>`` then
  ``<i> <v0> <v1> <v2> [v3] [attributes...]``.
* ``.poly``: a ``.node`` section (``0`` vertices means "read the ``.node`` file of the
  same name"), ``<#segments> <#markers 0|1>`` and ``<i> <a> <b> [marker]``, ``<#holes>``
  and ``<i> <x> <y>``, optionally ``<#regions>`` and ``<i> <x> <y> <attribute> <max area>``.

Mapping to :class:`~meshwright.core.mesh.Mesh` data (see ``core/mesh.py``): vertex markers
are ``point_data["marker"]``, vertex attributes ``point_data["attributes"]`` (n, a);
a single integer-valued element attribute is ``cell_data["marker"][cell_type]`` (region
marker), anything else ``cell_data["attributes"][cell_type]`` (m, a); ``.poly`` segments
are ``line`` cells with ``cell_data["marker"]["line"]``.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple

import numpy as np

from meshwright.core.errors import FormatError
from meshwright.core.mesh import Mesh

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


class NodeData(NamedTuple):
    """Contents of a ``.node`` file (or the vertex section of a ``.poly`` file).

    Attributes
    ----------
    points : (n, d) float64
    attributes : (n, a) float64
    markers : (n,) int32 or None
        None when the file declares no boundary markers.
    first_index : int
        Number of the first vertex in the file (0 or 1).
    """

    points: np.ndarray
    attributes: np.ndarray
    markers: np.ndarray | None
    first_index: int


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


@dataclass(frozen=True)
class PolyData:
    """Raw contents of a ``.poly`` file, every index 0-based.

    Attributes
    ----------
    vertices : (n, 2) float64
        From the ``.poly`` itself, or from the ``.node`` file of the same name.
    vertex_markers : (n,) int32
        Zeros when the file has none.
    vertex_attributes : (n, a) float64
    segments : (s, 2) int32
    segment_markers : (s,) int32
        Zeros when the file has none.
    holes : (h, 2) float64
        One point inside each hole.
    regions : (r, 4) float64
        ``x, y, attribute, max_area`` per region (max_area < 0: no constraint).
    """

    vertices: np.ndarray
    vertex_markers: np.ndarray
    vertex_attributes: np.ndarray
    segments: np.ndarray
    segment_markers: np.ndarray
    holes: np.ndarray
    regions: np.ndarray


# -------------------------------------------------------------------------- parsing


class _Records:
    """Non-blank, comment-stripped lines of a file with their 1-based line numbers."""

    def __init__(self, path: Path):
        self.path = path
        try:
            text = path.read_text()
        except UnicodeDecodeError as exc:
            raise FormatError(f"{path}: not a text file ({exc})") from exc
        self.items = []
        for lineno, raw in enumerate(text.splitlines(), start=1):
            fields = raw.split("#", 1)[0].split()
            if fields:
                self.items.append((lineno, fields))
        self.pos = 0

    def error(self, lineno: int | None, message: str) -> FormatError:
        where = f"{self.path}, line {lineno}" if lineno is not None else str(self.path)
        return FormatError(f"{where}: {message}")

    def header(self, what: str, n_min: int, n_max: int) -> list[int]:
        """Read one line of ``n_min`` to ``n_max`` integers (missing trailing ones are 0)."""
        if self.pos >= len(self.items):
            raise self.error(None, f"unexpected end of file, expected {what}")
        lineno, fields = self.items[self.pos]
        self.pos += 1
        if not n_min <= len(fields) <= n_max:
            raise self.error(lineno, f"expected {what} ({n_min} to {n_max} integers), got {' '.join(fields)!r}")
        try:
            values = [int(f) for f in fields]
        except ValueError:
            raise self.error(lineno, f"expected {what} (integers), got {' '.join(fields)!r}") from None
        if any(v < 0 for v in values):
            raise self.error(lineno, f"negative count in {what}: {' '.join(fields)!r}")
        return values + [0] * (n_max - len(values))

    def block(self, count: int, n_min: int, n_max: int, what: str) -> tuple[np.ndarray, np.ndarray]:
        """Read ``count`` lines of ``n_min`` to ``n_max`` numbers.

        Returns
        -------
        values : (count, n_max) float64
            Missing trailing fields are NaN.
        linenos : (count,) int64
        """
        items = self.items[self.pos : self.pos + count]
        if len(items) < count:
            raise self.error(None, f"unexpected end of file: expected {count} {what} lines, found {len(items)}")
        self.pos += count
        linenos = np.array([lineno for lineno, _ in items], dtype=np.int64)
        rows = []
        for lineno, fields in items:
            if not n_min <= len(fields) <= n_max:
                raise self.error(lineno, f"expected {n_min} to {n_max} fields for a {what}, got {len(fields)}")
            rows.append(fields + ["nan"] * (n_max - len(fields)))
        try:
            values = np.array(rows, dtype=np.float64).reshape(count, n_max)
        except ValueError:
            for lineno, fields in items:
                for field in fields:
                    try:
                        float(field)
                    except ValueError:
                        raise self.error(lineno, f"cannot parse {field!r} as a number in a {what}") from None
            raise
        return values, linenos

    def integers(self, values: np.ndarray, linenos: np.ndarray, what: str) -> np.ndarray:
        """Check that ``values`` (rows x cols) are finite integers; return them as int64."""
        bad = ~np.all(np.isfinite(values) & (values == np.round(values)), axis=1)
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise self.error(int(linenos[i]), f"{what} must be integers, got {values[i].tolist()}")
        return values.astype(np.int64)

    def finish(self) -> None:
        if self.pos < len(self.items):
            lineno, fields = self.items[self.pos]
            raise self.error(lineno, f"unexpected extra content {' '.join(fields)!r}")


def _first_index(rec: _Records, numbers: np.ndarray, linenos: np.ndarray, what: str) -> int:
    """Detect 0- or 1-based numbering from the first record and check it is consecutive."""
    if not len(numbers):
        return 0
    first = int(numbers[0])
    if first not in (0, 1):
        raise rec.error(int(linenos[0]), f"the first {what} must be numbered 0 or 1, got {first}")
    wrong = np.flatnonzero(numbers != np.arange(first, first + len(numbers)))
    if len(wrong):
        i = int(wrong[0])
        raise rec.error(int(linenos[i]), f"{what} numbered {int(numbers[i])}, expected {first + i}")
    return first


def _read_vertices(rec: _Records, header: list[int], dims: tuple[int, ...]) -> NodeData:
    n, dim, n_attr, n_markers = header
    if dim not in dims:
        raise rec.error(rec.items[rec.pos - 1][0], f"dimension must be {' or '.join(map(str, dims))}, got {dim}")
    if n_markers not in (0, 1):
        raise rec.error(rec.items[rec.pos - 1][0], f"number of boundary markers must be 0 or 1, got {n_markers}")
    ncol = 1 + dim + n_attr + n_markers
    values, linenos = rec.block(n, ncol, ncol, "vertex")
    numbers = rec.integers(values[:, :1], linenos, "vertex numbers")[:, 0]
    first = _first_index(rec, numbers, linenos, "vertex")
    markers = None
    if n_markers:
        markers = rec.integers(values[:, -1:], linenos, "vertex boundary markers")[:, 0].astype(np.int32)
    return NodeData(
        np.ascontiguousarray(values[:, 1 : 1 + dim]),
        np.ascontiguousarray(values[:, 1 + dim : 1 + dim + n_attr]),
        markers,
        first,
    )


def _indices(rec, values, linenos, first_index: int, n_points: int | None, what: str) -> np.ndarray:
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


def read_node(path) -> NodeData:
    """Read a Triangle / TetGen ``.node`` file (2-D or 3-D).

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    NodeData

    Raises
    ------
    FormatError
        Naming the file and line of the first malformed record.
    """
    rec = _Records(Path(path))
    node = _read_vertices(rec, rec.header("the .node header", 1, 4), (2, 3))
    rec.finish()
    return node


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
    FormatError
        Malformed line, unsupported nodes per element, a vertex reference out of range.
    """
    rec = _Records(Path(path))
    n, k, n_attr = rec.header("the .ele header", 2, 3)
    if k not in (3, 4):
        raise rec.error(rec.items[0][0], f"{k} nodes per element are not supported (3 or 4; no second order)")
    ncol = 1 + k + n_attr
    values, linenos = rec.block(n, ncol, ncol, "element")
    numbers = rec.integers(values[:, :1], linenos, "element numbers")[:, 0]
    base = _first_index(rec, numbers, linenos, "element") if first_index is None else first_index
    cells = _indices(rec, values[:, 1 : 1 + k], linenos, base, n_points, "element")
    rec.finish()
    return EleData(cells, np.ascontiguousarray(values[:, 1 + k :]))


def read_poly(path) -> PolyData:
    """Parse a Triangle ``.poly`` file (planar straight-line graph) into arrays.

    A vertex count of 0 means the vertices are in the ``.node`` file of the same name.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    PolyData
        Every index 0-based, whatever the file's numbering.

    Raises
    ------
    FormatError
        Naming the file and line of the first malformed record.
    """
    path = Path(path)
    rec = _Records(path)
    header = rec.header("the .poly vertex header", 1, 4)
    if header[0] == 0:
        node_path = path.with_suffix(".node")
        if not node_path.exists():
            raise rec.error(rec.items[0][0], f"0 vertices listed but {node_path} does not exist")
        node = read_node(node_path)
        if node.points.shape[1] != 2:
            raise FormatError(f"{node_path}: a .poly needs 2-D vertices, got {node.points.shape[1]}-D")
    else:
        node = _read_vertices(rec, header, (2,))
    n = len(node.points)
    n_seg, seg_markers = rec.header("the segment header", 1, 2)
    if seg_markers not in (0, 1):
        raise rec.error(None, f"number of segment boundary markers must be 0 or 1, got {seg_markers}")
    values, linenos = rec.block(n_seg, 3 + seg_markers, 3 + seg_markers, "segment")
    segments = _indices(rec, values[:, 1:3], linenos, node.first_index, n, "segment")
    markers = np.zeros(n_seg, np.int32)
    if seg_markers:
        markers = rec.integers(values[:, 3:4], linenos, "segment markers")[:, 0].astype(np.int32)
    (n_holes,) = rec.header("the hole count", 1, 1)
    holes, _ = rec.block(n_holes, 3, 3, "hole")
    regions = np.zeros((0, 4))
    if rec.pos < len(rec.items):
        (n_regions,) = rec.header("the region count", 1, 1)
        # Triangle reads x, y, attribute, max area; absent trailing values mean none.
        values, _ = rec.block(n_regions, 3, 5, "region")
        regions = values[:, 1:5]
        regions[:, 2] = np.nan_to_num(regions[:, 2], nan=0.0)
        regions[:, 3] = np.nan_to_num(regions[:, 3], nan=-1.0)
    rec.finish()
    return PolyData(
        vertices=node.points,
        vertex_markers=node.markers if node.markers is not None else np.zeros(n, np.int32),
        vertex_attributes=node.attributes,
        segments=segments,
        segment_markers=markers,
        holes=np.ascontiguousarray(holes[:, 1:3]),
        regions=np.ascontiguousarray(regions),
    )


def _stem(path) -> Path:
    path = Path(path)
    return path.with_suffix("") if path.suffix in TRIANGLE_SUFFIXES else path


def _cell_attributes(attributes: np.ndarray) -> tuple[str, np.ndarray] | None:
    """Map element attributes to a cell_data entry: one integer column is a marker."""
    if attributes.shape[1] == 0:
        return None
    if attributes.shape[1] == 1 and np.all(attributes == np.round(attributes)):
        return "marker", attributes[:, 0].astype(np.int32)
    return "attributes", attributes


def read_triangle(path) -> Mesh:
    """Read a Triangle / TetGen file set into a :class:`~meshwright.core.mesh.Mesh`.

    ``path`` may name the ``.node``, ``.ele`` or ``.poly`` file or the common stem.  A
    ``.poly`` path alone gives its vertices and segments (``line`` cells).  Otherwise the
    ``.node`` and, if present, ``.ele`` are read; the segments of a ``.poly`` of the same
    name that lists its vertices in that ``.node`` (vertex count 0) become ``line`` cells.

    Returns
    -------
    Mesh
    """
    path = Path(path)
    stem = _stem(path)
    if path.suffix == ".poly":
        poly = read_poly(path)
        return Mesh(
            poly.vertices,
            {"line": poly.segments},
            point_data={"marker": poly.vertex_markers},
            cell_data={"marker": {"line": poly.segment_markers}},
        )
    node = read_node(stem.with_suffix(".node"))
    cells: dict[str, np.ndarray] = {}
    cell_data: dict[str, dict[str, np.ndarray]] = {}
    ele_path = stem.with_suffix(".ele")
    if ele_path.exists():
        ele = read_ele(ele_path, node.first_index, len(node.points))
        cell_type = "triangle" if ele.cells.shape[1] == 3 else "tetra"
        if cell_type == "tetra" and node.points.shape[1] != 3:
            raise FormatError(f"{ele_path}: 4-node elements need a 3-D .node file")
        cells[cell_type] = ele.cells
        entry = _cell_attributes(ele.attributes)
        if entry is not None:
            cell_data[entry[0]] = {cell_type: entry[1]}
    poly_path = stem.with_suffix(".poly")
    if poly_path.exists() and node.points.shape[1] == 2 and _poly_uses_node_file(poly_path):
        poly = read_poly(poly_path)
        cells["line"] = poly.segments
        cell_data.setdefault("marker", {})["line"] = poly.segment_markers
    point_data = {}
    if node.markers is not None:
        point_data["marker"] = node.markers
    if node.attributes.shape[1]:
        point_data["attributes"] = node.attributes
    return Mesh(node.points, cells, point_data=point_data, cell_data=cell_data)


def _poly_uses_node_file(path: Path) -> bool:
    rec = _Records(path)
    return bool(rec.items) and rec.items[0][1][0] == "0"


# -------------------------------------------------------------------------- writing


def _write_table(path: Path, header: str, columns: list[tuple[np.ndarray, str]], comment: str) -> None:
    """Write a header line and one row per record; ``columns`` pairs (m, c) arrays and a
    printf format; integers stay exact because every value is below 2**53."""
    arrays = [np.asarray(a, dtype=np.float64).reshape(len(a), -1) for a, _ in columns]
    fmt = [f for (a, f), arr in zip(columns, arrays) for _ in range(arr.shape[1])]
    with open(path, "w") as fh:
        fh.write(f"# {comment}\n{header}\n")
        if arrays and len(arrays[0]):
            np.savetxt(fh, np.hstack(arrays), fmt=fmt, delimiter=" ")


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
    FormatError
        Cell types the files cannot store (2-D: only line and triangle; 3-D: only tetra).
    """
    if first_index not in (0, 1):
        raise FormatError(f"first_index must be 0 or 1, got {first_index}")
    stem = _stem(path)
    n, dim = mesh.points.shape
    storable = ("line", "triangle") if dim == 2 else ("tetra",)
    unsupported = [t for t, c in mesh.cells.items() if len(c) and t not in storable]
    if unsupported:
        raise FormatError(
            f"{stem}: {dim}-D Triangle/TetGen files cannot store {', '.join(unsupported)} cells "
            f"(only {', '.join(storable)})"
        )
    written = []
    columns = [(np.arange(first_index, first_index + n), "%d"), (mesh.points, "%.17g")]
    attributes = np.asarray(mesh.point_data.get("attributes", np.zeros((n, 0)))).reshape(n, -1)
    columns.append((attributes, "%.17g"))
    markers = mesh.point_data.get("marker")
    if markers is not None:
        columns.append((markers, "%d"))
    node_path = stem.with_suffix(".node")
    header = f"{n} {dim} {attributes.shape[1]} {int(markers is not None)}"
    _write_table(node_path, header, columns, "vertices: index x y [z] [attributes] [marker]")
    written.append(node_path)

    element_type = "triangle" if dim == 2 else "tetra"
    elements = mesh.cells_of(element_type)
    if len(elements):
        m, k = elements.shape
        marker = mesh.cell_data.get("marker", {}).get(element_type)
        attr = marker if marker is not None else mesh.cell_data.get("attributes", {}).get(element_type)
        attr = np.zeros((m, 0)) if attr is None else np.asarray(attr).reshape(m, -1)
        cols = [(np.arange(first_index, first_index + m), "%d"), (elements + first_index, "%d")]
        cols.append((attr, "%d" if marker is not None else "%.17g"))
        ele_path = stem.with_suffix(".ele")
        _write_table(ele_path, f"{m} {k} {attr.shape[1]}", cols, f"{element_type} elements: index vertices [attributes]")
        written.append(ele_path)

    if dim == 2:
        written.append(_write_poly(mesh, stem.with_suffix(".poly"), first_index))
    return written


def _write_poly(mesh: Mesh, path: Path, first_index: int) -> Path:
    segments = mesh.lines
    seg_markers = mesh.cell_data.get("marker", {}).get("line")
    if not len(segments) and len(mesh.triangles):
        segments = mesh.boundary_facets()
        seg_markers = np.ones(len(segments), np.int32)
    if seg_markers is None:
        seg_markers = np.zeros(len(segments), np.int32)
    s = len(segments)
    # One region point (a triangle centroid) per region marker, so that re-meshing the
    # .poly with Triangle's -A restores the region attributes.
    regions = np.zeros((0, 4))
    region_marker = mesh.cell_data.get("marker", {}).get("triangle")
    if region_marker is not None and len(region_marker):
        values, first = np.unique(region_marker, return_index=True)
        centroids = mesh.points[mesh.triangles[first]].mean(axis=1)
        regions = np.column_stack([centroids, values, -np.ones(len(values))])
    with open(path, "w") as fh:
        fh.write("# vertices are in the .node file of the same name\n0 2 0 0\n")
        fh.write(f"# segments: index a b marker\n{s} 1\n")
        if s:
            rows = np.column_stack([np.arange(first_index, first_index + s), segments + first_index, seg_markers])
            np.savetxt(fh, rows, fmt="%d")
        fh.write("# holes\n0\n")
        fh.write(f"# regions: index x y attribute max_area\n{len(regions)}\n")
        if len(regions):
            rows = np.column_stack([np.arange(first_index, first_index + len(regions)), regions])
            np.savetxt(fh, rows, fmt=["%d", "%.17g", "%.17g", "%d", "%g"])
    return path
