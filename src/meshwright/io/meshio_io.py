"""Reading and writing every meshio format (VTU, VTK, Gmsh, XDMF, OFF, Medit, ...).

meshio is imported inside the functions so that ``import meshwright.io`` stays cheap.

Data mapping between :class:`~meshwright.core.mesh.Mesh` and ``meshio.Mesh``:

* points: 2-D meshes are written with z = 0 (several formats require 3-D points); on
  reading, a z column that is identically zero is dropped unless ``dim=3`` is asked.
* ``cell_data[name][cell_type]`` becomes meshio's list of one array per cell block; a
  block that lacks ``name`` is filled with 0 (integers) or NaN (floats), and comes back
  so (marker 0 means "no marker").
* ``cell_data["marker"]`` is stored under the format's own marker convention:
  ``gmsh:physical`` for Gmsh (``gmsh:geometrical`` gets the same values, one entity per
  marker), ``medit:ref`` for Medit (also ``point_data["marker"]``), ``marker`` elsewhere;
  these names are mapped back to ``"marker"`` on reading.  ``gmsh:geometrical`` and
  ``gmsh:dim_tags`` are dropped.
* XDMF is written with ``data_format="XML"`` (no h5py needed) unless asked otherwise.
* ``.msh`` is written as Gmsh 2.2 ASCII by default (per-element physical tags); ask
  ``file_format="gmsh"`` for 4.1, where each (cell type, marker) pair becomes one entity
  and cells are therefore grouped by marker (point order is kept).  Other cell data
  (e.g. ``region_attribute``, float64) is Gmsh ``ElementData`` in both versions.
* Only VTU, VTK, Gmsh (2.2 and 4.1) and XDMF keep arbitrary cell data; Medit keeps the
  marker alone.  Writing cell data that the format cannot hold emits a
  :class:`DataLossWarning` naming the arrays left out (the file is still written).
"""

from __future__ import annotations

import types
import warnings
from pathlib import Path

import numpy as np

from meshwright.core.errors import FormatError, InputError
from meshwright.core.mesh import CELL_DIMS, CELL_NODES, Mesh

__all__ = ["read", "write", "to_meshio", "from_meshio", "DataLossWarning"]


class DataLossWarning(UserWarning):
    """A file format cannot hold some of the mesh's data; the file is written without it."""


# Cell-data names under which formats keep what meshwright calls "marker".
_MARKER_KEYS = {"gmsh": "gmsh:physical", "gmsh22": "gmsh:physical", "medit": "medit:ref"}
_MARKER_ALIASES = ("gmsh:physical", "medit:ref")
_DROPPED_CELL_DATA = ("gmsh:geometrical",)
_DROPPED_POINT_DATA = ("gmsh:dim_tags",)
_GMSH_FORMATS = ("gmsh", "gmsh22")
# Writers that keep every cell data array (any name, integer or float), checked by
# tests/test_io.py; the others keep the marker at most (_MARKER_ONLY_FORMATS).
_CELL_DATA_FORMATS = ("vtu", "vtk", "gmsh", "gmsh22", "xdmf")
_MARKER_ONLY_FORMATS = ("medit",)


def _format_from_path(path: Path) -> str:
    """Return the meshio writer name for ``path``'s extension (longest match wins)."""
    import meshio

    name = path.name.lower()
    matches = [ext for ext in meshio.extension_to_filetypes if name.endswith(ext)]
    if not matches:
        known = ", ".join(sorted(meshio.extension_to_filetypes))
        raise FormatError(f"{path}: unknown file extension; known: {known}, .node, .ele, .poly")
    ext = max(matches, key=len)
    if ext == ".msh":
        return "gmsh22"
    return meshio.extension_to_filetypes[ext][0]


