"""The quad polish's vertex-to-quad table (``_polish_kernel.vertex_cells``, a counting
sort) against a plain loop over the quads' corners."""

from __future__ import annotations

import numpy as np

from meshwright.quad._polish_kernel import vertex_cells


def test_vertex_cells_lists_each_vertex_quads_ascending_once_per_corner():
    rng = np.random.default_rng(5)
    for n, m in ((1, 0), (7, 3), (50, 200)):
        q = rng.integers(0, n, size=(m, 4)).astype(np.int64)
        ptr, idx = vertex_cells(q, n)
        want = [[c for c in range(m) for k in range(4) if q[c, k] == v] for v in range(n)]
        assert ptr[0] == 0 and len(ptr) == n + 1 and len(idx) == 4 * m
        assert [idx[ptr[v] : ptr[v + 1]].tolist() for v in range(n)] == want


def _min_sine_fraction(p, quad):
    """Smallest corner sine of a quad as an exact fraction's float: cross / (|u| |w|) from
    integer-free rational arithmetic on the float coordinates (Fraction), then one
    square root in floating point of the squared value, sign kept."""
    from fractions import Fraction

    worst = None
    for k in range(4):
        a, b, c = (p[quad[(k + j) % 4]] for j in (3, 0, 1))
        ux, uy = Fraction(c[0]) - Fraction(b[0]), Fraction(c[1]) - Fraction(b[1])
        wx, wy = Fraction(a[0]) - Fraction(b[0]), Fraction(a[1]) - Fraction(b[1])
        cr = ux * wy - uy * wx
        s2 = cr * cr / ((ux * ux + uy * uy) * (wx * wx + wy * wy))
        s = float(s2) ** 0.5 * (1 if cr > 0 else -1)
        worst = s if worst is None else min(worst, s)
    return worst


def test_polish_below_floor_test_agrees_with_the_exact_sine():
    """_below (a squared test with a margin, the sine computed only near the floor) marks
    exactly the quads whose smallest corner sine is below the floor: random quads, and
    rhombi whose sine is the floor times 1 +- 1e-11 (inside the margin: the sine is
    computed), checked against the sine in rational arithmetic."""
    from meshwright.quad._polish_kernel import _below

    rng = np.random.default_rng(11)
    floor = 0.8
    pts, quads = [], []
    for _ in range(400):
        base = rng.uniform(-5.0, 5.0, 2)
        r = rng.uniform(0.7, 1.3, 4)
        ang = (np.arange(4) + 0.5) * (0.5 * np.pi) + rng.uniform(-0.7, 0.7, 4)
        quads.append([len(pts) + k for k in range(4)])
        pts += [base + r[k] * np.array([np.cos(ang[k]), np.sin(ang[k])]) for k in range(4)]
    for rel in (-1e-11, 1e-11, -1e-6, 1e-6):
        t = np.arcsin(floor * (1.0 + rel))
        quads.append([len(pts) + k for k in range(4)])
        pts += [np.array([0.0, 0.0]), np.array([1.0, 0.0]), np.array([1.0 + np.cos(t), np.sin(t)]),
                np.array([np.cos(t), np.sin(t)])]
    p = np.array(pts)
    q = np.array(quads, dtype=np.int64)
    got = [bool(_below(p, q, c, floor)) for c in range(len(q))]
    want = [_min_sine_fraction(p, q[c]) < floor for c in range(len(q))]
    assert got == want
    assert 50 < sum(want) < len(q) - 50 and want[-4:] == [True, False, True, False]


def test_may_be_below_is_false_only_when_every_corner_is_clearly_above():
    from meshwright.quad.polish import may_be_below

    # A unit square's four corners have sine 1; a kite's sharpest corner has sine
    # sin(30 deg) = 0.5 (corner at the origin between directions 0 and 30 degrees).
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    q = np.array([[0, 1, 2, 3]], dtype=np.int64)
    assert not may_be_below(square, q, 0.99)
    kite = np.array([[0, 0], [1, 0], [1.2, 0.4], [np.cos(np.pi / 6), np.sin(np.pi / 6)]], float)
    assert may_be_below(kite, q, 0.51)
    assert not may_be_below(kite, q, 0.49)
    # A bent quad (the fourth corner pushed inside) and a degenerate one are below any floor.
    bent = square.copy()
    bent[2] = [0.4, 0.4]
    assert may_be_below(bent, q, 1e-3)
    flat = square.copy()
    flat[3] = [0.0, 0.0]
    assert may_be_below(flat, q, 1e-3)


def _strip(b):
    """Two quads on the line y = 0 (A, B, C at x = 0, b, 2) under the row y = 0.1
    (D, E, F at x = 0, 1, 2): B at b = 0.05 makes the left quad's corner at B and the
    right one's at E slivers (sine about 0.1); only B's move along the line opens them."""
    p = np.array([[0, 0], [b, 0], [2, 0], [0, 0.1], [1, 0.1], [2, 0.1]], float)
    q = np.array([[0, 1, 4, 3], [1, 2, 5, 4]], dtype=np.int64)
    return p, q


def test_polish_slides_a_line_node_along_its_line_between_its_neighbours():
    from meshwright.quad.polish import polish

    p, q = _strip(0.05)
    fixed = np.ones(6, dtype=bool)
    before = [_min_sine_fraction(p, c) for c in q]
    assert max(before) < 0.15
    # Pinned, B stays: the rows' nodes are all fixed.
    assert np.array_equal(polish(p, q, fixed, 0.3, 40), p)
    fixed[1] = False
    slide = np.full((6, 2), -1, dtype=np.int64)
    slide[1] = (0, 2)
    out = polish(p, q, fixed, 0.3, 40, slide)
    # Only B moved, along y = 0 and strictly between A and C (it passed neither).
    assert np.array_equal(np.delete(out, 1, axis=0), np.delete(p, 1, axis=0))
    assert out[1, 1] == 0.0 and 0.05 < out[1, 0] < 2.0
    after = [_min_sine_fraction(out, c) for c in q]
    assert all(a > b for a, b in zip(after, before)) and min(after) > 0.3



def test_line_sliders_are_the_line_nodes_between_two_corners_of_a_polygon():
    """Every boundary node of a rectangle's discretisation but its four corners (and a
    node kept) slides, between its two boundary neighbours; interior nodes do not."""
    from meshwright.geometry import polygon
    from meshwright.quad.polish import line_sliders

    corners = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]]
    disc = polygon(corners).discretize(0.25)
    n = len(disc.points) + 3
    segs = disc.segments.astype(np.int64)
    t = disc.segment_params[:, 0]
    vertices = segs[t == np.floor(t), 0]
    keep = np.concatenate([vertices, [5]])
    slide = line_sliders(n, segs, disc.segment_curve, polygon(corners), keep)
    for v in range(n):
        at_corner = any(np.array_equal(disc.points[v], c) for c in corners) if v < len(disc.points) else False
        if v >= len(disc.points) or at_corner or v == 5:
            assert slide[v].tolist() == [-1, -1]
        else:
            nb = sorted(int(w) for a, b in segs for w, o in ((a, b), (b, a)) if o == v)
            assert sorted(slide[v].tolist()) == nb
    assert (slide[:, 0] >= 0).sum() == len(disc.points) - 5
