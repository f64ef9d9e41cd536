r"""Point location and linear interpolation on a background of tetrahedra (the 3-D kernels of
:class:`meshwright.sizing.BackgroundGrid`, chapter 18.4.2 step 1).

Source: the background mesh of J. Peraire, J. Peiro and K. Morgan, "Adaptive remeshing for
three-dimensional compressible flow computations", J. Comput. Phys. 103, 1992 (spacing
given at the nodes of a coarse tetrahedral mesh, interpolated linearly inside each
tetrahedron); the closest point of a triangle is C. Ericson's, "Real-Time Collision
Detection", Morgan Kaufmann 2005, section 5.1.5 (Voronoi regions of the vertices, edges
and face).

A query is located by the bucket grid of :mod:`meshwright.sizing._buckets` (the tetrahedra
listed in its cube, then in growing shells of cubes), or by a walk across faces from a
hint for queries that move a little at a time.  Inside a tetrahedron the value is
``sum_k w_k values[v_k]`` with the barycentric weights ``w``.  A query in no tetrahedron
takes the weights of the nearest point of the nearest tetrahedron (the 2-D grid's rule),
found by a search in shells of cubes that skips every cube farther than the best so far
and stops at the first shell with no nearer cube: exact (up to rounding) for any query,
and a few shells for a query far outside.  All of this is floating-point interpolation,
not a topological decision: no exact predicate is needed, and a point on a shared face gets
the same value from either side up to rounding.

Layout: ``pts`` (n, 3) float64, ``tets`` (k, 4) int32 positively oriented,
``nbr`` (k, 4) int32 (across the face opposite vertex j, -1 on the border), ``start`` /
``items`` the CSR bucket lists, ``(x0, y0, z0)`` the grid's lower corner, ``cell`` the cube
side, ``(nx, ny, nz)`` the cubes per axis, ``values`` (n, c) float64 nodal columns.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["interpolate3d", "interpolate3d_one", "interpolate3d_walk", "weights3d"]

_MAX_WALK = 4096


@njit(inline="always")
def _det3(ux, uy, uz, vx, vy, vz, wx, wy, wz):
    return ux * (vy * wz - vz * wy) - uy * (vx * wz - vz * wx) + uz * (vx * wy - vy * wx)


@njit(inline="always")
def _corner(pts, tets, t, k, e, x, y, z):
    """Vertex k of tet t, or (x, y, z) in its place when k == e."""
    if k == e:
        return x, y, z
    v = tets[t, k]
    return pts[v, 0], pts[v, 1], pts[v, 2]


@njit(inline="always")
def _side(pts, tets, t, e, x, y, z):
    """Six times the signed volume of tet t with its vertex e replaced by (x, y, z)."""
    ax, ay, az = _corner(pts, tets, t, 0, e, x, y, z)
    bx, by, bz = _corner(pts, tets, t, 1, e, x, y, z)
    cx, cy, cz = _corner(pts, tets, t, 2, e, x, y, z)
    dx, dy, dz = _corner(pts, tets, t, 3, e, x, y, z)
    return _det3(bx - ax, by - ay, bz - az, cx - ax, cy - ay, cz - az, dx - ax, dy - ay, dz - az)


@njit(inline="always")
def _barycentric(pts, tets, t, x, y, z):
    """Barycentric weights ``(w0, w1, w2, w3)`` of (x, y, z) in tet t (they sum to 1)."""
    a = tets[t, 0]
    full = _det3(
        pts[tets[t, 1], 0] - pts[a, 0], pts[tets[t, 1], 1] - pts[a, 1], pts[tets[t, 1], 2] - pts[a, 2],
        pts[tets[t, 2], 0] - pts[a, 0], pts[tets[t, 2], 1] - pts[a, 1], pts[tets[t, 2], 2] - pts[a, 2],
        pts[tets[t, 3], 0] - pts[a, 0], pts[tets[t, 3], 1] - pts[a, 1], pts[tets[t, 3], 2] - pts[a, 2],
    )
    w1 = _side(pts, tets, t, 1, x, y, z) / full
    w2 = _side(pts, tets, t, 2, x, y, z) / full
    w3 = _side(pts, tets, t, 3, x, y, z) / full
    return 1.0 - w1 - w2 - w3, w1, w2, w3


@njit(inline="always")
def _closest_on_triangle(ax, ay, az, bx, by, bz, cx, cy, cz, px, py, pz):
    """Weights ``(u, v, w)`` of a, b, c of the point of the triangle abc nearest p
    (Ericson's Voronoi-region cases): non-negative, summing to 1."""
    abx, aby, abz = bx - ax, by - ay, bz - az
    acx, acy, acz = cx - ax, cy - ay, cz - az
    d1 = abx * (px - ax) + aby * (py - ay) + abz * (pz - az)
    d2 = acx * (px - ax) + acy * (py - ay) + acz * (pz - az)
    if d1 <= 0.0 and d2 <= 0.0:
        return 1.0, 0.0, 0.0
    d3 = abx * (px - bx) + aby * (py - by) + abz * (pz - bz)
    d4 = acx * (px - bx) + acy * (py - by) + acz * (pz - bz)
    if d3 >= 0.0 and d4 <= d3:
        return 0.0, 1.0, 0.0
    vc = d1 * d4 - d3 * d2
    if vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0:
        v = d1 / (d1 - d3)
        return 1.0 - v, v, 0.0
    d5 = abx * (px - cx) + aby * (py - cy) + abz * (pz - cz)
    d6 = acx * (px - cx) + acy * (py - cy) + acz * (pz - cz)
    if d6 >= 0.0 and d5 <= d6:
        return 0.0, 0.0, 1.0
    vb = d5 * d2 - d1 * d6
    if vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0:
        w = d2 / (d2 - d6)
        return 1.0 - w, 0.0, w
    va = d3 * d6 - d5 * d4
    if va <= 0.0 and d4 - d3 >= 0.0 and d5 - d6 >= 0.0:
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        return 0.0, 1.0 - w, w
    den = va + vb + vc
    if den == 0.0:
        return 1.0, 0.0, 0.0
    # Inside the face: rounding may leave a weight a hair below zero; clamp and renormalise
    # so the interpolation stays a convex combination.
    v = min(1.0, max(0.0, vb / den))
    w = min(1.0 - v, max(0.0, vc / den))
    return 1.0 - v - w, v, w


@njit(inline="always")
def _nearest_on_border(pts, tets, nbr, t, x, y, z):
    """``(d2, f, u, v, w)``: the border face f of tet t (one without a neighbour) nearest
    (x, y, z), the squared distance and the weights of its vertices ``tets[t, (f + 1) % 4]``,
    ``(f + 2) % 4``, ``(f + 3) % 4`` at the nearest point; d2 infinite when t has no border
    face."""
    best = np.inf
    bf = 0
    bu = 1.0
    bv = 0.0
    bw = 0.0
    for f in range(4):
        if nbr[t, f] >= 0:
            continue
        a = tets[t, (f + 1) % 4]
        b = tets[t, (f + 2) % 4]
        c = tets[t, (f + 3) % 4]
        u, v, w = _closest_on_triangle(
            pts[a, 0], pts[a, 1], pts[a, 2], pts[b, 0], pts[b, 1], pts[b, 2], pts[c, 0], pts[c, 1], pts[c, 2], x, y, z
        )
        qx = u * pts[a, 0] + v * pts[b, 0] + w * pts[c, 0]
        qy = u * pts[a, 1] + v * pts[b, 1] + w * pts[c, 1]
        qz = u * pts[a, 2] + v * pts[b, 2] + w * pts[c, 2]
        d2 = (qx - x) ** 2 + (qy - y) ** 2 + (qz - z) ** 2
        if d2 < best:
            best, bf, bu, bv, bw = d2, f, u, v, w
    return best, bf, bu, bv, bw


@njit(inline="always")
def _axis_gap(v, lo, i, cell):
    """Distance along one axis from v to the cube slab [lo + i cell, lo + (i + 1) cell]."""
    a = lo + i * cell
    if v < a:
        return a - v
    b = a + cell
    return v - b if v > b else 0.0


@njit(cache=True)
def weights3d(pts, tets, nbr, start, items, x0, y0, z0, cell, nx, ny, nz, x, y, z):
    """Background tet and barycentric weights ``(t, w0, w1, w2, w3)`` for the point (x, y, z).

    The containing tet is searched among those listed in the query's cube (a tet holding
    the query has the query in its bounding box, so it is listed there).  A point in no tet
    takes the weights of the nearest point of the background, which lies on a border face
    (one without a neighbour tet), searched in shells of cubes
    around the query's cube, cubes farther than the best distance so far skipped; the
    search stops at the first shell whose nearest cube is no nearer than the best (every
    later shell is farther still: along each axis a cube's distance grows with its offset).
    """
    ci = min(nx - 1, max(0, int((x - x0) / cell)))
    cj = min(ny - 1, max(0, int((y - y0) / cell)))
    ck = min(nz - 1, max(0, int((z - z0) / cell)))
    c = ci + nx * (cj + ny * ck)
    for s in range(start[c], start[c + 1]):
        t = items[s]
        w0, w1, w2, w3 = _barycentric(pts, tets, t, x, y, z)
        if min(w0, w1, w2, w3) >= 0.0:
            return t, w0, w1, w2, w3
    best = -1
    best_d2 = np.inf
    bf = 0
    bu = 1.0
    bv = 0.0
    bw = 0.0
    for ring in range(max(nx, ny, nz) + 1):
        ring_d2 = np.inf
        for k in range(max(0, ck - ring), min(nz, ck + ring + 1)):
            gz = _axis_gap(z, z0, k, cell)
            for j in range(max(0, cj - ring), min(ny, cj + ring + 1)):
                gy = _axis_gap(y, y0, j, cell)
                outer = max(abs(j - cj), abs(k - ck)) == ring
                # Inside the shell's (j, k) span only the two end cubes along x are new.
                step = 1 if outer or ring == 0 else 2 * ring
                for i in range(ci - ring, ci + ring + 1, step):
                    if i < 0 or i >= nx:
                        continue
                    gx = _axis_gap(x, x0, i, cell)
                    cube_d2 = gx * gx + gy * gy + gz * gz
                    ring_d2 = min(ring_d2, cube_d2)
                    if cube_d2 >= best_d2:
                        continue
                    c = i + nx * (j + ny * k)
                    for s in range(start[c], start[c + 1]):
                        t = items[s]
                        d2, f, u, v, w = _nearest_on_border(pts, tets, nbr, t, x, y, z)
                        if d2 < best_d2:
                            best, best_d2, bf, bu, bv, bw = t, d2, f, u, v, w
        if ring_d2 >= best_d2:
            break
    # Slot bf gets nothing; slots bf + 1, bf + 2, bf + 3 (mod 4) get u, v, w.
    ws = np.zeros(4)
    ws[(bf + 1) % 4] = bu
    ws[(bf + 2) % 4] = bv
    ws[(bf + 3) % 4] = bw
    return best, ws[0], ws[1], ws[2], ws[3]


@njit(inline="always")
def _combine(tets, t, values, col, w0, w1, w2, w3):
    return (
        w0 * values[tets[t, 0], col] + w1 * values[tets[t, 1], col]
        + w2 * values[tets[t, 2], col] + w3 * values[tets[t, 3], col]
    )


@njit(cache=True)
def interpolate3d_one(pts, tets, nbr, start, items, x0, y0, z0, cell, nx, ny, nz, values, col, x, y, z):
    """Linear interpolation of column ``col`` of ``values`` (n, c) at one point (x, y, z), the
    grid as :meth:`~meshwright.sizing.BackgroundGrid.kernel_args` gives it; kernels that
    need sizes inside their loops call this (or :func:`interpolate3d_walk`) directly."""
    t, w0, w1, w2, w3 = weights3d(pts, tets, nbr, start, items, x0, y0, z0, cell, nx, ny, nz, x, y, z)
    return _combine(tets, t, values, col, w0, w1, w2, w3)


@njit(cache=True)
def interpolate3d_walk(pts, tets, nbr, start, items, x0, y0, z0, cell, nx, ny, nz, values, col, hint, x, y, z):
    """:func:`interpolate3d_one` walking across faces from the tet ``hint[0]`` (updated), for
    queries that move a little at a time: O(distance) instead of a bucket scan.  A walk that
    leaves the background or runs past its step cap falls back to the bucket search."""
    t = hint[0]
    if t < 0 or t >= tets.shape[0]:
        t = 0
    for step in range(_MAX_WALK):
        moved = False
        for j in range(4):
            e = (j + step) % 4
            if _side(pts, tets, t, e, x, y, z) < 0.0:
                n = nbr[t, e]
                if n < 0:
                    return interpolate3d_one(
                        pts, tets, nbr, start, items, x0, y0, z0, cell, nx, ny, nz, values, col, x, y, z
                    )
                t = n
                moved = True
                break
        if not moved:
            hint[0] = t
            w0, w1, w2, w3 = _barycentric(pts, tets, t, x, y, z)
            return _combine(tets, t, values, col, w0, w1, w2, w3)
    return interpolate3d_one(pts, tets, nbr, start, items, x0, y0, z0, cell, nx, ny, nz, values, col, x, y, z)


@njit(cache=True)
def interpolate3d(pts, tets, nbr, start, items, x0, y0, z0, cell, nx, ny, nz, values, xyz):
    """Linear interpolation of ``values`` (n, c) at ``xyz`` (q, 3); returns (q, c) float64."""
    q = xyz.shape[0]
    k = values.shape[1]
    out = np.empty((q, k))
    for p in range(q):
        t, w0, w1, w2, w3 = weights3d(
            pts, tets, nbr, start, items, x0, y0, z0, cell, nx, ny, nz, xyz[p, 0], xyz[p, 1], xyz[p, 2]
        )
        for c in range(k):
            out[p, c] = _combine(tets, t, values, c, w0, w1, w2, w3)
    return out
