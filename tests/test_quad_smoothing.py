"""The guarded smoother's kernels (quad/smoothing.py) against independent oracles:
exact rational orientation (``fractions.Fraction``) for the filtered convexity test, and a
plain Python Gauss-Seidel sweep for the sliding smoother's interior moves."""

import math
from fractions import Fraction

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from meshwright.quad import smoothing as sm


def _orient(p, q, r):
    """Exact sign of the orientation of p, q, r (rationals)."""
    (ax, ay), (bx, by), (cx, cy) = ([Fraction(float(x)) for x in u] for u in (p, q, r))
    det = (ax - cx) * (by - cy) - (ay - cy) * (bx - cx)
    return (det > 0) - (det < 0)


# Coordinates 0 or of magnitude >= 1e-60, perturbations >= 1e-17: the products stay clear
# of underflow, the predicates' documented range (core/predicates.py).
_coord = st.floats(-10, 10).filter(lambda x: x == 0.0 or abs(x) >= 1e-60)


@settings(max_examples=200, deadline=None)
@given(
    _coord, _coord, _coord, _coord,
    st.floats(-2, 3).filter(lambda x: x == 0.0 or abs(x) >= 1e-60),
    st.sampled_from([0.0, 1e-17, 1e-15, 1e-12, 1e-3]), st.booleans(),
)
def test_filtered_convexity_is_exact(ax, ay, bx, by, t, tiny, up):
    """``_measure_xy``'s convexity (the sine pass's cross product certified by Shewchuk's bound, else the
    adaptive ``orient2d``) against the exact rational sign, on corners from collinear to
    clearly turned."""
    dx = ax + t * (bx - ax) + (tiny if up else -tiny)
    dy = ay + t * (by - ay) - (tiny if up else -tiny)
    pts = np.array([[ax, ay], [bx, by], [dx, dy]])
    for a, b, d in ((0, 1, 2), (1, 2, 0), (2, 0, 1), (0, 2, 1)):
        _, got = sm._measure_xy(*pts[a], *pts[b], *pts[d])
        assert got == (_orient(pts[a], pts[b], pts[d]) > 0)


def _grid(seed, k, jitter):
    rng = np.random.default_rng(seed)
    gx, gy = np.meshgrid(np.arange(k + 1.0), np.arange(k + 1.0), indexing="ij")
    xy = np.column_stack([gx.ravel(), gy.ravel()])
    inner = (xy[:, 0] > 0) & (xy[:, 0] < k) & (xy[:, 1] > 0) & (xy[:, 1] < k)
    xy[inner] += rng.uniform(-jitter, jitter, (int(inner.sum()), 2))
    idx = lambda i, j: i * (k + 1) + j
    quads = np.array([[idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)] for i in range(k) for j in range(k)])
    return xy, quads, inner


def _measure(p, c, n):
    """The guard's corner quality, from ``math`` and rationals: the sine of a strictly
    convex corner; else the sine from 180 to 270 degrees, then -2 + |sine| up to 360
    (falling with the angle over the reflex range); -2 for a degenerate corner."""
    ux, uy, wx, wy = n[0] - c[0], n[1] - c[1], p[0] - c[0], p[1] - c[1]
    den = math.sqrt((ux * ux + uy * uy) * (wx * wx + wy * wy))
    sine = (ux * wy - uy * wx) / den if den > 0 else -1.0
    if _orient(p, c, n) > 0:
        return sine
    if den == 0:
        return -2.0
    return min(sine, 0.0) if ux * wx + uy * wy <= 0 else -2.0 + abs(sine)


def _kernel_centroid(pts, star, v):
    """Centroid of the region where every corner of v's star that v changes is convex,
    by SciPy (a Chebyshev centre by linear programming, the half-spaces' intersection,
    its hull's area centroid), within the star's bounding box, relative to v; None if the
    region has no interior."""
    from scipy.optimize import linprog
    from scipy.spatial import ConvexHull, HalfspaceIntersection

    x0, y0 = pts[v]
    rows = []  # a x + b y + c <= 0 (SciPy's form) for the half-planes (X - u) x (Y - u) > 0
    for q in star[v]:
        i, m = q.index(v), len(q)
        for k in range(m):
            if m == 4 and k == (i + 2) % 4:
                continue  # the corner opposite v
            a, b, d = q[k - 1], q[k], q[(k + 1) % m]
            x, y = (d, a) if b == v else ((b, d) if a == v else (a, b))  # orient(v, x, y)
            X = (pts[x][0] - x0, pts[x][1] - y0)
            Y = (pts[y][0] - x0, pts[y][1] - y0)
            # X x Y + u_x (X_y - Y_y) - u_y (X_x - Y_x) > 0
            rows.append([-(X[1] - Y[1]), (X[0] - Y[0]), -(X[0] * Y[1] - X[1] * Y[0])])
    ring = [w for q in star[v] for w in q]
    lo = np.min([[pts[w][0] - x0, pts[w][1] - y0] for w in ring] + [[0.0, 0.0]], axis=0)
    hi = np.max([[pts[w][0] - x0, pts[w][1] - y0] for w in ring] + [[0.0, 0.0]], axis=0)
    rows += [[-1, 0, lo[0]], [1, 0, -hi[0]], [0, -1, lo[1]], [0, 1, -hi[1]]]
    h = np.array(rows, dtype=float)
    norm = np.hypot(h[:, 0], h[:, 1])
    lp = linprog([0, 0, -1], A_ub=np.column_stack([h[:, :2], norm]), b_ub=-h[:, 2], bounds=[(None, None)] * 2 + [(0, None)])
    if lp.status != 0 or lp.x[2] <= 1e-9 * max(hi - lo):
        return None
    corners = HalfspaceIntersection(h, lp.x[:2]).intersections
    hull = ConvexHull(corners)
    ring = corners[hull.vertices]
    x, y = ring[:, 0], ring[:, 1]
    w = x * np.roll(y, -1) - np.roll(x, -1) * y
    area = w.sum() / 2
    return (x0 + ((x + np.roll(x, -1)) * w).sum() / (6 * area), y0 + ((y + np.roll(y, -1)) * w).sum() / (6 * area))


