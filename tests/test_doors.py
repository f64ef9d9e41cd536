"""Every public door checks its arguments before any work and names the culprit.

``triangulate`` (every argument, against what the method's registry entry honours, the work
caps), ``delaunay`` (seed, coordinate range), ``smooth`` (points, connectivity),
``load_domain`` (JSON types, named by key path), ``Domain(regions=...)``, point files (non
UTF-8), the shared helpers (``fmt_point``, the coercer, the coordinate range), and the
command line end to end: a user mistake gives one line on stderr naming the culprit, exit
status 2, never a traceback.  Weatherill's ``alpha`` and the size-less modes of 18.1.3 and
18.3 are checked for their effect on density.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import meshwright as mw
from meshwright import geometry as g
from meshwright.cli import main
from meshwright.core.errors import (
    FormatError,
    GeometryError,
    InputError,
    MeshingError,
    MeshwrightError,
    SizeError,
    fmt_point,
)
from meshwright.core.validate_input import COORD_MAX, COORD_MIN, as_points, check_coordinate_range

METHODS = sorted(mw.MESH_METHODS)


# ---------------------------------------------------------------------------- helpers
def test_fmt_point_round_trips_any_dimension():
    p = (0.1, -1e-300, 2.0**200 / 3.0)
    text = fmt_point(p)
    assert text.startswith("(") and text.endswith(")")
    assert tuple(float(s) for s in text[1:-1].split(",")) == p
    assert fmt_point(np.array([1.0, 2.0])) == "(1, 2)"


def test_point_coercer_names_the_culprit():
    with pytest.raises(InputError, match=r"pts: point 2 is not finite: \(nan, 1\)"):
        as_points([[0, 0], [1, 0], [math.nan, 1]], "pts")
    with pytest.raises(InputError, match=r"shape \(n, 2\), got \(3,\)"):
        as_points([1.0, 2.0, 3.0])
    with pytest.raises(InputError, match="array of numbers"):
        as_points([["a", "b"]])
    out = as_points([[1, 2]], dim=2)
    assert out.dtype == np.float64 and out.flags.c_contiguous


@pytest.mark.parametrize("bad", [COORD_MIN / 2, -COORD_MIN / 2, COORD_MAX * 2, 1e-300, 1e300])
def test_coordinate_range_check_names_point(bad):
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.5, bad]])
    with pytest.raises(InputError, match=r"point 2 \(0.5, .*\) has a coordinate outside"):
        check_coordinate_range(pts)
    check_coordinate_range(np.array([[0.0, COORD_MIN], [COORD_MAX, -COORD_MAX]]))  # both ends allowed


# ---------------------------------------------------------------------------- triangulate door
@pytest.mark.parametrize("domain, culprit", [(42, "int"), ({"outer": 1}, "dict"), (np.zeros(3), r"shape \(3,\)")])
def test_triangulate_rejects_non_domains_naming_the_type(domain, culprit):
    with pytest.raises(InputError, match=culprit):
        mw.triangulate(domain)


def test_triangulate_domain_names_and_paths(tmp_path):
    with pytest.raises(InputError, match="'no-such-domain' is neither a built-in domain"):
        mw.triangulate("no-such-domain")
    with pytest.raises(InputError, match="missing.json"):
        mw.triangulate(tmp_path / "missing.json")
    path = tmp_path / "square.json"
    path.write_text(json.dumps({"outer": [[0, 0], [1, 0], [1, 1], [0, 1]]}))
    mesh = mw.triangulate(path, size=0.25)
    assert mesh.area() == pytest.approx(1.0, rel=1e-12)
    assert np.array_equal(mw.triangulate(str(path), size=0.25).points, mesh.points)


@pytest.mark.parametrize("size", [0, -1.0, math.nan, math.inf, "fine"])
def test_bad_size_is_a_size_error(size):
    with pytest.raises(SizeError, match="size"):
        mw.triangulate("circle", size)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("max_area", [0, -1.0, math.nan, math.inf, "big"])
def test_bad_max_area_is_refused_for_every_method(method, max_area):
    # front with max_area=0 halved segments for 64 rounds; a negative one ended in int(nan).
    with pytest.raises(SizeError, match="max_area"):
        mw.triangulate("circle", method=method, max_area=max_area)


@pytest.mark.parametrize("min_angle", [-1.0, math.nan, math.inf, 34.0, 60.0, "30", True])
def test_bad_min_angle(min_angle):
    with pytest.raises(InputError, match="min_angle"):
        mw.triangulate("circle", min_angle=min_angle)


def test_min_angle_the_method_cannot_honour_is_an_error():
    with pytest.raises(InputError, match="method 'front' cannot honour min_angle=30"):
        mw.triangulate("circle", method="front", min_angle=30)
    for name, m in mw.MESH_METHODS.items():
        assert 0.0 <= m.default_min_angle <= m.max_min_angle or m.max_min_angle == 0.0
        if m.max_min_angle:
            with pytest.raises(InputError, match=f"above what method '{name}' can honour"):
                mw.triangulate("circle", method=name, min_angle=m.max_min_angle + 0.5)


@pytest.mark.parametrize("method", ["weatherill", "frontal-delaunay"])
def test_min_angle_honoured_by_the_frontal_methods(method):
    mesh = mw.triangulate("circle", 0.2, method=method, min_angle=32)
    assert mesh.quality().summary()["triangle"]["min_angle"]["min"] >= 32.0 - 1e-9


@pytest.mark.parametrize("smooth", [-1, 1.5, True, "3"])
def test_bad_smooth(smooth):
    with pytest.raises(InputError, match="smooth"):
        mw.triangulate("circle", smooth=smooth)


@pytest.mark.parametrize("method", ["magic", None, 3])
def test_bad_method(method):
    with pytest.raises(InputError, match="unknown method"):
        mw.triangulate("circle", method=method)


def test_progress_is_refused_where_the_method_reports_none():
    silent = [k for k, m in mw.MESH_METHODS.items() if not m.reports_progress]
    assert silent == ["frontal-delaunay"]
    with pytest.raises(InputError, match="method 'frontal-delaunay' reports no progress"):
        mw.triangulate("circle", method="frontal-delaunay", progress=True)
    with pytest.raises(InputError, match="progress must be True or False"):
        mw.triangulate("circle", progress="yes")


@pytest.mark.parametrize("seed", [-1, 1.5, True, "a"])
def test_bad_seed_at_the_triangulate_door(seed):
    with pytest.raises(InputError, match="seed"):
        mw.triangulate("circle", seed=seed)


@pytest.mark.parametrize("max_points", [0, 2, 2.5, True, "many"])
def test_bad_max_points(max_points):
    with pytest.raises(InputError, match="max_points"):
        mw.triangulate("circle", max_points=max_points)


def test_alpha_only_for_weatherill_and_positive():
    with pytest.raises(InputError, match="alpha is an option of method 'weatherill' only; method 'delaunay'"):
        mw.triangulate("circle", alpha=0.6)
    for bad in (0, -0.5, math.nan, math.inf, "dense"):
        with pytest.raises(InputError, match="alpha"):
            mw.triangulate("circle", method="weatherill", alpha=bad)


# ---------------------------------------------------------------------------- work caps
def test_tiny_size_fails_at_once_with_the_count_and_the_cap():
    with pytest.raises(SizeError, match=r"size 1e-09 would need about 1\.\d+e\+18 points .* max_points = 100000000"):
        mw.triangulate(g.circle(), 1e-9)


def test_tiny_max_area_fails_at_once():
    with pytest.raises(SizeError, match=r"max_area 1e-12 would need about .* above max_points = 100000000"):
        mw.triangulate(g.circle(), max_area=1e-12, method="front")


def test_size_check_uses_the_given_cap():
    # About 630 boundary and 18 000 interior points for h = 0.01 on the unit disk.
    with pytest.raises(SizeError, match="above max_points = 5000"):
        mw.triangulate(g.circle(), 0.01, max_points=5000)


def test_graded_size_field_counts_boundary_points():
    with pytest.raises(SizeError, match=r"size field <lambda> would need .*\(6\.\d+e\+09 on the boundary\)"):
        mw.triangulate(g.circle(), lambda xy: np.full(len(xy), 1e-9))


@pytest.mark.parametrize("method", METHODS)
def test_every_method_stops_at_max_points_and_names_it(method):
    # The estimate (about 850 points) passes the door; every method needs about 1500.
    with pytest.raises(MeshingError, match=r"max_points ?= ?1000"):
        mw.triangulate(g.circle(), 0.05, method=method, max_points=1000)


# ---------------------------------------------------------------------------- coordinate range
def _incircle_exact(a, b, c, d):
    """Exact in-circle determinant (positive: d inside the ccw circle abc), rationals."""
    rows = []
    for p in (a, b, c):
        x, y = Fraction(p[0]) - Fraction(d[0]), Fraction(p[1]) - Fraction(d[1])
        rows.append((x, y, x * x + y * y))
    (a1, a2, a3), (b1, b2, b3), (c1, c2, c3) = rows
    return a1 * (b2 * c3 - b3 * c2) - a2 * (b1 * c3 - b3 * c1) + a3 * (b1 * c2 - b2 * c1)


@pytest.mark.parametrize("scale", [2.0**-140, 2.0**190])
def test_delaunay_exact_at_both_ends_of_the_range(scale):
    # Scaled so that every nonzero coordinate stays inside [2**-148, 2**200].
    cells = np.random.default_rng(3).permutation(256 * 256)[:60]
    pts = np.column_stack([cells // 256 + 1, cells % 256 + 1]) / 256.0 * scale
    tri = mw.delaunay(pts)
    assert np.array_equal(tri.points, pts)
    assert len(tri.triangles) == 2 * len(pts) - len(tri.hull) - 2
    p = tri.points
    for t in tri.triangles:
        a, b, c = p[t]
        area = (Fraction(b[0]) - Fraction(a[0])) * (Fraction(c[1]) - Fraction(a[1])) - (
            Fraction(b[1]) - Fraction(a[1])
        ) * (Fraction(c[0]) - Fraction(a[0]))
        assert area > 0
    for t, nb in zip(tri.triangles, tri.neighbors):
        for k in range(3):
            if nb[k] >= 0:
                far = [v for v in tri.triangles[nb[k]] if v not in t][0]
                assert _incircle_exact(*p[t], p[far]) <= 0


@pytest.mark.parametrize("scale", [1e-290, 1e-160, 1e70, 1e150])
def test_delaunay_refuses_coordinates_outside_the_range(scale):
    pts = np.random.default_rng(0).random((50, 2)) * scale
    with pytest.raises(InputError, match=r"points: point \d+ \(.*\) has a coordinate outside the exact predicates"):
        mw.delaunay(pts)


def test_triangulate_and_smooth_refuse_coordinates_outside_the_range():
    square = np.array([(0, 0), (1, 0), (1, 1), (0, 1)], float)
    with pytest.raises(InputError, match="domain boundary: point 1 .* outside the exact predicates' range"):
        mw.triangulate(square * 1e-300)
    with pytest.raises(InputError, match="outside the exact predicates' range"):
        mw.triangulate(square * 1e100)
    with pytest.raises(InputError, match=r"points: point 2 .* outside"):
        mw.smooth(square * [[1], [1], [1e100], [1]], [[0, 1, 2], [0, 2, 3]])


# ---------------------------------------------------------------------------- delaunay seed
@pytest.mark.parametrize("seed", [-1, 1.5, True, "x", None])
def test_delaunay_rejects_bad_seeds(seed):
    with pytest.raises(InputError, match="seed"):
        mw.delaunay(np.random.default_rng(0).random((10, 2)), seed=seed)


def test_delaunay_accepts_numpy_ints_and_generators():
    pts = np.random.default_rng(0).random((30, 2))
    a = mw.delaunay(pts, seed=np.int64(4))
    b = mw.delaunay(pts, seed=4)
    assert np.array_equal(a.triangles, b.triangles)
    mw.delaunay(pts, seed=np.random.default_rng(1))


# ---------------------------------------------------------------------------- smooth door
SQUARE = np.array([(0, 0), (1, 0), (1, 1), (0, 1), (0.4, 0.6)], float)
FAN = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]], np.int32)


def test_smooth_checks_points_and_connectivity():
    bad = SQUARE.copy()
    bad[3, 1] = math.nan
    with pytest.raises(InputError, match=r"point 3 is not finite: \(0, nan\)"):
        mw.smooth(bad, FAN)
    with pytest.raises(InputError, match=r"triangles row 1 \[1, 2, 5\] refers to a node outside \[0, 5\)"):
        mw.smooth(SQUARE, FAN + np.array([[0, 0, 0], [0, 0, 1], [0, 0, 0], [0, 0, 0]]))
    with pytest.raises(InputError, match=r"triangles row 0 \[-1, 1, 4\]"):
        mw.smooth(SQUARE, np.where(FAN == 0, -1, FAN))
    with pytest.raises(InputError, match="triangles must be an integer array .* float64"):
        mw.smooth(SQUARE, FAN.astype(float))
    with pytest.raises(InputError, match=r"triangles must have shape \(k, 3\)"):
        mw.smooth(SQUARE, FAN[:, :2])
    with pytest.raises(InputError, match="boundary_edges row 0"):
        mw.smooth(SQUARE, FAN, [[0, 9]])
    with pytest.raises(InputError, match="fixed entry 0 is node 7"):
        mw.smooth(SQUARE, FAN, fixed=[7])
    with pytest.raises(InputError, match=r"fixed as a mask must have shape \(5,\)"):
        mw.smooth(SQUARE, FAN, fixed=np.ones(3, bool))
    for passes in (-1, 2.5, True):
        with pytest.raises(InputError, match="passes"):
            mw.smooth(SQUARE, FAN, passes=passes)
    for relax in (0.0, 1.5, math.nan, "1"):
        with pytest.raises(InputError, match="relax"):
            mw.smooth(SQUARE, FAN, relax=relax)
    with pytest.raises(InputError, match="project must be callable"):
        mw.smooth(SQUARE, FAN, project=3)
    out = mw.smooth(SQUARE, FAN, passes=5)
    assert np.allclose(out[4], (0.5, 0.5))


# ---------------------------------------------------------------------------- load_domain types
OUTER = [[0, 0], [1, 0], [1, 1], [0, 1]]


@pytest.mark.parametrize(
    "spec, where",
    [
        ({"outer": [[0, 0], [1, 0], [1, "a"]]}, r"outer\[2\]\[1\]: expected a number"),
        ({"outer": [[0, 0], [1, 0], [1]]}, r"outer\[2\]: expected a point"),
        ({"outer": {"circle": 5}}, r"outer\.circle: expected an object"),
        ({"outer": {"circle": {"radius": "big"}}}, r"outer\.circle\.radius: expected a number"),
        ({"outer": {"circle": {"radius": -1}}}, r"outer\.circle\.radius: expected a positive"),
        ({"outer": {"circle": {"center": [0, None]}}}, r"outer\.circle\.center\[1\]"),
        ({"outer": {"circle": {}, "marker": 1.5}}, r"outer\.marker: expected an integer"),
        ({"outer": {"ellipse": {"a": [1]}}}, r"outer\.ellipse\.a"),
        ({"outer": {"naca": 12}}, r"outer\.naca: expected a string"),
        ({"outer": {"naca": "0012", "closed_te": "yes"}}, r"outer\.closed_te: expected true or false"),
        ({"outer": {"curves": [{"spline": OUTER, "closed": 1}]}}, r"outer\.curves\[0\]\.closed"),
        ({"outer": {"curves": [{"arc": {"center": [0, 0], "radius": 1, "theta0": "0", "theta1": 1}}]}},
         r"outer\.curves\[0\]\.arc\.theta0"),
        ({"outer": {"curves": [{"arc": {"center": [0, 0], "radius": 1, "theta0": 0}}]}}, r"missing 'theta1'"),
        ({"outer": {"curves": [{"line": [[0, 0], [1, 0]], "marker": "x"}]}}, r"outer\.curves\[0\]\.marker"),
        ({"outer": {"polygon": OUTER, "markers": [1, 2, True, 4]}}, r"outer\.markers"),
        ({"outer": OUTER, "holes": {"circle": {}}}, r"holes: expected a list"),
        ({"outer": OUTER, "points": [[0.5, "x"]]}, r"points\[0\]\[1\]"),
        ({"outer": OUTER, "regions": [{"point": [0.5, 0.5], "marker": "a"}]}, r"regions\[0\]\.marker"),
        ({"outer": OUTER, "regions": [{"point": [0.5, 0.5], "max_area": "x"}]}, r"regions\[0\]\.max_area"),
        ({"outer": OUTER, "regions": [{"point": 0.5}]}, r"regions\[0\]\.point"),
        ({"outer": OUTER, "size": "fine"}, r"size: expected a number"),
        ({"outer": OUTER, "size": 0}, r"size: expected a positive"),
        ({"outer": OUTER, "version": True}, r"unsupported geometry version"),
    ],
)
def test_load_domain_names_the_key_path_of_a_wrong_type(tmp_path, spec, where):
    path = tmp_path / "dom.json"
    path.write_text(json.dumps(spec))
    with pytest.raises(FormatError, match=where) as info:
        g.load_domain(path)
    assert str(path) in str(info.value)


def test_load_domain_non_utf8_names_the_file(tmp_path):
    path = tmp_path / "latin1.json"
    path.write_bytes('{"outer": [[0, 0], [1, 0], [1, 1]], "name": "caf\u00e9"}'.encode("latin-1"))
    with pytest.raises(FormatError, match=r"latin1\.json: not UTF-8 text"):
        g.load_domain(path)


# ---------------------------------------------------------------------------- Domain regions
@pytest.mark.parametrize(
    "regions, error, match",
    [
        ([(0.5, 0.5)], InputError, r"region 0 must be a row"),
        ([(0.5, 0.5, 1), "abc"], InputError, r"region 1 must be a row"),
        ([(0.5, 0.5, "a")], InputError, r"region 0 marker must be a number"),
        ([(0.5, 0.5, 1.5)], InputError, r"region 0 marker must be an integer, got 1.5"),
        ([(0.5, "y", 1)], InputError, r"region 0 y must be a number"),
        ([(0.5, 0.5, 1, "big")], InputError, r"region 0 max_area must be a number or None"),
        ([(0.5, 0.5, True)], InputError, r"region 0 marker"),
        (5, InputError, r"regions must be a sequence"),
        ([(math.nan, 0.5, 1)], GeometryError, r"region 0 seed has non-finite"),
        ([(0.5, 0.5, 1, -2.0)], GeometryError, r"region 0 .* max_area -2.0"),
    ],
)
def test_domain_region_rows(regions, error, match):
    with pytest.raises(error, match=match):
        g.Domain(np.array(OUTER, float), regions=regions)


def test_domain_region_rows_from_an_array():
    d = g.Domain(np.array(OUTER, float), regions=np.array([[0.5, 0.5, 7.0, -1.0 + 2.0]]))
    assert d.regions == ((0.5, 0.5, 7, 1.0),)


# ---------------------------------------------------------------------------- point files
def test_read_points_non_utf8_and_non_finite(tmp_path):
    latin = tmp_path / "pts.txt"
    latin.write_bytes("# caf\u00e9\n0 0\n1 0\n0 1\n".encode("latin-1"))
    with pytest.raises(FormatError, match=r"pts\.txt: not UTF-8 text"):
        mw.read_points(latin)
    node = tmp_path / "pts.node"
    node.write_bytes("3 2 0 0\n1 0 0\n2 1 0\n3 0 1 # caf\u00e9\n".encode("latin-1"))
    with pytest.raises(FormatError, match=r"pts\.node.*not UTF-8 text"):
        mw.read_points(node)
    nan = tmp_path / "nan.txt"
    nan.write_text("0 0\n1 nan\n0 1\n")
    with pytest.raises(FormatError, match=r"nan\.txt: point 1 has a non-finite coordinate \(1, nan\) \(line 2\)"):
        mw.read_points(nan)


# ---------------------------------------------------------------------------- CLI end to end
def _bad_point_files(tmp_path):
    """(name, path, the text the message must contain) for each kind of bad point file."""
    files = []

    def put(name, data: bytes, culprit):
        path = tmp_path / name
        path.write_bytes(data)
        files.append((name, path, culprit))

    files.append(("missing", tmp_path / "missing.txt", "missing.txt"))
    put("empty.txt", b"", "empty.txt: no points")
    put("latin1.txt", "0 0\n1 0\n0 1 # caf\u00e9\n".encode("latin-1"), "latin1.txt: not UTF-8")
    put("nan.txt", b"0 0\n1 0\nnan 1\n", "nan.txt: point 2 has a non-finite coordinate (nan, 1) (line 3)")
    put("columns.txt", b"0 0\n1 0 0 1\n0 1\n", "columns.txt, line 2")
    put("words.csv", b"x,y\n0,0\n1,zero\n", "words.csv, line 3: cannot parse")
    put("collinear.txt", b"0 0\n1 1\n2 2\n", "collinear")
    put("tiny.txt", b"0 0\n1e-300 0\n0 1e-300\n", "outside the exact predicates' range")
    np.save(tmp_path / "four.npy", np.zeros((5, 4)))
    files.append(("four.npy", tmp_path / "four.npy", "four.npy: expected a numeric (n, 2) or (n, 3)"))
    return files


@pytest.mark.parametrize("command", ["delaunay", "voronoi"])
def test_cli_bad_point_files(tmp_path, capsys, command):
    for name, path, culprit in _bad_point_files(tmp_path):
        status = main([command, str(path)])
        err = capsys.readouterr().err
        assert status == 2, name
        assert culprit in err, (name, err)
        assert err.count("\n") == 1 and "Traceback" not in err, name


def test_cli_duplicates(tmp_path, capsys):
    path = tmp_path / "dup.txt"
    path.write_text("0 0\n1 0\n0 1\n1 0\n")
    assert main(["delaunay", str(path), "--duplicates", "reject"]) == 2
    assert "coincident points: 1 and 3 at [1.0, 0.0]" in capsys.readouterr().err
    assert main(["delaunay", str(path)]) == 0  # merged by default
    assert main(["voronoi", str(path)]) == 0  # the duplicate gets an empty cell
    assert "4 cells" in capsys.readouterr().out


def test_cli_point_file_options(tmp_path, capsys):
    path = tmp_path / "ok.txt"
    path.write_text("0 0\n1 0\n0 1\n1 1\n")
    assert main(["delaunay", str(path), "--seed", "-3"]) == 2
    assert "seed must be non-negative, got -3" in capsys.readouterr().err
    xyz = tmp_path / "xyz.txt"
    xyz.write_text("0 0 0\n1 0 0\n0 1 0\n")
    assert main(["voronoi", str(xyz)]) == 2
    assert "xyz.txt: 3 coordinates per point; the Voronoi diagram is 2-D" in capsys.readouterr().err
    assert main(["voronoi", str(path), "--clip", "0", "0", "inf", "1"]) == 2
    assert "--clip box" in capsys.readouterr().err


def test_cli_mesh_refuses_what_the_method_cannot_honour(tmp_path, capsys):
    out = str(tmp_path / "m.vtu")
    assert main(["mesh", "circle", "-o", out, "--alpha", "0.5"]) == 2
    assert "alpha is an option of method 'weatherill' only" in capsys.readouterr().err
    assert main(["mesh", "circle", "-o", out, "--method", "front", "--min-angle", "30"]) == 2
    assert "method 'front' cannot honour min_angle=30" in capsys.readouterr().err
    assert main(["mesh", "circle", "-o", out, "--size", "1e-9"]) == 2
    assert "above max_points = 100000000" in capsys.readouterr().err
    assert main(["mesh", "circle", "-o", out, "--size", "0.05", "--max-points", "1000"]) == 1
    assert "max_points=1000" in capsys.readouterr().err
    latin = tmp_path / "dom.json"
    latin.write_bytes('{"outer": [[0, 0], [1, 0], [1, 1]]} \xe9'.encode("latin-1"))
    assert main(["mesh", str(latin), "-o", out]) == 2
    assert "dom.json: not UTF-8 text" in capsys.readouterr().err
    # Default min-angle per method: the front runs without one, Weatherill takes --alpha.
    assert main(["mesh", "circle", "-o", out, "--method", "weatherill", "--alpha", "0.8", "--size", "0.3"]) == 0


def test_cli_subprocess_prints_no_traceback(tmp_path):
    proc = subprocess.run(
        [sys.executable, "-m", "meshwright.cli", "delaunay", str(tmp_path / "absent.txt")],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr
    assert proc.stderr.startswith("meshwright delaunay: error: ") and "absent.txt" in proc.stderr


# ---------------------------------------------------------------------------- Weatherill's alpha, size-less modes
def test_weatherill_alpha_controls_density_monotonically():
    counts = [mw.triangulate(g.circle(), 0.1, method="weatherill", alpha=a).n_points for a in (0.4, 0.55, 0.7, 0.9)]
    assert all(a > b for a, b in zip(counts, counts[1:])), counts
    assert counts[0] > 1.5 * counts[-1], counts


def _graded_square():
    """Unit square with 41 vertices on its left side (spacing 0.025) and 5 on the others (0.25)."""
    left = np.column_stack([np.zeros(41), np.linspace(1, 0, 41)])[:-1]
    bottom = np.column_stack([np.linspace(0, 1, 5), np.zeros(5)])[:-1]
    right = np.column_stack([np.ones(5), np.linspace(0, 1, 5)])[:-1]
    top = np.column_stack([np.linspace(1, 0, 5), np.ones(5)])[:-1]
    return g.polygon(np.vstack([left, bottom, right, top]))


@pytest.mark.parametrize("method", ["weatherill", "frontal-delaunay"])
def test_size_less_modes_interpolate_the_boundary_spacing(method):
    dom = _graded_square()
    assert dom.size is None
    mesh = mw.triangulate(dom, method=method)
    p, t = mesh.points, mesh.cells["triangle"]
    a, b, c = p[t[:, 0]], p[t[:, 1]], p[t[:, 2]]
    area = 0.5 * np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
    x = (a[:, 0] + b[:, 0] + c[:, 0]) / 3.0
    fine, middle, coarse = area[x < 0.15].mean(), area[(x > 0.45) & (x < 0.55)].mean(), area[x > 0.85].mean()
    # Sizes grow away from the fine side: interior spacing follows the boundary's.
    assert fine < middle < coarse, (fine, middle, coarse)
    assert coarse > 10 * fine
    assert mesh.area() == pytest.approx(1.0, rel=1e-12)


# ---------------------------------------------------------------------------- fuzzing the doors
_ANY = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(-(2**70), 2**70),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=4),
    st.lists(st.floats(-2, 2), max_size=3),
)


@settings(deadline=None, max_examples=60, suppress_health_check=[HealthCheck.too_slow])
@given(
    st.fixed_dictionaries(
        {},
        optional={
            "size": st.one_of(_ANY, st.floats(0.05, 2.0)),
            "min_angle": st.one_of(_ANY, st.floats(0, 34)),
            "method": st.one_of(st.sampled_from(METHODS), _ANY),
            "smooth": st.one_of(_ANY, st.integers(0, 3)),
            "max_area": st.one_of(_ANY, st.floats(1e-3, 1.0)),
            "seed": _ANY,
            "progress": _ANY,
            "conforming": _ANY,
            "alpha": st.one_of(_ANY, st.floats(0.3, 2.0)),
        },
    )
)
def test_triangulate_fuzz_raises_only_meshwright_errors(kwargs):
    # A small cap keeps every accepted request cheap: refused at the door or capped in the method.
    try:
        mesh = mw.triangulate("circle", max_points=3000, **kwargs)
    except MeshwrightError:
        return
    mesh.validate()


_KEYS = [
    "outer", "holes", "segments", "points", "regions", "size", "version", "polygon", "markers", "marker",
    "circle", "center", "radius", "ellipse", "a", "b", "rotation", "naca", "chord", "aoa", "origin",
    "closed_te", "curves", "line", "arc", "theta0", "theta1", "degrees", "polyline", "spline", "closed",
    "point", "max_area",
]
_JSON = st.recursive(
    st.none() | st.booleans() | st.integers() | st.just(-(10**400)) | st.floats() | st.text(max_size=5),
    lambda inner: st.lists(inner, max_size=5) | st.dictionaries(st.sampled_from(_KEYS), inner, max_size=4),
    max_leaves=25,
)


@settings(deadline=None, max_examples=300)
@given(st.dictionaries(st.sampled_from(_KEYS[:7]), _JSON, max_size=4))
def test_domain_from_dict_fuzz_raises_only_format_or_geometry_errors(spec):
    try:
        g.domain_from_dict(spec)
    except (FormatError, GeometryError):
        pass


@settings(deadline=None, max_examples=200)
@given(
    st.sampled_from(["outer", "holes", "regions"]),
    _JSON,
)
def test_domain_from_dict_fuzz_inside_a_valid_file(key, value):
    spec = {"outer": {"circle": {"center": [0.5, 0.5], "radius": 2}}, "holes": [OUTER], "regions": []}
    spec[key] = value if key == "outer" else [value]
    try:
        g.domain_from_dict(spec)
    except (FormatError, GeometryError):
        pass


@settings(deadline=None, max_examples=150)
@given(
    st.sampled_from([".txt", ".csv", ".npy", ".node"]),
    st.one_of(
        st.binary(max_size=60),
        st.lists(
            st.lists(st.sampled_from(["0", "1.5", "-2e3", "nan", "inf", "x", ",", "#", "1e400", ""]), max_size=4).map(
                " ".join
            ),
            max_size=6,
        ).map(lambda rows: "\n".join(rows).encode()),
    ),
)
def test_read_points_fuzz_raises_only_format_errors(tmp_path_factory, suffix, data):
    path = tmp_path_factory.mktemp("fuzz") / ("pts" + suffix)
    path.write_bytes(data)
    try:
        pts = mw.read_points(path)
    except FormatError as exc:
        assert "pts" + suffix in str(exc)
        return
    assert pts.ndim == 2 and pts.shape[1] in (2, 3) and len(pts) and np.isfinite(pts).all()


@settings(deadline=None, max_examples=80)
@given(
    st.lists(st.tuples(st.floats(-4, 4), st.floats(-4, 4)), min_size=0, max_size=8),
    st.lists(st.tuples(st.integers(-2, 9), st.integers(-2, 9), st.integers(-2, 9)), max_size=6),
    st.one_of(_ANY, st.integers(0, 3)),
)
def test_smooth_fuzz_raises_only_input_errors(points, triangles, passes):
    try:
        pts = np.array(points, dtype=float).reshape(-1, 2)
        out = mw.smooth(pts, np.array(triangles, dtype=np.int64).reshape(-1, 3), passes=passes)
    except InputError:
        return
    assert out.shape == (len(points), 2)
