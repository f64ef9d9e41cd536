r"""Numba kernel of Zhu's pair-by-pair advancing front (see :mod:`meshwright.quad.zhu`).

Source: J. Z. Zhu, O. C. Zienkiewicz, E. Hinton and J. Wu, "A new approach to the
development of automatic quadrilateral mesh generation", Int. J. Numer. Meth. Eng. 32,
1991, as summarised in section 18.5.1 of the reference chapter (steps 1-9): the advancing
front makes a triangle ABC on an active side AB, then at once a second triangle on one of
ABC's active sides, the two forming a quadrilateral, every sub-front kept even.

Parity by colours
-----------------
The chapter keeps the number of active sides of every sub-front even: a split by an
existing node C leaves one sub-front odd (5(c)) and the second triangle must take its base
there, and its apex must leave no odd sub-front (6).  Here that count is never walked: every
front node carries a colour 0 / 1 fixed for its lifetime (``col``), and every front side
joins two nodes of different colours (the front is properly two-coloured; the initial
front is, when every loop of the boundary is even).  A closed loop of such sides has an
even length, so every sub-front is even whatever splits or merges happen.  A quadrilateral
ABCD made of ABC and its partner alternates colours, so its diagonal joins two nodes of the
same colour: with ``col[C] == col[A]`` the second triangle lies on side A C (the chapter's
odd sub-front of 5(c) is the one holding A C: the front path from C back to A has an even
length), with ``col[C] == col[B]`` on side C B, and a new node C may take either colour
(5(a)-(b): any active side).  The second triangle's apex D must have the colour of the
opposite corner (a node of the other colour would close an odd sub-front, 6), or be new.
So the parity rule is two table reads per candidate, and it costs nothing on splits.

Node placement (steps 2 and 6, 7): the triangle front's equilateral ideal apex; under a
uniform metric the first apex is a square's corner above B and the second the
parallelogram's fourth corner, so a boundary row comes out as squares (disk h=0.01: mean
scaled Jacobian 0.963 against 0.909 with equilateral apexes, no chord refinement).

Pockets: a pair that would leave a sub-front of four faces whose closing quadrilateral
is not strictly convex at an input node, or has a corner wider than 150 degrees between
input nodes, is not made (:func:`_bad_pocket`; the face tries its next candidate): no
pair could close that pocket, and the triangle front and the matching would close it with
that very quadrilateral, which no smoothing opens at nodes that do not move.
For the same reason no pair itself has a corner at an input node that is reflex or wider
than 168 degrees (:func:`_bent_input`), in any round.

Both triangles are tested before either is made: the second one on the *virtual* face of
the first (A -> C or C -> B), against the front as it is.  That is exact: the second
triangle lies in the closed half-plane left of its base, the first triangle (and with it
the face A -> B and any face the first closes) in the closed half-plane to the right, so no
face the first triangle adds or removes can meet the second, and no node of the first lies
inside the second.  Every decision is the front's exact validity test
(:func:`meshwright.tri._front_kernel._valid`: ``orient2d``, crossings, nodes inside).

State: the triangle front's :class:`~meshwright.tri._front_kernel.FrontState` (layout
there) and two arrays of this kernel::

    col    (pcap,) int8   colour of each node, -1 until it joins the front
    tpair  (tcap,) int8   1 where triangle t is the first of a pair with t + 1

A face with no admissible pair is postponed (``P_MAX_DEFER`` times; its last try searches
four times as far and adds a round that asks validity only, as the triangle front's does,
but takes no apex farther than :data:`FAR` rho from the base, nor the far ends of the faces
the box meets: a colour-restricted face took far nodes there, slivers across a graded
field), then given up until every other face has been tried, then left (``F_TRIES =
LEFT``, off the heap, still on the front) for the caller to close
(:mod:`meshwright.quad.zhu`).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.borrowed import borrowed
from meshwright.core.errors import MeshingError
from meshwright.core.spatial.cell_quadtree import Q_DEPTH, Q_NODES, Q_ROOM, STACK_PER_LEVEL
from meshwright.quad._pairing_kernel import corner_flat
from meshwright.tri._front_kernel import (
    F_A,
    F_B,
    F_NEXT,
    F_TRIES,
    M_FAIL,
    M_NF,
    M_NIN,
    M_NH,
    M_NP,
    M_NT,
    M_NW,
    M_STEPS,
    M_SYNC,
    P_CLEAR_E,
    P_DEFER,
    P_LONG,
    P_MAX_DEFER,
    P_MAX_POINTS,
    P_QMIN,
    P_SYNC_EVERY,
    P_UNIFORM,
    P_WAIT,
    R_DONE,
    R_POINTS,
    R_ROOM,
    R_STEPS,
    R_SYNC,
    ROOM_FACES,
    V_FACE,
    _find_face,
    _gather,
    _make_triangle,
    _orient,
    _quality,
    _to_metric,
    _valid,
    heap_push,
    pop_ready,
)

__all__ = ["FAR", "FLAT", "LEFT", "R_PAUSE", "colour_nodes", "new_scratch", "zhu_advance"]

LEFT = -1  # F_TRIES of a face the pair front left to the triangle front
FAR = 2.5  # no apex farther than FAR rho (metric) from a base end
FLAT = 1e-6  # no existing apex whose triangle's quality (metric) is below this: flat to round-off
WIDE_SINE = 0.2079  # sin 12 degrees: no pair's corner at an input node is wider than 168
R_PAUSE = 6  # the triangle count reached the caller's max_tris (R_* codes of the front kernel otherwise)


@njit(cache=True)
def colour_nodes(start, dst, col):
    """Breadth-first two-colouring of a graph in compressed rows, in place.

    Parameters
    ----------
    start : (n + 1,) int64
        Node ``v``'s neighbours are ``dst[start[v]:start[v + 1]]``.
    dst : (m,) int64
    col : (n,) int8
        -1 on entry; on return every node with a neighbour has 0 or 1: the smallest node of
        each connected piece 0, every other node the other colour than the node that reached
        it first.  Whether the colouring is proper is the caller's check.

    Each node enters the queue once, so the loop is bounded by ``n + m`` steps.
    """
    n = start.shape[0] - 1
    queue = np.empty(n, dtype=np.int64)
    for root in range(n):
        if col[root] >= 0 or start[root + 1] == start[root]:
            continue
        col[root] = 0
        queue[0] = root
        head, tail = 0, 1
        while head < tail:
            v = queue[head]
            head += 1
            for k in range(start[v], start[v + 1]):
                w = dst[k]
                if col[w] < 0:
                    col[w] = 1 - col[v]
                    queue[tail] = w
                    tail += 1


@njit(inline="always")
def _trial(i, nc, n_close, p, p_ok, cand, pts, par, rho, l11, l21, l22, u0, u1, a):
    """The apex tried ``i``-th (the triangle front's order: close nodes making a good, not
    over-long triangle, the ideal point, then every candidate in list order) and the new
    sides' clearance of that round; -1 to skip.  Rounds after the first ask validity only."""
    per = nc + n_close + 1
    clear = par[P_CLEAR_E] * rho
    if i >= per:
        # The second round (i < 2 per): a subtraction, not a 64-bit division per trial.
        clear = 0.0
        i -= per
    if i == n_close:
        return (np.int64(p) if p_ok else np.int64(-1)), clear
    close = i < n_close
    c = np.int64(cand[i if close else i - n_close - 1])
    # One metric transform, reach and quality for both kinds of candidate (each copy is
    # typed and lowered again: issue 13).  A close node must make a good triangle with
    # sides of at most LONG rho.  A list node may reach FAR rho: the last try's wider box
    # may hold far nodes, and a pair reaching one would span a graded field (slivers across
    # it); such a face is left to the triangle front instead.  Validity alone admits a node
    # on the base's line up to round-off, the next node of a straight boundary whose split
    # points lie a few ulps inside it; such a triangle pairs into a quad with a straight
    # corner (stress-zhu-6fde022a69d2 graded: fans of 1e-9 .. 1e-12 degree triangles from
    # one boundary node, min SJ 0.003), hence the FLAT floor.
    qx, qy = _to_metric(l11, l21, l22, pts[c, 0] - pts[a, 0], pts[c, 1] - pts[a, 1])
    reach = (par[P_LONG] if close else FAR) * rho
    if max(qx * qx + qy * qy, (qx - u0) ** 2 + (qy - u1) ** 2) > reach * reach or _quality(
        0.0, 0.0, u0, u1, qx, qy
    ) < (par[P_QMIN] if close else FLAT):
        return np.int64(-1), clear
    return c, clear


