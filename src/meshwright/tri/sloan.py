r"""Segment recovery of the constrained Delaunay triangulation by edge flips (Sloan 1993).

Source: S. W. Sloan, "A fast algorithm for generating constrained Delaunay triangulations",
Computers & Structures 47(3):441-450, 1993.  A segment ab missing from the triangulation is
traced from a through the triangles it crosses (:func:`_crossings`, exact ``orient2d``); the
crossed edges go into a queue.  An edge whose quadrilateral is strictly convex is flipped
(the new diagonal is queued again if it still crosses ab, else recorded as new); a
non-convex one goes to the back of the queue, which always empties (Sloan's lemma).  Then
every new edge that is not locally Delaunay (exact ``incircle_sos`` with the build's
perturbation keys) is flipped until none is::

      a                       a                       a
      |\   crossing edges     |\   flip while convex   |   new edges made
   ---+--\-----  ------>   ---|-+-----   ------>      |   locally Delaunay
      |    \                 |                       |
      b                       b                       b

A segment that runs exactly through a vertex r is cut there into (a, r) and (r, b); one that
crosses a constrained edge is reported (two segments intersect).  No vertex is added.

Arrays: the kernel's :class:`~meshwright.tri._kernel2d.TriState` (``pts``, ``tri``, ``nbr``,
``cons`` per half-edge = piece + 1, ``rank``) and the constrained layer's
:class:`~meshwright.tri._encroach.CdtState` (``vtri`` a triangle of each vertex, kept exact by
every flip; ``seg`` (P, 2) piece endpoints; ``seg_in`` (P,) input segment of each piece).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.flat import GHOST, back3, index3, next3, prev3
from meshwright.core.jit import inner
from meshwright.core.predicates import incircle_sos, orient2d
from meshwright.tri._encroach import edge_of, key_of
from meshwright.tri._kernel2d import flip

__all__ = ["recover_segments"]


@inner
def _twin(h, nbr):
    """The opposite half-edge of h."""
    t = h // 3
    n = nbr[h]
    return 3 * n + back3(nbr, n, t)


@njit(inline="always")
def _flip(h, s, vtri):
    """:func:`meshwright.tri._kernel2d.flip` of half-edge h's edge, keeping ``vtri`` exact."""
    n = flip(h, s)
    t = h // 3
    tri = s.tri
    # t = (p, u, q), n = (q, w, p) after the flip.
    vtri[tri[3 * t]] = t
    vtri[tri[3 * t + 1]] = t
    vtri[tri[3 * t + 2]] = t
    vtri[tri[3 * n + 1]] = n


@njit(inline="always")
def _ahead(pts, a, b, c):
    """Whether c, collinear with a and b, lies on the ray from a through b (c != a)."""
    if pts[a, 0] != pts[b, 0]:
        return (pts[c, 0] > pts[a, 0]) == (pts[b, 0] > pts[a, 0])
    return (pts[c, 1] > pts[a, 1]) == (pts[b, 1] > pts[a, 1])


@inner
def _crossings(a, b, s, vtri, elist):
    """Trace segment a -> b through the triangulation.

    Returns
    -------
    (int, int, int)
        ``(0, 0, 0)`` when ab is an edge; ``(1, r, ne)`` when the segment runs into vertex r,
        with the ``ne`` edges it crosses before r in ``elist`` as (left, right) pairs;
        ``(2, 0, ne)`` when it reaches b; ``(3, h, ne)`` when it crosses constrained half-edge h.
    """
    pts, tri, nbr, cons = s.pts, s.tri, s.nbr, s.cons
    t = vtri[a]
    start = t
    while True:
        i = index3(tri, t, a)
        c = tri[3 * t + next3(i)]
        d = tri[3 * t + prev3(i)]
        if c == b or d == b:
            return 0, 0, 0
        if c >= 0 and d >= 0:
            oc = orient2d(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[c, 0], pts[c, 1])
            od = orient2d(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[d, 0], pts[d, 1])
            if oc == 0.0 and _ahead(pts, a, b, c):
                return 1, c, 0
            if od == 0.0 and _ahead(pts, a, b, d):
                return 1, d, 0
            if oc < 0.0 and od > 0.0:
                break
        t = nbr[3 * t + next3(i)]
        if t == start:
            return 3, -1, 0
    left = d
    right = c
    h = 3 * t + i
    ne = 0
    while True:
        if cons[h] != 0:
            return 3, h, ne
        elist[2 * ne] = left
        elist[2 * ne + 1] = right
        ne += 1
        n = nbr[h]
        j = back3(nbr, n, t)
        r = tri[3 * n + j]
        if r == b:
            return 2, 0, ne
        o = orient2d(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[r, 0], pts[r, 1])
        if o == 0.0:
            return 1, r, ne
        if o > 0.0:
            h = 3 * n + index3(tri, n, left)
            left = r
        else:
            h = 3 * n + index3(tri, n, right)
            right = r
        t = n


