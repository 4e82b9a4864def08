"""What the lab's measurements return: frozen dataclasses, one per measurement and per row.

:func:`~physstep.lab.compare` returns a :class:`CompareResult` of :class:`CompareRow`,
:func:`~physstep.lab.sweep` a :class:`SweepResult` of :class:`SweepRow`,
:func:`~physstep.lab.order` an :class:`OrderResult` of :class:`OrderRun`,
:func:`~physstep.lab.stability` a :class:`StabilityResult` and
:func:`~physstep.lab.compare_solvers` a :class:`SolverCompareResult` of :class:`SolverRow`.
Read them by attribute (``res.rows[0].final_error``, ``res.dt_max``); ``to_dict()`` gives the
plain, JSON-ready dict the command line prints with ``--format json`` (lists for the tuples, the optional
fields left out where they do not apply, in the same key order).

Indexing a result as a dict (``res["dt_max"]``), as the lab's results were before they were
typed, still works through ``to_dict()`` but warns (DeprecationWarning): it builds a copy,
so assigning into it changes nothing. Use the attribute, or ``to_dict()`` once.
"""

from __future__ import annotations

import dataclasses
import warnings
from typing import Any


def _plain(value: Any) -> Any:
    """``value`` as the dict of the untyped lab had it: results as dicts, tuples as lists."""
    if isinstance(value, Result):
        return value.to_dict()
    if isinstance(value, tuple | list):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    return value


@dataclasses.dataclass(frozen=True, kw_only=True)
class Result:
    """What every result of the lab shares: ``to_dict()``, and indexing as a dict (deprecated).

    A field whose metadata says ``optional`` is left out of ``to_dict()`` when it is None (a
    key the measurement has only on some scenes); one that says ``dict=False`` is never in it
    (it says how the result was made, beside the measurement).
    """

    def to_dict(self) -> dict[str, Any]:
        """The result as a plain dict (JSON-ready: strings, numbers, None, lists and dicts), as
        the command line prints it with ``--format json``. A new dict at every call."""
        out: dict[str, Any] = {}
        for f in dataclasses.fields(self):
            if not f.metadata.get("dict", True):
                continue
            value = getattr(self, f.name)
            if value is None and f.metadata.get("optional", False):
                continue
            out[f.name] = _plain(value)
        return out

    def __getitem__(self, key: str) -> Any:
        """Deprecated: ``res[key]`` is ``res.to_dict()[key]`` (a copy), with a DeprecationWarning
        naming the attribute to read instead."""
        warnings.warn(
            f"indexing a lab result is deprecated: read the attribute (.{key}) or use .to_dict()[{key!r}]",
            DeprecationWarning,
            stacklevel=2,
        )
        return self.to_dict()[key]

    def __contains__(self, key: object) -> bool:
        """Deprecated: ``key in res`` is ``key in res.to_dict()`` (the keys the dict would
        have), with a DeprecationWarning."""
        warnings.warn(
            "'in' on a lab result is deprecated: compare the attribute with None, or use .to_dict()",
            DeprecationWarning,
            stacklevel=2,
        )
        return key in self.to_dict()

    #: Not iterable: a result is a record, not a sequence (indexing above is for keys only).
    __iter__ = None


#: The metadata of a field left out of ``to_dict()`` when it is None.
OPTIONAL = {"optional": True}


# --------------------------------------------------------------------------------------
# compare


@dataclasses.dataclass(frozen=True, kw_only=True)
class CompareRow(Result):
    """One method's run in :func:`~physstep.lab.compare`.

    Attributes:
        method: The method's registry name.
        order: Its order, from the registry.
        evals_per_step: Force (or flow) evaluations per step, measured.
        energy_max_rel_error: Max |relative energy error| over the finite rows
            (:data:`~physstep.lab.ENERGY_ERROR`); None where the energy is unknown (a flow, a
            force without a potential).
        energy_drift: Least-squares slope of the relative energy error, 1/s; None where the
            energy is unknown or without two finite rows.
        energy_scale: What the energy error is relative to, J; None where it is unknown.
        energy_dissipation: Why the run loses energy by design (the scene's damping, drag or
            inelastic contacts, or a method that damps): there the energy change is energy
            lost, not an error; None otherwise (and where the energy is unknown).
        final_error: Max coordinate distance of the final position from the exact solution
            or the reference (the result's ``error_against``); for rigid bodies, of the final
            body-frame angular velocities, rad/s. NaN for a run without a row.
        angular_momentum_max_rel_error: Rigid bodies: max |L - L0| / |L0| of the total
            angular momentum over the run; None otherwise.
        ns_per_step: Median ns per step over ``ns_per_step_runs`` timed runs.
        ns_per_step_runs: How many timed runs the median is over.
        steps: Steps the run took.
        t_end: Time it reached, s.
        diverged: The failure's message, or None; a diverged run's numbers cover it up to
            the step before.
    """

    method: str
    order: int
    evals_per_step: float
    energy_max_rel_error: float | None
    energy_drift: float | None
    energy_scale: float | None
    energy_dissipation: str | None
    final_error: float
    angular_momentum_max_rel_error: float | None
    ns_per_step: float
    ns_per_step_runs: int
    steps: int
    t_end: float
    diverged: str | None


