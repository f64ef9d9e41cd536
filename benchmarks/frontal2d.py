"""Benchmark: frontal Delaunay with and without its removable scaffold, against Gmsh's Frontal-Delaunay.

Usage::

    python benchmarks/frontal2d.py                 # disk n=1256 (~290k triangles) and NACA 0012
    python benchmarks/frontal2d.py --n 628         # a smaller disk
    python benchmarks/frontal2d.py --no-gmsh       # meshwright only
    python benchmarks/frontal2d.py --stages        # also where the time goes, per stage
    python benchmarks/frontal2d.py --gmsh-repeat 1 # Gmsh timed once (13 s idle on the disk)

The cases and Gmsh's set-up are those of ``quality2d.py`` (imported from it: the same unit
disk of ``n`` boundary points at size h, the same graded NACA 0012 far field, Gmsh
algorithm 6 on the same boundary points, one thread).  Every row is timed in this one
process, best of ``--repeat``, so the ratio to Gmsh is taken seconds apart; the load
average is printed with the table because the machine may be shared.

``--stages`` times the stages of one ``triangulate`` call (best run of ``--repeat``) by
wrapping the method's Python-level steps: the background grid (a sampled field's
refinement), the scaffold's quadtree, its seeding kernel, the front's start and run kernels,
renumbering the rows, and what ``triangulate`` does around them (discretisation, the
boundary's constrained triangulation, the ``Mesh``).

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


def stage_rows(domain, size, repeat: int) -> list[list[str]]:
    """Seconds per stage of the best of ``repeat`` frontal-delaunay runs (module docstring)."""
    import time

    import meshwright.tri.frontal_delaunay as fd
    from meshwright.tri import _frontal_kernel as fk
    from meshwright.tri import mesher, triangulate

    spent: dict[str, float] = {}
    patched = []

    def timed(owner, name, label):
        orig = getattr(owner, name)

        def run(*a, **kw):
            t0 = time.perf_counter()
            try:
                return orig(*a, **kw)
            finally:
                spent[label] = spent.get(label, 0.0) + time.perf_counter() - t0

        setattr(owner, name, run)
        patched.append((owner, name, orig))

    for owner, name, label in (
        (fd, "_background", "background grid (sample refinement)"), (fd, "scaffold_points", "scaffold quadtree"),
        (fk, "seed_scaffold", "scaffold seeding kernel"), (fk, "start", "front start kernel"),
        (fk, "run", "front kernel (insertion, removal, sizes)"), (fk, "close_rows", "row renumbering"),
        (mesher, "frontal_delaunay", "frontal_delaunay (all)"), (mesher, "_finish", "final refinement pass"),
    ):
        timed(owner, name, label)
    best = None
    try:
        for _ in range(repeat):
            spent.clear()
            t0 = time.perf_counter()
            triangulate(domain, size, method="frontal-delaunay")
            total = time.perf_counter() - t0
            if best is None or total < best[0]:
                best = (total, dict(spent))
    finally:
        for owner, name, orig in reversed(patched):
            setattr(owner, name, orig)
    total, spent = best
    inner = spent.pop("frontal_delaunay (all)", 0.0)
    finish = spent.get("final refinement pass", 0.0)
    rows = [[k, f"{v:.3f}", f"{100 * v / total:.1f}"] for k, v in spent.items()]
    glue = inner - sum(v for k, v in spent.items() if k != "final refinement pass")
    outside = total - inner - finish
    rows.append(["rest of frontal_delaunay (Python glue, growth)", f"{glue:.3f}", f"{100 * glue / total:.1f}"])
    rows.append(["triangulate around the method (discretise, CDT, Mesh)", f"{outside:.3f}", f"{100 * outside / total:.1f}"])
    rows.append(["total", f"{total:.3f}", "100.0"])
    return rows


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
    ap.add_argument("--gmsh-repeat", type=int, default=None, help="timed Gmsh runs (default: --repeat)")
    ap.add_argument("--no-naca", action="store_true", help="disk only")
    ap.add_argument("--stages", action="store_true", help="time the stages of one run per case")
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
    coarse = naca_case(1e-2, 1.0)  # a graded field also loads the sampling kernels
    for fn in runs.values():
        fn(warm[0], warm[1], boundary_of(warm[0], warm[1]))
        if not args.no_naca:
            fn(coarse[0], coarse[1], boundary_of(*coarse))

    cases = [(f"disk n={args.n}", *disk_case(args.n)[:2])]
    if not args.no_naca:
        cases.append(("naca0012 graded", *naca_case(1e-3, 1.0)))
    rows = []
    for label, domain, size in cases:
        boundary = boundary_of(domain, size)
        results = {}
        for name, fn in runs.items():
            repeat = args.gmsh_repeat if name.startswith("gmsh") and args.gmsh_repeat else args.repeat
            t, (pts, tris) = best_time(lambda fn=fn, d=domain, s=size, b=boundary: fn(d, s, b), repeat)
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
    if args.stages:
        for label, domain, size in cases:
            print()
            print_table([f"{label}: stage", "time [s]", "%"], stage_rows(domain, size, args.repeat))
    print()
    print_table(["stretched rectangle (s=4, 30 deg, delta=0.02)", "time [s]", "triangles", "median aspect",
                 "median direction", "mean 2r/R (stretched space)", "min angle (stretched space)"],
                stretched_rows(args.repeat))
    return 0


if __name__ == "__main__":
    sys.exit(main())