def _filler(per_type: dict[str, np.ndarray], m: int) -> np.ndarray:
    """Values for a block that lacks a data array: 0 for integers, NaN for floats."""
    sample = next(iter(per_type.values()))
    value = np.nan if np.issubdtype(sample.dtype, np.floating) else 0
    return np.full((m,) + sample.shape[1:], value, dtype=sample.dtype)


def to_meshio(mesh: Mesh, file_format: str | None = None):
    """Convert a :class:`Mesh` to a ``meshio.Mesh`` laid out for ``file_format``.

    Parameters
    ----------
    mesh : Mesh
    file_format : str, optional
        meshio writer name (``"vtu"``, ``"gmsh22"``, ``"gmsh"``, ``"medit"``, ...); decides
        the name of the marker data.

    Returns
    -------
    meshio.Mesh
        Points (n, 3) float64; empty cell blocks are left out.
    """
    import meshio

    points = mesh.points
    if mesh.dim == 2:
        points = np.column_stack([points, np.zeros(len(points))])
    blocks = [(t, c) for t, c in mesh.cells.items() if len(c)]
    marker_key = _MARKER_KEYS.get(file_format, "marker")
    cell_data = {}
    for name, per_type in mesh.cell_data.items():
        if not per_type or not blocks:
            continue
        key = marker_key if name == "marker" else name
        cell_data[key] = [per_type[t] if t in per_type else _filler(per_type, len(c)) for t, c in blocks]
    if file_format in _GMSH_FORMATS:
        physical = cell_data.get("gmsh:physical") or [np.zeros(len(c), np.int32) for _, c in blocks]
        cell_data["gmsh:physical"] = [np.asarray(p, dtype=np.int32) for p in physical]
        # The geometrical entity is the marker too: one entity per boundary / region marker.
        cell_data["gmsh:geometrical"] = [p.copy() for p in cell_data["gmsh:physical"]]
    point_data = dict(mesh.point_data)
    if file_format == "medit" and "marker" in point_data:
        point_data["medit:ref"] = point_data.pop("marker")
    if file_format == "gmsh":
        blocks, cell_data, point_data["gmsh:dim_tags"] = _gmsh41_entities(blocks, cell_data, len(points))
    return meshio.Mesh(points, blocks, point_data=point_data, cell_data=cell_data)


def _gmsh41_entities(blocks, cell_data, n_points):
    """Lay out cell blocks as Gmsh 4.1 entities.

    Gmsh 4.1 stores one physical tag per entity and meshio writes one entity per cell
    block, so every block is split by marker; entity tags are numbered per dimension.
    meshio writes the nodes grouped by entity, in (dimension, tag) order, and its reader
    keeps that file order for the points but the node-tag order for NodeData.  Giving
    the entities, in that order, consecutive index ranges of nodes keeps the file order
    equal to the point order (so point data stays aligned) and lets every entity own a
    node, which meshio's reader requires; the classification is nominal only.

    Returns
    -------
    blocks : list of (str, (m, k) int32)
        Cells grouped by marker within each type.
    cell_data : dict of str to list of arrays, split like the blocks
    dim_tags : (n_points, 2) int64
        Entity (dimension, tag) of every node.
    """
    if not blocks:
        return blocks, cell_data, np.zeros((n_points, 2), np.int64)
    new_blocks, parts, next_tag = [], [], {}
    for b, (cell_type, cells) in enumerate(blocks):
        physical = cell_data["gmsh:physical"][b]
        for value in np.unique(physical):
            rows = np.flatnonzero(physical == value)
            dim = CELL_DIMS[cell_type]
            next_tag[dim] = next_tag.get(dim, 0) + 1
            new_blocks.append((cell_type, cells[rows]))
            parts.append((b, rows, dim, next_tag[dim]))
    if len(parts) > n_points:
        raise FormatError(
            f"Gmsh 4.1 output needs at least one node per (cell type, marker) entity: {len(parts)} entities, "
            f"{n_points} nodes; write .msh with the default Gmsh 2.2 format instead"
        )
    new_data = {key: [arrays[b][rows] for b, rows, _, _ in parts] for key, arrays in cell_data.items()}
    new_data["gmsh:geometrical"] = [np.full(len(rows), tag, np.int32) for _, rows, _, tag in parts]
    entity_dim_tags = np.array(sorted((dim, tag) for _, _, dim, tag in parts), dtype=np.int64)
    owner = np.minimum(np.arange(n_points), len(parts) - 1)
    return new_blocks, new_data, entity_dim_tags[owner]


