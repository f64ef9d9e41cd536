"""Cut lines and the convex cells of a recursive bisection (the geometry of :mod:`.partition`).

Source: I. E. Sutherland and G. W. Hodgman, "Reentrant polygon clipping", Comm. ACM 17(1),
1974 (one clipping stage: a convex polygon against one line gives the two convex halves).

A *direction* is ``(axis, n, t)``: the cut is the line ``xy . n == c``, ``t`` runs along it.
Axis-parallel cuts (``axis`` 0: ``x == c``, ``n = (1, 0)``, ``t = (0, 1)``; ``axis`` 1:
``y == c``, ``n = (0, 1)``, ``t = (1, 0)``) read the coordinate itself, so their crossings and
ends keep ``c`` exactly; an oblique one (``axis`` -1) has ``n = (cos a, sin a)``,
``t = (-sin a, cos a)``.  A cell is a convex polygon ``(k, 2)`` float64, counter-clockwise,
with ``labels`` ``(k,)`` int64: the cut that edge ``i`` (vertex ``i`` to ``i + 1``) lies on, -1
on the padded bounding box.  The side ``xy . n > c`` of a cut is its *upper* side.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["AXES", "along", "box", "clip", "contains", "direction", "line_ends", "on_line", "proj", "segment_angle"]


def direction(axis: int, angle: float = 0.0) -> tuple:
    """The direction of an axis-parallel cut (``axis`` 0 or 1) or of an oblique one (``axis``
    -1, its normal at ``angle`` radians from the x axis)."""
    if axis == 0:
        return 0, np.array([1.0, 0.0]), np.array([0.0, 1.0])
    if axis == 1:
        return 1, np.array([0.0, 1.0]), np.array([1.0, 0.0])
    n = np.array([math.cos(angle), math.sin(angle)])
    return -1, n, np.array([-n[1], n[0]])


AXES = (direction(0), direction(1))


def proj(xy: np.ndarray, d) -> np.ndarray:
    """``xy . n`` of points ``(..., 2)``: the coordinate itself for an axis-parallel cut."""
    axis, n, _ = d
    return xy[..., axis] if axis >= 0 else xy[..., 0] * n[0] + xy[..., 1] * n[1]


def along(xy: np.ndarray, d) -> np.ndarray:
    """``xy . t`` of points ``(..., 2)``: the position along the cut."""
    axis, _, t = d
    return xy[..., 1 - axis] if axis >= 0 else xy[..., 0] * t[0] + xy[..., 1] * t[1]


def on_line(p: np.ndarray, q: np.ndarray, d, c: float) -> np.ndarray:
    """The point where segment ``p -> q`` (each (2,)) crosses the cut ``(d, c)``."""
    sp, sq = float(proj(p, d)) - c, float(proj(q, d)) - c
    x = p + (sp / (sp - sq)) * (q - p)
    if d[0] >= 0:
        x[d[0]] = c
    return x


def box(x0: float, y0: float, x1: float, y1: float) -> tuple[np.ndarray, np.ndarray]:
    """The root cell: a counter-clockwise box and its edge labels (all -1)."""
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], dtype=np.float64), np.full(4, -1, dtype=np.int64)


def clip(poly: np.ndarray, labels: np.ndarray, d, c: float, label: int):
    """Split a convex cell by the cut ``(d, c)``.

    Returns
    -------
    (lower, lower_labels), (upper, upper_labels), ends
        The halves ``xy . n < c`` and ``> c`` with their edge labels (the new edge along the
        cut gets ``label``), and the cut's two ends ``[(xy (2,), label of the edge it lies
        on)]`` sorted along ``t``.
    """
    s = proj(poly, d) - c
    m = len(poly)
    halves = ([], [], []), ([], [], [])  # per half: points, labels of the edges they start, on the cut
    ends = []
    for i in range(m):
        j = (i + 1) % m
        for h, sign in ((0, -1.0), (1, 1.0)):
            if s[i] * sign >= 0.0:
                halves[h][0].append(poly[i])
                halves[h][1].append(int(labels[i]))
                halves[h][2].append(s[i] == 0.0)
        if s[i] == 0.0:
            ends.append((poly[i].copy(), int(labels[i])))
        if s[i] * s[j] < 0.0:
            x = on_line(poly[i], poly[j], d, c)
            ends.append((x, int(labels[i])))
            for h in (0, 1):
                halves[h][0].append(x)
                halves[h][1].append(int(labels[i]))
                halves[h][2].append(True)
    out = []
    for pts, labs, on in halves:
        lab = np.array(labs, dtype=np.int64)
        on = np.array(on, dtype=bool)
        # An edge between two points on the cut lies along it.
        lab[on & np.roll(on, -1)] = label
        out.append((np.array(pts, dtype=np.float64), lab))
    ends.sort(key=lambda e: float(along(e[0], d)))
    return out[0], out[1], ends[:1] + ends[-1:]


def line_ends(poly: np.ndarray, labels: np.ndarray, d, cs: np.ndarray):
    """Where the cuts ``(d, cs[j])`` leave a convex cell: ``(xy (k, 2, 2), labels (k, 2))``,
    the two ends of each candidate and the label of the edge each lies on (all candidates
    strictly inside the cell's extent along ``n``)."""
    s = proj(poly, d)[None, :] - cs[:, None]  # (k, m)
    sn = np.roll(s, -1, axis=1)
    cross = (s * sn < 0.0) | ((s == 0.0) & (sn != 0.0))
    # The first two crossed edges of each candidate (a convex cell has exactly two).
    edges = np.argsort(~cross, axis=1, kind="stable")[:, :2]
    found = np.take_along_axis(cross, edges, axis=1)
    q = np.roll(poly, -1, axis=0)
    se, sne = np.take_along_axis(s, edges, axis=1), np.take_along_axis(sn, edges, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        f = np.where(found, se / (se - sne), 0.0)
    xy = poly[edges] + f[..., None] * (q[edges] - poly[edges])
    lab = np.where(found, labels[edges], -1)
    return xy, lab


def segment_angle(d: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Angles in degrees, in ``[0, 90]``, between segments ``d`` ``(s, 2)`` and a line along ``t``."""
    cos = np.abs(d @ t) / np.hypot(d[:, 0], d[:, 1])
    return np.degrees(np.arccos(np.clip(cos, 0.0, 1.0)))


def contains(poly: np.ndarray, xy: np.ndarray) -> np.ndarray:
    """Whether points ``xy`` (e, 2) lie in the convex cell or on its edges (to round-off)."""
    a = poly
    b = np.roll(poly, -1, axis=0)
    scale = float(np.ptp(poly, axis=0).max()) ** 2
    cross = (b[None, :, 0] - a[None, :, 0]) * (xy[:, None, 1] - a[None, :, 1]) - (
        b[None, :, 1] - a[None, :, 1]
    ) * (xy[:, None, 0] - a[None, :, 0])
    return (cross >= -1e-12 * scale).all(axis=1)
