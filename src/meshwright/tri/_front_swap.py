r"""Clean-up of the finished advancing-front mesh (:mod:`meshwright.tri.front`, step 10):
diagonal swapping measured in the metric (Löhner and Parikh 1988).

A module of its own so that the front's kernel (:mod:`meshwright.tri._front_kernel`) stays
within the project's file size; it takes only the kernel's exact orientation and metric
transform, and runs once per mesh after the front has closed.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.tri._front_kernel import _orient, _to_metric


@njit(inline="always")
def _min_angle(ax, ay, bx, by, cx, cy):
    """Smallest angle (radians) of a triangle given in the metric space."""
    out = np.pi
    for k in range(3):
        if k == 0:
            ux, uy, vx, vy = bx - ax, by - ay, cx - ax, cy - ay
        elif k == 1:
            ux, uy, vx, vy = cx - bx, cy - by, ax - bx, ay - by
        else:
            ux, uy, vx, vy = ax - cx, ay - cy, bx - cx, by - cy
        out = min(out, np.arctan2(abs(ux * vy - uy * vx), ux * vx + uy * vy))
    return out


@njit(cache=True)
def swap_edges(pts, met, tri, nbr, locked, max_passes, gain):
    """Diagonal swapping of the finished mesh (Löhner and Parikh 1988's clean-up step).

    An interior edge not ``locked`` (input segments) is swapped when the two triangles on it
    form a strictly convex quadrilateral (exact ``orient2d``) and the swap raises their
    smallest angle, measured in the mean metric of the four nodes, by more than ``gain``
    radians; every swap raises the pair's smallest angle, so passes end, and at most
    ``max_passes`` run.  ``tri`` (t, 3) int32 counter-clockwise, ``nbr`` (t, 3) int32 the
    triangle across the edge opposite each corner (-1: none), ``locked`` (t, 3) int8 per
    edge likewise; all three are updated in place.  Returns the number of swaps.
    """
    nt = tri.shape[0]
    total = 0
    for _ in range(max_passes):
        swaps = 0
        for t in range(nt):
            for k in range(3):
                u = nbr[t, k]
                if u < 0 or locked[t, k]:
                    continue
                c = tri[t, k]
                a = tri[t, (k + 1) % 3]
                b = tri[t, (k + 2) % 3]
                j = 0
                while j < 2 and nbr[u, j] != t:
                    j += 1
                d = tri[u, j]
                if _orient(pts, c, a, d) <= 0.0 or _orient(pts, d, b, c) <= 0.0:
                    continue
                m11 = 0.25 * (met[a, 0] + met[b, 0] + met[c, 0] + met[d, 0])
                m12 = 0.25 * (met[a, 1] + met[b, 1] + met[c, 1] + met[d, 1])
                m22 = 0.25 * (met[a, 2] + met[b, 2] + met[c, 2] + met[d, 2])
                l11 = np.sqrt(m11)
                l21 = m12 / l11
                l22 = np.sqrt(max(m22 - l21 * l21, 1e-12 * m22))
                ax, ay = 0.0, 0.0
                bx, by = _to_metric(l11, l21, l22, pts[b, 0] - pts[a, 0], pts[b, 1] - pts[a, 1])
                cx, cy = _to_metric(l11, l21, l22, pts[c, 0] - pts[a, 0], pts[c, 1] - pts[a, 1])
                dx, dy = _to_metric(l11, l21, l22, pts[d, 0] - pts[a, 0], pts[d, 1] - pts[a, 1])
                old = min(_min_angle(cx, cy, ax, ay, bx, by), _min_angle(dx, dy, bx, by, ax, ay))
                new = min(_min_angle(cx, cy, ax, ay, dx, dy), _min_angle(dx, dy, bx, by, cx, cy))
                if new <= old + gain:
                    continue
                # t = (c, a, b) and u = (d, b, a) become t = (c, a, d) and u = (d, b, c);
                # ta, tb, ua, ub lie across (b, c), (c, a), (a, d), (d, b).
                ta = nbr[t, (k + 1) % 3]
                tb = nbr[t, (k + 2) % 3]
                ua = nbr[u, (j + 1) % 3]
                ub = nbr[u, (j + 2) % 3]
                la = locked[t, (k + 1) % 3]
                lb = locked[t, (k + 2) % 3]
                lua = locked[u, (j + 1) % 3]
                lub = locked[u, (j + 2) % 3]
                tri[t, 0], tri[t, 1], tri[t, 2] = c, a, d
                nbr[t, 0], nbr[t, 1], nbr[t, 2] = ua, u, tb
                locked[t, 0], locked[t, 1], locked[t, 2] = lua, 0, lb
                tri[u, 0], tri[u, 1], tri[u, 2] = d, b, c
                nbr[u, 0], nbr[u, 1], nbr[u, 2] = ta, t, ub
                locked[u, 0], locked[u, 1], locked[u, 2] = la, 0, lub
                # Across (a, d) the neighbour now sees t, across (b, c) it sees u.
                if ua >= 0:
                    for q in range(3):
                        if nbr[ua, q] == u:
                            nbr[ua, q] = t
                if ta >= 0:
                    for q in range(3):
                        if nbr[ta, q] == t:
                            nbr[ta, q] = u
                swaps += 1
        total += swaps
        if swaps == 0:
            break
    return total
