"""Stress harness for the 2-D meshers (issues 12, 13): random domains through every method.

``make stress`` runs this file; it is not part of ``make test``.  A seeded generator
(:func:`generate`) draws domains of the kinds that break meshers in practice:

* star-shaped outer polygons at random scales (1e-3 .. 1e3) and offsets;
* near-collinear boundary runs (a vertex 1e-9 .. 1e-14 of the edge length off its edge) and
  near-cocircular ones (every radius 1 up to a few ulps);
* tiny features (a vertex pair 1e-6 of the extent apart), spikes (input angles of
  0.5 .. 5 degrees), thin domains (aspect ratio up to 1e4), a hole 1e-6 .. 1e-3 away from
  the outer boundary;
* polygonal holes, interior constraint segments and interior points, each in its own disk
  of an inscribed disk so that no two features cross;
* junctions (kind ``junction``): constraints ending inside a boundary segment or inside
  another constraint, crossing constraints and points on constraints, on coordinates of
  the 2**-20 grid so that the end points lie exactly on their segments (the domain splits
  them as Triangle does);
* sizes: the default (none), ``"boundary"``, a number, a jump of 1e4 inside a small disk
  (a callable), and a stretched background grid (the front honours it; the other methods
  use its isotropic spacing).

Each case (a JSON-safe dict, :func:`build` turns it into a domain and keyword arguments)
runs through every ``triangulate`` method (default) or the chosen ones, ``quadrangulate``
methods included (``--methods pairing zhu paving quadtree``), in a worker process with a
time limit.  A triangle mesh passes when ``Mesh.validate()`` is clean, its area equals the
domain's (polygons: up to round-off) and every input vertex and interior point is a mesh
vertex.  A quad mesh (``all_quad=True``) passes an oracle sharing no code with the
meshers (:func:`quad_oracle`, NumPy only): ``Mesh.validate()``, no cell but quads and
lines, every quad's four corners with a positive scaled Jacobian (strictly convex), the
quads' shoelace areas summing to the polygons' (outer minus holes, to ``AREA_RTOL``) and
every input vertex present.  A quad method's documented refusal of the domain (interior
segments or points it does not honour, ``size="boundary"`` where it needs a size: what its
``QUAD_METHODS`` entry declares; paving's refusal of a stretched background grid, which its
entry does not declare) counts as *refused*, not a failure.  A failure — an
exception of any kind (the domains are valid by construction, so a ``MeshwrightError``
counts too), a broken mesh, a time-out, a worker that dies (a crash in a kernel) — is
written to ``tests/regressions/`` as a reproducer that ``tests/test_regressions.py``
replays: ``"status": "open"`` until fixed (replayed as a strict xfail, so a fix is
noticed; a hang or a crash is not run), then ``"fixed"`` (replayed as a test).

Usage::

    python scripts/stress2d.py --count 2000 --seed 1 [--methods delaunay front] [--kinds junction] [--timeout 60] [--jobs 2] [--start 1500]
    python scripts/stress2d.py --count 400 --seed 12001 --methods pairing zhu paving quadtree

``--jobs N`` runs N worker processes (each compiles the kernels once, then takes one mesh
at a time); the domains drawn depend on ``--seed`` only, not on N.  ``--start K`` resumes a run that
stopped: the first K domains are drawn (so the later draws are the same) but not meshed.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import math
import multiprocessing as mp
import sys
import time
from pathlib import Path

import numpy as np

REGRESSIONS = Path(__file__).resolve().parents[1] / "tests" / "regressions"
AREA_RTOL = 1e-9
KINDS = ("plain", "collinear", "cocircular", "tiny", "spike", "thin", "junction")
GRID = 2.0**-20  # junction cases: every coordinate a multiple of this, so splits at k/8 are exact
JIT_TIMEOUT = 1800.0  # seconds a fresh worker may take to compile every method
SJ_FLOOR = 0.2  # issue 12: quad meshes below this min scaled Jacobian are listed (not failures)


def _star(rng, n, r_lo, r_hi, max_gap=math.pi / 2):
    """n vertices of a star polygon about the origin, no angular gap above ``max_gap``
    (so the disk of radius ``r_lo * cos(max_gap / 2)`` lies inside it)."""
    for _ in range(100):
        ang = np.sort(rng.random(n)) * 2 * math.pi
        gaps = np.diff(np.r_[ang, ang[0] + 2 * math.pi])
        if gaps.max() < max_gap and gaps.min() > 1e-3:
            break
    else:
        ang = np.arange(n) * 2 * math.pi / n
    r = rng.uniform(r_lo, r_hi, n)
    return np.c_[r * np.cos(ang), r * np.sin(ang)]


def _perturb_boundary(rng, outer, kind):
    """Insert a near-collinear run, near-cocircular radii or a tiny feature."""
    n = len(outer)
    if kind == "collinear":
        i = int(rng.integers(n))
        a, b = outer[i], outer[(i + 1) % n]
        k = int(rng.integers(1, 5))
        t = np.sort(rng.uniform(0.1, 0.9, k))
        d = b - a
        nrm = np.array([-d[1], d[0]])
        off = 10.0 ** rng.uniform(-14, -9, k) * rng.choice([-1.0, 0.0, 1.0], k)
        run = a + t[:, None] * d + off[:, None] * nrm
        return np.concatenate([outer[: i + 1], run, outer[i + 1 :]])
    if kind == "cocircular":
        ang = np.arctan2(outer[:, 1], outer[:, 0])
        r = 1.0 + rng.integers(-4, 5, n) * np.finfo(float).eps
        return np.c_[r * np.cos(ang), r * np.sin(ang)]
    if kind == "spike":
        i = int(rng.integers(n))
        a, b = outer[i], outer[(i + 1) % n]
        mid = 0.5 * (a + b)
        tip = mid * (1.0 + 0.5 * np.linalg.norm(b - a) / math.tan(math.radians(rng.uniform(0.5, 5))) / np.linalg.norm(mid))
        return np.concatenate([outer[: i + 1], tip[None], outer[i + 1 :]])
    if kind == "thin":
        return outer * np.array([1.0, 10.0 ** rng.uniform(-4, -2)])
    if kind == "tiny":
        i = int(rng.integers(n))
        a, b = outer[i], outer[(i + 1) % n]
        c = a + 1e-6 * (b - a) / np.linalg.norm(b - a) * rng.uniform(0.5, 2)
        return np.concatenate([outer[: i + 1], c[None], outer[i + 1 :]])
    return outer


def _features(rng, r_in, nholes, nsegs, npts):
    """Holes, segments and points, each inside its own disk within radius ``r_in``."""
    disks = []
    want = nholes + nsegs + npts
    for _ in range(50 * want):
        if len(disks) == want:
            break
        rad = r_in * rng.uniform(0.05, 0.25)
        c = rng.uniform(-1, 1, 2) * (r_in - rad) / math.sqrt(2)
        if all(np.hypot(*(c - d[0])) > rad + d[1] for d in disks):
            disks.append((c, rad))
    holes, segs, pts = [], [], []
    for j, (c, rad) in enumerate(disks):
        if j < nholes:
            holes.append((c + _star(rng, int(rng.integers(3, 9)), 0.4 * rad, 0.9 * rad, math.pi * 0.9)).tolist())
        elif j < nholes + nsegs:
            a = rng.uniform(0, 2 * math.pi)
            k = int(rng.integers(2, 4))
            t = np.linspace(-0.8, 0.8, k) * rad
            line = c + np.c_[t * math.cos(a), t * math.sin(a)]
            if k == 3:
                line[1] += rng.uniform(-0.2, 0.2, 2) * rad
            segs.append(line.tolist())
        else:
            pts.append(c.tolist())
    return holes, segs, pts


def _junctions(rng, outer, r_in):
    """Constraints and points meeting at exact junctions (coordinates on the GRID).

    Returns the snapped outer loop, the constraint polylines and the interior points.
    """
    outer = np.round(outer / GRID) * GRID
    n = len(outer)
    segs, pts = [], []
    for i in rng.choice(n, size=min(n, int(rng.integers(1, 3))), replace=False):
        a, b = outer[i], outer[(i + 1) % n]
        p = a + (b - a) * (int(rng.integers(1, 8)) / 8.0)  # exactly on edge a-b
        segs.append([p.tolist(), (p * (int(rng.integers(3, 10)) / 16.0)).tolist()])  # inward: inside a star
    chords = []
    for _ in range(int(rng.integers(2, 4))):
        ang = rng.uniform(0, 2 * math.pi, 2)
        ends = np.round(0.9 * r_in * np.c_[np.cos(ang), np.sin(ang)] / GRID) * GRID
        chords.append(ends)
        segs.append(ends.tolist())
    for c in chords:
        a, b = c
        ks = rng.permutation(np.arange(1, 8))[:2]
        # One constraint ends on the chord, one point lies on it (different places).
        p = a + (b - a) * (ks[0] / 8.0)
        q = np.round(rng.uniform(-0.5, 0.5, 2) * r_in / GRID) * GRID
        segs.append([q.tolist(), p.tolist()])
        pts.append((a + (b - a) * (ks[1] / 8.0)).tolist())
    return outer, segs, pts


def generate(rng: np.random.Generator, methods) -> dict:
    """One random case: a JSON-safe dict (see the module docstring)."""
    n = int(rng.integers(5, 40))
    outer = _star(rng, n, 0.5, 1.0)
    kind = str(rng.choice(KINDS, p=[0.22, 0.13, 0.13, 0.13, 0.13, 0.13, 0.13]))
    if kind == "cocircular":
        outer = _star(rng, int(rng.integers(8, 200)), 1.0, 1.0)
    outer = _perturb_boundary(rng, outer, kind)
    r_in = 0.5 * math.cos(math.pi / 4) * 0.95
    holes, segs, pts = _features(rng, r_in, int(rng.integers(0, 4)), int(rng.integers(0, 3)), int(rng.integers(0, 3)))
    if kind == "thin":
        holes, segs, pts = [], [], []
    elif kind == "junction":
        holes = []
        outer, segs, pts = _junctions(rng, outer, r_in)
    elif holes and rng.random() < 0.3:
        # a hole pushed to within 1e-6 .. 1e-3 of the outer boundary (invalid draws are
        # refused by the domain's validation and skipped)
        h = np.asarray(holes[0])
        v = outer[int(rng.integers(len(outer)))]
        far = h[np.argmax(h @ v)]
        holes[0] = (h + (v - far) * (1 - 10.0 ** rng.uniform(-6, -3))).tolist()
    scale = float(10.0 ** rng.uniform(-3, 3))
    shift = (rng.uniform(-1, 1, 2) * scale * 10).tolist()
    if kind == "junction":
        # A power of two and no shift keep every junction exact.
        scale, shift = float(2.0 ** int(rng.integers(-10, 11))), [0.0, 0.0]
    size_kind = str(rng.choice(["none", "boundary", "number", "jump", "background"], p=[0.3, 0.1, 0.3, 0.15, 0.15]))
    size = {"kind": size_kind}
    if size_kind in ("number", "jump", "background"):
        size["h"] = float(rng.uniform(0.03, 0.3))
    if size_kind == "jump":
        size["center"] = (outer[int(rng.integers(len(outer)))] if rng.random() < 0.5 else rng.uniform(-1, 1, 2) * 0.3).tolist()
        size["factor"] = 1e-4
    if size_kind == "background":
        size["stretch"] = float(rng.uniform(1, 10))
        size["direction"] = float(rng.uniform(0, math.pi))
    return {
        "kind": kind,
        "outer": outer.tolist(),
        "holes": holes,
        "segments": segs,
        "points": pts,
        "scale": scale,
        "shift": shift,
        "size": size,
        "min_angle": None if rng.random() < 0.5 else float(rng.choice([20.0, 25.0, 30.0])),
        "seed": int(rng.integers(1 << 20)),
        "methods": list(methods),
    }


def _jump_size(h, center, radius, factor):
    def size(xy):
        xy = np.asarray(xy, dtype=np.float64)
        d = np.hypot(xy[..., 0] - center[0], xy[..., 1] - center[1])
        return np.where(d < radius, h * factor, h)

    return size


def build(case: dict, method: str):
    """The domain, keyword arguments and input vertices of ``case`` for ``method``."""
    import meshwright as mw

    s, sh = case["scale"], np.asarray(case["shift"])

    def tr(p):
        return np.asarray(p, dtype=np.float64).reshape(-1, 2) * s + sh

    outer = tr(case["outer"])
    holes = [tr(h) for h in case["holes"]]
    segs = [tr(g) for g in case["segments"]]
    pts = tr(case["points"]) if case["points"] else None
    dom = mw.geometry.polygon(outer, holes=holes, segments=segs, points=pts)
    spec = case["size"]
    if spec["kind"] == "none":
        size = None
    elif spec["kind"] == "boundary":
        size = "boundary"
    elif spec["kind"] == "number":
        size = spec["h"] * s
    elif spec["kind"] == "jump":
        h = spec["h"] * s
        small = h * spec["factor"]
        size = _jump_size(h, tr(spec["center"])[0], 20 * small, spec["factor"])
    else:
        x0, y0, x1, y1 = dom.bbox
        pad = 0.1 * max(x1 - x0, y1 - y0)
        bp = np.array([[x0 - pad, y0 - pad], [x1 + pad, y0 - pad], [x1 + pad, y1 + pad], [x0 - pad, y1 + pad]])
        size = mw.sizing.BackgroundGrid(
            bp, np.array([[0, 1, 2], [0, 2, 3]]), spec["h"] * s, spec["stretch"], spec["direction"]
        )
    kw = {"method": method, "seed": case["seed"]}
    # A door rule, not a failure: frontal-delaunay under a stretched grid refuses min_angle.
    stretched = spec["kind"] == "background" and method == "frontal-delaunay"
    if method in mw.QUAD_METHODS:
        kw["all_quad"] = True  # quadrangulate has no min_angle
    elif case["min_angle"] is not None and mw.MESH_METHODS[method].max_min_angle >= case["min_angle"] and not stretched:
        kw["min_angle"] = case["min_angle"]
    inputs = [outer, *holes, *segs] + ([pts] if pts is not None else [])
    return dom, size, kw, np.concatenate(inputs)


class Refused(Exception):
    """A quad method refused the case at its door for a feature its ``QUAD_METHODS`` entry
    says it does not honour (not a failure)."""


def _refusal(case: dict, method: str) -> str | None:
    """What, by the method's registry entry, makes ``method`` refuse ``case`` (None: nothing)."""
    import meshwright as mw

    m = mw.QUAD_METHODS[method]
    if case["segments"] and not m.segments:
        return "does not honour interior segments"
    if case["points"] and not m.points:
        return "does not honour interior points"
    if case["size"]["kind"] == "boundary" and m.needs_size:
        return "needs a size"
    return None


