"""What the lab measures: a built-in scene, or your own system.

Every lab function takes, where it takes a scene name, a *system* as
:func:`physstep.simulate` does: a :class:`physstep.Flow`, or a zero-argument callable
returning a fresh :class:`physstep.World` (your particles and forces, Python forces
included) or a Flow. :class:`Subject` is either, probed once with a zero-length run.

A system's natural time scale cannot be read from parameters: :func:`time_scale` estimates
it from the initial state (see there), and the lab's functions that use it (``order``,
``stability``) take ``time_scale=`` to override the estimate.
"""

from __future__ import annotations

import contextlib
import math
from typing import Any

import numpy as np

import physstep
from physstep import Trajectory
from physstep.lab.common import ENERGY_ERROR, REFERENCE_METHOD, positive, timing_note

#: The time scale, s, of a system whose initial state gives none (all zero, or at rest with
#: no acceleration): pass ``time_scale=`` instead.
FALLBACK_TIME_SCALE = 1.0


def check_method(name: Any) -> None:
    """ValueError unless ``name`` is a method's name (the registry's message lists them)."""
    if not isinstance(name, str):
        raise ValueError(f"invalid method = {name!r}: must be a method name (a string)")
    physstep.method(name)


class Subject:
    """A built-in scene with its parameters, or a user system (no parameters), probed once.

    Raises ValueError for an unknown scene or parameter, for a system given ``params``, and
    for anything else.
    """

    def __init__(self, target: Any, params: dict[str, float] | None = None) -> None:
        if isinstance(target, str):
            self.spec: dict[str, Any] | None = physstep.scene(target)
        elif isinstance(target, physstep.Flow) or callable(target):
            if params:
                raise ValueError(
                    f"invalid params = {params!r}: a system has no scene parameters (build them into it)"
                )
            self.spec = None
        else:
            raise ValueError(
                f"invalid scene = {target!r}: must be a scene name, a Flow or a callable returning a World"
            )
        self.target = target
        self.params = params or None
        #: A zero-length run: the engine validates the scene and ``params`` and answers with the
        #: resolved parameters, the initial state (x, v, a) and whether an exact solution exists.
        self.probe: Trajectory = physstep.simulate(
            target, REFERENCE_METHOD if self.spec else None, dt=1.0, until=0.0, params=self.params
        )

    @property
    def is_system(self) -> bool:
        """True for a user system, False for a built-in scene."""
        return self.spec is None

    @property
    def name(self) -> str:
        """The scene's name, or the system's (its ``name``, its function's name, or "system")."""
        return self.probe.scene

    @property
    def kind(self) -> str:
        """``"particles"`` or ``"flow"`` (a first-order system: no split methods, no energy)."""
        return self.probe.kind

    @property
    def coords(self) -> int:
        """The number of coordinates of the state (particles times dimensions, or len(y))."""
        return int(self.probe.x.shape[1])

    @property
    def has_exact(self) -> bool:
        """Whether the scene has an exact solution (never a system)."""
        return self.probe.exact_x is not None

    @property
    def full_params(self) -> dict[str, float]:
        """Every parameter of the scene, defaults filled in ({} for a system)."""
        return dict(self.probe.params)

    @property
    def estimated(self) -> bool:
        """Whether the time scale and the state's scales are estimated (systems and flow
        scenes) rather than known from the scene's parameters."""
        return self.is_system or self.kind == "flow"

    def default(self, what: str, value: Any) -> float:
        """``value``, or the scene's default ``dt`` or ``until`` for None (a system has none:
        ValueError naming ``what``)."""
        if value is not None:
            return value
        if self.spec is None:
            noun = "step" if what == "dt" else "run length"
            raise ValueError(f"invalid {what} = None: a system has no default {noun}; give {what}")
        return self.spec[what]

    def run(
        self, method: str, dt: float, until: float, *, every: int = 1, stop_on_diverge: bool = False
    ) -> Trajectory:
        """:func:`physstep.simulate` of this scene or system.

        With ``stop_on_diverge`` a run that blows up is data, not an error (a user force or
        flow that turns non-finite ends it as a divergence does, ``diverged`` naming the
        force), and numpy's floating-point warnings inside Python forces are silenced.
        """
        with np.errstate(all="ignore") if stop_on_diverge else contextlib.nullcontext():
            return physstep.simulate(
                self.target, method, dt, until, self.params, every=every, stop_on_diverge=stop_on_diverge
            )

    def world(self, method: str, dt: float) -> physstep.World:
        """A fresh World of this scene or system with ``method`` and ``dt``."""
        if self.spec is not None:
            return physstep.World.from_scene(self.target, method, dt, self.params or {})
        made = self.target if isinstance(self.target, physstep.Flow) else self.target()
        if isinstance(made, physstep.Flow):
            return made.world(method, dt)
        made.method = method
        made.dt = dt
        return made

    def check_method(self, name: Any) -> None:
        """ValueError unless ``name`` is a method that applies: a split method on a flow is
        refused in one line."""
        check_method(name)
        if self.kind == "flow" and physstep.method(name).split:
            raise ValueError(
                f"method '{name}' needs a second-order system (positions and velocities); "
                f"{self.name} is a first-order flow: use a flow method such as rk4"
            )
        if self.kind == "bodies" and physstep.method(name).vector_positions:
            raise ValueError(
                f"method '{name}' does arithmetic on positions as vectors (2 x - x_prev), which "
                f"the orientations of {self.name}'s rigid bodies are not: use velocity-verlet or leapfrog"
            )

    def refuse_bodies(self, what: str) -> None:
        """ValueError for a lab measure that reads particles' and flows' states only (its
        criterion would see nothing of the bodies and call every dt stable)."""
        if self.kind == "bodies":
            raise ValueError(
                f"invalid scene = {self.name!r}: {what} is not measured on rigid bodies yet (its criterion "
                "reads particles' and flows' states); use compare, sweep or order"
            )

    def applies(self, name: str) -> bool:
        """Whether method ``name`` applies: not a split method on a flow, not Verlet on
        rigid bodies."""
        info = physstep.method(name)
        return not (self.kind == "flow" and info.split) and not (
            self.kind == "bodies" and info.vector_positions
        )

    def methods(self, methods: Any) -> tuple[list[str], list[str]]:
        """The methods to run and those skipped: ``"all"`` is every method that applies (a
        flow skips the split methods); a list is checked name by name (one that does not
        apply is refused); a bare string other than "all" is refused."""
        if isinstance(methods, str) and methods == "all":
            names = [m.name for m in physstep.methods()]
            skipped = [m for m in names if not self.applies(m)]
            return [m for m in names if m not in skipped], skipped
        if isinstance(methods, str | bytes):
            raise ValueError(
                f"invalid methods = {methods!r}: give a list of method names, e.g. [{methods!r}], or 'all'"
            )
        try:
            names = list(methods)
        except TypeError:
            raise ValueError(f"invalid methods = {methods!r}: give a list of method names") from None
        if not names:
            raise ValueError("invalid methods = []: give at least one method")
        for m in names:
            self.check_method(m)
        twice = sorted({m for m in names if names.count(m) > 1})
        if twice:
            raise ValueError(
                f"invalid methods = {names!r}: {', '.join(repr(m) for m in twice)} given twice "
                "(each method is one row)"
            )
        return names, []

    def time_scale(self, override: Any = None) -> float:
        """The natural time scale, s: ``override`` if given (finite > 0), else the scene's
        (:func:`scene_time_scale`) or the estimate from the initial state
        (:func:`estimated_time_scale`)."""
        if override is not None:
            return positive("time_scale", override)
        if self.estimated:
            return estimated_time_scale(self.probe)
        return scene_time_scale(self.name, self.full_params, self.spec)


