r"""Boundary recovery: make every face of a closed surface a union of Delaunay faces (18.4.1).

After the surface's vertices are tetrahedralized (:class:`~meshwright.tet.Tetrahedralization`),
a surface triangle is in general not a face of the Delaunay tetrahedralization: the chapter
(18.4.1, after Weatherill and Hassan 1994) recovers it by inserting points on the surface.
This module does the *conforming* variant (George, Hecht and Saltel 1991 call it "boundary
enforcement by point insertion"; Shewchuk 1998, "Tetrahedral mesh generation by Delaunay
refinement", analyses it): the input faces are kept as a triangulation of *subfaces*, and a
subface that is not a face of the tetrahedralization is split, with its points inserted into
the tetrahedralization, until every subface is present.

Guarantee and choice
--------------------
The output is a Delaunay tetrahedralization of the input vertices plus Steiner points lying on
the input faces (within round-off: a midpoint of a general 3-D segment is not representable;
on faces parallel to a coordinate plane it is exact), in which every subface is a face, so
every input triangle is a union of output faces.  It is chosen over a constrained Delaunay
tetrahedralization (flips plus Steiner points, as TetGen does) because it needs no flip
machinery that can stall, and because the quality refinement that follows
(:mod:`meshwright.tet.refine3d`) splits boundary faces anyway.  It is *presence based*: a
subface is split only when it is missing, not when a vertex merely lies in its diametral
ball, so a plate thinner than its faces are wide is recovered without refining its faces
down to its thickness (the top face of a thin prism is a Delaunay face: its two caps share a
circumsphere).

The subfaces of each input face are kept a 2-D Delaunay triangulation (Lawson's flips,
:func:`lawson`, decided on the face's projection along its dominant axis) after every
bisection: a subface whose circumcircle holds a point of its own face is not a Delaunay face
in 3-D either, and bisecting it instead cascaded on nearly planar walls.
Before splitting, a missing subface whose neighbour in the same input face would, flipped,
give two faces the tetrahedralization has, is flipped (:func:`flip_to_match`): cocircular
points leave the diagonal to the symbolic perturbation, and no split can settle such a tie.
Splitting is longest-edge bisection (Rivara 1984, "Algorithms for refining triangular grids
suitable for adaptive and multigrid techniques"): a missing edge is marked; a missing face
whose edges are present gets its longest edge marked; every subface with a marked edge gets
its longest edge marked too (the closure), and each subface is then bisected at its longest
edge's midpoint and its halves at their other marked edges::

        v_i                       v_i
        / \                       /|\
       /   \                     / | \
      /     \         ==>      m3  |  m2      (m3, m2 only where marked)
     /       \                 /   |   \
  v_i+1 ----- v_i+2        v_i+1 - m - v_i+2

so the subfaces stay conforming (a marked edge is split in both its subfaces) and their
angles stay bounded below by half the input's (Rivara).  An edge with one end an input vertex
is split not at its midpoint but on a concentric shell around that vertex, at the power of
two nearest half its length (:func:`shell_points`, Ruppert's and Shewchuk's remedy for small
input angles): two input edges at a small angle then get split points at equal radii and
stop making each other's pieces at the vertex missing.  Rivara's angle bound is for
midpoints; a shell point leaves pieces of 0.29-0.71 of the edge, and no bound is proved
here for that case.  Only the first recovery (before quality refinement) uses shells: the
recoveries between refinement rounds split at midpoints, as the refinement's encroachment
splits do (shell points next to refinement midpoints made edges short enough to cascade
again: fuzz seed 11 case 95, seed 41 case 38).  An edge shorter than ``guard`` is
never split: recovery that would need one raises :class:`MeshingError` naming the face.

Arrays
------
``tets`` (nt, 4) int32 and ``nbr`` (nt, 4) int32 are the public arrays of a
:class:`~meshwright.tet.Tetrahedralization` (``nbr[t, k]`` across the face opposite vertex
k, -1 on the hull); ``faces`` (m, 3) int32 the subfaces, vertices of the tetrahedralization,
oriented as their input face; ``parent`` (m,) int32 the input face each subface lies in.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.errors import MeshingError, fmt_point
from meshwright.core.predicates import incircle, orient2d
from meshwright.tet._bisect import _longest, bisect_marked, shell_points

__all__ = ["RECOVERY_ROUNDS", "SplitOrigins", "bisect_marked", "dominant_axes", "find_edges", "find_faces", "flip_to_match", "insert_new", "lawson", "lawson_pass", "raise_cap", "recover", "shell_points", "unique_edges", "vertex_tets"]

RECOVERY_ROUNDS = 64  # bisection rounds; each at least halves the longest missing edge
LAWSON_PASSES = 64  # bound on the work of one lawson() call (flips terminate anyway)


@njit(cache=True)
def vertex_tets(tets, nv):
    """One tet incident to each vertex, -1 for a vertex in no tet.

    Parameters
    ----------
    tets : (nt, 4) int32
    nv : int

    Returns
    -------
    (nv,) int32
    """
    vt = np.full(nv, -1, dtype=np.int32)
    for t in range(tets.shape[0]):
        for k in range(4):
            vt[tets[t, k]] = t
    return vt


@njit(cache=True)
def _star_search(tets, nbr, vt, stamp, queue, gen, a, b, c):
    """Breadth-first search of the star of vertex a for a tet holding b (and c when c >= 0).

    Returns ``4 t + k`` with k the slot not in {a, b, c} for a face query, ``4 t`` for an
    edge query, or -1 when no tet of the star holds them.
    """
    t0 = vt[a]
    if t0 < 0:
        return -1
    head = 0
    tail = 1
    queue[0] = t0
    stamp[t0] = gen
    while head < tail:
        t = queue[head]
        head += 1
        hb = -1
        hc = -1
        for k in range(4):
            w = tets[t, k]
            if w == b:
                hb = k
            elif w == c:
                hc = k
        if hb >= 0 and (c < 0 or hc >= 0):
            if c < 0:
                return 4 * t
            for k in range(4):
                w = tets[t, k]
                if w != a and w != b and w != c:
                    return 4 * t + k
        for k in range(4):
            if tets[t, k] == a:
                continue
            u = nbr[t, k]
            if u >= 0 and stamp[u] != gen:
                stamp[u] = gen
                queue[tail] = u
                tail += 1
    return -1


@njit(cache=True)
def find_faces(tets, nbr, vt, faces, hint):
    """Where each face occurs in the tetrahedralization.

    Parameters
    ----------
    tets, nbr : (nt, 4) int32
    vt : (nv,) int32
        :func:`vertex_tets`.
    faces : (m, 3) int32
    hint : (m,) int64 or (0,)
        A position ``4 t + k`` each face had before (-1: none).  Insertions move few tets
        (compaction fills the freed slots from the end), so most are still right; each is
        checked, and a face whose hint is wrong is searched in a star as without one.

    Returns
    -------
    (m,) int64
        ``4 t + k``: face ``tets[t]`` minus slot k; -1 where the face is missing.
    """
    nt = tets.shape[0]
    stamp = np.zeros(nt, dtype=np.int32)
    queue = np.empty(nt, dtype=np.int32)
    out = np.empty(faces.shape[0], dtype=np.int64)
    hinted = hint.shape[0] == faces.shape[0]
    for i in range(faces.shape[0]):
        if hinted and 0 <= hint[i] < 4 * nt and _holds_face(tets, hint[i], faces[i, 0], faces[i, 1], faces[i, 2]):
            out[i] = hint[i]
            continue
        out[i] = _star_search(tets, nbr, vt, stamp, queue, i + 1, faces[i, 0], faces[i, 1], faces[i, 2])
    return out


@njit(inline="always")
def _holds_face(tets, h, a, b, c):
    """Whether tet ``h // 4`` minus slot ``h % 4`` is the face {a, b, c}."""
    t = h // 4
    k = h % 4
    found = 0
    for j in range(4):
        if j != k:
            w = tets[t, j]
            if w == a or w == b or w == c:
                found += 1
    return found == 3


