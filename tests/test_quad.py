"""Quadrilateral meshing (issue 12): the quadrangulate door, quad quality and validation,
the all-quad midpoint split and the quadtree method (Yerry and Shephard, 18.5.3).

Oracles never share code with what they check: quality measures are recomputed corner by
corner with ``math`` and exact ``Fraction`` arithmetic, convexity by exact rational
cross products, boundary nodes against the curves' own evaluation, balance by box
geometry.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import meshwright as mw
from meshwright.cli import main
from meshwright.core.errors import InputError, MeshingError, SizeError, ValidationError
from meshwright.core.quality import quad_quality
from meshwright.geometry import builtin, circle, polygon
from meshwright.quad import QUAD_METHODS, QuadFill, quadrangulate
from meshwright.quad.quadtree import _near, build_tree
from meshwright.quad.subdivide import split_all


# ----------------------------------------------------------------------- the door


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        (dict(method="paving-someday"), InputError, "unknown quad method"),
        (dict(method=3), InputError, "unknown quad method"),
        (dict(all_quad="yes"), InputError, "all_quad"),
        (dict(progress=1), InputError, "progress"),
        (dict(progress=True), InputError, "reports no progress"),
        (dict(smooth=-1), InputError, "smooth"),
        (dict(max_points=2), InputError, "max_points"),
        (dict(max_points=1.5), InputError, "max_points"),
        (dict(seed=-3), InputError, "seed"),
        (dict(size=-0.1), SizeError, "-0.1"),
        (dict(size=float("nan")), SizeError, "nan"),
        (dict(size=0.0), SizeError, "0"),
        (dict(size=1e-7, max_points=10_000), SizeError, "max_points"),
    ],
)
def test_door_rejects_bad_arguments_before_any_work(kwargs, error, words):
    kwargs = dict(kwargs)
    size = kwargs.pop("size", 0.2)
    with pytest.raises(error, match=words):
        quadrangulate("circle", size, **kwargs)


def test_door_rejects_what_a_method_cannot_honour():
    square = [(0, 0), (1, 0), (1, 1), (0, 1)]
    with pytest.raises(InputError, match="needs a size"):
        quadrangulate(polygon(square), "boundary", method="paving")
    with pytest.raises(InputError, match=r"region 0 at \(0\.5, 0\.5\) has max_area 0\.01"):
        quadrangulate(polygon(square, regions=[(0.5, 0.5, 3, 0.01)]), 0.2)
    with pytest.raises(InputError, match="Domain"):
        quadrangulate(object(), 0.2)
    with pytest.raises(InputError, match="nope.json"):
        quadrangulate("nope.json", 0.2)


def test_registry_declares_capabilities():
    m = QUAD_METHODS["quadtree"]
    assert not m.needs_size and m.smooths and not m.reports_progress and m.segments and m.points and m.regions
    assert QUAD_METHODS["paving"].needs_size
    assert mw.QUAD_METHODS is QUAD_METHODS and mw.quadrangulate is quadrangulate


# ---------------------------------------------------------------- quality formulas


def _oracle(corners):
    """Per quad, from its four (x, y) corners: min/max angle (degrees), min corner sine,
    aspect ratio and skew, by the textbook definitions in plain ``math``."""
    angles, sines, lengths = [], [], []
    for k in range(4):
        (px, py), (cx, cy), (nx, ny) = corners[k - 1], corners[k], corners[(k + 1) % 4]
        ux, uy, vx, vy = nx - cx, ny - cy, px - cx, py - cy
        cross, dot = ux * vy - uy * vx, ux * vx + uy * vy
        a = math.degrees(math.atan2(cross, dot)) % 360.0
        angles.append(a)
        sines.append(cross / (math.hypot(ux, uy) * math.hypot(vx, vy)))
        lengths.append(math.hypot(ux, uy))
    area = 0.5 * sum(corners[k][0] * corners[(k + 1) % 4][1] - corners[(k + 1) % 4][0] * corners[k][1]
                     for k in range(4))
    p = corners
    a1 = (p[1][0] - p[0][0] + p[2][0] - p[3][0], p[1][1] - p[0][1] + p[2][1] - p[3][1])
    a2 = (p[2][0] - p[1][0] + p[3][0] - p[0][0], p[2][1] - p[1][1] + p[3][1] - p[0][1])
    skew = abs(a1[0] * a2[0] + a1[1] * a2[1]) / (math.hypot(*a1) * math.hypot(*a2))
    return min(angles), max(angles), min(sines), max(lengths) * sum(lengths) / (4 * area), skew, area


@pytest.mark.parametrize(
    "corners, expected",
    [
        ([(0, 0), (1, 0), (1, 1), (0, 1)], dict(scaled_jacobian=1.0, aspect_ratio=1.0, skew=0.0, min_angle=90.0)),
        ([(0, 0), (2, 0), (2, 1), (0, 1)], dict(scaled_jacobian=1.0, aspect_ratio=1.5, skew=0.0, edge_ratio=2.0)),
        # Rhombus with a 60-degree corner: sine 3^0.5/2, skew cos 60, aspect 1 / sin 60.
        (
            [(0, 0), (1, 0), (1.5, 3**0.5 / 2), (0.5, 3**0.5 / 2)],
            dict(scaled_jacobian=3**0.5 / 2, skew=0.5, aspect_ratio=2 / 3**0.5, min_angle=60.0, max_angle=120.0),
        ),
    ],
)
def test_quad_quality_known_shapes(corners, expected):
    q = quad_quality(np.array(corners, dtype=float), np.array([[0, 1, 2, 3]]))
    for name, value in expected.items():
        assert q[name][0] == pytest.approx(value, abs=1e-12), name


@given(
    st.lists(
        st.tuples(st.integers(-50, 50), st.integers(-50, 50)), min_size=4, max_size=4, unique=True
    )
)
def test_quad_quality_matches_the_corner_formulas(pts):
    # Only strictly convex counter-clockwise quads (exact rational test) have the
    # textbook values without branch conventions.
    crosses = [
        (Fraction(pts[(k + 1) % 4][0] - pts[k][0]) * (pts[k - 1][1] - pts[k][1]))
        - (Fraction(pts[(k + 1) % 4][1] - pts[k][1]) * (pts[k - 1][0] - pts[k][0]))
        for k in range(4)
    ]
    if not all(c > 0 for c in crosses):
        return
    q = quad_quality(np.array(pts, dtype=float), np.array([[0, 1, 2, 3]]))
    lo, hi, sj, aspect, skew, area = _oracle([tuple(map(float, p)) for p in pts])
    assert q["min_angle"][0] == pytest.approx(lo, abs=1e-9)
    assert q["max_angle"][0] == pytest.approx(hi, abs=1e-9)
    assert q["scaled_jacobian"][0] == pytest.approx(sj, abs=1e-12)
    assert q["aspect_ratio"][0] == pytest.approx(aspect, rel=1e-12)
    assert q["skew"][0] == pytest.approx(skew, abs=1e-12)
    assert q["area"][0] == pytest.approx(area, rel=1e-12)


# -------------------------------------------------------------------- validation


def _mesh(points, quads=(), triangles=(), lines=()):
    cells = {"quad": np.array(quads, dtype=np.int32).reshape(-1, 4)}
    if len(triangles):
        cells["triangle"] = np.array(triangles, dtype=np.int32).reshape(-1, 3)
    if len(lines):
        cells["line"] = np.array(lines, dtype=np.int32).reshape(-1, 2)
    return mw.Mesh(np.array(points, dtype=float), cells)


SQUARES = [(0, 0), (1, 0), (2, 0), (0, 1), (1, 1), (2, 1)]


def test_validate_good_quads_and_mixed_meshes():
    _mesh(SQUARES, [[0, 1, 4, 3], [1, 2, 5, 4]], lines=[[0, 1], [2, 5]]).validate()
    # A quad beside two triangles, every shared edge once each way.
    _mesh(SQUARES, [[0, 1, 4, 3]], [[1, 2, 5], [1, 5, 4]]).validate()


def test_validate_rejects_broken_quads():
    with pytest.raises(ValidationError, match="quad 1"):
        _mesh(SQUARES, [[0, 1, 4, 3], [1, 4, 5, 2]]).validate()  # clockwise
    # Edge 1-4 in three cells (the right square twice).
    with pytest.raises(ValidationError):
        _mesh(SQUARES, [[0, 1, 4, 3], [1, 2, 5, 4], [2, 5, 4, 1]]).validate()
    # Hanging node: vertex 6 splits the right square's left side, not the left square's.
    pts = [(0, 0), (1, 0), (2, 0), (0, 2), (1, 2), (2, 2), (1, 1)]
    with pytest.raises(ValidationError):
        _mesh(pts, [[0, 1, 4, 3], [1, 2, 5, 4]], [[6, 1, 2], [6, 2, 5], [6, 5, 4]]).validate()
    with pytest.raises(ValidationError, match="line"):
        _mesh(SQUARES, [[0, 1, 4, 3], [1, 2, 5, 4]], lines=[[0, 4]]).validate()


DART = [(0, 0), (2, 0), (1, 0.5), (1, 2)]  # reflex corner 2: simple, counter-clockwise
BOWTIE = [(0, 0), (1, 1), (1, 0), (0, 1)]
FLAT = [(0, 0), (1, 0), (2, 0), (1, 1)]  # 180-degree corner 1


def test_validate_nonconvex_only_when_allowed():
    dart = _mesh(DART, [[0, 1, 2, 3]])
    with pytest.raises(ValidationError, match="corner 2"):
        dart.validate()
    dart.validate(allow_nonconvex=True)
    _mesh(FLAT, [[0, 1, 2, 3]]).validate(allow_nonconvex=True)
    with pytest.raises(ValidationError, match="quad 0"):
        _mesh(FLAT, [[0, 1, 2, 3]]).validate()
    for bad in ([[0, 1, 2, 3]], [[0, 3, 2, 1]]):
        with pytest.raises(ValidationError, match="not a simple counter-clockwise"):
            _mesh(BOWTIE if bad == [[0, 1, 2, 3]] else DART, bad).validate(allow_nonconvex=True)
    with pytest.raises(InputError, match="allow_nonconvex"):
        dart.validate(allow_nonconvex="yes")


# -------------------------------------------------------------- all-quad split


def test_split_all_keeps_conformity_and_puts_midpoints_on_curves():
    dom = circle(radius=1.0)
    t = np.linspace(0.0, 2.0 * np.pi, 7)[:-1]
    pts = np.vstack([[0.0, 0.0], np.column_stack([np.cos(t), np.sin(t)])])
    tris = np.array([[0, 1 + k, 1 + (k + 1) % 6] for k in range(6)], dtype=np.int32)
    lines = np.array([[1 + k, 1 + (k + 1) % 6] for k in range(6)], dtype=np.int32)
    fill = QuadFill(pts, np.zeros((0, 4), np.int32), tris, lines, np.full(6, 7, np.int32), np.zeros(6, np.int32))
    out = split_all(fill, dom, 1000)
    assert len(out.triangles) == 0 and len(out.quads) == 18 and len(out.lines) == 12
    assert set(out.line_markers) == {7}
    m = mw.Mesh(out.points, {"quad": out.quads, "line": out.lines})
    m.validate()
    r = np.hypot(*out.points[np.unique(out.lines)].T)
    np.testing.assert_allclose(r, 1.0, rtol=0, atol=1e-12)
    # The arc midpoint of the chord from angle 0 to 60 degrees is at 30 degrees.
    assert np.min(np.hypot(*(out.points - [math.cos(math.pi / 6), math.sin(math.pi / 6)]).T)) < 1e-12
    with pytest.raises(MeshingError, match="max_points"):
        split_all(fill, dom, 20)


# -------------------------------------------------------------------- quadtree


def test_quadtree_is_two_to_one_balanced():
    # A target tiny near one corner forces a deep, graded tree.
    def target(x, y, s):
        return np.maximum(0.002, 0.5 * np.hypot(x - 0.01, y - 0.01)), np.ones(len(x), bool)

    lev, ci, cj, child = build_tree((0.0, 0.0, 1.0), target, 10**6)
    leaf = child < 0
    size = 1.0 / 2.0 ** lev[leaf]
    x0, y0 = ci[leaf] * size, cj[leaf] * size
    x1, y1 = x0 + size, y0 + size
    assert np.isclose(size**2, 1.0).sum() == 0 and np.sum(size**2) == pytest.approx(1.0)
    assert lev.max() >= 7
    # Side neighbours: boxes sharing a side piece of positive length.
    for i in np.flatnonzero(size < 0.1):
        touch_x = ((x1 == x0[i]) | (x0 == x1[i])) & (np.minimum(y1, y1[i]) > np.maximum(y0, y0[i]))
        touch_y = ((y1 == y0[i]) | (y0 == y1[i])) & (np.minimum(x1, x1[i]) > np.maximum(x0, x0[i]))
        ratio = size[touch_x | touch_y] / size[i]
        assert np.all((ratio >= 0.5) & (ratio <= 2.0)), i


def test_near_matches_brute_force_distances():
    rng = np.random.default_rng(5)
    a = rng.uniform(-1, 1, (300, 2))
    b = a + rng.normal(0, 0.05, (300, 2))
    b[:5] = a[:5]  # zero-length segments
    q = rng.uniform(-1.5, 1.5, (3000, 2))
    r = 10.0 ** rng.uniform(-3, 0.5, 3000)
    got = _near(q[:, 0].copy(), q[:, 1].copy(), r, a, b)
    ab = b - a
    ll = np.maximum((ab * ab).sum(axis=1), 1e-300)
    t = np.clip(((q[:, None, :] - a[None]) * ab[None]).sum(axis=2) / ll[None], 0.0, 1.0)
    gap = a[None] + t[..., None] * ab[None] - q[:, None, :]
    dist = np.sqrt((gap * gap).sum(axis=2)).min(axis=1)
    decided = np.abs(dist - r) > 1e-12 * r  # ties are either way
    np.testing.assert_array_equal(got[decided], (dist < r)[decided])
    assert 0 < got.sum() < len(q)


def _on_curves(dom, xy):
    """Distance of each point to the nearest curve of ``dom``, from dense curve samples
    refined by each curve's own projection."""
    best = np.full(len(xy), np.inf)
    for c in dom.curves:
        t = c.project(xy)
        best = np.minimum(best, np.hypot(*(c.evaluate(t) - xy).T))
    return best


