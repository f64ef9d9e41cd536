"""Mesh pictures with matplotlib (imported inside the functions, never at package import).

Elements are drawn as one ``PolyCollection`` per cell type, so 1e5+ cells render in
about a second; boundary ``line`` cells are drawn on top, thicker and coloured by marker.
With ``path`` and no ``ax`` the figure is rendered by the Agg canvas directly (no pyplot,
no display needed), so PNG output works headless whatever the configured backend.
"""

from __future__ import annotations

import numpy as np

from meshwright.core.errors import InputError

__all__ = ["plot_mesh", "plot_triangulation", "plot_quality_histogram"]

_FACE_COLOR = "#dce6f2"
_EDGE_COLOR = "#1f2a36"
_MAX_LEGEND_MARKERS = 10


def _auto_linewidth(n_cells: int) -> float:
    """Edge width that keeps dense meshes readable: 0.8 for small, down to 0.1 for 1e6 cells."""
    return float(np.clip(30.0 / np.sqrt(max(n_cells, 1)), 0.1, 0.8))


def _new_figure(path, figsize=(7.0, 7.0)):
    """An Agg-only figure when writing a file (headless), else a pyplot figure."""
    if path is not None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        fig = Figure(figsize=figsize)
        FigureCanvasAgg(fig)
        return fig
    import matplotlib.pyplot as plt

    return plt.figure(figsize=figsize)


def _new_axes(ax, path, projection=None):
    """Return (fig, ax): the given axes, an Agg-only figure when writing a file, else pyplot."""
    if ax is not None:
        return ax.figure, ax
    fig = _new_figure(path)
    return fig, fig.add_subplot(projection=projection)


def _finish(fig, ax, path, dpi) -> None:
    if ax.name != "3d":
        ax.set_aspect("equal")
        ax.autoscale_view()
    if path is not None:
        fig.savefig(path, dpi=dpi, bbox_inches="tight")


def _polys(points: np.ndarray, cells: np.ndarray, values, edgecolor, facecolor, linewidth, cmap, norm):
    from matplotlib.collections import PolyCollection

    coll = PolyCollection(
        points[cells], closed=True, edgecolors=edgecolor, linewidths=linewidth, facecolors=facecolor
    )
    if values is not None:
        coll.set_array(np.asarray(values, dtype=np.float64))
        coll.set_cmap(cmap)
        coll.set_norm(norm)
    return coll


def plot_triangulation(
    points,
    triangles,
    ax=None,
    path=None,
    values=None,
    linewidth=None,
    edgecolor=_EDGE_COLOR,
    facecolor="none",
    cmap="viridis",
    show_points=False,
    point_size=4.0,
    dpi=150,
):
    """Draw a triangulation given as arrays (Delaunay, Voronoi and demo figures).

    Parameters
    ----------
    points : (n, 2) float64
    triangles : (m, 3) int
    ax : matplotlib Axes, optional
        Draw into it; default a new figure.
    path : str or Path, optional
        Also save the figure there (PNG, SVG, PDF by extension).
    values : (m,) float, optional
        Colour the triangles by these values (a colour bar is added).
    linewidth : float, optional
        Edge width; default from the number of triangles.
    edgecolor, facecolor : matplotlib colours
    cmap : str or Colormap
    show_points : bool
        Also mark the points.
    point_size : float
    dpi : int

    Returns
    -------
    matplotlib.axes.Axes
    """
    from matplotlib.colors import Normalize

    points = np.asarray(points, dtype=np.float64)[:, :2]
    triangles = np.asarray(triangles, dtype=np.int64)
    if triangles.ndim != 2 or triangles.shape[1] != 3:
        raise InputError(f"triangles must have shape (m, 3), got {triangles.shape}")
    fig, ax = _new_axes(ax, path)
    lw = _auto_linewidth(len(triangles)) if linewidth is None else linewidth
    norm = None
    if values is not None:
        values = np.asarray(values, dtype=np.float64)
        if values.shape != (len(triangles),):
            raise InputError(f"values must have shape ({len(triangles)},), got {values.shape}")
        norm = Normalize(*_finite_range(values))
    coll = _polys(points, triangles, values, edgecolor, facecolor, lw, cmap, norm)
    ax.add_collection(coll)
    if values is not None:
        fig.colorbar(coll, ax=ax, shrink=0.8)
    if show_points:
        ax.plot(points[:, 0], points[:, 1], "o", ms=np.sqrt(point_size), color=edgecolor)
    ax.update_datalim(points)
    _finish(fig, ax, path, dpi)
    return ax


