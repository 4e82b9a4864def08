"""What every lab measurement shares: the limits of a run, argument checks, timing and the
energy statistics.

Every run the lab would make is checked against :func:`physstep.simulate`'s limits before
any is made (:func:`check_run`): a refusal names the lab's own argument (``dt``, ``dts``,
``until``, ``levels``).
"""

from __future__ import annotations

import math
import numbers
import pickle
import statistics
import sys
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from physstep import Trajectory

#: The method and refinement of the reference solution for scenes without an exact one.
REFERENCE_METHOD = "rk4"
REFERENCE_REFINE = 16
#: physstep.simulate's limits: steps per run, and values (t, x, v, a, energy per row) recorded.
MAX_STEPS = 1e9
MAX_RECORDED = 500_000_000
#: How the timings are repeated: at least TIMING_MIN_RUNS runs and TIMING_MIN_S seconds in
#: all, at most TIMING_MAX_RUNS runs or TIMING_MAX_S seconds; the median is reported.
TIMING_MIN_RUNS = 3
TIMING_MIN_S = 0.05
TIMING_MAX_RUNS = 25
TIMING_MAX_S = 1.0
#: What the energy errors are relative to (see :attr:`physstep.Trajectory.energy_scale`).
ENERGY_ERROR = (
    "(E - E0) / energy scale, the scale = |E0|, or the largest kinetic energy of the run where "
    "|E0| is below 1e-3 of it (a near cancellation); "
    "None where the energy is unknown (a flow, or a force without a potential)"
)
#: What the angular-momentum errors of rigid-body runs are (compare's |L| column).
ANGULAR_MOMENTUM_ERROR = (
    "max over the run of |L - L0| / |L0|, L the total angular momentum about the origin (|L - L0| "
    "when L0 = 0): an error where no external torque acts (racket), the physics where one does (top)"
)

EPS = float(np.finfo(float).eps)


def number(name: str, value: Any) -> float:
    """``value`` as a float, or ValueError naming ``name`` unless it is a real number."""
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise ValueError(f"invalid {name} = {value!r}: must be a number")
    return float(value)


def positive(name: str, value: Any) -> float:
    """``value`` as a float, or ValueError naming ``name`` unless it is finite and > 0."""
    x = number(name, value)
    if not (x > 0 and math.isfinite(x)):
        raise ValueError(f"invalid {name} = {x!r}: must be a finite number > 0")
    return x


def steps(dt: float, until: float) -> int:
    """The step count physstep.simulate takes for (dt, until): until / dt rounded down, a
    quotient within 1e-9 of a whole number counting as that number; infinite when the quotient
    is (a step that underflowed to 0: the smallest dt refined for a reference run)."""
    if dt == 0.0:
        return math.inf  # type: ignore[return-value]
    r = until / dt
    if not math.isfinite(r):
        return math.inf  # type: ignore[return-value]
    return int(round(r)) if abs(r - round(r)) <= 1e-9 * max(r, 1.0) else int(math.floor(r))


