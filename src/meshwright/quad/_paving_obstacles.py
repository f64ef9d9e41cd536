"""Interior segments and points as obstacles of the paving rows (:mod:`meshwright.quad.paving`).

The domain's interior segments (their discretised pieces) and interior points are not
paved over: a row whose quads come closer to one than :data:`GAP` times the size at the
row's paving nodes is refused (its paving boundary stops there), no closure takes a
region holding one, and the void fill (:func:`~meshwright.quad._paving_close.fill_voids`)
triangulates the stopped paving boundaries together with the obstacles, so that the
pairing of 18.5.1 meets every segment piece as a quad edge and every point as a node.

Array layout: points (n, 2) float64; quads (q, 4) int64 counter-clockwise; obstacle
pieces as two (m,) int64 end arrays ``oa``, ``ob`` (a point is a piece with ``oa ==
ob``).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from meshwright.core.predicates import orient2d
from meshwright.quad._paving_grid import segments_meet

__all__ = ["GAP", "Obstacles", "quads_near"]

GAP = 1.0  # sizes: a row's quads keep at least this far from an interior segment or point


@njit
def _dist2(px, py, ax, ay, bx, by):
    """Squared distance from (px, py) to the closed segment (ax, ay) (bx, by)."""
    dx = bx - ax
    dy = by - ay
    ll = dx * dx + dy * dy
    t = 0.0
    if ll > 0.0:
        t = min(1.0, max(0.0, ((px - ax) * dx + (py - ay) * dy) / ll))
    ex = ax + t * dx - px
    ey = ay + t * dy - py
    return ex * ex + ey * ey


@njit(cache=True)
def quads_near(pts, quads, reach, oa, ob, touch_ok):
    """Which quads an obstacle piece meets or comes within ``reach`` of.

    Parameters
    ----------
    pts : (n, 2) float64
    quads : (q, 4) int64
        Counter-clockwise.
    reach : (q,) float64
        Clearance each quad must keep (0: only touching counts).
    oa, ob : (m,) int64
        Obstacle pieces; ``oa[j] == ob[j]`` is a point.
    touch_ok : bool
        A quad side sharing a node with a piece does not count as meeting it (the check
        of a finished paving, whose quads may end on a segment's node).

    Returns
    -------
    (q,) bool
        Meeting and containment exact (``orient2d``); the clearance in floating point,
        a quality rule.
    """
    nq = quads.shape[0]
    out = np.zeros(nq, dtype=np.bool_)
    m = oa.shape[0]
    if m == 0 or nq == 0:
        return out
    # Only pieces reaching the quads' box (grown by the largest reach) are candidates.
    x0 = np.inf
    x1 = -np.inf
    y0 = np.inf
    y1 = -np.inf
    far = 0.0
    for c in range(nq):
        far = max(far, reach[c])
        for e in range(4):
            v = quads[c, e]
            x0 = min(x0, pts[v, 0])
            x1 = max(x1, pts[v, 0])
            y0 = min(y0, pts[v, 1])
            y1 = max(y1, pts[v, 1])
    cand = np.empty(m, dtype=np.int64)
    mc = 0
    for j in range(m):
        a = oa[j]
        b = ob[j]
        if max(pts[a, 0], pts[b, 0]) < x0 - far or min(pts[a, 0], pts[b, 0]) > x1 + far:
            continue
        if max(pts[a, 1], pts[b, 1]) < y0 - far or min(pts[a, 1], pts[b, 1]) > y1 + far:
            continue
        cand[mc] = j
        mc += 1
    # The candidates sorted by their boxes' left ends: a quad scans only those starting
    # within its own box's x range (grown by its reach and the widest candidate box).
    lx = np.empty(mc, dtype=np.float64)
    wide = 0.0
    for i in range(mc):
        a = oa[cand[i]]
        b = ob[cand[i]]
        lx[i] = min(pts[a, 0], pts[b, 0])
        wide = max(wide, max(pts[a, 0], pts[b, 0]) - lx[i])
    by_x = np.argsort(lx)
    lx = lx[by_x]
    cand = cand[:mc][by_x]
    for c in range(nq):
        r = reach[c]
        r2 = r * r
        qx0 = np.inf
        qx1 = -np.inf
        qy0 = np.inf
        qy1 = -np.inf
        for e in range(4):
            v = quads[c, e]
            qx0 = min(qx0, pts[v, 0])
            qx1 = max(qx1, pts[v, 0])
            qy0 = min(qy0, pts[v, 1])
            qy1 = max(qy1, pts[v, 1])
        # The left bound with room for its own rounding: a start no later than exact.
        lo = qx0 - r - wide
        lo -= 1e-12 * (abs(lo) + abs(qx0) + wide)
        for i in range(np.searchsorted(lx, lo), np.searchsorted(lx, qx1 + r, side="right")):
            j = cand[i]
            a = oa[j]
            b = ob[j]
            if max(pts[a, 0], pts[b, 0]) < qx0 - r or min(pts[a, 0], pts[b, 0]) > qx1 + r:
                continue
            if max(pts[a, 1], pts[b, 1]) < qy0 - r or min(pts[a, 1], pts[b, 1]) > qy1 + r:
                continue
            hit = False
            inside = True
            for e in range(4):
                u = quads[c, e]
                v = quads[c, (e + 1) % 4]
                if orient2d(pts[u, 0], pts[u, 1], pts[v, 0], pts[v, 1], pts[a, 0], pts[a, 1]) <= 0.0:
                    inside = False
                if touch_ok and (u == a or u == b or v == a or v == b):
                    continue
                if segments_meet(pts, u, v, a, b):
                    hit = True
                    break
                if r > 0.0:
                    d = min(
                        _dist2(pts[a, 0], pts[a, 1], pts[u, 0], pts[u, 1], pts[v, 0], pts[v, 1]),
                        _dist2(pts[b, 0], pts[b, 1], pts[u, 0], pts[u, 1], pts[v, 0], pts[v, 1]),
                        _dist2(pts[u, 0], pts[u, 1], pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1]),
                        _dist2(pts[v, 0], pts[v, 1], pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1]),
                    )
                    if d < r2:
                        hit = True
                        break
            if hit or inside:
                out[c] = True
                break
    return out


@njit(cache=True)
def _any_inside(p, q):
    """Whether a point of ``q`` (m, 2) lies inside the closed polygon ``p`` (k, 2) by the
    crossing count of a ray to +x (a quality rule: probes lie off the polygon's edges)."""
    k = p.shape[0]
    for j in range(q.shape[0]):
        x = q[j, 0]
        y = q[j, 1]
        odd = False
        for i in range(k):
            x0 = p[i, 0]
            y0 = p[i, 1]
            x1 = p[(i + 1) % k, 0]
            y1 = p[(i + 1) % k, 1]
            if (y0 <= y) != (y1 <= y) and x0 + (y - y0) / (y1 - y0) * (x1 - x0) > x:
                odd = not odd
        if odd:
            return True
    return False


class Obstacles(NamedTuple):
    """The domain's interior segments and points, in the paving's node ids.

    Attributes
    ----------
    oa, ob : (m,) int64
        Segment pieces (the discretisation's), then one piece per interior point with
        both ends the point.
    seg_a, seg_b : (s,) int64
        The segment pieces alone (constraints of the void fill).
    points : (p,) int64
        The interior points' nodes.
    """

    oa: np.ndarray
    ob: np.ndarray
    seg_a: np.ndarray
    seg_b: np.ndarray
    points: np.ndarray

    @classmethod
    def of(cls, domain, disc) -> Obstacles | None:
        """The obstacles of ``domain`` discretised as ``disc`` (None when it has none).
        The interior points are the discretisation's last nodes."""
        inner = domain.curve_loop[disc.segment_curve] < 0
        n_free = len(domain.points)
        if not inner.any() and not n_free:
            return None
        seg = disc.segments[inner].astype(np.int64)
        pts = np.arange(len(disc.points) - n_free, len(disc.points), dtype=np.int64)
        return cls(
            np.concatenate([seg[:, 0], pts]), np.concatenate([seg[:, 1], pts]),
            np.ascontiguousarray(seg[:, 0]), np.ascontiguousarray(seg[:, 1]), pts,
        )

    def only(self, keep: np.ndarray) -> Obstacles | None:
        """These obstacles with the segment pieces ``keep`` (a (s,) bool mask) and every
        point; None when nothing is left."""
        if keep.all():
            return self
        if not keep.any() and not len(self.points):
            return None
        sa, sb = self.seg_a[keep], self.seg_b[keep]
        return Obstacles(
            np.concatenate([sa, self.points]), np.concatenate([sb, self.points]), sa, sb, self.points
        )

    def probes(self, xy: np.ndarray) -> np.ndarray:
        """(m, 2): one point of each piece (a segment piece's midpoint, a point itself):
        a region bounded by paving boundaries holds a piece exactly when it holds its
        probe, since no paving boundary crosses a piece and a piece meets one only at a
        node (a segment ending on a loop)."""
        return 0.5 * (xy[self.oa] + xy[self.ob])

    def inside(self, xy: np.ndarray, loop: np.ndarray) -> bool:
        """Whether the polygon ``loop`` (node ids, either orientation) holds an obstacle
        (crossing count of the probes in the loop's box)."""
        p = np.ascontiguousarray(xy[loop])
        q = self.probes(xy)
        q = np.ascontiguousarray(q[((q >= p.min(axis=0)) & (q <= p.max(axis=0))).all(axis=1)])
        return bool(len(q)) and _any_inside(p, q)

    def row_refused(self, pts: np.ndarray, quads: np.ndarray, h: np.ndarray, n_old: int) -> bool:
        """Whether a candidate row's quads (new nodes from ``n_old`` on) come closer to an
        obstacle than :data:`GAP` times the size ``h`` at their committed corners."""
        q = np.ascontiguousarray(quads, dtype=np.int64)
        reach = GAP * np.nanmax(np.where(q < n_old, h[q], np.nan), axis=1)
        return bool(quads_near(pts, q, reach, self.oa, self.ob, False).any())

    def covered(self, xy: np.ndarray, quads: np.ndarray) -> bool:
        """Whether a paved quad meets or holds an obstacle piece other than at a shared
        node (the last check before the void fill)."""
        q = np.ascontiguousarray(quads, dtype=np.int64)
        return bool(quads_near(xy, q, np.zeros(len(q)), self.oa, self.ob, True).any())
