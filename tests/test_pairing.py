"""Quadrilaterals by pairing advancing-front triangles (issue 12, 18.5.1, Zhu et al. 1991).

Oracles never share code with what they check: convexity of every corner by exact
``Fraction`` cross products, scaled Jacobians recomputed corner by corner with ``math``,
boundary nodes against the circle's equation, parity by counting line cells per loop.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import meshwright as mw
from meshwright.core.errors import InputError, MeshingError
from meshwright.geometry import airfoil_in_farfield, circle, circles, naca_loop, polygon
from meshwright.quad import QUAD_METHODS, quadrangulate
from meshwright.quad import _enhance_kernel as ek
from meshwright.quad import _pairing_kernel as pk
from meshwright.quad.enhancement import enhance
from meshwright.quad.pairing import pair_domain, pair_triangles
from meshwright.quad.parity import ParityError, make_loops_even
from meshwright.sizing import BackgroundGrid, gradation
from meshwright.sizing.field import as_size_field

# ------------------------------------------------------------------ independent oracles


def _cross(p, q, r) -> Fraction:
    """Exact (q - p) x (r - p)."""
    px, py = Fraction(float(p[0])), Fraction(float(p[1]))
    return (Fraction(float(q[0])) - px) * (Fraction(float(r[1])) - py) - (Fraction(float(q[1])) - py) * (
        Fraction(float(r[0])) - px
    )


def _strictly_convex(xy, quad) -> bool:
    return all(_cross(xy[quad[k - 1]], xy[quad[k]], xy[quad[(k + 1) % 4]]) > 0 for k in range(4))


def _min_scaled_jacobian(xy, quads) -> float:
    worst = 1.0
    for q in quads:
        for k in range(4):
            p, c, n = xy[q[k - 1]], xy[q[k]], xy[q[(k + 1) % 4]]
            ux, uy = n[0] - c[0], n[1] - c[1]
            wx, wy = p[0] - c[0], p[1] - c[1]
            worst = min(worst, (ux * wy - uy * wx) / (math.hypot(ux, uy) * math.hypot(wx, wy)))
    return worst


def _check_all_quad(mesh, on_circle=()):
    """Every quad strictly convex (exact), conforming (each interior edge twice, opposite
    ways), line cells exactly the boundary edges, boundary nodes of curved loops on them."""
    xy, quads = mesh.points, mesh.cells["quad"]
    assert "triangle" not in mesh.cells
    assert all(_strictly_convex(xy, q) for q in quads)
    directed = {}
    for q in quads.tolist():
        for k in range(4):
            e = (q[k], q[(k + 1) % 4])
            assert e not in directed, f"edge {e} used twice in the same direction"
            directed[e] = True
    boundary = {e for e in directed if (e[1], e[0]) not in directed}
    lines = {tuple(e) for e in mesh.cells["line"].tolist()}
    assert boundary == lines
    for centre, radius in on_circle:
        v = np.unique(mesh.cells["line"])
        d = np.hypot(*(xy[v] - centre).T)
        near = np.abs(d - radius) < 1e-3 * radius
        assert np.allclose(d[near], radius, rtol=1e-9, atol=1e-12)


# ---------------------------------------------------------------------- even parity


def test_odd_loop_gets_one_node_on_the_true_curve_and_even_spacing():
    dom = circle()
    disc = dom.discretize(0.1)
    assert len(disc.segments) % 2 == 1  # the case under test: 63 segments
    even, added = make_loops_even(dom, disc)
    assert added == (0,)
    assert len(even.segments) == len(disc.segments) + 1
    assert np.allclose(np.hypot(*even.points.T), 1.0, rtol=0, atol=1e-12)
    seg = even.points[even.segments[:, 1]] - even.points[even.segments[:, 0]]
    length = np.hypot(*seg.T)
    # The respacing leaves no half-length segment beside the split.
    assert length.min() > 0.85 * np.median(length)
    # The chain is still one closed loop in order.
    assert np.array_equal(even.segments[:-1, 1], even.segments[1:, 0])
    assert even.segments[-1, 1] == even.segments[0, 0]


def test_even_loops_are_left_alone_and_fixed_odd_loops_are_named():
    dom = circle()
    disc = dom.discretize(0.1)
    even, _ = make_loops_even(dom, disc)
    again, added = make_loops_even(dom, even)
    assert added == () and again is even
    with pytest.raises(ParityError, match=r"outer loop \(loop 0\) has 63 boundary nodes"):
        make_loops_even(dom, disc, fixed_boundary=True)
    hole = circles(centers=[(0.5, 0.5)], radii=[0.2], box=(0, 0, 1, 1))
    with pytest.raises(ParityError, match=r"hole 0 \(loop 1\)"):
        make_loops_even(hole, hole.discretize(0.05), fixed_boundary=True)


def test_every_loop_of_the_mesh_is_even_before_any_split():
    dom = circles(centers=[(0.5, 0.5)], radii=[0.2], box=(0, 0, 1, 1))
    fill, report = pair_domain(dom, as_size_field(0.05), all_quad=False)
    mid = fill.points[fill.lines].mean(axis=1)
    on_hole = np.abs(np.hypot(*(mid - 0.5).T) - 0.2) < 0.01
    assert on_hole.sum() % 2 == 0 and (~on_hole).sum() % 2 == 0
    assert 1 in report.nodes_added


# ----------------------------------------------------------------- the pair step


def _strip():
    """Four triangles in a row under a gently bent roof (front order 1, 0, 2, 3)."""
    xy = np.array([[0, 0], [1, 0], [2, 0], [0, 1], [1, 1.1], [2, 1]], dtype=np.float64)
    tris = np.array([[1, 4, 3], [0, 1, 3], [1, 2, 4], [2, 5, 4]], dtype=np.int32)
    return xy, tris


def test_pairs_are_counter_clockwise_strictly_convex_and_cover_the_triangles():
    xy, tris = _strip()
    quads, first, left, _, _, _ = pair_triangles(xy, tris)
    assert len(left) == 0 and len(quads) == 2
    assert all(_strictly_convex(xy, q) for q in quads)
    covered = sorted(sorted(set(q.tolist())) for q in quads)
    assert covered == [[0, 1, 3, 4], [1, 2, 4, 5]]
    # Triangle 0 (made first) takes triangle 1, its only chance, not triangle 2.
    assert first.tolist() == [0, 2]


def test_a_non_convex_pair_only_in_the_relaxed_round():
    # A dart: the two triangles' union has a reflex corner at vertex 2.
    xy = np.array([[0, 0], [2, 0], [1, 0.3], [1, 2]], dtype=np.float64)
    tris = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.int32)
    quads, _, left, _, _, _ = pair_triangles(xy, tris, bounds=(0.5, 0.0), walks=0)
    assert len(quads) == 0 and sorted(left.tolist()) == [0, 1]
    # The relaxed round admits reflex corners, but not between two boundary sides (here
    # vertex 2 lies on the boundary of this two-triangle mesh).
    quads, _, left, _, _, _ = pair_triangles(xy, tris, bounds=(0.0, -1.0), walks=0)
    assert len(quads) == 0
    # Surrounded by triangles, the same dart pairs in the relaxed round only.
    ring = np.array([[0, 0], [2, 0], [1, 0.3], [1, 2], [1, -1], [3, 1], [-1, 1]], dtype=np.float64)
    tris = np.array([[0, 1, 2], [0, 2, 3], [0, 4, 1], [1, 5, 2], [2, 5, 3], [0, 3, 6]], dtype=np.int32)
    blocked = np.array([[0, 4], [4, 1], [1, 5], [5, 3], [3, 6], [6, 0]])
    from meshwright.core.mesh import build_neighbors

    nbr = build_neighbors(tris).astype(np.int32)
    assert nbr[0, 1] == 1  # triangle 0 meets the dart's other half across side 0-2
    assert pk.pair_score(ring, tris.ravel(), nbr.ravel(), 0, 1, 0.0) == -1.0
    assert pk.pair_score(ring, tris.ravel(), nbr.ravel(), 0, 1, -1.0) == 0.0
    quads, _, left, _, _, _ = pair_triangles(ring, tris, blocked, walks=0)
    assert len(left) == 0 and all(_strictly_convex(ring, q) for q in quads)


def test_a_quad_smoothing_cannot_open_is_cut_back_into_triangles():
    from meshwright.quad.enhancement import unpair_nonconvex as _unpair_nonconvex

    xy = np.array([[0, 0], [2, 0], [1, 0.3], [1, 2]], dtype=np.float64)
    quads = np.array([[0, 1, 3, 2]], dtype=np.int32)  # reflex at vertex 2
    q, t = _unpair_nonconvex(xy, quads, np.zeros((0, 3), dtype=np.int32))
    assert len(q) == 0 and len(t) == 2
    assert all(_cross(xy[a], xy[b], xy[c]) > 0 for a, b, c in t)
    assert sorted(set(t.ravel().tolist())) == [0, 1, 2, 3]


@pytest.mark.parametrize("d, split", [((0.0, 1.0), False), ((3.0, 0.05), True)])
def test_a_flat_ear_of_the_front_is_opened(d, split):
    from meshwright.quad.pairing import _open_ears

    # Ear t = (a, b, c) on two boundary sides, 174 degrees at a; s = (c, b, d) beyond b-c
    # (its other sides lead to triangles 2 and 3, not read).  With d above, the union is
    # convex and b-c flips to a-d; with d far right it is not, and b-c is split.
    xy = np.array([[0, -0.05], [1, 0], [-1, 0], d], dtype=np.float64)
    tris = np.array([[0, 1, 2], [2, 1, 3], [0, 0, 0], [0, 0, 0]], dtype=np.int32)
    nbr = np.array([[1, -1, -1], [2, 3, 0], [-1, -1, -1], [-1, -1, -1]], dtype=np.int32)
    out_xy, out_t, changed = _open_ears(xy, tris, nbr, np.full(4, -1, dtype=np.int32))
    assert changed == 1
    assert len(out_xy) == 4 + split and len(out_t) == 4 + 2 * split
    live = [0, 1] + ([4, 5] if split else [])
    assert all(_cross(out_xy[a], out_xy[b], out_xy[c]) > 0 for a, b, c in out_t[live])
    # Node 0 is no longer the corner of a single triangle.
    assert sum(0 in t for t in out_t[live].tolist()) == 2
    area = sum(float(_cross(out_xy[a], out_xy[b], out_xy[c])) for a, b, c in out_t[live])
    assert area == pytest.approx(float(_cross(xy[0], xy[1], xy[2]) + _cross(xy[2], xy[1], xy[3])))


def test_unpaired_triangles_split_at_their_centroids():
    from meshwright.quad.pairing import _split_left_overs

    xy, tris = _strip()
    mate = np.array([1, 0, -1, -1], dtype=np.int32)
    out_xy, out_t, out_mate, cut = _split_left_overs(xy, tris, mate)
    assert cut.tolist() == [2, 3] and len(out_xy) == len(xy) + 2 and len(out_t) == len(tris) + 4
    assert out_mate.tolist() == [1, 0, -1, -1, -1, -1, -1, -1]
    assert all(_cross(out_xy[a], out_xy[b], out_xy[c]) > 0 for a, b, c in out_t)
    area = sum(float(_cross(out_xy[a], out_xy[b], out_xy[c])) for a, b, c in out_t)
    assert area == pytest.approx(sum(float(_cross(xy[a], xy[b], xy[c])) for a, b, c in tris))
    assert np.allclose(out_xy[len(xy)], xy[tris[2]].mean(axis=0))


def test_blocked_sides_are_never_crossed():
    xy, tris = _strip()
    quads, _, left, _, _, _ = pair_triangles(xy, tris, blocked=np.array([[1, 3], [1, 4], [2, 4]]), walks=0)
    assert len(quads) == 0 and len(left) == 4


def test_augmenting_path_repairs_a_stranding_pairing():
    xy, tris = _strip()
    nbr = np.full((4, 3), -1, dtype=np.int32)
    from meshwright.core.mesh import build_neighbors

    nbr[:] = build_neighbors(tris)
    mate = np.array([-1, 2, 1, -1], dtype=np.int32)  # the middle pair strands both ends
    gained = pk.augment(pk.side_scores(xy, tris.ravel(), nbr.ravel(), None), nbr.ravel(), mate, 0.0, 100, pk.augment_scratch(4))
    assert gained == 1
    assert mate.tolist() == [1, 0, 3, 2]


@settings(max_examples=20, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(4, 60))
def test_dual_neighbours_match_a_dictionary_of_directed_edges(seed, npts):
    rng = np.random.default_rng(seed)
    xy = rng.random((npts, 2))
    tris = mw.delaunay(xy).triangles.astype(np.int32)
    rng.shuffle(tris)
    n = len(xy)
    edges = {(int(t[(k + 1) % 3]), int(t[(k + 2) % 3])): (i, k) for i, t in enumerate(tris) for k in range(3)}
    pick = [e for e in edges if rng.random() < 0.2]
    blocked = {(min(e), max(e)) for e in pick}
    bkey = np.array(sorted(a * n + b for a, b in blocked), dtype=np.int64)
    nbr, bad = pk.dual_neighbours(tris.ravel(), n, bkey)
    assert bad == -1
    for (u, w), (i, k) in edges.items():
        twin = edges.get((w, u))
        want = -1 if twin is None or (min(u, w), max(u, w)) in blocked else twin[0]
        assert nbr[3 * i + k] == want


@settings(max_examples=20, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(4, 40))
def test_neighbours_after_centroid_splits_match_a_dictionary(seed, npts):
    """The centre rounds update the neighbours of the cut triangles only; the result is
    the table of the split mesh (adjacent cut triangles, blocked sides kept blocked)."""
    from meshwright.core.mesh import build_neighbors
    from meshwright.quad.pairing import _split_left_overs

    rng = np.random.default_rng(seed)
    xy = rng.random((npts, 2))
    tris = mw.delaunay(xy).triangles.astype(np.int32)
    nbr = build_neighbors(tris).astype(np.int32)
    n = len(xy)
    blocked = set()
    for t, k in zip(*np.nonzero((rng.random(nbr.shape) < 0.15) & (nbr >= 0))):
        u, w = int(tris[t, (k + 1) % 3]), int(tris[t, (k + 2) % 3])
        blocked.add((min(u, w), max(u, w)))
    for t in range(len(tris)):
        for k in range(3):
            u, w = int(tris[t, (k + 1) % 3]), int(tris[t, (k + 2) % 3])
            if (min(u, w), max(u, w)) in blocked:
                nbr[t, k] = -1
    mate = np.where(rng.random(len(tris)) < 0.4, -1, 0).astype(np.int32)
    out_xy, out_t, _, cut = _split_left_overs(xy, tris, mate)
    got = pk.split_neighbours(nbr.ravel(), cut, len(tris))
    edges = {(int(t[(k + 1) % 3]), int(t[(k + 2) % 3])): (i, k) for i, t in enumerate(out_t) for k in range(3)}
    for (u, w), (i, k) in edges.items():
        twin = edges.get((w, u))
        want = -1 if twin is None or (u < n and w < n and (min(u, w), max(u, w)) in blocked) else twin[0]
        assert got[3 * i + k] == want


def test_dual_neighbours_name_an_inconsistent_triangle():
    # Triangle 1 traverses 0 -> 1 as triangle 0 does (flipped orientation).
    tris = np.array([[0, 1, 2], [1, 3, 0], [0, 1, 4]], dtype=np.int32)
    _, bad = pk.dual_neighbours(tris.ravel(), 5, np.zeros(0, dtype=np.int64))
    assert bad == 0
    # Edge 0-1 shared by three triangles: 1 -> 0 twice.
    tris = np.array([[0, 1, 2], [1, 0, 3], [1, 0, 4]], dtype=np.int32)
    _, bad = pk.dual_neighbours(tris.ravel(), 5, np.zeros(0, dtype=np.int64))
    assert bad == 0
    tris = np.array([[0, 1, 2], [1, 0, 3]], dtype=np.int32)
    nbr, bad = pk.dual_neighbours(tris.ravel(), 4, np.zeros(0, dtype=np.int64))
    assert bad == -1 and nbr.tolist() == [-1, -1, 1, -1, -1, 0]


@settings(max_examples=20, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(5, 40))
def test_side_score_table_classifies_every_side(seed, npts):
    """The rounds' table of raw scores (one per side) against Fractions and math: a side
    on the boundary or blocked takes no pair, a strictly convex pair scores its scaled
    Jacobian, a pair with a reflex or straight corner the REFLEX mark, and a corner wider
    than 150 degrees between two boundary sides forbids the pair; twins agree."""
    from meshwright.core.mesh import build_neighbors

    rng = np.random.default_rng(seed)
    xy = rng.random((npts, 2))
    tris = mw.delaunay(xy).triangles.astype(np.int32)
    nbr = build_neighbors(tris).astype(np.int32)
    nbr[rng.random(nbr.shape) < 0.1] = -1  # blocked sides (one side of a pair is enough to check)
    raw = pk.side_scores(xy, tris.ravel(), nbr.ravel(), None).reshape(-1, 3)

    def wide(p, c, n):  # corner c (previous p, next n) wider than 150 degrees, or reflex
        a = math.degrees(math.atan2(*reversed([(n[0] - c[0]) * (p[0] - c[0]) + (n[1] - c[1]) * (p[1] - c[1]),
                                                (n[0] - c[0]) * (p[1] - c[1]) - (n[1] - c[1]) * (p[0] - c[0])])))
        return a < 0 or a > 150.0

    for t in range(len(tris)):
        for k in range(3):
            s = int(nbr[t, k])
            back = s >= 0 and t in nbr[s].tolist()
            if not back:
                assert raw[t, k] == pk.NO_PAIR
                continue
            j = nbr[s].tolist().index(t)
            assert raw[t, k] == raw[s, j]
            a, b, c = (int(v) for v in (tris[t, k], tris[t, (k + 1) % 3], tris[t, (k + 2) % 3]))
            d = int(tris[s, j])
            jb, jc = tris[s].tolist().index(b), tris[s].tolist().index(c)
            flat = (nbr[t, (k + 2) % 3] < 0 and nbr[s, jc] < 0 and wide(xy[a], xy[b], xy[d])) or (
                nbr[t, (k + 1) % 3] < 0 and nbr[s, jb] < 0 and wide(xy[d], xy[c], xy[a]))
            if flat:
                assert raw[t, k] == pk.NO_PAIR
            elif _strictly_convex(xy, (a, b, d, c)):
                assert raw[t, k] == pytest.approx(_min_scaled_jacobian(xy, [(a, b, d, c)]), abs=1e-12)
            else:
                assert raw[t, k] == pk.REFLEX
            for qmin in (0.5, 0.0, -1.0):
                want = -1.0 if flat else (raw[t, k] if raw[t, k] >= qmin else -1.0) if raw[t, k] != pk.REFLEX else (
                    0.0 if qmin < 0 else -1.0)
                assert pk.pair_score(xy, tris.ravel(), nbr.ravel(), t, k, qmin) == want


def _max_matching_brute_force(nt, adj):
    """Size of a maximum matching by exhaustive search over vertex subsets (small graphs)."""
    from functools import lru_cache

    @lru_cache(maxsize=None)
    def best(mask):
        for v in range(nt):
            if not mask >> v & 1:
                r = best(mask | 1 << v)
                for w in adj[v]:
                    if not mask >> w & 1:
                        r = max(r, 1 + best(mask | 1 << v | 1 << w))
                return r
        return 0

    return best(0)


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(6, 11))
def test_augmenting_paths_reach_a_maximum_pairing(seed, npts):
    from meshwright.core.mesh import build_neighbors

    rng = np.random.default_rng(seed)
    xy = rng.random((npts, 2))
    tris = mw.delaunay(xy).triangles.astype(np.int32)
    nbr = build_neighbors(tris).astype(np.int32)
    nt = len(tris)
    flat_t, flat_n = tris.ravel(), nbr.ravel()
    adj = [
        {int(nbr[t, k]) for k in range(3) if nbr[t, k] >= 0 and pk.pair_score(xy, flat_t, flat_n, t, k, -1.0) >= 0}
        for t in range(nt)
    ]
    assert all(t in adj[s] for t in range(nt) for s in adj[t])  # an allowed pair is allowed both ways
    mate = np.full(nt, -1, dtype=np.int32)
    pk.augment(pk.side_scores(xy, tris.ravel(), nbr.ravel(), None), nbr.ravel(), mate, -1.0, 10**6, pk.augment_scratch(nt))
    for t in range(nt):
        if mate[t] >= 0:
            assert mate[mate[t]] == t and int(mate[t]) in adj[t]
    assert int((mate >= 0).sum()) // 2 == _max_matching_brute_force(nt, adj)



def _tutte_rank_matching(nt, adj, seed) -> int:
    """Size of a maximum matching as half the rank of a random Tutte matrix modulo a prime
    (Lovasz 1979): an algebraic oracle with no alternating paths or blossoms in it; the
    rank can only come out low, with probability below nt / p."""
    p = 2**61 - 1
    rng = np.random.default_rng(seed)
    t = [[0] * nt for _ in range(nt)]
    for u in range(nt):
        for w in adj[u]:
            if u < w:
                x = int(rng.integers(1, 2**62)) % p
                t[u][w], t[w][u] = x, (p - x) % p
    rank = 0
    for col in range(nt):
        piv = next((r for r in range(rank, nt) if t[r][col]), None)
        if piv is None:
            continue
        t[rank], t[piv] = t[piv], t[rank]
        inv = pow(t[rank][col], p - 2, p)
        for r in range(rank + 1, nt):
            if t[r][col]:
                f = t[r][col] * inv % p
                t[r] = [(a - f * b) % p for a, b in zip(t[r], t[rank])]
        rank += 1
    return rank // 2


# Seeds whose duals need a shrunk blossom's odd triangles searched again: a search that
# skipped them misses a pair on each (found among 300 seeds, about 1 % of them).
@pytest.mark.parametrize("seed, qmin", [(81, -1.0), (104, 0.3), (108, -1.0), (128, 0.3), (147, -1.0), (208, -1.0)])
def test_augmenting_paths_reach_a_maximum_pairing_through_blossoms(seed, qmin):
    from meshwright.core.mesh import build_neighbors

    rng = np.random.default_rng(seed)
    npts = int(rng.integers(25, 60))
    xy = rng.random((npts, 2))
    tris = mw.delaunay(xy).triangles.astype(np.int32)
    nbr = build_neighbors(tris).astype(np.int32)
    nt = len(tris)
    flat_t, flat_n = tris.ravel(), nbr.ravel()
    adj = [
        {int(nbr[t, k]) for k in range(3) if nbr[t, k] >= 0 and pk.pair_score(xy, flat_t, flat_n, t, k, qmin) >= 0}
        for t in range(nt)
    ]
    assert all(t in adj[s] for t in range(nt) for s in adj[t])  # an allowed pair is allowed both ways
    mate = np.full(nt, -1, dtype=np.int32)
    pk.augment(pk.side_scores(xy, tris.ravel(), nbr.ravel(), None), nbr.ravel(), mate, qmin, 10**6, pk.augment_scratch(nt))
    for t in range(nt):
        if mate[t] >= 0:
            assert mate[mate[t]] == t and int(mate[t]) in adj[t]
    assert int((mate >= 0).sum()) // 2 == _tutte_rank_matching(nt, adj, seed)



def _random_delaunay(seed, lo, hi):
    """The seeded generator, lo..hi random points, their Delaunay triangles and neighbours
    (t, 3) int32 and the pairing's side scores: the chain-search tests' input."""
    from meshwright.core.mesh import build_neighbors

    rng = np.random.default_rng(seed)
    xy = rng.random((int(rng.integers(lo, hi)), 2))
    tris = mw.delaunay(xy).triangles.astype(np.int32)
    nbr = build_neighbors(tris).astype(np.int32)
    return rng, xy, tris, nbr, pk.side_scores(xy, tris.ravel(), nbr.ravel(), None)


@pytest.mark.parametrize("seed", [81, 104, 147, 208])
def test_one_augment_scratch_serves_many_rounds(seed):
    """Rounds at falling bounds sharing one scratch set (left with blossom stamps and
    reset entries by the earlier rounds) pair exactly as rounds with fresh sets, and the
    last round (any pair, unbounded search) reaches the maximum (Tutte-rank oracle)."""
    rng, xy, tris, nbr, raw = _random_delaunay(seed, 25, 60)
    nt = len(tris)
    shared = pk.augment_scratch(nt)
    mate_shared = np.full(nt, -1, dtype=np.int32)
    mate_fresh = mate_shared.copy()
    for q, visit in ((0.5, 8), (0.3, 16), (0.0, 64), (-1.0, 10**6)):
        pk.augment(raw, nbr.ravel(), mate_shared, q, visit, shared)
        pk.augment(raw, nbr.ravel(), mate_fresh, q, visit, pk.augment_scratch(nt))
        assert mate_shared.tolist() == mate_fresh.tolist()
    flat_t, flat_n = tris.ravel(), nbr.ravel()
    adj = [
        {int(nbr[t, k]) for k in range(3) if nbr[t, k] >= 0 and pk.pair_score(xy, flat_t, flat_n, t, k, -1.0) >= 0}
        for t in range(nt)
    ]
    assert int((mate_shared >= 0).sum()) // 2 == _tutte_rank_matching(nt, adj, seed)
    # Each row's pred, base and flags, and head, tail, link are back at rest (marks keep
    # old stamps; sides, partners and visit positions are written before they are read).
    rest = pk.augment_scratch(nt)
    from meshwright.quad import _pairing_match as pm

    cols = [pm._PRED, pm._BASE, pm._FLAG]
    assert shared[0][:, cols].tolist() == rest[0][:, cols].tolist()
    for k in (5, 6, 7):
        assert shared[k].tolist() == rest[k].tolist()


def _walk_by_dictionary(xy, tris, mate, rng, qmin):
    """A walk written independently of the kernel: sides looked up in a dictionary of
    directed edges, each pair's quad tested with Fractions (strictly convex, every corner
    sine at least ``qmin``, no corner wider than 150 degrees between two boundary sides),
    one ``rng.permutation(3)`` per walking triangle.  Returns (tris, mate, flipped)."""
    tris, mate = [list(map(int, t)) for t in tris], mate.copy()

    def twin(t, k):
        u, w = tris[t][(k + 1) % 3], tris[t][(k + 2) % 3]
        for s, r in enumerate(tris):
            for j in range(3):
                if (r[(j + 1) % 3], r[(j + 2) % 3]) == (w, u):
                    return s, j
        return -1, -1

    def cross(p, c, n):
        p, c, n = ([Fraction(float(x)) for x in xy[v]] for v in (p, c, n))
        return (n[0] - c[0]) * (p[1] - c[1]) - (n[1] - c[1]) * (p[0] - c[0])

    def sine(p, c, n):
        u, w = xy[n] - xy[c], xy[p] - xy[c]
        return (u[0] * w[1] - u[1] * w[0]) / (math.hypot(*u) * math.hypot(*w))

    def wide(p, c, n):
        u, w = xy[n] - xy[c], xy[p] - xy[c]
        return math.degrees(math.atan2(u[0] * w[1] - u[1] * w[0], u @ w)) > 150.0 or cross(p, c, n) <= 0

    def allowed(t, k):
        s, j = twin(t, k)
        a, b, c = tris[t][k], tris[t][(k + 1) % 3], tris[t][(k + 2) % 3]
        d = tris[s][j]
        quad = [a, b, d, c]
        if any(cross(quad[i - 1], quad[i], quad[(i + 1) % 4]) <= 0 for i in range(4)):
            return False
        if min(sine(quad[i - 1], quad[i], quad[(i + 1) % 4]) for i in range(4)) < qmin:
            return False
        # Corner b between t's side a-b and s's side b-d, corner c between d-c and c-a.
        if twin(t, (k + 2) % 3)[0] < 0 and twin(s, tris[s].index(c))[0] < 0 and wide(a, b, d):
            return False
        return not (twin(t, (k + 1) % 3)[0] < 0 and twin(s, tris[s].index(b))[0] < 0 and wide(d, c, a))

    touched, flipped = set(), []
    for t in np.flatnonzero(mate < 0).tolist():
        if t in touched:
            continue
        for k in rng.permutation(3).tolist():
            s, _ = twin(t, k)
            if s < 0 or s in touched or mate[s] < 0 or mate[s] in touched or not allowed(t, k):
                continue
            old = int(mate[s])
            a, b, c = tris[t][k], tris[t][(k + 1) % 3], tris[t][(k + 2) % 3]
            d = next(v for v in tris[s] if v not in (b, c))
            tris[t], tris[s] = [a, b, d], [a, d, c]
            mate[old], mate[t], mate[s] = -1, s, t
            touched.update((t, s, old))
            flipped += [t, s]
            break
    return np.array(tris, dtype=np.int32), mate, flipped


@pytest.mark.parametrize("seed", [3, 81, 147, 208, 311])
def test_walks_flip_as_a_walk_by_dictionary(seed):
    """The compiled walk (orders drawn ahead, the generator set back to the rows used)
    flips, pairs and frees as a walk over a dictionary of edges with exact convexity and
    one permutation call per walking triangle, round after round, and leaves the
    generator where those calls leave it."""
    from meshwright.core.mesh import build_neighbors
    from meshwright.quad.pairing import _walk_left_overs

    rng, xy, tris, nbr, raw = _random_delaunay(seed, 40, 90)
    mate = np.full(len(tris), -1, dtype=np.int32)
    pk.greedy_pairs(raw, nbr.ravel(), mate, 0.5)
    mine, theirs = np.random.default_rng(seed), np.random.default_rng(seed)
    walked = 0
    for _ in range(5):
        want_tris, want_mate, want_flips = _walk_by_dictionary(xy, tris, mate, theirs, 0.3)
        flipped = _walk_left_overs(tris, nbr, mate, raw, mine, 0.3)
        assert flipped.tolist() == want_flips
        assert tris.tolist() == want_tris.tolist() and mate.tolist() == want_mate.tolist()
        assert nbr.tolist() == build_neighbors(tris).tolist()
        assert mine.integers(1 << 30) == theirs.integers(1 << 30)
        walked += len(flipped)
        if not len(flipped):
            break
        pk.rescore(raw, xy, tris.ravel(), nbr.ravel(), flipped, None)
    assert walked > 0


@pytest.mark.parametrize("seed", [3, 81, 147, 208])
def test_walk_rounds_refill_only_the_flipped_rows(seed):
    """After walks (flips that pair two triangles and free a third), a chain round that
    refills only the flipped triangles' rows of a table left by the previous round pairs
    exactly as a round that fills every row of a fresh one, round after round; the table
    has rows to spare (unused by either)."""
    from meshwright.quad.pairing import _walk_left_overs

    rng, xy, tris, nbr, raw = _random_delaunay(seed, 60, 120)
    nt = len(tris)
    mate = np.full(nt, -1, dtype=np.int32)
    shared = pk.augment_scratch(nt, 7)
    pk.greedy_pairs(raw, nbr.ravel(), mate, 0.5)
    pk.augment(raw, nbr.ravel(), mate, 0.5, 4, shared)
    walk = np.random.default_rng(seed)
    rounds = 0
    for _ in range(6):
        flipped = _walk_left_overs(tris, nbr, mate, raw, walk, 0.5)
        if not len(flipped):
            break
        pk.rescore(raw, xy, tris.ravel(), nbr.ravel(), flipped, None)
        # The next walk reads its scores from the table: rescoring the flipped triangles
        # must leave it equal to a table scored afresh.
        assert np.array_equal(raw, pk.side_scores(xy, tris.ravel(), nbr.ravel(), None))
        fresh = mate.copy()
        got = pk.augment_changed(raw, nbr.ravel(), mate, 0.5, 4, shared, flipped)
        want = pk.augment(raw, nbr.ravel(), fresh, 0.5, 4, pk.augment_scratch(nt))
        assert (got, mate.tolist()) == (want, fresh.tolist())
        rounds += 1
    assert rounds >= 1
    # Every pair is two neighbours across a side the bound allows, both ways.
    for t in np.flatnonzero(mate >= 0):
        s = mate[t]
        assert mate[s] == t
        k = int(np.flatnonzero(nbr[t] == s)[0])
        assert pk.pair_score(xy, tris.ravel(), nbr.ravel(), t, k, 0.5) >= 0.5


@pytest.mark.parametrize("seed", [3, 81, 147, 208])
def test_centre_rounds_refill_only_the_cut_rows(seed):
    """Centroid rounds that refill only the rows around the cut triangles of the table the
    last chain round left pair exactly as rounds filling every row of a fresh table."""
    from meshwright.quad.pairing import _centre_rounds, _pair_rounds

    _, xy, tris, _, _ = _random_delaunay(seed, 60, 120)
    n = len(xy)
    none = np.zeros(0, dtype=np.int64)
    # Short searches and no walks leave triangles for the centroid rounds.
    st = _pair_rounds(xy, tris.copy(), none, n, (0.5, 0.3), 2, 0, seed)
    left = int((st.mate < 0).sum())
    assert left >= 2
    fresh = st._replace(mate=st.mate.copy(), scratch=None)
    got = _centre_rounds(st, none, n, 0.3, 64, 2)
    want = _centre_rounds(fresh, none, n, 0.3, 64, 2)
    assert got.chains == want.chains > st.chains  # the chain rounds gained pairs
    assert got.mate.tolist() == want.mate.tolist()
    assert got.tris.tolist() == want.tris.tolist()
    assert (st.mate < 0).sum() == left  # st's own arrays are left as they were


def test_grow_rings_marks_the_nodes_of_quads_touching_the_last_ring():
    """The chord smoothing's rings (``grow_rings``) against a breadth-first oracle over the
    quads' node sets: ring r holds the nodes of every quad with a node within r - 1 rings."""
    rng = np.random.default_rng(5)
    quads = rng.integers(0, 400, size=(300, 4)).astype(np.int32)
    start = rng.random(400) < 0.02
    cells = [set(q) for q in quads.tolist()]
    want = set(np.flatnonzero(start).tolist())
    for rings in range(4):
        got = pk.grow_rings(quads, start, rings)
        assert set(np.flatnonzero(got).tolist()) == want
        want = want.union(*(c for c in cells if c & want))
    assert start.sum() < 20  # the input is left as it was