def skipped_note(subject: Subject, skipped: list[str]) -> str:
    """The note saying which methods "all" left out, or ""."""
    if not skipped:
        return ""
    if subject.kind == "bodies":
        return (
            f"skipped {', '.join(skipped)}: arithmetic on positions as vectors does not apply to "
            f"the orientations of {subject.name}'s rigid bodies"
        )
    return (
        f"skipped {', '.join(skipped)}: split methods need a second-order system and "
        f"{subject.name} is a first-order flow"
    )


def scene_time_scale(scene: str, p: dict[str, float], spec: dict[str, Any] | None) -> float:
    """A built-in particle scene's natural time scale, s, from its parameters: its period where
    it oscillates or orbits, its decay time m/c under drag, otherwise its default run length."""
    tau = 2.0 * math.pi
    if scene == "spring":
        if p["k"] > 0:
            return tau * math.sqrt(p["m"] / p["k"])
        if p["c"] > 0:
            return p["m"] / p["c"]
    elif scene == "drag" and p["c"] > 0:
        return p["m"] / p["c"]
    elif scene == "orbit":
        return tau * math.sqrt(p["r"] ** 3 / p["gm"])
    elif scene == "kepler":
        return tau
    elif scene == "pendulum" and p["g"] > 0:
        return tau * math.sqrt(p["length"] / p["g"])
    elif scene == "chain" and p["k"] > 0:
        return tau * math.sqrt(p["m"] / p["k"])
    assert spec is not None
    return float(spec["until"])


