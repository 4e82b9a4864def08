"""physstep: a game-physics integration engine.

Every integrator of the game-physics lecture notes behind one interface, particles with
composable forces, rigid bodies, the fixed-timestep game loop, and a lab that measures how
each method behaves on your system. The engine is Rust (``physstep._core``); this package
is the Python face.

Examples:
    >>> import physstep
    >>> traj = physstep.simulate("spring", "symplectic-euler", dt=1.0, until=2.0)
    >>> traj.x[:, 0].tolist()
    [20.0, 10.0, -5.0]
"""

from __future__ import annotations

# isort: off
# First, before numpy: Ctrl-C while the `physstep` command loads exits 130 (physstep._startup).
import physstep._startup  # noqa: F401
# isort: on

import copy
import functools
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from physstep import _constraints, _core
from physstep._core import (
    Bodies,
    Body,
    BodyForceHandle,
    BodyHandle,
    BodySpringHandle,
    Box,
    Capsule,
    Circle,
    ConstraintHandle,
    ConstraintWarning,
    ConvergenceError,
    Cylinder,
    DivergedError,
    ForceHandle,
    JointHandle,
    MassProperties,
    Mesh,
    Particle,
    ParticleHandle,
    ParticleHandles,
    Particles,
    Plane,
    Polygon,
    Segment,
    Shape,
    SolidForceHandle,
    SolidHandle,
    Solids,
    SolidShape,
    SolidSpringHandle,
    Sphere,
    StepError,
    World,
    WorldBusyError,
    angular_forms,
    contact_solvers,
    orientation_rules,
)
from physstep._scenefile import SceneFile, export_scene, load_scene, scene_text

__all__ = [
    "Bodies",
    "Body",
    "BodyForceHandle",
    "BodyHandle",
    "BodySpringHandle",
    "Box",
    "Capsule",
    "Circle",
    "ConstraintHandle",
    "ConstraintWarning",
    "ConvergenceError",
    "Cylinder",
    "DivergedError",
    "Flow",
    "ForceHandle",
    "JointHandle",
    "MassProperties",
    "Mesh",
    "MethodInfo",
    "Particle",
    "ParticleHandle",
    "ParticleHandles",
    "Particles",
    "Plane",
    "Polygon",
    "SceneFile",
    "Segment",
    "Shape",
    "SolidForceHandle",
    "SolidHandle",
    "SolidShape",
    "SolidSpringHandle",
    "SolverInfo",
    "Solids",
    "Sphere",
    "StepError",
    "Trajectory",
    "World",
    "WorldBusyError",
    "angular_forms",
    "contact_solvers",
    "export_scene",
    "load_scene",
    "method",
    "methods",
    "orientation_rules",
    "scene",
    "scene_text",
    "scenes",
    "simulate",
    "solvers",
    "summarize",
]

__version__ = "0.1.0"


def __getattr__(name: str) -> Any:
    """``physstep.lab`` and ``physstep.plot`` on first use: ``import physstep`` is enough,
    and matplotlib is loaded only when a plot is asked for."""
    if name in ("lab", "plot"):
        import importlib

        return importlib.import_module(f"physstep.{name}")
    raise AttributeError(f"module 'physstep' has no attribute {name!r}")


@dataclass(frozen=True)
class MethodInfo:
    """What an integrator is: its registry name, order, properties and one-line doc.

    ``split``: it needs positions and velocities apart (not for first-order flows);
    ``vector_positions``: it does arithmetic on positions as vectors (Verlet's
    ``2 x - x_prev``), so it does not apply to rigid bodies' orientations; ``period``: the
    steps after which its step map repeats (2 for the alternating symplectic Euler)."""

    name: str
    order: int
    symplectic: bool
    implicit: bool
    evals: int
    split: bool
    doc: str
    vector_positions: bool = False
    period: int = 1


def methods() -> list[MethodInfo]:
    """Every integrator in the registry, in order."""
    return [MethodInfo(**m) for m in _core.methods()]


@dataclass(frozen=True)
class SolverInfo:
    """What a contact solver is: its registry name (``World.contact_solver``), one line on
    what it does, its family (what it corrects: ``"velocity"``, impulses on the velocities
    with the positions following by the drift, or ``"velocity + position"``, impulses and
    then passes that move the positions), and the constraint passes it makes a step in terms
    of ``World.substeps`` and ``World.solver_iterations`` (every solver makes the same number
    at the same settings, so solvers compare at equal cost)."""

    name: str
    summary: str
    family: str
    passes: str


