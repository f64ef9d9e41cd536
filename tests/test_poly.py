"""Tests of Triangle's .poly format as a Domain: geometry.read_poly / write_poly (the parser in geometry/poly_format.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from meshwright.core.errors import FormatError, GeometryError, InputError
from meshwright.geometry import (
    circle,
    polygon,
    read_poly,
    write_poly,
)

TWO_PI = 2 * math.pi
# ---------------------------------------------------------------------------------------
# files
# ---------------------------------------------------------------------------------------
POLY = """# square with a hole, an interior and a dangling segment, a region
9 2 0 1
{b0} 0 0 5
{b1} 4 0 0
{b2} 4 4 0
{b3} 0 4 0
{b4} 1 1 0
{b5} 2 1 0
{b6} 2 2 0
{b7} 1 2 0
{b8} 3 3 0
10 1
1 {b0} {b1} 7
2 {b1} {b2} 0
3 {b2} {b3} 0
4 {b3} {b0} 0
5 {b4} {b5} 0
6 {b5} {b6} 0
7 {b6} {b7} 0
8 {b7} {b4} 0
9 {b1} {b6} 3
10 {b8} {b2} 0
1
1 1.5 1.5
1
1 0.5 3 4 0.1
"""


@pytest.mark.parametrize("base", [0, 1])
def test_read_poly(tmp_path, base):
    f = tmp_path / "a.poly"
    f.write_text(POLY.format(**{f"b{i}": i + base for i in range(9)}))
    d = read_poly(f)
    assert d.area() == pytest.approx(15.0)
    assert len(d.loops) == 2 and len(d.constraints) == 2
    assert d.regions == ((0.5, 3.0, 4, 0.1),)
    disc = d.discretize()
    assert sorted(disc.segment_markers.tolist()) == [0, 1, 1, 1, 1, 1, 1, 1, 3, 7]


def test_poly_round_trip(tmp_path):
    d = polygon(
        [(0, 0), (3, 0), (3, 2), (0, 2)],
        holes=[[(1, 0.5), (2, 0.5), (2, 1.5), (1, 1.5)]],
        segments=[[(2.5, 0.5), (2.5, 1.5)]],
        markers=[[1, 2, 3, 4], 6],
        points=[(0.5, 1.0)],
        regions=[(0.2, 0.2, 3, 0.05)],
    )
    f = tmp_path / "r.poly"
    write_poly(f, d)
    e = read_poly(f)
    a, b = d.discretize(), e.discretize()
    assert e.area() == pytest.approx(d.area())
    assert sorted(a.segment_markers.tolist()) == sorted(b.segment_markers.tolist())
    assert e.points.tolist() == [[0.5, 1.0]]
    assert e.regions == d.regions
    assert len(e.holes) == 1 and len(e.constraints) == 1


def test_poly_with_node_file_and_circle(tmp_path):
    d = circle((0, 0), 1.0)
    f = tmp_path / "c.poly"
    write_poly(f, d, size=0.1)
    lines = f.read_text().splitlines()
    nv = int(lines[1].split()[0])
    (tmp_path / "c.node").write_text("\n".join(lines[1 : 2 + nv]) + "\n")
    (tmp_path / "c.poly").write_text("0 2 0 1\n" + "\n".join(lines[2 + nv :]) + "\n")
    e = read_poly(f)
    assert e.area() == pytest.approx(
        d.discretize(0.1).points.shape[0] * 0.5 * math.sin(TWO_PI / nv)
    )


@pytest.mark.parametrize(
    "text, match, err",
    [
        ("3 2 0 0\n1 0 0\n2 1 x\n", r"x\.poly, line 3: vertex y: 'x' is not a finite number", FormatError),
        ("2 2 0 0\n1 0 0\n3 1 0\n", r"x\.poly, line 3: vertex numbered 3, expected 2", FormatError),
        (
            "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n2 0\n1 1 2\n2 2 9\n",
            r"x\.poly, line 7: segment endpoints 2 9 outside the vertex numbers, 1\.\.3",
            FormatError,
        ),
        (
            "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n2 0\n1 1 2\n2 2 3\n",
            r"x\.poly, line 7: unexpected end of file, expected the hole header",
            FormatError,
        ),
        (
            # A bow tie: split at its crossing (as Triangle does), its two loops touch there.
            "4 2 0 0\n1 0 0\n2 1 1\n3 1 0\n4 0 1\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n",
            r"boundary loops touch at vertex \(0\.5, 0\.5\)",
            GeometryError,
        ),
        (
            "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0.5 0\n4 0\n1 1 2\n2 2 3\n3 3 1\n4 1 4\n0\n",
            "segments on lines 7 and 10 overlap or intersect",
            GeometryError,
        ),
        (
            "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 1 0\n4 0\n1 1 2\n2 2 3\n3 3 1\n4 2 4\n0\n",
            r"x\.poly, line 10: segment has zero length",
            GeometryError,
        ),
    ],
)
def test_poly_errors(tmp_path, text, match, err):
    f = tmp_path / "x.poly"
    f.write_text(text)
    with pytest.raises(err, match=match):
        read_poly(f)


def test_poly_zero_vertices_twice_is_an_error_not_a_recursion(tmp_path):
    (tmp_path / "z.poly").write_text("0 2 0 0\n3 0\n1 1 2\n2 2 3\n3 3 1\n0\n")
    with pytest.raises(FormatError, match=r"z\.poly, line 1: 0 vertices declared, so they must be in z\.node"):
        read_poly(tmp_path / "z.poly")
    (tmp_path / "z.node").write_text("# deferring again would loop\n0 2 0 0\n")
    with pytest.raises(FormatError, match=r"z\.node, line 2: declares 0 vertices, but z\.poly \(line 1\)"):
        read_poly(tmp_path / "z.poly")


def test_poly_arguments_checked(tmp_path):
    with pytest.raises(InputError, match="file path, got int"):
        read_poly(3)
    with pytest.raises(InputError, match="Domain or a Discretization, got str"):
        write_poly(tmp_path / "a.poly", "circle")
    with pytest.raises(InputError, match="already discretised"):
        write_poly(tmp_path / "a.poly", circle((0, 0), 1.0).discretize(0.5), size=0.1)
    with pytest.raises(InputError, match="first_index must be 0 or 1"):
        write_poly(tmp_path / "a.poly", circle((0, 0), 1.0), first_index=2)


@pytest.mark.parametrize("first_index", [0, 1])
def test_poly_round_trip_first_index(tmp_path, first_index):
    d = polygon([(0, 0), (2, 0), (2, 1), (0, 1)], holes=[[(0.5, 0.25), (1.5, 0.25), (1.0, 0.75)]])
    f = tmp_path / "t.poly"
    write_poly(f, d, first_index=first_index)
    assert f.read_text().splitlines()[2].split()[0] == str(first_index)
    e = read_poly(f)
    np.testing.assert_array_equal(e.discretize().points, d.discretize().points)
    assert e.area() == d.area()


@settings(max_examples=150, deadline=None)
@given(data=st.data())
def test_damaged_poly_files_raise_meshwright_errors_only(data):
    """A damaged .poly (bytes replaced, a line dropped) gives a Domain or a FormatError /
    GeometryError naming the file, never a raw exception."""
    import tempfile
    from pathlib import Path

    from meshwright.core.errors import MeshwrightError

    lines = POLY.format(**{f"b{i}": i + 1 for i in range(9)}).encode().split(b"\n")
    if data.draw(st.booleans()):
        del lines[data.draw(st.integers(0, len(lines) - 1))]
    raw = bytearray(b"\n".join(lines))
    for _ in range(data.draw(st.integers(0, 2))):
        raw[data.draw(st.integers(0, len(raw) - 1))] = data.draw(st.sampled_from(b"0123456789 .-#\nx\xff"))
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "d.poly"
        path.write_bytes(bytes(raw))
        try:
            read_poly(path)
        except (FormatError, GeometryError) as exc:
            assert str(exc).startswith(str(path))
        except MeshwrightError as exc:
            pytest.fail(f"{type(exc).__name__} without the file name: {exc}")


def test_poly_faces_exact_for_directions_closer_than_arctan2_resolves(tmp_path):
    """Two segments leave (0, 0) 4e-19 rad apart (arctan2 ties them) and bound a sliver
    face of area 1/2 whose float shoelace sum rounds to 0: the half-edge order around each
    vertex and the faces' orientations must still be the exact ones."""
    from fractions import Fraction

    from meshwright.geometry.poly import _angular_order, _faces

    a = 2**30
    xy = np.array([(0, 0), (a, a + 1), (a + 1, a + 2), (0, 2 * a), (2 * a, 0)], dtype=np.float64)
    seg = np.array([(0, 1), (0, 2), (1, 2), (1, 3), (0, 3), (0, 4), (4, 2)])
    org = np.concatenate([seg[:, 0], seg[:, 1]])
    dst = np.concatenate([seg[:, 1], seg[:, 0]])

    def before(e, f):  # counter-clockwise from the +x axis, in rationals
        u = [Fraction(xy[dst[e], k]) - Fraction(xy[org[e], k]) for k in (0, 1)]
        v = [Fraction(xy[dst[f], k]) - Fraction(xy[org[f], k]) for k in (0, 1)]
        hu, hv = (w[1] < 0 or (w[1] == 0 and w[0] < 0) for w in (u, v))
        return hu < hv or (hu == hv and u[0] * v[1] - u[1] * v[0] > 0)

    order = _angular_order(xy, org, dst).tolist()
    assert order == sorted(order, key=lambda e: (org[e], sum(before(f, e) for f in range(len(org)) if org[f] == org[e])))
    face, area, positive, _, _ = _faces(xy, seg)
    sliver = face[1]  # half-edge 0 -> 2 runs along the sliver (0, 0), b, a
    assert area[sliver] == 0.0 and positive[sliver]  # the float sum loses it, the exact test not
    assert positive.sum() == 3 and len(positive) == 4


