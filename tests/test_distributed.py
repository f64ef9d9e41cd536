"""meshwright.distributed (issue 15) on local Dask clusters of 1, 2 and 4 worker processes.

Oracles share no code with the package: exact rational areas and orientations
(fractions.Fraction), edge counts by plain dictionaries, markers by the coordinates of the
rectangle's sides, meshio reading the XDMF file, and file bytes compared across runs (and
across a run that lost a worker).
"""

from __future__ import annotations

import hashlib
import math
import os
import signal
import sys
from collections import Counter
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

pytest.importorskip("dask")
pytest.importorskip("distributed")
pytest.importorskip("h5py")

from meshwright.core.errors import GeometryError, InputError, MeshingError, SizeError
from meshwright.distributed import (
    decompose,
    local_cluster,
    simulate_scaling,
    triangulate,
    warm,
)
from meshwright.geometry import Domain
from meshwright.geometry.curves import Arc
from meshwright.geometry.shapes import polygon
from meshwright.sizing.boundary import gradation

RECT = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]]
SIDE_MARKERS = [1, 2, 3, 4]  # bottom, right, top, left


def _rect():
    return polygon(RECT, markers=[SIDE_MARKERS])


def _disk_with_hole():
    return Domain(Arc((0.0, 0.0), 1.0, 0.0, 2 * math.pi), [Arc((0.4, 0.1), 0.15, 0.0, 2 * math.pi)])


# Fine at the hole, coarse far away (0.015 + 0.06 |x - (0.4, 0.1)|): the size varies strongly
# across the cuts.  A library field, so that worker processes can unpickle it.
_graded = gradation([[0.4, 0.1]], 0.015, growth=1.06)


@pytest.fixture(scope="module")
def clients():
    out = {}
    try:
        for n in (1, 2):
            c = local_cluster(n, memory_limit="2GiB")
            warm(c)
            out[n] = c
        yield out
    finally:
        for c in out.values():
            c.close()


def _digest(files) -> dict:
    return {Path(f).name: hashlib.sha256(Path(f).read_bytes()).hexdigest() for f in files}


def _check_mesh(mesh, holes: int):
    """Topology and geometry checks with exact arithmetic; returns the exact area."""
    pts, tris = mesh.points, mesh.cells["triangle"]
    assert len(np.unique(pts, axis=0)) == len(pts), "duplicate nodes"
    edges = Counter()
    area = Fraction(0)
    for a, b, c in tris.tolist():
        (ax, ay), (bx, by), (cx, cy) = (tuple(map(Fraction, pts[i])) for i in (a, b, c))
        cross = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
        assert cross > 0, f"triangle {a, b, c} not counter-clockwise"
        area += cross / 2
        for u, v in ((a, b), (b, c), (c, a)):
            edges[(min(u, v), max(u, v))] += 1
    assert max(edges.values()) == 2, "an edge in more than two triangles"
    boundary = {e for e, n in edges.items() if n == 1}
    lines = {(min(u, v), max(u, v)) for u, v in mesh.cells["line"].tolist()}
    assert boundary == lines, "boundary edges differ from the line cells"
    used = np.unique(tris)
    assert len(used) == len(pts)
    assert len(pts) - len(edges) + len(tris) == 1 - holes, "Euler characteristic"
    return area


def _min_angle_deg(pts, tris) -> float:
    p = pts[tris]
    out = 180.0
    for k in range(3):
        u = p[:, (k + 1) % 3] - p[:, k]
        v = p[:, (k + 2) % 3] - p[:, k]
        cos = (u * v).sum(1) / (np.hypot(*u.T) * np.hypot(*v.T))
        out = min(out, float(np.degrees(np.arccos(np.clip(cos, -1, 1))).min()))
    return out


