r"""Quadtree quad meshing (Yerry and Shephard 1984; section 18.5.3 of the reference text).

M. A. Yerry and M. S. Shephard, "Automatic three-dimensional mesh generation by the
modified-octree technique", IJNME 20 (1984) 1965-1990: a box around the domain is split
recursively (parent, sons, grandsons) until every cell is as small as the size field
asks, the tree is 2:1 balanced, exterior cells are removed and the cells along the
boundary are fitted to it.  Here the fit is the robust variant of the chapter's
superposition-deformation (Schneiders' grid-based method, 1996; see
``design-notes-quads.md`` section 4): cells closer to the boundary than ``CLEARANCE``
times their size are removed too, and the gap between the remaining core and the true
boundary is triangulated (:func:`meshwright.triangulate`, Delaunay refinement at
``GAP_MIN_ANGLE``, boundary points on the true curves).  Transition cells (a side with a
hanging node, or a side of the core split by the gap's refinement) become fans of
triangles around their centre.  With ``all_quad`` the tree is built at twice the size and
the midpoint split (:mod:`meshwright.quad.subdivide`) makes every element quads, with the
finish of :mod:`meshwright.quad._quadtree_finish` around it: slivers of thin junction
wedges merged into quads before, split centres moved off bad corners after.  With
``size="boundary"`` on a domain carrying no size the field is the boundary's own spacing,
graded inward (:func:`_boundary_field`).

Invariants: the tree is 2:1 balanced across sides (a leaf's side neighbour is at most one
level finer), so a side has at most one hanging node; the core's outline has no pinched
vertex (cells touching the rest of the core only by a corner are removed); every kept
cell lies inside the domain at a distance of at least ``CLEARANCE`` times its size from
every boundary and interior segment and interior point (which become vertices of the gap).

Array layout of the tree (node 0 is the root; the four sons of a node are consecutive)::

    lev   (cap,) int64   level l of the node (root 0)
    ci,cj (cap,) int64   integer position: the node covers [ci, ci+1) x [cj, cj+1) * L / 2^l
    child (cap,) int64   index of the first son, -1 for a leaf; son q = east + 2 north

Only the level and position are stored, so the same layout serves an octree (three
positions, eight sons) later.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from meshwright.core.errors import InputError, MeshingError
from meshwright.geometry.curves import Polyline
from meshwright.geometry.domain import Domain
from meshwright.geometry._kernels import trace_chains
from meshwright.quad._quadtree_finish import CENTRE_STEPS, merge_slivers, recentre
from meshwright.quad.subdivide import curve_midpoints, split_all
from meshwright.sizing.boundary import boundary_size, gradation, point_distribution
from meshwright.sizing.field import as_size_field
from meshwright.sizing.lfs import DEFAULT_GROWTH

__all__ = [
    "quadtree_fill", "quadtree_stages", "QuadtreeStages", "build_tree", "balance", "CLEARANCE", "GAP_MIN_ANGLE",
    "MAX_LEVEL",
]

MAX_LEVEL = 30  # integer positions stay exact in int64 keys (2 * 30 bits)
CLEARANCE = 0.5  # kept cells are at least this many cell sizes from the boundary
GAP_MIN_ANGLE = 28.0  # degrees: gap triangles split into quads with corner angles above ~25 deg
SAGITTA = 0.03  # largest curve-to-chord-midpoint distance, in segment lengths, before a split
SAGITTA_ROUNDS = 8
SAGITTA_GROWTH = 2.0  # steep: the refinement stays near the curve, away from the core's outline
SPLIT_RATIO = math.sqrt(2.0)  # a cell is split while its side exceeds this times the target size
FINISH_FLOOR = 0.3  # corner sine below which the all-quad finish merges slivers and moves split centres

# Side d of a cell in counter-clockwise order (south, east, north, west): the neighbour's
# offset, the cell's corners at the side's start and end (dx, dy), and the two sons of a
# finer neighbour that touch the side, in the side's direction.
_SIDE_DI = np.array([0, 1, 0, -1])
_SIDE_DJ = np.array([-1, 0, 1, 0])
_CORNER = np.array([[0, 0], [1, 0], [1, 1], [0, 1]])
_HALF_SONS = np.array([[2, 3], [0, 2], [1, 0], [3, 1]])


@njit(cache=True)
def _find(lev, ci, cj, child, level, i, j):
    """The node at ``level`` covering cell (i, j) of that level, or the leaf above it; -1
    outside the root."""
    if i < 0 or j < 0 or i >= (1 << level) or j >= (1 << level):
        return -1
    n = 0
    while child[n] >= 0 and lev[n] < level:
        shift = level - lev[n] - 1
        n = child[n] + ((i >> shift) & 1) + 2 * ((j >> shift) & 1)
    return n


@njit(cache=True)
def _split(lev, ci, cj, child, m, nn):
    """Give leaf ``m`` four sons at nodes nn..nn+3."""
    child[m] = nn
    for q in range(4):
        lev[nn + q] = lev[m] + 1
        ci[nn + q] = 2 * ci[m] + (q & 1)
        cj[nn + q] = 2 * cj[m] + (q >> 1)
        child[nn + q] = -1


@njit(cache=True)
def balance(lev, ci, cj, child, n_nodes):
    """Split leaves until every leaf's side neighbours are at most one level coarser.

    A ripple worklist: a leaf whose side neighbour is two or more levels coarser splits
    that neighbour and is checked again; new sons are checked in turn.

    Parameters
    ----------
    lev, ci, cj, child : (cap,) int64
        The tree (module docstring), grown in place.
    n_nodes : int
        Nodes in use.

    Returns
    -------
    int
        Nodes in use afterwards, or -1 when ``cap`` was reached (the tree stays
        consistent: grow the arrays and call again).
    """
    cap = lev.shape[0]
    stack = np.empty(max(64, 4 * n_nodes), dtype=np.int64)
    top = 0
    for n in range(n_nodes):
        if child[n] < 0:
            if top == stack.shape[0]:
                stack = np.concatenate((stack, np.empty(stack.shape[0], dtype=np.int64)))
            stack[top] = n
            top += 1
    while top > 0:
        top -= 1
        n = stack[top]
        if child[n] >= 0 or lev[n] < 2:
            continue
        for d in range(4):
            m = _find(lev, ci, cj, child, lev[n], ci[n] + _SIDE_DI[d], cj[n] + _SIDE_DJ[d])
            if m < 0 or child[m] >= 0 or lev[m] >= lev[n] - 1:
                continue
            if n_nodes + 4 > cap:
                return -1
            _split(lev, ci, cj, child, m, n_nodes)
            if top + 5 > stack.shape[0]:
                stack = np.concatenate((stack, np.empty(stack.shape[0], dtype=np.int64)))
            for q in range(4):
                stack[top] = n_nodes + q
                top += 1
            stack[top] = n
            top += 1
            n_nodes += 4
            break
    return n_nodes


@njit(inline="always")
def _seg_within(px, py, r, seg_a, seg_b, s):
    """Whether segment ``s`` passes within ``r`` of (px, py)."""
    ax = seg_a[s, 0]
    ay = seg_a[s, 1]
    dx = seg_b[s, 0] - ax
    dy = seg_b[s, 1] - ay
    qx = px - ax
    qy = py - ay
    ll = dx * dx + dy * dy
    f = 0.0 if ll == 0.0 else min(max((qx * dx + qy * dy) / ll, 0.0), 1.0)
    ex = qx - f * dx
    ey = qy - f * dy
    return ex * ex + ey * ey < r * r


@njit(cache=True)
def _near(cx, cy, radius, seg_a, seg_b):
    """(k,) bool: whether some segment passes within ``radius[i]`` of (cx[i], cy[i]).

    Segments are bucketed in a uniform grid of about one segment per cell (CSR: each
    segment listed in every cell its box meets); a query scans the cells its box meets,
    or every segment when that would be more cells than segments (a large cell far from
    the boundary).
    """
    k = cx.shape[0]
    m = seg_a.shape[0]
    out = np.zeros(k, dtype=np.bool_)
    if m == 0:
        return out
    x0 = min(seg_a[:, 0].min(), seg_b[:, 0].min())
    y0 = min(seg_a[:, 1].min(), seg_b[:, 1].min())
    x1 = max(seg_a[:, 0].max(), seg_b[:, 0].max())
    y1 = max(seg_a[:, 1].max(), seg_b[:, 1].max())
    g = max(x1 - x0, y1 - y0, 1e-300) / max(1.0, np.sqrt(m))
    nx = int((x1 - x0) / g) + 1
    ny = int((y1 - y0) / g) + 1
    count = np.zeros(nx * ny + 1, dtype=np.int64)
    box = np.empty((m, 4), dtype=np.int64)
    for s in range(m):
        box[s, 0] = int((min(seg_a[s, 0], seg_b[s, 0]) - x0) / g)
        box[s, 1] = min(int((max(seg_a[s, 0], seg_b[s, 0]) - x0) / g), nx - 1)
        box[s, 2] = int((min(seg_a[s, 1], seg_b[s, 1]) - y0) / g)
        box[s, 3] = min(int((max(seg_a[s, 1], seg_b[s, 1]) - y0) / g), ny - 1)
        for jj in range(box[s, 2], box[s, 3] + 1):
            for ii in range(box[s, 0], box[s, 1] + 1):
                count[jj * nx + ii + 1] += 1
    start = np.cumsum(count)
    items = np.empty(start[-1], dtype=np.int64)
    fill = start[:-1].copy()
    for s in range(m):
        for jj in range(box[s, 2], box[s, 3] + 1):
            for ii in range(box[s, 0], box[s, 1] + 1):
                items[fill[jj * nx + ii]] = s
                fill[jj * nx + ii] += 1
    for q in range(k):
        r = radius[q]
        i0 = max(int(np.floor((cx[q] - r - x0) / g)), 0)
        i1 = min(int(np.floor((cx[q] + r - x0) / g)), nx - 1)
        j0 = max(int(np.floor((cy[q] - r - y0) / g)), 0)
        j1 = min(int(np.floor((cy[q] + r - y0) / g)), ny - 1)
        if i0 > i1 or j0 > j1:
            continue
        if (i1 - i0 + 1) * (j1 - j0 + 1) > m:
            for s in range(m):
                if _seg_within(cx[q], cy[q], r, seg_a, seg_b, s):
                    out[q] = True
                    break
            continue
        for jj in range(j0, j1 + 1):
            for ii in range(i0, i1 + 1):
                c = jj * nx + ii
                for t in range(start[c], start[c + 1]):
                    if _seg_within(cx[q], cy[q], r, seg_a, seg_b, items[t]):
                        out[q] = True
                        break
                if out[q]:
                    break
            if out[q]:
                break
    return out


@njit(cache=True)
def _core_cells(lev, ci, cj, child, keep, top_level, cells):
    """Polygons and outline of the kept leaves ``cells``.

    Vertices are integer keys ``X * (2^top + 1) + Y`` on the grid of level ``top_level``.

    Returns
    -------
    poly : (c, 8) int64
        Each cell's vertices counter-clockwise from its south-west corner, hanging nodes
        included, -1 padded.
    outline : (e, 3) int64
        Directed outline edges (start key, end key, cell row), the core on their left.
    """
    c = cells.shape[0]
    poly = np.full((c, 8), -1, dtype=np.int64)
    outline = np.empty((8 * c, 3), dtype=np.int64)
    ne = 0
    side = np.int64(1) << top_level
    for r in range(c):
        n = cells[r]
        l = lev[n]
        s = np.int64(1) << (top_level - l)
        x0 = ci[n] * s
        y0 = cj[n] * s
        k = 0
        for d in range(4):
            ax = x0 + _CORNER[d, 0] * s
            ay = y0 + _CORNER[d, 1] * s
            bx = x0 + _CORNER[(d + 1) % 4, 0] * s
            by = y0 + _CORNER[(d + 1) % 4, 1] * s
            a = ax * (side + 1) + ay
            b = bx * (side + 1) + by
            poly[r, k] = a
            k += 1
            m = _find(lev, ci, cj, child, l, ci[n] + _SIDE_DI[d], cj[n] + _SIDE_DJ[d])
            if m >= 0 and child[m] >= 0:
                mid = ((ax + bx) // 2) * (side + 1) + (ay + by) // 2
                poly[r, k] = mid
                k += 1
                for h in range(2):
                    if not keep[child[m] + _HALF_SONS[d, h]]:
                        outline[ne, 0] = a if h == 0 else mid
                        outline[ne, 1] = mid if h == 0 else b
                        outline[ne, 2] = r
                        ne += 1
            elif m < 0 or not keep[m]:
                outline[ne, 0] = a
                outline[ne, 1] = b
                outline[ne, 2] = r
                ne += 1
    return poly, outline[:ne]


def build_tree(root, target, max_nodes: int):
    """Refine the root box level by level while a cell exceeds ``SPLIT_RATIO * target``.

    Parameters
    ----------
    root : (x0, y0, L)
        Lower-left corner and side of the root box.
    target : callable
        ``target(x (k,), y (k,), s (k,)) -> ((k,) float64 size, (k,) bool relevant)``: the
        target size over each cell of side ``s`` centred at (x, y), and whether the cell
        meets the domain (cells that do not are never split).
    max_nodes : int
        Cap on tree nodes.

    Returns
    -------
    lev, ci, cj, child : (n,) int64
        The 2:1 balanced tree (module docstring).

    Raises
    ------
    MeshingError
        More than ``max_nodes`` nodes, or a size below ``L / 2^MAX_LEVEL``.
    """
    x0, y0, side = root
    cap = 1024
    lev = np.zeros(cap, np.int64)
    ci = np.zeros(cap, np.int64)
    cj = np.zeros(cap, np.int64)
    child = np.full(cap, -1, np.int64)
    n_nodes = 1
    front = np.zeros(1, np.int64)
    for level in range(MAX_LEVEL + 1):
        if not len(front):
            break
        s = side / 2.0**level
        cx = x0 + (ci[front] + 0.5) * s
        cy = y0 + (cj[front] + 0.5) * s
        h, relevant = target(cx, cy, np.full(len(front), s))
        split = front[relevant & (s > SPLIT_RATIO * h)]
        if not len(split):
            break
        if level == MAX_LEVEL:
            raise MeshingError(
                f"the size field asks for cells below the finest quadtree level ({MAX_LEVEL}: side {s:.3g}) "
                f"near ({cx[0]:.6g}, {cy[0]:.6g}); coarsen the size"
            )
        need = n_nodes + 4 * len(split)
        if need > max_nodes:
            raise MeshingError(f"the quadtree needs more than {max_nodes} cells at level {level + 1}; coarsen the size")
        if need > cap:
            cap = max(2 * cap, need)
            lev, ci, cj, child = (np.concatenate([a, np.full(cap - len(a), f, np.int64)]) for a, f in
                                  ((lev, 0), (ci, 0), (cj, 0), (child, -1)))
        sons = n_nodes + 4 * np.arange(len(split))
        child[split] = sons
        q = np.arange(4)
        new = (sons[:, None] + q).ravel()
        lev[new] = level + 1
        ci[new] = (2 * ci[split][:, None] + (q & 1)).ravel()
        cj[new] = (2 * cj[split][:, None] + (q >> 1)).ravel()
        n_nodes = need
        front = new
    while True:
        done = balance(lev, ci, cj, child, n_nodes)
        if done >= 0:
            n_nodes = done
            break
        if 2 * cap > max_nodes:
            raise MeshingError(f"balancing the quadtree needs more than {max_nodes} cells; coarsen the size")
        cap *= 2
        lev, ci, cj, child = (np.concatenate([a, np.full(cap - len(a), f, np.int64)]) for a, f in
                              ((lev, 0), (ci, 0), (cj, 0), (child, -1)))
    return lev[:n_nodes].copy(), ci[:n_nodes].copy(), cj[:n_nodes].copy(), child[:n_nodes].copy()


def _core(lev, ci, cj, child, keep, top):
    """Polygons and outline of the kept leaves, pinched outline vertices removed.

    A vertex where the outline leaves twice joins two parts of the core by a corner; one
    of its cells is dropped and the outline recomputed (at most one pass per kept cell).
    """
    for _ in range(int(keep.sum()) + 1):
        cells = np.flatnonzero(keep)
        poly, outline = _core_cells(lev, ci, cj, child, keep, top, cells)
        starts, first, counts = np.unique(outline[:, 0], return_index=True, return_counts=True)
        pinched = counts > 1
        if not pinched.any():
            return cells, poly, outline
        keep[cells[outline[first[pinched], 2]]] = False
    raise MeshingError("removing pinched cells from the quadtree core did not terminate")


def _target(domain: Domain, field, factor: float, seg_a, seg_b):
    """The ``target`` callable of :func:`build_tree` for a domain and size field."""

    def target(cx, cy, s):
        xy = np.column_stack([cx, cy])
        h = field(xy)
        for dx, dy in ((-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)):
            h = np.minimum(h, field(np.column_stack([cx + dx * s, cy + dy * s])))
        relevant = domain.contains(xy) | _near(cx, cy, 0.75 * s, seg_a, seg_b)
        return factor * h, relevant

    return target


def _line_curves(domain: Domain, points, lines) -> np.ndarray:
    """(k,) int32: the curve of ``domain`` nearest to each line's midpoint."""
    mid = 0.5 * (points[lines[:, 0]] + points[lines[:, 1]])
    best = np.full(len(lines), np.inf)
    out = np.zeros(len(lines), np.int32)
    for c in range(len(domain.curves)):
        on = domain.project(np.full(len(lines), c), mid)[1]
        d = np.hypot(*(on - mid).T)
        closer = d < best
        best[closer] = d[closer]
        out[closer] = c
    return out


