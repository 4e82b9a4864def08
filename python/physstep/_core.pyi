"""Type stubs of the native module ``physstep._core`` (kept in step with crates/physstep-py).

Every bad argument raises ValueError naming the field and the value (``invalid dt = 0.0:
...``), never TypeError; a step that fails raises a :class:`StepError` with that step rolled
back; a World used by two threads at once raises :class:`WorldBusyError`.
"""

from collections.abc import Callable, Iterator
from typing import Any, final

import numpy as np
import numpy.typing as npt
from typing_extensions import disjoint_base

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
    "ForceHandle",
    "JointHandle",
    "MassProperties",
    "Mesh",
    "Particle",
    "ParticleHandle",
    "ParticleHandles",
    "Particles",
    "Plane",
    "Polygon",
    "Segment",
    "Shape",
    "SolidForceHandle",
    "SolidHandle",
    "SolidShape",
    "SolidSpringHandle",
    "Solids",
    "Sphere",
    "StepError",
    "World",
    "WorldBusyError",
    "_world_from_scene",
    "angular_forms",
    "contact_solvers",
    "solver_infos",
    "method_info",
    "methods",
    "orientation_rules",
    "read_scene",
    "scene_file_text",
    "scenes",
    "simulate",
]

class StepError(RuntimeError):
    """A step failed; the state was rolled back to before that step."""

class DivergedError(StepError):
    """A step produced a non-finite or runaway value (or a non-finite energy)."""

class ConvergenceError(StepError):
    """An implicit method's Newton iteration did not converge."""

class WorldBusyError(RuntimeError):
    """The World is in use by another thread (or by a callback inside its own step)."""

class ConstraintWarning(UserWarning):
    """The world's constraints cannot all be met (World.constraint_conflicts() lists why)."""

_Params = dict[str, float] | list[tuple[str, float]] | None

def methods() -> list[dict[str, Any]]:
    """Every integrator's metadata, in registry order: dicts with ``name``, ``order``,
    ``symplectic``, ``implicit``, ``evals`` (force evaluations per step), ``split``, ``doc``."""

def method_info(name: str) -> dict[str, Any]:
    """The metadata of the integrator ``name`` (the keys of :func:`methods`).

    Raises ValueError listing the valid names for an unknown one.
    """

def scenes() -> list[dict[str, Any]]:
    """Every built-in scene: dicts with ``name``, ``doc``, ``dim``, ``method`` (the method
    that runs it well at its ``dt``: the default of ``simulate``, ``World.from_scene`` and
    the command line), ``loss`` (where the scene loses energy by design: ``(when, param,
    why)`` with ``when`` one of ``"always"``, ``"nonzero"`` (when ``param`` is not 0),
    ``"below_one"`` (when ``param`` is below 1), or None), ``dt`` (s), ``until`` (s) and
    ``params`` (dicts with ``name``, ``default``, ``doc``)."""

def orientation_rules() -> dict[str, str]:
    """The orientation rules of rigid bodies (how a drift turns a body), in order: a dict of
    name to a one-line doc (``matrix``, ``quaternion``, ``exponential``, ``splitting``)."""

def angular_forms() -> dict[str, str]:
    """The angular forms of rigid bodies (what a kick integrates), in order: a dict of name to
    a one-line doc (``momentum``, ``velocity``, ``velocity-gyroscopic``,
    ``velocity-implicit``)."""

@final
class MassProperties:
    """The mass properties of a shape of constant density (:meth:`Shape.mass_properties`).

    Every array is a fresh copy.
    """

    @property
    def mass(self) -> float:
        """Mass, kg."""

    @property
    def volume(self) -> float:
        """Volume, m^3."""

    @property
    def center(self) -> npt.NDArray[np.float64]:
        """Centre of mass in the shape's frame (3,), m."""

    @property
    def inertia(self) -> npt.NDArray[np.float64]:
        """Inertia tensor about the centre of mass (3, 3), in the shape's axes, kg m^2."""

    @property
    def principal_moments(self) -> npt.NDArray[np.float64]:
        """The eigenvalues of :attr:`inertia`, ascending (3,), kg m^2."""

    @property
    def principal_axes(self) -> npt.NDArray[np.float64]:
        """The principal axes as rows (3, 3), orthonormal and right-handed: with
        ``R = principal_axes``, ``R @ inertia @ R.T == diag(principal_moments)``."""

@disjoint_base
class Shape:
    """A rigid-body shape in its own frame (sizes in m): :class:`Sphere`, :class:`Box`,
    :class:`Cylinder`, :class:`Capsule` or :class:`Mesh`.

    Shapes are immutable values: checked when made (ValueError naming the bad field), equal
    when their sizes are, hashable, and they pickle.
    """

    def mass_properties(self, mass: float | None = None, density: float | None = None) -> MassProperties:
        """The mass properties for a ``mass`` (kg) or a ``density`` (kg/m^3), at most one of
        them; with neither the density is 1 (mass = volume). ValueError naming ``mass`` or
        ``density`` (out of [1e-12, 1e12], or both given)."""

    @property
    def volume(self) -> float:
        """Volume, m^3."""

    def __eq__(self, other: object, /) -> bool:
        """Equal to a shape of the same kind and sizes (a mesh: the same vertices and triangles)."""

    def __hash__(self) -> int:
        """A hash consistent with ``==``."""

    def __reduce__(self) -> tuple[Any, tuple[Any, ...]]:
        """Pickles as the class and the constructor's arguments."""

@final
class Sphere(Shape):
    """A solid ball of ``radius`` (m) centred on the origin."""

    def __new__(cls, radius: float) -> Sphere:
        """ValueError naming ``radius`` unless it is in [1e-12, 1e12]."""

    @property
    def radius(self) -> float:
        """Radius, m."""

@final
class Box(Shape):
    """A solid box centred on the origin, its edges along the axes."""

    def __new__(cls, hx: float, hy: float, hz: float | None = None) -> Box:
        """Half edge lengths ``hx``, ``hy``, ``hz`` (m); ValueError naming ``half_extents[k]``
        unless each is in [1e-12, 1e12]. Without ``hz``, a 2D box (a rectangle) for
        :meth:`World.add_solid` in a 2D world (its ``hz`` reads 0; ``add_body`` refuses it)."""

    @property
    def half_extents(self) -> tuple[float, float, float]:
        """Half the edge lengths along x, y and z, m."""

@final
class Cylinder(Shape):
    """A solid circular cylinder along its local z axis, centred on the origin."""

    def __new__(cls, radius: float, height: float) -> Cylinder:
        """``radius`` and length ``height`` (m); ValueError naming the one out of [1e-12, 1e12]."""

    @property
    def radius(self) -> float:
        """Radius, m."""

    @property
    def height(self) -> float:
        """Length along local z, m."""

@final
class Capsule(Shape):
    """A capsule along local z centred on the origin: a cylinder closed by two hemispheres
    of its radius (total length ``height + 2 radius``)."""

    def __new__(cls, radius: float, height: float) -> Capsule:
        """``radius`` of the cylinder and caps, ``height`` of the cylindrical part alone (m);
        ValueError naming the one out of [1e-12, 1e12]."""

    @property
    def radius(self) -> float:
        """Radius of the cylinder and of the caps, m."""

    @property
    def height(self) -> float:
        """Length of the cylindrical part alone, m."""

@final
class Mesh(Shape):
    """A closed, consistently oriented triangle mesh bounding a solid; its mass properties
    are exact (divergence theorem)."""

    def __new__(cls, vertices: npt.ArrayLike, triangles: npt.ArrayLike) -> Mesh:
        """``vertices`` (n, 3), m, and ``triangles`` (m, 3) vertex indices, each wound
        counter-clockwise seen from outside, every edge shared by exactly two triangles in
        opposite directions. ValueError naming the bad field: ``vertices[3][2]``,
        ``triangles[5][1]``, ``triangles[5]`` (a hole, a flipped triangle, a non-manifold
        edge), ``triangles`` (inside out or flat)."""

    @property
    def vertices(self) -> npt.NDArray[np.float64]:
        """Vertex positions (n, 3), m: a copy."""

    @property
    def triangles(self) -> npt.NDArray[np.int64]:
        """Triangles (m, 3), vertex indices: a copy."""

@disjoint_base
class SolidShape:
    """A shape only solids take (sizes in m), checked when it is added to a world:
    :class:`Circle`, :class:`Polygon`, :class:`Segment` or :class:`Plane`."""

    @property
    def kind(self) -> str:
        """The shape's name: circle, polygon, segment or plane."""

@final
class Circle(SolidShape):
    """A disc in a 2D world, a sphere in a 3D one."""

    def __new__(cls, radius: float) -> Circle:
        """``radius`` (m), finite and > 0 (ValueError naming ``radius``)."""

@final
class Polygon(SolidShape):
    """A convex polygon (2D: its corners in order, either way round) or the convex hull of
    its points (3D)."""

    def __new__(cls, points: npt.ArrayLike) -> Polygon:
        """``points``, an array of shape (n, 2) or (n, 3), m. Convexity and area are checked
        when the polygon is added (ValueError naming ``points``)."""

