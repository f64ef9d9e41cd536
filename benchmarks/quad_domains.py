"""Benchmark: issue 12's "all-quad on every domain" and "min scaled Jacobian > 0.2" targets.

Usage::

    python benchmarks/quad_domains.py                     # pairing, zhu and quadtree
    python benchmarks/quad_domains.py --methods paving    # any QUAD_METHODS entries
    python benchmarks/quad_domains.py --only circle ring.poly

Runs :func:`meshwright.quadrangulate` (all-quad, the default) on the domains the test suite
meshes: every built-in domain at its own size and at half of it, the ``.poly`` files of
``tests/data`` at their default size, and the constructed cases of ``tests/test_pairing.py``
and ``tests/test_quad.py`` (holes, interior segments and points, a graded size jumping from
0.03 to 0.08, nested hole and island).  A method that refuses a domain's features (every method:
a region's area bound) is listed as refused, not failed.  Per case: the quad
count, whether the mesh is all-quad (no triangle cell), the min and mean scaled
Jacobian and the min / max interior angle (meshwright's
:func:`~meshwright.core.quality.quad_quality`), and the wall time (one run, after a
warm-up).  The last line counts the cases below the 0.2 bound.
"""

from __future__ import annotations

import argparse
import pathlib
import sys
import time

import numpy as np

DATA = pathlib.Path(__file__).resolve().parents[1] / "tests" / "data"


def domains():
    """(label, domain, size) of every case."""
    from meshwright.geometry import (
        BUILTIN_DOMAINS,
        builtin,
        circles,
        polygon,
        read_poly,
    )

    out = []
    for name in BUILTIN_DOMAINS:
        dom = builtin(name)
        out.append((name, dom, None))
        out.append((f"{name} x0.5", dom, lambda xy, f=dom.size: 0.5 * f(xy)))
    for path in sorted(DATA.glob("*.poly")):
        out.append((path.name, read_poly(path), None))
    square = [(0, 0), (1, 0), (1, 1), (0, 1)]
    out += [
        ("disk graded", builtin("circle"), lambda p: 0.03 + 0.1 * np.hypot(p[:, 0] - 0.5, p[:, 1])),
        ("square with hole", circles(centers=[(0.5, 0.5)], radii=[0.2], box=(0, 0, 1, 1)), 0.06),
        ("square, square hole, graded",
         polygon(square, holes=[[(0.3, 0.3), (0.3, 0.6), (0.6, 0.6), (0.6, 0.3)]]), lambda p: 0.03 + 0.05 * p[:, 0]),
        ("hole, segment, points", polygon(
            [(0, 0), (2, 0), (2, 1), (0, 1)], holes=[[(0.3, 0.3), (0.6, 0.3), (0.6, 0.6), (0.3, 0.6)]],
            segments=[[(1.0, 0.2), (1.7, 0.8)]], points=[(1.5, 0.2), (0.2, 0.8)]), 0.1),
        ("wall segment", polygon(
            [(0, 0), (0.5, 0), (1, 0), (1, 1), (0.5, 1), (0, 1)], segments=[[(0.5, 0), (0.5, 1)]]), 0.1),
        ("hole with island h=0.01", polygon(
            square, holes=[[(0.2, 0.2), (0.8, 0.2), (0.8, 0.8), (0.2, 0.8)],
                           [(0.4, 0.4), (0.6, 0.4), (0.6, 0.6), (0.4, 0.6)]],
            regions=[(0.5, 0.5, 7, None)]), 0.01),
    ]
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--methods", nargs="+", default=["pairing", "zhu", "quadtree"])
    ap.add_argument("--only", nargs="+", help="case labels to run (default: all)")
    args = ap.parse_args(argv)
    from meshwright.core.errors import InputError
    from meshwright.core.quality import quad_quality
    from meshwright.quad import quadrangulate

    for m in args.methods:
        quadrangulate("circle", 0.25, method=m)
    rows, below = [], 0
    for label, dom, size in domains():
        if args.only and label not in args.only:
            continue
        for m in args.methods:
            t = time.perf_counter()
            try:
                mesh = quadrangulate(dom, size, method=m)
            except InputError as e:
                rows.append((label, m, f"refused: {e}"[:90]))
                print(f"| {label} | {m} | {rows[-1][2]} |", flush=True)
                continue
            dt = time.perf_counter() - t
            q = quad_quality(mesh.points, mesh.cells["quad"])
            sj = q["scaled_jacobian"]
            below += int(sj.min() <= 0.2)
            cols = (
                f"{len(sj):>7,} | {'yes' if 'triangle' not in mesh.cells else 'NO'} | {sj.min():.3f} | "
                f"{sj.mean():.3f} | {q['min_angle'].min():5.1f} | {q['max_angle'].max():5.1f} | {dt:6.2f}"
            )
            rows.append((label, m, cols))
            print(f"| {label} | {m} | {rows[-1][2]} |", flush=True)
    print(f"cases with min scaled Jacobian <= 0.2: {below}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