@njit(inline="always")
def _convex(pts, q):
    """Quadrilateral q (four nodes) strictly convex (exact)."""
    for k in range(4):
        if _orient(pts, q[(k + 3) % 4], q[k], q[(k + 1) % 4]) <= 0.0:
            return False
    return True


@njit(inline="always")
def _flat_input(pts, nin, q):
    """Whether quadrilateral q (four nodes) has a corner wider than 150 degrees at an input
    node whose two neighbours in it are input nodes too (a quality rule)."""
    for k in range(4):
        v = q[k]
        prv = q[(k + 3) % 4]
        nxt = q[(k + 1) % 4]
        if v < nin and prv < nin and nxt < nin and corner_flat(pts, prv, v, nxt):
            return True
    return False


@njit(inline="always")
def _bent_input(pts, nin, q):
    """Whether quadrilateral q (four nodes) has a corner at an input node that is not
    strictly convex (exact ``orient2d``) or wider than 168 degrees (sine below
    :data:`WIDE_SINE` on the obtuse side, a quality rule), whatever its neighbours.

    Input nodes stay on their curves, so smoothing barely opens such a corner; the pair
    front's last round, which takes reflex corners elsewhere, made them (stress seed
    15001 domain 68: a reflex pair at a segment's node, min SJ 0.10 after smoothing).
    """
    for k in range(4):
        v = q[k]
        if v < nin:
            prv = q[(k + 3) % 4]
            nxt = q[(k + 1) % 4]
            if _orient(pts, prv, v, nxt) <= 0.0:
                return True
            ux = pts[nxt, 0] - pts[v, 0]
            uy = pts[nxt, 1] - pts[v, 1]
            wx = pts[prv, 0] - pts[v, 0]
            wy = pts[prv, 1] - pts[v, 1]
            span = np.sqrt((ux * ux + uy * uy) * (wx * wx + wy * wy))
            if ux * wx + uy * wy < 0.0 and ux * wy - uy * wx < WIDE_SINE * span:
                return True
    return False