def _gap_mesh(dom: Domain, gap_dom: Domain, hfield, marker_gap: int, job):
    """Triangulate the gap, refining its boundary where a segment's curve strays from it.

    With ``all_quad`` the midpoint of every boundary segment will move onto its curve; a
    segment whose curve lies more than ``SAGITTA`` times its length from its midpoint
    (a coarse chord on a tight curve, e.g. a flap's nose) gets a source of 0.3 times its
    length at its curve point in the size field and the gap is triangulated again, at
    most ``SAGITTA_ROUNDS`` times; the same rounds first run on the gap's boundary
    discretisation alone (:func:`_sagitta_sources`), so the triangulation is usually
    needed once (the three-element airfoil took six before).  A kink inside one curve (a cusp without a curve
    break) keeps its ratio however fine the chords; after the last round the gap is
    used as it is, and the exact orientation check of :func:`quadrangulate` on the
    finished cells is what guards validity there.

    Returns
    -------
    gap : Mesh
    boundary : (k,) bool
        Which of ``gap``'s line cells lie on the domain's curves (not on the core).
    line_curves : (b,) int32
        The curve of each of those lines.
    """
    from meshwright.tri.mesher import triangulate

    def attempt(h):
        # The gap is meshed at the tree's own field h (the domain's size, refined where chords
        # sag): triangulate's default grading from the boundary (issue 13) would also follow
        # the gap's short chords inward and split its triangles into quads of scaled Jacobian
        # below 0.1 on the three-element airfoil.
        gap = triangulate(
            gap_dom, h, min_angle=GAP_MIN_ANGLE, seed=job.seed, max_points=job.max_points, grading=None
        )
        boundary = gap.cell_data["marker"]["line"] != marker_gap
        return gap, boundary, _line_curves(dom, gap.points, gap.cells["line"][boundary])

    if job.all_quad:
        hfield = _sagitta_sources(dom, hfield)
    for _ in range(SAGITTA_ROUNDS):
        gap, boundary, curves = attempt(hfield)
        if not job.all_quad:
            return gap, boundary, curves
        lines = gap.cells["line"][boundary]
        a, b = gap.points[lines[:, 0]], gap.points[lines[:, 1]]
        length = np.hypot(*(b - a).T)
        on = curve_midpoints(dom, curves, a, b)
        bad = np.hypot(*(on - 0.5 * (a + b)).T) > SAGITTA * length
        if not bad.any():
            return gap, boundary, curves
        hfield = gradation(on[bad], 0.3 * length[bad], SAGITTA_GROWTH, base=hfield)
    return attempt(hfield)


