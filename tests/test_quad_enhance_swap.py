"""The enhancement's diagonal swapping (quad/_enhance_kernel.py ``_diagonal_swap``: cached
scaled Jacobians, early-exit bounds, sides refused once) against a plain Python pass that
tests every side of every quad in full, with ``math`` sines and rational convexity."""

import math
from fractions import Fraction

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from meshwright.quad import _enhance_kernel as ek
from meshwright.quad._pairing_kernel import FLAT

GAIN = 0.02


def _sine(xy, p, q, r):
    ux, uy = xy[r][0] - xy[q][0], xy[r][1] - xy[q][1]
    wx, wy = xy[p][0] - xy[q][0], xy[p][1] - xy[q][1]
    lu, lw = math.sqrt(ux * ux + uy * uy), math.sqrt(wx * wx + wy * wy)
    return (ux * wy - uy * wx) / (lu * lw) if lu * lw > 0 else 0.0


def _sj(xy, quad):
    return min([1.0] + [_sine(xy, quad[k - 1], quad[k], quad[(k + 1) % 4]) for k in range(4)])


def _convex(xy, quad):
    if len(set(quad)) < 4:
        return False
    for k in range(4):
        (ax, ay), (bx, by), (cx, cy) = ([Fraction(float(t)) for t in xy[v]] for v in (quad[k - 1], quad[k], quad[(k + 1) % 4]))
        if (ax - cx) * (by - cy) - (ay - cy) * (bx - cx) <= 0:
            return False
    return True


def _flat(xy, bnd, quad):
    for k in range(4):
        p, q, r = quad[k - 1], quad[k], quad[(k + 1) % 4]
        if bnd[p] and bnd[q] and bnd[r]:
            ux, uy = xy[r][0] - xy[q][0], xy[r][1] - xy[q][1]
            wx, wy = xy[p][0] - xy[q][0], xy[p][1] - xy[q][1]
            lu, lw = math.sqrt(ux * ux + uy * uy), math.sqrt(wx * wx + wy * wy)
            if lu * lw == 0:
                return True
            s, c = (ux * wy - uy * wx) / (lu * lw), (ux * wx + uy * wy) / (lu * lw)
            if s < 0 or (c < 0 and s < FLAT):
                return True
    return False


def _reference_swaps(xy, quads, bnd, dirty):
    """Every side of every examined quad tested in full (the chapter's pass, written out)."""
    quads = [list(q) for q in quads]
    lock = [False] * len(quads)
    done = 0
    for q1 in range(len(quads)):
        if lock[q1] or not dirty[q1]:
            continue
        for k in range(4):
            u, v = quads[q1][k], quads[q1][(k + 1) % 4]
            if bnd[u] and bnd[v]:
                continue
            q2 = -1
            for p in range(len(quads)):  # the kernel scans u's quads in index order, keeps the last
                if p != q1 and u in quads[p] and v in quads[p]:
                    q2 = p
            if q2 < 0 or lock[q2]:
                continue
            j = quads[q2].index(u)
            if quads[q2][(j + 3) % 4] != v:
                continue
            h = [u, quads[q2][(j + 1) % 4], quads[q2][(j + 2) % 4], v, quads[q1][(k + 2) % 4], quads[q1][(k + 3) % 4]]
            best = min(_sj(xy, h[0:4]), _sj(xy, [h[3], h[4], h[5], h[0]])) + GAIN
            pick = -1
            for r in (1, 2):
                a = [h[r], h[r + 1], h[r + 2], h[(r + 3) % 6]]
                b = [h[(r + 3) % 6], h[(r + 4) % 6], h[(r + 5) % 6], h[r]]
                if not (_convex(xy, a) and _convex(xy, b)) or _flat(xy, bnd, a) or _flat(xy, bnd, b):
                    continue
                val = min(_sj(xy, a), _sj(xy, b))
                if val > best:
                    best, pick = val, r
            if pick < 0:
                continue
            r = pick
            quads[q1] = [h[r], h[r + 1], h[r + 2], h[(r + 3) % 6]]
            quads[q2] = [h[(r + 3) % 6], h[(r + 4) % 6], h[(r + 5) % 6], h[r]]
            lock[q1] = lock[q2] = True
            done += 1
            break
    return np.array(quads), done


def _mesh(seed, k, jitter):
    """A jittered k x k grid of quads in which random side-by-side pairs had their shared
    side moved to another diagonal of their hexagon (where both quads stay convex), so
    that many pairs gain by a swap, by various margins."""
    rng = np.random.default_rng(seed)
    gx, gy = np.meshgrid(np.arange(k + 1.0), np.arange(k + 1.0), indexing="ij")
    xy = np.column_stack([gx.ravel(), gy.ravel()])
    inner = (xy[:, 0] > 0) & (xy[:, 0] < k) & (xy[:, 1] > 0) & (xy[:, 1] < k)
    xy[inner] += rng.uniform(-jitter, jitter, (int(inner.sum()), 2))
    idx = lambda i, j: i * (k + 1) + j  # noqa: E731
    quads = [[idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)] for i in range(k) for j in range(k)]
    for i in range(0, k - 1, 2):
        for j in range(k):
            if rng.random() < 0.3:
                continue
            a, b = i * k + j, (i + 1) * k + j
            q1, q2 = quads[a], quads[b]
            u, v = q1[1], q1[2]
            t = q2.index(u)
            h = [u, q2[(t + 1) % 4], q2[(t + 2) % 4], v, q1[3], q1[0]]
            r = int(rng.integers(1, 3))
            n1 = [h[r], h[r + 1], h[r + 2], h[(r + 3) % 6]]
            n2 = [h[(r + 3) % 6], h[(r + 4) % 6], h[(r + 5) % 6], h[r]]
            if _sj(xy, n1) > 0.0 and _sj(xy, n2) > 0.0:
                quads[a], quads[b] = n1, n2
    return xy, np.array(quads, dtype=np.int32), (~inner).astype(np.int8)


@settings(max_examples=15, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([0.15, 0.3]), st.booleans())
def test_diagonal_swap_decides_as_the_full_pass(seed, jitter, some_dirty):
    xy, quads, bnd = _mesh(seed, 8, jitter)
    m = len(quads)
    dirty = np.ones(m, np.int8)
    if some_dirty:
        dirty[np.random.default_rng(seed).random(m) < 0.4] = 0
    want, want_done = _reference_swaps(xy.tolist(), quads.tolist(), bnd.tolist(), dirty.tolist())
    alive = np.ones(m, np.int8)
    lock = np.zeros(m, np.int8)
    off, idx = ek.node_quads(quads, alive, len(xy))
    got = quads.copy()
    done = ek._diagonal_swap(xy, got, alive, bnd, off, idx, lock, GAIN, dirty)
    assert done == want_done
    assert np.array_equal(got, want)


def test_the_swap_test_meshes_do_swap():
    """The meshes of the test above give swaps to compare."""
    total = 0
    for seed in range(3):
        xy, quads, bnd = _mesh(seed, 8, 0.3)
        total += _reference_swaps(xy.tolist(), quads.tolist(), bnd.tolist(), [1] * len(quads))[1]
    assert total >= 8
