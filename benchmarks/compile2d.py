"""First-run (JIT compile) cost of every 2-D method: what a new user waits for on the first call.

Usage::

    python benchmarks/compile2d.py                 # every case, cold then cached
    python benchmarks/compile2d.py --cases delaunay front
    python benchmarks/compile2d.py --no-all        # skip the all-methods-in-one-process row
    python benchmarks/compile2d.py --profile 25 --no-all --cases delaunay   # where it goes
    python benchmarks/compile2d.py --only-all --cold-only --profile 40      # every method, one process
    python benchmarks/compile2d.py --only-all --cold-only --profile 20 --signatures  # duplicate specialisations

``MESHWRIGHT_STOCK_INLINING=1`` in the environment compiles with Numba's stock IR inliner
(:mod:`meshwright.core.fast_inline` not installed), for A/B measurements.

Each case runs in a fresh process.  *Cold* gives it an empty ``NUMBA_CACHE_DIR`` (nothing
compiled yet: a new user's first call); *cached* reruns it with the cache the cold run left
(every later session).  The row ``all 2-D methods`` runs every case one after the other in a
single cold process: kernels the methods share compile once, which is what a user who tries
every method pays in total.  Times are wall and CPU seconds of the child, split into
``import meshwright`` and the first call (on tiny inputs, so run time is negligible: the
cached column shows it).  On a loaded machine compare CPU seconds; wall seconds stretch with
the load.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(__file__))
from _harness import print_table

# Each snippet runs after ``import numpy as np; import meshwright as mw``; inputs are tiny.
CASES = {
    "delaunay": "mw.delaunay(np.random.default_rng(0).random((1000, 2)))",
    "delaunay watson": "mw.delaunay(np.random.default_rng(0).random((1000, 2)), algorithm='watson')",
    "voronoi": "mw.voronoi(mw.delaunay(np.random.default_rng(0).random((500, 2))), clip=(0, 0, 1, 1))",
    "triangulate delaunay": "mw.triangulate(mw.geometry.circle(), size=0.1, method='delaunay')",
    "triangulate weatherill": "mw.triangulate(mw.geometry.circle(), size=0.1, method='weatherill')",
    "triangulate frontal-delaunay": "mw.triangulate(mw.geometry.circle(), size=0.1, method='frontal-delaunay')",
    "triangulate front": "mw.triangulate(mw.geometry.circle(), size=0.1, method='front')",
    "smooth": "g = np.linspace(0, 1, 6); X, Y = np.meshgrid(g, g); I, J = np.meshgrid(np.arange(5), np.arange(5)); "
    "a = (6 * J + I).ravel(); T = np.r_[np.c_[a, a + 1, a + 7], np.c_[a, a + 7, a + 6]].astype(np.int32); "
    "mw.smooth(np.c_[X.ravel(), Y.ravel()], T, passes=3)",
    "quad pairing": "mw.quadrangulate(mw.geometry.circle(), size=0.15, method='pairing')",
    "quad zhu": "mw.quadrangulate(mw.geometry.circle(), size=0.15, method='zhu')",
    "quad paving": "mw.quadrangulate(mw.geometry.circle(), size=0.15, method='paving')",
    "quad quadtree": "mw.quadrangulate(mw.geometry.circle(), size=0.15, method='quadtree')",
}

CHILD = r"""
import json, sys, time
from numba.core import event as ev

class Compiles(ev.Listener):
    # Self CPU seconds and signature count per compiled function (nested compiles subtracted).
    def __init__(self):
        self.stack, self.self_s, self.count, self.passes, self.sigs = [], {}, {}, {}, {}

    def on_start(self, event):
        self.stack.append([time.process_time(), 0.0, time.perf_counter()])

    def on_end(self, event):
        t0, nested, w0 = self.stack.pop()
        total = time.process_time() - t0
        # The pass timings are wall seconds: scaled to CPU by this compile's own ratio.
        scale = total / max(time.perf_counter() - w0, 1e-9)
        if self.stack:
            self.stack[-1][1] += total
        d = event.data["dispatcher"]
        name = f"{d.py_func.__module__}.{d.py_func.__qualname__}"
        self.self_s[name] = self.self_s.get(name, 0.0) + total - nested
        self.count[name] = self.count.get(name, 0) + 1
        self.sigs.setdefault(name, []).append([total - nested, ", ".join(str(a) for a in event.data["args"])])
        # Wall seconds of the passes (the nested compiles run inside type inference).
        cres = d.overloads.get(tuple(event.data["args"]))
        times = cres.metadata.get("pipeline_times", {}).get("nopython", {}) if cres is not None else {}
        split = self.passes.setdefault(name, [0.0, 0.0, 0.0])
        for key, t in times.items():
            run = (t.init + t.run + t.finalize) * scale
            if key.endswith("inline_inlinables"):
                split[0] += run
            elif key.endswith("nopython_type_inference"):
                split[1] += run - nested
            elif key.endswith("native_lowering"):
                split[2] += run

rec = Compiles()
ev.register("numba:compile", rec)
w0 = time.perf_counter(); c0 = time.process_time()
import numpy as np
import meshwright as mw
wi = time.perf_counter() - w0; ci = time.process_time() - c0
out = {"import_wall": wi, "import_cpu": ci, "calls": []}
for code in json.loads(sys.argv[1]):
    w = time.perf_counter(); c = time.process_time()
    exec(code)
    out["calls"].append([time.perf_counter() - w, time.process_time() - c])