@settings(max_examples=10, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([0.0, 0.01]))
def test_sliding_interior_sweeps_match_a_python_sweep(seed, settle):
    """smooth_sliding without boundary lines: its interior sweeps (corner table, active
    set, worst corner first, filtered exact convexity, the kernel's centroid for a bad
    star) against a Python Gauss-Seidel sweep that recomputes every corner with ``math``,
    decides convexity by rationals and finds the kernel with SciPy.  The rule: a full,
    else a half step to the neighbours' mean, else (a star worse than ``UNTANGLE``) the
    kernel's centroid, kept if no convex corner of the star turns and no corner falls
    below the star's worst before.  The jitter leaves some quads non-convex."""
    xy, quads, inner = _grid(seed, 6, 0.45)
    lines = np.zeros((0, 2), np.int64)
    got = sm.smooth_sliding(xy, quads, np.zeros((0, 3), np.int64), lines, ~inner, None, 4, settle)

    ql = quads.tolist()
    star = {v: [q for q in ql if v in q] for v in range(len(xy))}
    nbrs = {}
    for v in range(len(xy)):
        nbrs[v] = []
        for q in star[v]:
            for w in (q[(q.index(v) + 1) % 4], q[(q.index(v) + 3) % 4]):
                if w not in nbrs[v]:
                    nbrs[v].append(w)
    pts = [list(p) for p in xy.tolist()]

    def corners(v):
        return [_measure(pts[q[i - 1]], pts[q[i]], pts[q[(i + 1) % 4]]) for q in star[v] for i in range(4)]

    def convex(v):
        return [_orient(pts[q[i - 1]], pts[q[i]], pts[q[(i + 1) % 4]]) > 0 for q in star[v] for i in range(4)]

    last, now = [True] * len(pts), [False] * len(pts)
    for _ in range(4):
        for v in np.flatnonzero(inner).tolist():
            if settle and not (last[v] or now[v] or any(last[w] or now[w] for w in nbrs[v])):
                continue
            tx = sum(pts[w][0] for w in nbrs[v]) / len(nbrs[v])
            ty = sum(pts[w][1] for w in nbrs[v]) / len(nbrs[v])
            x0, y0 = pts[v]
            before = min(corners(v) + [1.0])
            was = convex(v)
            trials = [(x0 + s * (tx - x0), y0 + s * (ty - y0)) for s in (1.0, 0.5)]
            if before < sm.UNTANGLE:
                trials.append("kernel")
            for t in trials:
                if t == "kernel":
                    pts[v] = [x0, y0]
                    t = _kernel_centroid(pts, star, v)
                    if t is None:
                        break
                pts[v] = list(t)
                if min(corners(v)) >= before and all(c or not w for c, w in zip(convex(v), was)):
                    w = nbrs[v][0]
                    if settle and (pts[v][0] - x0) ** 2 + (pts[v][1] - y0) ** 2 > settle**2 * (
                        (pts[w][0] - x0) ** 2 + (pts[w][1] - y0) ** 2
                    ):
                        now[v] = True
                    break
                pts[v] = [x0, y0]
        last, now = now, [False] * len(pts)
    assert np.allclose(got, np.array(pts), rtol=0, atol=1e-9)
    assert np.abs(got - xy).max() > 1e-3


def test_sliding_jitter_makes_nonconvex_quads():
    """The jitter of the sweep test above does produce non-convex quads (so that test
    exercises the exact convexity guard), checked on a few seeds."""
    found = 0
    for seed in range(5):
        xy, quads, _ = _grid(seed, 6, 0.45)
        for q in quads.tolist():
            found += not all(_orient(xy[q[i - 1]], xy[q[i]], xy[q[(i + 1) % 4]]) > 0 for i in range(4))
    assert found > 0