def _fraction_area(points, triangles):
    """Exact total area of triangles (absolute values), with rationals."""
    from fractions import Fraction

    p = [(Fraction(x), Fraction(y)) for x, y in np.asarray(points, dtype=float).tolist()]
    total = Fraction(0)
    for a, b, c in np.asarray(triangles).tolist():
        (ax, ay), (bx, by), (cx, cy) = p[a], p[b], p[c]
        total += abs((bx - ax) * (cy - ay) - (by - ay) * (cx - ax)) / 2
    return total


@pytest.mark.parametrize("name", ["A", "double_hex", "double_hex2", "double_hex3", "face", "square_circle_hole"])
def test_read_poly_triangle_examples_enclose_triangles_area(name):
    """Each closed example .poly that ships with Triangle becomes a Domain whose area is that
    of Triangle's own constrained triangulation of the file (``p``), summed exactly."""
    triangle = pytest.importorskip("triangle")
    from pathlib import Path

    path = Path(triangle.__file__).parent / "data" / f"{name}.poly"
    if not path.is_file():
        pytest.skip("the triangle package ships no example files")
    ref = triangle.triangulate(triangle.get_data(name), "p")
    d = read_poly(path)
    assert d.area() == pytest.approx(float(_fraction_area(ref["vertices"], ref["triangles"])), rel=1e-12)


