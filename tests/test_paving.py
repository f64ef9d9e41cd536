"""Paving (issue 12, 18.5.2, Blacker and Stephenson 1991).

Oracles never share code with what they check: convexity of every corner by exact
``Fraction`` cross products, interior angles recomputed with plain numpy ``arctan2`` (not
``core.quality``), conformity by counting directed edges, parity by counting line cells.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from meshwright.core.errors import InputError, MeshingError
from meshwright.geometry import annulus, circle, circles, polygon, rectangle
from meshwright.quad import QUAD_METHODS, quadrangulate
from meshwright.quad.parity import ParityError
from meshwright.quad.paving import closure_quads, node_classes, pave_domain
from meshwright.sizing import BackgroundGrid
from meshwright.sizing.field import as_size_field


def _cross(p, q, r) -> Fraction:
    """Exact (q - p) x (r - p)."""
    px, py = Fraction(float(p[0])), Fraction(float(p[1]))
    return (Fraction(float(q[0])) - px) * (Fraction(float(r[1])) - py) - (Fraction(float(q[1])) - py) * (
        Fraction(float(r[0])) - px
    )


def _angles(xy, quads) -> np.ndarray:
    """(q, 4) interior angles in degrees, plain numpy."""
    out = np.empty((len(quads), 4))
    for k in range(4):
        c = xy[quads[:, k]]
        u = xy[quads[:, (k + 1) % 4]] - c
        w = xy[quads[:, (k + 3) % 4]] - c
        out[:, k] = np.degrees(np.arctan2(u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0], (u * w).sum(axis=1)))
    return out


def _check_all_quad(mesh):
    """Validate, all quads strictly convex (exact), conforming, line cells = boundary."""
    mesh.validate()
    xy, quads = mesh.points, mesh.cells["quad"]
    assert "triangle" not in mesh.cells
    assert len(quads)
    assert all(_cross(xy[q[k - 1]], xy[q[k]], xy[q[(k + 1) % 4]]) > 0 for q in quads.tolist() for k in range(4))
    directed = set()
    for q in quads.tolist():
        for k in range(4):
            e = (q[k], q[(k + 1) % 4])
            assert e not in directed, f"edge {e} used twice in the same direction"
            directed.add(e)
    boundary = {e for e in directed if (e[1], e[0]) not in directed}
    assert boundary == {tuple(e) for e in mesh.cells["line"].tolist()}


def _jump(xy):
    return np.where(xy[:, 0] < 1.0, 0.05, 0.15)


CASES = {
    "disk": (circle(), 0.1),
    "annulus (hole)": (annulus(), 0.08),
    "three holes": (circles(), 0.15),
    "l-shape": (polygon([(-1, -1), (0, -1), (0, 0), (1, 0), (1, 1), (-1, 1)]), 0.1),
    "size jump": (rectangle(0.0, 0.0, 2.0, 1.0), _jump),
    "naca 0012 far field": ("naca0012", None),
}


@pytest.mark.parametrize("name", list(CASES))
def test_paved_meshes_are_valid_all_quad_and_cover_the_domain(name):
    dom, size = CASES[name]
    mesh = quadrangulate(dom, size, method="paving")
    _check_all_quad(mesh)
    if not isinstance(dom, str):
        assert mesh.area() == pytest.approx(abs(dom.area()), rel=2e-2)


def _star(rng, n, r0, r1, centre=(0.0, 0.0)):
    t = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    r = rng.uniform(r0, r1, n)
    return np.column_stack([centre[0] + r * np.cos(t), centre[1] + r * np.sin(t)])


@pytest.mark.parametrize("seed", range(4))
def test_random_star_domains_with_a_hole_are_valid(seed):
    """Concave random outlines, a random concave hole and a size growing away from the
    centre: fronts meet, join, stop and fill; the mesh stays valid and all-quad."""
    rng = np.random.default_rng(seed)
    dom = polygon(_star(rng, 11, 0.7, 1.0), holes=[_star(rng, 7, 0.15, 0.3)[::-1]])
    mesh = quadrangulate(dom, lambda xy: 0.04 + 0.06 * np.hypot(*xy.T), method="paving")
    _check_all_quad(mesh)
    assert mesh.area() == pytest.approx(abs(dom.area()), rel=2e-2)


# Derandomized: the same examples on every run (CI must not turn red by chance); the
# star below, found by random examples, is kept as a known failure.
@settings(max_examples=8, deadline=None, derandomize=True)
@given(
    radii=st.lists(st.floats(0.5, 1.0), min_size=5, max_size=14),
    h=st.floats(0.05, 0.2),
)
def test_random_star_polygons_are_paved_validly(radii, h):
    t = np.linspace(0.0, 2.0 * np.pi, len(radii), endpoint=False)
    r = np.asarray(radii)
    dom = polygon(np.column_stack([r * np.cos(t), r * np.sin(t)]))
    mesh = quadrangulate(dom, h, method="paving")
    _check_all_quad(mesh)
    assert mesh.area() == pytest.approx(abs(dom.area()), rel=1e-9)


def test_quad_dominant_fill_reports_its_triangles():
    """all_quad=False: the void fill's unpaired triangles stay (counted), nothing split."""
    fill, rep = pave_domain(circles(), 0.15, all_quad=False)
    assert rep.triangles_left == len(fill.triangles)
    assert not rep.split
    mesh = quadrangulate(circles(), 0.15, method="paving", all_quad=False)
    mesh.validate()
    assert len(mesh.cells.get("triangle", ())) == rep.triangles_left


