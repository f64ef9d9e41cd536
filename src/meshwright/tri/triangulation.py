"""2-D Delaunay triangulation: public :func:`delaunay` and the :class:`Triangulation` it returns.

Sources: Bowyer (1981) and Watson (1981), chapter 18.1.1-18.1.2, through the shared
insertion kernel :mod:`meshwright.tri._kernel2d`; insertion order by BRIO (Amenta, Choi &
Rote 2003) with Hilbert-sorted rounds (:mod:`meshwright.core.spatial_sort`).

Pipeline of :func:`delaunay`
----------------------------
1. Validate once: shape (n, 2), finite, inside the predicates' exact range
   (:func:`meshwright.core.validate_input.check_coordinate_range`), a valid seed, at least
   three distinct points not all collinear.
2. Order: BRIO from ``numpy.random.default_rng(seed)``; the first point not coinciding with
   the first, and the first not collinear with those two, are moved to positions 1 and 2 so
   insertion starts from a non-degenerate triangle and its three ghosts.
3. Copy the points in that order (vertex k = k-th inserted point, for memory locality) and
   insert them with the chosen algorithm's conflict test (``DELAUNAY_ALGORITHMS``).  A point
   equal to an inserted vertex is detected by the walk and not inserted.
4. Renumber to input order (triangles relabelled, rows copied back from the input).  The insertion
   ranks remain the keys of the symbolic perturbation (``_rank``), so later insertions see
   the same perturbed point set.
5. Duplicates: ``"reject"`` raises :class:`DuplicatePointError`; ``"merge"`` drops them and
   renumbers the remaining vertices monotonically, keys densely in the same order.
6. Compact the slots: finite triangles first, ghost triangles last.

State kept by :class:`Triangulation` (so :meth:`Triangulation.insert` is incremental)
-----------------------------------------------------------------------------------
``state``, the kernel's :class:`~meshwright.tri._kernel2d.TriState` (points (cap, 2) with the
first ``nv = meta[M_NV]`` rows used, ``tri``/``nbr`` with 3 entries per triangle slot, ghosts
included, Watson's ``circ``, ``rank``, ...), and ``_nt`` finite triangles occupying slots
``[0, nt)``.  ``triangles`` is a read-only view of ``state.tri``; an insertion copies it
first if that view was handed out, so arrays already returned never change.
Memory of a bulk build: about 76 bytes per point for Bowyer (108 for Watson) besides the
input.

Invariants: every point is a vertex (duplicates merged), all triangles strictly
counter-clockwise, the empty-circumcircle property holds exactly (under symbolic
perturbation for cocircular points), ``nt = 2 nv - h - 2`` for h hull vertices.
"""

from __future__ import annotations

from types import ModuleType
from typing import NamedTuple

import numpy as np

from meshwright.core.errors import DegenerateInputError, DuplicatePointError, InputError, MeshingError
from meshwright.core.spatial_sort import brio_order
from meshwright.core.validate_input import as_exact_points, check_seed
from meshwright.tri import bowyer, watson
from meshwright.tri._build2d import (
    compact, find_start, hull_loop, init_triangle, insert_batch, locate_points, promote, relabel,
)
from meshwright.tri._kernel2d import M_NTRI, M_NV, grow, new_state

__all__ = ["DelaunayAlgorithm", "DELAUNAY_ALGORITHMS", "Triangulation", "delaunay"]


class DelaunayAlgorithm(NamedTuple):
    """An insertion algorithm for the shared kernel.

    Attributes
    ----------
    name : str
    module : module
        :mod:`meshwright.tri.bowyer` or :mod:`meshwright.tri.watson`, its conflict test.
    keeps_circles : bool
        Whether a circle record (4 float32) is stored per triangle; this is what selects the
        conflict test inside the kernel.
    """

    name: str
    module: ModuleType
    keeps_circles: bool


DELAUNAY_ALGORITHMS = {
    "bowyer": DelaunayAlgorithm("bowyer", bowyer, False),
    "watson": DelaunayAlgorithm("watson", watson, True),
}