out["compiles"] = sorted(
    ([k, v, rec.count[k], *rec.passes.get(k, [0.0] * 3)] for k, v in rec.self_s.items()), key=lambda r: -r[1]
)
out["signatures"] = {k: v for k, v in rec.sigs.items() if len(v) > 1}
print(json.dumps(out))
"""


def run_child(snippets: list[str], cache: str) -> dict:
    """Run the snippets in one fresh process with ``NUMBA_CACHE_DIR=cache``; its timings."""
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    res = subprocess.run(
        [sys.executable, "-c", CHILD, json.dumps(snippets)], capture_output=True, text=True, env=env, check=False
    )
    if res.returncode != 0:
        raise RuntimeError(f"child failed:\n{res.stderr[-3000:]}")
    return json.loads(res.stdout.strip().splitlines()[-1])


def _print_signatures(cold: dict) -> None:
    """Functions compiled for more than one signature (int32 and int64 arguments, Literal
    constants, layouts): each extra signature is a whole extra compile of the function."""
    sigs = sorted(cold["signatures"].items(), key=lambda kv: -sum(s for s, _ in kv[1]))
    extra = sum(sum(s for s, _ in v) - max(s for s, _ in v) for _, v in sigs)
    print(f"  {len(sigs)} functions compiled more than once, {extra:.1f} s CPU beyond each one's costliest",
          file=sys.stderr)
    for fn, rows in sigs:
        print(f"  x{len(rows)}  {fn}", file=sys.stderr)
        for sec, args in rows:
            print(f"      {sec:6.2f} s  ({args[:160]})", file=sys.stderr)
    sys.stderr.flush()


def _print_profile(name: str, cold: dict, top: int) -> None:
    """The ``top`` costliest compiled functions of a cold run, self CPU seconds first."""
    rows = cold["compiles"]
    total = sum(r[1] for r in rows)
    print(f"\n{name}: {len(rows)} functions compiled, {total:.1f} s CPU in numba:compile", file=sys.stderr)
    sums = [sum(r[k] for r in rows) for k in (3, 4, 5)]
    print(f"  IR inlining {sums[0]:.1f} s, type inference {sums[1]:.1f} s, lowering + LLVM {sums[2]:.1f} s"
          " (CPU, self)", file=sys.stderr)
    print("     self  count  inline  typing  llvm  function", file=sys.stderr)
    for fn, sec, count, inl, typ, low in rows[:top]:
        print(f"  {sec:7.2f} s  x{count}  {inl:6.2f}  {typ:6.2f}  {low:5.2f}  {fn}", file=sys.stderr)
    sys.stderr.flush()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", nargs="*", choices=sorted(CASES), default=list(CASES))
    ap.add_argument("--no-all", action="store_true", help="skip the all-methods-in-one-process row")
    ap.add_argument("--only-all", action="store_true",
                    help="only the all-methods-in-one-process row (no per-case processes)")
    ap.add_argument("--profile", type=int, default=0, metavar="N",
                    help="print the N costliest compiled functions of each cold case")
    ap.add_argument("--cold-only", action="store_true", help="skip the cached reruns")
    ap.add_argument("--signatures", action="store_true",
                    help="with --profile: list the functions compiled for more than one signature")
    args = ap.parse_args()
    rows = []
    for name in [] if args.only_all else args.cases:
        with tempfile.TemporaryDirectory() as cache:
            cold = run_child([CASES[name]], cache)
            warm = cold if args.cold_only else run_child([CASES[name]], cache)
        if args.profile:
            _print_profile(name, cold, args.profile)
            if args.signatures:
                _print_signatures(cold)
        rows.append(
            [
                name,
                f"{cold['import_wall'] + cold['calls'][0][0]:.1f}",
                f"{cold['import_cpu'] + cold['calls'][0][1]:.1f}",
                f"{cold['calls'][0][1]:.1f}",
                f"{warm['import_wall'] + warm['calls'][0][0]:.2f}",
                f"{warm['import_cpu'] + warm['calls'][0][1]:.2f}",
            ]
        )
        print(f"{name}: done", file=sys.stderr, flush=True)
    if args.only_all or not args.no_all:
        snippets = [CASES[n] for n in args.cases]
        with tempfile.TemporaryDirectory() as cache:
            cold = run_child(snippets, cache)
            warm = cold if args.cold_only else run_child(snippets, cache)
        if args.profile:
            _print_profile("all cases", cold, args.profile)
            if args.signatures:
                _print_signatures(cold)
        cw = cold["import_wall"] + sum(c[0] for c in cold["calls"])
        cc = cold["import_cpu"] + sum(c[1] for c in cold["calls"])
        ww = warm["import_wall"] + sum(c[0] for c in warm["calls"])
        wc = warm["import_cpu"] + sum(c[1] for c in warm["calls"])
        rows.append(
            [f"all {len(snippets)} cases, one process", f"{cw:.1f}", f"{cc:.1f}",
             f"{cc - cold['import_cpu']:.1f}", f"{ww:.2f}", f"{wc:.2f}"]
        )
        if args.profile:
            for name, (wall, cpu) in zip(args.cases, cold["calls"]):
                print(f"  {name}: {cpu:.1f} s CPU in the one process ({wall:.1f} s wall)", file=sys.stderr)
    load = os.getloadavg()[0]
    print(f"\nload average {load:.2f} on {os.cpu_count()} CPUs; seconds to the first result, "
          "import included")
    print_table(
        ["case", "cold wall", "cold CPU", "of which call CPU", "cached wall", "cached CPU"], rows
    )


if __name__ == "__main__":
    main()
