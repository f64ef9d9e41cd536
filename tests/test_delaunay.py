"""Tests of the 2-D Delaunay triangulation (Bowyer and Watson insertion, meshwright.tri).

Every triangulation is checked against exact predicates and independently computed
properties: strict counter-clockwise triangles, empty circumcircles across every interior
edge, symmetric neighbours, every point a vertex, Euler's count, the area of an
independently computed convex hull, and the hull loop itself.
"""

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numba import njit

from meshwright.core.errors import DegenerateInputError, DuplicatePointError, InputError
from meshwright.core.predicates import incircle, orient2d
from meshwright.tri import DELAUNAY_ALGORITHMS, Triangulation, delaunay

ALGORITHMS = sorted(DELAUNAY_ALGORITHMS)


# ----------------------------------------------------------------------------- checkers
@njit(cache=True)
def _defects(pts, tri, nbr):
    """Counts of (non-ccw triangles, asymmetric neighbours, Delaunay violations), exact."""
    bad_ccw = 0
    bad_nbr = 0
    bad_del = 0
    for t in range(tri.shape[0]):
        a, b, c = tri[t, 0], tri[t, 1], tri[t, 2]
        if orient2d(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[c, 0], pts[c, 1]) <= 0.0:
            bad_ccw += 1
        for k in range(3):
            n = nbr[t, k]
            if n < 0:
                continue
            u, w = tri[t, (k + 1) % 3], tri[t, (k + 2) % 3]
            j = -1
            for i in range(3):
                if nbr[n, i] == t:
                    j = i
            if j < 0 or tri[n, (j + 1) % 3] != w or tri[n, (j + 2) % 3] != u:
                bad_nbr += 1
                continue
            d = tri[n, j]
            if incircle(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[c, 0], pts[c, 1], pts[d, 0], pts[d, 1]) > 0.0:
                bad_del += 1
    return bad_ccw, bad_nbr, bad_del


def _orient(p, q, r):
    """Exact sign of the orientation of p, q, r: a float filter, exact rationals when unsure.

    Independent of ``core.predicates`` (the oracle for the hull and for collinearity); the
    filter only answers when the products are normal doubles and the error bound is met.
    """
    left = (q[0] - p[0]) * (r[1] - p[1])
    right = (q[1] - p[1]) * (r[0] - p[0])
    bound = 1e-15 * (abs(left) + abs(right))
    if bound > 1e-290 and abs(left - right) > bound:
        return 1 if left > right else -1
    px, py, qx, qy, rx, ry = (Fraction(float(c)) for c in (p[0], p[1], q[0], q[1], r[0], r[1]))
    d = (qx - px) * (ry - py) - (qy - py) * (rx - px)
    return (d > 0) - (d < 0)


def _locally_delaunay_exact(pts, tri, nbr):
    """Whether every triangle is ccw and every interior edge locally Delaunay, in rationals."""
    q = [(Fraction(float(x)), Fraction(float(y))) for x, y in pts]
    for t in range(len(tri)):
        a, b, c = (q[i] for i in tri[t])
        if (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) <= 0:
            return False
        for k in range(3):
            n = nbr[t, k]
            if n < 0:
                continue
            d = q[int(tri[n][np.flatnonzero(nbr[n] == t)[0]])]
            rows = [(u[0] - d[0], u[1] - d[1]) for u in (a, b, c)]
            (ax, ay), (bx, by), (cx, cy) = rows
            al, bl, cl = (x * x + y * y for x, y in rows)
            if al * (bx * cy - by * cx) - bl * (ax * cy - ay * cx) + cl * (ax * by - ay * bx) > 0:
                return False
    return True


def _convex_hull(pts):
    """Monotone chain keeping collinear boundary points, exact orientation; ccw loop."""
    idx = sorted(range(len(pts)), key=lambda i: (pts[i, 0], pts[i, 1]))

    def chain(seq):
        h = []
        for i in seq:
            while len(h) >= 2 and _orient(pts[h[-2]], pts[h[-1]], pts[i]) < 0:
                h.pop()
            h.append(i)
        return h

    return chain(idx)[:-1] + chain(idx[::-1])[:-1]


