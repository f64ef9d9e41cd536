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
    from meshwright.quad._paving_polish import _below

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
