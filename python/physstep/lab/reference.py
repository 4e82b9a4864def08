"""What the errors are measured against: the exact solution, or a reference run.

A scene with an exact solution (spring, drag, projectile, orbit, kepler; pendulum with
``g=0``) is measured against it. Everything else (the other scenes, the flow scenes and
every user system) is measured against a reference run: :data:`REFERENCE_METHOD` (RK4: it
applies to particles and flows alike, and is the most accurate method that does; velocity
Verlet, SHAKE/RATTLE, on a scene with position constraints) at
``dt / REFERENCE_REFINE`` of the finest dt (finer, halved up to
:data:`REFERENCE_RETRIES` times, where RK4 is unstable at that step: a stiff scene),
interpolated with cubic Hermite polynomials between its rows (x and v for particles, y and
dy/dt for a flow). Every result says which in ``error_against``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

import physstep
from physstep import Trajectory
from physstep.lab.common import REFERENCE_METHOD, REFERENCE_REFINE


def reference_method(scene: Any, params: dict[str, float] | None = None) -> str:
    """The method of a reference run: :data:`REFERENCE_METHOD`, or ``velocity-verlet`` for a
    built-in scene with position constraints (the pendulum's rod): RK4 is projected onto
    them, first order, while velocity Verlet solves rigid ones by SHAKE/RATTLE, second order
    (see docs/constraints.md)."""
    if isinstance(scene, str):
        try:
            world = physstep.World.from_scene(scene, params=params)
        except ValueError:
            return REFERENCE_METHOD
        if world.constraint_count:
            return "velocity-verlet"
    return REFERENCE_METHOD


#: How many times the reference step is halved again when the run diverges at
#: ``dt / REFERENCE_REFINE`` (RK4 past its stability limit on a stiff scene: the 100-link
#: ``stiff-chain`` at dt = 1/60 s needs dt/64).
REFERENCE_RETRIES = 4


def reference(
    scene: Any, dt: float, until: float, params: dict[str, float] | None = None, *, every: int = 1
) -> Trajectory:
    """The reference run of a scene or system: :func:`reference_method` at
    ``dt / REFERENCE_REFINE``, one row every ``every`` of its steps (the last always); where
    that diverges, at half that step (and ``every`` doubled: the same rows), and so on up to
    :data:`REFERENCE_RETRIES` times; then the last run's :class:`physstep.DivergedError`.
    The step taken is the trajectory's ``dt``."""
    method = reference_method(scene, params)
    for k in range(REFERENCE_RETRIES + 1):
        finer = 2**k
        try:
            return physstep.simulate(
                scene, method, dt / (REFERENCE_REFINE * finer), until, params, every=every * finer
            )
        except physstep.DivergedError:
            if k == REFERENCE_RETRIES:
                raise
    raise AssertionError("unreachable")  # pragma: no cover


def hermite(traj: Trajectory, times: np.ndarray) -> np.ndarray:
    """Positions of ``traj`` at ``times`` by cubic Hermite interpolation of (x, v) between rows."""
    t = traj.t
    times = np.atleast_1d(np.asarray(times, dtype=float))
    i = np.clip(np.searchsorted(t, times, side="right") - 1, 0, len(t) - 2)
    h = t[i + 1] - t[i]
    s = ((times - t[i]) / h)[:, None]
    h = h[:, None]
    x0, x1, v0, v1 = traj.x[i], traj.x[i + 1], traj.v[i], traj.v[i + 1]
    h00 = 2 * s**3 - 3 * s**2 + 1
    h10 = s**3 - 2 * s**2 + s
    h01 = -2 * s**3 + 3 * s**2
    h11 = s**3 - s**2
    out = h00 * x0 + h10 * h * v0 + h01 * x1 + h11 * h * v1
    # rows hit exactly (to rounding) are taken as they are
    exact = np.isclose(
        times, t[np.clip(np.searchsorted(t, times), 0, len(t) - 1)], rtol=0, atol=1e-9 * h[:, 0]
    )
    j = np.clip(np.searchsorted(t, times), 0, len(t) - 1)
    out[exact] = traj.x[j[exact]]
    return out


def _body_spin_at(ref: Trajectory, t: np.ndarray) -> np.ndarray:
    """The reference's body-frame angular velocities at times ``t`` (rows, bodies, 3),
    interpolated linearly between its rows (recorded at a step far finer than the runs')."""
    assert ref.body_spin is not None
    flat = ref.body_spin.reshape(len(ref.t), -1)
    cols = [np.interp(t, ref.t, flat[:, k]) for k in range(flat.shape[1])]
    return np.stack(cols, axis=-1).reshape(len(t), *ref.body_spin.shape[1:])


def _is_bodies(traj: Trajectory) -> bool:
    """Whether the run's state is its rigid bodies' (no particles to measure)."""
    return traj.body_spin is not None and traj.x.shape[1] == 0


def final_error(traj: Trajectory, ref: Trajectory | None) -> float:
    """Max-coordinate distance of the final position from the exact or reference one; for
    rigid bodies, of the final body-frame angular velocities (rad/s) from the reference's."""
    if _is_bodies(traj):
        assert ref is not None and traj.body_spin is not None
        return float(np.abs(traj.body_spin[-1] - _body_spin_at(ref, traj.t[-1:])[0]).max())
    if traj.exact_x is not None:
        return float(np.abs(traj.x[-1] - traj.exact_x[-1]).max())
    assert ref is not None
    want = hermite(ref, np.array([traj.t[-1]]))[0]
    return float(np.abs(traj.x[-1] - want).max())


def max_error(traj: Trajectory, ref: Trajectory | None) -> float:
    """Max over the run (and over coordinates) of the distance from the exact/reference path;
    for rigid bodies, of the body-frame angular velocities from the reference's."""
    if _is_bodies(traj):
        assert ref is not None and traj.body_spin is not None
        return float(np.abs(traj.body_spin - _body_spin_at(ref, traj.t)).max())
    if traj.exact_x is not None:
        return float(np.abs(traj.x - traj.exact_x).max())
    assert ref is not None
    return float(np.abs(traj.x - hermite(ref, traj.t)).max())


def error_against(
    has_exact: bool, ref_dt: float | None, method: str = REFERENCE_METHOD, run_dt: float | None = None
) -> str:
    """What the errors were measured against, as a phrase (``error_against``): the
    reference's step as a part of the finest run's ``run_dt`` (REFERENCE_REFINE unless the
    reference had to go finer)."""
    if has_exact:
        return "exact solution"
    refine = REFERENCE_REFINE if not (run_dt and ref_dt) else round(run_dt / ref_dt)
    return f"reference: {method} at dt/{refine} = {ref_dt:.6g} s"
