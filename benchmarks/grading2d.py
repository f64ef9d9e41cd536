"""Benchmark: quality where the boundary is finer than the size (issue 13), against Gmsh.

Usage::

    python benchmarks/grading2d.py             # every case, every method, Gmsh both ways
    python benchmarks/grading2d.py --quick     # the 30 holes only
    python benchmarks/grading2d.py --no-grading  # meshwright with grading=None as well
    python benchmarks/grading2d.py --no-relax    # the relaxing methods with relax=False as well
    python benchmarks/grading2d.py --grading 1.2  # meshwright at grading=1.2 as well (repeatable)

Cases (domains whose given boundary points lie closer than the size; every method and Gmsh
get the same boundary points, the domain discretised at that size):

* ``holes30``: the unit square with 30 polygonal holes of radius 0.02-0.045, their vertices
  ``size / 5`` apart, size 0.05;
* ``radii``: the unit square with 12 holes of radius 0.01-0.12, vertex spacing from
  ``size / 8`` to ``size / 2``, size 0.06;
* ``naca``: a NACA 0012 polygon of 241 cosine-spaced vertices (1.7e-4 chord apart at the
  leading edge, 0.013 mid-chord, the trailing edge 0.0025 thick) in a box 6 x 4 chords,
  size 0.25;
* ``slit``: the unit square with a slit 0.6 long and 0.01 wide cut in from its left side,
  the slit's sides split every 0.01, size 0.05.

meshwright runs ``triangulate(domain, size, method=m)`` with the method's default grading
(``grading="auto"``: 1.1 for ``front`` and ``frontal-delaunay``, which relax here, 1.2 for ``weatherill``, none
for ``delaunay``; :data:`meshwright.tri.mesher.MESH_METHODS`), with ``--grading G`` also at
``grading=G`` and, with ``--no-grading``, also ``grading=None``; with ``--no-relax``,
the methods that relax by default (:mod:`meshwright.tri.relax`) also with ``relax=False``
at the relaxed default's grading.  Gmsh 4 runs
Frontal-Delaunay (``Mesh.Algorithm`` 6, one thread) on the same boundary points (one
Gmsh line per segment, mesh size ``size`` at every point, ``Mesh.MeshSizeMax`` = size), with
``Mesh.MeshSizeExtendFromBoundary`` 1 (its default: sizes interpolated from the boundary
mesh into the surface) and 0 (the size alone).  Reported: % of triangles under 20 degrees,
minimum angle, mean radius ratio 2r/R, triangles, time (best of ``--repeat``, after a JIT
warm-up).
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from _harness import best_time, gmsh_plane_surface, print_table


def _holes(centres, radii, spacing):
    out = []
    for c, r, h in zip(centres, radii, spacing):
        k = max(6, round(2.0 * math.pi * r / h))
        t = np.linspace(0.0, 2.0 * math.pi, k, endpoint=False)
        out.append(np.asarray(c) + r * np.column_stack([np.cos(t), np.sin(t)]))
    return out


def _scatter(n, rmin, rmax, gap, seed):
    """``n`` disjoint discs in the unit square (seeded rejection sampling)."""
    rng = np.random.default_rng(seed)
    cs, rs = [], []
    for _ in range(100_000):
        if len(cs) == n:
            break
        r = rng.uniform(rmin, rmax)
        c = rng.uniform(r + gap, 1.0 - r - gap, 2)
        if all(np.hypot(*(c - d)) > r + e + gap for d, e in zip(cs, rs)):
            cs.append(c)
            rs.append(r)
    return np.array(cs), np.array(rs)


def naca0012_polygon(k: int) -> np.ndarray:
    """NACA 0012 (unit chord, the standard open trailing edge 0.0025 thick, closed by a
    vertical segment) with ``k`` cosine-spaced segments on each side, counter-clockwise."""
    x = 0.5 * (1.0 - np.cos(np.linspace(0.0, math.pi, k + 1)))
    y = 0.6 * (0.2969 * np.sqrt(x) - 0.1260 * x - 0.3516 * x**2 + 0.2843 * x**3 - 0.1015 * x**4)
    lower = np.column_stack([x, -y])
    upper = np.column_stack([x[::-1], y[::-1]])[:-1]
    return np.concatenate([lower, upper])


def case(name: str):
    """(domain, size) of a case (module docstring)."""
    from meshwright.geometry import polygon

    square = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
    if name == "holes30":
        cs, rs = _scatter(30, 0.02, 0.045, 0.04, 1)
        return polygon(square, _holes(cs, rs, np.full(len(rs), 0.01))), 0.05
    if name == "radii":
        cs, rs = _scatter(12, 0.01, 0.12, 0.05, 2)
        spacing = 0.06 / np.linspace(2.0, 8.0, len(rs))
        return polygon(square, _holes(cs, rs, spacing)), 0.06
    if name == "naca":
        wing = naca0012_polygon(120)
        box = [(-2.5, -2.0), (3.5, -2.0), (3.5, 2.0), (-2.5, 2.0)]
        return polygon(box, [wing]), 0.25
    if name == "slit":
        y0, y1, x1 = 0.495, 0.505, 0.6
        xs = np.linspace(0.0, x1, 61)
        outer = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
        outer += [(0.0, y1)] + [(x, y1) for x in xs[1:]] + [(x, y0) for x in xs[::-1][:-1]] + [(0.0, y0)]
        return polygon(outer), 0.05
    raise ValueError(name)


CASES = ("holes30", "radii", "naca", "slit")


def measure(points, triangles) -> dict:
    from meshwright.core.quality import triangle_quality

    q = triangle_quality(np.asarray(points, dtype=np.float64), np.asarray(triangles))
    a = q["min_angle"]
    return {"under20": 100.0 * float(np.mean(a < 20.0)), "min_angle": float(a.min()),
            "rr_mean": float(q["radius_ratio"].mean()), "n": len(a)}


def run_gmsh(points, segments, size: float, extend: int):
    """Gmsh Frontal-Delaunay on the given boundary points (module docstring)."""
    import gmsh

    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.option.setNumber("Mesh.Algorithm", 6)
        gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", extend)
        gmsh.model.add("grading")
        gmsh_plane_surface(gmsh, points, segments, np.full(len(points), size))
        gmsh.model.mesh.generate(2)
        node_tags, xyz, _ = gmsh.model.mesh.getNodes()
        _, elem_nodes = gmsh.model.mesh.getElementsByType(2)
        order = np.empty(int(node_tags.max()) + 1, dtype=np.int64)
        order[node_tags.astype(np.int64)] = np.arange(len(node_tags))
        return xyz.reshape(-1, 3)[:, :2], order[elem_nodes.astype(np.int64)].reshape(-1, 3)
    finally:
        gmsh.finalize()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-grading", action="store_true", help="also run meshwright with grading=None")
    ap.add_argument("--grading", type=float, action="append", default=[], metavar="G",
                    help="also run meshwright with grading=G (repeatable)")
    ap.add_argument("--no-relax", action="store_true", help="also run the relaxing methods with relax=False")
    ap.add_argument("--methods", default="front,frontal-delaunay,delaunay,weatherill")
    args = ap.parse_args()
    import os

    from meshwright import MESH_METHODS, triangulate

    load = os.getloadavg()[0]
    runs = []
    for m in args.methods.split(","):
        auto = MESH_METHODS[m]
        runs.append((f"meshwright {m}" + ("" if auto.grades_itself else f" (g={auto.grading:g})"), m, "auto", None))
        runs += [(f"meshwright {m} grading={g:g}", m, g, None) for g in args.grading]
        if args.no_grading:
            runs.append((f"meshwright {m} grading=None", m, None, None))
        if args.no_relax and MESH_METHODS[m].relaxes:
            # At the relaxed default's grading: relaxation's own gain (auto is 1.2 unrelaxed).
            runs.append((f"meshwright {m} relax=False (g={auto.grading:g})", m, auto.grading, False))
    # JIT warm-up (not timed).
    warm, hw = case("holes30")
    for _, m, g, rl in runs:
        triangulate(warm, hw, method=m, grading=g, relax=rl)
    try:
        import gmsh  # noqa: F401

        have_gmsh = True
    except ImportError:
        have_gmsh = False
    rows = []
    for name in ("holes30",) if args.quick else CASES:
        dom, size = case(name)
        disc = dom.discretize(size)
        for label, m, g, rl in runs:
            t, mesh = best_time(
                lambda d=dom, s=size, m=m, g=g, rl=rl: triangulate(d, s, method=m, grading=g, relax=rl), args.repeat
            )
            r = measure(mesh.points, mesh.cells["triangle"])
            rows.append([name, label, f"{r['under20']:.2f}", f"{r['min_angle']:.1f}", f"{r['rr_mean']:.4f}",
                         f"{r['n']:,}", f"{t:.3f}"])
        if have_gmsh:
            for extend in (1, 0):
                t, (p, tri) = best_time(
                    lambda d=disc, s=size, e=extend: run_gmsh(d.points, d.segments, s, e), args.repeat
                )
                r = measure(p, tri)
                rows.append([name, f"Gmsh Frontal-Delaunay, extend {extend}", f"{r['under20']:.2f}",
                             f"{r['min_angle']:.1f}", f"{r['rr_mean']:.4f}", f"{r['n']:,}", f"{t:.3f}"])
    print(f"load average {load:.2f} (1 min) at start, {os.getloadavg()[0]:.2f} at end")
    print_table(["case", "method", "% < 20 deg", "min angle", "mean 2r/R", "triangles", "time [s]"], rows)


if __name__ == "__main__":
    main()