def _undeclared_refusal(case: dict) -> str | None:
    """The words of a refusal that a method documents but its registry entry does not
    declare: paving's of a stretched background grid (``paving_fill``: "... is not
    honoured; give an isotropic size")."""
    spec = case["size"]
    if spec["kind"] == "background" and spec["stretch"] > 1.0:
        return "is not honoured"
    return None


def _shoelace(loop: np.ndarray) -> float:
    """Unsigned area of a closed (n, 2) loop, about its first vertex (no shift round-off)."""
    d = loop[1:] - loop[0]
    return abs(0.5 * math.fsum(d[:-1, 0] * d[1:, 1] - d[:-1, 1] * d[1:, 0]))


def quad_oracle(points: np.ndarray, cells: dict, outer: np.ndarray, holes: list, inputs: np.ndarray) -> float:
    """The quad mesh checks that do not use meshwright (raise AssertionError on a failure).

    Parameters
    ----------
    points : (n, 2) float64
        The mesh's vertices.
    cells : dict of str to (m, k) int array
        The mesh's cell blocks; only ``"quad"`` and ``"line"`` are allowed.
    outer : (p, 2) float64
        The domain's outer loop; ``holes`` are (q, 2) float64 loops.
    inputs : (r, 2) float64
        Every input vertex (loops, segments, points): each must be a mesh vertex exactly.

    Returns
    -------
    float
        The smallest scaled Jacobian over every quad corner (positive on a pass).
    """
    other = sorted(set(cells) - {"quad", "line"})
    if other:
        raise AssertionError(f"an all-quad mesh has {', '.join(f'{len(cells[t])} {t}' for t in other)} cells")
    quads = np.asarray(cells.get("quad", np.zeros((0, 4), np.int64)), dtype=np.int64)
    if not len(quads):
        raise AssertionError("no quads")
    q = points[quads]  # (m, 4, 2)
    into = q - np.roll(q, 1, axis=1)  # edge arriving at each corner
    out = np.roll(q, -1, axis=1) - q  # edge leaving it
    cross = into[..., 0] * out[..., 1] - into[..., 1] * out[..., 0]
    sj = cross / (np.hypot(into[..., 0], into[..., 1]) * np.hypot(out[..., 0], out[..., 1]))
    bad = np.flatnonzero(~(sj.min(axis=1) > 0))  # NaN (a zero-length side) is bad too
    if len(bad):
        c = int(bad[0])
        raise AssertionError(
            f"{len(bad)} quads not strictly convex, e.g. quad {c} (min scaled Jacobian {sj[c].min()!r}) at "
            + ", ".join(f"({x:.17g}, {y:.17g})" for x, y in q[c])
        )
    # Each quad's area from its diagonals (differences only, so no shift round-off).
    d1, d2 = q[:, 2] - q[:, 0], q[:, 3] - q[:, 1]
    area = 0.5 * math.fsum(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])
    want = _shoelace(outer) - math.fsum(_shoelace(h) for h in holes)
    if not abs(area - want) <= AREA_RTOL * abs(want):
        raise AssertionError(f"quads' area {area!r} != polygons' area {want!r} (rel. {abs(area - want) / want:.3g})")
    pts = points[:, 0] + 1j * points[:, 1]
    missing = inputs[~np.isin(inputs[:, 0] + 1j * inputs[:, 1], pts)]
    if len(missing):
        raise AssertionError(f"{len(missing)} input vertices missing, e.g. {missing[0].tolist()}")
    return float(sj.min())


