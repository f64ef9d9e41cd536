"""Delaunay refinement on a discretised boundary: the small-angle rules see the input
segments (chains of pieces), not the pieces, and shell vertices at a needle's tip do not
encroach each other by rounding (:func:`meshwright.tri.ruppert.chains`,
:func:`meshwright.tri._refine_state.common_shell`).

Oracles: polygon edges found from coordinates alone; angles and distances recomputed here
with NumPy from the output mesh."""

from __future__ import annotations

import numpy as np
import pytest

import meshwright as mw
from meshwright.tri.cdt import SegmentCurves, cdt_build
from meshwright.tri.ruppert import chains

# A needle of angle THETA whose tip sits at coordinates ~0.6, so that near the tip the two
# sides are closer than the rounding of shell points (the stress run's thin domain 63260).
THETA = 4.6e-6
TIP = np.array([-0.6223894161037116, -0.44394468835065587])
LENGTH = 0.02


def _needle(ratio):
    """The needle, its side b ``ratio`` times as long as side a (another spacing along it)."""
    a = TIP + (LENGTH, 0.0)
    b = TIP + ratio * LENGTH * np.array([np.cos(THETA), np.sin(THETA)])
    return mw.geometry.polygon(np.array([TIP, a, b])), a, b


def _size(xy):
    # Fine at the tip, so the boundary is cut into pieces of ~2e-6 there.
    return 2e-6 + 0.2 * np.hypot(*(np.reshape(xy, (-1, 2)) - TIP).T)


def test_chains_are_the_polygon_edges():
    outer = np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 1.0], [1.0, 1.2], [0.0, 1.0]])
    dom = mw.geometry.polygon(outer)
    disc = dom.discretize(0.05)
    ct = cdt_build(disc.points, disc.segments, seed=0, curves=SegmentCurves.from_domain(dom, disc))
    pcor = chains(ct)
    seg = ct.constraints.seg[: len(pcor)]
    pts = ct.points
    assert len(seg) > 5 * len(outer)
    for p in range(len(seg)):
        mid = 0.5 * (pts[seg[p, 0]] + pts[seg[p, 1]])
        # The edge the piece lies on: the nearest of the polygon's edges to its midpoint.
        d = []
        for k in range(len(outer)):
            a, b = outer[k], outer[(k + 1) % len(outer)]
            t = np.clip(np.dot(mid - a, b - a) / np.dot(b - a, b - a), 0.0, 1.0)
            d.append(np.hypot(*(mid - (a + t * (b - a)))))
        k = int(np.argmin(d))
        ends = {tuple(pts[pcor[p, 1]]), tuple(pts[pcor[p, 2]])}
        assert ends == {tuple(outer[k]), tuple(outer[(k + 1) % len(outer)])}, p
    # One chain id per edge.
    assert len(np.unique(pcor[:, 0])) == len(outer)


# (ratio, most vertices per boundary vertex).  Equal sides: the boundary points face each
# other and nothing is refined (before: ~2 million vertices for weatherill).  Sides of
# 1 and 0.7: each boundary point of one side gets its counterpart on the other, bisected
# to 0.1 % of its distance from the tip (before: ~2.6 million vertices, vertices on the two
# sides' rounded shells encroaching each other toward the tip).
NEEDLES = [(1.0, 2), (0.7, 300)]


@pytest.mark.parametrize("method", ["weatherill", "frontal-delaunay"])
@pytest.mark.parametrize("ratio, most", NEEDLES)
def test_discretised_needle_is_left_alone(method, ratio, most):
    dom, a, b = _needle(ratio)
    mesh = mw.triangulate(dom, _size, method=method, min_angle=20.0, seed=1)
    mesh.validate()
    pts = mesh.points
    tris = mesh.cells_of("triangle")
    # Areas of ~1e-9 summed at coordinates ~0.6 keep about 8 digits.
    assert abs(mesh.area() - dom.area()) <= 1e-6 * dom.area()
    nb = len(np.unique(mesh.cells_of("line")))
    assert len(pts) <= most * nb, (len(pts), nb)
    d = np.hypot(*(pts - TIP).T)
    assert d[d > 0].min() > 1e-7
    # Every triangle under the bound has its shortest edge across the needle, between
    # vertices on the two sides equally far (0.1 %) from the tip: Shewchuk's rule.
    e = [pts[tris[:, (k + 2) % 3]] - pts[tris[:, (k + 1) % 3]] for k in range(3)]
    length = np.stack([np.hypot(*x.T) for x in e], axis=1)
    cross = np.abs(e[0][:, 0] * e[1][:, 1] - e[0][:, 1] * e[1][:, 0])
    sin_min = cross / np.prod(length, axis=1) * length.min(axis=1)
    bad = np.flatnonzero(sin_min < np.sin(np.radians(20.0)) * (1 - 1e-9))
    assert len(bad)
    side_a, side_b = (a - TIP) / LENGTH, (b - TIP) / (ratio * LENGTH)

    def off(q, side):
        r = pts[q] - TIP
        return abs(r[0] * side[1] - r[1] * side[0])

    # Clear of the third side (for ratio 0.7 it meets side a at another needle tip).
    near = np.hypot(*(pts[tris] - TIP).transpose(2, 0, 1)).max(axis=1) < 0.5 * ratio * LENGTH
    assert near[bad].sum() > 10
    for t in bad[near[bad]]:
        k = int(np.argmin(length[t]))
        u, w = tris[t, (k + 1) % 3], tris[t, (k + 2) % 3]
        du, dw = np.hypot(*(pts[u] - TIP)), np.hypot(*(pts[w] - TIP))
        assert 0.999 * dw**2 < du**2 < 1.001 * dw**2, (t, du, dw)
        on_a = {q for q in (u, w) if off(q, side_a) < off(q, side_b)}
        assert len(on_a) == 1, (t, u, w)