def check_run(
    dt: float,
    until: float,
    coords: int,
    *,
    every: int = 1,
    refine: int = 1,
    dt_name: str = "dt",
    what: str = "the run",
) -> int:
    """Steps of ``dt / refine`` up to ``until``, or ValueError naming ``until`` and ``dt_name``
    when :func:`physstep.simulate` would refuse the run (more than :data:`MAX_STEPS` steps, or
    more than :data:`MAX_RECORDED` values recorded at one row every ``every`` steps)."""
    n = steps(dt / refine, until)
    fix = f"use a larger {'dt in dts' if dt_name == 'dts' else dt_name} or a shorter until"
    if n > MAX_STEPS:
        raise ValueError(
            f"invalid until = {until!r} with {dt_name} = {dt!r}: {what} would take {n:.4g} steps "
            f"(at most {MAX_STEPS:.0e}); {fix}"
        )
    values = (n // every + 2) * (3 * coords + 2)
    if values > MAX_RECORDED:
        raise ValueError(
            f"invalid until = {until!r} with {dt_name} = {dt!r}: {what} would record {values} values "
            f"(at most {MAX_RECORDED}); {fix}"
        )
    return n


def max_abs(a: np.ndarray | None) -> float | None:
    """The largest finite |a|, or None when there is none (or ``a`` is None: energy unknown)."""
    if a is None:
        return None
    a = np.asarray(a, dtype=float)
    a = a[np.isfinite(a)]
    return float(np.abs(a).max()) if len(a) else None


def drift(traj: Trajectory) -> float | None:
    """Least-squares slope of the relative energy error (:data:`ENERGY_ERROR`) against time,
    1/s, over the finite rows; None when the energy is unknown, with fewer than two finite
    rows or a non-finite slope (computed in closed form: no SVD to fail on huge data)."""
    if len(traj.t) < 2 or traj.energy is None:
        return None
    t = np.asarray(traj.t, dtype=float)
    err = np.asarray(traj.energy_error, dtype=float)
    ok = np.isfinite(err) & np.isfinite(t)
    if ok.sum() < 2:
        return None
    t, err = t[ok], err[ok]
    with np.errstate(all="ignore"):
        tc = t - t.mean()
        den = float(np.dot(tc, tc))
        slope = float(np.dot(tc, err - err.mean())) / den if den > 0 else math.nan
    return slope if math.isfinite(slope) else None


def energy_scale(traj: Trajectory) -> float | None:
    """The run's energy scale, J (:attr:`physstep.Trajectory.energy_scale`), None if unknown."""
    return None if traj.energy is None else traj.energy_scale


def timed(run: Callable[[], Trajectory]) -> tuple[Trajectory, float, int]:
    """Runs ``run`` repeatedly for the timing (see :data:`TIMING_MIN_RUNS`); returns the first
    run, the median ns per step over the runs and the number of runs."""
    start = time.perf_counter()
    first = run()
    times = [first.ns_per_step]
    while len(times) < TIMING_MAX_RUNS:
        spent = time.perf_counter() - start
        if spent >= TIMING_MAX_S or (len(times) >= TIMING_MIN_RUNS and spent >= TIMING_MIN_S):
            break
        times.append(run().ns_per_step)
    return first, float(statistics.median(times)), len(times)


def timing_note() -> str:
    """How :func:`timed` made the ns/step numbers, as a sentence."""
    return (
        f"ns_per_step: median over ns_per_step_runs timed runs (at least {TIMING_MIN_RUNS} runs and "
        f"{TIMING_MIN_S:g} s in all, at most {TIMING_MAX_RUNS} runs or {TIMING_MAX_S:g} s)"
    )


#: Most local worker processes ``jobs`` may ask for.
MAX_JOBS = 1024


def check_jobs(scene: Any, jobs: Any, executor: Any) -> int | None:
    """Validates ``jobs`` and ``executor`` of a lab function; returns the number of local
    processes to start (None: run in this process, or on ``executor``).

    ValueError naming ``jobs`` (not a whole number from 1 to :data:`MAX_JOBS`, or given with
    ``executor``), ``executor`` (no ``submit``) or ``scene`` (a system that does not pickle,
    so it cannot reach another process).
    """
    if jobs is not None and (
        isinstance(jobs, bool) or not isinstance(jobs, numbers.Integral) or not 1 <= int(jobs) <= MAX_JOBS
    ):
        raise ValueError(f"invalid jobs = {jobs!r}: must be a whole number from 1 to {MAX_JOBS}")
    jobs = None if jobs is None else int(jobs)
    if executor is not None and jobs is not None:
        raise ValueError(f"invalid jobs = {jobs!r}: give jobs or executor, not both")
    if executor is not None and not callable(getattr(executor, "submit", None)):
        raise ValueError(f"invalid executor = {executor!r}: must be a concurrent.futures.Executor")
    parallel = executor is not None or (jobs or 1) > 1
    if parallel and not isinstance(scene, str):
        try:
            pickle.dumps(scene)
        except Exception:  # noqa: BLE001 - any pickling failure means the same thing here
            raise ValueError(
                f"invalid scene = {scene!r}: a system run with jobs or executor must pickle "
                "(a module-level function or a physstep.Flow, not a lambda or a closure)"
            ) from None
    interactive = not hasattr(sys.modules.get("__main__"), "__file__")
    if (jobs or 1) > 1 and interactive and getattr(scene, "__module__", None) == "__main__":
        raise ValueError(
            f"invalid scene = {scene!r}: defined in an interactive session (python -c, a notebook), "
            "which the worker processes jobs starts cannot import; define it in a module, or pass an "
            "executor that pickles by value (Dask's)"
        )
    return jobs if (jobs or 1) > 1 else None