def _python_scalars(m) -> None:
    """Turn the non-tag data of ``m`` into object arrays of Python numbers, in place.

    meshio 5.3's ASCII Gmsh writer formats data values with ``repr``, which NumPy 2 turns
    into ``np.float64(0.5)``; Python floats and ints print as plain numbers.
    """
    m.point_data = {
        k: v if k in _DROPPED_POINT_DATA else np.array(np.asarray(v).tolist(), dtype=object)
        for k, v in m.point_data.items()
    }
    m.cell_data = {
        k: v if k in ("gmsh:physical", "gmsh:geometrical") else [np.array(a.tolist(), dtype=object) for a in v]
        for k, v in m.cell_data.items()
    }


def from_meshio(m, dim: int | None = None, source: str = "meshio.Mesh") -> Mesh:
    """Convert a ``meshio.Mesh`` to a :class:`Mesh`.

    Blocks of the same cell type are concatenated in file order, with their data;
    marker conventions (``gmsh:physical``, ``medit:ref``) become ``cell_data["marker"]``.

    Parameters
    ----------
    m : meshio.Mesh
    dim : {2, 3}, optional
        Force the spatial dimension; by default a z column of zeros is dropped.
    source : str
        Name of the file, for error messages.

    Raises
    ------
    FormatError
        Unsupported cell types (e.g. second-order elements) or a non-zero z with dim=2.
    """
    points = np.asarray(m.points, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] not in (2, 3):
        raise FormatError(f"{source}: points have shape {points.shape}, expected (n, 2) or (n, 3)")
    if points.shape[1] == 3 and dim != 3 and not np.any(points[:, 2]):
        points = points[:, :2]
    if dim == 2 and points.shape[1] == 3:
        raise FormatError(f"{source}: dim=2 asked but the points have non-zero z coordinates")
    if dim == 3 and points.shape[1] == 2:
        points = np.column_stack([points, np.zeros(len(points))])
    types = [block.type for block in m.cells]
    unsupported = sorted({t for t in types if t not in CELL_NODES})
    if unsupported:
        raise FormatError(
            f"{source}: cell types {', '.join(unsupported)} are not supported ({', '.join(CELL_NODES)})"
        )
    order = list(dict.fromkeys(types))
    cells = {t: np.concatenate([b.data for b in m.cells if b.type == t]) for t in order}
    keys = list(m.cell_data)
    cell_data = {}
    for key in keys:
        if key in _DROPPED_CELL_DATA:
            continue
        name = key
        if key in _MARKER_ALIASES and "marker" not in keys:
            name = "marker"
        arrays = m.cell_data[key]
        cell_data[name] = {
            t: np.concatenate([np.asarray(a) for a, typ in zip(arrays, types) if typ == t]) for t in order
        }
    if "marker" in cell_data:
        cell_data["marker"] = {t: np.asarray(v).astype(np.int32) for t, v in cell_data["marker"].items()}
    point_data = {}
    for key, values in m.point_data.items():
        if key in _DROPPED_POINT_DATA:
            continue
        if key in _MARKER_ALIASES and "marker" not in m.point_data:
            key = "marker"
        values = np.asarray(values)
        # Formats that store point data as floats (Gmsh NodeData) bring integer markers back.
        if key == "marker" and np.all(values == np.round(values)):
            values = values.astype(np.int32)
        point_data[key] = values
    try:
        return Mesh(points, cells, point_data=point_data, cell_data=cell_data)
    except ValueError as exc:
        raise FormatError(f"{source}: {exc}") from exc


