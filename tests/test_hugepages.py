"""core.hugepages: NumPy's huge-page advice is off inside small_pages() and inside
tetrahedralize, restored afterwards (also when the call raises), and restored by delaunay."""

from __future__ import annotations

import numpy as np
import pytest

import meshwright as mw
from meshwright.core import hugepages

SWITCH = hugepages._switch()
pytestmark = pytest.mark.skipif(SWITCH is None, reason="this NumPy has no huge-page switch")


def _state() -> bool:
    previous = SWITCH(True)  # reading the flag means setting it: put it back at once
    SWITCH(previous)
    return previous


@pytest.mark.parametrize("start", [True, False])
def test_advice_off_inside_and_restored(start):
    before = SWITCH(start)
    try:
        with hugepages.small_pages():
            assert _state() is False
        assert _state() is start
        with pytest.raises(ZeroDivisionError):
            with hugepages.small_pages():
                1 / 0
        assert _state() is start
    finally:
        SWITCH(before)


def test_tetrahedralize_restores_the_advice(monkeypatch):
    seen = []
    import meshwright.tet.mesher as mesher

    real = mesher.TET_METHODS["delaunay"].run

    def spy(job):
        seen.append(_state())
        return real(job)

    monkeypatch.setitem(mesher.TET_METHODS, "delaunay", mesher.TET_METHODS["delaunay"]._replace(run=spy))
    before = _state()
    mesh = mw.tetrahedralize(mw.geometry.sphere(level=1), 0.5)
    mesh.validate()
    assert seen == [False] and _state() is before
    assert np.isfinite(mesh.points).all()


@pytest.mark.parametrize("dim", [2, 3])
def test_delaunay_restores_the_advice(dim):
    before = _state()
    tri = mw.delaunay(np.random.default_rng(dim).random((200, dim)))
    assert _state() is before
    tri.to_mesh().validate()
