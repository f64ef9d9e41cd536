"""Distributed 2-D meshing on Dask: parts meshed by the serial code, stitched without matching.

Design (issue 15), after the Delaunay decoupling method (L. Linardakis and N. Chrisochoides,
SIAM J. Sci. Comput. 27(4), 2006, and the graded version, 30(4), 2008) with PCDM's split
messages as the deterministic fallback (A. Chernikov and N. Chrisochoides, ACM TOMS 34(1), 2008):

1. :mod:`~meshwright.distributed.partition` (client): the boundary is discretised once; recursive
   bisection by straight cuts (axis-parallel, oblique where the 60-degree rule needs it)
   balanced by the size-field integral (``kappa * 4 / sqrt(3) * integral(1/h^2)`` predicted
   triangles), several parts per worker, cuts meeting the boundary and each other at >= 60
   degrees and clear of boundary vertices; the cuts' inside pieces are discretised by the
   boundary's 1-D placer and get global ids (the *skeleton*).
2. :mod:`~meshwright.distributed.part` (workers): every part is meshed independently by the
   serial Delaunay refinement with its interface segments as frozen boundary: the splits of
   an interface it needs are made at midpoints, named by their dyadic place on the skeleton
   segment, and reported.  The part's state stays on its worker between rounds.
3. :mod:`~meshwright.distributed.exchange` (client): every split a part made is made by its
   neighbour in the next round, which resumes from its state (``max_rounds``); the split
   points get ids after the skeleton's.
4. :mod:`~meshwright.distributed.numbering`: skeleton ids first, then every part's own points by
   an exclusive prefix sum of the part counts: int64, zero duplicates, no coordinate matching.
5. :mod:`~meshwright.distributed.writer`: one task per part writes its piece with global ids,
   the client writes the skeleton, HDF5 virtual datasets stitching the pieces and the XDMF
   file (meshio and ParaView read it).  The files are byte-identical for any worker count
   (fixed parts, seed).

:mod:`~meshwright.distributed.cluster` resolves the client (existing, address, or a local
cluster of single-threaded processes, configured to leave the cores to the parts) and warms
the Numba cache on every worker;
:mod:`~meshwright.distributed.simulate` replays measured part times on more virtual workers.
The skeleton (cut, discretise the interfaces with global ids, mesh parts, exchange, number by
prefix sums, write pieces) is dimension-free: 3-D would mesh planar interface facets with the
2-D mesher as its interfaces.

Limits: ``method="delaunay"`` only; no region seeds (nor islands); the output directory must be
on a file system the workers share.  Needs the ``distributed`` extra (dask, distributed, h5py).
"""

from meshwright.distributed.cluster import LOCAL_CLUSTER_CONFIG, local_cluster, warm
from meshwright.distributed.mesher import DistributedMesh, decompose, triangulate
from meshwright.distributed.partition import Decomposition
from meshwright.distributed.simulate import simulate_scaling

__all__ = [
    "LOCAL_CLUSTER_CONFIG", "Decomposition", "DistributedMesh", "decompose", "local_cluster", "simulate_scaling",
    "triangulate", "warm",
]
