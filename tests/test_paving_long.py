"""The long-loop chord closure (:func:`meshwright.quad._paving_close.close_loop` above
``LONG_LOOP`` nodes, kernel :mod:`meshwright.quad._paving_long`) on thin strips: checked
by plain NumPy cross products and shoelace areas, no meshwright geometry code."""

import numpy as np
import pytest

from meshwright.quad._paving_close import LONG_LOOP, close_loop


def _strip(n_side, length, width, bend):
    """A thin strip, counter-clockwise: ``n_side`` nodes along the bottom and back along
    the top (2 n_side nodes), bent by ``bend`` times a sine along its length."""
    x = np.linspace(0.0, length, n_side)
    y = bend * np.sin(2.0 * np.pi * x / length)
    bottom = np.column_stack([x, y])
    top = np.column_stack([x[::-1], y[::-1] + width])
    return np.vstack([bottom, top])


def _area(p):
    return 0.5 * float(np.sum(p[:, 0] * np.roll(p[:, 1], -1) - np.roll(p[:, 0], -1) * p[:, 1]))


@pytest.mark.parametrize("n_side, width, bend", [(400, 0.8, 0.0), (1500, 1.2, 20.0), (3001, 0.5, 5.0)])
def test_long_thin_strip_closes_all_quad(n_side, width, bend):
    xy = _strip(n_side, float(n_side - 1), width, bend)
    loop = np.arange(len(xy), dtype=np.int64)
    assert len(loop) > LONG_LOOP and len(loop) % 2 == 0
    got = close_loop(xy, loop, lambda p: np.ones(len(p)), np.zeros(0, np.int64), np.zeros(0, np.int64), 4 * len(loop))
    assert got is not None
    extra, quads, open_parts = got
    assert open_parts == []
    pts = np.vstack([xy, extra])
    q = pts[quads]
    # Every corner strictly convex (counter-clockwise), in floating point with a margin.
    e_in = q - np.roll(q, 1, axis=1)
    e_out = np.roll(q, -1, axis=1) - q
    cross = e_in[..., 0] * e_out[..., 1] - e_in[..., 1] * e_out[..., 0]
    assert (cross > 0.0).all()
    # The quads tile the strip: areas add up, every boundary node is used.
    d1, d2 = q[:, 2] - q[:, 0], q[:, 3] - q[:, 1]
    total = 0.5 * float(np.sum(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]))
    assert total == pytest.approx(_area(xy), rel=1e-9)
    assert np.isin(loop, quads).all()
    # Each interior edge is shared by exactly two quads, each boundary edge by one.
    e = np.sort(np.stack([quads, np.roll(quads, -1, axis=1)], axis=-1).reshape(-1, 2), axis=1)
    _, count = np.unique(e, axis=0, return_counts=True)
    assert set(count.tolist()) <= {1, 2}
    assert int((count == 1).sum()) == len(loop)


def test_long_loop_that_cannot_close_returns_none():
    # An odd loop never splits into even parts: no closure, nothing half done.
    xy = _strip(301, 300.0, 0.8, 0.0)[:-1]
    loop = np.arange(len(xy), dtype=np.int64)
    assert len(loop) % 2 == 1
    got = close_loop(xy, loop, lambda p: np.ones(len(p)), np.zeros(0, np.int64), np.zeros(0, np.int64), 4 * len(loop))
    assert got is None


def _polyline(corners):
    """Closed polygon through ``corners`` with nodes one unit apart on every side."""
    out = []
    for a, b in zip(corners, corners[1:] + corners[:1]):
        a, b = np.asarray(a, float), np.asarray(b, float)
        k = max(1, int(round(np.hypot(*(b - a)))))
        out.append(a + (b - a) * (np.arange(k)[:, None] / k))
    return np.vstack(out)


def test_long_loop_closes_in_part_and_leaves_the_thick_block_open():
    # A strip 0.8 wide ending in a block 40 wide: chords close the strip; no chord reaches
    # across the block, which comes back open (region on its left) for the void fill.
    xy = _polyline([(0, 0), (300, 0), (300, -20), (340, -20), (340, 21), (300, 21), (300, 1), (0, 1)])
    xy[:, 1] = np.where(xy[:, 1] == 1, 0.8, xy[:, 1])
    if len(xy) % 2:
        xy = np.vstack([xy, 0.5 * (xy[-1] + xy[0])])
    loop = np.arange(len(xy), dtype=np.int64)
    none = np.zeros(0, np.int64)
    assert close_loop(xy, loop, lambda p: np.ones(len(p)), none, none, 4 * len(loop)) is None
    got = close_loop(xy, loop, lambda p: np.ones(len(p)), none, none, 4 * len(loop), partial=True)
    assert got is not None
    extra, quads, open_parts = got
    pts = np.vstack([xy, extra])
    assert len(quads) and open_parts
    q = pts[quads]
    e_in = q - np.roll(q, 1, axis=1)
    e_out = np.roll(q, -1, axis=1) - q
    assert (e_in[..., 0] * e_out[..., 1] - e_in[..., 1] * e_out[..., 0] > 0.0).all()
    d1, d2 = q[:, 2] - q[:, 0], q[:, 3] - q[:, 1]
    closed = 0.5 * float(np.sum(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]))
    left = [_area(pts[g]) for g in open_parts]
    assert min(left) > 0.0
    # The quads and the open parts tile the loop's region; the block is among the open.
    assert closed + sum(left) == pytest.approx(_area(xy), rel=1e-9)
    assert max(left) > 0.5 * 40 * 41
