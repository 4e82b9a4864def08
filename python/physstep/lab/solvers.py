"""The solver lab: contact solvers side by side on one contact scene.

``lab.compare(scene, solvers=[...])`` (``physstep compare SCENE --solvers a,b``) runs the
scene once under each contact solver at the same settings (every solver makes ``2 x
substeps x solver_iterations`` passes over the contacts a step: the passes are counted as
they run and printed, so equal cost is measured, not assumed) and measures, for each:

- the deepest penetration over the run, and over its last second (where the solids settled);
- the drift of the tracked solid (the dynamic solid highest when the run starts: the top box
  of a stack or pyramid) from where it started;
- the largest joint error over the run (scenes with joints);
- the largest kinetic energy over the last second (jitter: a pile at rest has none);
- the change of the total energy, relative to its start (scenes where it is known);
- the ``ramp`` scene's slide distance against the closed form ``g (sin a - mu cos a) t^2 /
  2`` where friction is below ``tan(a)`` (the friction test);
- the cost: ms a step (a second run of the same steps in one call, timed alone) and the
  passes a step;

and gives a verdict (:data:`THRESHOLDS` says it in words). ``explodes``: the step failed, or a
solid ends faster than :data:`EXPLODE_SPEED` (a jammed overlap, as in ``confined``, is the
scene's, not an explosion: it shows in the penetrations). On a scene meant to stand
(:data:`STANDING`, and the ``ramp`` above its friction angle): ``stands`` where the tracked
solid ended within :data:`STAND_M` of its start, the penetration of the last second and the
joint error at most :data:`STAND_M`; ``sags`` where it ended within :data:`SAG_M`; ``falls``
otherwise. On a scene in motion: ``holds`` where the penetration of the last second and the
joint error are at most :data:`STAND_M` (a sliding ramp also within
:data:`FRICTION_TOLERANCE` of the closed form); ``drifts`` otherwise.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Sequence
from typing import Any

import numpy as np

import physstep
from physstep.lab.results import SolverCompareResult, SolverRow, SolverSweepResult

#: What the verdicts measure against: a tracked solid that moved farther, or a penetration or
#: joint error deeper, than this (m) does not stand or hold.
STAND_M = 0.01
#: A standing scene whose tracked solid moved farther than STAND_M but at most this (m) sags.
SAG_M = 0.1
#: A solid faster than this at the end (m/s) explodes.
EXPLODE_SPEED = 50.0
#: A sliding ramp holds when its slide distance is within this of the closed form.
FRICTION_TOLERANCE = 0.01
#: The scenes meant to stand still: their tracked solid's drift is the solver's error.
STANDING = frozenset(
    {"stack", "pyramid", "card-house", "mass-ratio", "arch", "box-stack", "far-pyramid", "high-mass-ratio"}
)


#: The verdicts in words.
THRESHOLDS = (
    f"explodes: the step failed or a solid ends faster than {EXPLODE_SPEED:g} m/s; a standing scene "
    f"stands where the tracked solid ends within {STAND_M:g} m of its start with the last second's "
    f"penetration and the joint error at most {STAND_M:g} m, sags where it ends within {SAG_M:g} m, "
    "falls otherwise; a scene in motion holds where the last second's penetration and the joint "
    f"error are at most {STAND_M:g} m (a sliding ramp also within {FRICTION_TOLERANCE:.0%} of the "
    "closed form), drifts otherwise"
)


def _solvers(solvers: Sequence[str] | str) -> list[str]:
    """The solver names asked for: a list, a comma-separated string, or ``"all"``."""
    known = list(physstep.contact_solvers())
    names = known if solvers == "all" else solvers.split(",") if isinstance(solvers, str) else list(solvers)
    if not names:
        raise ValueError("invalid solvers = []: name at least one contact solver")
    for n in names:
        if n not in known:
            raise ValueError(f"unknown contact solver {n!r}; valid contact solvers: {', '.join(known)}")
    return names


def _count(name: str, value: Any) -> int | None:
    """``value`` as a whole number from 1 to 1000, or None; ValueError naming ``name``."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or not 1 <= value <= 1000:
        raise ValueError(f"invalid {name} = {value!r}: must be a whole number from 1 to 1000")
    return int(value)


