"""Spring-analogy smoothing of tetrahedra (chapter 18.2 generalised): validity, surface kept, quality."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import meshwright as mw
from meshwright.core.errors import InputError
from meshwright.core.quality import tetra_quality
from meshwright.tet.smoothing import smooth_tets


def _det6(p, tet):
    """Six times the signed volume of a tet, in exact rationals (independent of the predicates)."""
    a, b, c, d = ([Fraction(float(x)) for x in p[i]] for i in tet)
    u = [b[k] - a[k] for k in range(3)]
    v = [c[k] - a[k] for k in range(3)]
    w = [d[k] - a[k] for k in range(3)]
    return (
        u[0] * (v[1] * w[2] - v[2] * w[1])
        - u[1] * (v[0] * w[2] - v[2] * w[0])
        + u[2] * (v[0] * w[1] - v[1] * w[0])
    )


def _cube_mesh(seed, interior=300, on_faces=60):
    """Delaunay tets of the unit cube's corners, points on its faces and inside."""
    rng = np.random.default_rng(seed)
    corners = np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)], dtype=float)
    face = rng.random((on_faces, 3))
    face[np.arange(on_faces), rng.integers(0, 3, on_faces)] = rng.integers(0, 2, on_faces)
    tz = mw.delaunay(np.vstack([corners, face, rng.random((interior, 3))]))
    return np.array(tz.points), np.array(tz.tetrahedra), np.array(tz.hull)


@pytest.fixture(scope="module")
def cube():
    p, t, hull = _cube_mesh(0)
    return p, t, hull, smooth_tets(p, t, hull, iterations=5)


def test_every_tet_stays_positive_and_the_volume_is_exact(cube):
    _p, t, _, q = cube
    dets = [_det6(q, tet) for tet in t]
    assert min(dets) > 0
    assert sum(dets) == 6  # the unit cube, exactly: the surface did not move by one ulp


def test_boundary_nodes_stay_on_their_planes(cube):
    p, _t, hull, q = cube
    b = np.unique(hull)
    # Each boundary coordinate that was 0 or 1 is still exactly that.
    on_plane = (p[b] == 0.0) | (p[b] == 1.0)
    assert np.array_equal(q[b][on_plane], p[b][on_plane])
    # Nodes on two or three planes (cube edges, corners) do not move; nodes inside one face slide.
    planes = on_plane.sum(axis=1)
    assert np.array_equal(q[b[planes >= 2]], p[b[planes >= 2]])
    assert (q[b[planes == 1]] != p[b[planes == 1]]).any(axis=1).sum() > 0.5 * (planes == 1).sum()
    assert np.all((q >= 0.0) & (q <= 1.0))


def test_quality_improves(cube):
    p, t, _, q = cube
    before, after = tetra_quality(p, t), tetra_quality(q, t)
    assert after["radius_ratio"].mean() > before["radius_ratio"].mean()
    # The worst tet of each moved node's star never got worse, so neither did the worst tet.
    assert after["radius_ratio"].min() >= before["radius_ratio"].min()
    assert after["min_dihedral"].min() > before["min_dihedral"].min()
    interior = np.setdiff1d(np.arange(len(p)), np.unique(cube[2]))
    assert (q[interior] != p[interior]).any(axis=1).mean() > 0.75


def test_zero_iterations_is_the_identity(cube):
    p, t, hull, _ = cube
    q = smooth_tets(p, t, hull, iterations=0)
    assert np.array_equal(q, p) and q is not p and q.dtype == np.float64


def test_default_boundary_is_the_hull(cube):
    p, t, _hull, q = cube
    np.testing.assert_array_equal(smooth_tets(p, t, iterations=5), q)


def test_fixed_and_markers():
    p, t, hull = _cube_mesh(1, interior=120, on_faces=40)
    interior = np.setdiff1d(np.arange(len(p)), np.unique(hull))
    keep = interior[::3]
    q = smooth_tets(p, t, hull, fixed=keep)
    assert np.array_equal(q[keep], p[keep])
    mask = np.zeros(len(p), dtype=bool)
    mask[keep] = True
    np.testing.assert_array_equal(smooth_tets(p, t, hull, fixed=mask), q)
    # Split the z = 0 side into two markers by the sign of x - 1/2: nodes where both meet stay.
    bottom = (p[hull][:, :, 2] == 0.0).all(axis=1)
    right = p[hull].mean(axis=1)[:, 0] > 0.5
    markers = np.where(bottom & right, 2, 1)
    q = smooth_tets(p, t, hull, markers=markers)
    nodes_1 = np.unique(hull[bottom & ~right])
    nodes_2 = np.unique(hull[bottom & right])
    border = np.intersect1d(nodes_1, nodes_2)
    assert len(border) > 0
    assert np.array_equal(q[border], p[border])


