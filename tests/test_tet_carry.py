"""Refinement rounds that carry the last state's labels and bad tets (tet/mesher.py).

* ``Tetrahedralization.track`` / ``tracked``: after insertions, every tet without a newer
  vertex is found, vertex for vertex, at the index ``tracked`` gives in the tets of the
  ``track`` call (checked against a copy of those tets);
* ``tetrahedralize``: at every state a refinement round computes, the carried solid flags,
  region ids and volume bounds equal a fresh :func:`meshwright.tet.exterior.classify` (the
  component search and depth rule, which the carry never calls), and the bad tets equal one
  whole-mesh pass of ``bad_solid`` (what the carry replaces: the new tets plus the
  survivors of the last bad set), on surfaces with and without seeds and with flat-tet flips.
"""

import ast
import sys
from pathlib import Path

import numpy as np
import pytest

import meshwright as mw
from meshwright.geometry import Surface
from meshwright.geometry.solids import box, sphere
from meshwright.tet.exterior import classify
from meshwright.tet.refine3d import bad_solid
from meshwright.tet.tetrahedralization import Tetrahedralization, delaunay3d

DATA = Path(__file__).parent / "data" / "tet_fuzz"


def test_tracked_names_each_surviving_tet():
    rng = np.random.default_rng(3)
    tz = delaunay3d(rng.random((400, 3)), seed=1)
    before = np.array(tz.tetrahedra)
    nv0 = tz.points.shape[0]
    tz.track()
    for _ in range(3):
        tz.insert(rng.random((60, 3)) * 0.5 + 0.25)
    tets = tz.tetrahedra
    src = tz.tracked()
    old = ~(tets >= nv0).any(axis=1)
    assert 0 < old.sum() < len(tets)
    assert np.array_equal(before[src[old]], tets[old])
    # every old tet that survived is found exactly once
    keys_before = {tuple(sorted(r)) for r in before.tolist()}
    survivors = [tuple(sorted(r)) for r in tets[old].tolist()]
    assert len(set(survivors)) == len(survivors) and set(survivors) <= keys_before
    assert len(set(src[old].tolist())) == old.sum()


def test_tracked_needs_track_and_the_ghost():
    pts = np.random.default_rng(4).random((20, 3))
    with pytest.raises(mw.MeshwrightError, match="track"):
        delaunay3d(pts).tracked()
    with pytest.raises(mw.MeshwrightError, match="ghost"):
        delaunay3d(pts, superstructure="box").track()


def _checked_run(monkeypatch, surface, **kw):
    """tetrahedralize with every state checked; (states, carried states)."""
    seen = {"states": 0, "carried": 0}
    track = Tetrahedralization.track

    def checking_track(self):
        f = sys._getframe(1).f_locals  # the refinement loop's state, just computed
        job = f["job"]
        solid, region, vmax = classify(self, f["barrier"], job.holes, job.regions)
        assert np.array_equal(solid, f["solid"])
        assert np.array_equal(region, f["region"])
        assert np.array_equal(vmax, f["vmax"])
        if f["queue_bound"]:
            want = bad_solid(f["pts"], f["tets"], f["solid"], f["vbound"], *f["bound"])
            assert np.array_equal(want, f["bad"])
        seen["states"] += 1
        seen["carried"] += f["new"] is not None
        return track(self)

    monkeypatch.setattr(Tetrahedralization, "track", checking_track)
    mesh = mw.tetrahedralize(surface, **kw)
    mesh.validate()
    return seen


def test_carried_states_equal_fresh_ones_sphere(monkeypatch):
    seen = _checked_run(monkeypatch, sphere(1.0, level=3), size=0.12, radius_edge=1.414)
    assert seen["carried"] >= 1


def test_carried_states_equal_fresh_ones_with_seeds(monkeypatch):
    outer = box((-1, -1, -1), (1, 1, 1))
    inner = sphere(0.5, level=2)
    pts = np.concatenate([outer.points, inner.points])
    tri = np.concatenate([outer.triangles, inner.triangles[:, ::-1] + len(outer.points)])
    surf = Surface(pts, tri)
    seen = _checked_run(monkeypatch, surf, size=0.2, radius_edge=1.5, regions=[(0.8, 0.8, 0.8, 7, 0.01), (0, 0, 0, 3, 0.0)])
    assert seen["carried"] >= 1


def test_carried_states_equal_fresh_ones_fuzz_reproducer(monkeypatch):
    d = np.load(DATA / "extruded_crease170.npz")
    seen = _checked_run(monkeypatch, Surface(d["points"], d["triangles"]), **ast.literal_eval(str(d["kw"])))
    assert seen["carried"] >= 1