def sharpest_corner(case: dict) -> float:
    """The smallest angle, in degrees, between the two sides at any vertex of the case's
    outer loop and holes (a quad corner there has a scaled Jacobian of at most its sine:
    issue 12's exception to the 0.2 bound)."""
    out = 180.0
    for loop in [case["outer"], *case["holes"]]:
        p = np.asarray(loop, dtype=np.float64)
        a = np.roll(p, 1, axis=0) - p
        b = np.roll(p, -1, axis=0) - p
        cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
        out = min(out, float(np.degrees(np.abs(np.arctan2(cross, (a * b).sum(axis=1)))).min()))
    return out


def unforced_min_sj(points: np.ndarray, quads: np.ndarray, lines: np.ndarray) -> float:
    """The smallest scaled Jacobian over the quad corners the input does not force.

    A corner whose two sides are both line cells (boundary or segment pieces) has the
    input's own angle there, so a sharp input corner bounds its scaled Jacobian by the
    angle's sine whatever the mesher does (issue 12's exception).  Every other corner
    counts.  NumPy only (no meshwright code).

    Parameters
    ----------
    points : (n, 2) float64
    quads : (m, 4) int
        Counter-clockwise quads.
    lines : (k, 2) int
        The mesh's line cells.

    Returns
    -------
    float
        ``inf`` when every corner is forced.
    """
    quads = np.asarray(quads, dtype=np.int64)
    lines = np.asarray(lines, dtype=np.int64).reshape(-1, 2)
    n = np.int64(len(points))
    keys = np.concatenate([lines[:, 0] * n + lines[:, 1], lines[:, 1] * n + lines[:, 0]])
    prev, nxt = np.roll(quads, 1, axis=1), np.roll(quads, -1, axis=1)
    forced = np.isin(prev * n + quads, keys) & np.isin(quads * n + nxt, keys)
    q = points[quads]
    into = q - np.roll(q, 1, axis=1)
    out = np.roll(q, -1, axis=1) - q
    cross = into[..., 0] * out[..., 1] - into[..., 1] * out[..., 0]
    sj = cross / (np.hypot(into[..., 0], into[..., 1]) * np.hypot(out[..., 0], out[..., 1]))
    free = sj[~forced]
    return float(free.min()) if len(free) else math.inf


