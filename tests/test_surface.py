"""geometry.Surface and its built-ins and readers: orientation and volume against formulas
computed here (exact rationals for polyhedra), every bad-input class named, the exact
triangle-pair test against a separating-axis oracle in integer arithmetic, file round trips."""

import itertools
import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from meshwright.core.errors import (
    FormatError,
    GeometryError,
    InputError,
    SizeError,
    fmt_point,
)
from meshwright.core.mesh import Mesh
from meshwright.geometry import (
    Surface,
    box,
    combine,
    extrude,
    far_field,
    read_surface,
    sphere,
    write_smesh,
)
from meshwright.geometry._surface_kernels import (
    HIT_CROSS,
    HIT_FOLD,
    HIT_VERTEX,
    NO_HIT,
    find_intersection,
)


def exact_volume(points, triangles):
    """Signed enclosed volume as a Fraction: sum of det[a, b, c] / 6 over the faces."""
    total = Fraction(0)
    for a, b, c in triangles:
        (ax, ay, az), (bx, by, bz), (cx, cy, cz) = (tuple(map(Fraction, points[v])) for v in (a, b, c))
        total += ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)
    return total / 6


def pair_kind(points, triangles):
    pts = np.asarray(points, dtype=np.float64)
    tri = np.asarray(triangles, dtype=np.int32)
    res, _ = find_intersection(pts, tri.ravel(), np.arange(len(tri), dtype=np.int64))
    return int(res[2])


# ------------------------------------------------------------------ built-ins


def test_box_volume_and_markers_exact():
    lo, hi = (-1.5, 0.25, 2.0), (0.5, 3.0, 2.125)
    b = box(lo, hi)
    b.validate()
    assert b.n_faces == 12 and b.n_points == 8
    assert exact_volume(b.points, b.triangles) == Fraction(2) * Fraction(11, 4) * Fraction(1, 8)
    assert np.array_equal(np.bincount(b.markers), [0, 2, 2, 2, 2, 2, 2])
    # Each side's faces lie on its plane and point away from the box.
    centre = (np.array(lo) + np.array(hi)) / 2
    for side in range(6):
        axis, high = divmod(side, 2)
        faces = b.triangles[b.markers == side + 1]
        coords = b.points[faces][..., axis]
        assert np.all(coords == (hi if high else lo)[axis])
        p = b.points[faces]
        normal = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
        assert np.all(np.einsum("mi,mi->m", normal, p[:, 0] - centre) > 0)


@pytest.mark.parametrize("level", [0, 1, 2, 3])
def test_sphere_counts_radius_and_outward(level):
    s = sphere(2.0, (1.0, -1.0, 0.5), level)
    s.validate()
    assert s.n_faces == 20 * 4**level and s.n_points == 10 * 4**level + 2
    r = np.linalg.norm(s.points - [1.0, -1.0, 0.5], axis=1)
    assert np.allclose(r, 2.0, rtol=0, atol=1e-14)
    p = s.points[s.triangles] - [1.0, -1.0, 0.5]
    assert np.all(np.einsum("mi,mi->m", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p.mean(axis=1)) > 0)


def test_sphere_volume_converges_from_below():
    exact = 4.0 / 3.0 * math.pi
    volumes = []
    for level in range(6):
        s = sphere(level=level)
        # Independent of Surface.enclosed_volume: tets from the centre by numpy's det.
        v = np.linalg.det(s.points[s.triangles]).sum() / 6.0
        assert v == pytest.approx(s.enclosed_volume(), rel=1e-12)
        volumes.append(v)
    assert all(v < exact for v in volumes)
    assert all(a < b for a, b in itertools.pairwise(volumes))
    assert exact - volumes[-1] < 2e-3 * exact
    # Second-order convergence: each level divides the error by about four.
    errors = [exact - v for v in volumes]
    assert all(3.0 < a / b < 5.0 for a, b in itertools.pairwise(errors[2:]))


