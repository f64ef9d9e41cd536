"""The sliver stage's work budget (tet/slivers.py MOVE_WORK): the vertex moves stop there,
the mesh stays valid and is reported; tetrahedralize keeps it only without a tet of the
chapter's a = r_in / R < 0.01.

Oracles: Mesh.validate, volumes by numpy determinants and r / R by core.quality (not the
kernels' formula); the flat tet of the last test is built by hand."""

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


def test_tetrahedralize_at_the_work_budget_keeps_a_mesh_without_flat_tets(monkeypatch):
    calls = []
    check = mesher._check_no_flat_slivers
    monkeypatch.setattr(mesher, "_check_no_flat_slivers", lambda m, r: (calls.append(r.left), check(m, r)))
    monkeypatch.setattr(slivers, "MOVE_WORK", 0)
    monkeypatch.setattr(slivers, "MOVE_WORK_MIN", 0)
    mesh = mesher.tetrahedralize(sphere(radius=1.0, level=2), size=0.3, radius_edge=1.414)
    assert calls and calls[0] > 0  # the budget was hit with slivers left
    mesh.validate()
    assert mesh.quality()["tetra"]["sliver_ratio"].min() >= mesher.SLIVER_FLOOR


def test_a_flat_tet_left_at_the_work_budget_is_an_error():
    pts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.4, 0.4, 1e-4]], float)
    mesh = Mesh(pts, {"tetra": np.array([[0, 1, 2, 3]])})
    assert np.linalg.det(pts[1:] - pts[0]) > 0  # positive and nearly flat: a far below 0.01
    report = slivers.SliverReport(threshold=0.12, found=1, removed_by_flip=0, removed_by_move=0, created=0, left=1)
    with pytest.raises(MeshingError, match=r"work budget.*tet 0 at .*a = r_in / R = .* < 0\.01"):
        mesher._check_no_flat_slivers(mesh, report)
