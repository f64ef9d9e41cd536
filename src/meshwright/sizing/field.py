"""Size fields: the target edge length ``h(x)`` every meshing method asks for.

A size field is anything :func:`as_size_field` accepts:

* a positive finite number (uniform spacing);
* a vectorised callable ``h(xy) -> sizes`` with ``xy`` of shape (n, d) float64 and sizes
  of shape (n,) (a scalar result is broadcast);
* an object with ``__call__`` of that signature (a background grid, a
  :func:`meshwright.sizing.boundary.gradation` field, ...).

The dimension d (2 for ``triangulate`` and the quad methods, 3 for ``tetrahedralize``) is
fixed when the field is made (``as_size_field(size, dim=3)``): the field is then called
with (n, d) points only, so a 2-D field handed to a 3-D mesher fails at the door instead of
being evaluated on the wrong columns.

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
    """Validated size function ``h(xy) -> (n,) float64`` in dimension ``dim``.

    Parameters
    ----------
    func : callable
        ``func(xy (n, dim) float64) -> (n,)`` (or a scalar, broadcast).
    constant : float, optional
        Set when the field is uniform, so callers can take fast paths.
    name : str, optional
        Used in error messages and ``repr``.
    dim : int
        2 or 3: the number of columns of the points the field takes.

    Raises
    ------
    InputError
        ``dim`` not 2 or 3.
    """

    def __init__(self, func, constant: float | None = None, name: str | None = None, dim: int = 2):
        self.dim = _check_dim(dim)
        self.func = func
        self.constant = constant
        self.name = name or getattr(func, "__name__", type(func).__name__)

    def __repr__(self) -> str:
        if self.constant is not None:
            return f"SizeField(constant={self.constant})"
        return f"SizeField({self.name})"

    def __call__(self, xy) -> np.ndarray:
        """Sizes at points ``xy`` (n, dim); returns (n,) float64, all positive and finite."""
        p = np.asarray(xy, dtype=np.float64)
        if p.ndim != 2 or p.shape[1] != self.dim:
            raise InputError(f"size field points must have shape (n, {self.dim}), got {p.shape}")
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
        xy : (n, dim) array_like of float64
            Points on the curve.
        tangents : (n, dim) array_like of float64
            Curve tangent at each point; any length (normalised inside), a zero row meaning
            "direction unknown" (the spacing across any stretching is used).

        Returns
        -------
        (n,) float64
            Positive, finite spacings.

        Raises
        ------
        InputError
            ``xy`` and ``tangents`` not both (n, dim), or a non-finite tangent (its index named).
        SizeError
            As for :meth:`__call__`.
        """
        unit_tangents(xy, tangents, self.dim)
        return self(xy)


def _check_dim(dim) -> int:
    if isinstance(dim, bool) or not isinstance(dim, numbers.Integral) or int(dim) not in (2, 3):
        raise InputError(f"dim must be 2 or 3, got {dim!r}")
    return int(dim)


def unit_tangents(xy, tangents, dim: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """Validate tangents against points and normalise them.

    Parameters
    ----------
    xy : (n, dim) array_like of float64
    tangents : (n, dim) array_like of float64
    dim : int
        2 or 3.

    Returns
    -------
    unit : (n, dim) float64
        ``tangents`` scaled to unit length; zero rows stay zero.
    zero : (n,) bool
        Rows that were zero.

    Raises
    ------
    InputError
        Shapes that are not both (n, dim), or a non-finite tangent (its index named).
    """
    p = np.asarray(xy, dtype=np.float64)
    t = np.asarray(tangents, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] != dim or t.shape != p.shape:
        raise InputError(
            f"size field points and tangents must both have shape (n, {dim}), got {p.shape} and {t.shape}"
        )
    bad = np.flatnonzero(~np.isfinite(t).all(axis=1))
    if len(bad):
        raise InputError(f"tangent {bad[0]} at {fmt_point(p[bad[0]])} is not finite: {t[bad[0]].tolist()}")
    # hypot folded over the columns: in 2-D exactly the hypot(tx, ty) of old.
    norm = np.hypot.reduce(t, axis=1)
    zero = norm == 0.0
    unit = t / np.where(zero, 1.0, norm)[:, None]
    return unit, zero


def as_size_field(size, dim: int = 2) -> SizeField:
    """Wrap a number, a vectorised callable or a callable object as a :class:`SizeField`.

    Parameters
    ----------
    size : float, callable or SizeField
        A positive constant, ``h(xy (n, dim) float64) -> (n,)``, or a size field (a
        :class:`~meshwright.sizing.BackgroundGrid` of that dimension, ...).
    dim : int
        2 (default: every 2-D mesher) or 3 (``tetrahedralize``): the points the field takes.

    Returns
    -------
    SizeField
        ``size`` itself when it is already a field of dimension ``dim``; a constant field of
        the other dimension is re-wrapped (a number means the same in 2-D and 3-D).

    Raises
    ------
    SizeError
        For a non-positive or non-finite constant, anything that is neither a number nor
        callable, or a non-constant size field made for the other dimension.
    InputError
        ``dim`` not 2 or 3.
    """
    dim = _check_dim(dim)
    if isinstance(size, SizeField):
        if size.dim == dim:
            return size
        if size.constant is not None:
            return SizeField(None, constant=size.constant, name=size.name, dim=dim)
        raise SizeError(
            f"size field {size.name} takes {size.dim}-D points (n, {size.dim}) but a {dim}-D size is "
            f"needed here (points (n, {dim}))"
        )
    if isinstance(size, numbers.Real) and not isinstance(size, bool):
        h = float(size)
        if not (np.isfinite(h) and h > 0.0):
            raise SizeError(f"constant size must be positive and finite, got {size!r}")
        return SizeField(None, constant=h, name=repr(h), dim=dim)
    if callable(size):
        return SizeField(size, dim=dim)
    raise SizeError(
        f"size must be a positive number or a callable h(xy (n, {dim})) -> (n,), got {type(size).__name__}"
    )


def minimum(*sizes, dim: int = 2) -> SizeField:
    """Pointwise minimum of several size specifications (each as :func:`as_size_field` with ``dim``)."""
    if not sizes:
        raise SizeError("minimum() needs at least one size")
    fields = [as_size_field(s, dim) for s in sizes]
    consts = [f.constant for f in fields]
    if all(c is not None for c in consts):
        return SizeField(None, constant=min(consts), name=repr(min(consts)), dim=dim)
    return SizeField(
        lambda xy: np.min([f(xy) for f in fields], axis=0),
        name="min(" + ", ".join(f.name for f in fields) + ")",
        dim=dim,
    )
