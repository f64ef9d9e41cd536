"""Triangle's ``.node`` and ``.poly`` text formats as arrays: the one parser and writer.

Source: J. R. Shewchuk, "Triangle: Engineering a 2D Quality Mesh Generator and Delaunay
Triangulator" (1996), and its file-format pages
(https://www.cs.cmu.edu/~quake/triangle.node.html, ``triangle.poly.html``)::

    .node   <#vertices> <dimension> <#attributes> <#boundary markers (0 or 1)>
            <vertex #> <x> <y> [attributes] [boundary marker]       one line per vertex
    .poly   the same vertex section; <#vertices> = 0 means the vertices are in the
            .node file of the same base name, then
            <#segments> <#boundary markers (0 or 1)>
            <segment #> <endpoint> <endpoint> [boundary marker]
            <#holes>
            <hole #> <x> <y>
            [<#regions>                                             optional section
             <region #> <x> <y> <attribute> [<maximum area>]]

Rules, as Triangle reads them: ``#`` starts a comment anywhere on a line; blank lines are
skipped; numbers may be written in any C / Fortran float notation (``-.5E+00``); header
fields after the first default to dimension 2 and 0 attributes, markers, segment markers;
a record may omit its trailing attributes and marker (0); vertices are numbered
consecutively from 0 or 1 (the first vertex decides) and every reference of a ``.poly``
uses that numbering, also when the vertices come from the ``.node`` file; the numbers of
segments, holes and regions are not used; a region without a maximum area takes its
attribute as the area bound (Triangle's ``-a`` then applies that value), and a maximum
area <= 0 means none.

Stricter than Triangle, so that no number is silently dropped or invented: every field
must be a finite number, indices and markers integers, a record may not carry more fields
than its header declares, nothing may follow the last section, and the file must be UTF-8
(ASCII) text.  Every violation raises :class:`~meshwright.core.errors.FormatError` naming
the file and the line.  A ``.poly`` with 0 vertices reads its ``.node`` file with
:func:`parse_node`, which never defers again: a ``.node`` that declares 0 vertices there
is an error, not a loop.

Layering: the parse stops at arrays (no :class:`~meshwright.geometry.Domain`, no
:class:`~meshwright.core.mesh.Mesh`) so that :func:`meshwright.geometry.read_poly` builds a
Domain from it and :mod:`meshwright.io.triangle_format` (a layer above) builds meshes and
reads the element files with the same :class:`Records`.  TetGen's 3-D ``.node`` shares the
grammar, so :func:`parse_node` reads it too.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple

import numpy as np

from meshwright.core.errors import FormatError, InputError

__all__ = [
    "Records",
    "NodeData",
    "PolyData",
    "parse_node",
    "parse_poly",
    "write_node_file",
    "write_poly_file",
]

_INT32_MAX = np.iinfo(np.int32).max


class NodeData(NamedTuple):
    """Contents of a ``.node`` file (or of the vertex section of a ``.poly`` file).

    Attributes
    ----------
    points : (n, d) float64
        d = 2 (Triangle) or 3 (TetGen).
    attributes : (n, a) float64
    markers : (n,) int32 or None
        None when the header declares no boundary markers.
    first_index : int
        Number of the first vertex (0 or 1); 0 for an empty file.
    lines : (n,) int64
        Line of each vertex in its file (1-based).
    """

    points: np.ndarray
    attributes: np.ndarray
    markers: np.ndarray | None
    first_index: int
    lines: np.ndarray


@dataclass(frozen=True)
class PolyData:
    """Contents of a ``.poly`` file, every index 0-based whatever the file's numbering.

    Attributes
    ----------
    vertices : (n, 2) float64
        From the ``.poly`` itself or from the ``.node`` file of the same name.
    vertex_markers : (n,) int32 or None
        None when the vertex header declares no markers.
    vertex_attributes : (n, a) float64
    segments : (s, 2) int32
    segment_markers : (s,) int32 or None
        None when the segment header declares no markers.
    holes : (h, 2) float64
        One point inside each hole.
    regions : (r, 4) float64
        ``x, y, attribute, max_area`` per region; ``max_area = -1`` when unconstrained.
    first_index : int
        Numbering of the vertices in the file(s): 0 or 1.
    vertex_path : Path
        The file the vertices were read from (the ``.poly`` or its ``.node``).
    vertex_lines, segment_lines, hole_lines, region_lines : (k,) int64
        Line of each record in its file, for error messages of later checks.
    """

    vertices: np.ndarray
    vertex_markers: np.ndarray | None
    vertex_attributes: np.ndarray
    segments: np.ndarray
    segment_markers: np.ndarray | None
    holes: np.ndarray
    regions: np.ndarray
    first_index: int
    vertex_path: Path
    vertex_lines: np.ndarray
    segment_lines: np.ndarray
    hole_lines: np.ndarray
    region_lines: np.ndarray


# -------------------------------------------------------------------------- records


class Records:
    """Non-blank, comment-stripped lines of a text file, with their 1-based line numbers.

    Parameters
    ----------
    path : str or Path

    Raises
    ------
    FormatError
        The file is missing, unreadable, or not UTF-8 (naming the line of the first bad
        byte).
    """

    def __init__(self, path):
        self.path = Path(path)
        try:
            raw = self.path.read_bytes()
        except FileNotFoundError:
            raise FormatError(f"{self.path}: no such file") from None
        except OSError as exc:
            raise FormatError(f"{self.path}: cannot read ({exc.strerror or exc})") from None
        try:
            text = raw.decode("utf-8-sig")
        except UnicodeDecodeError as exc:
            lineno = raw.count(b"\n", 0, exc.start) + 1
            raise FormatError(
                f"{self.path}, line {lineno}: not UTF-8 text (byte 0x{raw[exc.start]:02x}); "
                "is this a binary file?"
            ) from None
        # Split on "\n" only, so that line numbers are the ones an editor shows.
        lines = text.split("\n")
        self.n_lines = len(lines) - (lines[-1] == "")
        self.items: list[tuple[int, list[str]]] = []
        for lineno, line in enumerate(lines, start=1):
            fields = line.split("#", 1)[0].split()
            if fields:
                self.items.append((lineno, fields))
        self.pos = 0

    def error(self, lineno: int | None, message: str) -> FormatError:
        """A FormatError naming the file and, when given, the line."""
        where = self.path if lineno is None else f"{self.path}, line {lineno}"
        return FormatError(f"{where}: {message}")

    def more(self) -> bool:
        """Whether records are left."""
        return self.pos < len(self.items)

    def peek_first_field(self) -> str | None:
        """First field of the next record (None at the end), without consuming it."""
        return self.items[self.pos][1][0] if self.more() else None

    def header(self, what: str, names: tuple[str, ...], defaults: tuple[int, ...]) -> tuple[int, list[int]]:
        """Read one header line of non-negative integers.

        Parameters
        ----------
        what : str
            Name of the header, for messages.
        names : tuple of str
            Field names; the last ``len(defaults)`` are optional.
        defaults : tuple of int
            Values of missing optional trailing fields.

        Returns
        -------
        lineno : int
        values : list of int, one per name
        """
        if not self.more():
            raise self.error(max(self.n_lines, 1), f"unexpected end of file, expected {what} {_shape(names)}")
        lineno, fields = self.items[self.pos]
        self.pos += 1
        n_required = len(names) - len(defaults)
        if not n_required <= len(fields) <= len(names):
            raise self.error(lineno, f"expected {what} {_shape(names)}, got {' '.join(fields)!r}")
        values = []
        for field, name in zip(fields, names):
            value = _to_integer(field)
            if value is None or value < 0:
                raise self.error(lineno, f"{what}: {name} must be a non-negative integer, got {field!r}")
            values.append(value)
        values += defaults[len(fields) - n_required :]
        return lineno, values

    def table(
        self, count: int, what: str, names: tuple[str, ...], n_required: int, header_line: int
    ) -> tuple[np.ndarray, np.ndarray]:
        """Read ``count`` records of finite numbers.

        Parameters
        ----------
        count : int
            Number of records, as the header declared.
        what : str
            Record name (``"vertex"``, ``"segment"``, ...), for messages.
        names : tuple of str
            Field names, in order; at most this many fields per record.
        n_required : int
            The first ``n_required`` fields are required; missing trailing fields are 0.
        header_line : int
            Line of the header that declared ``count``, for messages.

        Returns
        -------
        values : (count, len(names)) float64
        linenos : (count,) int64
        """
        items = self.items[self.pos : self.pos + count]
        self.pos += len(items)
        ncol = len(names)
        linenos = np.fromiter((lineno for lineno, _ in items), dtype=np.int64, count=len(items))
        rows = []
        for lineno, fields in items:
            if not n_required <= len(fields) <= ncol:
                expected = f"{n_required} to {ncol}" if n_required < ncol else f"{ncol}"
                raise self.error(
                    lineno,
                    f"{'an' if what[0] in 'aeiou' else 'a'} {what} line holds {expected} fields {_shape(names)} as declared on line "
                    f"{header_line}, got {len(fields)}: {' '.join(fields)!r}",
                )
            rows.append(fields + ["0"] * (ncol - len(fields)))
        try:
            values = np.array(rows, dtype=np.float64).reshape(len(items), ncol)
        except ValueError:
            values = None
        if values is None or not np.isfinite(values).all():
            self._locate_bad_number(items, what, names)
        # Checked after the records that are there, so errors come in file order.
        if len(items) < count:
            raise self.error(
                max(self.n_lines, 1),
                f"unexpected end of file: line {header_line} declares {count} {_plural(what)}, found {len(items)}",
            )
        return values, linenos

    def _locate_bad_number(self, items, what: str, names: tuple[str, ...]) -> None:
        """Raise the error naming the first field that is not a finite number."""
        for lineno, fields in items:
            for field, name in zip(fields, names):
                try:
                    ok = np.isfinite(float(field))
                except ValueError:
                    ok = False
                if not ok:
                    raise self.error(lineno, f"{what} {name}: {field!r} is not a finite number")
        raise self.error(items[0][0], f"cannot read the {_plural(what)} from line {items[0][0]} on as numbers")

    def integers(self, values: np.ndarray, linenos: np.ndarray, what: str) -> np.ndarray:
        """Check that ``values`` (rows x cols, finite) hold int32 integers; return them as int64."""
        bad = np.flatnonzero(~np.all((values == np.round(values)) & (np.abs(values) <= _INT32_MAX), axis=1))
        if len(bad):
            i = int(bad[0])
            shown = " ".join(f"{v:g}" for v in values[i])
            raise self.error(int(linenos[i]), f"{what} must be integers, got {shown}")
        return values.astype(np.int64)

    def finish(self) -> None:
        """Raise if records are left after the last section."""
        if self.more():
            lineno, fields = self.items[self.pos]
            raise self.error(
                lineno, f"unexpected content after the last section: {' '.join(fields)!r} (wrong count above?)"
            )


def _shape(names: tuple[str, ...]) -> str:
    return "'" + " ".join(f"<{n}>" for n in names) + "'"


def _plural(what: str) -> str:
    return what[:-2] + "ices" if what.endswith("ex") else what + "s"


def _to_integer(field: str) -> int | None:
    """The integer a header field denotes (``7``, ``7.0``, ``7e0``), or None."""
    try:
        return int(field)
    except ValueError:
        pass
    try:
        value = float(field)
    except ValueError:
        return None
    return int(value) if np.isfinite(value) and value == round(value) else None


# -------------------------------------------------------------------------- parsing


def _numbering(rec: Records, numbers: np.ndarray, linenos: np.ndarray) -> int:
    """First index (0 or 1) of consecutively numbered vertices."""
    if not len(numbers):
        return 0
    first = int(numbers[0])
    if first not in (0, 1):
        raise rec.error(int(linenos[0]), f"the first vertex must be numbered 0 or 1, got {first}")
    wrong = np.flatnonzero(numbers != np.arange(first, first + len(numbers)))
    if len(wrong):
        i = int(wrong[0])
        raise rec.error(
            int(linenos[i]), f"vertex numbered {int(numbers[i])}, expected {first + i} (consecutive numbering)"
        )
    return first


def _vertex_section(rec: Records, header_line: int, header: list[int], dims: tuple[int, ...]) -> NodeData:
    n, dim, n_attr, n_markers = header
    if dim not in dims:
        raise rec.error(header_line, f"dimension must be {' or '.join(map(str, dims))}, got {dim}")
    if n_markers not in (0, 1):
        raise rec.error(header_line, f"number of vertex boundary markers must be 0 or 1, got {n_markers}")
    names = ("vertex #",) + ("x", "y", "z")[:dim] + ("attribute",) * n_attr + ("boundary marker",) * n_markers
    values, linenos = rec.table(n, "vertex", names, 1 + dim, header_line)
    numbers = rec.integers(values[:, :1], linenos, "vertex numbers")[:, 0]
    first = _numbering(rec, numbers, linenos)
    markers = None
    if n_markers:
        markers = rec.integers(values[:, -1:], linenos, "vertex boundary markers")[:, 0].astype(np.int32)
    return NodeData(
        np.ascontiguousarray(values[:, 1 : 1 + dim]),
        np.ascontiguousarray(values[:, 1 + dim : 1 + dim + n_attr]),
        markers,
        first,
        linenos,
    )


_NODE_HEADER = ("#vertices", "dimension", "#attributes", "#boundary markers")


def parse_node(path, dims: tuple[int, ...] = (2, 3)) -> NodeData:
    """Parse a Triangle (2-D) or TetGen (3-D) ``.node`` file.

    Parameters
    ----------
    path : str or Path
    dims : tuple of int
        Accepted dimensions.

    Returns
    -------
    NodeData

    Raises
    ------
    FormatError
        Naming the file and line of the first malformed record.
    """
    rec = Records(path)
    header_line, header = rec.header("the .node header", _NODE_HEADER, (2, 0, 0))
    node = _vertex_section(rec, header_line, header, dims)
    rec.finish()
    return node


def _companion_node(rec: Records, header_line: int) -> tuple[NodeData, Path]:
    """Vertices of a 0-vertex ``.poly``: its ``.node`` file, which may not defer again."""
    node_path = rec.path.with_suffix(".node")
    if node_path == rec.path or not node_path.is_file():
        raise rec.error(
            header_line,
            f"0 vertices declared, so they must be in {node_path.name} next to it, "
            + ("which is this very file" if node_path == rec.path else "which does not exist"),
        )
    node_rec = Records(node_path)
    line, header = node_rec.header("the .node header", _NODE_HEADER, (2, 0, 0))
    if header[0] == 0:
        raise node_rec.error(
            line,
            f"declares 0 vertices, but {rec.path.name} (line {header_line}) reads its vertices from this file",
        )
    node = _vertex_section(node_rec, line, header, (2,))
    node_rec.finish()
    return node, node_path


def parse_poly(path) -> PolyData:
    """Parse a Triangle ``.poly`` file (a planar straight-line graph) into arrays.

    A vertex count of 0 reads the vertices from the ``.node`` file of the same base name
    (which must list them: no further deferral).

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    PolyData

    Raises
    ------
    FormatError
        Missing or unreadable file or companion ``.node``, malformed or truncated record,
        count that disagrees with the records, non-finite number, vertex reference out of
        range, non-UTF-8 bytes: naming the file and line.
    """
    rec = Records(path)
    header_line, header = rec.header("the .poly vertex header", _NODE_HEADER, (2, 0, 0))
    if header[0] == 0:
        node, vertex_path = _companion_node(rec, header_line)
    else:
        node, vertex_path = _vertex_section(rec, header_line, header, (2,)), rec.path
    n = len(node.points)

    line, (n_seg, seg_markers) = rec.header("the segment header", ("#segments", "#boundary markers"), (0,))
    if seg_markers not in (0, 1):
        raise rec.error(line, f"number of segment boundary markers must be 0 or 1, got {seg_markers}")
    names = ("segment #", "endpoint", "endpoint") + ("boundary marker",) * seg_markers
    values, seg_lines = rec.table(n_seg, "segment", names, 3, line)
    ends = rec.integers(values[:, 1:3], seg_lines, "segment endpoints") - node.first_index
    bad = np.flatnonzero(np.any((ends < 0) | (ends >= n), axis=1))
    if len(bad):
        i = int(bad[0])
        shown = " ".join(str(v) for v in (ends[i] + node.first_index).tolist())
        source = "" if vertex_path == rec.path else f" of {vertex_path.name}"
        raise rec.error(
            int(seg_lines[i]),
            f"segment endpoints {shown} outside the vertex numbers{source}, "
            f"{node.first_index}..{node.first_index + n - 1}",
        )
    markers = None
    if seg_markers:
        markers = rec.integers(values[:, 3:4], seg_lines, "segment boundary markers")[:, 0].astype(np.int32)

    line, (n_holes,) = rec.header("the hole header", ("#holes",), ())
    values, hole_lines = rec.table(n_holes, "hole", ("hole #", "x", "y"), 3, line)
    holes = np.ascontiguousarray(values[:, 1:3])

    regions = np.zeros((0, 4))
    region_lines = np.zeros(0, dtype=np.int64)
    if rec.more():
        line, (n_regions,) = rec.header("the region header", ("#regions",), ())
        names = ("region #", "x", "y", "attribute", "maximum area")
        values, region_lines = rec.table(n_regions, "region", names, 4, line)
        regions = np.ascontiguousarray(values[:, 1:5])
        # Triangle uses the attribute as the area bound when the bound is missing.
        four = np.fromiter((len(f) == 4 for _, f in rec.items[rec.pos - n_regions : rec.pos]), bool, n_regions)
        regions[four, 3] = regions[four, 2]
        regions[regions[:, 3] <= 0, 3] = -1.0
    rec.finish()
    return PolyData(
        vertices=node.points,
        vertex_markers=node.markers,
        vertex_attributes=node.attributes,
        segments=ends.astype(np.int32),
        segment_markers=markers,
        holes=holes,
        regions=regions,
        first_index=node.first_index,
        vertex_path=vertex_path,
        vertex_lines=node.lines,
        segment_lines=seg_lines,
        hole_lines=hole_lines,
        region_lines=region_lines,
    )


# -------------------------------------------------------------------------- writing


def _float_array(a, name: str, shape: tuple) -> np.ndarray:
    """``a`` as float64 of ``shape`` (-1: any), finite; InputError naming ``name`` otherwise."""
    try:
        arr = np.asarray(a, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name} must be numeric: {exc}") from None
    if arr.size == 0 and len(shape) == 2 and shape[1] != -1:
        arr = arr.reshape(0, shape[1])  # [] for "none"
    if arr.ndim != len(shape) or any(s not in (-1, t) for s, t in zip(shape, arr.shape)):
        raise InputError(f"{name} must have shape {shape} (-1: any), got {arr.shape}")
    bad = np.flatnonzero(~np.isfinite(arr.reshape(len(arr), -1)).all(axis=1)) if arr.size else []
    if len(bad):
        raise InputError(f"{name} row {int(bad[0])} is not finite: {arr[int(bad[0])].tolist()}")
    return arr


def _int_array(a, name: str, shape: tuple, n_points: int | None = None) -> np.ndarray:
    """``a`` as int64 of ``shape``, int32 range (and below ``n_points`` when given)."""
    arr = _float_array(a, name, shape)
    wrong = ~((arr == np.round(arr)) & (np.abs(arr) <= _INT32_MAX))
    if n_points is not None:
        wrong |= (arr < 0) | (arr >= n_points)
    bad = np.flatnonzero(wrong.reshape(len(arr), -1).any(axis=1)) if arr.size else []
    if len(bad):
        limit = f" in 0..{n_points - 1}" if n_points is not None else ""
        raise InputError(f"{name} row {int(bad[0])} must be integers{limit}, got {arr[int(bad[0])].tolist()}")
    return arr.astype(np.int64)


def _check_first_index(first_index) -> int:
    if first_index not in (0, 1) or isinstance(first_index, bool):
        raise InputError(f"first_index must be 0 or 1, got {first_index!r}")
    return int(first_index)


def _write_rows(fh, columns: list[tuple[np.ndarray, str]]) -> None:
    """One line per row of the side-by-side ``columns`` ((m, c) arrays with a printf format)."""
    if not len(columns[0][0]):
        return
    arrays = [a.reshape(len(a), -1) for a, _ in columns]
    fmt = [f for (_, f), a in zip(columns, arrays) for _ in range(a.shape[1])]
    # Integers stay exact through float64: every one is below 2**31.
    np.savetxt(fh, np.hstack([a.astype(np.float64) for a in arrays]), fmt=fmt, delimiter=" ")


def _vertex_lines(fh, points, attributes, markers, first_index: int, header_comment: str) -> None:
    n, dim = points.shape
    fh.write(f"# {header_comment}\n{n} {dim} {attributes.shape[1]} {int(markers is not None)}\n")
    columns = [(np.arange(first_index, first_index + n), "%d"), (points, "%.17g"), (attributes, "%.17g")]
    if markers is not None:
        columns.append((markers, "%d"))
    _write_rows(fh, columns)


def _vertex_arrays(points, attributes, markers, dims: tuple[int, ...]):
    points = _float_array(points, "points", (-1, -1))
    if points.shape[1] not in dims:
        raise InputError(f"points must have {' or '.join(map(str, dims))} columns, got {points.shape[1]}")
    n = len(points)
    attributes = np.zeros((n, 0)) if attributes is None else _float_array(attributes, "attributes", (n, -1))
    if markers is not None:
        markers = _int_array(markers, "markers", (n,))
    return points, attributes, markers


def write_node_file(path, points, attributes=None, markers=None, first_index: int = 1) -> Path:
    """Write a Triangle (2-D) or TetGen (3-D) ``.node`` file.

    Coordinates and attributes are written with 17 significant digits, so
    :func:`parse_node` reads them back exactly.

    Parameters
    ----------
    path : str or Path
    points : (n, 2) or (n, 3) float64
    attributes : (n, a) float64, optional
    markers : (n,) int, optional
        Boundary markers; without them the header declares none.
    first_index : {0, 1}
        Number of the first vertex (Triangle's default is 1).

    Returns
    -------
    Path

    Raises
    ------
    InputError
        Wrong shapes, non-finite values, non-integer markers, ``first_index`` not 0 or 1.
    """
    first_index = _check_first_index(first_index)
    points, attributes, markers = _vertex_arrays(points, attributes, markers, (2, 3))
    path = Path(path)
    with open(path, "w", encoding="utf-8") as fh:
        _vertex_lines(fh, points, attributes, markers, first_index, "vertices: index x y [z] [attributes] [marker]")
    return path


def write_poly_file(
    path,
    segments,
    segment_markers=None,
    holes=None,
    regions=None,
    *,
    points=None,
    point_attributes=None,
    point_markers=None,
    first_index: int = 1,
) -> Path:
    """Write a Triangle ``.poly`` file.

    Parameters
    ----------
    path : str or Path
    segments : (s, 2) int
        0-based vertex indices.
    segment_markers : (s,) int, optional
        Without them the segment header declares none.
    holes : (h, 2) float64, optional
    regions : (r, 4) float64, optional
        ``x, y, attribute, max_area`` (``max_area <= 0``: unconstrained, written as -1).
    points : (n, 2) float64, optional
        The vertices; without them the file declares 0 vertices, i.e. they are in the
        ``.node`` file of the same name (written with :func:`write_node_file`).
    point_attributes : (n, a) float64, optional
    point_markers : (n,) int, optional
    first_index : {0, 1}
        Number of the first vertex, segment, hole and region.

    Returns
    -------
    Path

    Raises
    ------
    InputError
        Wrong shapes, non-finite values, non-integer or out-of-range indices, markers
        without vertices, ``first_index`` not 0 or 1.
    """
    first_index = _check_first_index(first_index)
    n_points = None
    if points is not None:
        points, point_attributes, point_markers = _vertex_arrays(points, point_attributes, point_markers, (2,))
        n_points = len(points)
    elif point_attributes is not None or point_markers is not None:
        raise InputError("point_attributes and point_markers need points (else they live in the .node file)")
    segments = _int_array(segments, "segments", (-1, 2), n_points)
    if np.any(segments < 0):
        raise InputError(f"segments row {int(np.flatnonzero((segments < 0).any(axis=1))[0])} has a negative index")
    s = len(segments)
    if segment_markers is not None:
        segment_markers = _int_array(segment_markers, "segment_markers", (s,))
    holes = np.zeros((0, 2)) if holes is None else _float_array(holes, "holes", (-1, 2))
    regions = np.zeros((0, 4)) if regions is None else _float_array(regions, "regions", (-1, 4))
    regions = regions.copy()
    regions[regions[:, 3] <= 0, 3] = -1.0
    path = Path(path)
    with open(path, "w", encoding="utf-8") as fh:
        if points is None:
            fh.write(f"# vertices are in {path.with_suffix('.node').name}\n0 2 0 0\n")
        else:
            _vertex_lines(fh, points, point_attributes, point_markers, first_index, "vertices: index x y [attributes] [marker]")
        fh.write(f"# segments: index a b [marker]\n{s} {int(segment_markers is not None)}\n")
        columns = [(np.arange(first_index, first_index + s), "%d"), (segments + first_index, "%d")]
        if segment_markers is not None:
            columns.append((segment_markers, "%d"))
        _write_rows(fh, columns)
        fh.write(f"# holes: index x y\n{len(holes)}\n")
        _write_rows(fh, [(np.arange(first_index, first_index + len(holes)), "%d"), (holes, "%.17g")])
        fh.write(f"# regions: index x y attribute max_area\n{len(regions)}\n")
        _write_rows(fh, [(np.arange(first_index, first_index + len(regions)), "%d"), (regions, "%.17g")])
    return path
