"""Cross-check against Shewchuk's Triangle (the ``triangle`` package, an independent reference).

* The constrained Delaunay triangulation of a planar straight-line graph in general position
  is unique, so meshwright's ``cdt_build`` must give exactly Triangle's ``pc`` edge set, and
  the exterior removal of ``classify()`` (Triangle's convention without segment sides) exactly
  Triangle's ``p`` triangles.
* Refinement: ``triangulate(polygon, min_angle=q, max_area=A)`` must meet the guarantees
  Triangle's ``pq<q>a<A>`` meets (checked on both): every angle at least q (q <= 20.7, input
  angles all >= 60 degrees), every triangle inside the polygon and the polygon covered, every
  polygon side a union of mesh edges, every area at most A.

The random inputs are seeded; general position is certified with exact rationals.
"""

from fractions import Fraction

import numpy as np
import pytest

from meshwright import triangulate
from meshwright.tri.cdt import cdt_build

triangle = pytest.importorskip("triangle")


# ------------------------------------------------------------------------------ exact helpers
def _orient(p, q, r):
    """Sign of the exact orientation of three float points (rationals, shares no code)."""
    px, py, qx, qy, rx, ry = (Fraction(float(c)) for c in (*p, *q, *r))
    d = (qx - px) * (ry - py) - (qy - py) * (rx - px)
    return (d > 0) - (d < 0)


def _segments_meet(a, b, c, d):
    """Whether closed segments ab and cd share a point (exact)."""
    o1, o2, o3, o4 = _orient(a, b, c), _orient(a, b, d), _orient(c, d, a), _orient(c, d, b)
    if o1 * o2 < 0 and o3 * o4 < 0:
        return True

    def on(p, q, r):  # r on closed segment pq, given collinear
        return min(p[0], q[0]) <= r[0] <= max(p[0], q[0]) and min(p[1], q[1]) <= r[1] <= max(p[1], q[1])

    return (
        (o1 == 0 and on(a, b, c)) or (o2 == 0 and on(a, b, d)) or (o3 == 0 and on(c, d, a)) or (o4 == 0 and on(c, d, b))
    )


def _add_segments(pts, seg, rng, tries, max_len):
    """Greedily add random segments that meet no segment and no point except at their ends."""
    seg = [tuple(s) for s in seg]
    n = len(pts)
    for _ in range(tries):
        i, j = (int(v) for v in rng.integers(0, n, 2))
        if i == j or np.hypot(*(pts[i] - pts[j])) > max_len:
            continue
        ok = all(
            not _segments_meet(pts[i], pts[j], pts[a], pts[b])
            for a, b in seg
            if len({i, j, a, b}) == 4
        ) and all(
            # Sharing an end is allowed, overlapping is not.
            _orient(pts[i], pts[j], pts[b if a in (i, j) else a]) != 0
            for a, b in seg
            if len({i, j, a, b}) == 3
        )
        # No point in the segment's interior (it would split it).
        ok = ok and not any(k not in (i, j) and _segments_meet(pts[i], pts[j], pts[k], pts[k]) for k in range(n))
        if ok:
            seg.append((i, j))
    return np.array(seg, dtype=np.int64).reshape(-1, 2)


def _star_polygon(rng, k, min_angle_deg):
    """A random star-shaped polygon (ccw) whose interior angles are all at least ``min_angle_deg``."""
    while True:
        theta = 2 * np.pi * (np.arange(k) + rng.uniform(-0.25, 0.25, k)) / k
        r = rng.uniform(0.6, 1.0, k)
        poly = np.column_stack([r * np.cos(theta), r * np.sin(theta)])
        if _interior_angles(poly).min() >= min_angle_deg:
            return poly


def _interior_angles(poly):
    """Interior angles in degrees of a counter-clockwise polygon (reflex ones above 180)."""
    prev, nxt = np.roll(poly, 1, axis=0) - poly, np.roll(poly, -1, axis=0) - poly
    a = np.arctan2(prev[:, 1], prev[:, 0]) - np.arctan2(nxt[:, 1], nxt[:, 0])
    return np.degrees(np.mod(a, 2 * np.pi))


def _edges(tris):
    t = np.asarray(tris, dtype=np.int64)
    e = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    return {(min(a, b), max(a, b)) for a, b in e.tolist()}


def _tri_set(tris):
    return {tuple(sorted(t)) for t in np.asarray(tris).tolist()}


# ------------------------------------------------------------------------------ the CDT
def _random_pslg(seed):
    """Boundary polygon, points inside and outside it, random non-crossing chords."""
    rng = np.random.default_rng(seed)
    k = int(rng.integers(8, 20))
    poly = _star_polygon(rng, k, 0.0)
    gap = np.max(np.diff(np.concatenate([np.sort(np.arctan2(poly[:, 1], poly[:, 0])), [np.inf]]))[:-1])
    inner_r = 0.6 * np.cos(min(np.pi / 3, 2 * np.pi / k + gap) / 2)
    m = int(rng.integers(5, 40))
    rad, ang = inner_r * np.sqrt(rng.random(m)), 2 * np.pi * rng.random(m)
    inside = np.column_stack([rad * np.cos(ang), rad * np.sin(ang)])
    outside = rng.uniform(1.05, 1.4, (6, 1)) * np.column_stack([np.cos(a := 2 * np.pi * rng.random(6)), np.sin(a)])
    pts = np.vstack([poly, inside, outside])
    loop = np.column_stack([np.arange(k), (np.arange(k) + 1) % k])
    seg = _add_segments(pts, loop, rng, tries=3 * m, max_len=0.5)
    return pts, seg, k