def solvers() -> list[SolverInfo]:
    """Every contact solver in the registry, in order (``physstep solvers`` prints them)."""
    return [SolverInfo(**s) for s in _core.solver_infos()]


def method(name: str) -> MethodInfo:
    """The integrator registered as ``name``; ValueError listing the valid names otherwise."""
    return MethodInfo(**_core.method_info(name))


@functools.cache
def _scene_specs() -> tuple[dict[str, Any], ...]:
    return tuple(_core.scenes())


def _spec(name: str) -> dict[str, Any]:
    for s in _scene_specs():
        if s["name"] == name:
            return s
    valid = ", ".join(s["name"] for s in _scene_specs())
    raise ValueError(f"unknown scene '{name}'; valid scenes: {valid}")


def scenes() -> list[dict[str, Any]]:
    """Every built-in scene: name, doc, dim, default method, dt and until, and parameters."""
    return copy.deepcopy(list(_scene_specs()))


def scene(name: str) -> dict[str, Any]:
    """One built-in scene's description; ValueError listing the valid names otherwise."""
    return copy.deepcopy(_spec(name))


@dataclass(frozen=True)
class Flow:
    """A first-order flow ``y' = fn(t, y)`` from ``y0``: a strange attractor, any ODE.

    ``fn(t, y)`` gets the time and the state (a 1-D array) and returns the derivative;
    ``jacobian(t, y)``, if given, returns ``df/dy`` (``len(y0)`` x ``len(y0)``) for the
    implicit methods. The flow methods (Euler, midpoint, Heun, RK4, the implicit ones)
    integrate it; the split methods refuse it with one clear line. Pass it (or a callable
    returning it) to :func:`simulate` and to every ``physstep.lab`` function in place of a
    scene name.

    Examples:
        >>> import physstep
        >>> decay = physstep.Flow(lambda t, y: -y, [1.0])
        >>> round(float(physstep.simulate(decay, "rk4", dt=0.1, until=1.0).x[-1, 0]), 5)
        0.36788
    """

    fn: Callable[[float, np.ndarray], Any]
    y0: Any
    jacobian: Callable[[float, np.ndarray], Any] | None = None
    name: str | None = None

    def world(self, method: str = "rk4", dt: float = 0.01) -> World:
        """A fresh World whose part is this flow."""
        return World.from_flow(self.fn, self.y0, method, dt, jacobian=self.jacobian, name=self.name)


def _system_world(system: Any, method: str | None, dt: float | None) -> tuple[World, str]:
    """The fresh World of a user system (a Flow, or a zero-argument callable returning a
    World or a Flow) with ``method`` and ``dt`` applied, and the system's name."""
    name = getattr(system, "name", None) or getattr(system, "__name__", None) or "system"
    made = system if isinstance(system, Flow) else system()
    if isinstance(made, Flow):
        world = made.world(method or "rk4", 0.01 if dt is None else dt)
        return world, made.name or name
    if not isinstance(made, World):
        raise ValueError(
            f"invalid system = {system!r}: must be a Flow or a callable returning a fresh World or Flow "
            f"(it returned {type(made).__name__})"
        )
    if method is not None:
        made.method = method
    if dt is not None:
        made.dt = dt
    return made, name


class _Deferred:
    """A column of a :class:`Trajectory` computed when it is first read: ``rows()`` returns
    the column(s) it stands for, and ``part`` picks one of a pair (the exact positions and
    velocities are computed together)."""

    __slots__ = ("_rows", "_part", "_done")

    def __init__(self, rows: Callable[[], Any], part: int | None = None) -> None:
        self._rows, self._part = rows, part
        self._done: tuple[Any] | None = None

    def value(self) -> Any:
        if self._done is None:
            self._done = (self._rows(),)
        out = self._done[0]
        return out if self._part is None else out[self._part]


