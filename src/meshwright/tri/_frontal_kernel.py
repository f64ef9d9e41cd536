r"""Numba kernel of the frontal Delaunay method (see :mod:`meshwright.tri.frontal_delaunay`).

State between calls, the method's :class:`FrontalState` bundle (the kernel returns
``F_ROOM`` whenever the constrained triangulation or the per-slot arrays must grow, and is
called again):

    acc    (cap,) int8       1 where the slot's triangle is accepted; every slot an
                             insertion or a removal rewrites is classified again (the
                             new vertex's star, the removal's new triangles), which
                             resets it, and a moved triangle takes its flag along
    ratio  (cap,) float64    R sqrt(3) / h of each slot's triangle, set when it is made
    qhead, qnext, qprev,     the queue of waiting front triangles, largest ratio first
    qbin, qhdr               (:mod:`meshwright.core.bucket_queue`'s slot queue, whose
                             entries are the slots themselves; qbin[t] >= 0 while slot t
                             is queued, and a slot's entry is deleted wherever the slot
                             is rewritten: classified again, or freed and moved into)
    stamp  (cap,) int64      visit marks of the disc searches (never reset: a counter)
    fmeta  (FM_LEN,) int64   stamp counter, points added, free rows, live scaffold
                             vertices, scaffold removed / kept, scan cursor
    par    (P_LEN,) float64  ACCEPT, SPACING, max points, constant size (0: background),
                             scaffold clearance, scaffold spacing, queue lift of the
                             triangles with a scaffold vertex
    vflag  (rows,) int8      1 at a live scaffold vertex
    free   (rows,) int32     stack of dead rows (removed scaffold vertices), reused first
    vbg    (rows,) int32     a background triangle at or near each vertex (-1: not yet),
                             where every size query near the vertex starts its walk
    scr    (SCRATCH,) int32  scratch of :func:`meshwright.tri._scaffold.remove_vertex`
    stack  (STACK,) int32    scratch of the disc searches (a kernel's own allocation could
                             not be borrowed, see below)

The scaffold: before the front starts, :func:`seed_scaffold` inserts coarse interior points
(spacing about ``par[P_SCAF]`` h, in Hilbert order), so that the unmeshed interior is made of
triangles of a few h instead of long triangles spanning it, whose circumcircles made every
frontal insertion's cavity as long as the front.  A triangle with a scaffold vertex is
never accepted; a scaffold vertex within ``par[P_CLEAR]`` h of a proposed point, or a
vertex of a triangle that has no room for a point, is removed
(:func:`meshwright.tri._scaffold.remove_vertex`) and the hole's triangles join the front
like an insertion's.  An empty queue therefore means that no scaffold vertex is left (a
safety scan removes any that are; one whose removal is refused stays as an ordinary
vertex and is counted).

The constrained triangulation is passed as its two bundles, ``s`` (``TriState``) and ``c``
(``CdtState``) of :class:`~meshwright.tri.cdt.ConstrainedTriangulation`.  ``bg`` is the
background grid's kernel tuple (:meth:`meshwright.sizing.BackgroundGrid.kernel_args`) plus
the walk's hint, passed as one tuple argument.

Every kernel first replaces its bundles by :func:`meshwright.core.borrowed.borrowed` views
of them: the per-step helpers are inlined and branch, so each array they take was an
atomic reference-count pair per call (about 20 % of the disk's run); the views have none.
The caller keeps the arrays alive for the whole call, and no view leaves it.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from meshwright.core.borrowed import borrowed
from meshwright.core.bucket_queue import Q_N, sq_pop, sq_push, sq_remove
from meshwright.core.flat import GHOST
from meshwright.core.geom2d import circumcentre_offset, corners, segment_dist2
from meshwright.sizing.background import interpolate_walk
from meshwright.tri import _encroach as enc
from meshwright.tri._kernel2d import (
    BROKEN,
    DUP_BASE,
    I_WALK,
    M_LAST,
    M_NTRI,
    M_NV,
    NEED_SPACE,
    _on_constraint,
    _walk,
    insert_arrays,
)
from meshwright.tri._frontal_queue import fq_bucket
from meshwright.tri._scaffold import KMAX, move_row, move_slot, remove_vertex

F_DONE, F_ROOM, F_BROKEN, F_POINTS = range(4)
FM_STAMP, FM_ADDED, FM_NFREE, FM_NSCAF, FM_REMOVED, FM_KEPT, FM_CURSOR, FM_LEN = range(8)
P_ACCEPT, P_SPACING, P_MAX_POINTS, P_CONST, P_CLEAR, P_SCAF, P_LIFT, P_LEN = range(8)
STACK = 4096  # triangles a disc search keeps pending (more: the disc is crowded)
_SQRT3 = np.sqrt(3.0)
_NEAR_NONE = -1
_NEAR_CROWDED = -2


class FrontalState(NamedTuple):
    """The frontal method's arrays (layout in the module docstring), one kernel argument."""

    acc: np.ndarray
    ratio: np.ndarray
    qhead: np.ndarray
    qnext: np.ndarray
    qprev: np.ndarray
    qbin: np.ndarray
    qhdr: np.ndarray
    stamp: np.ndarray
    fmeta: np.ndarray
    par: np.ndarray
    vflag: np.ndarray
    free: np.ndarray
    scr: np.ndarray
    vbg: np.ndarray
    stack: np.ndarray