@dataclasses.dataclass(frozen=True, kw_only=True)
class CompareResult(Result):
    """What :func:`~physstep.lab.compare` returns: one row per method at one dt.

    Attributes:
        scene: The scene's name, or the system's.
        kind: ``"particles"``, ``"bodies"`` or ``"flow"``.
        until: The run length asked for, s.
        until_requested: The same (the command line's name for it).
        params: Every parameter of the scene, defaults filled in ({} for a system).
        error_against: What ``final_error`` is measured against: the exact solution, or the
            reference run (its method and dt).
        energy_error: What the energy errors are relative to, as a sentence.
        timing: How ``ns_per_step`` was measured, as a sentence.
        skipped: The methods ``"all"`` left out (they do not apply).
        note: Why they were left out, and how ``jobs`` ran (see ``workers``); "" if nothing.
        rows: One :class:`CompareRow` per method, in the order asked.
        angular_momentum_error: Rigid-body scenes: what ``angular_momentum_max_rel_error``
            measures, as a sentence; None (and not in ``to_dict()``) otherwise.
        dt: The step, s.
        steps: Steps each run takes: ``until / dt`` rounded down.
        t_end: The time they reach, s (can fall short of ``until``).
        workers: Processes the rows ran in (1: this process; None: on the caller's
            ``executor``). Not in ``to_dict()``.
    """

    scene: str
    kind: str
    until: float
    until_requested: float
    params: dict[str, float]
    error_against: str
    energy_error: str
    timing: str
    skipped: tuple[str, ...]
    note: str
    rows: tuple[CompareRow, ...]
    angular_momentum_error: str | None = dataclasses.field(default=None, metadata=OPTIONAL)
    dt: float
    steps: int
    t_end: float
    workers: int | None = dataclasses.field(default=1, metadata={"dict": False})

    def row(self, method: str) -> CompareRow:
        """The row of ``method``; KeyError naming it and the methods run otherwise."""
        for r in self.rows:
            if r.method == method:
                return r
        raise KeyError(f"{method!r}: no such row (the rows: {', '.join(r.method for r in self.rows)})")


# --------------------------------------------------------------------------------------
# sweep


@dataclasses.dataclass(frozen=True, kw_only=True)
class SweepRow(Result):
    """One (method, dt) run of :func:`~physstep.lab.sweep`.

    Attributes:
        method: The method's registry name.
        dt: The step, s.
        steps: Steps the run took (``until / dt`` rounded down).
        t_end: Time it reached, s.
        evals: Force (or flow) evaluations, measured.
        time_s: The stepping loop's wall time, s (``ns_per_step`` times ``steps``).
        ns_per_step: Median ns per step over ``ns_per_step_runs`` timed runs.
        ns_per_step_runs: How many timed runs the median is over.
        error: Final position error, max over coordinates, against the exact solution or
            the reference interpolated to ``t_end``; None if the run diverged.
        max_error: The same, maximum over the whole run; None if it diverged.
        energy_max_rel_error: Max |relative energy error| (:data:`~physstep.lab.ENERGY_ERROR`);
            None where the energy is unknown.
        diverged: The failure's message, or None.
    """

    method: str
    dt: float
    steps: int
    t_end: float
    evals: int
    time_s: float
    ns_per_step: float
    ns_per_step_runs: int
    error: float | None
    max_error: float | None
    energy_max_rel_error: float | None
    diverged: str | None


@dataclasses.dataclass(frozen=True, kw_only=True)
class SweepResult(Result):
    """What :func:`~physstep.lab.sweep` returns: work-precision data, every method at every dt.

    Attributes:
        scene: The scene's name, or the system's.
        kind: ``"particles"``, ``"bodies"`` or ``"flow"``.
        until: The run length, s.
        until_requested: The same (the command line's name for it).
        params: Every parameter of the scene, defaults filled in ({} for a system).
        error_against: What the errors are measured against.
        energy_error: What the energy errors are relative to, as a sentence.
        timing: How ``ns_per_step`` was measured, as a sentence.
        skipped: The methods ``"all"`` left out.
        note: Why they were left out, and how ``jobs`` ran (see ``workers``); "" if nothing.
        rows: One :class:`SweepRow` per (method, dt): method by method, each from the largest
            dt down.
        workers: Processes the rows ran in (1: this process; None: on the caller's
            ``executor``). Not in ``to_dict()``.
    """

    scene: str
    kind: str
    until: float
    until_requested: float
    params: dict[str, float]
    error_against: str
    energy_error: str
    timing: str
    skipped: tuple[str, ...]
    note: str
    rows: tuple[SweepRow, ...]
    workers: int | None = dataclasses.field(default=1, metadata={"dict": False})