def test_rectangle_on_two_workers_is_a_valid_mesh(clients, tmp_path):
    dm = triangulate(_rect(), 0.08, client=clients[2], parts=4, out=tmp_path / "r.xdmf")
    mesh = dm.to_mesh()
    assert mesh.n_points == dm.n_points and len(mesh.cells["triangle"]) == dm.n_cells
    assert _check_mesh(mesh, holes=0) == 2
    assert _min_angle_deg(mesh.points, mesh.cells["triangle"]) >= 30.0 - 1e-9
    assert math.isclose(dm.stats["min_angle"], _min_angle_deg(mesh.points, mesh.cells["triangle"]), abs_tol=1e-9)
    # Markers as the sides they lie on (the serial mesher's segment markers).
    mid = mesh.points[mesh.cells["line"]].mean(axis=1)
    side = np.select([mid[:, 1] == 0, mid[:, 0] == 2, mid[:, 1] == 1, mid[:, 0] == 0], SIDE_MARKERS, -1)
    assert (side > 0).all(), "a line cell off the boundary"
    assert (mesh.cell_data["marker"]["line"] == side).all()
    # Boundary-node markers follow their lines, interior nodes have none.
    on = np.zeros(len(mesh.points), dtype=bool)
    on[mesh.cells["line"].ravel()] = True
    assert (mesh.point_data["marker"][~on] == 0).all() and (mesh.point_data["marker"][on] > 0).all()
    s = dm.stats
    assert s["parts"] == 4 and s["workers"] == 2 and len(s["triangles"]) == 4
    assert sum(s["triangles"]) == dm.n_cells


def test_meshio_reads_the_xdmf_back(clients, tmp_path):
    meshio = pytest.importorskip("meshio")
    dm = triangulate(_rect(), 0.1, client=clients[2], parts=3, out=tmp_path / "m.xdmf")
    m = meshio.read(dm.path)
    ours = dm.to_mesh()
    assert np.array_equal(m.points[:, :2], ours.points)
    assert np.array_equal(m.cells_dict["triangle"], ours.cells["triangle"])
    assert np.array_equal(m.point_data["marker"], ours.point_data["marker"])


def test_bytes_identical_across_worker_counts_and_reruns(clients, tmp_path):
    digests = []
    for n, run in ((1, "a"), (2, "b"), (2, "c")):
        d = tmp_path / run
        d.mkdir()
        dm = triangulate(_rect(), 0.07, client=clients[n], parts=5, seed=3, out=d / "mesh.xdmf")
        digests.append(_digest(dm.files))
    assert all(dg == digests[0] for dg in digests[1:])
    assert len(digests[0]) == 2 + 5


def _bands():
    # Fine (0.005) along x = 0.97 and x = 1.03, growing by 2 per unit length: the size varies
    # fast along any cut near the middle, which refinement then needs split.
    y = np.linspace(0.0, 1.0, 101)
    src = np.concatenate([np.column_stack([np.full_like(y, x), y]) for x in (0.97, 1.03)])
    return gradation(src, 0.005, growth=3.0, hmax=0.1)


def test_four_workers_give_the_same_bytes_as_one(clients, tmp_path):
    # A uniform size, and the graded bands whose parts resume after exchange rounds.
    cases = {"uniform": (0.05, 8), "rounds": (_bands(), 4)}
    ref, got = {}, {}
    for name, (size, parts) in cases.items():
        for n in (1, 2):
            (tmp_path / f"{name}{n}").mkdir()
            ref[name, n] = triangulate(
                _rect(), size, client=clients[n], parts=parts, seed=5, out=tmp_path / f"{name}{n}" / "mesh.xdmf"
            )
    with local_cluster(4, memory_limit="1GiB") as c4:
        warm(c4)
        for name, (size, parts) in cases.items():
            (tmp_path / f"{name}4").mkdir()
            got[name] = triangulate(_rect(), size, client=c4, parts=parts, seed=5, out=tmp_path / f"{name}4" / "mesh.xdmf")
    assert ref["rounds", 1].stats["rounds"] >= 1 and ref["rounds", 1].stats["split_points"] > 0
    for name, dm in got.items():
        assert dm.stats["workers"] == 4
        assert _digest(dm.files) == _digest(ref[name, 1].files) == _digest(ref[name, 2].files), name
        assert _check_mesh(dm.to_mesh(), holes=0) == 2