@pytest.mark.parametrize("h", [0.2, 0.155, 0.1, 0.07, 0.05, 0.03])
def test_disk_angles_meet_the_paving_targets(h):
    """Issue 12's targets on the disk: every interior angle in [45, 150] degrees (measured
    here: within [50, 130] over 48 sizes from 0.015 to 0.25)."""
    mesh = quadrangulate(circle(), h, method="paving")
    _check_all_quad(mesh)
    a = _angles(mesh.points, mesh.cells["quad"])
    assert a.min() >= 45.0
    assert a.max() <= 150.0


def test_disk_is_paved_to_the_centre_by_rows_tucks_and_a_closure():
    fill, rep = pave_domain(circle(), 0.05)
    assert rep.voids == 0 and rep.filled == 0 and not rep.split
    assert rep.rows >= 10 and rep.tucks > 0 and rep.closures >= 1
    assert rep.paved == len(fill.quads)
    # Tucks keep the spacing at the size while the rows shrink: about pi / h**2 quads
    # (without tucks the rows would keep all 126 boundary intervals down to the centre).
    assert len(fill.quads) == pytest.approx(np.pi / 0.05**2, rel=0.15)


def test_rectangle_is_a_structured_grid():
    """A rectangle with an even spacing is paved by rows and seams only: a grid, every
    angle within 2 degrees of 90 (the seams where the rows meet move nodes a little)."""
    mesh = quadrangulate(rectangle(0.0, 0.0, 2.0, 1.0), 0.1, method="paving")
    _check_all_quad(mesh)
    assert np.allclose(_angles(mesh.points, mesh.cells["quad"]), 90.0, atol=2.0)
    assert len(mesh.cells["quad"]) == 200


def test_holes_grow_rows_with_wedges_and_meeting_fronts_are_joined():
    """The annulus: the hole's rows grow by wedges, the two fronts meet, are joined and
    zipped by seams, and the rest is closed without any void fill."""
    _, rep = pave_domain(annulus(), 0.08)
    assert rep.rows > 0 and rep.wedges > 0 and rep.seams > 0 and rep.joints > 0
    assert rep.voids == 0 and rep.filled == 0 and not rep.split


@pytest.mark.parametrize("name", ["naca0012", "three-element"])
def test_airfoil_angles_reach_the_issue_target(name):
    """Issue 12's [45, 150] degrees on the airfoils at their own size (neither has a
    boundary corner sharper than 90 degrees, so no quad is exempt).  Before the void fill
    took the spacing of the stopped rows, the three-element airfoil had quads down to 24
    degrees: the void's front, at the field's larger size, fanned thin triangles onto the
    rows' short edges."""
    mesh = quadrangulate(name, method="paving")
    _check_all_quad(mesh)
    a = _angles(mesh.points, mesh.cells["quad"])
    assert a.min() >= 45.0 and a.max() <= 150.0


def test_loops_are_made_even_and_an_odd_fixed_loop_is_named():
    tri = polygon([(0, 0), (3, 0), (0, 3)])
    fill, rep = pave_domain(tri, 1.5)
    assert rep.nodes_added == (0,)
    assert len(fill.lines) % 2 == 0
    with pytest.raises(ParityError, match=r"outer loop \(loop 0\) has 7 boundary nodes"):
        pave_domain(tri, 1.5, fixed_boundary=True)


def test_node_classes_follow_the_angle_thresholds_and_keep_row_ends_apart():
    assert node_classes([90, 134, 135, 180, 224, 225, 314, 315, 359]).tolist() == [0, 1, 1, 1, 1, 3, 3, 5, 5]
    # Two neighbouring row ends: the sharper one stays an end.
    assert node_classes([100, 80, 180, 180]).tolist() == [1, 0, 1, 1]
    # Wrap-around neighbours too.
    assert node_classes([80, 180, 180, 100]).tolist() == [0, 1, 1, 1]


def test_closure_templates():
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    q, centre = closure_quads(square, [0, 1, 2, 3])
    assert q.tolist() == [[0, 1, 2, 3]] and centre is None
    dart = np.array([[0.0, 0.0], [2.0, 0.0], [0.5, 0.5], [0.0, 2.0]])
    assert closure_quads(dart, [0, 1, 2, 3])[0] is None
    hexagon = np.column_stack([np.cos(np.arange(6) * np.pi / 3), np.sin(np.arange(6) * np.pi / 3)])
    q, centre = closure_quads(hexagon, np.arange(6))
    assert q is not None
    xy = hexagon if centre is None else np.vstack([hexagon, centre])
    assert all(_cross(xy[r[k - 1]], xy[r[k]], xy[r[(k + 1) % 4]]) > 0 for r in q.tolist() for k in range(4))
    area = sum(0.5 * float(_cross(xy[r[0]], xy[r[1]], xy[r[2]]) + _cross(xy[r[0]], xy[r[2]], xy[r[3]])) for r in q)
    assert area == pytest.approx(1.5 * np.sqrt(3.0))