def _duplicate_message(vmap: np.ndarray, pts: np.ndarray) -> str:
    """Describe the first coincident pairs; ``vmap`` (n,) int32 maps each point to its vertex."""
    dup = np.flatnonzero(vmap != np.arange(vmap.size))
    pairs = [f"{min(i, vmap[i])} and {max(i, vmap[i])} at {pts[i].tolist()}" for i in dup[:3].tolist()]
    more = f" (and {dup.size - 3} more)" if dup.size > 3 else ""
    return "coincident points: " + "; ".join(pairs) + more


class Triangulation:
    """Delaunay triangulation of a 2-D point set, built incrementally (Bowyer or Watson).

    Parameters
    ----------
    points : (n, 2) array_like of float64
        At least three distinct, finite, not all collinear points.
    algorithm : {"bowyer", "watson"}
        Insertion algorithm (``DELAUNAY_ALGORITHMS``); both give the same triangulation.
    duplicates : {"merge", "reject"}
        Coincident points are merged into one vertex (``index_map``), or rejected with
        :class:`~meshwright.core.errors.DuplicatePointError`.
    seed : int or numpy.random.Generator
        Randomness of the insertion order and of the walk; the result is a function of it.

    Attributes
    ----------
    algorithm : str
    index_map : (n,) int32
        Vertex of each input point of the constructor (duplicates share one).
    state : TriState
        The insertion kernel's bundle (:mod:`meshwright.tri._kernel2d`), for code built on
        the kernel; replaced (not resized) when it grows.

    Notes
    -----
    ``points`` (nv, 2) float64, ``triangles`` (nt, 3) int32 counter-clockwise,
    ``neighbors`` (nt, 3) int32 (``neighbors[t, k]`` across the edge opposite
    ``triangles[t, k]``, -1 on the hull), ``hull`` (h,) int32 counter-clockwise and ``edges``
    (ne, 2) int32 are read-only arrays valid until the next :meth:`insert`.  Vertices are the
    distinct input points in input order; of coincident points the one inserted first is kept.
    """

    def __init__(self, points, algorithm: str = "bowyer", duplicates: str = "merge", seed=0):
        if algorithm not in DELAUNAY_ALGORITHMS:
            raise InputError(f"unknown algorithm {algorithm!r}; choose from {sorted(DELAUNAY_ALGORITHMS)}")
        if duplicates not in ("merge", "reject"):
            raise InputError(f"duplicates must be 'merge' or 'reject', got {duplicates!r}")
        seed = check_seed(seed)
        self.algorithm = algorithm
        self._alg = DELAUNAY_ALGORITHMS[algorithm]
        self._rng = np.random.default_rng(seed)
        self._cache: dict = {}
        self._exported = False
        pts = as_exact_points(points, "points")
        n = pts.shape[0]
        if n < 3:
            raise DegenerateInputError(f"a triangulation needs at least 3 points, got {n}")
        order = self._order(pts)
        # Build with vertex k = order[k], so neighbours in space are neighbours in memory, then
        # renumber to input order; the insertion ranks stay the perturbation keys.
        self.state = new_state(pts[order], 2 * n, int(self._rng.integers(1, 2**31)), circles=self._alg.keeps_circles)
        self._nv = n
        init_triangle(self.state, 0, 1, 2)
        vmap = np.empty(n, dtype=np.int32)
        vmap[:3] = np.arange(3)
        self._insert_rows(np.empty(0, dtype=np.int32), 3, n, vmap, 0)
        relabel(self.state.tri, self.state.meta[M_NTRI], order, 0)
        self.state.pts[:n] = pts  # rows back in input order: a sequential copy, not a scatter
        index_map = np.empty(n, dtype=np.int32)
        index_map[order] = order[vmap]
        del vmap
        rank = np.empty(n, dtype=np.int32)
        rank[order] = np.arange(n, dtype=np.int32)
        self.state = self.state._replace(rank=rank)
        del order
        if duplicates == "reject" and np.any(index_map != np.arange(n)):
            raise DuplicatePointError(_duplicate_message(index_map, self.state.pts))
        self.index_map = self._merge(index_map, 0)
        self._nt = compact(self.state)

    @property
    def _nv(self) -> int:
        return int(self.state.meta[M_NV])

    @_nv.setter
    def _nv(self, nv: int) -> None:
        self.state.meta[M_NV] = nv

    def _order(self, pts: np.ndarray) -> np.ndarray:
        """BRIO order (int32) whose first three points form a non-degenerate triangle."""
        order = brio_order(pts, self._rng)
        i, j = find_start(pts, order)
        if i < 0:
            raise DegenerateInputError(f"all {pts.shape[0]} points coincide at {pts[order[0]].tolist()}")
        if j < 0:
            a, b = int(order[0]), int(order[i])
            raise DegenerateInputError(
                f"all {pts.shape[0]} points are collinear, on the line through point {a} "
                f"{pts[a].tolist()} and point {b} {pts[b].tolist()}"
            )
        promote(order, i, 1)
        promote(order, j, 2)
        return order.astype(np.int32)

    def _insert_rows(self, order: np.ndarray, start: int, stop: int, vmap: np.ndarray, vbase: int) -> None:
        """Run the kernel on ``order[start:stop]``; ``vmap[v - vbase]`` receives each vertex."""
        bad, self.state = insert_batch(order, start, stop, vbase, self.state, vmap)
        if bad >= 0:
            self._nt = compact(self.state)
            raise MeshingError(
                f"inserting point {bad} at {self.state.pts[bad].tolist()} met an inconsistent cavity; "
                "the triangulation is no longer usable"
            )

    def _merge(self, vmap: np.ndarray, base: int) -> np.ndarray:
        """Drop duplicate rows ``>= base``, renumber monotonically; return the updated ``vmap``.

        Perturbation keys keep their relative order: ranks of the kept vertices are renumbered
        densely, so every later vertex id is a larger key than all of them.
        """
        keep = vmap == np.arange(base, base + vmap.size, dtype=np.int32)
        if keep.all():
            self._nv = base + vmap.size
            return vmap
        newid = (base + np.cumsum(keep) - 1).astype(np.int32)
        relabel(self.state.tri, self.state.meta[M_NTRI], newid, base)
        kept = int(newid[-1]) + 1
        pts = self.state.pts
        pts[base:kept] = pts[base : base + vmap.size][keep]
        self._nv = kept
        rank = self.state.rank
        if base < rank.size:
            ranks = rank[keep]
            dense = np.zeros(rank.size, dtype=np.int32)
            dense[ranks] = 1
            self.state = self.state._replace(rank=(np.cumsum(dense, dtype=np.int32) - 1)[ranks])
        out = vmap.copy()
        new = vmap >= base
        out[new] = newid[vmap[new] - base]
        return out

    # ------------------------------------------------------------------ public arrays
    @property
    def points(self) -> np.ndarray:
        """(nv, 2) float64 vertex coordinates (read-only view)."""
        view = self.state.pts[: self._nv]
        view.flags.writeable = False
        return view

    @property
    def triangles(self) -> np.ndarray:
        """(nt, 3) int32 finite triangles, counter-clockwise (read-only view)."""
        self._exported = True
        view = self.state.tri[: 3 * self._nt].reshape(self._nt, 3)
        view.flags.writeable = False
        return view

    @property
    def neighbors(self) -> np.ndarray:
        """(nt, 3) int32: ``neighbors[t, k]`` is across the edge opposite vertex k, -1 on the hull."""
        if "neighbors" not in self._cache:
            nb = self.state.nbr[: 3 * self._nt].reshape(self._nt, 3)
            out = np.where(nb >= self._nt, np.int32(-1), nb).astype(np.int32)
            out.flags.writeable = False
            self._cache["neighbors"] = out
        return self._cache["neighbors"]

    @property
    def hull(self) -> np.ndarray:
        """(h,) int32 convex-hull vertices, counter-clockwise, collinear hull points included."""
        if "hull" not in self._cache:
            h = int(self.state.meta[M_NTRI]) - self._nt
            out = hull_loop(self.state.tri, self.state.nbr, self._nt, h)
            out.flags.writeable = False
            self._cache["hull"] = out
        return self._cache["hull"]

    @property
    def edges(self) -> np.ndarray:
        """(ne, 2) int32 unique edges, ``edges[:, 0] < edges[:, 1]``, grouped by triangle."""
        if "edges" not in self._cache:
            tri = self.triangles
            nb = self.neighbors
            own = (nb < 0) | (nb > np.arange(self._nt, dtype=np.int32)[:, None])
            ends = np.stack([tri[:, [1, 2, 0]], tri[:, [2, 0, 1]]], axis=-1)[own]
            out = np.sort(ends, axis=1).astype(np.int32)
            out.flags.writeable = False
            self._cache["edges"] = out
        return self._cache["edges"]

    def __repr__(self) -> str:
        return (
            f"Triangulation({self.algorithm}: {self._nv} points, {self._nt} triangles, "
            f"{int(self.state.meta[M_NTRI]) - self._nt} hull vertices)"
        )

    # ------------------------------------------------------------------ operations
    def insert(self, points) -> np.ndarray:
        """Insert points into the triangulation (Delaunay is maintained incrementally).

        Parameters
        ----------
        points : (k, 2) array_like of float64
            Finite points; several are inserted in BRIO order.

        Returns
        -------
        (k,) int32
            Vertex of each point; a point equal to an existing vertex (or to an earlier point
            of this call) maps to that vertex and adds nothing.
        """
        new = as_exact_points(np.reshape(points, (-1, 2)) if np.size(points) == 2 else points, "points")
        k = new.shape[0]
        if k == 0:
            return np.empty(0, dtype=np.int32)
        base = self._nv
        rows = base + k
        self.state = grow(self.state, rows=rows)
        self.state.pts[base:rows] = new
        if self._exported:
            self.state = self.state._replace(tri=self.state.tri.copy())
            self._exported = False
        self._cache.clear()
        order = (brio_order(new, self._rng) + base).astype(np.int32)
        vmap = np.empty(k, dtype=np.int32)
        self._nv = rows
        self._insert_rows(order, 0, k, vmap, base)
        out = self._merge(vmap, base)
        self._nt = compact(self.state)
        return out

    def locate(self, xy):
        """Triangle containing each point (boundary included), -1 outside the convex hull.

        Parameters
        ----------
        xy : (2,) or (m, 2) array_like of float64

        Returns
        -------
        int or (m,) int32
            Index into ``triangles``.
        """
        arr = np.asarray(xy, dtype=np.float64)
        single = arr.shape == (2,)
        q = as_exact_points(arr.reshape(1, 2) if single else arr, "xy")
        out = locate_points(self.state._replace(meta=self.state.meta.copy()), q)
        return int(out[0]) if single else out

    def to_mesh(self):
        """The triangulation as a :class:`meshwright.core.mesh.Mesh` with one ``"triangle"`` block."""
        from meshwright.core.mesh import Mesh

        return Mesh(np.array(self.points), {"triangle": np.array(self.triangles)})


