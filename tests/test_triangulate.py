"""Quality triangle meshes of 2-D domains: ``meshwright.triangulate`` and the CDT under it.

Every mesh is checked for what a solver relies on: ``Mesh.validate()``, every input segment
present as a union of boundary edges, no triangle outside the domain, the area of the
discretised domain, boundary nodes on their true curves, markers on the right edges, and
the minimum angle away from small input angles.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import meshwright as mw
from meshwright import geometry as g
from meshwright.core.errors import GeometryError, InputError, MeshingError
from meshwright.tri.cdt import cdt_build
from meshwright.tri.ruppert import refine

METHODS = sorted(mw.MESH_METHODS)


def _shoelace(points, lines):
    """Signed area enclosed by oriented boundary line cells (sum of edge cross products)."""
    a, b = points[lines[:, 0]], points[lines[:, 1]]
    return 0.5 * float(np.sum(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]))


def _on_segment(p, a, b):
    """On the closed segment ab up to rounding (split points are rounded midpoints)."""
    d = np.subtract(b, a)
    L = math.hypot(*d)
    t = float(np.dot(np.subtract(p, a), d)) / L**2
    q = np.subtract(p, a)
    off = abs(float(d[0] * q[1] - d[1] * q[0])) / L
    return -1e-12 <= t <= 1 + 1e-12 and off <= 1e-12 * L


def _angles(points, tris):
    p = points[tris]
    e = [p[:, (k + 2) % 3] - p[:, (k + 1) % 3] for k in range(3)]
    lens = [np.hypot(*v.T) for v in e]
    out = []
    for k in range(3):
        # angle at vertex k, opposite edge k
        b, c = lens[(k + 1) % 3], lens[(k + 2) % 3]
        cosv = (b * b + c * c - lens[k] ** 2) / (2 * b * c)
        out.append(np.degrees(np.arccos(np.clip(cosv, -1, 1))))
    return np.column_stack(out)


def _distance_to_boundary(domain, xy):
    dist = np.full(len(xy), np.inf)
    for cid in range(len(domain.curves)):
        _, q = domain.project(np.full(len(xy), cid), xy)
        dist = np.minimum(dist, np.hypot(*(q - xy).T))
    return dist


def check(mesh, domain, min_angle=None, straight=False, small_input_angle_nodes=()):
    mesh.validate()
    pts = mesh.points
    tris = mesh.cells["triangle"]
    lines = mesh.cells["line"]
    boundary = mesh.boundary_facets()
    # Every boundary edge of the triangulation is a line cell.
    bset = {tuple(sorted(e)) for e in boundary.tolist()}
    lset = {tuple(sorted(e)) for e in lines.tolist()}
    assert bset <= lset
    # Area: exactly the polygon bounded by the boundary line cells.
    assert mesh.area() == pytest.approx(_shoelace(pts, boundary), rel=1e-12)
    if straight:
        assert mesh.area() == pytest.approx(domain.area(), rel=1e-12)
    # No triangle outside the domain: a centroid outside the true domain is allowed only
    # where a chord of a curved boundary cuts the curve (within a sliver of the triangle).
    cen = pts[tris].mean(axis=1)
    out = ~domain.contains(cen)
    if straight:
        assert not out.any()
    elif out.any():
        edge = np.hypot(*(pts[tris[out]] - pts[tris[out][:, [1, 2, 0]]]).transpose(2, 0, 1)).max(axis=1)
        assert (_distance_to_boundary(domain, cen[out]) <= 0.25 * edge).all()
    # Boundary nodes on the true curves.
    on = np.unique(lines)
    scale = max(np.ptp(pts[:, 0]), np.ptp(pts[:, 1]))
    assert _distance_to_boundary(domain, pts[on]).max() <= 1e-9 * scale
    if min_angle is not None:
        ang = _angles(pts, tris).min(axis=1)
        near_small = np.isin(tris, list(small_input_angle_nodes)).any(axis=1)
        assert ang[~near_small].min() >= min_angle - 1e-7


def _segments_present(mesh, disc):
    """Every discretised segment is the union of line cells lying on it."""
    pts = mesh.points
    lines = mesh.cells["line"]
    for a_i, b_i in disc.segments:
        a, b = disc.points[a_i], disc.points[b_i]
        total = 0.0
        for u, w in lines:
            if _on_segment(pts[u], a, b) and _on_segment(pts[w], a, b):
                total += math.dist(pts[u], pts[w])
        assert total == pytest.approx(math.dist(a, b), rel=1e-12)


# ---------------------------------------------------------------------------- CDT
def check_structure(ct):
    """The kernel arrays themselves: neighbour and constraint symmetry, orientation, flags."""
    from meshwright.core.flat import GHOST
    from meshwright.core.predicates import orient2d

    s = ct.state
    ntri = int(s.meta[0])
    tri, nbr, cons, treg, P = s.tri, s.nbr, s.cons, ct.constraints.treg, s.pts
    for t in range(ntri):
        for k in range(3):
            n = int(nbr[3 * t + k])
            u, w = tri[3 * t + (k + 1) % 3], tri[3 * t + (k + 2) % 3]
            j = [m for m in range(3) if nbr[3 * n + m] == t]
            assert len(j) == 1, f"triangle {t} edge {k}: neighbour {n} does not point back"
            j = j[0]
            assert (tri[3 * n + (j + 1) % 3], tri[3 * n + (j + 2) % 3]) == (w, u)
            assert cons[3 * t + k] == cons[3 * n + j]
        a, b, c = tri[3 * t : 3 * t + 3]
        if c == GHOST:
            assert treg[t] == -1
        else:
            assert orient2d(*P[a], *P[b], *P[c]) > 0.0


def test_cdt_square_with_square_hole():
    pts = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.3, 0.3], [0.7, 0.3], [0.7, 0.7], [0.3, 0.7]], float)
    segs = np.array([[0, 1], [1, 2], [2, 3], [3, 0], [4, 7], [7, 6], [6, 5], [5, 4]])
    ct = cdt_build(pts, segs).classify(segment_sides=np.ones(8, int))
    mesh = ct.to_mesh()
    mesh.validate()
    assert len(mesh.cells["triangle"]) == 8
    assert mesh.area() == pytest.approx(1 - 0.16, rel=1e-14)
    assert len(mesh.cells["line"]) == 8


def test_cdt_recovers_crossing_segment_and_is_constrained_delaunay():
    rng = np.random.default_rng(3)
    pts = np.vstack([[[0, 0], [1, 0], [1, 1], [0, 1]], rng.random((300, 2))])
    pts = np.vstack([pts, [[0.05, 0.5], [0.95, 0.52]]])
    n = len(pts)
    segs = np.array([[0, 1], [1, 2], [2, 3], [3, 0], [n - 2, n - 1]])
    ct = cdt_build(pts, segs).classify()
    edges, ids = ct.segments()
    assert set(ids.tolist()) == {0, 1, 2, 3, 4}
    tris = ct.triangles()
    cons = {tuple(sorted(e)) for e in edges.tolist()}
    # Constrained Delaunay: every free interior edge is locally Delaunay (exact in-circle).
    nb = ct.neighbors()
    P = ct.points
    for t in range(len(tris)):
        for k in range(3):
            o = nb[t, k]
            if o < 0:
                continue
            a, b = tris[t, (k + 1) % 3], tris[t, (k + 2) % 3]
            if tuple(sorted((a, b))) in cons:
                continue
            d = [v for v in tris[o] if v not in (a, b)][0]
            x = [P[v] for v in tris[t]] + [P[d]]
            assert mw_incircle(*x) <= 0.0


def mw_incircle(a, b, c, d):
    from meshwright.core.predicates import incircle

    return incircle(a[0], a[1], b[0], b[1], c[0], c[1], d[0], d[1])


@pytest.mark.parametrize(
    "poly",
    [
        # Rounded midpoints of slanted edges fall beside nearly collinear hull slivers.
        [(1.0, 0.0), (0.54030230586814, 0.8414709848078965), (-0.4161468365471424, 0.9092974268256817)],
        [(0.3985032192388468, 0.12355047718188743), (0.31156521699032486, 0.40694302843535274),
         (0.2479516484701556, 0.434188875975574), (0.027312021963955293, 0.47604247876228195),
         (-0.4530283494389257, 0.47597020591549055), (-0.5988330915200059, -0.013623487753517766),
         (0.5347397635159493, -0.7327949986006386), (0.31676198710700093, -0.2448816157709209),
         (0.7880701070437585, -0.15087637276013455), (0.710077545926793, -1.7391883875313093e-16)],
    ],
)
def test_split_beside_collinear_slivers(poly):
    from meshwright.tri.cdt import SegmentCurves

    dom = g.polygon(np.array(poly))
    disc = dom.discretize(0.15)
    ct = cdt_build(disc.points, disc.segments, curves=SegmentCurves.from_domain(dom, disc))
    ct.classify(segment_sides=np.ones(len(disc.segments)))
    refine(ct, min_angle=25, size=0.15)
    check_structure(ct)
    check(ct.to_mesh(), dom, min_angle=25, straight=True)


def test_cdt_crossing_segments_named():
    pts = np.array([[0, 0], [1, 1], [0, 1], [1, 0], [2, 2]], float)
    with pytest.raises(GeometryError, match="segment"):
        cdt_build(pts, [[0, 1], [2, 3]])


def test_refine_square_hole_quality():
    pts = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.3, 0.3], [0.7, 0.3], [0.7, 0.7], [0.3, 0.7]], float)
    segs = np.array([[0, 1], [1, 2], [2, 3], [3, 0], [4, 7], [7, 6], [6, 5], [5, 4]])
    ct = cdt_build(pts, segs).classify(segment_sides=np.ones(8, int))
    refine(ct, min_angle=32.0, max_area=1e-3)
    check_structure(ct)
    mesh = ct.to_mesh()
    mesh.validate()
    assert mesh.area() == pytest.approx(0.84, rel=1e-12)
    ang = _angles(mesh.points, mesh.cells["triangle"])
    assert ang.min() >= 32.0 - 1e-9
    assert mesh.quality().summary()["triangle"]["area"]["max"] <= 1e-3 * (1 + 1e-12)


# ---------------------------------------------------------------------------- triangulate
@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("name", sorted(g.BUILTIN_DOMAINS))
def test_builtin_domains(name, method):
    dom = g.builtin(name)
    # Every method but the front honours min_angle (the frontal ones by a last refinement pass).
    angle = None if method == "front" else 30
    mesh = mw.triangulate(dom, method=method, min_angle=angle)
    straight = name in ("rectangle", "l-shape")
    check(mesh, dom, min_angle=angle, straight=straight)


@pytest.mark.parametrize("method", METHODS)
def test_polygon_with_holes_and_interior_segment(method):
    outer = [(0, 0), (4, 0), (4, 3), (0, 3)]
    holes = [[(0.5, 0.5), (1.5, 0.5), (1.5, 1.5), (0.5, 1.5)], [(2.5, 1.0), (3.5, 1.0), (3.0, 2.5)]]
    dom = g.polygon(outer, holes=holes, segments=[np.array([(0.2, 2.0), (2.2, 2.8)])], markers=[3, 4, 5])
    mesh = mw.triangulate(dom, size=0.2, method=method)
    check(mesh, dom, min_angle=30 if method == "delaunay" else None, straight=True)
    _segments_present(mesh, dom.discretize(0.2))
    # Markers: every line on a hole loop carries that hole's marker.
    lines, marks = mesh.cells["line"], mesh.cell_data["marker"]["line"]
    mid = mesh.points[lines].mean(axis=1)
    in_hole1 = (np.abs(mid[:, 0] - 1.0) <= 0.5 + 1e-12) & (np.abs(mid[:, 1] - 1.0) <= 0.5 + 1e-12)
    assert (marks[in_hole1] == 4).all() and in_hole1.sum() >= 4
    on_outer = (np.isclose(mid[:, 0], 0) | np.isclose(mid[:, 0], 4) | np.isclose(mid[:, 1], 0) | np.isclose(mid[:, 1], 3))
    assert (marks[on_outer] == 3).all()


def test_size_and_min_angle_honoured_on_disk():
    dom = g.circle()
    mesh = mw.triangulate(dom, size=0.05, min_angle=33)
    check(mesh, dom, min_angle=33)
    q = mesh.quality().summary()["triangle"]
    assert q["area"]["max"] <= math.sqrt(3) / 4 * 0.05**2 * 1.0000001


def test_small_input_angle_terminates():
    # An interior segment at 1 degree to the bottom edge: refinement must stop, and only
    # triangles inside the thin wedge (Shewchuk's rule leaves those) may be skinny.
    a = math.radians(1.0)
    dom = g.polygon([(0, 0), (3, 0), (3, 2), (-1, 2)], segments=[np.array([(0, 0), (3 * math.cos(a), 3 * math.sin(a))])])
    mesh = mw.triangulate(dom, size=0.3, min_angle=30)
    check(mesh, dom, straight=True)
    cen = mesh.points[mesh.cells["triangle"]].mean(axis=1)
    outside_wedge = np.degrees(np.arctan2(cen[:, 1], cen[:, 0])) > 1.0
    ang = _angles(mesh.points, mesh.cells["triangle"]).min(axis=1)
    assert ang[outside_wedge].min() >= 30 - 1e-7


def test_near_touching_holes():
    outer = [(0, 0), (2, 0), (2, 1), (0, 1)]
    holes = [[(0.2, 0.2), (0.999, 0.2), (0.999, 0.8), (0.2, 0.8)], [(1.001, 0.2), (1.8, 0.2), (1.8, 0.8), (1.001, 0.8)]]
    dom = g.polygon(outer, holes=holes)
    mesh = mw.triangulate(dom, min_angle=28)
    check(mesh, dom, min_angle=28, straight=True)


def test_regions_markers_and_max_area():
    outer = [(0, 0), (2, 0), (2, 1), (0, 1)]
    inner = np.array([(0.25, 0.25), (0.75, 0.25), (0.75, 0.75), (0.25, 0.75), (0.25, 0.25)])
    dom = g.polygon(outer, segments=[inner], regions=[(0.5, 0.5, 7, 0.001), (1.5, 0.5, 9, None)])
    mesh = mw.triangulate(dom, min_angle=25)
    check(mesh, dom, min_angle=25, straight=True)
    tm = mesh.cell_data["marker"]["triangle"]
    cen = mesh.points[mesh.cells["triangle"]].mean(axis=1)
    box = (np.abs(cen[:, 0] - 0.5) < 0.25) & (np.abs(cen[:, 1] - 0.5) < 0.25)
    assert (tm[box] == 7).all() and (tm[~box] == 9).all()
    left = mesh.cells["triangle"][box]
    p = mesh.points[left]
    u, v = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    area = 0.5 * np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
    assert area.max() <= 0.001 * (1 + 1e-12)


def test_smoothing_keeps_boundary_on_curves_and_validity():
    dom = g.builtin("naca0012")
    rough = mw.triangulate(dom, method="weatherill")
    smooth = mw.triangulate(dom, method="weatherill", smooth=8)
    check(smooth, dom)
    assert np.array_equal(rough.cells["triangle"], smooth.cells["triangle"])
    q0 = rough.quality().summary()["triangle"]["radius_ratio"]
    q1 = smooth.quality().summary()["triangle"]["radius_ratio"]
    assert q1["min"] >= q0["min"] - 1e-12
    assert q1["mean"] > q0["mean"]


def test_curved_boundary_points_on_curve_after_refinement():
    dom = g.annulus()
    mesh = mw.triangulate(dom, size=0.04, min_angle=30)
    check(mesh, dom, min_angle=30)
    r = np.hypot(*mesh.points[np.unique(mesh.cells["line"])].T)
    assert np.all(np.isclose(r, 0.5, rtol=1e-12) | np.isclose(r, 1.0, rtol=1e-12))


@st.composite
def star_polygons(draw):
    n = draw(st.integers(3, 14))
    angles = np.sort(np.array(draw(st.lists(st.floats(0, 2 * math.pi, allow_nan=False), min_size=n, max_size=n, unique=True))))
    gaps = np.diff(np.r_[angles, angles[0] + 2 * math.pi])
    # Star-shaped about the origin (so simple) needs every angular gap below pi.
    if gaps.min() < 0.05 or gaps.max() > 0.9 * math.pi:
        angles = np.linspace(0, 2 * math.pi, n, endpoint=False)
    radii = np.array(draw(st.lists(st.floats(0.3, 1.0), min_size=n, max_size=n)))
    xy = np.column_stack([radii * np.cos(angles), radii * np.sin(angles)])
    # Magnitudes such as sin(1e-196) lie below the predicates' exact range, which the door
    # refuses (test_doors.py): flush them to zero, as test_delaunay's strategies do.
    return np.where(np.abs(xy) < 1e-30, 0.0, xy)


@settings(deadline=None)
@given(star_polygons(), st.sampled_from(METHODS))
def test_hypothesis_star_polygons(poly, method):
    dom = g.polygon(poly)
    angle = None if method == "front" else 25
    mesh = mw.triangulate(dom, size=0.15, method=method, min_angle=angle)
    check(mesh, dom, straight=True)


# ---------------------------------------------------------------------------- errors
def test_self_intersecting_polygon_named():
    with pytest.raises(GeometryError):
        mw.triangulate(g.polygon([(0, 0), (1, 1), (1, 0), (0, 1)]))


def test_unknown_method_and_bad_parameters():
    with pytest.raises(InputError, match="unknown method"):
        mw.triangulate(g.circle(), method="magic")
    with pytest.raises(InputError):
        mw.triangulate(g.circle(), min_angle=70)
    with pytest.raises(InputError):
        mw.triangulate(g.circle(), smooth=-1)


def test_point_cap_raises_clear_error():
    ct = cdt_build(np.array([[0, 0], [1, 0], [0, 1]], float), [[0, 1], [1, 2], [2, 0]]).classify()
    with pytest.raises(MeshingError, match="max_points"):
        refine(ct, min_angle=30, max_area=1e-6, max_points=50)


def test_cli_mesh(tmp_path, capsys):
    from meshwright.cli import main

    out = tmp_path / "naca.vtu"
    assert main(["mesh", "naca0012", "-o", str(out), "--quality", "--smooth", "3"]) == 0
    assert out.exists()
    mesh = mw.read(out)
    assert "triangle" in mesh.cells
    text = capsys.readouterr().out
    assert "min_angle" in text
    assert main(["mesh", str(tmp_path / "missing.poly"), "-o", str(out)]) == 2


# ---------------------------------------------------------------------------- frontal Delaunay
def _edge_lengths(mesh):
    p = mesh.points[mesh.cells["triangle"]]
    return np.hypot(*(p - p[:, [1, 2, 0]]).transpose(2, 0, 1))


def test_frontal_delaunay_follows_size_and_quality():
    dom = g.circle()
    mesh = mw.triangulate(dom, size=0.05, method="frontal-delaunay")
    check(mesh, dom)
    lengths = _edge_lengths(mesh)
    assert abs(np.median(lengths) / 0.05 - 1) < 0.15
    q = mesh.quality().summary()["triangle"]["radius_ratio"]
    assert q["mean"] > 0.9


def test_frontal_delaunay_size_ratio_above_1e4():
    from meshwright.sizing import gradation

    dom = g.airfoil_in_farfield("0012", radius=100.0)
    wall = np.concatenate([c.evaluate(c.fine_params()) for lp in dom.loops[1:] for c in lp])
    size = gradation(wall, 1e-3, 1.25, hmax=20.0)
    mesh = mw.triangulate(dom, size=size, method="frontal-delaunay")
    check(mesh, dom)
    lengths = _edge_lengths(mesh)
    assert lengths.max() / lengths.min() > 1e4


def test_conforming_delaunay_is_delaunay():
    rng = np.random.default_rng(5)
    pts = np.vstack([[[0, 0], [1, 0], [1, 1], [0, 1]], rng.random((200, 2)), [[0.1, 0.13], [0.93, 0.71]]])
    n = len(pts)
    segs = np.array([[0, 1], [1, 2], [2, 3], [3, 0], [n - 2, n - 1]])
    ct = cdt_build(pts, segs, conforming=True).classify()
    check_structure(ct)
    tri = mw.Mesh(ct.points, {"triangle": ct.triangles(False)})
    tri.validate(check_delaunay=True)
    edges, ids = ct.segments()
    lengths = np.hypot(*(ct.points[edges[:, 1]] - ct.points[edges[:, 0]]).T)
    assert np.bincount(ids, lengths)[4] == pytest.approx(math.dist(pts[n - 2], pts[n - 1]), rel=1e-12)


@pytest.mark.parametrize("method", METHODS)
def test_triangulate_conforming_option(method):
    dom = g.polygon([(0, 0), (3, 0), (3, 1), (0, 1)], holes=[[(1, 0.3), (2, 0.4), (1.5, 0.7)]])
    mesh = mw.triangulate(dom, size=0.3, method=method, conforming=True)
    check(mesh, dom, straight=True)
    # Every interior edge is locally Delaunay: the mesh passes the exact empty-circle check.
    mesh.validate(check_delaunay=True)


def test_interior_segment_between_loop_vertices_splits_regions():
    outer = [(0, 0), (1, 0), (2, 0), (2, 1), (1, 1), (0, 1)]
    dom = g.polygon(outer, segments=[np.array([(1, 0), (1, 1)])], regions=[(0.5, 0.5, 7, None), (1.5, 0.5, 9, None)])
    mesh = mw.triangulate(dom, size=0.2)
    check(mesh, dom, min_angle=30, straight=True)
    tm = mesh.cell_data["marker"]["triangle"]
    cen = mesh.points[mesh.cells["triangle"]].mean(axis=1)
    assert (tm[cen[:, 0] < 1] == 7).all() and (tm[cen[:, 0] > 1] == 9).all()
    # The divider is present as interior line cells covering x = 1 from y = 0 to 1.
    lines = mesh.cells["line"]
    on = np.all(mesh.points[lines][:, :, 0] == 1.0, axis=1)
    assert np.sum(np.abs(np.diff(mesh.points[lines[on]][:, :, 1], axis=1))) == pytest.approx(1.0, rel=1e-12)


@pytest.mark.parametrize("method", [k for k, m in mw.MESH_METHODS.items() if m.reports_progress])
def test_progress_bar_does_not_change_the_mesh(method):
    quiet = mw.triangulate("circle", 0.1, method=method)
    shown = mw.triangulate("circle", 0.1, method=method, progress=True)
    assert np.array_equal(quiet.points, shown.points)
    assert np.array_equal(quiet.cells["triangle"], shown.cells["triangle"])
