r"""Spring-analogy (Laplacian) smoothing of tetrahedral meshes, boundary nodes kept on the surface.

Source: chapter 18.2 "Mesh Smoothing" (Spradley 1999), generalised from triangles
(:mod:`meshwright.tri.smoothing`) to tetrahedra.  Each edge is a spring; the force on
node i is

    f_i = c * sum_{j in N(i)} (x_j - x_i)

and an explicit step moves it by ``dx_i = relax / |N(i)| * f_i / c``: a fraction ``relax``
of the way to the centroid of its neighbours (``relax = 1`` is the classic Laplacian).

Which nodes move, and how:

* **Interior nodes** (on no boundary face, not ``fixed``) move towards the centroid of
  their edge neighbours.
* **Planar boundary nodes** slide within their plane, towards the centroid of their
  neighbours *on the surface* (the vertices of their boundary faces): a node whose
  boundary faces are all coplanar (exact ``orient3d`` of every one of their vertices
  against a non-degenerate reference face: zero), form a closed fan around it (every link
  vertex on an even number of them) and, when ``markers`` are given, share one marker.
  The move is projected onto the plane and the coordinate along the normal's largest
  component is re-solved from the plane equation; it is accepted only if the new position
  lies *exactly* on the plane of the node's original reference face (exact ``orient3d``).
  On an axis-aligned plane that always holds; on a tilted plane rounding often prevents
  it, and the node then stays where it is.  So a boundary node never leaves the surface.
* **Other boundary nodes** (edges and corners of the surface, interface junctions) and
  ``fixed`` nodes never move.

Safeguards (as the 2-D smoother): a move is accepted only if every tetrahedron of the
node's star stays strictly positive (exact ``orient3d``) and the worst radius ratio
``3 r / R`` of the star does not decrease; otherwise the step is halved, up to
``MAX_HALVINGS`` times, and then skipped.  Since the tets of a sliding node stay positive,
its boundary faces cannot fold over within the plane (each is a face of a positive tet on
one side), so the union of its faces, and with it the surface, is unchanged.  Passes are
Gauss-Seidel (each move sees the moves before it), stopping early when nothing moves.

Array layout
------------
points : (n, 3) float64, a modified copy is returned
tets : (k, 4) int32, positively oriented (``orient3d > 0``)
boundary_faces : (b, 3) int32, faces of the tets (boundary and interface faces)
CSR adjacency (built once, by counting): node -> incident tets (``star_off`` (n + 1,) int64,
``star`` int32), node -> edge neighbours (``nb_off``, ``nb``), node -> surface neighbours
(``snb_off``, ``snb``), node -> incident boundary faces (``face_off``, ``face``).
Per node: ``kind`` (n,) int8 (0 interior, 1 planar sliding, 2 fixed), ``plane`` (n, 9)
float64 (the reference face's corners) and ``normal`` (n, 3) float64 (its unit normal).

Invariants: node count and connectivity never change; every tet stays strictly positive
after every accepted move; a boundary node is either unmoved or exactly on its plane.
"""

from __future__ import annotations

import numbers

import numpy as np
from numba import njit

from meshwright.core.errors import InputError, ValidationError
from meshwright.core.flat import TET_FACES
from meshwright.core.mesh import build_neighbors_tet
from meshwright.core.predicates import orient2d, orient3d, orient3d_batch
from meshwright.core.validate_input import as_cells, as_exact_points, as_node_indices, check_count
from meshwright.tet._flips import _ratio_xyz

__all__ = ["MAX_HALVINGS", "smooth_tets"]

MAX_HALVINGS = 4

INTERIOR, SLIDING, FIXED = 0, 1, 2


