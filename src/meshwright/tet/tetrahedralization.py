"""3-D Delaunay tetrahedralization: :class:`Tetrahedralization` and its builder.

Sources: Bowyer (1981) and Watson (1981), chapter 18.1.1-18.1.2 and the 3-D procedure of
18.4.1, through the shared insertion kernel :mod:`meshwright.tet._kernel3d`; insertion order
by BRIO (Amenta, Choi & Rote 2003) with Hilbert-sorted rounds
(:mod:`meshwright.core.spatial_sort`).

Pipeline
--------
1. Validate once: shape (n, 3), finite, at least four points not all coplanar.
2. Order: BRIO from ``numpy.random.default_rng(seed)``; the first point differing from the
   first, the first not collinear with those two and the first not coplanar with those three
   move to positions 1, 2, 3, so insertion starts from a proper tet and its four ghosts
   (``superstructure="ghost"``), or every point goes into the chapter's box
   (``superstructure="box"``).
3. Copy the points in that order (vertex k = k-th inserted point, for memory locality) and
   insert them with the chosen algorithm's conflict test (``TET_ALGORITHMS``).  A point equal
   to an inserted vertex is found by the walk and not inserted.
4. Renumber to input order; the insertion ranks stay the perturbation keys (``rank``).
5. Duplicates: ``"reject"`` raises :class:`DuplicatePointError`, ``"merge"`` drops them and
   renumbers the rest monotonically, keys densely in the same order.
6. Compact: finite tets first, ghosts last, freed slots dropped.

Superstructures
---------------
``"ghost"`` (default): a symbolic vertex at infinity; the result is the Delaunay
tetrahedralization of the convex hull.  ``"box"``: the chapter's eight supplementary points
(18.4.1 steps 2-3), a hexahedron one bounding-box extent away from the points on every side,
split into five tets; the points are inserted into it and the tets attached to a box point
are dropped at the end.  That loses every hull tet whose circumsphere contains a box point
(large, flat tets on the hull are not Delaunay once the box points exist): the result is a
subset of the ghost result, its boundary not always the convex hull.  Box vertices occupy
internal rows 0-7 and keep the lowest perturbation keys; points inserted later must lie
strictly inside the box.

State kept (so :meth:`Tetrahedralization.insert` is incremental): the kernel bundle
:class:`meshwright.tet._kernel3d.TetState`, the box offset ``vb`` (0 or 8 internal rows before
the vertices), ``nv`` vertices and ``nt`` finite tets in slots ``[0, nt)``.  Memory of a
Bowyer bulk build: 32 bytes per tet slot, about 7 slots per point, plus the coordinates,
keys and scratch: about 270 bytes per point at its peak (Watson adds 20 bytes per slot).
"""

from __future__ import annotations

from types import ModuleType
from typing import NamedTuple

import numpy as np

from meshwright.core.errors import DegenerateInputError, DuplicatePointError, InputError, MeshingError, fmt_point
from meshwright.core.flat import TET_FACES, grown
from meshwright.core.rng import seed_state
from meshwright.core.spatial_sort import brio_order
from meshwright.core.validate_input import as_exact_points, check_coordinate_range, check_seed
from meshwright.tet import bowyer, watson
from meshwright.tet._build3d import compact_tagged, find_start, first_repeat, init_tets, input_order_maps, relabel, scatter_rows
from meshwright.tet._kernel3d import (
    BROKEN,
    M_NEED,
    M_NEEDN,
    M_NTET,
    NEED_CAV,
    NEED_FACES,
    NEED_FREE,
    NEED_LOCAL,
    NEED_SPACE,
    NEED_TETS,
    NEED_VERTS,
    TetState,
    insert_batch,
    locate_points,
    new_meta,
)

__all__ = ["TetAlgorithm", "TET_ALGORITHMS", "SUPERSTRUCTURES", "BOX_TETS", "Tetrahedralization", "grow", "delaunay3d"]


class TetAlgorithm(NamedTuple):
    """An insertion algorithm of the 3-D kernel.

    Attributes
    ----------
    name : str
    module : module
        :mod:`meshwright.tet.bowyer` or :mod:`meshwright.tet.watson`, its conflict test.
    keeps_spheres : bool
        Whether a sphere record (5 float32) is stored per tet; this selects the test.
    """

    name: str
    module: ModuleType
    keeps_spheres: bool