# ------------------------------------------------------------------ enhancement


def test_node_elimination_merges_the_two_quads_of_a_doublet():
    xy = np.array([[0, 0], [2, 0], [2, 2], [0, 2], [0.9, 1.1]], dtype=np.float64)
    quads = np.array([[4, 0, 1, 2], [4, 2, 3, 0]], dtype=np.int32)
    boundary = np.array([1, 1, 1, 1, 0], dtype=bool)
    _, out, kept, counts = enhance(xy, quads, boundary)
    assert counts[0] == 1 and len(out) == 1
    assert sorted(out[0].tolist()) == [0, 1, 2, 3] and _strictly_convex(xy, out[0])


def test_element_elimination_collapses_a_diamond_between_two_valence_three_nodes():
    #          N --- D --- N'
    #          |   / | \   |      A and C interior, each in three quads; the diamond
    #          W - A   C - E      ABCD disappears and A, C merge at (0, 0).
    #          |   \ | /   |
    #          S --- B --- S'
    xy = np.array(
        [[-0.5, 0], [0, -1], [0.5, 0], [0, 1], [-1.5, 0], [-1, -1], [-1, 1], [1.5, 0], [1, -1], [1, 1]],
        dtype=np.float64,
    )
    A, B, C, D, W, S, N, E, S2, N2 = range(10)
    quads = np.array(
        [[A, B, C, D], [A, W, S, B], [A, D, N, W], [C, B, S2, E], [C, E, N2, D]], dtype=np.int32
    )
    boundary = np.ones(10, dtype=bool)
    boundary[[A, C]] = False
    out_xy, out, kept, counts = enhance(xy, quads, boundary)
    assert counts[1] == 1 and len(out) == 4 and 0 not in kept
    assert np.array_equal(out_xy[A], [0.0, 0.0])
    assert C not in out
    assert all(_strictly_convex(out_xy, q) for q in out)
    assert all((out == A).any(axis=1))


