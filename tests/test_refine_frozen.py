"""Refinement with frozen segments (``refine(frozen=ids)``): the hook of the distributed mesher.

A frozen segment is never split by a ``refine`` call; the subsegments refinement needed split
are reported in ``ct.held``; splitting them and refining again converges to a mesh with the
angle bound everywhere.  The oracle: the subsegment set of the frozen segment (vertex pairs
read from the triangulation, compared with the vertices on the segment's line), angles
computed here from coordinates, and ``Mesh.validate()``.
"""

from __future__ import annotations

import numpy as np
import pytest

from meshwright.core.errors import InputError
from meshwright.tri.cdt import cdt_build
from meshwright.tri.ruppert import refine, split_subsegment

SQUARE = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
SIDES = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])


def _size(xy):
    """Fine at the right side x = 1 (segment 1), coarse away from it."""
    return 0.02 + 0.2 * np.abs(xy[:, 0] - 1.0)


def _min_angle(ct):
    p = ct.points[ct.triangles(True)]
    worst = 180.0
    for k in range(3):
        u = p[:, (k + 1) % 3] - p[:, k]
        v = p[:, (k + 2) % 3] - p[:, k]
        c = (u * v).sum(1) / np.linalg.norm(u, axis=1) / np.linalg.norm(v, axis=1)
        worst = min(worst, float(np.degrees(np.arccos(np.clip(c, -1.0, 1.0))).min()))
    return worst


def _on_right_side(ct):
    """Vertex ids on x = 1 in order of y (the frozen side's vertices)."""
    xy = ct.points
    on = np.flatnonzero(xy[:, 0] == 1.0)
    return on[np.argsort(xy[on, 1])]


def test_frozen_side_keeps_its_vertices_and_reports_held_subsegments():
    ct = cdt_build(SQUARE, SIDES)
    ct.classify()
    refine(ct, min_angle=30.0, size=_size, frozen=[1])
    # Nothing was put on the frozen side: its only vertices are the two corners.
    assert list(_on_right_side(ct)) == [1, 2]
    edges, ids = ct.held
    assert edges.dtype == np.int32 and edges.shape == (1, 2)
    assert list(ids) == [1]
    assert sorted(edges[0]) == [1, 2]
    # The other sides were refined as usual.
    assert len(ct.points) > 20


def test_rounds_of_agreed_splits_converge_to_the_angle_bound():
    ct = cdt_build(SQUARE, SIDES)
    ct.classify()
    refine(ct, min_angle=30.0, size=_size, frozen=[1])
    rounds = 0
    while len(ct.held[0]):
        edges, ids = ct.held
        assert (ids == 1).all()
        xy = ct.points.copy()
        side = _on_right_side(ct)
        consecutive = {tuple(sorted(e)) for e in zip(side[:-1], side[1:])}
        for a, b in edges:
            assert tuple(sorted((int(a), int(b)))) in consecutive
            split_subsegment(ct, int(a), int(b), 0.5 * (xy[a] + xy[b]))
        refine(ct, min_angle=30.0, size=_size, frozen=[1])
        rounds += 1
        assert rounds < 12
    assert rounds >= 2
    assert _min_angle(ct) >= 30.0 - 1e-9
    mesh = ct.to_mesh()
    mesh.validate()
    assert np.isclose(mesh.area(), 1.0, rtol=1e-12)


def test_frozen_none_and_empty_are_the_serial_refinement():
    a = cdt_build(SQUARE, SIDES)
    b = cdt_build(SQUARE, SIDES)
    c = cdt_build(SQUARE, SIDES)
    for ct, fz in ((a, None), (b, np.zeros(0, dtype=np.int64)), (c, [7])):
        ct.classify()
        refine(ct, min_angle=30.0, size=_size, frozen=fz)
        assert len(ct.held[0]) == 0
    assert np.array_equal(a.points, b.points) and np.array_equal(a.points, c.points)
    assert np.array_equal(a.triangles(True), b.triangles(True))


@pytest.mark.parametrize("bad", [[[1]], [0.5], "1"])
def test_frozen_must_be_segment_ids(bad):
    ct = cdt_build(SQUARE, SIDES)
    with pytest.raises(InputError, match="frozen"):
        refine(ct, min_angle=30.0, frozen=bad)


def _rounds(ct, shrink):
    """The rounds of the test above; ``shrink`` trims the arrays after every refine call."""
    refine(ct, min_angle=30.0, size=_size, frozen=[1])
    for _ in range(12):
        if shrink:
            ct.shrink()
            s, c = ct.state, ct.constraints
            # Trimmed to what is used: no spare vertex rows, triangle slots or pieces.
            assert s.pts.shape[0] == ct.n_points and c.vtri.shape[0] == ct.n_points
            assert s.tri.shape[0] == s.nbr.shape[0] == s.cons.shape[0] == 3 * c.treg.shape[0]
        edges, _ = ct.held
        if not len(edges):
            return ct
        xy = ct.points.copy()
        for a, b in edges:
            split_subsegment(ct, int(a), int(b), 0.5 * (xy[a] + xy[b]))
        refine(ct, min_angle=30.0, size=_size, frozen=[1])
    raise AssertionError("rounds did not converge")


def test_shrink_between_rounds_gives_the_same_triangulation():
    plain, trimmed = cdt_build(SQUARE, SIDES), cdt_build(SQUARE, SIDES)
    plain.classify()
    trimmed.classify()
    _rounds(plain, False)
    _rounds(trimmed, True)
    assert np.array_equal(plain.points, trimmed.points)
    assert np.array_equal(plain.triangles(True), trimmed.triangles(True))
    assert np.array_equal(plain.triangle_markers(True), trimmed.triangle_markers(True))
    for got, want in zip(trimmed.segments(), plain.segments()):
        assert np.array_equal(got, want)
    def nbytes(ct):
        return sum(a.nbytes for a in tuple(ct.state) + tuple(ct.constraints))

    assert nbytes(trimmed.shrink()) < nbytes(plain)
    # Still usable after the trim: insertion and a finer refinement grow it again.
    trimmed.insert_point(0.25, 0.5)
    refine(trimmed, min_angle=30.0, size=0.05)
    mesh = trimmed.to_mesh()
    mesh.validate()
    assert np.isclose(mesh.area(), 1.0, rtol=1e-12)