def test_builtins_reject_bad_arguments():
    with pytest.raises(GeometryError, match="along y"):
        box((0, 1, 0), (1, 1, 1))
    with pytest.raises(InputError, match="hi"):
        box((0, 0, 0), (1, np.nan, 1))
    with pytest.raises(InputError, match="three numbers"):
        box((0, 0), (1, 1))
    with pytest.raises(SizeError, match="radius"):
        sphere(-1.0)
    with pytest.raises(InputError, match="level"):
        sphere(level=10)
    with pytest.raises(InputError, match="level"):
        sphere(level=1.5)


def _square_mesh(hole=False):
    """A unit square (optionally with a square hole) as counter-clockwise triangles."""
    outer = [(0, 0), (3, 0), (3, 3), (0, 3)]
    inner = [(1, 1), (2, 1), (2, 2), (1, 2)]
    pts = np.array(outer + inner, dtype=float)
    if hole:
        tri = [[0, 1, 5], [0, 5, 4], [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]]
    else:
        tri = [[0, 1, 5], [0, 5, 4], [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7],
               [4, 5, 6], [4, 6, 7]]
    lines = [[0, 1], [1, 2], [2, 3], [3, 0]] + ([[4, 5], [5, 6], [6, 7], [7, 4]] if hole else [])
    markers = [7] * 4 + ([9] * 4 if hole else [])
    return Mesh(pts, {"triangle": tri, "line": lines}, cell_data={"marker": {"line": markers}})


@pytest.mark.parametrize("hole", [False, True])
@pytest.mark.parametrize("layers", [1, 3])
def test_extrude_volume_walls_and_tunnel(hole, layers):
    s = extrude(_square_mesh(hole), 0.5, z0=-1.0, layers=layers, markers=(1, 2, 3))
    s.validate()
    area = 9 - (1 if hole else 0)
    assert exact_volume(s.points, s.triangles) == Fraction(area) / 2
    walls = 4 * (2 if hole else 1)
    n_cap = 8 if hole else 10
    assert np.array_equal(np.bincount(s.markers), [0, n_cap, n_cap, 2 * walls * layers])
    assert s.points[:, 2].min() == -1.0 and s.points[:, 2].max() == -0.5
    # A hole makes a tunnel: still one shell (walls join the caps), genus 1 by Euler.
    assert len(np.unique(s.shells())) == 1
    edges = {tuple(sorted(e)) for f in s.triangles for e in itertools.combinations(f, 2)}
    assert s.n_points - len(edges) + s.n_faces == (0 if hole else 2)


def test_extrude_line_markers_and_refusals():
    s = extrude(_square_mesh(True), 1.0, line_markers=True)
    wall = ~np.isin(np.arange(s.n_faces), np.arange(16))
    assert set(s.markers[wall]) == {7, 9}
    from meshwright.geometry import rectangle

    with pytest.raises(InputError, match="triangulate"):
        extrude(rectangle(0, 0, 1, 1), 1.0)
    with pytest.raises(InputError, match="height"):
        extrude(_square_mesh(), 0.0)
    with pytest.raises(InputError, match="layers"):
        extrude(_square_mesh(), 1.0, layers=0)
    m = _square_mesh()
    cw = Mesh(m.points, {"triangle": m.triangles[:, [0, 2, 1]]})
    with pytest.raises(GeometryError, match="triangle 0 .*counter-clockwise"):
        extrude(cw, 1.0)
    bare = Mesh(m.points, {"triangle": m.triangles})
    with pytest.raises(InputError, match="marker"):
        extrude(bare, 1.0, line_markers=True)


def test_extruded_naca_wing_in_far_field():
    import meshwright
    from meshwright.geometry import naca

    section = meshwright.triangulate(naca("0012"), 0.04)
    wing = extrude(section, 2.0, z0=-1.0, layers=4, markers=(11, 12, 13))
    wing.validate()
    # Volume by the shoelace area of the 2-D triangles, computed here.
    p = section.points[section.triangles]
    area = 0.5 * np.sum((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
                        - (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1]))
    assert wing.enclosed_volume() == pytest.approx(2.0 * area, rel=1e-12)
    s = far_field(wing, (-2, -2, -2), (3, 2, 2))
    s.validate()
    assert s.enclosed_volume() == pytest.approx(80.0 - 2.0 * area, rel=1e-12)