class _KillOnce:
    """A constant size h that kills the worker process evaluating it, once (a marker file
    remembers): the task Dask then runs again elsewhere must give the same bytes."""

    def __init__(self, h: float, marker: str | None):
        self.h, self.marker = h, marker

    def __call__(self, xy):
        if self.marker is not None and not os.path.exists(self.marker):
            from distributed import get_worker

            try:
                get_worker()
            except ValueError:
                pass  # on the client (decomposition)
            else:
                try:  # two workers may get here at once: only the one creating the marker dies
                    os.close(os.open(self.marker, os.O_CREAT | os.O_EXCL))
                except FileExistsError:
                    return np.full(len(xy), self.h)
                os.kill(os.getpid(), signal.SIGKILL)
        return np.full(len(xy), self.h)


def test_a_worker_killed_mid_run_changes_no_byte(clients, tmp_path):
    import cloudpickle

    # Worker processes cannot import this test module: ship _KillOnce by value.
    cloudpickle.register_pickle_by_value(sys.modules[__name__])
    try:
        (tmp_path / "ref").mkdir()
        (tmp_path / "killed").mkdir()
        ref = triangulate(_rect(), _KillOnce(0.06, None), client=clients[2], parts=4, out=tmp_path / "ref" / "m.xdmf")
        marker = tmp_path / "killed.marker"
        dm = triangulate(
            _rect(), _KillOnce(0.06, str(marker)), client=clients[2], parts=4, out=tmp_path / "killed" / "m.xdmf"
        )
    finally:
        cloudpickle.unregister_pickle_by_value(sys.modules[__name__])
    assert marker.exists(), "no worker was killed"
    assert _digest(dm.files) == _digest(ref.files)
    assert sorted(p.name for p in (tmp_path / "killed").iterdir()) == sorted(Path(f).name for f in dm.files)


class _KillWhileResuming:
    """The bands' size field, killing the worker process that evaluates it inside
    ``resume_part`` (once, a marker file remembers): the round-0 state that task resumed is
    lost with its worker, so Dask must mesh that part again and resume it."""

    def __init__(self, marker: str):
        self.field, self.marker = _bands(), marker

    def __call__(self, xy):
        if not os.path.exists(self.marker):
            frame = sys._getframe()
            while frame is not None and frame.f_code.co_name != "resume_part":
                frame = frame.f_back
            if frame is not None:
                try:  # both parts resume at once: only the worker creating the marker dies
                    os.close(os.open(self.marker, os.O_CREAT | os.O_EXCL))
                except FileExistsError:
                    return self.field(xy)
                os.kill(os.getpid(), signal.SIGKILL)
        return self.field(xy)


def test_a_worker_killed_while_resuming_a_part_changes_no_byte(clients, tmp_path):
    import cloudpickle

    cloudpickle.register_pickle_by_value(sys.modules[__name__])
    try:
        (tmp_path / "ref").mkdir()
        (tmp_path / "killed").mkdir()
        ref = triangulate(_rect(), _bands(), client=clients[2], parts=2, out=tmp_path / "ref" / "m.xdmf")
        marker = tmp_path / "killed.marker"
        dm = triangulate(
            _rect(), _KillWhileResuming(str(marker)), client=clients[2], parts=2, out=tmp_path / "killed" / "m.xdmf"
        )
    finally:
        cloudpickle.unregister_pickle_by_value(sys.modules[__name__])
    assert marker.exists(), "no worker was killed"
    assert ref.stats["rounds"] >= 1
    assert _digest(dm.files) == _digest(ref.files)


