"""Seeded fuzz of ``meshwright.tetrahedralize`` (issue 11): random closed surfaces, checked.

Cases, drawn from one seeded generator (case i is the same on every run): extruded random
star polygons (height 0.05-1.5, wall triangles on general vertical planes), a box holding
a smaller box cavity, and rotated coarse spheres (level 1-2, radius 0.2-2, random centre);
radius-edge bound 1.2, 1.5 or 2, a size 0.1-0.5 in 30 % of the cases.  Each mesh must pass
``Mesh.validate()``, enclose the input's volume (relative 1e-9, by the divergence theorem
on the input faces, not the mesher's code) and have boundary faces covering the input's
area per marker.  A failing case is saved as ``DIR/case<i>.npz`` (points, triangles, the
keyword arguments) for ``--replay``.

Usage::

    python scripts/fuzz_tet.py --cases 300 [--seed 7] [--save DIR] [--replay FILE.npz ...]

Exit status 1 when any case fails.  Not a benchmark: the times printed are for orientation.
"""

from __future__ import annotations

import argparse
import ast
import sys
import time
from pathlib import Path

import numpy as np

import meshwright as mw
from meshwright.core.quality import tetra_quality
from meshwright.geometry import Surface, box, combine, extrude, sphere


def make_case(rng: np.random.Generator):
    """One random surface and the keyword arguments of its run."""
    kind = int(rng.integers(3))
    if kind == 0:
        while True:  # a star polygon of nearly equal angles can self-intersect: draw again
            n = int(rng.integers(5, 12))
            ang = np.sort(rng.random(n)) * 2 * np.pi
            r = 0.5 + rng.random(n)
            try:
                dom = mw.geometry.polygon(np.c_[r * np.cos(ang), r * np.sin(ang)])
                break
            except mw.MeshwrightError:
                continue
        m2 = mw.triangulate(dom, size=float(rng.uniform(0.15, 0.5)))
        surf = extrude(m2, float(rng.uniform(0.05, 1.5)))
    elif kind == 1:
        lo = rng.random(3) * 0.2
        hi = lo + 0.5 + rng.random(3)
        surf = box(lo, hi)
        a, b = float(rng.uniform(0.1, 0.3)), float(rng.uniform(0.1, 0.3))
        c = (lo + hi) / 2
        if np.all(c - a > lo) and np.all(c + b < hi):
            surf = combine(surf, box(c - a, c + b).flipped())
    else:
        q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        sp = sphere(float(rng.uniform(0.2, 2)), center=rng.normal(size=3), level=int(rng.integers(1, 3)))
        surf = Surface(sp.points @ q.T, sp.triangles)
    kw = {"radius_edge": float(rng.choice([1.2, 1.5, 2.0])), "seed": int(rng.integers(1000))}
    if rng.random() < 0.3:
        kw["size"] = float(rng.uniform(0.1, 0.5))
    return kind, surf, kw


def check(surf: Surface, kw: dict) -> str:
    """Mesh one case; '' when it passes, else what failed."""
    try:
        mesh = mw.tetrahedralize(surf, **kw)
        mesh.validate()
    except mw.MeshwrightError as exc:
        return f"{type(exc).__name__}: {exc}"
    p = surf.points[surf.triangles]
    enclosed = np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6.0
    vol = float(mesh.volume())
    if abs(vol - enclosed) > 1e-9 * abs(enclosed):
        return f"volume {vol!r}, the surface encloses {enclosed!r}"
    q = mesh.points[mesh.cells["triangle"]]
    area = 0.5 * np.linalg.norm(np.cross(q[:, 1] - q[:, 0], q[:, 2] - q[:, 0]), axis=1)
    area_in = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    marks = mesh.cell_data["marker"]["triangle"]
    for m in np.unique(surf.markers):
        a, b = area[marks == m].sum(), area_in[surf.markers == m].sum()
        if abs(a - b) > 1e-9 * area_in.sum():
            return f"boundary area {a!r} with marker {m}, the surface's {b!r}"
    worst = float(tetra_quality(mesh.points, mesh.cells["tetra"])["min_dihedral"].min())
    return "" if np.isfinite(worst) else "non-finite dihedral angle"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", type=int, default=300)
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--first", type=int, default=0, help="index of the first case to run")
    ap.add_argument("--save", type=Path, default=None, help="directory for failing cases")
    ap.add_argument("--replay", type=Path, nargs="*", default=(), help="saved cases to run instead")
    args = ap.parse_args(argv)
    failed = 0
    if args.replay:
        for path in args.replay:
            data = np.load(path)
            why = check(Surface(data["points"], data["tris"]), ast.literal_eval(str(data["kw"])))
            print(f"{path}: {why or 'ok'}", flush=True)
            failed += bool(why)
        return int(failed > 0)
    rng = np.random.default_rng(args.seed)
    start = time.perf_counter()
    for i in range(args.first + args.cases):
        kind, surf, kw = make_case(rng)
        if i < args.first:
            continue
        why = check(surf, kw)
        if (i + 1 - args.first) % 25 == 0:
            print(f"{i + 1 - args.first} cases, {failed + bool(why)} failed ({time.perf_counter() - start:.0f} s)", flush=True)
        if why:
            failed += 1
            print(f"case {i} (kind {kind}, {kw}): {why[:300]}", flush=True)
            if args.save is not None:
                args.save.mkdir(parents=True, exist_ok=True)
                np.savez(args.save / f"case{i}.npz", points=surf.points, tris=surf.triangles, kw=repr(kw))
    print(f"{args.cases - failed} of {args.cases} passed ({time.perf_counter() - start:.0f} s)")
    return int(failed > 0)


if __name__ == "__main__":
    sys.exit(main())