def _sagitta_sources(dom: Domain, hfield):
    """The sagitta rounds of :func:`_gap_mesh` on the domain's boundary discretisation alone.

    Each round of :func:`_gap_mesh` triangulates the whole gap; the chords it refines are
    those of the discretisation (the refinement only halves some), so the sources are
    found here first, on ``dom.discretize`` (no triangulation; the gap's own discretisation
    places the same chords on the domain's curves and adds the core's outline, which is
    not checked: about twice the work), at most ``SAGITTA_ROUNDS`` times, with each
    chord's arc midpoint from its curve parameters; the loop of :func:`_gap_mesh` then
    checks the triangulation's chords as before and usually passes at once.
    """
    for _ in range(SAGITTA_ROUNDS):
        disc = dom.discretize(hfield)
        seg = disc.segments
        a, b = disc.points[seg[:, 0]], disc.points[seg[:, 1]]
        length = np.hypot(*(b - a).T)
        # The discretisation knows each chord's curve parameters: the arc midpoint needs
        # no projection (a Python golden-section search per curve, 60-85 % of the
        # three-element airfoil's quadtree time).
        ta, tb = disc.segment_params.T
        on = dom.split(disc.segment_curve, ta, tb)[1]
        bad = np.hypot(*(on - 0.5 * (a + b)).T) > SAGITTA * length
        if not bad.any():
            return hfield
        hfield = gradation(on[bad], 0.3 * length[bad], SAGITTA_GROWTH, base=hfield)
    return hfield


