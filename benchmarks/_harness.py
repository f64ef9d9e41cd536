"""Shared benchmark helpers: best-of timing, peak memory in a child process, JIT compile time,
and the Gmsh plane surface the 2-D quality benchmarks build from a discretised boundary.

Timings run meshwright and its peers on the same input in one process.  Peak memory is
measured in a fresh child process per (case, method) because Numba's allocations are
invisible to ``tracemalloc``: the child reports the growth of its peak resident set.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent


def best_time(fn, repeat: int) -> tuple[float, object]:
    """Run ``fn`` ``repeat`` times; return the best wall time in seconds and the last result."""
    best, result = float("inf"), None
    for _ in range(repeat):
        t0 = time.perf_counter()
        result = fn()
        best = min(best, time.perf_counter() - t0)
    return best, result


def child_json(script: str, *args: str, env: dict | None = None) -> dict:
    """Run ``python script args`` and parse the JSON object printed on its last line."""
    full_env = dict(os.environ)
    if env:
        full_env.update(env)
    out = subprocess.run(
        [sys.executable, str(ROOT / script), *args],
        capture_output=True,
        text=True,
        env=full_env,
        check=True,
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def _status_kib(field: str) -> int | None:
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith(field + ":"):
                    return int(line.split()[1])
    except OSError:
        return None
    return None


def reset_peak_rss() -> int:
    """Reset the peak-RSS mark (Linux ``clear_refs``) and return the current RSS in bytes.

    Without it, the peak left by imports and JIT compilation hides the growth of a run.
    """
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
    except OSError:
        pass
    rss = _status_kib("VmRSS")
    return 0 if rss is None else rss * 1024


def peak_rss_bytes() -> int:
    """Peak resident set size of this process in bytes (since the last reset, where Linux allows)."""
    hwm = _status_kib("VmHWM")
    if hwm is not None:
        return hwm * 1024
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def jit_compile_times(snippet: str) -> tuple[float, float]:
    """Return (cold, cached) seconds for ``import meshwright`` plus ``snippet`` in fresh processes.

    Cold uses an empty ``NUMBA_CACHE_DIR``; cached reruns with the cache the cold run left.
    """
    code = (
        "import time; t0 = time.perf_counter()\n"
        "import numpy as np\n"
        f"{snippet}\n"
        "import json; print(json.dumps({'t': time.perf_counter() - t0}))\n"
    )
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        times = []
        for _ in range(2):
            out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True)
            times.append(json.loads(out.stdout.strip().splitlines()[-1])["t"])
    return times[0], times[1]


def print_table(headers: list[str], rows: list[list[str]]) -> None:
    """Print an aligned Markdown table."""
    widths = [max(len(h), *(len(r[i]) for r in rows)) for i, h in enumerate(headers)]
    line = "| " + " | ".join(h.ljust(w) for h, w in zip(headers, widths)) + " |"
    print(line)
    print("|" + "|".join("-" * (w + 2) for w in widths) + "|")
    for r in rows:
        print("| " + " | ".join(c.ljust(w) for c, w in zip(r, widths)) + " |")


def add_memory_arguments(ap) -> None:
    """``--repeat``, ``--no-memory`` and the hidden ``--memory-child CASE N METHOD`` entry."""
    import argparse

    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-memory", action="store_true", help="skip the child-process memory runs")
    ap.add_argument("--memory-child", nargs=3, metavar=("CASE", "N", "METHOD"), help=argparse.SUPPRESS)


def memory_child(make_case, methods, case: str, n: int, method: str) -> None:
    """Child-process entry: run one method once and print its peak-RSS growth per point.

    ``make_case(name, n)`` gives the points, ``methods()`` the name -> callable table.
    """
    pts = make_case(case, n)
    fn = methods()[method]
    fn(make_case("random", 1000))  # JIT warm-up so compile memory is not charged to the case
    base = reset_peak_rss()
    fn(pts)
    print(json.dumps({"bytes_per_point": (peak_rss_bytes() - base) / len(pts)}))


def timed_cases(cases, make_case, found: dict, skip: dict, skip_why: dict, repeat: int, once_from: int):
    """Yield ``(case, n, points, {name: (seconds, result)})`` per case, skipping what ``skip`` says.

    A method ``name`` is skipped on a case when ``n > skip[case][name]`` (reason
    ``skip_why[name]`` printed); cases of ``once_from`` points or more are timed once.
    """
    for case, n in cases:
        pts = make_case(case, n)
        timed = {}
        for name, fn in found.items():
            if name in skip.get(case, {}) and n > skip[case][name]:
                print(f"skip {name} on {case} {n:,}: {skip_why[name]}", file=sys.stderr)
                continue
            timed[name] = best_time(lambda: fn(pts), 1 if len(pts) >= once_from else repeat)
        yield case, n, pts, timed


def _boundary_loops(segments) -> list[list[tuple[int, int]]]:
    """Split closed boundary segments (each vertex on two) into loops of (a, b) pairs."""
    nxt = {int(a): int(b) for a, b in segments}
    seen: set[int] = set()
    loops = []
    for a0 in nxt:
        if a0 in seen:
            continue
        lp, a = [], a0
        while a not in seen:
            seen.add(a)
            lp.append((a, nxt[a]))
            a = nxt[a]
        loops.append(lp)
    return loops


def gmsh_plane_surface(gmsh, points, segments, sizes=None) -> list[int]:
    """Add to the current Gmsh model the plane surface bounded by closed segment loops.

    ``points`` (n, 2) float64, ``segments`` (m, 2) int; ``sizes`` (n,) optional point sizes.
    The loop with the largest bounding box is the outer one, the others are holes.  Returns
    the Gmsh curve tags of the holes' lines (walls for a distance size field).
    """
    import numpy as np

    if sizes is None:
        tags = [gmsh.model.geo.addPoint(x, y, 0.0) for x, y in points]
    else:
        tags = [gmsh.model.geo.addPoint(x, y, 0.0, s) for (x, y), s in zip(points, sizes)]
    lines = {(int(a), int(b)): gmsh.model.geo.addLine(tags[a], tags[b]) for a, b in segments}
    loops = _boundary_loops(segments)
    curve_loops = [gmsh.model.geo.addCurveLoop([lines[e] for e in lp]) for lp in loops]
    ext = [np.ptp(points[[a for a, _ in lp]], axis=0).prod() for lp in loops]
    outer = int(np.argmax(ext))
    gmsh.model.geo.addPlaneSurface([curve_loops[outer]] + [c for i, c in enumerate(curve_loops) if i != outer])
    gmsh.model.geo.synchronize()
    return [lines[e] for i, lp in enumerate(loops) if i != outer for e in lp]