@njit(inline="always")
def _settled(t, acc):
    # A byte per slot, not the accepted vertex triple: the checks of a neighbour's state
    # were 11 % of the run's samples, mostly cache misses (disk, 289k triangles).
    return acc[t] != 0


@njit(inline="always")
def _inside(t, tri, treg):
    return t >= 0 and tri[3 * t + 2] != GHOST and treg[t] >= 0


@njit(inline="always")
def _radius(pts, tri, t):
    """Circumradius of triangle slot t (a square root: libm's overflow-safe ``hypot`` was
    3 % of the disk's run)."""
    ax, ay, bx, by, cx, cy = corners(pts, tri, t)
    ox, oy = circumcentre_offset(bx - ax, by - ay, cx - ax, cy - ay)
    return np.sqrt(ox * ox + oy * oy)


@njit(inline="always")
def _scaffold_of(t, tri, vflag):
    """A scaffold vertex of triangle t, or -1."""
    for k in range(3):
        if vflag[tri[3 * t + k]] != 0:
            return tri[3 * t + k]
    return -1


@njit(inline="always")
def _front_edge(t, pts, tri, nbr, treg, acc):
    """The longest edge of t toward an accepted triangle or out of the domain, or -1."""
    best = -1
    blen = -1.0
    for e in range(3):
        n = nbr[3 * t + e]
        if _inside(n, tri, treg) and not _settled(n, acc):
            continue
        a = tri[3 * t + (e + 1) % 3]
        b = tri[3 * t + (e + 2) % 3]
        # Squared lengths: libm's hypot call was about 1 % of the process's samples on the disk.
        ln = (pts[b, 0] - pts[a, 0]) ** 2 + (pts[b, 1] - pts[a, 1]) ** 2
        if ln > blen:
            blen = ln
            best = e
    return best


@njit(inline="always")
def _push(t, ratio, q):
    """Queue slot t by its ratio unless it is queued already; ``q`` is
    ``(qhead, qnext, qprev, qbin, qhdr)``."""
    qhead, qnext, qprev, qbin, qhdr = q
    if qbin[t] < 0:
        sq_push(t, fq_bucket(ratio[t]), qhead, qnext, qprev, qbin, qhdr)


@njit(inline="always")
def _unqueue(t, q):
    qhead, qnext, qprev, qbin, qhdr = q
    sq_remove(t, qhead, qnext, qprev, qbin, qhdr)


@njit(inline="always")
def _size(par, bg, t0, x, y):
    """The size at (x, y), its background walk started at background triangle t0 (when
    t0 >= 0; else where the last walk ended).  A walk from the last query, wherever the queue
    took it, crossed the graded background or left it across a hole into a bucket scan:
    7x the kernel's time on the graded NACA 0012; from a vertex of the triangle at hand it
    is a step or two."""
    if par[P_CONST] > 0.0:
        return par[P_CONST]
    bg_pts, bg_tri, bg_nbr, bg_start, bg_items, bg_x0, bg_y0, bg_cell, bg_nx, bg_ny, bg_val, bg_hint = bg
    if t0 >= 0:
        bg_hint[0] = t0
    return interpolate_walk(
        bg_pts, bg_tri, bg_nbr, bg_start, bg_items, bg_x0, bg_y0, bg_cell, bg_nx, bg_ny, bg_val, 0, bg_hint, x, y
    )