@njit(cache=True)
def _outline_rows(qx, qy, oa, ob):
    """For each query point, the outline edge (axis-parallel, ends ``oa``/``ob``) whose
    interior contains it exactly; -1 if none, -2 if several."""
    out = np.full(qx.shape[0], -1, dtype=np.int64)
    for e in range(qx.shape[0]):
        for r in range(oa.shape[0]):
            if oa[r, 1] == qy[e] and ob[r, 1] == qy[e]:
                inside = min(oa[r, 0], ob[r, 0]) < qx[e] < max(oa[r, 0], ob[r, 0])
            elif oa[r, 0] == qx[e] and ob[r, 0] == qx[e]:
                inside = min(oa[r, 1], ob[r, 1]) < qy[e] < max(oa[r, 1], ob[r, 1])
            else:
                inside = False
            if inside:
                out[e] = r if out[e] == -1 else -2
    return out


def _gap_domain(dom: Domain, core_xy, ends, marker_gap: int, gap_seeds) -> Domain:
    """The domain between the core's outline (loops of ``core_xy[ends]`` edges, marked
    ``marker_gap``) and the domain's own loops, segments and points; ``gap_seeds`` (s, 2)
    are the domain's region seeds outside the core (an island without core cells needs
    its own)."""
    holes = [list(lp) for lp in dom.loops[1:]]
    seeds = [(float(x), float(y), 0, None) for x, y in gap_seeds]
    if len(ends):
        verts, edge_order, offsets, _ = trace_chains(len(core_xy), ends)
        for k in range(len(offsets) - 1):
            loop = verts[offsets[k] + k : offsets[k + 1] + k + 1]
            holes.append([Polyline(core_xy[loop], closed=True, marker=marker_gap)])
            # A seed just off the outline on the gap side (the right of the directed edge):
            # the gap inside a ring-shaped core is an island of the gap domain.
            a, b = core_xy[ends[edge_order[offsets[k]]]]
            seeds.append((*(0.5 * (a + b) + 0.1 * np.array([b[1] - a[1], a[0] - b[0]])), 0, None))
    return Domain(
        list(dom.loops[0]), holes, segments=[list(c) for c in dom.constraints], points=dom.points, regions=seeds
    )


