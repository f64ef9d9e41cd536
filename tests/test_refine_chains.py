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

