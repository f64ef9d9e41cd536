"""Scaling simulation from measured part times: list scheduling of the tasks on P virtual workers.

Source: R. L. Graham, "Bounds on multiprocessing timing anomalies", SIAM J. Appl. Math. 17(2),
1969 (longest-processing-time-first list scheduling, within 4/3 of optimal); the trace-driven
method of the design notes (section 7): run the P-worker problem's tasks on the workers at
hand, record every task's compute time, schedule those times on P virtual workers round by
round (a round ends when its last part ends), and add the client's serial phases.

Model: ``T(P) = decompose + sum_r LPT_P(times of round r) + client_rounds + LPT_P(resolve times)
+ client_write``, where a part's time is its whole task (meshing and writing its piece), the
resolve times are the per-part seconds of the numbering tasks, and client phases are
measured, not scaled.  It ignores data transfer
(parts never move) and scheduler latency per task (about 2 ms here), which is why it is
validated against a real run before it is trusted.
"""

from __future__ import annotations

import heapq

import numpy as np

from meshwright.core.errors import InputError
from meshwright.core.validate_input import check_count

__all__ = ["lpt_makespan", "simulate_scaling"]


def lpt_makespan(times, workers: int) -> float:
    """Makespan of tasks ``times`` (seconds) on ``workers`` by longest-processing-time-first."""
    w = check_count(workers, "workers", 1)
    t = np.sort(np.asarray(times, dtype=np.float64).ravel())[::-1]
    if len(t) and not (np.isfinite(t).all() and (t >= 0).all()):
        raise InputError("task times must be finite and >= 0")
    loads = [0.0] * w
    for x in t.tolist():
        heapq.heapreplace(loads, loads[0] + x)
    return max(loads)


def simulate_scaling(stats: dict, workers: int) -> float:
    """Predicted wall time of the run ``stats`` describes on ``workers`` workers.

    Parameters
    ----------
    stats : dict
        ``DistributedMesh.stats`` of a run (its ``part_seconds``, ``write_seconds`` and
        ``seconds``).
    workers : int

    Returns
    -------
    float
        Seconds.
    """
    if not isinstance(stats, dict) or "part_seconds" not in stats or "seconds" not in stats:
        raise InputError("stats must be the stats dict of a DistributedMesh")
    w = check_count(workers, "workers", 1)
    sec = stats["seconds"]
    rounds = [lpt_makespan([s for _, s in r], w) for r in stats["part_seconds"]]
    tasks_mesh = sum(lpt_makespan([s for _, s in r], stats["workers"]) for r in stats["part_seconds"])
    client_mesh = max(0.0, sec["mesh"] - tasks_mesh)
    write_tasks = lpt_makespan(stats["write_seconds"], stats["workers"])
    client_write = max(0.0, sec["write"] - write_tasks)
    return sec["decompose"] + sum(rounds) + client_mesh + lpt_makespan(stats["write_seconds"], w) + client_write
