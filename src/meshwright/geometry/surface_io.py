"""Reading closed surfaces from files: meshio formats and TetGen's ``.smesh``, ``.poly``, ``.node``/``.face``.

TetGen's formats (H. Si, "TetGen, a Delaunay-based quality tetrahedral mesh generator",
ACM Trans. Math. Softw. 41(2), 2015, and its user manual, section 5), as read here::

    nodes   <#points> <3> <#attributes> <#markers (0|1)>      #points = 0: the .node file
            <point #> <x> <y> <z> [attributes] [marker]       numbered from 0 or 1
    .smesh  facets   <#facets> <#markers (0|1)>
                     <#corners> <corner> ... <corner> [marker]
    .poly   facets   <#facets> <#markers (0|1)>
                     <#polygons> [<#holes>] [marker]            then, per facet,
                     <#corners> <corner> ... <corner>          one line per polygon
    both    holes    <#holes>  /  <hole #> <x> <y> <z>
            regions  [<#regions>  /  <region #> <x> <y> <z> <region number> [<max volume>]]
    .face   <#faces> <#markers (0|1)>  /  <face #> <a> <b> <c> [marker]   (with its .node)

Comments (``#``) and blank lines are skipped as in :mod:`meshwright.geometry.poly_format`,
whose line reader and node-section parser are reused.  A polygon of more than three
corners is cut into triangles by exact ear clipping (:func:`_surface_kernels.ear_clip`);
polygons of one or two corners and facet holes (which need a planar constrained
triangulation) are refused with the line named.  TetGen faces carry no orientation, so
the surface read is :meth:`Surface.oriented` when it is closed and manifold (edges in two
faces each); an edge in more than two faces makes it ``multi_region``.  Points no face uses
(TetGen would insert them into the volume) are dropped with a warning.

Every other extension goes through :func:`meshwright.io.meshio_io.read` (STL, OBJ, PLY,
OFF, VTK, VTU, Gmsh ``.msh``, ...), imported when called: like
:meth:`~meshwright.core.mesh.Mesh.write`, the one call-time reference from a lower layer to
``io``, so that the meshio wrapper's fixes (no ``sys.exit``, truncated OFF/PLY headers,
Gmsh 2.2 element data) apply here too.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from meshwright.core.errors import FormatError, GeometryError, InputError
from meshwright.geometry._surface_kernels import ear_clip
from meshwright.geometry.poly_format import Records, _vertex_section, parse_node
from meshwright.geometry.surface import EdgeGroups, Surface

__all__ = ["read_surface", "write_smesh"]

_NODE_HEADER = ("#points", "dimension", "#attributes", "#boundary markers")


def read_surface(path, *, orient: bool | None = None) -> Surface:
    """Read a closed triangulated surface.

    Parameters
    ----------
    path : str or Path
        ``.smesh``, ``.poly`` (TetGen 3-D), ``.node`` or ``.face`` (the pair of the same
        base name), or any extension meshio reads (``.stl``, ``.obj``, ``.ply``,
        ``.off``, ``.vtk``, ``.vtu``, ``.msh``, ...), whose triangle cells are taken.
    orient : bool, optional
        True: return :meth:`Surface.oriented` (errors as it raises); False: the faces as
        written.  Default: for the TetGen formats, which carry no orientation, oriented
        when the surface is closed and manifold (else as read, for :meth:`Surface.validate`
        to name the fault); the other formats as written.

    Returns
    -------
    Surface

    Raises
    ------
    FormatError
        A missing, unreadable or malformed file, naming the file and the line.
    InputError
        ``orient`` not None/True/False.
    GeometryError
        ``orient`` on a surface that cannot be oriented (see :meth:`Surface.oriented`).
    """
    if orient not in (None, True, False):
        raise InputError(f"orient must be None, True or False, got {orient!r}")
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix in (".smesh", ".poly", ".node", ".face"):
        surface = _read_tetgen(path, suffix)
    else:
        from meshwright.io.meshio_io import read

        # meshio's STL reader probes "84 + count * 50 == size" in uint32, which overflows
        # (a RuntimeWarning only) on ASCII files; the probe's answer is right either way.
        with np.errstate(over="ignore"):
            mesh = read(path, dim=3)
        if not len(mesh.triangles):
            raise FormatError(f"{path}: no triangle cells (cells: {', '.join(mesh.cells) or 'none'})")
        try:
            surface = Surface.from_mesh(mesh)
        except InputError as exc:
            raise FormatError(f"{path}: {exc}") from exc
        if orient is None:
            return surface
    if orient is None:
        # Only a closed manifold surface has an orientation to restore; anything else is
        # returned as read, for validate() to name what is wrong.
        edges = EdgeGroups(surface.triangles, surface.n_points)
        if surface.multi_region or not np.all(edges.count == 2):
            return surface
        try:
            return surface.oriented()
        except GeometryError:
            return surface
    return surface.oriented() if orient else surface


# ------------------------------------------------------------------ TetGen


def _next(rec: Records, what: str) -> tuple[int, list[str]]:
    if not rec.more():
        raise rec.error(max(rec.n_lines, 1), f"unexpected end of file, expected {what}")
    item = rec.items[rec.pos]
    rec.pos += 1
    return item


def _ints(rec: Records, lineno: int, fields: list[str], what: str) -> list[int]:
    out = []
    for field in fields:
        try:
            out.append(int(field))
        except ValueError:
            raise rec.error(lineno, f"{what}: {field!r} is not an integer") from None
    return out


def _nodes(rec: Records):
    """Node section of ``rec`` (or of the companion ``.node`` when it declares 0 points)."""
    line, header = rec.header("the node header", _NODE_HEADER, (3, 0, 0))
    if header[0] > 0:
        return _vertex_section(rec, line, header, (3,))
    node_path = rec.path.with_suffix(".node")
    if node_path == rec.path or not node_path.is_file():
        raise rec.error(line, f"0 points declared, so they must be in {node_path.name}, which does not exist")
    node = parse_node(node_path, dims=(3,))
    if not len(node.points):
        raise FormatError(f"{node_path}: declares 0 points, but {rec.path.name} reads its points from it")
    return node


def _polygon(rec: Records, lineno: int, fields: list[str], n: int, first: int, has_marker: bool | None):
    """Corners (0-based) of one polygon line and its marker (None when none is given)."""
    values = _ints(rec, lineno, fields, "polygon")
    k = values[0]
    extra = len(values) - 1 - k
    if k < 3:
        raise rec.error(lineno, f"a polygon of {k} corners (segments and points inside facets are not supported)")
    allowed = (0, 1) if has_marker is None else ((1,) if has_marker else (0,))
    if extra not in allowed:
        raise rec.error(lineno, f"expected {k} corners{' and a marker' if has_marker else ''}, got {' '.join(fields)!r}")
    corners = np.array(values[1 : 1 + k], np.int64) - first
    bad = np.flatnonzero((corners < 0) | (corners >= n))
    if len(bad):
        raise rec.error(lineno, f"corner {corners[bad[0]] + first} outside the point numbers {first}..{first + n - 1}")
    if len(np.unique(corners)) < k:
        raise rec.error(lineno, "a polygon repeats a corner")
    return corners, (values[-1] if extra == 1 else None)


def _triangulate(rec: Records, lineno: int, points: np.ndarray, corners: np.ndarray) -> np.ndarray:
    if len(corners) == 3:
        return corners[None]
    q = points[corners]
    r = np.roll(q, -1, axis=0)
    # Twice the signed area in each cyclic projection (drop x, y, z).
    areas = np.array([np.sum(q[:, (a + 1) % 3] * r[:, (a + 2) % 3] - r[:, (a + 1) % 3] * q[:, (a + 2) % 3])
                      for a in range(3)])
    ax = int(np.argmax(np.abs(areas)))
    tris = ear_clip(points, corners, ax, 1.0 if areas[ax] > 0 else -1.0)
    if not len(tris):
        raise rec.error(lineno, f"the polygon of {len(corners)} corners is not simple and planar: it cannot be cut into triangles")
    return tris


def _seeds(rec: Records) -> tuple[np.ndarray, np.ndarray]:
    """Hole and (optional) region sections: (h, 3) and (r, 5) ``x y z id max_volume``."""
    line, (n_holes,) = rec.header("the hole header", ("#holes",), ())
    values, _ = rec.table(n_holes, "hole", ("hole #", "x", "y", "z"), 4, line)
    holes = np.ascontiguousarray(values[:, 1:4])
    regions = np.zeros((0, 5))
    if rec.more():
        line, (n_regions,) = rec.header("the region header", ("#regions",), ())
        names = ("region #", "x", "y", "z", "region number", "maximum volume")
        values, lines = rec.table(n_regions, "region", names, 5, line)
        rec.integers(values[:, 4:5], lines, "region numbers")
        six = np.fromiter((len(f) == 6 for _, f in rec.items[rec.pos - n_regions : rec.pos]), bool, n_regions)
        regions = np.ascontiguousarray(values[:, 1:6])
        regions[~six | (regions[:, 4] <= 0), 4] = -1.0
    rec.finish()
    return holes, regions


def _facets(rec: Records, points: np.ndarray, first: int, poly: bool):
    line, (n_facets, with_markers) = rec.header("the facet header", ("#facets", "#boundary markers"), (0,))
    if with_markers not in (0, 1):
        raise rec.error(line, f"number of facet boundary markers must be 0 or 1, got {with_markers}")
    tris, marks = [], []
    for _ in range(n_facets):
        lineno, fields = _next(rec, "a facet")
        marker = 1
        if poly:
            head = _ints(rec, lineno, fields, "facet header")
            if not 1 <= len(head) <= 3:
                raise rec.error(lineno, f"expected '<#polygons> [#holes] [marker]', got {' '.join(fields)!r}")
            n_poly, n_holes = head[0], (head[1] if len(head) > 1 else 0)
            if n_holes:
                raise rec.error(lineno, f"a facet with {n_holes} holes (facet holes are not supported)")
            if len(head) == 3 and with_markers:
                marker = head[2]
            polygons = [_next(rec, "a polygon") for _ in range(n_poly)]
            for pl, pf in polygons:
                corners, _ = _polygon(rec, pl, pf, len(points), first, False)
                tris.append(_triangulate(rec, pl, points, corners))
                marks.append(np.full(len(tris[-1]), marker))
        else:
            corners, m = _polygon(rec, lineno, fields, len(points), first, None)
            if m is not None:
                if not with_markers:
                    raise rec.error(lineno, "a facet marker, but the facet header declares none")
                marker = m
            tris.append(_triangulate(rec, lineno, points, corners))
            marks.append(np.full(len(tris[-1]), marker))
    if not tris:
        raise rec.error(line, "no facets")
    return np.concatenate(tris), np.concatenate(marks)


def _faces(path: Path, points: np.ndarray, first: int):
    rec = Records(path)
    line, (n, with_markers) = rec.header("the face header", ("#faces", "#boundary markers"), (0,))
    names = ("face #", "corner", "corner", "corner") + ("boundary marker",) * min(with_markers, 1)
    values, lines = rec.table(n, "face", names, 4, line)
    ints = rec.integers(values, lines, "face corners and markers")
    corners = ints[:, 1:4] - first
    bad = np.flatnonzero(np.any((corners < 0) | (corners >= len(points)), axis=1))
    if len(bad):
        raise rec.error(int(lines[bad[0]]), f"a corner outside the point numbers {first}..{first + len(points) - 1}")
    rec.finish()
    markers = ints[:, 4] if with_markers else np.ones(n, np.int64)
    return corners, markers


def _read_tetgen(path: Path, suffix: str) -> Surface:
    holes, regions = np.zeros((0, 3)), np.zeros((0, 5))
    if suffix in (".node", ".face"):
        node = parse_node(path.with_suffix(".node"), dims=(3,))
        tri, markers = _faces(path.with_suffix(".face"), node.points, node.first_index)
    else:
        rec = Records(path)
        node = _nodes(rec)
        tri, markers = _facets(rec, node.points, node.first_index, suffix == ".poly")
        holes, regions = _seeds(rec)
    points = node.points
    used = np.unique(tri)
    if len(used) < len(points):
        warnings.warn(f"{path}: {len(points) - len(used)} points lie on no face and are left out", stacklevel=3)
        renumber = np.full(len(points), -1, np.int64)
        renumber[used] = np.arange(len(used))
        points, tri = points[used], renumber[tri]
    rep = np.flatnonzero((tri[:, 0] == tri[:, 1]) | (tri[:, 1] == tri[:, 2]) | (tri[:, 2] == tri[:, 0]))
    if len(rep):
        raise FormatError(f"{path}: face {rep[0]} repeats a corner")
    try:
        multi = bool(np.any(EdgeGroups(tri, len(points)).count > 2))
        return Surface(points, tri, markers, holes, regions, multi)
    except InputError as exc:
        raise FormatError(f"{path}: {exc}") from exc


def write_smesh(surface: Surface, path) -> Path:
    """Write a surface as a TetGen ``.smesh`` file (points numbered from 0, 17 digits).

    Parameters
    ----------
    surface : Surface
    path : str or Path

    Returns
    -------
    Path

    Raises
    ------
    InputError
        ``surface`` not a Surface.
    FormatError
        The file cannot be written.
    """
    if not isinstance(surface, Surface):
        raise InputError(f"write_smesh needs a Surface, got {type(surface).__name__}")
    path = Path(path)
    lines = [f"# points: index x y z\n{surface.n_points} 3 0 0"]
    lines += [f"{i} {x:.17g} {y:.17g} {z:.17g}" for i, (x, y, z) in enumerate(surface.points)]
    lines.append(f"# facets: #corners corners marker\n{surface.n_faces} 1")
    lines += [f"3 {a} {b} {c} {m}" for (a, b, c), m in zip(surface.triangles, surface.markers)]
    lines.append(f"# holes\n{len(surface.holes)}")
    lines += [f"{i} {x:.17g} {y:.17g} {z:.17g}" for i, (x, y, z) in enumerate(surface.holes)]
    lines.append(f"# regions: index x y z region max_volume\n{len(surface.regions)}")
    lines += [f"{i} {r[0]:.17g} {r[1]:.17g} {r[2]:.17g} {int(r[3])} {r[4]:.17g}" for i, r in enumerate(surface.regions)]
    try:
        path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    except OSError as exc:
        raise FormatError(f"{path}: cannot write ({exc.strerror or exc})") from exc
    return path