def test_thin_plate_and_needles_validate():
    box((0, 0, 0), (1, 1, 1e-3)).validate()
    box((0, 0, 0), (1e3, 1e-3, 1e-3)).validate()
    # 20:1 size jumps: a fine sphere inside a coarse far field.
    far_field(sphere(0.05, (0.5, 0.5, 0.5), 3), (-0.5, -0.5, -0.5), (1.5, 1.5, 1.5)).validate()


def test_far_field_combine_shells_and_volume():
    body = sphere(0.5, (0.5, 0.5, 0.5), 2)
    body.markers[:] = 7
    s = far_field(body, (-1, -1, -1), (2, 2, 2))
    s.validate()
    assert s.enclosed_volume() == pytest.approx(27.0 - body.enclosed_volume(), rel=1e-12)
    assert len(np.unique(s.shells())) == 2
    assert set(s.markers) == {1, 2, 3, 4, 5, 6, 7}
    with pytest.raises(GeometryError, match="not strictly inside"):
        far_field(body, (0, 0, 0), (2, 2, 2))


def test_combine_merges_points_and_interfaces():
    a, b = box((0, 0, 0), (1, 1, 1)), box((1, 0, 0), (2, 1, 1))
    s = combine(a, b)
    assert s.n_points == 12
    assert s.n_faces == 22  # the shared side's two faces are kept once
    assert s.multi_region
    s.validate()
    # Two boxes touching along one edge: that edge lies in four faces.
    c = combine(a, box((1, 1, 0), (2, 2, 1)))
    assert c.multi_region and c.n_points == 14
    c.validate()
    with pytest.raises(GeometryError, match="non-manifold edge .* lies in 4 faces"):
        Surface(c.points, c.triangles).validate()
    # Identical surfaces merge into one, keeping the first markers.
    d = combine(a, a)
    assert d.n_faces == 12 and not d.multi_region


# ------------------------------------------------------------------ bad input, named


def test_door_names_bad_rows():
    b = box()
    pts = b.points.copy()
    pts[3, 1] = np.nan
    with pytest.raises(InputError, match="point 3"):
        Surface(pts, b.triangles)
    with pytest.raises(InputError, match="row 5"):
        Surface(b.points, np.vstack([b.triangles[:5], [[0, 1, 8]], b.triangles[6:]]))
    with pytest.raises(InputError, match=r"row 2 \[4, 4, 1\] repeats"):
        Surface(b.points, [[0, 1, 2], [1, 2, 3], [4, 4, 1]])
    with pytest.raises(InputError, match="markers"):
        Surface(b.points, b.triangles, markers=np.ones(11, int))
    with pytest.raises(InputError, match="regions"):
        Surface(b.points, b.triangles, regions=[[0.5, 0.5, 0.5, 1.0]])
    with pytest.raises(InputError, match="region_id"):
        Surface(b.points, b.triangles, regions=[[0.5, 0.5, 0.5, 1.5, 0.1]])
    with pytest.raises(InputError, match="multi_region"):
        Surface(b.points, b.triangles, multi_region=1)
    with pytest.raises(InputError, match="at least one triangle"):
        Surface(b.points, np.zeros((0, 3), int))


def test_open_edge_named_with_coordinates():
    b = box()
    gone = b.triangles[4]
    s = Surface(b.points, np.delete(b.triangles, 4, axis=0))
    with pytest.raises(GeometryError, match="open edge") as info:
        s.validate()
    msg = str(info.value)
    i, j = (int(v) for v in msg.split("open edge (")[1].split(")")[0].split(", "))
    assert {i, j} <= set(gone.tolist())
    assert f"from {fmt_point(b.points[i])} to {fmt_point(b.points[j])}" in msg


