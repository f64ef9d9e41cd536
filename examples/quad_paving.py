"""Paved domains in the manner of Figure 18.5.3 (Blacker and Stephenson 1991), and Zhu's
pair front for comparison (chapter 18.5.1, Zhu et al. 1991).

* a square plate with a circular hole, paved: rows of quads follow both boundaries and meet
  in seams;
* NACA 0012 in its far field with the built-in graded size, paved (zoom on the section);
* the three-element airfoil, paved (zoom on the slot between slat and main element, where
  the facing rows stop and the void between them is filled by paired triangles);
* the unit disk by ``method="zhu"``: the pair front makes the two triangles of each quad
  together, and under a uniform size its rows come out as squares.

Each panel's title gives the quad count and the interior angle range; the script prints
the mean and minimum scaled Jacobian too.

Run::

    python examples/quad_paving.py [OUTPUT_DIR]
"""

from __future__ import annotations

from _figures import output_dir, panels, save, zoom

import meshwright as mw
from meshwright.core.quality import quad_quality


def _cases():
    plate = mw.geometry.circles(centers=[(0.5, 0.5)], radii=[0.2], box=(0, 0, 1, 1))
    return (
        ("plate with a hole, paving", plate, 0.04, "paving", None),
        ("NACA 0012, paving", mw.geometry.builtin("naca0012"), None, "paving", ((-0.15, 1.15), (-0.5, 0.5))),
        ("three-element, paving", mw.geometry.builtin("three-element"), None, "paving",
         ((-0.12, 0.25), (-0.2, 0.12))),
        ("disk, zhu", mw.geometry.circle(), 0.08, "zhu", None),
    )


def main() -> None:
    out = output_dir()
    fig, axes = panels(4)
    for ax, (title, dom, size, method, window) in zip(axes, _cases()):
        mesh = mw.quadrangulate(dom, size, method=method)
        mesh.validate()
        q = quad_quality(mesh.points, mesh.cells["quad"])
        lo, hi = q["min_angle"].min(), q["max_angle"].max()
        mesh.plot(ax=ax)
        if window is not None:
            zoom(ax, *window)
        ax.set_title(f"{title}: {len(mesh.cells['quad'])} quads, angles {lo:.0f}-{hi:.0f}")
        sj = q["scaled_jacobian"]
        print(f"{title}: {len(mesh.cells['quad'])} quads, angles [{lo:.1f}, {hi:.1f}], "
              f"scaled Jacobian min {sj.min():.3f} mean {sj.mean():.3f}")
        if method == "paving" and window is None:
            mesh.write(str(out / "plate-paving.vtu"))
    save(fig, out / "quad_paving.png")


if __name__ == "__main__":
    main()
