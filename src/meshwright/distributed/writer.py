"""Output of a distributed mesh: one HDF5 piece per part, stitched by virtual datasets, and XDMF.

Sources: the XDMF3 model (xdmf.org, "XDMF Model and Format": a ``Triangle`` topology and an
``XY`` geometry whose data items live in HDF5); HDF5 virtual datasets (The HDF Group, RFC
"Virtual Dataset", HDF5 1.10), which VTK's distributed ``vtkHDFWriter`` also uses to join
pieces.  No mesh bytes pass through the client: each worker writes its own piece, the client
writes only the skeleton and the virtual layouts.

Files, for ``out = DIR/NAME.xdmf``:

* ``DIR/NAME_partNNNNN.h5`` (one per part, written on a worker): ``points`` (q, 2) float64,
  ``point_marker`` (q,) int32, ``cells`` (t, 3) int64 global ids, ``cell_marker`` (t,) int32,
  ``lines`` (l, 2) int64, ``line_marker`` (l,) int32, all with global ids: the part's last
  task writes it once the prefix sums are known (:mod:`meshwright.distributed.part`), into a
  temporary name renamed at the end (a task Dask runs again after a lost worker never leaves
  half a file);
* ``DIR/NAME.h5`` (client): ``skeleton_points`` and ``skeleton_point_marker``, and the virtual
  datasets ``points`` (N, 2), ``point_marker`` (N,), ``cells`` (T, 3), ``cell_marker`` (T,),
  ``lines`` (L, 2), ``line_marker`` (L,) in global-id order (skeleton, then parts in order);
  the sources are named relative to the file, so the directory can move;
* ``DIR/NAME.xdmf``: the triangle grid over ``NAME.h5`` with ``marker`` point and cell data
  (the boundary lines and their markers stay in the HDF5 files, see :func:`read_mesh_arrays`).

Byte-identical output: datasets, virtual ones included, are written without timestamps
(``track_times=False``, ``H5Pset_obj_track_times``), no group is created (groups would carry
times), in part order, with sizes that depend only on the parts; nothing records workers or
times.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

__all__ = ["part_path", "read_mesh_arrays", "write_mesh", "write_part"]

_FIELDS = (
    ("points", 2, "<f8"),
    ("point_marker", 0, "<i4"),
    ("cells", 3, "<i8"),
    ("cell_marker", 0, "<i4"),
    ("lines", 2, "<i8"),
    ("line_marker", 0, "<i4"),
)


def part_path(out: Path, i: int) -> Path:
    """Path of part ``i``'s piece next to ``out`` (``NAME.xdmf``)."""
    return out.with_name(f"{out.stem}_part{i:05d}.h5")


def _dataset(f, name, data, dtype):
    return f.create_dataset(name, data=np.ascontiguousarray(data, dtype=dtype), track_times=False)


def _virtual_dataset(f, name: str, layout, shape, dtype) -> None:
    """``f.create_virtual_dataset`` without modification times, so that reruns give the same bytes."""
    from h5py import h5d, h5s, h5t

    dcpl = layout._get_dcpl(f.filename)
    dcpl.set_fill_value(np.zeros(1, dtype=dtype))
    dcpl.set_obj_track_times(False)
    h5d.create(f.id, name=name.encode(), tid=h5t.py_create(np.dtype(dtype), logical=1),
               space=h5s.create_simple(shape), dcpl=dcpl).close()


def write_part(pm, path: str) -> int:
    """Write one part's piece (module docstring); returns its bytes.

    Parameters
    ----------
    pm : PartMesh
    path : str
        Final name; the data go to ``path.<random>.tmp`` first, renamed when complete.
    """
    import uuid

    import h5py

    tmp = f"{path}.{uuid.uuid4().hex}.tmp"
    with h5py.File(tmp, "w", libver="v110") as f:
        _dataset(f, "points", pm.points.reshape(-1, 2), "<f8")
        _dataset(f, "point_marker", pm.point_markers, "<i4")
        _dataset(f, "cells", pm.triangles.reshape(-1, 3), "<i8")
        _dataset(f, "cell_marker", pm.triangle_markers, "<i4")
        _dataset(f, "lines", pm.lines.reshape(-1, 2), "<i8")
        _dataset(f, "line_marker", pm.line_markers, "<i4")
    os.replace(tmp, path)
    return os.path.getsize(path)


