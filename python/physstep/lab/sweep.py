"""``sweep``: work-precision data, every method at every dt."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import physstep
from physstep import Trajectory
from physstep.lab.common import (
    REFERENCE_REFINE,
    check_jobs,
    check_run,
    max_abs,
    positive,
    steps,
    timed,
)
from physstep.lab.parallel import Rows, run_units
from physstep.lab.reference import error_against, final_error, max_error, reference
from physstep.lab.results import SweepResult, SweepRow
from physstep.lab.system import Subject, table


def _check_dts(dts: Sequence[float]) -> list[float]:
    if isinstance(dts, str | bytes):
        raise ValueError(f"invalid dts = {dts!r}: give a list of numbers")
    try:
        values = list(dts)
    except TypeError:
        raise ValueError(f"invalid dts = {dts!r}: give a list of numbers") from None
    if not values:
        raise ValueError("invalid dts = []: give at least one dt")
    return [positive("dts", d) for d in values]


def sweep(
    scene: Any,
    methods: Sequence[str] | str,
    dts: Sequence[float],
    until: float | None = None,
    params: dict[str, float] | None = None,
    *,
    progress: Callable[[int, int, str], None] | None = None,
    jobs: int | None = None,
    executor: Any = None,
) -> SweepResult:
    """Work-precision data: every method at every dt up to ``until``.

    ``scene`` is a built-in scene's name or a system (a :class:`physstep.Flow`, or a
    zero-argument callable returning a fresh World or Flow; it needs ``until``). ``methods``
    is a list of names or ``"all"``: every method that applies (a flow skips the split
    methods, and ``note`` says so); a split method named for a flow is refused.

    Returns a :class:`~physstep.lab.results.SweepResult` (its fields documented there;
    ``.to_dict()`` is what ``physstep sweep --format json`` prints) whose ``rows`` are one
    :class:`~physstep.lab.results.SweepRow` per (method, dt), method by method, each from the
    largest dt down: what the run took and reached (until / dt steps rounded down), its force
    evaluations and stepping time, its final error and its maximum error over the run (free
    of the cancellations a single time can show) against the exact solution or the
    reference at the smallest dt / 16, and its energy error (None where the energy is
    unknown); rows that diverged have ``error`` None. ``progress(done, total, label)`` is
    called after each run.

    Every dt must be <= ``until`` (at least one step); a run that :func:`physstep.simulate`
    would refuse is a ValueError naming ``dts`` and ``until`` before anything runs.

    ``jobs=N`` runs the rows in up to N local processes, in chunks (see
    :mod:`physstep.lab.parallel`: at most one process per CPU, and here, serially, when the
    work is too small to pay for starting them; ``note`` says so and ``workers`` says how
    many ran it); ``executor=`` on any ``concurrent.futures.Executor`` (a Dask
    ``Client.get_executor()``, a Ray pool), which is not shut down. The rows are the serial
    run's, in its order, bitwise (physstep is deterministic) but for the timing columns;
    ``progress`` is called here as rows come in.
    A system (not a scene name) must then pickle (a module-level function, a Flow).
    """
    jobs = check_jobs(scene, jobs, executor)
    subject = Subject(scene, params)
    names, skipped = subject.methods(methods)
    values = _check_dts(dts)
    until = positive("until", subject.default("until", until))
    for d in values:
        if d > until:
            raise ValueError(f"invalid dts: dt = {d!r} must be <= until = {until!r} (at least one step)")
    for d in values:
        check_run(d, until, subject.coords, dt_name="dts")
    ref = None
    if not subject.has_exact:
        check_run(
            min(values),
            until,
            subject.coords,
            refine=REFERENCE_REFINE,
            dt_name="dts",
            what="the reference run",
        )
        ref = reference(scene, min(values), until, params)
    units = [(m, d, until) for m in names for d in sorted(values, reverse=True)]
    labels = [f"{m} dt={d:g}" for m, d, _ in units]
    ran = run_units(
        Rows(scene, params, ref, _row),
        units,
        jobs,
        executor,
        here=lambda m, d, u: _row(subject, m, d, u, ref),
        work=[steps(d, u) * physstep.method(m).evals for m, d, u in units],
        progress=progress,
        labels=labels,
    )
    against = error_against(subject.has_exact, None if ref is None else ref.dt, run_dt=min(values))
    return SweepResult(
        **table(subject, until, against, skipped, ran.note), rows=tuple(ran.results), workers=ran.workers
    )


def _row(subject: Subject, method: str, dt: float, until: float, ref: Trajectory | None) -> SweepRow:
    """One row of :func:`sweep`."""
    traj, ns, runs = timed(lambda: subject.run(method, dt, until, stop_on_diverge=True))
    return SweepRow(
        method=method,
        dt=dt,
        steps=int(traj.steps),
        t_end=float(traj.t[-1]),
        evals=int(traj.evals),
        time_s=float(f"{ns * traj.steps * 1e-9:.12g}"),  # 12 digits: no float noise (e.g. ...0001)
        ns_per_step=ns,
        ns_per_step_runs=runs,
        error=None if traj.diverged else final_error(traj, ref),
        max_error=None if traj.diverged else max_error(traj, ref),
        energy_max_rel_error=max_abs(traj.energy_error),
        diverged=traj.diverged,
    )
