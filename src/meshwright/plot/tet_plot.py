"""Pictures of tetrahedral meshes: boundary surface, a clipped cut and the dihedral histogram.

One figure of three panels, the views TetGen and Gmsh users look at to judge a volume mesh:

1. the boundary surface (faces of the tetrahedra with no neighbour), coloured by the face
   markers of the mesh's ``triangle`` cells where they match;
2. a clipped cut: the tetrahedra whose centroid lies on the kept side of a plane, drawn as
   their faces that border no other kept tetrahedron (the jagged cut shows the interior
   elements, coloured by a quality measure of the tetrahedron they belong to);
3. histograms of every tetrahedron's smallest and largest dihedral angle, with the 10
   degree line the sliver benchmarks count below.

matplotlib draws a ``Poly3DCollection`` by depth-sorting its polygons (painter's
algorithm) within the collection, but orders separate collections by their mean depth
only; each 3-D panel is therefore ONE collection with per-face colours, so boundary and
cut faces hide each other correctly.  Faces are shaded by a fixed light (Lambert term of
the face normal) so the shape reads without edges on dense meshes.

matplotlib is imported inside the functions; a figure made here is an Agg ``Figure``
(no pyplot, works headless).

Arrays: ``points`` (n, 3) float64, ``tetra`` (m, 4) int32 positively oriented (the
:class:`~meshwright.core.mesh.Mesh` contract), faces (k, 3) vertex indices.
"""

from __future__ import annotations

import numpy as np

from meshwright.core.errors import InputError

__all__ = ["clipped_faces", "plot_tet_mesh"]

_SURFACE_COLOR = np.array([0.86, 0.90, 0.95])
_EDGE_COLOR = "#1f2a36"
_LIGHT = np.array([0.35, -0.55, 0.76]) / np.linalg.norm([0.35, -0.55, 0.76])
_SLIVER_LINE_DEG = 10.0
# Default view of the 3-D panels; the default cut removes the half facing this camera.
_ELEV, _AZIM = 22.0, -60.0


def _check_mesh(mesh):
    from meshwright.core.mesh import Mesh

    if not isinstance(mesh, Mesh):
        raise InputError(f"mesh must be a meshwright Mesh, got {type(mesh).__name__}")
    if mesh.dim != 3 or not len(mesh.tetra):
        raise InputError(f"plot_tet_mesh needs a 3-D mesh with tetra cells, got {mesh!r}")
    if len(mesh.hexahedra):
        raise InputError("plot_tet_mesh draws tetra-only meshes; this one also has hexahedron cells")


