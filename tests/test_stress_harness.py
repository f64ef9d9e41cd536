"""The stress harness's own machinery (``scripts/stress2d.py``): the quad oracle, the
refusal rule of the quad methods and the worker's isolation of crashes and hangs."""

from __future__ import annotations

import faulthandler
import math
import os
import signal
import sys
import time
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))
import stress2d as S  # noqa: E402  (the harness lives in scripts/)

# The unit square cut into four quads about its centre (node 4), counter-clockwise.
SQ_POINTS = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5], [0.5, 0], [1, 0.5], [0.5, 1], [0, 0.5]], float)
SQ_QUADS = np.array([[0, 5, 4, 8], [5, 1, 6, 4], [4, 6, 2, 7], [8, 4, 7, 3]])
OUTER = SQ_POINTS[:4]


def test_quad_oracle_accepts_a_good_mesh():
    sj = S.quad_oracle(SQ_POINTS, {"quad": SQ_QUADS, "line": np.zeros((0, 2), int)}, OUTER, [], OUTER)
    assert sj == pytest.approx(1.0)  # four squares
    kite = SQ_POINTS.copy()
    kite[4] = [0.6, 0.6]  # quad 2's corner there: sides (0.1, -0.4) in, (0.4, -0.1) out, cross 0.15 / 0.17
    sj = S.quad_oracle(kite, {"quad": SQ_QUADS}, OUTER, [], OUTER)
    assert sj == pytest.approx(15 / 17)


def test_quad_oracle_rejects_each_defect():
    with pytest.raises(AssertionError, match="2 triangle"):
        S.quad_oracle(SQ_POINTS, {"quad": SQ_QUADS, "triangle": np.array([[0, 1, 2], [0, 2, 3]])}, OUTER, [], OUTER)
    dart = SQ_POINTS.copy()
    dart[4] = [0.9, 0.9]  # the centre pushed out: quad 2's corner at it turns clockwise
    with pytest.raises(AssertionError, match="not strictly convex"):
        S.quad_oracle(dart, {"quad": SQ_QUADS}, OUTER, [], OUTER)
    flat = SQ_POINTS.copy()
    flat[4] = [0.25, 0.25]  # on the line from node 5 to node 8: quad 0 has a straight corner (SJ 0)
    with pytest.raises(AssertionError, match="not strictly convex"):
        S.quad_oracle(flat, {"quad": SQ_QUADS}, OUTER, [], OUTER)
    with pytest.raises(AssertionError, match="area"):
        S.quad_oracle(SQ_POINTS, {"quad": SQ_QUADS[:3]}, OUTER, [], OUTER)
    hole = np.array([[0.4, 0.4], [0.6, 0.4], [0.6, 0.6], [0.4, 0.6]])  # area 0.04
    with pytest.raises(AssertionError, match="area"):
        S.quad_oracle(SQ_POINTS, {"quad": SQ_QUADS}, OUTER, [hole], OUTER)
    with pytest.raises(AssertionError, match="1 input vertices missing"):
        S.quad_oracle(SQ_POINTS, {"quad": SQ_QUADS}, OUTER, [], np.vstack([OUTER, [[0.25, 0.25]]]))


def test_unforced_min_sj_skips_corners_between_two_lines():
    # A kite with a 10-degree corner at node 0 between two line cells (forced: SJ sin 10
    # deg); its far corner on the bisector, 1.3 out.
    t = math.radians(10.0)
    far = [1.3 * math.cos(t / 2), 1.3 * math.sin(t / 2)]
    pts = np.array([[0, 0], [1, 0], far, [math.cos(t), math.sin(t)]], float)
    quads = np.array([[0, 1, 2, 3]])
    q = pts[quads[0]]
    sj = [float(np.cross(q[k] - q[k - 1], q[(k + 1) % 4] - q[k])
                / (np.linalg.norm(q[k] - q[k - 1]) * np.linalg.norm(q[(k + 1) % 4] - q[k]))) for k in range(4)]
    both = np.array([[3, 0], [0, 1]])
    assert S.unforced_min_sj(pts, quads, both) == pytest.approx(min(sj[1:]))
    # With one of the two sides not a line cell the sharp corner counts.
    assert S.unforced_min_sj(pts, quads, both[:1]) == pytest.approx(math.sin(t))
    assert S.unforced_min_sj(pts, quads, np.array([[3, 0], [0, 1], [1, 2], [2, 3]])) == math.inf