@final
class Segment(SolidShape):
    """A segment from ``a`` to ``b``, thickened by ``radius`` (0: a bare segment, static or
    kinematic only)."""

    def __new__(cls, a: npt.ArrayLike, b: npt.ArrayLike, radius: float = 0.0) -> Segment:
        """Ends ``a`` and ``b`` (m), ``radius`` >= 0 (m)."""

@final
class Plane(SolidShape):
    """The ground: the half-space behind a plane (a line in 2D) through the solid's position,
    with outward ``normal``. Static or kinematic only."""

    def __new__(cls, normal: npt.ArrayLike) -> Plane:
        """``normal``, a non-zero direction (normalised when added)."""

def contact_solvers() -> dict[str, str]:
    """The contact solvers, name -> one line on what each does, in registry order."""

def solver_infos() -> list[dict[str, str]]:
    """The contact solvers in registry order, each a dict: ``name``, ``summary`` (one line on
    what it does), ``family`` (what it corrects: ``velocity``, or ``velocity + position``)
    and ``passes`` (the constraint passes it makes a step, in the settings' terms)."""

def read_scene(path: str) -> tuple[World, float | None]:
    """Reads the scene file at ``path``: the World it describes and its ``until`` (None when
    the file has none). ValueError naming the file, the line and the field for a bad file."""

def scene_file_text(world: World, title: Any, until: Any = None) -> str:
    """``world`` as the text of a scene file (``title`` in its first comment line, ``until``
    if given). ValueError for what a file cannot hold (Python forces and flows, body
    springs, bodies of a world that has stepped)."""

def _world_from_scene(parts: dict[str, Any], snapshot: bytes) -> World:
    """Rebuilds a World pickled by ``World.__reduce__``: ``parts["scene"]`` (the engine's
    scene text of it) parsed under ``parts["loop"]``/``parts["substeps"]``, its Python
    callables added back in order, and ``snapshot`` restored."""

def simulate(
    scene: str,
    method: str,
    dt: float,
    until: float,
    params: _Params = None,
    *,
    x0: npt.ArrayLike | None = None,
    v0: npt.ArrayLike | None = None,
    stages: bool | None = None,
    every: int | None = None,
    stop_on_diverge: bool | None = None,
) -> dict[str, Any]:
    """Runs the built-in ``scene`` with ``method`` at step ``dt`` (s) for ``until`` (s) and
    returns the fields of a ``physstep.Trajectory`` as a dict of numpy arrays; its
    ``exact`` is the scene's exact solution (``exact.rows(t)`` gives ``(exact_x,
    exact_v)``), computed only when asked, or None.

    ``params`` override the scene's parameters; ``x0``/``v0`` (m, m/s; flat or (n, dim))
    replace its initial state; ``every`` records one row in ``every`` steps (default 1);
    ``stages`` records the intermediate evaluation points; ``stop_on_diverge`` ends the run
    at a failing step and reports it in ``diverged`` instead of raising.

    Raises ValueError for any bad argument (unknown scene or method, dt <= 0, ...),
    DivergedError or ConvergenceError when a step fails, KeyboardInterrupt on Ctrl-C.
    """

@final
class Particle:
    """One particle of a World (``w.particles[i]``): its state read and written through the
    World. Each read is a copy; each write is validated as ``add_particle`` validates
    (ValueError naming the field, the World unchanged) and, as assigning
    ``World.positions`` does, restarts a method that carries memory (Verlet's previous
    positions: a teleport is not a velocity)."""

    @property
    def index(self) -> int:
        """The particle's index in the World (its row of ``World.positions``; for a view
        taken by handle, its current row: ValueError once the particle is removed)."""
    @property
    def position(self) -> npt.NDArray[np.float64]:
        """Position (dim,), m; assign to move the particle."""
    @position.setter
    def position(self, value: npt.ArrayLike) -> None: ...
    @property
    def velocity(self) -> npt.NDArray[np.float64]:
        """Velocity (dim,), m/s; assign to set it (a static particle's must stay zero)."""
    @velocity.setter
    def velocity(self, value: npt.ArrayLike) -> None: ...
    @property
    def mass(self) -> float:
        """Mass, kg; assign to change it (> 0 with a finite inverse, at most 1e100; the
        velocity is kept). A dynamic particle takes a finite mass; a static one stays
        static."""
    @mass.setter
    def mass(self, value: float) -> None: ...
    @property
    def static(self) -> bool:
        """Whether the particle is static (immovable): fixed when it is added."""

@final
class Particles:
    """The particles of a World as a sequence of :class:`Particle` views:
    ``len(w.particles)``, ``w.particles[i]`` (negative from the end; IndexError past the
    end), iteration. Rows in the order the particles were added, removed ones taken out.
    A view taken by a :class:`ParticleHandle` (``w.particles[h]``) follows that particle
    while others are removed (ValueError once it is removed itself); one taken by an int
    names the row."""

    def __len__(self) -> int: ...
    def __getitem__(self, key: int | ParticleHandle, /) -> Particle: ...
    def __iter__(self) -> Iterator[Particle]: ...

@final
class Body:
    """One rigid body of a World (``w.bodies[b]``): its state read and written through the
    World, validated as ``add_body`` validates (ValueError naming the field, the World
    unchanged); a write restarts a method that carries memory."""

    @property
    def index(self) -> int:
        """The body's index in the World (its row of ``World.bodies.positions``)."""
    @property
    def position(self) -> npt.NDArray[np.float64]:
        """Centre of mass (3,), m; assign to move the body (refused for a pinned body)."""
    @position.setter
    def position(self, value: npt.ArrayLike) -> None: ...
    @property
    def velocity(self) -> npt.NDArray[np.float64]:
        """Velocity of the centre of mass (3,), m/s; assign to set it (a pinned body's must
        be zero)."""
    @velocity.setter
    def velocity(self, value: npt.ArrayLike) -> None: ...
    @property
    def orientation(self) -> npt.NDArray[np.float64]:
        """Orientation of the shape frame (4,), a unit quaternion (w, x, y, z); assign any
        quaternion of length >= 1e-12: it is normalised, as ``add_body`` does (a shorter one
        or one not finite is refused). The angular velocity is kept."""
    @orientation.setter
    def orientation(self, value: npt.ArrayLike) -> None: ...
    @property
    def angular_velocity(self) -> npt.NDArray[np.float64]:
        """Angular velocity (3,), rad/s, world frame; assign to set it."""
    @angular_velocity.setter
    def angular_velocity(self, value: npt.ArrayLike) -> None: ...
    @property
    def mass(self) -> float:
        """Mass, kg."""

@final
class Bodies:
    """The rigid bodies of a World as a sequence of :class:`Body` views (``len``,
    ``w.bodies[b]``, iteration) with their state as arrays, copies with one row per body in
    the order they were added, removed ones taken out. A view taken by a
    :class:`BodyHandle` follows that body."""

    def __len__(self) -> int: ...
    def __getitem__(self, key: int | BodyHandle, /) -> Body: ...
    def __iter__(self) -> Iterator[Body]: ...
    @property
    def positions(self) -> npt.NDArray[np.float64]:
        """Centres of mass (nb, 3), m."""
    @property
    def velocities(self) -> npt.NDArray[np.float64]:
        """Velocities of the centres of mass (nb, 3), m/s."""
    @property
    def orientations(self) -> npt.NDArray[np.float64]:
        """Orientations of the shape frames (nb, 4), unit quaternions (w, x, y, z)."""
    @property
    def angular_velocities(self) -> npt.NDArray[np.float64]:
        """Angular velocities (nb, 3), rad/s, world frame."""

@final
class ParticleHandle:
    """A handle to one particle (or ball) of a World, what ``add_particle`` and ``add_ball``
    return. It names the particle by an id its World never gives again, so it stays that
    particle's while others are removed. ``operator.index(h)`` is the particle's current row,
    so ``w.positions[h]``, ``w.particles[h]`` and every call that takes a particle index
    (``add_spring(h, k, ...)``) take the handle; ValueError once the particle is removed.
    ``World.remove(h)`` removes it. A copy or a pickle of the World takes the handles of the
    World it came from. Handles are not ints: ``h + 1`` is a TypeError (``int(h)`` is the row).
    """

    @property
    def id(self) -> int:
        """The particle's id in its World: never given to another particle of that World."""
    @property
    def world(self) -> World:
        """The World the handle came from."""
    @property
    def alive(self) -> bool:
        """Whether the particle is still in its World."""
    def __index__(self) -> int:
        """The particle's current row; ValueError once it is removed."""
    def __eq__(self, value: object, /) -> bool:
        """Equal handles name the same particle of the same World (or its copies)."""
    def __hash__(self) -> int: ...

@final
class ParticleHandles:
    """The particles one ``add_particles`` or ``add_balls`` call added, as one handle: a
    sequence of :class:`ParticleHandle` (``hs[k]``, negative from the end; iteration) that
    costs O(1) however many there are. ``np.asarray(hs)`` (or ``hs.rows``) is their current
    rows, so ``w.positions[np.asarray(hs)]`` reads them; ``World.remove(hs)`` removes them
    all."""

    def __len__(self) -> int: ...
    def __getitem__(self, key: int, /) -> ParticleHandle: ...
    def __iter__(self) -> Iterator[ParticleHandle]: ...
    def __array__(self, dtype: Any = None, copy: Any = None) -> npt.NDArray[np.int64]:
        """The current rows (as ``rows``)."""
    @property
    def ids(self) -> npt.NDArray[np.int64]:
        """The particles' ids (consecutive)."""
    @property
    def rows(self) -> npt.NDArray[np.int64]:
        """The particles' current rows; ValueError naming the first removed one."""
    @property
    def alive(self) -> bool:
        """Whether every one of the particles is still in its World."""
    @property
    def world(self) -> World:
        """The World the handles came from."""
    def __eq__(self, value: object, /) -> bool:
        """Equal when they name the same particles of the same World."""
    def __hash__(self) -> int: ...