def _fans(pid, owner, extra_id, centres, xy):
    """Fan triangles of the core cells that are not plain quads.

    Parameters
    ----------
    pid : (c, 8) int64
        Each cell's polygon vertex ids (-1 padded).
    owner : (e,) int64
        Cell row of each extra outline vertex ``extra_id``.
    centres : (c, 2) float64
    xy : (n, 2) float64
        Coordinates of the ids.

    Returns
    -------
    plain : (c,) bool
        Cells kept as quads.
    fan : (f, 3) int64
        Triangles ``(centre, v_i, v_i+1)``, centre ids ``n + k`` for the k-th fan cell.
    fan_rows : (k,) int64
        The fan cells (rows of ``pid``), in centre-id order.
    """
    nv = (pid >= 0).sum(axis=1)
    plain = (nv == 4) & ~np.isin(np.arange(len(pid)), owner)
    fan_rows = np.flatnonzero(~plain)
    ring_cell = np.concatenate([np.repeat(fan_rows, nv[fan_rows]), owner])
    ring_vert = np.concatenate([pid[fan_rows][pid[fan_rows] >= 0], extra_id])
    # Every ring vertex lies on its cell's boundary: sorting by angle about the centre
    # orders the ring counter-clockwise.
    ang = np.arctan2(xy[ring_vert, 1] - centres[ring_cell, 1], xy[ring_vert, 0] - centres[ring_cell, 0])
    order = np.lexsort((ang, ring_cell))
    ring_cell, ring_vert = ring_cell[order], ring_vert[order]
    start = np.flatnonzero(np.r_[len(ring_cell) > 0, ring_cell[1:] != ring_cell[:-1]])
    count = np.diff(np.r_[start, len(ring_cell)])
    nxt = np.arange(len(ring_cell)) + 1
    nxt[start + count - 1] = start  # close each ring
    centre_id = len(xy) + np.searchsorted(fan_rows, ring_cell)
    return plain, np.column_stack([centre_id, ring_vert, ring_vert[nxt]]), fan_rows


