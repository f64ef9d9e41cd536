"""Checks of tetrahedral meshes that :meth:`Mesh.validate` adds to its generic ones.

``Mesh.validate`` already proves, for every cell type, exact positive orientation and
conforming facets (no face in three or more cells, each shared face traversed in
opposite directions).  For a mesh whose volume cells are tetrahedra this module adds:

1. the boundary surface (faces in one tet, oriented outwards) is a closed, oriented
   2-manifold: every boundary edge lies in exactly two boundary faces which traverse it
   in opposite directions, and the boundary faces around every boundary vertex form a
   single fan (a "pinched" vertex, where two parts of the mesh touch in a point, fails);
2. the volume enclosed by the boundary (divergence theorem, ``sum a . (b x c) / 6`` over
   the outward faces) equals the sum of the tet volumes to rounding;
3. optionally, the Delaunay property: for every interior face the vertex of the tet on
   the other side is not strictly inside the circumsphere of this tet (exact
   ``insphere``, cospherical ties pass).  Constrained faces are not exempt: the check is
   for unconstrained Delaunay tetrahedralizations.

A mesh with an internal void (the boundary has several components) is valid.  Array
layout: tets ``(m, 4)`` int, positively oriented (``orient3d > 0``), face k opposite
vertex k as in :mod:`meshwright.core.flat`; faces ``(f, 3)`` int, outward.
References: the divergence (Gauss) theorem for polyhedral volume; the local Delaunay
criterion of Delaunay (1934), as used by Watson (1981).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.errors import InputError, ValidationError
from meshwright.core.mesh import build_neighbors_tet
from meshwright.core.predicates import insphere
from meshwright.core.validate_cells import (
    _KERNEL_MIN,
    _fmt_cell,
    _fmt_point,
    _sort_groups,
)

__all__ = ["check_closed_surface", "check_delaunay_tetra", "check_enclosed_volume", "check_tetra", "tet_volume_terms"]

# Relative tolerance of the volume balance: both sums are exact identities of the same
# numbers, so they differ only by the rounding of O(m) products.
_VOLUME_RTOL = 1e-9


def check_tetra(mesh, check_delaunay: bool = False, shared: dict | None = None) -> None:
    """Run the tetra-specific checks on a mesh that passed the generic ones.

    Parameters
    ----------
    mesh : Mesh
        3-D mesh with tetrahedra (a mixed mesh with hexahedra is not checked here).
    check_delaunay : bool
        Also run :func:`check_delaunay_tetra`.
    shared : dict, optional
        What :meth:`Mesh.validate`'s generic checks computed: the tets' faces grouped
        (``("facets", 3)``: faces, counts, grouping) and :func:`tet_volume_terms`
        (``"tet_volume"``); without it they are computed here.

    Raises
    ------
    ValidationError
        Naming the face, edge, vertex or tets at fault.
    InputError
        ``check_delaunay`` on a mesh that also has hexahedra.
    """
    tets = mesh.tetra
    if len(mesh.hexahedra):
        if check_delaunay:
            raise InputError("check_delaunay needs a mesh of tetrahedra only; this one also has hexahedra")
        return
    shared = shared or {}
    if ("facets", 3) in shared:
        facets, count, _ = shared[("facets", 3)]
        faces = facets[count == 1].astype(np.int32)  # as boundary_facets, without sorting again
    else:
        faces = mesh.boundary_facets()
    check_closed_surface(faces, mesh.n_points)
    check_enclosed_volume(mesh.points, tets, faces, shared.get("tet_volume"))
    if check_delaunay:
        check_delaunay_tetra(mesh.points, tets)


def check_closed_surface(faces: np.ndarray, n_points: int) -> None:
    """Require a closed, consistently oriented, vertex-manifold triangle surface.

    Parameters
    ----------
    faces : (f, 3) int
        Oriented triangles (outward boundary faces of a tet mesh).
    n_points : int
        Upper bound of the vertex indices.

    Raises
    ------
    ValidationError
        An edge in one face or in more than two (open or non-manifold surface), an edge
        traversed twice in the same direction, or a vertex whose faces form several fans.
    """
    faces = np.asarray(faces, dtype=np.int64)
    if not len(faces):
        raise ValidationError("the tetrahedra have no boundary face: a bounded mesh must have one")
    # Directed edge j of face f runs from corner j to corner j+1.
    tail = faces.ravel()
    head = faces[:, [1, 2, 0]].ravel()
    keys = np.sort(np.column_stack([tail, head]), axis=1)
    order, group = _sort_groups(keys, n_points)
    sizes = np.bincount(group)
    count = np.empty(len(keys), np.int64)
    count[order] = sizes[group]
    bad = np.flatnonzero(count != 2)
    if len(bad):
        e = int(bad[0])
        members = order[group == group[np.flatnonzero(order == e)[0]]] // 3
        what = "open (a hole in the boundary)" if count[e] == 1 else "non-manifold"
        raise ValidationError(
            f"boundary edge ({tail[e]}, {head[e]}) lies in {count[e]} boundary faces "
            f"({_faces_text(faces, members)}): the boundary surface is {what}"
        )
    # Groups of two: the pair must traverse the edge in opposite directions.
    start = np.flatnonzero(np.diff(group, prepend=-1) != 0)
    first, second = order[start], order[start + 1]
    same = np.flatnonzero(tail[first] == tail[second])
    if len(same):
        e, g = int(first[same[0]]), int(second[same[0]])
        raise ValidationError(
            f"boundary edge ({tail[e]}, {head[e]}) is traversed in the same direction by boundary faces "
            f"{_faces_text(faces, [e // 3, g // 3])}: the boundary surface is not consistently oriented"
        )
    vertex, fans = _count_fans(faces, first, second, n_points)
    if vertex >= 0:
        around = np.flatnonzero(np.any(faces == vertex, axis=1))
        raise ValidationError(
            f"boundary vertex {vertex} is pinched: its {len(around)} boundary faces form {fans} separate fans "
            f"({_faces_text(faces, around[:6])}{', ...' if len(around) > 6 else ''}); the boundary is not a manifold"
        )


def _faces_text(faces: np.ndarray, idx) -> str:
    return ", ".join(f"({', '.join(str(int(v)) for v in faces[i])})" for i in idx)


@njit(cache=True)
def _find(parent, i):
    while parent[i] != i:
        parent[i] = parent[parent[i]]
        i = parent[i]
    return i


@njit(cache=True)
def _count_fans(faces, first, second, n_points):
    """Union the corners of adjacent faces around each vertex; return the first vertex with
    more than one class of corners and its number of classes, or (-1, 0).

    ``first[i]``, ``second[i]`` are the two directed edges ``3 f + j`` (from corner j to
    corner j + 1 of face f) of one undirected boundary edge.
    """
    nc = faces.shape[0] * 3
    parent = np.arange(nc)
    for i in range(first.shape[0]):
        e, g = first[i], second[i]
        f, j = e // 3, e % 3
        h, k = g // 3, g % 3
        # Opposite directions: e's tail is g's head and e's head is g's tail.
        a = _find(parent, 3 * f + j)
        b = _find(parent, 3 * h + (k + 1) % 3)
        parent[a] = b
        a = _find(parent, 3 * f + (j + 1) % 3)
        b = _find(parent, 3 * h + k)
        parent[a] = b
    classes = np.zeros(n_points, np.int64)
    for c in range(nc):
        if _find(parent, c) == c:
            classes[faces[c // 3, c % 3]] += 1
    for v in range(n_points):
        if classes[v] > 1:
            return v, classes[v]
    return -1, 0


def check_enclosed_volume(points: np.ndarray, tets: np.ndarray, faces: np.ndarray, tet_volume=None) -> None:
    """Require the volume enclosed by ``faces`` to equal the total volume of ``tets``.

    Parameters
    ----------
    points : (n, 3) float64
    tets : (m, 4) int
    faces : (f, 3) int
        Outward boundary faces of ``tets``.
    tet_volume : (float, float), optional
        :func:`tet_volume_terms` of ``points`` and ``tets`` if already computed.

    Raises
    ------
    ValidationError
        Giving both volumes, when they differ by more than rounding.
    """
    center = points.mean(axis=0)
    v_tets, tet_scale = tet_volume_terms(points, tets) if tet_volume is None else tet_volume
    # About the centroid: smaller products, less rounding.
    f = (points - center)[np.asarray(faces, dtype=np.int64)]
    face_terms = np.einsum("mi,mi->m", f[:, 0], np.cross(f[:, 1], f[:, 2])) / 6.0
    v_faces = float(face_terms.sum())
    scale = tet_scale + float(np.abs(face_terms).sum())
    if not abs(v_tets - v_faces) <= _VOLUME_RTOL * scale:
        raise ValidationError(
            f"the tets' volumes sum to {v_tets!r} but the boundary encloses {v_faces!r}: "
            "the boundary faces do not bound the tetrahedra"
        )


def tet_volume_terms(points: np.ndarray, tets: np.ndarray) -> tuple[float, float]:
    """Sum of the tets' signed volumes and sum of their absolute values, (float, float).

    Computed about the points' centroid (smaller products, less rounding); for large meshes
    in one Numba pass (the gathered NumPy form allocated 100 MB for a 1e6-tet mesh).

    Parameters
    ----------
    points : (n, 3) float64
    tets : (m, 4) int
    """
    center = points.mean(axis=0)
    if len(tets) < _KERNEL_MIN:  # nothing to compile for small meshes
        t = (points - center)[np.asarray(tets, dtype=np.int64)]
        terms = np.einsum("mi,mi->m", t[:, 1] - t[:, 0], np.cross(t[:, 2] - t[:, 0], t[:, 3] - t[:, 0])) / 6.0
        return float(terms.sum()), float(np.abs(terms).sum())
    total, absolute = _volume_terms(np.ascontiguousarray(points, dtype=np.float64), np.ascontiguousarray(tets), center)
    return float(total), float(absolute)


@njit(cache=True)
def _volume_terms(points, tets, center):
    total = 0.0
    absolute = 0.0
    for t in range(tets.shape[0]):
        a = tets[t, 0]
        ax = points[a, 0] - center[0]
        ay = points[a, 1] - center[1]
        az = points[a, 2] - center[2]
        b, c, d = tets[t, 1], tets[t, 2], tets[t, 3]
        ux = points[b, 0] - center[0] - ax
        uy = points[b, 1] - center[1] - ay
        uz = points[b, 2] - center[2] - az
        vx = points[c, 0] - center[0] - ax
        vy = points[c, 1] - center[1] - ay
        vz = points[c, 2] - center[2] - az
        wx = points[d, 0] - center[0] - ax
        wy = points[d, 1] - center[1] - ay
        wz = points[d, 2] - center[2] - az
        term = (ux * (vy * wz - vz * wy) + uy * (vz * wx - vx * wz) + uz * (vx * wy - vy * wx)) / 6.0
        total += term
        absolute += abs(term)
    return total, absolute


@njit(cache=True)
def _non_delaunay_faces(points, tets, nbr):
    """Interior faces (t, k), t < neighbour, whose opposite vertex is inside t's circumsphere."""
    m = tets.shape[0]
    found = np.zeros(m * 4, np.bool_)
    n_bad = 0
    for t in range(m):
        a, b, c, d = tets[t, 0], tets[t, 1], tets[t, 2], tets[t, 3]
        for k in range(4):
            u = nbr[t, k]
            if u <= t:
                continue
            e = -1
            for j in range(4):
                if nbr[u, j] == t:
                    e = tets[u, j]
            s = insphere(
                points[a, 0], points[a, 1], points[a, 2], points[b, 0], points[b, 1], points[b, 2],
                points[c, 0], points[c, 1], points[c, 2], points[d, 0], points[d, 1], points[d, 2],
                points[e, 0], points[e, 1], points[e, 2],
            )
            if s > 0.0:
                found[4 * t + k] = True
                n_bad += 1
    out = np.empty((n_bad, 2), np.int64)
    i = 0
    for f in range(m * 4):
        if found[f]:
            out[i, 0] = f // 4
            out[i, 1] = f % 4
            i += 1
    return out


