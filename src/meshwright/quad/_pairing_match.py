"""Alternating-chain searches of the pairing (side elimination, :mod:`meshwright.quad.pairing`
step 3), re-exported by :mod:`meshwright.quad._pairing_kernel`: augmenting paths with
blossoms shrunk (J. Edmonds, "Paths, trees, and flowers", Canad. J. Math. 17, 1965),
searched breadth first from each unpaired triangle over the sides a round allows.

Array layout (as :mod:`meshwright.quad._pairing_kernel`): ``nbr`` flat int32, the triangle
across side k of triangle t at ``3 t + k`` (-1: none or blocked); ``mate`` (nt,) int32,
the partner or -1; ``raw`` flat float64 like ``nbr``, the raw score of the pair across a
side (:func:`meshwright.quad._pairing_kernel.side_scores`: scaled Jacobian,
:data:`REFLEX` or :data:`NO_PAIR`).  The searches' per-triangle table is described
below (``_A0`` .. ``_FLAG``).
"""

from __future__ import annotations

import numpy as np
from numba import njit

NO_PAIR = -2.0  # raw score of a side no pair may take (below any scaled Jacobian)
REFLEX = -3.0  # raw score of a pair with a corner of 180 degrees or more

__all__ = ["NO_PAIR", "REFLEX", "augment", "augment_changed", "augment_scratch", "score_of"]


@njit(inline="always")
def score_of(r, qmin):
    """The score of a pair of raw score ``r`` in a round of bound ``qmin``: its scaled
    Jacobian, 0 for a reflex pair when ``qmin < 0`` (the chapter's quads with a corner of
    180 degrees or more, left to enhancement and smoothing), -1 when not allowed."""
    if r == NO_PAIR:
        return -1.0
    q = r
    if r == REFLEX:
        if qmin >= 0.0:
            return -1.0
        q = 0.0
    return q if q >= qmin else -1.0


# Columns of augment's per-triangle table (augment_scratch's ``st``, (nt, 8) int32): the
# fields a search reads for one triangle share a row, so a visit touches one or two cache
# lines instead of one per array.
_A0 = 0  # _A0.._A0 + 2: the neighbour across each side the round allows, -1 across the others
_MATE = 3  # partner, -1 while unpaired (the caller's mate, copied in and out)
_PRED = 4  # the outer triangle an inner one was reached from, -1 at rest
_BASE = 5  # base of the blossom the triangle is shrunk into, itself at rest
_VPOS = 6  # position in the search's visit list
_FLAG = 7  # bit 0: outer (in the queue), bit 1: marked base of the blossom being shrunk; 0 at rest
_OUTER = 1
_MARKED = 2
_SHORT_SORT = 16  # blossom members sorted by insertion up to this many, by the array sort beyond


@njit(cache=True)
def _lca(a, b, st, mark, stamp):
    """Base of the blossom closing at a and b (walk up both alternating trees)."""
    while True:
        a = st[a, _BASE]
        mark[a] = stamp
        m = st[a, _MATE]
        if m < 0:
            break
        a = st[m, _PRED]
    while True:
        b = st[b, _BASE]
        if mark[b] == stamp:
            return b
        b = st[st[b, _MATE], _PRED]


@njit(cache=True)
def _mark_path(v, b, child, st, bstack, nb):
    """Mark the bases on the path from v up to the blossom base b (pushed on ``bstack``)."""
    while st[v, _BASE] != b:
        m = st[v, _MATE]
        for x in (st[v, _BASE], st[m, _BASE]):
            if st[x, _FLAG] & _MARKED == 0:
                st[x, _FLAG] |= _MARKED
                bstack[nb] = x
                nb += 1
        st[v, _PRED] = child
        child = m
        v = st[m, _PRED]
    return nb