def test_sharpest_corner_of_the_loops():
    assert S.sharpest_corner(_case()) == pytest.approx(90.0)
    # A hole with a 5-degree corner at (0.2, 0.2): its sides leave along 0 and 5 degrees.
    t = math.radians(5.0)
    hole = [[0.2, 0.2], [0.4, 0.2], [0.2 + 0.2 * math.cos(t), 0.2 + 0.2 * math.sin(t)]]
    assert S.sharpest_corner(_case(holes=[hole])) == pytest.approx(5.0)
    # A straight vertex is not sharp (180 degrees between its sides).
    assert S.sharpest_corner(_case(outer=[[0, 0], [1, 0], [1, 1], [0.5, 1], [0, 1]])) == pytest.approx(90.0)


def _case(**over):
    case = {
        "kind": "plain", "outer": OUTER.tolist(), "holes": [], "segments": [], "points": [], "scale": 1.0,
        "shift": [0.0, 0.0], "size": {"kind": "number", "h": 0.3}, "min_angle": None, "seed": 0,
        "methods": ["paving"],
    }
    case.update(over)
    return case


def test_documented_refusals_are_not_failures():
    seg = _case(segments=[[[0.2, 0.5], [0.8, 0.5]]])
    assert S._refusal(seg, "paving") is None
    assert S._refusal(seg, "pairing") is None
    assert S._refusal(_case(points=[[0.5, 0.5]]), "paving") is None
    assert S._refusal(_case(size={"kind": "boundary"}), "paving") == "needs a size"
    assert S._refusal(_case(size={"kind": "boundary"}), "quadtree") is None
    assert S._refusal(_case(size={"kind": "boundary"}), "zhu") is None
    sj, free = S.check(_case(size={"kind": "boundary"}, methods=["quadtree"]), "quadtree")
    assert 0 < sj <= free
    with pytest.raises(S.Refused, match="needs a size"):
        S.check(_case(size={"kind": "boundary"}), "paving")
    stretched = {"kind": "background", "h": 0.3, "stretch": 3.0, "direction": 0.5}
    with pytest.raises(S.Refused, match="not declared in QUAD_METHODS"):
        S.check(_case(size=stretched), "paving")


def _run(jobs, timeout):
    out = []
    w = S._Worker([])  # no method to compile: the jobs run the patched check
    try:
        S._run_all(iter(jobs), [w], timeout, lambda i, case, method, status, msg: out.append((i, status, msg)))
    finally:
        w.close()
    return out


def _fake_check(case, method):
    if case == "segfault":
        faulthandler.disable()  # pytest's handler would print the child's traceback
        os.kill(os.getpid(), signal.SIGSEGV)
    if case == "hang":
        time.sleep(60)
    if isinstance(case, tuple):  # ("slow once", marker): a first run slowed by compiling
        marker = Path(case[1])
        if not marker.exists():
            marker.touch()
            time.sleep(60)


@pytest.mark.skipif(sys.platform == "win32", reason="SIGSEGV by os.kill")
def test_a_crash_or_a_hang_is_one_failure_and_the_run_goes_on(monkeypatch):
    # The workers are forked (Linux), so they run the patched check.
    monkeypatch.setattr(S, "check", _fake_check)
    out = _run([(0, "ok", "m"), (1, "segfault", "m"), (2, "ok", "m"), (3, "hang", "m"), (4, "ok", "m")], 3.0)
    assert [(i, st) for i, st, _ in out] == [(0, "ok"), (1, "fail"), (2, "ok"), (3, "fail"), (4, "ok")]
    assert out[1][2].startswith("Crash: the worker died (exit code -11)")
    assert out[3][2].startswith("Timeout")


def test_a_job_that_times_out_once_runs_again(monkeypatch, tmp_path):
    monkeypatch.setattr(S, "check", _fake_check)
    out = _run([(0, ("slow once", str(tmp_path / "compiled")), "m"), (1, "ok", "m")], 3.0)
    assert sorted((i, st) for i, st, _ in out) == [(0, "ok"), (1, "ok")]


def test_a_worker_that_fails_its_warm_up_is_an_error_at_once(monkeypatch):
    # Without the EOF the parent would wait out the warm-up limit: "did not compile".
    monkeypatch.setattr(S, "JIT_TIMEOUT", 60.0)
    w = S._Worker(["no such method"])  # triangulate refuses it in the worker's warm-up
    with pytest.raises(RuntimeError, match="died while compiling"):
        w.start()


def test_a_crash_reproducer_is_marked(tmp_path, monkeypatch):
    monkeypatch.setattr(S, "REGRESSIONS", tmp_path)
    path = S.record(_case(), "paving", "Crash: the worker died (exit code -11)")
    body = path.read_text()
    assert '"crash": true' in body and '"status": "open"' in body
