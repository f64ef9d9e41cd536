"""The quadtree method step by step (chapter 18.5.3, Yerry and Shephard 1984).

Redraws the chapter's two quadtree figures for a curved domain with a hole (an ellipse
with an off-centre circular hole, the size graded from 0.03 at the hole to 0.15), from the
stages the method itself builds (:func:`meshwright.quad.quadtree.quadtree_stages`) and
its final mesh (``quadrangulate(..., method="quadtree")``):

* ``quadtree_18_5_4.png``, Figure 18.5.4: (a) the initial domain, (b) the initial grid
  (the leaves of the refined, 2:1 balanced tree over the domain's box), (c) removal of
  the exterior grid (leaves whose centre is outside the domain, and those too close to
  the boundary, which the method also drops: the core is what stays), (d) the final
  all-quad mesh (the gap between the core and the true boundary meshed and split);
* ``quadtree_18_5_5.png``, Figure 18.5.5: (a) recursive subdividing, the nodes of each
  level drawn over each other, finer levels darker; (b) the parent-son-grandson relation
  of the tree along the path from the root to one of the finest leaves.

Run::

    python examples/quadtree_2d.py [OUTPUT_DIR]
"""

from __future__ import annotations

import math

import numpy as np
from _figures import output_dir, panels, save

import meshwright as mw
from meshwright.geometry import Arc, Domain, ellipse_loop
from meshwright.quad.quadtree import quadtree_stages
from meshwright.sizing import gradation

HOLE_CENTRE, HOLE_RADIUS = (0.7, 0.15), 0.35
TREE_LEVELS = 4  # levels drawn in Figure 18.5.5 (b), as in the chapter's four-level tree


def domain() -> Domain:
    """Ellipse (semi-axes 2 and 1.2) with a circular hole; size graded from the hole."""
    hole = Arc(HOLE_CENTRE, HOLE_RADIUS, 0.0, 2.0 * math.pi, 2)
    dom = Domain(ellipse_loop((0.0, 0.0), 2.0, 1.2, marker=1), [hole])
    dom.size = gradation(hole.evaluate(hole.fine_params()), 0.03, 1.3, 0.15)
    return dom


def _boundary(ax, dom: Domain) -> None:
    for loop in dom.loops:
        for curve in loop:
            xy = curve.evaluate(curve.fine_params())
            ax.plot(xy[:, 0], xy[:, 1], "k-", lw=1.5)


def _squares(st, nodes):
    """(k, 5, 2) closed outlines of the tree nodes ``nodes``."""
    x0, y0, side = st.root
    s = side / 2.0 ** st.lev[nodes]
    llx, lly = x0 + st.ci[nodes] * s, y0 + st.cj[nodes] * s
    cx = np.array([0, 1, 1, 0, 0])
    cy = np.array([0, 0, 1, 1, 0])
    return np.stack([llx[:, None] + cx * s[:, None], lly[:, None] + cy * s[:, None]], axis=2)


def _draw_cells(ax, st, nodes, edge="0.4", face="none", lw=0.5):
    from matplotlib.collections import PolyCollection

    ax.add_collection(PolyCollection(_squares(st, nodes), facecolors=face, edgecolors=edge, linewidths=lw))


def _frame(ax, box, title: str) -> None:
    """Equal-aspect view of ``box`` (x0, y0, x1, y1)."""
    ax.set_xlim(box[0], box[2])
    ax.set_ylim(box[1], box[3])
    ax.set_aspect("equal")
    ax.set_title(title)


def _root_box(st):
    x0, y0, side = st.root
    return x0, y0, x0 + side, y0 + side


def _domain_box(dom: Domain, margin: float = 0.15):
    x0, y0, x1, y1 = dom.bbox
    return x0 - margin, y0 - margin, x1 + margin, y1 + margin


def figure_18_5_4(dom: Domain, st, mesh, out) -> None:
    fig, axes = panels(4)
    _boundary(axes[0], dom)
    _frame(axes[0], _domain_box(dom), "(a) initial domain")

    _draw_cells(axes[1], st, st.leaves)
    _boundary(axes[1], dom)
    _frame(axes[1], _root_box(st), f"(b) initial grid: {len(st.leaves)} leaves, {int(st.lev.max())} levels")

    inside = st.leaves[st.inside]
    _draw_cells(axes[2], st, inside, face="lightsteelblue")
    _draw_cells(axes[2], st, st.core, face="tab:blue", edge="k")
    _boundary(axes[2], dom)
    _frame(axes[2], _domain_box(dom), f"(c) exterior removed: {len(inside)} inside, core {len(st.core)} (dark)")

    mesh.plot(ax=axes[3])
    _frame(axes[3], _domain_box(dom), f"(d) final mesh: {len(mesh.cells['quad'])} quads")
    save(fig, out / "quadtree_18_5_4.png")


def _path_to_finest(st) -> list[int]:
    """Node indices from the root to the first leaf of the finest level."""
    parent = np.full(len(st.lev), -1, dtype=np.int64)
    inner = np.flatnonzero(st.child >= 0)
    parent[st.child[inner][:, None] + np.arange(4)] = inner[:, None]
    node = int(st.leaves[np.argmax(st.lev[st.leaves])])
    path = [node]
    while parent[path[-1]] >= 0:
        path.append(int(parent[path[-1]]))
    return path[::-1]


def figure_18_5_5(dom: Domain, st, out) -> None:
    from matplotlib import colormaps

    fig, (grid, tree) = panels(2, size=6.0)
    top = int(st.lev.max())
    colours = colormaps["viridis"](np.linspace(0.15, 1.0, top + 1))
    _draw_cells(grid, st, st.leaves, edge="k", face=colours[st.lev[st.leaves]], lw=0.3)
    path = _path_to_finest(st)
    _draw_cells(grid, st, np.array(path), edge="tab:red", lw=1.5)
    _boundary(grid, dom)
    _frame(grid, _root_box(st), f"(a) recursive subdividing\nleaves coloured by level 0-{top}, light = finer")

    # (b): the first levels of the path as a tree, each node with its four sons one row down.
    shown = path[:TREE_LEVELS]
    xs = {shown[0]: 0.0}
    for depth, node in enumerate(shown[:-1]):
        width = 2.0 ** -depth
        for q in range(4):
            son = int(st.child[node]) + q
            xs[son] = xs[node] + (q - 1.5) * width
            colour = "tab:red" if son == shown[depth + 1] else "0.6"
            tree.plot([xs[node], xs[son]], [-depth, -depth - 1], "-", color=colour)
            tree.plot(xs[son], -depth - 1, "o", color=colour, ms=6)
            tree.annotate(str(q), (xs[son], -depth - 1.25), ha="center", fontsize=8)
    tree.plot(xs[shown[0]], 0, "o", color="tab:red", ms=8)
    for depth, name in enumerate(["parent (root)", "sons", "grandsons", "great-grandsons"][: len(shown)]):
        tree.annotate(name, (2.6, -depth), fontsize=10, va="center")
    tree.set_xlim(-2.6, 3.8)
    tree.set_ylim(-len(shown) + 0.4, 0.4)
    tree.set_axis_off()
    tree.set_title("(b) parent-son-grandson relation\nson q = east + 2 north; red: the red cells of (a)")
    save(fig, out / "quadtree_18_5_5.png")


def main() -> None:
    out = output_dir()
    dom = domain()
    st = quadtree_stages(dom)
    mesh = mw.quadrangulate(dom, method="quadtree")
    figure_18_5_4(dom, st, mesh, out)
    figure_18_5_5(dom, st, out)


if __name__ == "__main__":
    main()