def _check_cut(cut, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(origin, unit normal) of the cutting plane; default through the bounding-box centre,
    normal pointing towards the default camera's side (that half is removed)."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    if cut is None:
        normal = np.array([np.cos(np.radians(_AZIM)), np.sin(np.radians(_AZIM)), 0.0])
        return (lo + hi) / 2.0, normal
    try:
        origin, normal = cut
        origin = np.asarray(origin, dtype=np.float64)
        normal = np.asarray(normal, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"cut must be (origin, normal), two 3-vectors, got {cut!r}") from exc
    if origin.shape != (3,) or normal.shape != (3,):
        raise InputError(f"cut must be (origin, normal), two 3-vectors, got shapes {origin.shape} and {normal.shape}")
    if not (np.isfinite(origin).all() and np.isfinite(normal).all()):
        raise InputError(f"cut origin and normal must be finite, got {origin.tolist()} and {normal.tolist()}")
    length = float(np.linalg.norm(normal))
    if length == 0.0:
        raise InputError("cut normal must be a nonzero vector, got (0, 0, 0)")
    return origin, normal / length


def clipped_faces(mesh, cut=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Faces that show when the tetrahedra on one side of a plane are removed.

    A tetrahedron is kept when its centroid ``c`` has ``(c - origin) . normal <= 0``; the
    faces drawn are those of kept tetrahedra across which there is no kept tetrahedron
    (the boundary of the domain, and the jagged cut).

    Parameters
    ----------
    mesh : Mesh
        3-D, tetra cells (positively oriented), no hexahedra.
    cut : (origin, normal), optional
        The plane: origin (3,) float and normal (3,) float (nonzero); the side the
        normal points to is removed.  Default: through the centre of the bounding box,
        normal horizontal towards the default camera.

    Returns
    -------
    faces : (k, 3) int32
        Vertex indices, oriented out of the kept tetrahedron.
    owner : (k,) int32
        The kept tetrahedron of each face.
    on_cut : (k,) bool
        True for faces of the cut (an interior face of the mesh), False on the boundary.
    """
    from meshwright.core.flat import TET_FACES
    from meshwright.core.mesh import build_neighbors_tet

    _check_mesh(mesh)
    tets = mesh.tetra
    origin, normal = _check_cut(cut, mesh.points)
    keep = (mesh.points[tets].mean(axis=1) - origin) @ normal <= 0.0
    nbr = build_neighbors_tet(tets)
    keep_nbr = np.where(nbr >= 0, keep[np.maximum(nbr, 0)], False)
    owner, k = np.nonzero(keep[:, None] & ~keep_nbr)
    faces = tets[owner[:, None], TET_FACES[k]].astype(np.int32)
    return faces, owner.astype(np.int32), nbr[owner, k] >= 0


def _boundary_faces(mesh) -> tuple[np.ndarray, np.ndarray]:
    """Outward boundary faces of the tetra block and the tetrahedron owning each."""
    from meshwright.core.flat import TET_FACES
    from meshwright.core.mesh import build_neighbors_tet

    tets = mesh.tetra
    owner, k = np.nonzero(build_neighbors_tet(tets) < 0)
    return tets[owner[:, None], TET_FACES[k]].astype(np.int32), owner.astype(np.int32)


def _face_markers(mesh, faces: np.ndarray) -> np.ndarray | None:
    """Marker of each face from the ``triangle`` cells with the same vertex set; None when
    the mesh carries no triangle markers (int64 min for a face no triangle cell matches:
    markers are int32, so it matches no palette entry)."""
    tri = mesh.cells.get("triangle")
    markers = mesh.cell_data.get("marker", {}).get("triangle")
    if tri is None or markers is None or not len(tri) or not len(faces):
        return None
    keys = np.sort(np.concatenate([tri, faces]), axis=1)
    _, inverse = np.unique(keys, axis=0, return_inverse=True)
    inverse = inverse.ravel()
    lookup = np.full(inverse.max() + 1, np.iinfo(np.int64).min, dtype=np.int64)
    lookup[inverse[: len(tri)]] = markers
    return lookup[inverse[len(tri) :]]


def _shade(points: np.ndarray, faces: np.ndarray, rgb: np.ndarray) -> np.ndarray:
    """RGBA colours of ``rgb`` (k, 3) dimmed by a two-sided Lambert term of each face."""
    p = points[faces]
    n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    length = np.linalg.norm(n, axis=1)
    cos = np.abs(n @ _LIGHT) / np.where(length > 0.0, length, 1.0)
    out = np.ones((len(faces), 4))
    out[:, :3] = rgb * (0.45 + 0.55 * cos)[:, None]
    return out


def _palette(markers: np.ndarray | None) -> tuple[np.ndarray, np.ndarray] | None:
    """(sorted distinct markers, their pale tab10 tints), or None without markers."""
    if markers is None:
        return None
    import matplotlib as mpl

    unique = np.unique(markers)
    cmap = mpl.colormaps["tab10" if len(unique) <= 10 else "turbo"].resampled(max(len(unique), 1))
    base = np.asarray(cmap(np.arange(len(unique))))[:, :3]
    return unique, 0.45 * base + 0.55  # pale, so shading and the cut colours stay readable


def _marker_rgb(markers: np.ndarray | None, palette, count: int) -> np.ndarray:
    """(count, 3) base colours by marker; faces without a palette marker take the plain colour."""
    rgb = np.tile(_SURFACE_COLOR, (count, 1))
    if markers is None or palette is None:
        return rgb
    unique, tint = palette
    at = np.minimum(np.searchsorted(unique, markers), len(unique) - 1)
    found = unique[at] == markers
    rgb[found] = tint[at[found]]
    return rgb


def _square_limits(ax, points: np.ndarray) -> None:
    lo, hi = points.min(axis=0), points.max(axis=0)
    centre, half = (lo + hi) / 2.0, max(float((hi - lo).max()) / 2.0, 1e-12)
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
    ax.set_box_aspect((1.0, 1.0, 1.0))
    ax.view_init(elev=_ELEV, azim=_AZIM)


def plot_tet_mesh(
    mesh,
    path=None,
    *,
    cut=None,
    measure="min_dihedral",
    cmap="viridis",
    linewidth=None,
    bins=60,
    title=None,
    dpi=150,
    figure=None,
):
    """Draw a tetrahedral mesh: boundary surface, clipped cut, dihedral-angle histogram.

    Parameters
    ----------
    mesh : Mesh
        3-D, with tetra cells (positively oriented) and no hexahedra; ``triangle`` cells
        with ``cell_data["marker"]["triangle"]`` colour the boundary by marker.
    path : str or Path, optional
        Save the figure there (PNG, SVG, PDF by extension).
    cut : (origin, normal), optional
        Cutting plane of the middle panel (see :func:`clipped_faces`); the tetrahedra on
        the side the normal points to are removed.  Default: through the centre of the
        bounding box, removing the half that faces the camera.
    measure : str
        Tetra quality measure (:func:`meshwright.core.quality.tetra_quality`) colouring the
        cut faces, e.g. ``"min_dihedral"``, ``"radius_ratio"``, ``"sliver_ratio"``.
    cmap : str or Colormap
        Colour map of the cut faces.
    linewidth : float, optional
        Face edge width; default from the number of faces drawn.
    bins : int
        Histogram bins (>= 1).
    title : str, optional
        Figure title.
    dpi : int
    figure : matplotlib Figure, optional
        Draw into this (empty) figure; default a new Agg figure (headless).

    Returns
    -------
    matplotlib.figure.Figure
        Axes in order: boundary surface (3-D), cut (3-D), histogram, then the cut's colour bar.

    Raises
    ------
    InputError
        Not a 3-D tetra mesh, an unknown measure, a bad cut plane or bin count.
    """
    from matplotlib.colors import Normalize
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    from meshwright.core.quality import tetra_quality
    from meshwright.plot.mesh_plot import _auto_linewidth, _finite_range

    _check_mesh(mesh)
    if isinstance(bins, bool) or not isinstance(bins, (int, np.integer)) or bins < 1:
        raise InputError(f"bins must be a positive integer, got {bins!r}")
    quality = tetra_quality(mesh.points, mesh.tetra)
    if measure not in quality:
        raise InputError(f"tetra cells have no quality measure {measure!r}; available: {', '.join(quality)}")
    faces_cut, owner_cut, on_cut = clipped_faces(mesh, cut)
    faces_bnd, _ = _boundary_faces(mesh)

    if figure is None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        figure = Figure()
        FigureCanvasAgg(figure)
    figure.set_size_inches(18.0, 6.2)
    pts = mesh.points
    ax_surf = figure.add_subplot(1, 3, 1, projection="3d")
    ax_cut = figure.add_subplot(1, 3, 2, projection="3d")
    ax_hist = figure.add_subplot(1, 3, 3)

    markers = _face_markers(mesh, faces_bnd)
    palette = _palette(markers)
    rgb = _marker_rgb(markers, palette, len(faces_bnd))
    lw = _auto_linewidth(len(faces_bnd)) * 0.6 if linewidth is None else linewidth
    ax_surf.add_collection3d(
        Poly3DCollection(pts[faces_bnd], facecolors=_shade(pts, faces_bnd, rgb), edgecolors=_EDGE_COLOR, linewidths=lw)
    )
    if palette is not None and len(palette[0]) <= 10:
        from matplotlib.patches import Patch

        handles = [Patch(color=c, label=f"marker {int(v)}") for v, c in zip(*palette)]
        ax_surf.legend(handles=handles, loc="upper left", fontsize="small")
    ax_surf.set_title(f"boundary: {len(faces_bnd)} faces, {mesh.n_points} points")

    values = quality[measure]
    norm = Normalize(*_finite_range(values[np.isfinite(values)]))
    colormap = _colormap(cmap)
    cut_rgb = _marker_rgb(_face_markers(mesh, faces_cut), palette, len(faces_cut))
    cut_rgb[on_cut] = np.asarray(colormap(norm(values[owner_cut[on_cut]])))[:, :3]
    lw = _auto_linewidth(len(faces_cut)) * 0.6 if linewidth is None else linewidth
    ax_cut.add_collection3d(
        Poly3DCollection(pts[faces_cut], facecolors=_shade(pts, faces_cut, cut_rgb), edgecolors=_EDGE_COLOR, linewidths=lw)
    )
    ax_cut.set_title(f"clipped: {int(on_cut.sum())} faces of the cut, tets coloured by {measure}")
    from matplotlib.cm import ScalarMappable

    bar = ScalarMappable(norm=norm, cmap=colormap)
    bar.set_array(values)
    figure.colorbar(bar, ax=ax_cut, shrink=0.6, label=f"{measure} (cut faces)")
    for ax in (ax_surf, ax_cut):
        _square_limits(ax, pts)

    _dihedral_histogram(ax_hist, quality, int(bins))
    if title:
        figure.suptitle(title)
    if path is not None:
        figure.savefig(path, dpi=dpi, bbox_inches="tight")
    return figure


def _colormap(cmap):
    import matplotlib as mpl

    if isinstance(cmap, str):
        if cmap not in mpl.colormaps:
            raise InputError(f"unknown colour map {cmap!r}")
        return mpl.colormaps[cmap]
    return cmap


def _dihedral_histogram(ax, quality: dict, bins: int) -> None:
    """Histograms of the smallest and largest dihedral angle of every tetrahedron."""
    lo, hi = quality["min_dihedral"], quality["max_dihedral"]
    edges = np.linspace(0.0, 180.0, bins + 1)
    ax.hist(lo[np.isfinite(lo)], bins=edges, color="#4c72b0", alpha=0.75, log=True, label="min dihedral per tet")
    ax.hist(hi[np.isfinite(hi)], bins=edges, color="#dd8452", alpha=0.75, log=True, label="max dihedral per tet")
    ax.axvline(_SLIVER_LINE_DEG, color="C3", lw=1.0, ls="--", label=f"{_SLIVER_LINE_DEG:g} deg")
    ax.axvline(np.degrees(np.arccos(1.0 / 3.0)), color="C2", lw=1.0, ls="--", label="regular tet 70.53 deg")
    ax.set_xlim(0.0, 180.0)
    ax.set_xlabel("dihedral angle [deg]")
    ax.set_ylabel("tetra cells")
    below = float(np.mean(lo < _SLIVER_LINE_DEG)) if len(lo) else 0.0
    ax.set_title(
        f"dihedrals: {np.nanmin(lo):.2f} to {np.nanmax(hi):.2f} deg, "
        f"{100.0 * below:.3g} % of {len(lo)} tets below {_SLIVER_LINE_DEG:g} deg"
    )
    ax.legend(fontsize="small")