TET_ALGORITHMS = {
    "bowyer": TetAlgorithm("bowyer", bowyer, False),
    "watson": TetAlgorithm("watson", watson, True),
}
SUPERSTRUCTURES = ("ghost", "box")

# The chapter's hexahedron split into five tets: the central one and four corners
# (corner i has coordinates (i & 1, (i >> 1) & 1, (i >> 2) & 1) of the box).
BOX_TETS = np.array([[0, 3, 5, 6], [1, 0, 3, 5], [2, 0, 3, 6], [4, 0, 5, 6], [7, 3, 5, 6]])
_SCRATCH = 64  # initial cavity / face / local-vertex capacity


def grow(s: TetState) -> TetState:
    """A bundle whose array named by ``meta[M_NEED]`` holds ``meta[M_NEEDN]`` (doubling).

    Parameters
    ----------
    s : TetState
        After the kernel returned ``NEED_SPACE``.

    Returns
    -------
    TetState
        ``s`` with the short array(s) replaced by grown copies (:func:`meshwright.core.flat.grown`),
        or by new uninitialised arrays for the scratch ones (:func:`_scratch`).
    """
    code = int(s.meta[M_NEED])
    size = int(s.meta[M_NEEDN])
    if code == NEED_TETS:
        sph = grown(s.sph, watson.RECORD * size) if s.sph.size else s.sph
        return s._replace(tet=grown(s.tet, 4 * size), nbr=grown(s.nbr, 4 * size), sph=sph)
    if code == NEED_CAV:
        return s._replace(cav=_scratch(s.cav, size))
    if code == NEED_FACES:
        return s._replace(bnd=_scratch(s.bnd, 4 * size), twin=_scratch(s.twin, 3 * size))
    if code == NEED_LOCAL:
        return s._replace(vloc=_scratch(s.vloc, size), etab=_scratch(s.etab, size * size))
    if code == NEED_FREE:
        return s._replace(free=grown(s.free, size))
    if code == NEED_VERTS:
        return s._replace(vmark=_scratch(s.vmark, size))
    raise MeshingError(f"the 3-D kernel asked for space with unknown code {code}")


def _scratch(a: np.ndarray, need: int) -> np.ndarray:
    """``a`` if it holds ``need`` entries, else a new uninitialised array of max(need, 2 len(a))
    entries.  For the kernels' scratch arrays (cavity, faces, local vertex and edge tables,
    vertex marks): the kernel undoes its cavity before asking for space and rebuilds them on
    the retry, so their contents need no copy.  The edge table has (local vertices)**2
    entries: copying it as one cavity of the level-5 sphere's run grew to over 8,192
    boundary vertices was 0.22 of the 0.24 s CPU of all growths in that run (now 0.02 s).
    """
    if need <= a.shape[0]:
        return a
    return np.empty(max(need, 2 * a.shape[0]), dtype=a.dtype)


def _box_corners(pts: np.ndarray) -> np.ndarray:
    """(8, 3) corners of the chapter's box: the bounding box widened by its extent."""
    lo = pts.min(axis=0)
    hi = pts.max(axis=0)
    margin = float((hi - lo).max())
    lo = lo - margin
    hi = hi + margin
    i = np.arange(8)
    return np.stack([np.where(i & 1, hi[0], lo[0]), np.where(i & 2, hi[1], lo[1]), np.where(i & 4, hi[2], lo[2])], axis=1)


