"""``meshwright.distributed.triangulate``: decompose, mesh the parts on Dask workers, exchange, write.

Sources: L. Linardakis and N. Chrisochoides, "Delaunay decoupling method for parallel
guaranteed quality planar mesh refinement", SIAM J. Sci. Comput. 27(4), 2006 (parts meshed
independently by the serial code between pre-discretised separators); A. Chernikov and
N. Chrisochoides, "Parallel 2D constrained Delaunay mesh generation", ACM TOMS 34(1), 2008
(interface splits as messages, here deterministic rounds); the dask.distributed documentation
("Futures": data stays on the worker that made it, and tasks that depend on it run there).

Pipeline (client work is O(boundary + parts + interface splits); mesh bytes never reach
the client)::

    door checks --> decompose (client) --> round 0: one task per part (largest first): CDT,
            refinement with the interfaces frozen, the splits it needed made and reported;
            the part's state stays on its worker as a future, a small report comes back
        --> while a part lacks a split its neighbour made: exchange (client), and only those
            parts resume from their state (round r, at most max_rounds)
        --> numbering (split points after the skeleton, prefix sums of the own point counts)
        --> one task per part, where its state is: global ids, piece written
        --> client writes skeleton, VDS, XDMF

Tasks: parts (+ the resumed parts of exchange rounds) + one report task per part and round +
parts (writing); the client waits on one ``gather`` per phase.  Every state is kept until
the pieces are written (a neighbour's later split may need it); Dask counts its bytes
(``PartState.__sizeof__``) against the worker's memory and may spill it.  A worker lost
mid-run makes Dask run again the tasks whose results it held, from the same inputs.

Determinism: part ``i`` is meshed with the seed ``SeedSequence([seed, i])`` gives, from a
planar straight-line graph that depends only on the decomposition; the splits of a round
depend only on the states, so the files are the same bytes for any number of workers and on
reruns (fixed ``parts`` and ``seed``).
"""

from __future__ import annotations

import os
import tempfile
import time
import uuid
from pathlib import Path

import numpy as np

from meshwright.core.errors import InputError, MeshingError, MeshwrightError, SizeError
from meshwright.core.mesh import Mesh
from meshwright.core.validate_input import check_count, check_flag, check_seed
from meshwright.distributed import cluster as _cluster
from meshwright.distributed.exchange import Splits
from meshwright.distributed.numbering import part_offsets
from meshwright.distributed.part import (
    report_of,
    resume_part,
    start_part,
    write_part_state,
)
from meshwright.distributed.partition import decompose_domain, part_pslg
from meshwright.distributed.simulate import lpt_makespan
from meshwright.distributed.writer import part_path, read_mesh_arrays, write_mesh
from meshwright.tri.mesher import (
    DEFAULT_MAX_POINTS,
    MESH_METHODS,
    _domain_and_field,
    _min_angle,
)

__all__ = ["DEFAULT_MAX_CELLS", "FORMATS", "PARTS_PER_WORKER", "DistributedMesh", "decompose", "triangulate"]

FORMATS = ("xdmf",)
DEFAULT_MAX_CELLS = 10_000_000  # to_mesh: about 1.5 GB in one process
PARTS_PER_WORKER = 4  # over-decomposition of parts="auto"