def _slide_exact(params: dict[str, float], t: float) -> float | None:
    """The ``ramp`` box's slide distance after ``t`` s where friction is below tan(angle)."""
    a, mu, g = params["angle"], params["friction"], params["g"]
    accel = g * (math.sin(a) - mu * math.cos(a))
    return 0.5 * accel * t * t if accel > 0 else None


def compare_solvers(
    scene: str,
    solvers: Sequence[str] | str = "all",
    until: float | None = None,
    params: dict[str, float] | None = None,
    *,
    substeps: int | None = None,
    iterations: int | None = None,
) -> SolverCompareResult:
    """Each contact solver in ``solvers`` (names, a comma-separated string or ``"all"``) on the
    contact scene ``scene`` up to ``until`` (the scene's default if None), at the scene's step
    and the world's ``substeps`` and ``solver_iterations`` (or these). The measures and the
    verdicts are the module's (:mod:`physstep.lab.solvers`).

    ValueError naming the field for an unknown scene, solver or parameter, a scene without
    solids, or bad ``until``, ``substeps`` or ``iterations``.
    """
    names = _solvers(solvers)
    substeps, iterations = _count("substeps", substeps), _count("iterations", iterations)
    run = _Run.of(scene, until, params)
    rows = tuple(_row(run, s, substeps, iterations) for s in names)
    return SolverCompareResult(
        scene=scene,
        params=run.params,
        dt=run.dt,
        until=run.until,
        substeps=rows[0].substeps,
        iterations=rows[0].iterations,
        tracked=run.tracked,
        standing=scene in STANDING,
        thresholds=THRESHOLDS,
        rows=rows,
    )


#: The splits of 16 passes a step that :func:`sweep_solvers` tries by default: (substeps,
#: iterations) from all substeps to all iterations.
DEFAULT_SPLITS = ((8, 1), (4, 2), (2, 4), (1, 8))


def sweep_solvers(
    scene: str,
    solvers: Sequence[str] | str = "soft-step",
    splits: Sequence[tuple[int, int]] = DEFAULT_SPLITS,
    until: float | None = None,
    params: dict[str, float] | None = None,
) -> SolverSweepResult:
    """Each solver in ``solvers`` on ``scene`` at each ``(substeps, iterations)`` of ``splits``:
    the Avian question (6 substeps and 1 iteration, or 4 and 2?). The default splits all make
    16 passes a step (equal cost: the rows count them); any may be given. One
    :class:`~physstep.lab.results.SolverRow` per solver and split, solver by solver, with the
    measures and verdicts of :func:`compare_solvers`.

    ValueError naming the field for an unknown scene, solver or parameter, a scene without
    solids, bad ``until``, or a split that is not two whole numbers from 1 to 1000.
    """
    names = _solvers(solvers)
    pairs = list(splits)
    if not pairs:
        raise ValueError("invalid splits = []: give at least one (substeps, iterations)")
    checked = []
    for pair in pairs:
        if not (isinstance(pair, tuple | list) and len(pair) == 2):
            raise ValueError(f"invalid splits entry {pair!r}: must be (substeps, iterations)")
        checked.append((_count("substeps", pair[0]), _count("iterations", pair[1])))
    run = _Run.of(scene, until, params)
    rows = tuple(_row(run, s, n, k) for s in names for n, k in checked)
    return SolverSweepResult(
        scene=scene,
        params=run.params,
        dt=run.dt,
        until=run.until,
        tracked=run.tracked,
        standing=scene in STANDING,
        thresholds=THRESHOLDS,
        rows=rows,
    )


