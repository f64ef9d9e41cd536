"""What :func:`meshwright.tri.mesher.triangulate` does to a method's mesh afterwards: the
regions' markers and attributes, the relaxation (:mod:`meshwright.tri.relax`) and the
chapter's smoothing (:mod:`meshwright.tri.smoothing`) with sliding boundary nodes; and the
checks of ``relax`` against the bounds asked for.

Array layout: as :class:`~meshwright.core.mesh.Mesh` (points (n, 2) float64, triangles
(m, 3) int32 counter-clockwise, lines (k, 2) int32).
"""

from __future__ import annotations

import numpy as np

from meshwright.core.errors import InputError
from meshwright.core.mesh import Mesh
from meshwright.core.predicates import orient2d_batch
from meshwright.core.validate_input import check_flag
from meshwright.geometry.curves import Line, Polyline
from meshwright.geometry.domain import Discretization, Domain
from meshwright.tri.cdt import ConstrainedTriangulation
from meshwright.tri.smoothing import smooth as smooth_points


def region_data(mesh: Mesh, dom: Domain, disc: Discretization) -> Mesh:
    """Replace the region numbers of :func:`_regions` by the regions' markers and, when some
    region's attribute is not its marker, add the attributes as
    ``cell_data["region_attribute"]`` (0 outside every region, as Triangle; 0 on the lines
    too, since formats such as Gmsh's need data on every cell block).  Attributes equal to
    the markers add nothing, so such meshes keep the marker alone."""
    if not len(disc.regions):
        return mesh
    region = mesh.cell_data["marker"]["triangle"]
    cell_data = dict(mesh.cell_data)
    markers = np.concatenate([[0], disc.regions[:, 2]]).astype(np.int32)
    cell_data["marker"] = {**mesh.cell_data["marker"], "triangle": markers[region]}
    if np.array_equal(dom.region_attributes, disc.regions[:, 2]):
        return Mesh(mesh.points, mesh.cells, point_data=mesh.point_data, cell_data=cell_data)
    cell_data["region_attribute"] = {
        "triangle": np.concatenate([[0.0], dom.region_attributes])[region],
        "line": np.zeros(len(mesh.cells["line"])),
    }
    return Mesh(mesh.points, mesh.cells, point_data=mesh.point_data, cell_data=cell_data)


def _polyline_corners(points: np.ndarray, edges: np.ndarray, curve: np.ndarray, domain: Domain) -> np.ndarray:
    """(n,) bool: nodes where a straight curve (a Polyline's vertex) turns; exact test."""
    straight = np.array([isinstance(c, (Line, Polyline)) for c in domain.curves], dtype=bool)
    e = edges[straight[curve]]
    nxt = np.full(len(points), -1)
    prv = np.full(len(points), -1)
    nxt[e[:, 0]] = e[:, 1]
    prv[e[:, 1]] = e[:, 0]
    out = np.zeros(len(points), dtype=bool)
    mid = np.flatnonzero((nxt >= 0) & (prv >= 0))
    out[mid] = orient2d_batch(points, np.column_stack([prv[mid], mid, nxt[mid]])) != 0.0
    return out


def input_nodes(mesh: Mesh, ct: ConstrainedTriangulation, domain: Domain, disc: Discretization) -> np.ndarray:
    """(n,) bool: the mesh nodes that are the domain's own interior points (never moved)."""
    out = np.zeros(mesh.n_points, dtype=bool)
    npts = len(domain.points)
    if npts:
        used, newid = _renumbering(ct)
        inner = ct.index_map[len(disc.points) - npts :]
        out[newid[inner[used[inner]]]] = True
    return out


def _renumbering(ct: ConstrainedTriangulation) -> tuple[np.ndarray, np.ndarray]:
    """The vertices ``ct.to_mesh`` keeps, (n,) bool, and their new numbers, (n,) int64."""
    used = np.zeros(ct.n_points, dtype=bool)
    used[ct.triangles(True).ravel()] = True
    return used, np.cumsum(used) - 1


def smooth_mesh(mesh: Mesh, ct: ConstrainedTriangulation, domain: Domain, disc: Discretization, passes: int) -> Mesh:
    """Spring-analogy smoothing of ``mesh`` (made by ``ct.to_mesh``) with sliding boundary nodes."""
    used, newid = _renumbering(ct)
    edges, ids = ct.segments()
    keep = used[edges[:, 0]] & used[edges[:, 1]]
    edges, curve = newid[edges[keep]], disc.segment_curve[ids[keep]]
    n = mesh.n_points
    lo = np.full(n, np.iinfo(np.int64).max)
    hi = np.full(n, -1)
    np.minimum.at(lo, edges.ravel(), np.repeat(curve, 2))
    np.maximum.at(hi, edges.ravel(), np.repeat(curve, 2))
    fixed = (hi >= 0) & (lo != hi)  # where two curves meet: a corner of the true boundary
    fixed |= _polyline_corners(mesh.points, edges, curve, domain)
    fixed |= input_nodes(mesh, ct, domain, disc)
    vcurve = np.where(hi >= 0, hi, 0)

    def project(nodes, xy):
        return domain.project(vcurve[nodes], xy)[1]

    xy = smooth_points(mesh.points, mesh.cells["triangle"], edges, passes=passes, fixed=fixed, project=project)
    return Mesh(xy, mesh.cells, point_data=mesh.point_data, cell_data=mesh.cell_data)



def relax_flag(relax, m, angle: float, max_area, conforming: bool) -> bool | None:
    """``relax`` checked against the bounds asked for: False where the default leaves the
    mesh as made, None where it relaxes unless the domain refuses it (stretched, regional
    area bounds: known after the discretisation), True asked for."""
    if relax is not None:
        relax = check_flag(relax, "relax")
    bound = ("min_angle" if angle > 0.0 else "max_area" if max_area is not None
             else "conforming" if conforming else None)
    if relax and bound:
        raise InputError(f"relax=True may break the {bound} guarantee (its swaps and moves do not keep it); "
                         "call it without one of the two")
    if relax is None:
        return None if m.relaxes and bound is None else False
    return relax


def relax_domain(relax: bool | None, stretched: bool, disc: Discretization) -> bool:
    """``relax`` (from :func:`relax_flag`) against what the domain asks for: a stretched
    background or a region's area bound refuse True and turn the default off."""
    why = ("a stretched background grid" if stretched
           else "a region with an area bound" if (disc.regions[:, 3] > 0).any() else None)
    if relax and why:
        raise InputError(f"relax=True would break what {why} asks for (its swaps and moves are isotropic and "
                         "unbounded); call it with relax=False or None")
    return bool(relax is not False and why is None)