def test_resumed_part_keeps_its_triangles_away_from_the_new_splits():
    import pickle

    from meshwright.distributed.exchange import Splits
    from meshwright.distributed.part import resume_part, start_part
    from meshwright.distributed.partition import part_pslg

    dec = decompose(_rect(), _bands(), 2)
    field = _bands()
    curves = _rect().curves
    states = [start_part(part_pslg(dec, i, len(curves)), curves, field, 30.0, 11 + i, 10**6) for i in range(2)]
    splits = Splits(dec)
    for i, state in enumerate(states):
        splits.add(i, state.report.splits, state.report.xy)
    todo = splits.lacking()
    assert sorted(todo) == [0, 1], "each side lacks the other's splits"
    for i, lack in todo.items():
        before = states[i]
        tri0 = {frozenset(map(tuple, before.ct.points[t].tolist())) for t in before.ct.triangles(True)}
        after = resume_part(before, lack)
        tri1 = {frozenset(map(tuple, after.ct.points[t].tolist())) for t in after.ct.triangles(True)}
        new = np.array([[x, y] for _, _, x, y in lack])
        # The split points are on the interface, and new in this part.
        assert not any(tuple(p) in {v for t in tri0 for v in t} for p in new.tolist())
        assert all(tuple(p) in {v for t in tri1 for v in t} for p in new.tolist())
        # Two element sizes (hmax = 0.1) away: the refinement that follows the splits grades
        # outward through the angle bound by up to about one element (0.14 measured).
        far = {t for t in tri0 if min(math.dist(v, p) for v in t for p in new.tolist()) > 0.2}
        assert len(far) > len(tri0) // 2
        assert far <= tri1, "a triangle far from every new split point changed"
        # The state it resumed from is untouched (Dask may run the task again), and a state
        # that went through pickling (Dask spilling it) resumes to the same mesh.
        assert tri0 == {frozenset(map(tuple, before.ct.points[t].tolist())) for t in before.ct.triangles(True)}
        again = resume_part(pickle.loads(pickle.dumps(before)), lack)
        assert np.array_equal(again.ct.points, after.ct.points)
        assert np.array_equal(again.ct.triangles(True), after.ct.triangles(True))
        assert sys.getsizeof(after) >= after.ct.state.pts.nbytes + after.ct.state.tri.nbytes


def _dyadic_splits(choices):
    """Fractions made by splitting, at its midpoint, gap ``c mod gaps`` of [0, 1] for each ``c``."""
    chain = [Fraction(0), Fraction(1)]
    made = []
    for c in choices:
        k = c % (len(chain) - 1)
        f = (chain[k] + chain[k + 1]) / 2
        chain.insert(k + 1, f)
        made.append(f)
    return made


@given(
    st.lists(st.integers(0, 10**6), max_size=12),
    st.lists(st.integers(0, 10**6), max_size=12),
    st.lists(st.integers(0, 10**6), max_size=6),
)
@settings(max_examples=60, deadline=None)
def test_exchange_gives_each_side_the_other_sides_splits_in_an_order_it_can_make(a, b, c):
    from types import SimpleNamespace

    from meshwright.distributed.exchange import Splits

    # Interface segment 0 between parts 0 and 1, segment 1 between parts 1 and 2.
    dec = SimpleNamespace(n_parts=3, kind=np.array([2, 2]), left=np.array([0, 1]), right=np.array([1, 2]))
    ends = {0: ((0.0, 0.0), (1.0, 0.3)), 1: ((1.0, 0.3), (0.2, 1.7))}
    memo = {}

    def xy(s, f):
        """Coordinates by midpoints of the interval ends, as both sides compute them."""
        if f in (0, 1):
            return ends[s][int(f)]
        if (s, f) not in memo:
            h = Fraction(1, f.denominator)
            (x0, y0), (x1, y1) = xy(s, f - h), xy(s, f + h)
            memo[s, f] = (0.5 * (x0 + x1), 0.5 * (y0 + y1))
        return memo[s, f]

    made = {0: [(0, f) for f in _dyadic_splits(a)], 1: [(0, f) for f in _dyadic_splits(b)] + [(1, f) for f in
            _dyadic_splits(c)], 2: []}
    splits = Splits(dec)
    for i, names in made.items():
        splits.add(i, names, np.array([xy(s, f) for s, f in names]).reshape(-1, 2))
    chains = {(i, s): sorted({Fraction(0), Fraction(1)} | {f for t, f in made[i] if t == s}) for i in range(3) for s in
              (0, 1)}
    for i, todo in splits.lacking().items():
        for s, f, x, y in todo:
            chain = chains[i, s]
            k = next(j for j, g in enumerate(chain) if g > f)
            assert chain[k - 1] < f and (chain[k - 1] + chain[k]) / 2 == f, "not the midpoint of a subsegment"
            assert (x, y) == xy(s, f)
            chain.insert(k, f)
    for s, (i, j) in ((0, (0, 1)), (1, (1, 2))):
        assert chains[i, s] == chains[j, s], "the two sides of a segment differ"
    assert splits.lacking() == {}
    ids, coords = splits.numbered(10)
    names = sorted({n for m in made.values() for n in m})
    assert list(ids) == names and list(ids.values()) == list(range(10, 10 + len(names)))
    assert [tuple(p) for p in coords.tolist()] == [xy(s, f) for s, f in names]


