"""Zhu's pair front at an acute notch (issue 12): no pair leaves a four-face pocket whose
closing quadrilateral is reflex, or wider than 150 degrees, at input nodes, and
letter_a.poly meshes all-quad with every scaled Jacobian above 0.2.

Oracles never share code with the kernel: the front's loops are walked here from the live
faces (read after each pause), corners and convexity by exact ``Fraction`` arithmetic, the
scaled Jacobian from the corners with ``math``, conformity by a set of directed edges.
"""

from __future__ import annotations

import math
import pathlib
from fractions import Fraction

import numpy as np
import pytest

from meshwright.geometry import read_poly
from meshwright.quad import _enhance_kernel as ek
from meshwright.quad import quadrangulate
from meshwright.quad.pairing import make_loops_even
from meshwright.quad.zhu import PairFront
from meshwright.sizing.field import as_size_field
from meshwright.tri import _front_kernel as fk
from meshwright.tri.cdt import SegmentCurves, cdt_build
from test_zhu import _live_faces, _min_scaled_jacobian

LETTER_A = pathlib.Path(__file__).parent / "data" / "letter_a.poly"


def _cross(p, q, r) -> Fraction:
    """Exact (q - p) x (r - p)."""
    px, py = Fraction(float(p[0])), Fraction(float(p[1]))
    return (Fraction(float(q[0])) - px) * (Fraction(float(r[1])) - py) - (Fraction(float(q[1])) - py) * (
        Fraction(float(r[0])) - px
    )


def _dot(p, q, r) -> Fraction:
    """Exact (q - p) . (r - p)."""
    px, py = Fraction(float(p[0])), Fraction(float(p[1]))
    return (Fraction(float(q[0])) - px) * (Fraction(float(r[0])) - px) + (Fraction(float(q[1])) - py) * (
        Fraction(float(r[1])) - py
    )


def _four_loops(faces):
    """Closed loops of exactly four faces [(a, b)] whose four nodes start one live face each
    (no pinch point), as node lists in face order."""
    out_of = {}
    starts = {}
    for a, b in faces:
        out_of[a] = b
        starts[a] = starts.get(a, 0) + 1
    loops, seen = [], set()
    for a in out_of:
        if a in seen:
            continue
        loop = [a]
        while len(loop) <= 4 and starts.get(loop[-1], 0) == 1 and out_of[loop[-1]] != a:
            loop.append(out_of[loop[-1]])
        if len(loop) == 4 and starts.get(loop[-1], 0) == 1 and out_of[loop[-1]] == a:
            loops.append(loop)
            seen.update(loop)
    return loops


@pytest.mark.parametrize("size", [1.0, 0.8, 0.5])
def test_no_pair_leaves_a_pocket_that_is_not_convex_at_an_input_node(size):
    """Paused after every pair of the pair front on letter_a: every loop of four live
    faces a pair leaves is strictly convex at its input nodes (which no smoothing opens),
    with no corner wider than 150 degrees between input nodes."""
    dom = read_poly(LETTER_A)
    field = as_size_field(size)
    disc, _ = make_loops_even(dom, dom.discretize(field))
    ct = cdt_build(disc.points, disc.segments, seed=0, curves=SegmentCurves.from_domain(dom, disc))
    ct.classify(segment_sides=np.where(dom.curve_loop[disc.segment_curve] >= 0, 1, 0), holes=disc.holes, regions=[])
    pf = PairFront(ct, field)
    assert pf.coloured
    n_in = len(ct.points)
    before = {tuple(loop) for loop in _four_loops(_live_faces(pf))}
    for _ in range(2000):
        nt = int(pf.fr.fs.meta[fk.M_NT])
        pf.run(max_tris=nt + 2)
        if not pf.pairing:
            break
        xy = pf.fr.fs.pts
        for loop in _four_loops(_live_faces(pf)):
            if tuple(loop) in before:
                continue
            for k, v in enumerate(loop):
                if v >= n_in:
                    continue
                nxt, prv = loop[(k + 1) % 4], loop[k - 1]
                assert _cross(xy[v], xy[nxt], xy[prv]) > 0, f"pair {nt // 2} left the pocket {loop}, reflex at {v}"
                if nxt < n_in and prv < n_in:
                    angle = math.degrees(
                        math.atan2(float(_cross(xy[v], xy[nxt], xy[prv])), float(_dot(xy[v], xy[nxt], xy[prv])))
                    )
                    assert angle <= 150.0 + 1e-9, f"pair {nt // 2} left the pocket {loop}, {angle:.1f} degrees at {v}"
    else:
        pytest.fail("the pair front did not finish in 2000 pairs")


def test_a_fixed_reflex_corner_split_160_110_is_balanced_by_turning_the_free_node():
    """Two quads share the side v m at a fixed node v whose domain angle is 270 degrees,
    split 160 / 110: m turns about v towards the bisector, both corners at v come under
    150 degrees, every quad stays strictly convex (exact) and the worst scaled Jacobian
    (recomputed here) rises; the fixed and the other free nodes stay."""
    m_at = (math.cos(math.radians(160.0)), math.sin(math.radians(160.0)))
    xy = np.array([(0.0, 0.0), (1.0, 0.0), (0.2, 1.0), m_at, (-1.0, -0.8), (0.0, -1.0)])
    quads = np.array([[0, 1, 2, 3], [0, 3, 4, 5]], dtype=np.int32)
    fixed = np.array([1, 1, 0, 0, 0, 1], dtype=np.int8)
    before = xy.copy()
    alive = np.ones(2, dtype=np.int8)
    off, idx = ek.node_quads(quads, alive, len(xy))
    assert ek.balance_corners(xy, quads, alive, fixed, np.zeros(len(xy), dtype=np.int8), off, idx) == 1
    assert np.array_equal(np.delete(xy, 3, axis=0), np.delete(before, 3, axis=0))
    for q in quads.tolist():
        assert all(_cross(xy[q[k]], xy[q[(k + 1) % 4]], xy[q[k - 1]]) > 0 for k in range(4))
    angles = [math.degrees(math.atan2(float(_cross(xy[0], xy[n], xy[p])), float(_dot(xy[0], xy[n], xy[p]))))
              for n, p in ((1, 3), (3, 5))]
    assert max(angles) < 150.0 and sum(angles) == pytest.approx(270.0)
    assert _min_scaled_jacobian(xy, quads) > _min_scaled_jacobian(before, quads)


@pytest.mark.parametrize("size", [None, 1.0, 0.8, 0.5])
def test_letter_a_all_quad_with_scaled_jacobian_above_0_2(size):
    mesh = quadrangulate(LETTER_A, size, method="zhu")
    mesh.validate()
    xy, quads = mesh.points, mesh.cells["quad"]
    assert "triangle" not in mesh.cells
    assert all(all(_cross(xy[q[k]], xy[q[(k + 1) % 4]], xy[q[k - 1]]) > 0 for k in range(4)) for q in quads)
    directed = set()
    for q in quads.tolist():
        for k in range(4):
            e = (q[k], q[(k + 1) % 4])
            assert e not in directed
            directed.add(e)
    boundary = {e for e in directed if (e[1], e[0]) not in directed}
    assert boundary == {tuple(e) for e in mesh.cells["line"].tolist()}
    assert _min_scaled_jacobian(xy, quads) > 0.2
    area = sum(_cross(xy[q[0]], xy[q[1]], xy[q[2]]) + _cross(xy[q[0]], xy[q[2]], xy[q[3]]) for q in quads) / 2
    assert float(area) == pytest.approx(abs(read_poly(LETTER_A).area()), rel=1e-2)