class QuadtreeStages(NamedTuple):
    """The quadtree before its boundary gap is meshed (the chapter's Figure 18.5.4 b, c).

    Attributes
    ----------
    root : tuple of float
        ``(x0, y0, L)``: lower-left corner and side of the root box.
    lev, ci, cj, child : (n,) int64
        The refined, 2:1 balanced tree (module docstring); node ``k`` covers the square of
        side ``L / 2**lev[k]`` with lower-left corner ``(x0, y0) + (ci[k], cj[k]) * side``.
    leaves : (k,) int64
        The leaf nodes (the grid laid over the domain).
    inside : (k,) bool
        Whether each leaf's centre lies inside the domain.
    core : (c,) int64
        The kept leaves: inside, at least ``CLEARANCE`` sizes from every boundary, segment
        and interior point, no cell touching the rest only by a corner; the method's quads
        and transition fans are made of these.
    """

    root: tuple
    lev: np.ndarray
    ci: np.ndarray
    cj: np.ndarray
    child: np.ndarray
    leaves: np.ndarray
    inside: np.ndarray
    core: np.ndarray


def _stages(dom: Domain, field, factor: float, max_nodes: int):
    """Tree, exterior removal and core of :func:`quadtree_fill`.

    Returns
    -------
    stages : QuadtreeStages
    disc : Discretization
        The domain's boundary at ``field``.
    keep : (n,) bool
        The core's nodes, as a mask over the tree.
    poly, outline : see :func:`_core_cells`
    top : int
        The finest level.
    """
    disc = dom.discretize(field)
    # Interior points are zero-length segments: the core keeps clear of them and the gap
    # triangulation makes them vertices.
    seg_a = np.ascontiguousarray(np.vstack([disc.points[disc.segments[:, 0]], dom.points]))
    seg_b = np.ascontiguousarray(np.vstack([disc.points[disc.segments[:, 1]], dom.points]))
    x0, y0, x1, y1 = dom.bbox
    extent = max(x1 - x0, y1 - y0)
    side = 2.0 ** math.ceil(math.log2(extent * (1.0 + 1.0 / 64.0)))
    root = (0.5 * (x0 + x1) - 0.5 * side, 0.5 * (y0 + y1) - 0.5 * side, side)
    lev, ci, cj, child = build_tree(root, _target(dom, field, factor, seg_a, seg_b), max_nodes)
    top = int(lev.max())
    leaves = np.flatnonzero(child < 0)
    s = side / 2.0 ** lev[leaves]
    cx = root[0] + (ci[leaves] + 0.5) * s
    cy = root[1] + (cj[leaves] + 0.5) * s
    inside = dom.contains(np.column_stack([cx, cy]))
    clear = ~_near(cx, cy, (math.sqrt(0.5) + CLEARANCE) * s, seg_a, seg_b)
    keep = np.zeros(len(lev), dtype=np.bool_)
    keep[leaves[inside & clear]] = True
    cells, poly, outline = _core(lev, ci, cj, child, keep, top)
    stages = QuadtreeStages(root, lev, ci, cj, child, leaves, inside, cells)
    return stages, disc, keep, poly, outline, top


