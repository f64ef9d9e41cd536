"""Helpers of :meth:`meshwright.geometry.Domain.discretize`: point placement along curves,
vertex deduplication and interior seeds.

Placement follows the size field ``h``: the number of segments on a curve piece is the
rounded integral of ``1/h`` along its arc length, and the points sit at equal increments of
that integral, so spacing tracks ``h`` even where it varies.  The integral is evaluated by
the trapezoidal rule on a table refined until each interval is below ``h / 2``; a round
splits an interval into at most :data:`_MAX_SPLIT` pieces, so the table grades with ``h``
(a 1e-6 feature next to a graded field costs a few hundred points, not the millions a
uniform split at the interval's smaller size would).  ``h`` is
the spacing wanted along the curve (:meth:`meshwright.sizing.SizeField.along`), which a
stretched background grid makes depend on the curve's direction.  An isotropic field's
spacing depends on the point only, so a refining round asks it at the table's new points
alone: the points kept from the last round (every interval's start, exactly) keep their
sizes (:func:`_point_sizes`).  Every round evaluates the curves at the new parameters only
(:func:`_fill_points`).
"""

from __future__ import annotations

import numpy as np

from meshwright.core.errors import GeometryError, SizeError
from meshwright.geometry._kernels import INSIDE, classify_points
from meshwright.sizing.field import SizeField

__all__ = ["place_params", "unique_rows", "interior_seed"]

_MAX_SPLIT = 8
# 8**40 covers every ratio of curve length to size that float64 parameters can resolve.
_MAX_TABLE_ROUNDS = 40


def _chords(p: np.ndarray) -> np.ndarray:
    d = np.diff(p, axis=0)
    return np.hypot(d[:, 0], d[:, 1])