@pytest.mark.parametrize("seed", range(12))
def test_cdt_edges_equal_triangle_p(seed):
    pts, seg, _ = _random_pslg(seed)
    ct = cdt_build(pts, seg)
    assert np.array_equal(ct.index_map, np.arange(len(pts)))
    ref = triangle.triangulate({"vertices": pts, "segments": seg}, "pcQ")
    assert len(ref["vertices"]) == len(pts)  # no Steiner points: the PSLG is proper
    ours = _edges(ct.triangles(inside=False))
    assert ours == _edges(ref["triangles"])
    assert {(min(a, b), max(a, b)) for a, b in seg.tolist()} <= ours
    # Exterior removal from the hull inwards (Triangle's convention, no segment sides).
    ct.classify()
    eaten = triangle.triangulate({"vertices": pts, "segments": seg}, "pQ")
    assert len(eaten["triangles"]) > 0
    assert _tri_set(ct.triangles()) == _tri_set(eaten["triangles"])


# ------------------------------------------------------------------------------ refinement
def _angles_deg(p):
    a, b, c = p[:, 0], p[:, 1], p[:, 2]

    def ang(u, v, w):  # angle at u
        x, y = v - u, w - u
        return np.degrees(np.arctan2(np.abs(x[:, 0] * y[:, 1] - x[:, 1] * y[:, 0]), (x * y).sum(axis=1)))

    return np.stack([ang(a, b, c), ang(b, c, a), ang(c, a, b)], axis=1)


def _cross(u, v):
    return u[0] * v[1] - u[1] * v[0]


def _check_guarantees(points, tris, poly, q, max_area):
    """Triangle's guarantees for a refined mesh of the simple polygon ``poly`` (ccw)."""
    p = points[np.asarray(tris)]
    e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    area = 0.5 * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    assert np.all(area > 0)
    assert area.max() <= max_area * (1 + 1e-12)
    assert _angles_deg(p).min() >= q - 1e-9
    # Inside and covering: centroids inside the polygon, the areas add up to the polygon's.
    cen = p.mean(axis=1)
    nxt = np.roll(poly, -1, axis=0)
    crossings = np.zeros(len(cen), dtype=int)
    for (x0, y0), (x1, y1) in zip(poly, nxt):
        straddle = (y0 > cen[:, 1]) != (y1 > cen[:, 1])
        with np.errstate(divide="ignore", invalid="ignore"):
            xs = x0 + (cen[:, 1] - y0) * (x1 - x0) / (y1 - y0)
        crossings += straddle & (xs > cen[:, 0])
    assert np.all(crossings % 2 == 1)
    poly_area = 0.5 * np.sum(poly[:, 0] * nxt[:, 1] - nxt[:, 0] * poly[:, 1])
    assert np.isclose(area.sum(), poly_area, rtol=1e-12)
    # Boundary: the edges of one triangle only lie on the polygon's sides and chain each side.
    t = np.asarray(tris, dtype=np.int64)
    half = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    key = {tuple(h) for h in half.tolist()}
    boundary = [(a, b) for a, b in half.tolist() if (b, a) not in key]
    covered = np.zeros(len(poly))
    for a, b in boundary:
        pa, pb = points[a], points[b]
        dist = [
            max(abs(_cross(s1 - s0, pa - s0)), abs(_cross(s1 - s0, pb - s0))) / np.hypot(*(s1 - s0))
            for s0, s1 in zip(poly, nxt)
        ]
        side = int(np.argmin(dist))
        assert dist[side] <= 1e-12
        d = nxt[side] - poly[side]
        assert np.dot(pb - pa, d) > 0  # runs along the side, inside on its left
        covered[side] += np.hypot(*(pb - pa))
    assert np.allclose(covered, np.hypot(*(nxt - poly).T), rtol=1e-12)
    for corner in poly:  # the corners are mesh vertices
        assert np.min(np.hypot(*(points - corner).T)) == 0.0


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("q", [15.0, 20.7])
def test_refinement_meets_triangles_guarantees(seed, q):
    rng = np.random.default_rng(100 + seed)
    poly = _star_polygon(rng, int(rng.integers(6, 14)), 60.0)
    max_area = float(rng.uniform(0.004, 0.03))
    mesh = triangulate(poly, min_angle=q, max_area=max_area, seed=seed)
    tris = mesh.cells["triangle"]
    _check_guarantees(mesh.points, tris, poly, q, max_area)
    # The mesh's line cells are exactly its boundary edges.
    lines = {tuple(sorted(e)) for e in mesh.cells["line"].tolist()}
    t = np.asarray(tris, dtype=np.int64)
    half = {tuple(h) for h in np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]).tolist()}
    once = {tuple(sorted(h)) for h in half if h[::-1] not in half}
    assert lines == once
    # The reference meets the same checks (so they are not vacuous), and sizes are comparable.
    seg = np.column_stack([np.arange(len(poly)), (np.arange(len(poly)) + 1) % len(poly)])
    ref = triangle.triangulate({"vertices": poly, "segments": seg}, f"pq{q}a{max_area!r}Q")
    _check_guarantees(ref["vertices"], ref["triangles"], poly, q, max_area)
    ratio = len(tris) / len(ref["triangles"])
    assert 0.5 < ratio < 2.0
