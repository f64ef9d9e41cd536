r"""Numba kernel of the frontal Delaunay method (see :mod:`meshwright.tri.frontal_delaunay`).

State between calls, the method's :class:`FrontalState` bundle (the kernel returns
``F_ROOM`` whenever the constrained triangulation or the heap must grow, and is called
again):

    acc    (3 cap,) int32    vertex triple of the triangle accepted in each slot (a slot
                             reused by a later insertion no longer matches)
    ratio  (cap,) float64    R sqrt(3) / h of each slot's triangle, set when it is made
    hkey   (hcap,) float64   min-heap (:mod:`meshwright.core.heap`) of -ratio (largest
    htri   (hcap, 4) int32   circumradius / ideal first); payload: slot and vertex triple
                             of each entry (stale when the slot changed)
    stamp  (cap,) int64      visit marks of the spacing search (never reset: a counter)
    fmeta  (F_LEN,) int64    heap size, stamp counter, points added
    par    (P_LEN,) float64  ACCEPT, SPACING, max points, constant size (0: background)

The constrained triangulation is passed as its two bundles, ``s`` (``TriState``) and ``c``
(``CdtState``) of :class:`~meshwright.tri.cdt.ConstrainedTriangulation`; insertion goes
through :func:`meshwright.tri._encroach.insert_points`, one point at a time.  ``bg`` is the
background grid's kernel tuple (:meth:`meshwright.sizing.BackgroundGrid.kernel_args`) plus
the walk's hint, passed as one tuple argument.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from meshwright.core.flat import GHOST
from meshwright.core.geom2d import circumcircle, corners, segment_dist2
from meshwright.core.heap import heap_pop, heap_push
from meshwright.sizing.background import interpolate_walk
from meshwright.tri import _encroach as enc
from meshwright.tri._kernel2d import M_LAST, M_NTRI, M_NV, walk

F_DONE, F_ROOM, F_BROKEN, F_POINTS = range(4)
FM_HN, FM_STAMP, FM_ADDED, FM_LEN = range(4)
P_ACCEPT, P_SPACING, P_MAX_POINTS, P_CONST, P_LEN = range(5)
HEAP_ROOM = 256  # free heap entries needed before an insertion (one star pushes far fewer)
_SQRT3 = np.sqrt(3.0)


class FrontalState(NamedTuple):
    """The frontal method's arrays (layout in the module docstring), one kernel argument."""

    acc: np.ndarray
    ratio: np.ndarray
    hkey: np.ndarray
    htri: np.ndarray
    stamp: np.ndarray
    fmeta: np.ndarray
    par: np.ndarray


@njit(inline="always")
def _settled(t, tri, acc):
    return acc[3 * t] == tri[3 * t] and acc[3 * t + 1] == tri[3 * t + 1] and acc[3 * t + 2] == tri[3 * t + 2]


@njit(inline="always")
def _inside(t, tri, treg):
    return t >= 0 and tri[3 * t + 2] != GHOST and treg[t] >= 0


@njit(inline="always")
def _radius(pts, tri, t):
    """Circumradius of triangle slot t."""
    ax, ay, bx, by, cx, cy = corners(pts, tri, t)
    return circumcircle(ax, ay, bx, by, cx, cy)[2]


@njit(inline="always")
def _front_edge(t, pts, tri, nbr, treg, acc):
    """The longest edge of t toward an accepted triangle or out of the domain, or -1."""
    best = -1
    blen = -1.0
    for e in range(3):
        n = nbr[3 * t + e]
        if _inside(n, tri, treg) and not _settled(n, tri, acc):
            continue
        a = tri[3 * t + (e + 1) % 3]
        b = tri[3 * t + (e + 2) % 3]
        ln = np.hypot(pts[b, 0] - pts[a, 0], pts[b, 1] - pts[a, 1])
        if ln > blen:
            blen = ln
            best = e
    return best


@njit(inline="always")
def _push(hkey, htri, fmeta, key, t, tri):
    i = heap_push(hkey, htri, fmeta[FM_HN], key)
    fmeta[FM_HN] += 1
    htri[i, 0] = t
    for k in range(3):
        htri[i, k + 1] = tri[3 * t + k]