def delaunay(points, algorithm: str = "bowyer", duplicates: str = "merge", seed=0) -> Triangulation:
    """Delaunay triangulation of 2-D points (chapter 18.1: Bowyer or Watson insertion).

    Parameters
    ----------
    points : (n, 2) array_like of float64
        At least three distinct, finite, not all collinear points; every nonzero coordinate
        of magnitude in ``[2**-148, 2**200]``, where the predicates are exact (see
        :mod:`meshwright.core.validate_input`: scale by a power of two to get there).
    algorithm : {"bowyer", "watson"}
        Insertion algorithm; both give the identical triangulation.
    duplicates : {"merge", "reject"}
        Merge coincident points into one vertex (see ``Triangulation.index_map``) or raise
        :class:`~meshwright.core.errors.DuplicatePointError` naming them.
    seed : int or numpy.random.Generator
        Randomness of the insertion order (BRIO) and of the point-location walk: a
        non-negative int (not a bool or float) or a Generator.

    Returns
    -------
    Triangulation

    Raises
    ------
    InputError
        Wrong shape, non-numeric, NaN or infinite coordinates, a coordinate outside the
        predicates' exact range, a bad seed, unknown option.
    DegenerateInputError
        Fewer than three distinct points, or all collinear.
    DuplicatePointError
        Coincident points with ``duplicates="reject"``.
    """
    return Triangulation(points, algorithm=algorithm, duplicates=duplicates, seed=seed)
