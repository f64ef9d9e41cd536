"""3-D Delaunay (chapter 18.4.1): the eight-point box, its five tetrahedra, and insertions.

* the chapter's hexahedron of eight supplementary points split into five tetrahedra
  (steps 2-3 of 18.4.1), drawn exploded: four corner tets around the central one;
* twelve points inserted one by one into the box (step 4) and the box-attached tets
  removed: ``meshwright.delaunay(points, superstructure="box")``;
* three more points inserted incrementally (``Tetrahedralization.insert``);
* the same points with the default superstructure, a vertex at infinity: the full
  Delaunay tetrahedralization of the convex hull, with the hull tets the box lost in red.

Run::

    python examples/delaunay_3d.py [OUTPUT_DIR]
"""

from __future__ import annotations

import numpy as np
from _figures import output_dir, save

import meshwright as mw
from meshwright.tet.tetrahedralization import BOX_TETS

_EDGES = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]


def _axes(n: int):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(5.0 * n, 5.0))
    FigureCanvasAgg(fig)
    return fig, [fig.add_subplot(1, n, i + 1, projection="3d") for i in range(n)]


def _draw_tets(ax, points, tets, color="0.35", shrink=0.0, lw=0.8):
    """Edges of tets, each pulled towards its centroid by ``shrink`` (0: in place)."""
    from mpl_toolkits.mplot3d.art3d import Line3DCollection

    p = points[tets]
    p = p + shrink * (p.mean(axis=1, keepdims=True) - p)
    segs = [[q[i], q[j]] for q in p for i, j in _EDGES]
    ax.add_collection3d(Line3DCollection(segs, colors=color, linewidths=lw))


def _frame(ax, lo, hi, title):
    ax.set_xlim(lo, hi)
    ax.set_ylim(lo, hi)
    ax.set_zlim(lo, hi)
    ax.set_title(title)


def main() -> None:
    out = output_dir()
    fig, (a0, a1, a2, a3) = _axes(4)

    i = np.arange(8)
    cube = np.column_stack([i & 1, (i >> 1) & 1, (i >> 2) & 1]).astype(float)
    for t, color in zip(BOX_TETS, ["C3", "C0", "C1", "C2", "C4"]):
        _draw_tets(a0, cube, t[None, :], color=color, shrink=0.25, lw=1.5)
    a0.scatter(*cube.T, color="k", s=12)
    _frame(a0, -0.1, 1.1, "box: 8 points, 5 tetrahedra (exploded)")

    pts = np.random.default_rng(7).random((12, 3))
    box = mw.delaunay(pts, superstructure="box", seed=1)
    _draw_tets(a1, box.points, box.tetrahedra)
    a1.scatter(*pts.T, color="C0", s=14)
    _frame(a1, 0.0, 1.0, f"12 points in the box: {len(box.tetrahedra)} tets kept")

    new = np.array([[0.5, 0.5, 0.5], [0.3, 0.7, 0.4], [0.6, 0.2, 0.7]])
    box.insert(new)
    _draw_tets(a2, box.points, box.tetrahedra)
    a2.scatter(*pts.T, color="C0", s=14)
    a2.scatter(*new.T, color="C3", s=30)
    _frame(a2, 0.0, 1.0, f"3 insertions: {len(box.tetrahedra)} tets")

    ghost = mw.delaunay(np.vstack([pts, new]), seed=1)
    kept = {tuple(t) for t in np.sort(box.tetrahedra, axis=1).tolist()}
    lost = np.array([t for t in ghost.tetrahedra if tuple(sorted(t)) not in kept]).reshape(-1, 4)
    _draw_tets(a3, ghost.points, ghost.tetrahedra)
    if len(lost):
        _draw_tets(a3, ghost.points, lost, color="C3", lw=1.6)
    _frame(a3, 0.0, 1.0, f"vertex at infinity: {len(ghost.tetrahedra)} tets, {len(lost)} lost by the box")
    print(f"box: {len(box.tetrahedra)} tets; convex hull: {len(ghost.tetrahedra)} tets, {len(lost)} hull tets lost")
    save(fig, out / "delaunay_3d.png")


if __name__ == "__main__":
    main()