def write(mesh: Mesh, path, file_format: str | None = None, **kwargs) -> None:
    """Write ``mesh`` with meshio.

    Parameters
    ----------
    mesh : Mesh
    path : str or Path
    file_format : str, optional
        meshio writer name; default from the extension (``.msh`` -> ``"gmsh22"``).
    **kwargs
        Passed to ``meshio.write``; Gmsh files default to ``binary=False``.

    Raises
    ------
    FormatError
        Unknown extension, or meshio cannot store this mesh in this format.

    Warns
    -----
    DataLossWarning
        The format cannot hold some of the cell data (any but VTU, VTK, Gmsh and XDMF; Medit
        keeps the marker); the file is written without it.
    """
    import meshio

    path = Path(path)
    fmt = file_format or _format_from_path(path)
    if fmt in _GMSH_FORMATS:
        kwargs.setdefault("binary", False)
    if fmt == "xdmf":
        # Keep the data inside the .xdmf file: the HDF5 default needs h5py.
        kwargs.setdefault("data_format", "XML")
    m = to_meshio(mesh, fmt)
    if fmt in _GMSH_FORMATS and not kwargs["binary"]:
        _python_scalars(m)
    try:
        meshio.write(path, m, file_format=fmt, **kwargs)
    except ImportError as exc:
        raise FormatError(f"{path}: writing {fmt} needs the optional package {exc.name!r}") from exc
    except (meshio.WriteError, ValueError, KeyError, TypeError, IndexError, AttributeError, AssertionError) as exc:
        # meshio's writers fail on meshes they do not expect with any of these (AssertionError
        # and AttributeError from the Nastran, FLAC3D and UGRID writers on mixed line/triangle meshes).
        raise FormatError(f"{path}: cannot write as {fmt}: {str(exc) or type(exc).__name__}") from exc
    _warn_dropped(mesh, path, fmt)


def _warn_dropped(mesh: Mesh, path: Path, fmt: str) -> None:
    """Emit a :class:`DataLossWarning` naming the cell data ``fmt`` does not store."""
    if fmt in _CELL_DATA_FORMATS:
        return
    kept = ("marker",) if fmt in _MARKER_ONLY_FORMATS else ()
    dropped = sorted(name for name, per_type in mesh.cell_data.items() if per_type and name not in kept)
    if dropped:
        warnings.warn(
            f"{path}: the {fmt} format cannot store cell data {', '.join(dropped)}; written without it "
            f"(.vtu, .vtk, .msh and .xdmf keep it)",
            DataLossWarning,
            stacklevel=3,
        )


def _reader_formats(path: Path, file_format: str | None) -> list[str]:
    """meshio reader names to try, most likely first."""
    import meshio

    if file_format is not None:
        return ["gmsh" if file_format in _GMSH_FORMATS else file_format]
    name = path.name.lower()
    matches = [ext for ext in meshio.extension_to_filetypes if name.endswith(ext)]
    if not matches:
        raise FormatError(f"{path}: unknown file extension")
    formats = list(meshio.extension_to_filetypes[max(matches, key=len)])
    # .msh is far more often Gmsh than ANSYS.
    return sorted(formats, key=lambda f: f != "gmsh")


def _split_by_blocks(cells, cell_data_raw: dict) -> dict:
    """Split each file-wide ElementData array at the cell counts of the (type, array) blocks."""
    ends = np.cumsum([len(block[1]) for block in cells])[:-1]
    return {name: np.split(data, ends) for name, data in cell_data_raw.items()}


