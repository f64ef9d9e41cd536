"""The sliver stage's work budget (tet/slivers.py MOVE_WORK): the vertex moves stop there,
the mesh stays valid and the stop is reported; tetrahedralize keeps that mesh, and a
min_dihedral it does not meet is an error at once.

Oracles: Mesh.validate, volumes by numpy determinants (the enclosed volume by the
divergence theorem on the input faces) and r / R by core.quality (not the kernels' formula)."""

import numpy as np
import pytest

from meshwright.core.errors import MeshingError
from meshwright.core.mesh import Mesh
from meshwright.geometry import sphere
from meshwright.tet import mesher, slivers
from meshwright.tet.slivers import remove_slivers

spatial = pytest.importorskip("scipy.spatial")


def scipy_mesh(seed):
    pts = np.random.default_rng(seed).random((300, 3))
    tets = spatial.Delaunay(pts).simplices.copy()
    p = pts[tets]
    neg = np.linalg.det(p[:, 1:] - p[:, :1]) < 0
    tets[neg, 0], tets[neg, 1] = tets[neg, 1], tets[neg, 0].copy()
    return Mesh(pts, {"tetra": tets})


def volume(mesh):
    p = mesh.points[mesh.tetra]
    return np.linalg.det(p[:, 1:] - p[:, :1]).sum() / 6.0


def test_moves_stop_at_the_work_budget_with_a_valid_mesh(monkeypatch):
    mesh = scipy_mesh(11)
    _, full_report = remove_slivers(mesh, threshold=0.2, max_iter=4)
    assert full_report.left_reasons["work_cap"] == 0
    monkeypatch.setattr(slivers, "MOVE_WORK", 20)
    monkeypatch.setattr(slivers, "MOVE_WORK_MIN", 0)
    out, report = remove_slivers(mesh, threshold=0.2, max_iter=4)
    out.validate()
    assert volume(out) == pytest.approx(volume(mesh), rel=1e-12)
    assert 0 < report.moves < full_report.moves
    assert report.left_reasons["work_cap"] == report.left > 0
    a = out.quality()["tetra"]["sliver_ratio"]
    assert report.left == int(np.count_nonzero(a < 0.2))
    assert a.min() >= mesh.quality()["tetra"]["sliver_ratio"].min()


def test_tetrahedralize_at_the_work_budget_keeps_the_stage_mesh(monkeypatch):
    reports = []
    stage = slivers.remove_slivers_of_valid

    def spy(*args):
        out, report = stage(*args)
        reports.append(report)
        return out, report

    monkeypatch.setattr(slivers, "remove_slivers_of_valid", spy)
    monkeypatch.setattr(slivers, "MOVE_WORK", 0)
    monkeypatch.setattr(slivers, "MOVE_WORK_MIN", 0)
    surf = sphere(radius=1.0, level=2)
    mesh = mesher.tetrahedralize(surf, size=0.3, radius_edge=1.414)
    assert reports and reports[0].left_reasons["work_cap"] == reports[0].left > 0
    assert reports[0].moves == 0
    mesh.validate()
    p = surf.points[surf.triangles]
    enclosed = np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6.0
    assert volume(mesh) == pytest.approx(enclosed, rel=1e-12)


def test_min_dihedral_unmet_at_the_work_budget_is_an_error(monkeypatch):
    monkeypatch.setattr(slivers, "MOVE_WORK", 0)
    monkeypatch.setattr(slivers, "MOVE_WORK_MIN", 0)
    with pytest.raises(MeshingError, match="min_dihedral=20.* stopped at the moves' work budget"):
        mesher.tetrahedralize(sphere(radius=1.0, level=2), size=0.3, radius_edge=1.414, min_dihedral=20.0)
