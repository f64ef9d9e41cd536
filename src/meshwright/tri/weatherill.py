r"""Weatherill's automatic point generation inside a constrained Delaunay triangulation.

Sources: N. P. Weatherill, "Delaunay triangulation in computational fluid dynamics",
Computers & Mathematics with Applications 24(5/6):129-150, 1992; N. P. Weatherill and
O. Hassan, "Efficient three-dimensional Delaunay triangulation with automatic point creation
and imposed boundary constraints", Int. J. Numer. Meth. Engng 37:2005-2039, 1994; chapter
18.1.3 of the reference text.

The scheme (chapter 18.1.3, exactly)
------------------------------------
1. Every boundary point carries its point distribution function
   ``dP_i = (|x_{i+1} - x_i| + |x_i - x_{i-1}|) / 2`` (the caller computes it,
   :func:`meshwright.sizing.point_distribution`).
2. Start from the Delaunay triangulation of the boundary points: here the constrained one
   (:mod:`meshwright.tri.cdt`), so no boundary edge is ever lost, with the exterior removed.
3. One *pass* visits every triangle inside the domain:
   (a) the prospective point is its centroid;
   (b) its ``dP_m`` is the mean of the ``dP`` of the triangle's three nodes;
   (c) with ``d_m`` the distances from the point to the nodes, the point is rejected if any
       ``d_m < alpha dP_m`` and accepted otherwise;
   (d) an accepted point gets the interpolated ``dP_m`` as its own ``dP``.
4. Accepted points are inserted by constrained Delaunay insertion and passes repeat until
   one accepts no point.

Practical reading (as in Weatherill & Hassan's implementation): a candidate must also lie
at least ``alpha dP_m`` from every point accepted earlier in the same pass, otherwise the
centroids of neighbouring triangles, each far enough from its own nodes, end up in
clusters.  Both tests are one query here: no vertex of the pass-start triangulation and no
point accepted in this pass lies strictly inside the disk of radius ``alpha dP_m`` around the
candidate.  The disk is searched by a breadth-first walk over the inside triangles that it
reaches, starting from the candidate's own triangle (whose three nodes are the chapter's
``d_m``); accepted points are listed on the triangle they came from.  Deciding a whole pass
on the pass-start triangulation and inserting the accepted points afterwards, in Hilbert
order, gives the same accept/reject decisions as inserting each point at once (the only
vertices added during a pass are the accepted points) with far shorter point location.

An optional size field ``h`` caps ``dP_m`` by ``h(centroid)``; without it the spacing is
the chapter's, interpolated from the boundary alone.  ``alpha`` is the chapter's density
coefficient: :func:`meshwright.triangulate` takes it as ``alpha=`` for
``method="weatherill"`` (``--alpha`` on the command line), default :data:`DEFAULT_ALPHA`.

Termination: accepted points are pairwise at least ``alpha min(dP)`` apart and ``dP`` never
drops below the smallest boundary (or size-field) value, so a bounded domain holds finitely
many of them; ``max_passes`` and ``max_points`` caps raise
:class:`~meshwright.core.errors.MeshingError` all the same.

Array layout: per pass, the inside triangles ``tris`` (nt, 3) int32 and their neighbours
``nbrs`` (nt, 3) int32 (-1 across the domain boundary) of
:meth:`ConstrainedTriangulation.triangles` / ``neighbors``; ``dp`` (rows,) float64 indexed
by vertex id, grown by doubling.
"""

from __future__ import annotations

from typing import Callable

import numpy as np
from numba import njit

from meshwright.core.errors import InputError, MeshingError
from meshwright.core.geom2d import segment_dist2
from meshwright.core.spatial_sort import hilbert_order
from meshwright.sizing.field import as_size_field

__all__ = ["weatherill", "DEFAULT_ALPHA"]

# With alpha = 0.6 the mean edge of a uniform mesh comes out close to dP (measured on discs
# and squares); the centroid of an equilateral triangle of side s is s / sqrt(3) from its
# nodes, so passes stop once triangles have sides below about sqrt(3) alpha dP.
DEFAULT_ALPHA = 0.6


@njit(cache=True)
def _candidates(pts, tris, dp):
    """Centroid ``(nt, 2)`` and interpolated ``dP_m`` ``(nt,)`` of every triangle."""
    nt = tris.shape[0]
    xy = np.empty((nt, 2))
    dpm = np.empty(nt)
    for t in range(nt):
        a = tris[t, 0]
        b = tris[t, 1]
        c = tris[t, 2]
        xy[t, 0] = (pts[a, 0] + pts[b, 0] + pts[c, 0]) / 3.0
        xy[t, 1] = (pts[a, 1] + pts[b, 1] + pts[c, 1]) / 3.0
        dpm[t] = (dp[a] + dp[b] + dp[c]) / 3.0
    return xy, dpm


