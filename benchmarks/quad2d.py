"""Benchmark: 2-D quad meshing, meshwright (every quadrangulate method) vs Gmsh.

Usage::

    python benchmarks/quad2d.py            # disk h = 0.01, NACA 0012, three-element airfoil
    python benchmarks/quad2d.py --quick    # coarser sizes, a smoke run
    python benchmarks/quad2d.py --no-gmsh  # meshwright only
    python benchmarks/quad2d.py --no-jit   # skip the cold / cached JIT compile measurement
    python benchmarks/quad2d.py --methods pairing zhu   # some meshwright methods only (Gmsh still runs)

Cases (every method meshes the same domain in one process, after a JIT warm-up; every
meshwright run comes before the first Gmsh call, so none is timed in a process that Gmsh
has left threads or heap in):

* ``disk``: unit disk, uniform size ``h`` (0.01; 0.04 with ``--quick``);
* ``naca0012``: the built-in NACA 0012 in a far field of radius 10 chords, with half its
  own graded size (0.01 chord at the surface growing by 25 % to 2.5, all times 0.5;
  the size as it is with ``--quick``);
* ``three-element``: the built-in three-element airfoil (Figure 18.3.1), half its own
  graded size (as it is with ``--quick``).

meshwright runs every method of :data:`meshwright.quad.QUAD_METHODS` all-quad (the
default).  Gmsh (the ``gmsh`` Python package; skipped cleanly when absent) gets the same
geometry built from the domain's discretised boundary (points, lines, curve loops and a
plane surface with holes), mesh size at every boundary point equal to its mean segment
length, Frontal-Delaunay for quads (``Mesh.Algorithm 8``) with Blossom recombination
(``Mesh.RecombinationAlgorithm 1``, ``Mesh.RecombineAll 1``), once as it is (quad
dominant: it may leave triangles) and once with the all-quad subdivision
(``Mesh.SubdivisionAlgorithm 1``).  The interior size is Gmsh's own field reproducing the
case's (a constant, or ``min(hmax, h0 + slope d)`` by Distance and Threshold fields, ``d``
the distance to the holes' lines) and point sizes are off.  The subdivision splits every
element into four and halves the spacing, so that run gets the boundary and the field at
twice the size (what meshwright's quadtree does before its own midpoint split).  Measured
with Gmsh 4.15: its algorithm 8 splits each boundary line in two (twice meshwright's
boundary edges, the ``boundary edges`` column) while its interior quads come out at the
requested size (quad counts close to the pairing's); the quadtree has more quads because
its boundary gap's triangles become three quads each.

Every metric is computed by meshwright's own :func:`meshwright.core.quality.quad_quality`
on the quads of both meshes: quads per second (wall time, best of ``--repeat``, of the
whole call, Gmsh's geometry set-up included; ``cpu [s]`` the process CPU time of the same
calls, best of the runs, which a loaded machine inflates far less than the wall time:
``cpu rate x subdivision`` is the quads per CPU second against the subdivision's), the
fraction of quads among the cells,
min / mean scaled Jacobian, min / max interior angle, and the throughput relative to
each Gmsh run.  The JIT compile time of ``import meshwright`` plus a first small
:func:`meshwright.quadrangulate` of every method is reported cold (empty Numba cache)
and cached.
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

from _harness import best_time, gmsh_plane_surface, jit_compile_times, print_table

GMSH_BLOSSOM = "gmsh 8 + blossom"
GMSH_SUBDIV = "gmsh 8 + blossom + subdivision"


# The built-in airfoils' size (meshwright.geometry.shapes): h(x) = min(hmax, H_WALL +
# SLOPE * distance to the airfoil), hmax = 2.5 (a quarter of the far-field radius 10).
H_WALL, SLOPE, HMAX = 0.01, 0.25, 2.5


def cases(quick: bool) -> list[tuple[str, object, object, tuple]]:
    """(label, domain, size field, grading) of the three cases.

    ``grading`` = (h0, slope, hmax): the size is ``min(hmax, h0 + slope * d)`` with ``d``
    the distance to the domain's holes (slope 0: uniform ``h0``), which Gmsh reproduces
    with its own Distance and Threshold fields.
    """
    from meshwright.geometry import builtin, circle
    from meshwright.sizing import as_size_field

    h, scale = (0.04, 1.0) if quick else (0.01, 0.5)
    out = [(f"disk h={h:g}", circle(), as_size_field(h), (h, 0.0, h))]
    for name in ("naca0012", "three-element"):
        dom = builtin(name)
        field = as_size_field(lambda xy, f=dom.size: scale * f(xy))
        out.append((f"{name} x{scale:g}", dom, field, (scale * H_WALL, scale * SLOPE, scale * HMAX)))
    return out



def run_gmsh(domain, size, grading, subdivide: bool):
    """Gmsh Frontal-Delaunay for quads + Blossom (optionally subdivided) on the domain's boundary.

    The boundary is the domain discretised at ``k * size`` and the interior size Gmsh's own
    ``min(k hmax, k h0 + k slope d)`` (Distance to the holes' lines, Threshold), with
    ``k`` = 1, or 2 with the subdivision (module docstring).

    Returns (points (n, 2), quads (q, 4), triangles (t, 3)), 0-based.
    """
    import gmsh

    from meshwright.sizing import as_size_field

    k = 2.0 if subdivide else 1.0
    h0, slope, hmax = (k * g for g in grading)
    disc = domain.discretize(as_size_field(lambda xy, f=size: k * f(xy)))
    points, segments = disc.points, disc.segments
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.option.setNumber("Mesh.Algorithm", 8)
        gmsh.option.setNumber("Mesh.RecombinationAlgorithm", 1)
        gmsh.option.setNumber("Mesh.RecombineAll", 1)
        gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 1 if subdivide else 0)
        gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
        gmsh.model.add("bench")
        hole_lines = gmsh_plane_surface(gmsh, points, segments)
        if slope > 0.0:
            dist = gmsh.model.mesh.field.add("Distance")
            gmsh.model.mesh.field.setNumbers(dist, "CurvesList", hole_lines)
            gmsh.model.mesh.field.setNumber(dist, "Sampling", 4)
            grade = gmsh.model.mesh.field.add("Threshold")
            gmsh.model.mesh.field.setNumber(grade, "InField", dist)
            for key, value in (("SizeMin", h0), ("SizeMax", hmax), ("DistMin", 0.0),
                               ("DistMax", (hmax - h0) / slope)):
                gmsh.model.mesh.field.setNumber(grade, key, value)
        else:
            grade = gmsh.model.mesh.field.add("MathEval")
            gmsh.model.mesh.field.setString(grade, "F", repr(h0))
        gmsh.model.mesh.field.setAsBackgroundMesh(grade)
        gmsh.model.mesh.generate(2)
        node_tags, xyz, _ = gmsh.model.mesh.getNodes()
        order = np.empty(int(node_tags.max()) + 1, dtype=np.int64)
        order[node_tags.astype(np.int64)] = np.arange(len(node_tags))
        blocks = []
        for etype, k in ((3, 4), (2, 3)):  # 4-node quadrangle, 3-node triangle
            _, nodes = gmsh.model.mesh.getElementsByType(etype)
            blocks.append(order[nodes.astype(np.int64)].reshape(-1, k))
        return xyz.reshape(-1, 3)[:, :2], blocks[0], blocks[1]
    finally:
        gmsh.finalize()


def quality(points, quads, triangles) -> dict:
    """Boundary edges (used by one cell), quad fraction, the quads' scaled Jacobian and angles."""
    from meshwright.core.quality import quad_quality

    q = quad_quality(np.ascontiguousarray(points, dtype=np.float64), np.asarray(quads))
    edges = np.sort(np.vstack([np.asarray(quads)[:, [k, (k + 1) % 4]] for k in range(4)]
                              + [np.asarray(triangles)[:, [k, (k + 1) % 3]] for k in range(3)]), axis=1)
    _, count = np.unique(edges, axis=0, return_counts=True)
    return {
        "boundary": int((count == 1).sum()),
        "frac": len(quads) / max(1, len(quads) + len(triangles)),
        "sj_min": float(q["scaled_jacobian"].min()),
        "sj_mean": float(q["scaled_jacobian"].mean()),
        "ang_min": float(q["min_angle"].min()),
        "ang_max": float(q["max_angle"].max()),
    }


def methods(gmsh_too: bool, only=None) -> dict:
    """Name -> callable(domain, size, grading) -> (points, quads, triangles); ``only``: the
    meshwright methods to run (default: every ``QUAD_METHODS`` entry)."""
    from meshwright.quad import QUAD_METHODS, quadrangulate

    def mw(method):
        def go(domain, size, grading):
            m = quadrangulate(domain, size, method=method)
            return m.points, m.cells["quad"], m.cells.get("triangle", np.zeros((0, 3), np.int32))

        return go

    unknown = sorted(set(only or ()) - set(QUAD_METHODS))
    if unknown:
        raise SystemExit(f"unknown quad method(s) {', '.join(unknown)}; choose from {', '.join(sorted(QUAD_METHODS))}")
    found = {f"meshwright {name}": mw(name) for name in QUAD_METHODS if not only or name in only}
    if gmsh_too:
        try:
            import gmsh  # noqa: F401
        except ImportError:
            print("gmsh not installed: meshwright only", file=sys.stderr)
        else:
            found[GMSH_BLOSSOM] = lambda d, s, g: run_gmsh(d, s, g, False)
            found[GMSH_SUBDIV] = lambda d, s, g: run_gmsh(d, s, g, True)
    return found


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="coarser sizes")
    ap.add_argument("--repeat", type=int, default=1, help="timed runs per method (best is reported)")
    ap.add_argument("--no-gmsh", action="store_true", help="skip Gmsh")
    ap.add_argument("--no-jit", action="store_true", help="skip the cold / cached JIT compile measurement")
    ap.add_argument("--methods", nargs="+", metavar="METHOD", help="meshwright methods to run (default: all)")
    args = ap.parse_args(argv)

    if not args.no_jit:
        cold, cached = jit_compile_times(
            "from meshwright.quad import QUAD_METHODS, quadrangulate\n"
            "for m in QUAD_METHODS: quadrangulate('circle', 0.25, method=m)"
        )
        print(f"JIT: import + first quadrangulate (every method), cold cache {cold:.2f} s, warm cache {cached:.2f} s\n")

    from meshwright.geometry import circle
    from meshwright.sizing import as_size_field

    found = methods(not args.no_gmsh, args.methods)
    all_cases = cases(args.quick)
    timed = {label: {} for label, *_ in all_cases}
    # meshwright first, every case, then the peers: a Gmsh call leaves its own threads and heap
    # behind in the process, so no meshwright timing follows one (the twelfth session saw
    # meshwright 20-45 % slower after Gmsh, not reproduced since; the order rules it out).
    peers = [name for name in found if not name.startswith("meshwright")]
    for group in ([name for name in found if name not in peers], peers):
        for name in group:
            found[name](circle(), as_size_field(0.25), (0.25, 0.0, 0.25))
        for label, domain, size, grading in all_cases:
            for name in group:
                fn, cpu = found[name], []

                def run(fn=fn, cpu=cpu, d=domain, s=size, g=grading):
                    c0 = time.process_time()
                    out = fn(d, s, g)
                    cpu.append(time.process_time() - c0)
                    return out

                t, (pts, quads, tris) = best_time(run, args.repeat)
                timed[label][name] = (t, len(quads), quality(pts, quads, tris), min(cpu))
                print(f"done {label}: {name} {t:.2f} s (cpu {min(cpu):.2f} s)", file=sys.stderr)

    rows = []
    for label, *_ in all_cases:
        results = {name: timed[label][name] for name in found}
        refs = [results.get(GMSH_BLOSSOM), results.get(GMSH_SUBDIV)]
        sub = results.get(GMSH_SUBDIV)
        for name, (t, nq, q, c) in results.items():
            rate = nq / t
            rows.append([
                label, name, f"{t:.3f}", f"{c:.3f}", f"{nq:,}", f"{q['boundary']:,}", f"{rate:,.0f}", f"{q['frac']:.3f}",
                f"{q['sj_min']:.3f}", f"{q['sj_mean']:.3f}", f"{q['ang_min']:.1f}", f"{q['ang_max']:.1f}",
                *(f"{rate / (r[1] / r[0]):.2f}" if r else "-" for r in refs),
                f"{(nq / c) / (sub[1] / sub[3]):.2f}" if sub else "-",
            ])
    print_table(
        ["case", "method", "time [s]", "cpu [s]", "quads", "boundary edges", "quads/s", "quad fraction", "min SJ",
         "mean SJ", "min angle", "max angle", "quads/s x blossom", "quads/s x subdivision", "cpu rate x subdivision"],
        rows,
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
