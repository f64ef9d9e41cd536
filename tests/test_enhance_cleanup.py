"""Topological clean-up of the shape enhancement (quad/enhancement.py ``resplit_leftovers``,
quad/_enhance_kernel.py ``resplit_pass``, ``swap_low_pass``): a left-over triangle and a quad
beside it re-split along the pentagon diagonal that raises their worst corner sine, and a
low quad's side between two boundary nodes swapped in its hexagon.  Oracles: ``math`` sines
and rational orientation, written here."""

import math
from fractions import Fraction

import numpy as np
import pytest

from meshwright.quad.enhancement import RESPLIT_BELOW, SWAP_GAIN, resplit_leftovers


def _sine(xy, p, q, r):
    ux, uy = xy[r][0] - xy[q][0], xy[r][1] - xy[q][1]
    wx, wy = xy[p][0] - xy[q][0], xy[p][1] - xy[q][1]
    return (ux * wy - uy * wx) / (math.hypot(ux, uy) * math.hypot(wx, wy))


def _worst(xy, cell):
    return min(_sine(xy, cell[k - 1], cell[k], cell[(k + 1) % len(cell)]) for k in range(len(cell)))


def _convex(xy, cell):
    for k in range(len(cell)):
        (ax, ay), (bx, by), (cx, cy) = ([Fraction(float(t)) for t in xy[v]] for v in (cell[k - 1], cell[k], cell[(k + 1) % len(cell)]))
        if (ax - cx) * (by - cy) - (ay - cy) * (bx - cx) <= 0:
            return False
    return True


def _best_split(xy, pentagon):
    """The pentagon's five (triangle, quad) splits, convex ones only, best worst sine first."""
    out = []
    for i in range(5):
        t = [pentagon[(i + k) % 5] for k in range(3)]
        q = [pentagon[(i + k) % 5] for k in (2, 3, 4, 5)]
        if _convex(xy, t) and _convex(xy, q):
            out.append((min(_worst(xy, t), _worst(xy, q)), sorted(t), sorted(q)))
    return sorted(out, reverse=True)


def _square_and_cap(apex):
    """Unit square (0, 1, 2, 3) and the triangle (3, 2, 4) on its top side, 4 at ``apex``."""
    xy = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], apex])
    return xy, np.array([[0, 1, 2, 3]], dtype=np.int32), np.array([[3, 2, 4]], dtype=np.int32)


def _outer_lines(quads, tris):
    """Sides used once (the region's boundary), as line cells."""
    sides = {}
    for cell in [*quads.tolist(), *tris.tolist()]:
        for k in range(len(cell)):
            key = tuple(sorted((cell[k], cell[(k + 1) % len(cell)])))
            sides[key] = sides.get(key, 0) + 1
    return np.array([k for k, c in sides.items() if c == 1], dtype=np.int64)


def test_sliver_cap_is_resplit_along_the_best_diagonal():
    xy, quads, tris = _square_and_cap([0.4, 1.02])
    assert _worst(xy, [3, 2, 4]) < RESPLIT_BELOW  # the cap is a sliver (corner sines 0.05)
    lines = _outer_lines(quads, tris)
    bnd = np.zeros(len(xy), dtype=bool)
    bnd[lines.ravel()] = True
    q2, t2, count = resplit_leftovers(xy, quads, tris, bnd, lines)
    assert count == 1
    best = _best_split(xy, [3, 0, 1, 2, 4])
    assert best[0][0] > _worst(xy, [3, 2, 4]) + SWAP_GAIN
    # The oracle's best split: the triangle (1, 2, 4) below the apex's right, quad (0, 1, 4, 3).
    assert (sorted(t2[0].tolist()), sorted(q2[0].tolist())) == best[0][1:] == ([1, 2, 4], [0, 1, 3, 4])
    assert _convex(xy, q2[0].tolist()) and _convex(xy, t2[0].tolist())
    assert min(_worst(xy, q2[0].tolist()), _worst(xy, t2[0].tolist())) == pytest.approx(best[0][0])
    # The region stays the same: same outer sides.
    assert sorted(map(tuple, _outer_lines(q2, t2).tolist())) == sorted(map(tuple, lines.tolist()))
    # The inputs are not modified.
    assert quads.tolist() == [[0, 1, 2, 3]] and tris.tolist() == [[3, 2, 4]]


def test_a_line_between_them_is_never_crossed():
    xy, quads, tris = _square_and_cap([0.4, 1.02])
    lines = np.concatenate([_outer_lines(quads, tris), [[2, 3]]])  # an interior segment on 2-3
    q2, t2, count = resplit_leftovers(xy, quads, tris, np.ones(len(xy), dtype=bool), lines)
    assert count == 0 and q2.tolist() == [[0, 1, 2, 3]] and t2.tolist() == [[3, 2, 4]]


