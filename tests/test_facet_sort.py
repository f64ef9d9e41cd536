"""The counting sort of facets (core/facet_sort.py) and Mesh.validate on its path.

Oracles: Python's ``sorted`` over vertex tuples and sets of frozensets (no NumPy sort, no
shared code); the validation messages of the NumPy path for the same broken meshes.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import meshwright.core.mesh as core_mesh
import meshwright.core.validate_cells as core_cells
from meshwright.core.errors import ValidationError
from meshwright.core.facet_sort import (
    counts_partners,
    first_same_direction,
    fits,
    rows_found,
    sort_facets,
)
from meshwright.core.mesh import Mesh

rows_strategy = st.integers(2, 4).flatmap(
    lambda k: st.tuples(
        st.just(k),
        st.integers(1, 12).flatmap(
            lambda n: st.tuples(st.just(n), st.lists(st.lists(st.integers(0, n - 1), min_size=k, max_size=k), max_size=300))
        ),
    )
)


@settings(max_examples=150, deadline=None)
@given(rows_strategy)
def test_sort_facets_against_sorted_tuples(case):
    k, (n, rows) = case
    facets = np.array(rows, dtype=np.int64).reshape(-1, k)
    order, group, start, code = sort_facets(facets, n)
    key = [tuple(sorted(r)) for r in rows]
    # the stable lexicographic order of the sorted rows, ties by index
    assert order.tolist() == sorted(range(len(rows)), key=lambda i: (key[i], i))
    expect_group = []
    for p, i in enumerate(order.tolist()):
        expect_group.append(0 if p == 0 else expect_group[-1] + (key[i] != key[order[p - 1]]))
    assert group.tolist() == expect_group
    assert start.tolist() == [sum(1 for t in key if t[0] < v) for v in range(n + 1)]
    count, partner = counts_partners(order, group)
    for i, t in enumerate(key):
        same = [j for j, u in enumerate(key) if u == t]
        assert count[i] == len(same)
        assert partner[i] == (next(j for j in same if j != i) if len(same) == 2 else -1)
    queries = rows + [[n] * k, [-1] + [0] * (k - 1), list(range(k))]
    found = rows_found(start, code, np.array(queries, dtype=np.int64))
    assert found.tolist() == [tuple(sorted(q)) in set(key) for q in queries]


def _direction(row):
    """Orientation code of a cyclic vertex sequence (oracle: rotate the smallest first)."""
    if len(row) == 2:
        return row[0] < row[1]
    i = row.index(min(row))
    return row[(i + 1) % len(row)] < row[i - 1]


@settings(max_examples=100, deadline=None)
@given(st.integers(2, 4), st.lists(st.permutations(range(6)), min_size=1, max_size=60))
def test_first_same_direction(k, perms):
    rows = [list(p[:k]) for p in perms]
    key = [tuple(sorted(r)) for r in rows]
    facets = np.array(rows, dtype=np.int64)
    order, group, _, _ = sort_facets(facets, 6)
    _, partner = counts_partners(order, group)
    expect = -1
    for i in range(len(rows)):
        same = [j for j in range(len(rows)) if key[j] == key[i] and j != i]
        if len(same) == 1 and _direction(rows[i]) == _direction(rows[same[0]]):
            expect = i
            break
    assert first_same_direction(facets, partner) == expect


def test_out_of_range_and_fits():
    with pytest.raises(ValueError):
        sort_facets(np.array([[0, 5, 1]]), 5)
    assert fits(10**6, 4) and not fits(3 * 10**6, 4) and fits(10**9, 3)


def _cube_tets(n):
    """An n^3 grid of cubes, six positive tets each: (points, tets)."""
    g = np.arange(n + 1)
    pts = np.stack(np.meshgrid(g, g, g, indexing="ij"), axis=-1).reshape(-1, 3).astype(float)
    idx = np.arange((n + 1) ** 3).reshape(n + 1, n + 1, n + 1)
    c = np.stack([idx[:-1, :-1, :-1], idx[1:, :-1, :-1], idx[1:, 1:, :-1], idx[:-1, 1:, :-1],
                  idx[:-1, :-1, 1:], idx[1:, :-1, 1:], idx[1:, 1:, 1:], idx[:-1, 1:, 1:]], axis=-1).reshape(-1, 8)
    tets = c[:, core_mesh._HEX_TETS].reshape(-1, 4)
    p = pts[tets]
    vol = np.einsum("mi,mi->m", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0]))
    tets[vol < 0, 0], tets[vol < 0, 1] = tets[vol < 0, 1], tets[vol < 0, 0].copy()
    return pts, tets


def _message(mesh):
    try:
        mesh.validate()
    except ValidationError as exc:
        return str(exc)
    return None


@pytest.mark.parametrize("defect", ["none", "triple", "direction", "loose face", "line", "2-D line", "2-D direction"])
def test_validate_same_result_on_both_paths(monkeypatch, defect):
    pts, tets = _cube_tets(3)
    faces = Mesh(pts, {"tetra": tets}).boundary_facets()
    cells = {"tetra": tets, "triangle": faces}
    if defect == "triple":
        cells["tetra"] = np.vstack([tets, tets[5:6]])  # a copy: its faces in three cells
    elif defect == "direction":
        pts, cells = np.vstack([np.zeros(3), np.eye(3)]), {"tetra": np.array([[0, 1, 2, 3], [0, 1, 2, 3]])}
    elif defect == "loose face":
        cells["triangle"] = np.vstack([faces, [[0, 1, 60]]])
    elif defect == "line":
        cells["line"] = np.array([[0, 1], [0, 2]])  # (0, 2) spans two cubes: no tet's edge
    elif defect.startswith("2-D"):
        pts = pts[pts[:, 2] == 0, :2]  # the 4 x 4 grid of the bottom plane, ids 0, 4, 8, ...
        g = np.arange(16).reshape(4, 4)
        a, b, c, d = g[:-1, :-1].ravel(), g[1:, :-1].ravel(), g[1:, 1:].ravel(), g[:-1, 1:].ravel()
        tri = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
        cells = {"triangle": tri, "line": np.array([[0, 4], [1, 4]]) if defect == "2-D line" else np.zeros((0, 2), int)}
        if defect == "2-D direction":
            cells["triangle"] = np.vstack([tri, tri[:1]])
    mesh = Mesh(pts, cells)
    numpy_path = _message(mesh)
    monkeypatch.setattr(core_cells, "_KERNEL_MIN", 1)
    assert _message(mesh) == numpy_path
    assert (numpy_path is None) == (defect == "none"), numpy_path