def test_inconsistent_orientation_named():
    b = box()
    tri = b.triangles.copy()
    tri[7] = tri[7, [0, 2, 1]]
    with pytest.raises(GeometryError, match=r"same direction by face (7 |\d+ \(.*\) and face 7 ).*not consistently"):
        Surface(b.points, tri).validate()
    assert Surface(b.points, tri).oriented().enclosed_volume() == pytest.approx(1.0)


def test_degenerate_face_named():
    pts = [[0, 0, 0], [1, 1, 1], [3, 3, 3], [0, 1, 0]]
    with pytest.raises(GeometryError, match=r"face 1 \(0, 1, 2\) is degenerate"):
        Surface(pts, [[0, 1, 3], [0, 1, 2]]).validate()


def test_duplicate_and_unused_points_named():
    b = box()
    pts = np.vstack([b.points, b.points[5]])
    with pytest.raises(GeometryError, match="point 8 .* used by no face"):
        Surface(pts, b.triangles).validate()
    tri = b.triangles.copy()
    f = int(np.flatnonzero((tri == 5).any(axis=1))[0])
    tri[f][tri[f] == 5] = 8
    with pytest.raises(GeometryError, match=r"points 5 and 8 coincide at \(1, 0, 1\)"):
        Surface(pts, tri).validate()


def test_duplicate_face_named():
    b = box()
    with pytest.raises(GeometryError, match=r"face 3 .* and face 12 .* same vertices"):
        Surface(b.points, np.vstack([b.triangles, b.triangles[3, [1, 2, 0]]])).validate()


def test_overlapping_boxes_intersect():
    s = combine(box((0, 0, 0), (1, 1, 1)), box((0.5, 0.25, 0.25), (1.5, 0.75, 0.75)))
    with pytest.raises(GeometryError, match=r"face \d+ \(.*\) and face \d+ \(.*\) .* near \("):
        s.validate()


def test_inverted_shells_named():
    with pytest.raises(GeometryError, match="inverted: it lies inside 0 other shells"):
        box().flipped().validate()
    inner = sphere(0.25, (0.5, 0.5, 0.5), 1)
    with pytest.raises(GeometryError, match="inverted: it lies inside 1 other shells, so it is a cavity"):
        combine(box(), inner).validate()
    combine(box(), inner.flipped()).validate()
    # A solid inside the cavity (depth 2) must be positive again.
    core = sphere(0.1, (0.5, 0.5, 0.5), 1)
    combine(box(), inner.flipped(), core).validate()
    with pytest.raises(GeometryError, match="lies inside 2 other shells"):
        combine(box(), inner.flipped(), core.flipped()).validate()


def test_oriented_restores_random_flips():
    s = combine(box((-1, -1, -1), (2, 2, 2)), sphere(0.5, (0.5, 0.5, 0.5), 2).flipped(), sphere(0.2, (0.5, 0.5, 0.5), 1))
    rng = np.random.default_rng(3)
    tri = s.triangles.copy()
    flip = rng.random(len(tri)) < 0.5
    tri[flip] = tri[flip][:, [0, 2, 1]]
    o = Surface(s.points, tri, s.markers).oriented()
    o.validate()
    assert np.array_equal(o.triangles, s.triangles)


@given(st.lists(st.tuples(*[st.integers(-2, 10).map(lambda v: v / 4)] * 3), min_size=1, max_size=30))
def test_inside_even_odd_against_boxes(pts):
    # A box with a box cavity holding a box core; the grid of quarter points meets the
    # planes, edges and vertices of the faces (the ray's degenerate cases).
    s = combine(box((0, 0, 0), (2, 2, 2)), box((0.5, 0.5, 0.5), (1.5, 1.5, 1.5)).flipped(),
                box((0.75, 0.75, 0.75), (1.25, 1.25, 1.25)))
    pts = np.array(pts)

    def strictly_in(lo, hi):
        return np.all((pts > lo) & (pts < hi), axis=1)

    def on_boundary(lo, hi):
        closed = np.all((pts >= lo) & (pts <= hi), axis=1)
        return closed & ~strictly_in(lo, hi)

    on = on_boundary(0, 2) | on_boundary(0.5, 1.5) | on_boundary(0.75, 1.25)
    expected = strictly_in(0, 2) & ~(strictly_in(0.5, 1.5) & ~strictly_in(0.75, 1.25))
    assert np.array_equal(s.inside(pts)[~on], expected[~on])


