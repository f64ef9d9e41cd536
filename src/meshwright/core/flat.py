r"""Flat-array helpers shared by the ``@njit`` kernels: capacity growth, the ghost sentinel.

Kernels keep their data in flat, preallocated NumPy arrays (``tri[3*t + k]``,
``nbr[3*t + k]``, ...) and a count of used entries.  When a kernel may outgrow its
preallocated bound (points inserted into an existing structure), it calls :func:`grown`
to obtain a larger copy; amortised over the insertions the copying costs O(1) each.

Invariant: ``grown(a, need)`` returns ``a`` itself when it is already large enough, so
callers can write ``a = grown(a, need)`` unconditionally.

``GHOST = -1`` is the vertex id of the symbolic vertex at infinity in connectivity arrays
(ghost triangles close the convex hull; see :mod:`meshwright.tri._kernel2d`).

Tetrahedra (4 slots per tet, ``tet[4*t + k]``) are positively oriented,
``orient3d(v0, v1, v2, v3) > 0`` (v3 on the side of plane v0 v1 v2 that its normal
``(v1 - v0) x (v2 - v0)`` points to), and ``nbr[4*t + k]`` is the tet across the face
opposite vertex k.  ``TET_FACES[k]`` lists the local vertices of that face in the order
whose right-hand normal points *out* of the tet (counter-clockwise seen from outside)::

              v3
             /|\          face 0: v1 v2 v3     face 2: v0 v1 v3
            / | \         face 1: v0 v3 v2     face 3: v0 v2 v1
          v0--|--v2
            \ | /
             \|/
              v1
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["GHOST", "TET_FACES", "grown"]

GHOST = -1

# Outward-oriented faces of a positively oriented tet, by the local vertex they are opposite.
TET_FACES = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]], dtype=np.int64)


@njit(cache=True)
def grown(a, need):
    """Return ``a`` if it holds at least ``need`` entries, else a doubled copy.

    Parameters
    ----------
    a : (m,) array of any dtype
        Flat array whose first entries are in use.
    need : int
        Required length.

    Returns
    -------
    (max(m, need, 2m),) array of ``a.dtype``
        ``a`` itself, or a new array whose first ``m`` entries are those of ``a``; the rest
        are uninitialised.
    """
    m = a.shape[0]
    if need <= m:
        return a
    out = np.empty(max(need, 2 * m), dtype=a.dtype)
    out[:m] = a
    return out
