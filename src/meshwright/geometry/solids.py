"""Built-in closed surfaces: a box, a subdivided-icosahedron sphere, extruded 2-D meshes.

* :func:`box`: the 12 triangles of an axis-aligned box, markers 1..6 for the sides
  x = lo, x = hi, y = lo, y = hi, z = lo, z = hi.
* :func:`sphere`: the regular icosahedron (vertices the cyclic permutations of
  ``(0, +-1, +-phi)``) subdivided ``level`` times, each face into four at its edge
  midpoints, every new vertex pushed out to the sphere (Loop-style 1-to-4 subdivision;
  the classic geodesic sphere, e.g. Kenner, *Geodesic Math and How to Use It*, 1976).
  ``20 * 4**level`` faces; the inscribed polyhedron's volume approaches ``4/3 pi r**3``
  from below.
* :func:`extrude`: a triangulated 2-D region swept along z.  It takes a 2-D
  :class:`~meshwright.core.mesh.Mesh` rather than a :class:`~meshwright.geometry.Domain`
  because meshing a domain is the job of :func:`meshwright.triangulate`, a layer above
  ``geometry`` (imports point downward only): ``extrude(triangulate(domain, size), h)``.
  Caps are the 2-D triangles; walls are two triangles per boundary edge and layer; hole
  loops become tunnels.
* :func:`far_field`: a body in a box, ``combine(box(lo, hi), body.flipped())``.

Every face is oriented outwards (normal by the right-hand rule out of the solid).
"""

from __future__ import annotations

import numpy as np

from meshwright.core.errors import GeometryError, InputError, fmt_point
from meshwright.core.mesh import Mesh
from meshwright.core.predicates import orient2d_batch
from meshwright.core.topology import boundary_edges_of
from meshwright.core.validate_input import (
    as_exact_points,
    check_count,
    check_flag,
    check_positive,
)
from meshwright.geometry.surface import Surface, combine

__all__ = ["MAX_SPHERE_LEVEL", "box", "extrude", "far_field", "sphere"]

# 20 * 4**9 = 5.2e6 faces; beyond that the arrays alone take gigabytes.
MAX_SPHERE_LEVEL = 9

# Corner v = i + 2 j + 4 k of the box is (x_i, y_j, z_k); each side as a quad seen from
# outside, counter-clockwise.
_BOX_SIDES = np.array([[0, 4, 6, 2], [1, 3, 7, 5], [0, 1, 5, 4], [2, 6, 7, 3], [0, 2, 3, 1], [4, 5, 7, 6]])


def _point3(value, what: str) -> np.ndarray:
    """Three finite coordinates in the predicates' range, as a (3,) float64 array."""
    try:
        a = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{what} must be three numbers, got {value!r}") from exc
    if a.shape != (3,):
        raise InputError(f"{what} must be three numbers, got shape {a.shape}")
    return as_exact_points(a[None], what, 3)[0]


def _corners(lo, hi):
    lo, hi = _point3(lo, "lo"), _point3(hi, "hi")
    bad = np.flatnonzero(~(hi > lo))
    if len(bad):
        raise GeometryError(f"box: hi {fmt_point(hi)} must exceed lo {fmt_point(lo)} along {'xyz'[bad[0]]}")
    return lo, hi


def box(lo=(0.0, 0.0, 0.0), hi=(1.0, 1.0, 1.0)) -> Surface:
    """The axis-aligned box ``[lo, hi]`` as 12 outward triangles.

    Parameters
    ----------
    lo, hi : (3,) array_like of float
        Opposite corners, ``hi > lo`` along every axis.

    Returns
    -------
    Surface
        8 points (corner ``i + 2 j + 4 k`` at ``(x_i, y_j, z_k)``), 12 faces, markers 1..6
        for the sides x = lo, x = hi, y = lo, y = hi, z = lo, z = hi (two faces each).

    Raises
    ------
    InputError
        Not three finite numbers each.
    GeometryError
        ``hi <= lo`` along an axis.
    """
    lo, hi = _corners(lo, hi)
    i = np.arange(8)
    pts = np.column_stack([np.where(i & 1, hi[0], lo[0]), np.where(i & 2, hi[1], lo[1]), np.where(i & 4, hi[2], lo[2])])
    q = _BOX_SIDES
    tri = np.concatenate([q[:, [0, 1, 2]], q[:, [0, 2, 3]]])
    markers = np.tile(np.arange(1, 7), 2)
    order = np.argsort(markers, kind="stable")
    return Surface(pts, tri[order], markers[order])


