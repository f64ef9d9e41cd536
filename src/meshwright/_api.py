"""Dimension dispatch of the public Delaunay entry point ``meshwright.delaunay``.

``tri`` (2-D) and ``tet`` (3-D) are siblings that do not import each other; this module sits
above both and sends ``(n, 2)`` input to :func:`meshwright.tri.triangulation.delaunay` and
``(n, 3)`` input to :func:`meshwright.tet.tetrahedralization.delaunay3d`.  Both dimensions
offer the same algorithms (``DELAUNAY_ALGORITHMS``: Bowyer, Watson) and the same keywords.
``tet`` is imported on the first 3-D call only: a 2-D user never loads it.
"""

from __future__ import annotations

import numpy as np

from typing import TYPE_CHECKING

from meshwright.core.errors import InputError
from meshwright.core.hugepages import small_pages
from meshwright.tri import DELAUNAY_ALGORITHMS, Triangulation
from meshwright.tri import delaunay as delaunay2d

if TYPE_CHECKING:
    from meshwright.tet import Tetrahedralization

__all__ = ["delaunay"]


def delaunay(points, algorithm: str = "bowyer", duplicates: str = "merge", seed=0, superstructure: str = "ghost") -> Triangulation | Tetrahedralization:
    """Delaunay triangulation (2-D) or tetrahedralization (3-D) of a point set (chapter 18.1).

    Parameters
    ----------
    points : (n, 2) or (n, 3) array_like of float64
        Finite points: at least three not collinear (2-D), four not coplanar (3-D).
    algorithm : {"bowyer", "watson"}
        Insertion algorithm (``DELAUNAY_ALGORITHMS``); both give the identical result.
    duplicates : {"merge", "reject"}
        Merge coincident points into one vertex (``index_map``) or raise
        :class:`~meshwright.core.errors.DuplicatePointError` naming them.
    seed : int or numpy.random.Generator
        Randomness of the insertion order (BRIO) and of the point-location walk.
    superstructure : {"ghost", "box"}
        3-D only: symbolic vertex at infinity (the convex hull's tetrahedralization) or the
        chapter's eight-point box, whose attached hull tets are removed at the end
        (:mod:`meshwright.tet.tetrahedralization`).  2-D always uses the vertex at infinity.

    Returns
    -------
    Triangulation or Tetrahedralization
        By the number of columns of ``points``.

    Raises
    ------
    InputError
        A shape other than (n, 2) or (n, 3), non-numeric, NaN or infinite coordinates (the
        message names the first bad point), an unknown option.
    DegenerateInputError
        Too few points, or all collinear (2-D) / coplanar (3-D).
    DuplicatePointError
        Coincident points with ``duplicates="reject"``.
    """
    if algorithm not in DELAUNAY_ALGORITHMS:
        raise InputError(f"unknown algorithm {algorithm!r}; choose from {sorted(DELAUNAY_ALGORITHMS)}")
    if superstructure != "ghost":
        from meshwright.tet import SUPERSTRUCTURES

        if superstructure not in SUPERSTRUCTURES:
            raise InputError(f"superstructure must be one of {SUPERSTRUCTURES}, got {superstructure!r}")
    try:
        shape = np.shape(points)
    except ValueError as exc:
        raise InputError(f"points must be an (n, 2) or (n, 3) array of numbers: {exc}") from exc
    if len(shape) != 2 or shape[1] not in (2, 3):
        raise InputError(f"points must have shape (n, 2) or (n, 3), got {shape}")
    if shape[1] == 3:
        from meshwright.tet import delaunay3d

        with small_pages():  # no huge-page compaction stalls on the large arrays (core/hugepages.py)
            return delaunay3d(points, algorithm=algorithm, duplicates=duplicates, seed=seed, superstructure=superstructure)
    if superstructure != "ghost":
        raise InputError("superstructure='box' is offered for 3-D points only; 2-D uses the vertex at infinity")
    with small_pages():
        return delaunay2d(points, algorithm=algorithm, duplicates=duplicates, seed=seed)
