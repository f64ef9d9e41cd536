r"""Flat-array kernel of 3-D incremental Delaunay insertion, shared by Bowyer and Watson.

Both algorithms of the chapter (Watson 1981, 18.1.1; Bowyer 1981, 18.1.2; the 3-D procedure
of 18.4.1) insert one point at a time: find every tetrahedron whose circumball contains the
new point (the *cavity*, the chapter's set S), delete them and join the new point to the
cavity's boundary faces.  They differ only in the conflict test: an empty ``sph`` runs
Bowyer (:mod:`meshwright.tet.bowyer`), a sized one Watson (:mod:`meshwright.tet.watson`).

State bundle :class:`TetState` (``cap`` tet slots, ``meta[M_NTET]`` in use)
--------------------------------------------------------------------------
``pts``   (rows, 3) float64     vertex coordinates; vertex ids are row numbers.
``tet``   (4 cap,) int32        ``tet[4t + k]`` vertex k of tet t, positively oriented
                                (``orient3d(v0, v1, v2, v3) > 0``, :mod:`meshwright.core.flat`);
                                ``tet[4t + 3] == GHOST`` for a ghost, ``DELETED`` for a free slot.
``nbr``   (4 cap,) int32        ``nbr[4t + k]`` the tet across the face opposite vertex k,
                                ``TET_FACES[k]`` (outward oriented).
``sph``   (5 cap,) float32      Watson's circumsphere records; empty for Bowyer.
``rank``  (r,) int32            symbolic-perturbation key of vertex v: ``rank[v]`` for v < r,
                                v itself beyond.
``meta``  (8,) int64            ``[M_NTET]`` slots in use (free ones included), ``[M_LAST]`` a
                                recent finite tet, ``[M_RNG]`` xorshift32 state of the walk,
                                ``[M_NFREE]`` entries of ``free``, ``[M_NEED]`` / ``[M_NEEDN]``
                                which array a ``NEED_SPACE`` asks to grow and to what size.
``cav``   (c,) int32            cavity scratch: the cavity tets in breadth-first order.
``bnd``   (4 f,) int32          boundary faces of the cavity: three vertices (outward from
                                the cavity) and the outer half-face ``4 n + j``.
``twin``  (3 f,) int32          per boundary face and edge e (``f_e -> f_(e+1)%3``), the
                                ``3 j' + e'`` of the face holding the reversed edge.
``vloc``  (l,) int32            local number -> vertex slot of the cavity's boundary vertices.
``etab``  (>= l*l,) int32       directed-edge table ``etab[lu * L + lw] = 3 j + e`` (no reset:
                                every entry read is checked to belong to this insertion).
``vmark`` (>= rows + 1,) int32  vertex slot -> local number (sparse set: valid only if
                                ``vloc`` points back); the last entry stands for GHOST.
``free``  (q,) int32            slots freed when a cavity had more tets than boundary faces.

Superstructure: the symbolic vertex at infinity
----------------------------------------------
Every hull face ``a b c`` (normal pointing out) carries a ghost tet ``(a, b, c, GHOST)``,
GHOST always vertex 3, so finite and ghost tets tile the 3-sphere: every ``nbr`` entry is a
tet.  The ghost conflict rule (:mod:`meshwright.tet.bowyer`) makes the result the Delaunay
tetrahedralization of the convex hull.  The chapter's eight-point box is built on top of it
by the caller (the box's five tets and their twelve ghosts; nothing ever lies outside it).

Insertion of vertex v
---------------------
1. Locate: stochastic visibility walk (Devillers, Pion & Teillaud 2002, "Walking in a
   triangulation", Int. J. Found. Comput. Sci. 13(2)) with exact ``orient3d``, from a recent
   tet, leaving through the first face (from a pseudo-random one) that has p strictly
   outside.  It stops in a finite tet whose closure holds p (duplicates are found there) or
   in a ghost whose hull face p strictly sees; either conflicts with v.  Capped.
2. Cavity: breadth-first growth over conflicting neighbours; members are marked by storing
   ``-2 - v0`` in their vertex 0 (undone on every early return).  A non-conflicting
   neighbour gives a boundary face.
3. Check: the boundary of a cavity that is a ball is a triangulated sphere, so its V
   vertices and F faces satisfy ``2 V = F + 4`` (Euler), and every directed edge occurs once
   and its reverse once.  Anything else means predicate and triangulation disagree and is
   reported as ``BROKEN`` with nothing modified.
4. Fan: boundary face ``(f0, f1, f2)`` (outward) gives the new tet ``(f0, f2, f1, v)``, a
   ghost when a face vertex is GHOST (then evenly permuted so GHOST is vertex 3).  Slots: the
   cavity's first, then free ones, then new ones; leftover cavity slots become free.  New
   tets are linked across the outer face and, along each boundary edge, with the new tet
   of the face holding the reversed edge (``twin``), as in::

        boundary face f, edge u -> w           new tet of f  |  new tet of f'
        face f' holds w -> u           ==>     (.. u w .. v) | (.. w u .. v)  share u w v

Hot-path rules: no allocation and no Python objects; an array that may be too small makes
:func:`insert_vertex` return ``NEED_SPACE`` *before* anything is modified, and the caller
grows it (:func:`meshwright.tet.tetrahedralization.grow`, a new bundle by
``state._replace``) and retries.  The bundle is the one argument of the ``@njit`` entry
points (:func:`insert_vertex`, :func:`insert_batch`, :func:`locate_points`); they unpack it
once and the inlined helpers take the arrays one by one, because in Numba every attribute
read of a NamedTuple inside a loop is a new reference (an atomic increment and decrement).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from meshwright.core.borrowed import borrowed
from meshwright.core.flat import GHOST, TET_FACES
from meshwright.core.predicates import orient3d, orient3d_stage_a
from meshwright.core.rng import xorshift32
from meshwright.tet import bowyer, watson

__all__ = [
    "TetState",
    "GHOST",
    "DELETED",
    "NEED_SPACE",
    "BROKEN",
    "DUP_BASE",
    "M_NTET",
    "M_LAST",
    "M_RNG",
    "M_NFREE",
    "M_NEED",
    "M_NEEDN",
    "NEED_TETS",
    "NEED_CAV",
    "NEED_FACES",
    "NEED_LOCAL",
    "NEED_FREE",
    "NEED_VERTS",
    "new_meta",
    "walk",
    "insert_vertex",
    "insert_batch",
    "locate_points",
]


class TetState(NamedTuple):
    """The kernel's arrays, passed as one argument (layout in the module docstring)."""

    pts: np.ndarray
    tet: np.ndarray
    nbr: np.ndarray
    sph: np.ndarray
    rank: np.ndarray
    meta: np.ndarray
    cav: np.ndarray
    bnd: np.ndarray
    twin: np.ndarray
    vloc: np.ndarray
    etab: np.ndarray
    vmark: np.ndarray
    free: np.ndarray