@njit(cache=True)
def _incidence(cells, n):
    """CSR ``(offsets (n + 1,) int64, rows int32)``: the rows of ``cells`` (k, w) at each node."""
    off = np.zeros(n + 1, dtype=np.int64)
    for r in range(cells.shape[0]):
        for k in range(cells.shape[1]):
            off[cells[r, k] + 1] += 1
    for i in range(n):
        off[i + 1] += off[i]
    rows = np.empty(off[n], dtype=np.int32)
    fill = off[:-1].copy()
    for r in range(cells.shape[0]):
        for k in range(cells.shape[1]):
            v = cells[r, k]
            rows[fill[v]] = r
            fill[v] += 1
    return off, rows


@njit(cache=True)
def _neighbours(cells, off, rows, n):
    """CSR ``(offsets (n + 1,) int64, nodes int32)``: the distinct other vertices of the rows
    of ``cells`` at each node (edge neighbours for tets, surface neighbours for faces)."""
    seen = np.full(n, -1, dtype=np.int64)
    count = np.zeros(n + 1, dtype=np.int64)
    for i in range(n):
        for s in range(off[i], off[i + 1]):
            for k in range(cells.shape[1]):
                v = cells[rows[s], k]
                if v != i and seen[v] != i:
                    seen[v] = i
                    count[i + 1] += 1
    for i in range(n):
        count[i + 1] += count[i]
    out = np.empty(count[n], dtype=np.int32)
    seen[:] = -1
    for i in range(n):
        m = count[i]
        for s in range(off[i], off[i + 1]):
            for k in range(cells.shape[1]):
                v = cells[rows[s], k]
                if v != i and seen[v] != i:
                    seen[v] = i
                    out[m] = v
                    m += 1
    return count, out


@njit(inline="always")
def _radius_ratio(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz):
    """3 r / R of a tetrahedron (1 regular, 0 flat or inverted); floating-point, a measure, not a decision."""
    r = _ratio_xyz(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz)
    return 3.0 * r if r > 0.0 else 0.0


@njit(inline="always")
def _corner(xyz, tets, t, k, i, px, py, pz):
    """Vertex k of tet t, with node i at (px, py, pz)."""
    v = tets[t, k]
    if v == i:
        return px, py, pz
    return xyz[v, 0], xyz[v, 1], xyz[v, 2]


@njit(cache=True)
def _worst_around(xyz, tets, star_off, star, i, px, py, pz, floor):
    """Worst radius ratio of the tets around node i if it sat at (px, py, pz); -1.0 if any
    of them would not be strictly positive (exact orient3d).  Stops at the first tet below
    ``floor`` (returning its ratio): the caller only asks whether the worst reaches it."""
    worst = 1.0
    for s in range(star_off[i], star_off[i + 1]):
        t = star[s]
        ax, ay, az = _corner(xyz, tets, t, 0, i, px, py, pz)
        bx, by, bz = _corner(xyz, tets, t, 1, i, px, py, pz)
        cx, cy, cz = _corner(xyz, tets, t, 2, i, px, py, pz)
        dx, dy, dz = _corner(xyz, tets, t, 3, i, px, py, pz)
        if orient3d(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz) <= 0.0:
            return -1.0
        q = _radius_ratio(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz)
        if q < floor:
            return q
        worst = min(worst, q)
    return worst


@njit(inline="always")
def _collinear(ax, ay, az, bx, by, bz, cx, cy, cz):
    """Exact: a, b, c on one line (all three coordinate projections degenerate)."""
    return (
        orient2d(ax, ay, bx, by, cx, cy) == 0.0
        and orient2d(ay, az, by, bz, cy, cz) == 0.0
        and orient2d(az, ax, bz, bx, cz, cx) == 0.0
    )