def test_read_poly_keeps_float_region_attributes(tmp_path):
    """Triangle's regional attribute is a float: kept per region (marker 0 unless it is
    integral); a region line without its fifth field takes the attribute as area bound."""
    f = tmp_path / "r.poly"
    f.write_text(
        "4 2 0 0\n1 0 0\n2 2 0\n3 2 1\n4 0 1\n5 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 2 4\n0\n"
        "2\n1 1.5 0.1 0.25 0.5\n2 0.2 0.8 7\n"
    )
    dom = read_poly(f)
    assert dom.regions == ((1.5, 0.1, 0, 0.5), (0.2, 0.8, 7, 7.0))
    np.testing.assert_array_equal(dom.region_attributes, [0.25, 7.0])
    assert not dom.open_boundary


def test_read_poly_numbering_numbers_and_comments_agree(tmp_path):
    """The same square with a hole written 1-based and plain, and 0-based with Fortran
    numbers and comments on every line, reads to the same domain."""
    plain = (
        "8 2 0 0\n1 0 0\n2 3 0\n3 3 3\n4 0 3\n5 1 1\n6 2 1\n7 2 2\n8 1 2\n"
        "8 1\n1 1 2 5\n2 2 3 1\n3 3 4 1\n4 4 1 1\n5 5 6 2\n6 6 7 2\n7 7 8 2\n8 8 5 2\n"
        "1\n1 1.5 1.5\n"
    )
    fortran = (
        "# vertices\n8 2 0 0 # count dim attr markers\n"
        "0 0.000000E+00 -.000000E+00 # a\n1 0.300000E+01 0.0E0 # b\n2 .3E1 3.0 #\n3 -0. 0.3E+01\n"
        "4 0.1E+01 1 # hole\n5 2 .1e1\n6 2. 2.\n7 1 2 # last\n"
        "8 1 # segments\n0 0 1 5\n1 1 2 1 # x\n2 2 3 1\n3 3 0 1\n4 4 5 2\n5 5 6 2\n6 6 7 2\n7 7 4 2 #\n"
        "1 # holes\n0 0.15E+01 1.5E0 # seed\n# end\n"
    )
    domains = []
    for name, text in (("plain", plain), ("fortran", fortran)):
        (tmp_path / f"{name}.poly").write_text(text)
        domains.append(read_poly(tmp_path / f"{name}.poly"))
    a, b = (d.discretize() for d in domains)
    for field in ("points", "segments", "segment_markers", "holes"):
        np.testing.assert_array_equal(getattr(a, field), getattr(b, field))
    assert a.points.shape == (8, 2) and sorted(set(a.segment_markers.tolist())) == [1, 2, 5]


