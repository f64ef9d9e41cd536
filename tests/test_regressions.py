"""Replay of the stress harness's reproducers (``tests/regressions/*.json``, written by
``scripts/stress2d.py``): every fixed case must mesh and pass the harness's checks; an open
one is a strict xfail (a fix makes it pass, which fails here until its status is flipped
to ``"fixed"``); an open hang is not run (it would stall the suite), nor an open crash (a
worker that died: in-process it would end the suite).  ``check`` replays ``triangulate``
and ``quadrangulate`` reproducers alike, by the method's name."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

import meshwright as mw

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))
from stress2d import REGRESSIONS, check  # noqa: E402  (the harness lives in scripts/)

FILES = sorted(REGRESSIONS.glob("*.json")) if REGRESSIONS.is_dir() else []


def _param(path: Path):
    body = json.loads(path.read_text())
    if body["status"] == "fixed":
        return pytest.param(body, id=path.stem)
    if body["status"] != "open":
        raise ValueError(f"{path.name}: status must be 'open' or 'fixed', not {body['status']!r}")
    run = not (body.get("hang", False) or body.get("crash", False))
    mark = pytest.mark.xfail(strict=True, run=run, reason=body["error"][:200])
    return pytest.param(body, id=path.stem, marks=mark)


@pytest.mark.parametrize("body", [_param(p) for p in FILES])
def test_reproducer(body):
    check(body["case"], body["method"])


def test_reproducers_are_well_formed():
    for path in FILES:
        body = json.loads(path.read_text())
        assert set(body) >= {"case", "method", "status", "error"}, path.name
        assert body["method"] in body["case"]["methods"], path.name
        assert body["method"] in mw.MESH_METHODS or body["method"] in mw.QUAD_METHODS, path.name