def _icosahedron() -> tuple[np.ndarray, np.ndarray]:
    phi = (1.0 + 5.0**0.5) / 2.0
    base = np.array([[0, s, t * phi] for s in (-1, 1) for t in (-1, 1)], dtype=np.float64)
    pts = np.concatenate([base, base[:, [2, 0, 1]], base[:, [1, 2, 0]]])
    pts /= np.linalg.norm(pts, axis=1)[:, None]
    # The 20 faces are the triples of mutually nearest vertices (edge length 2 before scaling).
    d = np.linalg.norm(pts[:, None] - pts[None], axis=2)
    near = np.abs(d - d[d > 1e-9].min()) < 1e-9
    faces = [(a, b, c) for a in range(12) for b in range(a + 1, 12) for c in range(b + 1, 12)
             if near[a, b] and near[b, c] and near[a, c]]
    tri = np.array(faces, dtype=np.int64)
    p = pts[tri]
    outward = np.einsum("mi,mi->m", p[:, 0], np.cross(p[:, 1], p[:, 2])) > 0
    tri[~outward] = tri[~outward][:, [0, 2, 1]]
    return pts, tri


def sphere(radius=1.0, center=(0.0, 0.0, 0.0), level: int = 3) -> Surface:
    """A subdivided icosahedron with every vertex on the sphere.

    Parameters
    ----------
    radius : float
        Positive.
    center : (3,) array_like of float
    level : int
        Subdivisions, 0 to :data:`MAX_SPHERE_LEVEL`; ``20 * 4**level`` faces,
        ``10 * 4**level + 2`` points.

    Returns
    -------
    Surface
        Outward faces, marker 1.

    Raises
    ------
    InputError
        A bad center or level.
    SizeError
        A radius that is not positive and finite.
    """
    radius = check_positive(radius, "radius")
    center = _point3(center, "center")
    level = check_count(level, "level")
    if level > MAX_SPHERE_LEVEL:
        raise InputError(f"level must be at most {MAX_SPHERE_LEVEL} ({20 * 4**MAX_SPHERE_LEVEL} faces), got {level}")
    pts, tri = _icosahedron()
    for _ in range(level):
        n = len(pts)
        edges = np.sort(tri[:, [[0, 1], [1, 2], [2, 0]]].reshape(-1, 2), axis=1)
        uniq, inverse = np.unique(edges, axis=0, return_inverse=True)
        mid = pts[uniq[:, 0]] + pts[uniq[:, 1]]
        pts = np.concatenate([pts, mid / np.linalg.norm(mid, axis=1)[:, None]])
        e = (n + inverse.ravel()).reshape(-1, 3)  # midpoints of edges 01, 12, 20
        a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
        ab, bc, ca = e[:, 0], e[:, 1], e[:, 2]
        tri = np.concatenate([np.column_stack(t) for t in ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))])
    return Surface(center + radius * pts, tri)


