"""Internal passes of tetrahedralize checked against plain-Python oracles.

* exterior depths (tet/exterior.py): a 0-1 breadth-first search over single tets (barrier
  faces cost 1, the outside reaches hull faces), written here without the component graph;
* the subfaces an encroachment record names (tet/mesher.py): a dict of sorted vertex triples.
"""

from collections import deque

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from meshwright.tet.exterior import components, depths
from meshwright.tet.mesher import _subfaces_of


def _random_adjacency(rng, nt: int, pairs: int):
    """(nt, 4) int32 neighbours pairing random half-faces (-1: hull), symmetric barrier flags."""
    nbr = np.full((nt, 4), -1, dtype=np.int32)
    barrier = np.zeros((nt, 4), dtype=bool)
    free = list(rng.permutation(4 * nt))
    for _ in range(min(pairs, len(free) // 2)):
        a, b = free.pop(), free.pop()
        ta, ka = divmod(int(a), 4)
        tb, kb = divmod(int(b), 4)
        if ta == tb:
            continue
        nbr[ta, ka], nbr[tb, kb] = tb, ta
        barrier[ta, ka] = barrier[tb, kb] = rng.random() < 0.3
    hull = nbr < 0
    barrier[hull] = rng.random(int(hull.sum())) < 0.5
    return nbr, barrier


def _oracle_depth(nbr, barrier):
    """Least barriers crossed from the outside to each tet (None: unreachable)."""
    nt = nbr.shape[0]
    # 0-1 BFS: hull faces seed their tets with cost 0 (no barrier) or 1 (a barrier)
    dist = [None] * nt
    seeds = sorted({(int(barrier[t, k]), t) for t in range(nt) for k in range(4) if nbr[t, k] < 0})
    queue = deque()
    best = {}
    for w, t in seeds:
        if t not in best or w < best[t]:
            best[t] = w
    for t, w in best.items():
        (queue.appendleft if w == 0 else queue.append)((w, t))
    while queue:
        w, t = queue.popleft()
        if dist[t] is not None:
            continue
        dist[t] = w
        for k in range(4):
            u = int(nbr[t, k])
            if u >= 0 and dist[u] is None:
                c = w + int(barrier[t, k])
                (queue.appendleft if c == w else queue.append)((c, u))
    return dist


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 40), st.floats(0.2, 2.5))
def test_depths_match_a_tet_level_search(seed, nt, fill):
    rng = np.random.default_rng(seed)
    nbr, barrier = _random_adjacency(rng, nt, int(fill * nt))
    comp, count = components(nbr, barrier)
    depth = depths(nbr, barrier, comp, count)
    want = _oracle_depth(nbr, barrier)
    unset = np.iinfo(np.int64).max // 2
    for t in range(nt):
        assert depth[comp[t]] == (unset if want[t] is None else want[t])


@pytest.mark.parametrize("n", [50, 3_000_000])
def test_subfaces_of_finds_each_record(n):
    rng = np.random.default_rng(n)
    tri = np.unique(np.sort(rng.integers(0, n, (600, 3)), axis=1), axis=0)
    tri = tri[(tri[:, 0] != tri[:, 1]) & (tri[:, 1] != tri[:, 2])][:400]
    faces = tri[rng.permutation(len(tri))][:, [2, 0, 1]].astype(np.int32)
    pick = rng.choice(len(faces), 40, replace=False)
    rows = np.array([rng.permutation(f) for f in faces[pick]] + [[n - 1, n - 2, n - 3]] * 3)
    enc = np.concatenate([rows, rng.integers(0, 3, (len(rows), 1))], axis=1).astype(np.int32)
    index = {tuple(sorted(f)): i for i, f in enumerate(faces.tolist())}
    want = [(index[tuple(sorted(r[:3]))], r[3]) for r in enc.tolist() if tuple(sorted(r[:3])) in index]
    got, why = _subfaces_of(faces, enc)
    assert list(zip(got.tolist(), why.tolist())) == want
    empty = _subfaces_of(faces, np.zeros((0, 4), dtype=np.int32))
    assert empty[0].size == 0 and empty[1].size == 0
