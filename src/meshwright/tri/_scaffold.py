r"""Vertex removal from a constrained Delaunay triangulation, for removable scaffold points.

Source: O. Devillers, "On deletion in Delaunay triangulations", Int. J. Comput. Geom. Appl.
12(3), 2002 (the hole left by a vertex is filled by the Delaunay triangulation of its link,
built ear by ear; here the plain O(k^3) ear test instead of the paper's priority queue,
since a scaffold vertex has about six neighbours).

Removal of vertex v (:func:`remove_vertex`)
------------------------------------------
The star of v is walked counter-clockwise: link vertices ``u_0 .. u_{k-1}`` (the *ring*, a
polygon star-shaped from v) and the outer half-edge across each ring edge ``u_j -> u_{j+1}``.
The triangles of ``DT(ring)`` inside the polygon are exactly the triangles of the
triangulation without v inside the hole (both triangulate the polygon and the second is a
subset of the first), so an *ear* ``(u_p, u_j, u_n)`` of the current polygon is clipped when
it turns left (exact ``orient2d``) and no ring vertex lies in its circumcircle (the
in-circle test under the same symbolic perturbation as the insertion kernel,
:func:`meshwright.core.predicates.incircle_sos` on the keys of ``rank``); the ring's
Delaunay triangulation always has two such ears while more than three vertices are left.
The clip sequence is planned first and written only when complete: a refusal (v on the
hull or on a constrained edge, more than ``KMAX`` neighbours, a ring edge that is a
non-Delaunay constrained edge so that no ear qualifies) modifies nothing.

The k - 2 new triangles reuse the first k - 2 star slots; the last two slots are freed and
the caller fills them with the last triangles (:func:`move_slot`), so slots stay dense as
the insertion kernel needs.  Removed vertices leave dead rows (``vtri = -1``) that the
caller reuses for new points or closes at the end with :func:`move_row`.

Arrays: ``TriState`` ``s`` and ``CdtState`` ``c`` as in :mod:`meshwright.tri._encroach`;
``scr`` (8 KMAX,) int32 scratch: ring, star slots, outer half-edges, the polygon's next and
previous links, the planned ears (3 per triangle).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.flat import GHOST, back3, index3, next3, prev3
from meshwright.core.predicates import incircle_sos, incircle_stage_a, orient2d
from meshwright.tri._kernel2d import M_LAST

__all__ = ["KMAX", "SCRATCH", "move_row", "move_slot", "remove_vertex"]

KMAX = 64  # most neighbours of a removable vertex
SCRATCH = 8 * KMAX


@njit(inline="always")
def _key(rank, v):
    # int64 as the kernel's keys (tri._encroach.key_of): int32 keys compiled incircle_sos a
    # second time on the first frontal-delaunay run (0.4 s), for the same values.
    return np.int64(rank[v]) if v < rank.shape[0] else np.int64(v)


@njit(inline="always")
def _in_circle(pts, rank, a, b, c, w):
    """Whether w lies in the circumcircle of counter-clockwise (a, b, c), perturbed as the kernel."""
    det, err = incircle_stage_a(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[c, 0], pts[c, 1], pts[w, 0], pts[w, 1])
    if det > err:
        return True
    if -det > err:
        return False
    return incircle_sos(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[c, 0], pts[c, 1], pts[w, 0], pts[w, 1],
                        _key(rank, a), _key(rank, b), _key(rank, c), _key(rank, w)) > 0


@njit(inline="always")
def _link(tri, nbr, cons, h1, h2):
    """Make half-edges h1 and h2 twins; h1 takes h2's constraint."""
    nbr[h1] = h2 // 3
    nbr[h2] = h1 // 3
    cons[h1] = cons[h2]