class _Lazy:
    """A :class:`Trajectory` field whose value may be a :class:`_Deferred`, computed on
    first read and kept (a dataclass field whose default is this descriptor: the generated
    ``__init__``, ``repr``, ``==`` and ``dataclasses.replace`` all go through it)."""

    def __set_name__(self, owner: type, name: str) -> None:
        self._name = "_" + name

    def __get__(self, obj: Any, owner: type | None = None) -> Any:
        if obj is None:
            return None  # the field's default
        v = obj.__dict__.get(self._name)
        if isinstance(v, _Deferred):
            v = v.value()
            obj.__dict__[self._name] = v
        return v

    def __set__(self, obj: Any, value: Any) -> None:
        obj.__dict__[self._name] = value


def _exact_columns(raw: dict[str, Any]) -> None:
    """``raw["exact"]`` (the scene's exact solution, or None) as the deferred ``exact_x`` and
    ``exact_v`` columns at the recorded times."""
    exact = raw.pop("exact", None)
    if exact is None:
        raw["exact_x"] = raw["exact_v"] = None
        return
    t = raw["t"]
    both = _Deferred(lambda: exact.rows(t))
    raw["exact_x"] = _Deferred(both.value, 0)
    raw["exact_v"] = _Deferred(both.value, 1)


def _kinetic_column(raw: dict[str, Any]) -> None:
    """``raw["kinetic"]``, when the recording deferred it (a callable), as a deferred
    column."""
    k = raw.get("kinetic")
    if callable(k):
        raw["kinetic"] = _Deferred(k)


#: The smallest ``|E0|``, as a fraction of the largest kinetic energy of a run, that the energy
#: error is measured against (:attr:`Trajectory.energy_scale`): below it E0 is a near
#: cancellation (or rounding), and the error is relative to the energy that moves.
E0_MEANINGFUL = 1e-3


@dataclass
class Trajectory:
    """A recorded run: rows of time, positions, velocities, accelerations and energy.

    ``x``, ``v`` and ``a`` have shape (rows, coordinates): coordinate ``p * dim + k`` is axis
    ``k`` of particle ``p``. ``exact_x``/``exact_v`` hold the exact solution at the same
    times where the scene has one, and ``kinetic`` the kinetic energy of every row; the
    three are computed when first read (a run that never reads them does not pay for
    them). Where the world has rigid bodies (``kind == "bodies"``),
    ``angular_momentum`` (rows, 3) is the total about the origin and ``body_spin``
    (rows, bodies, 3) each body's angular velocity in its principal frame (ascending
    moments), where the tennis-racket flips show. Where the world has solids, ``contacts``
    says at the end how many solids there are, how many contact points touch, the deepest
    penetration (m) and the fastest solid (m/s), and where sleeping is on how many sleep
    (``asleep``: their contacts are not counted). Where the world has balls, ``collisions``
    holds the contact statistics at the end (``count``, ``max_overlap`` in m, ``pair_tests``).
    ``world`` is the World a system's run stepped (a scene file, your callable or Flow), at
    its final state; None for a built-in scene. What :func:`summarize` says of the run's
    constraints comes from it (or from the built-in scene), never from a scene of the same
    name.
    """

    scene: str
    method: str
    dt: float
    dim: int
    steps: int
    evals: int
    elapsed_ns: int
    params: dict[str, float]
    t: np.ndarray
    x: np.ndarray
    v: np.ndarray
    a: np.ndarray
    energy: np.ndarray | None
    kinetic: np.ndarray | None = _Lazy()  # type: ignore[assignment]
    kind: str = "particles"
    exact_x: np.ndarray | None = _Lazy()  # type: ignore[assignment]
    exact_v: np.ndarray | None = _Lazy()  # type: ignore[assignment]
    stages: list[tuple[int, str, float, list[float], list[float], list[float]]] | None = None
    diverged: str | None = None
    angular_momentum: np.ndarray | None = None
    body_spin: np.ndarray | None = None
    collisions: dict[str, float] | None = None
    contacts: dict[str, float] | None = None
    world: World | None = field(default=None, repr=False, compare=False)

    def __getstate__(self) -> dict[str, Any]:
        """For pickle (the lab sends reference runs to its worker processes): the columns
        computed on first read are computed now, as plain arrays (what they defer to is the
        engine's, which does not pickle)."""
        state = dict(self.__dict__)
        for name, value in state.items():
            if isinstance(value, _Deferred):
                state[name] = value.value()
        return state

    @property
    def ns_per_step(self) -> float:
        """Wall time of the stepping loop per step (recording included), ns."""
        return self.elapsed_ns / max(self.steps, 1)

    @property
    def energy_scale(self) -> float:
        """The energy the error is measured against, J (:attr:`energy_scale_of` says which):
        ``|E0|`` where it is a scale, at least :data:`E0_MEANINGFUL` of the largest kinetic
        energy of the run (a Kepler orbit's error is relative to its binding energy, so one
        that became unbound reads above 1); else the largest kinetic energy (a chain released
        from rest at the height of its pivot: E0 = 3e-30 J, from rounding, is no scale); 1 J
        (an absolute error) when nothing moves and E0 = 0.
        """
        return self._energy_scale()[0]

    @property
    def energy_scale_of(self) -> str:
        """What :attr:`energy_scale` is: ``"|E0|"``, ``"the largest kinetic energy"`` or
        ``"1 J"``."""
        return self._energy_scale()[1]

    def _energy_scale(self) -> tuple[float, str]:
        if self.energy is None:
            raise ValueError(
                f"the energy of this {self.kind} run is unknown (a flow, or a force without a potential)"
            )
        kin = float(np.max(self.kinetic)) if self.kinetic is not None and len(self.kinetic) else 0.0
        e0 = abs(float(self.energy[0]))
        if e0 > 0 and e0 >= E0_MEANINGFUL * kin:
            return e0, "|E0|"
        if kin > 0:
            return kin, "the largest kinetic energy"
        return 1.0, "1 J"

    @property
    def energy_error(self) -> np.ndarray | None:
        """Relative energy error ``(E - E0) / energy_scale`` of every row; None when the
        energy is unknown (a flow, or a user force without a potential)."""
        if self.energy is None:
            return None
        return (self.energy - self.energy[0]) / self.energy_scale

    @property
    def position_error(self) -> np.ndarray | None:
        """Distance from the exact positions of every row (max over coordinates), or None."""
        if self.exact_x is None:
            return None
        return np.abs(self.x - self.exact_x).max(axis=1)


