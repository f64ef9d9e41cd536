"""Global numbering without coordinate matching: skeleton ids first, then prefix sums of parts.

Source: the global-id scheme of pre-discretised interfaces (L. Linardakis and N. Chrisochoides,
"Delaunay decoupling method for parallel guaranteed quality planar mesh refinement", SIAM J.
Sci. Comput. 27(4), 2006): interface and boundary vertices are numbered once, on the client,
before any part is meshed, so parts never compare coordinates (the float matching that fails
in ParMmg, MmgTools/ParMmg#36).

Layout: global vertex ids are int64.  The skeleton's ``n_s`` points (those of the
decomposition, then the interface split points of the exchange rounds,
:mod:`meshwright.distributed.exchange`) take ids ``[0, n_s)``; part ``i``'s own ``q_i``
points take ``[o_i, o_i + q_i)`` with ``o_i = n_s + sum_{j < i} q_j`` (an exclusive prefix sum
in part order, so ids depend on the parts, never on the workers).  Zero duplicate nodes holds
by construction: each skeleton point has one id, and own points belong to one part.
"""

from __future__ import annotations

import numpy as np

__all__ = ["part_offsets"]


def part_offsets(n_skeleton: int, counts) -> np.ndarray:
    """First global id of each part's own points.

    Parameters
    ----------
    n_skeleton : int
    counts : (p,) int
        Own points per part, in part order.

    Returns
    -------
    (p,) int64
        ``n_skeleton`` plus the exclusive prefix sum of ``counts``.
    """
    c = np.asarray(counts, dtype=np.int64).ravel()
    return int(n_skeleton) + np.concatenate([[0], np.cumsum(c)[:-1]]).astype(np.int64)

