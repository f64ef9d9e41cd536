"""The paving example (examples/quad_paving.py) runs, writes its figure, and the plate it
paves is all-quad with every interior angle within paving's [45, 150] degree target
(angles recomputed here from the written file, not by the library's quality code)."""

from __future__ import annotations

import runpy
import sys
from pathlib import Path

import meshio
import numpy as np

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def test_paving_example_writes_figure_and_plate(tmp_path, monkeypatch):
    monkeypatch.setattr(sys, "argv", ["quad_paving.py", str(tmp_path)])
    monkeypatch.syspath_prepend(str(EXAMPLES))
    runpy.run_path(str(EXAMPLES / "quad_paving.py"), run_name="__main__")
    png = tmp_path / "quad_paving.png"
    assert png.exists() and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    m = meshio.read(tmp_path / "plate-paving.vtu")
    kinds = {c.type for c in m.cells}
    assert "quad" in kinds and "triangle" not in kinds
    quads = np.vstack([c.data for c in m.cells if c.type == "quad"])
    p = m.points[:, :2][quads]  # (q, 4, 2)
    prev, nxt = np.roll(p, 1, axis=1) - p, np.roll(p, -1, axis=1) - p
    cos = (prev * nxt).sum(-1) / (np.linalg.norm(prev, axis=-1) * np.linalg.norm(nxt, axis=-1))
    ang = np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))
    assert np.allclose(ang.sum(axis=1), 360.0, atol=1e-6)  # convex: the corners are the interior angles
    assert ang.min() >= 45.0 and ang.max() <= 150.0
