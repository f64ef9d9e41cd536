"""The chapter's 2-D examples: circle, circles, NACA 0012 and the three-element airfoil.

Each domain is meshed by Delaunay refinement (18.1.2 with Ruppert's point placement) and by
Weatherill's automatic point generation followed by spring-analogy smoothing (18.1.3, 18.2),
side by side, as in Figures 18.1.5, 18.1.7 and 18.3.1.  Run::

    python examples/chapter_2d.py [OUTPUT_DIR]
"""

from __future__ import annotations

from _figures import output_dir, panels, save, zoom

import meshwright as mw
from meshwright.geometry import builtin

CASES = {
    "circle": None,
    "circles": None,
    "naca0012": ((-0.2, 1.2), (-0.5, 0.5)),
    "three-element": ((-0.3, 1.4), (-0.6, 0.5)),
}


def main() -> None:
    out = output_dir()
    for name, window in CASES.items():
        domain = builtin(name)
        meshes = {
            "Delaunay refinement, 30 deg": mw.triangulate(domain, min_angle=30),
            "Weatherill + 8 smoothing passes": mw.triangulate(domain, method="weatherill", smooth=8),
        }
        fig, axes = panels(len(meshes))
        for ax, (title, mesh) in zip(axes, meshes.items()):
            mesh.validate()
            mesh.plot(ax=ax)
            q = mesh.quality().summary()["triangle"]
            ax.set_title(
                f"{title}\n{len(mesh.cells['triangle'])} triangles, min angle {q['min_angle']['min']:.1f}, "
                f"mean 2r/R {q['radius_ratio']['mean']:.3f}"
            )
            if window is not None:
                zoom(ax, *window)
        save(fig, out / f"{name}.png")
        meshes["Delaunay refinement, 30 deg"].write(str(out / f"{name}.vtu"))


if __name__ == "__main__":
    main()