class DistributedMesh:
    """The result of :func:`triangulate`: files on disk and their statistics, not the arrays.

    Attributes
    ----------
    path : str
        The XDMF file.
    files : list of str
        XDMF, the stitching HDF5 file, then the part pieces in part order.
    n_points, n_cells : int
        Vertices and triangles of the whole mesh.
    stats : dict
        ``parts``, ``workers``, ``rounds``, ``seconds`` (decompose, mesh, write, total),
        ``part_seconds`` (one list per round: ``(part, seconds)`` of its meshing or resuming
        task), ``part_cpu_seconds`` (the same with the tasks' CPU seconds), ``round_seconds``
        (client wall time of each round: submit to the last report), ``resumed_parts`` (per
        exchange round), ``resolve_seconds`` (wall time of the writing tasks),
        ``client_write_seconds`` (the client's skeleton, virtual datasets and XDMF),
        ``peak_rss`` (largest peak resident memory of a worker that ran a part, bytes),
        ``memory_limit`` (the smallest worker limit, 0 when unset), ``state_bytes`` (the
        largest part state kept between rounds), ``write_seconds`` and ``write_cpu_seconds``
        (per part: numbering and writing its piece), ``triangles`` and ``predicted`` per
        part, ``imbalance`` (largest part's triangles over the mean), ``worker_imbalance``
        (the largest worker's triangles over the mean when the parts are dealt to the workers
        largest first, as they are submitted: what E(P) pays), ``predicted_imbalance``,
        ``min_angle``, ``min_cut_angle``, ``skeleton_points``, ``split_points`` (interface
        points added by the rounds), ``triangles_over_predicted`` (total over the serial
        prediction), ``bytes_written``.
    """

    def __init__(self, path: str, files: list[str], n_points: int, n_cells: int, stats: dict):
        self.path, self.files, self.n_points, self.n_cells, self.stats = path, files, n_points, n_cells, stats

    def __repr__(self) -> str:
        return (
            f"DistributedMesh({self.n_points} points, {self.n_cells} triangles, {self.stats['parts']} parts, "
            f"{self.stats['rounds']} exchange rounds, {self.path!r})"
        )

    def to_mesh(self, max_cells: int = DEFAULT_MAX_CELLS) -> Mesh:
        """The whole mesh in this process, read from the files; refused above ``max_cells``.

        Parameters
        ----------
        max_cells : int
            Largest number of triangles to load.

        Returns
        -------
        Mesh
            ``"triangle"`` and ``"line"`` cells (int32) with ``cell_data["marker"]`` and
            ``point_data["marker"]``, as :func:`meshwright.triangulate` returns.

        Raises
        ------
        InputError
            ``max_cells`` not a positive integer.
        MeshingError
            More triangles than ``max_cells`` (or than int32 ids can hold).
        """
        cap = check_count(max_cells, "max_cells", 1)
        if self.n_cells > cap or self.n_points >= 2**31:
            raise MeshingError(
                f"the mesh has {self.n_cells} triangles and {self.n_points} points, above max_cells = {cap} "
                f"(or int32 ids); read the pieces of {self.path} part by part instead"
            )
        a = read_mesh_arrays(Path(self.path))
        return Mesh(
            a["points"],
            {"triangle": a["cells"].astype(np.int32), "line": a["lines"].astype(np.int32)},
            point_data={"marker": a["point_marker"]},
            cell_data={"marker": {"triangle": a["cell_marker"], "line": a["line_marker"]}},
        )


def _check_domain(domain, size):
    """The Domain and size field, refusing what the distributed path cannot honour."""
    dom, field = _domain_and_field(domain, size, False, None, False)
    if field is None:
        raise SizeError(
            "distributed meshing needs a size (a number, a callable h(xy) or a SizeField): its interfaces "
            "are discretised from it before meshing; 'boundary' names no spacing away from the boundary"
        )
    if dom.regions:
        raise InputError(
            f"the domain has {len(dom.regions)} region seed(s); distributed meshing does not split regions "
            "across parts yet: mesh it with meshwright.triangulate"
        )
    return dom, field


def _check_parts(parts) -> int | None:
    if isinstance(parts, str):
        if parts != "auto":
            raise InputError(f"parts must be 'auto' or an integer >= 1, got {parts!r}")
        return None
    return check_count(parts, "parts", 1)


def decompose(domain, size, parts: int):
    """The decomposition :func:`triangulate` would mesh (for inspection and plots).

    Parameters
    ----------
    domain : Domain, str, path or (n, 2) array_like
        As :func:`meshwright.triangulate` takes it (no region seeds).
    size : number, callable or SizeField
        The target edge length (required).
    parts : int
        Number of parts, at least 1.

    Returns
    -------
    Decomposition
        See :mod:`meshwright.distributed.partition`.

    Raises
    ------
    InputError, GeometryError, SizeError
        As :func:`triangulate`'s door.
    MeshingError
        No admissible cut position.
    """
    p = check_count(parts, "parts", 1)
    if size is None:
        raise SizeError("decompose needs a size: the cuts are balanced and discretised by it")
    dom, field = _check_domain(domain, size)
    return decompose_domain(dom, field, p)


def _check_out(out) -> Path | None:
    if out is None:
        return None
    if not isinstance(out, (str, os.PathLike)):
        raise InputError(f"out must be a path ending in .xdmf or None, got {type(out).__name__}")
    path = Path(out)
    if path.suffix.lower() != ".xdmf":
        raise InputError(f"out {str(out)!r} must end in .xdmf (the only format written: {', '.join(FORMATS)})")
    if not path.parent.is_dir():
        raise InputError(f"out {str(out)!r}: directory {str(path.parent)!r} does not exist")
    return path