def test_diagonal_swap_takes_the_better_diagonal_of_the_hexagon():
    ang = np.radians([0, 40, 100, 180, 220, 280])
    xy = np.column_stack([np.cos(ang), 0.6 * np.sin(ang)])
    # Hexagon u=0, c=1, d=2, v=3, a=4, b=5 split along 0-3: q1 = (u, v, a, b), q2 = (v, u, c, d).
    splits = {r: [[r, r + 1, r + 2, (r + 3) % 6], [(r + 3) % 6, (r + 4) % 6, (r + 5) % 6, r]] for r in range(3)}
    quality = {r: _min_scaled_jacobian(xy, q) for r, q in splits.items()}
    worst, best = min(quality, key=quality.get), max(quality, key=quality.get)
    assert quality[best] > quality[worst] + 0.05
    start = np.array(splits[worst], dtype=np.int32)
    _, out, _, counts = enhance(xy, start, np.ones(6, dtype=bool) & False)
    assert counts[2] >= 1
    assert _min_scaled_jacobian(xy, out) == pytest.approx(quality[best])
    assert all(_strictly_convex(xy, q) for q in out)


# ------------------------------------------------------------------ full meshes


NACA = airfoil_in_farfield("0012")
NACA_SIZE = gradation(naca_loop("0012")[0].evaluate(np.linspace(0.0, 2.0 * np.pi, 400)), 0.03, 1.3, 2.5)
CASES = {
    "disk uniform": (circle(), 0.1, [((0.0, 0.0), 1.0)]),
    "disk graded": (circle(), lambda p: 0.03 + 0.1 * np.hypot(p[:, 0] - 0.5, p[:, 1]), [((0.0, 0.0), 1.0)]),
    "square with hole": (circles(centers=[(0.5, 0.5)], radii=[0.2], box=(0, 0, 1, 1)), 0.06, [((0.5, 0.5), 0.2)]),
    "square with square hole graded": (
        polygon([(0, 0), (1, 0), (1, 1), (0, 1)], holes=[[(0.3, 0.3), (0.3, 0.6), (0.6, 0.6), (0.6, 0.3)]]),
        lambda p: 0.03 + 0.05 * p[:, 0],
        [],
    ),
    "naca 0012 far field graded": (NACA, NACA_SIZE, [((0.5, 0.0), 10.0)]),
}