def test_caps_are_errors_naming_the_stuck_front():
    with pytest.raises(MeshingError, match=r"outer loop \(loop 0\).*after 2 rounds"):
        pave_domain(circle(), 0.05, max_rounds=2)
    with pytest.raises(MeshingError, match="max_points = 200"):
        pave_domain(circle(), 0.05, max_points=200)


def test_registry_entry_and_the_door():
    m = QUAD_METHODS["paving"]
    assert m.needs_size and m.smooths and m.segments and m.points and m.regions
    # Area bounds of regions are refused by every quad method (markers are honoured).
    square = polygon([(0, 0), (1, 0), (1, 1), (0, 1)], regions=[(0.5, 0.5, 1, 0.01)])
    with pytest.raises(InputError, match="max_area"):
        quadrangulate(square, 0.1, method="paving")
    with pytest.raises(InputError, match="domain"):
        pave_domain("circle", 0.1)
    with pytest.raises(InputError, match="max_rounds"):
        pave_domain(circle(), 0.1, max_rounds=0)
    with pytest.raises(InputError, match="fixed_boundary"):
        pave_domain(circle(), 0.1, fixed_boundary="yes")
    stretched = BackgroundGrid.uniform(circle().bbox, 0.1, stretch=3.0, direction=0.5)
    with pytest.raises(InputError, match="stretched by up to 3"):
        quadrangulate(circle(), stretched, method="paving")


def test_smoothing_passes_keep_the_mesh_valid():
    mesh = quadrangulate(circles(), as_size_field(0.15), method="paving", smooth=3)
    _check_all_quad(mesh)


def test_row_kernel_grows_side_nodes_on_the_bisectors_and_merges_at_a_row_end():
    from meshwright.quad import _paving_kernel as pk

    # A regular 16-gon, counter-clockwise: every interior angle is 157.5 degrees, so each
    # side node grows one node towards the centre, d / sin(ang / 2) inside.
    n, radius, d = 16, 1.0, 0.1
    phi = 2.0 * np.pi * np.arange(n) / n
    p = np.column_stack([radius * np.cos(phi), radius * np.sin(phi)])
    f = np.arange(n, dtype=np.int64)
    ang = np.full(n, np.pi - 2.0 * np.pi / n)
    th0 = np.arctan2(*(np.roll(p, -1, axis=0) - p)[:, ::-1].T)
    m = np.ones(n, dtype=np.int64)
    ok, xy, quads, front, owner = pk.row_nodes(p, f, ang, m, np.full(n, d), th0, n)
    assert ok and len(xy) == n and len(quads) == n and owner.tolist() == list(range(n))
    expect = (radius - d / np.sin(0.5 * ang[0])) * np.column_stack([np.cos(phi), np.sin(phi)])
    assert np.allclose(xy, expect, atol=1e-12)
    assert front.tolist() == list(range(n, 2 * n))
    assert quads[0].tolist() == [0, 1, n + 1, n]
    every = np.vstack([p, xy])
    assert all(_cross(every[q[k]], every[q[(k + 1) % 4]], every[q[(k + 2) % 4]]) > 0 for q in quads for k in range(4))

    # Node 5 a row end: its neighbours' nodes merge into one, placed at the end's own
    # bisector point (d / sin(ang / 2), at most 1.5 d, inside); one quad closes over it.
    m[5] = 0
    ok, xy2, quads2, front2, owner2 = pk.row_nodes(p, f, ang, m, np.full(n, d), th0, n)
    assert ok and len(xy2) == n - 2 and len(quads2) == n - 1
    r_end = min(d / np.sin(0.5 * ang[5]), 1.5 * d)
    merged = int(np.flatnonzero(owner2 == 5)[0])
    assert np.allclose(xy2[merged], (radius - r_end) * np.array([np.cos(phi[5]), np.sin(phi[5])]), atol=1e-12)
    assert [4, 5, 6, n + merged] in quads2.tolist()
    # Two row ends side by side cannot be merged: the row degenerates.
    m[6] = 0
    assert not pk.row_nodes(p, f, ang, m, np.full(n, d), th0, n)[0]