class Tetrahedralization:
    """Delaunay tetrahedralization of a 3-D point set, built incrementally (Bowyer or Watson).

    Parameters
    ----------
    points : (n, 3) array_like of float64
        At least four finite points, not all coplanar.
    algorithm : {"bowyer", "watson"}
        Insertion algorithm (``TET_ALGORITHMS``); both give the same tetrahedralization.
    duplicates : {"merge", "reject"}
        Coincident points are merged into one vertex (``index_map``), or rejected with
        :class:`~meshwright.core.errors.DuplicatePointError`.
    seed : int or numpy.random.Generator
        Randomness of the insertion order and of the walk; the result is a function of it.
    superstructure : {"ghost", "box"}
        Vertex at infinity (the convex hull's tetrahedralization) or the chapter's eight-point
        box, whose attached tets are removed at the end (see the module docstring).

    Attributes
    ----------
    algorithm, superstructure : str
    index_map : (n,) int32
        Vertex of each input point of the constructor (duplicates share one).

    Notes
    -----
    ``points`` (nv, 3) float64, ``tetrahedra`` (nt, 4) int32 positively oriented,
    ``neighbors`` (nt, 4) int32 (across the face opposite vertex k, -1 on the boundary) and
    ``hull`` (h, 3) int32 (boundary faces, outward normals) are read-only arrays valid until
    the next :meth:`insert`.
    """

    def __init__(self, points, algorithm: str = "bowyer", duplicates: str = "merge", seed=0, superstructure: str = "ghost"):
        if algorithm not in TET_ALGORITHMS:
            raise InputError(f"unknown algorithm {algorithm!r}; choose from {sorted(TET_ALGORITHMS)}")
        if duplicates not in ("merge", "reject"):
            raise InputError(f"duplicates must be 'merge' or 'reject', got {duplicates!r}")
        if superstructure not in SUPERSTRUCTURES:
            raise InputError(f"superstructure must be 'ghost' or 'box', got {superstructure!r}")
        seed = check_seed(seed)
        pts = as_exact_points(points, "points", dim=3)
        n = pts.shape[0]
        if n < 4:
            raise DegenerateInputError(f"a tetrahedralization needs at least 4 points, got {n}")
        self.algorithm = algorithm
        self.superstructure = superstructure
        self._rng = np.random.default_rng(seed)
        self._cache: dict = {}
        self._exported = False
        self._tag = np.empty(0, dtype=np.int32)  # per-slot tags moved by compaction (see track)
        order = self._order(pts)
        vb = 8 if superstructure == "box" else 0
        self._vb = vb
        rows = vb + n
        P = np.empty((rows, 3))
        P[vb:] = pts[order]
        if vb:
            P[:vb] = _box_corners(pts)
            check_coordinate_range(P[:vb], "the corners of superstructure='box'")
        slots = 7 * n + 64
        keeps = TET_ALGORITHMS[algorithm].keeps_spheres
        self._s = TetState(
            pts=P,
            tet=np.empty(4 * slots, dtype=np.int32),
            nbr=np.empty(4 * slots, dtype=np.int32),
            sph=np.empty(watson.RECORD * slots if keeps else 0, dtype=np.float32),
            rank=np.empty(0, dtype=np.int32),
            meta=new_meta(seed_state(int(self._rng.integers(1, 2**31)))),
            cav=np.empty(_SCRATCH, dtype=np.int32),
            bnd=np.empty(4 * _SCRATCH, dtype=np.int32),
            twin=np.empty(3 * _SCRATCH, dtype=np.int32),
            vloc=np.empty(_SCRATCH, dtype=np.int32),
            etab=np.empty(_SCRATCH * _SCRATCH, dtype=np.int32),
            vmark=np.empty(rows + 1, dtype=np.int32),
            free=np.empty(_SCRATCH, dtype=np.int32),
        )
        s = self._s
        vmap = np.empty(n, dtype=np.int32)
        if vb:
            init_tets(P, BOX_TETS, s.tet, s.nbr, s.sph, s.meta)
            first = vb
        else:
            init_tets(P, np.array([[0, 1, 2, 3]]), s.tet, s.nbr, s.sph, s.meta)
            vmap[:4] = np.arange(4)
            first = 4
        self._nv = n
        self._run(np.arange(first, rows, dtype=np.int32), vmap, vb, order)
        # Peak memory is here: release what the renumbering does not need, in place after.
        self._s = self._s._replace(vmark=np.empty(0, dtype=np.int32))  # regrown by the next insert
        relabel(self._s.tet, int(self._s.meta[M_NTET]), order, vb, vb)
        scatter_rows(P, vb, order)
        rank = np.empty(rows, dtype=np.int32)
        rank[:vb] = np.arange(vb, dtype=np.int32)
        index_map = np.empty(n, dtype=np.int32)
        input_order_maps(order, vmap, vb, rank, index_map)
        del vmap, order
        self._s = self._s._replace(rank=rank)
        if duplicates == "reject":
            dup = first_repeat(index_map, vb)
            if dup >= 0:
                raise DuplicatePointError(
                    f"coincident points: {index_map[dup] - vb} and {dup} at {fmt_point(pts[dup])}"
                )
        self.index_map = self._merge(index_map, vb)
        self.index_map -= vb
        self._nt = self._compact()

    # ------------------------------------------------------------------ build helpers
    def _compact(self) -> int:
        """Compact the slots (:func:`compact_tagged`, moving the tracking tags); nt."""
        s = self._s
        slots = int(s.meta[M_NTET])
        if self._tag.shape[0] and self._tag.shape[0] < slots:
            # slots appended since track() hold tets with a new vertex: their tags are unused
            tag = np.full(max(slots, 2 * self._tag.shape[0]), -1, dtype=np.int32)
            tag[: self._tag.shape[0]] = self._tag
            self._tag = tag
        return compact_tagged(s.tet, s.nbr, s.sph, self._tag, s.meta)

    def track(self) -> None:
        """Start following the current tets through later insertions (see :meth:`tracked`);
        ``superstructure="ghost"`` only (the box's public tets are a filtered copy)."""
        if self._vb:
            raise MeshingError("Tetrahedralization.track() needs superstructure='ghost'")
        self._tag = np.arange(int(self._s.meta[M_NTET]), dtype=np.int32)

    def tracked(self) -> np.ndarray:
        """(nt,) int32: for each tet of :attr:`tetrahedra` that has no vertex inserted since
        :meth:`track`, its index in :attr:`tetrahedra` at that call; other entries are
        meaningless.  Every tet an insertion creates has the inserted vertex, so the tets
        without a newer vertex are exactly the ones that survived (Bowyer and Watson never
        change a tet but by deleting it)."""
        if self._tag.shape[0] == 0:
            raise MeshingError("Tetrahedralization.tracked() before track()")
        return self._tag[: self._nt]

    def _order(self, pts: np.ndarray) -> np.ndarray:
        """BRIO order (int32) whose first four points span a tet."""
        order = brio_order(pts, self._rng).astype(np.int32)
        i, j, k = find_start(pts, order)
        a = int(order[0])
        if i < 0:
            raise DegenerateInputError(f"all {pts.shape[0]} points coincide at {fmt_point(pts[a])}")
        if j < 0:
            b = int(order[i])
            raise DegenerateInputError(
                f"all {pts.shape[0]} points are collinear, on the line through point {a} {fmt_point(pts[a])} "
                f"and point {b} {fmt_point(pts[b])}"
            )
        if k < 0:
            b, c = int(order[i]), int(order[j])
            raise DegenerateInputError(
                f"all {pts.shape[0]} points are coplanar, in the plane of points {a}, {b}, {c} "
                f"({fmt_point(pts[a])}, {fmt_point(pts[b])}, {fmt_point(pts[c])}): no tetrahedron exists"
            )
        for pos, src in ((1, i), (2, j), (3, k)):
            x = order[src]
            order[pos + 1 : src + 1] = order[pos:src].copy()
            order[pos] = x
        return order

    def _run(self, order: np.ndarray, vmap: np.ndarray, vbase: int, input_ids: np.ndarray | None = None) -> None:
        """Insert internal vertices ``order``; ``vmap[v - vbase]`` receives each one's vertex."""
        start = 0
        while True:
            st, i = insert_batch(self._s, order, start, order.shape[0], vbase, vmap)
            if st == 0:
                return
            if st == NEED_SPACE:
                self._s = grow(self._s)
                start = i
                continue
            if st == BROKEN:
                v = int(order[i])
                who = int(input_ids[v - vbase]) if input_ids is not None else v - self._vb
                self._nt = self._compact()
                raise MeshingError(
                    f"inserting point {who} at {fmt_point(self._s.pts[v])} met an inconsistent cavity; "
                    "the tetrahedralization is no longer usable"
                )
            raise MeshingError(f"the 3-D kernel returned the unknown status {st}")

    def _merge(self, vmap: np.ndarray, base: int) -> np.ndarray:
        """Drop duplicate rows ``>= base``, renumber monotonically; return the updated ``vmap``."""
        if first_repeat(vmap, base) < 0:
            self._nv = base + vmap.size - self._vb
            return vmap
        keep = vmap == np.arange(base, base + vmap.size, dtype=np.int32)
        s = self._s
        rows = base + vmap.size
        newid = (base + np.cumsum(keep) - 1).astype(np.int32)
        relabel(s.tet, int(s.meta[M_NTET]), newid, base, 0)
        kept = int(newid[-1]) + 1
        s.pts[base:kept] = s.pts[base:rows][keep]
        self._nv = kept - self._vb
        if base < s.rank.size:
            ranks = s.rank[: base + vmap.size][np.concatenate([np.ones(base, dtype=bool), keep])]
            dense = np.zeros(s.rank.size, dtype=np.int32)
            dense[ranks] = 1
            self._s = s._replace(rank=(np.cumsum(dense, dtype=np.int32) - 1)[ranks])
        return np.where(vmap >= base, newid[np.maximum(vmap - base, 0)], vmap).astype(np.int32)

    def _public(self, name: str) -> np.ndarray:
        """Public array ``name`` (tetrahedra, neighbors, hull, or pub: slot -> public index), cached.

        With the ghost superstructure ``tetrahedra`` is a read-only view of the kernel's array
        (:meth:`insert` copies that array first if the view was handed out); with the box it is
        the filtered copy of the tets not attached to a box vertex.
        """
        if name in self._cache:
            return self._cache[name]
        nt = self._nt
        slots = int(self._s.meta[M_NTET])
        tet = self._s.tet[: 4 * nt].reshape(nt, 4)
        keep = (tet >= self._vb).all(axis=1) if self._vb else None
        if name == "pub" or (self._vb and name == "neighbors"):
            pub = np.full(slots, -1, dtype=np.int32)
            if self._vb:
                pub[:nt][keep] = np.arange(int(keep.sum()), dtype=np.int32)
            else:
                pub[:nt] = np.arange(nt, dtype=np.int32)
        if name == "pub":
            out = pub
        elif name == "tetrahedra":
            out = (tet[keep] - self._vb).astype(np.int32) if self._vb else tet
            self._exported = True
        elif name == "neighbors":
            nb = self._s.nbr[: 4 * nt].reshape(nt, 4)
            # np.where of two int32 operands is int32 already: no second copy of 4 nt entries
            out = pub[nb[keep]] if self._vb else np.where(nb >= nt, np.int32(-1), nb).astype(np.int32, copy=False)
        else:
            tets = self._public("tetrahedra")
            t, k = np.nonzero(self._public("neighbors") < 0)
            out = tets[t[:, None], TET_FACES[k]].astype(np.int32)
        out.flags.writeable = False
        self._cache[name] = out
        return out

    # ------------------------------------------------------------------ public arrays
    @property
    def points(self) -> np.ndarray:
        """(nv, 3) float64 vertex coordinates (read-only view)."""
        view = self._s.pts[self._vb : self._vb + self._nv]
        view.flags.writeable = False
        return view

    @property
    def tetrahedra(self) -> np.ndarray:
        """(nt, 4) int32 tetrahedra, ``orient3d(v0, v1, v2, v3) > 0`` (read-only)."""
        return self._public("tetrahedra")

    @property
    def neighbors(self) -> np.ndarray:
        """(nt, 4) int32: ``neighbors[t, k]`` is across the face opposite vertex k, -1 on the boundary."""
        return self._public("neighbors")

    @property
    def hull(self) -> np.ndarray:
        """(h, 3) int32 boundary faces, counter-clockwise seen from outside (outward normals)."""
        return self._public("hull")

    def __repr__(self) -> str:
        return f"Tetrahedralization({self.algorithm}, {self.superstructure}: {self._nv} points, {len(self.tetrahedra)} tetrahedra)"

    # ------------------------------------------------------------------ operations
    def insert(self, points) -> np.ndarray:
        """Insert points (the Delaunay property is maintained incrementally).

        Parameters
        ----------
        points : (k, 3) array_like of float64
            Finite points, inserted in BRIO order; with ``superstructure="box"`` strictly
            inside the box.

        Returns
        -------
        (k,) int32
            Vertex of each point; a point equal to an existing vertex (or to an earlier point
            of this call) maps to that vertex and adds nothing.
        """
        new = as_exact_points(np.reshape(points, (-1, 3)) if np.size(points) == 3 else points, "points", dim=3)
        k = new.shape[0]
        if k == 0:
            return np.empty(0, dtype=np.int32)
        if self._vb:
            box = self._s.pts[:8]
            lo = box.min(axis=0)
            hi = box.max(axis=0)
            out = np.flatnonzero(~((new > lo) & (new < hi)).all(axis=1))
            if out.size:
                raise InputError(
                    f"points: point {out[0]} {fmt_point(new[out[0]])} is not strictly inside the box "
                    f"{lo.tolist()} - {hi.tolist()} of superstructure='box'"
                )
        s = self._s
        base = self._vb + self._nv
        rows = base + k
        if s.pts.shape[0] < rows:
            P = np.empty((max(rows, 2 * s.pts.shape[0]), 3))
            P[:base] = s.pts[:base]
            s = s._replace(pts=P)
        s.pts[base:rows] = new
        if s.vmark.shape[0] <= s.pts.shape[0]:
            s = s._replace(vmark=np.empty(s.pts.shape[0] + 1, dtype=np.int32))
        if self._exported:
            s = s._replace(tet=s.tet.copy())  # arrays already handed out keep their values
            self._exported = False
        self._s = s
        self._cache = {}
        order = (brio_order(new, self._rng) + base).astype(np.int32)
        vmap = np.empty(k, dtype=np.int32)
        self._nv += k
        self._run(order, vmap, base)
        out = self._merge(vmap, base) - self._vb
        self._nt = self._compact()
        return out.astype(np.int32)

    def _edit_begin(self) -> TetState:
        """The kernel bundle, for a kernel that inserts vertices itself (refinement's queue).

        Arrays already handed out keep their values (the tet array is copied first).  Hand
        the bundle back with :meth:`_edit_end` before using the object again.
        """
        s = self._s
        if self._exported:
            s = s._replace(tet=s.tet.copy())
            self._exported = False
        self._s = s
        self._cache = {}
        return s

    def _edit_end(self, s: TetState, added: int) -> None:
        """Adopt the bundle ``s`` after a kernel appended ``added`` vertices (rows after the last)."""
        self._s = s
        self._nv += int(added)
        self._cache = {}
        self._nt = self._compact()

    def locate(self, xyz):
        """Tetrahedron containing each point (boundary included), -1 outside.

        Parameters
        ----------
        xyz : (3,) or (m, 3) array_like of float64

        Returns
        -------
        int or (m,) int32
            Index into ``tetrahedra``; -1 outside the convex hull (box mode: outside the
            kept tets).
        """
        try:
            arr = np.asarray(xyz, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise InputError(f"xyz must be a (3,) or (m, 3) array of numbers: {exc}") from exc
        single = arr.shape == (3,)
        q = as_exact_points(arr.reshape(1, 3) if single else arr, "xyz", dim=3)
        slots = locate_points(self._s._replace(meta=self._s.meta.copy()), q)
        if np.any(slots < -(1 << 39)):
            bad = int(np.flatnonzero(slots < -(1 << 39))[0])
            raise MeshingError(f"locating point {bad} {fmt_point(q[bad])}: the walk hit its step cap")
        pub = self._public("pub")
        out = np.where(slots >= 0, pub[np.maximum(slots, 0)], -1).astype(np.int32)
        return int(out[0]) if single else out

    def to_mesh(self):
        """The tetrahedralization as a :class:`meshwright.core.mesh.Mesh` with one ``"tetra"`` block."""
        from meshwright.core.mesh import Mesh

        return Mesh(np.array(self.points), {"tetra": np.array(self.tetrahedra)})


def delaunay3d(points, algorithm: str = "bowyer", duplicates: str = "merge", seed=0, superstructure: str = "ghost") -> Tetrahedralization:
    """Delaunay tetrahedralization of 3-D points (chapter 18.1, 18.4.1: Bowyer or Watson).

    Parameters
    ----------
    points : (n, 3) array_like of float64
        At least four finite points, not all coplanar.
    algorithm : {"bowyer", "watson"}
    duplicates : {"merge", "reject"}
    seed : int or numpy.random.Generator
    superstructure : {"ghost", "box"}

    Returns
    -------
    Tetrahedralization

    Raises
    ------
    InputError
        Wrong shape, non-numeric, NaN or infinite coordinates, unknown option.
    DegenerateInputError
        Fewer than four points, or all coincident, collinear or coplanar.
    DuplicatePointError
        Coincident points with ``duplicates="reject"``.
    """
    return Tetrahedralization(points, algorithm=algorithm, duplicates=duplicates, seed=seed, superstructure=superstructure)
