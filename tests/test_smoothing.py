"""Spring-analogy smoothing: validity, boundary sliding, quality never worse where it counts."""

import numpy as np
import pytest

import meshwright as mw
from meshwright.core.errors import InputError
from meshwright.core.predicates import orient2d_batch
from meshwright.core.topology import boundary_edges_of
from meshwright.tri.smoothing import node_adjacency, smooth


def grid_mesh(k: int, jitter: float, seed: int = 0):
    """Unit-square grid of k x k nodes split into ccw triangles, interior nodes jittered."""
    x, y = np.meshgrid(np.linspace(0, 1, k), np.linspace(0, 1, k))
    pts = np.column_stack([x.ravel(), y.ravel()])
    idx = np.arange(k * k).reshape(k, k)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel(), idx[1:, :-1].ravel()
    tris = np.vstack([np.column_stack([a, b, c]), np.column_stack([a, c, d])]).astype(np.int32)
    rng = np.random.default_rng(seed)
    interior = (pts[:, 0] > 0) & (pts[:, 0] < 1) & (pts[:, 1] > 0) & (pts[:, 1] < 1)
    pts[interior] += rng.uniform(-jitter, jitter, size=(interior.sum(), 2)) / (k - 1)
    return pts, tris


def radius_ratio(pts, tris):
    p = pts[tris]
    la = np.linalg.norm(p[:, 1] - p[:, 2], axis=1)
    lb = np.linalg.norm(p[:, 2] - p[:, 0], axis=1)
    lc = np.linalg.norm(p[:, 0] - p[:, 1], axis=1)
    area2 = (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (p[:, 1, 1] - p[:, 0, 1]) * (
        p[:, 2, 0] - p[:, 0, 0]
    )
    return 4 * area2**2 / ((la + lb + lc) * la * lb * lc)


def test_square_smoothing_keeps_validity_boundary_and_improves_quality():
    pts, tris = grid_mesh(12, jitter=0.45)
    out = smooth(pts, tris, passes=10)
    assert (orient2d_batch(out, tris) > 0).all()
    on_boundary = np.isin(np.arange(len(pts)), boundary_edges_of(tris).ravel())
    # Boundary nodes stay on their side of the square; corners do not move.
    bx = out[on_boundary]
    on_side = np.isclose(bx[:, 0], 0) | np.isclose(bx[:, 0], 1) | np.isclose(bx[:, 1], 0) | np.isclose(bx[:, 1], 1)
    assert on_side.all()
    corners = [0, 11, 132, 143]
    np.testing.assert_array_equal(out[corners], pts[corners])
    q0, q1 = radius_ratio(pts, tris), radius_ratio(out, tris)
    assert q1.mean() > q0.mean() + 0.02
    assert q1.min() >= q0.min() - 1e-12


def test_sliding_nodes_follow_the_true_curve():
    # A ring of 40 nodes on the unit circle around a centre node, nodes bunched on one side.
    theta = np.sort(np.random.default_rng(3).uniform(0, 2 * np.pi, 40))
    ring = np.column_stack([np.cos(theta), np.sin(theta)])
    pts = np.vstack([[0.0, 0.0], ring])
    n = len(ring)
    tris = np.column_stack([np.zeros(n), 1 + np.arange(n), 1 + (np.arange(n) + 1) % n]).astype(np.int32)

    def project(nodes, xy):
        return xy / np.linalg.norm(xy, axis=1)[:, None]

    out = smooth(pts, tris, passes=10, project=project)
    np.testing.assert_allclose(np.linalg.norm(out[1:], axis=1), 1.0, rtol=0, atol=1e-12)
    assert (orient2d_batch(out, tris) > 0).all()
    gaps = np.diff(np.unwrap(np.arctan2(out[1:, 1], out[1:, 0])))
    gaps0 = np.diff(theta)
    assert gaps.std() < gaps0.std()


def test_fixed_nodes_and_zero_passes():
    pts, tris = grid_mesh(6, jitter=0.3)
    out = smooth(pts, tris, passes=0)
    np.testing.assert_array_equal(out, pts)
    out = smooth(pts, tris, passes=5, fixed=np.array([7, 8]))
    np.testing.assert_array_equal(out[[7, 8]], pts[[7, 8]])
    assert not np.array_equal(out, pts)


def test_move_that_would_invert_is_refused():
    # Node 4 is a reflex-corner neighbour: the centroid of its neighbours lies outside its
    # star, so a full Laplacian step would fold a triangle; the smoother must refuse it.
    pts = np.array([[0, 0], [4, 0], [4, 1], [1, 1], [1, 4], [0, 4], [0.9, 0.9]], dtype=float)
    tris = np.array([[0, 1, 6], [1, 2, 6], [2, 3, 6], [3, 4, 6], [4, 5, 6], [5, 0, 6]], dtype=np.int32)
    assert (orient2d_batch(pts, tris) > 0).all()
    out = smooth(pts, tris, passes=10)
    assert (orient2d_batch(out, tris) > 0).all()


def test_adjacency_and_errors():
    pts, tris = grid_mesh(3, jitter=0.0)
    off, idx, toff, tidx = node_adjacency(tris, len(pts))
    assert off[-1] == len(idx) and toff[-1] == 3 * len(tris)
    centre = 4
    assert sorted(idx[off[centre] : off[centre + 1]]) == [0, 1, 3, 5, 7, 8]
    with pytest.raises(InputError, match="relax"):
        smooth(pts, tris, relax=1.5)
    with pytest.raises(InputError, match="shape"):
        smooth(pts[:, :1], tris)


def test_adjacency_lists_each_node_neighbours_once_in_ascending_order():
    """Against a set built edge by edge in Python (independent of the star pass)."""
    rng = np.random.default_rng(4)
    tri = mw.delaunay(rng.random((400, 2)))
    pts, tris = tri.points, tri.triangles
    n = len(pts) + 3  # trailing nodes in no triangle get empty lists
    off, idx, _, _ = node_adjacency(tris, n)
    want = [set() for _ in range(n)]
    for a, b, c in tris.tolist():
        for u, v in ((a, b), (b, c), (c, a)):
            want[u].add(v)
            want[v].add(u)
    assert off.dtype == np.int64 and idx.dtype == np.int32 and off[-1] == len(idx)
    for v in range(n):
        assert idx[off[v] : off[v + 1]].tolist() == sorted(want[v])


def _guarded_pass_reference(pts, tris, free):
    """One Gauss-Seidel pass of the documented guarded smoother in plain Python: each free
    node (ascending) steps to its neighbours' centroid, halved up to four times until every
    triangle of its star is counter-clockwise (exact, in Fractions) with a radius ratio
    (np.hypot edges) positive and not below the star's worst before the move."""
    from fractions import Fraction

    star = [[] for _ in range(len(pts))]
    for t, row in enumerate(tris.tolist()):
        for v in row:
            star[v].append(t)
    near = [sorted({u for t in star[v] for u in tris[t].tolist()} - {v}) for v in range(len(pts))]

    tris_list = tris.tolist()

    def worst(v, px, py):
        out = 1.0
        for t in star[v]:
            (ax, ay), (bx, by), (cx, cy) = [(px, py) if u == v else (pts[u, 0], pts[u, 1]) for u in tris_list[t]]
            fa = [Fraction(float(z)) for z in (ax, ay, bx, by, cx, cy)]
            if (fa[2] - fa[0]) * (fa[5] - fa[1]) - (fa[3] - fa[1]) * (fa[4] - fa[0]) <= 0:
                return -1.0
            la, lb, lc = np.hypot(bx - cx, by - cy), np.hypot(cx - ax, cy - ay), np.hypot(ax - bx, ay - by)
            area2 = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
            q = 0.0 if area2 <= 0.0 else 4.0 * area2 * area2 / ((la + lb + lc) * la * lb * lc)
            out = min(out, q)
        return out

    moved = 0
    for v in range(len(pts)):
        if not free[v]:
            continue
        x0, y0 = pts[v, 0], pts[v, 1]
        fx = fy = 0.0
        for u in near[v]:
            fx += pts[u, 0] - x0
            fy += pts[u, 1] - y0
        dx, dy = 1.0 * fx / len(near[v]), 1.0 * fy / len(near[v])
        before = worst(v, x0, y0)
        for _ in range(5):
            after = worst(v, x0 + dx, y0 + dy)
            if after >= before and after > 0.0:
                pts[v] = (x0 + dx, y0 + dy)
                moved += 1
                break
            dx *= 0.5
            dy *= 0.5
    return moved


@pytest.mark.parametrize("seed, jitter, scale", [(0, 0.45, 1.0), (1, 0.45, 1.0), (2, 0.45, 1.0), (3, 0.0, 1.0),
                                                  (4, 1e-12, 1.0), (5, 0.45, 2.0**-140), (6, 0.45, 2.0**190)])
def test_guarded_passes_match_a_plain_reference(seed, jitter, scale):
    """smooth (interior passes; a cache and a sqrt filter inside) and smooth_nodes (relax's
    entry, on a star-only CSR) move exactly as the plain pass, node for node and bit for bit:
    on jittered grids, on a regular one and one jittered by 1e-12 (a move's ratio equal or
    within the filter's margin of the bound: hypot decides) and on grids at the ends of the
    exact predicates' range (2**-140 and 2**190 wide)."""
    from meshwright.tri.relax import _rows_touching
    from meshwright.tri.smoothing import incident_rows
    from meshwright.tri.smoothing import smooth_nodes

    pts, tris = grid_mesh(9, jitter, seed)
    pts *= scale
    rng = np.random.default_rng(seed)
    interior = (pts[:, 0] > 0) & (pts[:, 0] < scale) & (pts[:, 1] > 0) & (pts[:, 1] < scale)
    free = interior & (rng.random(len(pts)) < 0.6)
    expect = pts.copy()
    counts = [_guarded_pass_reference(expect, tris, free) for _ in range(3)]
    if jitter > 0.1 and scale == 1.0:
        assert counts[0] > 0 and sum(counts) < 3 * free.sum()  # moves taken, and some visits refused
    got = smooth(pts, tris, np.zeros((0, 2), dtype=np.int32), passes=3, fixed=~free)
    assert np.array_equal(got, expect)
    xy = pts.copy()
    rows = _rows_touching(tris, free)
    off, inc = incident_rows(tris, rows, len(pts))
    smooth_nodes(xy, tris, off, inc, free, 3)
    assert np.array_equal(xy, expect)
