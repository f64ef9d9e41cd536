"""Dask clients for distributed meshing: resolving the ``client`` argument, local clusters, warming.

Source: the dask.distributed documentation ("Client", "LocalCluster", "Worker memory
management": spill at 60 %, pause at 80 %, terminate at 95 % of ``memory_limit``), and the
Numba cache practice of OasisLMF/OasisPlatform#1398: compile once in one process, then let the
other workers load the cache (several workers building one cache at once can crash,
numba/numba#4807).

Workers are single-threaded processes (the long meshing kernels are ``nogil``, so a worker's
event loop keeps answering the scheduler's heartbeats while a part meshes).  A local cluster
is started under :data:`LOCAL_CLUSTER_CONFIG` (dask's documented configuration keys): with
dask's defaults every worker samples its task thread's stack 100 times a second for the
dashboard's profile, and every server checks its event loop 50 times a second and its memory
10 times; on a 2-core machine the idle 1- and 2-worker clusters of a benchmark took 0.18 of a
core that way, 0.02 with this configuration, and while two workers mesh each worker's event
loop thread took 4-6 % of a core (0.5 % without).  Apply the same keys to a cluster of your own
(``dask.config.set(LOCAL_CLUSTER_CONFIG)`` before starting it, or its YAML file).

Memory a Numba task allocates is unmanaged (it cannot spill), so a part must fit in
:data:`MEMORY_FRACTION` of its worker's ``memory_limit``; :func:`worker_memory_limit` reads the
smallest limit of a cluster.  The part states kept between exchange rounds are task results:
managed memory, counted by their ``__sizeof__`` (Dask may spill them); the check before
meshing counts the states of the other parts a worker keeps (:data:`STATE_BYTES_PER_TRIANGLE`)
beside the part it meshes.
"""

from __future__ import annotations

import contextlib
import copy
import os

from meshwright.core.errors import InputError
from meshwright.core.validate_input import check_count

__all__ = [
    "BYTES_PER_TRIANGLE", "LOCAL_CLUSTER_CONFIG", "MEMORY_FRACTION", "STATE_BYTES_PER_TRIANGLE", "local_cluster",
    "resolve_client", "warm", "worker_memory_limit",
]

MEMORY_FRACTION = 0.6  # largest share of a worker's memory_limit a part may need
# Peak resident bytes per triangle of one part's task (CDT, refinement, references, piece) over
# a warmed worker's memory: 407 B measured on 1.5e6-triangle parts (a rectangle and the graded
# disk); the arrays grown by doubling are briefly held twice.
BYTES_PER_TRIANGLE = 420
# A part's state kept between exchange rounds (its CDT, trimmed by ``shrink``): 60 B per
# triangle measured on the rectangle and the graded disk (2.5e5-triangle parts); 88-271 B
# before the trim, the refinement's spare room.  Counted with a margin.
STATE_BYTES_PER_TRIANGLE = 96
# The dask configuration of the local clusters started here (module docstring): what the
# workers would spend on the dashboard's profiler and on frequent checks goes to the parts.
LOCAL_CLUSTER_CONFIG = {
    "distributed.worker.profile.enabled": False,  # 100 Hz stack sampling of the task thread
    "distributed.admin.tick.interval": "1s",  # event-loop blocking check, every 20 ms by default
    "distributed.admin.system-monitor.interval": "5s",  # dashboard's CPU / memory / network series
    "distributed.worker.memory.monitor-interval": "500ms",  # spill / pause / terminate checks (100 ms)
}


def _require_distributed():
    try:
        import distributed  # noqa: F401
        import h5py  # noqa: F401
    except ImportError as exc:
        raise InputError(
            f"distributed meshing needs dask.distributed and h5py ({exc.name} is missing): "
            "pip install 'meshwright[distributed]'"
        ) from None


def local_cluster(n_workers: int | None = None, memory_limit="auto"):
    """A ``LocalCluster`` of single-threaded worker processes and its ``Client``.

    Parameters
    ----------
    n_workers : int, optional
        Default: the number of CPUs.
    memory_limit : str or int
        Per worker, as dask takes it (``"auto"``, ``"2GiB"``, bytes).

    Returns
    -------
    distributed.Client
        Closing it (or leaving its ``with`` block) also closes the cluster.  Scheduler,
        nannies and workers run under :data:`LOCAL_CLUSTER_CONFIG` (a nanny hands the
        configuration it was created with to the worker process it starts, and restarts).
    """
    _require_distributed()
    import dask
    from distributed import Client

    n = (os.cpu_count() or 1) if n_workers is None else check_count(n_workers, "n_workers", 1)
    with dask.config.set(LOCAL_CLUSTER_CONFIG):
        # A nanny merges the configuration it is given over dask's global one, one level deep,
        # and hands the result to every worker process it (re)starts: a copy of the whole
        # "distributed" section outlives this block (dask.config.set restores the global
        # section in place on exit, which a worker restarted later would otherwise see).
        workers = {"distributed": copy.deepcopy(dask.config.get("distributed"))}
        # A client given cluster keywords owns the LocalCluster it starts and closes it with itself.
        return Client(
            n_workers=n, threads_per_worker=1, processes=True, memory_limit=memory_limit, dashboard_address=":0",
            config=workers,
        )