@njit(cache=True)
def _contract(cur, st, bstack, nb, head, tail, link, vis, cand, queue, qtail):
    """Shrink the blossom of the marked bases ``bstack[:nb]`` into ``cur``.

    Each base keeps the list of the triangles it stands for (``head``/``tail``/``link``),
    so only the blossom's own members are visited, not the whole search (a scan of every
    visited triangle per blossom made failing searches quadratic in ``max_visit``).  The
    members not yet in the queue enter it in the order they were first reached
    (``_VPOS``), as a scan of the visit list would push them.  Returns the new queue tail.
    """
    nc = 0
    for r in range(nb):
        b = bstack[r]
        i = head[b]
        while i >= 0:
            st[i, _BASE] = cur
            if st[i, _FLAG] & _OUTER == 0:
                st[i, _FLAG] |= _OUTER
                cand[nc] = st[i, _VPOS]
                nc += 1
            i = link[i]
        if b != cur:
            link[tail[cur]] = head[b]
            tail[cur] = tail[b]
            head[b] = -1
        st[b, _FLAG] &= ~_MARKED
    # Sorted in place: a blossom-heavy search contracts thousands of times, and np.sort
    # would allocate a new array for each.  Most blossoms bring a handful of new members,
    # for which an insertion sort is several times cheaper than the array sort's call (a
    # capped search on the h=0.01 disk spent half its time there).
    if nc > _SHORT_SORT:
        cand[:nc].sort()
    else:
        for r in range(1, nc):
            x = cand[r]
            j = r - 1
            while j >= 0 and cand[j] > x:
                cand[j + 1] = cand[j]
                j -= 1
            cand[j + 1] = x
    for r in range(nc):
        queue[qtail] = vis[cand[r]]
        qtail += 1
    return qtail


@njit(cache=True)
def _search(st, root, mark, stamp, vis, queue, max_visit, bstack, head, tail, link, cand):
    """Edmonds' alternating-tree search from ``root``; returns the free triangle reached or -1.

    ``vis[:count]`` lists every triangle whose ``st`` row (bar its sides and partner) or
    member-list entries changed; the count is returned second so the caller can reset
    them.
    """
    nv = 0
    vis[nv] = root
    st[root, _VPOS] = nv
    nv += 1
    st[root, _FLAG] |= _OUTER
    head_q = 0
    tail_q = 0
    queue[tail_q] = root
    tail_q += 1
    while head_q < tail_q:
        if nv >= max_visit:
            return -1, nv, stamp
        v = queue[head_q]
        head_q += 1
        for k in range(3):
            to = st[v, _A0 + k]
            if to < 0:
                continue
            if st[v, _BASE] == st[to, _BASE] or st[v, _MATE] == to:
                continue
            mt = st[to, _MATE]
            if to == root or (mt >= 0 and st[mt, _PRED] >= 0):
                stamp += 1
                cur = _lca(v, to, st, mark, stamp)
                nb = _mark_path(v, cur, to, st, bstack, np.int64(0))
                nb = _mark_path(to, cur, v, st, bstack, nb)
                tail_q = _contract(cur, st, bstack, nb, head, tail, link, vis, cand, queue, tail_q)
            elif st[to, _PRED] < 0:
                st[to, _PRED] = v
                vis[nv] = to
                st[to, _VPOS] = nv
                nv += 1
                if mt < 0:
                    return to, nv, stamp
                st[mt, _FLAG] |= _OUTER
                vis[nv] = mt
                st[mt, _VPOS] = nv
                nv += 1
                queue[tail_q] = mt
                tail_q += 1
    return -1, nv, stamp


def augment_scratch(nt: int, spare: int = 0):
    """Work arrays of :func:`augment` for ``nt`` triangles, in their rest state.

    One set serves every :func:`augment` call on the same triangles: each search puts back
    what it changed, and the blossom stamp (``stamp``) carries over, so a caller making
    several rounds allocates and fills the O(nt) arrays once (about 1 ms a call at 78,000
    triangles, a dozen calls on the disk h=0.01).  ``spare`` rows more let it serve the
    same triangles with a few appended (centroid splits), since a call uses only the rows
    of its ``mate``.

    Returns
    -------
    tuple
        ``st`` (nt + spare, 8) int32, the per-triangle table (columns ``_A0`` .. ``_FLAG``;
        at rest ``_PRED`` -1, ``_BASE`` the row's own index, ``_FLAG`` 0, the sides and
        partner filled by each call), ``mark`` (rows,) int64, ``vis`` and ``queue``
        (2 rows + 2,) int32, ``bstack`` (rows + 1,) int32, ``head`` and ``tail`` (rows,)
        int32 (identity), ``link`` (rows,) int32 (-1), ``cand`` (rows + 1,) int32,
        ``stamp`` (1,) int64.
    """
    nt = int(nt) + int(spare)
    ident = np.arange(nt, dtype=np.int32)
    st = np.zeros((nt, 8), dtype=np.int32)
    st[:, _PRED] = -1
    st[:, _BASE] = ident
    return (
        st, np.zeros(nt, dtype=np.int64), np.empty(2 * nt + 2, dtype=np.int32), np.empty(2 * nt + 2, dtype=np.int32),
        np.empty(nt + 1, dtype=np.int32), ident.copy(), ident.copy(), np.full(nt, -1, dtype=np.int32),
        np.empty(nt + 1, dtype=np.int32), np.zeros(1, dtype=np.int64),
    )