def simulate(
    scene: str,
    method: str | None = None,
    dt: float | None = None,
    until: float | None = None,
    params: dict[str, float] | None = None,
    *,
    x0: Any = None,
    v0: Any = None,
    stages: bool = False,
    every: int = 1,
    stop_on_diverge: bool = False,
) -> Trajectory:
    """Runs a built-in scene, or your own system, with an integrator and records it.

    ``scene`` is a built-in scene's name, a :class:`Flow`, or a zero-argument callable
    that returns a fresh :class:`World` (your particles and forces, Python forces included)
    or a :class:`Flow`. For a system, ``until`` is required, ``method`` and ``dt`` (when
    given) replace the world's own, and the trajectory has no exact solution (the lab
    measures it against a reference run).

    ``method``, ``dt`` and ``until`` default to the scene's own (see :func:`scenes`: RK4 for
    the flows, backward Euler for the stiff scenes, symplectic Euler elsewhere); ``params``
    override the scene's parameters; ``x0``/``v0`` (flat or (n, dim)) replace its initial
    state. ``every`` records one row in ``every`` steps (the last is always recorded).
    ``stages`` records the intermediate evaluation points (midpoint's ``half``, RK4's
    ``xa``, ``xb``, ``xc``). A step that diverges raises :class:`DivergedError`, or with
    ``stop_on_diverge`` ends the run there and is reported in ``Trajectory.diverged``.

    Raises ValueError naming the bad field and value for any bad input.
    """
    if isinstance(scene, Flow) or (callable(scene) and not isinstance(scene, str)):
        return _simulate_system(scene, method, dt, until, params, x0, v0, stages, every, stop_on_diverge)
    if not isinstance(scene, str):
        raise ValueError(
            f"invalid scene = {scene!r}: must be a scene name, a Flow or a callable returning a World"
        )
    spec = _spec(scene)
    raw = _core.simulate(
        scene,
        spec["method"] if method is None else method,
        spec["dt"] if dt is None else dt,
        spec["until"] if until is None else until,
        params,
        x0=x0,
        v0=v0,
        stages=stages,
        every=every,
        stop_on_diverge=stop_on_diverge,
    )
    _exact_columns(raw)
    _kinetic_column(raw)
    return Trajectory(**raw)