def _gather(c, futures: dict, what: str, progress: bool = False) -> dict:
    """Results of futures (one ``gather``), keyed as given; a part's failure is re-raised naming it.

    A worker lost three times on one task (``KilledWorker``: dask's nanny ends a worker above
    95 % of its memory limit) becomes a :class:`MeshingError` naming the part.
    """
    from distributed import KilledWorker

    keys = sorted(futures)
    if progress:
        from distributed import as_completed
        from tqdm import tqdm

        for _ in tqdm(as_completed([futures[k] for k in keys]), total=len(keys), desc=what, leave=False):
            pass
    try:
        values = c.gather([futures[k] for k in keys], errors="raise")
    except (MeshwrightError, KilledWorker) as exc:
        failed = [k for k in keys if futures[k].status == "error"]
        name = f"part {failed[0]}" if failed else "a part"
        if isinstance(exc, KilledWorker):
            raise MeshingError(
                f"{name} ({what}): every worker that ran it died (dask gave up after its allowed failures; "
                "out of memory?); use more parts or workers with more memory"
            ) from None
        raise type(exc)(f"{name} ({what}): {exc}") from exc
    return dict(zip(keys, values))


def triangulate(
    domain,
    size=None,
    *,
    client=None,
    parts="auto",
    min_angle: float | None = 30.0,
    method: str = "delaunay",
    seed: int = 0,
    out=None,
    format: str = "xdmf",
    max_rounds: int = 4,
    progress: bool = False,
    max_points: int | None = None,
) -> DistributedMesh:
    """Quality triangle mesh of a 2-D domain meshed in parts on Dask workers, written as XDMF/HDF5.

    Every argument is checked here before any work (the client's workers are contacted only
    after the others pass).

    Parameters
    ----------
    domain : Domain, str, path or (n, 2) array_like
        As :func:`meshwright.triangulate`; region seeds (and so islands) are not supported.
    size : number, callable or SizeField, optional
        Target edge length; default the domain's own, else its local feature size, graded.
    client : distributed.Client, str or None
        A client, a scheduler address, or None: the default client if one exists, else a
        local cluster of single-threaded processes (closed on return).
    parts : "auto" or int
        Number of parts; ``"auto"`` is :data:`PARTS_PER_WORKER` per worker.
    min_angle : float, optional
        Degrees, up to the serial mesher's 33.8 (None: its default 30).
    method : str
        ``"delaunay"`` only (the refinement whose interface splits the exchange reproduces).
    seed : int
        Non-negative; part ``i`` uses a seed derived from ``(seed, i)``.
    out : path, optional
        ``NAME.xdmf``; the pieces go next to it (:mod:`meshwright.distributed.writer`), on a
        file system the workers share.  Default: a new temporary directory.
    format : str
        ``"xdmf"`` (XDMF3 over HDF5 virtual datasets).
    max_rounds : int
        Most exchange rounds; one more needed raises :class:`MeshingError`.
    progress : bool
        A progress bar over the parts of each round.
    max_points : int, optional
        Cap on every part's vertices (default :data:`meshwright.tri.mesher.DEFAULT_MAX_POINTS`).

    Returns
    -------
    DistributedMesh

    Raises
    ------
    InputError
        A malformed argument (named), an unsupported method or format, region seeds, dask or
        h5py missing, an unreachable scheduler.
    GeometryError, SizeError, FormatError
        As :func:`meshwright.triangulate`'s door.
    MeshingError
        A part predicted to need, beside the states of the other parts its worker keeps,
        more than 60 % of a worker's memory limit (part, bytes and limit named), more than
        ``max_rounds`` exchange rounds, a part hitting ``max_points``
        (part named), or no cut position.
    """
    if not isinstance(method, str) or method not in MESH_METHODS:
        raise InputError(f"unknown method {method!r}; choose one of {', '.join(sorted(MESH_METHODS))}")
    if method != "delaunay":
        raise InputError(
            f"distributed meshing runs method 'delaunay' only (its interface splits are the midpoints the "
            f"exchange reproduces), got {method!r}"
        )
    angle = _min_angle(MESH_METHODS[method], min_angle)
    seed = check_seed(seed)
    if isinstance(seed, np.random.Generator):
        raise InputError("seed must be a non-negative integer here: a Generator cannot be shared by workers")
    n_parts = _check_parts(parts)
    out_path = _check_out(out)
    if not isinstance(format, str) or format not in FORMATS:
        raise InputError(f"format must be one of {', '.join(FORMATS)}, got {format!r}")
    rounds_cap = check_count(max_rounds, "max_rounds", 0)
    progress = check_flag(progress, "progress")
    cap = DEFAULT_MAX_POINTS if max_points is None else check_count(max_points, "max_points", 3)
    _cluster._require_distributed()
    from distributed import Client

    if client is not None and not isinstance(client, (Client, str)):
        raise InputError(
            f"client must be a distributed.Client, a scheduler address or None, got {type(client).__name__}"
        )
    dom, field = _check_domain(domain, size)
    if out_path is None:
        out_path = Path(tempfile.mkdtemp(prefix="meshwright-")) / "mesh.xdmf"
    with _cluster.resolve_client(client) as c:
        return _run(c, dom, field, n_parts, angle, seed, out_path, rounds_cap, progress, cap)