# --------------------------------------------------------------------------------------
# order


@dataclasses.dataclass(frozen=True, kw_only=True)
class OrderRun(Result):
    """One step size of :func:`~physstep.lab.order`.

    Attributes:
        dt: The step, s.
        steps: Steps to ``until``.
        error: Final error (max over coordinates); ``inf`` if the run diverged.
        order: The pairwise order from the previous (coarser) run; None for the first, or
            where either error is at roundoff level.
    """

    dt: float
    steps: int
    error: float
    order: float | None


@dataclasses.dataclass(frozen=True, kw_only=True)
class OrderResult(Result):
    """What :func:`~physstep.lab.order` returns: the observed convergence order of a method.

    Attributes:
        scene: The scene's name, or the system's.
        kind: ``"particles"``, ``"bodies"`` or ``"flow"``.
        method: The method's registry name.
        info_order: Its order, from the registry.
        order: The observed order: least-squares slope of log error on log dt over the three
            finest runs in the asymptotic range; None if fewer than two (``note`` says why).
        order_all: The same slope over every usable run; None likewise.
        until: The run length, s.
        params: Every parameter of the scene, defaults filled in ({} for a system).
        error_against: What the errors are measured against.
        error: What the error is, as a sentence.
        runs: One :class:`OrderRun` per step size, from the coarsest.
        note: Runs left out of the fit and why, or why there is no order; "" if nothing.
    """

    scene: str
    kind: str
    method: str
    info_order: int
    order: float | None
    order_all: float | None
    until: float
    params: dict[str, float]
    error_against: str
    error: str
    runs: tuple[OrderRun, ...]
    note: str


# --------------------------------------------------------------------------------------
# stability


@dataclasses.dataclass(frozen=True, kw_only=True)
class GrowthTest(Result):
    """The numbers of the bounded-growth test of :func:`~physstep.lab.stability`.

    Attributes:
        steps: Steps each run takes.
        limit: The bound :data:`~physstep.lab.GROWTH_LIMIT`: |x_k - x_0| <= limit x_scale and
            |v_k - v_0| <= limit v_scale throughout (max norms).
        x_scale: The position scale A, m.
        v_scale: The velocity scale V, m/s.
    """

    steps: int
    limit: float
    x_scale: float
    v_scale: float


@dataclasses.dataclass(frozen=True, kw_only=True)
class StabilityResult(Result):
    """What :func:`~physstep.lab.stability` returns: the largest stable dt of a method.

    Attributes:
        scene: The scene's name, or the system's.
        kind: ``"particles"`` or ``"flow"``.
        method: The method's registry name.
        params: Every parameter of the scene, defaults filled in ({} for a system).
        dt_max: The largest stable dt, s: the stable interval that starts at dt -> 0 ends
            there; 0 if unstable at the grid's lowest point, None if stable up to ``cap``.
        dt_unstable: The unstable dt found just above it, s (None with ``dt_max`` None).
        analysis: ``"amplification matrix"`` or ``"bounded growth"``.
        criterion: The test, spelt out.
        cap: The largest dt searched, s.
        rtol: The bisection's relative tolerance.
        time_scale: The natural time scale the grid is in, s.
        grid: The search grid: (lowest dt, highest dt, points per decade).
        note: The verdict as a sentence.
        growth: Bounded growth only: the test's numbers; None (and not in ``to_dict()``) for
            the amplification matrix.
        stable_above: Bounded growth only: the dts above ``dt_max`` found stable again (a
            resonance window); None (and not in ``to_dict()``) for the amplification matrix.
        horizon: Bounded growth only: the longer horizon the limit was checked against
            (``steps``, ``dt_max``, ``long_dt_max``: see :data:`~physstep.lab.HORIZON_STEPS`);
            None (and not in ``to_dict()``) for the amplification matrix.
        spectral_radius_at_dt_max: Amplification matrix with a finite ``dt_max`` > 0 only:
            the per-step spectral radius there; None (and not in ``to_dict()``) otherwise.
    """

    scene: str
    kind: str
    method: str
    params: dict[str, float]
    dt_max: float | None
    dt_unstable: float | None
    analysis: str
    criterion: str
    cap: float
    rtol: float
    time_scale: float
    grid: tuple[float, float, int]
    note: str
    growth: GrowthTest | None = dataclasses.field(default=None, metadata=OPTIONAL)
    stable_above: tuple[float, ...] | None = dataclasses.field(default=None, metadata=OPTIONAL)
    horizon: dict[str, Any] | None = dataclasses.field(default=None, metadata=OPTIONAL)
    spectral_radius_at_dt_max: float | None = dataclasses.field(default=None, metadata=OPTIONAL)