def test_tangled_stars_open():
    """Grid vertices pushed through their neighbours leave folded and reflex quads that no
    Laplacian step of one vertex makes all convex; the sliding smoother (exact guard with
    the kernel's centroid) opens every one, never turns a convex corner, and never lowers
    a star's worst corner quality (checked with rationals and ``math``)."""
    for seed in range(6):
        xy, quads, inner = _grid(seed, 6, 0.1)
        rng = np.random.default_rng(seed)
        ids = np.flatnonzero(inner)
        for v in rng.choice(ids, 3, replace=False):
            xy[v] += rng.choice([-1.0, 1.0], 2) * rng.uniform(0.9, 1.4, 2)
        ql = quads.tolist()
        bad = [q for q in ql if not all(_orient(xy[q[i - 1]], xy[q[i]], xy[q[(i + 1) % 4]]) > 0 for i in range(4))]
        assert bad
        lines = np.zeros((0, 2), np.int64)
        got = sm.smooth_sliding(xy, quads, np.zeros((0, 3), np.int64), lines, ~inner, None, 6)
        for q in ql:
            assert all(_orient(got[q[i - 1]], got[q[i]], got[q[(i + 1) % 4]]) > 0 for i in range(4)), (seed, q)
        worst = min(_measure(xy[q[i - 1]], xy[q[i]], xy[q[(i + 1) % 4]]) for q in ql for i in range(4))
        after = min(_measure(got[q[i - 1]], got[q[i]], got[q[(i + 1) % 4]]) for q in ql for i in range(4))
        assert after >= worst


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_cell_tables_match_dictionaries(seed):
    """cell_tables against lists built cell by cell: each vertex's cells in index order,
    and its edge neighbours in the order the Laplacian sums them (its cells in order, in
    each the next corner, then the previous one, each neighbour once, first appearance),
    on quads and triangles sharing vertices in random order."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(5, 40))
    quads = np.array([rng.choice(n, 4, replace=False) for _ in range(int(rng.integers(0, 30)))], np.int64).reshape(-1, 4)
    tris = np.array([rng.choice(n, 3, replace=False) for _ in range(int(rng.integers(0, 30)))], np.int64).reshape(-1, 3)
    cells, cell_ptr, cell_idx, nbr_ptr, nbr_idx = sm.cell_tables(np.zeros((n, 2)), quads, tris)
    rows = [list(q) for q in quads.tolist()] + [list(t) for t in tris.tolist()]
    for v in range(n):
        mine = [c for c, row in enumerate(rows) if v in row]
        assert cell_idx[cell_ptr[v] : cell_ptr[v + 1]].tolist() == mine
        want = []
        for c in mine:
            row = rows[c]
            i = row.index(v)
            for w in (row[(i + 1) % len(row)], row[i - 1]):
                if w not in want:
                    want.append(w)
        assert nbr_idx[nbr_ptr[v] : nbr_ptr[v + 1]].tolist() == want
    assert cell_idx.dtype == np.int32 and nbr_idx.dtype == np.int32
    assert cells[len(quads) :, 3].tolist() == [-1] * len(tris)


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_corner_table_matches_python_corners(seed):
    """The corner table (sines, and with ``exact`` the convexity flags) against each
    corner recomputed in Python floats (sine: cross product over the root of the squared
    sides' product, -1 when degenerate) and rational orientation, on random quads and
    triangles with repeated and collinear corners; a triangle's unused slot is 1."""
    rng = np.random.default_rng(seed)
    n = 12
    xy = rng.integers(-3, 4, (n, 2)).astype(float) * rng.choice([1.0, 0.1, 1e-7])
    quads = rng.integers(0, n, (int(rng.integers(0, 12)), 4))
    tris = rng.integers(0, n, (int(rng.integers(0, 12)), 3))
    cells = sm.cell_tables(xy, quads, tris)[0]
    cs0, cv0 = sm._corner_table(xy, cells, np.bool_(False))
    cs1, cv1 = sm._corner_table(xy, cells, np.bool_(True))
    assert cv0.shape == (0, 4)
    for c, row in enumerate([list(q) for q in quads.tolist()] + [list(t) for t in tris.tolist()]):
        for k in range(4):
            if k >= len(row):
                assert cs0[c, k] == 1.0 and cs1[c, k] == 1.0 and cv1[c, k] == 1
                continue
            a, b, d = xy[row[k - 1]], xy[row[k]], xy[row[(k + 1) % len(row)]]
            ux, uy, wx, wy = d[0] - b[0], d[1] - b[1], a[0] - b[0], a[1] - b[1]
            den = math.sqrt((ux * ux + uy * uy) * (wx * wx + wy * wy))
            sine = (ux * wy - uy * wx) / den if den > 0.0 else -1.0
            assert cs0[c, k] == sine
            convex = _orient(a, b, d) > 0
            assert cv1[c, k] == (1 if convex else 0)
            if convex:
                assert cs1[c, k] == sine
            else:
                assert cs1[c, k] <= 0.0