@njit(cache=True)
def find_edges(tets, nbr, vt, edges):
    """Whether each edge (e, 2) int32 is an edge of the tetrahedralization; (e,) bool."""
    nt = tets.shape[0]
    stamp = np.zeros(nt, dtype=np.int32)
    queue = np.empty(nt, dtype=np.int32)
    out = np.empty(edges.shape[0], dtype=np.bool_)
    for i in range(edges.shape[0]):
        out[i] = _star_search(tets, nbr, vt, stamp, queue, i + 1, edges[i, 0], edges[i, 1], -1) >= 0
    return out


@njit(inline="always")
def _orient_in(pts, ax, a, b, c):
    """orient2d of a, b, c projected along coordinate axis ``ax`` (exact)."""
    i = (ax + 1) % 3
    j = (ax + 2) % 3
    return orient2d(pts[a, i], pts[a, j], pts[b, i], pts[b, j], pts[c, i], pts[c, j])


@njit(cache=True)
def _edge_faces(face_edges, n_edges):
    """The two subfaces on each edge, as ``3 * face + k`` (k: the edge's slot in the face;
    -1 where the edge has fewer)."""
    first = np.full(n_edges, -1, dtype=np.int64)
    second = np.full(n_edges, -1, dtype=np.int64)
    for f in range(face_edges.shape[0]):
        for k in range(3):
            e = face_edges[f, k]
            if first[e] < 0:
                first[e] = 3 * f + k
            else:
                second[e] = 3 * f + k
    return first, second