def test_well_shaped_pairs_do_not_change():
    xy, quads, tris = _square_and_cap([0.4, 1.8])
    assert _worst(xy, [3, 2, 4]) > RESPLIT_BELOW
    lines = _outer_lines(quads, tris)
    bnd = np.zeros(len(xy), dtype=bool)
    q2, t2, count = resplit_leftovers(xy, quads, tris, bnd, lines)
    assert count == 0 and q2.tolist() == [[0, 1, 2, 3]] and t2.tolist() == [[3, 2, 4]]



# A hexagon (counter-clockwise, every node on its boundary) split along 0-3 into two quads,
# one with a corner of sine 0.124; along 1-4 both are well shaped (0.891).
HEXAGON = [[0.6, 0.9], [-0.2, 1.0], [-0.4, 1.0], [-0.5, -1.1], [0.0, -1.3], [0.8, -0.8]]
HEX_SIDES = np.array([[k, (k + 1) % 6] for k in range(6)])


def _hexagon_splits(xy):
    """Worst corner sine of each of the hexagon's three quad pairs (None: not convex)."""
    out = {}
    for r in range(3):
        a = [(r + k) % 6 for k in range(4)]
        b = [(r + 3 + k) % 6 for k in range(4)]
        ok = _convex(xy, a) and _convex(xy, b)
        out[frozenset([frozenset(a), frozenset(b)])] = min(_worst(xy, a), _worst(xy, b)) if ok else None
    return out


def test_low_quads_swap_a_side_between_boundary_nodes():
    xy = np.array(HEXAGON)
    quads = np.array([[0, 3, 4, 5], [3, 0, 1, 2]], dtype=np.int32)
    splits = _hexagon_splits(xy)
    now = frozenset(frozenset(q) for q in quads.tolist())
    best = max((k for k in splits if splits[k] is not None), key=splits.get)
    assert splits[now] < RESPLIT_BELOW and splits[best] > splits[now] + SWAP_GAIN
    q2, t2, count = resplit_leftovers(xy, quads, np.zeros((0, 3), dtype=np.int32), np.ones(6, dtype=bool), HEX_SIDES)
    assert count == 1 and len(t2) == 0
    assert frozenset(frozenset(q) for q in q2.tolist()) == best == frozenset([frozenset([1, 2, 3, 4]), frozenset([4, 5, 0, 1])])
    for q in q2.tolist():
        assert _convex(xy, q)
    assert sorted(map(tuple, np.sort(_outer_lines(q2, t2), axis=1).tolist())) == sorted(
        map(tuple, np.sort(HEX_SIDES, axis=1).tolist()))


def test_no_swap_across_a_line_or_at_free_nodes():
    xy = np.array(HEXAGON)
    quads = np.array([[0, 3, 4, 5], [3, 0, 1, 2]], dtype=np.int32)
    none = np.zeros((0, 3), dtype=np.int32)
    # 0-3 an interior segment: it stays.
    q2, _, count = resplit_leftovers(xy, quads, none, np.ones(6, dtype=bool), np.concatenate([HEX_SIDES, [[0, 3]]]))
    assert count == 0 and q2.tolist() == quads.tolist()
    # Sides with a free node are enhance()'s to swap, not this clean-up's.
    q2, _, count = resplit_leftovers(xy, quads, none, np.array([1, 1, 1, 0, 1, 1], dtype=bool), HEX_SIDES)
    assert count == 0 and q2.tolist() == quads.tolist()

# Stress seed 15001, domain 96 (kind "plain", a 1e4 size jump in a small disc), method zhu:
# its chord refinement left an unforced corner of sine 0.109 next to left-over triangles;
# with the re-split the unforced worst corner sine is 0.301 (numbers copied from the case).
OUTER_96 = [[0.7893654817230402, 0.4382468274435422], [0.26683227352173844, 0.43772589722633176], [0.2252910202250063, 0.48090199268750256], [0.30203365945989025, 0.6859673107238359], [-0.020628466749435914, 0.9039510173416287], [-0.397347585501413, 0.8056215387735233], [-0.31451487737376577, 0.629644303087388], [-0.6231673363450968, 0.18913136268093725], [-0.46035177483163203, -0.22523049335825113], [-0.4797678639466652, -0.3125303812180963], [-0.7345178025362566, -0.6684164475071468], [-0.25701825846666626, -0.9054670265492404], [0.3615916285830567, -0.6833354840332645], [0.7909095937004026, -0.5132794997908975], [0.7807367619281212, -0.4074317851525165], [0.5947649864513208, -0.2613342785079294]]
SEGMENTS_96 = [[[0.03522233765971983, -0.08196093774305258], [0.05285127066783307, -0.04502737665494857]]]
POINTS_96 = [[-0.08498645169078863, -0.0736408771219265], [0.12860291216459813, -0.004032112442569294]]
SCALE_96, SHIFT_96, SEED_96 = 375.7585332556951, [-1255.7607733324378, -573.9938928729194], 990600
H_96, CENTRE_96, FACTOR_96 = 0.10064766025050709, [0.2252910202250063, 0.48090199268750256], 0.0001