# --------------------------------------------------------------------------------------
# compare_solvers (the solver lab)


@dataclasses.dataclass(frozen=True, kw_only=True)
class SolverRow(Result):
    """One contact solver's run in :func:`~physstep.lab.compare_solvers`.

    Attributes:
        solver: The solver's registry name.
        substeps: The substeps it ran with.
        iterations: The solver iterations it ran with.
        passes_per_step: Passes over the contacts a step, counted as they ran (the mean).
        ms_per_step: Wall time a step of the same run repeated in one call, ms.
        max_penetration: The deepest penetration over the run, m.
        settled_penetration: The deepest penetration over the run's last second, m.
        drift: How far the tracked solid ended from where it started, m.
        joint_error: The largest joint error over the run, m; None without joints.
        jitter: The largest kinetic energy over the run's last second, J.
        energy_change: (E_end - E0) / |E0| of the total energy; None where it is unknown.
        friction_error: The ``ramp`` scene sliding: (slide - exact) / exact of the distance
            the box slid against ``g (sin a - mu cos a) t^2 / 2``; None otherwise.
        steps: Steps the run took.
        diverged: The failure's message, or None (the numbers cover the run up to it).
        verdict: ``stands``, ``sags`` or ``falls`` (a standing scene), ``holds`` or ``drifts``
            (a scene in motion), or ``explodes`` (the thresholds of :mod:`physstep.lab.solvers`).
    """

    solver: str
    substeps: int
    iterations: int
    passes_per_step: float
    ms_per_step: float
    max_penetration: float
    settled_penetration: float
    drift: float
    joint_error: float | None = dataclasses.field(default=None, metadata=OPTIONAL)
    jitter: float
    energy_change: float | None = dataclasses.field(default=None, metadata=OPTIONAL)
    friction_error: float | None = dataclasses.field(default=None, metadata=OPTIONAL)
    steps: int
    diverged: str | None
    verdict: str


@dataclasses.dataclass(frozen=True, kw_only=True)
class _SolverRuns(Result):
    """What the solver lab's two results share (:class:`SolverCompareResult`,
    :class:`SolverSweepResult`).

    Attributes:
        scene: The scene's name.
        params: Its parameters as run (the defaults with the overrides).
        dt: The step, s.
        until: The end time, s.
        tracked: The tracked solid's row (the dynamic solid highest at the start).
        standing: Whether the scene is meant to stand (its drift is an error).
        thresholds: The verdicts' thresholds, in words.
        rows: One :class:`SolverRow` per run (each says its solver, substeps and iterations).
    """

    scene: str
    params: dict[str, float]
    dt: float
    until: float
    tracked: int
    standing: bool
    thresholds: str
    rows: tuple[SolverRow, ...]

    def row(self, solver: str) -> SolverRow:
        """The (first) row of ``solver``; KeyError if it did not run."""
        for r in self.rows:
            if r.solver == solver:
                return r
        raise KeyError(solver)


@dataclasses.dataclass(frozen=True, kw_only=True)
class SolverCompareResult(_SolverRuns):
    """What :func:`~physstep.lab.compare_solvers` returns: the fields of every solver-lab
    result (``scene``, ``params``, ``dt``, ``until``, ``tracked``, ``standing``,
    ``thresholds``, ``rows``: one :class:`SolverRow` per solver, in the order asked) and the
    settings every solver ran with.

    Attributes:
        substeps: The substeps every solver ran with.
        iterations: The solver iterations every solver ran with.
    """

    substeps: int
    iterations: int


@dataclasses.dataclass(frozen=True, kw_only=True)
class SolverSweepResult(_SolverRuns):
    """What :func:`~physstep.lab.sweep_solvers` returns: the fields of every solver-lab result
    (``scene``, ``params``, ``dt``, ``until``, ``tracked``, ``standing``, ``thresholds``),
    its ``rows`` one :class:`SolverRow` per solver and split (each says its substeps and
    iterations), solver by solver in the order asked, the splits in theirs."""