@njit(inline="always")
def _boundary_edge(parent, first, second, e):
    """Whether subface edge e lies on its input face's boundary (one face of that parent)."""
    return second[e] < 0 or parent[first[e] // 3] != parent[second[e] // 3]


@njit(inline="always")
def _folds_onto_edge(faces, parent, in_faces, ends, face_edges, first, second, f, k, g, j):
    """Whether flipping edge p q of f = (r, p, q) (r at k) and g = (s, q, p) (s at j) to r s
    would make a degenerate face: p or q a Steiner point on the segment r s.

    Such a point lies on r s only within round-off, so no orientation test can refuse the
    flip; it is told by the topology: p was created splitting r s (``ends``), or p is on an
    input edge with r and s (both its edges in the quad on the input face's boundary, and
    p no corner of the input face).
    """
    pf = parent[f]
    r = faces[f, k]
    s = faces[g, j]
    for side in range(2):
        v = faces[f, (k + 1 + side) % 3]  # p, then q
        if (ends[v, 0] == r and ends[v, 1] == s) or (ends[v, 0] == s and ends[v, 1] == r):
            return True
        e1 = face_edges[f, (k + 2 - side) % 3]  # r p, then q r
        e2 = face_edges[g, (j + 1 + side) % 3]  # p s, then s q
        if v == in_faces[pf, 0] or v == in_faces[pf, 1] or v == in_faces[pf, 2]:
            continue
        if _boundary_edge(parent, first, second, e1) and _boundary_edge(parent, first, second, e2):
            return True
    return False


@njit(cache=True)
def flip_to_match(pts, tets, nbr, vt, faces, parent, in_faces, ends, axis, face_edges, n_edges, missing):
    r"""Flip pairs of subfaces of one input face to the diagonal the tetrahedralization has.

    A missing subface f and its neighbour g across an edge p q interior to their input face
    form a quadrilateral r p s q (r, s the apices); when the tetrahedralization has the edge
    r s and both faces r p s and r s q, the pair becomes those two (orientation kept)::

            p                   p
           /|\                 / \
          / | \               /   \
         r  f|g  s    ==>     r-----s
          \ | /               \   /
           \|/                 \ /
            q                   q

    Cocircular points (a rectangle split on one diagonal, the midpoint of a right triangle's
    hypotenuse) leave the choice of diagonal to the symbolic perturbation; matching it needs
    no new point, where splitting would recreate the tie at every scale.

    Parameters
    ----------
    pts : (nv, 3) float64
    tets, nbr : (nt, 4) int32
    vt : (nv,) int32
    faces : (m, 3) int32
        Modified in place.
    parent : (m,) int32
    in_faces : (p, 3) int32
        The input faces (their corners may join a flipped edge).
    ends : (nv, 2) int32
        The edge each Steiner vertex was created on (:class:`SplitOrigins`), -1 else.
    axis : (p,) int64
        :func:`dominant_axes` of the input faces: convexity of r p s q is decided by exact
        ``orient2d`` on the face's projection (a float test let a vertex lying on the new
        diagonal by round-off through, and its degenerate face was split at that vertex).
    face_edges : (m, 3) int64
        Edge ids as :func:`unique_edges` gives (stale after a flip: one flip per face).
    n_edges : int
    missing : (m,) bool

    Returns
    -------
    int
        Number of flips.
    """
    nt = tets.shape[0]
    stamp = np.zeros(nt, dtype=np.int32)
    queue = np.empty(nt, dtype=np.int32)
    first, second = _edge_faces(face_edges, n_edges)
    touched = np.zeros(faces.shape[0], dtype=np.bool_)
    gen = 0
    flips = 0
    for f in range(faces.shape[0]):
        if not missing[f] or touched[f]:
            continue
        for k in range(3):
            e = face_edges[f, k]
            h = second[e] if first[e] == 3 * f + k else first[e]
            if h < 0:
                continue
            g = h // 3
            j = h % 3
            if touched[g] or parent[g] != parent[f]:
                continue
            r = faces[f, k]
            p = faces[f, (k + 1) % 3]
            q = faces[f, (k + 2) % 3]
            s = faces[g, j]
            ax = axis[parent[f]]
            o = _orient_in(pts, ax, r, p, q)
            if o == 0.0 or o * _orient_in(pts, ax, r, p, s) <= 0.0 or o * _orient_in(pts, ax, r, s, q) <= 0.0:
                continue  # r p s q not strictly convex: the flipped pair would fold or degenerate
            if _folds_onto_edge(faces, parent, in_faces, ends, face_edges, first, second, f, k, g, j):
                continue
            gen += 1
            if _star_search(tets, nbr, vt, stamp, queue, gen, r, s, -1) < 0:
                continue
            gen += 1
            if _star_search(tets, nbr, vt, stamp, queue, gen, r, p, s) < 0:
                continue
            gen += 1
            if _star_search(tets, nbr, vt, stamp, queue, gen, r, s, q) < 0:
                continue
            faces[f, 0], faces[f, 1], faces[f, 2] = r, p, s
            faces[g, 0], faces[g, 1], faces[g, 2] = r, s, q
            touched[f] = True
            touched[g] = True
            flips += 1
            break
    return flips


@njit(cache=True)
def lawson_pass(pts, faces, parent, in_faces, ends, axis, face_edges, n_edges, kept):
    r"""One pass of Lawson's edge flips toward the 2-D Delaunay triangulation of each input face.

    The subfaces of an input face are flipped, pair by pair (each face at most once per
    pass), where the apex s of the neighbour lies strictly inside the circumcircle of r p q
    and r p s q is strictly convex, decided by exact ``orient2d`` / ``incircle`` on the
    face's projection along its dominant normal axis (a consistent planar point set even
    where Steiner points are off the plane by round-off).  Longest-edge bisection alone
    leaves needles whose circumcircles hold the next row of points; on a nearly planar
    wall, every split then made another missing subface (a cascade to the guard).

    Parameters
    ----------
    pts : (nv, 3) float64
    faces : (m, 3) int32
        Modified in place.
    parent : (m,) int32
    in_faces : (p, 3) int32
        The input faces.
    ends : (nv, 2) int32
        :class:`SplitOrigins` of the vertices.
    axis : (p,) int64
        Dominant normal axis of each input face.
    face_edges : (m, 3) int64
        As :func:`unique_edges` gives.
    n_edges : int
    kept : (K, 4) int64
        Sorted vertex quadruples, rows in lexicographic order: a pair of subfaces on one of
        them is not flipped (the flat tets :func:`meshwright.tet.mesher` moved out of the
        solid by taking the other diagonal; flipping back undid that every round).

    Returns
    -------
    int
        Number of flips.
    """
    first, second = _edge_faces(face_edges, n_edges)
    touched = np.zeros(faces.shape[0], dtype=np.bool_)
    flips = 0
    for f in range(faces.shape[0]):
        if touched[f]:
            continue
        ax = axis[parent[f]]
        i = (ax + 1) % 3
        j = (ax + 2) % 3
        for k in range(3):
            e = face_edges[f, k]
            h = second[e] if first[e] == 3 * f + k else first[e]
            if h < 0:
                continue
            g = h // 3
            if touched[g] or parent[g] != parent[f]:
                continue
            r = faces[f, k]
            p = faces[f, (k + 1) % 3]
            q = faces[f, (k + 2) % 3]
            s = faces[g, h % 3]
            o = _orient_in(pts, ax, r, p, q)
            if o == 0.0:
                continue
            sg = 1.0 if o > 0.0 else -1.0
            if sg * _orient_in(pts, ax, r, p, s) <= 0.0 or sg * _orient_in(pts, ax, r, s, q) <= 0.0:
                continue
            if sg * incircle(pts[r, i], pts[r, j], pts[p, i], pts[p, j], pts[q, i], pts[q, j], pts[s, i], pts[s, j]) <= 0.0:
                continue
            if _folds_onto_edge(faces, parent, in_faces, ends, face_edges, first, second, f, k, g, h % 3):
                continue
            if kept.shape[0] and _is_kept(kept, r, p, q, s):
                continue
            faces[f, 0], faces[f, 1], faces[f, 2] = r, p, s
            faces[g, 0], faces[g, 1], faces[g, 2] = r, s, q
            touched[f] = True
            touched[g] = True
            flips += 1
            break
    return flips


@njit(cache=True)
def _is_kept(kept, r, p, q, s):
    """Whether the sorted quadruple of r, p, q, s is a row of ``kept`` (binary search)."""
    row = np.array([r, p, q, s], dtype=np.int64)
    row.sort()
    lo = 0
    hi = kept.shape[0]
    while lo < hi:
        mid = (lo + hi) // 2
        c = 0
        while c < 4 and kept[mid, c] == row[c]:
            c += 1
        if c == 4:
            return True
        if kept[mid, c] < row[c]:
            lo = mid + 1
        else:
            hi = mid
    return False


def lawson(pts: np.ndarray, faces: np.ndarray, parent: np.ndarray, in_faces: np.ndarray, ends: np.ndarray, axis: np.ndarray, kept=None) -> int:
    """:func:`lawson_pass` until no flip is left (at most :data:`LAWSON_PASSES`); total flips.

    ``faces`` is modified in place.  The cap only bounds the work: Lawson's flips terminate,
    and subfaces still missing afterwards are split.  ``kept``: quadruples not to flip
    (:func:`lawson_pass`), an iterable of 4 vertex ids each.
    """
    kept = _kept_rows(kept)
    total = 0
    for _ in range(LAWSON_PASSES):
        _, face_edges = unique_edges(faces)
        n = lawson_pass(pts, faces, parent, in_faces, ends, axis, face_edges, int(face_edges.max()) + 1, kept)
        total += n
        if n == 0:
            break
    return total


def _kept_rows(kept) -> np.ndarray:
    """(K, 4) int64 sorted quadruples in lexicographic row order, from an iterable of 4 ids."""
    rows = np.sort(np.array(sorted(kept or ()), dtype=np.int64).reshape(-1, 4), axis=1)
    return np.ascontiguousarray(rows[np.lexsort(rows.T[::-1])])


def dominant_axes(points: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Coordinate axis of the largest normal component of each input face; (p,) int64."""
    p = points[faces]
    n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    return np.argmax(np.abs(n), axis=1).astype(np.int64)


def unique_edges(faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Undirected edges of a triangulation and each face's edge ids.

    Parameters
    ----------
    faces : (m, 3) int32

    Returns
    -------
    edges : (e, 2) int32
        Sorted vertex pairs, in increasing (low, high) order.
    face_edges : (m, 3) int64
        ``face_edges[f, k]`` is the edge opposite corner k of face f.
    """
    if faces.shape[0] == 0:
        return np.zeros((0, 2), dtype=np.int32), np.zeros((0, 3), dtype=np.int64)
    return _unique_edges(np.ascontiguousarray(faces, dtype=np.int32), int(faces.max()) + 1)


@njit(cache=True)
def _unique_edges(faces, n):
    """:func:`unique_edges` by distribution counting on the low vertex, then insertion sort
    of each low vertex's few high vertices (Knuth, TAOCP vol. 3, 5.2): the order of
    ``np.unique`` on the keys ``low * n + high`` (its argsort of 3 m keys was 8 ms a call,
    66 calls in the level-5 sphere's run)."""
    m = faces.shape[0]
    start = np.zeros(n + 1, dtype=np.int64)
    for f in range(m):
        for k in range(3):
            a = faces[f, (k + 1) % 3]
            b = faces[f, (k + 2) % 3]
            start[min(a, b) + 1] += 1
    for v in range(n):
        start[v + 1] += start[v]
    fill = start[:n].copy()
    hi = np.empty(3 * m, dtype=np.int64)
    half = np.empty(3 * m, dtype=np.int64)  # 3 f + k of each slot
    for f in range(m):
        for k in range(3):
            a = faces[f, (k + 1) % 3]
            b = faces[f, (k + 2) % 3]
            lo = min(a, b)
            p = fill[lo]
            hi[p] = max(a, b)
            half[p] = 3 * f + k
            fill[lo] += 1
    face_edges = np.empty((m, 3), dtype=np.int64)
    edges = np.empty((3 * m, 2), dtype=np.int32)
    ne = 0
    for v in range(n):
        lo_p = start[v]
        hi_p = start[v + 1]
        for p in range(lo_p + 1, hi_p):
            x = hi[p]
            y = half[p]
            q = p - 1
            while q >= lo_p and hi[q] > x:
                hi[q + 1] = hi[q]
                half[q + 1] = half[q]
                q -= 1
            hi[q + 1] = x
            half[q + 1] = y
        for p in range(lo_p, hi_p):
            if p == lo_p or hi[p] != hi[p - 1]:
                edges[ne, 0] = v
                edges[ne, 1] = hi[p]
                ne += 1
            face_edges[half[p] // 3, half[p] % 3] = ne - 1
    return edges[:ne].copy(), face_edges


def recover(tz, faces: np.ndarray, parent: np.ndarray, guard: float, max_points: int, in_faces: np.ndarray, axis: np.ndarray, origins, rounds: int = RECOVERY_ROUNDS, kept=None, hint=None, n_apex: int = 0):
    """Split missing subfaces until every one is a face of the tetrahedralization ``tz``.

    Parameters
    ----------
    tz : Tetrahedralization
        Holds every vertex of ``faces``; points are inserted into it.
    faces : (m, 3) int32
    parent : (m,) int32
    guard : float
        Shortest edge that may be split.
    max_points : int
        Cap on the vertices of ``tz``.
    in_faces : (p, 3) int32
        The input faces.
    axis : (p,) int64
        :func:`dominant_axes` of the input faces.
    origins : SplitOrigins
        Updated with the midpoints inserted.
    rounds : int
    kept : iterable of 4 vertex ids, optional
        Quadruples whose subface pair :func:`lawson` leaves as it is.
    hint : (m,) int64, optional
        Where each face was last found (:func:`find_faces`).
    n_apex : int
        Vertices below this id (the input's) are the centres of the concentric shells that
        edges at them are split on (:func:`shell_points`).

    Returns
    -------
    faces, parent, where : the recovered subfaces and :func:`find_faces` of each.
    """
    faces = np.array(faces, dtype=np.int32)  # flips change it in place
    lawson(tz.points, faces, parent, in_faces, origins.view(tz.points.shape[0]), axis, kept)
    splits = 0
    hint = np.zeros(0, dtype=np.int64) if hint is None else hint
    vt = None
    for _ in range(8 * rounds):
        if vt is None:  # the tets changed (flip_to_match flips subfaces only)
            tets = tz.tetrahedra
            nbr = tz.neighbors
            vt = vertex_tets(tets, tz.points.shape[0])
        where = find_faces(tets, nbr, vt, faces, hint)
        hint = where
        missing = where < 0
        if not missing.any():
            return faces, parent, where
        edges, face_edges = unique_edges(faces)
        if flip_to_match(tz.points, tets, nbr, vt, faces, parent, in_faces, origins.view(tz.points.shape[0]), axis, face_edges, edges.shape[0], missing):
            continue
        splits += 1
        if splits > rounds:
            break
        mark = ~find_edges(tets, nbr, vt, edges)
        pts = tz.points
        lonely = missing & ~mark[face_edges].any(axis=1)
        for f in np.flatnonzero(lonely):
            mark[face_edges[f, _longest(pts, faces, face_edges, f)]] = True
        short = mark & (np.linalg.norm(pts[edges[:, 0]] - pts[edges[:, 1]], axis=1) < guard)
        if short.any():
            e = int(np.flatnonzero(short)[0])
            a, b = edges[e]
            raise MeshingError(
                f"boundary recovery needs to split the edge {fmt_point(pts[a])} - {fmt_point(pts[b])} "
                f"shorter than {guard:.3g}: " + _why_short(pts, in_faces, pts[a], 256.0 * guard)
            )
        if tz.points.shape[0] + int(mark.sum()) > max_points:
            raise_cap(max_points, "boundary recovery")
        faces, parent, _, same = bisect_marked(pts, faces, parent, edges, face_edges, mark, lambda p: insert_new(tz, p), origins, n_apex)
        hint = np.where(same >= 0, where[np.maximum(same, 0)], -1)
        vt = None
        lawson(tz.points, faces, parent, in_faces, origins.view(tz.points.shape[0]), axis, kept)
    f = int(np.flatnonzero(missing)[0])
    raise MeshingError(
        f"boundary recovery did not converge in {rounds} rounds: subface {fmt_point(tz.points[faces[f, 0]])}, "
        f"{fmt_point(tz.points[faces[f, 1]])}, {fmt_point(tz.points[faces[f, 2]])} is still missing"
    )


SHARP_DIHEDRAL = 30.0  # degrees: a wedge this sharp at a cascade is named in the error


def _why_short(pts: np.ndarray, in_faces: np.ndarray, p: np.ndarray, near: float) -> str:
    """Why recovery cascaded to point ``p`` (3,): the sharp input edge it sits at, if any.

    The input edge nearest ``p`` (within ``near``) whose two faces meet at less than
    :data:`SHARP_DIHEDRAL` degrees (the angle between their half-planes, on either side) is
    named with its angle: near such an edge each face's Steiner points fall in the empty
    spheres of the other's subfaces, and presence-based conforming recovery splits on to the
    guard (an extruded star's 6-degree notch, fuzz seed 21 case 18).  Else the general cause.
    """
    edges, face_edges = unique_edges(in_faces)
    a = pts[edges[:, 0]]
    d = pts[edges[:, 1]] - a
    t = np.clip(np.einsum("ij,ij->i", p - a, d) / np.einsum("ij,ij->i", d, d), 0.0, 1.0)
    dist = np.linalg.norm(a + t[:, None] * d - p, axis=1)
    e = int(np.argmin(dist))
    two = np.flatnonzero((face_edges == e).any(axis=1))
    if dist[e] <= near and two.size == 2:
        side = []
        for f in two:
            c = pts[[v for v in in_faces[f] if v not in edges[e]][0]] - a[e]
            side.append(c - (c @ d[e]) / (d[e] @ d[e]) * d[e])  # the face's half-plane, across the edge
        cos = side[0] @ side[1] / (np.linalg.norm(side[0]) * np.linalg.norm(side[1]))
        angle = float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))
        if angle < SHARP_DIHEDRAL:
            return (
                f"it lies at the input edge {fmt_point(pts[edges[e, 0]])} - {fmt_point(pts[edges[e, 1]])}, where two "
                f"input faces meet at {angle:.2f} degrees: this presence-based conforming recovery does not separate "
                "faces at so sharp a dihedral angle (a known limit; open the wedge or cut it off)"
            )
    return "the surface has features closer than its faces allow (faces nearly touching, or a needle face next to a large one)"


class SplitOrigins:
    """The edge (a, b) each Steiner vertex was created on, (-1, -1) for other vertices.

    A growable (nv, 2) int32 table: flips consult it so as never to join the ends of a split
    edge across its midpoint (a face that is degenerate but for round-off).
    """

    def __init__(self, nv: int):
        self._ends = np.full((max(nv, 1), 2), -1, dtype=np.int32)

    def record(self, ids: np.ndarray, edges: np.ndarray) -> None:
        """Vertices ``ids`` (k,) were created on ``edges`` (k, 2)."""
        self.view(int(ids.max()) + 1)[ids] = edges

    def view(self, nv: int) -> np.ndarray:
        """The table's first ``nv`` rows, (nv, 2) int32, grown by doubling when needed."""
        if nv > self._ends.shape[0]:
            grown = np.full((max(nv, 2 * self._ends.shape[0]), 2), -1, dtype=np.int32)
            grown[: self._ends.shape[0]] = self._ends
            self._ends = grown
        return self._ends[:nv]


def insert_new(tz, points: np.ndarray) -> np.ndarray:
    """Insert points that must all be new vertices of ``tz``; (k,) int32 their ids."""
    before = tz.points.shape[0]
    ids = tz.insert(points)
    old = np.flatnonzero(ids < before)
    if old.size:
        i = int(old[0])
        raise MeshingError(f"a Steiner point {fmt_point(points[i])} coincides with vertex {int(ids[i])}")
    return ids


def raise_cap(max_points: int, stage: str):
    """Raise the :class:`SizeError` of a mesh that would exceed ``max_points`` vertices."""
    from meshwright.core.errors import SizeError

    raise SizeError(
        f"{stage} needs more than max_points={max_points} vertices; raise max_points or give a larger size"
    )
