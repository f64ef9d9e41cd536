"""The exterior-removal errors of ``ConstrainedTriangulation.classify`` name their culprit.

Crafted inputs trigger each error: an open loop ("not closed", located at the triangle next
to the gap), a reversed side of a square and a hole oriented like its outer loop ("both
sides", naming a segment of the offending pair and where it happens).
"""

import re

import numpy as np
import pytest

from meshwright.core.errors import GeometryError
from meshwright.tri.cdt import cdt_build

SQUARE = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]])
INNER = np.array([[1.0, 1.0], [3.0, 1.0], [3.0, 2.5], [1.0, 2.5]])
LOOP = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])


def _points_in(message):
    """The coordinate pairs ``(x, y)`` a message names, as floats."""
    return [tuple(map(float, m)) for m in re.findall(r"\(([-\d.e+]+), ([-\d.e+]+)\)", message)]


def _centroids_with_edge(ct, a, b):
    tri = ct.triangles(inside=False)
    has = [t for t in tri.tolist() if a in t and b in t]
    return [tuple(ct.points[t].mean(axis=0)) for t in has]


def test_classify_open_loop_names_the_gap():
    # A 12-gon with its side 7 -> 8 missing: the inside leaks out through that gap only.
    t = 2 * np.pi * np.arange(12) / 12
    pts = np.column_stack([np.cos(t), np.sin(t)])
    seg = np.array([(i, (i + 1) % 12) for i in range(12) if i != 7])
    ct = cdt_build(pts, seg)
    with pytest.raises(GeometryError, match="not closed") as info:
        ct.classify(segment_sides=np.ones(len(seg)))
    (where,) = _points_in(str(info.value))
    (expected,) = _centroids_with_edge(ct, 7, 8)
    assert np.allclose(where, expected, rtol=0, atol=1e-15)


def test_classify_reversed_segment_names_the_segment():
    seg = LOOP.copy()
    seg[2] = seg[2, ::-1]  # 3 -> 2: claims the domain lies above the top side
    ct = cdt_build(SQUARE, seg)
    with pytest.raises(GeometryError, match="both sides") as info:
        ct.classify(segment_sides=np.ones(4))
    msg = str(info.value)
    # The clash is between segment 2 and a neighbour sharing its triangle; either may be named,
    # with its own end points, at a triangle on segment 2.
    i = int(re.search(r"segment (\d+) from", msg).group(1))
    assert i in (1, 2, 3)
    a, b, where = _points_in(msg)
    assert (a, b) == tuple(map(tuple, SQUARE[seg[i]]))
    assert any(np.allclose(where, c, rtol=0, atol=1e-15) for c in _centroids_with_edge(ct, 2, 3))


def test_classify_hole_oriented_like_the_outer_loop_names_a_hole_segment():
    pts = np.vstack([SQUARE, INNER])
    seg = np.vstack([LOOP, LOOP + 4])  # the hole runs counter-clockwise, like the outer loop
    ct = cdt_build(pts, seg)
    with pytest.raises(GeometryError, match="both sides") as info:
        ct.classify(segment_sides=np.ones(8))
    msg = str(info.value)
    m = re.search(r"segment (\d+) from", msg)
    assert m is not None and 4 <= int(m.group(1)) < 8
    i = int(m.group(1))
    a, b, _ = _points_in(msg)
    assert (a, b) == tuple(map(tuple, pts[seg[i]]))


def test_classify_consistent_loops_pass():
    # The same inputs with the hole clockwise and the square's sides in order classify cleanly.
    pts = np.vstack([SQUARE, INNER])
    seg = np.vstack([LOOP, (LOOP + 4)[:, ::-1]])
    ct = cdt_build(pts, seg).classify(segment_sides=np.ones(8))
    tri = ct.triangles()
    u, v = (ct.points[tri[:, k]] - ct.points[tri[:, 0]] for k in (1, 2))
    area = 0.5 * (u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
    assert np.all(area > 0)
    assert np.isclose(area.sum(), 16.0 - 3.0)