@njit(inline="always")
def _next_after(x, q, gone, f, vint, face, falive, np_):
    """The node after x on the front as it would be once quad ``q`` (four nodes,
    counter-clockwise, on face f = q[0] -> q[1]) is made; -1 when x would start no face or
    more than one (a pinch point, where the loop through x is not one path).

    The quad's side q[k] -> q[k+1] (k = 1, 2, 3) fills the live front face of the same
    direction (bit k of ``gone``) or else adds its reverse q[k+1] -> q[k] to the front, as
    :func:`~meshwright.tri._front_kernel._make_triangle` does for each of the two triangles.
    """
    nxt = np.int64(-1)
    count = 0
    g = vint[x, V_FACE] if x < np_ else -1  # a new node starts no face yet (np_: the node count)
    while g >= 0:
        if falive[g] != 0 and g != f:
            y = np.int64(face[g, F_B])
            filled = False
            for k in range(1, 4):
                if (gone >> k) & 1 and q[k] == x and q[(k + 1) % 4] == y:
                    filled = True
            if not filled:
                nxt = y
                count += 1
        g = face[g, F_NEXT]
    for k in range(1, 4):
        if not (gone >> k) & 1 and q[(k + 1) % 4] == x:
            nxt = q[k]
            count += 1
    return nxt if count == 1 else np.int64(-1)


