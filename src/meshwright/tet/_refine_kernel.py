r"""Delaunay refinement of the solid, one point at a time from a queue, in one Numba kernel.

The interior-point step of 18.4.1 as Shewchuk (1998, "Tetrahedral mesh generation by
Delaunay refinement", Proc. 14th SoCG) and Si (2015, TetGen, ACM TOMS 41(2)) run it: a queue
of bad tets (radius-edge ratio over the bound, circumradius over the size, volume over its
region's bound); the kernel pops one, walks from it to its circumcentre c, grows c's cavity
(exact ``insphere`` with symbolic perturbation, :mod:`meshwright.tet.bowyer`) and replaces it
by the fan of c (:mod:`meshwright.tet._kernel3d`), then examines the new tets and queues the
bad ones, until the queue is empty.  Cavities are stopped at the *protected* faces (the
subfaces of the recovered surface, ``bar``): c is not inserted, but reported as encroaching,
when the walk to it crosses a subface, when its cavity would delete a subface outright (the
tet across conflicts too) or when c lies in the diametral ball of a subface its cavity meets.
The caller (:func:`meshwright.tet.mesher._run_delaunay`) splits the reported subfaces, recovers
the surface and calls the kernel again with the tets still bad; the round-based
:func:`meshwright.tet.refine3d.select_points` stays for callable size fields (the field is
Python) and for crease caps.  A point inserted this way is Bowyer-Watson insertion into the
whole tetrahedralization restricted to a cavity that meets no subface, so the result is the
same Delaunay tetrahedralization as inserting c by :meth:`Tetrahedralization.insert`: every
subface stays a face (none is in a cavity) and the mesh stays Delaunay.

Priority: buckets of half powers of two of the circumradius, largest first
(:mod:`meshwright.core.bucket_queue`, newest first inside a bucket), as the rounds took bad
tets largest circumradius first: a large tet's centre removes many small bad tets with it.
Queue entries carry the tet's four vertices; an entry whose slot no longer holds them is stale.

Arrays (besides the :class:`~meshwright.tet._kernel3d.TetState` arrays, unpacked)::

    bar    (4 cap,) uint8    1 where face k of slot t is a subface (both sides flagged)
    sol    (cap,) uint8      1 for solid tets
    vbound (cap,) float64    the volume bound of each slot's region (inf: none)
    head, nxt, qval, hdr     the bucket queue; qval (qcap, 5) int32: slot and its 4 vertices
    enc    (ecap, 9) int32   encroached subfaces (3 vertices), why (0 quality, 1 size, 2 volume),
                             the bad tet's slot and its 4 vertices; on DONE only the records
                             whose bad tet is still there are kept (a later point removed the
                             others, as the rounds deferred them: splitting for them too made
                             twice the surface points)
    out    (4,) int64        [0] vertices in use, [1] encroachments recorded, [2] points inserted
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.borrowed import borrowed
from meshwright.core.bucket_queue import Q_N, bq_pop, bq_push
from meshwright.core.flat import TET_FACES
from meshwright.core.predicates import orient3d
from meshwright.core.rng import xorshift32
from meshwright.tet._kernel3d import (
    BROKEN,
    DELETED,
    M_NFREE,
    M_NTET,
    NEED_CAV,
    NEED_FACES,
    NEED_FREE,
    NEED_SPACE,
    NEED_TETS,
    _check_boundary,
    _conflict,
    _fan,
    _need,
    _slot,
    _unmark,
)

__all__ = ["DONE", "ENC_FULL", "NEED_PTS", "NEED_QUEUE", "OUT_ENC", "OUT_INSERTED", "OUT_NV", "POINT_CAP", "WALK_CAP", "push_bad", "refine_queue"]

DONE = 0
ENC_FULL = 1  # the encroachment list is full: split those first
NEED_PTS = 2  # grow pts (and vmark) and call again
NEED_QUEUE = 3  # grow the queue and call again
POINT_CAP = 4  # max_points reached
OUT_NV = 0
OUT_ENC = 1
OUT_INSERTED = 2
WALK_CAP = 1 << 16
N_BUCKETS = 64


@njit(inline="always")
def _sphere(pts, tet, t):
    """Circumcentre (x, y, z), squared circumradius, squared shortest edge and volume of slot t."""
    a = tet[4 * t]
    b = tet[4 * t + 1]
    c = tet[4 * t + 2]
    d = tet[4 * t + 3]
    ux = pts[b, 0] - pts[a, 0]
    uy = pts[b, 1] - pts[a, 1]
    uz = pts[b, 2] - pts[a, 2]
    vx = pts[c, 0] - pts[a, 0]
    vy = pts[c, 1] - pts[a, 1]
    vz = pts[c, 2] - pts[a, 2]
    wx = pts[d, 0] - pts[a, 0]
    wy = pts[d, 1] - pts[a, 1]
    wz = pts[d, 2] - pts[a, 2]
    cx = vy * wz - vz * wy
    cy = vz * wx - vx * wz
    cz = vx * wy - vy * wx
    det = ux * cx + uy * cy + uz * cz
    lu = ux * ux + uy * uy + uz * uz
    lv = vx * vx + vy * vy + vz * vz
    lw = wx * wx + wy * wy + wz * wz
    e2 = min(lu, min(lv, lw))
    e2 = min(e2, (vx - ux) ** 2 + (vy - uy) ** 2 + (vz - uz) ** 2)
    e2 = min(e2, (wx - ux) ** 2 + (wy - uy) ** 2 + (wz - uz) ** 2)
    e2 = min(e2, (wx - vx) ** 2 + (wy - vy) ** 2 + (wz - vz) ** 2)
    if det == 0.0:
        return np.inf, np.inf, np.inf, np.inf, e2, 0.0
    d2 = 2.0 * det
    ox = (lu * cx + lv * (wy * uz - wz * uy) + lw * (uy * vz - uz * vy)) / d2
    oy = (lu * cy + lv * (wz * ux - wx * uz) + lw * (uz * vx - ux * vz)) / d2
    oz = (lu * cz + lv * (wx * uy - wy * ux) + lw * (ux * vy - uy * vx)) / d2
    return pts[a, 0] + ox, pts[a, 1] + oy, pts[a, 2] + oz, ox * ox + oy * oy + oz * oz, e2, det / 6.0


@njit(inline="always")
def _why_bad(r2, e2, vol, vmax, re2, rmax2, exempt2):
    """0 quality, 1 size, 2 volume, -1 not bad (a size or volume reason wins: it reaches further)."""
    if vol > vmax:
        return 2
    if r2 > rmax2:
        return 1
    if r2 > re2 * e2 and e2 >= exempt2:
        return 0
    return -1


@njit(inline="always")
def _bucket(r2, rref2):
    """Bucket of a tet: half powers of two of R below ``sqrt(rref2)``, largest R first."""
    if not r2 > 0.0 or r2 >= rref2:
        return 0
    b = int(np.log2(rref2 / r2))  # log2 of the R^2 ratio: half powers of two of R
    return min(b, N_BUCKETS - 1)


@njit(inline="always")
def _push(head, nxt, qval, hdr, tet, t, b):
    e = bq_push(head, nxt, hdr, b)
    qval[e, 0] = t
    for k in range(4):
        qval[e, 1 + k] = tet[4 * t + k]


@njit(cache=True)
def push_bad(tet, sol, vbound, pts, cand, re2, rmax2, exempt2, rref2, head, nxt, qval, hdr):
    """Queue the slots ``cand`` (k,) int64 that are bad; returns how many were queued.

    ``qval`` must have room for k more entries.
    """
    n = 0
    for i in range(cand.shape[0]):
        t = cand[i]
        if sol[t] == 0:
            continue
        _, _, _, r2, e2, vol = _sphere(pts, tet, t)
        if _why_bad(r2, e2, vol, vbound[t], re2, rmax2, exempt2) >= 0:
            _push(head, nxt, qval, hdr, tet, t, _bucket(r2, rref2))
            n += 1
    return n


@njit(inline="always")
def _beyond(pts, tet, u, k, cx, cy, cz):
    """Whether c lies strictly beyond face k of slot u (outward face ``TET_FACES[k]``)."""
    a = tet[4 * u + TET_FACES[k, 0]]
    b = tet[4 * u + TET_FACES[k, 1]]
    c = tet[4 * u + TET_FACES[k, 2]]
    return orient3d(pts[a, 0], pts[a, 1], pts[a, 2], pts[b, 0], pts[b, 1], pts[b, 2],
                    pts[c, 0], pts[c, 1], pts[c, 2], cx, cy, cz) > 0.0


@njit(inline="always")
def _in_diametral_ball(pts, a, b, c, px, py, pz):
    """Whether p lies strictly inside the smallest ball through triangle (a, b, c) (floating point)."""
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
    sx = lu * vx - lv * ux
    sy = lu * vy - lv * uy
    sz = lu * vz - lv * uz
    ox = (sy * nz - sz * ny) / (2.0 * n2)
    oy = (sz * nx - sx * nz) / (2.0 * n2)
    oz = (sx * ny - sy * nx) / (2.0 * n2)
    dx = px - pts[a, 0] - ox
    dy = py - pts[a, 1] - oy
    dz = pz - pts[a, 2] - oz
    return dx * dx + dy * dy + dz * dz < ox * ox + oy * oy + oz * oz


@njit(inline="always")
def _live(tet, enc, n):
    """Keep the first n records whose bad tet is still in the mesh; returns how many."""
    kept = 0
    for i in range(n):
        t = enc[i, 4]
        if tet[4 * t] == enc[i, 5] and tet[4 * t + 1] == enc[i, 6] and tet[4 * t + 2] == enc[i, 7] and tet[4 * t + 3] == enc[i, 8]:
            for j in range(9):
                enc[kept, j] = enc[i, j]
            kept += 1
    return kept


@njit(inline="always")
def _record(enc, out, tet, u, k, why, t):
    """Note face k of slot u as encroached by the centre of slot t; False when the list is
    full even after dropping the records whose tet a later point removed."""
    n = out[OUT_ENC]
    if n >= enc.shape[0]:
        n = _live(tet, enc, n)
        out[OUT_ENC] = n
        if n >= enc.shape[0] // 2:
            return False
    a = tet[4 * u + TET_FACES[k, 0]]
    b = tet[4 * u + TET_FACES[k, 1]]
    c = tet[4 * u + TET_FACES[k, 2]]
    enc[n, 0] = a if a >= -1 else -2 - a
    enc[n, 1] = b if b >= -1 else -2 - b
    enc[n, 2] = c if c >= -1 else -2 - c
    enc[n, 3] = why
    enc[n, 4] = t
    for j in range(4):
        enc[n, 5 + j] = tet[4 * t + j]
    out[OUT_ENC] = n + 1
    return True


@njit(cache=True)
def refine_queue(s, bar, sol, vbound, head, nxt, qval, hdr, enc, out, re2, rmax2, exempt2, rref2, max_rows, rng_state):
    """Insert circumcentres of queued bad tets until the queue is empty (or a status says why not).

    Parameters
    ----------
    s : TetState
        The tetrahedralization (Bowyer: ``sph`` empty); ``s.pts`` rows ``< out[OUT_NV]`` in use.
    bar : (4 cap,) uint8
    sol : (cap,) uint8
    vbound : (cap,) float64
    head, nxt, qval, hdr
        The bucket queue (:mod:`meshwright.core.bucket_queue`), qval (qcap, 5) int32.
    enc : (ecap, 9) int32
    out : (4,) int64
    re2 : float
        Squared radius-edge bound (inf: none).
    rmax2 : float
        Squared largest circumradius allowed by the size (inf: none).
    exempt2 : float
        Squared shortest edge below which a tet is exempt from the radius-edge bound.
    rref2 : float
        Squared circumradius of the first bucket.
    max_rows : int
        Cap on the vertices (max_points).
    rng_state : int
        Non-zero xorshift32 state of the walks.

    Returns
    -------
    int
        :data:`DONE`, :data:`ENC_FULL`, :data:`NEED_PTS`, :data:`NEED_QUEUE`, :data:`POINT_CAP`,
        ``NEED_SPACE`` (grow the kernel array ``meta[M_NEED]`` names, and ``bar``, ``sol``,
        ``vbound`` with the tets) or ``BROKEN``.  On every return the queue holds every bad
        tet not yet handled (the entry being handled is pushed back first).
    """
    pts, tet, nbr, sph, rank, meta, cav, bnd, twin, vloc, etab, vmark, free = borrowed(s)
    bar, sol, vbound, head, nxt, qval, hdr, enc, out = borrowed((bar, sol, vbound, head, nxt, qval, hdr, enc, out))
    state = np.int64(rng_state) & 0xFFFFFFFF
    ccap = cav.shape[0]
    fcap = bnd.shape[0] // 4
    qcap = qval.shape[0]
    while hdr[Q_N] > 0:
        e = bq_pop(head, nxt, hdr)
        t = qval[e, 0]
        if tet[4 * t + 3] == DELETED or tet[4 * t] != qval[e, 1] or tet[4 * t + 1] != qval[e, 2] or tet[4 * t + 2] != qval[e, 3] or tet[4 * t + 3] != qval[e, 4]:
            continue
        cx, cy, cz, r2, e2, vol = _sphere(pts, tet, t)
        why = _why_bad(r2, e2, vol, vbound[t], re2, rmax2, exempt2)
        if why < 0 or not (np.isfinite(cx) and np.isfinite(cy) and np.isfinite(cz)):
            continue
        v = out[OUT_NV]
        if v >= max_rows:
            _push(head, nxt, qval, hdr, tet, t, _bucket(r2, rref2))
            return POINT_CAP
        if v >= pts.shape[0] or v + 1 >= vmark.shape[0]:
            _push(head, nxt, qval, hdr, tet, t, _bucket(r2, rref2))
            return NEED_PTS
        # 1. visibility walk inside the solid; crossing a subface: c is beyond it
        u = t
        hit = -1
        arrived = False
        for _ in range(WALK_CAP):
            state = xorshift32(state)
            k0 = state & 3
            moved = False
            for j in range(4):
                k = (k0 + j) & 3
                if _beyond(pts, tet, u, k, cx, cy, cz):
                    if bar[4 * u + k]:
                        hit = 4 * u + k
                    elif sol[nbr[4 * u + k]]:
                        u = nbr[4 * u + k]
                        moved = True
                    break
            if hit >= 0 or not moved:
                arrived = hit < 0 and not moved
                break
        if not arrived and hit < 0:
            continue  # walk cap, or a solid tet unprotected towards the outside (not expected)
        if hit >= 0:
            if not _record(enc, out, tet, hit // 4, hit % 4, why, t):
                return ENC_FULL
            continue
        # a centre on a vertex of its tet (round-off): nothing to insert
        dup = False
        for k in range(4):
            w = tet[4 * u + k]
            if pts[w, 0] == cx and pts[w, 1] == cy and pts[w, 2] == cz:
                dup = True
        if dup:
            continue
        pts[v, 0] = cx
        pts[v, 1] = cy
        pts[v, 2] = cz
        # 2. cavity, stopped at subfaces (marks: tet[4 c] = -2 - v0, as in _kernel3d)
        cav[0] = u
        tet[4 * u] = -2 - tet[4 * u]
        m = 1
        nf = 0
        i = 0
        hit = -1
        need = 0
        while i < m and hit < 0 and need == 0:
            c = cav[i]
            i += 1
            b4 = 4 * c
            for k in range(4):
                n = nbr[b4 + k]
                if tet[4 * n] < -1:
                    continue
                if bar[b4 + k]:
                    a0 = tet[b4 + TET_FACES[k, 0]]
                    a1 = tet[b4 + TET_FACES[k, 1]]
                    a2 = tet[b4 + TET_FACES[k, 2]]
                    a0 = a0 if a0 >= -1 else -2 - a0
                    a1 = a1 if a1 >= -1 else -2 - a1
                    a2 = a2 if a2 >= -1 else -2 - a2
                    if _conflict(pts, tet, nbr, sph, rank, n, v, cx, cy, cz) or _in_diametral_ball(pts, a0, a1, a2, cx, cy, cz):
                        hit = b4 + k
                        break
                elif sol[n] == 0:
                    hit = b4 + k  # not expected: a solid tet unprotected towards the outside
                    break
                elif _conflict(pts, tet, nbr, sph, rank, n, v, cx, cy, cz):
                    if m == ccap:
                        need = 1
                        break
                    tet[4 * n] = -2 - tet[4 * n]
                    cav[m] = n
                    m += 1
                    continue
                if nf == fcap:
                    need = 2
                    break
                n4 = 4 * n
                j = 0
                while j < 3 and nbr[n4 + j] != c:
                    j += 1
                o = 4 * nf
                for q in range(3):
                    f = tet[b4 + TET_FACES[k, q]]
                    bnd[o + q] = f if f >= -1 else -2 - f
                bnd[o + 3] = n4 + j
                nf += 1
        if hit >= 0:
            _unmark(tet, cav, m)
            if not _record(enc, out, tet, hit // 4, hit % 4, why, t):
                return ENC_FULL
            continue
        if need:
            _push(head, nxt, qval, hdr, tet, t, _bucket(r2, rref2))
            if need == 1:
                return _need(tet, cav, meta, m, NEED_CAV, 2 * ccap)
            return _need(tet, cav, meta, m, NEED_FACES, 2 * fcap)
        st = _check_boundary(tet, meta, cav, bnd, twin, vloc, etab, vmark, m, nf)
        if st == BROKEN:
            return BROKEN
        if st < 0 or hdr[Q_N] + nf + 1 > qcap:
            if st >= 0:
                _unmark(tet, cav, m)
            _push(head, nxt, qval, hdr, tet, t, _bucket(r2, rref2))
            return NEED_SPACE if st < 0 else NEED_QUEUE
        ntet = meta[M_NTET]
        nfree = meta[M_NFREE]
        grow = ntet + max(nf - m - nfree, 0)
        if 4 * grow > tet.shape[0] or 4 * grow > nbr.shape[0] or grow > sol.shape[0]:
            _push(head, nxt, qval, hdr, tet, t, _bucket(r2, rref2))
            return _need(tet, cav, meta, m, NEED_TETS, grow)
        if m > nf and nfree + m - nf > free.shape[0]:
            _push(head, nxt, qval, hdr, tet, t, _bucket(r2, rref2))
            return _need(tet, cav, meta, m, NEED_FREE, nfree + m - nf)
        # 3. fan; the new tet of boundary face j faces the outside across slot 3 (no ghost
        # lies in a solid cavity), which is a subface exactly when the outer half-face is
        vb = vbound[cav[0]]
        _fan(pts, tet, nbr, sph, meta, cav, bnd, twin, free, v, m, nf)
        for j in range(nf):
            tn = _slot(j, m, nfree, ntet, cav, free)
            h = bnd[4 * j + 3]
            bar[4 * tn] = 0
            bar[4 * tn + 1] = 0
            bar[4 * tn + 2] = 0
            bar[4 * tn + 3] = bar[h]
            sol[tn] = 1
            vbound[tn] = vb
        out[OUT_NV] = v + 1
        out[OUT_INSERTED] += 1
        # 4. examine the new tets
        for j in range(nf):
            tn = _slot(j, m, nfree, ntet, cav, free)
            _, _, _, r2n, e2n, voln = _sphere(pts, tet, tn)
            if _why_bad(r2n, e2n, voln, vb, re2, rmax2, exempt2) >= 0:
                _push(head, nxt, qval, hdr, tet, tn, _bucket(r2n, rref2))
    out[OUT_ENC] = _live(tet, enc, out[OUT_ENC])
    return DONE
