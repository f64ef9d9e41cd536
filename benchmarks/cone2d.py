"""Cost of the graded size field's cone minimum (``sizing.boundary._cone_min``) in the
airfoil runs of issue 13, and an A/B of two source trees in alternating processes.

    python benchmarks/cone2d.py                         # this tree: one table
    python benchmarks/cone2d.py --ab OLD_SRC --rounds 3 # OLD_SRC/meshwright against this tree
    python benchmarks/cone2d.py --ab OLD_SRC --new NEW_SRC  # two exported trees (git archive)

Cases (the benchmarks' own): ``quality2d.py``'s graded NACA 0012 (wall size 1e-3, hmax 1)
by ``front`` and ``frontal-delaunay``; ``grading2d.py``'s NACA (241 vertices in a box,
size 0.25, the default grading) by the same two; ``quad2d.py``'s NACA 0012 and
three-element airfoil at half their size by ``pairing``, ``paving`` and ``quadtree``.

Each run is timed best of ``--repeat`` after a warm-up, with the seconds spent inside
``_cone_min`` (exclusive: the kernel is wrapped, so a field graded from another graded
field counts each kernel call once) and the number of size queries it answered.  The
mesh's node and element counts and a hash of its points show that both trees make the
same meshes.  ``--ab`` runs this script in child processes, the old tree (``PYTHONPATH``
first) and this one alternately, ``--rounds`` times each, and prints the best of each
beside the ratio; Numba caches go to separate directories so neither tree reads the
other's.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent
sys.path.insert(0, str(ROOT))


def cases():
    """(label, method, run) of every case (module docstring)."""
    import grading2d
    import quad2d
    import quality2d

    import meshwright as mw

    d1, s1 = quality2d.naca_case(1e-3, 1.0)
    d2, s2 = grading2d.case("naca")
    out = []
    for m in ("front", "frontal-delaunay"):
        out.append(("quality2d naca graded", m, lambda m=m: mw.triangulate(d1, s1, method=m)))
        out.append(("grading2d naca", m, lambda m=m: mw.triangulate(d2, s2, method=m)))
    for label, dom, field, _ in quad2d.cases(False)[1:]:
        for m in ("pairing", "paving", "quadtree"):
            out.append((f"quad2d {label}", m, lambda m=m, d=dom, f=field: mw.quadrangulate(d, f, method=m)))
    return out


def measure(repeat: int) -> list[dict]:
    """One row per case: best total seconds, the cone kernel's seconds and queries in that run."""
    from meshwright.sizing import boundary

    real = boundary._cone_min
    acc = {"t": 0.0, "n": 0}

    def wrapped(query, *args):
        t = time.perf_counter()
        out = real(query, *args)
        acc["t"] += time.perf_counter() - t
        acc["n"] += len(query)
        return out

    boundary._cone_min = wrapped
    rows = []
    for label, method, run in cases():
        run()
        best = None
        for _ in range(repeat):
            acc.update(t=0.0, n=0)
            t = time.perf_counter()
            mesh = run()
            total = time.perf_counter() - t
            if best is None or total < best[0]:
                best = (total, acc["t"], acc["n"])
        cells = sum(len(c) for c in mesh.cells.values())
        digest = hashlib.sha1(np.ascontiguousarray(mesh.points).tobytes()).hexdigest()[:10]
        rows.append({"case": label, "method": method, "total": best[0], "cone": best[1], "queries": best[2],
                     "nodes": int(mesh.n_points), "cells": int(cells), "hash": digest})
    return rows


def load() -> str:
    return " ".join(f"{x:.1f}" for x in os.getloadavg())


def ab(old_src: str, new_src: str | None, rounds: int, repeat: int) -> None:
    here = str(Path(__file__).resolve().parents[1] / "src")
    trees = {"old": old_src, "new": new_src or here}
    best: dict = {}
    loads = []
    for r in range(rounds):
        for name in ("old", "new"):
            env = dict(os.environ, PYTHONPATH=trees[name],
                       NUMBA_CACHE_DIR=os.environ.get("NUMBA_CACHE_DIR", "/tmp/cone2d-nbcache") + "-" + name)
            loads.append(load())
            out = subprocess.run([sys.executable, __file__, "--json", "--repeat", str(repeat)], env=env,
                                 capture_output=True, text=True, check=True)
            for row in json.loads(out.stdout.strip().splitlines()[-1]):
                key = (row["case"], row["method"])
                have = best.setdefault(name, {}).get(key)
                if have is None or row["total"] < have["total"]:
                    best[name][key] = row
            print(f"round {r + 1} {name} done (load {loads[-1]})", file=sys.stderr, flush=True)
    print(f"load averages at each child's start: {'; '.join(loads)}")
    print("| case | method | nodes / cells (old = new) | total old s | total new s | new/old | cone old s | cone new s "
          "| cone new/old | queries | cone old us/q | cone new us/q |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for key, o in best["old"].items():
        n = best["new"][key]
        same = "same" if (o["hash"], o["nodes"], o["cells"]) == (n["hash"], n["nodes"], n["cells"]) else "DIFFER"
        print(f"| {key[0]} | {key[1]} | {n['nodes']} / {n['cells']} ({same}) | {o['total']:.3f} | {n['total']:.3f} "
              f"| {n['total'] / o['total']:.2f} | {o['cone']:.4f} | {n['cone']:.4f} | {n['cone'] / o['cone']:.2f} "
              f"| {n['queries']} | {1e6 * o['cone'] / max(o['queries'], 1):.2f} | {1e6 * n['cone'] / max(n['queries'], 1):.2f} |")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--json", action="store_true", help="print the rows as one JSON line (for --ab)")
    ap.add_argument("--ab", metavar="OLD_SRC", help="directory holding the old tree's meshwright package")
    ap.add_argument("--new", metavar="NEW_SRC", help="the new tree's package directory (default: this tree's src)")
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    if args.ab:
        ab(args.ab, args.new, args.rounds, args.repeat)
        return
    rows = measure(args.repeat)
    if args.json:
        print(json.dumps(rows))
        return
    print(f"load {load()}")
    for r in rows:
        print(f"{r['case']:26s} {r['method']:17s} total {r['total']:.3f} s, cone {r['cone']:.4f} s "
              f"({100 * r['cone'] / r['total']:.0f} %), {r['queries']} queries, {r['nodes']} nodes, {r['cells']} cells")


if __name__ == "__main__":
    main()
