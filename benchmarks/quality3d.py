"""Benchmark: quality tetrahedral meshes of the unit sphere, meshwright vs TetGen and Gmsh.

Usage::

    python benchmarks/quality3d.py            # the issue's sizes: about 1e5 and 1e6 tets
    python benchmarks/quality3d.py --quick    # about 1e4 tets, a smoke run
    python benchmarks/quality3d.py --levels 4 --repeat 1
    python benchmarks/quality3d.py --levels 5 --tets 1000000   # every mesher calibrated to ~1e6 tets
    python benchmarks/quality3d.py --levels 5 --factor gmsh-hxt=0.67 --factor meshwright=0.885
    python benchmarks/quality3d.py --levels 5 --repeat 1 --no-jit --factor meshwright=0.885 --methods meshwright --stages

Case: the unit sphere as :func:`meshwright.geometry.sphere` triangulates it (icosahedron
subdivided ``level`` times, vertices on the true sphere; level 3: 1280 faces, level 4:
5120, level 5: 20480).  Every mesher gets that same surface triangulation and the same
target edge length ``h`` (the mean edge length of the surface), so the interior is as fine
as the boundary and the counts are comparable:

* meshwright: ``tetrahedralize(surface, size=h, radius_edge=RHO)`` (default ``RHO`` 1.414,
  TetGen's bound below; ``slivers="remove"``);
* TetGen (the ``tetgen`` package): switches ``pq1.414a<V>Q`` with ``V = h^3 / (6 sqrt 2)``,
  the volume of the regular tetrahedron of edge ``h`` (without ``a`` TetGen grades
  coarser inside and the tet counts would not compare);
* Gmsh Delaunay (``Mesh.Algorithm3D = 1``) and HXT (``Mesh.Algorithm3D = 10``), one
  thread, the surface given as a discrete entity (kept as is), ``Mesh.MeshSizeMax = h``;
  Gmsh's default optimisation pass included (it is part of its pipeline).

What a size ``h`` means differs between the meshers, so the same ``h`` does not give the same
mesh.  Measured on the level-4 sphere (h 0.0755; interior edges = edges with at least one
vertex off the boundary; ``edge/h`` columns): meshwright mean 1.08 h (median 1.06, 10-90 %
0.84-1.35), TetGen ``a`` = regular-tet volume 0.89 h (median 0.89), Gmsh Delaunay 1.39 h and
HXT 1.43 h (median 1.43, 10-90 % 1.07-1.79); boundary edges are the surface's, h on average.
So meshwright's size is not too fine: its criterion (split a tet whose circumradius exceeds
0.8 h, where the regular tet of edge h has 0.61 h) gives edges of about h, as a size h should,
and TetGen is a little finer; it is Gmsh whose interior edges come out about 1.4 times its
``MeshSizeMax``, so at one ``h`` Gmsh makes about 2.1x fewer tets than meshwright (and
TetGen 1.7x more).  Comparing times at one ``h`` therefore favours Gmsh by the tet count.
``--tets N`` calibrates each mesher's size factor ``f`` (its size is ``f h``; TetGen's volume
bound scales by ``f^3``) so that all produce about N tets from the same surface (a few untimed
runs, ``f <- f (count / N)^(1/3)``, until within 5 %), and ``--factor NAME=F`` gives the
factors directly; the table prints both ratios to HXT: by time (``x HXT``) and by throughput
(``x HXT tets/s``: HXT's tets/s over this mesher's).  Neither alone is the whole story: at
equal counts the time ratio is the fair one; at one ``h`` the throughput ratio is.  Calibrated
on the level-4 sphere to meshwright's 86,758 tets: TetGen 1.195, Gmsh Delaunay 0.779, HXT
0.751, and then every mesher's interior edges measure 1.06-1.09 h; for about 1e6 tets on the
level-5 sphere: meshwright 0.885, TetGen 1.057, Gmsh Delaunay 0.70, HXT 0.672 (963k-999k
tets, interior edges 0.94-0.98 h).  The size criterion was therefore left as it is: it is the
yardstick that differed, not meshwright's meaning of h.

Quality is computed by :func:`meshwright.core.quality.tetra_quality` for every mesher
(peers' tets reoriented positive first): minimum and maximum dihedral angle, mean and
minimum radius ratio (``3 r / R``, 1 for the regular tetrahedron), the chapter's sliver
flag ``a = r / R < 0.01`` count, and the fraction of tets with a dihedral angle below
10 degrees.  Times are wall times, best of ``--repeat`` (once at 1e6 tets), after a JIT
warm-up; the JIT compile time of ``import meshwright`` plus a first small
``tetrahedralize`` is reported cold (empty Numba cache) and cached.  The warm-up meshes the
level-3 sphere with every method (until the sixth session the level-1 sphere, which left
the loading of the large-mesh kernels to the timed run).
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

from _harness import best_time, jit_compile_times, print_table
from meshwright.core.errors import MeshwrightError

SQRT2 = np.sqrt(2.0)
LEVELS_FULL = [4, 5]  # about 1e5 and 1e6 tets at the surface's own edge length
LEVELS_QUICK = [3]  # about 1e4


WARM_LEVEL = 3  # sphere level of the warm-up run of every method


def sphere_case(level: int):
    """The unit sphere's surface at ``level`` and its mean edge length h: (surface, h)."""
    from meshwright.geometry import sphere

    surf = sphere(radius=1.0, level=level)
    p = surf.points[surf.triangles]
    h = float(np.linalg.norm(p - np.roll(p, 1, axis=1), axis=2).mean())
    return surf, h