def _check_quad(case: dict, method: str) -> tuple[float, float]:
    import meshwright as mw

    dom, size, kw, inputs = build(case, method)
    why = _refusal(case, method)
    try:
        mesh = mw.quadrangulate(dom, size, **kw)
    except mw.InputError as e:
        if why is not None and why in str(e):
            raise Refused(str(e)) from None
        extra = _undeclared_refusal(case)
        if extra is not None and extra in str(e):
            raise Refused(f"{e} (a refusal not declared in QUAD_METHODS)") from None
        raise
    if why is not None:
        raise AssertionError(f"the door accepted a case that the registry says the method refuses ({why})")
    mesh.validate()
    s, sh = case["scale"], np.asarray(case["shift"])
    outer = np.asarray(case["outer"], dtype=np.float64) * s + sh
    holes = [np.asarray(h, dtype=np.float64) * s + sh for h in case["holes"]]
    sj = quad_oracle(mesh.points, mesh.cells, outer, holes, inputs)
    return sj, unforced_min_sj(mesh.points, mesh.quads, mesh.cells.get("line", np.zeros((0, 2), np.int64)))


def check(case: dict, method: str) -> tuple[float, float] | None:
    """Run one method on one case; raise on any failure (see the module docstring), or
    :class:`Refused` where a quad method refuses the case at its door as documented.
    A quad method's pass returns its mesh's smallest scaled Jacobian and the smallest at a
    corner the input does not force (:func:`unforced_min_sj`); None for triangles."""
    import meshwright as mw

    if method in mw.QUAD_METHODS:
        return _check_quad(case, method)
    dom, size, kw, inputs = build(case, method)
    mesh = mw.triangulate(dom, size, **kw)
    mesh.validate()
    area = float(mesh.area())
    want = float(dom.area())
    if not abs(area - want) <= AREA_RTOL * abs(want):
        raise AssertionError(f"mesh area {area!r} != domain area {want!r}")
    # Exact coordinate equality, by complex numbers (NumPy sorts them lexicographically).
    pts = mesh.points[:, 0] + 1j * mesh.points[:, 1]
    missing = inputs[~np.isin(inputs[:, 0] + 1j * inputs[:, 1], pts)]
    if len(missing):
        raise AssertionError(f"{len(missing)} input vertices missing, e.g. {missing[0].tolist()}")