@inner
def _sloan(a, b, ne, s, vtri, elist, nlist):
    """Make ab an edge by flipping the ``ne`` crossing edges, then restore Delaunay.

    S. W. Sloan, "A fast algorithm for generating constrained Delaunay triangulations",
    Computers & Structures 47(3), 1993: a crossing edge whose quad is strictly convex is
    flipped (the new diagonal is queued again if it still crosses ab, else recorded as new);
    otherwise it goes to the back of the queue.  Then every new edge that is not locally
    Delaunay (exact ``incircle_sos``) is flipped until none is.
    """
    pts, tri, nbr, cons, rank = s.pts, s.tri, s.nbr, s.cons, s.rank
    head = 0
    cnt = ne
    nn = 0
    while cnt > 0:
        u = elist[2 * head]
        w = elist[2 * head + 1]
        head = head + 1 if head + 1 < ne else 0
        cnt -= 1
        h = edge_of(np.int64(u), np.int64(w), tri, nbr, vtri)
        t = h // 3
        p = tri[h]
        n = nbr[h]
        q = tri[3 * n + back3(nbr, n, t)]
        ou = orient2d(pts[p, 0], pts[p, 1], pts[q, 0], pts[q, 1], pts[u, 0], pts[u, 1])
        ow = orient2d(pts[p, 0], pts[p, 1], pts[q, 0], pts[q, 1], pts[w, 0], pts[w, 1])
        tail = head + cnt if head + cnt < ne else head + cnt - ne
        if (ou > 0.0 and ow < 0.0) or (ou < 0.0 and ow > 0.0):
            _flip(h, s, vtri)
            crosses = False
            if p != a and p != b and q != a and q != b:
                op = orient2d(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[p, 0], pts[p, 1])
                oq = orient2d(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[q, 0], pts[q, 1])
                crosses = (op > 0.0 and oq < 0.0) or (op < 0.0 and oq > 0.0)
            if crosses:
                elist[2 * tail] = p
                elist[2 * tail + 1] = q
                cnt += 1
            elif not ((p == a and q == b) or (p == b and q == a)):
                nlist[2 * nn] = p
                nlist[2 * nn + 1] = q
                nn += 1
        else:
            elist[2 * tail] = u
            elist[2 * tail + 1] = w
            cnt += 1
    changed = True
    while changed:
        changed = False
        for e in range(nn):
            h = edge_of(np.int64(nlist[2 * e]), np.int64(nlist[2 * e + 1]), tri, nbr, vtri)
            t = h // 3
            n = nbr[h]
            if cons[h] != 0 or tri[3 * t + 2] == GHOST or tri[3 * n + 2] == GHOST:
                continue
            x = tri[3 * t]
            y = tri[3 * t + 1]
            z = tri[3 * t + 2]
            q = tri[3 * n + back3(nbr, n, t)]
            if incircle_sos(
                pts[x, 0], pts[x, 1], pts[y, 0], pts[y, 1], pts[z, 0], pts[z, 1], pts[q, 0], pts[q, 1],
                key_of(rank, x), key_of(rank, y), key_of(rank, z), key_of(rank, q),
            ) > 0:
                p = tri[h]
                _flip(h, s, vtri)
                nlist[2 * e] = p
                nlist[2 * e + 1] = q
                changed = True


@njit(cache=True, nogil=True)
def recover_segments(s, c, todo, rs, elist, nlist):
    """Recover every queued segment piece as constrained edges (no new vertices).

    Parameters
    ----------
    s : TriState
        The triangulation (:mod:`meshwright.tri._kernel2d`); ``cons`` receives the pieces.
    c : CdtState
        The constrained layer (:mod:`meshwright.tri._encroach`): ``vtri``, ``seg``, ``seg_in``.
    todo : (k,) int32
        Pieces to recover, processed from ``todo[rs[1] - 1]`` down.
    rs : (4,) int64
        ``[pieces in use, pieces queued, culprit piece, culprit half-edge]``.
    elist, nlist : (2 e,) int32
        Scratch: crossing edges and new edges, room for every edge of the triangulation.

    ``todo[:rs[1]]`` are pieces (rows of ``seg``) still to recover, ``rs[0]`` pieces in use.
    A piece running exactly through a vertex r is cut there: it becomes (a, r) and the new
    piece (r, b) (same input row ``seg_in``) is queued.  A piece already present as a
    constrained edge of another piece (a duplicate or overlapping segment) keeps the first.

    Returns
    -------
    int
        0 done; 1 the piece table ``seg`` is full (grow it and call again); 2 two segments
        intersect: ``rs[2]`` is the piece being recovered, ``rs[3]`` the crossed constrained
        half-edge (or -1 if the trace failed).
    """
    tri, nbr, cons, vtri, seg, seg_in = s.tri, s.nbr, s.cons, c.vtri, c.seg, c.seg_in
    while rs[1] > 0:
        p = todo[rs[1] - 1]
        a = seg[p, 0]
        b = seg[p, 1]
        kind, r, ne = _crossings(a, b, s, vtri, elist)
        if kind == 3:
            rs[2] = p
            rs[3] = r
            return 2
        if kind == 1:
            if rs[0] == seg.shape[0]:
                return 1
            np_ = rs[0]
            seg[np_, 0] = r
            seg[np_, 1] = b
            seg_in[np_] = seg_in[p]
            seg[p, 1] = r
            b = r
            rs[0] = np_ + 1
            todo[rs[1] - 1] = np_
            rs[1] += 1
            todo[rs[1] - 1] = p
        rs[1] -= 1
        if ne > 0:
            _sloan(a, b, ne, s, vtri, elist, nlist)
        h = edge_of(np.int64(a), np.int64(b), tri, nbr, vtri)
        if cons[h] == 0:
            cons[h] = p + 1
            cons[_twin(h, nbr)] = p + 1
    return 0