@njit(cache=True)
def _classify(xyz, faces, markers, face_off, face, kind, plane, normal):
    """Mark boundary nodes SLIDING (coplanar closed fan, one marker) or FIXED, in place.

    ``kind`` on entry: INTERIOR everywhere except FIXED for the caller's fixed nodes.
    """
    n = xyz.shape[0]
    for i in range(n):
        lo = face_off[i]
        hi = face_off[i + 1]
        if hi == lo or kind[i] == FIXED:
            continue
        kind[i] = FIXED
        ref = -1
        for s in range(lo, hi):
            f = face[s]
            a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
            if not _collinear(xyz[a, 0], xyz[a, 1], xyz[a, 2], xyz[b, 0], xyz[b, 1], xyz[b, 2],
                              xyz[c, 0], xyz[c, 1], xyz[c, 2]):
                ref = f
                break
        if ref < 0:
            continue
        a, b, c = faces[ref, 0], faces[ref, 1], faces[ref, 2]
        ok = True
        link = np.empty(2 * (hi - lo), dtype=np.int64)
        for s in range(lo, hi):
            f = face[s]
            if markers[f] != markers[ref]:
                ok = False
                break
            m = 0
            for k in range(3):
                v = faces[f, k]
                if orient3d(xyz[a, 0], xyz[a, 1], xyz[a, 2], xyz[b, 0], xyz[b, 1], xyz[b, 2],
                            xyz[c, 0], xyz[c, 1], xyz[c, 2], xyz[v, 0], xyz[v, 1], xyz[v, 2]) != 0.0:
                    ok = False
                if v != i:
                    link[2 * (s - lo) + m] = v
                    m += 1
        if not ok:
            continue
        # A closed fan meets every link vertex an even number of times.
        link.sort()
        run = 1
        for s in range(1, link.shape[0] + 1):
            if s < link.shape[0] and link[s] == link[s - 1]:
                run += 1
                continue
            if run % 2 == 1:
                ok = False
            run = 1
        if not ok:
            continue
        ux, uy, uz = xyz[b, 0] - xyz[a, 0], xyz[b, 1] - xyz[a, 1], xyz[b, 2] - xyz[a, 2]
        vx, vy, vz = xyz[c, 0] - xyz[a, 0], xyz[c, 1] - xyz[a, 1], xyz[c, 2] - xyz[a, 2]
        nx, ny, nz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
        length = np.sqrt(nx * nx + ny * ny + nz * nz)
        if not length > 0.0:
            continue
        for k in range(3):
            v = faces[ref, k]
            plane[i, 3 * k] = xyz[v, 0]
            plane[i, 3 * k + 1] = xyz[v, 1]
            plane[i, 3 * k + 2] = xyz[v, 2]
        normal[i, 0] = nx / length
        normal[i, 1] = ny / length
        normal[i, 2] = nz / length
        kind[i] = SLIDING


@njit(inline="always")
def _on_plane(plane, i, px, py, pz):
    return orient3d(plane[i, 0], plane[i, 1], plane[i, 2], plane[i, 3], plane[i, 4], plane[i, 5],
                    plane[i, 6], plane[i, 7], plane[i, 8], px, py, pz) == 0.0


@njit(inline="always")
def _snap(plane, normal, i, px, py, pz):
    """(px, py, pz) with its coordinate along the normal's largest component re-solved
    from the plane equation through the reference face's first corner (floating point)."""
    nx, ny, nz = normal[i, 0], normal[i, 1], normal[i, 2]
    ax, ay, az = plane[i, 0], plane[i, 1], plane[i, 2]
    if abs(nx) >= abs(ny) and abs(nx) >= abs(nz):
        return ax - (ny * (py - ay) + nz * (pz - az)) / nx, py, pz
    if abs(ny) >= abs(nz):
        return px, ay - (nx * (px - ax) + nz * (pz - az)) / ny, pz
    return px, py, az - (nx * (px - ax) + ny * (py - ay)) / nz