# Stress seed 15001, domain 137 (kind "collinear", three holes), method zhu: a quad the
# smoothing left non-convex is cut into a triangle with a 0.8-degree corner at a boundary
# node; re-split after the cut, the unforced worst corner sine is 0.302 (0.142 without).
OUTER_137 = [[0.49814748595195035, 0.17569732149116374], [0.5419009232753063, 0.28233463024596384], [0.49400703237997934, 0.3697873859675363], [0.4654078813998201, 0.42200854649091324], [0.3749130198099512, 0.5872493502084122], [0.29592136590842016, 0.7314856543421557], [0.2137679318118943, 0.8814952707846037], [-0.3342218180956541, 0.8333580200415219], [-0.47044708402809776, 0.377181510658831], [-0.9166517326143602, 0.2506477411922684], [-0.841897361546816, -0.13853159462780687], [-0.8764210126212499, -0.17407726314076036], [-0.05084209564833881, -0.8429422078403157], [0.5504388680257597, -0.7275102541417616], [0.5152459885681259, -0.38629051058972647], [0.6788267784292615, -0.3481975997515971]]
HOLES_137 = [[[0.08678767105106978, 0.0101234834646748], [0.020268387825550592, 0.032887928434512055], [0.028252771548536105, 0.018930865316421585], [0.011227857493176195, 0.019464539546589922], [0.0062937162522698695, 0.012729157464716166], [0.03160085163686079, 0.006203426613430944], [0.010227226708920109, -0.015931718382373592], [0.05321974597148389, -0.03424665222508445]], [[-0.20578925156466502, 0.0217195448217885], [-0.2269021606925745, -0.010165978637667918], [-0.2336618131768643, -0.013233435668967508], [-0.21811120738259157, -0.025627245077530652], [-0.16136453801348344, -0.023512884958982492], [-0.14805885240224007, -0.028370015505108447], [-0.14366687459621658, -0.0011274809342817333]], [[-0.004088847735964915, -0.1784618623757907], [-0.008943732620559839, -0.17885927611707655], [-0.010032562414257647, -0.180168618037403], [-0.02262804822419117, -0.17333072536149746], [-0.018423868331772574, -0.19740438527997936]]]
POINTS_137 = [[0.07787745180000802, -0.10576693272150717]]
SCALE_137, SHIFT_137, H_137, SEED_137 = 3.2215456718179376, [2.397617377470062, 21.368655765287432], 0.23347495386934092, 646505


# Stress seed 15001, domain 92 (kind "plain", size "boundary", two segments, one point),
# method zhu: a quad at a reflex boundary corner, across a side to a node the enhancement
# never moves, has a 173.5-degree corner there; swapped across that side: 0.378 (0.113 without).
OUTER_92 = [[0.5848840284497157, 0.011175717258352558], [0.7855155822269809, 0.06596247438517333], [0.5725209854660012, 0.5008047792007065], [0.3304502975170604, 0.5060313679392091], [0.4409885004221956, 0.8121194060134684], [0.14242554886150305, 0.662007507569608], [0.06662423246581335, 0.6800139650739496], [0.01819460002246018, 0.807882772798888], [-0.08837865819438125, 0.7723956657472464], [-0.5685915708146101, 0.6974888639479611], [-0.8995104768377411, 0.19799020887634544], [-0.45586597222556524, -0.21439573539547316], [-0.5576605352215064, -0.2881898625832298], [-0.5616886165735612, -0.520205439789457], [0.11484983542537028, -0.8443769707195311], [0.8613532782322771, -0.25279060585081903]]
SEGMENTS_92 = [[[0.054944188088755334, -0.02388468580067815], [0.058795958283338216, 0.06853203504374454]], [[-0.15715174015158379, 0.10257622598231625], [-0.1994315844729787, 0.18356547353759028]]]
POINTS_92 = [[-0.14106794148756258, -0.03656674048682231]]
SCALE_92, SHIFT_92, SEED_92 = 250.4119515360177, [-1346.8109445463701, -1580.2839173954399], 633720