@njit(inline="always")
def _fill_row(st, raw, nbr, mate, qmin, t):
    """Copy triangle t's allowed sides (a neighbour, and a score of at least ``qmin``) and
    its partner into its row of ``st``."""
    for k in range(3):
        i = 3 * t + k
        st[t, _A0 + k] = nbr[i] if nbr[i] >= 0 and score_of(raw[i], qmin) >= 0.0 else -1
    st[t, _MATE] = mate[t]


@njit(cache=True)
def augment(raw, nbr, mate, qmin, max_visit, scratch):
    """Pair left-over triangles along augmenting paths (Edmonds 1965, blossoms shrunk).

    From an unpaired triangle u an alternating tree grows across allowed sides; reaching
    another unpaired triangle v, the pairs along the path shift by one so that u and v
    are both paired.  Each search enters at most ``max_visit`` triangles (it then gives up
    on u), so the pass costs O(left-overs x max_visit) plus the blossoms' members.
    ``raw`` is :func:`~meshwright.quad._pairing_kernel.side_scores`' table; ``scratch`` is :func:`augment_scratch` of at
    least ``len(mate)`` rows, left in its rest state.  Returns the number of pairs gained.

    The sides the round allows (a neighbour, and a score of at least ``qmin``,
    :func:`score_of`) and the partners are copied once per call into the rows of ``st``
    (a path's new pairs are written to both), so a visit reads one row per triangle
    instead of one entry of each array.  A search
    that shrank no blossom changed only its triangles' ``_PRED`` and ``_FLAG``.
    """
    st = scratch[0]
    for t in range(mate.shape[0]):
        _fill_row(st, raw, nbr, mate, qmin, t)
    return _augment_rows(mate, max_visit, scratch)


@njit(cache=True)
def augment_changed(raw, nbr, mate, qmin, max_visit, scratch, changed):
    """:func:`augment` after an :func:`augment` (or this) call on the same triangles at
    the same ``qmin`` with the same ``scratch``, when since then only the triangles
    ``changed`` (k,) int64 got new sides or partners, their neighbours new sides (the
    twins :func:`~meshwright.quad._pairing_kernel.rescore` writes, or sides pointing back at them) and their former
    partners new partners, these being neighbours of the changed triangles too: the
    walks' flips (:func:`meshwright.quad.pairing._walk_left_overs`; a flip's two
    triangles keep the outer sides of their union, and the freed partner of one lay
    across such a side).  Only the rows of ``changed`` and of their neighbours are copied
    again (the rest of the table still holds what the last call left), so a walk round
    does not refill every triangle's row.  Same results as :func:`augment`.
    """
    st = scratch[0]
    for i in range(changed.shape[0]):
        t = changed[i]
        _fill_row(st, raw, nbr, mate, qmin, t)
        for k in range(3):
            s = nbr[3 * t + k]
            if s >= 0:
                _fill_row(st, raw, nbr, mate, qmin, s)
    return _augment_rows(mate, max_visit, scratch)


@njit(cache=True)
def _augment_rows(mate, max_visit, scratch):
    """The searches of :func:`augment` from every unpaired triangle, on rows already filled."""
    nt = mate.shape[0]
    st, mark, vis, queue, bstack, head, tail, link, cand, stamps = scratch
    # Blossom stamps go on from the last call: marks it left must not match new ones.
    stamp = stamps[0]
    gained = 0
    for u in range(nt):
        # ``mate`` holds the same partners as the table's ``_MATE`` column (both are
        # written on every path and by the fill), read at 4 bytes a row instead of 32.
        if mate[u] >= 0:
            continue
        before = stamp
        found, nv, stamp = _search(st, u, mark, stamp, vis, queue, max_visit, bstack, head, tail, link, cand)
        if found >= 0:
            v = found
            while v >= 0:
                pv = st[v, _PRED]
                ppv = st[pv, _MATE]
                st[v, _MATE] = pv
                st[pv, _MATE] = v
                mate[v] = pv
                mate[pv] = v
                v = ppv
            gained += 1
        for r in range(nv):
            i = vis[r]
            st[i, _PRED] = -1
            st[i, _FLAG] = 0
        if stamp != before:
            for r in range(nv):
                i = vis[r]
                st[i, _BASE] = i
                head[i] = i
                tail[i] = i
                link[i] = -1
    stamps[0] = stamp
    return gained