DELETED = -2  # tet[4t + 3] of a free slot
# insert_vertex status: >= 0 a new finite tet incident to v; a status <= DUP_BASE means v
# coincides with vertex DUP_BASE - status (nothing changed).
NEED_SPACE = -1
BROKEN = -2
DUP_BASE = -3
# meta slots
M_NTET = 0
M_LAST = 1
M_RNG = 2
M_NFREE = 3
M_NEED = 4
M_NEEDN = 5
META_LEN = 8
# M_NEED codes: which array is short, M_NEEDN the size it must reach
NEED_TETS = 1  # tet/nbr/sph slots
NEED_CAV = 2
NEED_FACES = 3  # bnd/twin
NEED_LOCAL = 4  # vloc/etab
NEED_FREE = 5
NEED_VERTS = 6  # vmark


def new_meta(rng_state: int) -> np.ndarray:
    """Fresh kernel header: no tets, walk start 0, the given non-zero xorshift32 state."""
    meta = np.zeros(META_LEN, dtype=np.int64)
    meta[M_RNG] = rng_state
    return meta


@njit(inline="always")
def _orient(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz):
    """``orient3d`` with Shewchuk's stage-A filter inlined; the exact predicate only if unsure."""
    det, err = orient3d_stage_a(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz)
    if det > err or -det > err:
        return -det
    return orient3d(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz)


