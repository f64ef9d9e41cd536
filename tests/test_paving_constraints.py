"""Paving honours interior segments, interior points and region seeds (issue 12).

Oracles never share code with what they check: segment pieces are found by exact
``Fraction`` collinearity of the mesh's nodes with the input segment (not from the
domain's discretisation), corners' scaled Jacobians and areas by plain numpy, region
markers by a crossing-count point-in-polygon test of each quad's centroid.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from meshwright.geometry import polygon
from meshwright.quad import quadrangulate
from meshwright.quad.paving import pave_domain

SQUARE = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]


def _cross(p, q, r) -> Fraction:
    """Exact (q - p) x (r - p)."""
    px, py = Fraction(float(p[0])), Fraction(float(p[1]))
    return (Fraction(float(q[0])) - px) * (Fraction(float(r[1])) - py) - (Fraction(float(q[1])) - py) * (
        Fraction(float(r[0])) - px
    )


def _corner_sj(xy, quads) -> np.ndarray:
    """(q, 4) scaled Jacobian at each corner: sine of the corner angle, plain numpy."""
    out = np.empty((len(quads), 4))
    for k in range(4):
        c = xy[quads[:, k]]
        u = xy[quads[:, (k + 1) % 4]] - c
        w = xy[quads[:, (k + 3) % 4]] - c
        cr = u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0]
        out[:, k] = cr / (np.hypot(*u.T) * np.hypot(*w.T))
    return out


def _edges(quads) -> set:
    return {frozenset((q[k], q[(k + 1) % 4])) for q in quads.tolist() for k in range(4)}


def _on_segment(xy, a, b) -> list[int]:
    """Mesh nodes exactly on the closed segment a b, ordered from a to b."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    near = np.flatnonzero(
        (xy[:, 0] >= min(a[0], b[0])) & (xy[:, 0] <= max(a[0], b[0]))
        & (xy[:, 1] >= min(a[1], b[1])) & (xy[:, 1] <= max(a[1], b[1]))
    )
    on = [int(v) for v in near if _cross(a, b, xy[v]) == 0]
    return sorted(on, key=lambda v: float(np.dot(xy[v] - a, b - a)))


def _check(mesh, segments=(), points=(), corners=()):
    """All-quad, valid, strictly convex (exact), area of the domain; every segment a chain
    of quad edges; every point a node; scaled Jacobian > 0.2 at corners not on an input
    vertex."""
    mesh.validate()
    assert set(mesh.cells) <= {"quad", "line"}
    xy, quads = mesh.points, mesh.cells["quad"]
    assert all(_cross(xy[r[k - 1]], xy[r[k]], xy[r[(k + 1) % 4]]) > 0 for r in quads.tolist() for k in range(4))
    edges = _edges(quads)
    for a, b in segments:
        chain = _on_segment(xy, a, b)
        assert len(chain) >= 2
        assert xy[chain[0]].tolist() == list(a) and xy[chain[-1]].tolist() == list(b)
        assert all(frozenset(uv) in edges for uv in zip(chain[:-1], chain[1:])), "a segment piece is no quad edge"
    for p in points:
        assert (xy == np.asarray(p)).all(axis=1).any(), f"point {p} is no node"
    sj = _corner_sj(xy, quads)
    fixed = np.array([list(c) for c in corners] + [list(e) for s in segments for e in s], dtype=float).reshape(-1, 2)
    at_input = (xy[quads][:, :, None, :] == fixed[None, None, :, :]).all(axis=3).any(axis=2)
    assert sj[~at_input].min() > 0.2
    return sj


@pytest.mark.parametrize(
    "segments",
    [
        [[(0.3, 0.5), (0.7, 0.5)]],  # dangling
        [[(0.5, 0.0), (0.5, 0.6)]],  # touching the boundary
        [[(0.2, 0.5), (0.8, 0.5)], [(0.5, 0.2), (0.5, 0.8)]],  # a cross
    ],
    ids=["dangling", "touching", "cross"],
)
def test_segments_are_chains_of_quad_edges(segments):
    dom = polygon(SQUARE, segments=segments)
    mesh = quadrangulate(dom, 0.1, method="paving")
    _check(mesh, segments=segments, corners=SQUARE)
    xy, q = mesh.points, mesh.cells["quad"]
    shoelace = 0.5 * sum(
        (xy[q[:, k], 0] * xy[q[:, (k + 1) % 4], 1] - xy[q[:, (k + 1) % 4], 0] * xy[q[:, k], 1]).sum() for k in range(4)
    )
    assert shoelace == pytest.approx(1.0, rel=1e-12)


def test_interior_points_are_nodes_that_stay():
    points = [(0.3, 0.3), (0.7, 0.6), (0.52, 0.5)]
    mesh = quadrangulate(polygon(SQUARE, points=points), 0.08, method="paving", smooth=3)
    _check(mesh, points=points, corners=SQUARE)