@njit(inline="always")
def _hint_of(t, tri, vbg):
    """A background triangle near triangle t (a vertex's), or -1."""
    for k in range(3):
        if vbg[tri[3 * t + k]] >= 0:
            return vbg[tri[3 * t + k]]
    return -1


@njit(inline="always")
def classify(t, pts, tri, acc, ratio, par, bg, vflag, vbg, q):
    """Store slot t's ``R sqrt(3) / h`` in ``ratio[t]``; accept t if it is within ACCEPT and
    has no scaffold vertex."""
    _unqueue(t, q)  # a key from before (a scaffold vertex's lift, a former triangle) no longer holds
    acc[t] = 0
    r = _radius(pts, tri, t)
    h = par[P_CONST]
    if h <= 0.0:
        gx = (pts[tri[3 * t], 0] + pts[tri[3 * t + 1], 0] + pts[tri[3 * t + 2], 0]) / 3.0
        gy = (pts[tri[3 * t], 1] + pts[tri[3 * t + 1], 1] + pts[tri[3 * t + 2], 1]) / 3.0
        h = _size(par, bg, _hint_of(t, tri, vbg), gx, gy)
    ratio[t] = r * _SQRT3 / h
    if _scaffold_of(t, tri, vflag) >= 0:
        # Waits before every scaffold-free triangle, as the triangles spanning the open
        # interior do without a scaffold (without the lift: mean radius ratio 0.9887
        # against 0.9968 on the disk at h = 0.01).
        ratio[t] += par[P_LIFT]
    elif ratio[t] <= par[P_ACCEPT]:
        acc[t] = 1


@njit(inline="always")
def _push_if_front(t, pts, tri, nbr, treg, acc, ratio, q):
    """Queue slot t (ratio known since it was made) if it waits on the front (and is not
    queued yet: checked first, it spares most front-edge searches)."""
    if not _inside(t, tri, treg) or q[3][t] >= 0 or _settled(t, acc):
        return
    if _front_edge(t, pts, tri, nbr, treg, acc) < 0:
        return
    _push(t, ratio, q)


@njit(cache=True)
def start(s, c, f, bg):
    """Locate the vertices that have no background triangle yet (in row order: along the
    boundary loops, each walk short), accept the right-sized inside triangles and push the
    others that touch the front."""
    s, c, f, bg = borrowed(s), borrowed(c), borrowed(f), borrowed(bg)
    pts, tri, nbr, treg = s.pts, s.tri, s.nbr, c.treg
    acc, ratio, par, vflag, vbg = f.acc, f.ratio, f.par, f.vflag, f.vbg
    q = (f.qhead, f.qnext, f.qprev, f.qbin, f.qhdr)
    if par[P_CONST] == 0.0:
        for v in range(s.meta[M_NV]):
            if vbg[v] < 0 and c.vtri[v] >= 0:
                _size(par, bg, -1, pts[v, 0], pts[v, 1])
                vbg[v] = bg[11][0]
    ntri = s.meta[M_NTRI]
    for t in range(ntri):
        if _inside(t, tri, treg):
            classify(t, pts, tri, acc, ratio, par, bg, vflag, vbg, q)
    for t in range(ntri):
        _push_if_front(t, pts, tri, nbr, treg, acc, ratio, q)


