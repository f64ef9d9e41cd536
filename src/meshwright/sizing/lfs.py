r"""Local feature size of a planar straight-line graph, graded and capped: the default size.

Source: J. Ruppert, "A Delaunay refinement algorithm for quality 2-dimensional mesh
generation", Journal of Algorithms 18(3):548-585, 1995, whose local feature size
``lfs(x)`` is the radius of the smallest disk centred at ``x`` meeting two non-incident
features (vertices or segments) of the PSLG; J. R. Shewchuk, "Delaunay refinement
algorithms for triangular mesh generation", Computational Geometry 22:21-74, 2002, who
sizes meshes by it.  The field built here, :func:`lfs_field`, is what
:func:`meshwright.triangulate` uses when no size is given:

* at every vertex ``v``: the distance to the nearest vertex or segment not incident to
  ``v``, an upper bound on ``lfs(v)`` (the disk through that feature meets two
  non-incident features, it and ``v``) and the usual estimate of it;
* along every segment ``s``: the distance to the nearest vertex or segment sharing no
  vertex with ``s``, sampled by bisection until consecutive samples are at most ``step``
  times the smaller of their two values apart (``lfs`` is 1-Lipschitz, so the samples
  resolve it within a factor ``1 - step / 2``), so that a long segment running close to
  another feature is split along its whole length, not only at its ends;
* sizes ``scale * lfs`` at those sources, graded into the domain by
  :func:`meshwright.sizing.boundary.gradation` (``|grad h| <= growth - 1``, Persson 2006)
  and capped by ``hmax``, by default ``cap`` times the graph's extent.

Zero distances (coincident vertices, a vertex lying on a segment) are not features of one
another here: the meshers merge such points, and a size must be positive.

Nearest-feature queries run in ``@njit`` kernels over a loose quadtree of boxes
(:mod:`meshwright.core.spatial.loose_quadtree`): a query box around the point doubles
until the nearest admissible feature found lies within it.  Long segments enter the tree
as pieces no longer than the mean segment length, so no query wades through every long
segment.  Array layout of the index (``P`` pieces, then the ``n`` vertices as degenerate
pieces)::

    pxy    (P + n, 4) float64  piece end points x0, y0, x1, y1
    owner  (P + n,) int64      segment of a piece, or -1 - v for vertex v
    qbox   (P + n, 4) float64  bounding box of each piece (the tree's items)
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from meshwright.core.errors import InputError, SizeError
from meshwright.core.spatial.loose_quadtree import Q_DEPTH, Q_NODES, STACK_PER_LEVEL, qt_insert, qt_new, qt_query
from meshwright.sizing.boundary import gradation
from meshwright.sizing.field import SizeField

__all__ = ["DEFAULT_CAP", "DEFAULT_GROWTH", "DEFAULT_SCALE", "lfs_field", "local_feature_size", "turning_size"]

# Chosen by measurement on Triangle's example files (benchmarks/README.md, issue 14): the
# one setting tried that kept every method within 3x Triangle's pq30 count at >= 20 degrees
# on every file but la.poly.
DEFAULT_SCALE = 1.25  # size = scale * lfs at the sources
DEFAULT_GROWTH = 1.2  # |grad h| <= 0.2
DEFAULT_CAP = 0.5  # largest size: this fraction of the graph's extent
DEFAULT_STEP = 0.5  # sample spacing along segments, as a fraction of the local lfs
_MAX_DEPTH = 60  # bisections of one segment: beyond them a piece is below float resolution
_STACK = 2 * _MAX_DEPTH + 4
_MAX_DOUBLINGS = 2200  # of a query box: from the smallest positive double past any extent


@nb.njit(cache=True)
def _build_index(pts, seg, piece_len, qgeo, qmeta, qchild, qhead):
    """The pieces and vertices as tree items (layout in the module docstring)."""
    m = seg.shape[0]
    n = pts.shape[0]
    count = np.empty(m, dtype=np.int64)
    total = 0
    for s in range(m):
        a = seg[s, 0]
        b = seg[s, 1]
        length = np.hypot(pts[b, 0] - pts[a, 0], pts[b, 1] - pts[a, 1])
        count[s] = max(1, int(np.ceil(length / piece_len)))
        total += count[s]
    items = total + n
    pxy = np.empty((items, 4))
    owner = np.empty(items, dtype=np.int64)
    k = 0
    for s in range(m):
        ax = pts[seg[s, 0], 0]
        ay = pts[seg[s, 0], 1]
        dx = pts[seg[s, 1], 0] - ax
        dy = pts[seg[s, 1], 1] - ay
        c = count[s]
        for j in range(c):
            pxy[k, 0] = ax + dx * (j / c)
            pxy[k, 1] = ay + dy * (j / c)
            pxy[k, 2] = ax + dx * ((j + 1) / c)
            pxy[k, 3] = ay + dy * ((j + 1) / c)
            owner[k] = s
            k += 1
    for v in range(n):
        pxy[k, 0] = pts[v, 0]
        pxy[k, 1] = pts[v, 1]
        pxy[k, 2] = pts[v, 0]
        pxy[k, 3] = pts[v, 1]
        owner[k] = -1 - v
        k += 1
    qbox = np.empty((items, 4))
    qnext = np.empty(items, dtype=np.int32)
    room = qmeta[Q_DEPTH] + 1
    for it in range(items):
        qbox[it, 0] = min(pxy[it, 0], pxy[it, 2])
        qbox[it, 1] = min(pxy[it, 1], pxy[it, 3])
        qbox[it, 2] = max(pxy[it, 0], pxy[it, 2])
        qbox[it, 3] = max(pxy[it, 1], pxy[it, 3])
        if qmeta[Q_NODES] + room > qhead.shape[0]:
            cap = 2 * qhead.shape[0] + room
            head = np.full(cap, -1, dtype=np.int32)
            head[: qhead.shape[0]] = qhead
            child = np.full(4 * cap, -1, dtype=np.int32)
            child[: qchild.shape[0]] = qchild
            qhead = head
            qchild = child
        qt_insert(it, qgeo, qmeta, qchild, qhead, qnext, qbox)
    return pxy, owner, qbox, qnext, qchild, qhead


@nb.njit(inline="always")
def _piece_distance(qx, qy, pxy, it):
    """Distance from (qx, qy) to piece ``it`` (a point when both ends coincide)."""
    x0 = pxy[it, 0]
    y0 = pxy[it, 1]
    dx = pxy[it, 2] - x0
    dy = pxy[it, 3] - y0
    ex = qx - x0
    ey = qy - y0
    len2 = dx * dx + dy * dy
    if len2 > 0.0:
        t = min(max((ex * dx + ey * dy) / len2, 0.0), 1.0)
        ex -= t * dx
        ey -= t * dy
    return np.sqrt(ex * ex + ey * ey)


@nb.njit(inline="always")
def _nearest(qx, qy, a, b, r, rmax, seg, pxy, owner, qgeo, qchild, qhead, qnext, qbox, alive, out, stack, fstack):
    """Distance from (qx, qy) to the nearest feature incident to neither vertex ``a`` nor
    ``b`` (a vertex query passes ``a == b``); inf when there is none within ``rmax``.

    The box of half-width ``r`` doubles until the best distance found is at most ``r``:
    every feature nearer than that meets the box, so the answer is exact."""
    best = np.inf
    for _ in range(_MAX_DOUBLINGS):
        k = qt_query(qx - r, qy - r, qx + r, qy + r, qgeo, qchild, qhead, qnext, qbox, alive, out, stack, fstack)
        for j in range(k):
            it = out[j]
            o = owner[it]
            if o >= 0:
                u = seg[o, 0]
                w = seg[o, 1]
                if u == a or u == b or w == a or w == b:
                    continue
            else:
                v = -1 - o
                if v == a or v == b:
                    continue
            d = _piece_distance(qx, qy, pxy, it)
            if 0.0 < d < best:
                best = d
        if best <= r or r > rmax:
            break
        r *= 2.0
    return best


@nb.njit(cache=True)
def _feature_sizes(
    pts, seg, depth, r_vertex, rmax, hcap, step, max_samples, pxy, owner, qgeo, qchild, qhead, qnext, qbox
):
    """Vertex lfs (n,) and the segment samples: (xy (k, 2), lfs (k,), k); k = -1 when
    more than ``max_samples`` samples would be needed."""
    n = pts.shape[0]
    items = qbox.shape[0]
    alive = np.ones(items, dtype=np.int8)
    out = np.empty(items, dtype=np.int64)
    rows = STACK_PER_LEVEL * (depth + 2)
    stack = np.empty(rows, dtype=np.int64)
    fstack = np.empty((rows, 3))
    vlfs = np.empty(n)
    for v in range(n):
        vlfs[v] = _nearest(
            pts[v, 0], pts[v, 1], v, v, r_vertex[v], rmax, seg, pxy, owner, qgeo, qchild, qhead, qnext, qbox,
            alive, out, stack, fstack,
        )
    cap = max(16, 2 * seg.shape[0])
    sxy = np.empty((cap, 2))
    slfs = np.empty(cap)
    k = 0
    st = np.empty((_STACK, 4))
    for s in range(seg.shape[0]):
        a = seg[s, 0]
        b = seg[s, 1]
        ax = pts[a, 0]
        ay = pts[a, 1]
        dx = pts[b, 0] - ax
        dy = pts[b, 1] - ay
        length = np.hypot(dx, dy)
        r0 = min(vlfs[a], vlfs[b], hcap)
        la = _nearest(
            ax, ay, a, b, r0, rmax, seg, pxy, owner, qgeo, qchild, qhead, qnext, qbox, alive, out, stack, fstack
        )
        lb = _nearest(
            ax + dx, ay + dy, a, b, r0, rmax, seg, pxy, owner, qgeo, qchild, qhead, qnext, qbox, alive, out, stack,
            fstack,
        )
        top = 1
        st[0, 0] = 0.0
        st[0, 1] = 1.0
        st[0, 2] = la
        st[0, 3] = lb
        while top > 0:
            top -= 1
            t0 = st[top, 0]
            t1 = st[top, 1]
            l0 = st[top, 2]
            l1 = st[top, 3]
            if (t1 - t0) * length <= step * min(l0, l1, hcap) or top + 2 > _STACK:
                continue
            tm = 0.5 * (t0 + t1)
            if tm <= t0 or tm >= t1:
                continue
            x = ax + dx * tm
            y = ay + dy * tm
            lm = _nearest(
                x, y, a, b, min(l0, l1, hcap), rmax, seg, pxy, owner, qgeo, qchild, qhead, qnext, qbox, alive, out,
                stack, fstack,
            )
            if k == max_samples:
                return vlfs, sxy, slfs, -1
            if k == sxy.shape[0]:
                grown_xy = np.empty((2 * k, 2))
                grown_xy[:k] = sxy
                grown_l = np.empty(2 * k)
                grown_l[:k] = slfs
                sxy = grown_xy
                slfs = grown_l
            sxy[k, 0] = x
            sxy[k, 1] = y
            slfs[k] = lm
            k += 1
            st[top, 0] = t0
            st[top, 1] = tm
            st[top, 2] = l0
            st[top, 3] = lm
            st[top + 1, 0] = tm
            st[top + 1, 1] = t1
            st[top + 1, 2] = lm
            st[top + 1, 3] = l1
            top += 2
    return vlfs, sxy[:k], slfs[:k], k


def _check_pslg(points, segments) -> tuple[np.ndarray, np.ndarray]:
    p = np.ascontiguousarray(np.asarray(points, dtype=np.float64))
    s = np.ascontiguousarray(np.asarray(segments, dtype=np.int64))
    if p.ndim != 2 or p.shape[1] != 2 or len(p) < 2:
        raise InputError(f"local feature size needs points of shape (n, 2) with n >= 2, got {p.shape}")
    if s.ndim != 2 or s.shape[1] != 2:
        raise InputError(f"segments must have shape (m, 2), got {s.shape}")
    bad = np.flatnonzero(~np.isfinite(p).all(axis=1))
    if len(bad):
        raise InputError(f"point {bad[0]} is not finite: {p[bad[0]].tolist()}")
    if len(s) and (s.min() < 0 or s.max() >= len(p)):
        i = int(np.flatnonzero((s < 0).any(axis=1) | (s >= len(p)).any(axis=1))[0])
        raise InputError(f"segment {i} = {s[i].tolist()} has a vertex index outside [0, {len(p)})")
    loops = np.flatnonzero(s[:, 0] == s[:, 1])
    if len(loops):
        raise InputError(f"segment {loops[0]} joins vertex {s[loops[0], 0]} to itself")
    return p, s


def local_feature_size(points, segments, *, hmax: float | None = None, step: float = DEFAULT_STEP,
                       max_samples: int = 10**7):
    """Local feature size at the vertices of a PSLG and at samples along its segments.

    Parameters
    ----------
    points : (n, 2) float64
        Vertices, ``n >= 2``; points on no segment are isolated vertex features.
    segments : (m, 2) int
        Vertex indices of the segments.
    hmax : float, optional
        Segments are sampled no finer than ``step * hmax`` where the lfs exceeds it
        (default: no such bound, the graph's extent).
    step : float
        Sample spacing along segments as a fraction of the smaller lfs of two neighbouring
        samples, in (0, 1].
    max_samples : int
        Cap on the segment samples; more raise :class:`SizeError`.

    Returns
    -------
    vertex_lfs : (n,) float64
        Distance from each vertex to the nearest vertex or segment not incident to it; inf
        where there is none (a graph of one segment).
    sample_xy : (k, 2) float64
        Points strictly inside the segments.
    sample_lfs : (k,) float64
        Distance from each sample to the nearest vertex or segment sharing no vertex with
        the sample's segment; inf where there is none.

    Raises
    ------
    InputError
        Malformed points or segments (the culprit named), or ``step`` outside (0, 1].
    SizeError
        More than ``max_samples`` samples needed (features far below the extent).
    """
    p, s = _check_pslg(points, segments)
    if not (isinstance(step, (int, float)) and 0.0 < step <= 1.0):
        raise InputError(f"step must lie in (0, 1], got {step!r}")
    lo, hi = p.min(axis=0), p.max(axis=0)
    extent = float(max(hi - lo))
    if extent <= 0.0:
        raise InputError("local feature size needs points that are not all coincident")
    hcap = extent if hmax is None else float(hmax)
    if not (math.isfinite(hcap) and hcap > 0.0):
        raise SizeError(f"hmax must be positive and finite, got {hmax!r}")
    lengths = np.hypot(*(p[s[:, 1]] - p[s[:, 0]]).T) if len(s) else np.zeros(0)
    piece_len = float(lengths.mean()) if len(s) and lengths.mean() > 0 else extent
    finest = float(lengths[lengths > 0].min()) if (lengths > 0).any() else piece_len
    qgeo, qmeta, qchild, qhead = qt_new((lo[0], lo[1], hi[0], hi[1]), 0.25 * finest, nodes=4 * (len(p) + len(s)) + 64)
    pxy, owner, qbox, qnext, qchild, qhead = _build_index(p, s, piece_len, qgeo, qmeta, qchild, qhead)
    # A vertex's first query box: its shortest segment, which bounds the answer unless a
    # nearer feature exists (then the box only has fewer items to look at).
    r_vertex = np.full(len(p), piece_len)
    if len(s):
        np.minimum.at(r_vertex, s.ravel(), np.repeat(lengths, 2))
    r_vertex = np.maximum(r_vertex, 1e-300)
    vlfs, sxy, slfs, k = _feature_sizes(
        p, s, int(qmeta[Q_DEPTH]), r_vertex, 4.0 * extent, hcap, float(step), int(max_samples), pxy, owner, qgeo,
        qchild, qhead, qnext, qbox,
    )
    if k < 0:
        raise SizeError(
            f"the local feature size needs more than {max_samples} samples along the {len(s)} segments "
            f"(extent {extent:.3g}): features are too close for their size; give a size"
        )
    return vlfs, sxy, slfs


def turning_size(xy, angle: float) -> np.ndarray:
    """Sizes resolving a curve's turning: ``angle`` radians of turn per element.

    Parameters
    ----------
    xy : (k, 2) float64
        A fine polyline along a smooth curve, ``k >= 3``.
    angle : float
        Turn per element, radians in (0, pi).

    Returns
    -------
    (k - 2,) float64
        At each interior vertex, ``angle`` times the radius of curvature estimated from the
        two chords meeting there (their mean length over the turn between them); inf where
        the polyline runs straight.
    """
    p = np.asarray(xy, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] != 2 or len(p) < 3:
        raise InputError(f"turning_size needs a polyline of shape (k, 2) with k >= 3, got {p.shape}")
    d = np.diff(p, axis=0)
    length = np.hypot(d[:, 0], d[:, 1])
    turn = np.abs(np.arctan2(d[:-1, 0] * d[1:, 1] - d[:-1, 1] * d[1:, 0], (d[:-1] * d[1:]).sum(axis=1)))
    mean = 0.5 * (length[:-1] + length[1:])
    with np.errstate(divide="ignore"):
        return np.where(turn > 0.0, angle * mean / np.where(turn > 0.0, turn, 1.0), np.inf)


def lfs_field(points, segments, *, scale: float = DEFAULT_SCALE, growth: float = DEFAULT_GROWTH,
              cap: float = DEFAULT_CAP, extra=None, max_samples: int = 10**7) -> SizeField:
    """The default size field of a PSLG: ``scale * lfs``, graded by ``growth``, capped.

    Parameters
    ----------
    points : (n, 2) float64
    segments : (m, 2) int
        The PSLG (see :func:`local_feature_size`).
    scale : float
        Size at a source per unit of local feature size, positive.
    growth : float
        ``g >= 1``: the size grows by at most ``g - 1`` per unit distance
        (:func:`meshwright.sizing.boundary.gradation`).
    cap : float
        Largest size as a fraction of the graph's extent (its bounding box's longer side),
        positive.
    extra : tuple of ((j, 2) float64, (j,) float64), optional
        More sources with their sizes (e.g. :func:`turning_size` along curves); infinite
        sizes are ignored.
    max_samples : int
        As for :func:`local_feature_size`.

    Returns
    -------
    SizeField
        ``h(x) = min(hmax, min_i (h_i + (g - 1) |x - x_i|))`` over the vertices, the
        segment samples and ``extra``, with ``h_i = scale * lfs_i`` and ``hmax = cap *
        extent``; where a source has no feature at all its size is ``hmax``.

    Raises
    ------
    InputError, SizeError
        As :func:`local_feature_size`; a non-positive ``scale`` or ``cap`` or a ``growth``
        below 1 (:class:`SizeError`), malformed ``extra`` (:class:`InputError`).
    """
    for name, v in (("scale", scale), ("cap", cap)):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not (math.isfinite(v) and v > 0.0):
            raise SizeError(f"{name} must be positive and finite, got {v!r}")
    if isinstance(growth, bool) or not isinstance(growth, (int, float)) or not (math.isfinite(growth) and growth >= 1):
        raise SizeError(f"growth must be a finite factor >= 1, got {growth!r}")
    p, s = _check_pslg(points, segments)
    extent = float(np.ptp(p, axis=0).max())
    hmax = cap * extent
    vlfs, sxy, slfs = local_feature_size(p, s, hmax=hmax / scale, max_samples=max_samples)
    src = [p, sxy]
    h = [scale * vlfs, scale * slfs]
    if extra is not None:
        exy = np.asarray(extra[0], dtype=np.float64).reshape(-1, 2)
        eh = np.asarray(extra[1], dtype=np.float64).ravel()
        if len(eh) != len(exy) or np.isnan(eh).any() or (eh <= 0).any() or not np.isfinite(exy).all():
            raise InputError(f"extra sources must be finite points (j, 2) with j positive sizes, got {exy.shape}, "
                             f"{eh.shape}")
        src.append(exy)
        h.append(eh)
    h = np.minimum(np.concatenate(h), hmax)
    return SizeField(
        gradation(np.concatenate(src), h, growth, hmax).func,
        name=f"local feature size (scale {scale:g}, growth {growth:g}, cap {cap:g} x extent)",
    )