@njit(cache=True)
def select_spaced(pts, tri, nbr, inside, cand, host, radius):
    """Accept or reject candidates in order; returns (k,) bool.

    Candidate i, lying in triangle slot ``host[i]``, is accepted when no vertex of the
    triangles its disk of radius ``radius[i]`` reaches, and no candidate accepted before it
    that was listed on one of those triangles, lies strictly inside the disk.  (The frontal
    Delaunay method, :mod:`meshwright.tri.frontal_delaunay`, places one point at a time in
    Rebay's order and keeps its spacing inside its own kernel, so this batch test is
    Weatherill's alone.)

    Parameters
    ----------
    pts : (nv, 2) float64
    tri, nbr : (3 cap,) int32
        The kernel's flat triangles and neighbours (:mod:`meshwright.tri._kernel2d`).
    inside : (ntri,) bool
        Slots of finite triangles inside the domain; the search never leaves them.
    cand : (k, 2) float64
    host : (k,) int64
        Inside slot holding each candidate.
    radius : (k,) float64
    """
    nt = inside.shape[0]
    k = cand.shape[0]
    accepted = np.zeros(k, dtype=np.bool_)
    head = np.full(nt, -1, dtype=np.int32)  # first accepted candidate listed on slot t
    nxt = np.full(k, -1, dtype=np.int32)
    stamp = np.full(nt, -1, dtype=np.int32)  # last candidate whose walk visited slot t
    stack = np.empty(nt, dtype=np.int32)
    for i in range(k):
        qx = cand[i, 0]
        qy = cand[i, 1]
        r2 = radius[i] * radius[i]
        ok = True
        top = 1
        stack[0] = host[i]
        stamp[host[i]] = i
        while top > 0 and ok:
            top -= 1
            t = stack[top]
            for m in range(3):
                v = tri[3 * t + m]
                dx = pts[v, 0] - qx
                dy = pts[v, 1] - qy
                if dx * dx + dy * dy < r2:
                    ok = False
            j = head[t]
            while j >= 0 and ok:
                dx = cand[j, 0] - qx
                dy = cand[j, 1] - qy
                if dx * dx + dy * dy < r2:
                    ok = False
                j = nxt[j]
            for m in range(3):
                n = nbr[3 * t + m]
                if not inside[n] or stamp[n] == i:
                    continue
                a = tri[3 * t + (m + 1) % 3]
                b = tri[3 * t + (m + 2) % 3]
                # Only triangles the open disk reaches can hold a point inside it.
                if segment_dist2(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], qx, qy) < r2:
                    stamp[n] = i
                    stack[top] = n
                    top += 1
        if ok:
            accepted[i] = True
            nxt[i] = head[host[i]]
            head[host[i]] = i
    return accepted


def weatherill(
    ct,
    dp,
    alpha: float = DEFAULT_ALPHA,
    *,
    size=None,
    max_passes: int = 200,
    max_points: int | None = None,
    callback: Callable[[int, int, int], None] | None = None,
):
    """Fill a classified constrained triangulation with Weatherill's points, in place.

    Parameters
    ----------
    ct : ConstrainedTriangulation
        From :func:`meshwright.tri.cdt.cdt_build`, exterior removed by ``classify``.
    dp : (nv,) array_like of float64
        Point distribution function ``dP`` of every current vertex (``ct.n_points``
        entries, positive and finite), e.g. :func:`meshwright.sizing.point_distribution`
        of the boundary.
    alpha : float
        Density coefficient: a candidate closer than ``alpha dP_m`` to a node is rejected,
        so smaller values give denser meshes.
    size : number, callable or SizeField, optional
        Caps the interpolated ``dP_m`` of a candidate by ``h(candidate)``.
    max_passes : int
        Cap on the passes over the triangles.
    max_points : int, optional
        Cap on the number of vertices.
    callback : callable, optional
        ``callback(pass_index, accepted, n_points)`` after every pass (progress bars,
        snapshots of the intermediate grids).

    Returns
    -------
    (nv_final,) float64
        ``dP`` of every vertex of the filled triangulation (new nodes carry their
        interpolated values).

    Raises
    ------
    InputError
        ``dp`` of the wrong length or not positive, ``alpha`` not positive.
    MeshingError
        ``max_passes`` passes still accepted points, or ``max_points`` would be exceeded.
    """
    nv = ct.n_points
    d = np.asarray(dp, dtype=np.float64).ravel()
    if d.shape != (nv,):
        raise InputError(f"dp needs one value per vertex ({nv}), got shape {d.shape}")
    bad = np.flatnonzero(~(np.isfinite(d) & (d > 0.0)))
    if len(bad):
        raise InputError(f"dp of vertex {bad[0]} at {ct.points[bad[0]].tolist()} is {d[bad[0]]!r}; it must be positive")
    if not (np.isfinite(alpha) and alpha > 0.0):
        raise InputError(f"alpha must be positive and finite, got {alpha!r}")
    field = None if size is None else as_size_field(size)
    cap = np.iinfo(np.int32).max if max_points is None else int(max_points)
    store = np.empty(max(16, 2 * nv))
    store[:nv] = d
    for p in range(int(max_passes)):
        pts = ct.points
        tris = ct.triangles(True)
        cand, dpm = _candidates(pts, tris, store)
        if field is not None:
            dpm = np.minimum(dpm, field(cand))
        inside = ct.inside_slots()
        host = np.flatnonzero(inside)
        accepted = np.flatnonzero(select_spaced(pts, ct.state.tri, ct.state.nbr, inside, cand, host, alpha * dpm))
        if len(accepted) == 0:
            if callback is not None:
                callback(p, 0, ct.n_points)
            return store[: ct.n_points].copy()
        if ct.n_points + len(accepted) > cap:
            raise MeshingError(
                f"Weatherill pass {p} would add {len(accepted)} points to {ct.n_points}, above "
                f"max_points = {cap}; raise max_points or alpha"
            )
        order = accepted[hilbert_order(cand[accepted])]
        vids = ct.insert_points(cand[order])
        if int(vids.max()) >= len(store):
            grown = np.empty(max(2 * len(store), int(vids.max()) + 1))
            grown[: len(store)] = store
            store = grown
        store[vids] = dpm[order]
        if callback is not None:
            callback(p, len(accepted), ct.n_points)
    raise MeshingError(
        f"Weatherill's scheme still accepted points after max_passes = {max_passes} passes "
        f"({ct.n_points} vertices); raise max_passes or alpha"
    )
