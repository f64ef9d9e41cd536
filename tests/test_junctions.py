"""Junctions of straight pieces (geometry/_junctions.py): a constraint ending inside a
segment, an interior point on a segment, crossing constraints, in a Domain and in a
Triangle ``.poly`` file; split as Triangle splits them, every input segment recovered as a
chain of mesh edges.  Oracles: exact rational arithmetic (``fractions``) written here."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

import meshwright as mw
from meshwright.core.errors import GeometryError
from meshwright.geometry import Domain, polygon, read_poly

SQUARE = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])


def _orient(a, b, c) -> Fraction:
    ax, ay, bx, by, cx, cy = (Fraction(float(v)) for v in (*a, *b, *c))
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)


def _on_segment(a, b, p) -> bool:
    if _orient(a, b, p) != 0:
        return False
    return min(a[0], b[0]) <= p[0] <= max(a[0], b[0]) and min(a[1], b[1]) <= p[1] <= max(a[1], b[1])


def _edges(mesh) -> set:
    tri = mesh.cells["triangle"]
    e = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
    return set(map(tuple, np.sort(e, axis=1).tolist()))


def _recovered(mesh, a, b) -> bool:
    """Whether the mesh vertices on segment a-b, in order along it, are joined by mesh edges
    and include both ends."""
    pts = mesh.points[:, :2]
    on = [i for i in range(len(pts)) if _on_segment(a, b, pts[i])]
    d = np.asarray(b, dtype=float) - np.asarray(a, dtype=float)
    on.sort(key=lambda i: float((pts[i] - a) @ d))
    if not on or not np.array_equal(pts[on[0]], a) or not np.array_equal(pts[on[-1]], b):
        return False
    edges = _edges(mesh)
    return all(tuple(sorted((i, j))) in edges for i, j in zip(on[:-1], on[1:]))


def _exact_crossing(a0, a1, b0, b1):
    ax, ay, bx, by = (Fraction(float(v)) for v in (*a0, *a1))
    cx, cy, dx, dy = (Fraction(float(v)) for v in (*b0, *b1))
    den = (bx - ax) * (dy - cy) - (by - ay) * (dx - cx)
    t = ((cx - ax) * (dy - cy) - (cy - ay) * (dx - cx)) / den
    return ax + t * (bx - ax), ay + t * (by - ay)


def _has_vertex(mesh, p) -> bool:
    return bool((mesh.points[:, :2] == np.asarray(p, dtype=float)).all(axis=1).any())


def test_constraint_ending_inside_a_loop_segment():
    seg = np.array([[0.5, 0.0], [0.5, 0.7]])
    dom = polygon(SQUARE, segments=[seg])
    assert any((c.points == [0.5, 0.0]).all(axis=1).any() for c in dom.loops[0])
    mesh = mw.triangulate(dom, 0.2)
    mesh.validate()
    assert _recovered(mesh, seg[0], seg[1])
    assert _recovered(mesh, SQUARE[0], [0.5, 0.0]) and _recovered(mesh, [0.5, 0.0], SQUARE[1])
    assert mesh.area() == pytest.approx(1.0, rel=1e-12)


def test_constraint_ending_inside_another_constraint():
    a = np.array([[0.2, 0.5], [0.8, 0.5]])
    b = np.array([[0.5, 0.5], [0.5, 0.9]])
    dom = polygon(SQUARE, segments=[a, b])
    mesh = mw.triangulate(dom, 0.2)
    mesh.validate()
    for s in (a, b):
        assert _recovered(mesh, s[0], s[1])
    assert _has_vertex(mesh, [0.5, 0.5])


@pytest.mark.parametrize("seed", range(4))
def test_crossing_constraints_split_at_the_rounded_crossing(seed):
    rng = np.random.default_rng(seed)
    segs = [0.1 + 0.8 * rng.random((2, 2)) for _ in range(5)]
    dom = polygon(SQUARE, segments=segs)
    mesh = mw.triangulate(dom, 0.1)
    mesh.validate()
    crossings = 0
    for i in range(len(segs)):
        for j in range(i + 1, len(segs)):
            (a0, a1), (b0, b1) = segs[i], segs[j]
            o = [_orient(a0, a1, b0), _orient(a0, a1, b1), _orient(b0, b1, a0), _orient(b0, b1, a1)]
            if o[0] * o[1] < 0 and o[2] * o[3] < 0:
                crossings += 1
                x = np.array([float(v) for v in _exact_crossing(a0, a1, b0, b1)])
                # The crossing, rounded to the nearest doubles, is a mesh vertex.
                assert _has_vertex(mesh, x), (i, j, x)
    assert mesh.area() == pytest.approx(1.0, rel=1e-12)
    if seed == 0:
        assert crossings > 0


def test_interior_points_on_segments_become_their_vertices():
    seg = np.array([[0.2, 0.5], [0.8, 0.5]])
    pts = np.array([[0.5, 0.0], [0.4, 0.5], [1.0, 1.0], [0.3, 0.3]])
    dom = polygon(SQUARE, segments=[seg], points=pts)
    # Only the point off every segment stays an interior point; the others are vertices.
    assert dom.points.tolist() == [[0.3, 0.3]]
    mesh = mw.triangulate(dom, 0.25)
    mesh.validate()
    for p in pts:
        assert _has_vertex(mesh, p)
    assert _recovered(mesh, seg[0], seg[1])


def test_markers_kept_by_split_loop_segments():
    loop = mw.geometry.Polyline(SQUARE, markers=[5, 6, 7, 8], closed=True)
    dom = Domain(loop, segments=[np.array([[0.25, 0.0], [0.25, 0.5]]), np.array([[0.75, 0.0], [0.75, 0.5]])])
    mesh = mw.triangulate(dom, 0.2)
    lines = mesh.cells["line"]
    marks = mesh.cell_data["marker"]["line"]
    y = mesh.points[lines, 1]
    bottom = (y == 0.0).all(axis=1)
    assert bottom.sum() >= 3
    assert set(np.asarray(marks)[bottom].tolist()) == {5}


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"segments": [np.array([[0.5, 0.5], [1.5, 0.5]])]}, "intersects"),  # a constraint leaving the domain
        ({"holes": [np.array([[0.5, 0.0], [0.7, 0.3], [0.3, 0.3]])]}, "intersects"),  # a hole touching the outer loop
        ({"segments": [np.array([[0.2, 0.5], [0.6, 0.5]]), np.array([[0.4, 0.5], [0.8, 0.5]])]}, "intersects"),
    ],
)
def test_junctions_that_stay_errors(kwargs, match):
    with pytest.raises(GeometryError, match=match):
        polygon(SQUARE, **kwargs)


POLY_T = """6 2 0 0
1 0 0
2 2 0
3 2 2
4 0 2
5 1 0
6 1 1.5
6 1
1 1 2 3
2 2 3 3
3 3 4 3
4 4 1 3
5 5 6 0
6 6 3 0
0
"""

POLY_X = """7 2 0 0
1 0 0
2 4 0
3 4 4
4 0 4
5 1 0.3
6 3 3.1
7 0.5 3
7 0
1 1 2
2 2 3
3 3 4
4 4 1
5 1 3
6 5 6
7 2 7
0
"""


def test_poly_file_with_a_t_junction(tmp_path):
    f = tmp_path / "t.poly"
    f.write_text(POLY_T)
    dom = read_poly(f)
    mesh = mw.triangulate(dom, 0.3)
    mesh.validate()
    assert _recovered(mesh, [1.0, 0.0], [1.0, 1.5]) and _recovered(mesh, [1.0, 1.5], [2.0, 2.0])
    assert _recovered(mesh, [0.0, 0.0], [1.0, 0.0]) and _recovered(mesh, [1.0, 0.0], [2.0, 0.0])
    assert mesh.area() == pytest.approx(4.0, rel=1e-12)


def test_poly_file_with_crossing_segments(tmp_path):
    f = tmp_path / "x.poly"
    f.write_text(POLY_X)
    mesh = mw.triangulate(read_poly(f), 0.5)
    mesh.validate()
    diagonal, short, long = ([0, 0], [4, 4]), ([1, 0.3], [3, 3.1]), ([4, 0], [0.5, 3])
    for a, b in ((diagonal, short), (diagonal, long), (short, long)):
        x = np.array([float(v) for v in _exact_crossing(*a, *b)])
        assert _has_vertex(mesh, x), (a, b, x)
    assert mesh.area() == pytest.approx(16.0, rel=1e-12)
