r"""Exterior removal of the constrained Delaunay triangulation: floods over its triangles.

Chapter 18.1.2 of the reference text (removing the superstructure and the exterior): boundary
loops run with the domain on their left, so the side of a boundary segment that belongs to
the domain is known from the sign of the cross product of the segment direction with the
vector to a triangle's apex.  :func:`classify_sides` seeds the triangles on the domain side
of every *sided* segment piece and floods across free edges (and unsided constraints);
anything not reached is exterior.  Without sides it eats from the ghost triangles up to the
segments instead (Triangle's convention).  :func:`flood` spreads a region flag from seed
triangles (holes, region seeds) up to the constraints.

State: the kernel's :class:`~meshwright.tri._kernel2d.TriState` ``s`` and the constrained
layer's :class:`~meshwright.tri._encroach.CdtState` ``c``, whose ``treg`` (cap,) int32 is
written: -1 exterior or ghost, 0 inside, r + 1 region r.  ``pside`` (P,) int8 per piece:
+1 domain on the left, -1 on the right, 0 unknown.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.flat import GHOST

__all__ = ["FLOOD_OK", "FLOOD_LEAK", "FLOOD_CLASH", "flood", "classify_sides"]

FLOOD_OK = 0
FLOOD_LEAK = 1  # the domain side of a segment reaches a ghost: open boundary
FLOOD_CLASH = 2  # the domain side of one segment is the exterior side of another


@njit(cache=True)
def _free(h, cons, pside, cross_unsided):
    """Whether a flood may cross half-edge h."""
    c = cons[h]
    return c == 0 or (cross_unsided and pside[c - 1] == 0)


@njit(cache=True, nogil=True)
def flood(stack, top, value, accept_lo, s, c, pside, cross_unsided):
    """Spread ``value`` from ``stack[:top]`` over triangles with ``treg >= accept_lo`` != value."""
    tri, nbr, cons, treg = s.tri, s.nbr, s.cons, c.treg
    while top > 0:
        top -= 1
        t = stack[top]
        for k in range(3):
            n = nbr[3 * t + k]
            if _free(3 * t + k, cons, pside, cross_unsided) and tri[3 * n + 2] != GHOST:
                if treg[n] >= accept_lo and treg[n] != value:
                    treg[n] = value
                    stack[top] = n
                    top += 1


@njit(inline="always")
def _on_domain_side(t, k, p, pts, tri, seg, pside):
    """Whether finite triangle t lies on the domain side of piece p, along its edge k."""
    u = tri[3 * t + (k + 1) % 3]
    w = tri[3 * t + (k + 2) % 3]
    # t lies left of u -> w; the piece's domain side is left of its a -> b when pside > 0.
    # Subsegments of a curved piece are near-parallel to its chord.
    dot = (pts[w, 0] - pts[u, 0]) * (pts[seg[p, 1], 0] - pts[seg[p, 0], 0]) + (pts[w, 1] - pts[u, 1]) * (
        pts[seg[p, 1], 1] - pts[seg[p, 0], 1]
    )
    return (dot > 0.0) == (pside[p] > 0)


@njit(cache=True, nogil=True)
def classify_sides(s, c, pside, ntri, stack, info):
    """Exterior removal by segment sides; returns a ``FLOOD_*`` code (culprit in ``info``).

    ``c.treg``: -2 unknown, -3 exterior side of a sided segment, 0 inside; on return -1 / 0.
    Without any sided segment, every triangle reachable from a ghost is exterior.
    """
    pts, tri, nbr, cons, seg, treg = s.pts, s.tri, s.nbr, s.cons, c.seg, c.treg
    top = 0
    for t in range(ntri):
        treg[t] = -1 if tri[3 * t + 2] == GHOST else -2
    for t in range(ntri):
        if tri[3 * t + 2] == GHOST:
            continue
        for k in range(3):
            cc = cons[3 * t + k]
            if cc == 0 or pside[cc - 1] == 0:
                continue
            p = cc - 1
            inside = _on_domain_side(t, k, p, pts, tri, seg, pside)
            if (inside and treg[t] == -3) or (not inside and treg[t] == 0):
                info[0] = p
                info[1] = t
                return FLOOD_CLASH
            if inside and treg[t] != 0:
                treg[t] = 0
                stack[top] = t
                top += 1
            elif not inside:
                treg[t] = -3
    unsided = np.bool_(True)  # a typed True: a literal would compile _free twice
    if top == 0:
        # Triangle's convention: eat from the convex hull up to the segments.
        for t in range(ntri):
            if tri[3 * t + 2] == GHOST:
                stack[top] = t
                top += 1
        while top > 0:
            top -= 1
            t = stack[top]
            for k in range(3):
                n = nbr[3 * t + k]
                if cons[3 * t + k] == 0 and treg[n] == -2:
                    treg[n] = -1
                    stack[top] = n
                    top += 1
        for t in range(ntri):
            if treg[t] == -2:
                treg[t] = 0
        return FLOOD_OK
    while top > 0:
        top -= 1
        t = stack[top]
        for k in range(3):
            if not _free(3 * t + k, cons, pside, unsided):
                continue
            n = nbr[3 * t + k]
            if tri[3 * n + 2] == GHOST or treg[n] == -3:
                # A clash: n is on the exterior side of one of its own sided pieces.
                info[0] = -1
                if tri[3 * n + 2] != GHOST:
                    for m in range(3):
                        cc = cons[3 * n + m]
                        if cc != 0 and pside[cc - 1] != 0 and not _on_domain_side(n, m, cc - 1, pts, tri, seg, pside):
                            info[0] = cc - 1
                info[1] = t
                return FLOOD_LEAK if tri[3 * n + 2] == GHOST else FLOOD_CLASH
            if treg[n] == -2:
                treg[n] = 0
                stack[top] = n
                top += 1
    for t in range(ntri):
        if treg[t] < 0:
            treg[t] = -1
    return FLOOD_OK
