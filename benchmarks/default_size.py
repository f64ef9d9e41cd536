"""Benchmark: what every ``triangulate`` method gives on Triangle's example files with no size.

Usage::

    python benchmarks/default_size.py                  # every method, every example .poly
    python benchmarks/default_size.py --size boundary  # the chapter's boundary spacing instead
    python benchmarks/default_size.py --files A face   # a subset

The inputs are the ``.poly`` files that ship in the ``triangle`` package's ``data`` folder
(Triangle's outputs ``*.1.poly`` etc. excluded); ``box.poly`` is meshed with
``convex_hull=True`` (Triangle ``-c``).  Reported per file and method: minimum angle
(degrees) and triangle count, next to Triangle's ``pq30`` (``pcq30`` for box;
for ``la.poly``, whose regions carry area bounds that every meshwright method honours,
also ``pq30a`` with the bounds as Triangle's own reader takes them) and the count ratio.
Issue 14's targets: min angle >= 20 degrees (``delaunay`` >= 30) and at most 3x
Triangle's count.  Where two segments meet below 20 degrees (la.poly) no mesh can reach
that at the apex, and Ruppert's guarantee does not hold in the wedge: the angle away from
them (triangles whose centroid lies farther than the shorter of the two segments from
such a vertex) is given in brackets, for Triangle too.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np


def min_angle(points: np.ndarray, triangles: np.ndarray) -> float:
    """Smallest interior angle (degrees) of the triangles."""
    p = points[triangles]
    worst = 180.0
    for k in range(3):
        u = p[:, (k + 1) % 3] - p[:, k]
        v = p[:, (k + 2) % 3] - p[:, k]
        cos = np.einsum("ij,ij->i", u, v) / (np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1))
        worst = min(worst, float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))).min()))
    return worst


def small_input_angles(disc, limit: float) -> np.ndarray:
    """(k, 3) rows (x, y, r): a vertex where two segments meet below ``limit`` degrees and
    the shorter of the two; Ruppert's guarantee does not hold within r of it."""
    p, s = disc.points, disc.segments
    rows = []
    for v in range(len(p)):
        nbr = np.concatenate([s[s[:, 0] == v, 1], s[s[:, 1] == v, 0]])
        for i in range(len(nbr)):
            for j in range(i + 1, len(nbr)):
                u, w = p[nbr[i]] - p[v], p[nbr[j]] - p[v]
                cos = u @ w / (np.linalg.norm(u) * np.linalg.norm(w))
                if np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))) < limit:
                    rows.append((*p[v], min(np.linalg.norm(u), np.linalg.norm(w))))
    return np.array(rows, dtype=float).reshape(-1, 3)


def min_angle_away(points: np.ndarray, triangles: np.ndarray, small: np.ndarray) -> float:
    """:func:`min_angle` of the triangles whose centroid lies outside every small angle's disk."""
    centre = points[triangles].mean(axis=1)
    near = np.hypot(centre[:, None, 0] - small[None, :, 0], centre[:, None, 1] - small[None, :, 1])
    return min_angle(points, triangles[~(near <= small[None, :, 2]).any(axis=1)])


def examples(folder: Path, names) -> list[Path]:
    """The example inputs: every ``*.poly`` without a numbered output suffix."""
    paths = [p for p in sorted(folder.glob("*.poly")) if "." not in p.stem]
    return [p for p in paths if not names or p.stem in names]


def reference(triangle, path: Path) -> list[tuple[str, int, dict]]:
    """Triangle's own meshes of the file: (flags, triangle count, Triangle's output)."""
    flags = "pcq30" if path.stem == "box" else "pq30"
    data = triangle.load(str(path.parent), path.stem)
    if path.stem == "la":
        # Triangle's reader takes a region line's third number as the attribute and copies
        # it into the missing area bound; the package's loader does not.
        data["regions"][:, 2] = data["regions"][:, 3]
    ref = triangle.triangulate(data, flags)
    out = [(flags, len(ref["triangles"]), ref)]
    if path.stem == "la":
        ref = triangle.triangulate(data, "pq30a")
        out.append(("pq30a", len(ref["triangles"]), ref))
    return out


def main(argv=None) -> int:
    import triangle

    import meshwright as mw
    from meshwright.geometry import read_poly

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", default=None, help="size passed to triangulate (default None; 'boundary')")
    ap.add_argument("--files", nargs="*", default=None, help="file stems (default: every example)")
    ap.add_argument("--methods", nargs="*", default=None, help="methods (default: every MESH_METHODS key)")
    args = ap.parse_args(argv)
    folder = Path(triangle.__file__).parent / "data"
    methods = args.methods or list(mw.MESH_METHODS)
    size = args.size
    if size is not None and size != "boundary":
        size = float(size)
    print(f"size={size!r}")
    print("| file | Triangle | " + " | ".join(methods) + " |")
    print("|---|---|" + "---|" * len(methods))
    for path in examples(folder, args.files):
        refs = reference(triangle, path)
        dom = read_poly(path)
        small = small_input_angles(dom.discretize(), 20.0)
        base = refs[-1][1]

        def angle(points, triangles, small=small) -> str:
            text = f"{min_angle(points, triangles):.1f}°"
            return text + (f" ({min_angle_away(points, triangles, small):.1f}° away)" if len(small) else "")

        cells = []
        for m in methods:
            t0 = time.perf_counter()
            try:
                mesh = mw.triangulate(dom, size, method=m, convex_hull=path.stem == "box")
            except mw.MeshwrightError as exc:
                cells.append(f"failed: {type(exc).__name__}")
                continue
            dt = time.perf_counter() - t0
            n = len(mesh.triangles)
            cells.append(f"{angle(mesh.points, mesh.triangles)}, {n} ({n / base:.2f}x), {dt:.1f} s")
        ref = "; ".join(f"`{f}` {angle(r['vertices'], r['triangles'])}, {n}" for f, n, r in refs)
        print(f"| `{path.name}` | {ref} | " + " | ".join(cells) + " |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