@dataclasses.dataclass(frozen=True)
class _Run:
    """A contact scene as the solver lab runs it: its parameters, step, steps and tracked solid."""

    scene: str
    user_params: dict[str, float] | None
    params: dict[str, float]
    dt: float
    until: float
    steps: int
    tracked: int

    @staticmethod
    def of(scene: str, until: float | None, params: dict[str, float] | None) -> _Run:
        """The run of ``scene`` up to ``until`` (its default if None); ValueError for a scene
        without solids or a bad ``until`` or parameter."""
        spec = physstep.scene(scene)
        probe = physstep.World.from_scene(scene, params=params)
        if probe.solid_count == 0:
            raise ValueError(
                f"invalid scene = {scene!r}: it has no solids (the solver lab runs the contact scenes: "
                "single-box, pyramid, ramp, bridge, dice, ...)"
            )
        end = float(spec["until"] if until is None else until)
        if not (math.isfinite(end) and end > 0):
            raise ValueError(f"invalid until = {until!r}: must be finite and > 0")
        dt = probe.dt
        steps = int(end / dt + 1e-9)
        if steps < 1:
            raise ValueError(f"invalid until = {until!r}: must be at least one step (dt = {dt:g})")
        start = probe.solid_positions()
        dynamic = [i for i, h in enumerate(probe.solids) if h.kind == "dynamic"]
        tracked = max(dynamic, key=lambda i: (start[i, 1], -i)) if dynamic else 0
        merged = {**{p["name"]: float(p["default"]) for p in spec["params"]}, **(params or {})}
        return _Run(scene, params, merged, dt, end, steps, tracked)

    def world(self, solver: str, substeps: int | None, iterations: int | None) -> physstep.World:
        """A fresh World of the scene under ``solver`` at these settings (the world's where None)."""
        w = physstep.World.from_scene(self.scene, params=self.user_params)
        w.contact_solver = solver
        if substeps is not None:
            w.substeps = substeps
        if iterations is not None:
            w.solver_iterations = iterations
        return w


def _row(run: _Run, solver: str, substeps: int | None, iterations: int | None) -> SolverRow:
    """One solver's row on ``run``: the run measured step by step, then the same steps timed in
    one call."""
    scene, steps, dt, tracked = run.scene, run.steps, run.dt, run.tracked
    w = run.world(solver, substeps, iterations)
    start = w.solid_positions()[tracked].copy()
    e0 = w.energy()
    joints = w.joint_count > 0
    deepest, settled, joint_error, jitter, passes = 0.0, 0.0, 0.0, 0.0, 0
    last_second = max(steps - int(round(1.0 / dt)), 0)
    diverged, done = None, 0
    for k in range(steps):
        try:
            w.step(1)
        except (physstep.StepError, ValueError) as e:
            diverged = str(e).splitlines()[0]
            break
        done += 1
        passes += w.contact_passes
        deepest = max(deepest, w.max_penetration)
        if joints:
            joint_error = max(joint_error, float(np.max(w.joint_errors())))
        if k >= last_second:
            jitter = max(jitter, w.kinetic_energy())
            settled = max(settled, w.max_penetration)
    drift = float(np.linalg.norm(w.solid_positions()[tracked] - start))
    e1 = w.energy()
    energy_change = None if e0 is None or e1 is None or e0 == 0 else (e1 - e0) / abs(e0)
    friction_error = None
    if scene == "ramp" and diverged is None:
        exact = _slide_exact(run.params, done * dt)
        if exact is not None:
            friction_error = (drift - exact) / exact
    speed = float(np.max(np.linalg.norm(w.solid_velocities(), axis=1), initial=0.0))
    timing = run.world(solver, substeps, iterations)
    t0 = time.perf_counter()
    try:
        timing.step(max(done, 1))
    except (physstep.StepError, ValueError):
        pass
    ms = (time.perf_counter() - t0) * 1e3 / max(done, 1)
    holds = settled <= STAND_M and joint_error <= STAND_M
    if diverged is not None or speed > EXPLODE_SPEED:
        verdict = "explodes"
    elif scene in STANDING or (scene == "ramp" and friction_error is None):
        verdict = "stands" if holds and drift <= STAND_M else "sags" if drift <= SAG_M else "falls"
    elif friction_error is not None:
        verdict = "holds" if holds and abs(friction_error) <= FRICTION_TOLERANCE else "drifts"
    else:
        verdict = "holds" if holds else "drifts"
    return SolverRow(
        solver=solver,
        substeps=w.substeps,
        iterations=w.solver_iterations,
        passes_per_step=passes / max(done, 1),
        ms_per_step=ms,
        max_penetration=deepest,
        settled_penetration=settled,
        drift=drift,
        joint_error=joint_error if joints else None,
        jitter=jitter,
        energy_change=energy_change,
        friction_error=friction_error,
        steps=done,
        diverged=diverged,
        verdict=verdict,
    )