@njit(cache=True)
def _smooth(xyz, tets, star_off, star, nb_off, nb, snb_off, snb, kind, plane, normal, relax, iterations):
    """``iterations`` Gauss-Seidel passes over the movable nodes, in place; returns the
    number of moves accepted."""
    n = xyz.shape[0]
    total = 0
    for _ in range(iterations):
        moved = 0
        for i in range(n):
            k = kind[i]
            if k == FIXED or star_off[i + 1] == star_off[i]:
                continue
            off = nb_off if k == INTERIOR else snb_off
            lst = nb if k == INTERIOR else snb
            cnt = off[i + 1] - off[i]
            if cnt == 0:
                continue
            dx = 0.0
            dy = 0.0
            dz = 0.0
            for s in range(off[i], off[i + 1]):
                j = lst[s]
                dx += xyz[j, 0] - xyz[i, 0]
                dy += xyz[j, 1] - xyz[i, 1]
                dz += xyz[j, 2] - xyz[i, 2]
            dx *= relax / cnt
            dy *= relax / cnt
            dz *= relax / cnt
            if k == SLIDING:
                along = dx * normal[i, 0] + dy * normal[i, 1] + dz * normal[i, 2]
                dx -= along * normal[i, 0]
                dy -= along * normal[i, 1]
                dz -= along * normal[i, 2]
            before = _worst_around(xyz, tets, star_off, star, i, xyz[i, 0], xyz[i, 1], xyz[i, 2], -1.0)
            for _h in range(MAX_HALVINGS + 1):
                px = xyz[i, 0] + dx
                py = xyz[i, 1] + dy
                pz = xyz[i, 2] + dz
                ok = True
                if k == SLIDING:
                    px, py, pz = _snap(plane, normal, i, px, py, pz)
                    ok = _on_plane(plane, i, px, py, pz)
                if ok:
                    after = _worst_around(xyz, tets, star_off, star, i, px, py, pz, before)
                    if after > 0.0 and after >= before:
                        xyz[i, 0] = px
                        xyz[i, 1] = py
                        xyz[i, 2] = pz
                        moved += 1
                        break
                dx *= 0.5
                dy *= 0.5
                dz *= 0.5
        total += moved
        if moved == 0:
            break
    return total