def _check_paired(name, smooth):
    """Valid, all-quad, boundary on the curves, min scaled Jacobian > 0.2, area kept."""
    dom, size, curves = CASES[name]
    mesh = quadrangulate(dom, size, method="pairing", smooth=smooth)
    mesh.validate()
    _check_all_quad(mesh, curves)
    assert _min_scaled_jacobian(mesh.points, mesh.cells["quad"]) > 0.2
    assert mesh.area() == pytest.approx(abs(dom.area()), rel=2e-2)


@pytest.mark.parametrize("name", list(CASES))
def test_all_quad_meshes_are_valid_with_scaled_jacobian_above_0_2(name):
    _check_paired(name, smooth=5)


@pytest.mark.parametrize("name", ["disk uniform", "naca 0012 far field graded"])
def test_without_extra_sweeps_the_enhancement_alone_keeps_the_bound(name):
    _check_paired(name, smooth=0)


def test_stretched_background_grid_gives_stretched_quads():
    dom = mw.geometry.rectangle(0, 0, 2, 1)
    bg = BackgroundGrid.uniform(dom.bbox, 0.05, stretch=3.0, direction=0.0)
    mesh = quadrangulate(dom, bg, method="pairing", smooth=3)
    mesh.validate()
    _check_all_quad(mesh)
    q = mesh.points[mesh.cells["quad"]]
    dx = np.abs(np.diff(q[:, :, 0], axis=1, append=q[:, :1, 0])).max(axis=1)
    dy = np.abs(np.diff(q[:, :, 1], axis=1, append=q[:, :1, 1])).max(axis=1)
    assert np.median(dx / dy) > 1.8


