"""The quadtree example (examples/quadtree_2d.py) runs and writes its two figures, and the
stages it draws are consistent with the mesh quadrangulate returns."""

from __future__ import annotations

import runpy
import sys
from pathlib import Path

import numpy as np

import meshwright as mw
from meshwright.quad.quadtree import CLEARANCE, quadtree_stages

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def test_quadtree_example_writes_both_figures(tmp_path, monkeypatch):
    monkeypatch.setattr(sys, "argv", ["quadtree_2d.py", str(tmp_path)])
    monkeypatch.syspath_prepend(str(EXAMPLES))
    runpy.run_path(str(EXAMPLES / "quadtree_2d.py"), run_name="__main__")
    for name in ("quadtree_18_5_4.png", "quadtree_18_5_5.png"):
        png = tmp_path / name
        assert png.exists() and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_stages_are_the_tree_the_mesh_is_built_on():
    # Unit square at size 0.1, all-quad: the tree is built at 0.2, so no cell is coarser
    # than 0.2 * sqrt(2) (the split ratio) where it meets the square.
    stages = quadtree_stages("rectangle", 0.1)
    x0, y0, side = stages.root
    s = side / 2.0 ** stages.lev
    lo = np.column_stack([x0 + stages.ci * s, y0 + stages.cj * s])
    # Sons tile their parent exactly: four sons, each half the side, at the parent's corners.
    inner = np.flatnonzero(stages.child >= 0)
    for q in range(4):
        son = stages.child[inner] + q
        assert np.array_equal(stages.lev[son], stages.lev[inner] + 1)
        assert np.array_equal(stages.ci[son], 2 * stages.ci[inner] + (q & 1))
        assert np.array_equal(stages.cj[son], 2 * stages.cj[inner] + (q >> 1))
    assert np.array_equal(np.sort(stages.leaves), np.flatnonzero(stages.child < 0))
    # The core lies inside the rectangle [0, 2] x [0, 1], CLEARANCE sizes from its sides.
    core_lo, core_s = lo[stages.core], s[stages.core]
    assert len(stages.core) > 0 and set(stages.core) <= set(stages.leaves[stages.inside])
    gap = np.minimum.reduce([core_lo[:, 0], core_lo[:, 1], 2.0 - core_lo[:, 0] - core_s, 1.0 - core_lo[:, 1] - core_s])
    assert (gap >= CLEARANCE * core_s - 1e-12).all()
    # Every core cell's corners are vertices of the final mesh (the method's quads are these cells).
    mesh = mw.quadrangulate("rectangle", 0.1, method="quadtree")
    corners = np.vstack([core_lo, core_lo + core_s[:, None]])
    have = {tuple(p) for p in mesh.points}
    assert all(tuple(p) in have for p in corners)
