"""The quadtree of split boxes under the advancing front (core/spatial/cell_quadtree).

Oracle: brute-force closed-box comparisons in NumPy over every live item; the tree must
return exactly those items, each once, through interleaved insertions, lazy deletions and
queries, for boxes inside, across and outside the root square, points, touching edges and
the depth cap.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from meshwright.core.spatial.cell_quadtree import (
    Q_DEPTH,
    Q_NODES,
    Q_ROOM,
    STACK_PER_LEVEL,
    ct_insert,
    ct_new,
    ct_query,
)

coord = st.floats(-1.5, 2.0)
extent = st.one_of(st.just(0.0), st.floats(0.0, 1e-6), st.floats(0.0, 0.05), st.floats(0.0, 1.5))
box = st.tuples(coord, coord, extent, extent)
# An operation: insert a box, delete a live item (by rank), or query a box.
op = st.one_of(
    st.tuples(st.just("insert"), box),
    st.tuples(st.just("delete"), st.integers(0, 10**6)),
    st.tuples(st.just("query"), box),
)


class _Tree:
    def __init__(self, cap, finest):
        self.qgeo, self.qmeta, self.qchild, self.qhead = ct_new((0.0, 0.0, 1.0, 1.0), finest, nodes=8)
        self.qbox = np.empty((cap, 4))
        self.qcell = np.empty((cap, 2), dtype=np.int64)
        self.qnext = np.empty(4 * cap, dtype=np.int32)
        self.alive = np.zeros(cap, dtype=np.int8)
        self.n = 0
        rows = STACK_PER_LEVEL * (int(self.qmeta[Q_DEPTH]) + 2)
        self.stack = np.empty(rows, dtype=np.int64)
        self.fstack = np.empty((rows, 3))

    def insert(self, b):
        # The caller's room guarantee: qmeta[Q_ROOM] free nodes before every insertion.
        need = int(self.qmeta[Q_NODES]) + int(self.qmeta[Q_ROOM])
        if need > len(self.qhead):
            m = max(need, 2 * len(self.qhead))
            self.qhead = np.concatenate([self.qhead, np.full(m - len(self.qhead), -1, dtype=np.int32)])
            self.qchild = np.concatenate([self.qchild, np.full(4 * m - len(self.qchild), -1, dtype=np.int32)])
        i = self.n
        self.qbox[i] = b
        self.alive[i] = 1
        before = int(self.qmeta[Q_NODES])
        ct_insert(i, self.qgeo, self.qmeta, self.qchild, self.qhead, self.qnext, self.qcell, self.qbox)
        assert int(self.qmeta[Q_NODES]) - before <= int(self.qmeta[Q_ROOM])
        self.n += 1

    def query(self, x0, y0, x1, y1, cap):
        out = np.empty(cap, dtype=np.int32)
        k = ct_query(x0, y0, x1, y1, self.qgeo, self.qmeta, self.qchild, self.qhead, self.qnext, self.qcell,
                     self.qbox, self.alive, out, self.stack, self.fstack)
        return k, out[: min(k, cap)]


def _brute(qbox, alive, x0, y0, x1, y1):
    b = qbox
    hit = (b[:, 2] >= x0) & (b[:, 0] <= x1) & (b[:, 3] >= y0) & (b[:, 1] <= y1) & (alive == 1)
    return np.flatnonzero(hit).tolist()


@settings(deadline=None, max_examples=120)
@given(st.lists(op, min_size=1, max_size=120), st.sampled_from([1e-9, 1e-3, 0.05, 2.0]))
def test_query_matches_brute_force(ops, finest):
    t = _Tree(len(ops), finest)
    for kind, arg in ops:
        if kind == "insert":
            x, y, w, h = arg
            t.insert((x, y, x + w, y + h))
        elif kind == "delete":
            live = np.flatnonzero(t.alive[: t.n])
            if len(live):
                t.alive[live[arg % len(live)]] = 0
        else:
            x, y, w, h = arg
            k, got = t.query(x, y, x + w, y + h, t.n + 1)
            assert k == len(got)
            assert len(set(got.tolist())) == k  # each item once
            assert sorted(got.tolist()) == _brute(t.qbox[: t.n], t.alive[: t.n], x, y, x + w, y + h)


def test_touching_boxes_and_points_are_found():
    # Closed boxes: a query touching an item's edge or corner, or a point item on its border.
    t = _Tree(8, 1e-3)
    t.insert((0.25, 0.25, 0.5, 0.5))
    t.insert((0.5, 0.5, 0.5, 0.5))  # a point
    t.insert((0.75, 0.1, 0.8, 0.1))  # a horizontal segment's box
    k, got = t.query(0.5, 0.5, 0.6, 0.6, 8)
    assert sorted(got.tolist()) == [0, 1]
    k, got = t.query(0.0, 0.0, 0.25, 0.25, 8)
    assert got.tolist() == [0]
    k, got = t.query(0.8, 0.1, 0.9, 0.2, 8)
    assert got.tolist() == [2]


def test_many_items_in_one_finest_cell():
    # Items far below the finest cell share it; the exact comparison still tells them apart.
    t = _Tree(200, 0.1)
    rng = np.random.default_rng(3)
    pts = 0.5 + 1e-9 * rng.random((200, 2))
    for p in pts:
        t.insert((p[0], p[1], p[0], p[1]))
    cut = 0.5 + 0.5e-9
    k, got = t.query(0.0, 0.0, cut, 1.0, 201)
    assert sorted(got.tolist()) == np.flatnonzero(pts[:, 0] <= cut).tolist()


def test_reports_overflow():
    t = _Tree(10, 0.01)
    for i in range(10):
        t.insert((0.1 * i, 0.0, 0.1 * i + 0.05, 0.05))
    k, got = t.query(-1.0, -1.0, 2.0, 2.0, 3)
    assert k == 10 and len(got) == 3


def test_dead_entries_are_unlinked():
    # A deleted item's entries leave the lists the queries pass (lazy deletion), so later
    # queries do not scan them again.
    t = _Tree(64, 1e-3)
    for i in range(64):
        x = (i % 8) / 8.0
        y = (i // 8) / 8.0
        t.insert((x, y, x + 0.2, y + 0.2))
    t.alive[:] = 0
    t.query(-1.0, -1.0, 2.0, 2.0, 64)
    assert np.all(t.qhead[: int(t.qmeta[Q_NODES])] == -1)
