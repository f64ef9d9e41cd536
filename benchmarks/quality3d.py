"""Benchmark: quality tetrahedral meshes of the unit sphere, meshwright vs TetGen and Gmsh.

Usage::

    python benchmarks/quality3d.py            # the issue's sizes: about 1e5 and 1e6 tets
    python benchmarks/quality3d.py --quick    # about 1e4 tets, a smoke run
    python benchmarks/quality3d.py --levels 4 --repeat 1

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

Quality is computed by :func:`meshwright.core.quality.tetra_quality` for every mesher
(peers' tets reoriented positive first): minimum and maximum dihedral angle, mean and
minimum radius ratio (``3 r / R``, 1 for the regular tetrahedron), the chapter's sliver
flag ``a = r / R < 0.01`` count, and the fraction of tets with a dihedral angle below
10 degrees.  Times are wall times, best of ``--repeat`` (once at 1e6 tets), after a JIT
warm-up; the JIT compile time of ``import meshwright`` plus a first small
``tetrahedralize`` is reported cold (empty Numba cache) and cached.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

from _harness import best_time, jit_compile_times, print_table
from meshwright.core.errors import MeshwrightError

SQRT2 = np.sqrt(2.0)
LEVELS_FULL = [4, 5]  # about 1e5 and 1e6 tets at the surface's own edge length
LEVELS_QUICK = [3]  # about 1e4


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
    args = ap.parse_args(argv)

    if not args.no_jit:
        cold, cached = jit_compile_times(
            "from meshwright import tetrahedralize\n"
            "from meshwright.geometry import sphere\n"
            "tetrahedralize(sphere(level=1), size=0.5)"
        )
        print(f"JIT: import + first tetrahedralize, cold cache {cold:.2f} s, warm cache {cached:.2f} s\n")

    found = methods(args.radius_edge)
    warm, hw = sphere_case(1)
    for fn in found.values():
        fn(warm, hw)
    rows = []
    for level in args.levels or (LEVELS_QUICK if args.quick else LEVELS_FULL):
        surface, h = sphere_case(level)
        results = {}
        for name, fn in found.items():
            try:
                t, (points, tets) = best_time(lambda fn=fn, s=surface, h=h: fn(s, h), args.repeat if level < 5 else 1)
            except MeshwrightError as exc:  # a row saying why beats losing the other columns
                print(f"{name} failed on level {level}: {exc}", file=sys.stderr)
                continue
            results[name] = (t, quality_row(points, tets))
        ref = results.get("tetgen", (None,))[0]
        hxt = results.get("gmsh-hxt", (None,))[0]
        for name, (t, q) in results.items():
            rows.append(
                [
                    f"sphere L{level} ({len(surface.triangles):,} faces, h {h:.4f})",
                    name,
                    f"{t:.3f}",
                    f"{q['tets']:,}",
                    f"{q['tets'] / t:,.0f}",
                    f"{t / ref:.2f}" if ref else "-",
                    f"{t / hxt:.2f}" if hxt else "-",
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
            "time [s]",
            "tets",
            "tets/s",
            "x TetGen",
            "x HXT",
            "min dihedral",
            "max dihedral",
            "mean radius ratio",
            "min radius ratio",
            "a < 0.01",
            "% dihedral < 10",
        ],
        rows,
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