@final
class BodyHandle:
    """A handle to one rigid body of a World, what ``add_body`` returns. It names the body by
    an id its World never gives again. ``operator.index(h)`` is the body's current row, so
    ``w.bodies[h]``, ``apply_force(h, ...)``, ``add_body_spring(h, ...)`` take it; ValueError
    once the body is removed. ``World.remove(h)`` removes it with the body springs and
    forces at its points."""

    @property
    def id(self) -> int:
        """The body's id in its World: never given to another body of that World."""
    @property
    def world(self) -> World:
        """The World the handle came from."""
    @property
    def alive(self) -> bool:
        """Whether the body is still in its World."""
    def __index__(self) -> int:
        """The body's current row; ValueError once it is removed."""
    def __eq__(self, value: object, /) -> bool:
        """Equal handles name the same body of the same World (or its copies)."""
    def __hash__(self) -> int: ...

@final
class BodySpringHandle:
    """A handle to one body spring, what ``add_body_spring`` returns: ``id``, ``alive``;
    ``stiffness``, ``rest_length`` and ``damping`` read and written (checked as
    ``add_body_spring`` checks them; the next step sees a change);
    ``operator.index(h)`` is its place among the body springs. ``World.remove(h)`` removes
    it; it also goes with its body or the particle it ends on."""

    @property
    def stiffness(self) -> float:
        """Stiffness, N/m (a number in [0, 1e12]); ValueError once removed."""
    @stiffness.setter
    def stiffness(self, value: float) -> None: ...
    @property
    def rest_length(self) -> float:
        """Rest length, m (a number in [0, 1e12])."""
    @rest_length.setter
    def rest_length(self, value: float) -> None: ...
    @property
    def damping(self) -> float:
        """Damping along the spring, N s/m (a number in [0, 1e12])."""
    @damping.setter
    def damping(self, value: float) -> None: ...
    @property
    def id(self) -> int:
        """The spring's id in its World: never given to another body spring of it."""
    @property
    def world(self) -> World:
        """The World the handle came from."""
    @property
    def alive(self) -> bool:
        """Whether the spring is still in its World."""
    def __index__(self) -> int:
        """Its place among the body springs; ValueError once removed."""
    def __eq__(self, value: object, /) -> bool:
        """Equal handles name the same spring of the same World (or its copies)."""
    def __hash__(self) -> int: ...

@final
class BodyForceHandle:
    """A handle to one Python force at a body point, what ``add_body_force`` returns:
    ``id``, ``alive``; ``operator.index(h)`` is its place among the body forces.
    ``World.remove(h)`` removes it; it also goes with its body."""

    @property
    def id(self) -> int:
        """The force's id in its World: never given to another body force of it."""
    @property
    def world(self) -> World:
        """The World the handle came from."""
    @property
    def alive(self) -> bool:
        """Whether the force is still in its World."""
    def __index__(self) -> int:
        """Its place among the body forces; ValueError once removed."""
    def __eq__(self, value: object, /) -> bool:
        """Equal handles name the same force of the same World (or its copies)."""
    def __hash__(self) -> int: ...

@final
class ConstraintHandle:
    """A handle to one position constraint of a World, what ``add_distance_constraint``,
    ``add_pin``, ``add_rope``, ``add_distance_limit`` and ``add_plane`` return. It names the
    constraint by an id its World never gives again. Its parameters read through it
    (read-only: remove it and add another to change one); a parameter its kind has not
    raises AttributeError, a removed constraint ValueError. ``operator.index(h)`` is its
    place among the World's constraints; ``World.remove(h)`` removes it. A constraint is
    also removed with a particle it names."""

    @property
    def id(self) -> int:
        """The constraint's id in its World: never given to another constraint of it."""
    @property
    def world(self) -> World:
        """The World the handle came from."""
    @property
    def alive(self) -> bool:
        """Whether the constraint is still in its World."""
    @property
    def kind(self) -> str:
        """``distance``, ``limit`` (a rope or a distance limit), ``pin`` or ``plane``."""
    def __index__(self) -> int:
        """The constraint's place among the World's constraints (the sweep order)."""
    @property
    def i(self) -> int:
        """The (first) particle's current row (distance, limit, pin)."""
    @property
    def j(self) -> int | None:
        """The other particle's current row, or None for a fixed point (distance, limit)."""
    @property
    def anchor(self) -> npt.NDArray[np.float64] | None:
        """The fixed point (dim,), m, or None when the other end is a particle."""
    @property
    def length(self) -> float:
        """A distance constraint's length, m."""
    @property
    def compliance(self) -> float:
        """A distance constraint's compliance, m/N (0: rigid)."""
    @property
    def min_length(self) -> float:
        """A limit's shortest distance, m (0 for a rope)."""
    @property
    def max_length(self) -> float:
        """A limit's longest distance, m."""
    @property
    def point(self) -> npt.NDArray[np.float64]:
        """A pin's point (dim,), m."""
    @property
    def normal(self) -> npt.NDArray[np.float64]:
        """A plane's unit normal (dim,)."""
    @property
    def offset(self) -> float:
        """A plane's offset along its normal, m."""
    def __eq__(self, value: object, /) -> bool:
        """Equal handles name the same constraint of the same World (or its copies)."""
    def __hash__(self) -> int: ...

@final
class SolidHandle:
    """A handle to one solid of a World (what ``add_solid`` returns), and its view: read and
    write its state through it, validated as ``add_solid`` (ValueError naming the field, the
    World unchanged). ``operator.index(h)`` and ``int(h)`` are its row now, so every call and
    array that takes a solid index takes the handle; ValueError once it was removed
    (``World.remove(h)``, which also removes the joints, springs and forces on it)."""

    @property
    def id(self) -> int:
        """The id in its World: never given to another of its kind in that World."""
    @property
    def world(self) -> World:
        """The World the handle came from."""
    @property
    def alive(self) -> bool:
        """Whether it is still in its World."""
    @property
    def row(self) -> int:
        """Its row now among its kind (the add order, the removed ones taken out); ValueError
        once removed."""
    def __eq__(self, other: object, /) -> bool: ...
    def __hash__(self) -> int: ...
    def __index__(self) -> int:
        """The solid's row now (ValueError once removed)."""
    def __int__(self) -> int:
        """The solid's row now (ValueError once removed)."""
    @property
    def kind(self) -> str:
        """ "dynamic", "static" or "kinematic"."""
    @property
    def shape(self) -> SolidShape:
        """The shape as added (read-only; its ``kind`` names it)."""
    @property
    def position(self) -> npt.NDArray[np.float64]:
        """Origin of the shape (dim,), m; assign to move the solid (its contacts' warm
        starts and render interpolation's previous pose are forgotten)."""
    @position.setter
    def position(self, value: npt.ArrayLike) -> None: ...
    @property
    def velocity(self) -> npt.NDArray[np.float64]:
        """Velocity of the centre of mass (dim,), m/s; assign to set it (a static solid's
        stays zero)."""
    @velocity.setter
    def velocity(self, value: npt.ArrayLike) -> None: ...
    @property
    def angle(self) -> float:
        """Angle, rad (2D worlds; AttributeError in 3D); assign to turn the solid."""
    @angle.setter
    def angle(self, value: float) -> None: ...
    @property
    def orientation(self) -> Any:
        """The angle (2D, a float) or a unit quaternion (4,) as (w, x, y, z) (3D); assign to
        turn the solid (a quaternion is normalised; a zero one is refused)."""
    @orientation.setter
    def orientation(self, value: float | npt.ArrayLike) -> None: ...
    @property
    def angular_velocity(self) -> Any:
        """Angular velocity, rad/s: a float in 2D, (3,) world frame in 3D; assign to set it."""
    @angular_velocity.setter
    def angular_velocity(self, value: float | npt.ArrayLike) -> None: ...

@final
class Solids:
    """The solids of a World as a sequence of :class:`SolidHandle` (``len``, ``w.solids[i]``
    or ``w.solids[h]``, iteration in row order)."""

    def __len__(self) -> int: ...
    def __getitem__(self, key: int | SolidHandle, /) -> SolidHandle: ...
    def __iter__(self) -> Iterator[SolidHandle]: ...

