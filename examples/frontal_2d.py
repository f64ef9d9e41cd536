"""Frontal Delaunay (chapter 18.3) on the three-element airfoil of Figure 18.3.1.

Size 2e-4 chord at the walls, growing by 25 % per unit length up to 4 chords in a far field
of radius 20 chords: a size ratio above 1e4 between the smallest and the largest element.
Points are placed one at a time, worst front triangle first (Rebay's order): each on the
perpendicular bisector of the triangle's front edge, inserted by constrained Delaunay
insertion; five smoothing passes follow.  Run::

    python examples/frontal_2d.py [OUTPUT_DIR]
"""

from __future__ import annotations

import numpy as np
from _figures import output_dir, panels, save, zoom

import meshwright as mw
from meshwright.geometry import three_element_airfoil
from meshwright.sizing import gradation


def main() -> None:
    out = output_dir()
    domain = three_element_airfoil(radius=20.0)
    walls = np.concatenate([c.evaluate(c.fine_params()) for loop in domain.loops[1:] for c in loop])
    size = gradation(walls, 2e-4, 1.25, hmax=4.0)
    mesh = mw.triangulate(domain, size=size, method="frontal-delaunay", smooth=5)
    mesh.validate()
    p = mesh.points[mesh.cells["triangle"]]
    edges = np.hypot(*(p - p[:, [1, 2, 0]]).transpose(2, 0, 1))
    q = mesh.quality().summary()["triangle"]
    print(
        f"{len(mesh.cells['triangle'])} triangles, edge lengths {edges.min():.2e} .. {edges.max():.2e} "
        f"(ratio {edges.max() / edges.min():.1e}), mean radius ratio {q['radius_ratio']['mean']:.3f}"
    )
    fig, axes = panels(3)
    windows = [((-21, 21), (-21, 21)), ((-0.4, 1.5), (-0.7, 0.5)), ((0.9, 1.05), (-0.12, 0.03))]
    for ax, window in zip(axes, windows):
        mesh.plot(ax=ax)
        zoom(ax, *window)
    save(fig, out / "three-element-frontal.png")
    mesh.write(str(out / "three-element-frontal.vtu"))


if __name__ == "__main__":
    main()