@njit(inline="always")
def _size(par, bg, x, y):
    if par[P_CONST] > 0.0:
        return par[P_CONST]
    bg_pts, bg_tri, bg_nbr, bg_start, bg_items, bg_x0, bg_y0, bg_cell, bg_nx, bg_ny, bg_val, bg_hint = bg
    return interpolate_walk(
        bg_pts, bg_tri, bg_nbr, bg_start, bg_items, bg_x0, bg_y0, bg_cell, bg_nx, bg_ny, bg_val, 0, bg_hint, x, y
    )


@njit(inline="always")
def classify(t, pts, tri, acc, ratio, par, bg):
    """Store slot t's ``R sqrt(3) / h`` in ``ratio[t]``; accept t if it is within ACCEPT."""
    r = _radius(pts, tri, t)
    gx = (pts[tri[3 * t], 0] + pts[tri[3 * t + 1], 0] + pts[tri[3 * t + 2], 0]) / 3.0
    gy = (pts[tri[3 * t], 1] + pts[tri[3 * t + 1], 1] + pts[tri[3 * t + 2], 1]) / 3.0
    h = _size(par, bg, gx, gy)
    ratio[t] = r * _SQRT3 / h
    if ratio[t] <= par[P_ACCEPT]:
        for k in range(3):
            acc[3 * t + k] = tri[3 * t + k]


@njit(inline="always")
def _push_if_front(t, pts, tri, nbr, treg, acc, ratio, hkey, htri, fmeta):
    """Queue slot t (ratio known since it was made) if it waits on the front."""
    if not _inside(t, tri, treg) or _settled(t, tri, acc) or _front_edge(t, pts, tri, nbr, treg, acc) < 0:
        return
    _push(hkey, htri, fmeta, -ratio[t], t, tri)


@njit(cache=True)
def start(s, c, f, bg):
    """Accept the right-sized inside triangles and push the others that touch the front."""
    pts, tri, nbr, treg = s.pts, s.tri, s.nbr, c.treg
    acc, ratio, hkey, htri, fmeta, par = f.acc, f.ratio, f.hkey, f.htri, f.fmeta, f.par
    ntri = s.meta[M_NTRI]
    for t in range(ntri):
        if _inside(t, tri, treg):
            classify(t, pts, tri, acc, ratio, par, bg)
    for t in range(ntri):
        _push_if_front(t, pts, tri, nbr, treg, acc, ratio, hkey, htri, fmeta)


@njit(inline="always")
def _too_close(px, py, r, host, pts, tri, nbr, treg, stamp, fmeta, stack):
    """Whether a vertex lies within r of p: search the triangles the disc reaches from host."""
    fmeta[FM_STAMP] += 1
    mark = fmeta[FM_STAMP]
    r2 = r * r
    top = 1
    stack[0] = host
    stamp[host] = mark
    while top > 0:
        top -= 1
        t = stack[top]
        for m in range(3):
            v = tri[3 * t + m]
            if (pts[v, 0] - px) ** 2 + (pts[v, 1] - py) ** 2 < r2:
                return True
        for e in range(3):
            n = nbr[3 * t + e]
            if not _inside(n, tri, treg) or stamp[n] == mark:
                continue
            a = tri[3 * t + (e + 1) % 3]
            b = tri[3 * t + (e + 2) % 3]
            if segment_dist2(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], px, py) < r2:
                if top >= stack.shape[0]:
                    return True  # a disc this crowded is too close anyway
                stamp[n] = mark
                stack[top] = n
                top += 1
    return False