def _boundary_field(dom: Domain):
    """The size of ``size="boundary"`` on a domain carrying none: each boundary and segment
    vertex's own spacing (Weatherill's point distribution ``dP``), graded inward at
    :data:`~meshwright.sizing.lfs.DEFAULT_GROWTH` as triangulate's front grades its
    background, and capped at the largest spacing (a background interpolated between the
    boundary vertices never exceeds it)."""
    disc = dom.discretize(None)
    dp = point_distribution(disc.points, disc.segments)
    return boundary_size(disc.points, disc.segments, DEFAULT_GROWTH, hmax=float(np.nanmax(dp)))


def quadtree_stages(domain, size=None, *, all_quad: bool = True, max_points: int | None = None) -> QuadtreeStages:
    """The intermediate stages of the quadtree method, for pictures and inspection.

    Builds exactly what ``quadrangulate(domain, size, method="quadtree", all_quad=...)``
    builds before it meshes the boundary gap: the balanced tree over the domain's box,
    which leaves lie inside, and the core of kept cells.

    Parameters
    ----------
    domain : Domain, str, path or (n, 2) array_like
        As for :func:`meshwright.quadrangulate`.
    size : number, callable or SizeField, optional
        Target quad size; default the domain's own.
    all_quad : bool
        As for :func:`meshwright.quadrangulate`: True builds the tree at twice the size
        (the midpoint split halves it afterwards).
    max_points : int, optional
        Cap on tree nodes (default :data:`meshwright.tri.mesher.DEFAULT_MAX_POINTS`).

    Returns
    -------
    QuadtreeStages

    Raises
    ------
    InputError
        Not a domain, a flag that is not a bool, a bad ``max_points``, or no size.
    SizeError
        A size that is zero, negative or not finite.
    MeshingError
        The tree needs more than ``max_points`` nodes.
    """
    from meshwright.core.validate_input import check_count
    from meshwright.tri.mesher import DEFAULT_MAX_POINTS, _as_domain

    if not isinstance(all_quad, (bool, np.bool_)):
        raise InputError(f"all_quad must be True or False, got {all_quad!r}")
    cap = DEFAULT_MAX_POINTS if max_points is None else check_count(max_points, "max_points", 4)
    field = None if size is None else as_size_field(size)
    dom = _as_domain(domain)
    field = dom.size if field is None else field
    if field is None:
        raise InputError("quadtree_stages needs a size: give size=... (the domain carries none)")
    return _stages(dom, field, 2.0 if all_quad else 1.0, cap)[0]