def _rotate_to_min(loop):
    loop = list(loop)
    i = loop.index(min(loop))
    return loop[i:] + loop[:i]


def _polygon_area(p):
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def check(tr, inp):
    """Assert that ``tr`` is a valid Delaunay triangulation of the input points ``inp``."""
    inp = np.asarray(inp, dtype=float)
    pts, tri, nbr = tr.points, tr.triangles, tr.neighbors
    nv, nt = len(pts), len(tri)
    # Every input point is a vertex; vertices are distinct input points.
    assert tr.index_map.shape == (len(inp),) and tr.index_map.dtype == np.int32
    assert np.array_equal(pts[tr.index_map], inp)
    assert len(np.unique(pts, axis=0)) == nv == len(np.unique(inp, axis=0))
    assert tri.dtype == np.int32 and nbr.dtype == np.int32 and tri.shape == nbr.shape == (nt, 3)
    assert np.array_equal(np.unique(tri), np.arange(nv))
    bad_ccw, bad_nbr, bad_del = _defects(pts, tri, nbr)
    assert (bad_ccw, bad_nbr, bad_del) == (0, 0, 0)
    # Hull: independent convex hull with collinear points, Euler count, area.
    hull = _convex_hull(pts)
    assert _rotate_to_min(tr.hull) == _rotate_to_min(hull)
    assert tr.hull.dtype == np.int32
    h = len(hull)
    assert nt == 2 * nv - h - 2
    assert int((nbr < 0).sum()) == h
    a, b, c = pts[tri[:, 0]], pts[tri[:, 1]], pts[tri[:, 2]]
    areas = 0.5 * ((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
    hull_area = _polygon_area(pts[hull] - pts[hull].mean(axis=0))
    # Centring (for large offsets) rounds away areas far below the extent squared.
    extent = float(np.ptp(pts, axis=0).max())
    assert np.isclose(areas.sum(), hull_area, rtol=1e-9, atol=1e-12 * extent**2)
    # Edges: each once, Euler's formula.
    e = tr.edges
    assert e.dtype == np.int32 and len(e) == 3 * nv - h - 3 == len(np.unique(e, axis=0))
    assert np.all(e[:, 0] < e[:, 1])


def tri_set(tr):
    return {tuple(sorted(map(int, t))) for t in tr.triangles}


def is_degenerate(pts):
    """Fewer than three distinct points or all collinear (exact)."""
    u = np.unique(np.asarray(pts, dtype=float), axis=0)
    if len(u) < 3:
        return True
    return all(_orient(u[0], u[1], u[i]) == 0 for i in range(2, len(u)))


def check_both(pts, seed=0):
    """Triangulate with every algorithm; check each and that they are identical."""
    if is_degenerate(pts):
        for alg in ALGORITHMS:
            with pytest.raises(DegenerateInputError):
                delaunay(pts, algorithm=alg, seed=seed)
        return None
    trs = [delaunay(pts, algorithm=alg, seed=seed) for alg in ALGORITHMS]
    check(trs[0], pts)
    for tr in trs[1:]:
        assert np.array_equal(tr.triangles, trs[0].triangles)
        assert np.array_equal(tr.neighbors, trs[0].neighbors)
        assert np.array_equal(tr.index_map, trs[0].index_map)
    return trs[0]


# ----------------------------------------------------------------------------- fixed inputs
@pytest.mark.parametrize("n", [3, 4, 10, 100, 3000])
def test_random_matches_scipy(n):
    spatial = pytest.importorskip("scipy.spatial")
    pts = np.random.default_rng(n).random((n, 2))
    tr = check_both(pts)
    assert tri_set(tr) == {tuple(sorted(s)) for s in spatial.Delaunay(pts).simplices}


def test_larger_random_matches_scipy_and_watson():
    spatial = pytest.importorskip("scipy.spatial")
    pts = np.random.default_rng(11).normal(size=(30000, 2))
    tr = check_both(pts)
    assert tri_set(tr) == {tuple(sorted(s)) for s in spatial.Delaunay(pts).simplices}


def test_square_grid_cocircular():
    x, y = np.meshgrid(np.arange(25.0), np.arange(19.0))
    check_both(np.column_stack([x.ravel(), y.ravel()]), seed=3)


def test_pythagorean_circle_exactly_cocircular():
    # 12 integer points on the circle of radius 5 and its centre-less interior: all cocircular.
    base = [(3, 4), (4, 3), (5, 0), (0, 5)]
    pts = {(sx * a, sy * b) for a, b in base for sx in (1, -1) for sy in (1, -1)}
    pts = np.array(sorted(pts), dtype=float)
    tr = check_both(pts)
    assert len(tr.hull) == 12
    check_both(np.vstack([pts, [[0.0, 0.0]]]))


def test_points_on_circle():
    t = 2 * np.pi * np.arange(500) / 500
    check_both(np.column_stack([np.cos(t), np.sin(t)]), seed=1)


def test_collinear_hull_points_are_vertices():
    side = np.linspace(0, 1, 11)
    pts = np.vstack(
        [np.column_stack([side, 0 * side]), np.column_stack([side, 0 * side + 1]),
         np.column_stack([0 * side, side]), np.column_stack([0 * side + 1, side]), [[0.5, 0.5]]]
    )
    tr = check_both(pts)
    assert len(tr.hull) == 40


@pytest.mark.parametrize("offset, scale", [(1e9, 1.0), (0.0, 1e-9), (-1e9, 1e-3)])
def test_extreme_offsets_and_scales(offset, scale):
    rng = np.random.default_rng(5)
    check_both(offset + scale * rng.random((400, 2)))
    x, y = np.meshgrid(np.arange(12.0), np.arange(9.0))
    check_both(offset + scale * np.column_stack([x.ravel(), y.ravel()]))


@pytest.mark.parametrize("kind", ["random", "grid"])
def test_below_the_exact_range_is_refused_not_called_collinear(kind):
    # At 1e-290 the products in orient2d underflow to zero, so an oracle built on orient2d
    # would agree with a wrong "all collinear".  Exact rationals say these points are not
    # collinear: the door must refuse them by range (test_doors.py checks the message).
    if kind == "random":
        pts = 1e-300 + 1e-290 * np.random.default_rng(5).random((200, 2))
    else:
        x, y = np.meshgrid(np.arange(12.0), np.arange(9.0))
        pts = 1e-300 + 1e-290 * np.column_stack([x.ravel(), y.ravel()])
    assert not is_degenerate(pts)
    for alg in ALGORITHMS:
        with pytest.raises(InputError, match="range") as info:
            delaunay(pts, algorithm=alg)
        assert not isinstance(info.value, DegenerateInputError)
    # Scaled by a power of two (exact) into the range, as the message advises, they
    # triangulate; checked in rationals.
    tr = check_both(pts * 2.0**900)
    assert _locally_delaunay_exact(tr.points, tr.triangles, tr.neighbors)


def test_seed_changes_nothing_but_slots():
    pts = np.random.default_rng(0).random((500, 2))
    assert tri_set(delaunay(pts, seed=1)) == tri_set(delaunay(pts, seed=2))
    assert np.array_equal(delaunay(pts, seed=4).triangles, delaunay(pts, seed=4).triangles)
    rng = np.random.default_rng(9)
    assert tri_set(delaunay(pts, seed=rng)) == tri_set(delaunay(pts))


# ----------------------------------------------------------------------------- hypothesis
# As in test_predicates: magnitudes below 1e-30 are flushed to zero, since the predicates'
# exactness contract excludes underflow (and hypothesis loves 5e-278 beside 1.0).
coord = st.floats(-1e3, 1e3, allow_nan=False, allow_infinity=False).map(lambda x: 0.0 if abs(x) < 1e-30 else x)


@settings(deadline=None)
@given(st.lists(st.tuples(coord, coord), min_size=3, max_size=60), st.integers(0, 3))
def test_hypothesis_random_points(pts, seed):
    check_both(np.array(pts), seed)


@settings(deadline=None)
@given(st.lists(st.tuples(st.integers(0, 6), st.integers(0, 6)), min_size=3, max_size=60), st.integers(0, 3))
def test_hypothesis_integer_grid(pts, seed):
    check_both(np.array(pts, dtype=float), seed)


@settings(deadline=None)
@given(st.integers(3, 80), st.floats(1e-6, 1e6), st.integers(0, 3))
def test_hypothesis_circle(k, r, seed):
    t = 2 * np.pi * np.arange(k) / k
    check_both(r * np.column_stack([np.cos(t), np.sin(t)]), seed)


@settings(deadline=None)
@given(
    st.lists(st.integers(-50, 50), min_size=2, max_size=40),
    st.tuples(st.integers(-5, 5), st.integers(-5, 5)).filter(lambda d: d != (0, 0)),
    st.tuples(st.integers(-60, 60), st.integers(-60, 60)),
    st.integers(0, 3),
)
def test_hypothesis_collinear_plus_one(ts, d, extra, seed):
    line = np.array([(t * d[0], t * d[1]) for t in ts], dtype=float)
    check_both(np.vstack([line, [extra]]), seed)


@settings(deadline=None)
@given(st.integers(3, 200), st.sampled_from([(1e9, 1.0), (0.0, 1e-9), (1e9, 1e-6)]), st.integers(0, 2**31))
def test_hypothesis_offsets(n, off_scale, seed):
    offset, scale = off_scale
    pts = offset + scale * np.random.default_rng(seed).random((n, 2))
    check_both(pts, seed % 4)


# ----------------------------------------------------------------------------- insert / locate
@pytest.mark.parametrize("algorithm", ALGORITHMS)
def test_insert_matches_batch(algorithm):
    pts = np.random.default_rng(2).random((2000, 2)) * 4 - 1
    tr = delaunay(pts[:100], algorithm=algorithm)
    held = tr.triangles
    before = held.copy()
    ids = tr.insert(pts[100:1500])
    assert np.array_equal(held, before)  # arrays handed out never change
    assert np.array_equal(ids, np.arange(100, 1500))
    for i in range(1500, 2000, 50):
        assert np.array_equal(tr.insert(pts[i:i + 50]), np.arange(i, i + 50))
    tr.index_map = np.arange(2000, dtype=np.int32)  # check() relates vertices to all points
    check(tr, pts)
    assert tri_set(tr) == tri_set(delaunay(pts))


def test_insert_outside_hull_duplicates_and_single_points():
    grid = np.array([[0, 0], [1, 0], [0, 1], [1, 1]], dtype=float)
    tr = delaunay(grid)
    assert tr.insert([0.5, 0.5]).tolist() == [4]
    assert tr.insert([[1, 1], [3, 3], [3, 3], [0.5, 0.5], [2, 0]]).tolist() == [3, 5, 5, 4, 6]
    assert tr.insert(np.empty((0, 2))).shape == (0,)
    allpts = np.array([[0, 0], [1, 0], [0, 1], [1, 1], [0.5, 0.5], [3, 3], [2, 0]], dtype=float)
    tr.index_map = np.arange(7, dtype=np.int32)
    check(tr, allpts)
    # Onto a hull edge, and collinear beyond a hull vertex.
    tr.insert([[1.5, 0], [4, 4]])
    assert {8, 7} <= set(tr.hull.tolist())


@pytest.mark.parametrize("algorithm", ALGORITHMS)
def test_insert_cocircular_grid_incrementally(algorithm):
    x, y = np.meshgrid(np.arange(8.0), np.arange(8.0))
    pts = np.column_stack([x.ravel(), y.ravel()])
    tr = delaunay(pts[::3], algorithm=algorithm, seed=5)
    rest = np.delete(pts, np.arange(0, len(pts), 3), axis=0)
    for p in rest:
        tr.insert(p)
    tr.index_map = np.arange(len(tr.points), dtype=np.int32)
    check(tr, tr.points)


def test_locate():
    pts = np.random.default_rng(4).random((300, 2))
    tr = delaunay(pts)
    q = np.random.default_rng(5).random((500, 2)) * 1.4 - 0.2
    found = tr.locate(q)
    assert found.shape == (500,) and found.dtype == np.int32
    tri, p = tr.triangles, tr.points
    for (x, y), t in zip(q, found):
        if t >= 0:
            a, b, c = p[tri[t]]
            assert min(_orient(a, b, (x, y)), _orient(b, c, (x, y)), _orient(c, a, (x, y))) >= 0
        else:
            hull = p[tr.hull]
            assert any(_orient(hull[i], hull[(i + 1) % len(hull)], (x, y)) < 0 for i in range(len(hull)))
    assert [tr.locate(xy) for xy in q[:20]] == found[:20].tolist()
    for v in (0, 17, int(tr.hull[0])):
        assert v in tri[tr.locate(p[v])]


def test_to_mesh():
    pts = np.random.default_rng(6).random((50, 2))
    tr = delaunay(pts)
    mesh = tr.to_mesh()
    assert np.array_equal(mesh.cells_of("triangle"), tr.triangles)
    mesh.validate()


# ----------------------------------------------------------------------------- errors
@pytest.mark.parametrize(
    "bad, error, match",
    [
        ([[0, 0], [1, 0], [np.nan, 1]], InputError, "point 2"),
        ([[0, 0], [1, 0], [0, np.inf]], InputError, "point 2"),
        (np.zeros((4, 3)), InputError, "shape"),
        (np.zeros(6), InputError, "shape"),
        ([[0, 0], [1, "x"], [0, 1]], InputError, "numbers"),
        ([[0, 0], [1, 0]], DegenerateInputError, "at least 3"),
        ([[0, 0], [1, 1], [2, 2], [3, 3]], DegenerateInputError, "collinear"),
        ([[1, 2]] * 5, DegenerateInputError, "coincide"),
        ([[0, 0], [0, 0], [1, 1], [1, 1]], DegenerateInputError, "collinear"),
    ],
)
def test_errors(bad, error, match):
    with pytest.raises(error, match=match):
        delaunay(bad)


def test_bad_options():
    pts = np.random.default_rng(0).random((5, 2))
    with pytest.raises(InputError, match="algorithm"):
        delaunay(pts, algorithm="lawson")
    with pytest.raises(InputError, match="duplicates"):
        delaunay(pts, duplicates="keep")
    with pytest.raises(InputError, match="shape"):
        delaunay(pts).insert(np.zeros((2, 3)))


def test_duplicates_reject_and_merge():
    pts = np.array([[0, 0], [1, 0], [0.25, 0.75], [1, 0], [0, 1], [0, 0], [1, 0]], dtype=float)
    with pytest.raises(DuplicatePointError, match=r"1 and 3 at \[1.0, 0.0\]|0 and 5 at \[0.0, 0.0\]"):
        delaunay(pts, duplicates="reject")
    for alg in ALGORITHMS:
        tr = delaunay(pts, algorithm=alg)
        check(tr, pts)
        assert len(tr.points) == 4
        im = tr.index_map
        assert im[1] == im[3] == im[6] and im[0] == im[5] and len(set(im.tolist())) == 4


def test_triangulation_class_is_delaunay():
    pts = np.random.default_rng(8).random((40, 2))
    assert tri_set(Triangulation(pts)) == tri_set(delaunay(pts))
    assert "40 points" in repr(Triangulation(pts, algorithm="watson"))
