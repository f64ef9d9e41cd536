"""The 2-D kernel's state bundle and the shared core helpers under it.

Oracles are independent of the code checked: exact rationals (``fractions.Fraction``) for
orientation, in-circle and circumcentres, ``heapq``/``sorted`` for the heap, and plain
array comparisons for the growth contract.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numba import njit

from meshwright.core.geom2d import circumcentre, off_centre
from meshwright.core.heap import heap_pop, heap_push
from meshwright.tri._kernel2d import BROKEN, GHOST, M_NTRI, M_NV, M_SHORT_WORK, TriState, grow, new_state, split_edge
from meshwright.tri.cdt import cdt_build


# ---------------------------------------------------------------------------- exact oracles
def _orient(a, b, c) -> Fraction:
    a, b, c = ([Fraction(float(x)) for x in p] for p in (a, b, c))
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])


def _incircle(a, b, c, d) -> Fraction:
    rows = []
    for p in (a, b, c):
        x, y = Fraction(float(p[0])) - Fraction(float(d[0])), Fraction(float(p[1])) - Fraction(float(d[1]))
        rows.append((x, y, x * x + y * y))
    (a0, a1, a2), (b0, b1, b2), (c0, c1, c2) = rows
    return a0 * (b1 * c2 - b2 * c1) - a1 * (b0 * c2 - b2 * c0) + a2 * (b0 * c1 - b1 * c0)


def _check_cdt(s: TriState):
    """Links symmetric, constraints equal on both sides, finite triangles ccw, free edges
    locally Delaunay: all checked in exact rationals."""
    ntri = int(s.meta[M_NTRI])
    tri, nbr, cons, pts = s.tri, s.nbr, s.cons, s.pts
    for t in range(ntri):
        for k in range(3):
            n = int(nbr[3 * t + k])
            back = [m for m in range(3) if nbr[3 * n + m] == t]
            assert len(back) == 1, f"triangle {t} edge {k}: neighbour {n} does not point back"
            j = back[0]
            assert cons[3 * t + k] == cons[3 * n + j]
            if tri[3 * t + 2] == GHOST or tri[3 * n + 2] == GHOST or cons[3 * t + k] != 0:
                continue
            a, b, c = (pts[tri[3 * t + m]] for m in range(3))
            assert _incircle(a, b, c, pts[tri[3 * n + j]]) <= 0, f"free edge {k} of triangle {t} is not Delaunay"
        if tri[3 * t + 2] != GHOST:
            assert _orient(*(pts[tri[3 * t + m]] for m in range(3))) > 0


def _grid_cdt():
    """5 x 5 grid points with the constrained edge (0, 0)-(1, 0)."""
    xy = np.array([(x, y) for y in range(5) for x in range(5)], dtype=np.float64)
    xy += np.random.default_rng(3).uniform(-0.1, 0.1, xy.shape) * (xy % 4 != 0)  # keep the hull straight
    return cdt_build(xy, [[0, 1]], seed=1)


def _half_edge(s: TriState, a: int, b: int) -> int:
    ntri = int(s.meta[M_NTRI])
    for h in range(3 * ntri):
        t, k = divmod(h, 3)
        if s.tri[3 * t + (k + 1) % 3] == a and s.tri[3 * t + (k + 2) % 3] == b:
            return h
    raise AssertionError(f"{a}-{b} is not an edge")


# ---------------------------------------------------------------------------- split_edge
def test_split_edge_refused_modifies_nothing():
    ct = _grid_cdt()
    ct.reserve(ct.n_points + 1, int(ct.state.meta[M_NTRI]) + 2)
    s = ct.state
    v = ct.n_points
    s.pts[v] = 3.5, 3.5  # in neither triangle of the edge, far from both
    before = [a.copy() for a in (s.tri, s.nbr, s.cons)] + [int(s.meta[M_NTRI])]
    assert split_edge(v, _half_edge(s, 0, 1), s) == BROKEN
    after = [s.tri, s.nbr, s.cons, int(s.meta[M_NTRI])]
    for x, y in zip(before[:3], after[:3]):
        np.testing.assert_array_equal(x, y)
    assert before[3] == after[3]


@pytest.mark.parametrize("frac", [0.5, 0.9, 0.999])
def test_split_edge_off_chord_keeps_constrained_delaunay(frac):
    """A split point inside the edge's upper triangle, off the chord (the flip path when the
    two-sided cavity is not star-shaped): the result is a valid CDT with both halves
    constrained."""
    ct = _grid_cdt()
    ct.reserve(ct.n_points + 1, int(ct.state.meta[M_NTRI]) + 2)
    s = ct.state
    h = _half_edge(s, 0, 1)
    t = h // 3
    apex = s.pts[s.tri[h]]
    mid = 0.5 * (s.pts[0] + s.pts[1])
    v = ct.n_points
    s.pts[v] = apex + frac * (mid - apex)
    assert _orient(s.pts[0], s.pts[1], s.pts[v]) > 0 and t >= 0
    tn = split_edge(v, h, s)
    assert tn >= 0
    s.meta[M_NV] = v + 1
    _check_cdt(s)
    piece = [int(s.cons[_half_edge(s, a, b)]) for a, b in ((0, v), (v, 1), (v, 0), (1, v))]
    assert len(set(piece)) == 1 and piece[0] != 0


# ---------------------------------------------------------------------------- growth
def test_grow_doubles_and_keeps_the_used_part():
    pts = np.random.default_rng(0).random((8, 2))
    s = new_state(pts, 4, 1, circles=True, constrained=True)
    s.tri[:] = np.arange(12)
    s.cons[:] = 7
    s.meta[M_NTRI] = 4
    s.meta[M_NV] = 8
    assert grow(s) is not s  # one more insertion needs 6 slots
    g = grow(s, rows=20, slots=10)
    assert g.pts.shape[0] >= 20 and g.vmark.shape[0] > g.pts.shape[0]
    np.testing.assert_array_equal(g.pts[:8], pts)
    assert g.tri.shape[0] >= 30 and g.nbr.shape == g.tri.shape and g.cons.shape == g.tri.shape
    assert g.circ.shape[0] == 4 * (g.tri.shape[0] // 3)
    np.testing.assert_array_equal(g.tri[:12], np.arange(12))
    assert (g.cons[:12] == 7).all() and (g.cons[12:] == 0).all()
    assert g.meta is s.meta and g.work is s.work
    g.meta[M_SHORT_WORK] = 1
    w = grow(g, rows=20, slots=10)
    assert w.work.shape[0] == 2 * g.work.shape[0] and w.meta[M_SHORT_WORK] == 0
    assert grow(w, rows=20, slots=10) is w


# ---------------------------------------------------------------------------- heap
@njit
def _heap_sort(keys):
    n = keys.shape[0]
    hk = np.empty(n)
    hv = np.empty((n, 2), dtype=np.int32)
    for i in range(n):
        j = heap_push(hk, hv, i, keys[i])
        hv[j, 0] = i
        hv[j, 1] = -i
    out = np.empty((n, 3))
    for i in range(n):
        out[i, 0] = hk[0]
        out[i, 1] = hv[0, 0]
        out[i, 2] = hv[0, 1]
        heap_pop(hk, hv, n - i)
    return out


@settings(max_examples=50)
@given(st.lists(st.floats(-1e6, 1e6), min_size=1, max_size=200))
def test_heap_pops_in_key_order_with_payloads(keys):
    k = np.array(keys)
    out = _heap_sort(k)
    assert out[:, 0].tolist() == sorted(keys)
    np.testing.assert_array_equal(k[out[:, 1].astype(int)], out[:, 0])
    np.testing.assert_array_equal(out[:, 2], -out[:, 1])  # payload rows move whole
    assert sorted(out[:, 1].astype(int).tolist()) == list(range(len(keys)))


# ---------------------------------------------------------------------------- geom2d
@njit
def _cc(a, b, c):
    return circumcentre(a[0], a[1], b[0], b[1], c[0], c[1])


@njit
def _oc(a, b, c, off):
    return off_centre(a[0], a[1], b[0], b[1], c[0], c[1], off)


@settings(max_examples=50)
@given(st.lists(st.floats(-100, 100), min_size=6, max_size=6))
def test_circumcentre_matches_exact_rationals(xs):
    a, b, c = np.array(xs).reshape(3, 2)
    det = _orient(a, b, c)
    scale = max(1.0, float(np.abs(np.array(xs)).max()))
    if abs(det) < 1e-3 * scale * scale:
        return  # nearly degenerate: the construction is ill-conditioned by nature
    A, B, C = ([Fraction(float(x)) for x in p] for p in (a, b, c))
    ux, uy, wx, wy = B[0] - A[0], B[1] - A[1], C[0] - A[0], C[1] - A[1]
    d = 2 * (ux * wy - uy * wx)
    ox = A[0] + (wy * (ux * ux + uy * uy) - uy * (wx * wx + wy * wy)) / d
    oy = A[1] + (ux * (wx * wx + wy * wy) - wx * (ux * ux + uy * uy)) / d
    got = _cc(a, b, c)
    r = float(abs(ox - A[0]) + abs(oy - A[1])) + scale
    assert abs(got[0] - float(ox)) <= 1e-9 * r and abs(got[1] - float(oy)) <= 1e-9 * r


def test_off_centre_is_circumcentre_when_nearer_and_on_the_bisector_otherwise():
    a, b, c = np.array([0.0, 0.0]), np.array([1.0, 0.0]), np.array([0.5, 0.2])  # obtuse at c
    assert _oc(a, b, c, 0.0) == _cc(a, b, c)
    a, b, c = np.array([0.0, 0.0]), np.array([0.1, 0.0]), np.array([0.05, 2.0])  # skinny, short ab
    x, y = _oc(a, b, c, 0.5)
    assert x == pytest.approx(0.05) and y == pytest.approx(0.05)  # 0.5 |ab| above the midpoint
