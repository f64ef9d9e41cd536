"""Closed triangulated surfaces, the input of :func:`meshwright.tetrahedralize`.

A :class:`Surface` is points, oriented triangles and face markers, plus TetGen-style hole
and region seeds.  Orientation convention: each face's normal (right-hand rule over its
corners) points out of the solid it bounds, so an outer boundary encloses positive volume
and a cavity negative volume; the even-odd rule of a point-in-solid test decides which
shells are outer and which are cavities (depth 0, 2, ... outer; 1, 3, ... cavities).
Surfaces with interfaces between regions (edges in more than two faces) are marked
``multi_region``: their faces carry no orientation requirement.

:meth:`Surface.validate` proves, in this order, with exact predicates
(:mod:`meshwright.geometry._surface_kernels`): every point used and no two equal; no
degenerate face; every edge in two faces (at least two when ``multi_region``) and no two
faces on the same vertices; opposite traversal of every edge by its two faces; no two faces
meeting other than in their shared vertices or edge; every shell signed as its nesting
depth requires.  The first violation raises :class:`~meshwright.core.errors.GeometryError`
naming the points, edge, faces and coordinates at fault.

:meth:`Surface.inside` is the same even-odd ray parity for arbitrary query points.

The edge matching is the one of :mod:`meshwright.core.validate3d`
(:func:`~meshwright.core.validate_cells._sort_groups` over sorted directed-edge keys).  The sign of a
shell's volume is the floating-point divergence-theorem sum certified by an a-priori bound
on its rounding error (Higham, *Accuracy and Stability of Numerical Algorithms*, 2002,
ch. 4): a sum within the bound is refused, never guessed.

Arrays: ``points`` (n, 3) float64 C-contiguous; ``triangles`` (m, 3) int32; ``markers``
(m,) int32; ``holes`` (h, 3) float64; ``regions`` (r, 5) float64 rows
``(x, y, z, region_id, max_volume)``.
"""

from __future__ import annotations

import numpy as np

from meshwright.core.errors import GeometryError, InputError, fmt_point
from meshwright.core.mesh import Mesh
from meshwright.core.spatial_sort import hilbert_order
from meshwright.core.validate_cells import _facet_orientation, _sort_groups
from meshwright.core.validate_input import as_cells, as_exact_points, check_flag
from meshwright.geometry._surface_kernels import (
    HIT_CROSS,
    HIT_DUPLICATE,
    HIT_FOLD,
    HIT_VERTEX,
    NO_HIT,
    degenerate_faces,
    find_intersection,
    label_shells,
    nesting_parity,
    orient_shells,
    volume_terms,
)

__all__ = ["Surface", "combine"]

_EPS = 2.0**-53


