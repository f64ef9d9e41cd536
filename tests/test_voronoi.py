"""Tests of the Voronoi diagram (tri/voronoi.py) and its plot (plot/voronoi_plot.py).

Every check is geometric and independent of how the diagram was built, so a wrong diagram
(wrong vertex, wrong cell order, a missing or extra piece) fails: vertices equidistant from
their forming points, ridges on bisectors, cells convex, counter-clockwise and nearest to their
own point, clipped areas summing to the clip region, and agreement with scipy/Qhull.
"""

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from meshwright.core.errors import DegenerateInputError, GeometryError, InputError
from meshwright.tri.triangulation import delaunay
from meshwright.tri.voronoi import voronoi

L_SHAPE = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]  # area 3
U_SHAPE = [(0, 0), (3, 0), (3, 3), (2, 3), (2, 1), (1, 1), (1, 3), (0, 3)]  # area 7


def random_points(n, seed, lo=0.0, hi=1.0):
    return np.random.default_rng(seed).uniform(lo, hi, size=(n, 2))


def grid_points(m):
    x, y = np.meshgrid(np.arange(m, dtype=float), np.arange(m, dtype=float))
    return np.column_stack([x.ravel(), y.ravel()])


def tol(vor):
    return 1e-9 * max(1.0, float(np.abs(vor.points).max()))


def cells(vor):
    off = vor.cell_offsets
    return [vor.cell_vertices[off[i] : off[i + 1]] for i in range(len(vor.points))]


def polygon_area(xy):
    x, y = xy[:, 0], xy[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def inside_polygon(xy, poly, eps):
    """True where a point is inside or within eps of the polygon (even-odd + distance)."""
    poly = np.asarray(poly, dtype=float)
    a, b = poly, np.roll(poly, -1, axis=0)
    x, y = xy[:, 0:1], xy[:, 1:2]
    crosses = ((a[:, 1] > y) != (b[:, 1] > y)) & (
        a[:, 0] + (y - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1] + 1e-300) > x
    )
    ab = b - a
    t = np.clip(((x - a[:, 0]) * ab[:, 0] + (y - a[:, 1]) * ab[:, 1]) / (ab**2).sum(1), 0, 1)
    dist = np.hypot(a[:, 0] + t * ab[:, 0] - x, a[:, 1] + t * ab[:, 1] - y).min(axis=1)
    return (crosses.sum(axis=1) % 2 == 1) | (dist <= eps)


# --------------------------------------------------------------------------- checks


def check_vertices(vor):
    nt = len(vor.forming_points)
    d = np.linalg.norm(vor.vertices[:nt, None, :] - vor.points[vor.forming_points], axis=2)
    assert np.all(d.max(axis=1) - d.min(axis=1) <= tol(vor) * (1.0 + d.max(axis=1)))
    # Bowyer's structure: neighbouring vertices share two forming points.
    t, k = np.nonzero(vor.vertex_neighbors >= 0)
    for tt, kk in zip(t[:50], k[:50]):
        other = vor.vertex_neighbors[tt, kk]
        shared = set(vor.forming_points[tt]) & set(vor.forming_points[other])
        assert shared == set(vor.forming_points[tt]) - {vor.forming_points[tt, kk]}


