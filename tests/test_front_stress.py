"""Root causes of the stress harness's reproducers (issue 13), each reduced to a small case.

``stress-front-2230c2849a0d``: an interior segment alone in the unmeshed region, longer
than about 1.67 element sizes (size "boundary": its own length), made the advancing
front's ideal point fail its clearance from the segment's other side, the face's own
twin, which lies at the point's height; with no other node in reach the face had no
candidate at all.
"""

from __future__ import annotations

import numpy as np
import pytest

import meshwright as mw
from meshwright import geometry as g
from meshwright.tri import front as F
from meshwright.tri.cdt import cdt_build


def _square_with_slit(side, spacing, slit):
    """A square of ``side`` split every ``spacing`` along its sides, with an interior
    segment of length ``slit`` across its centre, as a classified triangulation."""
    dom = g.polygon([(0, 0), (side, 0), (side, side), (0, side)])
    disc = dom.discretize(spacing)
    c = 0.5 * side
    pts = np.vstack([disc.points, [(c - 0.5 * slit, c), (c + 0.5 * slit, c)]])
    n = len(disc.points)
    segs = np.vstack([disc.segments, [(n, n + 1)]])
    ct = cdt_build(pts, segs)
    sides = np.r_[np.ones(len(disc.segments), dtype=int), 0]
    ct.classify(segment_sides=sides)
    return ct


@pytest.mark.parametrize("slit", [1.8, 2.0, 3.0, 3.8])
def test_lone_interior_segment_advances_at_once(slit, monkeypatch):
    # The segment's faces are the shortest, so they come first while no other front is
    # near, and no node lies within their search: the ideal point is the only candidate.
    # Without postponements or back-offs the face must advance on its first try.
    ct = _square_with_slit(12.0, 6.0, slit)
    monkeypatch.setattr(F, "MAX_DEFER", 0)
    pts, tris = F.advancing_front(ct, lambda xy: 1.0 + 1e-3 * xy[:, 0], max_backoff=0)
    mesh = mw.Mesh(pts, {"triangle": tris})
    mesh.validate()
    a = pts[tris]
    e1, e2 = a[:, 1] - a[:, 0], a[:, 2] - a[:, 0]
    assert 0.5 * np.sum(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]) == pytest.approx(144.0, rel=1e-12)
    # Both sides of the segment are meshed: it is an edge of exactly two triangles.
    n = len(pts)
    i, j = len(ct.points) - 2, len(ct.points) - 1
    edges = np.sort(np.vstack([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), axis=1)
    assert int(np.sum(edges[:, 0] * n + edges[:, 1] == i * n + j)) == 2