@njit(cache=True)
def remove_vertex(v, s, c, scr):
    """Remove interior vertex v and fill its hole with the Delaunay triangles of its ring.

    Parameters
    ----------
    v : int
        A vertex strictly inside the triangulated domain, on no constrained edge.
    s : TriState
    c : CdtState
        ``vtri`` and ``treg`` are kept; ``vtri[v]`` becomes -1 (a dead row).
    scr : (SCRATCH,) int32
        Scratch; on success ``scr[KMAX : KMAX + k - 2]`` are the new triangles' slots and
        ``scr[KMAX + k - 2]``, ``scr[KMAX + k - 1]`` the two freed slots.

    Returns
    -------
    int
        k, the number of neighbours (>= 3), on success; -1 when refused (nothing modified).
    """
    pts, tri, nbr, cons, rank, meta = s.pts, s.tri, s.nbr, s.cons, s.rank, s.meta
    vtri, treg = c.vtri, c.treg
    ring = scr[0:KMAX]
    st = scr[KMAX : 2 * KMAX]
    hout = scr[2 * KMAX : 3 * KMAX]
    nxt = scr[3 * KMAX : 4 * KMAX]
    prv = scr[4 * KMAX : 5 * KMAX]
    plan = scr[5 * KMAX : 8 * KMAX]
    if s.circ.shape[0] > 0 or v < 0 or vtri[v] < 0:
        return -1
    t = vtri[v]
    t0 = t
    k = 0
    for _ in range(KMAX + 1):
        i = index3(tri, t, v)
        if tri[3 * t + i] != v or k == KMAX:
            return -1
        a = tri[3 * t + next3(i)]
        b = tri[3 * t + prev3(i)]
        if a == GHOST or b == GHOST or cons[3 * t + next3(i)] != 0 or cons[3 * t + prev3(i)] != 0:
            return -1
        n = nbr[3 * t + i]
        ring[k] = a
        st[k] = t
        hout[k] = 3 * n + back3(nbr, n, t)
        k += 1
        t = nbr[3 * t + next3(i)]
        if t == t0:
            break
    if t != t0 or k < 3:
        return -1
    # Plan the ears (nothing written yet).
    for j in range(k):
        nxt[j] = j + 1 if j + 1 < k else 0
        prv[j] = j - 1 if j > 0 else k - 1
    m = k
    j = 0
    q = 0
    miss = 0
    while m > 3:
        p = prv[j]
        n = nxt[j]
        a = ring[p]
        b = ring[j]
        d = ring[n]
        ok = orient2d(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[d, 0], pts[d, 1]) > 0.0
        if ok:
            for w in range(k):
                if w != p and w != j and w != n and _in_circle(pts, rank, a, b, d, ring[w]):
                    ok = False
                    break
        if ok:
            plan[3 * q] = p
            plan[3 * q + 1] = j
            plan[3 * q + 2] = n
            q += 1
            nxt[p] = n
            prv[n] = p
            m -= 1
            j = p
            miss = 0
        else:
            j = n
            miss += 1
            if miss > m:
                return -1
    p = prv[j]
    n = nxt[j]
    if orient2d(pts[ring[p], 0], pts[ring[p], 1], pts[ring[j], 0], pts[ring[j], 1], pts[ring[n], 0],
                pts[ring[n], 1]) <= 0.0:
        return -1
    plan[3 * q] = p
    plan[3 * q + 1] = j
    plan[3 * q + 2] = n
    # Write: triangle q of the plan goes to star slot st[q].
    region = treg[st[0]]
    for q in range(k - 2):
        p = plan[3 * q]
        j = plan[3 * q + 1]
        n = plan[3 * q + 2]
        tn = st[q]
        b3 = 3 * tn
        tri[b3] = ring[p]
        tri[b3 + 1] = ring[j]
        tri[b3 + 2] = ring[n]
        treg[tn] = region
        _link(tri, nbr, cons, b3 + 2, hout[p])  # edge p -> j
        _link(tri, nbr, cons, b3, hout[j])  # edge j -> n
        if q == k - 3:
            _link(tri, nbr, cons, b3 + 1, hout[n])  # edge n -> p closes the last triangle
        else:
            cons[b3 + 1] = 0
            hout[p] = b3 + 1  # the polygon's new edge p -> n, seen from outside
        vtri[ring[p]] = tn
        vtri[ring[j]] = tn
        vtri[ring[n]] = tn
    vtri[v] = -1
    meta[M_LAST] = st[0]
    return k


@njit(inline="always")
def move_slot(src, dst, tri, nbr, cons, treg, vtri, meta):
    """Move the triangle of slot src into the free slot dst, relinking its neighbours."""
    for k in range(3):
        tri[3 * dst + k] = tri[3 * src + k]
        nbr[3 * dst + k] = nbr[3 * src + k]
        cons[3 * dst + k] = cons[3 * src + k]
    treg[dst] = treg[src]
    for k in range(3):
        n = nbr[3 * dst + k]
        nbr[3 * n + back3(nbr, n, src)] = dst
        w = tri[3 * dst + k]
        if w >= 0 and vtri[w] == src:
            vtri[w] = dst
    if meta[M_LAST] == src:
        meta[M_LAST] = dst


@njit(cache=True)
def move_row(src, dst, s, c):
    """Renumber live vertex src as the dead row dst (coordinates, star, constrained data).

    The perturbation keys are swapped (``s.rank`` must cover both rows), so src keeps its key
    and the row it leaves gets the dead vertex's unused one.  Returns False when the star
    walk does not close (nothing but a prefix of the star renamed: the caller reports it).
    """
    pts, tri, nbr, rank = s.pts, s.tri, s.nbr, s.rank
    vtri = c.vtri
    t = vtri[src]
    t0 = t
    closed = False
    for _ in range(1 << 20):
        i = index3(tri, t, src)
        if tri[3 * t + i] != src:
            return False
        tri[3 * t + i] = dst
        t = nbr[3 * t + next3(i)]
        if t == t0:
            closed = True
            break
    if not closed:
        return False
    pts[dst, 0] = pts[src, 0]
    pts[dst, 1] = pts[src, 1]
    vtri[dst] = t0
    vtri[src] = -1
    c.vseg[dst] = c.vseg[src]
    c.vpar[dst] = c.vpar[src]
    c.vacute[dst] = c.vacute[src]
    kd = rank[dst]
    rank[dst] = rank[src]
    rank[src] = kd
    return True