@pytest.mark.parametrize("name, size", [("circle", 0.1), ("naca0012", None), ("three-element", None), ("circles", None)])
def test_quadtree_builtin_domains_all_quad_valid_and_on_the_curves(name, size):
    dom = builtin(name)
    mesh = quadrangulate(dom, size)
    assert set(mesh.cells) == {"quad", "line"}
    mesh.validate()
    q = mesh.quality()["quad"]
    assert q["scaled_jacobian"].min() > 0.2
    nodes = np.unique(mesh.lines)
    assert _on_curves(dom, mesh.points[nodes]).max() < 1e-9
    # Every boundary edge of the quads is a line cell, and the reverse.
    assert len(mesh.boundary_facets()) == len(mesh.lines)
    assert set(np.unique(mesh.cell_data["marker"]["line"])) == set(np.unique(dom.discretize().segment_markers))
    # The quads tile the polygon of the boundary lines (domain on their left), which is
    # the domain up to the chords' sagittas.
    a, b = mesh.points[mesh.lines[:, 0]], mesh.points[mesh.lines[:, 1]]
    enclosed = 0.5 * np.sum(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
    assert mesh.area() == pytest.approx(enclosed, rel=1e-12)
    assert mesh.area() == pytest.approx(abs(dom.area()), rel=1e-2)


def test_quadtree_mixed_mode_interior_segments_and_points():
    dom = polygon(
        [(0, 0), (2, 0), (2, 1), (0, 1)],
        holes=[[(0.3, 0.3), (0.6, 0.3), (0.6, 0.6), (0.3, 0.6)]],
        segments=[[(1.0, 0.2), (1.7, 0.8)]],
        points=[(1.5, 0.2), (0.2, 0.8)],
    )
    mixed = quadrangulate(dom, 0.1, all_quad=False)
    assert len(mixed.triangles) > 0 and len(mixed.quads) > 0
    mixed.validate()
    full = quadrangulate(dom, 0.1)
    assert "triangle" not in full.cells
    full.validate()
    assert full.area() == pytest.approx(1.91, rel=1e-12)
    for p in ([1.5, 0.2], [0.2, 0.8]):
        assert np.any(np.all(full.points == p, axis=1))
    mid = full.points[full.lines].mean(axis=1)
    on_segment = np.abs((mid[:, 0] - 1.0) * 0.6 - (mid[:, 1] - 0.2) * 0.7) < 1e-12
    # Both sides of the segment are quads: its edges are interior, two quads each.
    assert on_segment.sum() >= 2
    assert len(full.boundary_facets()) == len(full.lines) - on_segment.sum()


def test_smoothing_keeps_boundary_and_never_lowers_the_minimum():
    dom = builtin("naca0012")
    raw = quadrangulate(dom)
    smooth = quadrangulate(dom, smooth=3)
    smooth.validate()
    assert np.array_equal(raw.quads, smooth.quads)
    nodes = np.unique(raw.lines)
    assert np.array_equal(raw.points[nodes], smooth.points[nodes])
    before = raw.quality()["quad"]["scaled_jacobian"]
    after = smooth.quality()["quad"]["scaled_jacobian"]
    assert after.min() >= before.min() and after.mean() > before.mean() + 0.02
    mixed = quadrangulate("circle", 0.2, all_quad=False, smooth=2)
    mixed.validate()


@settings(max_examples=20)
@given(
    st.lists(st.floats(0.35, 1.0), min_size=5, max_size=12),
    st.floats(-3.0, 3.0),
    st.floats(0.03, 0.2),
    st.integers(0, 2),
)
def test_quadtree_random_star_polygons(radii, log_scale, rel_size, passes):
    # Star-shaped polygons at any scale; angles of the input >= 30 degrees, so every
    # quad's corners should stay well away from 0 and 180 degrees.
    n = len(radii)
    t = 2.0 * np.pi * np.arange(n) / n
    pts = 10.0**log_scale * np.column_stack([np.array(radii) * np.cos(t), np.array(radii) * np.sin(t)])
    angles = []
    for k in range(n):
        u, v = pts[(k + 1) % n] - pts[k], pts[k - 1] - pts[k]
        angles.append(math.degrees(math.atan2(abs(u[0] * v[1] - u[1] * v[0]), u @ v)))
    assume(min(angles) >= 30.0)
    mesh = quadrangulate(polygon(pts), rel_size * 10.0**log_scale, smooth=passes)
    assert set(mesh.cells) == {"quad", "line"}
    mesh.validate()
    assert mesh.quality()["quad"]["scaled_jacobian"].min() > 0.2
    assert mesh.area() == pytest.approx(abs(polygon(pts).area()), rel=1e-9)


@pytest.mark.parametrize("method", ["quadtree", "pairing", "zhu"])
@pytest.mark.parametrize("all_quad", [True, False])
def test_region_markers_flood_from_seeds_and_stop_at_segments(all_quad, method):
    dom = polygon(
        [(0, 0), (0.5, 0), (1, 0), (1, 1), (0.5, 1), (0, 1)],
        segments=[[(0.5, 0), (0.5, 1)]],
        regions=[(0.25, 0.5, 3, None), (0.75, 0.5, 5, None)],
    )
    mesh = quadrangulate(dom, 0.1, all_quad=all_quad, method=method)
    mesh.validate()
    for kind in mesh.cells.keys() - {"line"}:
        centre = mesh.points[mesh.cells[kind]].mean(axis=1)
        np.testing.assert_array_equal(mesh.cell_data["marker"][kind], np.where(centre[:, 0] < 0.5, 3, 5))


@pytest.mark.parametrize("method", ["quadtree", "pairing", "zhu"])
def test_region_marker_of_an_island(method):
    # Square with a square hole holding a square island (seeded, marker 7): the island is
    # meshed and marked, the ring between hole and island is not.
    island = [(0.4, 0.4), (0.6, 0.4), (0.6, 0.6), (0.4, 0.6)]
    hole = [(0.2, 0.2), (0.8, 0.2), (0.8, 0.8), (0.2, 0.8)]
    dom = polygon([(0, 0), (1, 0), (1, 1), (0, 1)], holes=[hole, island], regions=[(0.5, 0.5, 7, None)])
    for h in (0.05, 0.01):
        mesh = quadrangulate(dom, h, method=method)
        mesh.validate()
        mk = mesh.cell_data["marker"]["quad"]
        inside = np.all((mesh.points[mesh.quads] >= 0.4) & (mesh.points[mesh.quads] <= 0.6), axis=(1, 2))
        np.testing.assert_array_equal(mk, np.where(inside, 7, 0))
        assert mesh.area() == pytest.approx(0.68, rel=1e-12)


def test_quadtree_caps_are_named():
    with pytest.raises(MeshingError, match="max_points|cells"):
        quadrangulate("circle", 0.05, max_points=1200)


# -------------------------------------------------------------------------- CLI


def test_cli_quad(tmp_path, capsys):
    out = tmp_path / "q.vtu"
    png = tmp_path / "q.png"
    assert main(["quad", "circle", "-o", str(out), "--size", "0.2", "--quality", "--plot", str(png)]) == 0
    text = capsys.readouterr().out
    assert "scaled_jacobian" in text and out.exists() and png.exists()
    back = mw.read(out)
    assert len(back.quads) > 0 and len(back.triangles) == 0
    assert main(["quad", "circle", "--size", "0.2", "--mixed"]) == 0
    assert "triangles left" in capsys.readouterr().out
    assert main(["quad", "circle", "--size", "-1"]) == 2
    assert main(["quad", "circle", "--smooth", "-3"]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and "smooth" in err


def test_cover_check_edges_match_a_set_oracle():
    """one_sided_edges (the cover check's kernel) against Python sets of directed edges, on
    a quad mesh with cells removed (voids) and a triangle beside a quad; with ``lines``, the
    lines that are no cell's edge either way against the same sets."""
    from meshwright.core.validate_quad import one_sided_edges

    mesh = quadrangulate(circle(), 0.2, method="quadtree")
    full = np.asarray(mesh.cells["quad"], dtype=np.int64)
    rng = np.random.default_rng(5)
    removed = rng.choice(len(full), 7, replace=False)
    quads = np.delete(full, removed, axis=0)
    # One quad split into two triangles: its edges pair with the neighbours' either way.
    a, b, c, d = quads[0]
    tris = np.array([[a, b, c], [a, c, d]], dtype=np.int64)
    quads = quads[1:]
    cells = [q.tolist() for q in quads] + [t.tolist() for t in tris]
    directed = {(u, w) for cell in cells for u, w in zip(cell, cell[1:] + cell[:1])}
    expect = {e for e in directed if (e[1], e[0]) not in directed}
    got = one_sided_edges(len(mesh.points), quads, tris)
    assert got.dtype == np.int64 and got.shape[1] == 2
    assert {tuple(e) for e in got.tolist()} == expect and len(got) == len(expect)
    assert (a, c) not in expect and len(expect) > 7 * 4
    # The mesh's lines reversed, the split quad's diagonal (an edge now), a kept quad's
    # diagonal and every side of the removed quads (some are no cell's edge any more).
    gone = full[removed]
    sides = np.stack([gone, np.roll(gone, -1, axis=1)], axis=2).reshape(-1, 2)
    probe = np.vstack([np.asarray(mesh.cells["line"], dtype=np.int64)[:, ::-1], [[a, c]],
                       [[quads[1, 0], quads[1, 2]]], sides])
    either = directed | {(w, u) for u, w in directed}
    expect_orphan = [i for i, (u, w) in enumerate(probe.tolist()) if (u, w) not in either]
    edges, orphan = one_sided_edges(len(mesh.points), quads, tris, probe)
    assert (edges == got).all() and orphan.dtype == np.int64
    assert orphan.tolist() == expect_orphan
    n_lines = len(mesh.cells["line"])
    assert n_lines not in expect_orphan and n_lines + 1 in expect_orphan and expect_orphan[-1] > n_lines + 1


@settings(max_examples=10, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([0.0, 0.01]))
def test_guarded_smoothing_matches_a_python_sweep(seed, settle):
    """smooth_cells (its corner sines kept in a table between moves) against a plain
    Python Gauss-Seidel sweep that recomputes every sine with ``math``: the same guard (a
    full, else a half step to the neighbours' mean, kept if no corner sine of the star
    falls below the star's smallest before), the same moves."""
    from meshwright.quad.smoothing import smooth_cells

    rng = np.random.default_rng(seed)
    k = 6
    gx, gy = np.meshgrid(np.arange(k + 1.0), np.arange(k + 1.0), indexing="ij")
    xy = np.column_stack([gx.ravel(), gy.ravel()])
    inner = (xy[:, 0] > 0) & (xy[:, 0] < k) & (xy[:, 1] > 0) & (xy[:, 1] < k)
    xy[inner] += rng.uniform(-0.3, 0.3, (int(inner.sum()), 2))
    idx = lambda i, j: i * (k + 1) + j  # noqa: E731
    quads = np.array([[idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)] for i in range(k) for j in range(k)])
    got = smooth_cells(xy, quads, np.zeros((0, 3), np.int64), ~inner, 3, settle)

    def sine(p, c, n):
        ux, uy, wx, wy = n[0] - c[0], n[1] - c[1], p[0] - c[0], p[1] - c[1]
        return (ux * wy - uy * wx) / math.sqrt((ux * ux + uy * uy) * (wx * wx + wy * wy))

    star = {v: [q for q in quads.tolist() if v in q] for v in range(len(xy))}
    nbrs = {}
    for v in range(len(xy)):  # the kernel's order: cells in order, next then previous corner
        nbrs[v] = []
        for q in star[v]:
            for w in (q[(q.index(v) + 1) % 4], q[(q.index(v) + 3) % 4]):
                if w not in nbrs[v]:
                    nbrs[v].append(w)
    pts = [list(p) for p in xy.tolist()]

    def star_min(v):
        return min(sine(pts[q[i - 1]], pts[q[i]], pts[q[(i + 1) % 4]]) for q in star[v] for i in range(4))

    last, now = [True] * len(pts), [False] * len(pts)
    for sweep in range(3):
        for v in np.flatnonzero(inner).tolist():
            if settle and sweep and not (last[v] or now[v] or any(last[w] or now[w] for w in nbrs[v])):
                continue
            tx = sum(pts[w][0] for w in nbrs[v]) / len(nbrs[v])
            ty = sum(pts[w][1] for w in nbrs[v]) / len(nbrs[v])
            x0, y0 = pts[v]
            before = star_min(v)
            for step in (1.0, 0.5):
                pts[v] = [x0 + step * (tx - x0), y0 + step * (ty - y0)]
                if star_min(v) >= before:
                    w = nbrs[v][0]
                    if settle and (pts[v][0] - x0) ** 2 + (pts[v][1] - y0) ** 2 > settle**2 * (
                        (pts[w][0] - x0) ** 2 + (pts[w][1] - y0) ** 2
                    ):
                        now[v] = True
                    break
                pts[v] = [x0, y0]
        last, now = now, [False] * len(pts)
    assert np.allclose(got, np.array(pts), rtol=0, atol=1e-9)


def test_simple_ccw_quads_match_rational_orientations():
    """simple_ccw_quads (one compiled pass) against Fraction orientations: a quad is simple
    and counter-clockwise iff the diagonal from corner 0 or from corner 1 leaves two strictly
    counter-clockwise triangles.  Random corners on a coarse grid (many collinear and
    repeated corners) and the same grid shifted by 1e-17-scale offsets (near-collinear)."""
    from meshwright.core.validate_quad import simple_ccw_quads

    def orient(p, a, b, c):
        ax, ay = map(Fraction, p[a])
        bx, by = map(Fraction, p[b])
        cx, cy = map(Fraction, p[c])
        return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)

    rng = np.random.default_rng(11)
    for shift in (0.0, 1e-17, 3e-16):
        p = rng.integers(0, 4, size=(12, 2)).astype(float) * 0.1
        p[::3] += shift
        q = rng.integers(0, 12, size=(1500, 4))
        got = simple_ccw_quads(p, q.astype(np.int32))
        expect = [any(orient(p, c[k], c[k + 1], c[k + 2]) > 0 and orient(p, c[k + 2], c[(k + 3) % 4], c[k]) > 0
                      for k in (0, 1)) for c in q.tolist()]
        assert got.dtype == np.bool_ and got.tolist() == expect
        assert 0 < sum(expect) < len(expect)