def check_delaunay_tetra(points: np.ndarray, tets: np.ndarray) -> None:
    """Require every interior face to be locally Delaunay (exact ``insphere``).

    Parameters
    ----------
    points : (n, 3) float64
    tets : (m, 4) int
        Positively oriented, conforming (as :meth:`Mesh.validate` checks first).

    Raises
    ------
    ValidationError
        Naming the first face, its two tets, and the vertex inside the circumsphere.
    """
    tets = np.ascontiguousarray(tets, dtype=np.int64)
    nbr = build_neighbors_tet(tets).astype(np.int64)
    bad = _non_delaunay_faces(np.ascontiguousarray(points, dtype=np.float64), tets, nbr)
    if len(bad):
        t, k = int(bad[0, 0]), int(bad[0, 1])
        u = int(nbr[t, k])
        e = int(tets[u][nbr[u] == t][0])
        face = ", ".join(str(int(v)) for v in np.delete(tets[t], k))
        raise ValidationError(
            f"face ({face}) between {_fmt_cell('tetra', t, tets[t])} and {_fmt_cell('tetra', u, tets[u])} "
            f"is not locally Delaunay: vertex {e} at {_fmt_point(points[e])} lies inside the circumsphere "
            f"of tetra {t} ({len(bad)} such faces)"
        )
