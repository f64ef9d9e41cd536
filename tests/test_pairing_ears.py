"""Pairing when an ear is opened by a midpoint split (quad/pairing._open_ears).

The split appends two triangles; the pairing's partner table must grow with them (it was
allocated before the split: a read past its end, an IndexError or a crash in the
matching kernel).  The domain is a sliver void left by an experimental paving run: a
16-node loop along a wing's slot with one flat ear that no diagonal flip can open.
"""

from __future__ import annotations

import numpy as np

from meshwright.quad.pairing import pair_triangles

# The loop runs 14 -> 15 -> 0 -> 1 -> ... -> 13 -> 14 (the blocked edges below).
POINTS = np.array([
    [0.4624597849128855, 0.18269384083239484], [0.4706892392735915, 0.18257190533287135],
    [0.4793888391234906, 0.18218553217157726], [0.4888071042875121, 0.18148458789394006],
    [0.4991305911195601, 0.18074248570442408], [0.5103102738338314, 0.1798716881404403],
    [0.5220594487437982, 0.17899302232541292], [0.5339056661704953, 0.17801227471801948],
    [0.5454143319386069, 0.1770024171254494], [0.5563914390278464, 0.1761041424630004],
    [0.5669653636433406, 0.17519147040020178], [0.5776027440239573, 0.17428371936479656],
    [0.5888617762314668, 0.17320685907390498], [0.6010038412725623, 0.17195182341570575],
    [0.6081530564403195, 0.17566341640113584], [0.4527982182641869, 0.18660286089063105],
])
TRIANGLES = np.array([
    [13, 14, 12], [0, 1, 15], [1, 2, 15], [2, 3, 15], [3, 4, 15], [9, 10, 11], [8, 9, 7],
    [4, 5, 15], [11, 12, 14], [5, 6, 15], [6, 7, 15], [9, 11, 14], [7, 9, 14], [7, 14, 15],
], dtype=np.int32)
LOOP = [14, 15] + list(range(14))
BLOCKED = np.array([[LOOP[i], LOOP[(i + 1) % 16]] for i in range(16)])


def _area2(p, cells):
    """Twice the signed areas of polygons (m, k) by the shoelace formula."""
    x, y = p[cells, 0], p[cells, 1]
    return (x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y).sum(axis=1)


def test_split_ear_pairs_without_reading_past_the_partner_table():
    quads, first, left, tris, _, pts = pair_triangles(POINTS, TRIANGLES, BLOCKED, seed=0)
    # The ear was split: a midpoint and two triangles more than the input.
    assert len(pts) > len(POINTS) and len(tris) > len(TRIANGLES)
    assert np.array_equal(pts[: len(POINTS)], POINTS)
    # Every triangle after the split is in exactly one pair or left over.
    assert len(first) == len(quads)
    assert 2 * len(quads) + len(left) == len(tris)
    assert len(np.unique(left)) == len(left)
    # Quads strictly convex (every corner's cross product > 0) and the pieces tile the
    # loop: their areas add up to the loop's (shoelace, independent of the pairing).
    for q in quads:
        e = pts[np.roll(q, -1)] - pts[q]
        cross = e[:, 0] * np.roll(e[:, 1], -1) - e[:, 1] * np.roll(e[:, 0], -1)
        assert (cross > 0).all(), q
    loop = _area2(POINTS, np.array([LOOP]))[0]
    pieces = _area2(pts, quads).sum() + _area2(pts, tris[left]).sum()
    assert abs(pieces - loop) <= 1e-12 * abs(loop) + 1e-15