def check_ridges(vor):
    p, rp, rv = vor.points, vor.ridge_points, vor.ridge_vertices
    pu, pv = p[rp[:, 0]], p[rp[:, 1]]
    edge = pv - pu
    eps = tol(vor)
    for col in (0, 1):
        ok = rv[:, col] >= 0
        x = vor.vertices[rv[ok, col]]
        du, dv = np.linalg.norm(x - pu[ok], axis=1), np.linalg.norm(x - pv[ok], axis=1)
        assert np.all(np.abs(du - dv) <= eps * (1 + du)), "ridge end off the bisector"
    finite = rv[:, 1] >= 0
    d = vor.vertices[rv[finite, 1]] - vor.vertices[rv[finite, 0]]
    length = np.linalg.norm(d, axis=1)
    long = length > 1e-6 * np.linalg.norm(edge[finite], axis=1)
    e = edge[finite][long]
    dl = d[long]
    cos = np.abs((dl * e).sum(1)) / (np.linalg.norm(dl, axis=1) * np.linalg.norm(e, axis=1))
    assert np.all(cos < 1e-6), "ridge not perpendicular to its Delaunay edge"
    # ridge_points[:, 1] is on the left of the ridge.
    assert np.all(dl[:, 0] * e[:, 1] - dl[:, 1] * e[:, 0] > 0)
    if (~finite).any():
        dirs = vor.ridge_directions[~finite]
        assert np.allclose(np.linalg.norm(dirs, axis=1), 1.0)
        hull_edge = edge[~finite]
        assert np.all(np.abs((dirs * hull_edge).sum(1)) <= 1e-12 * np.linalg.norm(hull_edge, axis=1))
        # Outward: away from the third forming point of the hull triangle.
        fp = vor.forming_points[rv[~finite, 0]]
        third = np.where(fp != rp[~finite, 0:1], fp, -1)
        third = np.where(third != rp[~finite, 1:2], third, -1).max(axis=1)
        assert np.all((dirs * (p[third] - pu[~finite])).sum(1) < 0)
    assert np.all(vor.ridge_directions[finite] == 0)


def check_nearest(vor, eps_scale=1.0):
    """Every vertex of cell i is at least as near to point i as to any other point."""
    owner = np.repeat(np.arange(len(vor.points)), np.diff(vor.cell_offsets))
    ok = vor.cell_vertices >= 0
    x = vor.vertices[vor.cell_vertices[ok]]
    d = np.linalg.norm(x[:, None, :] - vor.points[None, :, :], axis=2)
    own = d[np.arange(len(x)), owner[ok]]
    assert np.all(own <= d.min(axis=1) + eps_scale * tol(vor) * (1 + own))


def check_convex_ccw(vor, rel=1e-9):
    for i, c in enumerate(cells(vor)):
        if not vor.bounded[i] or len(c) == 0:
            continue
        xy = vor.vertices[c]
        a, b = np.roll(xy, -1, axis=0) - xy, np.roll(xy, -2, axis=0) - np.roll(xy, -1, axis=0)
        turn = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
        scale = np.abs(xy - xy.mean(axis=0)).max() ** 2
        assert np.all(turn >= -rel * scale), f"cell {i} not convex counter-clockwise"
        assert polygon_area(xy) > 0


