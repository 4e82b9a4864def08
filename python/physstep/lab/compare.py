"""``compare``: one row per method on one scene or system at one dt."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, overload

import numpy as np

import physstep
from physstep import Trajectory
from physstep.lab.common import (
    ANGULAR_MOMENTUM_ERROR,
    REFERENCE_METHOD,
    REFERENCE_REFINE,
    check_jobs,
    check_run,
    drift,
    energy_scale,
    max_abs,
    positive,
    timed,
)
from physstep.lab.parallel import Rows, run_units
from physstep.lab.reference import error_against, final_error, reference
from physstep.lab.results import CompareResult, CompareRow, SolverCompareResult
from physstep.lab.solvers import compare_solvers
from physstep.lab.system import Subject, table


def run_args(subject: Subject, dt: Any, until: Any, dt_name: str = "dt") -> tuple[float, float]:
    """The (dt, until) of a compare run: the scene's defaults for None (a system has none),
    both finite > 0, and at least one step (dt <= until)."""
    dt = positive(dt_name, subject.default("dt", dt))
    until = positive("until", subject.default("until", until))
    if dt > until:
        raise ValueError(f"invalid {dt_name} = {dt!r}: must be <= until = {until!r} (at least one step)")
    return dt, until


@overload
def compare(
    scene: Any,
    methods: Sequence[str] | str,
    dt: float | None = None,
    until: float | None = None,
    params: dict[str, float] | None = None,
    *,
    jobs: int | None = None,
    executor: Any = None,
) -> CompareResult: ...


@overload
def compare(
    scene: Any,
    methods: None = None,
    dt: None = None,
    until: float | None = None,
    params: dict[str, float] | None = None,
    *,
    solvers: Sequence[str] | str,
    substeps: int | None = None,
    iterations: int | None = None,
) -> SolverCompareResult: ...


def compare(
    scene: Any,
    methods: Sequence[str] | str | None = None,
    dt: float | None = None,
    until: float | None = None,
    params: dict[str, float] | None = None,
    *,
    jobs: int | None = None,
    executor: Any = None,
    solvers: Sequence[str] | str | None = None,
    substeps: int | None = None,
    iterations: int | None = None,
) -> CompareResult | SolverCompareResult:
    """One row per method on ``scene`` at ``dt`` up to ``until`` (the scene's defaults if None);
    with ``solvers=`` (names or ``"all"``) instead of ``methods``, one row per contact solver on
    a contact scene, at ``substeps`` and ``iterations`` (:func:`compare_solvers`, whose
    :class:`~physstep.lab.results.SolverCompareResult` it returns).

    ``scene`` is a built-in scene's name or a system (a :class:`physstep.Flow`, or a
    zero-argument callable returning a fresh World or Flow), as :func:`physstep.simulate`
    takes; a system needs ``dt`` and ``until`` and takes no ``params``. ``methods`` is a list
    of names or ``"all"``: every method that applies (a flow skips the split methods, and
    ``note`` says so); a split method named for a flow is refused.

    Returns a :class:`~physstep.lab.results.CompareResult` (its fields documented there;
    ``.to_dict()`` is what ``physstep compare --format json`` prints) whose ``rows`` are one
    :class:`~physstep.lab.results.CompareRow` per method: its order, force evaluations per
    step, energy error and drift (None where the energy is unknown: a flow, or a force
    without a potential), why the run loses energy by design where it does (the scene's damping,
    drag or inelastic contacts, or a method that damps: there the energy change is energy lost, not
    an error), final error against ``error_against``, the angular-momentum error
    on rigid bodies, ns per step and whether it diverged (a diverged run reports its errors
    up to the step before). Every run takes until / dt steps rounded down: ``t_end`` can
    fall short of ``until``. Verlet does not apply to rigid bodies: ``"all"`` skips it with a
    note, naming it is refused. ValueError naming ``dt`` or ``until`` before anything runs if
    a run would be refused (no whole step, too many steps, too large a recording).

    ``jobs=N`` runs the methods in up to N local processes, in chunks (see
    :mod:`physstep.lab.parallel`: at most one process per CPU, and here, serially,
    when the work is too small to pay for starting them; ``note`` says so and ``workers``
    says how many ran it); ``executor=`` on any ``concurrent.futures.Executor`` (a Dask
    ``Client.get_executor()``, a Ray pool), which is not shut down. The rows are the serial
    run's, in its order, bitwise but for the timing columns. A system (not a scene name)
    must then pickle (a module-level function, a Flow).
    """
    if solvers is not None:
        for name, value in (("methods", methods), ("dt", dt), ("jobs", jobs), ("executor", executor)):
            if value is not None:
                raise ValueError(
                    f"invalid {name} = {value!r} with solvers: compare methods or solvers, not both"
                )
        return compare_solvers(scene, solvers, until, params, substeps=substeps, iterations=iterations)
    for name, value in (("substeps", substeps), ("iterations", iterations)):
        if value is not None:
            raise ValueError(f"invalid {name} = {value!r}: it applies with solvers= only")
    if methods is None:
        raise ValueError("invalid methods = None: name the methods (or 'all'), or give solvers=")
    jobs = check_jobs(scene, jobs, executor)
    subject = Subject(scene, params)
    names, skipped = subject.methods(methods)
    dt, until = run_args(subject, dt, until)
    steps = check_run(dt, until, subject.coords)
    ref = None
    if not subject.has_exact:
        check_run(
            dt,
            until,
            subject.coords,
            every=REFERENCE_REFINE,
            refine=REFERENCE_REFINE,
            what="the reference run",
        )
        ref = reference(scene, dt, until, params, every=REFERENCE_REFINE)
    units = [(m, dt, until) for m in names]
    ran = run_units(
        Rows(scene, params, ref, _row),
        units,
        jobs,
        executor,
        here=lambda m, d, u: _row(subject, m, d, u, ref),
        work=[physstep.method(m).evals for m in names],  # one dt: the same steps each
    )
    rows = tuple(ran.results)
    t_end = next((r.t_end for r in rows if not r.diverged), steps * dt)
    against = error_against(
        subject.has_exact,
        None if ref is None else ref.dt,
        REFERENCE_METHOD if ref is None else ref.method,
        run_dt=dt,
    )
    return CompareResult(
        **table(subject, until, against, skipped, ran.note),
        rows=rows,
        # the |L| column's meaning, beside energy_error's
        angular_momentum_error=ANGULAR_MOMENTUM_ERROR if subject.kind == "bodies" else None,
        # compare runs one dt: the table says it, with the steps it takes and the time they reach.
        dt=dt,
        steps=steps,
        t_end=t_end,
        workers=ran.workers,
    )


def _l_error(traj: Trajectory) -> float | None:
    """Max relative error of the total angular momentum over the run (rigid bodies), or None."""
    ang = traj.angular_momentum
    if ang is None or not len(ang):
        return None
    l0 = float(np.linalg.norm(ang[0]))
    return float(np.max(np.linalg.norm(ang - ang[0], axis=1)) / (l0 if l0 > 0 else 1.0))


def _row(subject: Subject, method: str, dt: float, until: float, ref: Trajectory | None) -> CompareRow:
    """One row of :func:`compare`."""
    traj, ns, runs = timed(lambda: subject.run(method, dt, until, stop_on_diverge=True))
    return CompareRow(
        method=method,
        order=physstep.method(method).order,
        evals_per_step=traj.evals / max(traj.steps, 1),
        energy_max_rel_error=max_abs(traj.energy_error),
        energy_drift=drift(traj),
        energy_scale=energy_scale(traj),
        energy_dissipation=physstep._dissipation(traj) if traj.energy is not None else None,
        final_error=final_error(traj, ref) if len(traj.t) else math.nan,
        angular_momentum_max_rel_error=_l_error(traj),
        ns_per_step=ns,
        ns_per_step_runs=runs,
        steps=int(traj.steps),
        t_end=float(traj.t[-1]),
        diverged=traj.diverged,
    )