def test_tuck_and_wedge_scan_follows_the_running_surplus():
    from meshwright.quad import _paving_kernel as pk

    n = 12
    m = np.ones(n, dtype=np.int64)
    deg = np.full(n, 180.0)
    floating = np.ones(n, dtype=bool)
    calm = np.zeros(n, dtype=bool)
    # Edges 0.5 of the size: the shortfall reaches -2 (past -1.6) at every fourth node,
    # where a tuck takes it back by 2 (ADJUST_GAP = 4 apart).
    t, w = pk.adjust_row(m, np.full(n, 0.5), calm, floating, deg, 4, 1.6, 179.5, 185.0)
    assert (t, w) == (0, 0)  # 180 degrees is not flatter than 179.5: no tuck allowed
    deg[:] = 170.0
    t, w = pk.adjust_row(m, np.full(n, 0.5), calm, floating, deg, 4, 1.6, 179.5, 185.0)
    assert (t, w) == (3, 0) and np.flatnonzero(m == 0).tolist() == [3, 7, 11]
    m[:] = 1
    deg[:] = 190.0
    t, w = pk.adjust_row(m, np.full(n, 1.5), calm, floating, deg, 4, 1.6, 179.5, 185.0)
    assert (t, w) == (0, 3) and np.flatnonzero(m == 3).tolist() == [3, 7, 11]
    # Marked nodes (a repaired row's calm_only) and fixed nodes take none.
    m[:] = 1
    calm[7] = True
    floating[3] = False
    t, w = pk.adjust_row(m, np.full(n, 1.5), calm, floating, deg, 4, 1.6, 179.5, 185.0)
    assert 3 not in np.flatnonzero(m == 3) and 7 not in np.flatnonzero(m == 3) and w >= 1


def test_star_whose_rows_left_a_tangled_void():
    """A random star (found by random examples): a seam merged away the node a joint had
    left on two paving boundaries, the other one closed over it, and a tangled four-node
    void was left (quadrangulate's cover check refused it).  The quads must cover the
    polygon: their exact areas sum to its exact area."""
    radii = [1.0, 0.53125, 0.5625, 0.6875, 1.0, 0.5234375, 1.0, 0.78125, 0.546875, 0.796875, 1.0, 0.75, 0.625, 0.75]
    t = np.linspace(0.0, 2.0 * np.pi, len(radii), endpoint=False)
    r = np.asarray(radii)
    dom = polygon(np.column_stack([r * np.cos(t), r * np.sin(t)]))
    mesh = quadrangulate(dom, 0.111328125, method="paving")
    _check_all_quad(mesh)
    xy = mesh.points
    twice = sum(_cross(xy[q[0]], xy[q[1]], xy[q[2]]) + _cross(xy[q[0]], xy[q[2]], xy[q[3]])
                for q in mesh.cells["quad"].tolist())
    lines = {a: b for a, b in mesh.cells["line"].tolist()}
    start = next(iter(lines))
    order, v = [start], lines[start]
    while v != start and len(order) <= len(lines):
        order.append(v)
        v = lines[v]
    assert len(order) == len(lines)
    origin = xy[order[0]]
    ring = sum(_cross(origin, xy[a], xy[b]) for a, b in zip(order[1:-1], order[2:]))
    assert twice == ring


def test_seam_keeps_a_node_another_paving_boundary_holds():
    """The seam rule behind the star's void: a seam merges its apex's next neighbour into
    the previous one; when another paving boundary holds that node (a joint's node), the
    seam is refused, since the other boundary would keep a node no quad has any more."""
    from meshwright.quad.paving import _Paver

    def paver():
        pv = _Paver(np.zeros((0, 2)), as_size_field(1.0), 10**6)
        pv.add_points(np.array([[9.0, 9.0], [2.0, -0.3], [0.0, 0.0], [2.0, 0.3], [4.0, 2.0],
                                [4.0, -2.0], [3.0, -3.0], [2.0, -4.0], [1.0, -3.0]]), 0)
        return pv

    # Apex 2 at 17 degrees (every other corner above 40); its neighbours 3 (previous)
    # and 1 (next, also on the other paving boundary).
    front = np.array([5, 4, 3, 2, 1], dtype=np.int64)
    other = np.array([1, 8, 7, 6], dtype=np.int64)
    alone = paver()
    assert alone.seam(front.copy(), [], 4).tolist() == [5, 4, 3] and alone.seams == 1  # alone, it is seamed
    pv = paver()
    kept = pv.seam(front.copy(), [other], 4)
    assert kept.tolist() == front.tolist() and pv.seams == 0
    assert pv.pts[1].tolist() == [2.0, -0.3]



@pytest.mark.parametrize(("r_in", "n", "closes"), [(0.2, 200, False), (0.97, 200, True), (0.2, 20, True)])
def test_stopped_region_is_bridged_only_when_it_may_close(r_in, n, closes, monkeypatch):
    """join_and_close builds the bridge of a stopped region to its holes only when the
    region may then be closed: few nodes, or thin with every chord as long as the outer
    boundary's diagonal (oracle: the ring's area and perimeter written out with math)."""
    import math

    import meshwright.quad.paving as pv_mod
    from meshwright.quad.paving import SPLIT_MAX, THIN, _Paver

    t = 2.0 * np.pi * np.arange(n) / n
    pv = _Paver(np.zeros((0, 2)), as_size_field(0.05), 10**6)
    outer = pv.add_points(np.column_stack([np.cos(t), np.sin(t)]), 0)
    hole = pv.add_points(r_in * np.column_stack([np.cos(-t), np.sin(-t)]), 0)
    chord = 2.0 * math.sin(math.pi / n)
    area = 0.5 * n * math.sin(2.0 * math.pi / n) * (1.0 - r_in**2)
    perimeter = n * chord * (1.0 + r_in) + 2.0 * 2.0 * math.sqrt(2.0)  # n % 4 == 0: the box is [-1, 1]^2
    expect = 2 * n + 2 <= SPLIT_MAX or area < THIN * perimeter * 0.05
    assert expect == closes
    assert pv._may_close([outer, hole]) == closes
    calls = []

    def spy(*a):
        calls.append(1)

    monkeypatch.setattr(pv_mod, "bridge", spy)
    left = pv.join_and_close([outer, hole], 1)
    assert len(calls) == (1 if closes else 0)
    assert len(left) == 2 and left[0] is outer and left[1] is hole