def test_quad_dominant_mesh_reports_its_triangles():
    dom, size, _ = CASES["naca 0012 far field graded"]
    fill, report = pair_domain(dom, as_size_field(size), all_quad=False)
    assert report.triangles_left == len(fill.triangles) == report.left_over + 2 * report.reverted
    assert not report.split
    assert 2 * report.paired + report.left_over == report.triangles
    mesh = quadrangulate(dom, size, method="pairing", all_quad=False, smooth=5)
    assert len(mesh.cells.get("triangle", ())) == report.triangles_left
    mesh.validate()


def test_left_over_triangles_are_finished_by_chords_only():
    from meshwright.core.mesh import Mesh
    from meshwright.quad import QuadFill
    from meshwright.quad.chords import chord_split

    xy = np.array([[0, 0], [1, 0], [2, 0], [3, 0], [0, 1], [1, 1], [2, 1], [3, 1]], dtype=np.float64)
    quads = np.array([[0, 1, 5, 4], [2, 3, 7, 6]], dtype=np.int32)
    tris = np.array([[1, 2, 6], [1, 6, 5]], dtype=np.int32)
    lines = np.array([[0, 1], [1, 2], [2, 3], [3, 7], [7, 6], [6, 5], [5, 4], [4, 0]], dtype=np.int32)
    dom = polygon([(0, 0), (3, 0), (3, 1), (0, 1)])
    curves = np.zeros(8, dtype=np.int32)  # the polygon is one closed polyline
    fill = QuadFill(xy, quads, tris, lines, np.ones(8, dtype=np.int32), curves)
    out = chord_split(fill, dom, 100)
    # Quad A and B each crossed once (2 + 2), both triangles into three (3 + 3).
    assert len(out.triangles) == 0 and len(out.quads) == 10
    mesh = Mesh(out.points, {"quad": out.quads, "line": out.lines})
    mesh.validate()
    _check_all_quad(mesh)
    # Split boundary sides: 1-2 and 6-5 (triangle sides), 3-7 and 4-0 (chord ends).
    assert len(out.lines) == len(lines) + 4
    assert mesh.area() == pytest.approx(3.0)
    with pytest.raises(MeshingError, match="max_points = 12"):
        chord_split(fill, dom, 12)


