"""How :func:`~physstep.lab.compare` and :func:`~physstep.lab.sweep` run their rows: here, in
local worker processes (``jobs=``) or on the caller's executor (``executor=``).

Every row is one independent, deterministic simulation, so wherever it runs it is bitwise
the serial run's (but for the timing columns), and the rows come back in the serial order.

``jobs=N`` is worth its cost only where the work is large: a worker process is started
("spawn": the parent may hold threads) and imports numpy and physstep before it takes a
row, about :data:`POOL_START_S` seconds. So :func:`run_units`:

- runs the first row here and estimates, from its single-run time and the work of the
  others (steps times evaluations per step), what the rest would cost serially
  (:func:`estimate`, which follows :func:`~physstep.lab.common.timed`'s repetitions);
- starts at most one process per remaining row and per CPU this process may use
  (``os.sched_getaffinity``: processes do not run faster for being more than the CPUs),
  and none at all, running the rest here, where the estimated gain
  ``rest * (1 - 1 / workers)`` is below :data:`POOL_START_S` (the result's ``note`` says so);
- hands each worker chunks of consecutive rows of about equal estimated cost
  (:data:`CHUNKS_PER_WORKER` per worker, so a slow chunk does not leave the others idle):
  the scene or system and the reference run travel once per chunk, not once per row, and a
  worker builds the scene once per chunk.

On an executor (Dask, Ray, a thread pool) every row is its own task, as the executor
spreads them over whatever it has; nothing is estimated.
"""

from __future__ import annotations

import concurrent.futures
import dataclasses
import math
import multiprocessing
import os
import pickle
import time
from collections.abc import Callable, Sequence
from typing import Any

from physstep import Trajectory
from physstep.lab.common import TIMING_MAX_RUNS, TIMING_MAX_S, TIMING_MIN_RUNS, TIMING_MIN_S
from physstep.lab.system import Subject

#: Seconds to start a worker process and import physstep into it (spawn, numpy included),
#: measured at 0.4 to 0.8 s on a 2-CPU machine at load 2 (1 s: a margin): what ``jobs`` must save.
POOL_START_S = 1.0
#: Chunks of rows per worker process: a few, so that the workers finish together.
CHUNKS_PER_WORKER = 4