@njit(cache=True)
def _bad_pocket(pts, vint, face, falive, np_, nin, f, q):
    """Whether making quad ``q`` (four nodes, counter-clockwise, on face f = q[0] -> q[1])
    would leave a sub-front of four faces with a corner at an input node that is not
    strictly convex (exact ``orient2d``), or wider than 150 degrees between two input
    nodes (:func:`_flat_input`, the rule the pairs themselves obey).

    No admissible pair closes such a pocket (its one closing quadrilateral), so the
    triangle front would fill it and the matching pair its two triangles into that
    quadrilateral; input nodes never leave their curves and a corner of the domain never
    moves, so no smoothing opens it, and a non-convex one is cut back into two triangles
    whose chords leave slivers (letter_a.poly at its acute notch: min scaled Jacobian
    0.094).  A pocket bad only at generated nodes is allowed: smoothing moves those.
    Pinch points are not followed (such a loop is not judged).

    ``np_``: the node count (new corners are ``>= np_``), ``nin``: the input nodes'.  A
    compiled call, not inlined: the kernel needs it only where the quad has an existing
    free corner, and its inlined body (with its copies of _find_face, _next_after and
    _flat_input) was about a tenth of the kernel's IR statements (issue 13).
    """
    if q[2] >= np_ and q[3] >= np_:
        # Two new corners (the common case): the front gains the path q0 q3 q2 q1 in
        # place of one face, so its loop grows and no other loop changes.
        return False
    gone = 0
    for k in range(1, 4):
        if q[k] < np_ and _find_face(q[k], q[(k + 1) % 4], vint, face, falive) >= 0:
            gone |= 1 << k
    # A loop the pair changes passes through a corner of the quad: it holds a face the
    # pair adds, or a corner whose other face the pair fills (a pinch point resolved).
    for k in range(4):
        # The loop x0 x1 x2 x3 back to x0, walked by one inlined copy of _next_after.
        x0 = q[k]
        x1 = x2 = x3 = np.int64(-1)
        x = x0
        four = False
        for step in range(4):
            x = _next_after(x, q, gone, f, vint, face, falive, np_)
            if step == 3:
                four = x == x0
            elif x < 0 or (step >= 1 and x == x0) or (step == 2 and x == x1):
                break
            elif step == 0:
                x1 = x
            elif step == 1:
                x2 = x
            else:
                x3 = x
        if not four:
            continue
        loop = (x0, x1, x2, x3)
        if _flat_input(pts, nin, loop):
            return True
        for m in range(4):
            v = loop[m]
            if v < nin and _orient(pts, loop[(m + 3) % 4], v, loop[(m + 1) % 4]) <= 0.0:
                return True
    return False