def oriented(points: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """``tets`` (m, 4) int32 with the first two vertices swapped where the volume is negative."""
    tets = np.array(tets, dtype=np.int32)
    p = points[tets]
    neg = np.einsum("mi,mi->m", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])) < 0.0
    tets[neg, 0], tets[neg, 1] = tets[neg, 1], tets[neg, 0].copy()
    return tets


def edge_ratios(points: np.ndarray, tets: np.ndarray, h: float) -> tuple[float, float]:
    """Mean and median length over ``h`` of the interior edges (at least one end off the boundary)."""
    tets = np.asarray(tets, dtype=np.int64)
    faces = np.sort(tets[:, [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]]].reshape(-1, 3), axis=1)
    uniq, count = np.unique(faces, axis=0, return_counts=True)
    on_boundary = np.zeros(len(points), dtype=bool)
    on_boundary[uniq[count == 1].ravel()] = True
    edges = np.unique(np.sort(tets[:, [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]]].reshape(-1, 2), axis=1), axis=0)
    edges = edges[~(on_boundary[edges[:, 0]] & on_boundary[edges[:, 1]])]
    length = np.linalg.norm(points[edges[:, 0]] - points[edges[:, 1]], axis=1) / h
    return float(length.mean()), float(np.median(length))


def calibrate(fn, surface, h: float, target: int, factor: float, name: str) -> float:
    """Size factor f with about ``target`` tets from ``fn(surface, f h)`` (untimed runs)."""
    for _ in range(4):
        count = len(fn(surface, factor * h)[1])
        print(f"calibrating {name}: factor {factor:.4f} -> {count:,} tets", file=sys.stderr)
        if abs(count / target - 1.0) < 0.05:
            break
        factor *= (count / target) ** (1.0 / 3.0)
    return factor


def run_meshwright(surface, h: float, radius_edge: float):
    from meshwright import tetrahedralize

    mesh = tetrahedralize(surface, size=h, radius_edge=radius_edge)
    return mesh.points, mesh.tetra


def run_tetgen(surface, h: float):
    import tetgen

    vmax = h**3 / (6.0 * SQRT2)
    gen = tetgen.TetGen(np.ascontiguousarray(surface.points), np.ascontiguousarray(surface.triangles, dtype=np.int32))
    nodes, elems = gen.tetrahedralize(switches=f"pq1.414a{vmax:.6g}Q")[:2]
    return nodes, oriented(nodes, elems)