def extrude(mesh, height, *, z0=0.0, layers: int = 1, markers=(1, 2, 3), line_markers: bool = False) -> Surface:
    """The closed surface of a triangulated 2-D region swept from ``z0`` to ``z0 + height``.

    Parameters
    ----------
    mesh : Mesh
        2-D mesh with counter-clockwise triangle cells (e.g. ``meshwright.triangulate(domain)``);
        its boundary edges (in one triangle) become the walls, hole loops tunnels.
    height : float
        Positive.
    z0 : float
        Height of the bottom cap.
    layers : int
        Wall triangles are stacked in ``layers`` equal rows (>= 1); the caps are the 2-D
        triangles once each.
    markers : (3,) ints
        Markers of the bottom cap, the top cap and the walls.
    line_markers : bool
        Instead take each wall's marker from the mesh's ``line`` cell on its boundary edge
        (``cell_data["marker"]["line"]``); every boundary edge must be a line cell.

    Returns
    -------
    Surface
        Points: the 2-D points at ``z0``, then at ``z0 + height``, then the boundary points
        of the inner layers (2-D points in no triangle left out, the rest in their order).

    Raises
    ------
    InputError
        Not a 2-D Mesh with triangles (a Domain must be meshed first), bad height, layers
        or markers, a boundary edge without a line cell when ``line_markers``.
    GeometryError
        A triangle that is not counter-clockwise (exact orient2d), named with its corners.
    """
    if not isinstance(mesh, Mesh):
        raise InputError(
            f"extrude needs a 2-D Mesh of triangles, got {type(mesh).__name__}; mesh a Domain first: "
            "extrude(meshwright.triangulate(domain, size), height)"
        )
    if mesh.dim != 2 or not len(mesh.triangles):
        raise InputError(f"extrude needs a 2-D mesh with triangle cells, got {mesh!r}")
    height = check_positive(height, "height", InputError)
    z0 = _point3((0.0, 0.0, z0), "z0")[2]
    layers = check_count(layers, "layers", minimum=1)
    line_markers = check_flag(line_markers, "line_markers")
    marks = np.asarray(markers)
    if marks.shape != (3,) or not np.issubdtype(marks.dtype, np.integer) or marks.dtype == bool:
        raise InputError(f"markers must be three integers (bottom, top, walls), got {markers!r}")
    tri = mesh.triangles.astype(np.int64)
    signs = orient2d_batch(mesh.points, tri)
    bad = np.flatnonzero(signs <= 0)
    if len(bad):
        t = int(bad[0])
        raise GeometryError(
            f"triangle {t} {tri[t].tolist()} at {', '.join(fmt_point(mesh.points[v]) for v in tri[t])} is not "
            "counter-clockwise: extrude needs a valid 2-D triangle mesh"
        )
    n = mesh.n_points
    edges = boundary_edges_of(tri).astype(np.int64)
    wall_marks = np.full(len(edges), marks[2], np.int64)
    if line_markers:
        wall_marks = _line_markers(mesh, edges)
    bverts = np.unique(edges)
    slot = np.full(n, -1, np.int64)
    slot[bverts] = np.arange(len(bverts))

    def vid(v, layer):
        if layer == 0:
            return v
        if layer == layers:
            return v + n
        return 2 * n + (layer - 1) * len(bverts) + slot[v]

    walls = []
    for layer in range(layers):
        a0, b0 = vid(edges[:, 0], layer), vid(edges[:, 1], layer)
        a1, b1 = vid(edges[:, 0], layer + 1), vid(edges[:, 1], layer + 1)
        walls += [np.column_stack([a0, b0, b1]), np.column_stack([a0, b1, a1])]
    zs = z0 + height * np.arange(1, layers) / layers
    pts = np.concatenate(
        [np.column_stack([mesh.points, np.full(n, z0)]), np.column_stack([mesh.points, np.full(n, z0 + height)])]
        + [np.column_stack([mesh.points[bverts], np.full(len(bverts), z)]) for z in zs]
    )
    faces = np.concatenate([tri[:, [0, 2, 1]], tri + n] + walls)
    face_marks = np.concatenate(
        [np.full(len(tri), marks[0]), np.full(len(tri), marks[1])] + [wall_marks, wall_marks] * layers
    )
    used = np.unique(faces)
    if len(used) < len(pts):
        renumber = np.full(len(pts), -1, np.int64)
        renumber[used] = np.arange(len(used))
        pts, faces = pts[used], renumber[faces]
    return Surface(pts, faces, face_marks)


def _line_markers(mesh: Mesh, edges: np.ndarray) -> np.ndarray:
    """Marker of the line cell on every boundary edge."""
    values = mesh.cell_data.get("marker", {}).get("line")
    if values is None:
        raise InputError("line_markers=True needs cell_data['marker']['line'] on the mesh")
    base = np.array([mesh.n_points, 1])
    codes = np.sort(mesh.lines.astype(np.int64), axis=1) @ base
    order = np.argsort(codes)
    query = np.sort(edges, axis=1) @ base
    pos = np.minimum(np.searchsorted(codes[order], query), max(len(order) - 1, 0))
    found = codes[order][pos] == query if len(order) else np.zeros(len(edges), bool)
    if not found.all():
        i, j = edges[int(np.flatnonzero(~found)[0])]
        raise InputError(f"boundary edge ({i}, {j}) from {fmt_point(mesh.points[i])} to {fmt_point(mesh.points[j])} "
                         "has no line cell to take its marker from")
    return np.asarray(values, dtype=np.int64)[order][pos]


def far_field(body: Surface, lo, hi) -> Surface:
    """The region between a box and a body inside it: ``combine(box(lo, hi), body.flipped())``.

    Box markers are 1..6 (:func:`box`); the body keeps its own (choose them distinct).

    Raises
    ------
    InputError
        ``body`` not a Surface.
    GeometryError
        The body's bounding box is not strictly inside ``[lo, hi]``.
    """
    if not isinstance(body, Surface):
        raise InputError(f"far_field needs a Surface body, got {type(body).__name__}")
    outer = box(lo, hi)
    blo, bhi = body.bbox
    olo, ohi = outer.bbox
    if not (np.all(blo > olo) and np.all(bhi < ohi)):
        raise GeometryError(
            f"the body's bounding box {fmt_point(blo)} .. {fmt_point(bhi)} is not strictly inside the far field "
            f"{fmt_point(olo)} .. {fmt_point(ohi)}"
        )
    return combine(outer, body.flipped())
