"""Drawing of a Voronoi diagram over its Delaunay triangulation (chapter Figure 18.1.1a).

Light lines are the Delaunay triangles, heavy lines the Voronoi polygons (Voronoi 1908,
Dirichlet 1850).  matplotlib is imported inside the function, never at package import; with
``path`` and no ``ax`` the figure is rendered by the Agg canvas directly, so PNG output works
headless and leaves pyplot's global state alone.
"""

from __future__ import annotations

import numpy as np

__all__ = ["plot_voronoi"]

_DELAUNAY_STYLE = {"colors": "0.65", "linewidths": 0.6, "zorder": 1}
_VORONOI_STYLE = {"colors": "k", "linewidths": 1.6, "zorder": 2}


def plot_voronoi(vor, ax=None, path=None, show_delaunay=True, show_points=True):
    """Draw the Voronoi polygons (heavy) over the Delaunay triangulation (light).

    Unclipped, infinite ridges are drawn as rays long enough to leave the view, which is the
    bounding box of the points with a 10 % margin; clipped, the clip polygon is drawn too and
    the view is its bounding box.

    Parameters
    ----------
    vor : meshwright.tri.voronoi.Voronoi
    ax : matplotlib.axes.Axes, optional
        Axes to draw into; a new figure is made when omitted.
    path : str or os.PathLike, optional
        Write the figure to this file (PNG etc., by extension).
    show_delaunay : bool
        Draw the Delaunay edges (``vor.forming_points``).
    show_points : bool
        Mark the generators ``vor.points``.

    Returns
    -------
    matplotlib.axes.Axes
    """
    from matplotlib.collections import LineCollection

    if ax is None:
        if path is not None:
            from matplotlib.backends.backend_agg import FigureCanvasAgg
            from matplotlib.figure import Figure

            fig = Figure(figsize=(6, 6))
            FigureCanvasAgg(fig)
            ax = fig.add_subplot()
        else:
            import matplotlib.pyplot as plt

            _, ax = plt.subplots(figsize=(6, 6))

    pts = vor.points
    if vor.clip_polygon is not None:
        lo, hi = vor.clip_polygon.min(axis=0), vor.clip_polygon.max(axis=0)
    else:
        lo, hi = pts.min(axis=0), pts.max(axis=0)
    margin = 0.1 * max(float((hi - lo).max()), 1e-12)
    lo, hi = lo - margin, hi + margin

    if show_delaunay:
        sides = vor.forming_points[:, [[1, 2], [2, 0], [0, 1]]].reshape(-1, 2)
        edges = np.unique(np.sort(sides, axis=1), axis=0)
        ax.add_collection(LineCollection(pts[edges], **_DELAUNAY_STYLE))

    rv = vor.ridge_vertices
    finite = rv[:, 1] >= 0
    segments = [vor.vertices[rv[finite]]]
    if not finite.all():
        start = vor.vertices[rv[~finite, 0]]
        # Long enough to cross the view from any start point, so the ray's end is never seen.
        reach = np.hypot(*(hi - lo)) + np.hypot(*(start - 0.5 * (lo + hi)).T)
        end = start + vor.ridge_directions[~finite] * reach[:, None]
        segments.append(np.stack([start, end], axis=1))
    if vor.clip_polygon is not None:
        poly = vor.clip_polygon
        segments.append(np.stack([poly, np.roll(poly, -1, axis=0)], axis=1))
    ax.add_collection(LineCollection(np.concatenate(segments), **_VORONOI_STYLE))

    if show_points:
        ax.plot(pts[:, 0], pts[:, 1], "o", color="k", markersize=3, zorder=3)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    ax.set_title(f"Voronoi diagram of {len(pts)} points over their Delaunay triangulation")
    if path is not None:
        ax.figure.savefig(path, dpi=150, bbox_inches="tight")
    return ax
