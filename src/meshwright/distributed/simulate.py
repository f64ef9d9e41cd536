"""Scaling simulation from measured part times: list scheduling of the tasks on P virtual workers.

Source: R. L. Graham, "Bounds on multiprocessing timing anomalies", SIAM J. Appl. Math. 17(2),
1969 (longest-processing-time-first list scheduling, within 4/3 of optimal); the trace-driven
method of the design notes (section 7): run the P-worker problem's tasks on the workers at
hand, record every task's compute time, schedule those times on P virtual workers round by
round (a round ends when its last part ends), and add the client's serial phases.

Two simulations:

* :func:`simulate_scaling` (trace-driven, the ``P``-problem run for real on fewer workers):
  ``T(P) = decompose + sum_r LPT_P(times of round r) + client_rounds + LPT_P(resolve times)
  + client_write``, where a part's time is its whole task (meshing and writing its piece),
  the resolve times are the per-part seconds of the numbering tasks, and client phases are
  measured, not scaled.  It ignores data transfer (parts never move) and scheduler latency
  per task (about 2 ms here), which is why it is validated against a real run before it is
  trusted.
* :func:`model_time` (cost model, for problems too large to mesh here): the per-task costs of
  a real run (:func:`fit_costs`: part-task seconds per triangle, numbering-task seconds per
  triangle, the client's fixed time per phase beyond the tasks' makespan, and the triangles
  a part gets per predicted triangle) applied to the ``P``-problem's real decomposition
  (its predicted part sizes), plus that problem's client phases measured for real
  (decomposition, and the skeleton, virtual datasets and XDMF written for its part sizes).
  ``T(P) = decompose_P + round_overhead + LPT_P(rate * t_i) + resolve_overhead +
  LPT_P(resolve_rate * t_i) + client_write_P`` with ``t_i = triangles_per_predicted *
  predicted_i``.  Not modelled: exchange rounds beyond those of the calibration run (their
  work is folded into the rate), the prediction error of single parts and their different
  speeds per triangle (the calibration's spreads are reported beside it), memory bandwidth
  shared by the workers of one machine.
"""

from __future__ import annotations

import heapq
from typing import NamedTuple

import numpy as np

from meshwright.core.errors import InputError
from meshwright.core.validate_input import check_count

__all__ = ["TaskCosts", "fit_costs", "lpt_makespan", "model_time", "simulate_scaling"]


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


class TaskCosts(NamedTuple):
    """Per-task costs of a real run (:func:`fit_costs`), seconds.

    Attributes
    ----------
    seconds_per_triangle : float
        Part tasks (meshing, exchange rounds and writing) per final triangle.
    cpu_per_triangle : float
        The same in CPU seconds of the tasks' threads.
    resolve_per_triangle : float
        Numbering tasks per triangle.
    round_overhead : float
        Client wall time of the meshing rounds beyond the part tasks' makespan on the run's
        workers (submission, scheduling, gathering the summaries, stragglers).
    resolve_overhead : float
        The same for the numbering tasks.
    triangles_per_predicted : float
        Final triangles over the decomposition's prediction.
    spread : float
        Largest relative deviation of one part's triangles from that ratio.
    rate_spread : float
        Largest relative deviation of one part's seconds per triangle (its last round) from
        ``seconds_per_triangle``: the model does not schedule it.
    cpu_rate_spread : float
        The same for the CPU seconds.
    """

    seconds_per_triangle: float
    cpu_per_triangle: float
    resolve_per_triangle: float
    round_overhead: float
    resolve_overhead: float
    triangles_per_predicted: float
    spread: float
    rate_spread: float
    cpu_rate_spread: float