def _unforced_worst(points, quads, lines):
    """Smallest corner sine over the corners not between two line cells (issue 12)."""
    keys = {tuple(sorted(e)) for e in lines.tolist()}
    worst = math.inf
    for q in quads.tolist():
        for k in range(4):
            p, c, n = q[k - 1], q[k], q[(k + 1) % 4]
            if tuple(sorted((p, c))) in keys and tuple(sorted((c, n))) in keys:
                continue
            worst = min(worst, _sine(points, p, c, n))
    return worst


@pytest.fixture
def resplit_in_pairing(monkeypatch):
    """pair_domain with resplit_leftovers where pairing.py is to call it: after the
    enhancement (here at the entry of the smoothing that follows it, in place on the
    arrays pair_domain holds) and after quads left non-convex are cut back into
    triangles (on unpair_nonconvex's result).  Remove it once pairing.py makes both calls."""
    from meshwright.quad import pairing

    enhance, smooth, unpair = pairing.enhance, pairing.smooth_quads, pairing.unpair_nonconvex
    seen = {}

    def enhance_then_arm(*args, **kwargs):
        seen["armed"] = True
        return enhance(*args, **kwargs)

    def smooth_after_resplit(xy, quads, tris, lines, *args, **kwargs):
        if seen.pop("armed", False):
            bnd = np.zeros(len(xy), dtype=bool)
            bnd[np.asarray(lines).ravel()] = True
            bnd[np.asarray(args[2], dtype=np.int64)] = True  # fixed_pts
            seen.update(bnd=bnd, lines=lines)
            q2, t2, _ = resplit_leftovers(xy, quads, tris, bnd, lines)
            quads[...] = q2
            tris[...] = t2
        return smooth(xy, quads, tris, lines, *args, **kwargs)

    def unpair_then_resplit(xy, quads, tris):
        quads, tris = unpair(xy, quads, tris)
        if "bnd" in seen:
            quads, tris, _ = resplit_leftovers(xy, quads, tris, seen["bnd"], seen["lines"])
        return quads, tris

    monkeypatch.setattr(pairing, "enhance", enhance_then_arm)
    monkeypatch.setattr(pairing, "smooth_quads", smooth_after_resplit)
    monkeypatch.setattr(pairing, "unpair_nonconvex", unpair_then_resplit)


def test_stress_domain_96_reaches_the_bound(resplit_in_pairing):
    import meshwright as mw

    def tr(p):
        return np.asarray(p, dtype=np.float64).reshape(-1, 2) * SCALE_96 + np.asarray(SHIFT_96)

    h = H_96 * SCALE_96
    centre = tr(CENTRE_96)[0]

    def size(xy):  # the stress harness's jump: h * FACTOR_96 within 20 fine sizes of the centre
        xy = np.asarray(xy, dtype=np.float64)
        d = np.hypot(xy[..., 0] - centre[0], xy[..., 1] - centre[1])
        return np.where(d < 20 * h * FACTOR_96, h * FACTOR_96, h)

    dom = mw.geometry.polygon(tr(OUTER_96), segments=[tr(g) for g in SEGMENTS_96], points=tr(POINTS_96))
    m = mw.quadrangulate(dom, size, method="zhu", seed=SEED_96, all_quad=True)
    assert set(m.cells) == {"quad", "line"}
    for q in m.quads.tolist():
        assert _convex(m.points, q)
    assert _unforced_worst(m.points, m.quads, m.cells["line"]) > 0.2  # 0.301 (0.109 without the re-split)


def test_stress_domain_137_reaches_the_bound(resplit_in_pairing):
    import meshwright as mw

    def tr(p):
        return np.asarray(p, dtype=np.float64).reshape(-1, 2) * SCALE_137 + np.asarray(SHIFT_137)

    dom = mw.geometry.polygon(tr(OUTER_137), holes=[tr(h) for h in HOLES_137], points=tr(POINTS_137))
    m = mw.quadrangulate(dom, H_137 * SCALE_137, method="zhu", seed=SEED_137, all_quad=True)
    assert set(m.cells) == {"quad", "line"}
    for q in m.quads.tolist():
        assert _convex(m.points, q)
    assert _unforced_worst(m.points, m.quads, m.cells["line"]) > 0.2  # 0.302 (0.142 without the re-split)