def test_rows_stop_short_of_the_obstacles():
    # A short dangling segment in a large square: rows are laid from the boundary until
    # they come near it, and the void fill meets it.
    seg = [[(0.45, 0.5), (0.55, 0.5)]]
    dom = polygon(SQUARE, segments=seg)
    fill, report = pave_domain(dom, 0.05)
    assert report.rows >= 6 and report.voids >= 1 and report.filled > 0
    _check(quadrangulate(dom, 0.05, method="paving"), segments=seg, corners=SQUARE)


def _inside(poly, p) -> bool:
    """Crossing count: ``p`` strictly inside polygon ``poly`` (no vertex on its ray)."""
    n, c = len(poly), False
    for i in range(n):
        (x0, y0), (x1, y1) = poly[i], poly[(i + 1) % n]
        if (y0 > p[1]) != (y1 > p[1]) and p[0] < x0 + (p[1] - y0) * (x1 - x0) / (y1 - y0):
            c = not c
    return c


def test_wall_segment_and_region_seeds():
    wall = [[(0.5, 0.0), (0.5, 1.0)]]
    dom = polygon(
        [(0, 0), (0.5, 0), (1, 0), (1, 1), (0.5, 1), (0, 1)], segments=wall,
        regions=[(0.25, 0.5, 3, None), (0.75, 0.5, 5, None)],
    )
    mesh = quadrangulate(dom, 0.1, method="paving")
    _check(mesh, segments=wall, corners=SQUARE)
    left = [(0, 0), (0.5, 0), (0.5, 1), (0, 1)]
    centre = mesh.points[mesh.cells["quad"]].mean(axis=1)
    want = [3 if _inside(left, c) else 5 for c in centre.tolist()]
    assert mesh.cell_data["marker"]["quad"].tolist() == want


def test_hole_with_an_island_and_seeds():
    hole = [(0.2, 0.2), (0.8, 0.2), (0.8, 0.8), (0.2, 0.8)]
    island = [(0.4, 0.4), (0.6, 0.4), (0.6, 0.6), (0.4, 0.6)]
    dom = polygon(SQUARE, holes=[hole, island], regions=[(0.5, 0.5, 7, None), (0.1, 0.1, 2, None)])
    mesh = quadrangulate(dom, 0.05, method="paving")
    _check(mesh, corners=SQUARE + hole + island)
    centre = mesh.points[mesh.cells["quad"]].mean(axis=1)
    want = [7 if _inside(island, c) else 2 for c in centre.tolist()]
    assert mesh.cell_data["marker"]["quad"].tolist() == want
    assert {7, 2} == set(want)


def test_segments_on_the_boundary_are_paved_from_both_sides():
    # A segment from the boundary is run by the paving boundary on both sides: rows grow
    # from it (no void fill is needed on a square at this size).
    seg = [[(0.5, 0.0), (0.5, 0.6)]]
    fill, report = pave_domain(polygon(SQUARE, segments=seg), 0.05)
    assert report.rows >= 6
    xy, q = fill.points, fill.quads
    # The quads beside the segment are the rows' rectangles.
    on = (xy[:, 0] == 0.5) & (xy[:, 1] <= 0.6)
    beside = q[on[q].sum(axis=1) == 2]
    assert len(beside) == 24
    assert _corner_sj(xy, beside).min() > 0.95


def test_face_cycles_of_a_wall_and_a_dangling_segment():
    from meshwright.quad._paving_hard import face_cycles

    # Square 0-1-2-3 with nodes 4 (bottom middle) and 5 (top middle) on the loop, a wall
    # 4-6-5 and a dangling piece 6-7 to the right.
    xy = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0], [0.5, 1], [0.5, 0.5], [0.75, 0.5]], float)
    loop = np.array([0, 4, 1, 2, 5, 3])
    sa, sb = np.array([4, 6, 6]), np.array([6, 5, 7])
    cycles, source = face_cycles(xy, [loop], sa, sb)
    assert source == [0, 0]
    areas = sorted(
        0.5 * float(sum(xy[c[k], 0] * xy[c[(k + 1) % len(c)], 1] - xy[c[(k + 1) % len(c)], 0] * xy[c[k], 1]
                        for k in range(len(c))))
        for c in cycles
    )
    assert areas == [0.5, 0.5]
    directed = sorted((int(c[k]), int(c[(k + 1) % len(c)])) for c in cycles for k in range(len(c)))
    want = sorted([(0, 4), (4, 1), (1, 2), (2, 5), (5, 3), (3, 0)] + [(4, 6), (6, 4), (6, 5), (5, 6), (6, 7), (7, 6)])
    assert directed == want