def test_local_clusters_leave_the_cores_to_the_parts(clients):
    import dask

    def settings():
        return (
            dask.config.get("distributed.worker.profile.enabled"),
            dask.config.get("distributed.admin.tick.interval"),
        )

    # Also on workers the nanny restarted (the tests that kill one ran before).
    for c in clients.values():
        assert set(c.run(settings).values()) == {(False, "1s")}


def test_graded_size_across_a_cut_forces_exchange_rounds(clients, tmp_path):
    dm = triangulate(_rect(), _bands(), client=clients[2], parts=2, out=tmp_path / "g.xdmf")
    assert dm.stats["rounds"] >= 1 and dm.stats["split_points"] > 0
    mesh = dm.to_mesh()
    assert _check_mesh(mesh, holes=0) == 2
    assert _min_angle_deg(mesh.points, mesh.cells["triangle"]) >= 30.0 - 1e-9
    # The same run allowed fewer rounds fails with a clear error.
    with pytest.raises(MeshingError, match="max_rounds"):
        triangulate(_rect(), _bands(), client=clients[2], parts=2, max_rounds=0, out=tmp_path / "h.xdmf")
    # Replaying the measured part times: more virtual workers never take longer.
    times = [simulate_scaling(dm.stats, p) for p in (1, 2, 4)]
    assert times[0] >= times[1] >= times[2] > 0


def test_curved_domain_with_a_hole(clients, tmp_path):
    dm = triangulate(_disk_with_hole(), _graded, client=clients[2], parts=4, out=tmp_path / "d.xdmf")
    mesh = dm.to_mesh()
    area = _check_mesh(mesh, holes=1)
    # Chords of circles: the polygon's area approaches pi (1 - 0.15^2) from below.
    assert 0.99 * math.pi * (1 - 0.0225) < float(area) <= math.pi * (1 - 0.0225)
    assert _min_angle_deg(mesh.points, mesh.cells["triangle"]) >= 30.0 - 1e-9
    # Every boundary node lies on its circle.
    b = np.unique(mesh.cells["line"])
    r_out = np.hypot(*mesh.points[b].T)
    r_in = np.hypot(mesh.points[b, 0] - 0.4, mesh.points[b, 1] - 0.1)
    assert np.all(np.isclose(r_out, 1.0, atol=1e-12) | np.isclose(r_in, 0.15, atol=1e-12))