def fit_costs(stats: dict) -> TaskCosts:
    """The per-task costs of a run, from its ``DistributedMesh.stats``.

    Parameters
    ----------
    stats : dict
        Needs ``part_seconds``, ``part_cpu_seconds``, ``round_seconds``, ``write_seconds``,
        ``resolve_seconds``, ``triangles``, ``predicted`` and ``workers``.

    Returns
    -------
    TaskCosts
    """
    need = ("part_seconds", "part_cpu_seconds", "round_seconds", "write_seconds", "resolve_seconds", "triangles")
    if not isinstance(stats, dict) or any(k not in stats for k in need):
        raise InputError(f"stats must be the stats dict of a DistributedMesh (with {', '.join(need)})")
    w = int(stats["workers"])
    tris = np.asarray(stats["triangles"], dtype=np.float64)
    pred = np.asarray(stats["predicted"], dtype=np.float64)
    n = max(float(tris.sum()), 1.0)
    work = sum(t for r in stats["part_seconds"] for _, t in r)
    cpu = sum(t for r in stats["part_cpu_seconds"] for _, t in r)
    makespans = sum(lpt_makespan([t for _, t in r], w) for r in stats["part_seconds"])
    resolve = float(np.sum(stats["write_seconds"]))
    ratio = float(tris.sum() / pred.sum()) if pred.sum() > 0 else 1.0
    spread = float(np.max(np.abs(tris / (ratio * pred) - 1.0))) if len(pred) and (pred > 0).all() else 0.0
    last = {}
    for r in stats["part_seconds"]:
        last.update(dict(r))
    last_cpu = {}
    for r in stats["part_cpu_seconds"]:
        last_cpu.update(dict(r))

    def rate_spread(per: dict, total: float) -> float:
        x = np.array([per[i] / tris[i] for i in sorted(per) if tris[i] > 0])
        return float(np.max(np.abs(x * n / total - 1.0))) if len(x) and total > 0 else 0.0

    return TaskCosts(
        seconds_per_triangle=work / n,
        cpu_per_triangle=cpu / n,
        resolve_per_triangle=resolve / n,
        round_overhead=max(0.0, float(sum(stats["round_seconds"])) - makespans),
        resolve_overhead=max(0.0, float(stats["resolve_seconds"]) - lpt_makespan(stats["write_seconds"], w)),
        triangles_per_predicted=ratio,
        spread=spread,
        rate_spread=rate_spread(last, work),
        cpu_rate_spread=rate_spread(last_cpu, cpu),
    )


def model_time(costs: TaskCosts, predicted, workers: int, decompose_seconds: float, client_write_seconds: float,
               rate: float | None = None, rate_spread: float | None = None) -> dict:
    """Modelled wall time of a run on ``workers`` workers (module docstring, :func:`model_time`).

    Parameters
    ----------
    costs : TaskCosts
        From a real (calibration) run.
    predicted : (p,) array_like
        The problem's predicted triangles per part (``Decomposition.predicted``).
    workers : int
    decompose_seconds, client_write_seconds : float
        The problem's client phases, measured.
    rate : float, optional
        Part seconds per triangle instead of ``costs.seconds_per_triangle``.
    rate_spread : float, optional
        The spread of that rate between parts (default ``costs.rate_spread``), for ``bound``.

    Returns
    -------
    dict
        ``total`` and its phases ``decompose``, ``parts`` (makespan of the part tasks),
        ``rest`` (overheads, numbering tasks, client write), ``worker_imbalance``, and
        ``bound``: ``total`` plus the largest part's time times the calibration's spreads of
        triangles and of speed (the slowest part ending its worker's list, which LPT on
        predicted sizes cannot foresee).
    """
    if not isinstance(costs, TaskCosts):
        raise InputError(f"costs must be a TaskCosts (fit_costs), got {type(costs).__name__}")
    w = check_count(workers, "workers", 1)
    t = np.asarray(predicted, dtype=np.float64).ravel() * costs.triangles_per_predicted
    r = costs.seconds_per_triangle if rate is None else float(rate)
    parts = lpt_makespan(r * t, w)
    rest = (costs.round_overhead + costs.resolve_overhead + lpt_makespan(costs.resolve_per_triangle * t, w)
            + float(client_write_seconds))
    q = costs.rate_spread if rate_spread is None else float(rate_spread)
    late = ((1.0 + q) * (1.0 + costs.spread) - 1.0) * float((r * t).max()) if len(t) else 0.0
    return {
        "bound": float(decompose_seconds) + parts + rest + late,
        "total": float(decompose_seconds) + parts + rest,
        "decompose": float(decompose_seconds),
        "parts": parts,
        "rest": rest,
        "worker_imbalance": lpt_makespan(t, w) * w / t.sum() if t.sum() else 1.0,
    }