def test_stress_domain_92_reaches_the_bound(resplit_in_pairing):
    import meshwright as mw

    def tr(p):
        return np.asarray(p, dtype=np.float64).reshape(-1, 2) * SCALE_92 + np.asarray(SHIFT_92)

    dom = mw.geometry.polygon(tr(OUTER_92), segments=[tr(g) for g in SEGMENTS_92], points=tr(POINTS_92))
    m = mw.quadrangulate(dom, "boundary", method="zhu", seed=SEED_92, all_quad=True)
    assert set(m.cells) == {"quad", "line"}
    for q in m.quads.tolist():
        assert _convex(m.points, q)
    assert _unforced_worst(m.points, m.quads, m.cells["line"]) > 0.2  # 0.378 (0.113 without the swap)


def _sides(cells):
    """Side (sorted pair) -> number of cells using it."""
    count = {}
    for cell in cells:
        for k in range(len(cell)):
            key = tuple(sorted((cell[k], cell[(k + 1) % len(cell)])))
            count[key] = count.get(key, 0) + 1
    return count


def _area(xy, cells):
    total = Fraction(0)
    for cell in cells:
        pts = [[Fraction(float(t)) for t in xy[v]] for v in cell]
        total += sum(pts[k - 1][0] * pts[k][1] - pts[k][0] * pts[k - 1][1] for k in range(len(pts))) / 2
    return total


@pytest.mark.parametrize("seed", range(6))
def test_random_meshes_stay_conforming_and_convex(seed):
    """A triangulated square, its triangles paired into convex quads at random (some left
    over) and jittered so that slivers appear; some interior sides are lines.  After the
    clean-up: the same nodes, boundary and area, every side inside used twice, the lines
    kept, every cell strictly convex (rational), no cell's worst sine under the bound lower."""
    import meshwright as mw

    rng = np.random.default_rng(seed)
    m = mw.triangulate(mw.geometry.polygon([[0, 0], [1, 0], [1, 1], [0, 1]]), 0.15, seed=seed)
    xy = m.points.copy()
    lines = m.cells["line"].astype(np.int64)
    on = np.zeros(len(xy), dtype=bool)
    on[lines.ravel()] = True
    tris = m.cells["triangle"].tolist()
    # Interior nodes pulled towards a neighbour: thin cells, still counter-clockwise.
    for v in rng.permutation(np.flatnonzero(~on))[: len(xy) // 4]:
        w = next(t for t in tris if v in t)
        target = w[(w.index(v) + 1) % 3]
        trial = xy.copy()
        trial[v] = xy[v] + 0.6 * (xy[target] - xy[v])
        if all(_convex(trial, t) for t in tris if v in t):
            xy = trial
    interior = [s for s, c in _sides(tris).items() if c == 2]
    segs = [interior[i] for i in rng.choice(len(interior), 4, replace=False)]
    mate = {}
    quads = []
    left = []
    for i in rng.permutation(len(tris)).tolist():
        if i in mate:
            continue
        t = tris[i]
        for k in range(3):
            a, b, c = t[k], t[(k + 1) % 3], t[(k + 2) % 3]
            j = next((j for j, s in enumerate(tris) if j != i and j not in mate and a in s and b in s), None)
            if j is None or tuple(sorted((a, b))) in segs or rng.random() < 0.2:
                continue
            d = next(x for x in tris[j] if x not in (a, b))
            q = [b, c, a, d]
            if _convex(xy, q):
                mate[i], mate[j] = j, i
                quads.append(q)
                break
        else:
            left.append(t)
            mate[i] = -1
    quads = np.array(quads, dtype=np.int32)
    left = np.array(left, dtype=np.int32).reshape(-1, 3)
    all_lines = np.concatenate([lines, np.array(segs, dtype=np.int64)])
    bnd = on.copy()
    bnd[np.array(segs).ravel()] = True
    q2, t2, _ = resplit_leftovers(xy, quads, left, bnd, all_lines)
    before = [*quads.tolist(), *left.tolist()]
    after = [*q2.tolist(), *t2.tolist()]
    assert len(q2) == len(quads) and len(t2) == len(left)
    s0, s1 = _sides(before), _sides(after)
    assert {s for s, c in s1.items() if c == 1} == {s for s, c in s0.items() if c == 1}
    assert set(s1.values()) <= {1, 2}
    assert all(s1.get(tuple(sorted(s))) == 2 for s in segs)
    assert _area(xy, after) == _area(xy, before)
    assert all(_convex(xy, c) for c in after)
    assert sorted({v for c in after for v in c}) == sorted({v for c in before for v in c})
    # A changed cell pair never lowers the worst sine over all cells.
    assert min(_worst(xy, c) for c in after) >= min(_worst(xy, c) for c in before)