@njit(inline="always")
def _conflict(pts, tet, nbr, sph, rank, t, v, px, py, pz):
    """Conflict of tet t with the new vertex: Watson's filter first if spheres are kept.

    One copy of the exact test serves both algorithms (half the compiled code)."""
    if sph.shape[0] > 0:
        f = watson.filter_sign(tet, sph, t, px, py, pz)
        if f != 0:
            return f > 0
    return bowyer.conflict(pts, tet, nbr, rank, t, v, px, py, pz)


@njit(inline="always")
def _vslot(u, vmark):
    """Scratch index of vertex u; GHOST uses the last entry."""
    return u if u >= 0 else vmark.shape[0] - 1


@njit(inline="always")
def walk(pts, tet, nbr, meta, t, px, py, pz):
    """Stochastic visibility walk from tet t towards p; advances ``meta[M_RNG]``.

    Returns
    -------
    int
        A finite tet whose closure contains p, a ghost whose hull face has p strictly
        outside, or -1 when the step cap (four times the slots plus 100) is hit.
    """
    if tet[4 * t + 3] == GHOST:
        t = nbr[4 * t + 3]
    came = -1
    r = meta[M_RNG]
    cap = 4 * meta[M_NTET] + 100
    steps = 0
    while True:
        r = xorshift32(r)
        k = r & 3
        b4 = 4 * t
        nxt = -1
        for _ in range(4):
            n = nbr[b4 + k]
            if n != came:
                a = tet[b4 + TET_FACES[k, 0]]
                b = tet[b4 + TET_FACES[k, 1]]
                c = tet[b4 + TET_FACES[k, 2]]
                if _orient(pts[a, 0], pts[a, 1], pts[a, 2], pts[b, 0], pts[b, 1], pts[b, 2],
                           pts[c, 0], pts[c, 1], pts[c, 2], px, py, pz) > 0.0:
                    nxt = n
                    break
            k = (k + 1) & 3
        if nxt < 0:
            break
        came = t
        t = nxt
        if tet[4 * t + 3] == GHOST:
            break
        steps += 1
        if steps > cap:
            t = -1
            break
    meta[M_RNG] = r
    return t


@njit(inline="always")
def _unmark(tet, cav, m):
    """Undo the cavity marks of the first m cavity tets."""
    for i in range(m):
        c = cav[i]
        tet[4 * c] = -2 - tet[4 * c]


@njit(inline="always")
def _need(tet, cav, meta, m, code, size):
    """Undo the marks of an m-tet cavity and ask for ``size`` entries of array ``code``."""
    _unmark(tet, cav, m)
    meta[M_NEED] = code
    meta[M_NEEDN] = size
    return NEED_SPACE


