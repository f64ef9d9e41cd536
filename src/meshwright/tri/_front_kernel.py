r"""Numba kernel of the 2-D advancing-front method (see :mod:`meshwright.tri.front`).

The kernel is resumable: all state lives in the arrays below and :func:`advance` returns
a code whenever Python must act (grow arrays, evaluate the size field at new nodes) and is
simply called again.

State: one :class:`FrontState` bundle (fields below, in order, passed whole to the kernel
functions; capacities grow by doubling in :mod:`meshwright.tri.front`) and the parameters
``par``::

    pts    (pcap, 2) float64   nodes; [0, meta[M_NIN]) are the input vertices
    met    (pcap, 3) float64   metric (m11, m12, m22) of each node: a vector v has length
                               sqrt(v^T M v) in units of the local element size
    vint   (pcap, 4) int32     per node: first out-face, first triangle slot (3 t + k),
                               free-point item (-1 none), query stamp
    face   (fcap, 4) int32     per face: start a, end b, next out-face of a, tries
    falive (fcap,) int8        1 while the face is on the front
    qbox   (fcap, 4) float64   the quadtree of split boxes (:mod:`meshwright.core.spatial.cell_quadtree`):
    qgeo, qmeta, qchild,       item boxes (item = face id), root geometry, header, children,
    qhead, qnext, qcell        node lists, entry links (4 fcap,) and items' integer corners
    hkey, hface (fcap, 1)      binary min-heap (:mod:`meshwright.core.heap`) of faces by key
                               (length, plus deferrals)
    wkey, wface                faces waiting for the metric of a new end (meta[M_NW] of them)
    tri    (tcap, 3) int32     triangles (a, b, c) counter-clockwise
    tnext  (tcap, 3) int32     next slot in the triangle list of the k-th vertex
    talive (tcap,) int8        0 once removed by a back-off
    meta   (M_LEN,) int64      counters (M_*)
    par    (P_LEN,) float64    parameters (P_*)

A face a -> b has the region still to be meshed on its left.  A *free point* (an input
vertex on no segment, or one orphaned by a back-off) is a degenerate item a == b in the
quadtree only, so every validity test sees it as a front node.

Validity of a new triangle (a, b, c) on face a -> b, every test exact (``orient2d``):
c strictly left of a -> b; the edges a c and c b meet no front face except at shared
endpoints; no front node lies in the closed triangle other than its corners.  The open
triangle then lies in the component of the unmeshed region left of a -> b, so triangles
never overlap, whatever the floating-point placement of the points.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from meshwright.core.borrowed import borrowed
from meshwright.core.heap import heap_pop as core_heap_pop
from meshwright.core.heap import heap_push as core_heap_push
from meshwright.core.spatial.cell_quadtree import (
    Q_DEPTH,
    Q_NODES,
    Q_ROOM,
    STACK_PER_LEVEL,
    ct_insert,
    ct_query,
)
from meshwright.tri._front_geometry import (
    _behind,
    _boxes_meet,
    _meets,
    _orient,
    _quality,
    _seg_dist2,
    _to_metric,
)

R_DONE = 0  # the front is empty
R_SYNC = 1  # nodes [meta[M_SYNC], meta[M_NP]) await their metric
R_ROOM = 2  # an array needs more room
R_STUCK = 3  # face meta[M_FAIL] cannot be advanced even after backing off
R_STEPS = 4  # the step cap was hit
R_POINTS = 5  # the node cap par[P_MAX_POINTS] was passed

M_NP, M_NF, M_NH, M_NT, M_STEPS, M_BACKOFF, M_SYNC, M_FAIL, M_NIN, M_STAMP, M_NW, M_LEN = range(12)
P_CLOSE, P_SEARCH, P_CLEAR_N, P_CLEAR_F, P_DEFER, P_SYNC_EVERY, P_MAX_BACKOFF, P_MAX_DEFER, P_QMIN, P_CLEAR_E, P_LONG, P_UNIFORM, P_MAX_POINTS, P_WAIT, P_LEN = range(15)

V_FACE, V_TRI, V_FREE, V_STAMP = range(4)
F_A, F_B, F_NEXT, F_TRIES = range(4)

ROOM_FACES = 512  # free face / heap slots required before each step (a back-off adds <= 3 * 96)
BACKOFF_TRIS = 32  # triangles removed per ring of a back-off
MAX_LEVEL = 3  # back-off rings before giving up on a face
SCRATCH = 256  # room of the scratch search arrays (a larger query replaces them)
WAIT_RATIO = 4.0  # par[P_WAIT] of a graded front: a ready face this many times longer than a waiting one waits too


class FrontState(NamedTuple):
    """The advancing front's arrays (layout in the module docstring), one kernel argument."""

    pts: np.ndarray
    met: np.ndarray
    vint: np.ndarray
    face: np.ndarray
    falive: np.ndarray
    qbox: np.ndarray
    qgeo: np.ndarray
    qmeta: np.ndarray
    qchild: np.ndarray
    qhead: np.ndarray
    qnext: np.ndarray
    qcell: np.ndarray
    hkey: np.ndarray
    hface: np.ndarray
    wkey: np.ndarray
    wface: np.ndarray
    tri: np.ndarray
    tnext: np.ndarray
    talive: np.ndarray
    meta: np.ndarray