def check_own_point_inside(vor):
    """Clipped convex cells contain their generator (generators inside the region)."""
    for i, c in enumerate(cells(vor)):
        xy = vor.vertices[c]
        a, b = xy, np.roll(xy, -1, axis=0)
        cross = (b[:, 0] - a[:, 0]) * (vor.points[i, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (
            vor.points[i, 0] - a[:, 0]
        )
        assert len(c) >= 3 and np.all(cross >= -tol(vor)), f"point {i} outside its cell"


def check_unbounded_chains(vor):
    for i, c in enumerate(cells(vor)):
        if vor.bounded[i]:
            assert np.all(c >= 0)
            continue
        assert c[0] == -1 and c[-1] == -1 and np.all(c[1:-1] >= 0), f"cell {i}: {c}"
        rays = vor.cell_rays(i)
        # Arriving ray: the first vertex is on the bisector of i and its hull successor;
        # the cell lies to the left when walking in from infinity (direction -rays[0]).
        first, last = vor.vertices[c[1]], vor.vertices[c[-2]]
        for start, along in ((first - rays[0], -rays[0]), (last, rays[1])):
            to_p = vor.points[i] - start
            assert along[0] * to_p[1] - along[1] * to_p[0] > 0


# --------------------------------------------------------------------------- unclipped


@pytest.fixture(scope="module")
def random_vor():
    return voronoi(random_points(300, seed=7))


def test_random_diagram_is_valid(random_vor):
    vor = random_vor
    check_vertices(vor)
    check_ridges(vor)
    check_convex_ccw(vor)
    check_nearest(vor)
    check_unbounded_chains(vor)
    hull = set(delaunay(vor.points).hull.tolist())
    assert set(np.flatnonzero(~vor.bounded).tolist()) == hull
    areas = vor.cell_areas()
    assert np.all(np.isinf(areas[~vor.bounded])) and np.all(areas[vor.bounded] > 0)
    assert vor.cell_vertices.dtype == np.int32 and vor.ridge_points.dtype == np.int32
    assert vor.cell_offsets.shape == (301,)


def test_ridges_are_the_delaunay_edges(random_vor):
    tri = random_vor.forming_points
    edges = np.unique(np.sort(tri[:, [[1, 2], [2, 0], [0, 1]]].reshape(-1, 2), axis=1), axis=0)
    ridges = np.unique(np.sort(random_vor.ridge_points, axis=1), axis=0)
    assert len(ridges) == len(random_vor.ridge_points)
    np.testing.assert_array_equal(ridges, edges)


def test_matches_scipy(random_vor):
    spatial = pytest.importorskip("scipy.spatial")
    ref = spatial.Voronoi(random_vor.points)
    ours = random_vor.vertices
    assert len(ours) == len(ref.vertices)
    tree = spatial.cKDTree(ref.vertices)
    dist, match = tree.query(ours)
    assert np.all(dist <= 1e-9 * (1 + np.abs(ours).max(axis=1)))
    assert len(np.unique(match)) == len(ref.vertices)

    def ridge_map(rp, rv, vmap):
        """{separated point pair: set of (matched) end vertices}."""
        return {
            frozenset(map(int, p)): frozenset(vmap[v] if v >= 0 else -1 for v in r)
            for p, r in zip(rp, rv)
        }

    mine = ridge_map(random_vor.ridge_points, random_vor.ridge_vertices, match)
    theirs = ridge_map(ref.ridge_points, ref.ridge_vertices, np.arange(len(ref.vertices)))
    assert mine == theirs
    for i in range(0, len(random_vor.points), 7):
        region = ref.regions[ref.point_region[i]]
        ids = random_vor.cell_vertices[random_vor.cell_offsets[i] : random_vor.cell_offsets[i + 1]]
        assert set(match[ids[ids >= 0]].tolist()) == {v for v in region if v >= 0}


def test_triangulation_input_equals_points_input(random_vor):
    vor = voronoi(delaunay(random_vor.points))
    np.testing.assert_array_equal(vor.vertices, random_vor.vertices)
    np.testing.assert_array_equal(vor.cell_vertices, random_vor.cell_vertices)


def test_cocircular_grid():
    vor = voronoi(grid_points(6))
    check_vertices(vor)
    check_ridges(vor)
    check_convex_ccw(vor)
    check_nearest(vor)
    check_unbounded_chains(vor)
    interior = vor.bounded
    assert interior.sum() == 16
    np.testing.assert_allclose(vor.cell_areas()[interior], 1.0, rtol=1e-12)
    # All Voronoi vertices sit at cell-centre positions (duplicates of cocircular quads).
    np.testing.assert_allclose(vor.vertices % 1.0, 0.5, atol=1e-12)


def test_three_points_have_three_unbounded_cells():
    vor = voronoi([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    np.testing.assert_allclose(vor.vertices, [[0.5, 0.5]])
    assert not vor.bounded.any()
    assert [c.tolist() for c in cells(vor)] == [[-1, 0, -1]] * 3
    check_ridges(vor)
    check_unbounded_chains(vor)


def test_duplicates_keep_input_numbering():
    pts = random_points(50, seed=8)
    dup = np.concatenate([pts, pts[[4, 9]]])
    vor = voronoi(dup)
    assert len(vor.points) == 52
    assert np.all(np.diff(vor.cell_offsets)[50:] == 0) and not vor.bounded[50:].any()
    np.testing.assert_array_equal(vor.cell_vertices, voronoi(pts).cell_vertices)
    clipped = voronoi(dup, clip=(0, 0, 1, 1))
    assert clipped.cell_areas()[50:].sum() == 0
    np.testing.assert_allclose(clipped.cell_areas().sum(), 1.0, rtol=1e-12)


# --------------------------------------------------------------------------- clipped


def check_clipped(vor, region, area, connected=True):
    """A clipped diagram tiles the region; ``connected=False`` allows cells cut in pieces."""
    eps = 1e-9 * max(1.0, float(np.abs(region).max()))
    assert vor.bounded.all()
    assert (vor.ridge_vertices >= 0).all() and (vor.cell_vertices >= 0).all()
    np.testing.assert_allclose(vor.cell_areas().sum(), area, rtol=1e-12)
    assert np.all(vor.cell_areas() >= -eps)
    assert np.all(inside_polygon(vor.vertices[vor.ridge_vertices.ravel()], region, eps))
    if connected:
        assert np.all(inside_polygon(vor.vertices[vor.cell_vertices], region, eps))
    check_nearest(vor)
    check_ridges(vor)
    # Vertices added by clipping lie on the region's boundary.
    nt = len(vor.forming_points)
    assert np.all(inside_polygon(vor.vertices[nt:], region, eps))


def test_box_clip_tiles_the_box():
    pts = random_points(300, seed=3)
    vor = voronoi(pts, clip=(0, 0, 1, 1))
    check_clipped(vor, [(0, 0), (1, 0), (1, 1), (0, 1)], 1.0)
    check_convex_ccw(vor)
    check_own_point_inside(vor)
    # Clip vertices are shared: a crossing with a box side by the two cells it separates,
    # a corner by one cell.
    nt = len(vor.forming_points)
    refs = np.bincount(vor.cell_vertices, minlength=len(vor.vertices))[nt:]
    assert sorted(refs.tolist()).count(1) == 4 and set(refs.tolist()) <= {1, 2}
    # Interior cells are untouched.
    full = voronoi(pts)
    for i, c in enumerate(cells(full)):
        if full.bounded[i] and np.all((full.vertices[c] > 0) & (full.vertices[c] < 1)):
            np.testing.assert_array_equal(cells(vor)[i], c)


def test_box_clip_with_points_outside():
    pts = random_points(200, seed=5, lo=-0.5, hi=1.5)
    vor = voronoi(pts, clip=(0, 0, 1, 1))
    check_clipped(vor, [(0, 0), (1, 0), (1, 1), (0, 1)], 1.0)
    check_convex_ccw(vor)
    far = np.all((pts < -0.45) | (pts > 1.45), axis=1)
    assert np.all(np.diff(vor.cell_offsets)[far] == 0)


def test_l_shape_clip():
    pts = random_points(250, seed=11, hi=2.0)
    vor = voronoi(pts, clip=L_SHAPE)
    check_clipped(vor, L_SHAPE, 3.0)
    cw = voronoi(pts, clip=L_SHAPE[::-1])
    np.testing.assert_allclose(cw.cell_areas(), vor.cell_areas(), atol=1e-12)
    assert polygon_area(cw.clip_polygon) == pytest.approx(3.0)


def test_non_convex_clip_splits_a_cell():
    pts = np.array([[1.5, 2.5], [0.5, 0.5], [2.5, 0.5], [1.5, 0.2]])
    vor = voronoi(pts, clip=U_SHAPE)
    check_clipped(vor, U_SHAPE, 7.0, connected=False)
    split = vor.cell(0)
    assert (split[:, 0] < 1).any() and (split[:, 0] > 2).any()
    # Point 0 (in the notch) owns the tops of both arms: x + 2y > 4 on the left arm and its
    # mirror image on the right, 1.25 each.
    assert vor.cell_areas()[0] == pytest.approx(2.5, rel=1e-12)


def test_grid_clip_gives_unit_cells():
    vor = voronoi(grid_points(6), clip=(-0.5, -0.5, 5.5, 5.5))
    np.testing.assert_allclose(vor.cell_areas(), 1.0, rtol=1e-12)
    check_convex_ccw(vor)
    check_nearest(vor)


@given(
    st.lists(st.tuples(st.integers(0, 64), st.integers(0, 64)), min_size=3, max_size=40),
    st.integers(0, 3),
)
def test_box_clip_property(coords, scale_exp):
    """Coarse grid points: many cocircular and collinear quadruples, duplicates, any scale."""
    pts = np.array(coords, dtype=float) / 64.0 * 10.0**scale_exp
    rel = pts - pts[0]
    assume(np.any(rel[:, 0, None] * rel[None, :, 1] != rel[:, 1, None] * rel[None, :, 0]))
    box = np.array([0.0, 0.0, 1.0, 1.0]) * 10.0**scale_exp
    vor = voronoi(pts, clip=box)
    np.testing.assert_allclose(vor.cell_areas().sum(), 100.0**scale_exp, rtol=1e-9)
    check_convex_ccw(vor, rel=1e-7)
    check_nearest(vor, eps_scale=1e3)


# --------------------------------------------------------------------------- errors


def test_bad_points():
    pts = random_points(10, seed=0)
    pts[3, 1] = np.nan
    with pytest.raises(InputError, match="point 3"):
        voronoi(pts)
    with pytest.raises(InputError, match="shape"):
        voronoi(np.zeros((5, 3)))
    for seed in (-1, 1.5, "0", True):
        with pytest.raises(InputError, match="seed"):
            voronoi(random_points(10, seed=0), seed=seed)


@pytest.mark.parametrize(
    "clip, error, match",
    [
        ((0, 0, 1), InputError, "shape"),
        ((1, 0, 0, 1), InputError, "xmin < xmax"),
        ((0, 0, 1, np.inf), InputError, "finite"),
        ([(0, 0), (1, 1)], GeometryError, "at least 3"),
        ([(0, 0), (1, 1), (1, 0), (0, 1)], GeometryError, "not simple"),
        ([(0, 0), (1, 0), (2, 0)], GeometryError, "not simple"),
        ([(0, 0), (1, 0), (np.nan, 1)], InputError, "vertex 2"),
        ("box", InputError, "clip"),
    ],
)
def test_bad_clip(clip, error, match):
    with pytest.raises(error, match=match):
        voronoi(random_points(10, seed=0), clip=clip)


def test_bad_triangulation_and_index():
    class Broken:
        points = random_points(4, seed=1)
        triangles = np.array([[0, 1, 2], [0, 2, 3]])
        neighbors = np.array([[-1, -1, -1], [-1, -1, 0]])

    with pytest.raises(InputError, match="which does not list it"):
        voronoi(Broken())

    class Empty:
        points = random_points(4, seed=1)
        triangles = np.zeros((0, 3), dtype=int)
        neighbors = np.zeros((0, 3), dtype=int)

    with pytest.raises(DegenerateInputError):
        voronoi(Empty())
    vor = voronoi(random_points(10, seed=2))
    with pytest.raises(InputError, match="out of range"):
        vor.cell(10)
    with pytest.raises(InputError, match="not unbounded"):
        vor.cell_rays(int(np.flatnonzero(vor.bounded)[0]))


def _exact_circumcentre(a, b, c):
    """The circumcentre by Cramer's rule on |x - a|^2 = |x - b|^2 = |x - c|^2, in rationals."""
    (ax, ay), (bx, by), (cx, cy) = ((Fraction(float(x)), Fraction(float(y))) for x, y in (a, b, c))
    # 2 (b - a) . x = |b|^2 - |a|^2, 2 (c - a) . x = |c|^2 - |a|^2
    m11, m12, r1 = 2 * (bx - ax), 2 * (by - ay), bx * bx + by * by - ax * ax - ay * ay
    m21, m22, r2 = 2 * (cx - ax), 2 * (cy - ay), cx * cx + cy * cy - ax * ax - ay * ay
    det = m11 * m22 - m12 * m21
    return (r1 * m22 - m12 * r2) / det, (m11 * r2 - r1 * m21) / det


@pytest.mark.parametrize(
    "pts",
    [
        # Float area exactly 0 (the products round to 1), exact area 2**-104.
        [(0.0, 0.0), (1.0, 1.0 - 2.0**-52), (1.0 + 2.0**-52, 1.0)],
        # The same far from the origin, and a float area with no correct digit.
        [(1e6, 1e6), (1e6 + 1.0, 1e6 + 1.0 - 2.0**-33), (1e6 + 1.0 + 2.0**-33, 1e6 + 1.0)],
        [(0.0, 0.0), (3.0, 1.0 + 2.0**-51), (6.0 + 2.0**-50, 2.0 + 3 * 2.0**-51)],
    ],
)
def test_float_zero_area_triangle_gives_the_exact_circumcentre(pts):
    pts = np.array(pts)
    vor = voronoi(pts)
    assert vor.forming_points.shape == (1, 3)
    assert np.isfinite(vor.vertices).all()
    ex, ey = _exact_circumcentre(*pts[vor.forming_points[0]])
    # Correctly rounded: the exact centre rounded once.
    assert tuple(vor.vertices[0]) == (float(ex), float(ey))


def test_thin_hull_triangles_give_accurate_vertices():
    # A slightly bent diagonal line above a cloud: its hull triangles are so flat that the
    # float area has lost most digits (the plain formula is off by about 1 % here).
    x = np.linspace(0.0, 1.0, 60)
    line = np.column_stack([x, x + 1e-12 * x * x])
    pts = np.vstack([line, random_points(40, seed=3) * [1.0, 0.5] + [0.5, 0.0]])
    vor = voronoi(pts)
    for t, (a, b, c) in enumerate(pts[vor.forming_points]):
        ex, ey = (float(v) for v in _exact_circumcentre(a, b, c))
        r = np.hypot(ex - a[0], ey - a[1])
        assert np.hypot(vor.vertices[t, 0] - ex, vor.vertices[t, 1] - ey) <= 1e-12 * r


@pytest.mark.parametrize("value, index", [(1e-290, 4), (3e60, 7), (-2.0**201, 2)])
def test_coordinates_outside_the_exact_range(value, index):
    pts = random_points(10, seed=5)
    pts[index, 1] = value
    with pytest.raises(InputError, match=f"point {index} .*range"):
        voronoi(pts)

    class Given:
        points = pts
        triangles = np.array([[0, 1, 2]])
        neighbors = np.array([[-1, -1, -1]])

    with pytest.raises(InputError, match=f"point {index} .*range"):
        voronoi(Given())
    # Zero is in range, and so are the range's ends.
    pts[index] = (0.0, 2.0**-148)
    pts[(index + 1) % 10] = (2.0**200, -(2.0**200))
    assert np.isfinite(voronoi(pts).vertices).all()


def test_supplied_triangles_must_be_counter_clockwise():
    class Given:
        points = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [2.0, 2.0], [0.5, 0.5]])
        triangles = np.array([[0, 1, 2], [1, 3, 2]])
        neighbors = np.array([[1, -1, -1], [-1, 0, -1]])

    voronoi(Given())
    Given.triangles = np.array([[0, 1, 2], [1, 2, 3]])
    with pytest.raises(InputError, match=r"triangle 1 is not strictly counter-clockwise.*point.* 3 \(2, 2\)"):
        voronoi(Given())
    Given.triangles = np.array([[0, 1, 2], [1, 4, 2]])  # 4 lies on edge 1-2: zero area
    with pytest.raises(InputError, match="triangle 1 is not strictly counter-clockwise"):
        voronoi(Given())


# --------------------------------------------------------------------------- plot


@pytest.mark.parametrize("clip", [None, (0, 0, 1, 1), L_SHAPE])
def test_plot_writes_png(tmp_path, clip):
    from meshwright.plot.voronoi_plot import plot_voronoi

    pts = random_points(60, seed=4) * (2 if clip == L_SHAPE else 1)
    path = tmp_path / "voronoi.png"
    ax = plot_voronoi(voronoi(pts, clip=clip), path=path)
    assert path.stat().st_size > 1000
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert len(ax.collections) == 2
