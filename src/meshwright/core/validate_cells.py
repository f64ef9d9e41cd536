"""Facet matching and the conformity checks of :meth:`meshwright.core.mesh.Mesh.validate`.

The cell tables of the data model (vertices per cell, dimension, outward facets, edges) and
the checks that pair facets: cells sharing a facet must traverse it in opposite directions
and no facet may have more than two cells (conformity), the mesh must have a boundary and a
positive measure, and lower-dimensional cells must be facets or edges of the elements
(embedding).  Facets are grouped by vertex set once per :meth:`~meshwright.core.mesh.Mesh.validate`
call and the grouping is shared between the checks (``shared``): NumPy's stable sort of one
integer key per sorted row below :data:`_KERNEL_MIN` rows, distribution counting on the
smallest vertex above (Knuth, TAOCP vol. 3, 1973, 5.2; :mod:`meshwright.core.facet_sort`),
which gives the same order, so every message names the same cells on both paths.

Arrays: facets ``(f, k)`` int64 of vertex ids in ``[0, n_points)``, row ``nf * c + j`` =
facet j of cell c (``nf`` facets per cell); ``order``, ``group`` ``(f,)`` int64 as
:func:`_sort_groups` returns them.  Messages name cell type, index and vertices
(:func:`_fmt_cell`) and coordinates (:func:`_fmt_point`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from meshwright.core.errors import ValidationError

if TYPE_CHECKING:
    from meshwright.core.mesh import Mesh

__all__ = ["CELL_DIMS", "CELL_NODES", "boundary_facets"]

# Vertices per cell and topological dimension of every supported cell type.
CELL_NODES = {"vertex": 1, "line": 2, "triangle": 3, "quad": 4, "tetra": 4, "hexahedron": 8}
CELL_DIMS = {"vertex": 0, "line": 1, "triangle": 2, "quad": 2, "tetra": 3, "hexahedron": 3}

# Outward-oriented facets (local vertex indices).  Triangle facet k is the edge opposite
# vertex k (ARCHITECTURE.md: from vertex k+1 to vertex k+2); tetra facet k is the face
# opposite vertex k.
_FACETS = {
    "triangle": np.array([[1, 2], [2, 0], [0, 1]]),
    "quad": np.array([[0, 1], [1, 2], [2, 3], [3, 0]]),
    "tetra": np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]]),
    "hexahedron": np.array(
        [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]
    ),
}
# Undirected edges, used to check that line cells lie on edges of the elements.
_EDGES = {
    "triangle": _FACETS["triangle"],
    "quad": _FACETS["quad"],
    "tetra": np.array([[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]]),
    "hexahedron": np.array(
        [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4], [0, 4], [1, 5], [2, 6], [3, 7]]
    ),
}

_FACET_NAMES = {2: "edge", 3: "face", 4: "face"}


def _fmt_point(p: np.ndarray) -> str:
    return "(" + ", ".join(repr(float(x)) for x in p) + ")"


def _fmt_cell(cell_type: str, index: int, vertices: np.ndarray) -> str:
    return f"{cell_type} {index} (vertices {', '.join(str(int(v)) for v in vertices)})"


def _top_types(mesh: Mesh) -> list[str]:
    """Non-empty cell types of the highest topological dimension >= 2 (empty if none)."""
    present = [t for t, c in mesh.cells.items() if len(c) and CELL_DIMS[t] >= 2]
    if not present:
        return []
    top = max(CELL_DIMS[t] for t in present)
    return [t for t in present if CELL_DIMS[t] == top]


def _facet_orientation(facets: np.ndarray) -> np.ndarray:
    """Return a boolean code per facet; two facets on the same vertex set traverse it in
    opposite directions exactly when their codes differ.

    Parameters
    ----------
    facets : (f, k) int, k >= 2

    Returns
    -------
    (f,) bool
    """
    if facets.shape[1] == 2:
        return facets[:, 0] < facets[:, 1]
    # Rotate the smallest vertex to the front; the direction is whether its successor
    # is smaller than its predecessor (invariant under rotation, flips under reversal).
    k = facets.shape[1]
    rows = np.arange(len(facets))
    first = np.argmin(facets, axis=1)
    return facets[rows, (first + 1) % k] < facets[rows, (first - 1) % k]


def _sort_groups(keys: np.ndarray, n_points: int) -> tuple[np.ndarray, np.ndarray]:
    """Sort rows of ``keys`` so that equal rows are adjacent.

    Parameters
    ----------
    keys : (f, k) int64, each row sorted
    n_points : int
        Upper bound of the vertex indices.

    Returns
    -------
    order : (f,) int64
        Permutation putting equal rows next to each other.
    group : (f,) int64
        Group number of sorted position i (equal rows share a number, 0-based).
    """
    f, k = keys.shape
    if f == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    base = max(int(n_points), 1)
    if base**k < 2**62:
        # One int64 per row: a single argsort beats a k-column lexsort.
        code = keys @ (base ** np.arange(k - 1, -1, -1, dtype=np.int64))
        order = np.argsort(code, kind="stable")
        new = np.diff(code[order]) != 0
    else:
        order = np.lexsort(keys.T[::-1])
        new = np.any(np.diff(keys[order], axis=0) != 0, axis=1)
    group = np.concatenate([[0], np.cumsum(new)])
    return order, group


# Below this many rows NumPy's sort groups them (nothing to compile for small meshes); above
# it the counting sort of :mod:`meshwright.core.facet_sort`, which gives the same order.
_KERNEL_MIN = 1 << 15


class _Grouped(NamedTuple):
    """Rows grouped by vertex set: ``order``, ``group`` as :func:`_sort_groups` returns them,
    and ``lookup`` = (start, code) of :func:`meshwright.core.facet_sort.sort_facets` for
    membership queries, or None when NumPy sorted the rows."""

    order: np.ndarray
    group: np.ndarray
    lookup: tuple | None


def _group_rows(rows: np.ndarray, n_points: int) -> _Grouped:
    """Group the rows (f, k) int of vertex ids in ``[0, n_points)`` by vertex set."""
    f, k = rows.shape
    if f >= _KERNEL_MIN:
        from meshwright.core.facet_sort import fits, sort_facets

        if fits(n_points, k) and rows.min() >= 0 and rows.max() < n_points:
            order, group, start, code = sort_facets(rows, n_points)
            return _Grouped(order, group, (start, code))
    order, group = _sort_groups(np.sort(rows, axis=1).astype(np.int64), n_points)
    return _Grouped(order, group, None)


def _match_facets(facets: np.ndarray, n_points: int):
    """Pair facets that have the same vertex set.

    Parameters
    ----------
    facets : (f, k) int
        Vertex ids in ``[0, n_points)``.
    n_points : int

    Returns
    -------
    count : (f,) int64
        Number of facets (this one included) on the same vertex set.
    partner : (f,) int64
        The other facet of a pair, -1 when ``count != 2``.
    order, group : (f,) int64
        As returned by :func:`_sort_groups`, to list the members of a group.
    """
    count, partner, grouped = _match_grouped(facets, n_points)
    return count, partner, grouped.order, grouped.group


def _match_grouped(facets: np.ndarray, n_points: int):
    """:func:`_match_facets` with the :class:`_Grouped` record (its lookup answers later
    membership queries against these facets without sorting them again)."""
    grouped = _group_rows(facets, n_points)
    order, group = grouped.order, grouped.group
    if grouped.lookup is not None:
        from meshwright.core.facet_sort import counts_partners

        count, partner = counts_partners(order, group)
        return count, partner, grouped
    sizes = np.bincount(group) if len(group) else np.zeros(0, np.int64)
    count = np.empty(len(facets), np.int64)
    count[order] = sizes[group]
    partner = np.full(len(facets), -1, np.int64)
    # A group of two starts at a sorted position whose successor is in the same group.
    start = np.flatnonzero(np.diff(group, prepend=-1) != 0)
    pair = start[sizes[group[start]] == 2]
    partner[order[pair]] = order[pair + 1]
    partner[order[pair + 1]] = order[pair]
    return count, partner, grouped


def _raise_on_bad_pairs(facets, count, partner, order, group, describe) -> None:
    """Raise ValidationError for facets shared by more than two cells or by two cells
    traversing them in the same direction.  ``describe(f)`` names the owner of facet f."""
    kind = _FACET_NAMES[facets.shape[1]]
    over = np.flatnonzero(count > 2)
    if len(over):
        members = order[group == group[np.flatnonzero(order == over[0])[0]]]
        names = ", ".join(describe(f) for f in members)
        verts = ", ".join(str(int(v)) for v in np.sort(facets[over[0]]))
        raise ValidationError(f"{kind} ({verts}) is shared by {len(members)} cells: {names}")
    if len(facets) >= _KERNEL_MIN:
        from meshwright.core.facet_sort import first_same_direction

        first = first_same_direction(np.ascontiguousarray(facets), partner)
        same = [first] if first >= 0 else []
    else:
        code = _facet_orientation(facets)
        same = np.flatnonzero((partner >= 0) & (code == code[np.maximum(partner, 0)]))
    if len(same):
        f, g = same[0], partner[same[0]]
        verts = ", ".join(str(int(v)) for v in facets[f])
        raise ValidationError(
            f"{kind} ({verts}) is traversed in the same direction by {describe(f)} and "
            f"{describe(g)}: inconsistent orientation or overlapping cells"
        )


def _cell_facets(cells: np.ndarray, table: np.ndarray) -> np.ndarray:
    """Return the facets of every cell, row ``len(table) * c + j`` = facet j of cell c.

    Parameters
    ----------
    cells : (m, k) int
    table : (nf, kf) int, local vertex indices of the facets

    Returns
    -------
    (m * nf, kf) int64
    """
    # np.take along the rows, then widen: ``cells[:, table]`` comes out in Fortran-like
    # order and its reshape copied it again (106 -> 55 ms for 1e6 tets)
    return np.take(np.asarray(cells), table.ravel(), axis=1).reshape(-1, table.shape[1]).astype(np.int64)


def boundary_facets(mesh) -> np.ndarray:
    """The facets of ``mesh``'s highest-dimensional cells that belong to a single cell
    (:meth:`meshwright.core.mesh.Mesh.boundary_facets`), (b, k) int32."""
    top = _top_types(mesh)
    facets = [_cell_facets(mesh.cells[t], _FACETS[t]) for t in top]
    size = min((f.shape[1] for f in facets), default=2)
    facets = np.concatenate([f for f in facets if f.shape[1] == size] or [np.zeros((0, size), np.int64)])
    count = _match_facets(facets, mesh.n_points)[0]
    return facets[count == 1].astype(np.int32)


def _check_conformity(mesh: Mesh, top: list[str], shared: dict | None = None) -> None:
    """Conforming facets of the ``top`` cells, a boundary facet and a positive measure.

    ``shared`` (one :meth:`Mesh.validate` call's dict) receives, per facet size k, the
    facets, their counts and their :class:`_Grouped` record under ``("facets", k)``, so the
    later checks match against them instead of sorting the facets again.
    """
    per_size: dict[int, list] = {}
    for cell_type in top:
        facets = _cell_facets(mesh.cells[cell_type], _FACETS[cell_type])
        per_size.setdefault(facets.shape[1], []).append((cell_type, facets))
    n_boundary = 0
    for size, groups in per_size.items():
        facets = np.concatenate([f for _, f in groups])
        # Owner of every facet row: (cell type, cell index).
        owner_type = np.concatenate([np.full(len(f), i) for i, (_, f) in enumerate(groups)])
        offsets = np.concatenate([[0], np.cumsum([len(f) for _, f in groups])])
        nf = [len(_FACETS[t]) for t, _ in groups]

        def describe(f, groups=groups, owner_type=owner_type, offsets=offsets, nf=nf):
            i = owner_type[f]
            cell_type = groups[i][0]
            c = (f - offsets[i]) // nf[i]
            return _fmt_cell(cell_type, c, mesh.cells[cell_type][c])

        count, partner, grouped = _match_grouped(facets, mesh.n_points)
        _raise_on_bad_pairs(facets, count, partner, grouped.order, grouped.group, describe)
        n_boundary += int(np.count_nonzero(count == 1))
        if shared is not None:
            shared[("facets", size)] = (facets, count, grouped)
    if CELL_DIMS[top[0]] != mesh.dim:
        return  # a surface in 3-D may be closed and has no signed measure
    word = "edge" if mesh.dim == 2 else "face"
    if n_boundary == 0:
        raise ValidationError(f"mesh has no boundary {word}: a bounded {mesh.dim}-D mesh must have one")
    if mesh.dim == 3 and top == ["tetra"] and shared is not None:
        # the tets' volume terms once, for this check and the enclosed-volume balance
        from meshwright.core.validate3d import tet_volume_terms

        shared["tet_volume"] = tet_volume_terms(mesh.points, mesh.tetra)
        total = shared["tet_volume"][0]
    else:
        total = mesh.area() if mesh.dim == 2 else mesh.volume()
    if not total > 0.0:
        raise ValidationError(f"total {'area' if mesh.dim == 2 else 'volume'} {total!r} is not positive")


def _rows_in(query: np.ndarray, table: np.ndarray, n_points: int) -> np.ndarray:
    """For each row of ``query`` (q, k), whether its vertex set is a row of ``table`` (t, k).

    Returns
    -------
    (q,) bool
    """
    keys = np.concatenate([table, query]).astype(np.int64)
    grouped = _group_rows(keys, n_points)
    order, group = grouped.order, grouped.group
    in_table = np.zeros(group[-1] + 1 if len(group) else 0, dtype=bool)
    in_table[group[order < len(table)]] = True
    found = np.empty(len(keys), dtype=bool)
    found[order] = in_table[group]
    return found[len(table) :]


def _check_embedded(mesh: Mesh, top: list[str], shared: dict | None = None) -> None:
    """Lower-dimensional cells must be edges / faces of the elements.

    Facets that :func:`_check_conformity` grouped (``shared``) answer the queries without
    another sort; the elements' edges of a volume mesh are built only when it has lines.
    """
    top_dim = CELL_DIMS[top[0]]
    for cell_type in ("line", "triangle", "quad"):
        block = mesh.cells_of(cell_type)
        if not len(block) or CELL_DIMS[cell_type] >= top_dim:
            continue
        k = CELL_NODES[cell_type]
        if cell_type == "line" and top_dim == 3:
            table = np.concatenate([_cell_facets(mesh.cells[t], _EDGES[t]) for t in top])
        elif top_dim == 3 and {"triangle": "tetra", "quad": "hexahedron"}[cell_type] not in top:
            table = np.zeros((0, k), np.int64)
        else:
            # the facets of size k: the 2-D elements' edges, the tets' or hexahedra's faces
            table = None
        found = None
        if table is None and shared is not None and ("facets", k) in shared:
            facets, _, grouped = shared[("facets", k)]
            if grouped.lookup is not None:
                from meshwright.core.facet_sort import rows_found

                found = rows_found(*grouped.lookup, block)
            table = facets
        if table is None:
            table = np.concatenate([_cell_facets(mesh.cells[t], _FACETS[t]) for t in top if _FACETS[t].shape[1] == k])
        if found is None:
            found = _rows_in(block, table, mesh.n_points)
        missing = np.flatnonzero(~found)
        if len(missing):
            c = int(missing[0])
            what = "an edge" if cell_type == "line" else "a face"
            raise ValidationError(
                f"{_fmt_cell(cell_type, c, block[c])} is not {what} of any {'/'.join(top)} cell "
                f"({len(missing)} such {cell_type} cells)"
            )