def _worker(conn, methods) -> None:
    import meshwright as mw

    # Compile every method's kernels before the first job, so no time-out counts JIT time.
    square = mw.geometry.polygon([[0, 0], [1, 0], [1, 1], [0, 1]])
    for m in methods:
        if m in mw.QUAD_METHODS:
            mw.quadrangulate(square, 0.3, method=m)
        else:
            mw.triangulate(square, 0.3, method=m)
    conn.send("ready")
    while True:
        job = conn.recv()
        if job is None:
            return
        case, method = job
        t = time.perf_counter()
        try:
            sj = check(case, method)
            conn.send(("ok", "" if sj is None else f"{sj[0]!r} {sj[1]!r}", time.perf_counter() - t))
        except Refused as e:
            conn.send(("refused", str(e)[:2000], time.perf_counter() - t))
        except BaseException as e:  # noqa: BLE001 - every failure is recorded
            conn.send(("fail", f"{type(e).__name__}: {e}"[:2000], time.perf_counter() - t))


class _Worker:
    """One worker process fed one job at a time; killed and restarted after a time-out."""

    def __init__(self, methods):
        self.methods = methods
        self.proc = None
        self.job = None  # (domain index, case, method, deadline) while busy

    def start(self):
        a, b = mp.Pipe()
        self.conn = a
        self.proc = mp.Process(target=_worker, args=(b, self.methods), daemon=True)
        self.proc.start()
        # The child holds its own end; with ours closed, a child that dies reads as EOF
        # here at once (an error in the warm-up waited JIT_TIMEOUT before).
        b.close()
        if not self.conn.poll(JIT_TIMEOUT):
            raise RuntimeError(f"the worker did not compile the kernels in {JIT_TIMEOUT} s")
        try:
            ready = self.conn.recv()
        except EOFError:
            self.proc.join()
            raise RuntimeError(f"the worker died while compiling the kernels (exit code {self.proc.exitcode})") from None
        if ready != "ready":
            raise RuntimeError(f"the worker answered {ready!r} instead of 'ready'")

    def send(self, i, case, method, timeout):
        if self.proc is None or not self.proc.is_alive():
            self.start()
        self.conn.send((case, method))
        self.job = (i, case, method, time.monotonic() + timeout)

    def kill(self):
        self.proc.kill()
        self.proc.join()
        self.proc = None

    def close(self):
        if self.proc is not None and self.proc.is_alive():
            try:
                self.conn.send(None)
            except OSError:  # the worker is gone (it took the interrupt too)
                pass
            self.proc.join(5)
            if self.proc.is_alive():  # busy with a mesh: a run cut short does not wait for it
                self.kill()


