"""Size fields: the target edge length ``h(x)`` every meshing method asks for.

A size field is anything :func:`as_size_field` accepts:

* a positive finite number (uniform spacing);
* a vectorised callable ``h(xy) -> sizes`` with ``xy`` of shape (n, 2) float64 and sizes
  of shape (n,) (a scalar result is broadcast);
* an object with ``__call__`` of that signature (a background grid, a
  :func:`meshwright.sizing.boundary.gradation` field, ...).

It is wrapped in a :class:`SizeField` whose ``__call__`` validates every answer, so a bad
user function fails with a :class:`~meshwright.core.errors.SizeError` naming the point
where it went wrong instead of corrupting a mesh.  The "node spacing" of the background
grid in the advancing-front method (chapter 18.2 of the reference text) is such a field.
"""

from __future__ import annotations

import numbers

import numpy as np

from meshwright.core.errors import InputError, SizeError, fmt_point

__all__ = ["SizeField", "as_size_field", "minimum"]


class SizeField:
    """Validated size function ``h(xy) -> (n,) float64``.

    Parameters
    ----------
    func : callable
        ``func(xy (n, 2) float64) -> (n,)`` (or a scalar, broadcast).
    constant : float, optional
        Set when the field is uniform, so callers can take fast paths.
    name : str, optional
        Used in error messages and ``repr``.
    """

    def __init__(self, func, constant: float | None = None, name: str | None = None):
        self.func = func
        self.constant = constant
        self.name = name or getattr(func, "__name__", type(func).__name__)

    def __repr__(self) -> str:
        if self.constant is not None:
            return f"SizeField(constant={self.constant})"
        return f"SizeField({self.name})"

    def __call__(self, xy) -> np.ndarray:
        """Sizes at points ``xy`` (n, 2); returns (n,) float64, all positive and finite."""
        p = np.asarray(xy, dtype=np.float64)
        if p.ndim != 2 or p.shape[1] != 2:
            raise InputError(f"size field points must have shape (n, 2), got {p.shape}")
        if self.constant is not None:
            return np.full(len(p), self.constant)
        h = np.asarray(self.func(p), dtype=np.float64)
        if h.ndim == 0:
            h = np.full(len(p), float(h))
        if h.shape != (len(p),):
            raise SizeError(
                f"size field {self.name} returned shape {h.shape} for {len(p)} points; "
                f"expected ({len(p)},)"
            )
        bad = np.flatnonzero(~(np.isfinite(h) & (h > 0.0)))
        if len(bad):
            i = bad[0]
            raise SizeError(
                f"size field {self.name} gives h = {float(h[i])!r} at {fmt_point(p[i])}; "
                f"sizes must be positive and finite ({len(bad)} bad value(s))"
            )
        return h

    def along(self, xy, tangents) -> np.ndarray:
        """Spacing wanted along a curve through ``xy`` with the given tangents.

        An isotropic field asks for the same spacing in every direction, so this default
        ignores the tangents and returns ``self(xy)``; direction-aware fields (a stretched
        :class:`~meshwright.sizing.BackgroundGrid`) override it.  Boundary discretisation
        calls this, so a curve running along a stretching direction gets longer segments.

        Parameters
        ----------
        xy : (n, 2) array_like of float64
            Points on the curve.
        tangents : (n, 2) array_like of float64
            Curve tangent at each point; any length (normalised inside), a zero row meaning
            "direction unknown" (the spacing across any stretching is used).

        Returns
        -------
        (n,) float64
            Positive, finite spacings.

        Raises
        ------
        InputError
            ``xy`` and ``tangents`` not both (n, 2), or a non-finite tangent (its index named).
        SizeError
            As for :meth:`__call__`.
        """
        unit_tangents(xy, tangents)
        return self(xy)


def unit_tangents(xy, tangents) -> tuple[np.ndarray, np.ndarray]:
    """Validate tangents against points and normalise them.

    Parameters
    ----------
    xy : (n, 2) array_like of float64
    tangents : (n, 2) array_like of float64

    Returns
    -------
    unit : (n, 2) float64
        ``tangents`` scaled to unit length; zero rows stay zero.
    zero : (n,) bool
        Rows that were zero.

    Raises
    ------
    InputError
        Shapes that are not both (n, 2), or a non-finite tangent (its index named).
    """
    p = np.asarray(xy, dtype=np.float64)
    t = np.asarray(tangents, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] != 2 or t.shape != p.shape:
        raise InputError(
            f"size field points and tangents must both have shape (n, 2), got {p.shape} and {t.shape}"
        )
    bad = np.flatnonzero(~np.isfinite(t).all(axis=1))
    if len(bad):
        raise InputError(f"tangent {bad[0]} at {fmt_point(p[bad[0]])} is not finite: {t[bad[0]].tolist()}")
    norm = np.hypot(t[:, 0], t[:, 1])
    zero = norm == 0.0
    unit = t / np.where(zero, 1.0, norm)[:, None]
    return unit, zero


def as_size_field(size) -> SizeField:
    """Wrap a number, a vectorised callable or a callable object as a :class:`SizeField`.

    Raises
    ------
    SizeError
        For a non-positive or non-finite constant, or anything that is neither a number
        nor callable.
    """
    if isinstance(size, SizeField):
        return size
    if isinstance(size, numbers.Real) and not isinstance(size, bool):
        h = float(size)
        if not (np.isfinite(h) and h > 0.0):
            raise SizeError(f"constant size must be positive and finite, got {size!r}")
        return SizeField(None, constant=h, name=repr(h))
    if callable(size):
        return SizeField(size)
    raise SizeError(
        f"size must be a positive number or a callable h(xy (n, 2)) -> (n,), got {type(size).__name__}"
    )


def minimum(*sizes) -> SizeField:
    """Pointwise minimum of several size specifications (each as :func:`as_size_field`)."""
    if not sizes:
        raise SizeError("minimum() needs at least one size")
    fields = [as_size_field(s) for s in sizes]
    consts = [f.constant for f in fields]
    if all(c is not None for c in consts):
        return SizeField(None, constant=min(consts), name=repr(min(consts)))
    return SizeField(
        lambda xy: np.min([f(xy) for f in fields], axis=0),
        name="min(" + ", ".join(f.name for f in fields) + ")",
    )
