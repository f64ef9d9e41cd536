"""Built-in closed surfaces by name, for :func:`meshwright.tetrahedralize` and the CLI.

The chapter's 3-D examples (18.4): a sphere, a box with a spherical cavity, and a wing of the
NACA 0012 section in a box far field (Figure 18.4.1).  The wing's caps are a 2-D mesh of the
section, so this module sits in the tet layer, above :mod:`meshwright.tri`.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from meshwright.core.errors import InputError
from meshwright.geometry import Surface, box, extrude, far_field, naca, sphere

__all__ = ["BUILTIN_SURFACES", "builtin_surface", "naca_wing", "box_cavity"]


def naca_wing(span: float = 1.0, chord_size: float = 0.1, far: float = 1.0) -> Surface:
    """NACA 0012 wing (chord 1, sharp trailing edge) of the given span in a box far field.

    The section is meshed by :func:`meshwright.triangulate` at spacing ``chord_size`` and
    extruded along z in layers of that spacing; the far-field box lies ``far`` chords away
    on every side.  Markers: wing 11 (root cap), 12 (tip cap), 13 (skin); box 1..6.  The
    sharp trailing edge is a 16-degree wedge, an acute input angle: tets there finer than
    the surface are exempt from the radius-edge bound (:mod:`meshwright.tet.mesher`).  The
    blunt section (0.25 % thick base) draws the refinement down to its thickness along the
    span: 4x the tets and a minute, measured.
    """
    from meshwright.tri import triangulate

    section = triangulate(naca("0012", closed_te=True), size=chord_size)
    layers = max(1, int(round(span / chord_size)))
    wing = extrude(section, span, z0=-0.5 * span, layers=layers, markers=(11, 12, 13))
    return far_field(wing, (-far, -far, -0.5 * span - far), (1.0 + far, far, 0.5 * span + far))


def box_cavity(level: int = 2) -> Surface:
    """The cube [-1, 1]^3 minus the ball of radius 0.5 (box markers 1..6, sphere 7)."""
    ball = sphere(0.5, level=level)
    ball = Surface(ball.points, ball.triangles, markers=np.full(len(ball.triangles), 7))
    return far_field(ball, (-1.0, -1.0, -1.0), (1.0, 1.0, 1.0))


BUILTIN_SURFACES: dict[str, Callable[[], Surface]] = {
    "sphere": lambda: sphere(1.0, level=3),
    "box": lambda: box(),
    "box-cavity": box_cavity,
    "naca-wing": naca_wing,
}


def builtin_surface(name: str) -> Surface:
    """The built-in surface ``name`` (a key of ``BUILTIN_SURFACES``)."""
    if name not in BUILTIN_SURFACES:
        raise InputError(f"unknown built-in surface {name!r}; choose from {sorted(BUILTIN_SURFACES)} or give a file")
    return BUILTIN_SURFACES[name]()
