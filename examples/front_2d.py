"""Advancing front (chapter 18.2): the hexagon of Figure 18.2.2, smoothing as in Figure
18.2.4, a stretched background grid, and NACA 0012.

* the hexagon with its six boundary nodes as the initial front and the spacing of its
  sides: the front adds a couple of interior nodes and closes;
* a disk meshed with the front, then with five spring-analogy smoothing passes;
* a rectangle under a uniform background grid with spacing delta = 0.05, stretching s = 4
  along alpha = 30 degrees: elements 4 delta long along alpha (printed: the median aspect
  ratio and direction of the triangles);
* NACA 0012 in a far field (the built-in domain and its graded size).

Run::

    python examples/front_2d.py [OUTPUT_DIR]
"""

from __future__ import annotations

import numpy as np
from _figures import output_dir, panels, save, zoom

import meshwright as mw
from meshwright.geometry import circle, polygon
from meshwright.sizing import BackgroundGrid


def _aspect_and_direction(mesh):
    p = mesh.points[mesh.cells["triangle"]]
    d = p - p.mean(axis=1, keepdims=True)
    w, v = np.linalg.eigh(np.einsum("tki,tkj->tij", d, d))
    return np.sqrt(w[:, 1] / w[:, 0]), np.degrees(np.arctan2(v[:, 1, 1], v[:, 0, 1])) % 180.0


def main() -> None:
    out = output_dir()
    fig, axes = panels(4)

    angles = np.radians(np.arange(6) * 60.0)
    hexagon = polygon(np.column_stack([np.cos(angles), np.sin(angles)]))
    mesh = mw.triangulate(hexagon, size=1.0, method="front")
    mesh.validate()
    mesh.plot(ax=axes[0])
    for i, (x, y) in enumerate(mesh.points):
        axes[0].annotate(str(i + 1), (x, y), textcoords="offset points", xytext=(4, 4))
    axes[0].set_title(f"Figure 18.2.2: hexagon, {len(mesh.cells['triangle'])} triangles")

    raw = mw.triangulate(circle(), size=0.12, method="front")
    smooth = mw.triangulate(circle(), size=0.12, method="front", smooth=5)
    for m, name in ((raw, "front"), (smooth, "front + 5 smoothing passes")):
        q = m.quality().summary()["triangle"]
        print(f"disk, {name}: mean radius ratio {q['radius_ratio']['mean']:.4f}, min angle {q['min_angle']['min']:.1f}")
    smooth.plot(ax=axes[1])
    axes[1].set_title("Figure 18.2.4: front, then smoothing")

    rect = polygon([(0, 0), (4, 0), (4, 1), (0, 1)])
    bg = BackgroundGrid.uniform(rect.bbox, 0.05, stretch=4.0, direction=np.radians(30.0))
    stretched = mw.triangulate(rect, bg, method="front")
    stretched.validate()
    aspect, direction = _aspect_and_direction(stretched)
    print(f"stretched: median aspect {np.median(aspect):.2f} (s = 4), median direction {np.median(direction):.1f} deg (30)")
    stretched.plot(ax=axes[2])
    zoom(axes[2], (0, 2), (0, 1))
    axes[2].set_title("s = 4 along 30 degrees")

    naca = mw.triangulate("naca0012", method="front")
    naca.validate()
    naca.plot(ax=axes[3])
    zoom(axes[3], (-0.2, 1.2), (-0.5, 0.5))
    axes[3].set_title(f"NACA 0012, {len(naca.cells['triangle'])} triangles")
    save(fig, out / "front.png")
    naca.write(str(out / "naca0012-front.vtu"))


if __name__ == "__main__":
    main()