# ------------------------------------------------------------------------------- heap
@njit(inline="always")
def heap_push(hkey, hface, meta, key, f):
    """Push face ``f`` with ``key`` on the heap of :mod:`meshwright.core.heap` (room checked by
    the caller)."""
    i = core_heap_push(hkey, hface, meta[M_NH], key)
    meta[M_NH] += 1
    hface[i, 0] = f


@njit(inline="always")
def _heap_pop(hkey, hface, meta):
    """Remove the shortest face; returns (key, face)."""
    top_key = hkey[0]
    top = hface[0, 0]
    core_heap_pop(hkey, hface, meta[M_NH])
    meta[M_NH] -= 1
    return top_key, top


@njit(inline="always")
def pop_ready(fs, wmin, ratio):
    """The shortest face whose ends have their metric, or -1 for none (Python must evaluate
    the size field if faces wait, ``meta[M_NW] > 0``); returns ``(f, key, wmin)``.

    A face with a new end waits (``wkey`` / ``wface``); ``wmin`` is the smallest waiting
    key so far in this kernel call (``inf`` at its start).  With ``ratio > 0``
    (``par[P_WAIT]``, :data:`WAIT_RATIO` where the caller grades a size jump; 0 keeps the
    earlier order) a ready face longer than ``ratio`` times it is pushed back and -1
    returned: advancing it first would lay
    a large triangle beside small faces still to advance (at a size jump, a node far out
    that the small faces then fan to, in slivers), as the shortest-first order forbids.
    """
    hkey, hface, wkey, wface, falive, face, meta = fs.hkey, fs.hface, fs.wkey, fs.wface, fs.falive, fs.face, fs.meta
    while meta[M_NH] > 0:
        key, f = _heap_pop(hkey, hface, meta)
        if falive[f]:
            if face[f, F_A] < meta[M_SYNC] and face[f, F_B] < meta[M_SYNC]:
                if ratio > 0.0 and key > ratio * wmin:
                    heap_push(hkey, hface, meta, key, f)
                    return -1, key, wmin
                return f, key, wmin
            wkey[meta[M_NW]] = key
            wface[meta[M_NW]] = f
            meta[M_NW] += 1
            wmin = min(wmin, key)
    return -1, 0.0, wmin


# ------------------------------------------------------------------------------- faces
@njit(inline="always")
def _find_face(u, v, vint, face, falive):
    """The live face u -> v, or -1; dead faces met in u's list are unlinked."""
    prev = -1
    f = vint[u, V_FACE]
    while f >= 0:
        nxt = face[f, F_NEXT]
        if falive[f] == 0:
            if prev < 0:
                vint[u, V_FACE] = nxt
            else:
                face[prev, F_NEXT] = nxt
        else:
            if face[f, F_B] == v:
                return f
            prev = f
        f = nxt
    return -1


@njit(inline="always")
def add_item(u, v, fs):
    """New quadtree item u -> v (a face, or a free point when u == v); returns its id."""
    pts, face, falive, qbox, qgeo, qmeta = fs.pts, fs.face, fs.falive, fs.qbox, fs.qgeo, fs.qmeta
    qchild, qhead, qnext, qcell, meta = fs.qchild, fs.qhead, fs.qnext, fs.qcell, fs.meta
    f = meta[M_NF]
    meta[M_NF] = f + 1
    face[f, F_A] = u
    face[f, F_B] = v
    face[f, F_NEXT] = -1
    face[f, F_TRIES] = 0
    falive[f] = 1
    qbox[f, 0] = min(pts[u, 0], pts[v, 0])
    qbox[f, 1] = min(pts[u, 1], pts[v, 1])
    qbox[f, 2] = max(pts[u, 0], pts[v, 0])
    qbox[f, 3] = max(pts[u, 1], pts[v, 1])
    ct_insert(f, qgeo, qmeta, qchild, qhead, qnext, qcell, qbox)
    return f