def _curve_queries(curve, t: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Where and in which direction to ask a size field about one curve's table.

    Tangents are central differences of the table points (one-sided at the ends), taken
    within each piece: at a corner between pieces (a polyline vertex) the two sides differ,
    so the corner is asked twice, once with each piece's direction, and each interval uses
    the answer of its own side.

    Parameters
    ----------
    curve : Curve
    t : (k,) float64
        Table parameters, ordered along the curve.
    p : (k, 2) float64
        The points at ``t``.

    Returns
    -------
    xy : (k + c, 2) float64
        The table points, then the ``c`` corners again.
    tangents : (k + c, 2) float64
        Not normalised; zero where the table gives no direction (a single point).
    corners : (c,) int64
        Table indices of the corners, in the order they are repeated in ``xy``.
    """
    k = len(p)
    if k < 2:
        return p, np.zeros_like(p), np.zeros(0, dtype=np.int64)
    d = np.diff(p, axis=0)
    piece = curve.piece_index(t[:-1])
    corners = np.flatnonzero(piece[1:] != piece[:-1]) + 1
    tan = np.empty_like(p)
    tan[0], tan[-1] = d[0], d[-1]
    tan[1:-1] = p[2:] - p[:-2]
    # A corner's own entry serves the interval leaving it, the repeat the one arriving.
    tan[corners] = d[corners]
    return np.concatenate([p, p[corners]]), np.concatenate([tan, d[corners - 1]]), corners


def _interval_sizes(curves, size, tables, pts) -> list[tuple[np.ndarray, np.ndarray]]:
    """Sizes along the curves at both ends of every table interval, in one field call.

    Returns, per curve, ``(h0, h1)``, each (k_i - 1,) float64: the spacing at the start and
    at the end of each interval, in the interval's direction.  For an isotropic field
    ``h0 == h[:-1]`` and ``h1 == h[1:]`` of the point sizes ``h``.
    """
    queries = [_curve_queries(c, t, p) for c, t, p in zip(curves, tables, pts)]
    hq = size.along(np.concatenate([q[0] for q in queries]), np.concatenate([q[1] for q in queries]))
    out = []
    for (xy, _, corners), h in zip(queries, np.split(hq, np.cumsum([len(q[0]) for q in queries])[:-1])):
        k = len(xy) - len(corners)
        h1 = h[1:k].copy()
        h1[corners - 1] = h[k:]
        out.append((h[: max(k - 1, 0)], h1))
    return out


def _point_sizes(size, pts, known) -> list[tuple[np.ndarray, np.ndarray]]:
    """:func:`_interval_sizes` for an isotropic field, asking it only where ``known`` has no size.

    Parameters
    ----------
    size : SizeField
        Isotropic (:meth:`SizeField.along` not overridden): the spacing at a point is
        ``size(xy)`` whatever the direction, and a corner's two sides get the same one.
    pts : list of (k_i, 2) float64
        Every curve's table points.
    known : list of (k_i,) float64
        Sizes at the table points already asked (NaN where not); filled in place.

    Returns
    -------
    list of (h0, h1)
        As :func:`_interval_sizes`: ``h[:-1]`` and ``h[1:]`` of each curve's point sizes.
    """
    ask = [np.flatnonzero(np.isnan(h)) for h in known]
    if any(len(a) for a in ask):
        hq = size(np.concatenate([p[a] for p, a in zip(pts, ask)]))
        for h, a, part in zip(known, ask, np.split(hq, np.cumsum([len(a) for a in ask])[:-1])):
            h[a] = part
    return [(h[:-1], h[1:]) for h in known]


def _fill_points(curve, t, p) -> np.ndarray:
    """Table points ``p`` (k, 2) with the rows still NaN evaluated at their parameters ``t``
    (the rows kept from the last round are the same parameters, so the same points)."""
    new = np.flatnonzero(np.isnan(p[:, 0]))
    if len(new):
        p[new] = curve.evaluate(t[new])
    return p


def _resolve_size(curves, size, tables):
    """Refine the parameter tables until every interval is at most half the local size.

    The size is the spacing wanted along the curve (:meth:`SizeField.along`), so a
    stretched background grid gives longer segments along its stretching direction.

    Returns the refined tables, their points and the interval end sizes ``(h0, h1)`` of
    :func:`_interval_sizes` (lists, one entry per curve).
    """
    # Sizes at the table points, kept across rounds for an isotropic field (NaN: not asked),
    # and the points themselves (None: the whole table is new).
    iso = isinstance(size, SizeField) and type(size).along is SizeField.along
    known = [np.full(len(t), np.nan) for t in tables]
    carry = [None] * len(curves)
    for _ in range(_MAX_TABLE_ROUNDS):
        pts = [c.evaluate(t) if p is None else _fill_points(c, t, p) for c, t, p in zip(curves, tables, carry)]
        carry = list(pts)
        hv = _point_sizes(size, pts, known) if iso else _interval_sizes(curves, size, tables, pts)
        refined = False
        for k, (t, p, (h0, h1)) in enumerate(zip(tables, pts, hv)):
            need = np.ceil(_chords(p) / (0.5 * np.minimum(h0, h1)))
            if (need <= 1).all():
                continue
            refined = True
            nsub = np.clip(need, 1, _MAX_SPLIT).astype(np.int64)
            # Split interval j into nsub[j] equal parameter steps (t may decrease: arcs).
            left = np.repeat(t[:-1], nsub)
            step = np.repeat((t[1:] - t[:-1]) / nsub, nsub)
            first = np.cumsum(nsub) - nsub
            k_in = np.arange(nsub.sum()) - np.repeat(first, nsub)
            tables[k] = np.concatenate([left + k_in * step, t[-1:]])
            # Each interval's first piece starts at its old start (k_in = 0: t + 0 * step).
            kept = np.full(len(tables[k]), np.nan)
            kept[first] = known[k][:-1]
            kept[-1] = known[k][-1]
            known[k] = kept
            moved = np.full((len(tables[k]), 2), np.nan)
            moved[first] = p[:-1]
            moved[-1] = p[-1]
            carry[k] = moved
        if not refined:
            return tables, pts, hv
    # Each round splits at least eightfold where the size is not met: a field still unmet
    # after 40 rounds shrinks as fast as the table refines (a size going to 0 at a point).
    worst = [(-1.0, 0, 0)]
    for k, (p, (h0, h1)) in enumerate(zip(pts, hv)):
        if len(p) > 1:
            ratio = _chords(p) / np.minimum(h0, h1)
            j = int(np.argmax(ratio))
            worst.append((float(ratio[j]), k, j))
    _, k, j = max(worst)
    x, y = pts[k][j]
    raise SizeError(
        f"the size field keeps shrinking along curve {k} near ({x:.17g}, {y:.17g}) (size "
        f"{min(hv[k][0][j], hv[k][1][j]):.3g} there after {_MAX_TABLE_ROUNDS} rounds of refining the boundary "
        "table): it must stay bounded away from 0 on the boundary"
    )


def place_params(curves, size, factors) -> list[np.ndarray]:
    """Discretisation parameters of each curve, ordered along it, both ends included.

    Parameters
    ----------
    curves : sequence of Curve
    size : SizeField or None
        Spacing along the curves (:meth:`SizeField.along`); None places ``min_segments``
        segments per piece, evenly in arc length.
    factors : (c,) int
        Multipliers of the segment counts (raised where a coarse polygon is invalid).

    Returns
    -------
    list of (k_i,) float64
    """
    tables = [c.fine_params().copy() for c in curves]
    if size is not None:
        tables, pts, hv = _resolve_size(curves, size, tables)
    else:
        pts = [c.evaluate(t) for c, t in zip(curves, tables)]
        hv = [None] * len(curves)
    out = []
    for c, t, p, h, f in zip(curves, tables, pts, hv, factors):
        ds = _chords(p)
        w = ds if h is None else ds * 0.5 * (1.0 / h[0] + 1.0 / h[1])
        breaks = c.breaks()
        npieces = len(breaks) - 1
        piece = np.minimum(c.piece_index(t[:-1]), npieces - 1)
        total = np.bincount(piece, w, minlength=npieces)
        count = np.full(npieces, c.min_segments, dtype=np.int64)
        if h is not None:
            count = np.maximum(count, np.rint(total).astype(np.int64))
        count *= int(f)
        cum = np.concatenate([[0.0], np.cumsum(w)])
        first = np.concatenate([[0.0], np.cumsum(total)])[:-1]
        rep = np.repeat(np.arange(npieces), count)
        k = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
        tt = np.interp(first[rep] + k / count[rep] * total[rep], cum, t)
        # Piece ends are kept exactly (polyline corners).
        tt[k == 0] = breaks[rep[k == 0]]
        out.append(np.concatenate([tt, breaks[-1:]]))
    return out


def unique_rows(xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Merge exactly coincident points, keeping first-occurrence order.

    Parameters
    ----------
    xy : (n, 2) float64

    Returns
    -------
    unique : (u, 2) float64
        Distinct points in order of first occurrence.
    inverse : (n,) int64
        ``unique[inverse] == xy``.
    """
    n = len(xy)
    if n == 0:
        return xy.copy(), np.zeros(0, dtype=np.int64)
    # + 0.0 turns -0.0 into 0.0 so both merge.
    x = xy[:, 0] + 0.0
    y = xy[:, 1] + 0.0
    order = np.lexsort((y, x))
    xs, ys = x[order], y[order]
    new = np.ones(n, dtype=bool)
    new[1:] = (xs[1:] != xs[:-1]) | (ys[1:] != ys[:-1])
    group = np.cumsum(new) - 1
    first = np.full(group[-1] + 1, n, dtype=np.int64)
    np.minimum.at(first, group, order)
    rank = np.empty(len(first), dtype=np.int64)
    rank[np.argsort(first, kind="stable")] = np.arange(len(first))
    inverse = np.empty(n, dtype=np.int64)
    inverse[order] = rank[group]
    return xy[np.sort(first)].copy(), inverse


def interior_seed(seg_a: np.ndarray, seg_b: np.ndarray, what: str) -> np.ndarray:
    """A point strictly inside the polygons formed by segments ``seg_a -> seg_b`` (m, 2).

    Casts horizontal lines through gaps between vertex ordinates (so they miss every
    vertex): the widest gaps and those nearest the quartiles of the height.  The middle of
    the longest inside interval found, confirmed with the exact crossing test, is returned,
    so the seed sits well inside even thin rotated shapes such as flaps.  ``what`` names
    the polygon in the error raised when none is found.
    """
    ys = np.unique(np.concatenate([seg_a[:, 1], seg_b[:, 1]]))
    if len(ys) < 2:
        raise GeometryError(f"cannot find a point strictly inside {what}; it has no height")
    mids = 0.5 * (ys[:-1] + ys[1:])
    quart = np.searchsorted(mids, ys[0] + np.array([0.25, 0.5, 0.75]) * (ys[-1] - ys[0]))
    pick = np.unique(
        np.concatenate([np.argsort(-np.diff(ys))[:8], np.minimum(quart, len(mids) - 1)])
    )
    lines = mids[pick]
    # Every line's crossings at once (segment rows, line columns), then each line's two
    # widest inside intervals as candidates, all confirmed by one crossing test.
    cross = (seg_a[:, 1, None] > lines) != (seg_b[:, 1, None] > lines)
    line, col = np.nonzero(cross.T)
    a, b = seg_a[col], seg_b[col]
    at = a[:, 0] + (lines[line] - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    ends = np.searchsorted(line, np.arange(len(lines) + 1))
    tries, cands = [], []
    for j, y in enumerate(lines):
        xs = np.sort(at[ends[j] : ends[j + 1]])
        widths = xs[1::2] - xs[0:-1:2]
        top = np.argsort(-widths)[:2]
        tries.append(widths[top])
        cands.extend([0.5 * (xs[2 * i] + xs[2 * i + 1]), y] for i in top)
    inside = classify_points(np.array(cands, dtype=np.float64).reshape(-1, 2), seg_a, seg_b) == INSIDE
    # The same choice as trying the candidates one by one: line by line, a line's
    # candidates widest first while wider than the best confirmed interval.
    best, best_w, c = None, 0.0, 0
    for w in tries:
        for i in range(len(w)):
            if w[i] <= best_w:
                break
            if inside[c + i]:
                best, best_w = np.array(cands[c + i]), w[i]
        c += len(w)
    if best is None:
        raise GeometryError(f"cannot find a point strictly inside {what}; is it degenerate?")
    return best