def test_chords_keep_the_mesh_local_and_the_boundary_on_its_curves():
    # Which pairings leave triangles moves with the boundary discretisation: the first
    # of these that does is checked.
    for name in ("square with square hole graded", "square with hole", "naca 0012 far field graded"):
        dom, size, curves = CASES[name]
        fill, report = pair_domain(dom, as_size_field(size))
        if report.split:
            break
    else:
        pytest.skip("no pairing left a triangle; the chords are not exercised here")
    mixed, _ = pair_domain(dom, as_size_field(size), all_quad=False)
    assert len(fill.triangles) == 0
    # Far fewer quads than one midpoint split of every element would give.
    assert len(fill.quads) < 2 * (len(mixed.quads) + len(mixed.triangles))
    from meshwright.core.mesh import Mesh

    mesh = Mesh(fill.points, {"quad": fill.quads, "line": fill.lines})
    mesh.validate()
    _check_all_quad(mesh, curves)


def test_enhancement_counts_and_result_stay_convex():
    fill, report = pair_domain(circle(), as_size_field(0.1), smooth=0, all_quad=False)
    assert sum(report.eliminated) > 0
    assert all(_strictly_convex(fill.points, q) for q in fill.quads)


# ------------------------------------------------------------------ caps and doors


def test_registry_entry_declares_what_pairing_honours():
    m = QUAD_METHODS["pairing"]
    assert m.smooths and not m.needs_size and m.segments and m.points and m.regions


def test_cap_on_points_is_an_error_naming_it():
    # A callable size escapes the door's estimate of interior points: the front hits the cap.
    with pytest.raises(MeshingError, match="max_points = 300"):
        quadrangulate(circle(), lambda p: np.full(len(p), 0.05), method="pairing", max_points=300)