class EdgeGroups:
    """Directed edges of the faces grouped by undirected edge (also used by the readers).

    Parameters
    ----------
    triangles : (m, 3) int
    n_points : int
        Upper bound of the vertex indices.

    Attributes
    ----------
    tail, head : (3 m,) int64
        Directed edge ``3 f + k`` runs from corner k to corner k + 1 of face f.
    order, group : (3 m,) int64
        :func:`~meshwright.core.validate_cells._sort_groups` of the undirected keys.
    count : (3 m,) int64
        Number of directed edges (faces) on each directed edge's undirected edge.
    first, second : (e,) int64
        The two directed edges of every edge in exactly two faces.
    same : (e,) bool
        Whether that pair traverses its edge in the same direction.
    """

    def __init__(self, triangles: np.ndarray, n_points: int):
        t = triangles.astype(np.int64)
        self.tail = t.ravel()
        self.head = t[:, [1, 2, 0]].ravel()
        keys = np.sort(np.column_stack([self.tail, self.head]), axis=1)
        self.order, self.group = _sort_groups(keys, n_points)
        sizes = np.bincount(self.group) if len(self.group) else np.zeros(0, np.int64)
        self.count = np.empty(len(keys), np.int64)
        self.count[self.order] = sizes[self.group]
        start = np.flatnonzero(np.diff(self.group, prepend=-1) != 0)
        start = start[sizes[self.group[start]] == 2]
        self.first = self.order[start]
        self.second = self.order[start + 1]
        self.same = self.tail[self.first] == self.tail[self.second]

    def members(self, e: int) -> np.ndarray:
        """Faces of the undirected edge of directed edge ``e``."""
        pos = int(np.flatnonzero(self.order == e)[0])
        return np.sort(self.order[self.group == self.group[pos]] // 3)


class Surface:
    """A closed triangulated surface: points, outward-oriented faces, markers and seeds.

    Parameters
    ----------
    points : (n, 3) array_like of float
        Finite, in the exact predicates' range (:mod:`meshwright.core.validate_input`).
    triangles : (m, 3) array_like of int
        Faces, m >= 1, indices into ``points``, three distinct vertices each, oriented so
        that the normal points out of the solid the face bounds.
    markers : (m,) array_like of int, optional
        Face markers (default 1).
    holes : (h, 3) array_like of float, optional
        Seeds of void regions (TetGen's hole list).
    regions : (r, 5) array_like of float, optional
        Rows ``(x, y, z, region_id, max_volume)``, region_id an integer, max_volume <= 0
        meaning no bound.
    multi_region : bool
        Faces may be interfaces between regions (edges in more than two faces); such a
        surface has no orientation requirement.

    Attributes
    ----------
    points : (n, 3) float64, C-contiguous
    triangles : (m, 3) int32
    markers : (m,) int32
    holes : (h, 3) float64
    regions : (r, 5) float64
    multi_region : bool

    Raises
    ------
    InputError
        A malformed argument, named with the first bad row.
    """

    def __init__(self, points, triangles, markers=None, holes=None, regions=None, multi_region=False):
        self.points = as_exact_points(points, "points", dim=3)
        n = len(self.points)
        tri = as_cells(triangles, "triangles", 3, n)
        if not len(tri):
            raise InputError("a surface needs at least one triangle, got none")
        rep = np.flatnonzero((tri[:, 0] == tri[:, 1]) | (tri[:, 1] == tri[:, 2]) | (tri[:, 2] == tri[:, 0]))
        if len(rep):
            raise InputError(f"triangles row {rep[0]} {tri[rep[0]].tolist()} repeats a vertex")
        self.triangles = tri
        self.markers = _as_markers(markers, len(tri))
        self.holes = np.zeros((0, 3)) if holes is None or np.size(holes) == 0 else as_exact_points(holes, "holes", 3)
        self.regions = _as_regions(regions)
        self.multi_region = check_flag(multi_region, "multi_region")

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_mesh(cls, mesh, holes=None, regions=None, multi_region=None) -> Surface:
        """The triangle cells of a 3-D :class:`~meshwright.core.mesh.Mesh` as a surface.

        Points that no triangle uses (a file's curve and volume nodes) are dropped and the
        rest renumbered in their order; other cell types are ignored.  Markers come from
        ``cell_data["marker"]["triangle"]`` (default 1).

        Parameters
        ----------
        mesh : Mesh
            ``mesh.dim == 3`` with at least one triangle.
        holes, regions : optional
            As for :class:`Surface`.
        multi_region : bool, optional
            Default: whether some edge lies in more than two triangles.

        Raises
        ------
        InputError
            Not a 3-D Mesh, or without triangle cells.
        """
        if not isinstance(mesh, Mesh):
            raise InputError(f"from_mesh needs a meshwright Mesh, got {type(mesh).__name__}")
        if mesh.dim != 3:
            raise InputError(f"from_mesh needs a 3-D mesh, got dim={mesh.dim}")
        tri = mesh.triangles
        if not len(tri):
            raise InputError(f"the mesh has no triangle cells (cells: {', '.join(mesh.cells) or 'none'})")
        markers = mesh.cell_data.get("marker", {}).get("triangle")
        used = np.unique(tri)
        renumber = np.full(mesh.n_points, -1, np.int64)
        renumber[used] = np.arange(len(used))
        tri = renumber[tri]
        if multi_region is None:
            multi_region = bool(np.any(EdgeGroups(tri, len(used)).count > 2))
        return cls(mesh.points[used], tri, markers, holes, regions, multi_region)

    # ------------------------------------------------------------------ measures
    @property
    def n_points(self) -> int:
        """Number of points n."""
        return len(self.points)

    @property
    def n_faces(self) -> int:
        """Number of faces m."""
        return len(self.triangles)

    @property
    def bbox(self) -> np.ndarray:
        """(2, 3) float64: lowest and highest coordinates of the points the faces use."""
        used = self.points[np.unique(self.triangles)]
        return np.array([used.min(axis=0), used.max(axis=0)])

    def area(self) -> float:
        """Total area of the faces."""
        p = self.points[self.triangles]
        return float(0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1).sum())

    def enclosed_volume(self) -> float:
        """Signed enclosed volume: the sum over faces of ``det[a, b, c] / 6`` (about the box centre)."""
        return float(self._volume_terms()[0].sum() / 6.0)

    def _volume_terms(self) -> tuple[np.ndarray, np.ndarray]:
        """Per face ``det[a - o, b - o, c - o]`` and its permanent (for the error bound); o
        the centre of the points' box, which keeps the products small."""
        o = 0.5 * (self.points.min(axis=0) + self.points.max(axis=0))
        return volume_terms(self.points, self.triangles.ravel(), o)

    def shells(self) -> np.ndarray:
        """(m,) int32 shell of each face: connected components through the edges in exactly
        two faces, numbered 0, 1, ... in order of their first face."""
        edges = EdgeGroups(self.triangles, self.n_points)
        labels, _ = label_shells(self.n_faces, edges.first, edges.second)
        return labels.astype(np.int32)

    def inside(self, xyz) -> np.ndarray:
        """Whether each point lies in the solid by the even-odd rule: inside an odd number
        of shells (exact ray parity, :func:`_surface_kernels.nesting_parity`).

        Parameters
        ----------
        xyz : (k, 3) array_like of float

        Returns
        -------
        (k,) bool
            Unspecified for a point on the surface itself; on a closed surface without
            self-intersections (:meth:`validate`) exact for every other point.
        """
        q = as_exact_points(xyz, "xyz", dim=3)
        labels = self.shells().astype(np.int64)
        k = int(labels.max()) + 1
        p = np.concatenate([self.points, q])
        query = np.arange(self.n_points, len(p), dtype=np.int64)
        parity = nesting_parity(p, self.triangles.ravel(), labels, k, query, np.full(len(q), -1, np.int64))
        return parity.sum(axis=1) % 2 == 1

    # ------------------------------------------------------------------ transforms
    def flipped(self) -> Surface:
        """The same surface with every face reversed (a solid becomes a cavity)."""
        return Surface(self.points, self.triangles[:, [0, 2, 1]], self.markers, self.holes, self.regions,
                       self.multi_region)

    def oriented(self) -> Surface:
        """A copy oriented by the convention: faces consistent within each shell, shells at
        even nesting depth enclosing positive volume, at odd depth negative.

        For inputs that carry no orientation (TetGen files).  The surface must be closed
        and manifold; self-intersections are not looked for (:meth:`validate` does).

        Raises
        ------
        InputError
            On a multi-region surface (its faces have no orientation to restore).
        GeometryError
            What :meth:`validate` reports about points, degenerate faces and edges, or a
            non-orientable shell.
        """
        if self.multi_region:
            raise InputError("a multi-region surface has no orientation convention to restore")
        self._check_points()
        self._check_faces()
        edges = EdgeGroups(self.triangles, self.n_points)
        self._check_edges(edges, orientation=False)
        flip, bad = orient_shells(self.n_faces, edges.first, edges.second, edges.same)
        if bad >= 0:
            e = int(edges.first[bad])
            raise GeometryError(
                f"the shell through edge {self._edge_text(e)} cannot be oriented consistently "
                "(a one-sided surface such as a Moebius strip)"
            )
        tri = self.triangles.copy()
        tri[flip] = tri[flip][:, [0, 2, 1]]
        out = Surface(self.points, tri, self.markers, self.holes, self.regions)
        labels, depth, volume, _ = out._nesting(EdgeGroups(tri, self.n_points))
        wrong = np.flatnonzero((depth % 2 == 0) != (volume > 0))
        flip = np.isin(labels, wrong)
        tri[flip] = tri[flip][:, [0, 2, 1]]
        return Surface(self.points, tri, self.markers, self.holes, self.regions)

    def to_mesh(self) -> Mesh:
        """The faces as a 3-D :class:`~meshwright.core.mesh.Mesh` of triangle cells with markers."""
        return Mesh(self.points, {"triangle": self.triangles}, cell_data={"marker": {"triangle": self.markers}})

    def __repr__(self) -> str:
        extra = " multi_region" if self.multi_region else ""
        return (f"Surface(n_points={self.n_points}, n_faces={self.n_faces}, holes={len(self.holes)}, "
                f"regions={len(self.regions)}{extra})")

    # ------------------------------------------------------------------ validation
    def validate(self) -> None:
        """Prove the surface is fit to bound a tetrahedral mesh.

        Raises
        ------
        GeometryError
            The first violation, in this order: a point used by no face, two equal points,
            a degenerate (zero-area) face, an open edge (in one face) or a non-manifold one
            (more than two faces, unless ``multi_region``), two faces on the same vertices,
            an edge traversed in the same direction by its two faces, two faces that meet
            other than in their shared vertices or edge, a shell whose volume has the
            wrong sign for its nesting depth (or too small a volume to sign).  The message
            names the vertices, faces and coordinates at fault.  Shells or fans of faces
            touching in a vertex (a "pinched" vertex) are allowed: faces sharing only a
            vertex are tested to meet nowhere else.
        """
        self._check_points()
        self._check_faces()
        edges = EdgeGroups(self.triangles, self.n_points)
        self._check_edges(edges, orientation=not self.multi_region)
        self._check_intersections()
        if not self.multi_region:
            self._check_shells(edges)

    def _face_text(self, f: int) -> str:
        return f"face {f} ({', '.join(str(int(v)) for v in self.triangles[f])})"

    def _edge_text(self, e: int) -> str:
        f, k = divmod(int(e), 3)
        i, j = int(self.triangles[f, k]), int(self.triangles[f, (k + 1) % 3])
        return f"({i}, {j}) from {fmt_point(self.points[i])} to {fmt_point(self.points[j])}"

    def _check_points(self) -> None:
        used = np.zeros(self.n_points, bool)
        used[self.triangles.ravel()] = True
        if not used.all():
            i = int(np.flatnonzero(~used)[0])
            raise GeometryError(f"point {i} at {fmt_point(self.points[i])} is used by no face "
                                f"({int((~used).sum())} such points)")
        order = np.lexsort(self.points.T[::-1])
        same = np.flatnonzero(np.all(self.points[order[1:]] == self.points[order[:-1]], axis=1))
        if len(same):
            i, j = sorted((int(order[same[0]]), int(order[same[0] + 1])))
            raise GeometryError(f"points {i} and {j} coincide at {fmt_point(self.points[i])}")

    def _check_faces(self) -> None:
        bad = np.flatnonzero(degenerate_faces(self.points, self.triangles.ravel()))
        if len(bad):
            f = int(bad[0])
            corners = ", ".join(fmt_point(self.points[v]) for v in self.triangles[f])
            raise GeometryError(
                f"{self._face_text(f)} is degenerate: its corners {corners} are collinear (zero area)"
                f"{f'; {len(bad)} such faces' if len(bad) > 1 else ''}"
            )

    def _check_edges(self, edges: EdgeGroups, orientation: bool) -> None:
        open_ = np.flatnonzero(edges.count == 1)
        if len(open_):
            e = int(open_[0])
            raise GeometryError(
                f"open edge {self._edge_text(e)} lies in {self._face_text(e // 3)} only: the surface "
                f"is not closed ({len(open_)} open edges)"
            )
        keys = np.sort(self.triangles.astype(np.int64), axis=1)
        order, group = _sort_groups(keys, self.n_points)
        dup = np.flatnonzero(np.diff(group) == 0)
        if len(dup):
            f, g = sorted((int(order[dup[0]]), int(order[dup[0] + 1])))
            raise GeometryError(f"{self._face_text(f)} and {self._face_text(g)} have the same vertices "
                                "(a duplicate face)")
        if not self.multi_region:
            over = np.flatnonzero(edges.count > 2)
            if len(over):
                e = int(over[0])
                faces = ", ".join(self._face_text(int(f)) for f in edges.members(e))
                raise GeometryError(
                    f"non-manifold edge {self._edge_text(e)} lies in {edges.count[e]} faces ({faces}); "
                    "pass multi_region=True if these are interfaces between regions"
                )
        if orientation and edges.same.any():
            i = int(np.flatnonzero(edges.same)[0])
            e, g = int(edges.first[i]), int(edges.second[i])
            raise GeometryError(
                f"edge {self._edge_text(e)} is traversed in the same direction by {self._face_text(e // 3)} "
                f"and {self._face_text(g // 3)}: the faces are not consistently oriented "
                "(Surface.oriented() repairs this)"
            )

    def _check_intersections(self) -> None:
        p = self.points[self.triangles]
        order = hilbert_order(p.mean(axis=1), bits=10)
        res, w = find_intersection(self.points, self.triangles.ravel(), order)
        kind = int(res[2])
        if kind == NO_HIT:
            return
        f, g = int(res[0]), int(res[1])
        what = {
            HIT_CROSS: "intersect",
            HIT_VERTEX: "share a vertex and also meet elsewhere",
            HIT_FOLD: "share an edge and overlap in one plane (folded onto each other)",
            HIT_DUPLICATE: "coincide",
        }[kind]
        raise GeometryError(
            f"{self._face_text(f)} and {self._face_text(g)} {what} near {fmt_point(w)}: "
            "the surface intersects itself"
        )

    def _nesting(self, edges: EdgeGroups):
        """Shell labels, nesting depth and signed volume (x6) of every shell; error bounds."""
        labels, k = label_shells(self.n_faces, edges.first, edges.second)
        depth = np.zeros(k, np.int64)
        if k > 1:
            depth = self._depths(labels, k)
        det, perm = self._volume_terms()
        volume = np.bincount(labels, weights=det, minlength=k)
        faces = np.bincount(labels, minlength=k)
        bound = (faces + 16) * 8.0 * _EPS * np.bincount(labels, weights=perm, minlength=k)
        return labels, depth, volume, bound

    def _depths(self, labels: np.ndarray, k: int) -> np.ndarray:
        """Number of other shells enclosing each shell (ray parity from one of its vertices
        that lies on no other shell)."""
        verts = self.triangles.ravel().astype(np.int64)
        shell_of = np.repeat(labels, 3)
        pairs = np.unique(verts * k + shell_of)
        n_shells_at = np.bincount(pairs // k, minlength=self.n_points)
        own = n_shells_at[verts] == 1
        query = np.full(k, -1, np.int64)
        shells, at = np.unique(shell_of[own], return_index=True)
        query[shells] = verts[own][at]
        if np.any(query < 0):
            s = int(np.flatnonzero(query < 0)[0])
            f = int(np.flatnonzero(labels == s)[0])
            raise GeometryError(
                f"every vertex of the shell of {self._face_text(f)} also lies on another shell: "
                "its nesting cannot be decided"
            )
        parity = nesting_parity(self.points, self.triangles.ravel(), labels, k, query, np.arange(k))
        return parity.sum(axis=1).astype(np.int64)

    def _check_shells(self, edges: EdgeGroups) -> None:
        labels, depth, volume, bound = self._nesting(edges)
        first = np.unique(labels, return_index=True)[1]
        flat = np.flatnonzero(~(np.abs(volume) > bound))
        if len(flat):
            s = int(flat[0])
            raise GeometryError(
                f"the shell of {self._face_text(int(first[s]))} encloses volume {float(volume[s]) / 6.0!r}, too "
                "small to tell its orientation from rounding: the shell is flat or folded"
            )
        outer = depth % 2 == 0
        wrong = np.flatnonzero(outer != (volume > 0))
        if len(wrong):
            s = int(wrong[0])
            f = int(first[s])
            corner = fmt_point(self.points[self.triangles[f, 0]])
            role = "an outer boundary (positive volume)" if outer[s] else "a cavity (negative volume)"
            raise GeometryError(
                f"the shell of {self._face_text(f)} at {corner} is inverted: it lies inside {int(depth[s])} "
                f"other shells, so it is {role}, but it encloses {float(volume[s]) / 6.0!r}; reverse its faces "
                "(Surface.flipped(), or Surface.oriented() for the whole surface)"
            )


def _as_markers(markers, m: int) -> np.ndarray:
    if markers is None:
        return np.ones(m, np.int32)
    a = np.asarray(markers)
    if a.dtype == bool or not np.issubdtype(a.dtype, np.integer):
        raise InputError(f"markers must be integers, got dtype {a.dtype}")
    if a.shape != (m,):
        raise InputError(f"markers must have shape ({m},), one per triangle, got {a.shape}")
    big = np.flatnonzero(np.abs(a.astype(np.int64)) > np.iinfo(np.int32).max)
    if len(big):
        raise InputError(f"marker {big[0]} ({a[big[0]]}) does not fit in int32")
    return np.ascontiguousarray(a, dtype=np.int32)


def _as_regions(regions) -> np.ndarray:
    if regions is None:
        return np.zeros((0, 5))
    try:
        r = np.array(regions, dtype=np.float64, ndmin=2)
    except (TypeError, ValueError) as exc:
        raise InputError(f"regions must be rows (x, y, z, region_id, max_volume): {exc}") from exc
    if r.size == 0:
        return np.zeros((0, 5))
    if r.ndim != 2 or r.shape[1] != 5:
        raise InputError(f"regions must have shape (r, 5): rows (x, y, z, region_id, max_volume), got {r.shape}")
    bad = np.flatnonzero(~np.isfinite(r).all(axis=1))
    if len(bad):
        raise InputError(f"region {bad[0]} {r[bad[0]].tolist()} is not finite")
    as_exact_points(r[:, :3], "region seeds", dim=3)
    ids = r[:, 3]
    bad = np.flatnonzero((ids != np.round(ids)) | (np.abs(ids) > np.iinfo(np.int32).max))
    if len(bad):
        raise InputError(f"region {bad[0]} has region_id {ids[bad[0]]!r}, not an int32 integer")
    return np.ascontiguousarray(r)


def combine(*surfaces: Surface) -> Surface:
    """One surface from several: points concatenated with exactly equal points merged,
    faces concatenated with faces on the same vertices kept once (the first's marker).

    The result is ``multi_region`` when an input is, when two merged faces had opposite
    orientations (an interface between two solids), or when an edge ends up in more than
    two faces.  Hole and region seeds are concatenated.  A body in a far field is
    ``combine(box(...), body.flipped())``.

    Parameters
    ----------
    *surfaces : Surface
        At least one.

    Returns
    -------
    Surface

    Raises
    ------
    InputError
        No surface, or an argument that is not a Surface.
    GeometryError
        A face whose corners merge into fewer than three points, named with its surface.
    """
    if not surfaces:
        raise InputError("combine needs at least one surface")
    for i, s in enumerate(surfaces):
        if not isinstance(s, Surface):
            raise InputError(f"combine argument {i} is a {type(s).__name__}, not a Surface")
    offsets = np.cumsum([0] + [s.n_points for s in surfaces])
    points = np.concatenate([s.points for s in surfaces])
    tri = np.concatenate([s.triangles.astype(np.int64) + o for s, o in zip(surfaces, offsets)])
    source = np.repeat(np.arange(len(surfaces)), [s.n_faces for s in surfaces])
    local = np.concatenate([np.arange(s.n_faces) for s in surfaces])
    markers = np.concatenate([s.markers for s in surfaces])
    _, first, inverse = np.unique(points, axis=0, return_index=True, return_inverse=True)
    # Number the merged points in order of first appearance.
    rank = np.empty(len(first), np.int64)
    rank[np.argsort(first, kind="stable")] = np.arange(len(first))
    tri = rank[inverse.ravel()][tri]
    points = points[np.sort(first)]
    rep = np.flatnonzero((tri[:, 0] == tri[:, 1]) | (tri[:, 1] == tri[:, 2]) | (tri[:, 2] == tri[:, 0]))
    if len(rep):
        f = int(rep[0])
        raise GeometryError(
            f"face {local[f]} of surface {source[f]} collapses when equal points merge "
            f"(its corners become {tri[f].tolist()})"
        )
    keys = np.sort(tri, axis=1)
    order, group = _sort_groups(keys, len(points))
    start = np.diff(group, prepend=-1) != 0
    keep = np.zeros(len(tri), bool)
    keep[order[start]] = True
    head = order[start][group]  # the kept face of every face's group, in sorted order
    opposite = _facet_orientation(tri[order]) != _facet_orientation(tri[head])
    multi = any(s.multi_region for s in surfaces) or bool(opposite.any())
    tri, markers = tri[keep], markers[keep]
    if not multi:
        multi = bool(np.any(EdgeGroups(tri, len(points)).count > 2))
    return Surface(
        points,
        tri,
        markers,
        np.concatenate([s.holes for s in surfaces]),
        np.concatenate([s.regions for s in surfaces]),
        multi,
    )