def _finite_range(values: np.ndarray) -> tuple[float, float]:
    finite = values[np.isfinite(values)]
    if not len(finite):
        return 0.0, 1.0
    lo, hi = float(finite.min()), float(finite.max())
    return (lo, hi) if hi > lo else (lo - 0.5, hi + 0.5)


def _face_values(mesh, face_types, show_quality, color_by):
    """Per-cell colour values of each face block, and a colour-bar label."""
    if show_quality is not None and color_by is not None:
        raise InputError("give show_quality or color_by, not both")
    if show_quality is not None:
        report = mesh.quality()
        values = {}
        for t in face_types:
            if show_quality not in report[t]:
                raise InputError(f"{t} cells have no quality measure {show_quality!r}; available: {', '.join(report[t])}")
            values[t] = report[t][show_quality]
        return values, show_quality
    if color_by is None:
        return None, None
    if isinstance(color_by, str):
        if color_by not in mesh.cell_data:
            raise InputError(f"color_by={color_by!r} is not a cell_data name; available: {', '.join(mesh.cell_data) or 'none'}")
        data = mesh.cell_data[color_by]
        missing = [t for t in face_types if t not in data]
        if missing:
            raise InputError(f"cell_data[{color_by!r}] has no values for {', '.join(missing)} cells")
        return {t: np.asarray(data[t], dtype=np.float64) for t in face_types}, color_by
    # An array with one value per face cell, blocks in mesh order.
    flat = np.asarray(color_by, dtype=np.float64)
    sizes = [len(mesh.cells[t]) for t in face_types]
    if flat.shape != (sum(sizes),):
        raise InputError(f"color_by array must have shape ({sum(sizes)},), one value per {'/'.join(face_types)} cell")
    split = np.split(flat, np.cumsum(sizes)[:-1])
    return dict(zip(face_types, split)), None


def _draw_lines(ax, mesh, segments, markers, linewidth):
    """Boundary lines, coloured by marker with a legend when there are few markers."""
    from matplotlib.collections import LineCollection
    from matplotlib.lines import Line2D

    pts = mesh.points[:, :2]
    if markers is None:
        ax.add_collection(LineCollection(pts[segments], colors=_EDGE_COLOR, linewidths=linewidth))
        return
    import matplotlib as mpl

    unique, index = np.unique(markers, return_inverse=True)
    cmap = mpl.colormaps["tab10" if len(unique) <= _MAX_LEGEND_MARKERS else "turbo"].resampled(max(len(unique), 1))
    colors = cmap(np.arange(len(unique)))
    ax.add_collection(LineCollection(pts[segments], colors=colors[index.ravel()], linewidths=linewidth))
    if len(unique) <= _MAX_LEGEND_MARKERS:
        handles = [Line2D([], [], color=colors[i], lw=linewidth, label=f"marker {int(v)}") for i, v in enumerate(unique)]
        ax.legend(handles=handles, loc="upper right", fontsize="small", framealpha=0.8)