def test_bad_arguments_are_refused_at_the_door():
    with pytest.raises(InputError, match="smooth"):
        quadrangulate(circle(), 0.1, method="pairing", smooth=-1)
    # Region markers are honoured, region area bounds are not (a size field is the way).
    square = polygon([(0, 0), (1, 0), (1, 1), (0, 1)], regions=[(0.5, 0.5, 3, 0.01)])
    with pytest.raises(InputError, match=r"region 0 at \(0\.5, 0\.5\) has max_area 0\.01"):
        quadrangulate(square, 0.1, method="pairing")


def test_lower_level_doors_name_the_culprit():
    from meshwright.quad import QuadFill
    from meshwright.quad.chords import chord_split

    xy, tris = _strip()
    with pytest.raises(InputError, match="triangle 0 .* not counter-clockwise"):
        pair_triangles(xy, tris[:, ::-1])
    with pytest.raises(InputError, match="triangles row 1"):
        pair_triangles(xy, np.array([[1, 4, 3], [0, 1, 9]]))
    with pytest.raises(InputError, match="bounds"):
        pair_triangles(xy, tris, bounds=())
    with pytest.raises(InputError, match="boundary"):
        enhance(xy, np.array([[0, 1, 4, 3]]), np.zeros(3, dtype=bool))
    with pytest.raises(InputError, match="domain"):
        pair_domain("circle")
    with pytest.raises(InputError, match="all_quad"):
        pair_domain(circle(), 0.1, all_quad="yes")
    with pytest.raises(InputError, match="fill"):
        chord_split((xy, tris), circle(), 10)
    empty = np.zeros((0, 2), dtype=np.int32)
    fill = QuadFill(xy, np.zeros((0, 4), dtype=np.int32), tris, empty, np.zeros(0, np.int32), np.zeros(0, np.int32))
    with pytest.raises(InputError, match="max_points"):
        chord_split(fill, circle(), -1)


def test_interior_segment_and_point_are_kept():
    dom = polygon([(0, 0), (2, 0), (2, 1), (0, 1)], segments=[[(0.5, 0.5), (1.5, 0.5)]], points=[(1.0, 0.8)])
    mesh = quadrangulate(dom, 0.1, method="pairing", smooth=3)
    mesh.validate()
    xy = mesh.points
    assert np.any(np.all(xy == [1.0, 0.8], axis=1))
    lines = mesh.cells["line"]
    on_seg = np.all(np.abs(xy[lines][:, :, 1] - 0.5) < 1e-12, axis=1)
    assert on_seg.sum() >= 10
    assert all(_strictly_convex(xy, q) for q in mesh.cells["quad"])


def test_sliding_smoother_keeps_quads_convex_on_the_curve_and_the_minimum():
    """The enhancement's smoother (quad.smoothing.smooth_sliding) on an unsmoothed paired
    disk: connectivity kept, every quad still strictly convex (exact cross products),
    sliding nodes still on the circle, the fixed ones where they were, the smallest scaled
    Jacobian not lower, and something moved."""
    from meshwright.quad.smoothing import smooth_sliding

    fill, _ = pair_domain(circle(), as_size_field(0.1), smooth=0)
    xy, quads, lines = fill.points, fill.quads, fill.lines
    fixed = np.zeros(len(xy), dtype=bool)
    fixed[lines[0, 0]] = True
    def onto_circle(nodes, p, at):
        return p / np.hypot(*p.T)[:, None]

    moved = smooth_sliding(xy, quads, np.zeros((0, 3), np.int32), lines, fixed, onto_circle, 5)
    assert all(_strictly_convex(moved, q) for q in quads)
    on = np.unique(lines)
    np.testing.assert_allclose(np.hypot(*moved[on].T), 1.0, atol=1e-12)
    assert np.array_equal(moved[fixed], xy[fixed])
    assert _min_scaled_jacobian(moved, quads) >= _min_scaled_jacobian(xy, quads)
    inner = np.setdiff1d(np.arange(len(xy)), on)
    assert np.abs(moved[inner] - xy[inner]).max() > 1e-3
    assert np.abs(moved[on] - xy[on]).max() > 1e-4


def test_node_quads_lists_each_nodes_live_quads_in_order():
    rng = np.random.default_rng(5)
    quads = np.array([rng.choice(12, 4, replace=False) for _ in range(40)], dtype=np.int32)
    alive = (rng.random(40) < 0.7).astype(np.int8)
    off, idx = ek.node_quads(quads, alive, 13)
    for v in range(13):
        want = [q for q in range(40) if alive[q] and v in quads[q].tolist()]
        assert idx[off[v] : off[v + 1]].tolist() == want


def test_enhancement_worklist_decides_as_full_passes():
    """enhance() examines, after its first pass, only the quads next to the last pass's
    changes; the same passes over every quad (dirty flags reset to all) must give the same
    nodes and quads, on raw pairings of a disk and an airfoil with hundreds of operations."""
    from meshwright.quad.enhancement import ACCEPT, ENHANCE_PASSES, SWAP_GAIN

    cases = [(circle(), 0.05), (airfoil_in_farfield("0012", radius=3.0), 0.15)]
    for dom, h in cases:
        tri = mw.triangulate(dom, h, method="front")
        quads, _, left, t3, _, xy = pair_triangles(tri.points, tri.cells["triangle"], tri.cells["line"])
        bnd = np.zeros(len(xy), dtype=bool)
        bnd[tri.cells["line"].ravel()] = True
        xy_w, q_w, _, counts = enhance(xy, quads, bnd, t3[left])
        assert sum(counts) > 20
        # The same passes, every quad examined each time.
        p = xy.copy()
        qd = quads.copy()
        alive = np.ones(len(qd), dtype=np.int8)
        tri_node = np.zeros(len(p), dtype=np.int8)
        tri_node[t3[left].ravel()] = 1
        for _ in range(ENHANCE_PASSES):
            off, idx = ek.node_quads(qd, alive, len(p))
            got = ek.enhance_pass(
                p, qd, alive, bnd.astype(np.int8), off, idx, tri_node, ACCEPT, SWAP_GAIN, np.ones(len(qd), np.int8)
            )
            if sum(got) == 0:
                break
        assert np.array_equal(xy_w, p)
        assert np.array_equal(q_w, qd[alive == 1])


def test_sliding_nodes_stay_on_the_naca_section():
    """The enhancement's smoothing slides the airfoil's boundary nodes along the
    parametric NACA 0012 curve by Newton steps in its parameter: every one of them still
    satisfies the section's thickness formula (written out here: y = +-5 t (0.2969 sqrt x
    - 0.1260 x - 0.3516 x^2 + 0.2843 x^3 - 0.1036 x^4), t = 0.12, sharp trailing edge), and
    they did move along it (the mesh's airfoil nodes are not the discretisation's)."""
    dom, size, _ = CASES["naca 0012 far field graded"]
    mesh = quadrangulate(dom, size, method="pairing")
    v = np.unique(mesh.cells["line"])
    p = mesh.points[v]
    wall = p[(p[:, 0] > -1e-9) & (p[:, 0] < 1.0 + 1e-9) & (np.abs(p[:, 1]) < 0.2)]
    assert len(wall) > 50
    x = np.clip(wall[:, 0], 0.0, 1.0)
    yt = 0.6 * (0.2969 * np.sqrt(x) - 0.1260 * x - 0.3516 * x**2 + 0.2843 * x**3 - 0.1036 * x**4)
    np.testing.assert_allclose(np.abs(wall[:, 1]), yt, rtol=0, atol=1e-9)
    disc = dom.discretize(as_size_field(size)).points
    d = np.min(np.hypot(*(wall[:, None, :] - disc[None, :, :]).transpose(2, 0, 1)), axis=1)
    assert (d > 1e-6).sum() > len(wall) // 4