def estimated_time_scale(probe: Trajectory) -> float:
    """The time scale, s, of a system (or a flow scene), estimated from its initial state.

    - particles: 2 pi sqrt(|x0| / |a0|) from the initial acceleration (norms over every
      coordinate): the period of a harmonic oscillator let go from rest, of a circular orbit,
      the fall time's scale under gravity; with no acceleration 2 pi |x0| / |v0|; else
      :data:`FALLBACK_TIME_SCALE`.
    - flows y' = f(t, y): 2 pi |y0| / |f(0, y0)|: the period of a rotation y' = w J y, 2 pi
      tau for a decay y' = -y / tau (Lorenz from (1, 1, 1): 0.418 s, about the time of one
      turn round a lobe); :data:`FALLBACK_TIME_SCALE` at a fixed point or at y0 = 0.

    Positions are measured from the origin: an oscillator about another point, or a state
    far from where the motion happens, misleads it. Pass ``time_scale=`` then.
    """
    x, v, a = (float(np.linalg.norm(q[0])) if q.shape[1] else 0.0 for q in (probe.x, probe.v, probe.a))
    if probe.kind == "flow":
        ratio = x / v if x > 0 and v > 0 else math.nan
    elif x > 0 and a > 0:
        ratio = math.sqrt(x / a)
    else:
        ratio = x / v if x > 0 and v > 0 else math.nan
    tau = 2.0 * math.pi * ratio
    return tau if math.isfinite(tau) and tau > 0 else FALLBACK_TIME_SCALE


def time_scale(scene: Any, params: dict[str, float] | None = None) -> float:
    """The natural time scale, s, of a scene or system.

    A built-in particle scene's comes from its parameters: its period where it oscillates or
    orbits, its decay time m/c under drag, otherwise its default run length. A system's
    (and a flow scene's: lorenz, rossler, thomas) is estimated from its initial state, see
    :func:`estimated_time_scale`.
    """
    return Subject(scene, params).time_scale()


def table(
    subject: Subject, until: float, error_against: str, skipped: list[str], jobs_note: str = ""
) -> dict[str, Any]:
    """The fields every table of runs (compare, sweep) shares but its rows: what was
    measured, against what and how; ``jobs_note`` (how ``jobs`` ran, where not as asked) is
    appended to the note."""
    note = "; ".join(n for n in (skipped_note(subject, skipped), jobs_note) if n)
    return {
        "scene": subject.name,
        "kind": subject.kind,
        "until": until,
        "until_requested": until,
        "params": subject.full_params,
        "error_against": error_against,
        "energy_error": ENERGY_ERROR,
        "timing": timing_note(),
        "skipped": tuple(skipped),
        "note": note,
    }