def test_read_poly_open_segments_close_with_the_hull(tmp_path):
    """No segments at all, or one lone segment: the convex hull of the vertices closes the
    boundary (marker 1 off the given segments), hull vertices on a hull edge kept."""
    f = tmp_path / "open.poly"
    f.write_text("5 2 0 0\n1 0 0\n2 2 0\n3 2 2\n4 0 2\n5 1 0\n1 1\n1 1 5 4\n0\n")
    dom = read_poly(f)
    assert dom.open_boundary and dom.area() == 4.0
    disc = dom.discretize()
    assert len(disc.points) == 5  # (1, 0) stays a boundary vertex
    mid = disc.points[disc.segments].mean(axis=1)
    np.testing.assert_array_equal(disc.segment_markers[(mid[:, 1] == 0) & (mid[:, 0] < 1)], [4])
    assert (disc.segment_markers[(mid[:, 1] > 0) | (mid[:, 0] > 1)] == 1).all()
    f.write_text("3 2 0 0\n1 0 0\n2 1 0\n3 2 0\n0 0\n0\n")
    with pytest.raises(GeometryError, match="enclose no region"):
        read_poly(f)


@settings(max_examples=40, deadline=None)
@given(pts=st.lists(st.tuples(st.integers(-6, 6), st.integers(-6, 6)), min_size=3, max_size=25, unique=True))
def test_read_poly_hull_of_a_point_set(tmp_path_factory, pts):
    """A .poly with vertices only is closed by their convex hull: scipy's hull area as the
    oracle, every vertex kept (points on a hull edge as boundary vertices)."""
    spatial = pytest.importorskip("scipy.spatial")
    xy = np.array(pts, dtype=np.float64)
    f = tmp_path_factory.mktemp("hull") / "p.poly"
    f.write_text(f"{len(xy)} 2 0 0\n" + "".join(f"{i + 1} {x} {y}\n" for i, (x, y) in enumerate(pts)) + "0 0\n0\n")
    if np.linalg.matrix_rank(xy[1:] - xy[0]) < 2:
        with pytest.raises(GeometryError, match="enclose no region"):
            read_poly(f)
        return
    dom = read_poly(f)
    assert dom.open_boundary
    assert dom.area() == pytest.approx(spatial.ConvexHull(xy).volume, rel=1e-12)
    assert len(dom.discretize().points) == len(xy)