def _pieces_and_chains(dom, h):
    disc = dom.discretize(h)
    ct = cdt_build(disc.points, disc.segments, seed=0, curves=SegmentCurves.from_domain(dom, disc))
    pcor = chains(ct)
    return ct.constraints.seg[: len(pcor)], ct.points, pcor


def test_chains_end_where_a_constraint_meets_the_edge():
    # A constraint from the middle of the bottom edge at 30 degrees: the bottom edge is two
    # straight segments meeting the constraint there, each its own chain.
    foot, tip = np.array([1.5, 0.0]), np.array([1.5 + 0.8 * np.cos(np.pi / 6), 0.8 * np.sin(np.pi / 6)])
    box = np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 1.0], [0.0, 1.0]])
    dom = mw.geometry.Domain(box, segments=[np.array([foot, tip])])
    seg, pts, pcor = _pieces_and_chains(dom, 0.05)
    ends = {tuple(pts[pcor[p, 1]]) for p in range(len(seg))} | {tuple(pts[pcor[p, 2]]) for p in range(len(seg))}
    assert ends == {tuple(v) for v in (*box, foot, tip)}
    for p in range(len(seg)):
        mid = 0.5 * (pts[seg[p, 0]] + pts[seg[p, 1]])
        mine = {tuple(pts[pcor[p, 1]]), tuple(pts[pcor[p, 2]])}
        if abs(mid[1]) < 1e-12:  # the bottom edge, left or right of the foot
            assert mine == ({(0.0, 0.0), tuple(foot)} if mid[0] < foot[0] else {tuple(foot), (3.0, 0.0)}), p
        elif abs((tip - foot)[0] * (mid - foot)[1] - (tip - foot)[1] * (mid - foot)[0]) < 1e-9:
            assert mine == {tuple(foot), tuple(tip)}, p
    assert len(np.unique(pcor[:, 0])) == 6


def test_curve_pieces_are_their_own_chains():
    # A closed NACA section is one curve whose start and end are its sharp trailing edge:
    # its pieces stay what they were before chains (each its own chain).
    seg, pts, pcor = _pieces_and_chains(mw.geometry.naca("0012", closed_te=True), 0.05)
    assert len(seg) > 20
    assert (pcor[:, 0] == np.arange(len(seg))).all()
    assert (pcor[:, 1:] == seg).all()


@pytest.mark.parametrize("h", [0.05, 0.1, 0.2])
def test_closed_trailing_edge_is_refined(h):
    # The 16-degree trailing edge where the closed section starts and ends (the demo's NACA
    # wing section at h = 0.1 failed with 'subsegment ... cannot be split' when the whole
    # curve was one chain with no ends: no small-angle rule there).
    dom = mw.geometry.naca("0012", closed_te=True)
    mesh = mw.triangulate(dom, size=h)
    mesh.validate()
    pts = mesh.points
    tris = mesh.cells_of("triangle")
    te = np.array([1.0, 0.0])
    e = [pts[tris[:, (k + 2) % 3]] - pts[tris[:, (k + 1) % 3]] for k in range(3)]
    length = np.stack([np.hypot(*x.T) for x in e], axis=1)
    cross = np.abs(e[0][:, 0] * e[1][:, 1] - e[0][:, 1] * e[1][:, 0])
    sin_min = cross / np.prod(length, axis=1) * length.min(axis=1)
    # Every triangle under 30 degrees is the trailing edge's own, or has its shortest edge
    # across the wedge between a vertex of each surface equally far (0.1 %) from it.
    bad = np.flatnonzero(sin_min < np.sin(np.radians(30.0)) * (1 - 1e-9))
    assert 0 < len(bad) <= 4
    for t in bad:
        if (np.hypot(*(pts[tris[t]] - te).T) == 0).any():
            continue
        k = int(np.argmin(length[t]))
        u, w = tris[t, (k + 1) % 3], tris[t, (k + 2) % 3]
        du, dw = np.hypot(*(pts[u] - te)), np.hypot(*(pts[w] - te))
        assert 0.999 * dw**2 < du**2 < 1.001 * dw**2, (t, du, dw)
        assert pts[u, 1] * pts[w, 1] < 0, (t, pts[u], pts[w])