@njit(inline="always")
def _enter(f, fs):
    """Make item f (u -> v, u != v) a front face: u's out-list and the heap (key: its length)."""
    pts, vint, face, hkey, hface, meta = fs.pts, fs.vint, fs.face, fs.hkey, fs.hface, fs.meta
    u = face[f, F_A]
    v = face[f, F_B]
    face[f, F_NEXT] = vint[u, V_FACE]
    vint[u, V_FACE] = f
    heap_push(hkey, hface, meta, np.hypot(pts[v, 0] - pts[u, 0], pts[v, 1] - pts[u, 1]), f)


@njit(inline="always")
def add_face(u, v, fs):
    """New front face u -> v: quadtree, u's out-list and the heap (key: its length)."""
    f = add_item(u, v, fs)
    _enter(f, fs)
    return f


@njit(cache=True)
def seed_front(faces, free, fs):
    """The initial front: faces (k, 2) int32 ``u -> v`` (:func:`add_face`, in order) and free
    points (j,) int32 (:func:`add_item`); room for all of them is the caller's.  One call
    instead of one per face from Python, each of which unboxed the whole bundle.  One loop
    over both, so that the quadtree insertion is inlined once (issue 13, first-run compile)."""
    fs = borrowed(fs)
    nf = faces.shape[0]
    for i in range(nf + free.shape[0]):
        if i < nf:
            u = np.int64(faces[i, 0])
            v = np.int64(faces[i, 1])
        else:
            u = np.int64(free[i - nf])
            v = u
        g = add_item(u, v, fs)
        if i < nf:
            _enter(g, fs)
        else:
            fs.vint[v, V_FREE] = g


# ------------------------------------------------------------------------------- validity
@njit(inline="always")
def _valid(pts, face, qbox, a, b, c, f, items, ni, nodes, nn, clear, l11, l21, l22):
    """Triangle (a, b, c) on face f = a -> b may be added (module docstring).

    With ``clear > 0`` also every front node must keep the metric distance ``clear`` from
    the new sides a c and c b (a quality rule, not a validity one: a side grazing a node
    leaves a sliver to fill later).
    """
    if _orient(pts, a, b, c) <= 0.0:
        return False
    x0 = min(pts[a, 0], pts[b, 0], pts[c, 0])
    x1 = max(pts[a, 0], pts[b, 0], pts[c, 0])
    y0 = min(pts[a, 1], pts[b, 1], pts[c, 1])
    y1 = max(pts[a, 1], pts[b, 1], pts[c, 1])
    if clear > 0.0:
        cx = pts[c, 0]
        cy = pts[c, 1]
        sax, say = _to_metric(l11, l21, l22, pts[a, 0] - cx, pts[a, 1] - cy)
        sbx, sby = _to_metric(l11, l21, l22, pts[b, 0] - cx, pts[b, 1] - cy)
        clear2 = clear * clear
        for i in range(nn):
            v = nodes[i]
            if v == c:
                continue
            vx, vy = _to_metric(l11, l21, l22, pts[v, 0] - cx, pts[v, 1] - cy)
            if _seg_dist2(sax - vx, say - vy, -vx, -vy) < clear2 or _seg_dist2(sbx - vx, sby - vy, -vx, -vy) < clear2:
                return False
    for i in range(ni):
        g = items[i]
        r = face[g, F_A]
        s = face[g, F_B]
        if g == f or r == s:
            continue
        if qbox[g, 2] < x0 or qbox[g, 0] > x1 or qbox[g, 3] < y0 or qbox[g, 1] > y1:
            continue
        # A side whose closed box misses the face's cannot meet it: most faces of the
        # triangle's box lie beside one of its two new sides, so their exact tests are skipped.
        if _boxes_meet(pts, qbox, g, a, c) and _meets(pts, a, c, r, s):
            return False
        if _boxes_meet(pts, qbox, g, c, b) and _meets(pts, c, b, r, s):
            return False
    for i in range(nn):
        v = nodes[i]
        if v == c or pts[v, 0] < x0 or pts[v, 0] > x1 or pts[v, 1] < y0 or pts[v, 1] > y1:
            continue
        if _orient(pts, a, b, v) >= 0.0 and _orient(pts, b, c, v) >= 0.0 and _orient(pts, c, a, v) >= 0.0:
            return False
    return True