# ------------------------------------------------------------------ the pair test


def test_crafted_pairs():
    # Two triangles crossing through each other's interior.
    assert pair_kind([[0, 0, 0], [2, 0, 0], [0, 2, 0], [0.5, 0.5, -1], [0.5, 0.5, 1], [3, 3, 0.5]],
                     [[0, 1, 2], [3, 4, 5]]) == HIT_CROSS
    # Coplanar overlap without shared vertices, and one inside the other.
    assert pair_kind([[0, 0, 0], [2, 0, 0], [0, 2, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]],
                     [[0, 1, 2], [3, 4, 5]]) == HIT_CROSS
    assert pair_kind([[0, 0, 0], [4, 0, 0], [0, 4, 0], [1, 1, 0], [2, 1, 0], [1, 2, 0]],
                     [[0, 1, 2], [3, 4, 5]]) == HIT_CROSS
    # A folded pair: sharing edge 0-1, third vertices on the same side in one plane.
    assert pair_kind([[0, 0, 0], [2, 0, 0], [0, 2, 0], [1, 1, 0]], [[0, 1, 2], [1, 0, 3]]) == HIT_FOLD
    # Sharing an edge, flat but on opposite sides, or bent: fine.
    assert pair_kind([[0, 0, 0], [2, 0, 0], [0, 2, 0], [1, -1, 0]], [[0, 1, 2], [1, 0, 3]]) == NO_HIT
    assert pair_kind([[0, 0, 0], [2, 0, 0], [0, 2, 0], [1, 1, 1]], [[0, 1, 2], [1, 0, 3]]) == NO_HIT
    # Touching at a shared vertex only, in and out of plane.
    assert pair_kind([[0, 0, 0], [1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0]], [[0, 1, 2], [0, 3, 4]]) == NO_HIT
    assert pair_kind([[0, 0, 0], [1, 0, 0], [0, 1, 0], [-1, -1, 1], [1, -1, 5]], [[0, 1, 2], [0, 3, 4]]) == NO_HIT
    # Sharing a vertex and overlapping in one plane, or piercing.
    assert pair_kind([[0, 0, 0], [2, 0, 0], [0, 2, 0], [1, 1, 0], [2, 1, 0]], [[0, 1, 2], [0, 3, 4]]) == HIT_VERTEX
    assert pair_kind([[0, 0, 0], [2, 0, 0], [0, 2, 0], [1, 0.5, -1], [0.5, 1, 1]], [[0, 1, 2], [0, 3, 4]]) == HIT_VERTEX
    # A vertex of one touching the interior of the other (no shared index) is a contact.
    assert pair_kind([[0, 0, 0], [2, 0, 0], [0, 2, 0], [0.5, 0.5, 0], [1, 1, 1], [0, 1, 1]],
                     [[0, 1, 2], [3, 4, 5]]) == HIT_CROSS


def _sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def sat_meet(A, B):
    """Closed convex hulls of the integer point lists A and B meet: no separating axis among
    the edge directions, the normals and all their cross products (exact integers)."""
    dirs = [_sub(p, q) for S in (A, B) for p, q in itertools.combinations(S, 2)]
    normals = [_cross(_sub(S[1], S[0]), _sub(S[2], S[0])) for S in (A, B) if len(S) == 3]
    base = dirs + normals
    axes = base + [_cross(u, v) for u, v in itertools.combinations(base, 2)]
    for ax in axes:
        if not any(ax):
            continue
        pa = [_dot(ax, p) for p in A]
        pb = [_dot(ax, p) for p in B]
        if max(pa) < min(pb) or max(pb) < min(pa):
            return False
    return True


coord = st.integers(-3, 3)
point = st.tuples(coord, coord, coord)


def _nondegenerate(a, b, c):
    return any(_cross(_sub(b, a), _sub(c, a)))


