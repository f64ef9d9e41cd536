"""Exchange rounds: the interface splits one part made, made by its neighbour too.

Source: A. Chernikov and N. Chrisochoides, "Parallel 2D constrained Delaunay mesh generation",
ACM TOMS 34(1), 2008 (PCDM: a part that must split an interface subsegment sends the split to
its neighbour, which splits the same subsegment); here the messages go through the client in
rounds, so the result does not depend on their timing.

A split point is named ``(s, f)``: skeleton segment ``s`` and the dyadic fraction ``f``
(:class:`fractions.Fraction`) of it where it lies (:mod:`meshwright.distributed.part`).  The
client keeps every point made so far (:class:`Splits`, the union over the parts) and what
each part has; after a round, every part beside a segment gets the points of it that it
lacks, shallowest first (a point's two ends then exist in the part: they are the ends of its
dyadic interval, and no point of the part lies inside that interval, or the part would have
that interval's midpoint, the point itself).  The same point made by both sides must have the
same coordinates (checked).  After the last round the points take global ids after the
skeleton's, in ``(s, f)`` order: they depend only on the points, never on the workers.

Layout: ``Splits.xy`` maps ``(s, f)`` to an ``(x, y)`` tuple of floats; ``have[i]`` is the set
of names part ``i`` holds.
"""

from __future__ import annotations

import numpy as np

from meshwright.core.errors import MeshingError
from meshwright.distributed.partition import KIND_INTERFACE, Decomposition

__all__ = ["Splits"]


class Splits:
    """The interface split points of a run and which part holds which (module docstring).

    Parameters
    ----------
    dec : Decomposition
    """

    def __init__(self, dec: Decomposition):
        self.xy = {}
        self.have = [set() for _ in range(dec.n_parts)]
        iface = np.flatnonzero(dec.kind == KIND_INTERFACE)
        # The two parts beside each interface segment.
        self.sides = {int(s): (int(dec.left[s]), int(dec.right[s])) for s in iface.tolist()}

    def add(self, i: int, names, xy: np.ndarray) -> None:
        """Record the points part ``i`` made (``names`` (k,) of ``(s, f)``, ``xy`` (k, 2) float64)."""
        for (s, f), (x, y) in zip(names, np.asarray(xy, dtype=np.float64).reshape(-1, 2).tolist()):
            old = self.xy.setdefault((s, f), (x, y))
            if old != (x, y):
                raise MeshingError(
                    f"part {i} split skeleton segment {s} at {f} at ({x!r}, {y!r}) but another part at "
                    f"({old[0]!r}, {old[1]!r}): the two sides would not match"
                )
            self.have[i].add((s, f))

    def lacking(self) -> dict:
        """Per part that lacks some, the points of its segments it lacks, shallowest first.

        Returns
        -------
        dict
            Part -> list of ``(s, f, x, y)``, sorted by ``(denominator of f, s, f)``.  Making
            them marks them held.
        """
        out = {}
        for (s, f), (x, y) in self.xy.items():
            for i in self.sides[s]:
                if i >= 0 and (s, f) not in self.have[i]:
                    out.setdefault(i, []).append((s, f, x, y))
        for i, todo in out.items():
            todo.sort(key=lambda t: (t[1].denominator, t[0], t[1]))
            self.have[i].update((s, f) for s, f, _, _ in todo)
        return dict(sorted(out.items()))

    def numbered(self, n_skeleton: int) -> tuple[dict, np.ndarray]:
        """Global ids of the points, after the skeleton's ``n_skeleton``, in ``(s, f)`` order.

        Returns
        -------
        dict
            ``(s, f) -> id`` (int64 range ``[n_skeleton, n_skeleton + k)``).
        (k, 2) float64
            Their coordinates in id order.
        """
        names = sorted(self.xy)
        ids = {name: n_skeleton + k for k, name in enumerate(names)}
        xy = np.array([self.xy[name] for name in names], dtype=np.float64).reshape(-1, 2)
        return ids, xy

    def of_part(self, i: int, ids: dict) -> dict:
        """The ids of the points part ``i`` holds (what its writing task needs)."""
        return {name: ids[name] for name in sorted(self.have[i])}