@njit(inline="always")
def _try_pair(f, fs, par, col, tpair, items, nodes, cand, ckey, items2, nodes2, cand2, ckey2, stack, fstack):
    """Advance face f by one quadrilateral (steps 1-9) if any admissible pair exists.

    Two searches, nested: for each admissible first apex C of the triangle on f = A -> B,
    each admissible base of the second triangle (step 5: the side of ABC joining two nodes
    of one colour) and each apex D on it (step 6).  They are written as one loop over the
    search ``lvl`` (0: C, 1: D) with a single call of the candidate search, of the trial
    order and of the validity test, so that the kernel holds one inlined copy of each
    (the nested form held two: the largest part of this kernel's compile time, and a
    compiled call in place of the second costs run time).  ``g*`` are the current level's
    search and its results; the first level's results are ``kept`` and its arrays swapped
    into the second set (``items2`` ...) while the second runs, so that every call reads
    one set of variables, not a selection by level per argument.  The two sets are alike
    scratch: they may come back in either order.

    Returns ``(ok, items, nodes, cand, ckey, items2, nodes2, cand2, ckey2)``.
    """
    pts, met, face, qbox, meta = fs.pts, fs.met, fs.face, fs.qbox, fs.meta
    nin = meta[M_NIN]
    a = np.int64(face[f, F_A])
    b = np.int64(face[f, F_B])
    last = face[f, F_TRIES] >= par[P_MAX_DEFER]
    p = meta[M_NP]
    uniform = par[P_UNIFORM] != 0.0
    # Under a uniform metric the first triangle's ideal apex is a square's corner above B
    # and the second's the parallelogram's fourth corner: rows of squares.  A graded field
    # keeps the triangle front's equilateral apex (squares there met the far field's
    # elements at corners of 175 degrees on the airfoils, min SJ 0.05).
    shape = np.int64(-2) if uniform else np.int64(-1)
    rounds = 2 if last else 1
    zero = np.int64(0)
    gni, gnn, gnc, gclose, gok, grho, g11, g21, g22, gu0, gu1 = zero, zero, zero, zero, False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    kept = (gni, gnn, gnc, gclose, gok, grho, g11, g21, g22, gu0, gu1)
    lvl = 0
    ga, gb, gp, gf, gshape, gwant = a, b, p, np.int64(f), shape, np.int64(-1)
    fresh = True  # the level's candidates are still to be gathered
    i = zero  # next trial of the level
    fi = zero  # the first level's next trial, kept while the second runs
    total = zero
    side = 2  # no first apex yet: no base to try
    c = u = w = o = p2 = want = np.int64(-1)
    cu = np.int8(0)
    px = py = clear = 0.0
    ok = False
    # Bounded: each pass takes the level's next trial (at most rounds * (nc + n_close + 1)
    # a level), or moves to the next base (two per first apex), or ends the search.
    while True:
        if fresh:
            fresh = False
            gni, gnn, gnc, gclose, gok, grho, g11, g21, g22, gu0, gu1, gitems, gnodes, gcand, gckey = _gather(
                ga, gb, gf, gp, gshape, last, False, fs, par, col, gwant, items, nodes, cand, ckey, stack, fstack
            )
            # _gather hands back its scratch arrays unless it outgrew one (then a larger one
            # of its own).  new_scratch leaves room for every face, so that never happens,
            # and the search keeps the caller's borrowed arrays: loop-carried arrays that
            # might be the kernel's own cost reference-count calls on every trial (issue 12).
            if (
                gitems.shape[0] != items.shape[0]
                or gnodes.shape[0] != nodes.shape[0]
                or gcand.shape[0] != cand.shape[0]
                or gckey.shape[0] != ckey.shape[0]
            ):
                raise MeshingError("pair front: a candidate search outgrew its scratch arrays")
            if lvl == 0:
                px = pts[p, 0]
                py = pts[p, 1]
            i = zero
            total = rounds * (gnc + gclose + 1)
        x = np.int64(-1)
        if i < total:
            x, clear = _trial(i, gnc, gclose, gp, gok, cand, pts, par, grho, g11, g21, g22, gu0, gu1, ga)
            i += 1
        next_base = False
        if x < 0:
            if i < total:
                continue
            if lvl == 0:
                break
            next_base = True  # no apex D on this base
        else:
            if lvl == 0 and x == p:
                # The second triangle's search wrote its own ideal point; this one is the first's.
                pts[p, 0] = px
                pts[p, 1] = py
            # The quad is u o w x (o right of u -> w); its corners at u and w may be reflex,
            # which the chapter allows (step 8) but only in the last round here.  A corner
            # between two input nodes wider than 150 degrees is never made, nor one at an input
            # node that is reflex or wider than 168 degrees: they barely move, so no smoothing
            # would open it (the face tries its next pair, else is left to the triangle front).
            if lvl == 1 and (
                (clear > 0.0 and not _convex(pts, (u, o, w, x)))
                or _flat_input(pts, nin, (u, o, w, x))
                or _bent_input(pts, nin, (u, o, w, x))
            ):
                continue
            if not _valid(pts, face, qbox, ga, gb, x, gf, items, gni, nodes, gnn, clear, g11, g21, g22):
                continue
            if lvl == 0:
                c = x
                p2 = p + 1 if c == p else p
                if c == p:
                    for k in range(3):
                        met[p, k] = met[a, k]
                side = -1
                next_base = True
            else:
                d = x
                dx = pts[d, 0]
                dy = pts[d, 1]
                if c == p:
                    pts[p, 0] = px
                    pts[p, 1] = py
                quad = (a, b, c, d) if side == 0 else (a, b, d, c)
                # (Two new corners, the common case, need no walk: the call is skipped.)
                if (c < p or d < p) and _bad_pocket(pts, fs.vint, face, fs.falive, p, nin, np.int64(f), quad):
                    next_base = True
                else:
                    # Both triangles by one inlined copy of the front's update.
                    for t in range(2):
                        tf_ = np.int64(f)
                        if t == 1:
                            col[c] = cu
                            tf_ = np.int64(_find_face(u, w, fs.vint, face, fs.falive))
                            if d == p2:
                                pts[d, 0] = dx
                                pts[d, 1] = dy
                        _make_triangle(tf_, a if t == 0 else u, b if t == 0 else w, c if t == 0 else d, fs, uniform)
                    if col[d] < 0:
                        col[d] = want
                    tpair[meta[M_NT] - 2] = 1
                    tpair[meta[M_NT] - 1] = 0
                    ok = True
                    break
        if not next_base:
            continue
        # Step 5: the base of the second triangle is the side of ABC joining two nodes of
        # one colour; a new (or uncoloured) C may take either colour, A C tried first.
        side += 1
        if side == 0 and col[c] >= 0 and col[c] != col[a]:
            side = 1
        if side == 1 and col[c] >= 0 and col[c] != col[b]:
            side = 2
        if side < 2:
            if lvl == 0:
                kept = (gni, gnn, gnc, gclose, gok, grho, g11, g21, g22, gu0, gu1)
                fi = i
                items, nodes, cand, ckey, items2, nodes2, cand2, ckey2 = (
                    items2, nodes2, cand2, ckey2, items, nodes, cand, ckey
                )
            u = a if side == 0 else c
            w = c if side == 0 else b
            o = b if side == 0 else a
            cu = col[a] if side == 0 else col[b]
            want = np.int64(1 - cu)
            ga, gb, gp, gf, gshape, gwant = u, w, p2, np.int64(-1), o if c == p and uniform else np.int64(-1), want
            lvl = 1
            fresh = True
        elif lvl == 1:
            # Both bases tried: the first search goes on with its next apex.
            gni, gnn, gnc, gclose, gok, grho, g11, g21, g22, gu0, gu1 = kept
            i = fi
            total = rounds * (gnc + gclose + 1)
            items, nodes, cand, ckey, items2, nodes2, cand2, ckey2 = (
                items2, nodes2, cand2, ckey2, items, nodes, cand, ckey
            )
            ga, gb, gp, gf, gshape, gwant = a, b, p, np.int64(f), shape, np.int64(-1)
            lvl = 0
    return ok, items, nodes, cand, ckey, items2, nodes2, cand2, ckey2