def plot_mesh(
    mesh,
    ax=None,
    path=None,
    show_quality=None,
    color_by=None,
    linewidth=None,
    cmap="viridis",
    show_points=False,
    title=None,
    dpi=150,
):
    """Draw a :class:`~meshwright.core.mesh.Mesh`.

    2-D meshes: triangles and quads as polygons (plain, or coloured by a quality measure
    or cell data), ``line`` cells on top, thicker and coloured by
    ``cell_data["marker"]["line"]`` (without line cells, the boundary edges are
    emphasised).  3-D meshes: the boundary faces of the volume cells (or the surface
    triangles / quads) in a 3-D axes; with ``show_quality`` (tetra meshes) the boundary
    faces take the colour of their tet's measure and a figure made here gets a histogram
    of the measure over all tets beside the surface (see :func:`plot_quality_histogram`).
    A tetra mesh drawn plainly into a figure made here (no ``ax``, ``show_quality``,
    ``color_by``, ``show_points``) gets :func:`meshwright.plot.tet_plot.plot_tet_mesh`'s
    three panels (boundary, clipped cut, dihedral histogram); the surface's axes is returned.

    Parameters
    ----------
    mesh : Mesh
    ax : matplotlib Axes, optional
        Draw into it (a 3-D axes for 3-D meshes); default a new figure.
    path : str or Path, optional
        Save the figure there; without ``ax`` the Agg canvas is used, so this works headless.
    show_quality : str, optional
        Colour 2-D cells by a measure of :meth:`Mesh.quality`, e.g. ``"min_angle"``,
        ``"radius_ratio"``, ``"area"`` (it must exist for every face cell type present);
        for tetra meshes e.g. ``"min_dihedral"`` or ``"sliver_ratio"``.
    color_by : str or (m,) array, optional
        Colour 2-D cells by ``cell_data[color_by]`` (e.g. ``"marker"`` for regions) or by
        one value per triangle / quad cell (blocks in mesh order).
    linewidth : float, optional
        Element edge width; default from the number of cells.  Boundary lines are 3x.
    cmap : str or Colormap
    show_points : bool
        Also mark the vertices.
    title : str, optional
    dpi : int

    Returns
    -------
    matplotlib.axes.Axes
    """
    if mesh.dim == 3:
        if ax is None and show_quality is None and color_by is None and not show_points and _tetra_only(mesh):
            from meshwright.plot.tet_plot import plot_tet_mesh

            fig = _new_figure(path)
            return plot_tet_mesh(mesh, path, linewidth=linewidth, title=title, dpi=dpi, cmap=cmap, figure=fig).axes[0]
        return _plot_mesh_3d(mesh, ax, path, linewidth, title, dpi, show_quality, color_by, cmap, show_points)
    from matplotlib.colors import Normalize

    face_types = [t for t in ("triangle", "quad") if t in mesh.cells and len(mesh.cells[t])]
    n_faces = sum(len(mesh.cells[t]) for t in face_types)
    lw = _auto_linewidth(n_faces) if linewidth is None else linewidth
    values, label = _face_values(mesh, face_types, show_quality, color_by)
    fig, ax = _new_axes(ax, path)
    pts = mesh.points
    norm = None
    if values is not None:
        norm = Normalize(*_finite_range(np.concatenate([values[t] for t in face_types] or [np.zeros(0)])))
    coll = None
    for t in face_types:
        coll = _polys(
            pts, mesh.cells[t], None if values is None else values[t], _EDGE_COLOR, _FACE_COLOR, lw, cmap, norm
        )
        ax.add_collection(coll)
    if values is not None and coll is not None:
        fig.colorbar(coll, ax=ax, shrink=0.8, label=label)
    boundary_lw = max(3.0 * lw, 1.2)
    if len(mesh.lines):
        _draw_lines(ax, mesh, mesh.lines, mesh.cell_data.get("marker", {}).get("line"), boundary_lw)
    elif face_types:
        _draw_lines(ax, mesh, mesh.boundary_facets(), None, boundary_lw)
    if show_points:
        ax.plot(pts[:, 0], pts[:, 1], "o", ms=2.0, color=_EDGE_COLOR)
    ax.update_datalim(pts)
    if title:
        ax.set_title(title)
    _finish(fig, ax, path, dpi)
    return ax


def _tetra_only(mesh) -> bool:
    return bool(len(mesh.tetra)) and not len(mesh.hexahedra)


def _tetra_surface(mesh):
    """Outward boundary faces of the tetra block and the tet owning each, or None when the
    mesh also has hexahedra."""
    from meshwright.core.flat import TET_FACES
    from meshwright.core.mesh import build_neighbors_tet

    if len(mesh.hexahedra) or not len(mesh.tetra):
        return None
    tets = mesh.tetra
    owner, k = np.nonzero(build_neighbors_tet(tets) < 0)
    return tets[owner[:, None], TET_FACES[k]], owner