def _plain_polish(xy, quads, fixed, floor, rounds):
    """The cleanup's pattern search written out in plain Python (`math`): every pass
    recomputes every sine, every trial the whole star's minimum."""
    import math

    p = [list(map(float, v)) for v in xy]
    q = [list(map(int, c)) for c in quads]
    star = [[] for _ in p]
    for c, cell in enumerate(q):
        for v in cell:
            star[v].append(c)

    def sine(a, b, d, v, x, y):
        def at(w):
            return (x, y) if w == v else (p[w][0], p[w][1])

        (ax, ay), (bx, by), (dx, dy) = at(a), at(b), at(d)
        ux, uy, wx, wy = dx - bx, dy - by, ax - bx, ay - by
        den = math.sqrt((ux * ux + uy * uy) * (wx * wx + wy * wy))
        return (ux * wy - uy * wx) / den if den > 0.0 else -1.0

    def star_min(v, x, y):
        return min(sine(q[c][k - 1], q[c][k], q[c][(k + 1) % 4], v, x, y) for c in star[v] for k in range(4))

    def quad_min(c):
        return min(sine(q[c][k - 1], q[c][k], q[c][(k + 1) % 4], -1, 0.0, 0.0) for k in range(4))

    dirs = [(math.cos(i * math.pi / 8.0), math.sin(i * math.pi / 8.0)) for i in range(16)]
    for _ in range(rounds):
        nodes = sorted({v for c in range(len(q)) if quad_min(c) < floor for v in q[c] if not fixed[v]})
        moved = 0
        for v in nodes:
            x0, y0 = p[v]
            # np.hypot is the C library's, as in the kernel (math.hypot rounds otherwise).
            reach = min(float(np.hypot(p[w][0] - x0, p[w][1] - y0)) for c in star[v] for k in range(4) if q[c][k] == v
                        for w in (q[c][(k + 1) % 4], q[c][k - 1]))
            best, bx, by = star_min(v, x0, y0), x0, y0
            for s in (0.25, 0.125, 0.0625):
                for dx, dy in dirs:
                    x, y = x0 + s * reach * dx, y0 + s * reach * dy
                    w = star_min(v, x, y)
                    if w > best:
                        best, bx, by = w, x, y
            if (bx, by) != (x0, y0):
                p[v] = [bx, by]
                moved += 1
        if not moved:
            break
    return np.array(p)


@settings(max_examples=15, deadline=None)
@given(st.integers(0, 2**31 - 1))
def test_polish_matches_a_plain_pattern_search(seed):
    """The cleanup kernel (skips of nodes whose opposite corners are their worst, trials
    stopped at the first corner not above the best, per-quad minima updated around the
    moved nodes) makes the moves of the plain search that recomputes everything."""
    from meshwright.quad.polish import polish

    rng = np.random.default_rng(seed)
    k = 6
    gx, gy = np.meshgrid(np.arange(k + 1, dtype=np.float64), np.arange(k + 1, dtype=np.float64))
    xy = np.column_stack([gx.ravel(), gy.ravel()])
    inner = (xy[:, 0] > 0) & (xy[:, 0] < k) & (xy[:, 1] > 0) & (xy[:, 1] < k)
    xy[inner] += rng.uniform(-0.3, 0.3, size=(int(inner.sum()), 2))
    v = (np.arange(k)[None, :] + (k + 1) * np.arange(k)[:, None]).ravel()
    quads = np.column_stack([v, v + 1, v + k + 2, v + k + 1]).astype(np.int64)
    got = polish(xy, quads, ~inner, 0.95, 4)
    assert np.array_equal(got, _plain_polish(xy, quads, ~inner, 0.95, 4))
    assert np.array_equal(xy[~inner], got[~inner])