def _junction_angles(dec) -> list:
    """Angles (degrees, as lines) between an interface segment and every other skeleton
    segment at its ends, from the segments' coordinates alone."""
    ends = {}
    for s, (a, b) in enumerate(dec.segments.tolist()):
        ends.setdefault(a, []).append(s)
        ends.setdefault(b, []).append(s)
    out = []
    for segs in ends.values():
        for s in segs:
            if dec.kind[s] != 2:
                continue
            u = np.diff(dec.points[dec.segments[s]], axis=0)[0]
            for r in segs:
                v = np.diff(dec.points[dec.segments[r]], axis=0)[0]
                cos = abs(float(u @ v)) / (math.hypot(*u) * math.hypot(*v))
                if r != s and cos < 1.0 - 1e-12:  # collinear pieces of one cut are no junction
                    out.append(math.degrees(math.acos(min(cos, 1.0))))
    return out


def test_oblique_cuts_balance_the_rim_and_mesh_a_valid_disk(clients, tmp_path):
    # At 8 parts the balanced positions near the rim lie where no axis-parallel line meets the
    # circle at 60 degrees (a line does so only within 0.5 of the centre): some cuts turn.
    dec = decompose(_disk_with_hole(), _graded, 8)
    oblique = (dec.cuts[:, 0] != 0.0) & (dec.cuts[:, 1] != 0.0)
    assert oblique.any()
    assert dec.imbalance <= 1.10 and dec.min_cut_angle >= 60.0
    # Every angle an interface makes at its ends (boundary crossings, cut/cut junctions) is an
    # input angle of the parts: at least 60 degrees (chords of curves bend a little).
    assert min(_junction_angles(dec)) >= 59.0
    dm = triangulate(_disk_with_hole(), _graded, client=clients[2], parts=8, out=tmp_path / "o.xdmf")
    mesh = dm.to_mesh()
    area = _check_mesh(mesh, holes=1)
    assert 0.99 * math.pi * (1 - 0.0225) < float(area) <= math.pi * (1 - 0.0225)
    assert _min_angle_deg(mesh.points, mesh.cells["triangle"]) >= 30.0 - 1e-9
    assert dm.stats["imbalance"] <= 1.15  # 540 triangles a part: boundary layers weigh more than at scale


@pytest.mark.parametrize("h0, growth, parts", [(0.004, 1.5, 16), (0.003, 1.8, 12), (0.004, 1.3, 8)])
def test_oblique_junctions_are_single_points_and_every_part_is_closed(h0, growth, parts):
    # Found by fuzzing: an oblique cut through an earlier cut's end computed that point again
    # with other rounding (two skeleton points 6e-17 apart, an open loop in each part), and a
    # junction between the hole's chord and its arc left an interface sliver in the hole.
    dec = decompose(_disk_with_hole(), gradation([[0.4, 0.1]], h0, growth=growth), parts)
    p = dec.points
    gap = np.hypot(p[:, None, 0] - p[None, :, 0], p[:, None, 1] - p[None, :, 1])
    np.fill_diagonal(gap, np.inf)
    assert gap.min() > 1e-9
    for i in range(parts):
        # The part's boundary: its own segments, and interfaces with it on the right reversed.
        own = dec.segments[dec.left == i]
        theirs = dec.segments[dec.right == i][:, ::-1]
        seg = np.concatenate([own, theirs])
        out_deg = Counter(seg[:, 0].tolist())
        in_deg = Counter(seg[:, 1].tolist())
        assert out_deg == in_deg, f"part {i} has an open loop"


def test_clipping_a_cell_by_an_oblique_line_keeps_its_area():
    from meshwright.distributed.cells import box, clip, direction

    poly, labels = box(0.0, 0.0, 2.0, 1.0)
    d = direction(-1, math.radians(30.0))
    (lo, lo_lab), (hi, hi_lab), ends = clip(poly, labels, d, 1.0, 7)

    def area(p):
        q = [tuple(map(Fraction, v)) for v in p.tolist()]
        return sum(a[0] * b[1] - b[0] * a[1] for a, b in zip(q, q[1:] + q[:1])) / 2

    assert area(lo) > 0 and area(hi) > 0
    assert abs(float(area(lo) + area(hi)) - 2.0) < 1e-12
    # The new edge along the cut is labelled in both halves; the two ends lie on the box.
    assert (lo_lab == 7).sum() == 1 and (hi_lab == 7).sum() == 1
    assert len(ends) == 2 and all(lab == -1 for _, lab in ends)
    for xy, _ in ends:
        assert abs(xy[0] * math.cos(math.radians(30)) + xy[1] * math.sin(math.radians(30)) - 1.0) < 1e-12