# ------------------------------------------------------------------------------- steps
@njit(inline="always")
def _make_triangle(f, a, b, c, fs, uniform):
    """Add triangle (a, b, c) on face f = a -> b and update the front (module docstring)."""
    met, vint, face, falive, tri, tnext = fs.met, fs.vint, fs.face, fs.falive, fs.tri, fs.tnext
    talive, meta = fs.talive, fs.meta
    if c == meta[M_NP]:
        meta[M_NP] = c + 1
        for k in range(3):
            met[c, k] = met[a, k]
        if uniform:
            meta[M_SYNC] = c + 1
        vint[c, V_FACE] = -1
        vint[c, V_TRI] = -1
        vint[c, V_FREE] = -1
        vint[c, V_STAMP] = -1
    t = meta[M_NT]
    meta[M_NT] = t + 1
    tri[t, 0] = a
    tri[t, 1] = b
    tri[t, 2] = c
    talive[t] = 1
    for k in range(3):
        v = tri[t, k]
        tnext[t, k] = vint[v, V_TRI]
        vint[v, V_TRI] = 3 * t + k
    falive[f] = 0
    if vint[c, V_FREE] >= 0:
        falive[vint[c, V_FREE]] = 0
        vint[c, V_FREE] = -1
    # Edge b -> c (and c -> a) of the new triangle fills the front face of the same
    # direction if there is one; otherwise its reverse joins the front:
    #
    #            c                    c
    #           / \                  ^ \
    #          /   \     ->         /   v      new faces a -> c, c -> b
    #         a --> b              a     b     (face a -> b is gone)
    for e in range(2):
        u = b if e == 0 else c
        v = c if e == 0 else a
        g = _find_face(u, v, vint, face, falive)
        if g >= 0:
            falive[g] = 0
        else:
            add_face(v, u, fs)


@njit(cache=True)
def _has_live_face(v, vint, face, falive):
    """Whether v starts a live face (looking for a face to no vertex unlinks the dead)."""
    _find_face(v, -2, vint, face, falive)
    return vint[v, V_FACE] >= 0