@njit(inline="always")
def _near(px, py, rclear, rspace, rseg, host, pts, tri, nbr, cons, treg, vflag, stamp, fmeta, stack):
    """Search the triangles the disc of radius ``max(rclear, rspace)`` about p reaches from
    host: a scaffold vertex within rclear, ``_NEAR_CROWDED`` when another vertex lies within
    rspace or a constrained edge of a triangle the disc reaches lies within ``rseg`` (0: no
    such test), else ``_NEAR_NONE``."""
    fmeta[FM_STAMP] += 1
    mark = fmeta[FM_STAMP]
    rc2 = rclear * rclear
    rs2 = rspace * rspace
    rg2 = rseg * rseg
    r2 = max(rc2, rs2)
    top = 1
    stack[0] = host
    stamp[host] = mark
    while top > 0:
        top -= 1
        t = stack[top]
        for m in range(3):
            v = tri[3 * t + m]
            d2 = (pts[v, 0] - px) ** 2 + (pts[v, 1] - py) ** 2
            if vflag[v] != 0:
                if d2 < rc2:
                    return v
            elif d2 < rs2:
                return _NEAR_CROWDED
        for e in range(3):
            n = nbr[3 * t + e]
            fence = cons[3 * t + e] != 0 or not _inside(n, tri, treg)
            if (fence and rg2 == 0.0) or (not fence and stamp[n] == mark):
                continue
            a = tri[3 * t + (e + 1) % 3]
            b = tri[3 * t + (e + 2) % 3]
            d2 = segment_dist2(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], px, py)
            if fence:
                if d2 < rg2:
                    return _NEAR_CROWDED
                continue
            if d2 < r2:
                if top >= stack.shape[0]:
                    return _NEAR_CROWDED  # a disc this crowded is too close anyway
                stamp[n] = mark
                stack[top] = n
                top += 1
    return _NEAR_NONE


@njit(inline="always")
def _insert_at(px, py, host, pts, tri, nbr, circ, rank, cons, meta, work, vmark, vtri, treg, vseg, vpar, vacute,
               free, fmeta, vflag, rows):
    """Insert p (inside, strictly off every constrained edge) into a dead row if one is
    free, else a new row (the bundles' arrays passed one by one, read once per kernel
    call: a bundle's field read costs an atomic reference-count pair each time).  Returns
    the vertex, or ``NEED_SPACE`` / ``BROKEN`` / a duplicate code of
    :func:`meshwright.tri._kernel2d.insert_vertex` (nothing changed then)."""
    nfree = fmeta[FM_NFREE]
    row = free[nfree - 1] if nfree > 0 else meta[M_NV]
    if row >= rows:
        return NEED_SPACE
    pts[row, 0] = px
    pts[row, 1] = py
    f0 = treg[host]
    meta[M_LAST] = host
    tn = insert_arrays(pts, tri, nbr, circ, rank, cons, meta, work, vmark, row, host, np.int64(I_WALK))
    if tn < 0:
        return tn
    if nfree > 0:
        fmeta[FM_NFREE] = nfree - 1
    else:
        meta[M_NV] = row + 1
    vseg[row] = -1
    vacute[row] = 0
    vpar[row] = np.nan
    vflag[row] = 0
    enc.link_star(row, tn, -1, -1, f0, f0, f0, tri, nbr, vtri, treg)
    return row



@njit(cache=True)
def seed_scaffold(xy, i0, s, c, f, bg):
    """Insert the scaffold candidates ``xy[i0:]`` (k, 2) that fall inside the domain and
    keep ``par[P_SCAF] / 2`` h from every vertex.

    Returns
    -------
    (int, int)
        ``(i, F_DONE)`` with i = len(xy), or ``(i, F_ROOM)`` / ``(i, F_BROKEN)`` at point i.
    """
    s, c, f, bg = borrowed(s), borrowed(c), borrowed(f), borrowed(bg)
    pts, tri, nbr, circ, rank, cons, meta, work, vmark = s
    vtri, treg, vseg, vpar, vacute = c.vtri, c.treg, c.vseg, c.vpar, c.vacute
    stamp, fmeta, par, vflag, free, vbg, stack = f.stamp, f.fmeta, f.par, f.vflag, f.free, f.vbg, f.stack
    rows, slots = enc.room_of(s, c)
    for i in range(i0, xy.shape[0]):
        ntri = meta[M_NTRI]
        if ntri + 2 > slots or stamp.shape[0] < ntri + 2 or meta[M_NV] + 1 > min(rows, vflag.shape[0], vbg.shape[0]):
            return i, F_ROOM
        px = xy[i, 0]
        py = xy[i, 1]
        host, _ = _walk(pts, tri, nbr, cons, meta, meta[M_LAST] if meta[M_LAST] < ntri else 0, px, py, False)
        if host >= 0:
            # The next walk starts here, refused or not: from the last insertion, runs of
            # refused candidates made each walk longer (a 1e4-aspect strip of 105k
            # boundary points: 10.7 s of seeding).
            meta[M_LAST] = host
        if not _inside(host, tri, treg) or _on_constraint(pts, tri, cons, host, px, py) >= 0:
            continue
        # The candidates come in Hilbert order: the last walk's end is a near start.
        r = 0.5 * par[P_SCAF] * _size(par, bg, -1, px, py)
        if _near(px, py, r, r, 0.0, host, pts, tri, nbr, cons, treg, vflag, stamp, fmeta, stack) != _NEAR_NONE:
            continue
        v = _insert_at(px, py, host, pts, tri, nbr, circ, rank, cons, meta, work, vmark, vtri, treg, vseg, vpar,
                       vacute, free, fmeta, vflag, rows)
        if v == NEED_SPACE:
            return i, F_ROOM
        if v == BROKEN:
            return i, F_BROKEN
        if v >= 0:
            vflag[v] = 1
            vbg[v] = bg[11][0]
            fmeta[FM_NSCAF] += 1
    return xy.shape[0], F_DONE


