"""Mesh.validate() on tetrahedral meshes: good meshes pass; flipped, duplicated, missing and
non-Delaunay tets are named.  The reference meshes come from scipy's Qhull."""

import numpy as np
import pytest

from meshwright.core.errors import InputError, ValidationError
from meshwright.core.mesh import Mesh
from meshwright.core.validate3d import check_closed_surface, check_enclosed_volume
from test_mesh import CUBE, positive
from test_mesh import CUBE_5 as CUBE_5_RAW

spatial = pytest.importorskip("scipy.spatial")

CUBE_5 = positive(CUBE, CUBE_5_RAW)  # the cube split in five, positively oriented


def scipy_mesh(n=150, seed=0):
    pts = np.random.default_rng(seed).random((n, 3))
    d = spatial.Delaunay(pts)
    return pts, positive(pts, d.simplices), d.convex_hull


def test_good_meshes_pass():
    Mesh(CUBE, {"tetra": CUBE_5}).validate()
    pts, tets, _ = scipy_mesh()
    Mesh(pts, {"tetra": tets}).validate(check_delaunay=True)


def test_flipped_tet_is_named():
    pts, tets, _ = scipy_mesh()
    tets[17, [0, 1]] = tets[17, [1, 0]]
    with pytest.raises(ValidationError, match=r"tetra 17 \(vertices .*\) .* inverted"):
        Mesh(pts, {"tetra": tets}).validate()


def test_duplicated_tet_is_named():
    pts, tets, _ = scipy_mesh()
    with pytest.raises(ValidationError, match=r"shared by 3 cells.*tetra 40|traversed in the same direction"):
        Mesh(pts, {"tetra": np.vstack([tets, tets[40:41]])}).validate()


def _hull_edges(hull):
    e = np.sort(np.concatenate([hull[:, [0, 1]], hull[:, [1, 2]], hull[:, [2, 0]]]), axis=1)
    return {tuple(x) for x in e}


def test_missing_tet_touching_the_hull_at_an_edge_or_a_vertex():
    pts, tets, hull = scipy_mesh(300, seed=1)
    on_hull = np.zeros(len(pts), bool)
    on_hull[hull.ravel()] = True
    hull_faces = {tuple(sorted(f)) for f in hull}
    hull_edges = _hull_edges(hull)
    edge_case = vertex_case = None
    for t, tet in enumerate(tets):
        if any(tuple(sorted(np.delete(tet, k))) in hull_faces for k in range(4)):
            continue
        edges = {tuple(sorted((tet[i], tet[j]))) for i in range(4) for j in range(i)}
        if edges & hull_edges:
            edge_case = t if edge_case is None else edge_case
        elif on_hull[tet].sum() == 1:
            vertex_case = t if vertex_case is None else vertex_case
    assert edge_case is not None and vertex_case is not None
    with pytest.raises(ValidationError, match=r"lies in 4 boundary faces .* non-manifold"):
        Mesh(pts, {"tetra": np.delete(tets, edge_case, axis=0)}).validate()
    v = int(tets[vertex_case][on_hull[tets[vertex_case]]][0])
    with pytest.raises(ValidationError, match=rf"boundary vertex {v} is pinched: .* 2 separate fans"):
        Mesh(pts, {"tetra": np.delete(tets, vertex_case, axis=0)}).validate()


def test_missing_interior_tet_leaves_a_valid_mesh_with_a_void():
    pts, tets, hull = scipy_mesh(300, seed=1)
    on_hull = np.zeros(len(pts), bool)
    on_hull[hull.ravel()] = True
    t = int(np.flatnonzero(~on_hull[tets].any(axis=1))[0])
    mesh = Mesh(pts, {"tetra": np.delete(tets, t, axis=0)})
    mesh.validate(check_delaunay=True)
    assert len(mesh.boundary_facets()) == len(hull) + 4


def test_non_delaunay_pair_is_named():
    # e lies inside the circumsphere of abcd (the unit sphere) on the other side of face abc.
    pts = np.array([[1, 0, 0], [-0.5, 0.8, 0], [-0.5, -0.8, 0], [0, 0, 1], [0, 0, -0.5]])
    tets = positive(pts, np.array([[0, 1, 2, 3], [0, 1, 2, 4]]))
    mesh = Mesh(pts, {"tetra": tets})
    mesh.validate()
    with pytest.raises(ValidationError, match=r"not locally Delaunay: vertex [34] .* inside the circumsphere"):
        mesh.validate(check_delaunay=True)
    # Moving e out of the sphere makes the pair Delaunay.
    pts[4, 2] = -2.0
    Mesh(pts, {"tetra": tets}).validate(check_delaunay=True)


def test_cospherical_pair_passes_the_delaunay_check():
    # Five points on the unit sphere: exact ties pass.
    pts = np.array([[1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, 0, 1], [0, 0, -1.0]])
    tets = positive(pts, np.array([[0, 1, 2, 3], [0, 1, 2, 4]]))
    Mesh(pts, {"tetra": tets}).validate(check_delaunay=True)


def test_surface_and_volume_checks_directly():
    mesh = Mesh(CUBE, {"tetra": CUBE_5})
    faces = mesh.boundary_facets()
    check_closed_surface(faces, 8)
    with pytest.raises(ValidationError, match=r"lies in 1 boundary faces .* open"):
        check_closed_surface(faces[1:], 8)
    flipped = faces.copy()
    flipped[0] = flipped[0, ::-1]
    with pytest.raises(ValidationError, match="same direction"):
        check_closed_surface(flipped, 8)
    with pytest.raises(ValidationError, match="no boundary face"):
        check_closed_surface(np.zeros((0, 3), int), 8)
    check_enclosed_volume(CUBE, CUBE_5, faces)
    with pytest.raises(ValidationError, match=r"volumes sum to 1\.0.* encloses"):
        check_enclosed_volume(CUBE, CUBE_5, np.vstack([faces, [[0, 1, 4]]]))


def test_check_delaunay_on_mixed_mesh_is_an_error():
    # A hexahedron with five tets stacked on its top face.
    pts = np.vstack([CUBE, CUBE[4:] + [0, 0, 1]])
    hexa = np.array([[0, 1, 2, 3, 4, 5, 6, 7]])
    tets = CUBE_5 + 4
    with pytest.raises(InputError, match="hexahedra"):
        Mesh(pts, {"tetra": tets, "hexahedron": hexa}).validate(check_delaunay=True)