@contextlib.contextmanager
def resolve_client(client):
    """The client to use, as a context: an existing ``Client``, a scheduler address, or None.

    None takes the default client if one exists, else starts a :func:`local_cluster` that is
    closed on exit.  An address connects a client that is closed on exit.

    Raises
    ------
    InputError
        ``client`` of another type, dask.distributed or h5py missing, or an address that does
        not answer (named).
    """
    _require_distributed()
    from distributed import Client, default_client

    if client is not None and not isinstance(client, (Client, str)):
        raise InputError(
            f"client must be a distributed.Client, a scheduler address or None, got {type(client).__name__}"
        )
    if isinstance(client, Client):
        yield client
        return
    if isinstance(client, str):
        try:
            c = Client(client, timeout="10s")
        except (OSError, TimeoutError, ValueError) as exc:
            raise InputError(f"cannot reach the dask scheduler at {client!r}: {exc}") from None
        try:
            yield c
        finally:
            c.close()
        return
    try:
        yield default_client()
        return
    except ValueError:
        pass
    c = local_cluster()
    try:
        yield c
    finally:
        c.close()


def worker_memory_limit(client) -> int:
    """The smallest ``memory_limit`` (bytes) of the client's workers; 0 when none is set."""
    limits = [w.get("memory_limit") or 0 for w in client.scheduler_info()["workers"].values()]
    limits = [m for m in limits if m > 0]
    return min(limits) if limits else 0


def _warm_once() -> float:
    """Compile (or load from the cache) the kernels a part uses by meshing the two parts of a
    small rectangle whose size forces interface splits and a resumed round, and import h5py
    (the first task to use either would otherwise count the loading as its time)."""
    import time

    import h5py  # noqa: F401

    from meshwright.distributed.exchange import Splits
    from meshwright.distributed.mesher import _check_domain
    from meshwright.distributed.part import (
        min_angle_of,
        part_mesh,
        resume_part,
        start_part,
    )
    from meshwright.distributed.partition import decompose_domain, part_pslg
    from meshwright.geometry.shapes import polygon
    from meshwright.sizing.boundary import gradation

    t0 = time.perf_counter()
    # Fine near the cut on both sides, unevenly: each part needs splits the other lacks.
    src = [[0.96, 0.5], [1.05, 0.3]]
    dom, field = _check_domain(polygon([[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]]), gradation(src, 0.01, 3.0))
    dec = decompose_domain(dom, field, 2)
    states = [start_part(part_pslg(dec, i, len(dom.curves)), dom.curves, field, 30.0, i, 10**6) for i in range(2)]
    splits = Splits(dec)
    todo = range(2)
    for _ in range(4):
        for i in todo:
            splits.add(i, states[i].report.splits, states[i].report.xy)
        todo = splits.lacking()
        for i, lack in todo.items():
            states[i] = resume_part(states[i], lack)
    ids, xy = splits.numbered(len(dec.points))
    for i, st in enumerate(states):
        part_mesh(st, splits.of_part(i, ids), len(dec.points) + len(xy))
        min_angle_of(st.ct.points, st.ct.triangles(True))
    return time.perf_counter() - t0


def warm(client) -> dict:
    """Load the meshing kernels on every worker: one worker first (it may build the Numba
    cache), then all the others (they load it).

    Parameters
    ----------
    client : distributed.Client

    Returns
    -------
    dict
        Worker address -> seconds it took.
    """
    _require_distributed()
    from distributed import Client

    if not isinstance(client, Client):
        raise InputError(f"warm needs a distributed.Client, got {type(client).__name__}")
    workers = sorted(client.scheduler_info()["workers"])
    if not workers:
        return {}
    out = client.run(_warm_once, workers=workers[:1])
    if len(workers) > 1:
        out.update(client.run(_warm_once, workers=workers[1:]))
    return out