def new_scratch(depth, faces):
    """The kernel's scratch arrays, made by the caller (see :func:`zhu_advance`).

    Parameters
    ----------
    depth : int
        The front's quadtree depth (``fs.qmeta[Q_DEPTH]``).
    faces : int
        The front's face capacity (``len(fs.face)``; make new scratch when it grows).  A
        query returns each live item once, so at most ``faces`` items and twice as many
        nodes and candidates: the search never outgrows these arrays (``np.empty``: pages
        no search reaches are never touched).

    Returns
    -------
    tuple
        ``(items, nodes, cand, ckey, items2, nodes2, cand2, ckey2, stack, fstack)``: for
        each triangle of a pair (faces,) int32 items and (2 faces,) int32 / int32 / float64
        nodes, candidates and keys; the quadtree query's stacks (s,) int64 and (s, 3)
        float64, s = STACK_PER_LEVEL (depth + 2).
    """
    s = STACK_PER_LEVEL * (int(depth) + 2)
    n = 2 * int(faces)
    per_triangle = [(np.empty(n // 2, np.int32), np.empty(n, np.int32), np.empty(n, np.int32), np.empty(n))
                    for _ in range(2)]
    return (*per_triangle[0], *per_triangle[1], np.empty(s, np.int64), np.empty((s, 3)))


@njit(cache=True)
def zhu_advance(fs, par, col, tpair, max_tris, scratch):
    """Run the pair front until it is empty or Python must act; returns an ``R_*`` code of
    :mod:`meshwright.tri._front_kernel` (``R_DONE``: no face left on the heap; faces
    marked ``LEFT`` may remain on the front) or :data:`R_PAUSE`.

    ``col`` (pcap,) int8 and ``tpair`` (tcap,) int8 as in the module docstring, at least
    as long as ``fs.pts`` and ``fs.tri``; ``max_tris``: pause before the triangle count
    would pass it (a caller stepping pair by pair); ``scratch``: :func:`new_scratch`'s
    tuple, which the caller keeps (sized for ``fs``'s faces).  The scratch is the caller's,
    not allocated here: a kernel's own arrays carry a reference count, and every inlined
    helper they are handed to pays an increment and a decrement per array and call
    (``core.borrowed``).
    """
    fs, par, col, tpair, scratch = borrowed(fs), borrowed(par), borrowed(col), borrowed(tpair), borrowed(scratch)
    pts, face, falive, qmeta, qhead, hkey = fs.pts, fs.face, fs.falive, fs.qmeta, fs.qhead, fs.hkey
    hface, wkey, wface, tri, meta = fs.hface, fs.wkey, fs.wface, fs.tri, fs.meta
    items, nodes, cand, ckey, items2, nodes2, cand2, ckey2, stack, fstack = scratch
    depth = qmeta[Q_DEPTH]
    node_room = qmeta[Q_ROOM]
    if (
        stack.shape[0] < STACK_PER_LEVEL * (depth + 2)
        or fstack.shape[0] < STACK_PER_LEVEL * (depth + 2)
        or items.shape[0] < face.shape[0]
    ):
        raise MeshingError("pair front: scratch arrays smaller than new_scratch makes them")
    for i in range(meta[M_NW]):
        if falive[wface[i]]:
            heap_push(hkey, hface, meta, wkey[i], wface[i])
    meta[M_NW] = 0
    wmin = np.inf
    sync_every = int(par[P_SYNC_EVERY])
    max_defer = int(par[P_MAX_DEFER])
    # One return: each return statement exits through its own copy of the IR's variable
    # releases (issue 13).
    code = -1
    while code < 0:
        if (
            meta[M_NP] + 2 > pts.shape[0]
            or meta[M_NF] + ROOM_FACES > face.shape[0]
            or meta[M_NH] + ROOM_FACES > hkey.shape[0]
            or meta[M_NW] + 2 > wface.shape[0]
            or meta[M_NT] + 2 > tri.shape[0]
            or qmeta[Q_NODES] + ROOM_FACES * (node_room + 1) > qhead.shape[0]
        ):
            code = R_ROOM
        elif meta[M_NP] - meta[M_SYNC] >= sync_every:
            code = R_SYNC
        elif meta[M_NP] > par[P_MAX_POINTS]:
            code = R_POINTS
        elif meta[M_STEPS] > 16 * meta[M_NF] + 100_000:
            code = R_STEPS
        elif meta[M_NT] + 2 > max_tris:
            code = R_PAUSE
        if code >= 0:
            continue
        f, key, wmin = pop_ready(fs, wmin, par[P_WAIT])
        if f < 0:
            code = R_SYNC if meta[M_NW] > 0 else R_DONE
            continue
        meta[M_STEPS] += 1
        ok, items, nodes, cand, ckey, items2, nodes2, cand2, ckey2 = _try_pair(
            f, fs, par, col, tpair, items, nodes, cand, ckey, items2, nodes2, cand2, ckey2, stack, fstack
        )
        if ok:
            continue
        tries = face[f, F_TRIES] + 1
        face[f, F_TRIES] = tries
        if tries > max_defer + 1:
            # Left to the triangle front: off the heap, still on the front.
            face[f, F_TRIES] = LEFT
            meta[M_FAIL] = f
            continue
        # Postponed behind every ordinary face (the front around it moves on first), or on
        # its last try given up until every other face has been tried: the pairs made
        # meanwhile may open it (the key stays above any postponed face's).  One inlined
        # heap push for both (issue 13).
        heap_push(hkey, hface, meta, key + (1.0 if tries <= max_defer else 8.0) * par[P_DEFER], f)
    return code
