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

One point at a time when the size is a number or absent: :func:`refine_in_queue` hands the
bad tets to the queue kernel of :mod:`meshwright.tet._refine_kernel` (walk, cavity stopped at
subfaces, insertion, new tets examined), which reports the subfaces whose encroachment
stopped a point; the caller splits them, recovers the surface and calls it again (3 rounds
on the level-4 sphere where the rounds below took 55-62).  A callable size field is Python,
so it keeps the rounds of :func:`select_points`, which also propose the crease-cap apexes
of :func:`crease_caps` (points placed near the surface on purpose).

Rounds (:func:`select_points`): every round takes all bad tets (largest circumradius
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
int32 and ``barrier`` (nt, 4) bool as in :mod:`meshwright.tet.exterior`; ``bad`` (b,) int32
the bad tets in priority order.  The circumspheres of the tets a cavity meets are computed
where they are needed (:func:`_sphere_at`, the bits of :func:`circumspheres`): a round for a
few crease caps no longer pays a pass over every tet.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.flat import TET_FACES
from meshwright.core.predicates import orient3d
from meshwright.core.rng import xorshift32
from meshwright.tet._refine_kernel import _in_diametral_ball as in_face_ball

__all__ = ["SIZE_FACTOR", "WALK_CAP", "bad_solid", "circumspheres", "crease_caps", "flag_counts", "refine_in_queue", "select_points"]

SIZE_FACTOR = 0.8  # a tet is too large when R > SIZE_FACTOR * h
WALK_CAP = 1 << 16


def flag_counts(flags: np.ndarray) -> np.ndarray:
    """Set flags per row of ``flags`` (nt, 4) bool, (nt,) uint32.

    The four flag bytes of a row read as one uint32; multiplying by 0x01010101 sums them
    into its top byte (each byte is 0 or 1, so no carry crosses a byte).  ``sum(axis=1)``
    over the bool rows cast every flag to int64: 38 ms at 1e6 tets against 0.4 ms.
    """
    rows = np.ascontiguousarray(flags, dtype=np.bool_).view(np.uint32).ravel()
    return (rows * np.uint32(0x01010101)) >> np.uint32(24)


def circumspheres(pts: np.ndarray, tets: np.ndarray):
    """Circumcentres (nt, 3), squared circumradii (nt,), shortest edges (nt,) and volumes (nt,).

    Degenerate (zero-volume) tets get an infinite radius and centre.  One fused Numba pass
    (:func:`_circumspheres`): the NumPy version's temporaries cost 13 % of a refinement.
    """
    return _circumspheres(pts, np.ascontiguousarray(tets))


@njit(inline="always")
def _sphere_terms(pts, tets, t):
    """Circumcentre offset (ox, oy, oz) from vertex 0 (inf when degenerate), the orientation
    determinant and the squared shortest edge of tet t: the one formula both
    :func:`_circumspheres` and :func:`_bad_solid` use, so they agree to the bit."""
    a = tets[t, 0]
    ux = pts[tets[t, 1], 0] - pts[a, 0]
    uy = pts[tets[t, 1], 1] - pts[a, 1]
    uz = pts[tets[t, 1], 2] - pts[a, 2]
    vx = pts[tets[t, 2], 0] - pts[a, 0]
    vy = pts[tets[t, 2], 1] - pts[a, 1]
    vz = pts[tets[t, 2], 2] - pts[a, 2]
    wx = pts[tets[t, 3], 0] - pts[a, 0]
    wy = pts[tets[t, 3], 1] - pts[a, 1]
    wz = pts[tets[t, 3], 2] - pts[a, 2]
    cx = vy * wz - vz * wy
    cy = vz * wx - vx * wz
    cz = vx * wy - vy * wx
    det = ux * cx + uy * cy + uz * cz
    lu = ux * ux + uy * uy + uz * uz
    lv = vx * vx + vy * vy + vz * vz
    lw = wx * wx + wy * wy + wz * wz
    d = 2.0 * det
    ox = (lu * cx + lv * (wy * uz - wz * uy) + lw * (uy * vz - uz * vy)) / d if d != 0.0 else np.inf
    oy = (lu * cy + lv * (wz * ux - wx * uz) + lw * (uz * vx - ux * vz)) / d if d != 0.0 else np.inf
    oz = (lu * cz + lv * (wx * uy - wy * ux) + lw * (ux * vy - uy * vx)) / d if d != 0.0 else np.inf
    if not (np.isfinite(ox) and np.isfinite(oy) and np.isfinite(oz)):
        ox = np.inf
        oy = np.inf
        oz = np.inf
    e2 = min(lu, min(lv, lw))
    for i, j in ((1, 2), (2, 3), (1, 3)):
        p = tets[t, i]
        q = tets[t, j]
        dx = pts[p, 0] - pts[q, 0]
        dy = pts[p, 1] - pts[q, 1]
        dz = pts[p, 2] - pts[q, 2]
        e2 = min(e2, dx * dx + dy * dy + dz * dz)
    return ox, oy, oz, det, e2


@njit(inline="always")
def _sphere_at(pts, tets, t):
    """Circumcentre (x, y, z) and squared circumradius of tet t, as :func:`_circumspheres`
    stores them (the same operations, so the same bits)."""
    ox, oy, oz, _, _ = _sphere_terms(pts, tets, t)
    a = tets[t, 0]
    return pts[a, 0] + ox, pts[a, 1] + oy, pts[a, 2] + oz, ox * ox + oy * oy + oz * oz


@njit(cache=True)
def _circumspheres(pts, tets):
    nt = tets.shape[0]
    cc = np.empty((nt, 3))
    r2 = np.empty(nt)
    lmin = np.empty(nt)
    vol = np.empty(nt)
    for t in range(nt):
        ox, oy, oz, det, e2 = _sphere_terms(pts, tets, t)
        a = tets[t, 0]
        cc[t, 0] = pts[a, 0] + ox
        cc[t, 1] = pts[a, 1] + oy
        cc[t, 2] = pts[a, 2] + oz
        r2[t] = ox * ox + oy * oy + oz * oz
        lmin[t] = np.sqrt(e2)
        vol[t] = det / 6.0
    return cc, r2, lmin, vol


def bad_solid(pts: np.ndarray, tets: np.ndarray, solid: np.ndarray, vbound: np.ndarray, rmax: float, quality: float, floor: float, among=None) -> np.ndarray:
    """Solid tets over a volume, size or radius-edge bound, in one pass without the
    circumcentres: (b,) int64 ascending.

    Parameters
    ----------
    pts : (nv, 3) float64
    tets : (nt, 4) int32
    solid : (nt,) bool
    vbound : (nt,) float64
        Volume bound of each tet (inf: none).
    rmax : float
        Largest circumradius (inf: none).
    quality : float
        Bound on circumradius / shortest edge (inf: none), for tets whose shortest edge is
        at least ``floor``.
    among : (c,) int64 ascending, optional
        Only these tets are examined (the new tets of an incremental round).

    A tet is bad when ``vol > vbound``, ``R > rmax`` or ``R > quality * l_min`` with
    ``l_min >= floor``: the test of ``tet.mesher._bad`` for a constant size, evaluated in the
    same order on the same numbers (the whole-mesh :func:`circumspheres` and its four output
    arrays were refinement's largest pass per round).
    """
    cand = np.arange(tets.shape[0], dtype=np.int64) if among is None else np.ascontiguousarray(among, dtype=np.int64)
    return _bad_solid(pts, np.ascontiguousarray(tets), solid, vbound, rmax, quality, floor, cand)


@njit(cache=True)
def _bad_solid(pts, tets, solid, vbound, rmax, quality, floor, cand):
    out = np.empty(cand.shape[0], dtype=np.int64)
    n = 0
    for i in range(cand.shape[0]):
        t = cand[i]
        if not solid[t]:
            continue
        ox, oy, oz, det, e2 = _sphere_terms(pts, tets, t)
        r = np.sqrt(ox * ox + oy * oy + oz * oz)
        lmin = np.sqrt(e2)
        if det / 6.0 > vbound[t] or r > rmax or (r > quality * lmin and lmin >= floor):
            out[n] = t
            n += 1
    return out[:n].copy()


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
    return in_face_ball(pts, tets[w, (k + 1) % 4], tets[w, (k + 2) % 4], tets[w, (k + 3) % 4], cx, cy, cz)


@njit(cache=True)
def select_points(pts, tets, nbr, barrier, bad, target, close, rng_state):
    """Walk to each bad tet's point, grow its cavity, accept, defer or redirect it.

    Parameters
    ----------
    pts : (nv, 3) float64
    tets, nbr : (nt, 4) int32
    barrier : (nt, 4) bool
    bad : (b,) int32
        Bad tets in priority order.
    target : (b, 3) float64
        The point proposed for each (its circumcentre, or a crease cap's apex).
    close : (b,) bool
        The point may lie in a subface's diametral ball (a crease cap's apex must: it is
        placed near the surface on purpose); it still may not delete a subface.
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
    state = np.int64(rng_state) & 0xFFFFFFFF
    for i in range(b):
        t = bad[i]
        cx = target[i, 0]
        cy = target[i, 1]
        cz = target[i, 2]
        if not (np.isfinite(cx) and np.isfinite(cy) and np.isfinite(cz)):
            continue
        # 1. visibility walk inside the region; crossing a subface means c is beyond it
        u = t
        ok = False
        for _ in range(WALK_CAP):
            state = xorshift32(state)
            k0 = state & 3
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
                        sx, sy, sz, sr2 = _sphere_at(pts, tets, x)
                        dx = cx - sx
                        dy = cy - sy
                        dz = cz - sz
                        gone = dx * dx + dy * dy + dz * dz < sr2
                    if gone or (not close[i] and _in_diametral_ball(pts, tets, w, k, cx, cy, cz)):
                        enc[i] = 4 * w + k
                        break
                    continue
                x = nbr[w, k]
                if x < 0 or stamp[x] == gen:
                    continue
                sx, sy, sz, sr2 = _sphere_at(pts, tets, x)
                dx = cx - sx
                dy = cy - sy
                dz = cz - sz
                if dx * dx + dy * dy + dz * dz < sr2:
                    stamp[x] = gen
                    queue[tail] = x
                    tail += 1
        if enc[i] >= 0 or defer:
            continue
        accept[i] = True
        for q in range(tail):
            owner[queue[q]] = i
    return accept, enc


def crease_caps(pts, tets, barrier, solid, face_of, parent, threshold):
    """Solid tets flattened over a crease of the surface, and an apex point to remove each.

    A solid tet whose two faces are subfaces of two different input faces has the crease
    between them for an edge; when the crease is nearly flat the tet is a sliver (the sphere's
    level-4 facets meet at 176 degrees) that neither a flip (two of its faces are boundary)
    nor a vertex move (all four vertices lie on the surface) can repair, and Delaunay
    refinement does not see it (its radius-edge ratio is small).  Whether refinement leaves
    one depended on round-off alone.  The point proposed for it lies inside the solid below
    the crease edge's midpoint, at the first depth of 0.3, 0.2, 0.1 and 0.05 times the edge's
    length that is inside the tet's circumsphere (so inserting it deletes the tet); the sliver
    stage moves that interior vertex afterwards.

    Parameters
    ----------
    pts : (nv, 3) float64
    tets : (nt, 4) int32
    barrier : (nt, 4) bool
    solid : (nt,) bool
    face_of : (4 nt,) int32
        The subface at each barrier slot ``4 t + k``, -1 elsewhere.
    parent : (m,) int32
        The input face of each subface.
    threshold : float
        Sliver ratio ``a = r_in / R`` below which a crease tet is a cap.

    Returns
    -------
    caps : (c,) int64
        The cap tets.
    apex : (c, 3) float64
        The point proposed for each.
    """
    cand = np.flatnonzero(solid & (flag_counts(barrier) >= 2))
    if cand.size == 0:
        return cand, np.zeros((0, 3))
    cc, r2, _, vol = circumspheres(pts, tets[cand])  # of the candidates only
    p = pts[tets[cand]]
    area = np.zeros(cand.size)
    normals = np.empty((cand.size, 4, 3))
    for k in range(4):
        f = p[:, TET_FACES[k]]
        n = np.cross(f[:, 1] - f[:, 0], f[:, 2] - f[:, 0])
        normals[:, k] = n
        area += 0.5 * np.linalg.norm(n, axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = 3.0 * np.abs(vol) / area / np.sqrt(r2)
    low = ~(ratio >= threshold)
    cand = cand[low]
    normals = normals[low]
    p = p[low]
    cc = cc[low]
    r2 = r2[low]
    caps = []
    apex = []
    for i, t in enumerate(cand.tolist()):
        slots = np.flatnonzero(barrier[t])
        face_parent = parent[face_of[4 * t + slots]]
        pair = None
        for x in range(slots.size):
            for y in range(x + 1, slots.size):
                if face_parent[x] != face_parent[y]:
                    pair = (int(slots[x]), int(slots[y]))
                    break
            if pair is not None:
                break
        if pair is None:
            continue  # flat on one input face: the unflatten step's case
        a, b = (k for k in range(4) if k not in pair)
        mid = 0.5 * (p[i, a] + p[i, b])
        length = float(np.linalg.norm(p[i, a] - p[i, b]))
        out = sum(normals[i, k] / np.linalg.norm(normals[i, k]) for k in pair)
        size = float(np.linalg.norm(out))
        if not (size > 0.0 and np.isfinite(size)):
            continue
        for depth in (0.3, 0.2, 0.1, 0.05):
            q = mid - out / size * depth * length
            if float(np.sum((q - cc[i]) ** 2)) < r2[i]:
                caps.append(t)
                apex.append(q)
                break
    return np.array(caps, dtype=np.int64), np.array(apex, dtype=np.float64).reshape(-1, 3)


@njit(cache=True)
def _queue_flags(nbr, barrier, solid, vbound, cap):
    """The queue kernel's per-slot arrays for ``cap`` slots: ``bar`` (4 cap,) uint8 subface
    flags, ``sol`` (cap,) uint8 and ``vb`` (cap,) float64 (inf past the public tets).

    A subface on the hull has a ghost on its other side: the ghost's half-face is flagged
    too, so the face stays protected when a new tet takes the finite side's place.
    """
    nt = solid.shape[0]
    bar = np.zeros(4 * cap, dtype=np.uint8)
    sol = np.zeros(cap, dtype=np.uint8)
    vb = np.full(cap, np.inf)
    for t in range(nt):
        sol[t] = solid[t]
        vb[t] = vbound[t]
        for k in range(4):
            if barrier[t, k]:
                bar[4 * t + k] = 1
                g = nbr[4 * t + k]
                if g >= nt:
                    for j in range(4):
                        if nbr[4 * g + j] == t:
                            bar[4 * g + j] = 1
    return bar, sol, vb


def refine_in_queue(tz, barrier, solid, vbound, bad, radius_edge, rmax, exempt, max_points, rng_state):
    """Refine the solid of ``tz`` one point at a time (:mod:`meshwright.tet._refine_kernel`).

    Parameters
    ----------
    tz : Tetrahedralization
        Bowyer, ghost superstructure; vertices are appended to it.
    barrier : (nt, 4) bool
        Subface slots of the public tets.
    solid : (nt,) bool
    vbound : (nt,) float64
        Volume bound of each tet (inf: none).
    bad : (b,) int64
        Tets to start from (only the bad ones are queued).
    radius_edge, rmax, exempt : float
        Radius-edge bound (inf: none), largest circumradius (inf: none), shortest edge of a
        tet the radius-edge bound applies to.
    max_points : int
        Cap on the vertices of ``tz``.
    rng_state : int
        Non-zero seed of the walks.

    Returns
    -------
    inserted : int
        Points inserted.
    enc : (k, 4) int32
        Subfaces (three vertices) whose encroachment stopped a point, and why (0 radius-edge,
        1 size, 2 volume).
    capped : bool
        ``max_points`` was reached.
    """
    from meshwright.core.bucket_queue import new_queue
    from meshwright.core.errors import MeshingError
    from meshwright.core.flat import grown_rows
    from meshwright.tet import _refine_kernel as K
    from meshwright.tet.tetrahedralization import grow

    tets = tz.tetrahedra
    rows0 = tz._vb + tz.points.shape[0]
    r2 = circumspheres(tz.points, tets[bad])[1] if bad.size else np.ones(1)
    rref2 = float(np.max(r2[np.isfinite(r2)], initial=1.0))
    s = tz._edit_begin()
    bar, sol, vb = _queue_flags(s.nbr, barrier, solid, vbound, s.tet.shape[0] // 4)
    head, nxt, qval, hdr = new_queue(K.N_BUCKETS, max(1024, 4 * bad.size), 5)
    re2 = radius_edge * radius_edge
    rmax2 = rmax * rmax
    exempt2 = exempt * exempt
    K.push_bad(s.tet, sol, vb, s.pts, bad.astype(np.int64), re2, rmax2, exempt2, rref2, head, nxt, qval, hdr)
    enc = np.empty((8192, 9), dtype=np.int32)
    out = np.zeros(4, dtype=np.int64)
    out[K.OUT_NV] = rows0
    status = K.DONE
    while True:
        status = K.refine_queue(s, bar, sol, vb, head, nxt, qval, hdr, enc, out, re2, rmax2, exempt2, rref2, tz._vb + max_points, rng_state)
        if status in (K.DONE, K.ENC_FULL, K.POINT_CAP):
            break
        if status == K.NEED_PTS:
            rows = 2 * s.pts.shape[0]
            s = s._replace(pts=grown_rows(s.pts, rows), vmark=np.empty(rows + 1, dtype=np.int32))
        elif status == K.NEED_QUEUE:
            qcap = 2 * qval.shape[0]
            nxt = grown_rows(nxt, qcap)
            qval = grown_rows(qval, qcap)
        elif status == K.NEED_SPACE:
            s = grow(s)
            cap = s.tet.shape[0] // 4
            if cap > sol.shape[0]:
                bar = grown_rows(bar, 4 * cap)
                sol = grown_rows(sol, cap)
                vb = grown_rows(vb, cap)
        else:
            tz._edit_end(s, out[K.OUT_NV] - rows0)
            raise MeshingError("Delaunay refinement met an inconsistent cavity (predicates and tetrahedralization disagree)")
    tz._edit_end(s, out[K.OUT_NV] - rows0)
    return int(out[K.OUT_INSERTED]), enc[: out[K.OUT_ENC], :4].copy(), status == K.POINT_CAP
