"""Quality-guarded Laplacian smoothing of quad-dominant meshes (shared by the quad methods).

Each free vertex moves towards the mean of its edge neighbours (Gauss-Seidel sweeps, the
plain Laplacian of Herrmann 1976 as used by every chapter 18.5 method after its
topology is fixed); a move is kept only if the smallest corner sine (the scaled Jacobian
of quads, the sine of the angle for triangles) over the cells around the vertex does not
fall, else half the move is tried, else the vertex stays.  This is the "smart" Laplacian
of Canann, Tristano and Staten (IMR 1998): it never inverts a cell and never lowers the
mesh's minimum scaled Jacobian, so a valid mesh stays valid.  Vertices on ``line`` cells
(the boundary and interior segments) are fixed, which keeps them on their true curves.

:func:`smooth_sliding` is the same guard with boundary vertices sliding along their true
curves (the pairing's enhancement smoothing, 18.5.1): a sliding vertex's Laplacian step is
projected onto the chord of its two boundary neighbours and put back on its curve by the
caller's projection, and every move is also checked exactly: every cell around the vertex
must be strictly convex (a triangle strictly counter-clockwise) after it by exact
``orient2d``, so a vertex of a relaxed non-convex quad moves only to make it convex.

Array layout: points (n, 2) float64; cells (m, 4) int64, a triangle padded with -1 in
column 3, counter-clockwise; vertex-to-cell and vertex-to-neighbour tables in CSR form
(``ptr`` (n + 1,), ``idx``), built in one linear pass (:func:`cell_tables`).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from meshwright.core.errors import InputError
from meshwright.core.predicates import orient2d
from meshwright.core.validate_input import check_count

__all__ = ["smooth_cells", "smooth_sliding", "cell_tables"]


@njit(inline="always")
def _corner_sine(points, a, b, d):
    """Sine of the corner at b between b->d and b->a (-1 for a degenerate corner)."""
    ux = points[d, 0] - points[b, 0]
    uy = points[d, 1] - points[b, 1]
    wx = points[a, 0] - points[b, 0]
    wy = points[a, 1] - points[b, 1]
    den = np.sqrt((ux * ux + uy * uy) * (wx * wx + wy * wy))
    return (ux * wy - uy * wx) / den if den > 0.0 else -1.0


@njit(inline="always")
def _neighbour_mean(points, nbr_ptr, nbr_idx, v):
    """Mean of vertex ``v``'s neighbours (the spring analogy's equilibrium)."""
    tx = 0.0
    ty = 0.0
    for t in range(nbr_ptr[v], nbr_ptr[v + 1]):
        tx += points[nbr_idx[t], 0]
        ty += points[nbr_idx[t], 1]
    k = nbr_ptr[v + 1] - nbr_ptr[v]
    return tx / k, ty / k


@njit(inline="always")
def _settled(nbr_ptr, nbr_idx, last, now, v):
    """Whether neither ``v`` nor an edge neighbour moved in the last sweep or this one."""
    if last[v] != 0 or now[v] != 0:
        return False
    for t in range(nbr_ptr[v], nbr_ptr[v + 1]):
        w = nbr_idx[t]
        if last[w] != 0 or now[w] != 0:
            return False
    return True


@njit(inline="always")
def _note_move(points, nbr_ptr, nbr_idx, now, v, x0, y0, settle):
    """Flag ``v`` in ``now`` if it moved from (x0, y0) by more than ``settle`` times its
    distance to its first neighbour."""
    w = nbr_idx[nbr_ptr[v]]
    ref = (points[w, 0] - x0) ** 2 + (points[w, 1] - y0) ** 2
    shift = (points[v, 0] - x0) ** 2 + (points[v, 1] - y0) ** 2
    if shift > settle * settle * ref:
        now[v] = 1


@njit(cache=True)
def _corner_table(points, cells):
    """Sine of every corner, (m, 4) float64: ``cs[c, k]`` of corner k of cell c (unused
    slot of a triangle: 1)."""
    m = cells.shape[0]
    cs = np.ones((m, 4))
    for c in range(m):
        nv = 4 if cells[c, 3] >= 0 else 3
        for k in range(nv):
            cs[c, k] = _corner_sine(points, cells[c, (k + nv - 1) % nv], cells[c, k], cells[c, (k + 1) % nv])
    return cs


@njit(cache=True)
def _star_min(cs, cells, cell_ptr, cell_idx, v):
    """Smallest corner sine over the cells around ``v``, read from the table ``cs``."""
    worst = 1.0
    for t in range(cell_ptr[v], cell_ptr[v + 1]):
        c = cell_idx[t]
        nv = 4 if cells[c, 3] >= 0 else 3
        for k in range(nv):
            if cs[c, k] < worst:
                worst = cs[c, k]
    return worst


@njit(cache=True)
def _moved_sines(points, cells, cell_ptr, cell_idx, v, bound, tmp):
    """Whether every corner sine that moving ``v`` changes is at least ``bound``.

    With ``bound`` the star's smallest sine before the move, this is the guard's test
    (the smallest sine does not fall) without the corners opposite ``v`` in its quads
    (unchanged, and not below ``bound``), stopping at the first failure.  The sines are
    kept in ``tmp`` (star order) for :func:`_store_sines`.
    """
    i = 0
    for t in range(cell_ptr[v], cell_ptr[v + 1]):
        c = cell_idx[t]
        nv = 4 if cells[c, 3] >= 0 else 3
        kv = 0
        while cells[c, kv] != v:
            kv += 1
        for k in range(nv):
            if nv == 4 and k == (kv + 2) % 4:
                continue
            s = _corner_sine(points, cells[c, (k + nv - 1) % nv], cells[c, k], cells[c, (k + 1) % nv])
            if s < bound:
                return False
            tmp[i] = s
            i += 1
    return True


@njit(cache=True)
def _store_sines(cs, cells, cell_ptr, cell_idx, v, tmp):
    """Write the sines :func:`_moved_sines` kept back into the corner table."""
    i = 0
    for t in range(cell_ptr[v], cell_ptr[v + 1]):
        c = cell_idx[t]
        nv = 4 if cells[c, 3] >= 0 else 3
        kv = 0
        while cells[c, kv] != v:
            kv += 1
        for k in range(nv):
            if nv == 4 and k == (kv + 2) % 4:
                continue
            cs[c, k] = tmp[i]
            i += 1


@njit(cache=True)
def _sweeps(points, cells, cell_ptr, cell_idx, nbr_ptr, nbr_idx, free, passes, settle):
    """Gauss-Seidel guarded Laplacian sweeps in place; returns the moves kept.

    With ``settle > 0`` a vertex is visited again only while it or an edge neighbour
    moved, in this sweep or the last, by more than ``settle`` times the vertex's distance
    to its first neighbour; 0 visits every free vertex in every sweep.  The sine of every
    corner is kept in a table (:func:`_corner_table`), brought up to
    date with each kept move from the sines its test computed: a visit reads its star's
    smallest sine instead of computing it.
    """
    n = points.shape[0]
    kept = 0
    last = np.ones(n, np.int8)
    now = np.zeros(n, np.int8)
    cs = _corner_table(points, cells)
    most = 0
    for v in range(n):
        most = max(most, cell_ptr[v + 1] - cell_ptr[v])
    tmp = np.empty(4 * most + 1)
    for sweep in range(passes):
        for v in range(n):
            if not free[v] or nbr_ptr[v + 1] == nbr_ptr[v]:
                continue
            if settle > 0.0 and sweep > 0 and _settled(nbr_ptr, nbr_idx, last, now, v):
                continue
            tx, ty = _neighbour_mean(points, nbr_ptr, nbr_idx, v)
            x0 = points[v, 0]
            y0 = points[v, 1]
            before = _star_min(cs, cells, cell_ptr, cell_idx, v)
            for step in (1.0, 0.5):
                points[v, 0] = x0 + step * (tx - x0)
                points[v, 1] = y0 + step * (ty - y0)
                if _moved_sines(points, cells, cell_ptr, cell_idx, v, before, tmp):
                    _store_sines(cs, cells, cell_ptr, cell_idx, v, tmp)
                    kept += 1
                    if settle > 0.0:
                        _note_move(points, nbr_ptr, nbr_idx, now, v, x0, y0, settle)
                    break
                points[v, 0] = x0
                points[v, 1] = y0
        last, now = now, last
        now[:] = 0
    return kept

@njit(cache=True)
def _tables(cells, n):
    """Vertex -> cells and vertex -> edge neighbours (deduplicated), both CSR, in O(cells)."""
    m = cells.shape[0]
    cell_ptr = np.zeros(n + 1, np.int64)
    for c in range(m):
        for k in range(4):
            if cells[c, k] >= 0:
                cell_ptr[cells[c, k] + 1] += 1
    for v in range(n):
        cell_ptr[v + 1] += cell_ptr[v]
    fill = cell_ptr[:-1].copy()
    cell_idx = np.empty(cell_ptr[n], np.int64)
    for c in range(m):
        for k in range(4):
            v = cells[c, k]
            if v >= 0:
                cell_idx[fill[v]] = c
                fill[v] += 1
    # Each cell gives a vertex its two edge neighbours; a stamp drops the repeats.
    stamp = np.full(n, -1, np.int64)
    nbr_ptr = np.zeros(n + 1, np.int64)
    nbr_idx = np.empty(2 * cell_ptr[n], np.int64)
    top = 0
    for v in range(n):
        for s in range(cell_ptr[v], cell_ptr[v + 1]):
            c = cell_idx[s]
            nv = 4 if cells[c, 3] >= 0 else 3
            for k in range(nv):
                if cells[c, k] == v:
                    for w in (cells[c, (k + 1) % nv], cells[c, (k + nv - 1) % nv]):
                        if stamp[w] != v:
                            stamp[w] = v
                            nbr_idx[top] = w
                            top += 1
        nbr_ptr[v + 1] = top
    return cell_ptr, cell_idx, nbr_ptr, nbr_idx[:top].copy()


def cell_tables(points, quads, triangles):
    """Padded cells and their vertex tables.

    Parameters
    ----------
    points : (n, 2) float64
    quads : (m, 4) int
    triangles : (t, 3) int

    Returns
    -------
    cells : (m + t, 4) int64
        Quads, then triangles padded with -1.
    cell_ptr, cell_idx : (n + 1,) int64, (4m + 3t,) int64
        Cells around each vertex.
    nbr_ptr, nbr_idx : (n + 1,) int64, (k,) int64
        Edge neighbours of each vertex, each once.
    """
    cells = np.full((len(quads) + len(triangles), 4), -1, np.int64)
    cells[: len(quads)] = quads
    cells[len(quads) :, :3] = triangles
    return (cells, *_tables(cells, len(points)))


@njit(cache=True)
def _valid_cell(points, cells, c):
    """Whether cell c is strictly convex (quad) or strictly counter-clockwise (triangle), exact."""
    nv = 4 if cells[c, 3] >= 0 else 3
    for k in range(nv if nv == 4 else 1):
        a = cells[c, (k + nv - 1) % nv]
        b = cells[c, k]
        d = cells[c, (k + 1) % nv]
        if orient2d(points[a, 0], points[a, 1], points[b, 0], points[b, 1], points[d, 0], points[d, 1]) <= 0.0:
            return False
    return True


@njit(cache=True)
def _try_move(points, cells, cell_ptr, cell_idx, v, tx, ty, before, cs, tmp):
    """Move v to (tx, ty) if every cell of its star is valid there (exact) and the star's
    smallest corner sine (``before``, :func:`_star_min` where v is now) does not fall; a
    star with a non-convex quad thus moves only to become valid, as the pairing's relaxed
    pairs need.  A kept move updates the corner table ``cs`` (:func:`_corner_table`)."""
    x0 = points[v, 0]
    y0 = points[v, 1]
    points[v, 0] = tx
    points[v, 1] = ty
    if _moved_sines(points, cells, cell_ptr, cell_idx, v, before, tmp):
        ok = True
        for s in range(cell_ptr[v], cell_ptr[v + 1]):
            if not _valid_cell(points, cells, cell_idx[s]):
                ok = False
                break
        if ok:
            _store_sines(cs, cells, cell_ptr, cell_idx, v, tmp)
            return True
    points[v, 0] = x0
    points[v, 1] = y0
    return False


@njit(cache=True)
def _interior_sweep(points, cells, cell_ptr, cell_idx, nbr_ptr, nbr_idx, free, last, now, settle, cs, tmp):
    """One Gauss-Seidel guarded Laplacian sweep over the free vertices, exact validity
    kept; with ``settle > 0`` only those not :func:`_settled` (``last``: the moves of the
    previous sweep, ``now``: this one's, flagged here).  ``cs``: the corner table, kept
    up to date; ``tmp``: scratch for a star's sines."""
    kept = 0
    for v in range(points.shape[0]):
        if not free[v] or nbr_ptr[v + 1] == nbr_ptr[v]:
            continue
        if settle > 0.0 and _settled(nbr_ptr, nbr_idx, last, now, v):
            continue
        tx, ty = _neighbour_mean(points, nbr_ptr, nbr_idx, v)
        x0 = points[v, 0]
        y0 = points[v, 1]
        # A refused trial puts v back exactly, so both trials share one ``before``.
        before = _star_min(cs, cells, cell_ptr, cell_idx, v)
        for step in (1.0, 0.5):
            if _try_move(
                points, cells, cell_ptr, cell_idx, v, x0 + step * (tx - x0), y0 + step * (ty - y0), before, cs, tmp
            ):
                kept += 1
                if settle > 0.0:
                    _note_move(points, nbr_ptr, nbr_idx, now, v, x0, y0, settle)
                break
    return kept


@njit(cache=True)
def _tangent_steps(points, nbr_ptr, nbr_idx, nodes, chord):
    """Laplacian steps of the sliding vertices projected on their boundary chords, (k, 2)."""
    out = np.empty((nodes.shape[0], 2))
    for s in range(nodes.shape[0]):
        v = nodes[s]
        fx = 0.0
        fy = 0.0
        for t in range(nbr_ptr[v], nbr_ptr[v + 1]):
            fx += points[nbr_idx[t], 0] - points[v, 0]
            fy += points[nbr_idx[t], 1] - points[v, 1]
        k = max(nbr_ptr[v + 1] - nbr_ptr[v], 1)
        d = (fx * chord[s, 0] + fy * chord[s, 1]) / k
        out[s, 0] = d * chord[s, 0]
        out[s, 1] = d * chord[s, 1]
    return out


@njit(cache=True)
def _slide(points, cells, cell_ptr, cell_idx, nodes, full, half, cs, tmp):
    """Move each sliding vertex to its projected full step, else its projected half step
    (``cs``, ``tmp``: as :func:`_interior_sweep`)."""
    kept = 0
    for s in range(nodes.shape[0]):
        v = nodes[s]
        before = _star_min(cs, cells, cell_ptr, cell_idx, v)
        if _try_move(points, cells, cell_ptr, cell_idx, v, full[s, 0], full[s, 1], before, cs, tmp) or _try_move(
            points, cells, cell_ptr, cell_idx, v, half[s, 0], half[s, 1], before, cs, tmp
        ):
            kept += 1
    return kept


def _check_settle(settle) -> float:
    try:
        settle = float(settle)
    except (TypeError, ValueError):
        raise InputError(f"settle must be a number, got {settle!r}") from None
    if not (np.isfinite(settle) and settle >= 0.0):
        raise InputError(f"settle must be finite and >= 0, got {settle!r}")
    return settle


def smooth_cells(points, quads, triangles, fixed, passes: int, settle: float = 0.0) -> np.ndarray:
    """Guarded Laplacian smoothing (module docstring).

    Parameters
    ----------
    points : (n, 2) float64
    quads : (m, 4) int
    triangles : (t, 3) int
        Counter-clockwise cells of a valid mesh.
    fixed : (n,) bool
        Vertices that never move (boundary and interior-segment vertices).
    passes : int
        Gauss-Seidel sweeps (>= 0).
    settle : float
        After the first sweep, skip vertices whose neighbourhood has settled: neither
        the vertex nor an edge neighbour moved by more than ``settle`` times its
        distance to a neighbour in the last sweep (0: every sweep visits every vertex).

    Returns
    -------
    (n, 2) float64
        New coordinates (the input is not modified).

    Raises
    ------
    InputError
        ``passes`` not a count, ``settle`` negative or not finite.
    """
    passes = check_count(passes, "passes")
    settle = _check_settle(settle)
    pts = np.array(points, dtype=np.float64, order="C")
    cells, cell_ptr, cell_idx, nbr_ptr, nbr_idx = cell_tables(pts, quads, triangles)
    free = ~np.asarray(fixed, dtype=bool)
    _sweeps(pts, cells, cell_ptr, cell_idx, nbr_ptr, nbr_idx, free, passes, settle)
    return pts


def smooth_sliding(points, quads, triangles, lines, fixed, project, passes: int, settle: float = 0.0) -> np.ndarray:
    """Guarded Laplacian with boundary vertices sliding on their curves (module docstring).

    Parameters
    ----------
    points : (n, 2) float64
        Not modified.
    quads : (m, 4) int
    triangles : (t, 3) int
        Counter-clockwise cells; quads may be non-convex (they only get better).
    lines : (k, 2) int
        Boundary and interior-segment edges: their vertices with exactly two line
        neighbours slide, the others stay.
    fixed : (n,) bool
        Vertices that never move (curve joints, polygon corners, given points).
    project : callable
        ``project(nodes (j,) int64, xy (j, 2), at (j, 2)) -> (j, 2)``: trial positions
        ``xy`` of nodes now at ``at`` put on the nodes' curves (the closest points, or a
        step along the curve towards them).
    passes : int
        Sweeps: all free interior vertices (Gauss-Seidel), then all sliding ones.
    settle : float
        As :func:`smooth_cells`: after the first sweep, interior vertices whose
        neighbourhood has settled are skipped (0: none).

    Returns
    -------
    (n, 2) float64
        New coordinates.

    Raises
    ------
    InputError
        ``passes`` not a count, ``settle`` negative or not finite.
    """
    passes = check_count(passes, "passes")
    settle = _check_settle(settle)
    pts = np.array(points, dtype=np.float64, order="C")
    n = len(pts)
    cells, cell_ptr, cell_idx, nbr_ptr, nbr_idx = cell_tables(pts, quads, triangles)
    e = np.asarray(lines, dtype=np.int64).reshape(-1, 2)
    deg = np.bincount(e.ravel(), minlength=n)
    on_line = deg > 0
    free = ~np.asarray(fixed, dtype=bool) & ~on_line
    # The two line neighbours of every vertex of line degree two.
    owner = np.concatenate([e[:, 0], e[:, 1]])
    other = np.concatenate([e[:, 1], e[:, 0]])
    order = np.argsort(owner, kind="stable")
    start = np.concatenate([[0], np.cumsum(deg)[:-1]])
    slide = np.flatnonzero((deg == 2) & ~np.asarray(fixed, dtype=bool))
    ends = other[order][np.stack([start[slide], start[slide] + 1], axis=1)]
    last = np.ones(n, np.int8)
    now = np.zeros(n, np.int8)
    cs = _corner_table(pts, cells)
    tmp = np.empty(4 * int(np.diff(cell_ptr).max(initial=0)) + 1)
    for _ in range(passes):
        _interior_sweep(pts, cells, cell_ptr, cell_idx, nbr_ptr, nbr_idx, free, last, now, settle, cs, tmp)
        last, now = now, last
        now[:] = 0
        # Sliding vertices count as moved: their interior neighbours stay awake.
        last[slide] = 1
        if not len(slide):
            continue
        chord = pts[ends[:, 1]] - pts[ends[:, 0]]
        norm = np.hypot(chord[:, 0], chord[:, 1])
        ok = norm > 0.0
        nodes = slide[ok]
        chord = chord[ok] / norm[ok, None]
        step = _tangent_steps(pts, nbr_ptr, nbr_idx, nodes, np.ascontiguousarray(chord))
        # One projection call for both trial steps: on curves given as functions its cost
        # is per call (a vectorised golden-section search), a third of the pairing's time
        # on the three-element airfoil when made twice.
        at = pts[nodes]
        both = project(np.concatenate([nodes, nodes]), np.vstack([at + step, at + 0.5 * step]), np.vstack([at, at]))
        full = np.ascontiguousarray(both[: len(nodes)], dtype=np.float64)
        half = np.ascontiguousarray(both[len(nodes) :], dtype=np.float64)
        _slide(pts, cells, cell_ptr, cell_idx, nodes, full, half, cs, tmp)
    return pts