def test_cost_model_reproduces_a_hand_schedule():
    from meshwright.distributed.simulate import fit_costs, model_time

    # One worker ran 4 parts of 1 s (1000 triangles each, 1000 predicted) in rounds lasting
    # 4.5 s, and numbering tasks of 0.1 s each in 0.5 s.
    stats = {
        "workers": 1, "part_seconds": [[(i, 1.0) for i in range(4)]], "part_cpu_seconds": [[(i, 0.5) for i in range(4)]],
        "round_seconds": [4.5], "write_seconds": [0.1] * 4, "resolve_seconds": 0.5,
        "triangles": [1000] * 4, "predicted": [1000.0] * 4,
    }
    k = fit_costs(stats)
    assert k.seconds_per_triangle == pytest.approx(1e-3) and k.cpu_per_triangle == pytest.approx(5e-4)
    assert k.round_overhead == pytest.approx(0.5) and k.resolve_overhead == pytest.approx(0.1)
    # 8 parts of 1000 on 2 workers: 4 s of parts, 0.4 s numbering, overheads and the client's 0.3 s.
    m = model_time(k, [1000.0] * 8, 2, 0.2, 0.3)
    assert m["parts"] == pytest.approx(4.0) and m["total"] == pytest.approx(0.2 + 4.0 + 0.5 + 0.1 + 0.4 + 0.3)
    assert m["bound"] == pytest.approx(m["total"])  # equal parts, equal speeds: nothing to add
    # One part 20 % slower per triangle: the bound adds 20 % of the largest part's 1 s.
    stats["part_seconds"] = [[(0, 1.2)] + [(i, 1.0) for i in range(1, 4)]]
    k = fit_costs(stats)
    m = model_time(k, [1000.0] * 8, 2, 0.2, 0.3)
    assert m["bound"] - m["total"] == pytest.approx(k.rate_spread * k.seconds_per_triangle * 1000.0)
    assert k.rate_spread == pytest.approx(1.2 / 1.05 - 1.0)
    with pytest.raises(InputError, match="stats"):
        fit_costs({"workers": 1})


def test_to_mesh_refuses_more_cells_than_allowed(clients, tmp_path):
    dm = triangulate(_rect(), 0.2, client=clients[1], parts=2, out=tmp_path / "s.xdmf")
    with pytest.raises(MeshingError, match="max_cells = 10"):
        dm.to_mesh(max_cells=10)
    with pytest.raises(InputError, match="max_cells"):
        dm.to_mesh(max_cells=0)


def test_part_above_the_memory_limit_is_refused_before_meshing(clients, tmp_path):
    # About 3e7 triangles in one part: far above 60 % of a 2 GiB worker.
    with pytest.raises(MeshingError, match=r"part 0 would need about .* memory limit"):
        triangulate(_rect(), 0.0005, client=clients[1], parts=1, out=tmp_path / "big.xdmf")


def test_memory_check_counts_the_states_a_worker_keeps():
    from meshwright.distributed.cluster import BYTES_PER_TRIANGLE, MEMORY_FRACTION
    from meshwright.distributed.mesher import _check_memory

    limit = 2**31
    # Parts that fit alone: n triangles at the running peak use 90 % of the budget.
    n = 0.9 * MEMORY_FRACTION * limit / BYTES_PER_TRIANGLE
    _check_memory(np.full(4, n), 4, limit)  # one part per worker: no state kept beside it
    _check_memory(np.full(4, n), 4, 0)  # no limit
    # Two parts per worker: the other part's state does not fit beside the running one.
    with pytest.raises(MeshingError, match=r"part 2 would need .* beside .* states of its worker's other parts"):
        _check_memory(np.array([n / 2, n / 3, n, n / 4]), 2, limit)


