"""Exchange rounds: split requests on interfaces turned into the same splits on both sides.

Source: A. Chernikov and N. Chrisochoides, "Parallel 2D constrained Delaunay mesh generation",
ACM TOMS 34(1), 2008 (PCDM: a part that must split an interface subsegment sends the split to
its neighbour, which splits the same subsegment); here the messages go through the client in
rounds, so the result does not depend on their timing.

Rule: refinement splits a straight subsegment at its midpoint, recursively, so the points it
put on an interface segment ``a -> b`` sit at dyadic fractions of it.  The split of a skeleton
segment reproduces them: starting from ``[0, 1]``, an interval is halved while a requested point
lies strictly inside it (away from its ends by :data:`_END_TOL` of its length), and the new
points are ``a + m (b - a)`` for the dyadic ``m``: computed once, from the skeleton's own
coordinates, so both parts get the same bits (an axis-parallel cut keeps its coordinate
exactly).  Requests of both parts are merged; segments are processed in skeleton order and each
split segment's pieces replace it in place, so the new skeleton ids depend only on the
requests, never on which worker answered first.
"""

from __future__ import annotations

import numpy as np

from meshwright.distributed.partition import Decomposition

__all__ = ["apply_splits", "split_fractions"]

_END_TOL = 1e-3


def split_fractions(f: np.ndarray) -> np.ndarray:
    """Dyadic split positions in ``(0, 1)`` covering requested fractions ``f`` (module docstring).

    Parameters
    ----------
    f : (k,) float64
        Fractions along the segment of the points refinement put on it.

    Returns
    -------
    (j,) float64
        Sorted, at least one value when ``f`` holds a fraction inside ``(0, 1)``.
    """
    out = []
    stack = [(0.0, 1.0)]
    while stack:
        lo, hi = stack.pop()
        tol = _END_TOL * (hi - lo)
        if not np.any((f > lo + tol) & (f < hi - tol)):
            continue
        m = 0.5 * (lo + hi)
        out.append(m)
        stack.append((lo, m))
        stack.append((m, hi))
    return np.sort(np.array(out, dtype=np.float64))


def apply_splits(dec: Decomposition, requests: dict) -> tuple[Decomposition, np.ndarray]:
    """The skeleton with the requested interface segments split, and the parts to mesh again.

    Parameters
    ----------
    dec : Decomposition
    requests : dict
        Skeleton segment id -> (k, 2) float64 points refinement put on it (both parts merged).

    Returns
    -------
    Decomposition
        New skeleton: points appended, every split segment replaced in place by its pieces.
    (r,) int32
        Sorted parts on either side of a split segment.
    """
    pts = [dec.points]
    n = len(dec.points)
    rows = []  # per old segment: the new rows (as arrays of end ids)
    touched = []
    for s in range(len(dec.segments)):
        a, b = dec.segments[s]
        if s not in requests:
            rows.append(np.array([[a, b]], dtype=np.int64))
            continue
        pa, pb = dec.points[a], dec.points[b]
        d = pb - pa
        q = np.asarray(requests[s], dtype=np.float64).reshape(-1, 2)
        f = ((q - pa) @ d) / (d @ d)
        m = split_fractions(f)
        if len(m) == 0:
            rows.append(np.array([[a, b]], dtype=np.int64))
            continue
        new = pa + m[:, None] * d
        # The cut's own coordinate stays exact (d is zero along it).
        new[:, d == 0.0] = pa[d == 0.0]
        ids = np.arange(n, n + len(m), dtype=np.int64)
        n += len(m)
        pts.append(new)
        chain = np.concatenate([[a], ids, [b]])
        rows.append(np.column_stack([chain[:-1], chain[1:]]))
        touched.extend([int(dec.left[s]), int(dec.right[s])])
    counts = np.array([len(r) for r in rows], dtype=np.int64)
    old = np.repeat(np.arange(len(dec.segments)), counts)
    new_dec = dec._replace(
        points=np.ascontiguousarray(np.concatenate(pts)),
        point_markers=np.concatenate([dec.point_markers, np.zeros(n - len(dec.points), dtype=np.int32)]),
        segments=np.concatenate(rows),
        kind=dec.kind[old],
        left=dec.left[old],
        right=dec.right[old],
        markers=dec.markers[old],
        curve=dec.curve[old],
        params=dec.params[old],
    )
    parts = np.unique(np.array([p for p in touched if p >= 0], dtype=np.int32))
    return new_dec, parts