@final
class JointHandle:
    """A handle to one joint (what ``add_joint`` returns): its parameters as made; the motor
    and limits writable, validated as ``add_joint``."""

    @property
    def id(self) -> int:
        """The id in its World: never given to another of its kind in that World."""
    @property
    def world(self) -> World:
        """The World the handle came from."""
    @property
    def alive(self) -> bool:
        """Whether it is still in its World."""
    @property
    def row(self) -> int:
        """Its row now among its kind (the add order, the removed ones taken out); ValueError
        once removed."""
    def __eq__(self, other: object, /) -> bool: ...
    def __hash__(self) -> int: ...
    @property
    def kind(self) -> str:
        """ "ball", "revolute", "distance", "weld" or "prismatic"."""
    @property
    def a(self) -> SolidHandle | None:
        """The first solid's handle."""
    @property
    def b(self) -> SolidHandle | None:
        """The second solid's handle, or None: the world."""
    @property
    def anchor(self) -> npt.NDArray[np.float64]:
        """The anchor as given when the joint was made (world coordinates then), m."""
    @property
    def anchor_b(self) -> npt.NDArray[np.float64] | None:
        """The end on ``b`` as given (a distance joint's), or None."""
    @property
    def axis(self) -> npt.NDArray[np.float64] | None:
        """The axis as given, or None."""
    @property
    def length(self) -> float | None:
        """A distance joint's length as given (None: as made)."""
    @property
    def min_length(self) -> float | None: ...
    @property
    def max_length(self) -> float | None: ...
    @property
    def hertz(self) -> float:
        """Softness, Hz (0: rigid)."""
    @property
    def damping_ratio(self) -> float: ...
    @property
    def collide(self) -> bool:
        """Whether its two solids still collide."""
    @property
    def lower(self) -> float | None:
        """The lower limit (rad, or m for a slider; None: none); assign a number or None."""
    @lower.setter
    def lower(self, value: float | None) -> None: ...
    @property
    def upper(self) -> float | None:
        """The upper limit (None: none); assign a number or None."""
    @upper.setter
    def upper(self, value: float | None) -> None: ...
    @property
    def motor_speed(self) -> float:
        """The motor's speed (rad/s, or m/s for a slider); assign to change it."""
    @motor_speed.setter
    def motor_speed(self, value: float) -> None: ...
    @property
    def max_motor(self) -> float:
        """The motor's largest torque (N m) or force (N), >= 0; assign to change it."""
    @max_motor.setter
    def max_motor(self, value: float) -> None: ...

@final
class SolidSpringHandle:
    """A handle to one spring between solids (what ``add_solid_spring`` returns)."""

    @property
    def id(self) -> int:
        """The id in its World: never given to another of its kind in that World."""
    @property
    def world(self) -> World:
        """The World the handle came from."""
    @property
    def alive(self) -> bool:
        """Whether it is still in its World."""
    @property
    def row(self) -> int:
        """Its row now among its kind (the add order, the removed ones taken out); ValueError
        once removed."""
    def __eq__(self, other: object, /) -> bool: ...
    def __hash__(self) -> int: ...
    @property
    def a(self) -> SolidHandle:
        """The first solid's handle."""
    @property
    def b(self) -> SolidHandle | None:
        """The second solid's handle, or None: a fixed point of the world."""
    @property
    def point_a(self) -> npt.NDArray[np.float64]:
        """The end on ``a``, in its frame, m."""
    @property
    def point_b(self) -> npt.NDArray[np.float64]:
        """The end on ``b`` in its frame, or the world point, m."""
    @property
    def stiffness(self) -> float:
        """Stiffness, N/m; assign to change it (in [0, 1e12])."""
    @stiffness.setter
    def stiffness(self, value: float) -> None: ...
    @property
    def rest_length(self) -> float:
        """Rest length, m; assign to change it."""
    @rest_length.setter
    def rest_length(self, value: float) -> None: ...
    @property
    def damping(self) -> float:
        """Damping along the spring, N s/m; assign to change it."""
    @damping.setter
    def damping(self, value: float) -> None: ...

@final
class SolidForceHandle:
    """A handle to one force from Python on a solid (what ``add_solid_force`` returns)."""

    @property
    def id(self) -> int:
        """The id in its World: never given to another of its kind in that World."""
    @property
    def world(self) -> World:
        """The World the handle came from."""
    @property
    def alive(self) -> bool:
        """Whether it is still in its World."""
    @property
    def row(self) -> int:
        """Its row now among its kind (the add order, the removed ones taken out); ValueError
        once removed."""
    def __eq__(self, other: object, /) -> bool: ...
    def __hash__(self) -> int: ...
    @property
    def name(self) -> str:
        """The force's name."""
    @property
    def solid(self) -> SolidHandle:
        """The handle of the solid it acts on."""

@final
class ForceHandle:
    """A handle to one force of a World, what every ``add_*`` of a force returns
    (``add_gravity``, ``add_spring``, ``add_drag``, ``add_central_gravity``,
    ``add_nbody_gravity``, ``add_rod``, ``add_force``). It names the force by an id its
    World never gives again, so it stays that force's while others are added or removed.
    The force's parameters read and write through it (``h.stiffness = 2e3``), validated as
    the ``add_*`` call was (ValueError naming the field, the force unchanged); the next step
    sees the change. A parameter the force's kind has not raises AttributeError; a handle of
    a removed force raises ValueError. ``World.remove(h)`` removes the force. A copy or a
    pickle of the World takes the handles of the World it came from (``copy.force(h)``).
    """

    @property
    def id(self) -> int:
        """The force's id in its World: never given to another force of that World."""
    @property
    def kind(self) -> str:
        """``gravity``, ``spring``, ``drag``, ``central-gravity``, ``nbody``, ``rod``, or
        ``python`` (a force added with ``add_force``, which has no parameters here)."""
    @property
    def world(self) -> World:
        """The World the handle came from."""
    @property
    def alive(self) -> bool:
        """Whether the force is still in its World."""
    def __eq__(self, value: object, /) -> bool:
        """Equal handles name the same force of the same World."""
    def __hash__(self) -> int: ...
    @property
    def stiffness(self) -> float:
        """A spring's stiffness, N/m (>= 0)."""
    @stiffness.setter
    def stiffness(self, value: float) -> None: ...
    @property
    def rest_length(self) -> float:
        """A spring's rest length, m (>= 0)."""
    @rest_length.setter
    def rest_length(self, value: float) -> None: ...
    @property
    def damping(self) -> float:
        """A spring's damping along it, N s/m (>= 0)."""
    @damping.setter
    def damping(self, value: float) -> None: ...
    @property
    def i(self) -> int:
        """The first particle of a spring or rod (the lower index of a pair: the World
        stores a pair as ``i < j``). Read-only: remove the force and add another to change
        its ends."""
    @property
    def j(self) -> int | None:
        """The other particle of a spring or rod, or None when its other end is an anchor.
        Read-only."""
    @property
    def anchor(self) -> npt.NDArray[np.float64] | None:
        """The anchor point (dim,) of a spring or rod to a fixed point, m, or None when its
        other end is a particle. Writable for a spring to an anchor (a mouse spring that
        follows the cursor); a rod's anchor must keep the rod's length."""
    @anchor.setter
    def anchor(self, value: npt.ArrayLike) -> None: ...
    @property
    def length(self) -> float:
        """A rod's length, m (read-only: a rod holds the length its ends have)."""
    @property
    def g(self) -> Any:
        """Uniform gravity's acceleration (dim,), m/s^2; n-body gravity's constant G (a
        number)."""
    @g.setter
    def g(self, value: Any) -> None: ...
    @property
    def softening(self) -> float:
        """N-body gravity's softening length, m (>= 0)."""
    @softening.setter
    def softening(self, value: float) -> None: ...
    @property
    def linear(self) -> float:
        """Drag's linear coefficient, N s/m (>= 0)."""
    @linear.setter
    def linear(self, value: float) -> None: ...
    @property
    def quadratic(self) -> float:
        """Drag's quadratic coefficient, N s^2/m^2 (>= 0)."""
    @quadratic.setter
    def quadratic(self, value: float) -> None: ...
    @property
    def center(self) -> npt.NDArray[np.float64]:
        """Central gravity's centre (dim,), m."""
    @center.setter
    def center(self, value: npt.ArrayLike) -> None: ...
    @property
    def gm(self) -> float:
        """Central gravity's parameter G M, m^3/s^2."""
    @gm.setter
    def gm(self, value: float) -> None: ...

