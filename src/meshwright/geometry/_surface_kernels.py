"""Numba kernels behind :class:`meshwright.geometry.Surface`: exact face tests, shells, nesting.

Every topological decision is an exact sign of :func:`~meshwright.core.predicates.orient3d`
or :func:`~meshwright.core.predicates.orient2d` (in a coordinate projection where the plane
of the triangle at hand does not degenerate), or an exact comparison of coordinates.  The
kernels assume what :meth:`Surface.validate` proves before calling them: no two points
coincide (so two faces share a point exactly when they share a vertex index) and no face
is degenerate (its corners are not collinear).

* :func:`find_intersection`: two faces that meet other than in their shared vertices or
  edge.  Broad phase: a bounding-volume hierarchy of the face boxes over the faces in
  Hilbert order (implicit median splits, leaves of :data:`LEAF` faces), traversed against
  itself with an explicit stack of node pairs; near-linear in the number of faces for
  surfaces of any mix of face sizes (a uniform grid is not: one far-field face covers all
  its cells).  Narrow phase by the number of shared vertices: none, the closed
  triangle-triangle test "an edge of one meets the other" (two closed triangles meet iff an
  edge of one meets the other: the extreme points of their convex intersection lie on
  their boundaries); one vertex ``a``, the same test on the edges opposite ``a`` plus the
  edges from ``a`` that enter the other triangle's wedge at ``a`` in its plane; an edge,
  the two triangles overlap iff they are coplanar with their third vertices on the same
  side of it; three, a duplicate face.
* :func:`nesting_parity`: ray parity of query points against each shell, the ray to +x
  symbolically perturbed to ``(y + e, z + e**2)`` so that it meets no edge and no vertex
  (Edelsbrunner and Mücke's Simulation of Simplicity); faces parallel to x are never hit.
* :func:`label_shells`, :func:`orient_shells`: union-find and breadth-first propagation over
  the manifold edges (edges in exactly two faces).
* :func:`volume_terms`: the divergence-theorem terms of the enclosed volume and their
  permanents, from which :mod:`meshwright.geometry.surface` bounds the rounding error.
* :func:`ear_clip`: a planar polygon (a TetGen facet) cut into triangles by ear clipping
  in its dominant coordinate projection, exact ``orient2d`` for convexity and emptiness.

Array layout: points ``(n, 3)`` float64; faces flat int32 ``tri[3 * f + k]`` (corner k of
face f); directed edge ``3 f + k`` runs from corner k to corner k + 1 of face f.

References: J. R. Shewchuk (1997) for the predicates; H. Edelsbrunner and E. P. Mücke,
ACM Trans. Graphics 9(1), 1990 (SoS); T. Möller, "A fast triangle-triangle intersection
test", J. Graphics Tools 2(2), 1997 (plane-side rejection); C. Ericson, *Real-Time Collision
Detection*, Morgan Kaufmann 2005, ch. 6 (tree-versus-tree traversal); O'Rourke,
*Computational Geometry in C*, 2nd ed. 1998, 1.2 (ear clipping).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.flat import grown
from meshwright.core.predicates import orient2d, orient3d

__all__ = [
    "HIT_CROSS",
    "HIT_DUPLICATE",
    "HIT_FOLD",
    "HIT_VERTEX",
    "LEAF",
    "NO_HIT",
    "degenerate_faces",
    "ear_clip",
    "find_intersection",
    "label_shells",
    "nesting_parity",
    "orient_shells",
    "volume_terms",
]

LEAF = 8
# Kinds of intersection find_intersection reports.
NO_HIT = 0
HIT_CROSS = 1  # faces without a shared vertex meet
HIT_VERTEX = 2  # faces sharing one vertex meet elsewhere too
HIT_FOLD = 3  # faces sharing an edge lie in one plane on the same side of it
HIT_DUPLICATE = 4  # faces on the same three vertices


# ------------------------------------------------------------------ exact primitives


@njit(inline="always")
def _o3(p, a, b, c, d):
    return orient3d(p[a, 0], p[a, 1], p[a, 2], p[b, 0], p[b, 1], p[b, 2],
                    p[c, 0], p[c, 1], p[c, 2], p[d, 0], p[d, 1], p[d, 2])


@njit(inline="always")
def _o2(p, a, b, c, ax):
    """orient2d of a, b, c projected along axis ``ax`` (cyclic pair: orientation kept)."""
    u = (ax + 1) % 3
    v = (ax + 2) % 3
    return orient2d(p[a, u], p[a, v], p[b, u], p[b, v], p[c, u], p[c, v])


@njit(cache=True)
def _drop_axis(p, a, b, c):
    """An axis along which triangle abc projects to a non-degenerate triangle, or -1."""
    for ax in (2, 0, 1):
        if _o2(p, a, b, c, ax) != 0.0:
            return ax
    return -1


@njit(cache=True)
def degenerate_faces(p, tri):
    """Faces whose three corners are collinear (exact: zero area in all three projections).

    Parameters
    ----------
    p : (n, 3) float64
    tri : (3 m,) int32

    Returns
    -------
    (m,) bool
    """
    m = tri.shape[0] // 3
    out = np.zeros(m, np.bool_)
    for f in range(m):
        out[f] = _drop_axis(p, tri[3 * f], tri[3 * f + 1], tri[3 * f + 2]) < 0
    return out


@njit(inline="always")
def _lex_less(p, i, j, u, v):
    return p[i, u] < p[j, u] or (p[i, u] == p[j, u] and p[i, v] < p[j, v])


@njit(cache=True)
def _segments_2d(p, a, b, c, d, ax, w):
    """Closed segments ab and cd (coplanar) meet in projection ``ax``; a meeting point in ``w``."""
    d1 = _o2(p, c, d, a, ax)
    d2 = _o2(p, c, d, b, ax)
    if (d1 > 0.0 and d2 > 0.0) or (d1 < 0.0 and d2 < 0.0):
        return False
    d3 = _o2(p, a, b, c, ax)
    d4 = _o2(p, a, b, d, ax)
    if (d3 > 0.0 and d4 > 0.0) or (d3 < 0.0 and d4 < 0.0):
        return False
    if d1 == 0.0 and d2 == 0.0:
        u = (ax + 1) % 3
        v = (ax + 2) % 3
        lo1, hi1 = (a, b) if _lex_less(p, a, b, u, v) else (b, a)
        lo2, hi2 = (c, d) if _lex_less(p, c, d, u, v) else (d, c)
        if _lex_less(p, hi1, lo2, u, v) or _lex_less(p, hi2, lo1, u, v):
            return False
        q = lo2 if _lex_less(p, lo1, lo2, u, v) else lo1
        for k in range(3):
            w[k] = p[q, k]
        return True
    t = d1 / (d1 - d2)
    for k in range(3):
        w[k] = p[a, k] + t * (p[b, k] - p[a, k])
    return True


@njit(inline="always")
def _in_triangle_2d(p, q, a, b, c, ax, s):
    """Point q in the closed triangle abc (coplanar; ``s`` the sign of its projection)."""
    return (_o2(p, a, b, q, ax) * s >= 0.0 and _o2(p, b, c, q, ax) * s >= 0.0
            and _o2(p, c, a, q, ax) * s >= 0.0)


@njit(cache=True)
def _segment_triangle(p, a, b, t0, t1, t2, w):
    """Closed segment ab meets closed triangle t0 t1 t2; a meeting point in ``w``."""
    oa = _o3(p, t0, t1, t2, a)
    ob = _o3(p, t0, t1, t2, b)
    if (oa > 0.0 and ob > 0.0) or (oa < 0.0 and ob < 0.0):
        return False
    if oa == 0.0 and ob == 0.0:
        ax = _drop_axis(p, t0, t1, t2)
        s = 1.0 if _o2(p, t0, t1, t2, ax) > 0.0 else -1.0
        for q in (a, b):
            if _in_triangle_2d(p, q, t0, t1, t2, ax, s):
                for k in range(3):
                    w[k] = p[q, k]
                return True
        return (_segments_2d(p, a, b, t0, t1, ax, w) or _segments_2d(p, a, b, t1, t2, ax, w)
                or _segments_2d(p, a, b, t2, t0, ax, w))
    s1 = _o3(p, a, b, t0, t1)
    s2 = _o3(p, a, b, t1, t2)
    s3 = _o3(p, a, b, t2, t0)
    if (s1 >= 0.0 and s2 >= 0.0 and s3 >= 0.0) or (s1 <= 0.0 and s2 <= 0.0 and s3 <= 0.0):
        t = oa / (oa - ob)
        for k in range(3):
            w[k] = p[a, k] + t * (p[b, k] - p[a, k])
        return True
    return False


@njit(cache=True)
def _enters(p, a, x, y, z, w):
    """Edge ax (from the shared vertex a) runs into triangle a y z beyond a: x lies in the
    plane of a y z and in its closed wedge at a.  A point of the overlap in ``w``."""
    if _o3(p, a, y, z, x) != 0.0:
        return False
    ax = _drop_axis(p, a, y, z)
    s = 1.0 if _o2(p, a, y, z, ax) > 0.0 else -1.0
    if _o2(p, a, y, x, ax) * s < 0.0 or _o2(p, a, x, z, ax) * s < 0.0:
        return False
    # Halfway to where ax leaves the triangle (through yz) or to x.
    t = 1.0
    e1 = _o2(p, y, z, a, ax)
    e2 = _o2(p, y, z, x, ax)
    if e1 * e2 < 0.0:
        t = e1 / (e1 - e2)
    for k in range(3):
        w[k] = p[a, k] + 0.5 * t * (p[x, k] - p[a, k])
    return True


@njit(inline="always")
def _same_side_strict(o1, o2):
    return (o1 > 0.0 and o2 > 0.0) or (o1 < 0.0 and o2 < 0.0)


@njit(cache=True)
def _pair(p, tri, f, g, w):
    """Kind of intersection of faces f and g other than their shared vertices/edge."""
    fa = tri[3 * f]
    fb = tri[3 * f + 1]
    fc = tri[3 * f + 2]
    ga = tri[3 * g]
    gb = tri[3 * g + 1]
    gc = tri[3 * g + 2]
    shared = 0
    # Position in f of a shared vertex and of a vertex of f not in g.
    fs = -1
    fo = -1
    for i in range(3):
        v = tri[3 * f + i]
        if v == ga or v == gb or v == gc:
            shared += 1
            fs = i
        else:
            fo = i
    if shared == 3:
        for k in range(3):
            w[k] = (p[fa, k] + p[fb, k] + p[fc, k]) / 3.0
        return HIT_DUPLICATE
    if shared == 0:
        # Plane-side rejection (Möller): one triangle strictly on one side of the other's plane.
        ob = _o3(p, fa, fb, fc, gb)
        if _same_side_strict(_o3(p, fa, fb, fc, ga), ob) and _same_side_strict(ob, _o3(p, fa, fb, fc, gc)):
            return NO_HIT
        ob = _o3(p, ga, gb, gc, fb)
        if _same_side_strict(_o3(p, ga, gb, gc, fa), ob) and _same_side_strict(ob, _o3(p, ga, gb, gc, fc)):
            return NO_HIT
        if (_segment_triangle(p, fa, fb, ga, gb, gc, w) or _segment_triangle(p, fb, fc, ga, gb, gc, w)
                or _segment_triangle(p, fc, fa, ga, gb, gc, w) or _segment_triangle(p, ga, gb, fa, fb, fc, w)
                or _segment_triangle(p, gb, gc, fa, fb, fc, w) or _segment_triangle(p, gc, ga, fa, fb, fc, w)):
            return HIT_CROSS
        return NO_HIT
    if shared == 2:
        # Rotate f to (a, b, c) with c = fo not in g; d = g's vertex not in f.
        a = tri[3 * f + (fo + 1) % 3]
        b = tri[3 * f + (fo + 2) % 3]
        c = tri[3 * f + fo]
        d = gc
        if ga != a and ga != b:
            d = ga
        elif gb != a and gb != b:
            d = gb
        if _o3(p, a, b, c, d) != 0.0:
            return NO_HIT
        ax = _drop_axis(p, a, b, c)
        if _same_side_strict(_o2(p, a, b, c, ax), _o2(p, a, b, d, ax)):
            for k in range(3):
                w[k] = 0.5 * (p[a, k] + p[b, k])
            return HIT_FOLD
        return NO_HIT
    # One shared vertex a: f = (a, b, c), g = (a, d, e).
    a = tri[3 * f + fs]
    b = tri[3 * f + (fs + 1) % 3]
    c = tri[3 * f + (fs + 2) % 3]
    gs = 0 if ga == a else (1 if gb == a else 2)
    d = tri[3 * g + (gs + 1) % 3]
    e = tri[3 * g + (gs + 2) % 3]
    if _same_side_strict(_o3(p, a, b, c, d), _o3(p, a, b, c, e)):
        return NO_HIT
    if _same_side_strict(_o3(p, a, d, e, b), _o3(p, a, d, e, c)):
        return NO_HIT
    if (_segment_triangle(p, b, c, a, d, e, w) or _segment_triangle(p, d, e, a, b, c, w)
            or _enters(p, a, b, d, e, w) or _enters(p, a, c, d, e, w)
            or _enters(p, a, d, b, c, w) or _enters(p, a, e, b, c, w)):
        return HIT_VERTEX
    return NO_HIT


# ------------------------------------------------------------------ broad phase


@njit(cache=True)
def _sorted_boxes(p, tri, order):
    """Box of face ``order[i]`` in row i: ``(xlo, ylo, zlo, xhi, yhi, zhi)``; rows in tree
    order, so the leaves read contiguous memory."""
    m = order.shape[0]
    box = np.empty((m, 6))
    for i in range(m):
        f = order[i]
        for k in range(3):
            v0 = p[tri[3 * f], k]
            v1 = p[tri[3 * f + 1], k]
            v2 = p[tri[3 * f + 2], k]
            box[i, k] = min(v0, v1, v2)
            box[i, k + 3] = max(v0, v1, v2)
    return box


@njit(inline="always")
def _boxes_meet(a, i, b, j):
    return (a[i, 0] <= b[j, 3] and b[j, 0] <= a[i, 3] and a[i, 1] <= b[j, 4]
            and b[j, 1] <= a[i, 4] and a[i, 2] <= b[j, 5] and b[j, 2] <= a[i, 5])


@njit(cache=True)
def _build_tree(box):
    """Median-split hierarchy over the rows of ``box``; node i covers rows
    ``start[i]:end[i]``, children ``child[i]`` and ``child[i] + 1`` (-1 for a leaf),
    boxes ``nbox[i]`` as the rows of ``box``."""
    m = box.shape[0]
    cap = max(2 * m, 1)
    start = np.empty(cap, np.int64)
    end = np.empty(cap, np.int64)
    child = np.full(cap, -1, np.int64)
    start[0] = 0
    end[0] = m
    count = 1
    i = 0
    # Nodes are created in breadth order, so scanning them in creation order splits each once.
    while i < count:
        if end[i] - start[i] > LEAF:
            mid = (start[i] + end[i]) // 2
            child[i] = count
            start[count] = start[i]
            end[count] = mid
            start[count + 1] = mid
            end[count + 1] = end[i]
            count += 2
        i += 1
    nbox = np.empty((count, 6))
    for i in range(count - 1, -1, -1):
        c = child[i]
        for k in range(3):
            nbox[i, k] = np.inf
            nbox[i, k + 3] = -np.inf
        if c < 0:
            for j in range(start[i], end[i]):
                for k in range(3):
                    nbox[i, k] = min(nbox[i, k], box[j, k])
                    nbox[i, k + 3] = max(nbox[i, k + 3], box[j, k + 3])
        else:
            for k in range(3):
                nbox[i, k] = min(nbox[c, k], nbox[c + 1, k])
                nbox[i, k + 3] = max(nbox[c, k + 3], nbox[c + 1, k + 3])
    return start[:count], end[:count], child[:count], nbox


@njit(cache=True)
def _leaf_pairs(p, tri, order, box, nbox, s1, e1, b, s2, e2, same, w, res):
    """Test the face pairs of two leaves (leaf ``b`` at rows s2:e2; one leaf against
    itself when ``same``)."""
    for i in range(s1, e1):
        if not same and not _boxes_meet(box, i, nbox, b):
            continue
        for j in range(i + 1 if same else s2, e2):
            if not _boxes_meet(box, i, box, j):
                continue
            f = order[i]
            g = order[j]
            kind = _pair(p, tri, f, g, w)
            if kind != NO_HIT:
                res[0] = min(f, g)
                res[1] = max(f, g)
                res[2] = kind
                return True
    return False


@njit(cache=True)
def find_intersection(p, tri, order):
    """First pair of faces that meet other than in their shared vertices or edge.

    Parameters
    ----------
    p : (n, 3) float64
        No two points equal.
    tri : (3 m,) int32
        Non-degenerate faces.
    order : (m,) int64
        The faces in a spatially coherent order (Hilbert order of their centroids): only
        the tree's efficiency depends on it.

    Returns
    -------
    res : (3,) int64
        ``(f, g, kind)`` with f < g, kind one of the ``HIT_*`` codes; ``(-1, -1, NO_HIT)``
        when no two faces meet wrongly.
    witness : (3,) float64
        A point (rounded) of the offending intersection.
    """
    res = np.array([-1, -1, NO_HIT], np.int64)
    w = np.zeros(3)
    if order.shape[0] < 2:
        return res, w
    box = _sorted_boxes(p, tri, order)
    start, end, child, nbox = _build_tree(box)
    stack = np.empty(256, np.int64)
    stack[0] = 0
    stack[1] = 0
    top = 2
    while top > 0:
        top -= 2
        a = stack[top]
        b = stack[top + 1]
        if top + 6 > stack.shape[0]:
            stack = grown(stack, top + 6)
        ca = child[a]
        cb = child[b]
        if a == b:
            if ca < 0:
                if _leaf_pairs(p, tri, order, box, nbox, start[a], end[a], a, start[a], end[a], True, w, res):
                    return res, w
            else:
                stack[top] = ca
                stack[top + 1] = ca
                stack[top + 2] = ca + 1
                stack[top + 3] = ca + 1
                stack[top + 4] = ca
                stack[top + 5] = ca + 1
                top += 6
            continue
        if not _boxes_meet(nbox, a, nbox, b):
            continue
        if ca < 0 and cb < 0:
            if _leaf_pairs(p, tri, order, box, nbox, start[a], end[a], b, start[b], end[b], False, w, res):
                return res, w
        elif cb < 0 or (ca >= 0 and end[a] - start[a] >= end[b] - start[b]):
            stack[top] = ca
            stack[top + 1] = b
            stack[top + 2] = ca + 1
            stack[top + 3] = b
            top += 4
        else:
            stack[top] = a
            stack[top + 1] = cb
            stack[top + 2] = a
            stack[top + 3] = cb + 1
            top += 4
    return res, w


# ------------------------------------------------------------------ nesting


@njit(cache=True)
def nesting_parity(p, tri, shell, n_shells, query, query_shell):
    """Parity of the crossings of the ray from each query point to +x with each shell.

    Parameters
    ----------
    p : (n, 3) float64
    tri : (3 m,) int32
    shell : (m,) int64
        Shell of each face, in ``[0, n_shells)``.
    n_shells : int
    query : (k,) int64
        Query vertices, none lying on a shell other than its own.
    query_shell : (k,) int64
        Shell of each query vertex (its own shell is not tested).

    Returns
    -------
    (k, n_shells) uint8
        1 where the query point lies inside the shell (odd number of crossings).
    """
    m = tri.shape[0] // 3
    k = query.shape[0]
    out = np.zeros((k, n_shells), np.uint8)
    # Queries sorted by y: each face scans only those within its y extent.
    qy = np.empty(k)
    for i in range(k):
        qy[i] = p[query[i], 1]
    by_y = np.argsort(qy)
    qy = qy[by_y]
    for f in range(m):
        a = tri[3 * f]
        b = tri[3 * f + 1]
        c = tri[3 * f + 2]
        s = _o2(p, a, b, c, 0)
        if s == 0.0:
            continue  # parallel to the ray: the perturbed ray misses it
        xmax = max(p[a, 0], p[b, 0], p[c, 0])
        ylo = min(p[a, 1], p[b, 1], p[c, 1])
        yhi = max(p[a, 1], p[b, 1], p[c, 1])
        zlo = min(p[a, 2], p[b, 2], p[c, 2])
        zhi = max(p[a, 2], p[b, 2], p[c, 2])
        t = shell[f]
        for r in range(np.searchsorted(qy, ylo), np.searchsorted(qy, yhi, side="right")):
            i = by_y[r]
            if query_shell[i] == t:
                continue
            q = query[i]
            if p[q, 0] >= xmax or p[q, 2] < zlo or p[q, 2] > zhi:
                continue
            inside = True
            for j in range(3):
                u = tri[3 * f + j]
                v = tri[3 * f + (j + 1) % 3]
                d = _o2(p, u, v, q, 0)
                if d == 0.0:
                    # Sign of the perturbation terms: -(vz - uz) e + (vy - uy) e**2.
                    d = p[u, 2] - p[v, 2] if p[v, 2] != p[u, 2] else p[v, 1] - p[u, 1]
                if (d > 0.0) != (s > 0.0):
                    inside = False
                    break
            if inside and _o3(p, a, b, c, q) * s < 0.0:
                out[i, t] ^= 1
    return out


@njit(cache=True)
def volume_terms(p, tri, o):
    """Per face ``det[a - o, b - o, c - o]`` (six times the signed volume of the tet from o)
    and its permanent (the same products in absolute value, for the rounding bound).

    Parameters
    ----------
    p : (n, 3) float64
    tri : (3 m,) int32
    o : (3,) float64

    Returns
    -------
    det, perm : (m,) float64
    """
    m = tri.shape[0] // 3
    det = np.empty(m)
    perm = np.empty(m)
    for f in range(m):
        a = tri[3 * f]
        b = tri[3 * f + 1]
        c = tri[3 * f + 2]
        ax, ay, az = p[a, 0] - o[0], p[a, 1] - o[1], p[a, 2] - o[2]
        bx, by, bz = p[b, 0] - o[0], p[b, 1] - o[1], p[b, 2] - o[2]
        cx, cy, cz = p[c, 0] - o[0], p[c, 1] - o[1], p[c, 2] - o[2]
        det[f] = ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx)
        perm[f] = (abs(ax) * (abs(by * cz) + abs(bz * cy)) + abs(ay) * (abs(bz * cx) + abs(bx * cz))
                   + abs(az) * (abs(bx * cy) + abs(by * cx)))
    return det, perm


# ------------------------------------------------------------------ shells and orientation


@njit(inline="always")
def _root(parent, i):
    while parent[i] != i:
        parent[i] = parent[parent[i]]
        i = parent[i]
    return i


@njit(cache=True)
def label_shells(m, first, second):
    """Connected components of the faces through the paired directed edges.

    Parameters
    ----------
    m : int
        Number of faces.
    first, second : (e,) int64
        The two directed edges (``3 f + k``) of each edge that lies in exactly two faces.

    Returns
    -------
    labels : (m,) int64
        Component of each face, numbered 0, 1, ... in order of their first face.
    count : int
    """
    parent = np.arange(m)
    for i in range(first.shape[0]):
        a = _root(parent, first[i] // 3)
        b = _root(parent, second[i] // 3)
        if a != b:
            parent[max(a, b)] = min(a, b)
    labels = np.empty(m, np.int64)
    count = 0
    for f in range(m):
        r = _root(parent, f)
        if r == f:
            labels[f] = count
            count += 1
        else:
            labels[f] = labels[r]
    return labels, count


@njit(cache=True)
def orient_shells(m, first, second, same):
    """Flip flags making every manifold edge traversed in opposite directions.

    Breadth-first from the first face of each component (kept as it is), a neighbour is
    flipped when it traverses the shared edge in the same direction as the reached face.

    Parameters
    ----------
    m : int
    first, second : (e,) int64
        Paired directed edges as in :func:`label_shells`.
    same : (e,) bool
        Whether the pair traverses its edge in the same direction.

    Returns
    -------
    flip : (m,) bool
    bad : int
        Index into ``first`` of an edge whose faces cannot be made consistent (a
        non-orientable component), or -1.
    """
    deg = np.zeros(m + 1, np.int64)
    for i in range(first.shape[0]):
        deg[first[i] // 3 + 1] += 1
        deg[second[i] // 3 + 1] += 1
    for f in range(m):
        deg[f + 1] += deg[f]
    adj = np.empty(deg[m], np.int64)
    fill = deg[:m].copy()
    for i in range(first.shape[0]):
        f = first[i] // 3
        g = second[i] // 3
        adj[fill[f]] = i
        fill[f] += 1
        adj[fill[g]] = i
        fill[g] += 1
    flip = np.zeros(m, np.bool_)
    seen = np.zeros(m, np.bool_)
    queue = np.empty(m, np.int64)
    for s in range(m):
        if seen[s]:
            continue
        seen[s] = True
        queue[0] = s
        head = 0
        tail = 1
        while head < tail:
            f = queue[head]
            head += 1
            for j in range(deg[f], deg[f + 1]):
                i = adj[j]
                g = second[i] // 3 if first[i] // 3 == f else first[i] // 3
                want = flip[f] ^ same[i]
                if not seen[g]:
                    seen[g] = True
                    flip[g] = want
                    queue[tail] = g
                    tail += 1
                elif flip[g] != want:
                    return flip, i
    return flip, -1


# ------------------------------------------------------------------ facets


@njit(cache=True)
def ear_clip(p, poly, ax, s):
    """Triangulate a simple planar polygon by ear clipping.

    Parameters
    ----------
    p : (n, 3) float64
    poly : (k,) int64
        Corner indices, k >= 3, in order.
    ax : int
        Projection axis in which the polygon does not degenerate.
    s : float
        +1 when the corners run counter-clockwise in that projection, -1 otherwise.

    Returns
    -------
    (k - 2, 3) int64
        Triangles in the corners' rotational sense; empty (0 rows) when no ear is found
        (the polygon is not simple, or its corners are collinear).
    """
    k = poly.shape[0]
    nxt = np.empty(k, np.int64)
    prv = np.empty(k, np.int64)
    for i in range(k):
        nxt[i] = (i + 1) % k
        prv[i] = (i - 1) % k
    out = np.empty((k - 2, 3), np.int64)
    n_out = 0
    left = k
    i = 0
    misses = 0
    while left > 3:
        if misses > left:
            return out[:0]
        a = poly[prv[i]]
        b = poly[i]
        c = poly[nxt[i]]
        ear = _o2(p, a, b, c, ax) * s > 0.0
        j = nxt[nxt[i]]
        while ear and j != prv[i]:
            q = poly[j]
            if q != a and q != c and _in_triangle_2d(p, q, a, b, c, ax, s):
                ear = False
            j = nxt[j]
        if ear:
            out[n_out, 0] = a
            out[n_out, 1] = b
            out[n_out, 2] = c
            n_out += 1
            nxt[prv[i]] = nxt[i]
            prv[nxt[i]] = prv[i]
            left -= 1
            i = prv[i]
            misses = 0
        else:
            i = nxt[i]
            misses += 1
    a = poly[prv[i]]
    b = poly[i]
    c = poly[nxt[i]]
    if _o2(p, a, b, c, ax) * s <= 0.0:
        return out[:0]
    out[n_out, 0] = a
    out[n_out, 1] = b
    out[n_out, 2] = c
    return out