def _jobs(rng, args, mw):
    """``(domain index, case, method)`` for every valid drawn domain and method."""
    for i in range(args.count):
        case = generate(rng, args.methods)
        if i < args.start or case["kind"] not in args.kinds:
            continue
        try:
            build(case, args.methods[0])[0].validate()
        except mw.MeshwrightError as e:
            print(f"[{i}] generator produced an invalid domain, skipped: {e}")
            continue
        for method in args.methods:
            yield i, case, method


def _run_all(jobs, workers, timeout, report) -> None:
    """Feed ``jobs`` to the idle ``workers``; ``report(i, case, method, status, msg)`` for
    each result, a worker past ``timeout`` seconds being killed (its job a failure).

    A job that times out runs once more in a fresh worker before it counts: the warm-up
    compiles only what a square needs, and a kernel a case reaches first compiles inside
    its time limit (30-90 s each on a loaded machine: seed 13004's paving run timed out
    9 cases that mesh in 0.2-21 s CPU once compiled); the compiled code is cached by
    then, so a second time-out is the case's own."""
    from multiprocessing.connection import wait

    pending = iter(jobs)
    again = []  # jobs that timed out once
    retried = set()
    more = True
    while True:
        for w in workers:
            if w.job is None and (again or more):
                nxt = again.pop() if again else next(pending, None)
                if nxt is None:
                    more = False
                else:
                    w.send(*nxt, timeout)
        busy = [w for w in workers if w.job is not None]
        if not busy:
            return
        left = min(w.job[3] for w in busy) - time.monotonic()
        ready = wait([w.conn for w in busy], timeout=max(left, 0.0))
        for w in busy:
            i, case, method, deadline = w.job
            if w.conn in ready:
                try:
                    status, msg, _ = w.conn.recv()
                except (EOFError, ConnectionError):
                    # The worker died mid-job (a segfault in a kernel, the OOM killer): a
                    # failure of this job; the next send starts a fresh worker.
                    w.proc.join()
                    status, msg = "fail", f"Crash: the worker died (exit code {w.proc.exitcode})"
                    w.proc = None
            elif time.monotonic() >= deadline:
                w.kill()
                if (i, method) not in retried:
                    retried.add((i, method))
                    again.append((i, case, method))
                    w.job = None
                    continue
                status, msg = "fail", f"Timeout: no result in {timeout} s (twice)"
            else:
                continue
            w.job = None
            report(i, case, method, status, msg)