@njit(inline="always")
def _grow_cavity(pts, tet, nbr, sph, rank, meta, cav, bnd, v, t0):
    """Breadth-first cavity from t0; returns ``(m, nf)`` or ``(NEED_SPACE, 0)``.

    On success the m cavity tets (still marked) are in ``cav`` and the nf boundary faces in
    ``bnd``.
    """
    px = pts[v, 0]
    py = pts[v, 1]
    pz = pts[v, 2]
    ccap = cav.shape[0]
    fcap = bnd.shape[0] // 4
    cav[0] = t0
    tet[4 * t0] = -2 - tet[4 * t0]
    m = 1
    nf = 0
    i = 0
    while i < m:
        c = cav[i]
        i += 1
        b4 = 4 * c
        for k in range(4):
            n = nbr[b4 + k]
            if tet[4 * n] < -1:
                continue
            if _conflict(pts, tet, nbr, sph, rank, n, v, px, py, pz):
                if m == ccap:
                    return _need(tet, cav, meta, m, NEED_CAV, 2 * ccap), 0
                tet[4 * n] = -2 - tet[4 * n]
                cav[m] = n
                m += 1
            else:
                if nf == fcap:
                    return _need(tet, cav, meta, m, NEED_FACES, 2 * fcap), 0
                n4 = 4 * n
                j = 0
                while j < 3 and nbr[n4 + j] != c:
                    j += 1
                o = 4 * nf
                for e in range(3):
                    f = tet[b4 + TET_FACES[k, e]]
                    bnd[o + e] = f if f >= -1 else -2 - f
                bnd[o + 3] = n4 + j
                nf += 1
    return m, nf


