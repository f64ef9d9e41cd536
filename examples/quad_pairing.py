"""Quadrilaterals from pairs of advancing-front triangles (chapter 18.5.1, Zhu et al. 1991).

* Figure 18.5.1 (a): triangle ABC on the front side AB with a new node C, the second
  triangle ACD on its side AC with a new node D: quad ABCD, no sub-front;
* Figure 18.5.1 (b): D is a node of the front, so the front splits into sub-fronts SF1 and
  SF2; the chapter's rule (steps 5-6) takes the D that leaves both with an even number of
  active sides (the counts are computed from the drawn front and printed in the panel);
* NACA 0012 in a far field paired by ``meshwright.quad.pairing``: the quad-dominant pairing
  (left-over triangles red), and the all-quad mesh ``quadrangulate(..., method="pairing")``
  returns (printed: quads, triangles left, min scaled Jacobian);
* a disk with a graded size, where a boundary fan leaves triangles (red): the chords from
  them (``meshwright.quad.chords``) refine only the quads they cross (second figure).

Run::

    python examples/quad_pairing.py [OUTPUT_DIR]
"""

from __future__ import annotations

import numpy as np
from _figures import output_dir, panels, save, zoom

import meshwright as mw
from meshwright.core.mesh import Mesh
from meshwright.core.quality import quad_quality
from meshwright.quad.pairing import pair_domain

# A closed front (counter-clockwise, 12 sides, even) around the region still to mesh.
FRONT = np.array(
    [[0, 0], [1, 0], [2, 0], [3, 0.1], [3.6, 0.8], [3.5, 1.8], [2.8, 2.4],
     [2.0, 2.5], [1.0, 2.5], [0.1, 2.3], [-0.5, 1.6], [-0.4, 0.7]],
    dtype=np.float64,
)
A, B = 1, 2  # the base side AB of the first triangle


def _draw_front(ax, nodes, style="k-", label=None):
    loop = np.vstack([nodes, nodes[:1]])
    ax.plot(loop[:, 0], loop[:, 1], style, lw=1.5, label=label)


def _label(ax, xy, text, dx=0.06, dy=-0.18):
    ax.plot(*xy, "ko", ms=4)
    ax.annotate(text, xy, xytext=(xy[0] + dx, xy[1] + dy), fontsize=12, weight="bold")


def _panel_a(ax):
    _draw_front(ax, FRONT, "k-", "front")
    a, b = FRONT[A], FRONT[B]
    c = np.array([2.1, 0.95])  # new node C of triangle ABC
    d = np.array([1.0, 1.0])  # new node D of the second triangle ACD
    ax.fill(*np.array([a, b, c, d]).T, color="tab:blue", alpha=0.3)
    ax.plot(*np.array([a, c]).T, "b--", lw=1)
    ax.plot(*np.array([b, c, d, a]).T, "b-", lw=2)
    for p, t in ((a, "A"), (b, "B"), (c, "C"), (d, "D")):
        _label(ax, p, t)
    new_front = np.vstack([FRONT[:B], [d, c], FRONT[B:]])
    ax.set_title(f"18.5.1 (a): D new, front {len(FRONT)} -> {len(new_front)} sides, no sub-front")
    ax.set_aspect("equal")


def _sub_fronts(d_index):
    """Sides of SF1 (B .. D along the front, then D -> C -> B) and SF2 (D .. A, then A -> D)."""
    n = len(FRONT)
    k1 = (d_index - B) % n  # front sides from B to D
    k2 = (A - d_index) % n  # front sides from D to A
    return k1 + 2, k2 + 1