@njit(inline="always")
def _star_update(v, n, scr, pts, tri, nbr, treg, vtri, acc, ratio, q, par, bg, vflag, vbg):
    """Classify, then queue on the front: with n > 0 the n new triangles of a scaffold
    removal (slots ``scr[KMAX:KMAX + n]``, :func:`_drop`) and their three neighbours each;
    with n < 0 only the three neighbours of slot ``scr[KMAX]`` (a triangle accepted as it is,
    not classified again); else the star of vertex v, each slot and its outer neighbour.

    One loop over both phases and all kinds, so that :func:`run` inlines one copy of
    :func:`classify` and of :func:`_push_if_front` for all of them (a copy per call site is
    typed and lowered again on the first run; issue 13)."""
    for phase in range(2):
        sl = scr[KMAX] if n != 0 else vtri[v]
        s0 = sl
        for i in range(n if n > 0 else (1 if n < 0 else 1024)):
            k = -1
            if n != 0:
                sl = scr[KMAX + i]
            else:
                k = 0
                while tri[3 * sl + k] != v:
                    k += 1
            if phase == 0:
                if n > 0 or (n == 0 and _inside(sl, tri, treg)):
                    classify(sl, pts, tri, acc, ratio, par, bg, vflag, vbg, q)
            else:
                # The slot (j = -1; an accepted one is not queued), then its outer
                # neighbour in a star or all three.
                for j in range(-1, 3):
                    if j < 0 or n != 0 or j == k:
                        _push_if_front(sl if j < 0 else nbr[3 * sl + j], pts, tri, nbr, treg, acc, ratio, q)
            if n == 0:
                sl = nbr[3 * sl + (k + 1) % 3]
                if sl == s0 or sl < 0:
                    break


@njit(cache=True)
def _drop(v, pts, tri, nbr, cons, treg, vtri, meta, acc, ratio, q, fmeta, par, bg, vflag, vbg, free, scr, s, c):
    """Remove scaffold vertex v, refill the freed slots from the end, queue the new front.

    A call, not inlined: :func:`run` calls it from three places, and three inlined copies
    of its body (with :func:`_star_update` and every ``_push_if_front``) made the first
    frontal-delaunay call cost about 100 s of compile (CPU, kernels it shares with other
    methods cached); as a call, 39 s, and no measurable run time (one call per removed
    scaffold vertex; disk of 289k triangles, 2026-12-02).

    Returns the number n of new triangles, their slots in ``scr[KMAX:KMAX + n]``, which the
    caller classifies and queues with its own inlined :func:`_star_update`; or 0 when the
    removal was refused: v stays as an ordinary vertex (counted in ``FM_KEPT``) whose star
    the caller updates the same way (copies here were typed and lowered again on every
    first run: issue 13, about 3 s for the star's, 2 s for the new triangles').
    """
    vflag[v] = 0
    fmeta[FM_NSCAF] -= 1
    k = remove_vertex(v, s, c, scr)
    if k < 0:
        fmeta[FM_KEPT] += 1
        return 0
    fmeta[FM_REMOVED] += 1
    free[fmeta[FM_NFREE]] = v
    fmeta[FM_NFREE] += 1
    st = scr[KMAX : 2 * KMAX]
    fa = st[k - 2]
    fb = st[k - 1]
    for fs in (max(fa, fb), min(fa, fb)):
        _unqueue(fs, q)  # the freed slot's triangle is gone
        last = meta[M_NTRI] - 1
        if fs != last:
            # The entry of the last slot's triangle names that slot: it moves with it.
            _unqueue(last, q)
            move_slot(last, fs, tri, nbr, cons, treg, vtri, meta)
            acc[fs] = acc[last]
            ratio[fs] = ratio[last]
            for i in range(k - 2):
                if st[i] == last:
                    st[i] = fs
            _push_if_front(fs, pts, tri, nbr, treg, acc, ratio, q)
        meta[M_NTRI] = last
    return k - 2