@njit(inline="always")
def _check_boundary(tet, meta, cav, bnd, twin, vloc, etab, vmark, m, nf):
    """Number the boundary vertices, pair the directed edges; 0, NEED_SPACE or BROKEN.

    Fills ``twin``.  Only scratch arrays are written; on failure the cavity marks are undone.
    """
    lcap = vloc.shape[0]
    if 3 * nf > twin.shape[0]:
        return _need(tet, cav, meta, m, NEED_FACES, nf)
    nl = 0
    for o in range(4 * nf):
        if o % 4 == 3:
            continue
        u = _vslot(bnd[o], vmark)
        lu = vmark[u]
        if lu < 0 or lu >= nl or vloc[lu] != u:
            if nl == lcap:
                return _need(tet, cav, meta, m, NEED_LOCAL, 2 * lcap)
            vmark[u] = nl
            vloc[nl] = u
            nl += 1
    if 2 * nl != nf + 4:
        _unmark(tet, cav, m)
        return BROKEN
    if nl * nl > etab.shape[0]:
        return _need(tet, cav, meta, m, NEED_LOCAL, nl)
    for j in range(nf):
        o = 4 * j
        for e in range(3):
            lu = vmark[_vslot(bnd[o + e], vmark)]
            lw = vmark[_vslot(bnd[o + (e + 1) % 3], vmark)]
            etab[lu * nl + lw] = 3 * j + e
    for j in range(nf):
        o = 4 * j
        for e in range(3):
            u = bnd[o + e]
            w = bnd[o + (e + 1) % 3]
            lu = vmark[_vslot(u, vmark)]
            lw = vmark[_vslot(w, vmark)]
            h = etab[lw * nl + lu]
            ok = etab[lu * nl + lw] == 3 * j + e and 0 <= h < 3 * nf
            if ok:
                o2 = 4 * (h // 3)
                e2 = h % 3
                ok = bnd[o2 + e2] == w and bnd[o2 + (e2 + 1) % 3] == u
            if not ok:
                _unmark(tet, cav, m)
                return BROKEN
            twin[3 * j + e] = h
    return 0


@njit(inline="always")
def _slot(j, m, nfree, ntet, cav, free):
    """Tet slot of the new tet of boundary face j: cavity slots, free slots, new slots."""
    if j < m:
        return cav[j]
    if j - m < nfree:
        return free[nfree - 1 - (j - m)]
    return ntet + (j - m - nfree)


@njit(inline="always")
def _perm(g):
    """Stored order of the conceptual tet ``X`` whose vertex g is GHOST (-1: none).

    ``tet[4t + k] = X[p[k]]`` is an even permutation putting GHOST at slot 3; returns
    ``(p0, p1, p2, p3, q0, q1, q2, q3)`` with q the inverse (slot of ``X[i]``).
    """
    if g == 0:
        return 1, 3, 2, 0, 3, 0, 2, 1
    if g == 1:
        return 0, 2, 3, 1, 0, 3, 1, 2
    if g == 2:
        return 0, 3, 1, 2, 0, 2, 3, 1
    return 0, 1, 2, 3, 0, 1, 2, 3


@njit(inline="always")
def _fan(pts, tet, nbr, sph, meta, cav, bnd, twin, free, v, m, nf):
    """Replace the checked cavity by the fan of v; returns a new finite tet incident to v."""
    ntet = meta[M_NTET]
    nfree = meta[M_NFREE]
    result = -1
    for j in range(nf):
        o = 4 * j
        x0 = bnd[o]
        x1 = bnd[o + 2]
        x2 = bnd[o + 1]
        g = 0 if x0 == GHOST else (1 if x1 == GHOST else (2 if x2 == GHOST else -1))
        p0, p1, p2, p3, q0, q1, q2, q3 = _perm(g)
        x = (np.int64(x0), np.int64(x1), np.int64(x2), np.int64(v))
        tn = _slot(j, m, nfree, ntet, cav, free)
        b4 = 4 * tn
        tet[b4] = x[p0]
        tet[b4 + 1] = x[p1]
        tet[b4 + 2] = x[p2]
        tet[b4 + 3] = x[p3]
        h = bnd[o + 3]
        nbr[b4 + q3] = h // 4
        nbr[h] = tn
        # X0 = f0 is opposite the edge f1 -> f2 (e = 1), X1 = f2 opposite f0 -> f1 (e = 0),
        # X2 = f1 opposite f2 -> f0 (e = 2).
        nbr[b4 + q0] = _slot(twin[3 * j + 1] // 3, m, nfree, ntet, cav, free)
        nbr[b4 + q1] = _slot(twin[3 * j] // 3, m, nfree, ntet, cav, free)
        nbr[b4 + q2] = _slot(twin[3 * j + 2] // 3, m, nfree, ntet, cav, free)
        if g < 0:
            result = tn
    if sph.shape[0] > 0:
        for j in range(nf):
            watson.sphere(pts, tet, sph, _slot(j, m, nfree, ntet, cav, free))
    if nf >= m:
        used = min(nfree, nf - m)
        meta[M_NFREE] = nfree - used
        meta[M_NTET] = ntet + (nf - m - used)
    else:
        for i in range(nf, m):
            c = cav[i]
            tet[4 * c] = 0
            tet[4 * c + 3] = DELETED
            free[nfree] = c
            nfree += 1
        meta[M_NFREE] = nfree
    meta[M_LAST] = result
    return result


@njit(inline="always")
def _insert(pts, tet, nbr, sph, rank, meta, cav, bnd, twin, vloc, etab, vmark, free, v, t):
    """Body of :func:`insert_vertex` over the unpacked bundle, inlined into the batch loop.

    Helpers take arrays, not the bundle: every attribute read of a NamedTuple inside a loop
    costs an atomic reference-count pair in Numba.
    """
    if vmark.shape[0] <= max(v, pts.shape[0]):
        meta[M_NEED] = NEED_VERTS
        meta[M_NEEDN] = pts.shape[0] + 1
        return NEED_SPACE
    px = pts[v, 0]
    py = pts[v, 1]
    pz = pts[v, 2]
    t0 = walk(pts, tet, nbr, meta, t, px, py, pz)
    if t0 < 0:
        return BROKEN
    if tet[4 * t0 + 3] != GHOST:
        for k in range(4):
            w = tet[4 * t0 + k]
            if pts[w, 0] == px and pts[w, 1] == py and pts[w, 2] == pz:
                return DUP_BASE - w
    m, nf = _grow_cavity(pts, tet, nbr, sph, rank, meta, cav, bnd, v, t0)
    if m < 0:
        return m
    st = _check_boundary(tet, meta, cav, bnd, twin, vloc, etab, vmark, m, nf)
    if st < 0:
        return st
    extra = nf - m - meta[M_NFREE]
    need = meta[M_NTET] + max(extra, 0)
    if 4 * need > tet.shape[0] or 4 * need > nbr.shape[0] or (
        sph.shape[0] > 0 and watson.RECORD * need > sph.shape[0]
    ):
        return _need(tet, cav, meta, m, NEED_TETS, need)
    if m > nf and meta[M_NFREE] + m - nf > free.shape[0]:
        return _need(tet, cav, meta, m, NEED_FREE, meta[M_NFREE] + m - nf)
    return _fan(pts, tet, nbr, sph, meta, cav, bnd, twin, free, v, m, nf)


@njit(cache=True)
def insert_vertex(s, v, t):
    """Insert vertex v (row v of ``s.pts``) by cavity re-tetrahedralization, walking from t.

    Parameters
    ----------
    s : TetState
    v : int
        Vertex to insert; ``s.pts[v]`` holds its coordinates, ``s.vmark`` has more rows.
    t : int
        Start tet of the walk (finite or ghost, in use).

    Returns
    -------
    int
        A new finite tet incident to v; or ``NEED_SPACE`` (``meta[M_NEED]`` says which array,
        ``meta[M_NEEDN]`` how large), ``BROKEN`` (inconsistent cavity or walk cap), or
        ``DUP_BASE - w`` when v coincides with vertex w.  Only success modifies the
        tetrahedralization.
    """
    s = borrowed(s)
    return _insert(s.pts, s.tet, s.nbr, s.sph, s.rank, s.meta, s.cav, s.bnd, s.twin, s.vloc, s.etab, s.vmark, s.free, v, t)


@njit(cache=True)
def insert_batch(s, order, start, stop, vbase, vmap):
    """Insert the vertices ``order[start:stop]`` one by one, each walk from the last new tet.

    Parameters
    ----------
    s : TetState
    order : (k,) int32
        Vertices (rows of ``s.pts``) in insertion order.
    start, stop : int
    vbase : int
        ``vmap`` is indexed by ``v - vbase``.
    vmap : (k,) int32
        Output: ``vmap[v - vbase] = v`` for an inserted vertex, else the vertex it coincides
        with.

    Returns
    -------
    tuple of int
        ``(status, i)``: status 0 when all are inserted; ``NEED_SPACE`` at position i (grow
        the array ``meta[M_NEED]`` names and call again from i); ``BROKEN`` at position i
        (the tetrahedralization is unchanged by ``order[i]``, later vertices not inserted).
    """
    pts, tet, nbr, sph, rank, meta, cav, bnd, twin, vloc, etab, vmark, free = borrowed(s)
    t = meta[M_LAST]
    for i in range(start, stop):
        v = order[i]
        st = _insert(pts, tet, nbr, sph, rank, meta, cav, bnd, twin, vloc, etab, vmark, free, v, t)
        if st >= 0:
            vmap[v - vbase] = v
            t = st
        elif st == NEED_SPACE or st == BROKEN:
            return st, i
        else:
            vmap[v - vbase] = DUP_BASE - st
    return 0, stop


@njit(cache=True)
def locate_points(s, xyz):
    """Tet whose closure contains each query point, or the ghost it ends in (-1 - ghost).

    Parameters
    ----------
    s : TetState
        ``meta[M_RNG]`` advances; pass a bundle with a copied ``meta``.
    xyz : (m, 3) float64

    Returns
    -------
    (m,) int64
        A finite tet slot; ``-1 - g`` for a ghost slot g (the point is outside the hull);
        ``-1 - 2**40`` if the walk hit its cap.
    """
    pts = s.pts
    tet = s.tet
    nbr = s.nbr
    meta = s.meta
    m = xyz.shape[0]
    out = np.empty(m, dtype=np.int64)
    t = meta[M_LAST]
    for i in range(m):
        r = walk(pts, tet, nbr, meta, t, xyz[i, 0], xyz[i, 1], xyz[i, 2])
        if r < 0:
            out[i] = -1 - (1 << 40)
            continue
        t = r
        out[i] = -1 - r if tet[4 * r + 3] == GHOST else r
    return out