def _simulate_system(
    system: Any,
    method: str | None,
    dt: float | None,
    until: float | None,
    params: Any,
    x0: Any,
    v0: Any,
    stages: bool,
    every: int,
    stop_on_diverge: bool,
) -> Trajectory:
    if params:
        raise ValueError(
            f"invalid params = {params!r}: a system has no scene parameters (build them into it)"
        )
    if until is None:
        raise ValueError("invalid until = None: a system has no default run length; give until")
    world, name = _system_world(system, method, dt)
    if x0 is not None:
        world.positions = np.asarray(x0, dtype=float).reshape(world.positions.shape)
    if v0 is not None:
        world.velocities = np.asarray(v0, dtype=float).reshape(world.velocities.shape)
    raw = world.record(until, every=every, stop_on_diverge=stop_on_diverge, stages=stages)
    _kinetic_column(raw)
    return Trajectory(scene=name, params={}, world=world, **raw)


def _dissipation(traj: Trajectory) -> str | None:
    """Why the run loses energy by design, or None: the scene's damping, drag or inelastic
    contacts (``scene(name)["loss"]``, with the run's parameters), or a method that damps
    (implicit and not symplectic: backward Euler)."""
    why: list[str] = []
    if traj.world is None:
        try:
            loss = _spec(traj.scene)["loss"]
        except ValueError:
            loss = None
        if loss is not None:
            when, param, reason = loss
            value = traj.params.get(param, 0.0)
            if when == "always" or (when == "nonzero" and value != 0) or (when == "below_one" and value < 1):
                why.append(reason)
    info = {m.name: m for m in methods()}.get(traj.method)
    if info is not None and info.implicit and not info.symplectic:
        why.append(f"{traj.method} damps by design")
    return "; ".join(why) or None


def summarize(traj: Trajectory) -> dict[str, Any]:
    """The summary of a run, as ``physstep run --format json`` prints it."""
    e = traj.energy
    out: dict[str, Any] = {
        "scene": traj.scene,
        "method": traj.method,
        "dt": traj.dt,
        "params": dict(traj.params),
        "steps": int(traj.steps),
        "t": float(traj.t[-1]),
        "final": {"x": traj.x[-1].tolist(), "v": traj.v[-1].tolist()},
        "energy": None,
        "evals": int(traj.evals),
        "ns_per_step": traj.ns_per_step,
    }
    if e is not None:
        e0, scale = float(e[0]), traj.energy_scale
        out["energy"] = {
            "initial": e0,
            "final": float(e[-1]),
            "max_rel_error": float(np.max(np.abs(e - e0)) / scale),
            "scale": scale,
            "scale_of": traj.energy_scale_of,
            # Where the scene or the method loses energy by design: why, and the energy lost
            # (J; what the run lost is not an error there).
            "dissipation": _dissipation(traj),
            "lost": e0 - float(e[-1]),
        }
    if traj.angular_momentum is not None:
        ang = traj.angular_momentum
        l0 = float(np.linalg.norm(ang[0]))
        out["angular_momentum"] = {
            "initial": ang[0].tolist(),
            "final": ang[-1].tolist(),
            "max_rel_error": float(np.max(np.linalg.norm(ang - ang[0], axis=1)) / (l0 if l0 > 0 else 1.0)),
        }
    if traj.exact_x is not None:
        err = traj.position_error
        assert err is not None
        out["error"] = {"final_position": float(err[-1]), "max_position": float(err.max())}
    constraints = _constraints.summary(traj)
    if constraints is not None:
        out["constraints"] = constraints
    if traj.collisions is not None:
        c = traj.collisions
        out["collisions"] = {"count": int(c["count"]), "max_overlap": float(c["max_overlap"])}
    if traj.contacts is not None:
        c = traj.contacts
        out["contacts"] = {
            "solids": int(c["solids"]),
            "count": int(c["count"]),
            "max_penetration": float(c["max_penetration"]),
            "max_speed": float(c["max_speed"]),
        }
        if "asleep" in c:
            out["contacts"]["asleep"] = int(c["asleep"])
    if traj.diverged:
        out["diverged"] = traj.diverged
    return out