@pytest.mark.parametrize(
    "kwargs, error, match",
    [
        ({"parts": 0}, InputError, "parts"),
        ({"parts": "many"}, InputError, "parts"),
        ({"parts": 2.5}, InputError, "parts"),
        ({"client": 42}, InputError, "client"),
        ({"method": "front"}, InputError, "delaunay"),
        ({"method": "nope"}, InputError, "unknown method"),
        ({"max_rounds": -1}, InputError, "max_rounds"),
        ({"seed": -1}, InputError, "seed"),
        ({"seed": np.random.default_rng(0)}, InputError, "Generator"),
        ({"format": "vtu"}, InputError, "format"),
        ({"out": "mesh.vtu"}, InputError, ".xdmf"),
        ({"out": "/no/such/dir/mesh.xdmf"}, InputError, "does not exist"),
        ({"min_angle": 40}, InputError, "min_angle"),
        ({"progress": "yes"}, InputError, "progress"),
        ({"max_points": 1}, InputError, "max_points"),
    ],
)
def test_door_checks_before_any_work(kwargs, error, match):
    with pytest.raises(error, match=match):
        triangulate(_rect(), 0.1, **kwargs)


def test_door_refuses_region_seeds_missing_size_and_bad_domains():
    with pytest.raises(InputError, match="region"):
        triangulate(polygon(RECT, regions=[(0.5, 0.5, 7, None)]), 0.1)
    with pytest.raises(SizeError, match="size"):
        triangulate(_rect(), "boundary")
    with pytest.raises(SizeError):
        triangulate(_rect(), -1.0)
    with pytest.raises(GeometryError):
        triangulate([[0, 0], [1, 1], [1, 0], [0, 1]], 0.1)
    with pytest.raises(InputError, match="parts"):
        decompose(_rect(), 0.1, 0)


def test_decomposition_balances_and_keeps_cut_angles():
    # A graded rectangle balances within the 1.10; so does the disk at 8 parts, where
    # the 60-degree rule forbids cutting near the rim (a line crosses the unit circle at >= 60
    # degrees only within 0.5 of its centre) and cuts split k parts unevenly to stay balanced.
    rect = decompose(_rect(), lambda xy: 0.01 + 0.05 * xy[:, 0], 8)
    assert rect.imbalance <= 1.10 and rect.min_cut_angle == 90.0
    dec = decompose(_disk_with_hole(), _graded, 8)
    assert dec.n_parts == 8
    assert dec.imbalance <= 1.10
    assert dec.min_cut_angle >= 60.0
    # Interface segments have a part on each side; loop segments one part.
    iface = dec.kind == 2
    assert (dec.left[iface] >= 0).all() and (dec.right[iface] >= 0).all()
    assert (dec.left[iface] != dec.right[iface]).all()
    assert (dec.right[~iface] == -1).all() and (dec.left[~iface] >= 0).all()
    assert len(np.unique(dec.points, axis=0)) == len(dec.points)


@pytest.mark.parametrize(
    "extra, match",
    [
        (["--workers", "0", "-o", "x.xdmf"], "--workers must be >= 1"),
        (["--workers", "1", "-o", "x.vtu"], "-o OUT.xdmf"),
        (["--workers", "1", "--scheduler", "tcp://127.0.0.1:1", "-o", "x.xdmf"], "mutually exclusive"),
        (["--workers", "1", "--smooth", "2", "-o", "x.xdmf"], "--smooth"),
    ],
)
def test_cli_refuses_distributed_mistakes_in_one_line(extra, match, capsys):
    from meshwright.cli import main

    assert main(["mesh", "circle", "--size", "0.1", *extra]) == 2
    err = capsys.readouterr().err
    assert match in err and "Traceback" not in err and err.count("\n") == 1