def _check_memory(predicted: np.ndarray, workers: int, limit: int) -> None:
    """Refuse parts that would not fit their worker (``limit`` bytes, 0: no limit).

    A worker meshes one part while it keeps the states of the others it was dealt (up to
    ``ceil(parts / workers)``, all kept until the pieces are written): the largest part's
    peak (:data:`~meshwright.distributed.cluster.BYTES_PER_TRIANGLE`) plus the states of the
    next largest (:data:`~meshwright.distributed.cluster.STATE_BYTES_PER_TRIANGLE`) must fit
    in :data:`~meshwright.distributed.cluster.MEMORY_FRACTION` of the limit.

    Parameters
    ----------
    predicted : (p,) float64
        Predicted triangles per part.
    workers : int
    limit : int
    """
    order = np.argsort(-predicted, kind="stable")
    i = int(order[0])
    need = predicted[i] * _cluster.BYTES_PER_TRIANGLE
    kept = predicted[order[1 : -(-len(predicted) // workers)]].sum() * _cluster.STATE_BYTES_PER_TRIANGLE
    if limit and need + kept > _cluster.MEMORY_FRACTION * limit:
        raise MeshingError(
            f"part {i} would need about {need / 2**20:.0f} MiB ({predicted[i]:.3g} triangles at "
            f"{_cluster.BYTES_PER_TRIANGLE} B) beside {kept / 2**20:.0f} MiB of the states of its worker's other "
            f"parts ({_cluster.STATE_BYTES_PER_TRIANGLE} B a triangle) but a worker's memory limit is "
            f"{limit / 2**20:.0f} MiB (a part may use {_cluster.MEMORY_FRACTION:.0%}); use more workers or "
            "workers with more memory"
        )


def _identity(x):
    return x


def _run(c, dom, field, n_parts, angle, seed, out_path, rounds_cap, progress, cap) -> DistributedMesh:
    t_start = time.perf_counter()
    workers = len(c.scheduler_info()["workers"])
    if workers == 0:
        raise MeshingError("the dask cluster has no workers")
    P = PARTS_PER_WORKER * workers if n_parts is None else n_parts
    dec = decompose_domain(dom, field, P)
    t_dec = time.perf_counter() - t_start
    limit = _cluster.worker_memory_limit(c)
    _check_memory(dec.predicted, workers, limit)
    token = uuid.uuid4().hex[:12]
    n_curves = len(dom.curves)
    # Tasks holding the curves and the field, not scattered data: Dask can compute them again
    # if every worker that held them dies.
    curves_f = c.submit(_identity, dom.curves, key=f"meshwright-{token}-curves", pure=False)
    field_f = c.submit(_identity, field, key=f"meshwright-{token}-field", pure=False)
    seeds = [int(np.random.SeedSequence([seed, i]).generate_state(1)[0]) for i in range(P)]
    part_seconds, part_cpu, round_walls = [], [], []
    splits = Splits(dec)
    reports = {}
    # Round 0, largest parts first: every part's state stays on its worker as a future.
    states = {
        i: c.submit(
            start_part, part_pslg(dec, i, n_curves), curves_f, field_f, angle, seeds[i], cap,
            key=f"meshwright-{token}-part-r0-{i}", pure=False,
        )
        for i in np.argsort(-dec.predicted, kind="stable").tolist()
    }
    t_mesh = time.perf_counter()
    todo = {i: None for i in states}
    rounds = 0
    while True:
        t_round = time.perf_counter()
        done = _gather(c, {i: c.submit(report_of, states[i], key=f"meshwright-{token}-report-r{rounds}-{i}")
                           for i in todo}, f"round {rounds}", progress)
        round_walls.append(time.perf_counter() - t_round)
        for i in sorted(done):
            splits.add(i, done[i].splits, done[i].xy)
        reports.update(done)
        part_seconds.append([(i, done[i].seconds) for i in sorted(done)])
        part_cpu.append([(i, done[i].cpu_seconds) for i in sorted(done)])
        todo = splits.lacking()
        if not todo:
            break
        if rounds >= rounds_cap:
            i, first = next(iter(todo.items()))
            s = first[0][0]
            raise MeshingError(
                f"interfaces still need splits after {rounds} exchange rounds (max_rounds = {rounds_cap}): "
                f"{len(todo)} part(s), e.g. part {i} on skeleton segment {s} from "
                f"{dec.points[dec.segments[s, 0]].tolist()}; raise max_rounds or use fewer parts"
            )
        rounds += 1
        # Only the parts beside a new split resume; the others' states stay as they are.
        for i, lack in todo.items():
            states[i] = c.submit(resume_part, states[i], lack, key=f"meshwright-{token}-part-r{rounds}-{i}",
                                 pure=False)
    t_mesh = time.perf_counter() - t_mesh
    t_write = time.perf_counter()
    split_ids, split_xy = splits.numbered(len(dec.points))
    n_skeleton = len(dec.points) + len(split_xy)
    offsets = part_offsets(n_skeleton, [reports[i].n_own for i in range(P)])
    # One task per part, where its state is: global ids, then the piece.
    writes = {
        i: c.submit(
            write_part_state, states[i], splits.of_part(i, split_ids), int(offsets[i]), str(part_path(out_path, i)),
            key=f"meshwright-{token}-write-{i}", pure=False,
        )
        for i in range(P)
    }
    pieces_d = _gather(c, writes, "writing")
    del states, writes
    t_resolve = time.perf_counter() - t_write
    pieces = [pieces_d[i] for i in range(P)]
    t_client = time.perf_counter()
    points = np.concatenate([dec.points, split_xy])
    markers = np.concatenate([dec.point_markers, np.zeros(len(split_xy), dtype=np.int32)])
    files = write_mesh(out_path, points, markers, pieces) + [p.path for p in pieces]
    t_client = time.perf_counter() - t_client
    # Attempts of tasks that lost their worker leave temporary files behind.
    for tmp in out_path.parent.glob(f"{out_path.stem}_part*.h5.*.tmp"):
        tmp.unlink(missing_ok=True)
    t_write = time.perf_counter() - t_write
    tris = np.array([p.n_triangles for p in pieces], dtype=np.int64)
    n_points = n_skeleton + sum(p.n_points for p in pieces)
    stats = {
        "parts": P,
        "workers": workers,
        "rounds": rounds,
        "seconds": {
            "decompose": t_dec, "mesh": t_mesh, "write": t_write, "total": time.perf_counter() - t_start,
        },
        "part_seconds": part_seconds,
        "part_cpu_seconds": part_cpu,
        "round_seconds": round_walls,
        "resolve_seconds": t_resolve,
        "client_write_seconds": t_client,
        "peak_rss": int(max(max(r.peak_rss for r in reports.values()), max(p.peak_rss for p in pieces))),
        "memory_limit": int(limit),
        "state_bytes": int(max(r.state_bytes for r in reports.values())),
        "write_seconds": [p.seconds for p in pieces],
        "write_cpu_seconds": [p.cpu_seconds for p in pieces],
        "triangles": tris.tolist(),
        "predicted": dec.predicted.tolist(),
        "imbalance": float(tris.max() / tris.mean()),
        "worker_imbalance": float(lpt_makespan(tris, workers) * workers / tris.sum()) if tris.sum() else 1.0,
        "predicted_imbalance": dec.imbalance,
        "min_angle": float(min(p.min_angle for p in pieces)),
        "min_cut_angle": dec.min_cut_angle,
        "skeleton_points": len(dec.points),
        "split_points": len(split_xy),
        "resumed_parts": [sorted(i for i, _ in r) for r in part_seconds[1:]],
        "triangles_over_predicted": float(tris.sum() / dec.predicted.sum()),
        "bytes_written": int(sum(os.path.getsize(f) for f in files)),
    }
    return DistributedMesh(str(out_path), files, int(n_points), int(tris.sum()), stats)