def run_gmsh(surface, h: float, algorithm: int):
    """Gmsh 3-D mesher ``algorithm`` (1 Delaunay, 10 HXT) inside the given surface triangulation."""
    import gmsh

    gmsh.initialize(["-noenv"], readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.option.setNumber("Mesh.MaxNumThreads3D", 1)
        gmsh.option.setNumber("Mesh.Algorithm3D", algorithm)
        gmsh.option.setNumber("Mesh.MeshSizeMax", h)
        gmsh.model.add("sphere")
        s = gmsh.model.addDiscreteEntity(2)
        n = len(surface.points)
        gmsh.model.mesh.addNodes(2, s, np.arange(1, n + 1), surface.points.ravel())
        gmsh.model.mesh.addElementsByType(s, 2, [], (surface.triangles.astype(np.int64) + 1).ravel())
        loop = gmsh.model.geo.addSurfaceLoop([s])
        gmsh.model.geo.addVolume([loop])
        gmsh.model.geo.synchronize()
        gmsh.model.mesh.generate(3)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        _, nodes = gmsh.model.mesh.getElementsByType(4)
    finally:
        gmsh.finalize()
    index = np.zeros(int(tags.max()) + 1, dtype=np.int64)
    index[tags.astype(np.int64)] = np.arange(len(tags))
    points = np.ascontiguousarray(coords.reshape(-1, 3))
    return points, oriented(points, index[nodes.astype(np.int64)].reshape(-1, 4))


def methods(radius_edge: float) -> dict:
    """name -> callable(surface, h) -> (points, tets); peers that are absent are left out."""
    found = {"meshwright": lambda s, h: run_meshwright(s, h, radius_edge)}
    try:
        import tetgen  # noqa: F401

        found["tetgen"] = run_tetgen
    except ImportError:
        print("tetgen is absent: no TetGen column (pip install tetgen)", file=sys.stderr)
    try:
        import gmsh  # noqa: F401

        found["gmsh-delaunay"] = lambda s, h: run_gmsh(s, h, 1)
        found["gmsh-hxt"] = lambda s, h: run_gmsh(s, h, 10)
    except ImportError:
        print("gmsh is absent: no Gmsh columns (pip install gmsh)", file=sys.stderr)
    return found


# meshwright stage functions timed by --stages: (module, attribute, label)
STAGES = [
    ("meshwright.tet.mesher", "_unflatten", "unflatten (subface flags, classification, flat-tet flips)"),
    ("meshwright.tet.mesher", "classify", "  of which classify"),
    ("meshwright.tet.mesher", "carry_labels", "  of which carried labels (new tets flooded)"),
    ("meshwright.tet.mesher", "circumspheres", "circumspheres"),
    ("meshwright.tet.mesher", "bad_solid", "bad tets, one pass (queue rounds)"),
    ("meshwright.tet.mesher", "_bad", "bad tets"),
    ("meshwright.tet.mesher", "_new_caps", "crease caps"),
    ("meshwright.tet.mesher", "refine_in_queue", "refinement queue kernel"),
    ("meshwright.tet.mesher", "recover", "boundary recovery"),
    ("meshwright.tet.mesher", "bisect_marked", "subface splits"),
    ("meshwright.tet.mesher", "_remove_slivers", "sliver stage (with the final validation)"),
    ("meshwright.core.mesh.Mesh", "validate", "  of which Mesh.validate"),
    ("meshwright.tet.tetrahedralization.Tetrahedralization", "__init__", "initial Delaunay"),
]


def staged(fn):
    """``fn`` wrapped so that each call also returns {label: [seconds, calls]} of :data:`STAGES`."""
    import functools
    import importlib
    import time

    def run(*args):
        acc: dict = {}
        saved = []
        for where, name, label in STAGES:
            parts = where.split(".")
            for cut in range(len(parts), 0, -1):
                try:
                    owner = importlib.import_module(".".join(parts[:cut]))
                    break
                except ImportError:
                    continue
            for attr in parts[cut:]:
                owner = getattr(owner, attr)
            orig = getattr(owner, name, None)
            if orig is None:
                continue  # a stage this version does not have

            @functools.wraps(orig)
            def timed(*a, _orig=orig, _label=label, **k):
                t0 = time.perf_counter()
                try:
                    return _orig(*a, **k)
                finally:
                    cell = acc.setdefault(_label, [0.0, 0])
                    cell[0] += time.perf_counter() - t0
                    cell[1] += 1

            saved.append((owner, name, orig))
            setattr(owner, name, timed)
        try:
            return fn(*args), acc
        finally:
            for owner, name, orig in saved:
                setattr(owner, name, orig)

    return run


def quality_row(points: np.ndarray, tets: np.ndarray) -> dict:
    """Summary of the tetra quality measures of one mesh."""
    from meshwright.core.quality import tetra_quality

    q = tetra_quality(points, tets)
    return {
        "tets": len(tets),
        "min_dih": float(q["min_dihedral"].min()),
        "max_dih": float(q["max_dihedral"].max()),
        "rr_mean": float(q["radius_ratio"].mean()),
        "rr_min": float(q["radius_ratio"].min()),
        "slivers": int((q["sliver_ratio"] < 0.01).sum()),
        "below10": float((q["min_dihedral"] < 10.0).mean()),
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="sphere level 3 only (about 1e4 tets)")
    ap.add_argument("--levels", nargs="+", type=int, metavar="L", help="sphere subdivision levels to run")
    ap.add_argument("--radius-edge", type=float, default=1.414, help="meshwright's radius-edge bound")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-jit", action="store_true", help="skip the JIT compile-time measurement")
    ap.add_argument("--tets", type=int, metavar="N", help="calibrate each mesher's size factor to about N tets")
    ap.add_argument("--factor", action="append", default=[], metavar="NAME=F", help="a mesher's size factor (size F h)")
    ap.add_argument("--methods", nargs="+", metavar="NAME", help="run only these meshers (meshwright, tetgen, gmsh-delaunay, gmsh-hxt)")
    ap.add_argument("--stages", action="store_true", help="also print meshwright's seconds per stage (its best run)")
    args = ap.parse_args(argv)
    factors = {}
    for item in args.factor:
        name, _, value = item.partition("=")
        try:
            factors[name] = float(value)
        except ValueError:
            ap.error(f"--factor wants NAME=F, got {item!r}")

    if not args.no_jit:
        cold, cached = jit_compile_times(
            "from meshwright import tetrahedralize\n"
            "from meshwright.geometry import sphere\n"
            "tetrahedralize(sphere(level=1), size=0.5)"
        )
        print(f"JIT: import + first tetrahedralize, cold cache {cold:.2f} s, warm cache {cached:.2f} s\n")

    found = methods(args.radius_edge)
    if args.methods:
        unknown = sorted(set(args.methods) - set(found))
        if unknown:
            ap.error(f"--methods: {', '.join(unknown)} not available; choose from {', '.join(found)}")
        found = {name: fn for name, fn in found.items() if name in args.methods}
    # the level-3 sphere (about 1e4 tets): large enough that the warm-up also loads the
    # kernels only large meshes reach (the facet sort of Mesh.validate above 32,768 facets),
    # which a level-1 warm-up left to the timed run (0.3-0.6 s of the 1e6-tet one)
    warm, hw = sphere_case(WARM_LEVEL)
    for fn in found.values():
        fn(warm, hw)
    rows = []
    stage_rows: list = []
    for level in args.levels or (LEVELS_QUICK if args.quick else LEVELS_FULL):
        surface, h = sphere_case(level)
        results = {}
        for name, fn in found.items():
            try:
                f = factors.get(name, 1.0)
                if args.tets:
                    f = calibrate(fn, surface, h, args.tets, f, name)
                if args.stages and name == "meshwright":
                    runs = []
                    for _ in range(args.repeat if level < 5 else 1):
                        t0 = time.perf_counter()
                        out, acc = staged(fn)(surface, f * h)
                        runs.append((time.perf_counter() - t0, out, acc))
                    t, (points, tets), acc = min(runs, key=lambda r: r[0])
                    stage_rows += [
                        [f"L{level}", label, f"{acc[label][0]:.3f}", str(acc[label][1]), f"{100 * acc[label][0] / t:.1f}"]
                        for _, _, label in STAGES
                        if label in acc
                    ]
                    stage_rows.append([f"L{level}", "total", f"{t:.3f}", "1", "100.0"])
                else:
                    t, (points, tets) = best_time(lambda fn=fn, s=surface, hf=f * h: fn(s, hf), args.repeat if level < 5 else 1)
            except MeshwrightError as exc:  # a row saying why beats losing the other columns
                print(f"{name} failed on level {level}: {exc}", file=sys.stderr)
                continue
            results[name] = (t, f, edge_ratios(points, tets, h), quality_row(points, tets))
        ref = results.get("tetgen", (None,))[0]
        hxt = results.get("gmsh-hxt")
        for name, (t, f, (e_mean, e_median), q) in results.items():
            rows.append(
                [
                    f"sphere L{level} ({len(surface.triangles):,} faces, h {h:.4f})",
                    name,
                    f"{f:.3f}",
                    f"{t:.3f}",
                    f"{q['tets']:,}",
                    f"{q['tets'] / t:,.0f}",
                    f"{e_mean:.2f} / {e_median:.2f}",
                    f"{t / ref:.2f}" if ref else "-",
                    f"{t / hxt[0]:.2f}" if hxt else "-",
                    f"{(hxt[3]['tets'] / hxt[0]) / (q['tets'] / t):.2f}" if hxt else "-",
                    f"{q['min_dih']:.2f}",
                    f"{q['max_dih']:.2f}",
                    f"{q['rr_mean']:.3f}",
                    f"{q['rr_min']:.4f}",
                    str(q["slivers"]),
                    f"{100.0 * q['below10']:.3f}",
                ]
            )
            print(" | ".join(rows[-1]), file=sys.stderr)
    print_table(
        [
            "case",
            "method",
            "size factor",
            "time [s]",
            "tets",
            "tets/s",
            "edge/h mean / median",
            "x TetGen",
            "x HXT",
            "x HXT tets/s",
            "min dihedral",
            "max dihedral",
            "mean radius ratio",
            "min radius ratio",
            "a < 0.01",
            "% dihedral < 10",
        ],
        rows,
    )
    if stage_rows:
        print()
        print_table(["case", "meshwright stage", "seconds", "calls", "% of the run"], stage_rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