def test_row_geometry_kernels_against_plain_formulas():
    """Angles, classes, depth, provisional edges, bisectors and seam candidates of a
    random star-shaped paving boundary, against the chapter's formulas written out with
    `math` per node (floating point: equal to a few ulps)."""
    import math

    from meshwright.quad import _paving_row as pr

    rng = np.random.default_rng(7)
    n = 40
    t = np.sort(rng.uniform(0.0, 2.0 * np.pi, n))
    r = rng.uniform(0.5, 1.0, n)
    p = np.column_stack([r * np.cos(t), r * np.sin(t)])
    h = rng.uniform(0.05, 0.2, n)
    scale = rng.choice([1.0, 0.7], n)
    ang, deg, m, depth, th0, mid, plen = pr.row_prepare(p, h, scale, 135.0, 225.0, 315.0)
    want_ang, want_th, le = [], [], []
    for i in range(n):
        (x, y), (xn, yn), (xp, yp) = p[i], p[(i + 1) % n], p[i - 1]
        a = math.atan2((xn - x) * (yp - y) - (yn - y) * (xp - x), (xn - x) * (xp - x) + (yn - y) * (yp - y))
        want_ang.append(a + 2.0 * math.pi if a <= 0.0 else a)
        want_th.append(math.atan2(yn - y, xn - x))
        le.append(math.dist(p[i], p[(i + 1) % n]))
    assert np.allclose(ang, want_ang, rtol=0, atol=1e-12) and np.allclose(th0, want_th, rtol=0, atol=1e-12)
    assert np.allclose(deg, np.degrees(want_ang), rtol=1e-13)
    d = [min(max(h[i], 0.25 * (le[i] + le[i - 1])), le[i] + le[i - 1]) for i in range(n)]
    want_depth = [0.25 * (d[i - 1] + 2.0 * d[i] + d[(i + 1) % n]) * scale[i] for i in range(n)]
    assert np.allclose(depth, want_depth, rtol=1e-13)
    prov = []
    for i in range(n):
        th, dist = want_th[i] + 0.5 * want_ang[i], want_depth[i] / max(math.sin(0.5 * want_ang[i]), 0.5)
        prov.append((p[i, 0] + dist * math.cos(th), p[i, 1] + dist * math.sin(th)))
    for i in range(n):
        a, b = prov[i], prov[(i + 1) % n]
        assert math.isclose(plen[i], math.dist(a, b), rel_tol=1e-12)
        assert np.allclose(mid[i], [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])], rtol=0, atol=1e-12)
    # Classes: thresholds, and no two neighbouring row ends (the sharper one stays).
    want_m = np.select([deg < 135.0, deg < 225.0, deg < 315.0], [0, 1, 3], 5)
    assert ((m == want_m) | ((want_m == 0) & (m == 1))).all()
    assert not any(m[i] == 0 and m[(i + 1) % n] == 0 for i in range(n))
    for i in np.flatnonzero((want_m == 0) & (m == 1)):
        assert m[i - 1] == 0 and deg[i - 1] <= deg[i] or m[(i + 1) % n] == 0 and deg[(i + 1) % n] <= deg[i]
    # Bisectors of two boundaries at once, and the seam candidates (floating nodes only).
    ids = np.concatenate([np.arange(n), np.arange(n)[::-1]]).astype(np.int64)
    nrm = pr.front_bisectors(p, ids, np.array([0, n, 2 * n], dtype=np.int64))
    assert np.allclose(nrm[:n], np.column_stack([np.cos(np.add(want_th, 0.5 * np.array(want_ang))),
                                                 np.sin(np.add(want_th, 0.5 * np.array(want_ang)))]), atol=1e-12)
    assert np.allclose(np.hypot(*nrm.T), 1.0)
    sharp = pr.sharp_nodes(p, np.arange(n, dtype=np.int64), 10, 100.0)
    want = sorted((i for i in range(10, n) if deg[i] < 100.0), key=lambda i: deg[i])
    assert sharp.tolist() == want


