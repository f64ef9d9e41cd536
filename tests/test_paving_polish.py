"""The paving polish's vertex-to-quad table (``_paving_polish.vertex_cells``, a counting
sort) against a plain loop over the quads' corners."""

from __future__ import annotations

import numpy as np

from meshwright.quad._paving_polish import vertex_cells


def test_vertex_cells_lists_each_vertex_quads_ascending_once_per_corner():
    rng = np.random.default_rng(5)
    for n, m in ((1, 0), (7, 3), (50, 200)):
        q = rng.integers(0, n, size=(m, 4)).astype(np.int64)
        ptr, idx = vertex_cells(q, n)
        want = [[c for c in range(m) for k in range(4) if q[c, k] == v] for v in range(n)]
        assert ptr[0] == 0 and len(ptr) == n + 1 and len(idx) == 4 * m
        assert [idx[ptr[v] : ptr[v + 1]].tolist() for v in range(n)] == want
