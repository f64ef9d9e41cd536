"""Zhu's quads at a 1e4 size jump on a polygon corner (issue 12: stress2d seed 15001,
domains 72 and 96, min scaled Jacobian 0.0012 / 0.00035 where pairing made 0.15 / 0.27).

The cause: pair_domain hands zhu_front an ungraded boundary, so beside the fine pieces
in the jump's disc lies one coarse segment, and the front closes it on a node near its
fine end: a sliver of about fine / coarse radians that no enhancement opens.  pair_domain
now hands zhu_front ``grade=not fixed_boundary`` as it does the triangle front (since
1d21a42): the boundary halves towards the fine end and domains 72 / 96 mesh with min SJ
0.142 / 0.054 (0.0012 / 0.00035 without).

Oracles: the scaled Jacobian from the corners with ``math`` (test_zhu's helper), convexity
and conformity by test_zhu's exact checks; the domain is built here from the case's
numbers, not by the stress script.
"""

from __future__ import annotations

import numpy as np
import pytest

from meshwright import geometry as g
from meshwright.quad import quadrangulate
from test_zhu import _check_all_quad, _min_scaled_jacobian

# Stress cases of seed 15001 (scripts/stress2d.py generate()), as build() scales them:
# outer loop, holes, interior segments, points, scale, shift, h, the jump's corner, seed, bound.
CASES = {
    # 72: the jump at a polygon corner.  Min SJ 0.0012 ungraded, 0.142 graded; pairing's
    # graded triangle front 0.15.  Bound 0.1.
    72: ([[0.9114809471143168, 0.0], [0.16398907751591127, 0.5047064841472766],
          [-0.7406693109268708, 0.5381277535767975], [-0.6035201461723446, -0.43848305270222004],
          [0.2944101330923157, -0.9061012197957958]],
         [[[-0.1466444936684208, 0.04709810676984803], [-0.1676547402268716, 0.05029936392272362],
           [-0.18474061997484126, 0.054609598713191265], [-0.18585790086086756, -0.04062169091159261],
           [-0.14078655429111359, -0.033310343759994934], [-0.11449076182436368, -0.006228303262912391]]],
         [],
         [[0.15023817413896018, -0.15603285291060498], [0.16700328552354454, -0.028528265732581652]],
         0.0014529398822145094, [-0.011762801792835844, 0.006709704125535675], 0.11652486887837396, 1, 381815, 0.1),
    # 96: the jump at a corner beside a long straight side (its first node lies outside
    # the disc, so grading by the pieces' end sizes does not split it).  Min SJ 0.00035
    # ungraded, 0.054 graded (slivers along that side remain: pairing 0.27).  Bound 0.02.
    96: ([[0.7893654817230402, 0.4382468274435422], [0.26683227352173844, 0.43772589722633176],
          [0.2252910202250063, 0.48090199268750256], [0.30203365945989025, 0.6859673107238359],
          [-0.020628466749435914, 0.9039510173416287], [-0.397347585501413, 0.8056215387735233],
          [-0.31451487737376577, 0.629644303087388], [-0.6231673363450968, 0.18913136268093725],
          [-0.46035177483163203, -0.22523049335825113], [-0.4797678639466652, -0.3125303812180963],
          [-0.7345178025362566, -0.6684164475071468], [-0.25701825846666626, -0.9054670265492404],
          [0.3615916285830567, -0.6833354840332645], [0.7909095937004026, -0.5132794997908975],
          [0.7807367619281212, -0.4074317851525165], [0.5947649864513208, -0.2613342785079294]],
         [],
         [[[0.03522233765971983, -0.08196093774305258], [0.05285127066783307, -0.04502737665494857]]],
         [[-0.08498645169078863, -0.0736408771219265], [0.12860291216459813, -0.004032112442569294]],
         375.7585332556951, [-1255.7607733324378, -573.9938928729194], 0.10064766025050709, 2, 990600, 0.02),
}
FACTOR = 1e-4
# The bounds (last entries): the ungraded slivers are about fine / coarse = 1e-4 radians
# (SJ 1e-4 .. 1e-3); each bound is at least 20 times the ungraded result and below the
# graded one measured, which is what this domain allows zhu now (issue 12's 0.2 is not met
# on 96: its left slivers are the next step).


@pytest.mark.parametrize("index", sorted(CASES))
def test_zhu_at_corner_jump_graded(index):
    outer, holes, segments, points, scale, shift, h, centre, seed, bound = CASES[index]

    def tr(p):
        return np.asarray(p, dtype=np.float64) * scale + np.asarray(shift)

    corner = tr(outer[centre])
    size, radius = h * scale, 20 * h * scale * FACTOR

    def step(xy):
        """1e-4 of the size inside a disc of 20 fine sizes around the corner."""
        xy = np.asarray(xy, dtype=np.float64)
        d = np.hypot(xy[..., 0] - corner[0], xy[..., 1] - corner[1])
        return np.where(d < radius, size * FACTOR, size)

    dom = g.polygon(tr(outer), holes=[tr(x) for x in holes], segments=[tr(x) for x in segments], points=tr(points))
    mesh = quadrangulate(dom, step, method="zhu", all_quad=True, seed=seed)
    mesh.validate()
    _check_all_quad(mesh)
    # The jump's disc is meshed: the corner's fine pieces are there.
    assert (np.hypot(*(mesh.points - corner).T) < radius).sum() >= 10
    assert _min_scaled_jacobian(mesh.points, mesh.cells["quad"]) > bound