def test_a_hard_line_paving_that_loses_a_piece_is_redone_with_obstacles(monkeypatch):
    import meshwright.quad.paving as pv_mod

    calls = []
    real = pv_mod.pieces_two_sided

    def lost_once(quads, tris, sa, sb):
        calls.append(len(sa))
        return real(quads, tris, sa, sb) and len(calls) > 1

    paves = []
    real_pave = pv_mod._pave

    def pave(*args):
        paves.append(args[-2] is args[-1])  # the rows' obstacles are all of them: the fallback
        return real_pave(*args)

    monkeypatch.setattr(pv_mod, "pieces_two_sided", lost_once)
    monkeypatch.setattr(pv_mod, "_pave", pave)
    seg = [[(0.5, 0.0), (0.5, 0.6)], [(0.2, 0.8), (0.4, 0.8)]]
    points = [(0.8, 0.3)]
    mesh = quadrangulate(polygon(SQUARE, segments=seg, points=points), 0.05, method="paving")
    assert len(calls) == 2 and paves == [False, True]
    _check(mesh, segments=seg, points=points, corners=SQUARE)


def _seg_dist(p, q, a, b) -> float:
    """Distance between closed segments p q and a b, by sampling-free formula in floats
    (0 when they meet, decided exactly)."""
    def meet():
        d1, d2 = _cross(a, b, p), _cross(a, b, q)
        d3, d4 = _cross(p, q, a), _cross(p, q, b)
        if d1 * d2 < 0 and d3 * d4 < 0:
            return True

        def on(u, v, w):
            return _cross(u, v, w) == 0 and min(u[0], v[0]) <= w[0] <= max(u[0], v[0]) and min(
                u[1], v[1]) <= w[1] <= max(u[1], v[1])

        return on(a, b, p) or on(a, b, q) or on(p, q, a) or on(p, q, b)

    if meet():
        return 0.0

    def pd(x, u, v):
        d = v - u
        t = 0.0 if not d.any() else min(1.0, max(0.0, float(np.dot(x - u, d) / np.dot(d, d))))
        return float(np.hypot(*(u + t * d - x)))

    return min(pd(p, a, b), pd(q, a, b), pd(a, p, q), pd(b, p, q))


def test_quads_near_matches_an_oracle():
    from meshwright.quad._paving_obstacles import quads_near

    rng = np.random.default_rng(7)
    pts = rng.integers(0, 16, size=(60, 2)).astype(float) / 4.0
    # Axis-aligned unit quads (counter-clockwise) at random corners, obstacle pieces and points.
    base = rng.integers(0, 12, size=(30, 2)).astype(float) / 4.0
    corners = np.concatenate([base + o for o in ([0, 0], [1, 0], [1, 1], [0, 1])])
    xy = np.vstack([pts, corners])
    n, nq = len(pts), len(base)
    quads = np.column_stack([n + k * nq + np.arange(nq) for k in range(4)]).astype(np.int64)
    oa = np.concatenate([np.arange(0, 40, 2), np.arange(40, 50)]).astype(np.int64)
    ob = np.concatenate([np.arange(1, 40, 2), np.arange(40, 50)]).astype(np.int64)
    reach = rng.choice([0.0, 0.1, 0.3], size=nq)
    got = quads_near(xy, quads, reach, oa, ob, False)
    for c in range(nq):
        q = xy[quads[c]]
        want = False
        for a, b in zip(oa, ob):
            inside = all(_cross(q[k], q[(k + 1) % 4], xy[a]) > 0 for k in range(4))
            d = min(_seg_dist(q[k], q[(k + 1) % 4], xy[a], xy[b]) for k in range(4))
            want = want or inside or d == 0.0 or d < reach[c]
        assert got[c] == want, c


def test_a_long_free_segment_is_paved_around():
    # Eight pieces meeting no loop: a hard line (rows around it as around a hole), every
    # quad beside it a row's rectangle.
    seg = [[(0.3, 0.5), (0.7, 0.5)]]
    dom = polygon(SQUARE, segments=seg)
    fill, report = pave_domain(dom, 0.05)
    assert report.rows >= 6
    xy, q = fill.points, fill.quads
    on = (xy[:, 1] == 0.5) & (xy[:, 0] >= 0.3) & (xy[:, 0] <= 0.7)
    beside = q[on[q].sum(axis=1) == 2]
    assert len(beside) == 16
    assert _corner_sj(xy, beside).min() > 0.95
    _check(quadrangulate(dom, 0.05, method="paving"), segments=seg, corners=SQUARE)


def test_despike_keeps_the_slits_of_hard_lines():
    from meshwright.quad._paving_close import despike

    front = np.array([7, 1, 2, 1, 8, 9])  # 1-2-1: a piece run both ways between fixed nodes 1, 2
    assert despike(front, keep=5).tolist() == front.tolist()
    assert despike(front).tolist() == [7, 1, 8, 9]
    assert despike(np.array([7, 1, 6, 1, 8, 9]), keep=5).tolist() == [7, 1, 8, 9]  # 6 floats: zipped