@njit(cache=True)
def run(s, c, f, bg):
    """Insert Rebay points, worst front triangle first, until the queue is empty and no
    scaffold vertex is left.

    The bundles' fields are read once here and handed to the per-step helpers as arrays:
    a field read inside a loop costs a reference-count pair per iteration.
    """
    s, c, f, bg = borrowed(s), borrowed(c), borrowed(f), borrowed(bg)
    pts, tri, nbr, circ, rank, cons, meta, work, vmark = s
    vtri, treg, vseg, vpar, vacute = c.vtri, c.treg, c.vseg, c.vpar, c.vacute
    acc, ratio, stamp, fmeta, par = f.acc, f.ratio, f.stamp, f.fmeta, f.par
    vflag, free, scr, vbg, stack = f.vflag, f.free, f.scr, f.vbg, f.stack
    qhead, qnext, qprev, qbin, qhdr = f.qhead, f.qnext, f.qprev, f.qbin, f.qhdr
    q = (qhead, qnext, qprev, qbin, qhdr)
    rows, slots = enc.room_of(s, c)
    rows = min(rows, vflag.shape[0], free.shape[0], vbg.shape[0])
    # The vertex whose new star (or, nnew > 0, whose removal's new triangles; nnew < 0: the
    # neighbours of the triangle in scr[KMAX], accepted without a point) the last step
    # left to classify and queue: done here, at the top of the next step, so that the loop
    # has one inlined copy of _star_update for insertions and removals alike (it changes no
    # slot count, so the room check below holds after it as before).
    pending = -1
    nnew = 0  # with pending: a removal's new triangles, 0 for pending's star, -1 for an accepted slot
    while True:
        if pending >= 0:
            _star_update(pending, nnew, scr, pts, tri, nbr, treg, vtri, acc, ratio, q, par, bg, vflag, vbg)
            pending = -1
        ntri = meta[M_NTRI]
        if (
            acc.shape[0] < ntri + 2 or min(qbin.shape[0], qnext.shape[0], qprev.shape[0]) < ntri + 2
            or stamp.shape[0] < ntri + 2 or ratio.shape[0] < ntri + 2 or ntri + 2 > slots
        ):
            return F_ROOM
        if qhdr[Q_N] == 0:
            if fmeta[FM_NSCAF] == 0:
                return F_DONE
            # Safety scan: a scaffold vertex the front never reached.
            v = fmeta[FM_CURSOR]
            while v < meta[M_NV] and vflag[v] == 0:
                v += 1
            fmeta[FM_CURSOR] = v
            if v >= meta[M_NV]:
                fmeta[FM_NSCAF] = 0
                continue
            nnew = _drop(v, pts, tri, nbr, cons, treg, vtri, meta, acc, ratio, q, fmeta, par, bg, vflag, vbg, free, scr,
                         s, c)
            pending = v
            continue
        if meta[M_NV] - fmeta[FM_NFREE] - fmeta[FM_NSCAF] >= par[P_MAX_POINTS]:
            return F_POINTS
        # A queued slot holds a live inside triangle that is not accepted: every rewrite or
        # acceptance of a slot takes its entry out first (classify, _drop).
        t = sq_pop(qhead, qnext, qprev, qbin, qhdr)
        e = _front_edge(t, pts, tri, nbr, treg, acc)
        if e < 0:
            continue
        rad = _radius(pts, tri, t)
        # Rebay's point on the perpendicular bisector of the front edge ab (module
        # docstring of frontal_delaunay), sized at the edge: a long waiting triangle's
        # circumcentre may lie where the size is far larger.
        a = tri[3 * t + (e + 1) % 3]
        b = tri[3 * t + (e + 2) % 3]
        h = _size(par, bg, vbg[a], 0.5 * (pts[a, 0] + pts[b, 0]), 0.5 * (pts[a, 1] + pts[b, 1]))
        near_bg = bg[11][0]
        blen = np.sqrt((pts[b, 0] - pts[a, 0]) ** 2 + (pts[b, 1] - pts[a, 1]) ** 2)
        p = 0.5 * blen
        nx = -(pts[b, 1] - pts[a, 1]) / blen
        ny = (pts[b, 0] - pts[a, 0]) / blen
        rho = min(max(h / _SQRT3, p), rad)
        d = rho + np.sqrt(max(rho * rho - p * p, 0.0))
        px = 0.5 * (pts[a, 0] + pts[b, 0]) + d * nx
        py = 0.5 * (pts[a, 1] + pts[b, 1]) + d * ny
        host, _ = _walk(pts, tri, nbr, cons, meta, t, px, py, False)
        near = _NEAR_CROWDED
        if _inside(host, tri, treg) and _on_constraint(pts, tri, cons, host, px, py) < 0:
            # Half the front edge's half-length from every constrained edge: the point is
            # at least that from its own front edge, and a spike's Rebay point landed 3e-14
            # off the opposite side (stress reproducer 3200dccf8449: the flat triangle made
            # the final min-angle pass fail).
            near = _near(px, py, par[P_CLEAR] * h, par[P_SPACING] * h, 0.5 * p, host, pts, tri, nbr, cons, treg,
                         vflag, stamp, fmeta, stack)
        if near >= 0:
            # A scaffold vertex in the way: remove it and try t again (if it survived).
            _push(t, ratio, q)
            nnew = _drop(near, pts, tri, nbr, cons, treg, vtri, meta, acc, ratio, q, fmeta, par, bg, vflag, vbg, free,
                         scr, s, c)
            pending = near
            continue
        if near == _NEAR_CROWDED:
            # No room for a point: the triangle stays as it is and joins the accepted ones,
            # unless it hangs on a scaffold vertex, which goes instead.
            sv = _scaffold_of(t, tri, vflag)
            if sv >= 0:
                nnew = _drop(sv, pts, tri, nbr, cons, treg, vtri, meta, acc, ratio, q, fmeta, par, bg, vflag, vbg, free,
                             scr, s, c)
                pending = sv
                continue
            acc[t] = 1
            # Its neighbours are queued by the next step's _star_update (one inlined copy).
            scr[KMAX] = t
            pending = t
            nnew = -1
            continue
        v = _insert_at(px, py, host, pts, tri, nbr, circ, rank, cons, meta, work, vmark, vtri, treg, vseg, vpar,
                       vacute, free, fmeta, vflag, rows)
        if v == NEED_SPACE:
            _push(t, ratio, q)
            return F_ROOM
        if v == BROKEN:
            return F_BROKEN
        if v <= DUP_BASE:
            continue  # the point was already a vertex
        fmeta[FM_ADDED] += 1
        vbg[v] = near_bg  # the front edge's midpoint is within about h of v
        pending = v
        nnew = 0


@njit(cache=True)
def close_rows(s, c, f):
    """Renumber the last live vertices into the dead rows left by removed scaffold vertices,
    so that rows ``[0, meta[M_NV])`` are all live.  Returns False if a star did not close."""
    meta, vtri = s.meta, c.vtri
    free, fmeta = f.free, f.fmeta
    for _ in range(free.shape[0] + 1):
        if fmeta[FM_NFREE] == 0:
            return True
        last = meta[M_NV] - 1
        if vtri[last] < 0:
            for j in range(fmeta[FM_NFREE]):
                if free[j] == last:
                    free[j] = free[fmeta[FM_NFREE] - 1]
                    break
            fmeta[FM_NFREE] -= 1
            meta[M_NV] = last
            continue
        fmeta[FM_NFREE] -= 1
        if not move_row(last, free[fmeta[FM_NFREE]], s, c):
            return False
        meta[M_NV] = last
    return fmeta[FM_NFREE] == 0