def _plot_mesh_3d(mesh, ax, path, linewidth, title, dpi, show_quality=None, color_by=None, cmap="viridis", show_points=False):
    """3-D meshes: the boundary surface; with ``show_quality`` (tetra meshes) each boundary
    face takes the colour of its tet's measure and, in a figure made here, a histogram of
    that measure over all tets sits beside the surface."""
    from matplotlib.colors import Normalize
    from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

    if color_by is not None:
        raise InputError("color_by is for 2-D meshes; colour a 3-D tetra mesh with show_quality")
    surface = _tetra_surface(mesh) if show_quality is not None else None
    values = None
    if show_quality is not None:
        if surface is None:
            raise InputError("show_quality on a 3-D mesh needs tetra cells only (no hexahedra)")
        report = mesh.quality()["tetra"]
        if show_quality not in report:
            raise InputError(f"tetra cells have no quality measure {show_quality!r}; available: {', '.join(report)}")
        values = report[show_quality]
    volume = any(t in mesh.cells and len(mesh.cells[t]) for t in ("tetra", "hexahedron"))
    if surface is not None:
        faces = [surface[0]]
    else:
        faces = [mesh.boundary_facets()] if volume else [mesh.cells[t] for t in ("triangle", "quad") if t in mesh.cells]
    hist_ax = None
    if ax is None and values is not None:
        fig = _new_figure(path, figsize=(13.0, 6.0))
        ax = fig.add_subplot(1, 2, 1, projection="3d")
        hist_ax = fig.add_subplot(1, 2, 2)
    else:
        fig, ax = _new_axes(ax, path, projection="3d")
    n = sum(len(f) for f in faces)
    lw = _auto_linewidth(n) if linewidth is None else linewidth
    for f in faces:
        if not len(f):
            continue
        coll = Poly3DCollection(mesh.points[f], facecolors=_FACE_COLOR, edgecolors=_EDGE_COLOR, linewidths=lw, alpha=0.9)
        if values is not None:
            coll.set_array(values[surface[1]])
            coll.set_cmap(cmap)
            coll.set_norm(Normalize(*_finite_range(values)))
        ax.add_collection3d(coll)
        if values is not None:
            fig.colorbar(coll, ax=ax, shrink=0.6, label=f"{show_quality} (boundary tets)")
    if len(mesh.lines):
        ax.add_collection3d(Line3DCollection(mesh.points[mesh.lines], colors="C3", linewidths=max(3 * lw, 1.2)))
    if show_points:
        p = mesh.points
        ax.scatter(p[:, 0], p[:, 1], p[:, 2], s=2.0, color=_EDGE_COLOR)
    lo, hi = mesh.points.min(axis=0), mesh.points.max(axis=0)
    centre, half = (lo + hi) / 2.0, max(float((hi - lo).max()) / 2.0, 1e-12)
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
    if title:
        ax.set_title(title)
    if hist_ax is not None:
        plot_quality_histogram(mesh, show_quality, ax=hist_ax)
    _finish(fig, ax, path, dpi)
    return ax


# Reference lines drawn on quality histograms: the chapter's sliver flag, the regular tet.
_HIST_MARKS = {
    "sliver_ratio": ((0.01, "sliver flag a < 0.01 (18.1.1)"), (1.0 / 3.0, "regular tet 1/3")),
    "radius_ratio": ((1.0, "regular element"),),
    "min_dihedral": ((np.degrees(np.arccos(1.0 / 3.0)), "regular tet 70.53 deg"),),
    "max_dihedral": ((np.degrees(np.arccos(1.0 / 3.0)), "regular tet 70.53 deg"),),
}


def plot_quality_histogram(mesh, measure="min_dihedral", cell_type=None, ax=None, path=None, bins=50, log=True, dpi=150):
    """Histogram of one quality measure over all cells of a type (Mesh.quality()).

    Parameters
    ----------
    mesh : Mesh
    measure : str
        A measure of :mod:`meshwright.core.quality`, e.g. ``"min_dihedral"``,
        ``"sliver_ratio"`` (tetra), ``"min_angle"`` (triangle).
    cell_type : str, optional
        Default: ``"tetra"`` if the mesh has tetrahedra, else the first cell type with
        measures.
    ax : matplotlib Axes, optional
    path : str or Path, optional
        Save the figure there (headless Agg canvas when no ``ax`` is given).
    bins : int
        Number of bins (>= 1).
    log : bool
        Logarithmic count axis, so the few worst cells (slivers) stay visible.
    dpi : int

    Returns
    -------
    matplotlib.axes.Axes
    """
    if isinstance(bins, bool) or not isinstance(bins, (int, np.integer)) or bins < 1:
        raise InputError(f"bins must be a positive integer, got {bins!r}")
    report = mesh.quality()
    if cell_type is None:
        cell_type = "tetra" if "tetra" in report else next(iter(report.cell_types), None)
    if cell_type is None or cell_type not in report:
        raise InputError(f"the mesh has no {cell_type or 'cells with quality measures'}")
    if measure not in report[cell_type]:
        raise InputError(f"{cell_type} cells have no quality measure {measure!r}; available: {', '.join(report[cell_type])}")
    values = report[cell_type][measure]
    finite = values[np.isfinite(values)]
    fig, ax = _new_axes(ax, path)
    ax.hist(finite, bins=int(bins), range=_finite_range(finite), color="#4c72b0", log=log)
    for i, (x, label) in enumerate(_HIST_MARKS.get(measure, ())):
        ax.axvline(x, color=("C3", "C2")[i], lw=1.0, ls="--", label=label)
    if measure in _HIST_MARKS:
        ax.legend(fontsize="small")
    unit = " [deg]" if "angle" in measure or "dihedral" in measure else ""
    ax.set_xlabel(f"{measure}{unit}")
    ax.set_ylabel(f"{cell_type} cells")
    ax.set_title(f"{measure}: min {finite.min():.4g}, mean {finite.mean():.4g} ({len(values)} cells)" if len(finite) else measure)
    if path is not None:
        fig.savefig(path, dpi=dpi, bbox_inches="tight")
    return ax
