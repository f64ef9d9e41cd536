"""Chord refinement's boundary midpoints from the lines' curve parameters
(``chord_split(..., line_params=...)``, as paving passes its discretisation's
``segment_params``).  The oracles are plain trigonometry on the unit circle."""

from __future__ import annotations

import math

import numpy as np
import pytest

from meshwright.core.errors import InputError
from meshwright.geometry import circle
from meshwright.quad.chords import chord_split
from meshwright.quad.mesher import QuadFill


def _fan(angles):
    """Triangles (centre, rim i, rim i + 1) under unit-circle rim nodes at ``angles``
    (increasing, radians); the rim sides are the lines, on curve 0."""
    rim = np.column_stack([np.cos(angles), np.sin(angles)])
    xy = np.vstack([[0.0, 0.0], rim])
    k = len(angles)
    tris = np.column_stack([np.zeros(k - 1), np.arange(1, k), np.arange(2, k + 1)]).astype(np.int32)
    lines = np.column_stack([np.arange(1, k), np.arange(2, k + 1)]).astype(np.int32)
    return QuadFill(xy, np.zeros((0, 4), np.int32), tris, lines, np.ones(k - 1, np.int32), np.zeros(k - 1, np.int32))


def test_split_lines_take_the_arc_midpoint_of_their_parameters():
    angles = np.array([0.1, 0.35, 0.9, 1.2])
    fill = _fan(angles)
    params = np.column_stack([angles[:-1], angles[1:]])
    out = chord_split(fill, circle(), 100, line_params=params)
    assert len(out.triangles) == 0 and len(out.quads) == 3 * len(fill.triangles)
    # Every line is split: its new node is the second end of its first half.
    assert len(out.lines) == 2 * len(fill.lines)
    mids = out.points[out.lines[0::2, 1]]
    half = 0.5 * (angles[:-1] + angles[1:])
    for (x, y), t in zip(mids.tolist(), half.tolist()):
        assert x == pytest.approx(math.cos(t), abs=1e-14)
        assert y == pytest.approx(math.sin(t), abs=1e-14)
    # The same cells and lines as the projecting route, and the same points up to its
    # search tolerance.
    ref = chord_split(fill, circle(), 100)
    assert np.array_equal(ref.quads, out.quads) and np.array_equal(ref.lines, out.lines)
    assert np.abs(ref.points - out.points).max() < 1e-6


def test_line_params_are_checked_at_the_door():
    fill = _fan(np.array([0.0, 0.5, 1.0]))
    for bad in (np.zeros((1, 2)), np.zeros((2, 3)), np.array([[0.0, 0.5], [0.5, np.nan]])):
        with pytest.raises(InputError, match="line_params"):
            chord_split(fill, circle(), 100, line_params=bad)
