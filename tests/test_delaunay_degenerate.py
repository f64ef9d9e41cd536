"""2-D Delaunay builds on the inputs the cheap exact stages serve, checked in exact rationals.

Grids (every in-circle test of a cell is exactly zero), rounded points on a circle (every
test near-degenerate), grids moved by one ulp, points of an integer circle.  The oracle is
Fraction arithmetic only: every triangle strictly counter-clockwise, no vertex strictly
inside the circumcircle of a triangle across an edge (exact zeros allowed: cocircular
points), and the triangle count of a triangulation of the convex hull.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from meshwright.tri.triangulation import delaunay


def _orient(p, q, r) -> Fraction:
    return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])


def _incircle(a, b, c, d) -> Fraction:
    rows = [(p[0] - d[0], p[1] - d[1]) for p in (a, b, c)]
    lift = [x * x + y * y for x, y in rows]
    (ax, ay), (bx, by), (cx, cy) = rows
    return lift[0] * (bx * cy - cx * by) + lift[1] * (cx * ay - ax * cy) + lift[2] * (ax * by - bx * ay)


def _hull_size(q) -> int:
    """Convex hull vertex count, collinear hull points included (monotone chain, exact)."""
    pts = sorted(set(q))
    if len(pts) < 3:
        return len(pts)

    def chain(seq):
        out = []
        for p in seq:
            while len(out) >= 2 and _orient(out[-2], out[-1], p) < 0:
                out.pop()
            out.append(p)
        return out

    return len(chain(pts)) + len(chain(pts[::-1])) - 2


def check_exact_delaunay(pts: np.ndarray, algorithm: str) -> None:
    tr = delaunay(pts, algorithm=algorithm)
    q = [(Fraction(float(x)), Fraction(float(y))) for x, y in tr.points]
    tris = tr.triangles
    nbrs = tr.neighbors
    for t, (a, b, c) in enumerate(tris):
        assert _orient(q[a], q[b], q[c]) > 0, f"triangle {t} not ccw"
        for k in range(3):
            n = nbrs[t, k]
            if n < 0:
                continue
            d = [v for v in tris[n] if v not in (a, b, c)]
            assert len(d) == 1
            assert _incircle(q[a], q[b], q[c], q[d[0]]) <= 0, f"vertex {d[0]} inside triangle {t}'s circle"
    assert len(tris) == 2 * len(q) - _hull_size(q) - 2


@pytest.mark.parametrize("algorithm", ["bowyer", "watson"])
@pytest.mark.parametrize("scale", [1.0, 2.0**-20, 3.0])
def test_grid(algorithm, scale):
    x, y = np.meshgrid(np.arange(23.0), np.arange(17.0))
    check_exact_delaunay(np.column_stack([x.ravel(), y.ravel()]) * scale, algorithm)


@pytest.mark.parametrize("algorithm", ["bowyer", "watson"])
def test_rounded_circle(algorithm):
    t = 2.0 * np.pi * np.arange(300) / 300
    check_exact_delaunay(np.column_stack([np.cos(t), np.sin(t)]), algorithm)


@pytest.mark.parametrize("seed", range(3))
def test_grid_moved_by_one_ulp(seed):
    rng = np.random.default_rng(seed)
    x, y = np.meshgrid(np.arange(15.0), np.arange(15.0))
    pts = np.column_stack([x.ravel(), y.ravel()]) + 100.0
    pick = rng.random(pts.shape) < 0.2
    pts[pick] = np.nextafter(pts[pick], np.where(rng.random(pick.sum()) < 0.5, np.inf, -np.inf))
    check_exact_delaunay(pts, "bowyer")


def test_integer_circle_and_grid_mix():
    # All integer points with x**2 + y**2 == 25**2 (exactly cocircular) plus a grid inside.
    ring = [(x, y) for x in range(-25, 26) for y in range(-25, 26) if x * x + y * y == 625]
    inner = [(x, y) for x in range(-10, 11, 2) for y in range(-10, 11, 2)]
    check_exact_delaunay(np.array(ring + inner, dtype=float), "bowyer")
