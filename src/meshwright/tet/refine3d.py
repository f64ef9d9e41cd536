r"""Delaunay refinement of a recovered tetrahedral mesh: interior points at circumcentres (18.4.1).

The chapter's 3-D procedure creates interior points until the elements match the spacing
wanted; this module does it as Delaunay refinement (Shewchuk 1998, "Tetrahedral mesh
generation by Delaunay refinement", Proc. 14th SoCG; Si 2015, TetGen, ACM TOMS 41(2)): a
solid tet is *bad* when its radius-edge ratio ``R / l_min`` exceeds the bound B, its
circumradius exceeds ``0.8 h`` (``h`` the size field at its centroid; 0.612 h is the regular
tet of edge h) or its volume exceeds its region's bound, and the point inserted for it is its
circumcentre c, unless c *encroaches* a subface: c lies beyond a subface (the walk from the tet
to c would cross it), inside the diametral ball of a subface met by its cavity, or inside the
circumballs of the tets on both sides of one (inserting c would delete it).  Then the
subface is split instead (its longest edge bisected, :mod:`meshwright.tet.recovery`), which
keeps new points away from the boundary, the condition of Shewchuk's termination proof for
B > 2 and input angles >= 90 degrees.  Smaller input angles can make splits cascade: an edge
shorter than ``guard`` is never split and the tets that would need it stay (counted in the
report), as TetGen and Triangle exempt tets at small input angles.

Rounds, not one point at a time: every round takes all bad tets (largest circumradius
first), walks to each circumcentre, grows its cavity in the round's mesh and *defers* it when
that cavity meets the cavity of a point accepted earlier in the round.  The accepted points
have disjoint cavities, an independent set as in parallel Delaunay refinement (Chernikov and
Chrisochoides 2006), so inserting them together equals inserting them one by one: one
point repairs all the bad tets its cavity removes.  (Accepting every point farther than
half a circumradius from the others instead gave ten times the points on the sphere: most
were not needed once their neighbours were in.)  Then the accepted points and surface
midpoints are inserted into the Delaunay tetrahedralization in BRIO order
(:meth:`Tetrahedralization.insert`) and missing subfaces are recovered.  Each round costs
O(n) array passes.

Arrays (kernel :func:`select_points`): ``pts`` (nv, 3) float64; ``tets``, ``nbr`` (nt, 4)
int32 and ``barrier`` (nt, 4) bool as in :mod:`meshwright.tet.exterior`; ``cc`` (nt, 3)
float64 circumcentres and ``r2`` (nt,) float64 squared circumradii; ``bad`` (b,) int32 the
bad tets in priority order.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.predicates import orient3d

__all__ = ["select_points", "circumspheres", "SIZE_FACTOR", "WALK_CAP"]

SIZE_FACTOR = 0.8  # a tet is too large when R > SIZE_FACTOR * h
WALK_CAP = 1 << 16


def circumspheres(pts: np.ndarray, tets: np.ndarray):
    """Circumcentres (nt, 3), squared circumradii (nt,), shortest edges (nt,) and volumes (nt,).

    Degenerate (zero-volume) tets get an infinite radius and centre.
    """
    p0 = pts[tets[:, 0]]
    u = pts[tets[:, 1]] - p0
    v = pts[tets[:, 2]] - p0
    w = pts[tets[:, 3]] - p0
    vxw = np.cross(v, w)
    det = np.einsum("ij,ij->i", u, vxw)
    lu = np.einsum("ij,ij->i", u, u)
    lv = np.einsum("ij,ij->i", v, v)
    lw = np.einsum("ij,ij->i", w, w)
    with np.errstate(divide="ignore", invalid="ignore"):
        off = (lu[:, None] * vxw + lv[:, None] * np.cross(w, u) + lw[:, None] * np.cross(u, v)) / (2.0 * det[:, None])
    off[~np.isfinite(off).all(axis=1)] = np.inf
    r2 = np.einsum("ij,ij->i", off, off)
    e2 = np.minimum(np.minimum(lu, lv), lw)
    for a, b in ((1, 2), (2, 3), (1, 3)):
        d = pts[tets[:, a]] - pts[tets[:, b]]
        e2 = np.minimum(e2, np.einsum("ij,ij->i", d, d))
    return p0 + off, r2, np.sqrt(e2), det / 6.0


@njit(inline="always")
def _beyond(pts, tets, u, k, cx, cy, cz):
    """Whether point c lies strictly beyond face k of tet u (the tet with c for vertex k is negative)."""
    q = np.empty((4, 3))
    for j in range(4):
        v = tets[u, j]
        q[j, 0] = pts[v, 0]
        q[j, 1] = pts[v, 1]
        q[j, 2] = pts[v, 2]
    q[k, 0] = cx
    q[k, 1] = cy
    q[k, 2] = cz
    return orient3d(q[0, 0], q[0, 1], q[0, 2], q[1, 0], q[1, 1], q[1, 2], q[2, 0], q[2, 1], q[2, 2], q[3, 0], q[3, 1], q[3, 2]) < 0.0


@njit(inline="always")
def _in_diametral_ball(pts, tets, w, k, cx, cy, cz):
    """Whether c lies strictly inside the smallest ball through face k of tet w."""
    a = tets[w, (k + 1) % 4]
    b = tets[w, (k + 2) % 4]
    c = tets[w, (k + 3) % 4]
    ux = pts[b, 0] - pts[a, 0]
    uy = pts[b, 1] - pts[a, 1]
    uz = pts[b, 2] - pts[a, 2]
    vx = pts[c, 0] - pts[a, 0]
    vy = pts[c, 1] - pts[a, 1]
    vz = pts[c, 2] - pts[a, 2]
    nx = uy * vz - uz * vy
    ny = uz * vx - ux * vz
    nz = ux * vy - uy * vx
    n2 = nx * nx + ny * ny + nz * nz
    if n2 == 0.0:
        return False
    lu = ux * ux + uy * uy + uz * uz
    lv = vx * vx + vy * vy + vz * vz
    # centre offset = (|u|^2 v - |v|^2 u) x n / (2 |n|^2)
    sx = lu * vx - lv * ux
    sy = lu * vy - lv * uy
    sz = lu * vz - lv * uz
    ox = (sy * nz - sz * ny) / (2.0 * n2)
    oy = (sz * nx - sx * nz) / (2.0 * n2)
    oz = (sx * ny - sy * nx) / (2.0 * n2)
    r2 = ox * ox + oy * oy + oz * oz
    dx = cx - pts[a, 0] - ox
    dy = cy - pts[a, 1] - oy
    dz = cz - pts[a, 2] - oz
    return dx * dx + dy * dy + dz * dz < r2


@njit(cache=True)
def select_points(pts, tets, nbr, barrier, cc, r2, bad, rng_state):
    """Walk to each bad tet's circumcentre, grow its cavity, accept, defer or redirect it.

    Parameters
    ----------
    pts : (nv, 3) float64
    tets, nbr : (nt, 4) int32
    barrier : (nt, 4) bool
    cc : (nt, 3) float64
    r2 : (nt,) float64
    bad : (b,) int32
        Bad tets in priority order.
    rng_state : int
        Non-zero seed of the walk's face rotation (xorshift32).

    Returns
    -------
    accept : (b,) bool
        The circumcentre of ``bad[i]`` is to be inserted.
    enc : (b,) int64
        ``4 w + k`` of a subface it encroaches (split that instead), else -1.
    """
    nt = tets.shape[0]
    b = bad.shape[0]
    accept = np.zeros(b, dtype=np.bool_)
    enc = np.full(b, -1, dtype=np.int64)
    owner = np.full(nt, -1, dtype=np.int32)
    stamp = np.zeros(nt, dtype=np.int32)
    queue = np.empty(nt, dtype=np.int32)
    state = np.uint32(rng_state)
    for i in range(b):
        t = bad[i]
        cx = cc[t, 0]
        cy = cc[t, 1]
        cz = cc[t, 2]
        if not (np.isfinite(cx) and np.isfinite(cy) and np.isfinite(cz)):
            continue
        # 1. visibility walk inside the region; crossing a subface means c is beyond it
        u = t
        ok = False
        for _ in range(WALK_CAP):
            state ^= state << np.uint32(13)
            state ^= state >> np.uint32(17)
            state ^= state << np.uint32(5)
            k0 = int(state & np.uint32(3))
            moved = False
            for j in range(4):
                k = (k0 + j) & 3
                if _beyond(pts, tets, u, k, cx, cy, cz):
                    if barrier[u, k]:
                        enc[i] = 4 * u + k
                    elif nbr[u, k] >= 0:
                        u = nbr[u, k]
                        moved = True
                    break
            if enc[i] >= 0 or not moved:
                ok = enc[i] < 0 and not moved
                break
        if not ok:
            continue
        # 2. cavity in the region; a subface met whose diametral ball holds c is encroached
        gen = i + 1
        head = 0
        tail = 1
        queue[0] = u
        stamp[u] = gen
        defer = False
        while head < tail and enc[i] < 0 and not defer:
            w = queue[head]
            head += 1
            if owner[w] >= 0:
                defer = True
                break
            for k in range(4):
                if barrier[w, k]:
                    # encroached, or deleted outright: the tet across conflicts too
                    x = nbr[w, k]
                    gone = False
                    if x >= 0:
                        dx = cx - cc[x, 0]
                        dy = cy - cc[x, 1]
                        dz = cz - cc[x, 2]
                        gone = dx * dx + dy * dy + dz * dz < r2[x]
                    if gone or _in_diametral_ball(pts, tets, w, k, cx, cy, cz):
                        enc[i] = 4 * w + k
                        break
                    continue
                x = nbr[w, k]
                if x < 0 or stamp[x] == gen:
                    continue
                dx = cx - cc[x, 0]
                dy = cy - cc[x, 1]
                dz = cz - cc[x, 2]
                if dx * dx + dy * dy + dz * dz < r2[x]:
                    stamp[x] = gen
                    queue[tail] = x
                    tail += 1
        if enc[i] >= 0 or defer:
            continue
        accept[i] = True
        for q in range(tail):
            owner[queue[q]] = i
    return accept, enc
