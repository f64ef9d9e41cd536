"""The arguments of :class:`~meshwright.geometry.domain.Domain`, checked at its door: loops
and chains (a Curve, a sequence of Curves or an (n, 2) vertex array), region rows
``(x, y, marker[, max_area])`` and regional attributes, each named by its index when
malformed.
"""

from __future__ import annotations

import numbers

import numpy as np

from meshwright.core.errors import GeometryError, InputError
from meshwright.geometry.curves import Curve, Polyline

__all__ = ["as_chain", "check_region_attributes", "region_row"]


def as_chain(item, what: str) -> tuple[Curve, ...]:
    """A loop or chain given as a Curve, a sequence of Curves or an (n, 2) vertex array."""
    if isinstance(item, Curve):
        return (item,)
    if isinstance(item, (list, tuple)) and item and all(isinstance(c, Curve) for c in item):
        return tuple(item)
    try:
        arr = np.asarray(item, dtype=np.float64)
    except (TypeError, ValueError):
        arr = None
    if arr is None or arr.ndim != 2 or arr.shape[1] != 2:
        raise InputError(f"{what} must be a Curve, a sequence of Curves or an (n, 2) array")
    return (Polyline(arr, closed=what.startswith(("outer", "hole"))),)


def region_row(r, i: int) -> tuple[float, float, int, float | None]:
    """One region row ``(x, y, marker[, max_area])`` checked entry by entry."""
    if isinstance(r, (str, bytes)) or not hasattr(r, "__len__") or len(r) not in (3, 4):
        raise InputError(f"region {i} must be a row (x, y, marker[, max_area]), got {r!r}")
    for k, name in enumerate(("x", "y", "marker")):
        if isinstance(r[k], (bool, np.bool_)) or not isinstance(r[k], numbers.Real):
            raise InputError(f"region {i} {name} must be a number, got {r[k]!r} ({type(r[k]).__name__})")
    x, y = float(r[0]), float(r[1])
    if not float(r[2]).is_integer():
        raise InputError(f"region {i} marker must be an integer, got {r[2]!r}")
    marker = int(r[2])
    area = None if len(r) == 3 or r[3] is None else r[3]
    if area is not None and (isinstance(area, (bool, np.bool_)) or not isinstance(area, numbers.Real)):
        raise InputError(f"region {i} max_area must be a number or None, got {area!r} ({type(area).__name__})")
    area = None if area is None else float(area)
    if not (np.isfinite(x) and np.isfinite(y)):
        raise GeometryError(f"region {i} seed has non-finite coordinates ({x}, {y})")
    if area is not None and not (np.isfinite(area) and area > 0):
        raise GeometryError(f"region {i} at ({x}, {y}) has max_area {area!r}; use None or > 0")
    return x, y, marker, area


def check_region_attributes(values, regions) -> np.ndarray:
    """(r,) float64 regional attributes, checked one per region (default: the markers)."""
    if values is None:
        return np.array([float(r[2]) for r in regions], dtype=np.float64)
    if isinstance(values, (str, bytes)) or not hasattr(values, "__len__"):
        raise InputError(f"region_attributes must be a sequence of numbers, got {values!r}")
    if len(values) != len(regions):
        raise InputError(f"region_attributes has {len(values)} entries for {len(regions)} regions")
    for i, v in enumerate(values):
        if isinstance(v, (bool, np.bool_)) or not isinstance(v, numbers.Real) or not np.isfinite(v):
            raise InputError(f"region {i} attribute must be a finite number, got {v!r}")
    return np.array([float(v) for v in values], dtype=np.float64)
