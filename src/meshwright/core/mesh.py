"""The :class:`Mesh` data model every meshing layer produces, with validation and neighbours.

A mesh is points plus meshio-style cell blocks::

    points      (n, d) float64, C-contiguous, d in {2, 3}
    cells       {"triangle": (m, 3) int32, "line": (b, 2) int32, ...}
    point_data  {name: (n, ...) array}
    cell_data   {name: {cell_type: (m, ...) array}}

Fixed data names (the I/O layer maps them to each file format's convention):

* ``cell_data["marker"][cell_type]`` (m,) int32: boundary markers on ``"line"`` cells
  (``"triangle"``/``"quad"`` faces of a 3-D mesh), region markers on the elements of the
  mesh dimension; 0 means "no marker" (Triangle's convention).
* ``point_data["marker"]`` (n,) int32: boundary markers of points (Triangle ``.node``).
* ``point_data["attributes"]`` (n, a) float64 and ``cell_data["attributes"][cell_type]``
  (m, a) float64: Triangle node and element attributes that are not markers.

Orientation conventions: triangles and quads counter-clockwise in 2-D; tetrahedra and
hexahedra with positive volume (``orient3d > 0``, VTK/meshio vertex order).  The facet
tables below list the facets of each cell type oriented outwards, so two cells sharing
a facet traverse it in opposite directions.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from meshwright.core.errors import InputError, ValidationError
from meshwright.core.quality import QUALITY_FUNCTIONS, QualityReport
from meshwright.core.validate_cells import (
    _FACET_NAMES,
    _FACETS,
    CELL_DIMS,
    CELL_NODES,
    _cell_facets,
    _check_conformity,
    _check_embedded,
    _fmt_cell,
    _fmt_point,
    _match_facets,
    _raise_on_bad_pairs,
    _rows_in,
    _top_types,
)
from meshwright.core.validate_cells import boundary_facets as _boundary_facets

__all__ = [
    "Mesh",
    "CELL_NODES",
    "CELL_DIMS",
    "build_neighbors",
    "build_neighbors_tet",
    "check_neighbors",
]

# Corner triangles of a quad: both diagonal splits.  All four positive <=> the quad is
# strictly convex and counter-clockwise, i.e. its bilinear map has a positive Jacobian.
_QUAD_CORNERS = np.array([[3, 0, 1], [0, 1, 2], [1, 2, 3], [2, 3, 0]])
# Corner tetrahedra of a hexahedron (a corner and its three neighbours, right-handed).
_HEX_CORNERS = np.array(
    [[0, 1, 3, 4], [1, 2, 0, 5], [2, 3, 1, 6], [3, 0, 2, 7], [4, 7, 5, 0], [5, 4, 6, 1], [6, 5, 7, 2], [7, 6, 4, 3]]
)
# Six positive tetrahedra around the diagonal 0-6 that tile a hexahedron (volume).
_HEX_TETS = np.array([[0, 1, 2, 6], [0, 2, 3, 6], [0, 3, 7, 6], [0, 7, 4, 6], [0, 4, 5, 6], [0, 5, 1, 6]])


# ----------------------------------------------------------------------------- facets


def _neighbors_from_facets(cells: np.ndarray, cell_type: str) -> np.ndarray:
    cells = np.asarray(cells)
    table = _FACETS[cell_type]
    nf = len(table)
    if cells.ndim != 2 or cells.shape[1] != CELL_NODES[cell_type]:
        raise InputError(f"{cell_type} cells must have shape (m, {CELL_NODES[cell_type]}), got {cells.shape}")
    facets = _cell_facets(cells, table)
    n = int(cells.max()) + 1 if cells.size else 0
    count, partner, order, group = _match_facets(facets, n)

    def describe(f):
        return _fmt_cell(cell_type, f // nf, cells[f // nf])

    _raise_on_bad_pairs(facets, count, partner, order, group, describe)
    nbr = np.where(partner >= 0, partner // nf, -1)
    return nbr.reshape(-1, nf).astype(np.int32)


def build_neighbors(triangles: np.ndarray) -> np.ndarray:
    """Return the neighbour across each edge of counter-clockwise triangles.

    Parameters
    ----------
    triangles : (m, 3) int
        Vertex indices, counter-clockwise.

    Returns
    -------
    (m, 3) int32
        ``nbr[t, k]`` is the triangle across the edge opposite vertex k of triangle t,
        -1 on the boundary.

    Raises
    ------
    ValidationError
        An edge shared by more than two triangles, or by two triangles traversing it in
        the same direction (inconsistent orientation); the message names both.
    """
    return _neighbors_from_facets(triangles, "triangle")


def build_neighbors_tet(tets: np.ndarray) -> np.ndarray:
    """Return the neighbour across each face of positively oriented tetrahedra.

    Parameters
    ----------
    tets : (m, 4) int
        Vertex indices with ``orient3d > 0``.

    Returns
    -------
    (m, 4) int32
        ``nbr[t, k]`` is the tetrahedron across the face opposite vertex k, -1 on the
        boundary.

    Raises
    ------
    ValidationError
        A face shared by more than two tetrahedra or with inconsistent orientation.
    """
    return _neighbors_from_facets(tets, "tetra")


def check_neighbors(cells: np.ndarray, neighbors: np.ndarray) -> None:
    """Check that a neighbour table is symmetric and matches the shared facets.

    For every ``u = neighbors[t, k] >= 0``: ``u`` is a valid cell, ``t`` appears exactly
    once in ``neighbors[u]``, say at ``j``, and the facet opposite vertex k of t has the
    same vertices as the facet opposite vertex j of u.

    Parameters
    ----------
    cells : (m, 3) or (m, 4) int
        Triangles or tetrahedra.
    neighbors : (m, 3) or (m, 4) int
        As returned by :func:`build_neighbors` / :func:`build_neighbors_tet`.

    Raises
    ------
    ValidationError
        Naming the first cell, slot and neighbour at fault.
    """
    cells = np.asarray(cells, dtype=np.int64)
    nbr = np.asarray(neighbors, dtype=np.int64)
    if cells.ndim != 2 or cells.shape[1] not in (3, 4) or nbr.shape != cells.shape:
        raise InputError(f"cells {cells.shape} and neighbors {nbr.shape} must both be (m, 3) or (m, 4)")
    m, k = cells.shape
    cell_type = "triangle" if k == 3 else "tetra"
    bad = np.flatnonzero((nbr.ravel() < -1) | (nbr.ravel() >= m))
    if len(bad):
        t, s = divmod(int(bad[0]), k)
        raise ValidationError(f"{cell_type} {t} slot {s}: neighbour {nbr[t, s]} is not a cell index or -1")
    idx = np.flatnonzero(nbr.ravel() >= 0)
    t, s = idx // k, idx % k
    u = nbr[t, s]
    back = nbr[u] == t[:, None]
    j = np.argmax(back, axis=1)
    table = _FACETS[cell_type]
    mine = np.sort(cells[t[:, None], table[s]], axis=1)
    theirs = np.sort(cells[u[:, None], table[j]], axis=1)
    wrong = np.flatnonzero((back.sum(axis=1) != 1) | np.any(mine != theirs, axis=1))
    if len(wrong):
        w = wrong[0]
        raise ValidationError(
            f"{cell_type} {t[w]} slot {s[w]} points to {cell_type} {u[w]}, which does not point back "
            f"exactly once across the same {_FACET_NAMES[table.shape[1]]} (vertices "
            f"{', '.join(str(int(v)) for v in mine[w])})"
        )


# ------------------------------------------------------------------------ measures


def _signed_measure(points: np.ndarray, cell_type: str, cells: np.ndarray) -> np.ndarray:
    """Signed area (2-D cells) or volume (3-D cells) of every cell, (m,) float64.

    Triangles and quads of a 3-D point set are surface cells: their area is unsigned.
    """
    p = points[np.asarray(cells, dtype=np.int64)]
    if cell_type in ("triangle", "quad"):
        # Shoelace on the diagonals (the triangle's second "diagonal" degenerates to an edge).
        d1 = p[:, 2] - p[:, 0]
        d2 = (p[:, 3] if cell_type == "quad" else p[:, 0]) - p[:, 1]
        if points.shape[1] == 2:
            return 0.5 * (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])
        return 0.5 * np.linalg.norm(np.cross(d1, d2), axis=1)
    if cell_type == "tetra":
        return np.linalg.det(p[:, 1:] - p[:, :1]) / 6.0
    if cell_type == "hexahedron":
        q = p[:, _HEX_TETS]  # (m, 6, 4, 3)
        return np.linalg.det(q[:, :, 1:] - q[:, :, :1]).sum(axis=1) / 6.0
    return np.zeros(len(cells))


# ---------------------------------------------------------------------- the class


class Mesh:
    """Points and meshio-style cell blocks, with optional point and cell data.

    Parameters
    ----------
    points : (n, d) array_like of float, d in {2, 3}
        Stored as C-contiguous float64 (no copy when already so).
    cells : dict of str to (m, k) array_like of int, or iterable of (str, array) pairs
        Cell type (``"vertex"``, ``"line"``, ``"triangle"``, ``"quad"``, ``"tetra"``,
        ``"hexahedron"``) to vertex indices; stored as C-contiguous int32.
    point_data : dict of str to (n, ...) array_like, optional
    cell_data : dict of str to dict of str to (m, ...) array_like, optional
        ``cell_data[name][cell_type]``, one entry per cell of that block; a name need not
        cover every block.  ``cell_data["marker"]`` holds boundary / region markers.

    Raises
    ------
    InputError
        Wrong shapes or dtypes, non-finite coordinates, an index out of range, data of
        the wrong length; the message names the block, cell and vertex at fault.
    """

    def __init__(self, points, cells=None, point_data=None, cell_data=None):
        self.points = _coerce_points(points)
        n = len(self.points)
        self.cells = _coerce_cells(cells, n, self.points.shape[1])
        self.point_data = {}
        for name, values in (point_data or {}).items():
            values = np.asarray(values)
            if values.ndim == 0 or len(values) != n:
                raise InputError(f"point_data[{name!r}] has shape {values.shape}, expected ({n}, ...)")
            self.point_data[name] = values
        self.cell_data = {}
        for name, blocks in (cell_data or {}).items():
            if not isinstance(blocks, Mapping):
                raise InputError(f"cell_data[{name!r}] must be a dict of cell type to array")
            self.cell_data[name] = {}
            for cell_type, values in blocks.items():
                if cell_type not in self.cells:
                    raise InputError(f"cell_data[{name!r}] has a {cell_type!r} entry but the mesh has no such cells")
                values = np.asarray(values)
                m = len(self.cells[cell_type])
                if values.ndim == 0 or len(values) != m:
                    raise InputError(
                        f"cell_data[{name!r}][{cell_type!r}] has shape {values.shape}, expected ({m}, ...)"
                    )
                self.cell_data[name][cell_type] = values

    # ------------------------------------------------------------------ accessors
    @property
    def dim(self) -> int:
        """Spatial dimension d of the points (2 or 3)."""
        return self.points.shape[1]

    @property
    def n_points(self) -> int:
        """Number of points n."""
        return len(self.points)

    @property
    def n_cells(self) -> int:
        """Total number of cells over all blocks."""
        return sum(len(c) for c in self.cells.values())

    def cells_of(self, cell_type: str) -> np.ndarray:
        """Return the ``cell_type`` block, or an empty ``(0, k)`` int32 array if absent."""
        if cell_type not in CELL_NODES:
            raise InputError(f"unknown cell type {cell_type!r}; supported: {', '.join(CELL_NODES)}")
        block = self.cells.get(cell_type)
        return block if block is not None else np.zeros((0, CELL_NODES[cell_type]), np.int32)

    lines = property(lambda self: self.cells_of("line"), doc="(m, 2) int32 line cells.")
    triangles = property(lambda self: self.cells_of("triangle"), doc="(m, 3) int32 triangles.")
    quads = property(lambda self: self.cells_of("quad"), doc="(m, 4) int32 quadrilaterals.")
    tetra = property(lambda self: self.cells_of("tetra"), doc="(m, 4) int32 tetrahedra.")
    hexahedra = property(lambda self: self.cells_of("hexahedron"), doc="(m, 8) int32 hexahedra.")

    def __repr__(self) -> str:
        blocks = ", ".join(f"{k}: {len(v)}" for k, v in self.cells.items())
        text = f"Mesh(dim={self.dim}, n_points={self.n_points}, cells={{{blocks}}}"
        if self.point_data:
            text += f", point_data={sorted(self.point_data)}"
        if self.cell_data:
            text += f", cell_data={sorted(self.cell_data)}"
        return text + ")"

    # ------------------------------------------------------------------ measures
    def area(self) -> float:
        """Total signed area of the triangle and quad cells (unsigned for 3-D surfaces)."""
        return float(sum(_signed_measure(self.points, t, self.cells_of(t)).sum() for t in ("triangle", "quad")))

    def volume(self) -> float:
        """Total signed volume of the tetra and hexahedron cells (0 without any)."""
        return float(sum(_signed_measure(self.points, t, self.cells_of(t)).sum() for t in ("tetra", "hexahedron")))

    def quality(self) -> QualityReport:
        """Per-element quality of the non-empty triangle, quad and tetra blocks.

        Returns
        -------
        QualityReport
            ``report[cell_type][measure]`` (m,) float64; see :mod:`meshwright.core.quality`.
        """
        return QualityReport(
            {t: QUALITY_FUNCTIONS[t](self.points, c) for t, c in self.cells.items() if t in QUALITY_FUNCTIONS and len(c)}
        )

    def boundary_facets(self) -> np.ndarray:
        """Facets of the highest-dimensional cells that belong to a single cell.

        Returns
        -------
        (b, k) int32
            Boundary edges (2-D cells; counter-clockwise around the domain) or faces
            (3-D cells; oriented outwards).  Facets have one size per call: with both
            tetrahedra and hexahedra, only the triangular faces of the tetrahedra.
        """
        return _boundary_facets(self)

    # ----------------------------------------------------------------- validation
    def validate(self, check_delaunay: bool = False, allow_nonconvex: bool = False) -> None:
        """Raise :class:`ValidationError` on the first defect found; return None if valid.

        Checks, in order: every vertex used by a cell; no two vertices with identical
        coordinates; no cell repeating a vertex; positive orientation of every element
        of the space dimension (exact predicates; quads must be strictly convex, all
        eight corner tetrahedra of a hexahedron positive); conforming facets (no edge /
        face shared by more than two elements, shared ones traversed in opposite
        directions); at least one boundary facet and a positive total area / volume
        for elements of the space dimension; ``line`` cells (and triangles / quads of a
        volume mesh) lying on facets of the elements.  Meshes of lines only get the
        first three checks.

        Parameters
        ----------
        check_delaunay : bool
            Also require every interior edge of the triangles of a 2-D mesh to be locally
            Delaunay (exact ``incircle``; cocircular quadruples pass).  Interior edges
            that are ``line`` cells are constraints and exempt (constrained Delaunay).
            Tetrahedral meshes: every interior face (exact ``insphere``); tetrahedra
            also get the checks of :mod:`meshwright.core.validate3d` (closed manifold
            boundary, enclosed volume equal to the tets' volume).
        allow_nonconvex : bool
            Accept 2-D quads that are simple and counter-clockwise but not convex (see
            :mod:`meshwright.core.validate_quad`) instead of requiring a strictly
            positive Jacobian at every corner.

        Raises
        ------
        ValidationError
            Naming the first defect: cell type and index, vertex indices, coordinates.
        InputError
            ``check_delaunay`` on a mesh without 2-D triangles or tetrahedra.
        """
        if self.n_points == 0:
            raise ValidationError("mesh has no points")
        _check_used_vertices(self)
        _check_duplicate_points(self.points)
        for cell_type, block in self.cells.items():
            _check_repeated_vertices(cell_type, block)
        if not isinstance(allow_nonconvex, (bool, np.bool_)):
            raise InputError(f"allow_nonconvex must be True or False, got {allow_nonconvex!r}")
        top = _top_types(self)
        if top and CELL_DIMS[top[0]] == self.dim and allow_nonconvex and self.dim == 2:
            from meshwright.core.validate_quad import check_orientation_nonconvex

            check_orientation_nonconvex(self)
        elif top and CELL_DIMS[top[0]] == self.dim:
            _check_orientation(self)
        shared: dict = {}  # the facets grouped once, shared by the checks below
        if top:
            _check_conformity(self, top, shared)
            _check_embedded(self, top, shared)
        if self.dim == 3 and len(self.tetra):
            from meshwright.core.validate3d import check_tetra

            check_tetra(self, check_delaunay, shared)  # closed boundary, enclosed volume, Delaunay
        elif check_delaunay:
            _check_delaunay(self)

    # ----------------------------------------------------------------- delegation
    def write(self, path, file_format: str | None = None, **kwargs) -> None:
        """Write the mesh; see :func:`meshwright.io.write` (format from the extension)."""
        from meshwright.io import write

        write(self, path, file_format=file_format, **kwargs)

    def plot(self, ax=None, path=None, **kwargs):
        """Draw the mesh; see :func:`meshwright.plot.mesh_plot.plot_mesh`.  Returns the Axes."""
        from meshwright.plot.mesh_plot import plot_mesh

        return plot_mesh(self, ax=ax, path=path, **kwargs)


# -------------------------------------------------------------------- coercion


def _coerce_points(points) -> np.ndarray:
    try:
        arr = np.asarray(points, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"points cannot be converted to float64: {exc}") from exc
    if arr.ndim != 2 or arr.shape[1] not in (2, 3):
        raise InputError(f"points must have shape (n, 2) or (n, 3), got {arr.shape}")
    if not np.isfinite(arr).all():
        i = int(np.flatnonzero(~np.isfinite(arr).all(axis=1))[0])
        raise InputError(f"point {i} has a non-finite coordinate {_fmt_point(arr[i])}")
    return np.ascontiguousarray(arr)


def _coerce_cells(cells, n_points: int, dim: int) -> dict[str, np.ndarray]:
    pairs = cells.items() if isinstance(cells, Mapping) else (cells or ())
    out: dict[str, np.ndarray] = {}
    for pair in pairs:
        try:
            cell_type, block = pair
        except (TypeError, ValueError) as exc:
            raise InputError(f"cells must be a dict or (cell_type, array) pairs, got {pair!r}") from exc
        if cell_type not in CELL_NODES:
            raise InputError(f"unknown cell type {cell_type!r}; supported: {', '.join(CELL_NODES)}")
        if cell_type in out:
            raise InputError(f"cell type {cell_type!r} given twice; concatenate the blocks")
        k = CELL_NODES[cell_type]
        if CELL_DIMS[cell_type] > dim:
            raise InputError(f"{cell_type} cells need {CELL_DIMS[cell_type]}-D points, got {dim}-D")
        arr = np.asarray(block)
        if arr.size == 0:
            arr = np.zeros((0, k), np.int32)
        if not np.issubdtype(arr.dtype, np.integer):
            raise InputError(f"cells[{cell_type!r}] must hold integers, got dtype {arr.dtype}")
        if arr.ndim != 2 or arr.shape[1] != k:
            raise InputError(f"cells[{cell_type!r}] must have shape (m, {k}), got {arr.shape}")
        if arr.size and (arr.min() < 0 or arr.max() >= n_points):
            c = int(np.flatnonzero(((arr < 0) | (arr >= n_points)).any(axis=1))[0])
            raise InputError(
                f"{_fmt_cell(cell_type, c, arr[c])} references a vertex outside 0..{n_points - 1}"
            )
        out[cell_type] = np.ascontiguousarray(arr, dtype=np.int32)
    return out


# ------------------------------------------------------------------ validation steps


def _check_used_vertices(mesh: Mesh) -> None:
    used = np.zeros(mesh.n_points, dtype=bool)
    for block in mesh.cells.values():
        used[block.ravel()] = True
    unused = np.flatnonzero(~used)
    if len(unused):
        i = int(unused[0])
        raise ValidationError(
            f"vertex {i} at {_fmt_point(mesh.points[i])} is not used by any cell "
            f"({len(unused)} unused vertices in total)"
        )


def _check_duplicate_points(points: np.ndarray) -> None:
    order = np.lexsort(points.T[::-1])
    same = np.flatnonzero(np.all(points[order[1:]] == points[order[:-1]], axis=1))
    if len(same):
        i, j = sorted((int(order[same[0]]), int(order[same[0] + 1])))
        raise ValidationError(f"vertices {i} and {j} have identical coordinates {_fmt_point(points[i])}")


def _check_repeated_vertices(cell_type: str, block: np.ndarray) -> None:
    if block.shape[1] < 2:
        return
    s = np.sort(block, axis=1)
    bad = np.flatnonzero(np.any(s[:, 1:] == s[:, :-1], axis=1))
    if len(bad):
        c = int(bad[0])
        row = s[c]
        v = int(row[1:][row[1:] == row[:-1]][0])
        raise ValidationError(f"{_fmt_cell(cell_type, c, block[c])} repeats vertex {v}")


def _check_orientation(mesh: Mesh) -> None:
    """Exact orientation of every element of the space dimension (predicates imported here
    so that building a Mesh never compiles them)."""
    from meshwright.core.predicates import orient2d_batch, orient3d_batch

    points = mesh.points
    if mesh.dim == 2:
        checks = [("triangle", None, orient2d_batch), ("quad", _QUAD_CORNERS, orient2d_batch)]
        word = "area"
    else:
        checks = [("tetra", None, orient3d_batch), ("hexahedron", _HEX_CORNERS, orient3d_batch)]
        word = "volume"
    for cell_type, corners, batch in checks:
        block = mesh.cells_of(cell_type)
        if not len(block):
            continue
        simplices = block if corners is None else np.ascontiguousarray(block[:, corners].reshape(-1, corners.shape[1]))
        sign = np.asarray(batch(points, simplices)).reshape(len(block), -1)
        bad = np.flatnonzero(np.any(sign <= 0, axis=1))
        if len(bad):
            c = int(bad[0])
            what = "degenerate (zero" if np.all(sign[c] >= 0) else "inverted (negative"
            where = ", ".join(_fmt_point(points[v]) for v in block[c])
            detail = "" if corners is None else f" at corner {int(np.argmax(sign[c] <= 0))}"
            raise ValidationError(
                f"{_fmt_cell(cell_type, c, block[c])} at {where} is {what} {word}{detail}); "
                f"{len(bad)} such cells in total"
            )


# Shewchuk's static error bound of the floating-point incircle determinant:
# |det - exact| <= ICC_ERRBOUND * permanent (robust predicates paper, iccerrboundA).
_EPS = np.finfo(np.float64).eps / 2.0
_ICC_ERRBOUND = (10.0 + 96.0 * _EPS) * _EPS


def _check_delaunay(mesh: Mesh) -> None:
    """Every interior edge of the triangles that is not a ``line`` cell must be locally Delaunay.

    A vectorised floating-point determinant with Shewchuk's error bound decides most
    edges; only the undecided (near-cocircular) ones go to the exact ``incircle``.
    """
    tri = mesh.triangles
    if mesh.dim != 2 or not len(tri):
        raise InputError("check_delaunay needs a 2-D mesh with triangle cells")
    nbr = build_neighbors(tri)
    t, k = np.nonzero(nbr > np.arange(len(tri))[:, None])  # each interior edge once
    if len(mesh.lines):
        # Constrained Delaunay: an interior edge carried by a line cell is a constraint.
        edges = np.column_stack([tri[t, (k + 1) % 3], tri[t, (k + 2) % 3]])
        free = ~_rows_in(edges, mesh.lines, mesh.n_points)
        t, k = t[free], k[free]
    u = nbr[t, k].astype(np.int64)
    j = np.argmax(nbr[u] == t[:, None], axis=1)
    d = tri[u, j]  # vertex of u opposite the shared edge
    p = mesh.points
    a, b, c, q = p[tri[t, 0]], p[tri[t, 1]], p[tri[t, 2]], p[d]
    ad, bd, cd = a - q, b - q, c - q
    alift, blift, clift = (np.einsum("ij,ij->i", v, v) for v in (ad, bd, cd))
    bc = bd[:, 0] * cd[:, 1] - cd[:, 0] * bd[:, 1]
    ca = cd[:, 0] * ad[:, 1] - ad[:, 0] * cd[:, 1]
    ab = ad[:, 0] * bd[:, 1] - bd[:, 0] * ad[:, 1]
    det = alift * bc + blift * ca + clift * ab
    permanent = (
        alift * (np.abs(bd[:, 0] * cd[:, 1]) + np.abs(cd[:, 0] * bd[:, 1]))
        + blift * (np.abs(cd[:, 0] * ad[:, 1]) + np.abs(ad[:, 0] * cd[:, 1]))
        + clift * (np.abs(ad[:, 0] * bd[:, 1]) + np.abs(bd[:, 0] * ad[:, 1]))
    )
    bound = _ICC_ERRBOUND * permanent
    inside = det > bound
    undecided = np.flatnonzero(np.abs(det) <= bound)
    if len(undecided):
        from meshwright.core.predicates import incircle

        for e in undecided:
            inside[e] = incircle(*a[e], *b[e], *c[e], *q[e]) > 0
    bad = np.flatnonzero(inside)
    if len(bad):
        e = int(bad[0])
        raise ValidationError(
            f"edge ({tri[t[e], (k[e] + 1) % 3]}, {tri[t[e], (k[e] + 2) % 3]}) between "
            f"{_fmt_cell('triangle', int(t[e]), tri[t[e]])} and {_fmt_cell('triangle', int(u[e]), tri[u[e]])} "
            f"is not locally Delaunay: vertex {int(d[e])} at {_fmt_point(p[d[e]])} lies inside the circumcircle "
            f"({len(bad)} such edges)"
        )
