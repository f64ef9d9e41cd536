"""Benchmark: 2-D Delaunay triangulation, meshwright (Bowyer, Watson) vs Triangle and scipy.

Usage::

    python benchmarks/delaunay2d.py            # the issue's cases (1e5, 1e6, 4e6 random, grid, circle)
    python benchmarks/delaunay2d.py --quick    # small sizes, a smoke run
    python benchmarks/delaunay2d.py --no-memory
    python benchmarks/delaunay2d.py --cases random:1e6 grid:1e6 --no-memory

All methods run on the same points in one process; times are the best of ``--repeat`` runs
after a JIT warm-up, as wall time and as CPU time of this process (on a shared machine the
CPU-time ratio is the steadier one: every method here is single-threaded).  Ratios are to
Triangle (``triangle.triangulate(..., "Q")``, Shewchuk's divide-and-conquer).  Peak memory
per point is measured in a child process per (case, method).  JIT compile time (cold and
cached) is reported separately.
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np
from _harness import (
    add_memory_arguments,
    child_json,
    jit_compile_times,
    memory_child,
    print_table,
    timed_cases,
)


def make_case(name: str, n: int, seed: int = 1) -> np.ndarray:
    """Return the (n, 2) float64 points of a named benchmark case."""
    rng = np.random.default_rng(seed)
    if name == "random":
        return rng.random((n, 2))
    if name == "grid":
        k = int(round(np.sqrt(n)))
        x, y = np.meshgrid(np.arange(k, dtype=float), np.arange(k, dtype=float))
        return np.column_stack([x.ravel(), y.ravel()])
    if name == "circle":
        t = 2.0 * np.pi * np.arange(n) / n
        return np.column_stack([np.cos(t), np.sin(t)])
    raise ValueError(name)


def methods() -> dict:
    """Return the available methods: name -> callable(points) -> number of triangles."""
    from meshwright import delaunay

    found = {
        "bowyer": lambda p: len(delaunay(p, algorithm="bowyer").triangles),
        "watson": lambda p: len(delaunay(p, algorithm="watson").triangles),
    }
    try:
        import triangle

        found["triangle"] = lambda p: len(triangle.triangulate({"vertices": p}, "Q")["triangles"])
    except ImportError:
        pass
    try:
        from scipy.spatial import Delaunay

        found["scipy"] = lambda p: len(Delaunay(p).simplices)
    except ImportError:
        pass
    return found


CASES_FULL = [("random", 100_000), ("random", 1_000_000), ("random", 4_000_000), ("grid", 1_000_000), ("circle", 100_000)]
# Qhull (scipy) needs O(n^2.3) time on cocircular points: 9.5 s for 10,000 on a circle here.
SKIP = {"circle": {"scipy": 10_000}}
SKIP_WHY = {"scipy": "qhull is superlinear on cocircular points (about 1,000 s extrapolated)"}
CASES_QUICK = [("random", 20_000), ("grid", 10_000), ("circle", 5_000)]


def _parse_cases(items: list[str]) -> list[tuple[str, int]]:
    out = []
    for item in items:
        name, _, n = item.partition(":")
        out.append((name, int(float(n))))
    return out


def cpu_timed(found: dict) -> tuple[dict, dict]:
    """Wrap each method so every call records its CPU time; returns (wrapped, best CPU per name)."""
    best: dict = {}

    def wrap(name, fn):
        def run(p):
            c0 = time.process_time()
            out = fn(p)
            best[name] = min(best.get(name, float("inf")), time.process_time() - c0)
            return out

        return run

    return {name: wrap(name, fn) for name, fn in found.items()}, best


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="small sizes only")
    ap.add_argument("--cases", nargs="+", metavar="NAME:N", help="cases to run, e.g. random:1e6 circle:1e5")
    add_memory_arguments(ap)
    args = ap.parse_args(argv)
    if args.memory_child:
        case, n, method = args.memory_child
        memory_child(make_case, methods, case, int(n), method)
        return 0

    cold, cached = jit_compile_times(
        "from meshwright import delaunay\n"
        "p = np.random.default_rng(0).random((100, 2))\n"
        "delaunay(p, algorithm='bowyer'); delaunay(p, algorithm='watson')"
    )
    print(f"JIT: import + first call, cold cache {cold:.2f} s, warm cache {cached:.2f} s\n")

    found = methods()
    warm = make_case("random", 2000)
    for fn in found.values():
        fn(warm)
    rows = []
    cases = _parse_cases(args.cases) if args.cases else (CASES_QUICK if args.quick else CASES_FULL)
    wrapped, cpu = cpu_timed(found)
    for case, n, _, timed in timed_cases(cases, make_case, wrapped, SKIP, SKIP_WHY, args.repeat, 4_000_000):
        ref = timed["triangle"][0] if "triangle" in timed else None
        cref = cpu.get("triangle")
        for name, (t, _) in timed.items():
            mem = "-"
            if not args.no_memory:
                mem = "%.0f" % child_json("delaunay2d.py", "--memory-child", case, str(n), name)["bytes_per_point"]
            ratio = f"{t / ref:.2f}" if ref else "-"
            c = cpu[name]
            cratio = f"{c / cref:.2f}" if cref else "-"
            rows.append([f"{case} {n:,}", name, f"{t:.3f}", ratio, f"{c:.3f}", cratio, mem])
            print(" | ".join(rows[-1]), file=sys.stderr)
        cpu.clear()
    print_table(["case", "method", "time [s]", "x Triangle", "CPU [s]", "x Triangle (CPU)", "peak bytes/point"], rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