def test_curve_slider_keeps_nodes_that_do_not_move_and_follows_the_curve():
    """The slider (enhancement._CurveSlider) on the three-element airfoil's parametric
    curves: a zero step gives back every node where it is (its parameter found
    exactly), and a small step along the tangent lands on the curve at the parameter the
    step's arc length reaches (oracle: the curve evaluated at the nodes' own parameters)."""
    from meshwright.geometry import builtin
    from meshwright.geometry.curves import Parametric
    from meshwright.quad.enhancement import _CurveSlider

    dom = builtin("three-element")
    ids = [i for i, c in enumerate(dom.curves) if isinstance(c, Parametric)]
    assert ids
    rng = np.random.default_rng(3)
    for cid in ids:
        c = dom.curves[cid]
        span = c.t1 - c.t0
        t = np.sort(rng.uniform(c.t0 + 0.05 * span, c.t1 - 0.05 * span, 200))
        at = c.evaluate(t)
        nodes = np.arange(len(t))
        slider = _CurveSlider(dom, np.full(len(t), cid))
        np.testing.assert_allclose(slider(nodes, at.copy(), at), at, rtol=0, atol=1e-10)
        # A step to C(t + dt) itself, for a tiny dt, is reproduced to second order.
        dt = 1e-6 * span
        target = c.evaluate(t + dt)
        got = slider(nodes, target, at)
        np.testing.assert_allclose(got, target, rtol=0, atol=1e-9)


def test_curve_slider_with_known_parameters_searches_nothing():
    """Given the nodes' parameters (as the pairing passes the discretisation's), the slider
    never searches the curve (its ``project`` is made to fail here) and its trial
    positions agree with those of the searching slider; oracle: the curve evaluated at
    the parameters the test drew, and the tangent step computed here by hand."""
    from meshwright.geometry import builtin
    from meshwright.geometry.curves import Parametric
    from meshwright.quad.enhancement import _CurveSlider

    dom = builtin("three-element")
    cid = next(i for i, c in enumerate(dom.curves) if isinstance(c, Parametric))
    c = dom.curves[cid]
    span = c.t1 - c.t0
    t = np.sort(np.random.default_rng(5).uniform(c.t0 + 0.05 * span, c.t1 - 0.05 * span, 100))
    at = c.evaluate(t)
    nodes = np.arange(len(t))
    dt = 1e-5 * span
    target = c.evaluate(t + dt)
    searched = _CurveSlider(dom, np.full(len(t), cid))(nodes, target, at)
    known = _CurveSlider(dom, np.full(len(t), cid), at, t)

    def no_search(*a, **k):
        raise AssertionError("the slider searched the curve for a known parameter")

    c.project = no_search
    try:
        got = known(nodes, target, at)
    finally:
        del c.project
    # One Newton step of the distance from t along a central-difference tangent.
    h = 1e-7 * span
    tan = (c.evaluate(t + h) - c.evaluate(t - h)) / (2 * h)
    step = ((target - at) * tan).sum(axis=1) / (tan * tan).sum(axis=1)
    np.testing.assert_allclose(got, c.evaluate(t + step), rtol=0, atol=1e-12)
    np.testing.assert_allclose(got, searched, rtol=0, atol=1e-9)


def test_smooth_quads_refuses_parameters_of_the_wrong_shape():
    from meshwright.quad.enhancement import smooth_quads

    dom = circle()
    xy = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    quads = np.array([[0, 1, 2, 3]], dtype=np.int32)
    lines = np.array([[0, 1], [1, 2], [2, 3], [3, 0]], dtype=np.int32)
    with pytest.raises(InputError, match="params"):
        smooth_quads(xy, quads, np.zeros((0, 3), np.int32), lines, np.zeros(4, np.int64), dom, np.zeros(0, np.int64),
                     1, True, np.zeros(3))


def test_pairing_keeps_the_seam_node_of_a_closed_parametric_curve():
    """The NACA 0012 section is one closed parametric curve whose seam is the sharp
    trailing edge: the pairing's sliding keeps that node exactly where the
    discretisation put it (oracle: the section's formula gives x = 1, y = 0 there)."""
    dom = airfoil_in_farfield("0012")
    mesh = quadrangulate(dom, 0.1, method="pairing")
    p = mesh.points
    assert np.min(np.hypot(p[:, 0] - 1.0, p[:, 1])) <= 1e-15


@pytest.mark.parametrize("seed", [0, 5, 9])
def test_compact_nodes_keep_used_nodes_in_order(seed):
    """Unused nodes are dropped, the kept ones keep their order and coordinates, and every
    block is renumbered to the same points (oracle: np.unique over the blocks)."""
    rng = np.random.default_rng(seed)
    n = 50
    xy = rng.random((n, 2))
    quads = rng.integers(0, n, (12, 4)).astype(np.int32)
    tris = rng.integers(0, n, (3 * (seed % 2), 3)).astype(np.int32)
    lines = rng.integers(0, n, (5, 2)).astype(np.int32)
    pts, q, t, ln, remap = pk.compact_nodes(xy, quads, tris.reshape(-1, 3), lines)
    used = np.unique(np.concatenate([quads.ravel(), tris.ravel(), lines.ravel()]))
    assert len(used) < n  # some node is dropped
    assert np.array_equal(pts, xy[used])
    for new, old in ((q, quads), (t, tris.reshape(-1, 3)), (ln, lines)):
        assert new.dtype == np.int32 and np.array_equal(pts[new], xy[old])
    assert remap.tolist() == [int(np.searchsorted(used, v)) if v in used else -1 for v in range(n)]


@pytest.mark.parametrize("seed", [1, 4, 12])
def test_mate_sides_are_the_pairs_entries_of_a_dictionary_table(seed):
    """For a pairing made elsewhere, side k of t holds its partner exactly where the
    partner runs that side the other way and the edge is not blocked (oracle: a dictionary
    of directed edges), -1 everywhere else."""
    rng, xy, tris, nbr, raw = _random_delaunay(seed, 30, 60)
    n, nt = len(xy), len(tris)
    mate = np.full(nt, -1, dtype=np.int32)
    pk.greedy_pairs(raw, nbr.ravel(), mate, -1.0)
    # A few pairs that share no side, and blocked edges (some of them pairs' sides).
    for t, s in ((0, nt - 1), (1, nt - 2)):
        if mate[t] < 0 and mate[s] < 0 and s not in nbr[t]:
            mate[t], mate[s] = s, t
    edges = {(int(r[(k + 1) % 3]), int(r[(k + 2) % 3])): (i, k) for i, r in enumerate(tris) for k in range(3)}
    blocked = {(min(e), max(e)) for e in edges if rng.random() < 0.3}
    bkey = np.array(sorted(a * n + b for a, b in blocked), dtype=np.int64)
    got = pk.mate_sides(tris.ravel(), mate, n, bkey).reshape(-1, 3)
    for (u, w), (t, k) in edges.items():
        twin = edges.get((w, u))
        want = int(mate[t]) if twin and twin[0] == mate[t] >= 0 and (min(u, w), max(u, w)) not in blocked else -1
        assert got[t, k] == want
    assert (got >= 0).any() and any(mate[t] >= 0 and (got[t] < 0).all() for t in range(nt))