@njit(cache=True)
def _has_live_triangle(v, vint, tnext, talive):
    slot = vint[v, V_TRI]
    prev = -1
    while slot >= 0:
        t = slot // 3
        nxt = tnext[t, slot % 3]
        if talive[t]:
            return True
        # Unlink removed triangles from v's list.
        if prev < 0:
            vint[v, V_TRI] = nxt
        else:
            tnext[prev // 3, prev % 3] = nxt
        slot = nxt
    return False


@njit(cache=True)
def _backoff(f, level, fs, tbuf, vbuf):
    """Remove the triangles within ``level`` rings of face f's ends; reopen their faces.

    The removed triangles become unmeshed: each of their edges u -> v cancels the front
    face v -> u when the other side is unmeshed too, and otherwise joins the front.
    Input vertices left with no triangle and no face become free points; orphaned
    generated nodes simply drop out of the front (they are not in the output).
    """
    vint, face, falive, tri, tnext, talive = fs.vint, fs.face, fs.falive, fs.tri, fs.tnext, fs.talive
    meta = fs.meta
    meta[M_STAMP] += 1
    stamp = meta[M_STAMP]
    nv = 2
    vbuf[0] = face[f, F_A]
    vbuf[1] = face[f, F_B]
    vint[vbuf[0], V_STAMP] = stamp
    vint[vbuf[1], V_STAMP] = stamp
    nt = 0
    lo = 0
    cap = min(tbuf.shape[0], BACKOFF_TRIS * level)
    for _ in range(level):
        hi = nv
        for i in range(lo, hi):
            v = vbuf[i]
            slot = vint[v, V_TRI]
            while slot >= 0 and nt < cap:
                t = slot // 3
                if talive[t]:
                    talive[t] = 0
                    tbuf[nt] = t
                    nt += 1
                    for k in range(3):
                        w = tri[t, k]
                        if vint[w, V_STAMP] != stamp and nv < vbuf.shape[0]:
                            vint[w, V_STAMP] = stamp
                            vbuf[nv] = w
                            nv += 1
                slot = tnext[t, slot % 3]
        lo = hi
    # The removed triangles' edges, then the orphaned input vertices, in one loop: one
    # inlined quadtree insertion for faces and free points (issue 13, first-run compile).
    for j in range(3 * nt + nv):
        if j < 3 * nt:
            t = tbuf[j // 3]
            u = np.int64(tri[t, j % 3])
            v = np.int64(tri[t, (j % 3 + 1) % 3])
            g = _find_face(v, u, vint, face, falive)
            if g >= 0:
                falive[g] = 0
                continue
        else:
            v = np.int64(vbuf[j - 3 * nt])
            u = v
            if v >= meta[M_NIN] or vint[v, V_FREE] >= 0 or _has_live_triangle(v, vint, tnext, talive):
                continue
            if _has_live_face(v, vint, face, falive):
                continue
        g = add_item(u, v, fs)
        if u != v:
            _enter(g, fs)
        else:
            vint[v, V_FREE] = g
    return nt


@njit(inline="always")
def _gather(a, b, fid, p, o, wide, grow, fs, par, col, want, items, nodes, cand, ckey, stack, fstack):
    """Candidate apexes of a triangle on face a -> b (step 5 of 18.2), shared by this
    front (:func:`_try_face`) and Zhu's pair front (:mod:`meshwright.quad._zhu_kernel`).

    The ideal point is written at ``pts[p]``: the equilateral apex of unit metric size
    (``o == -1``, Peraire et al. 1987; its sides kept within [0.55, 2] face lengths so the
    element neither collapses nor jumps in size), a square's corner above b (-2), or the
    parallelogram's fourth corner across a b from node ``o``.  ``fid`` is the face's id, -1
    for a virtual face.  ``wide``: a face's last try, whose box reaches four times as far;
    ``grow`` (the triangle front's last try): the box then grows to the far ends of the
    faces it meets.  With ``want >= 0`` only nodes of colour ``want`` in ``col`` (int8),
    or uncoloured (-1), are candidates; every node still counts for validity and
    clearance.  The triangle front passes ``want = -1`` and an empty ``col``.

    Returns ``(ni, nn, nc, n_close, p_ok, rho, l11, l21, l22, u0, u1, items, nodes, cand,
    ckey)``: query items and nodes, candidates (``n_close`` close ones first, nearest
    first; the others best triangle first; equal keys by node id), whether the ideal point
    keeps its clearances, the metric's Cholesky factor and the base in it; the scratch
    arrays come back because they may have been replaced by larger ones.
    """
    pts, met, vint, face, falive, qbox, qgeo = fs.pts, fs.met, fs.vint, fs.face, fs.falive, fs.qbox, fs.qgeo
    qmeta, qchild, qhead, qnext, qcell, meta = fs.qmeta, fs.qchild, fs.qhead, fs.qnext, fs.qcell, fs.meta
    m11 = 0.5 * (met[a, 0] + met[b, 0])
    m12 = 0.5 * (met[a, 1] + met[b, 1])
    m22 = 0.5 * (met[a, 2] + met[b, 2])
    l11 = np.sqrt(m11)
    l21 = m12 / l11
    l22 = np.sqrt(max(m22 - l21 * l21, 1e-12 * m22))
    ax = pts[a, 0]
    ay = pts[a, 1]
    bx = pts[b, 0]
    by = pts[b, 1]
    u0, u1 = _to_metric(l11, l21, l22, bx - ax, by - ay)
    ln = np.hypot(u0, u1)
    rho = min(max(1.0, 0.55 * ln), 2.0 * ln)
    if o >= 0:
        # The quad's fourth corner: a parallelogram with the first triangle.
        px = ax + bx - pts[o, 0]
        py = ay + by - pts[o, 1]
    else:
        # o == -1: the triangle front's equilateral apex; -2: a square's corner above b.
        hgt = rho if o == -2 else np.sqrt(max(rho * rho - 0.25 * ln * ln, 0.0))
        w0 = -u1 / ln * hgt
        w1 = u0 / ln * hgt
        oy = w1 / l22
        ox = (w0 - l21 * oy) / l11
        px = (bx if o == -2 else 0.5 * (ax + bx)) + ox
        py = (by if o == -2 else 0.5 * (ay + by)) + oy
    pts[p, 0] = px
    pts[p, 1] = py
    # Search box: the metric disc of radius SEARCH rho about the apex, and the face.
    det = m11 * m22 - m12 * m12
    rad = par[P_SEARCH] * (4.0 * max(rho, 1.0) if wide else rho)
    wx = rad * np.sqrt(m22 / det)
    wy = rad * np.sqrt(m11 / det)
    x0 = min(px - wx, ax, bx)
    x1 = max(px + wx, ax, bx)
    y0 = min(py - wy, ay, by)
    y1 = max(py + wy, ay, by)
    # One inlined copy of the query for every round and the retry with a larger ``items``
    # (each copy is typed and lowered again in every kernel that inlines this one: issue 13).
    # A retry asks the same box again and finds the same ni, so it fits: at most two
    # queries per round.
    rnd = 0
    ni = 0
    for _ in range(4 if grow else 2):
        ni = ct_query(x0, y0, x1, y1, qgeo, qmeta, qchild, qhead, qnext, qcell, qbox, falive, items, stack, fstack)
        if ni > items.shape[0]:
            items = np.empty(2 * ni, dtype=np.int32)
            continue
        if not grow or rnd == 1:
            break
        rnd = 1
        # A gap narrower than the spacing, or a front loop of three faces, closes with
        # nodes however far they lie (the pair front does not grow: a colour-restricted
        # face took far nodes there).
        for i in range(ni):
            g = items[i]
            for v in (face[g, F_A], face[g, F_B]):
                x0 = min(x0, pts[v, 0])
                x1 = max(x1, pts[v, 0])
                y0 = min(y0, pts[v, 1])
                y1 = max(y1, pts[v, 1])
    meta[M_STAMP] += 1
    stamp = meta[M_STAMP]
    vint[a, V_STAMP] = stamp
    vint[b, V_STAMP] = stamp
    nn = 0
    p_ok = True
    clear_f = par[P_CLEAR_F] * rho
    clear_n = par[P_CLEAR_N] * rho
    # A node or face behind the face (a sharp corner at a or b puts its neighbours there)
    # is reached from the new point only around a or b: its distance is at least the
    # shorter of p a and p b (rho for the equilateral apex), not its straight distance.
    # A virtual face (fid -1, the pair front's diagonal) hides nothing: the triangle across
    # it is not meshed yet.
    pax, pay = _to_metric(l11, l21, l22, ax - px, ay - py)
    pbx, pby = _to_metric(l11, l21, l22, bx - px, by - py)
    around2 = min(pax * pax + pay * pay, pbx * pbx + pby * pby) if fid >= 0 else 0.0
    if nodes.shape[0] < 2 * ni:
        nodes = np.empty(2 * ni, dtype=np.int32)
    for i in range(ni):
        g = items[i]
        r = np.int64(face[g, F_A])
        s = np.int64(face[g, F_B])
        for v in (r, s):
            if vint[v, V_STAMP] != stamp:
                vint[v, V_STAMP] = stamp
                nodes[nn] = v
                nn += 1
        # The face's own twin (the other side of an interior segment) lies on the face:
        # its distance is the ideal point's height, not a clearance to keep.
        if g != fid and r != s and p_ok and not (r == b and s == a):
            rx, ry = _to_metric(l11, l21, l22, pts[r, 0] - px, pts[r, 1] - py)
            sx, sy = _to_metric(l11, l21, l22, pts[s, 0] - px, pts[s, 1] - py)
            if _seg_dist2(rx, ry, sx, sy) < clear_f * clear_f and not (
                around2 >= clear_f * clear_f
                and (r == a or r == b or _behind(pts, a, b, p, r))
                and (s == a or s == b or _behind(pts, a, b, p, s))
            ):
                p_ok = False
    if cand.shape[0] < nn:
        cand = np.empty(2 * nn, dtype=np.int32)
        ckey = np.empty(2 * nn)
    nc = 0
    close = par[P_CLOSE] * rho
    for i in range(nn):
        v = nodes[i]
        dx, dy = _to_metric(l11, l21, l22, pts[v, 0] - px, pts[v, 1] - py)
        d2 = dx * dx + dy * dy
        if d2 < clear_n * clear_n and not (around2 >= clear_n * clear_n and _behind(pts, a, b, p, v)):
            p_ok = False
        if want >= 0 and col[v] >= 0 and col[v] != want:
            continue
        # A candidate outside the search box would make a triangle reaching faces the
        # query did not return.
        inbox = x0 <= pts[v, 0] <= x1 and y0 <= pts[v, 1] <= y1
        if inbox and _orient(pts, a, b, v) > 0.0:
            # Nodes near the apex come first, nearest first (keys < 1); the others after
            # the new point, best triangle first (keys 2 - quality, in (1, 2]).
            if d2 < close * close:
                key = np.sqrt(d2) / close
            else:
                qx, qy = _to_metric(l11, l21, l22, pts[v, 0] - ax, pts[v, 1] - ay)
                key = 2.0 - _quality(0.0, 0.0, u0, u1, qx, qy)
            # Equal keys (mirror-image nodes) go by node id, so the choice does not depend
            # on the order in which the quadtree returns the faces.
            j = nc
            while j > 0 and (ckey[j - 1] > key or (ckey[j - 1] == key and cand[j - 1] > v)):
                cand[j] = cand[j - 1]
                ckey[j] = ckey[j - 1]
                j -= 1
            cand[j] = v
            ckey[j] = key
            nc += 1
    n_close = 0
    while n_close < nc and ckey[n_close] < 1.0:
        n_close += 1
    return ni, nn, nc, n_close, p_ok, rho, l11, l21, l22, u0, u1, items, nodes, cand, ckey


@njit(inline="always")
def _try_face(f, fs, par, nocol, items, nodes, cand, ckey, stack, fstack):
    """Advance face f by one triangle if any valid apex exists (``nocol``: an empty int8
    array, :func:`_gather`'s colours, which this front does not use).

    Returns ``(ok, items, nodes, cand, ckey)``: the scratch arrays come back because they
    may have been replaced by larger ones.
    """
    pts, face, qbox = fs.pts, fs.face, fs.qbox
    a = np.int64(face[f, F_A])
    b = np.int64(face[f, F_B])
    p = fs.meta[M_NP]
    # A face on its last try before backing off searches four times as far, and at least
    # four element sizes (a short face in a narrow gap needs its far neighbours).
    last = face[f, F_TRIES] >= par[P_MAX_DEFER]
    ni, nn, nc, n_close, p_ok, rho, l11, l21, l22, u0, u1, items, nodes, cand, ckey = _gather(
        a, b, f, p, -1, last, last, fs, par, nocol, -1, items, nodes, cand, ckey, stack, fstack
    )
    ax = pts[a, 0]
    ay = pts[a, 1]
    qmin = par[P_QMIN]
    longest = par[P_LONG] * rho
    # The first round keeps nodes clear of the new sides; the second, on a face's last try
    # before backing off, only asks validity.
    rounds = 2 if last else 1
    for i in range(rounds * (nc + n_close + 1)):
        clear = par[P_CLEAR_E] * rho if i < nc + n_close + 1 else 0.0
        i = i % (nc + n_close + 1)
        # Order of trial: close nodes making a good, not over-long triangle, the new
        # point, then every node in list order (close ones nearest first, the others best
        # triangle first).
        if i < n_close:
            c = np.int64(cand[i])
            qx, qy = _to_metric(l11, l21, l22, pts[c, 0] - ax, pts[c, 1] - ay)
            long2 = longest * longest
            if _quality(0.0, 0.0, u0, u1, qx, qy) < qmin or max(qx * qx + qy * qy, (qx - u0) ** 2 + (qy - u1) ** 2) > long2:
                continue
        elif i == n_close:
            if not p_ok:
                continue
            c = p
        else:
            c = np.int64(cand[i - n_close - 1])
        if _valid(pts, face, qbox, a, b, c, f, items, ni, nodes, nn, clear, l11, l21, l22):
            _make_triangle(f, a, b, c, fs, par[P_UNIFORM] != 0.0)
            return True, items, nodes, cand, ckey
    return False, items, nodes, cand, ckey


def new_scratch(depth, size=SCRATCH):
    """The kernel's scratch arrays, made by the caller and kept between calls (see
    :func:`advance`).

    Parameters
    ----------
    depth : int
        The front's quadtree depth (``fs.qmeta[Q_DEPTH]``).
    size : int
        Room for query items, nodes and candidates.

    Returns
    -------
    tuple
        ``(items, nodes, cand, ckey, stack, fstack, tbuf, vbuf, nocol)``: (size,) int32 /
        int32 / int32 / float64 for the candidate search, the quadtree query's stacks (s,)
        int64 and (s, 3) float64 with s = STACK_PER_LEVEL (depth + 2), the back-off's
        triangle and node buffers, and the empty int8 colours of :func:`_gather`.
    """
    s = STACK_PER_LEVEL * (int(depth) + 2)
    return (
        np.empty(size, np.int32), np.empty(size, np.int32), np.empty(size, np.int32), np.empty(size),
        np.empty(s, np.int64), np.empty((s, 3)), np.empty(BACKOFF_TRIS * MAX_LEVEL, np.int32),
        np.empty(3 * BACKOFF_TRIS * MAX_LEVEL + 2, np.int32), np.empty(0, np.int8),
    )


@njit(cache=True)
def advance(fs, par, scratch):
    """Run the front until it is empty or Python must act; returns an ``R_*`` code.

    A face with an end whose metric is not known yet (a node made since the last
    evaluation of the size field) waits; when only waiting faces are left, or enough nodes
    are new, Python evaluates the field (``R_SYNC``) and the waiting faces return.

    ``scratch`` is :func:`new_scratch`'s tuple, the caller's and borrowed like ``fs``: an
    array the kernel allocated would cost a reference-count pair (two atomic operations)
    at every inlined helper it passes through, in every step (15 % of the run's samples
    on pairing's disk).  A search array a query outgrows is replaced by a larger one of the
    kernel's for the rest of the call.
    """
    fs, par, scratch = borrowed(fs), borrowed(par), borrowed(scratch)
    pts, face, falive, qmeta, qhead, hkey = fs.pts, fs.face, fs.falive, fs.qmeta, fs.qhead, fs.hkey
    hface, wkey, wface, tri, meta = fs.hface, fs.wkey, fs.wface, fs.tri, fs.meta
    for i in range(meta[M_NW]):
        if falive[wface[i]]:
            heap_push(hkey, hface, meta, wkey[i], wface[i])
    meta[M_NW] = 0
    wmin = np.inf
    items, nodes, cand, ckey, stack, fstack, tbuf, vbuf, nocol = scratch
    depth = qmeta[Q_DEPTH]
    node_room = qmeta[Q_ROOM]
    if stack.shape[0] < STACK_PER_LEVEL * (depth + 2) or fstack.shape[0] < STACK_PER_LEVEL * (depth + 2):
        stack = np.empty(STACK_PER_LEVEL * (depth + 2), dtype=np.int64)
        fstack = np.empty((STACK_PER_LEVEL * (depth + 2), 3))
    sync_every = int(par[P_SYNC_EVERY])
    max_defer = int(par[P_MAX_DEFER])
    while True:
        if (
            meta[M_NP] + 2 > pts.shape[0]
            or meta[M_NF] + ROOM_FACES > face.shape[0]
            or meta[M_NH] + ROOM_FACES > hkey.shape[0]
            or meta[M_NW] + 2 > wface.shape[0]
            or meta[M_NT] + 2 > tri.shape[0]
            # (node_room + 1: as the pair front's kernel asks, so one growth serves both)
            or qmeta[Q_NODES] + ROOM_FACES * (node_room + 1) > qhead.shape[0]
        ):
            return R_ROOM
        if meta[M_NP] - meta[M_SYNC] >= sync_every:
            return R_SYNC
        if meta[M_NP] > par[P_MAX_POINTS]:
            return R_POINTS
        if meta[M_STEPS] > 16 * meta[M_NF] + 100_000:
            return R_STEPS
        f, key, wmin = pop_ready(fs, wmin, par[P_WAIT])
        if f < 0:
            return R_SYNC if meta[M_NW] > 0 else R_DONE
        meta[M_STEPS] += 1
        ok, items, nodes, cand, ckey = _try_face(f, fs, par, nocol, items, nodes, cand, ckey, stack, fstack)
        if ok:
            continue
        tries = face[f, F_TRIES] + 1
        face[f, F_TRIES] = tries
        if tries <= max_defer:
            # Postponed behind every ordinary face: the front around it moves on first.
            key += par[P_DEFER]
        else:
            level = tries - max_defer
            if level > MAX_LEVEL or meta[M_BACKOFF] >= par[P_MAX_BACKOFF]:
                meta[M_FAIL] = f
                return R_STUCK
            meta[M_BACKOFF] += 1
            _backoff(f, level, fs, tbuf, vbuf)
            if not falive[f]:
                continue
            key = np.hypot(pts[face[f, F_B], 0] - pts[face[f, F_A], 0], pts[face[f, F_B], 1] - pts[face[f, F_A], 1])
        # One inlined heap push for both (issue 13, first-run compile).
        heap_push(hkey, hface, meta, key, f)