@njit(cache=True)
def run(s, c, f, bg):
    """Insert Rebay points, worst front triangle first, until the heap is empty.

    The bundles' fields are read once here and handed to the per-step helpers as arrays:
    a field read inside a loop costs a reference-count pair per iteration.
    """
    q = np.empty((1, 2))
    out = np.empty(1, dtype=np.int32)
    stack = np.empty(4096, dtype=np.int32)
    pts, tri, nbr, meta, treg, vtri = s.pts, s.tri, s.nbr, s.meta, c.treg, c.vtri
    acc, ratio, hkey, htri, stamp, fmeta, par = f.acc, f.ratio, f.hkey, f.htri, f.stamp, f.fmeta, f.par
    while fmeta[FM_HN] > 0:
        ntri = meta[M_NTRI]
        if (
            fmeta[FM_HN] + HEAP_ROOM > hkey.shape[0] or acc.shape[0] < 3 * (ntri + 2)
            or stamp.shape[0] < ntri + 2 or ratio.shape[0] < ntri + 2
        ):
            return F_ROOM
        if meta[M_NV] >= par[P_MAX_POINTS]:
            return F_POINTS
        t, a0, b0, c0 = htri[0, 0], htri[0, 1], htri[0, 2], htri[0, 3]
        heap_pop(hkey, htri, fmeta[FM_HN])
        fmeta[FM_HN] -= 1
        if t >= ntri or tri[3 * t] != a0 or tri[3 * t + 1] != b0 or tri[3 * t + 2] != c0:
            continue
        if not _inside(t, tri, treg) or _settled(t, tri, acc):
            continue
        e = _front_edge(t, pts, tri, nbr, treg, acc)
        if e < 0:
            continue
        rad = _radius(pts, tri, t)
        # Rebay's point on the perpendicular bisector of the front edge ab (module
        # docstring of frontal_delaunay), sized at the edge: a long waiting triangle's
        # circumcentre may lie where the size is far larger.
        a = tri[3 * t + (e + 1) % 3]
        b = tri[3 * t + (e + 2) % 3]
        h = _size(par, bg, 0.5 * (pts[a, 0] + pts[b, 0]), 0.5 * (pts[a, 1] + pts[b, 1]))
        blen = np.hypot(pts[b, 0] - pts[a, 0], pts[b, 1] - pts[a, 1])
        p = 0.5 * blen
        nx = -(pts[b, 1] - pts[a, 1]) / blen
        ny = (pts[b, 0] - pts[a, 0]) / blen
        rho = min(max(h / _SQRT3, p), rad)
        d = rho + np.sqrt(max(rho * rho - p * p, 0.0))
        px = 0.5 * (pts[a, 0] + pts[b, 0]) + d * nx
        py = 0.5 * (pts[a, 1] + pts[b, 1]) + d * ny
        host, _ = walk(s, t, px, py, False)
        if not _inside(host, tri, treg) or _too_close(px, py, par[P_SPACING] * h, host, pts, tri, nbr, treg, stamp,
                                                      fmeta, stack):
            # No room for a point: the triangle stays as it is and joins the accepted ones.
            for k in range(3):
                acc[3 * t + k] = tri[3 * t + k]
            for k in range(3):
                _push_if_front(nbr[3 * t + k], pts, tri, nbr, treg, acc, ratio, hkey, htri, fmeta)
            continue
        q[0, 0] = px
        q[0, 1] = py
        meta[M_LAST] = host
        _, code = enc.insert_points(q, 0, out, s, c)
        if code == enc.R_ROOM:
            _push(hkey, htri, fmeta, -ratio[t], t, tri)
            return F_ROOM
        if code != enc.R_DONE:
            return F_BROKEN
        v = out[0]
        if v < meta[M_NV] - 1:
            continue  # the point was already a vertex
        fmeta[FM_ADDED] += 1
        # The star of v: rotate across the edge v -> next around v.
        s0 = vtri[v]
        sl = s0
        for _ in range(1024):
            k = 0
            while tri[3 * sl + k] != v:
                k += 1
            if _inside(sl, tri, treg):
                classify(sl, pts, tri, acc, ratio, par, bg)
            sl = nbr[3 * sl + (k + 1) % 3]
            if sl == s0 or sl < 0:
                break
        sl = s0
        for _ in range(1024):
            k = 0
            while tri[3 * sl + k] != v:
                k += 1
            _push_if_front(sl, pts, tri, nbr, treg, acc, ratio, hkey, htri, fmeta)
            _push_if_front(nbr[3 * sl + k], pts, tri, nbr, treg, acc, ratio, hkey, htri, fmeta)
            sl = nbr[3 * sl + (k + 1) % 3]
            if sl == s0 or sl < 0:
                break
    return F_DONE
