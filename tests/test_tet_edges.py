"""recovery.unique_edges (a counting-sort kernel): the undirected edges of a triangle list in
increasing (low, high) order and each face's edge ids, against sorted Python sets."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from meshwright.tet.recovery import unique_edges


def oracle(faces):
    pairs = sorted({tuple(sorted((int(f[(k + 1) % 3]), int(f[(k + 2) % 3])))) for f in faces for k in range(3)})
    index = {p: i for i, p in enumerate(pairs)}
    ids = [[index[tuple(sorted((int(f[(k + 1) % 3]), int(f[(k + 2) % 3]))))] for k in range(3)] for f in faces]
    return pairs, ids


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(*[st.integers(0, 30)] * 3), min_size=1, max_size=40))
def test_edges_and_face_edges_match_sorted_sets(rows):
    faces = np.array(rows, dtype=np.int32)
    edges, face_edges = unique_edges(faces)
    pairs, ids = oracle(rows)
    assert edges.dtype == np.int32 and face_edges.dtype == np.int64
    assert [tuple(e) for e in edges.tolist()] == pairs
    assert face_edges.tolist() == ids


def test_no_faces():
    edges, face_edges = unique_edges(np.zeros((0, 3), dtype=np.int32))
    assert edges.shape == (0, 2) and face_edges.shape == (0, 3)
