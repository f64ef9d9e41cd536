"""Benchmark: 3-D Delaunay tetrahedralization, meshwright (Bowyer, Watson) vs TetGen and scipy.

Usage::

    python benchmarks/delaunay3d.py            # the issue's cases (1e5, 1e6 random, 100^3 grid)
    python benchmarks/delaunay3d.py --quick    # 1e5 random and a 30^3 grid, a smoke run
    python benchmarks/delaunay3d.py --cases random:100000 grid:1000000 --no-memory

All methods run on the same points in one process; times are the best of ``--repeat`` runs
after a JIT warm-up.  Ratios are to TetGen through ``meshpy`` (``meshpy.tet.build`` with
switches ``Q``: the Delaunay tetrahedralization of the points; the ``tetgen`` package
crashes on point-only input), skipped cleanly when meshpy is absent.  scipy is Qhull.  Peak
memory per point is measured in a child process per (case, method); JIT compile time (cold
and cached) is reported separately.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

from _harness import add_memory_arguments, child_json, jit_compile_times, memory_child, print_table, timed_cases


def make_case(name: str, n: int, seed: int = 1) -> np.ndarray:
    """Return the (n, 3) float64 points of a named benchmark case (``grid``: k^3 >= n lattice)."""
    if name == "random":
        return np.random.default_rng(seed).random((n, 3))
    if name == "grid":
        k = int(round(n ** (1.0 / 3.0)))
        g = np.arange(k, dtype=float)
        return np.stack(np.meshgrid(g, g, g, indexing="ij"), -1).reshape(-1, 3)
    raise ValueError(name)


def methods() -> dict:
    """Return the available methods: name -> callable(points) -> number of tetrahedra."""
    from meshwright import delaunay

    found = {
        "bowyer": lambda p: len(delaunay(p, algorithm="bowyer").tetrahedra),
        "watson": lambda p: len(delaunay(p, algorithm="watson").tetrahedra),
    }
    try:
        from meshpy.tet import MeshInfo, Options, build

        def tetgen(p):
            info = MeshInfo()
            info.set_points(p)
            return len(build(info, options=Options("Q")).elements)

        found["tetgen"] = tetgen
    except ImportError:
        print("meshpy is absent: no TetGen column (pip install meshpy)", file=sys.stderr)
    try:
        from scipy.spatial import Delaunay

        found["scipy"] = lambda p: len(Delaunay(p).simplices)
    except ImportError:
        pass
    return found


CASES_FULL = [("random", 100_000), ("random", 1_000_000), ("grid", 1_000_000)]
# Qhull (scipy) on the lattice: 13.5 s and 4.8 kB per point for 40^3 here, superlinear.
SKIP = {"grid": {"scipy": 100_000}}
SKIP_WHY = {"scipy": "qhull is slow and memory-hungry on cospherical lattice points (13.5 s, 4.8 kB/point at 64,000)"}
CASES_QUICK = [("random", 100_000), ("grid", 27_000)]


def _parse_cases(items: list[str]) -> list[tuple[str, int]]:
    out = []
    for item in items:
        name, _, n = item.partition(":")
        out.append((name, int(float(n))))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="1e5 random and a 30^3 grid only")
    ap.add_argument("--cases", nargs="+", metavar="NAME:N", help="cases to run, e.g. random:1e6 grid:1e6")
    add_memory_arguments(ap)
    args = ap.parse_args(argv)
    if args.memory_child:
        case, n, method = args.memory_child
        memory_child(make_case, methods, case, int(n), method)
        return 0

    cold, cached = jit_compile_times(
        "from meshwright import delaunay\n"
        "p = np.random.default_rng(0).random((100, 3))\n"
        "delaunay(p, algorithm='bowyer'); delaunay(p, algorithm='watson')"
    )
    print(f"JIT: import + first 3-D calls (Bowyer and Watson), cold cache {cold:.2f} s, warm cache {cached:.2f} s\n")

    found = methods()
    warm = make_case("random", 2000)
    for fn in found.values():
        fn(warm)
    cases = _parse_cases(args.cases) if args.cases else (CASES_QUICK if args.quick else CASES_FULL)
    rows = []
    for case, n, pts, timed in timed_cases(cases, make_case, found, SKIP, SKIP_WHY, args.repeat, 1_000_000):
        times = {name: t for name, (t, _) in timed.items()}
        counts = {name: c for name, (_, c) in timed.items()}
        ref = times.get("tetgen")
        for name, t in times.items():
            mem = "-"
            if not args.no_memory:
                mem = "%.0f" % child_json("delaunay3d.py", "--memory-child", case, str(n), name)["bytes_per_point"]
            ratio = f"{t / ref:.2f}" if ref else "-"
            rows.append([f"{case} {len(pts):,}", name, f"{t:.3f}", ratio, f"{t / times['bowyer']:.2f}", str(counts[name]), mem])
            print(" | ".join(rows[-1]), file=sys.stderr)
    print_table(["case", "method", "time [s]", "x TetGen", "x Bowyer", "tets", "peak bytes/point"], rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