def cpus() -> int:
    """The CPUs this process may run on (its affinity where the system tells it)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


def timed_cost(run_s: float) -> float:
    """The wall time, s, :func:`~physstep.lab.common.timed` takes over a run of ``run_s`` s:
    at least :data:`TIMING_MIN_RUNS` runs and :data:`TIMING_MIN_S` s, at most
    :data:`TIMING_MAX_RUNS` runs or :data:`TIMING_MAX_S` s (the last run started before it)."""
    if run_s <= 0:
        return TIMING_MIN_S
    runs = max(TIMING_MIN_RUNS, math.ceil(TIMING_MIN_S / run_s))
    runs = min(runs, TIMING_MAX_RUNS, max(1, math.ceil(TIMING_MAX_S / run_s)))
    return runs * run_s


def estimate(first_s: float, first_run_s: float, work: Sequence[float]) -> list[float]:
    """Estimated wall times, s, of rows of ``work`` (``work[0]`` the first row's) from the
    first row's wall time ``first_s`` and its single run's time ``first_run_s``: each run
    scaled by its work, repeated as :func:`timed_cost` says, plus the first row's overhead
    (what its wall time has beyond its timed runs: building the scene, the errors)."""
    overhead = max(0.0, first_s - timed_cost(first_run_s))
    w0 = work[0] if work[0] > 0 else 1.0
    return [timed_cost(first_run_s * w / w0) + overhead for w in work]


def chunks(costs: Sequence[float], n: int) -> list[tuple[int, int]]:
    """``[start, stop)`` ranges splitting ``costs`` into at most ``n`` runs of consecutive
    items of about equal total cost, none empty, in order."""
    n = max(1, min(n, len(costs)))
    total = sum(costs)
    out: list[tuple[int, int]] = []
    start, acc = 0, 0.0
    for i, c in enumerate(costs):
        acc += c
        left = len(costs) - i - 1  # items after this one
        want = n - len(out) - 1  # chunks still to make after this one
        if want > 0 and left >= want and (acc >= total * (len(out) + 1) / n or left == want):
            out.append((start, i + 1))
            start = i + 1
    out.append((start, len(costs)))
    return out


@dataclasses.dataclass(frozen=True)
class Rows:
    """A chunk of rows, as a worker process runs it: the scene or system (pickled once per
    chunk), its parameters, the reference run, and the row function ``row(subject, *unit,
    ref)`` (module level, so that it pickles)."""

    scene: Any
    params: dict[str, float] | None
    ref: Trajectory | None
    row: Callable[..., Any]

    def __call__(self, units: Sequence[tuple[Any, ...]]) -> list[Any]:
        subject = Subject(self.scene, self.params)
        return [self.row(subject, *u, self.ref) for u in units]


@dataclasses.dataclass(frozen=True)
class Ran:
    """What :func:`run_units` made: the ``results`` in the order of the units, the worker
    processes they ran in (1: here; None: on the caller's executor) and a ``note`` saying
    how ``jobs`` was taken where it was not as asked ("" otherwise)."""

    results: list[Any]
    workers: int | None
    note: str


def decide(jobs: int, cpus: int, costs: Sequence[float]) -> tuple[int, str]:
    """How many worker processes ``jobs`` gets for rows of estimated serial ``costs`` (s) on
    ``cpus`` CPUs, and the note saying so where it is not ``jobs`` ("" where it is): at most
    one per row and per CPU, and 1 (run here) where fewer than two would run or where the
    time they would save, ``sum(costs) * (1 - 1 / workers)``, is below :data:`POOL_START_S`.

    The load of the machine is not read: its average lags a minute behind (this process's
    own work of a moment ago counts in it), and other processes of a lower priority give way
    to the workers anyway."""
    workers = min(jobs, cpus, len(costs))
    asked = f"jobs={jobs}"
    if workers < 2:
        why = "no row left" if not costs else "one row left" if len(costs) == 1 else "one CPU"
        return 1, f"{asked} ran here, serially: {why}"
    rest = sum(costs)
    if rest * (1 - 1 / workers) < POOL_START_S:
        return 1, (
            f"{asked} ran here, serially: the rows' work (about {rest:.2g} s) is too small to pay for "
            f"starting {workers} worker processes (about {POOL_START_S:g} s each)"
        )
    if workers < jobs:
        return workers, f"{asked} ran in {workers} processes ({cpus} CPUs, {len(costs)} rows after the first)"
    return workers, ""


def run_units(
    rows: Rows,
    units: list[tuple[Any, ...]],
    jobs: int | None,
    executor: Any,
    *,
    here: Callable[..., Any],
    work: Sequence[float],
    progress: Callable[[int, int, str], None] | None = None,
    labels: list[str] | None = None,
) -> Ran:
    """Every unit's row: ``here(*u)`` in this process (``jobs`` and ``executor`` None), else
    as the module says, ``rows`` running chunks of units elsewhere. ``work[i]`` is unit i's
    work in any unit (steps times evaluations per step): only the ratios count.
    ``progress(done, total, label)`` is called in this process as rows come in, in order.
    Results are in the order of ``units``, whatever order they finish in."""
    total = len(units)
    out: list[Any] = []

    def add(result: Any) -> None:
        out.append(result)
        if progress is not None:
            progress(len(out), total, labels[len(out) - 1] if labels else "")

    def serial(start: int) -> None:
        for u in units[start:]:
            add(here(*u))

    if executor is not None:
        futures = [executor.submit(rows, [u]) for u in units]
        for f in futures:
            add(f.result()[0])
        return Ran(out, None, "")
    if jobs is None or total == 0:
        serial(0)
        return Ran(out, 1, "")
    began = time.perf_counter()
    add(here(*units[0]))
    first_s = time.perf_counter() - began
    first = out[0]
    costs = estimate(first_s, first.ns_per_step * first.steps * 1e-9, work)[1:]
    workers, note = decide(jobs, cpus(), costs)
    if workers == 1:
        serial(1)
        return Ran(out, 1, note)
    spans = chunks(costs, workers * CHUNKS_PER_WORKER)
    # Pickled once, here: the reference run is not pickled again for every chunk, and what
    # does not pickle fails here, before a process starts (a call that fails to pickle
    # inside the pool leaves its shutdown waiting for ever).
    payload = pickle.dumps(rows)
    # spawn, not fork: the parent may hold threads (rayon's, a GUI's).
    pool = concurrent.futures.ProcessPoolExecutor(
        max_workers=workers, mp_context=multiprocessing.get_context("spawn")
    )
    try:
        futures = [pool.submit(_chunk, payload, units[1 + a : 1 + b]) for a, b in spans]
        for f in futures:
            for result in f.result():
                add(result)
    finally:
        pool.shutdown(cancel_futures=True)
    return Ran(out, workers, note)


def _chunk(payload: bytes, units: Sequence[tuple[Any, ...]]) -> list[Any]:
    """A chunk of rows in a worker process: the pickled :class:`Rows` over ``units``."""
    rows: Rows = pickle.loads(payload)
    return rows(units)