@final
class World:
    """Particles, forces, an integrator and a fixed-timestep game loop.

    ``World(dim, method="symplectic-euler", dt=1/120, max_steps_per_frame=8,
    max_frame_time=0.1, loop="accumulator", substeps=1)``: ``dim`` is 1, 2 or 3, ``dt`` and
    ``max_frame_time`` are in s. Raises ValueError for a bad argument. A World serves one
    thread at a time: any method raises WorldBusyError while another thread (or a callback
    of its own step) holds it.
    """

    def __new__(
        cls,
        dim: int,
        method: str | None = None,
        dt: float | None = None,
        max_steps_per_frame: int | None = None,
        max_frame_time: float | None = None,
        loop: str | None = None,
        substeps: int | None = None,
    ) -> World:
        """A world of ``dim`` dimensions with no particles; ValueError for a bad argument."""

    @staticmethod
    def from_scene(
        name: str,
        method: str | None = None,
        dt: float | None = None,
        params: _Params = None,
    ) -> World:
        """A world built from the built-in scene ``name`` (``params`` override its parameters;
        ``dt`` in s). ``method`` and ``dt`` default to the scene's own (:func:`physstep.scenes`
        lists them: RK4 for the flows, backward Euler for the stiff scenes). Raises ValueError
        for an unknown scene, method or parameter."""

    @staticmethod
    def from_flow(
        func: Callable[[float, npt.NDArray[np.float64]], npt.ArrayLike],
        y0: npt.ArrayLike,
        method: str | None = None,
        dt: float | None = None,
        jacobian: Callable[[float, npt.NDArray[np.float64]], npt.ArrayLike] | None = None,
        name: str | None = None,
    ) -> World:
        """A world whose part is the first-order flow ``y' = func(t, y)`` from ``y0`` (method
        default ``rk4``); ``jacobian(t, y)`` returns df/dy for the implicit methods.

        Raises ValueError if ``func`` or ``jacobian`` is not callable or ``y0`` is not a vector
        of numbers, and for a split method (they need positions and velocities).
        """

    def record(
        self,
        until: float,
        every: int | None = None,
        stop_on_diverge: bool | None = None,
        stages: bool | None = None,
    ) -> dict[str, Any]:
        """Runs this world from its state for ``until`` s of its fixed dt, a row every
        ``every`` steps; returns the fields of a ``physstep.Trajectory`` (as a dict).

        Raises ValueError for a bad argument, DivergedError or ConvergenceError when a step
        fails (unless ``stop_on_diverge``), a user force's own exception unchanged.
        """

    def __copy__(self) -> World:
        """A copy: the same particles, forces, method, clock and state (Python callables shared)."""
    def __deepcopy__(self, memo: Any) -> World:
        """As ``__copy__``: the engine's data copied, Python callables shared."""
    def __reduce__(self) -> tuple[Any, tuple[dict[str, Any], bytes]]:
        """Pickles as the engine's scene text of the world and its snapshot, with its Python
        callables beside them (a World whose callable does not pickle, a lambda, refuses in
        one line: pickle.PicklingError)."""
    @property
    def dim(self) -> int:
        """Spatial dimensions (1, 2 or 3)."""

    def __len__(self) -> int:
        """Number of particles."""

    @property
    def method(self) -> str:
        """The integrator's registry name; assign a name to switch (ValueError if unknown)."""

    @method.setter
    def method(self, name: str) -> None: ...
    @property
    def dt(self) -> float:
        """The fixed step, s; assign to change it (ValueError unless finite and > 0)."""

    @dt.setter
    def dt(self, dt: float) -> None: ...
    def add_particle(
        self, position: Any, velocity: Any = None, mass: float | None = None, static: bool | None = None
    ) -> ParticleHandle:
        """Adds a particle at ``position`` (dim numbers, m) with ``velocity`` (m/s, default 0)
        and ``mass`` (kg, default 1; ``inf`` or ``static=True``: immovable); returns its
        handle (``w.positions[h]``, ``w.remove(h)``).

        Raises ValueError naming the bad field.
        """

    def add_particles(
        self,
        positions: npt.ArrayLike,
        velocities: npt.ArrayLike | None = None,
        masses: npt.ArrayLike | None = None,
        static: bool | None = None,
    ) -> ParticleHandles:
        """Adds ``positions`` (k, dim; m) with optional ``velocities`` (k, dim; m/s) and
        ``masses`` (k,; kg); returns their handles as one ``ParticleHandles``. ValueError for
        a bad shape or value."""

    def add_ball(
        self, position: Any, velocity: Any = None, radius: float | None = None, mass: float | None = None
    ) -> ParticleHandle:
        """Adds a ball: a particle of ``radius`` (m, default 1) at ``position`` (dim numbers, m)
        with ``velocity`` (m/s, default 0) and ``mass`` (kg, default 1; ``inf``: immovable) that
        collides with the other balls and the walls at its time of impact. Returns its handle.

        Raises ValueError naming the field: a radius not finite and > 0, a ball that would
        overlap another (touching is allowed) or stick out of the walls; the world is unchanged.
        """

    def add_balls(
        self,
        positions: npt.ArrayLike,
        radii: float | npt.ArrayLike,
        velocities: npt.ArrayLike | None = None,
        masses: npt.ArrayLike | None = None,
    ) -> ParticleHandles:
        """Adds balls at ``positions`` (k, dim; m) of ``radii`` (one number, or (k,); m) with
        optional ``velocities`` (k, dim; m/s) and ``masses`` (k,; kg); returns their handles.
        ValueError as :meth:`add_ball`, naming the first bad entry."""

    def add_walls(self, lo: npt.ArrayLike, hi: npt.ArrayLike) -> None:
        """Puts the balls in the axis-aligned box ``lo``..``hi`` (dim numbers each, m),
        replacing any walls before. ValueError for ``hi[k] <= lo[k]`` or a ball outside."""

    @property
    def restitution(self) -> float:
        """Coefficient of restitution of every contact, 0 to 1 (1: elastic, the default)."""

    @restitution.setter
    def restitution(self, e: float) -> None: ...
    @property
    def radii(self) -> npt.NDArray[np.float64]:
        """The radius of every particle (n,), m: 0 for a particle that is not a ball (a copy)."""

    @property
    def walls(self) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]] | None:
        """The walls as ``(lo, hi)`` arrays, or None."""

    @property
    def collisions(self) -> dict[str, Any]:
        """What the contacts came to since the world was built: ``count`` (contacts resolved),
        ``max_overlap`` (the deepest overlap of two balls, or of a ball past a wall, after any
        step, m) and ``pair_tests`` (pairs the narrow phase tested: grows with N, not N^2)."""

    def add_gravity(self, g: Any) -> ForceHandle:
        """Adds uniform gravity ``g`` (dim numbers, m/s^2) on every dynamic particle; returns
        its handle."""

    def add_spring(
        self,
        i: int | ParticleHandle,
        j_or_anchor: Any,
        stiffness: float,
        rest_length: float | None = None,
        damping: float | None = None,
    ) -> ForceHandle:
        """Adds a damped spring (``stiffness`` N/m, ``damping`` N s/m) from particle ``i`` to a
        particle or an anchor point (dim numbers, m); ``rest_length`` (m) defaults to the
        current distance. Returns its handle (``h.stiffness = ...``). ValueError for a bad
        index or value."""

    def add_drag(self, linear: float | None = None, quadratic: float | None = None) -> ForceHandle:
        """Adds drag F = -(linear + quadratic |v|) v on every particle (N s/m, N s^2/m^2);
        returns its handle."""

    def add_central_gravity(self, center: Any, gm: float) -> ForceHandle:
        """Adds gravity towards ``center`` (m) with ``gm`` (m^3/s^2): a = -gm r / |r|^3;
        returns its handle."""

    def add_nbody_gravity(self, g: float | None = None, softening: float | None = None) -> ForceHandle:
        """Adds mutual gravity between all particles (constant ``g``, default 1; ``softening``
        length, m); returns its handle."""

    def add_rod(self, i: int | ParticleHandle, j_or_anchor: Any, length: float | None = None) -> ForceHandle:
        """Adds a force-based rod from particle ``i`` to a particle or an anchor point holding
        the current distance (``length``, m, when given, must equal it: ValueError); returns
        its handle."""

    def remove(
        self,
        handle: ForceHandle
        | ParticleHandle
        | ParticleHandles
        | ConstraintHandle
        | BodyHandle
        | BodySpringHandle
        | BodyForceHandle
        | SolidHandle
        | JointHandle
        | SolidSpringHandle
        | SolidForceHandle,
    ) -> None:
        """Removes what ``handle`` names (a force, a particle or ball, the particles of one
        ``add_particles``, a constraint, a rigid body with the springs and forces at its
        points, a body spring, a force at a body point, a solid, a joint, a solid spring or a
        force on a solid); the World then steps bitwise as one that never had it, and the
        other handles stay valid. A particle takes with it the springs, rods, body springs
        and constraints with an end on it, a solid its joints, springs and forces (their
        handles are no longer alive; docs: Contact, "Handles and removal"); the rows after
        it move up a row, in their order, and a method that carries memory restarts (as
        assigning ``positions`` does). ValueError for a handle of a removed entity or of
        another World (not a copy or pickle of this one)."""

    def force(self, handle: ForceHandle) -> ForceHandle:
        """This World's handle of the force ``handle`` names: a handle of the World this one
        was copied or unpickled from reaches the same force here. ValueError for a removed
        force or another World's handle."""

    @property
    def particles(self) -> Particles:
        """The particles as a sequence of views: ``w.particles[i].position = ...``."""

    @property
    def solids(self) -> Solids:
        """The solids as a sequence of handles, each also the solid's view
        (``w.solids[i].velocity = ...``), in row order: the order they were added, the
        removed ones taken out."""

    @property
    def joints(self) -> list[JointHandle]:
        """Handles of the joints, in row order."""

    @property
    def solid_springs(self) -> list[SolidSpringHandle]:
        """Handles of the solid springs, in row order."""

    @property
    def bodies(self) -> Bodies:
        """The rigid bodies as a sequence of views (``w.bodies[b].velocity = ...``) with their
        state as arrays (``w.bodies.positions``)."""

    @property
    def forces(self) -> list[ForceHandle]:
        """Handles of every force: the built-in ones in the World's canonical order (the
        order they act in), then the Python forces in the order they were added."""

    def add_distance_constraint(
        self, i: int | ParticleHandle, j: Any, length: float | None = None, compliance: float | None = None
    ) -> ConstraintHandle:
        """Adds the position constraint |x_i - x_j| = ``length`` (m; default the current
        distance) between particle ``i`` and particle ``j`` or an anchor point (dim numbers,
        m). ``compliance`` (m/N, default 0): 0 is rigid (SHAKE/RATTLE under velocity-verlet
        and leapfrog, projection otherwise), above 0 soft (XPBD). Returns its handle.
        ValueError naming the field for a missing particle, ``j == i``, a length that is not
        > 0 or a compliance that is not >= 0."""

    def add_pin(self, i: int | ParticleHandle, point: Any) -> ConstraintHandle:
        """Holds particle ``i`` at ``point`` (dim numbers, m); other constraints see it as
        fixed. Returns its handle. ValueError naming the field."""

    def add_rope(self, i: int | ParticleHandle, j: Any, max_length: float) -> ConstraintHandle:
        """A rope of ``max_length`` (m, > 0) from particle ``i`` to particle ``j`` or an anchor
        point: the distance may shrink, not grow past it. Returns its handle."""

    def add_distance_limit(
        self, i: int | ParticleHandle, j: Any, min_length: float, max_length: float
    ) -> ConstraintHandle:
        """A joint limit ``min_length`` <= |x_i - x_j| <= ``max_length`` (m). Returns its
        handle."""

    def add_plane(self, normal: Any, offset: float | None = None) -> ConstraintHandle:
        """Keeps every particle in the half-space normal . x >= ``offset`` (m, default 0): a
        ground (normal (0, 1)) or a wall of a box. ``normal`` (dim numbers, nonzero) points
        into the allowed side and is made unit. Returns its handle."""

    @property
    def constraint_iterations(self) -> int:
        """Relaxation sweeps per step (default 16), at most: the sweeps stop once every
        constraint is within 1e-13 (relative); ``constraint_stats`` counts the steps that
        reached this cap first. Assign to change it (ValueError outside 1 to 1000000)."""

    @constraint_iterations.setter
    def constraint_iterations(self, n: int) -> None: ...
    def constraint_conflicts(self) -> list[str]:
        """What in the constraints cannot be met whatever the sweeps, one line each (empty when
        nothing is seen): a particle pinned to two points, two pinned balls closer than their
        radii, opposite planes with no point between them, a pinned particle behind a plane,
        held ends at a distance a constraint forbids, a distance whose ends coincide. Adding
        such a constraint warns (`ConstraintWarning`); the check is of pairs, not a proof."""

    @property
    def constraint_stats(self) -> dict[str, Any]:
        """What the relaxation sweeps did: {"last_sweeps": the last step's sweeps,
        "capped_steps": steps whose sweeps ended at constraint_iterations with a constraint
        still off by more than 1e-13 (relative), "capped_violation": the largest violation,
        m, such a step left (0.0 when none)}. A diagnostic over the world's steps, not state."""

    @property
    def constraint_count(self) -> int:
        """The number of constraints."""

    def constraint_violation(self) -> float:
        """The largest violation of any constraint at the current positions, m (0.0 without
        constraints)."""

    def set_implicit(
        self,
        *,
        tol: float | None = None,
        max_iter: int | None = None,
        cg_tol: float | None = None,
        cg_max_iter: int | None = None,
        dense_up_to: int | None = None,
        preconditioner: str | None = None,
        exact_jacobian: bool | None = None,
        energy_halvings: int | None = None,
    ) -> None:
        """Sets the implicit methods' solver: Newton's relative tolerance ``tol`` and cap
        ``max_iter``, the conjugate-gradient tolerance ``cg_tol`` and cap ``cg_max_iter`` of
        the sparse solve and its ``preconditioner`` (``"cholesky"``: the complete sparse
        Cholesky factor in a minimum-degree order, the exact solve, made at a step's first
        Newton update and kept for its next where that is cheaper; ``"incomplete-cholesky"``:
        block IC(0) on the springs, exact on a chain; ``"block-jacobi"``: the particles'
        diagonal blocks), and ``dense_up_to`` (systems of at most this many unknowns are
        solved densely; 0 always sparse), and ``exact_jacobian`` (with ``"cholesky"``, each
        sparse Newton update of backward Euler and implicit midpoint takes the springs' exact
        Jacobian where the whole matrix is positive definite, the semidefinite one elsewhere;
        ``False``: the semidefinite one always, the iteration before 2026-11-27), and
        ``energy_halvings`` (the linearly implicit step: a step that would raise the energy by
        more than rounding is taken again as two of half the size, each checked the same way,
        at most this many times over, 0 to 16; 0 takes one linear solve a step always).
        Arguments left out keep their values; the defaults are ``tol=1e-11, max_iter=500,
        cg_tol=1e-10, cg_max_iter=1000, preconditioner="cholesky", dense_up_to=64,
        exact_jacobian=True, energy_halvings=4``.
        ``tol`` is relative to the terms Newton balances, stiffness included: with the exact
        Jacobian the last update lands on the rounding floor and a backward-Euler step of a
        stiff chain at the default is the converged one; with the semidefinite matrix alone
        its velocities were about 1e-6 (relative) from the converged step's (docs/stiff.md);
        ``tol=1e-13`` gives the converged step either way."""

    @property
    def solve_stats(self) -> dict[str, Any] | None:
        """What the latest step's implicit solve did: ``newton`` (updates; under
        ``linearly-implicit-euler`` its linear solves, 1, or 3 and more where the step was
        halved to keep the energy from rising), ``cg`` (conjugate-gradient iterations, 0 for
        the dense solve), ``residual`` (Newton's final, relative), ``sparse``; None under an
        explicit method."""

    def step(self, n: int | None = None) -> None:
        """Takes ``n`` fixed steps (default 1). Raises DivergedError or ConvergenceError if a
        step fails (that step rolled back, those before it kept); Ctrl-C stops after a whole
        step, heard inside a long step too (KeyboardInterrupt, the step under way rolled back)."""

    def advance(self, frame_time: float) -> int:
        """Runs one frame of the game loop over ``frame_time`` s of wall time; returns the
        number of fixed steps taken. Raises as :meth:`step` does."""

    @property
    def alpha(self) -> float:
        """Render interpolation factor in [0, 1) after the latest :meth:`advance`."""

    @property
    def clock_stats(self) -> tuple[int, int, float, float]:
        """Totals of the game loop: frames, steps, clamped time (s) and dropped time (s)."""

    def interpolated_positions(self) -> npt.NDArray[np.float64]:
        """Positions to draw (n, dim), m: previous + alpha (current - previous); a new
        array (a copy), unlike :attr:`positions`."""

    def interpolated_solid_positions(self) -> npt.NDArray[np.float64]:
        """Solid positions to draw (n, dim), m: as :meth:`interpolated_positions`, between
        the solids' poses before the last step of the latest :meth:`advance` and the current
        ones (the current ones after a :meth:`step`); a copy."""

    def interpolated_solid_orientations(self) -> npt.NDArray[np.float64]:
        """Solid orientations to draw, shaped as :meth:`solid_orientations` gives them
        (angles (n,) in 2D, rad; quaternions (n, 4) as (w, x, y, z) in 3D): the angle moved
        by ``alpha`` of its change over the last step, the quaternion slerped."""

    @property
    def positions(self) -> npt.NDArray[np.float64]:
        """Positions (n, dim), m: a read-only view of the world's own memory, not a copy
        (docs/views.md). Steps and assignments show through it in place; after particles or
        bodies are added it is detached (it keeps the values it had then). Writing through
        it raises ValueError: take ``np.array(w.positions)`` for a copy to keep or change.
        Assign an array of that shape to move the particles (ValueError for a bad shape or a
        non-finite value)."""

    @positions.setter
    def positions(self, x: npt.ArrayLike) -> None: ...
    @property
    def velocities(self) -> npt.NDArray[np.float64]:
        """Velocities (n, dim), m/s: a read-only view of the world's own memory, not a copy,
        as :attr:`positions` is (docs/views.md). Assign an array of that shape to change them
        (ValueError for a bad shape or a non-finite value)."""

    @velocities.setter
    def velocities(self, v: npt.ArrayLike) -> None: ...
    @property
    def accelerations(self) -> npt.NDArray[np.float64]:
        """Accelerations at the current state (n, dim), m/s^2: a new array (a copy)."""

    @property
    def time(self) -> float:
        """Physics time, s."""

    @property
    def steps(self) -> int:
        """Steps taken."""

    @property
    def evals(self) -> int:
        """Force evaluations made."""

    def kinetic_energy(self) -> float:
        """Kinetic energy, J: the dynamic particles', the bodies' and the solids' (translation
        and rotation)."""

    def energy(self) -> float | None:
        """Kinetic plus potential energy, J; None when a user force has no potential.
        Raises DivergedError if it is not finite."""

    def momentum(self) -> npt.NDArray[np.float64]:
        """Total momentum of the dynamic particles (dim,), kg m/s."""

    def snapshot(self) -> bytes:
        """The whole dynamic state as checksummed bytes (:meth:`restore` puts it back bitwise)."""

    def restore(self, data: bytes | bytearray | memoryview) -> None:
        """Restores a :meth:`snapshot` of this world; a damaged or foreign one is a ValueError
        and the world is unchanged."""

    def state_hash(self) -> int:
        """A 64-bit hash of the dynamic state: equal for bitwise-equal states."""

    def add_force(
        self,
        func: Callable[..., npt.ArrayLike | None],
        *,
        potential: Callable[[npt.NDArray[np.float64]], float] | None = None,
        jacobian: Callable[..., tuple[npt.ArrayLike, npt.ArrayLike]] | None = None,
        velocity_dependent: bool | None = None,
        name: str | None = None,
        inplace: bool | None = None,
    ) -> ForceHandle:
        """Adds a Python force: ``func(t, x, v)`` gets positions and velocities (n, dim) as
        read-only arrays and returns forces (n, dim), N; with ``inplace=True`` it is
        ``func(t, x, v, out)`` and writes them into ``out`` (n, dim, zeroed), returning None.
        ``x`` and ``v`` are valid during the call only: read-only views of the World's own
        state where the method evaluates there (no copy), else copies in reused arrays; a
        function that keeps one past its call is warned once (RuntimeWarning: keep
        ``x.copy()``). ``potential(x)`` (J) makes the
        energy known; ``jacobian(t, x, v)`` returns (dF/dx, dF/dv) for the implicit methods;
        ``velocity_dependent=False`` (the force ignores ``v``) saves re-evaluations: velocity
        Verlet then evaluates once a step, from the stored derivative.
        Returns its handle (kind ``python``; ``World.remove`` takes it); ValueError if an
        argument is not callable.
        An exception raised inside propagates unchanged from the step, which is rolled
        back."""

    def phase_state(self) -> npt.NDArray[np.float64]:
        """The vector the step map acts on: positions and velocities (flat), then the
        integrator's vector memory (Verlet's previous positions, leapfrog's half-step
        velocities)."""

    def set_phase_state(self, z: npt.ArrayLike) -> None:
        """Sets what :meth:`phase_state` returns, without restarting the integrator
        (ValueError for a wrong length or a non-finite value)."""

    # Rigid bodies (3D worlds).
    def add_body(
        self,
        shape: Shape,
        *,
        mass: float | None = None,
        density: float | None = None,
        position: npt.ArrayLike | None = None,
        orientation: npt.ArrayLike | None = None,
        velocity: npt.ArrayLike | None = None,
        angular_velocity: npt.ArrayLike | None = None,
        pivot: npt.ArrayLike | None = None,
        angular_drag: float | None = None,
    ) -> BodyHandle:
        """Adds a rigid body of ``shape`` and returns its handle (a :class:`BodyHandle`). ``mass`` (kg)
        or ``density`` (kg/m^3), at most one (neither: density 1); ``position`` of the shape's
        origin (m, default the origin); ``orientation`` of the shape's frame, a quaternion (w, x, y,
        z), normalised (default the identity); ``velocity`` of the centre of mass (m/s);
        ``angular_velocity`` (rad/s, world frame); ``pivot``, a point of the shape (shape frame, m)
        pinned to the world where it starts (a top on its tip; ``velocity`` must then be zero);
        ``angular_drag``, a torque ``-c omega`` (N m s, default 0). ValueError naming the bad field
        (``dim`` in a world that is not 3D); the world is then unchanged."""

    @property
    def body_count(self) -> int:
        """Number of rigid bodies."""

    def body_positions(self) -> npt.NDArray[np.float64]:
        """Centres of mass of the bodies (nb, 3), m."""

    def body_orientations(self) -> npt.NDArray[np.float64]:
        """Orientations of the bodies' shape frames (nb, 4), unit quaternions (w, x, y, z)."""

    def body_velocities(self) -> npt.NDArray[np.float64]:
        """Velocities of the bodies' centres of mass (nb, 3), m/s."""

    def body_angular_velocities(self) -> npt.NDArray[np.float64]:
        """Angular velocities of the bodies (nb, 3), rad/s, world frame."""

    def body_angular_momenta(self) -> npt.NDArray[np.float64]:
        """Angular momenta of the bodies about their centres of mass (nb, 3), kg m^2/s."""

    def angular_momentum(self) -> npt.NDArray[np.float64]:
        """Total angular momentum about the origin (3,), kg m^2/s: the particles' (3D worlds)
        and the bodies' ``c x P + L``."""

    def apply_force(self, body: int, force: npt.ArrayLike, at: npt.ArrayLike | None = None) -> None:
        """Applies ``force`` (N, world frame) to ``body`` for the next step, at the world point
        ``at`` (m; default the centre of mass), which adds the torque ``(at - c) x force``.
        Loads add up until a step takes them. ValueError naming ``body``, ``force`` or ``at``."""

    def apply_torque(self, body: int, torque: npt.ArrayLike) -> None:
        """Applies ``torque`` (N m, world frame) to ``body`` for the next step. ValueError
        naming ``body`` or ``torque``."""

    @property
    def orientation_rule(self) -> str:
        """How drifts turn the bodies: ``matrix``, ``quaternion``, ``exponential`` or
        ``splitting`` (default); assign a name to switch (ValueError listing the valid names)."""

    @orientation_rule.setter
    def orientation_rule(self, name: str) -> None: ...
    @property
    def angular_form(self) -> str:
        """What the bodies' angular state holds, so what a kick integrates: ``momentum`` (the
        notes' form, default), ``velocity`` (gyroscopic term ignored, as many engines do),
        ``velocity-gyroscopic`` (explicit) or ``velocity-implicit`` (Catto's one Newton
        step); assign a name to switch (angular momentum kept; ValueError
        listing the valid names)."""

    @angular_form.setter
    def angular_form(self, name: str) -> None: ...
    def add_body_force(
        self,
        body: int | BodyHandle,
        func: Callable[[float, npt.NDArray[np.float64], npt.NDArray[np.float64]], npt.ArrayLike],
        *,
        point: npt.ArrayLike | None = None,
        potential: Callable[[npt.NDArray[np.float64]], float] | None = None,
        velocity_dependent: bool | None = None,
        name: str | None = None,
    ) -> BodyForceHandle:
        """Adds a force written in Python acting at ``point`` of ``body`` (shape frame, m;
        default the shape's origin): ``func(t, x, v)`` gets the point's world position and
        velocity as (1, 3) arrays and returns the force on it (1, 3), N, which also turns the
        body. ``potential(x)`` (J) keeps the energy known; ``velocity_dependent=False`` saves
        re-evaluations. An exception raised inside propagates unchanged, with the step rolled
        back. Returns its handle (``w.remove(h)``); it goes with its body."""

    def add_body_spring(
        self,
        body: int | BodyHandle,
        point: npt.ArrayLike,
        other: Any,
        stiffness: float,
        rest_length: float | None = None,
        damping: float | None = None,
    ) -> BodySpringHandle:
        """Adds a damped spring (``stiffness`` N/m, ``damping`` N s/m) from ``point`` of
        ``body`` (shape frame, m) to ``other``, a particle (index or handle) or an anchor point
        (3 numbers, m); ``rest_length`` (m) defaults to the current distance. Returns its
        handle (``w.remove(h)``); it goes with its body or its particle. ValueError naming the
        bad field."""

    def add_solid(
        self,
        shape: Shape | SolidShape,
        *,
        position: npt.ArrayLike | None = None,
        orientation: float | npt.ArrayLike | None = None,
        velocity: npt.ArrayLike | None = None,
        angular_velocity: float | npt.ArrayLike | None = None,
        kind: str | None = None,
        density: float | None = None,
        friction: float | None = None,
        restitution: float | None = None,
        linear_damping: float | None = None,
        angular_damping: float | None = None,
        bullet: bool | None = None,
    ) -> SolidHandle:
        """Adds a solid: a rigid body with a shape that collides with the other solids,
        stepped by the contact solver (docs: Contact); returns its :class:`SolidHandle`
        (an index: its row now).
        ``shape``: :class:`Circle`, :class:`Box` (two half extents in 2D, three in 3D),
        :class:`Capsule`, :class:`Polygon`, :class:`Segment`, :class:`Plane` (static),
        :class:`Sphere` or :class:`Mesh` (static). ``position`` of the shape's origin (m,
        default the origin); ``orientation``: the angle (rad) in 2D, a quaternion (w, x, y,
        z) in 3D; ``velocity`` (m/s) and ``angular_velocity`` (rad/s: one number in 2D);
        ``kind``: "dynamic" (default), "static" or "kinematic"; ``density`` (kg/m^2 in 2D,
        kg/m^3 in 3D; default 1); ``friction`` >= 0 (default 0.6; a pair: the geometric
        mean); ``restitution`` in [0, 1] (default 0; a pair: the larger);
        ``linear_damping`` and ``angular_damping``, drag in 1/s (>= 0, default 0: in each
        substep v *= 1 / (1 + h c), so speed decays as exp(-c t)); ``bullet`` (default
        False): continuous collision sweeps a dynamic bullet against the dynamic solids that
        are not bullets too (a small fast projectile then does not pass through a box).
        ValueError naming the bad field; the world is then unchanged."""

    def add_solid_spring(
        self,
        a: int | SolidHandle,
        point_a: npt.ArrayLike,
        b: int | SolidHandle | None = None,
        point_b: npt.ArrayLike | None = None,
        *,
        stiffness: float,
        rest_length: float | None = None,
        damping: float | None = None,
    ) -> SolidSpringHandle:
        """Adds a spring between ``point_a`` of solid ``a`` and ``point_b`` of solid ``b``
        (each in its solid's frame, the frame its shape is given in, m), or, with ``b``
        None, the fixed world point ``point_b``: the force k (L - rest_length) + damping
        (the ends' relative speed along the line), N, pulls the two ends together along the
        line between them, equal and opposite, and turns each solid about its centre;
        applied in each of the contact solver's substeps. ``stiffness`` N/m and ``damping``
        N s/m (default 0) >= 0; ``rest_length`` (m, >= 0) defaults to the distance between
        the ends now (0: the linear spring k d). Returns its :class:`SolidSpringHandle`.
        ValueError naming the bad field; the world is then unchanged."""

    @property
    def solid_spring_count(self) -> int:
        """Number of solid springs."""

    def solid_spring_ends(self) -> npt.NDArray[np.float64]:
        """The solid springs' two ends now (n, 2, dim), m: the end on ``a``, then the end on
        ``b`` (or the world point). What a game draws."""

    def solid_energy(self) -> float:
        """Energy of the solids, J: kinetic (translation and rotation), potential in the
        world's gravity (0 at the origin) and in the solid springs. What the exact motion of
        solids touching nothing, under gravity and undamped springs, conserves."""

    def apply_solid_force(
        self, solid: int | SolidHandle, force: npt.ArrayLike, point: npt.ArrayLike | None = None
    ) -> None:
        """Applies ``force`` (N, world frame: dim numbers) to solid ``solid`` for the next
        step, at the world point ``point`` (default its centre of mass), which also turns
        it. Loads add up until a step takes them, held constant over its substeps.
        ValueError naming the bad field."""

    def add_solid_force(
        self,
        solid: int | SolidHandle,
        func: Callable[[float, npt.NDArray[np.float64], npt.NDArray[np.float64]], npt.ArrayLike],
        point: npt.ArrayLike | None = None,
        *,
        potential: Callable[[npt.NDArray[np.float64]], float] | None = None,
        name: str | None = None,
    ) -> SolidForceHandle:
        """Adds a force from Python at ``point`` of solid ``solid`` (its frame, the frame its
        shape is given in, m; default the origin of its shape): ``func(t, x, v)`` sees that
        point as one particle, its world position and velocity as (1, dim) arrays, and
        returns the force on it (1, dim), N, which also turns the solid about its centre. It
        is evaluated once a step, at the step's start, and held constant over the contact
        solver's substeps. ``potential(x)`` (J) keeps :meth:`energy` known; ``name`` names it
        in errors (default the function's). An exception raised inside propagates unchanged,
        and a result that is not finite is a ValueError naming the force; the step is
        rolled back either way. Returns its :class:`SolidForceHandle`."""

    @property
    def solid_force_count(self) -> int:
        """Number of forces from Python on solids."""

    def apply_solid_torque(self, solid: int | SolidHandle, torque: float | npt.ArrayLike) -> None:
        """Applies ``torque`` (N m: one number in 2D, a world-frame vector in 3D) to solid
        ``solid`` for the next step. ValueError naming the bad field."""

    @property
    def solid_count(self) -> int:
        """Number of solids."""

    def solid_positions(self) -> npt.NDArray[np.float64]:
        """Origins of the solids' shapes (n, dim), m."""

    def solid_orientations(self) -> npt.NDArray[np.float64]:
        """Orientations of the solids: angles (n,) in 2D, rad; quaternions (n, 4) as (w, x,
        y, z) in 3D."""

    def solid_velocities(self) -> npt.NDArray[np.float64]:
        """Velocities of the solids' centres of mass (n, dim), m/s."""

    def solid_angular_velocities(self) -> npt.NDArray[np.float64]:
        """Angular velocities of the solids: (n,) in 2D, (n, 3) in 3D, rad/s."""

    def contacts(self) -> dict[str, npt.NDArray[Any]]:
        """The contact points of the latest step as arrays: ``pairs`` (m, 2) solid indices,
        ``points`` and ``normals`` (m, dim), ``depths`` (m,) (negative: not yet touching),
        ``normal_impulses`` and ``friction_impulses`` (m,), N s."""

    @property
    def max_penetration(self) -> float:
        """The deepest penetration among the latest step's contacts, m (0 without
        contacts)."""

    @property
    def contact_passes(self) -> int:
        """The passes over the contacts the contact solver made in the latest step, counted as
        they ran (solve, relax and position passes; 0 without solids or before a step). Every
        solver makes ``2 x substeps x solver_iterations`` (the lab compares them at equal
        cost)."""

    @property
    def contact_solver(self) -> str:
        """The contact solver's name (:func:`contact_solvers` lists them)."""

    @contact_solver.setter
    def contact_solver(self, name: str) -> None: ...
    @property
    def substeps(self) -> int:
        """Substeps of the contact solver a step (1 to 1000; default 8)."""

    @substeps.setter
    def substeps(self, n: int) -> None: ...
    @property
    def solver_iterations(self) -> int:
        """Solve and relax passes of the contact solver a substep (1 to 1000; default 1)."""

    @solver_iterations.setter
    def solver_iterations(self, n: int) -> None: ...
    def add_joint(
        self,
        kind: str,
        a: int | SolidHandle,
        b: int | SolidHandle | None = None,
        *,
        anchor: npt.ArrayLike,
        anchor_b: npt.ArrayLike | None = None,
        axis: npt.ArrayLike | None = None,
        length: float | None = None,
        min_length: float | None = None,
        max_length: float | None = None,
        hertz: float | None = None,
        damping_ratio: float | None = None,
        lower: float | None = None,
        upper: float | None = None,
        motor_speed: float | None = None,
        max_motor: float | None = None,
        collide: bool = False,
    ) -> JointHandle:
        """Adds a joint between solids ``a`` and ``b`` (handles or indices from
        :meth:`add_solid`; ``b`` None: the world, fixed), solved with the contacts; returns
        its :class:`JointHandle`. ``kind``: "ball" (a shared point), "revolute" (a hinge: the point, turning
        only about ``axis`` in 3D; limits ``lower``/``upper`` in rad, a motor ``motor_speed``
        rad/s of at most ``max_motor`` N m), "distance" (the anchors ``length`` apart,
        default as made: rigid with ``hertz`` 0, else a spring of ``hertz`` and
        ``damping_ratio``, between ``min_length`` and ``max_length``), "weld" (glued; soft
        with ``hertz`` > 0) or "prismatic" (a slider along ``axis``: limits of travel
        ``lower``/``upper`` in m, a motor of at most ``max_motor`` N). ``anchor``: the
        shared point in world coordinates now (the end on ``a`` for a distance joint;
        ``anchor_b`` the end on ``b``). Angles and travel count from the pose now; for a
        joint to the world they are the solid's own. ``collide``: whether the two still
        collide (default no). ValueError naming the bad field; the world is then
        unchanged."""

    @property
    def joint_count(self) -> int:
        """Number of joints."""

    def joint_errors(self) -> npt.NDArray[np.float64]:
        """Each joint's position error now (m,): how far apart its anchors are (ball,
        revolute, weld), off its axis (prismatic), or outside its lengths (distance)."""

    @property
    def joint_hertz(self) -> float:
        """Stiffness of the joints, Hz (default 120, capped at a quarter of the substep
        rate)."""

    @joint_hertz.setter
    def joint_hertz(self, v: float) -> None: ...
    @property
    def joint_projection(self) -> int:
        """Passes after each step that move jointed solids back together (0 to 1000;
        default 0). Tightens free-swinging linkages (a whipping chain's joints 30x closer);
        under a steady load it fights the soft joints and keeps a structure from coming
        fully to rest."""

    @joint_projection.setter
    def joint_projection(self, n: int) -> None: ...
    @property
    def continuous_collision(self) -> bool:
        """Continuous collision of fast solids (default True): a dynamic solid that moves
        farther than the speculative distance (2 cm) in a step is swept against the static
        and kinematic solids and put back to where it first touches one, so it neither sinks
        into the ground nor passes through a thin wall. False: such a solid can end a step
        deep inside (a 1 m box thrown at the ground at 20 m/s sinks 30 cm)."""

    @continuous_collision.setter
    def continuous_collision(self, on: bool) -> None: ...
    @property
    def sleep_time(self) -> float:
        """How long an island of touching (or jointed) solids must be slow before it falls
        asleep, s (default 0: never; Box2D's is 0.5). Slow: speed, and angular speed times
        the largest radius, below 0.05 m/s. A sleeping solid leaves the contact solver, keeps
        its place exactly and has zero velocity, until a moving solid comes within reach, a
        joint or spring ties it to one, a load acts on it, gravity changes or its motion is
        set; then its whole island wakes. Setting 0 wakes every solid at the next step.
        ValueError naming ``sleep_time`` unless finite and >= 0."""

    @sleep_time.setter
    def sleep_time(self, v: float) -> None: ...
    def solids_asleep(self) -> npt.NDArray[np.bool_]:
        """Whether each solid is asleep (n,) bool (see :attr:`sleep_time`)."""
    def interpolated_body_orientations(self) -> npt.NDArray[np.float64]:
        """Body orientations to draw (nb, 4), (w, x, y, z): slerped by :attr:`alpha` between
        the state before the last step of the latest :meth:`advance` and the current one."""