def _boundary(tets: np.ndarray, boundary_faces, markers, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Checked ``(faces (b, 3) int32, markers (b,) int64)``; default: faces on one tet only."""
    tet_faces = tets[:, TET_FACES].reshape(-1, 3)
    if boundary_faces is None:
        if markers is not None:
            raise InputError("markers need boundary_faces: they label its rows")
        try:
            open_face = build_neighbors_tet(tets).ravel() < 0 if len(tets) else np.zeros(0, dtype=bool)
        except ValidationError as exc:
            raise InputError(f"tets: {exc}") from exc
        faces = np.ascontiguousarray(tet_faces[open_face], dtype=np.int32)
        return faces, np.zeros(len(faces), dtype=np.int64)
    faces = as_cells(boundary_faces, "boundary_faces", 3, n)
    if markers is None:
        mk = np.zeros(len(faces), dtype=np.int64)
    else:
        mk = np.asarray(markers)
        if mk.shape != (len(faces),) or (mk.size and (mk.dtype == bool or not np.issubdtype(mk.dtype, np.integer))):
            raise InputError(f"markers must be ({len(faces)},) integers, one per boundary face, got {mk.shape} {mk.dtype}")
        mk = mk.astype(np.int64)
    # Every boundary face must be a face of a tet: compare sorted vertex triples, one int64
    # code each while n**3 fits, rows otherwise.
    key_t = np.sort(tet_faces.astype(np.int64), axis=1)
    key_f = np.sort(faces.astype(np.int64), axis=1)
    if n < 2**20:
        code_t = np.sort(key_t @ np.array([n * n, n, 1]))
        code_f = key_f @ np.array([n * n, n, 1])
        pos = np.minimum(np.searchsorted(code_t, code_f), len(code_t) - 1)
        found = code_t[pos] == code_f if len(code_t) else np.zeros(len(code_f), dtype=bool)
    else:
        _, group = np.unique(np.concatenate([key_t, key_f]), axis=0, return_inverse=True)
        group = group.ravel()
        in_tets = np.zeros(int(group.max()) + 1, dtype=bool)
        in_tets[group[: len(key_t)]] = True
        found = in_tets[group[len(key_t) :]]
    missing = np.flatnonzero(~found)
    if len(missing):
        i = missing[0]
        raise InputError(f"boundary_faces row {i} {faces[i].tolist()} is not a face of any tet")
    return faces, mk


def smooth_tets(
    points,
    tets,
    boundary_faces=None,
    *,
    iterations: int = 5,
    relax: float = 1.0,
    fixed=None,
    markers=None,
) -> np.ndarray:
    """Smooth a tetrahedral mesh with the chapter's spring analogy, keeping the surface.

    Parameters
    ----------
    points : (n, 3) array_like of float64
        Node coordinates (not modified; a smoothed copy is returned).
    tets : (k, 4) array_like of int
        Positively oriented tetrahedra (``orient3d > 0``).
    boundary_faces : (b, 3) array_like of int, optional
        Faces of the tets on the surface to keep: the boundary and any interface between
        regions (a ``Mesh``'s ``triangle`` cells).  Default: the faces of exactly one tet.
    iterations : int
        Number of passes (time steps); 0 returns an unchanged copy.  5-10 suffice.
    relax : float
        ``c * dt`` of the spring analogy, in (0, 1]; 1 moves a node to its neighbours' centroid.
    fixed : (f,) int or (n,) bool, optional
        Nodes that never move.
    markers : (b,) int, optional
        Marker of each boundary face; a node where faces of different markers meet is fixed,
        so marker borders stay where they are even inside one plane.

    Returns
    -------
    (n, 3) float64
        Smoothed coordinates, connectivity unchanged: every tet strictly positive (exact
        ``orient3d``), the worst radius ratio around every moved node not decreased, every
        boundary node unmoved or slid exactly within its plane (see the module docstring).

    Raises
    ------
    InputError
        Naming the argument: ``points`` not (n, 3), NaN/infinite or outside the predicates'
        exact range; ``tets`` / ``boundary_faces`` / ``fixed`` not integer, of the wrong
        shape or referring to a node outside ``[0, n)`` (the row named); a tet that is not
        positively oriented (its index named); a boundary face that is no face of a tet;
        ``markers`` not one integer per boundary face; ``iterations`` not an integer >= 0;
        ``relax`` outside (0, 1].
    """
    xyz = as_exact_points(points, "points", 3, copy=True)
    n = len(xyz)
    cells = as_cells(tets, "tets", 4, n)
    iterations = check_count(iterations, "iterations")
    if isinstance(relax, bool) or not isinstance(relax, numbers.Real) or not 0.0 < float(relax) <= 1.0:
        raise InputError(f"relax = c*dt must be a number in (0, 1], got {relax!r}")
    relax = float(relax)
    fixed_nodes = as_node_indices(fixed, n)
    if len(cells):
        sign = orient3d_batch(xyz, cells)
        bad = np.flatnonzero(sign <= 0.0)
        if len(bad):
            t = bad[0]
            raise InputError(f"tets row {t} {cells[t].tolist()} is not positively oriented (orient3d <= 0)")
    faces, mk = _boundary(cells, boundary_faces, markers, n)
    if iterations == 0 or len(cells) == 0:
        return xyz

    star_off, star = _incidence(cells, n)
    nb_off, nb = _neighbours(cells, star_off, star, n)
    face_off, face = _incidence(faces, n)
    snb_off, snb = _neighbours(faces, face_off, face, n)
    kind = np.zeros(n, dtype=np.int8)
    kind[fixed_nodes] = FIXED
    plane = np.zeros((n, 9))
    normal = np.zeros((n, 3))
    _classify(xyz, faces, mk, face_off, face, kind, plane, normal)
    _smooth(xyz, cells, star_off, star, nb_off, nb, snb_off, snb, kind, plane, normal, relax, iterations)
    return xyz
