"""Zhu's pairs at input nodes on a sane stress domain (issue 12: min SJ above 0.2).

Stress seed 15001 domain 68 (scripts/stress2d.py generate(); a junction: 9-gon, 7
interior segments, 3 points, size 0.0345, sharpest input corner 67.8 degrees): zhu's pair
front made, in its last round, a pair with a reflex corner at a segment's node
((0.00974, -0.00296)); segment nodes do not move, the smoothing could not open it and the
quads around it ended at min SJ 0.102 (pairing: 0.249).  The pair front now refuses a
pair whose corner at an input node is reflex or wider than 168 degrees
(:func:`meshwright.quad._zhu_kernel._bent_input`): min SJ 0.305.

Oracles: the scaled Jacobian from the corners with ``math`` (test_zhu's helper) and
test_zhu's exact convexity and conformity checks; the domain is built here from the case's
numbers, not by the stress script.
"""

from __future__ import annotations

import numpy as np

from meshwright import geometry as g
from meshwright.quad import quadrangulate
from test_zhu import _check_all_quad, _min_scaled_jacobian

OUTER_68 = [
    [0.08016622066497803, 0.08059132099151611], [0.01346743106842041, 0.06256258487701416],
    [-0.11768829822540283, 0.025435209274291992], [-0.1184929609298706, -0.0038841962814331055],
    [-0.0797433853149414, -0.015913963317871094], [-0.03047049045562744, -0.08014059066772461],
    [0.031132221221923828, -0.11118221282958984], [0.0851743221282959, -0.06385231018066406],
    [0.06637704372406006, -0.029907584190368652],
]
SEGMENTS_68 = [
    [[0.08282466232776642, -0.059609219431877136], [0.025882706977427006, -0.018627881072461605]],
    [[0.03150153160095215, -0.020867109298706055], [-0.026540279388427734, 0.026896119117736816]],
    [[-0.036882638931274414, -0.008213043212890625], [-0.029451608657836914, -0.02367246150970459]],
    [[0.03777813911437988, 0.0007715225219726562], [0.030822396278381348, -0.021857738494873047]],
    [[-0.016656160354614258, 0.005936861038208008], [0.009735852479934692, -0.002955898642539978]],
    [[0.014824509620666504, -0.00767207145690918], [-0.03409600257873535, -0.014010325074195862]],
    [[0.0015028715133666992, 0.01882350444793701], [0.0334307998418808, -0.013371765613555908]],
]
POINTS_68 = [
    [0.024246305227279663, -0.014896705746650696], [-0.03223824501037598, -0.017875179648399353],
    [0.031691864132881165, -0.019029080867767334],
]
SIZE_68 = 0.03451952443126505
SEED_68 = 831545


def test_zhu_no_reflex_pair_at_segment_node():
    dom = g.polygon(
        np.array(OUTER_68), segments=[np.array(s) for s in SEGMENTS_68], points=np.array(POINTS_68)
    )
    mesh = quadrangulate(dom, SIZE_68, method="zhu", all_quad=True, seed=SEED_68)
    mesh.validate()
    _check_all_quad(mesh)
    # Every input corner is at least 67.8 degrees (sine 0.925), so the whole mesh is held
    # to issue 12's bar: 0.102 before, 0.305 now.
    assert _min_scaled_jacobian(mesh.points, mesh.cells["quad"]) > 0.2