def _panel_b(ax):
    _draw_front(ax, FRONT, "k-")
    a, b = FRONT[A], FRONT[B]
    c = np.array([2.0, 1.1])
    # Rule 6: of the front nodes facing AC, take the one leaving both sub-fronts even.
    candidates = [8, 9, 7]
    d_index = next(i for i in candidates if all(k % 2 == 0 for k in _sub_fronts(i)))
    odd = next(i for i in candidates if any(k % 2 for k in _sub_fronts(i)))
    d = FRONT[d_index]
    ax.fill(*np.array([a, b, c, d]).T, color="tab:green", alpha=0.3)
    ax.plot(*np.array([a, c]).T, "g--", lw=1)
    ax.plot(*np.array([b, c, d, a]).T, "g-", lw=2)
    for p, t in ((a, "A"), (b, "B"), (c, "C"), (d, "D")):
        _label(ax, p, t)
    sf1, sf2 = _sub_fronts(d_index)
    ax.annotate(f"SF1: {sf1} sides", (2.6, 1.3), fontsize=11, color="tab:green")
    ax.annotate(f"SF2: {sf2} sides", (-0.35, 1.3), fontsize=11, color="tab:green")
    o1, o2 = _sub_fronts(odd)
    ax.plot(*np.array([c, FRONT[odd]]).T, "r:", lw=1)
    ax.annotate(f"node {odd}: {o1} / {o2} (odd), refused", FRONT[odd] + [-0.4, 0.12], fontsize=9, color="tab:red")
    ax.set_title("18.5.1 (b): D on the front, sub-fronts SF1 and SF2 both even")
    ax.set_aspect("equal")
    return sf1, sf2


def _naca():
    dom = mw.geometry.builtin("naca0012")
    fill, report = pair_domain(dom, dom.size, all_quad=False)
    cells = {"quad": fill.quads, "triangle": fill.triangles, "line": fill.lines}
    mixed = Mesh(fill.points, {k: v for k, v in cells.items() if len(v)})
    mixed.validate()
    full = mw.quadrangulate(dom, method="pairing", smooth=5)
    full.validate()
    return mixed, full, report


def main() -> None:
    out = output_dir()
    fig, axes = panels(4)
    _panel_a(axes[0])
    sf1, sf2 = _panel_b(axes[1])
    print(f"Figure 18.5.1 (b): SF1 has {sf1} active sides, SF2 {sf2}")

    mixed, full, report = _naca()
    mixed.plot(ax=axes[2])
    tri = mixed.cells.get("triangle", np.zeros((0, 3), dtype=np.int32))
    for t in tri:
        axes[2].fill(*mixed.points[t].T, color="tab:red", alpha=0.8)
    zoom(axes[2], (-0.2, 1.2), (-0.5, 0.5))
    axes[2].set_title(f"NACA 0012 pairing: {len(mixed.cells['quad'])} quads, {len(tri)} triangles left")
    full.plot(ax=axes[3])
    zoom(axes[3], (-0.2, 1.2), (-0.5, 0.5))
    sj = quad_quality(full.points, full.cells["quad"])["scaled_jacobian"]
    axes[3].set_title(f"all-quad: {len(full.cells['quad'])} quads, min scaled Jacobian {sj.min():.2f}")
    print(
        f"NACA 0012: {report.triangles} front triangles, {report.paired} pairs ({report.chains} by chains), "
        f"{report.left_over} left over; enhancement {report.eliminated}; all-quad {len(full.cells['quad'])} quads, "
        f"min scaled Jacobian {sj.min():.3f}, mean {sj.mean():.3f}"
    )
    save(fig, out / "quad_pairing.png")
    full.write(str(out / "naca0012-pairing.vtu"))
    _chords(out)


def _chords(out):
    dom = mw.geometry.circle()
    size = mw.sizing.as_size_field(lambda p: 0.02 + 0.12 * np.hypot(p[:, 0] - 0.5, p[:, 1]))
    mixed, report = pair_domain(dom, size, all_quad=False)
    full, _ = pair_domain(dom, size)
    fig, axes = panels(2)
    for ax, fill, title in (
        (axes[0], mixed, f"pairing: {len(mixed.quads)} quads, {len(mixed.triangles)} triangles left"),
        (axes[1], full, f"chords through the left-overs: {len(full.quads)} quads"),
    ):
        cells = {"quad": fill.quads, "line": fill.lines}
        if len(fill.triangles):
            cells["triangle"] = fill.triangles
        Mesh(fill.points, cells).plot(ax=ax)
        for t in fill.triangles:
            ax.fill(*fill.points[t].T, color="tab:red", alpha=0.8)
        ax.set_title(title)
    sj = quad_quality(full.points, full.quads)["scaled_jacobian"]
    print(f"graded disk: {report.left_over} triangles left by pairing; chords -> {len(full.quads)} quads, "
          f"min scaled Jacobian {sj.min():.3f}")
    save(fig, out / "quad_pairing_chords.png")


if __name__ == "__main__":
    main()