@given(st.lists(point, min_size=6, max_size=6, unique=True))
def test_pair_without_shared_vertex_matches_sat(pts):
    A, B = pts[:3], pts[3:]
    assume(_nondegenerate(*A) and _nondegenerate(*B))
    assert (pair_kind(pts, [[0, 1, 2], [3, 4, 5]]) != NO_HIT) == sat_meet(A, B)


@given(st.lists(point, min_size=5, max_size=5, unique=True))
def test_pair_with_shared_vertex_matches_sat(pts):
    a, b, c, d, e = pts
    assume(_nondegenerate(a, b, c) and _nondegenerate(a, d, e))
    # The triangles meet beyond a iff their cones at a do: the segment [b - a, c - a] meets
    # the triangle (0, R (d - a), R (e - a)) for R beyond every Cramer ratio of these coordinates.
    R = 10**4
    seg = [_sub(b, a), _sub(c, a)]
    cone = [(0, 0, 0), tuple(R * x for x in _sub(d, a)), tuple(R * x for x in _sub(e, a))]
    assert (pair_kind(pts, [[0, 1, 2], [0, 3, 4]]) != NO_HIT) == sat_meet(seg, cone)


# ------------------------------------------------------------------ fuzz


# Magnitudes below 1e-6 become 0: the door refuses coordinates under the predicates' exact
# range (2**-148), which a subnormal shift would give.
unit = st.floats(-1, 1).map(lambda x: x if abs(x) > 1e-6 else 0.0)
offset = st.floats(-100, 100).map(lambda x: x if abs(x) > 1e-6 else 0.0)


@given(st.lists(unit, min_size=9, max_size=9), st.tuples(offset, offset, offset), st.floats(1e-3, 1e3))
def test_moved_box_stays_valid(gauss, shift, scale):
    q, r = np.linalg.qr(np.reshape(gauss, (3, 3)) + 3 * np.eye(3))
    q = q * np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    b = box((0, 0, 0), (1, 2, 3))
    moved = Surface(scale * b.points @ q.T + shift, b.triangles, b.markers)
    moved.validate()
    assert moved.enclosed_volume() == pytest.approx(6 * scale**3, rel=1e-9)


# ------------------------------------------------------------------ files


@pytest.mark.parametrize("ext", ["stl", "obj", "off", "vtu"])
def test_meshio_round_trip(tmp_path, ext):
    meshio = pytest.importorskip("meshio")
    s = sphere(level=2)
    path = tmp_path / f"sphere.{ext}"
    meshio.write_points_cells(path, s.points, [("triangle", s.triangles)])
    r = read_surface(path)
    r.validate()
    assert r.n_faces == s.n_faces and r.n_points == s.n_points
    # Match the points (STL is written rounded, STL's reader reorders them), then compare
    # the faces as oriented triples of the original numbering.
    dist = np.linalg.norm(r.points[:, None] - s.points[None], axis=2)
    match = dist.argmin(axis=1)
    assert dist.min(axis=1).max() <= (1e-6 if ext == "stl" else 0.0)
    assert len(np.unique(match)) == s.n_points

    def oriented_faces(tri):
        rolled = [np.roll(t, -int(np.argmin(t))) for t in tri]
        return sorted(map(tuple, rolled))

    assert oriented_faces(match[r.triangles]) == oriented_faces(s.triangles)


SMESH = """# a unit box with a cubic cavity, 1-based, unoriented quads
16 3 0 0
1 0 0 0
2 1 0 0
3 1 1 0
4 0 1 0
5 0 0 1
6 1 0 1
7 1 1 1
8 0 1 1
9 0.25 0.25 0.25
10 0.75 0.25 0.25
11 0.75 0.75 0.25
12 0.25 0.75 0.25
13 0.25 0.25 0.75
14 0.75 0.25 0.75
15 0.75 0.75 0.75
16 0.25 0.75 0.75
12 1
4 1 2 3 4 1
4 5 6 7 8 1   # same sense as the bottom: TetGen does not care
4 1 2 6 5 1
4 2 3 7 6 1
4 3 4 8 7 1
4 4 1 5 8 1
4 9 10 11 12 2
4 13 14 15 16 2
4 9 10 14 13 2
4 10 11 15 14 2
4 11 12 16 15 2
4 12 9 13 16 2
1
1 0.5 0.5 0.5
1
1 0.1 0.1 0.1 7 0.01
"""