def test_row_finish_relaxes_along_the_row_and_refuses_odd_rows():
    from meshwright.quad import _paving_row as pr

    rng = np.random.default_rng(3)
    k, n0 = 10, 100
    phi = 2.0 * np.pi * np.arange(k) / k + rng.uniform(-0.1, 0.1, k)
    xy = np.column_stack([np.cos(phi), np.sin(phi)])
    quads = np.array([[0, 1, n0 + 1, n0]], dtype=np.int64)
    front = np.repeat(np.arange(n0, n0 + k, dtype=np.int64), [1, 2] * (k // 2))  # repeats dropped
    got = xy.copy()
    f = pr.row_finish(got, quads, front, n0, 1)
    assert f.tolist() == list(range(n0, n0 + k))
    for i in range(k):
        prev, nxt = xy[i - 1], xy[(i + 1) % k]
        tan = (nxt - prev) / np.linalg.norm(nxt - prev)
        lap = 0.25 * (prev + nxt - 2.0 * xy[i])
        assert np.allclose(got[i], xy[i] + np.dot(lap, tan) * tan, atol=1e-14)
    assert pr.row_finish(xy.copy(), quads, front[:-1][front[:-1] != n0 + k - 1], n0, 1) is None  # odd count
    assert pr.row_finish(xy.copy(), np.array([[0, 1, 1, n0]], dtype=np.int64), front, n0, 1) is None


@settings(max_examples=60, deadline=None)
@given(st.lists(st.lists(st.integers(0, 6), min_size=1, max_size=6), min_size=1, max_size=3))
def test_edges_once_against_a_set_of_directed_edges(fronts):
    from meshwright.quad._paving_close import consistent

    edges = [(f[i], f[(i + 1) % len(f)]) for f in fronts for i in range(len(f))]
    want = all(a != b for a, b in edges) and len(set(edges)) == len(edges)
    assert consistent([np.array(f, dtype=np.int64) for f in fronts]) == want


def _plain_grid_value(pts, tris, delta, x, y):
    """Linear interpolation of ``delta`` at (x, y) in the triangle that holds it, found
    by exact ``Fraction`` orientations over every triangle; None outside them all."""
    fx, fy = Fraction(float(x)), Fraction(float(y))
    for t in tris.tolist():
        a, b, c = (tuple(Fraction(float(v)) for v in pts[i]) for i in t)
        area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
        w = [
            ((q[0] - fx) * (r[1] - fy) - (q[1] - fy) * (r[0] - fx)) / area
            for q, r in ((b, c), (c, a), (a, b))
        ]
        if min(w) >= 0:
            return float(sum(wi * Fraction(float(delta[i])) for wi, i in zip(w, t)))
    return None


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_walk_spacing_matches_exact_interpolation(seed):
    """The void fill's walking interpolation of a background grid (a jittered grid with
    a hole, so that walks leave it and fall back to the bucket scan) against exact
    rational barycentric interpolation in the triangle found by testing every one."""
    from meshwright.quad._paving_kernel import walk_spacing

    rng = np.random.default_rng(seed)
    k = 8
    gx, gy = np.meshgrid(np.arange(k + 1, dtype=np.float64), np.arange(k + 1, dtype=np.float64))
    pts = np.column_stack([gx.ravel(), gy.ravel()])
    inner = (pts[:, 0] > 0) & (pts[:, 0] < k) & (pts[:, 1] > 0) & (pts[:, 1] < k)
    pts[inner] += rng.uniform(-0.25, 0.25, size=(int(inner.sum()), 2))
    tris = []
    for j in range(k):
        for i in range(k):
            if 3 <= i <= 4 and 2 <= j <= 5:
                continue  # the hole
            v = j * (k + 1) + i
            tris += [(v, v + 1, v + k + 2), (v, v + k + 2, v + k + 1)]
    tris = np.array(tris, dtype=np.int64)
    delta = rng.uniform(0.1, 2.0, size=len(pts))
    grid = BackgroundGrid(pts, tris, delta)
    # A front-like sequence: short steps, and jumps across the hole.
    walk = np.cumsum(rng.uniform(-0.4, 0.4, size=(150, 2)), axis=0) % k
    jumps = rng.uniform(0.0, k, size=(50, 2))
    xy = np.concatenate([walk, jumps, walk[::-1]])
    want = [_plain_grid_value(pts, tris, delta, x, y) for x, y in xy.tolist()]
    keep = np.array([w is not None for w in want])
    assert keep.sum() > 250
    got = walk_spacing(*grid.kernel_args(), np.zeros(1, dtype=np.int64), np.ascontiguousarray(xy[keep]))
    assert np.allclose(got, np.array([w for w in want if w is not None]), rtol=1e-12, atol=0.0)


def test_serpentine_order_of_size_queries():
    """The void fill's size queries are asked along the rows of a 16 x 16 grid of their
    box, every other row backwards, in input order within a cell (cells recomputed
    here with plain floor division, one point at a time)."""
    from meshwright.quad._paving_close import serpentine

    rng = np.random.default_rng(3)
    xy = np.concatenate([rng.uniform(-2.0, 5.0, size=(300, 2)), [[-2.0, -2.0], [5.0, 5.0]]])
    xy[::7] = xy[3]  # repeats: ties keep their input order
    order = serpentine(xy)
    assert sorted(order.tolist()) == list(range(len(xy)))
    lo, ext = xy.min(axis=0), float((xy.max(axis=0) - xy.min(axis=0)).max())
    keys = []
    for i in order.tolist():
        cx, cy = (min(int(16 * ((float(xy[i, d]) - float(lo[d])) / ext)), 15) for d in (0, 1))
        keys.append((cy * 16 + (cx if cy % 2 == 0 else 15 - cx), i))
    assert keys == sorted(keys)
    assert serpentine(np.zeros((1, 2))).tolist() == [0] and serpentine(np.ones((3, 2))).tolist() == [0, 1, 2]


def _closed_segments_meet(p, q, r, s) -> bool:
    """Exact: closed segments p q and r s share a point."""
    def side(a, b, c):
        v = _cross(a, b, c)
        return (v > 0) - (v < 0)

    def on(a, b, c):
        return min(a[0], b[0]) <= c[0] <= max(a[0], b[0]) and min(a[1], b[1]) <= c[1] <= max(a[1], b[1])

    o1, o2, o3, o4 = side(p, q, r), side(p, q, s), side(r, s, p), side(r, s, q)
    if o1 * o2 < 0 and o3 * o4 < 0:
        return True
    return any(o == 0 and on(a, b, c) for o, a, b, c in ((o1, p, q, r), (o2, p, q, s), (o3, r, s, p), (o4, r, s, q)))


@pytest.mark.parametrize("seed", range(6))
def test_grid_crossings_against_exact_segment_tests(seed):
    """The row check's grid search of meeting segments on lattice points (collinear
    overlaps, touching ends, a node on another segment, zero-length boxes) with a few
    segments across the whole box (the grid's list of long segments): each query meets
    a segment sharing no end node with it exactly when ``Fraction`` tests say so."""
    from meshwright.quad._paving_grid import grid_crossings

    rng = np.random.default_rng(seed)
    pts = np.unique(rng.integers(0, 40, size=(200, 2)), axis=0).astype(np.float64)
    if seed % 2:
        pts = pts * 0.1 + 0.3  # coordinates that do not fall on the cells' edges
    n = len(pts)
    near = [(i, j) for i in range(n) for j in range(i + 1, n) if np.abs(pts[i] - pts[j]).max() <= 3.0]
    pick = rng.choice(len(near), size=50, replace=False)
    seg = [near[k] for k in pick] + [tuple(rng.choice(n, 2, replace=False)) for _ in range(3 + seed)]
    seg = np.array(seg, dtype=np.int64)
    queries = seg[rng.permutation(len(seg))[:40]]
    got = grid_crossings(pts, queries[:, 0].copy(), queries[:, 1].copy(), seg[:, 0].copy(), seg[:, 1].copy())
    want = [
        any(not ({a, b} & {u, w}) and _closed_segments_meet(pts[a], pts[b], pts[u], pts[w]) for u, w in seg.tolist())
        for a, b in queries.tolist()
    ]
    assert 0 < sum(want) < len(want)
    assert got.tolist() == want


@pytest.mark.parametrize("seed", range(9))
def test_check_row_against_exact_segment_and_containment_tests(seed):
    """Step 7's kernel on rows of random depths (crossings, folded quads) grown from a
    random star-shaped paving boundary around a small hole's: the paving nodes it
    refuses are those of the written rule, every test exact with ``Fraction``s over
    every pair of edges and every node."""
    from meshwright.quad import _paving_kernel as pk

    rng = np.random.default_rng(seed)
    n = 24
    phi = np.sort(rng.uniform(0.0, 2.0 * np.pi, n))
    phi = 2.0 * np.pi * (np.arange(n) + rng.uniform(-0.2, 0.2, n)) / n if seed % 3 == 0 else phi
    outer = np.column_stack([np.cos(phi), np.sin(phi)]) * rng.uniform(0.99 - 0.04 * (seed % 3), 1.01 + 0.04 * (seed % 3), size=(n, 1))
    c = rng.uniform(-0.4, 0.4, 2)
    psi = -np.arange(6) * (np.pi / 3.0)  # clockwise: a hole's paving boundary
    hole = c + rng.uniform(0.1, 0.3) * np.column_stack([np.cos(psi), np.sin(psi)])
    pts0 = np.vstack([outer, hole])
    f = np.arange(n, dtype=np.int64)
    g = np.arange(n, n + 6, dtype=np.int64)
    nxt, prv = np.roll(outer, -1, axis=0) - outer, np.roll(outer, 1, axis=0) - outer
    th0 = np.arctan2(nxt[:, 1], nxt[:, 0])
    ang = np.mod(np.arctan2(prv[:, 1], prv[:, 0]) - th0, 2.0 * np.pi)
    m = node_classes(np.degrees(ang))
    depth = rng.uniform(0.02, (0.08, 0.2, 0.6)[seed % 3], n)  # clean rows to folded ones
    n_old = len(pts0)
    ok, xy, quads, _, owner = pk.row_nodes(outer, f, ang, m, depth, th0, n_old)
    if not ok:
        return
    pts = np.vstack([pts0, xy])
    sa = np.concatenate([f, g])
    sb = np.concatenate([np.roll(f, -1), np.roll(g, -1)])
    bad = pk.check_row(pts, f, quads, owner, np.int64(n_old), sa, sb, np.concatenate([f, g]))

    new_edges = [(int(q[k]), int(q[(k + 1) % 4])) for q in quads for k in range(4)
                 if q[k] >= n_old or q[(k + 1) % 4] >= n_old]
    edges = list(zip(sa.tolist(), sb.tolist())) + new_edges
    hit = set()
    for a, b in new_edges:
        if any(len({a, b, u, w}) == 4 and _closed_segments_meet(pts[a], pts[b], pts[u], pts[w]) for u, w in edges):
            hit |= {a, b}
    for q in quads.tolist():
        folded = any(_cross(pts[q[k - 1]], pts[q[k]], pts[q[(k + 1) % 4]]) <= 0 for k in range(4))
        holds = any(v not in q and all(_cross(pts[q[k]], pts[q[(k + 1) % 4]], pts[v]) >= 0 for k in range(4))
                    for v in range(n_old))
        if folded or holds:
            hit |= set(q)
    want = np.zeros(n, dtype=bool)
    for v in hit:
        if v >= n_old:
            want[owner[v - n_old]] = True
        elif v < n:
            want[v] = True
    assert np.array_equal(bad, want)