def write_mesh(out: Path, skeleton_points: np.ndarray, skeleton_markers: np.ndarray, pieces) -> list[str]:
    """Write ``NAME.h5`` (skeleton and virtual datasets) and ``NAME.xdmf`` (module docstring).

    Parameters
    ----------
    out : Path
        ``NAME.xdmf``.
    skeleton_points : (n, 2) float64
    skeleton_markers : (n,) int32
    pieces : sequence of PartSummary
        In part order (``path``, ``n_points``, ``n_triangles``, ``n_lines``).

    Returns
    -------
    list of str
        The two paths written.
    """
    import h5py

    h5 = out.with_suffix(".h5")
    sizes = {
        "points": [len(skeleton_points)] + [p.n_points for p in pieces],
        "cells": [0] + [p.n_triangles for p in pieces],
        "lines": [0] + [p.n_lines for p in pieces],
    }
    sizes["point_marker"], sizes["cell_marker"], sizes["line_marker"] = sizes["points"], sizes["cells"], sizes["lines"]
    with h5py.File(h5, "w", libver="v110") as f:
        _dataset(f, "skeleton_points", skeleton_points, "<f8")
        _dataset(f, "skeleton_point_marker", skeleton_markers, "<i4")
        for name, width, dtype in _FIELDS:
            n = sizes[name]
            shape = (sum(n), width) if width else (sum(n),)
            layout = h5py.VirtualLayout(shape=shape, dtype=dtype)
            start = 0
            for k, count in enumerate(n):
                if count == 0:
                    continue
                src_shape = (count, width) if width else (count,)
                if k == 0:
                    src = h5py.VirtualSource(".", "skeleton_" + name, shape=src_shape)
                else:
                    src = h5py.VirtualSource(Path(pieces[k - 1].path).name, name, shape=src_shape)
                layout[start : start + count] = src
                start += count
            _virtual_dataset(f, name, layout, shape, dtype)
    n_pts, n_cells = sum(sizes["points"]), sum(sizes["cells"])
    ref = h5.name
    xml = f"""<?xml version="1.0"?>
<Xdmf Version="3.0">
  <Domain>
    <Grid Name="meshwright" GridType="Uniform">
      <Topology TopologyType="Triangle" NumberOfElements="{n_cells}">
        <DataItem DataType="Int" Precision="8" Dimensions="{n_cells} 3" Format="HDF">{ref}:/cells</DataItem>
      </Topology>
      <Geometry GeometryType="XY">
        <DataItem DataType="Float" Precision="8" Dimensions="{n_pts} 2" Format="HDF">{ref}:/points</DataItem>
      </Geometry>
      <Attribute Name="marker" AttributeType="Scalar" Center="Node">
        <DataItem DataType="Int" Precision="4" Dimensions="{n_pts}" Format="HDF">{ref}:/point_marker</DataItem>
      </Attribute>
      <Attribute Name="marker" AttributeType="Scalar" Center="Cell">
        <DataItem DataType="Int" Precision="4" Dimensions="{n_cells}" Format="HDF">{ref}:/cell_marker</DataItem>
      </Attribute>
    </Grid>
  </Domain>
</Xdmf>
"""
    out.write_text(xml)
    return [str(out), str(h5)]


def read_mesh_arrays(out: Path) -> dict:
    """Every dataset of ``NAME.h5`` as NumPy arrays (through the virtual datasets).

    Returns
    -------
    dict
        ``points`` (N, 2) float64, ``point_marker`` (N,) int32, ``cells`` (T, 3) int64,
        ``cell_marker`` (T,) int32, ``lines`` (L, 2) int64, ``line_marker`` (L,) int32.
    """
    import h5py

    # Sources are named relative to the virtual file: open it from its own directory's view.
    with h5py.File(Path(out).with_suffix(".h5"), "r") as f:
        return {name: f[name][()] for name, _, _ in _FIELDS}