def test_smesh_with_hole_and_region(tmp_path):
    path = tmp_path / "cavity.smesh"
    path.write_text(SMESH)
    s = read_surface(path)
    s.validate()
    assert s.n_points == 16 and s.n_faces == 24
    assert np.array_equal(np.bincount(s.markers), [0, 12, 12])
    assert np.array_equal(s.holes, [[0.5, 0.5, 0.5]])
    assert np.array_equal(s.regions, [[0.1, 0.1, 0.1, 7, 0.01]])
    assert exact_volume(s.points, s.triangles) == 1 - Fraction(1, 8)
    again = read_surface(write_smesh(s, tmp_path / "again.smesh"))
    assert np.array_equal(again.points, s.points) and np.array_equal(again.triangles, s.triangles)
    assert np.array_equal(again.regions, s.regions) and np.array_equal(again.holes, s.holes)


def test_tetgen_poly_and_node_face(tmp_path):
    (tmp_path / "b.node").write_text("8 3 0 0\n" + "".join(
        f"{i} {i & 1} {(i >> 1) & 1} {(i >> 2) & 1}\n" for i in range(8)))
    facets = [[0, 4, 6, 2], [1, 3, 7, 5], [0, 1, 5, 4], [2, 6, 7, 3], [0, 2, 3, 1], [4, 5, 7, 6]]
    body = "".join(f"1 0 {k + 1}\n4 {' '.join(map(str, f))}\n" for k, f in enumerate(facets))
    (tmp_path / "b.poly").write_text(f"0 3 0 0\n6 1\n{body}0\n")
    s = read_surface(tmp_path / "b.poly")
    s.validate()
    assert exact_volume(s.points, s.triangles) == 1
    assert np.array_equal(np.bincount(s.markers), [0, 2, 2, 2, 2, 2, 2])
    b = box()
    (tmp_path / "b.face").write_text("12 1\n" + "".join(
        f"{i} {t[0]} {t[2]} {t[1]} {m}\n" for i, (t, m) in enumerate(zip(b.triangles, b.markers))))
    f = read_surface(tmp_path / "b.face")
    f.validate()
    assert np.array_equal(f.triangles, b.triangles)


@pytest.mark.parametrize(
    "text, match",
    [
        ("3 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n1 0\n3 0 1 5\n0\n", "line 6: corner 5 outside"),
        ("3 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n1 0\n2 0 1\n0\n", "line 6: a polygon of 2 corners"),
        ("3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n", "line 1: dimension must be 3"),
        ("3 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n2 0\n3 0 1 2\n", "unexpected end of file"),
        ("4 3 0 0\n0 0 0 0\n1 1 0 0\n2 2 0 0\n3 3 0 0\n1 0\n4 0 1 2 3\n0\n", "line 7: the polygon of 4 corners"),
    ],
)
def test_smesh_errors_name_the_line(tmp_path, text, match):
    path = tmp_path / "bad.smesh"
    path.write_text(text)
    with pytest.raises(FormatError, match=match):
        read_surface(path)


def test_from_mesh_drops_unused_points_and_reads_markers():
    b = box()
    pts = np.vstack([[9.0, 9.0, 9.0], b.points])
    m = Mesh(pts, {"triangle": b.triangles + 1, "line": [[0, 1]]}, cell_data={"marker": {"triangle": b.markers + 10}})
    s = Surface.from_mesh(m)
    assert s.n_points == 8 and np.array_equal(s.triangles, b.triangles)
    assert np.array_equal(s.markers, b.markers + 10)
    s.validate()
    with pytest.raises(InputError, match="3-D"):
        Surface.from_mesh(Mesh(np.zeros((3, 2)), {"triangle": [[0, 1, 2]]}))
