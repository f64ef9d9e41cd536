"""Draw the decomposition ``meshwright.distributed`` would mesh: parts, cuts and interfaces.

Usage::

    python examples/decompose_plot.py OUT.png [--parts 8]

A disk with two holes and a size graded from the first hole: the cuts are balanced by the
integral of 1/h^2 (more, smaller parts near the fine region), meet the boundary and each other
at 60 degrees or more (so near the rim, between the axes, some cuts turn away from the axes),
and their inside pieces (red) are discretised before meshing.  The legend gives each
part's predicted triangle count.
"""

from __future__ import annotations

import argparse
import math

import numpy as np


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", help="PNG file")
    ap.add_argument("--parts", type=int, default=8)
    args = ap.parse_args()

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from meshwright.distributed import decompose
    from meshwright.geometry import Domain
    from meshwright.geometry.curves import Arc

    dom = Domain(
        Arc((0.0, 0.0), 1.0, 0.0, 2 * math.pi),
        [Arc((0.4, 0.1), 0.15, 0.0, 2 * math.pi), Arc((-0.3, -0.35), 0.2, 0.0, 2 * math.pi)],
    )

    def size(xy):
        return 0.01 + 0.04 * np.hypot(xy[:, 0] - 0.4, xy[:, 1] - 0.1)

    dec = decompose(dom, size, args.parts)
    fig, ax = plt.subplots(figsize=(7, 7))
    cmap = plt.get_cmap("tab20")
    for i in range(dec.n_parts):
        seg = dec.segments[(dec.left == i) & (dec.kind != 2)]
        p = dec.points[seg]
        ax.plot(p[:, :, 0].T, p[:, :, 1].T, color=cmap(i % 20), lw=2.5)
        ax.plot([], [], color=cmap(i % 20), lw=2.5, label=f"part {i}: {dec.predicted[i]:.0f} triangles")
    iface = dec.points[dec.segments[dec.kind == 2]]
    ax.plot(iface[:, :, 0].T, iface[:, :, 1].T, color="red", lw=1.0)
    ax.plot(*dec.points[np.unique(dec.segments[dec.kind == 2])].T, ".", color="red", ms=2)
    ax.set_aspect("equal")
    ax.legend(fontsize=7, loc="upper right")
    ax.set_title(
        f"{dec.n_parts} parts, predicted imbalance {dec.imbalance:.3f}, smallest cut angle {dec.min_cut_angle:.1f} deg"
    )
    fig.savefig(args.out, dpi=120)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