def _read_gmsh(path: Path):
    """meshio's Gmsh reader, with the ElementData of Gmsh 2.2 files split correctly.

    meshio 5.3's 2.2 reader keeps its cells as ``(type, array)`` pairs and splits the
    ElementData arrays at the cumulative ``len`` of those pairs (2 each) instead of the
    blocks' cell counts, so every 2.2 file with element data (``region_attribute``) and
    more than one cell block fails to read.  The same reader runs here with that one
    function replaced in a copy of its globals; meshio's modules are left untouched.
    """
    from meshio.gmsh import _gmsh22, main

    code = _gmsh22.read_buffer.__code__
    if "cell_data_from_raw" not in code.co_names:  # a meshio that no longer splits this way
        return main.read(str(path))
    gmsh22 = types.SimpleNamespace(
        read_buffer=types.FunctionType(code, {**vars(_gmsh22), "cell_data_from_raw": _split_by_blocks})
    )
    readers = {version: gmsh22 if reader is _gmsh22 else reader for version, reader in main._readers.items()}
    read_buffer = types.FunctionType(main.read_buffer.__code__, {**vars(main), "_readers": readers})
    with open(path, "rb") as fh:
        return read_buffer(fh)


def _ends_inside_header(path: Path, fmt: str) -> bool:
    """Whether ``path`` ends inside an OFF or PLY header.

    meshio 5.3's OFF reader skips comment lines and its PLY reader reads header lines
    until a line that ends the header, both without checking for the end of the file:
    on a file cut short they loop forever.  Such files are refused before the call.
    """
    if fmt not in ("off", "ply"):
        return False
    with open(path, "rb") as fh:
        head = fh.read(1 << 20)
    if fmt == "ply":
        return len(head) < (1 << 20) and b"end_header" not in head
    significant = [ln for ln in head.split(b"\n")[1:] if ln.strip() and not ln.strip().startswith(b"#")]
    return not significant


def read(path, file_format: str | None = None, dim: int | None = None) -> Mesh:
    """Read any meshio format into a :class:`Mesh`.

    Parameters
    ----------
    path : str or Path
    file_format : str, optional
        meshio reader name; default from the extension.
    dim : {2, 3}, optional
        See :func:`from_meshio`.

    Raises
    ------
    InputError
        ``dim`` not None, 2 or 3.
    FormatError
        The file is missing or unreadable, cannot be parsed in that format (corrupt,
        truncated, not UTF-8 where the format is text), or holds unsupported cells.
    """
    # reader_map is private to meshio: meshio.read() prints the error and calls
    # sys.exit(1) when no reader succeeds, so the readers are called directly; the
    # meshio version is pinned in pyproject.toml to the series this was checked against.
    from meshio._helpers import reader_map

    path = Path(path)
    if dim not in (None, 2, 3):
        raise InputError(f"dim must be None, 2 or 3, got {dim!r}")
    if not path.is_file():
        raise FormatError(f"{path}: no such file" if not path.exists() else f"{path}: not a regular file")
    errors = []
    for fmt in _reader_formats(path, file_format):
        if fmt not in reader_map:
            raise FormatError(f"{path}: unknown meshio format {fmt!r}")
        try:
            if _ends_inside_header(path, fmt):
                errors.append(f"as {fmt}: the file ends inside the header")
                continue
            m = _read_gmsh(path) if fmt == "gmsh" else reader_map[fmt](str(path))
        except ImportError as exc:
            raise FormatError(f"{path}: reading {fmt} needs the optional package {exc.name!r}") from exc
        except OSError as exc:
            raise FormatError(f"{path}: cannot read ({exc.strerror or exc})") from exc
        except Exception as exc:  # noqa: BLE001
            # Third-party parsers of untrusted files fail in any way a corrupt file leads
            # them (ReadError, ValueError, UnicodeDecodeError, IndexError, AssertionError,
            # struct and zlib errors, ...): each means "not readable as this format".
            errors.append(f"as {fmt}: {str(exc) or type(exc).__name__}")
            continue
        return from_meshio(m, dim=dim, source=str(path))
    raise FormatError(f"{path}: cannot read ({'; '.join(errors)})")
