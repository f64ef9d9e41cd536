"""Benchmark: 2-D quality meshing, meshwright (every triangulate method) vs Triangle and Gmsh.

Usage::

    python benchmarks/quality2d.py            # unit disk (~460k triangles) and NACA 0012
    python benchmarks/quality2d.py --quick    # small sizes, a smoke run
    python benchmarks/quality2d.py --no-gmsh  # skip Gmsh (its 2-D meshers are slow here)

Cases (all methods get the same boundary points, in one process, after a JIT warm-up):

* ``disk``: unit disk, 1256 equally spaced boundary points (spacing h = 0.005), minimum
  angle 30 degrees.  Triangle runs ``pq30a<A>Q`` with ``A = sqrt(3)/4 h^2``, the area of the
  equilateral triangle of side h (about 460k triangles); meshwright gets ``size = h`` and
  ``max_area = A`` for ``delaunay`` (the other meshwright methods get the size h only);
  Gmsh gets mesh size h at every boundary point.
* ``naca0012``: NACA 0012 (unit chord) in a circular far field of radius 10 chords, graded
  size 1e-3 chord at the surface growing by 20 % per unit length up to 1 chord
  (:func:`meshwright.sizing.gradation`).  Triangle runs ``pq30Q`` (its refinement grades
  from the boundary spacing by itself) and Gmsh extends the boundary point sizes.

Reported per method: wall time (best of ``--repeat``), triangles per second, minimum angle,
mean and minimum radius ratio (``2r/R``, 1 for equilateral), and the time and triangle
count relative to Triangle, and the throughput relative to Gmsh's Frontal-Delaunay (issue
targets for the frontal methods are multiples of it).  The JIT compile time of ``import meshwright`` plus a first
small :func:`meshwright.tri.triangulate` is reported cold (empty Numba cache) and cached.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

from _harness import best_time, gmsh_plane_surface, jit_compile_times, print_table


def disk_case(n: int):
    """Unit-disk domain with ``n`` boundary points; returns (domain, size, max_area)."""
    from meshwright.geometry import circle

    h = 2.0 * np.sin(np.pi / n)  # chord of the polygon inscribed with n vertices
    return circle(), h, np.sqrt(3.0) / 4.0 * h * h


def naca_case(h_wall: float, hmax: float):
    """NACA 0012 in a far field of radius 10 chords with a graded size; returns (domain, size)."""
    from meshwright.geometry import airfoil_in_farfield, naca_loop
    from meshwright.sizing import gradation

    loop = naca_loop("0012")
    surface = loop[0].evaluate(loop[0].fine_params())
    size = gradation(surface, h_wall, 1.2, hmax)
    return airfoil_in_farfield([loop], radius=10.0), size


def boundary_of(domain, size):
    """The discretised boundary every method shares: (points (n, 2), segments (m, 2), holes (h, 2))."""
    disc = domain.discretize(size)
    return disc.points, disc.segments, disc.holes


def run_triangle(points, segments, holes, max_area):
    import triangle

    opts = "pq30Q" + ("" if max_area is None else f"a{max_area:.12f}")
    data = {"vertices": points, "segments": segments}
    if len(holes):
        data["holes"] = holes
    r = triangle.triangulate(data, opts)
    return r["vertices"], r["triangles"]


def run_gmsh(points, segments, holes, algorithm: int):
    """Gmsh 2-D mesher ``algorithm`` (5 Delaunay, 6 Frontal-Delaunay) on the same boundary.

    Mesh size at every boundary point is its mean segment length (Weatherill's dP), which
    Gmsh extends into the interior; one thread, as the other methods.
    """
    import gmsh

    from meshwright.sizing import point_distribution

    dp = point_distribution(points, segments)
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.option.setNumber("Mesh.Algorithm", algorithm)
        gmsh.model.add("bench")
        gmsh_plane_surface(gmsh, points, segments, dp)
        gmsh.model.mesh.generate(2)
        node_tags, xyz, _ = gmsh.model.mesh.getNodes()
        _, elem_nodes = gmsh.model.mesh.getElementsByType(2)
        order = np.empty(int(node_tags.max()) + 1, dtype=np.int64)
        order[node_tags.astype(np.int64)] = np.arange(len(node_tags))
        return xyz.reshape(-1, 3)[:, :2], order[elem_nodes.astype(np.int64)].reshape(-1, 3)
    finally:
        gmsh.finalize()



def quality(points, triangles) -> dict:
    """Minimum angle (degrees), mean and minimum radius ratio of a triangle set."""
    from meshwright.core.quality import triangle_quality

    q = triangle_quality(np.asarray(points, dtype=np.float64), np.asarray(triangles))
    return {
        "min_angle": float(q["min_angle"].min()),
        "rr_mean": float(q["radius_ratio"].mean()),
        "rr_min": float(q["radius_ratio"].min()),
    }


def methods(gmsh_too: bool) -> dict:
    """Name -> callable(domain, size, max_area, boundary) -> (points, triangles)."""
    from meshwright.tri import MESH_METHODS, triangulate

    def mw(method, relax=None):
        # Delaunay refinement gets Triangle's area bound; the frontal and Weatherill methods,
        # like Gmsh, only the size h (an area bound would re-refine their regular layers).
        def go(domain, size, max_area, boundary):
            area = max_area if method == "delaunay" else None
            # min_angle only where it was always honoured (the others would add a refinement pass).
            angle = 30.0 if method == "delaunay" else None
            m = triangulate(domain, size, method=method, max_area=area, min_angle=angle, relax=relax)
            return m.points, m.cells["triangle"]

        return go

    found = {f"meshwright {name}": mw(name) for name in MESH_METHODS}
    # The relaxing methods as made, too: relaxation's cost and gain (meshwright.tri.relax).
    found.update({f"meshwright {name} relax=False": mw(name, False) for name, m in MESH_METHODS.items() if m.relaxes})
    try:
        import triangle  # noqa: F401

        found["triangle"] = lambda d, s, a, b: run_triangle(*b, a)
    except ImportError:
        pass
    if gmsh_too:
        try:
            import gmsh  # noqa: F401

            found["gmsh delaunay (5)"] = lambda d, s, a, b: run_gmsh(*b, 5)
            found["gmsh frontal-delaunay (6)"] = lambda d, s, a, b: run_gmsh(*b, 6)
        except ImportError:
            pass
    return found


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="small sizes only")
    ap.add_argument("--repeat", type=int, default=1, help="timed runs per method (best is reported)")
    ap.add_argument("--no-gmsh", action="store_true", help="skip Gmsh")
    args = ap.parse_args(argv)

    cold, cached = jit_compile_times(
        "from meshwright.tri import triangulate\n"
        "from meshwright.tri import MESH_METHODS\n"
        "for m in MESH_METHODS: triangulate('circle', 0.2, method=m)"
    )
    print(f"JIT: import + first triangulate (every method), cold cache {cold:.2f} s, warm cache {cached:.2f} s\n")

    found = methods(not args.no_gmsh)
    warm_domain, warm_size, warm_area = disk_case(64)
    warm_boundary = boundary_of(warm_domain, warm_size)
    for fn in found.values():
        fn(warm_domain, warm_size, warm_area, warm_boundary)

    disk = disk_case(314 if args.quick else 1256)
    naca_domain, naca_size = naca_case(1e-2 if args.quick else 1e-3, 1.0)
    cases = [
        ("disk n=%d" % (314 if args.quick else 1256), disk[0], disk[1], disk[2]),
        ("naca0012 graded", naca_domain, naca_size, None),
    ]
    rows = []
    for label, domain, size, max_area in cases:
        boundary = boundary_of(domain, size)
        results = {}
        for name, fn in found.items():
            t, (pts, tris) = best_time(lambda: fn(domain, size, max_area, boundary), args.repeat)
            results[name] = (t, len(tris), quality(pts, tris))
            print(f"done {label}: {name} {t:.2f} s", file=sys.stderr)
        ref = results.get("triangle")
        gfd = results.get("gmsh frontal-delaunay (6)")
        for name, (t, nt, q) in results.items():
            rows.append([
                label, name, f"{t:.3f}", f"{nt:,}", f"{nt / t:,.0f}", f"{q['min_angle']:.2f}",
                f"{q['rr_mean']:.4f}", f"{q['rr_min']:.4f}",
                f"{t / ref[0]:.2f}" if ref else "-", f"{nt / ref[1]:.2f}" if ref else "-",
                f"{(nt / t) / (gfd[1] / gfd[0]):.1f}" if gfd else "-",
            ])
    print_table(
        ["case", "method", "time [s]", "triangles", "tri/s", "min angle", "mean 2r/R", "min 2r/R",
         "time x Triangle", "tris x Triangle", "tri/s x Gmsh (6)"],
        rows,
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
