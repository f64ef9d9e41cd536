"""Default caps of Delaunay refinement (``tri/_refine_caps.py``): the step cap follows the
run's progress.

The oracle is arithmetic on the documented rule (``20 min(points cap, expected +
inserted)``, granted only above ``GRANT`` times the old cap), not the loop: a stand-in
triangulation reports how many vertices the run has added.  The loop's own use of the rule
is covered by the stress reproducers (``tests/regressions``: a polygon of aspect 1e4 whose
steps outrun the size estimate).
"""

from __future__ import annotations

import numpy as np
import pytest

from meshwright.core.errors import MeshingError
from meshwright.tri._refine_caps import GRANT, GRANT_POINTS, STEPS_PER_POINT, Caps
from meshwright.tri.cdt import cdt_build
from meshwright.tri.ruppert import refine

SQUARE = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
SIDES = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])


class _Grown:
    """Stand-in for a triangulation after ``inserted`` refinement vertices."""

    def __init__(self, nv: int, inserted: int):
        self.n_points = nv + inserted


def _caps(**kw) -> Caps:
    ct = cdt_build(SQUARE, SIDES)
    ct.classify()
    return Caps(ct, np.inf, None, **kw)


def test_default_step_cap_is_twenty_per_expected_vertex():
    caps = _caps()
    assert caps.free_steps and caps.free_points
    assert caps.max_steps == STEPS_PER_POINT * min(caps.max_points, caps.expected)


def test_a_stalled_run_gets_no_more_steps():
    caps = _caps(max_points=10**8)
    before = caps.max_steps
    assert not caps.more_steps(_Grown(caps.nv, 0))
    assert caps.max_steps == before


def test_a_run_that_keeps_inserting_gets_more_steps():
    caps = _caps(max_points=10**8)  # what triangulate passes
    inserted = 10 * caps.expected
    assert caps.more_steps(_Grown(caps.nv, inserted))
    assert caps.max_steps == STEPS_PER_POINT * (caps.expected + inserted)
    # Then it stalls: no grant without new vertices.
    assert not caps.more_steps(_Grown(caps.nv, inserted))


def test_little_progress_is_no_grant():
    caps = _caps(max_points=10**8)
    # Just under both thresholds: fewer than GRANT_POINTS vertices' steps and GRANT x.
    few = min(GRANT_POINTS, int((GRANT - 1.0) * caps.max_steps / STEPS_PER_POINT)) - 1
    assert not caps.more_steps(_Grown(caps.nv, max(few, 0)))


def test_grants_stop_at_the_point_cap():
    caps = _caps(max_points=500)
    assert not caps.free_points
    caps.max_steps = 100
    assert caps.more_steps(_Grown(caps.nv, 10**6))
    assert caps.max_steps == STEPS_PER_POINT * 500
    assert not caps.more_steps(_Grown(caps.nv, 10**7))


def test_a_callers_step_cap_is_honoured_exactly():
    caps = _caps(max_steps=7)
    assert caps.max_steps == 7
    assert not caps.more_steps(_Grown(caps.nv, 10**6))
    ct = cdt_build(SQUARE, SIDES)
    ct.classify()
    with pytest.raises(MeshingError, match="max_steps=7 reached"):
        refine(ct, size=0.01, max_steps=7)
