"""Tetrahedron quality measures: exact values of the regular tet, a flat sliver, and
agreement with an independent rational computation (fractions.Fraction) on random tets."""

import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from meshwright.core.mesh import Mesh
from meshwright.core.quality import tetra_quality

# Positively oriented regular tetrahedron of edge 2 sqrt(2).
REGULAR = np.array([[1, -1, -1], [1, 1, 1], [-1, 1, -1], [-1, -1, 1.0]])


def _sub(a, b):
    return [x - y for x, y in zip(a, b)]


def _dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _det3(r0, r1, r2):
    return _dot(r0, _cross(r1, r2))


def exact_measures(p):
    """Volume, dihedral angles, r/R and R/l_min of one tet from rationals, by other formulas:
    dihedrals from the vertices projected on the plane normal to each edge, R from
    Cramer's rule on the circumcentre equations."""
    q = [[Fraction(float(x)) for x in row] for row in p]
    u, v, w = (_sub(q[i], q[0]) for i in (1, 2, 3))
    six_v = _det3(u, v, w)
    dihedrals = []
    for i, j in ((0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)):
        k, m = (x for x in range(4) if x not in (i, j))
        e = _sub(q[j], q[i])
        ee = _dot(e, e)
        a, b = _sub(q[k], q[i]), _sub(q[m], q[i])
        a = _sub(a, [c * _dot(a, e) / ee for c in e])
        b = _sub(b, [c * _dot(b, e) / ee for c in e])
        ab = _dot(a, b)
        cos2 = ab * ab / (_dot(a, a) * _dot(b, b))
        dihedrals.append(math.degrees(math.acos(math.copysign(math.sqrt(cos2), ab))))
    # Circumcentre c: 2 (q_k - q_0) . c = |q_k|^2 - |q_0|^2, k = 1, 2, 3.
    rows = [[2 * x for x in _sub(q[k], q[0])] for k in (1, 2, 3)]
    rhs = [_dot(q[k], q[k]) - _dot(q[0], q[0]) for k in (1, 2, 3)]
    d = _det3(*rows)
    cols = list(zip(*rows))
    centre = []
    for c in range(3):
        cc = [list(col) for col in cols]
        cc[c] = rhs
        centre.append(_det3(*[list(r) for r in zip(*cc)]) / d)
    r2 = _dot(_sub(centre, q[0]), _sub(centre, q[0]))
    faces = ((1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2))
    area = sum(math.sqrt(_dot(n, n)) / 2 for n in (_cross(_sub(q[b], q[a]), _sub(q[c], q[a])) for a, b, c in faces))
    r_in = 3 * float(six_v / 6) / area
    big_r = math.sqrt(r2)
    lmin = min(math.sqrt(_dot(_sub(q[a], q[b]), _sub(q[a], q[b]))) for a in range(4) for b in range(a))
    return six_v / 6, dihedrals, r_in / big_r, big_r / lmin


def test_regular_tet_exact_values():
    q = Mesh(REGULAR, {"tetra": [[0, 1, 2, 3]]}).quality()["tetra"]
    dihedral = math.degrees(math.acos(1 / 3))
    np.testing.assert_allclose(q["sliver_ratio"], [1 / 3], rtol=1e-14)
    np.testing.assert_allclose(q["radius_ratio"], [1.0], rtol=1e-14)
    np.testing.assert_allclose(q["radius_edge_ratio"], [math.sqrt(6) / 4], rtol=1e-14)
    np.testing.assert_allclose(q["min_dihedral"], [dihedral], rtol=1e-13)
    np.testing.assert_allclose(q["max_dihedral"], [dihedral], rtol=1e-13)
    np.testing.assert_allclose(q["edge_ratio"], [1.0], rtol=1e-14)
    np.testing.assert_allclose(q["volume"], [8 / 3], rtol=1e-14)


@pytest.mark.parametrize("h", [1e-2, 1e-4, 1e-8])
def test_flat_sliver_is_flagged_but_has_a_fine_radius_edge_ratio(h):
    # Four points near the equator of a sphere: good faces, almost no volume (Figure 18.1.4a).
    pts = np.array([[1, 0, 0], [0, 1, h], [-1, 0, 0], [0, -1, h]], float)
    tet = [[0, 1, 2, 3]] if np.linalg.det(pts[1:] - pts[0]) > 0 else [[1, 0, 2, 3]]
    q = tetra_quality(pts, np.array(tet))
    assert 0 < q["sliver_ratio"][0] < h and q["sliver_ratio"][0] < 0.01
    assert q["radius_ratio"][0] == pytest.approx(3 * q["sliver_ratio"][0])
    assert q["min_dihedral"][0] < math.degrees(2 * h) and q["max_dihedral"][0] > 180 - math.degrees(3 * h)
    # The radius-edge ratio cannot see slivers: it stays near 1/sqrt(2).
    assert q["radius_edge_ratio"][0] == pytest.approx(1 / math.sqrt(2), rel=1e-3)
    assert q["volume"][0] > 0


def test_degenerate_and_inverted_tets_are_signed():
    pts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0, 0, 1.0]])
    q = tetra_quality(pts, np.array([[0, 1, 2, 3], [0, 2, 1, 4]]))
    assert q["sliver_ratio"][0] == 0.0 and q["radius_edge_ratio"][0] == np.inf and q["volume"][0] == 0.0
    assert q["sliver_ratio"][1] < 0 and q["volume"][1] == pytest.approx(-1 / 6)
    assert np.all(np.isfinite(q["min_dihedral"]))


coord = st.floats(-10, 10, allow_nan=False, allow_infinity=False)


@given(st.lists(st.tuples(coord, coord, coord), min_size=4, max_size=4), st.floats(-1e6, 1e6))
def test_measures_agree_with_exact_rational_formulas(pts, offset):
    p = np.array(pts) + offset
    q0 = [[Fraction(float(x)) for x in row] for row in p]
    vol = _det3(*(_sub(q0[i], q0[0]) for i in (1, 2, 3))) / 6
    scale = max(np.ptp(p, axis=0).max(), 1e-300)
    # Well-shaped enough that float64 has a few significant digits left after the offset.
    assume(abs(float(vol)) > 1e-3 * scale**3 and abs(offset) < 1e3 * scale)
    if vol < 0:
        p = p[[1, 0, 2, 3]]
    vol, dihedrals, a, rer = exact_measures(p)
    q = tetra_quality(p, np.array([[0, 1, 2, 3]]))
    assert q["volume"][0] == pytest.approx(float(vol), rel=1e-6)
    assert q["min_dihedral"][0] == pytest.approx(min(dihedrals), abs=1e-5)
    assert q["max_dihedral"][0] == pytest.approx(max(dihedrals), abs=1e-5)
    assert q["sliver_ratio"][0] == pytest.approx(a, rel=1e-6)
    assert q["radius_edge_ratio"][0] == pytest.approx(rer, rel=1e-6)
    assert 0 < q["sliver_ratio"][0] <= 1 / 3 + 1e-12


def test_quality_table_lists_the_tetra_measures():
    table = Mesh(REGULAR, {"tetra": [[0, 1, 2, 3]]}).quality().table()
    for name in ("sliver_ratio", "radius_edge_ratio", "min_dihedral [deg]", "volume"):
        assert name in table