def test_tilted_plane_nodes_stay_exactly_on_it():
    # The prism x, y >= 0, x + y <= 1, 0 <= z <= 1: points on x + y = 1 with dyadic x lie on
    # it exactly; every boundary node that was on it stays on it exactly.
    rng = np.random.default_rng(2)
    corners = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [0, 1, 1]], dtype=float)
    x = rng.integers(1, 64, 40) / 64.0
    slant = np.column_stack([x, 1.0 - x, rng.integers(1, 64, 40) / 64.0])
    inside = rng.random((400, 3)) * [0.5, 0.5, 1.0]
    tz = mw.delaunay(np.vstack([corners, slant, inside]))
    p, t, hull = np.array(tz.points), np.array(tz.tetrahedra), np.array(tz.hull)
    q = smooth_tets(p, t, hull)
    on = [i for i in np.unique(hull) if Fraction(p[i, 0]) + Fraction(p[i, 1]) == 1]
    assert len(on) >= 40
    assert all(Fraction(q[i, 0]) + Fraction(q[i, 1]) == 1 for i in on)
    assert min(_det6(q, tet) for tet in t) > 0
    assert sum(_det6(q, tet) for tet in t) == 3  # six times the prism's volume 1/2


@settings(deadline=None, max_examples=15)
@given(st.integers(0, 2**31 - 1), st.integers(1, 8), st.floats(0.1, 1.0))
def test_random_meshes_stay_valid(seed, iterations, relax):
    p, t, hull = _cube_mesh(seed, interior=40, on_faces=20)
    q = smooth_tets(p, t, hull, iterations=iterations, relax=relax)
    dets = [_det6(q, tet) for tet in t]
    assert min(dets) > 0 and sum(dets) == 6
    b = np.unique(hull)
    on_plane = (p[b] == 0.0) | (p[b] == 1.0)
    assert np.array_equal(q[b][on_plane], p[b][on_plane])
    assert tetra_quality(q, t)["radius_ratio"].min() >= tetra_quality(p, t)["radius_ratio"].min()


def test_bad_input_names_the_argument():
    p, t, hull = _cube_mesh(3, interior=20, on_faces=0)
    flipped = t.copy()
    flipped[5, [2, 3]] = flipped[5, [3, 2]]
    nan = p.copy()
    nan[4, 1] = np.nan
    cases = [
        ({"points": p[:, :2]}, "points"),
        ({"points": nan}, "points: point 4"),
        ({"points": p * 1e300}, "points"),
        ({"tets": t[:, :3]}, "tets"),
        ({"tets": t.astype(float)}, "tets"),
        ({"tets": np.where(t == 0, len(p), t)}, "tets row"),
        ({"tets": flipped}, "tets row 5"),
        ({"boundary_faces": hull[:, :2]}, "boundary_faces"),
        ({"boundary_faces": np.array([_not_a_face(t)])}, "boundary_faces row 0 .* not a face"),
        ({"iterations": -1}, "iterations"),
        ({"iterations": 1.5}, "iterations"),
        ({"iterations": True}, "iterations"),
        ({"relax": 0.0}, "relax"),
        ({"relax": 1.5}, "relax"),
        ({"relax": np.nan}, "relax"),
        ({"fixed": [len(p)]}, "fixed"),
        ({"fixed": np.zeros(3, dtype=bool)}, "fixed"),
        ({"markers": np.ones(3, dtype=int)}, "markers"),
    ]
    for change, message in cases:
        args = {"points": p, "tets": t, "boundary_faces": hull} | change
        points, tets, faces = args.pop("points"), args.pop("tets"), args.pop("boundary_faces")
        with pytest.raises(InputError, match=message):
            smooth_tets(points, tets, faces, **args)
    with pytest.raises(InputError, match="markers need boundary_faces"):
        smooth_tets(p, t, markers=np.ones(len(hull), dtype=int))


def _not_a_face(t):
    """Three nodes that are no face of any tet."""
    faces = {frozenset(tet[list(k)]) for tet in t for k in ((1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2))}
    n = int(t.max()) + 1
    for a in range(n):
        for b in range(a + 1, n):
            for c in range(b + 1, n):
                if frozenset((a, b, c)) not in faces:
                    return [a, b, c]
    raise AssertionError("every triple is a face")