def record(case: dict, method: str, message: str) -> Path:
    """Write a reproducer for ``case`` under ``method`` (idempotent: named by its hash)."""
    body = {"case": case, "method": method}
    key = hashlib.sha1(json.dumps(body, sort_keys=True).encode()).hexdigest()[:12]
    path = REGRESSIONS / f"stress-{method}-{key}.json"
    if not path.exists():
        REGRESSIONS.mkdir(exist_ok=True)
        body.update(status="open", error=message, hang=message.startswith("Timeout"))
        if message.startswith("Crash"):
            body["crash"] = True  # replayed in-process it would kill the test run
        path.write_text(json.dumps(body, indent=1) + "\n")
    return path


def main(argv=None) -> int:
    import meshwright as mw

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--count", type=int, default=1000, help="number of domains")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--methods", nargs="*", choices=sorted(mw.MESH_METHODS) + sorted(mw.QUAD_METHODS),
                    default=sorted(mw.MESH_METHODS),
                    help="triangulate methods (default: all of them) and / or quadrangulate methods")
    ap.add_argument("--all-methods", action="store_true",
                    help="every triangulate and every quadrangulate method (overrides --methods)")
    ap.add_argument("--timeout", type=float, default=60.0, help="seconds per mesh before it counts as a hang")
    ap.add_argument("--jobs", type=int, default=1, help="worker processes (one core each)")
    ap.add_argument("--kinds", nargs="*", choices=KINDS, default=list(KINDS),
                    help="run only the domains of these kinds (the same draws as a full run)")
    ap.add_argument("--start", type=int, default=0,
                    help="draw but skip the domains before this index (resume a run: the same draws)")
    ap.add_argument("--no-record", action="store_true", help="report failures without writing reproducers")
    args = ap.parse_args(argv)
    if args.all_methods:
        args.methods = sorted(mw.MESH_METHODS) + sorted(mw.QUAD_METHODS)
    if args.jobs < 1:
        ap.error(f"--jobs must be at least 1, got {args.jobs}")
    if not 0 <= args.start <= args.count:
        ap.error(f"--start must be in [0, --count], got {args.start}")
    rng = np.random.default_rng(args.seed)
    workers = [_Worker(args.methods) for _ in range(args.jobs)]
    tally = {"runs": 0, "fails": 0, "domains": set(), "low": []}
    per = {m: {"ok": 0, "refused": 0, "fail": 0} for m in args.methods}
    t0 = time.perf_counter()

    def report(i, case, method, status, msg):
        tally["runs"] += 1
        per[method][status] += 1
        if status == "ok" and msg and float(msg.split()[0]) < SJ_FLOOR:
            sj, free = (float(x) for x in msg.split())
            corner = sharpest_corner(case)
            tally["low"].append((sj, i, method, corner, free))
            print(f"[{i}] {method} ({case['kind']}, size {case['size']['kind']}): min SJ {sj:.3g}, "
                  f"{free:.3g} at corners the input does not force, sharpest input corner {corner:.3g} degrees",
                  flush=True)
        if status == "fail":
            tally["fails"] += 1
            where = "" if args.no_record else f" -> {record(case, method, msg).name}"
            print(f"[{i}] {method} ({case['kind']}, size {case['size']['kind']}): {msg[:200]}{where}", flush=True)
        tally["domains"].add(i)
        if tally["runs"] % (100 * len(args.methods)) == 0:
            print(f"{len(tally['domains'])} domains, {tally['runs']} meshes, {tally['fails']} failures, "
                  f"{time.perf_counter() - t0:.0f} s", flush=True)

    stopped = False
    try:
        _run_all(_jobs(rng, args, mw), workers, args.timeout, report)
    except KeyboardInterrupt:
        # A run cut short (Ctrl-C, `timeout -s INT`) still reports what it meshed.
        stopped = True
    finally:
        for w in workers:
            w.close()
    if stopped:
        last = max(tally["domains"], default=-1)
        print(f"interrupted: {len(tally['domains'])} domains meshed (highest index {last}), {tally['runs']} "
              f"meshes, {tally['fails']} failures in {time.perf_counter() - t0:.0f} s")
    else:
        print(f"done: {args.count} domains drawn, {len(tally['domains'])} meshed, {tally['runs']} meshes, "
              f"{tally['fails']} failures in {time.perf_counter() - t0:.0f} s")
    for m, c in per.items():
        low = sorted(sj for sj, _, mm, _, _ in tally["low"] if mm == m)
        sharp = math.degrees(math.asin(SJ_FLOOR))
        free = sum(1 for _, _, mm, corner, _ in tally["low"] if mm == m and corner >= sharp)
        unforced = sorted(f for _, _, mm, _, f in tally["low"] if mm == m and f < SJ_FLOOR)
        under = (f", {len(low)} under min SJ {SJ_FLOOR} (lowest {low[0]:.3g}; {free} of them with no input "
                 f"corner under {sharp:.1f} degrees; {len(unforced)} under it at a corner the input does not "
                 f"force{f', lowest {unforced[0]:.3g}' if unforced else ''})") if low else ""
        print(f"  {m}: {c['ok']} meshed, {c['refused']} refused, {c['fail']} failed{under}")
    return 1 if tally["fails"] else 0


if __name__ == "__main__":
    sys.exit(main())