def quadtree_fill(job):
    """The quadtree method of :func:`meshwright.quadrangulate` (see the module docstring).

    Parameters
    ----------
    job : QuadJob

    Returns
    -------
    QuadFill
        Quads of the core, triangles of its transition fans and of the boundary gap; with
        ``all_quad`` those split into quads (module docstring).

    Raises
    ------
    MeshingError
        A cap on cells or points was hit, or the gap triangulation broke the outline
        (named).
    """
    from meshwright.quad.mesher import QuadFill

    dom = job.domain
    field = _boundary_field(dom) if job.field is None else job.field
    factor = 2.0 if job.all_quad else 1.0
    stages, disc, keep, poly, outline, top = _stages(dom, field, factor, job.max_points)
    root, lev, ci, cj, child, cells = stages.root, stages.lev, stages.ci, stages.cj, stages.child, stages.core
    side = root[2]

    # Core vertices: integer keys -> coordinates.
    unit = side / 2.0**top
    keys = np.unique(poly[poly >= 0])
    kx, ky = keys // ((1 << top) + 1), keys % ((1 << top) + 1)
    core_xy = np.column_stack([root[0] + kx * unit, root[1] + ky * unit])
    ends = np.searchsorted(keys, outline[:, :2])

    marker_gap = int(disc.segment_markers.max(initial=0)) + 1
    seeds = np.array([r[:2] for r in dom.regions], dtype=np.float64).reshape(-1, 2)
    si = np.floor((seeds[:, 0] - root[0]) / unit).astype(np.int64)
    sj = np.floor((seeds[:, 1] - root[1]) / unit).astype(np.int64)
    in_core = np.array([keep[max(_find(lev, ci, cj, child, top, a, b), 0)] for a, b in zip(si, sj)], dtype=bool)
    gap_dom = _gap_domain(dom, core_xy, ends, marker_gap, seeds[~in_core])
    hfield = as_size_field(lambda xy: factor * field(xy))
    gap, boundary, line_curves = _gap_mesh(dom, gap_dom, hfield, marker_gap, job)

    # One vertex numbering for the core's vertices and the gap's.
    allxy, inv = np.unique(np.vstack([core_xy, gap.points]), axis=0, return_inverse=True)
    inv = inv.ravel()
    core_id, gap_id = inv[: len(core_xy)], inv[len(core_xy) :]
    lost = ends[~np.isin(core_id[ends[:, 0]], gap_id), 0]
    if len(lost):
        x, y = core_xy[lost[0]]
        raise MeshingError(f"the gap triangulation lost the core's outline vertex ({x:.17g}, {y:.17g})")
    gl = gap.cells["line"]
    gm = gap.cell_data["marker"]["line"]
    # Gap vertices inserted on the outline (Delaunay refinement splits) join their cell's fan.
    on_outline = np.unique(gl[gm == marker_gap])
    extra = on_outline[~np.isin(gap_id[on_outline], core_id)]
    rows = _outline_rows(gap.points[extra, 0], gap.points[extra, 1], core_xy[ends[:, 0]], core_xy[ends[:, 1]])
    if len(rows) and rows.min() < 0:
        e = int(np.argmin(rows))
        px, py = gap.points[extra[e]]
        raise MeshingError(
            f"gap vertex ({px:.17g}, {py:.17g}) lies on {'no' if rows[e] == -1 else 'several'} outline edges of the core"
        )

    pid = np.where(poly >= 0, core_id[np.searchsorted(keys, np.maximum(poly, 0))], -1)
    s_cell = side / 2.0 ** lev[cells]
    centres = np.column_stack([root[0] + (ci[cells] + 0.5) * s_cell, root[1] + (cj[cells] + 0.5) * s_cell])
    plain, fan, fan_rows = _fans(pid, outline[rows, 2], gap_id[extra], centres, allxy)
    points = np.ascontiguousarray(np.vstack([allxy, centres[fan_rows]]))
    if len(points) > job.max_points:
        raise MeshingError(f"the quadtree mesh has {len(points)} vertices, above max_points = {job.max_points}")
    quads = pid[plain][:, :4]
    triangles = np.concatenate([fan, gap_id[gap.cells["triangle"]]])
    lines = gap_id[gl[boundary]]
    if job.all_quad:
        merged, triangles = merge_slivers(points, triangles, lines, FINISH_FLOOR)
        quads = np.concatenate([quads, merged])
    fill = QuadFill(
        points,
        np.ascontiguousarray(quads, dtype=np.int32),
        np.ascontiguousarray(triangles, dtype=np.int32),
        lines.astype(np.int32),
        gm[boundary].astype(np.int32),
        line_curves,
    )
    if not job.all_quad:
        return fill
    split = split_all(fill, dom, job.max_points)
    recentre(split.points, split.quads.astype(np.int64), len(split.points) - len(quads) - len(triangles), FINISH_FLOOR,
             CENTRE_STEPS)
    return split
