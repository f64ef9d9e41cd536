"""Benchmark: frontal Delaunay with and without its removable scaffold, against Gmsh's Frontal-Delaunay.

Usage::

    python benchmarks/frontal2d.py                 # disk n=1256 (~290k triangles) and NACA 0012
    python benchmarks/frontal2d.py --n 628         # a smaller disk
    python benchmarks/frontal2d.py --no-gmsh       # meshwright only

The cases and Gmsh's set-up are those of ``quality2d.py`` (imported from it: the same unit
disk of ``n`` boundary points at size h, the same graded NACA 0012 far field, Gmsh
algorithm 6 on the same boundary points, one thread).  Every row is timed in this one
process, best of ``--repeat``, so the ratio to Gmsh is taken seconds apart; the load
average is printed with the table because the machine may be shared.

Also measured: a rectangle under a uniformly stretched background grid (s = 4 along 30
degrees), the median principal-axis aspect and direction of the elements for
``frontal-delaunay`` and ``front``, and the mean radius ratio in the stretched space.
"""

from __future__ import annotations

import argparse
import math
import os
import sys

import numpy as np
from _harness import best_time, print_table
from quality2d import boundary_of, disk_case, naca_case, quality, run_gmsh


def _frontal(domain, size, scaffold: bool):
    """``triangulate(method="frontal-delaunay")`` with the scaffold switched on or off."""
    from meshwright.tri import mesher, triangulate

    orig = mesher.frontal_delaunay

    def placed(ct, field, **kw):
        return orig(ct, field, scaffold=scaffold, **kw)

    mesher.frontal_delaunay = placed
    try:
        m = triangulate(domain, size, method="frontal-delaunay")
    finally:
        mesher.frontal_delaunay = orig
    return m.points, m.cells["triangle"]


def _principal(points, tris):
    """Median aspect and major-axis direction (degrees) of the triangles' vertex clouds."""
    p = points[tris]
    d = p - p.mean(axis=1, keepdims=True)
    w, v = np.linalg.eigh(np.einsum("tki,tkj->tij", d, d))
    return float(np.median(np.sqrt(w[:, 1] / w[:, 0]))), float(
        np.median(np.degrees(np.arctan2(v[:, 1, 1], v[:, 0, 1])) % 180.0)
    )


def stretched_rows(repeat: int) -> list[list[str]]:
    import meshwright as mw
    from meshwright.sizing import BackgroundGrid

    dom = mw.geometry.polygon([(0, 0), (4, 0), (4, 1), (0, 1)])
    bg = BackgroundGrid.uniform(dom.bbox, 0.02, stretch=4.0, direction=math.radians(30))
    T = bg.transform(np.zeros((1, 2)))[0]
    rows = []
    for method in ("frontal-delaunay", "front"):
        t, m = best_time(lambda method=method: mw.triangulate(dom, bg, method=method), repeat)
        tris = m.cells["triangle"]
        aspect, direction = _principal(m.points, tris)
        q = quality(m.points @ T.T, tris)
        rows.append([method, f"{t:.3f}", f"{len(tris):,}", f"{aspect:.2f}", f"{direction:.1f}",
                     f"{q['rr_mean']:.4f}", f"{q['min_angle']:.2f}"])
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1256, help="boundary points of the disk")
    ap.add_argument("--repeat", type=int, default=3, help="timed runs per method (best is reported)")
    ap.add_argument("--no-gmsh", action="store_true", help="skip Gmsh")
    ap.add_argument("--no-naca", action="store_true", help="disk only")
    args = ap.parse_args(argv)

    runs = {
        "frontal-delaunay (scaffold)": lambda d, s, b: _frontal(d, s, True),
        "frontal-delaunay (no scaffold)": lambda d, s, b: _frontal(d, s, False),
    }
    if not args.no_gmsh:
        try:
            import gmsh  # noqa: F401

            runs["gmsh frontal-delaunay (6)"] = lambda d, s, b: run_gmsh(*b, 6)
        except ImportError:
            print("gmsh not installed: its row is skipped", file=sys.stderr)
    warm = disk_case(64)
    for fn in runs.values():
        fn(warm[0], warm[1], boundary_of(warm[0], warm[1]))

    cases = [(f"disk n={args.n}", *disk_case(args.n)[:2])]
    if not args.no_naca:
        cases.append(("naca0012 graded", *naca_case(1e-3, 1.0)))
    rows = []
    for label, domain, size in cases:
        boundary = boundary_of(domain, size)
        results = {}
        for name, fn in runs.items():
            t, (pts, tris) = best_time(lambda fn=fn, d=domain, s=size, b=boundary: fn(d, s, b), args.repeat)
            results[name] = (t, len(tris), quality(pts, tris))
            print(f"done {label}: {name} {t:.2f} s (load {os.getloadavg()[0]:.1f})", file=sys.stderr)
        gfd = results.get("gmsh frontal-delaunay (6)")
        for name, (t, nt, q) in results.items():
            rows.append([
                label, name, f"{t:.3f}", f"{nt:,}", f"{nt / t:,.0f}", f"{q['min_angle']:.2f}",
                f"{q['rr_mean']:.4f}", f"{q['rr_min']:.4f}", f"{(nt / t) / (gfd[1] / gfd[0]):.1f}" if gfd else "-",
            ])
    print(f"load average at the end: {' '.join(f'{x:.2f}' for x in os.getloadavg())}\n")
    print_table(["case", "method", "time [s]", "triangles", "tri/s", "min angle", "mean 2r/R", "min 2r/R",
                 "tri/s x Gmsh (6)"], rows)
    print()
    print_table(["stretched rectangle (s=4, 30 deg, delta=0.02)", "time [s]", "triangles", "median aspect",
                 "median direction", "mean 2r/R (stretched space)", "min angle (stretched space)"],
                stretched_rows(args.repeat))
    return 0


if __name__ == "__main__":
    sys.exit(main())
