"""Particles and constraints by handle (issue 26, item 3): add_particle, add_ball and the
add_* of constraints return handles that stay their entity's while others are removed;
``World.remove(h)`` removes a particle with what hangs on it (springs, rods, constraints),
and the World then steps bitwise as one built without it; copies, pickles, snapshots and
hashes cover the ids; bad removals are one clear line, the World unchanged."""

from __future__ import annotations

import copy
import operator
import pickle
from typing import Any

import numpy as np
import physstep
import pytest


def push(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
    """A module-level Python force (picklable): depends on each particle's own state only."""
    return 0.2 - 0.05 * x


P = [
    ([0.0, 0.0], [0.0, 0.1], 1.0),
    ([1.0, 0.2], [0.1, 0.0], 1.5),
    ([2.0, -0.3], [0.0, 0.3], 0.5),
    ([0.5, 1.0], [-0.2, 0.1], 2.0),
]


def _bits(w: physstep.World) -> tuple[bytes, bytes]:
    return (np.asarray(w.positions).tobytes(), np.asarray(w.velocities).tobytes())


def _one_line(exc: pytest.ExceptionInfo[BaseException]) -> str:
    text = str(exc.value)
    assert "\n" not in text
    return text


def test_three_particles_remove_the_second_the_third_handle_still_reaches_it() -> None:
    w = physstep.World(2, dt=0.01)
    a, b, c = (w.add_particle([float(k), 0.0], velocity=[0.0, float(k)], mass=1.0 + k) for k in range(3))
    assert isinstance(c, physstep.ParticleHandle) and (a.id, b.id, c.id) == (0, 1, 2)
    assert operator.index(c) == 2 and w.positions[c].tolist() == [2.0, 0.0]
    w.remove(b)
    assert w.positions.shape == (2, 2) and w.velocities.shape == (2, 2) and len(w) == 2
    assert operator.index(c) == 1 and w.positions[c].tolist() == [2.0, 0.0]
    assert w.velocities[c].tolist() == [0.0, 2.0] and w.particles[c].mass == 3.0
    assert (a.alive, b.alive, c.alive) == (True, False, True)
    with pytest.raises(ValueError) as e:
        operator.index(b)
    assert _one_line(e) == "invalid particle = ParticleHandle(id=1): it was removed from its World"
    # A view taken by handle follows the particle; a new particle gets a new id.
    view = w.particles[c]
    d = w.add_particle([9.0, 9.0])
    assert d.id == 3 and operator.index(d) == 2
    w.remove(a)
    assert view.position.tolist() == [2.0, 0.0] and view.index == 0
    view.velocity = [1.0, 0.0]
    assert w.velocities[0].tolist() == [1.0, 0.0]
    assert len({c, d, w.particles[c] and c}) == 2 and c != d and hash(c) != hash(d)


def _forces_world(method: str, without: bool) -> tuple[physstep.World, list[physstep.ParticleHandle]]:
    """Four particles under every kind of force, particle 1 on a pair spring, an anchor
    spring and a rod; ``without``: the world built without particle 1 and what hung on it."""
    w = physstep.World(2, method=method, dt=0.01)
    h = [w.add_particle(x, velocity=v, mass=m) for k, (x, v, m) in enumerate(P) if not (without and k == 1)]
    at = {0: h[0], 2: h[-2], 3: h[-1]} if without else dict(enumerate(h))
    w.add_gravity([0.0, -9.81])
    w.add_drag(0.05, 0.01)
    w.add_central_gravity([5.0, 5.0], 3.0)
    w.add_nbody_gravity(0.1, 0.05)
    w.add_force(push)
    if not without:
        w.add_spring(at[0], at[1], 40.0, rest_length=0.8, damping=0.2)
        w.add_spring(at[1], [0.0, 2.0], 40.0, rest_length=0.8, damping=0.2)
        w.add_rod(at[1], at[3])
    w.add_spring(at[3], at[2], 40.0, rest_length=0.8, damping=0.2)
    w.add_spring(at[3], [0.5, 2.0], 40.0, rest_length=0.8, damping=0.2)
    w.add_rod(at[0], at[2])
    return w, h


@pytest.mark.parametrize("method", ["symplectic-euler", "velocity-verlet", "rk4", "leapfrog", "verlet"])
def test_a_removed_particle_leaves_the_world_stepping_bitwise_as_one_built_without_it(method: str) -> None:
    a, h = _forces_world(method, without=False)
    forces = a.forces
    a.remove(h[1])
    b, _ = _forces_world(method, without=True)
    assert [f.kind for f in a.forces] == [f.kind for f in b.forces]
    assert sum(not f.alive for f in forces) == 3  # two springs and a rod went with it
    a.step(40)
    b.step(40)
    assert _bits(a) == _bits(b)
    # After steps: the rest goes on as a world started from that state.
    a, h = _forces_world(method, without=False)
    a.step(25)
    a.remove(h[1])
    b, _ = _forces_world(method, without=True)
    b.positions, b.velocities = a.positions, a.velocities
    a.step(30)
    b.step(30)
    assert _bits(a) == _bits(b)


def test_removing_a_particle_takes_its_springs_and_constraints_and_renumbers_the_rest() -> None:
    w = physstep.World(2, method="symplectic-euler", dt=0.01)
    h = [w.add_particle(x, velocity=v, mass=m) for x, v, m in P]
    s01 = w.add_spring(h[0], h[1], 10.0)
    s23 = w.add_spring(h[2], h[3], 10.0)
    pin = w.add_pin(h[0], [0.0, 0.0])
    rope = w.add_rope(h[1], h[3], 3.0)
    limit = w.add_distance_limit(h[2], h[3], 0.1, 4.0)
    dist = w.add_distance_constraint(h[3], [1.0, 1.0], length=1.5, compliance=1e-4)
    plane = w.add_plane([0.0, 2.0], -5.0)
    assert isinstance(rope, physstep.ConstraintHandle) and operator.index(plane) == 4
    w.remove(h[1])
    assert (s01.alive, s23.alive, rope.alive) == (False, True, False)
    assert (s23.i, s23.j) == (1, 2)
    assert (limit.kind, limit.i, limit.j, limit.min_length, limit.max_length) == ("limit", 1, 2, 0.1, 4.0)
    assert (dist.kind, dist.i, dist.j, dist.length, dist.compliance) == ("distance", 2, None, 1.5, 1e-4)
    assert dist.anchor.tolist() == [1.0, 1.0] and pin.point.tolist() == [0.0, 0.0]
    assert plane.normal.tolist() == [0.0, 1.0] and plane.offset == -5.0
    assert w.constraint_count == 4 and operator.index(plane) == 3
    with pytest.raises(AttributeError) as ae:
        _ = pin.length
    assert _one_line(ae) == "a pin constraint has no length"
    w.remove(limit)
    assert not limit.alive and w.constraint_count == 3 and operator.index(plane) == 2
    with pytest.raises(ValueError) as e:
        _ = limit.kind
    assert _one_line(e) == "invalid constraint = ConstraintHandle(id=2): it was removed from its World"
    w.step(10)


def test_batches_of_particles_and_balls_are_one_handle() -> None:
    w = physstep.World(2, method="velocity-verlet", dt=0.01)
    w.add_walls([-5.0, -5.0], [5.0, 5.0])
    first = w.add_ball([-3.0, 0.0], velocity=[1.0, 0.0], radius=0.3)
    balls = w.add_balls([[0.0, 0.0], [2.0, 0.0], [3.5, 0.0]], radii=[0.2, 0.4, 0.3])
    assert isinstance(balls, physstep.ParticleHandles) and len(balls) == 3
    assert balls.ids.tolist() == [1, 2, 3] and np.asarray(balls).tolist() == [1, 2, 3]
    w.remove(balls[1])
    assert w.radii.tolist() == [0.3, 0.2, 0.3] and operator.index(balls[-1]) == 2
    with pytest.raises(ValueError) as e:
        _ = balls.rows
    assert _one_line(e).startswith("invalid particle = ParticleHandle(id=2) (of ParticleHandles(ids 1..4)):")
    ref = physstep.World(2, method="velocity-verlet", dt=0.01)
    ref.add_walls([-5.0, -5.0], [5.0, 5.0])
    ref.add_ball([-3.0, 0.0], velocity=[1.0, 0.0], radius=0.3)
    ref.add_balls([[0.0, 0.0], [3.5, 0.0]], radii=[0.2, 0.3])
    w.step(300)
    ref.step(300)
    assert _bits(w) == _bits(ref) and w.collisions["count"] > 0
    w.remove(first)
    assert len(w) == 2 and not first.alive
    rest = w.add_particles(np.ones((2, 2)))
    w.remove(rest)
    assert len(w) == 2 and not rest.alive


def test_a_batch_removed_at_once_is_the_batch_removed_one_by_one() -> None:
    # One pass over the rows for the whole batch (was one pass a particle: 12 s for 1e5).
    def build() -> tuple[physstep.World, physstep.ParticleHandles]:
        w = physstep.World(2, method="velocity-verlet", dt=0.01)
        w.add_gravity([0.0, -9.81])
        first = w.add_particles(np.column_stack([np.arange(6.0), np.zeros(6)]))
        batch = w.add_particles(np.column_stack([np.arange(6.0), np.ones(6)]))
        for k in range(6):
            w.add_spring(first[k], batch[k], 50.0)
        w.add_spring(batch[5], [6.0, 2.0], 10.0)
        w.add_pin(first[0], [0.0, 0.0])
        w.step(5)
        return w, batch

    a, batch_a = build()
    b, batch_b = build()
    a.remove(batch_a)
    for h in list(batch_b):
        b.remove(h)
    assert len(a) == 6 and not batch_a.alive
    assert (_bits(a), a.state_hash()) == (_bits(b), b.state_hash())
    a.step(40)
    b.step(40)
    assert _bits(a) == _bits(b)


def test_pickles_copies_and_snapshots_cover_the_ids() -> None:
    w = physstep.World(2, method="velocity-verlet", dt=0.01)
    h = [w.add_particle(x, velocity=v, mass=m) for x, v, m in P]
    w.add_gravity([0.0, -9.81])
    s = w.add_spring(h[2], h[3], 30.0)
    c = w.add_distance_constraint(h[0], h[2])
    before = w.snapshot()
    hash_before_removal = w.state_hash()
    w.step(5)
    w.remove(h[1])
    # The same rows and numbers with other ids hash differently.
    assert w.state_hash() != hash_before_removal
    with pytest.raises(ValueError) as e:
        w.restore(before)
    assert "other particles, bodies or constraints" in _one_line(e)
    for twin in (pickle.loads(pickle.dumps(w)), copy.copy(w)):
        assert twin.state_hash() == w.state_hash()
        assert twin.particles[h[3]].index == 2  # w's handles reach the same particles
        twin.remove(h[3])
        assert len(twin) == 2 and len(w) == 3 and s.alive
        with pytest.raises(ValueError):
            twin.force(s)  # the spring went with the particle, in the twin only
    w.step(20)
    p = pickle.loads(pickle.dumps(w))
    w.step(15)
    p.step(15)
    assert w.state_hash() == p.state_hash() and _bits(w) == _bits(p)
    assert c.alive and operator.index(c) == 0
    # A snapshot after the removal restores bitwise.
    snap = w.snapshot()
    w.step(7)
    later = w.state_hash()
    w.restore(snap)
    w.step(7)
    assert w.state_hash() == later


def test_bad_removals_are_one_line_and_change_nothing() -> None:
    w = physstep.World(2, dt=0.01)
    h = [w.add_particle(x, velocity=v, mass=m) for x, v, m in P]
    c = w.add_pin(h[0], [0.0, 0.0])
    w.remove(h[1])
    w.remove(c)
    other = physstep.World(2)
    foreign = other.add_particle([0.0, 0.0])
    kept = (_bits(w), w.state_hash())
    for handle, expected in [
        (h[1], "invalid particle = ParticleHandle(id=1): it was removed from its World"),
        (c, "invalid constraint = 0: must be the id of a constraint of this world (it was removed, or never"),
        (foreign, "invalid particle = ParticleHandle(id=0): must be a handle of this World's particles"),
        (
            3,
            "invalid handle = 3: must be a ForceHandle, ParticleHandle, ParticleHandles, ConstraintHandle,",
        ),
    ]:
        with pytest.raises(ValueError) as e:
            w.remove(handle)
        assert _one_line(e).startswith(expected)
    with pytest.raises(ValueError) as e:
        w.add_spring(h[1], h[2], 10.0)
    assert _one_line(e) == "invalid i = ParticleHandle(id=1): it was removed from its World"
    with pytest.raises(ValueError) as e:
        w.add_rope(h[0], foreign, 1.0)
    # The argument is named (j), the kind of handle it must be too (it read "this World's js").
    assert _one_line(e).startswith(
        "invalid j = ParticleHandle(id=0): must be a handle of this World's particles (it is another World's;"
    )
    with pytest.raises(IndexError):
        _ = w.positions[h[1]]  # numpy turns the handle's ValueError into its own IndexError
    assert (_bits(w), w.state_hash()) == kept


def test_a_handle_of_another_kind_is_not_an_index_of_this_one() -> None:
    w = physstep.World(3)
    p = [w.add_particle([float(k), 0.0, 0.0]) for k in range(3)]
    pin = w.add_pin(p[2], [2.0, 0.0, 0.0])
    body = w.add_body(physstep.Sphere(0.1))
    kept = (_bits(w), w.state_hash())
    for call, expected in [
        (
            lambda: w.add_spring(p[0], pin, 1.0),
            "invalid j_or_anchor = ConstraintHandle(id=0): must be a particle",
        ),
        (lambda: w.add_rope(body, p[1], 1.0), "invalid i = BodyHandle(id=0): must be a particle index or"),
        (lambda: w.particles[pin], "invalid index = ConstraintHandle(id=0): must be a particle index or"),
        (
            lambda: w.bodies[p[0]],
            "invalid index = ParticleHandle(id=0): must be a body index or a BodyHandle",
        ),
        (lambda: w.apply_force(p[0], [1.0, 0.0, 0.0]), "invalid body = ParticleHandle(id=0): must be a body"),
        (lambda: w.add_body_force(p[0], lift), "invalid body = ParticleHandle(id=0): must be a body"),
    ]:
        with pytest.raises(ValueError) as e:
            call()
        assert _one_line(e).startswith(expected)
    assert (_bits(w), w.state_hash()) == kept


def test_a_solid_argument_refuses_another_kinds_handle_and_a_particle_one_a_solids() -> None:
    # Both used to take the other kind's row through its __index__: silently another entity.
    w = physstep.World(2)
    p = w.add_particle([0.0, 5.0])
    w.add_solid(physstep.Box(5.0, 0.5), kind="static")
    box = w.add_solid(physstep.Box(0.5, 0.5), position=[0.0, 2.0])
    kept = (_bits(w), w.state_hash(), w.solid_positions().tobytes())
    for call, expected in [
        (
            lambda: w.add_joint("ball", p, box, anchor=[0.0, 2.0]),
            "invalid a = ParticleHandle(id=0): must be a solid index or a SolidHandle",
        ),
        (
            lambda: w.add_joint("ball", box, p, anchor=[0.0, 2.0]),
            "invalid b = ParticleHandle(id=0): must be a solid index or a SolidHandle",
        ),
        (lambda: w.particles[box], "invalid index = SolidHandle(id=1): must be a particle index or"),
        (lambda: w.add_spring(box, p, 1.0), "invalid i = SolidHandle(id=1): must be a particle index or"),
    ]:
        with pytest.raises(ValueError) as e:
            call()
        assert _one_line(e).startswith(expected)
    assert (_bits(w), w.state_hash(), w.solid_positions().tobytes()) == kept


def lift(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
    """A module-level force at a body point (picklable)."""
    return np.array([[0.0, 5.0, 0.0]])


def test_bodies_by_handle_and_their_removal() -> None:
    def build(with_first: bool) -> tuple[physstep.World, list[physstep.BodyHandle]]:
        w = physstep.World(3, method="velocity-verlet", dt=0.01)
        p = w.add_particle([0.0, 2.0, 0.0], velocity=[0.1, 0.0, 0.0])
        w.add_gravity([0.0, -9.81, 0.0])
        hs = []
        if with_first:
            hs.append(w.add_body(physstep.Box(0.5, 0.3, 0.2), mass=2.0, position=[-1.0, 0.0, 0.0]))
            w.add_body_spring(hs[0], [0.5, 0.0, 0.0], p, 20.0, damping=0.1)
        box = physstep.Box(0.5, 0.3, 0.2)
        hs.append(w.add_body(box, mass=3.0, position=[1.0, 0.0, 0.0], angular_velocity=[1.0, 2.0, 0.0]))
        w.add_body_spring(hs[-1], [0.0, 0.3, 0.0], [1.0, 2.0, 0.0], 30.0, rest_length=0.5)
        return w, hs

    a, (b0, b1) = build(True)
    assert isinstance(b1, physstep.BodyHandle) and operator.index(b1) == 1
    view = a.bodies[b1]
    on_first = a.add_body_force(b0, lift, point=[0.1, 0.0, 0.0])
    spring = a.add_body_spring(b0, [0.0, 0.0, 0.2], [0.0, 3.0, 0.0], 5.0)
    assert isinstance(spring, physstep.BodySpringHandle) and isinstance(on_first, physstep.BodyForceHandle)
    assert (operator.index(spring), operator.index(on_first)) == (2, 0)
    a.remove(spring)
    assert not spring.alive
    a.remove(b0)
    assert not on_first.alive  # the force at its point went with it
    assert (b0.alive, b1.alive, operator.index(b1), view.index, view.mass) == (False, True, 0, 0, 3.0)
    with pytest.raises(ValueError) as e:
        a.apply_force(b0, [1.0, 0.0, 0.0])
    assert _one_line(e) == "invalid body = BodyHandle(id=0): it was removed from its World"
    other, _ = build(False)
    with pytest.raises(ValueError) as e:
        other.apply_force(b1, [1.0, 0.0, 0.0])
    assert _one_line(e).startswith(
        "invalid body = BodyHandle(id=1): must be a handle of this World's bodies ("
    )
    ref, _ = build(False)
    a.step(30)
    ref.step(30)
    assert _bits(a) == _bits(ref)
    assert a.bodies.positions.tobytes() == ref.bodies.positions.tobytes()
    assert a.bodies.orientations.tobytes() == ref.bodies.orientations.tobytes()
    up = a.add_body_force(b1, lift)
    p = pickle.loads(pickle.dumps(a))
    assert p.state_hash() == a.state_hash() and p.bodies[b1].mass == 3.0
    p.step(10)
    a.step(10)
    assert p.state_hash() == a.state_hash()
    for w in (a, p):
        w.remove(up)  # a's handle reaches the force in its unpickled twin
        w.step(5)
    assert p.state_hash() == a.state_hash()
    with pytest.raises(ValueError) as e:
        a.remove(up)
    assert _one_line(e).startswith("invalid body_force = 1: must be the id of a body force of this world")


def test_a_body_springs_parameters_read_and_write_through_its_handle() -> None:
    def world(stiffness: float, rest: float, damping: float) -> tuple[physstep.World, Any]:
        w = physstep.World(3, method="symplectic-euler", dt=0.01)
        b = w.add_body(physstep.Box(0.5, 0.3, 0.2), mass=2.0, position=[0.0, 0.0, 0.0])
        end = [2.0, 1.0, 0.0]
        s = w.add_body_spring(b, [0.5, 0.0, 0.0], end, stiffness, rest_length=rest, damping=damping)
        return w, s

    changed, s = world(20.0, 0.5, 0.1)
    assert (s.stiffness, s.rest_length, s.damping) == (20.0, 0.5, 0.1)
    s.stiffness, s.rest_length, s.damping = 80.0, 1.5, 0.7
    assert (s.stiffness, s.rest_length, s.damping) == (80.0, 1.5, 0.7)
    built, _ = world(80.0, 1.5, 0.7)
    changed.step(50)
    built.step(50)
    # A change is a new spring in the old one's place: bitwise the world built with it.
    assert changed.state_hash() == built.state_hash()
    old, _ = world(20.0, 0.5, 0.1)
    old.step(50)
    assert old.state_hash() != changed.state_hash()
    for field, bad in [("stiffness", -1.0), ("rest_length", float("nan")), ("damping", float("inf"))]:
        before = changed.state_hash()
        with pytest.raises(ValueError, match=rf"^invalid {field} = .*: must be a number in \[0, 1e12\]$"):
            setattr(s, field, bad)
        assert changed.state_hash() == before
    changed.remove(s)
    with pytest.raises(ValueError, match="BodySpringHandle.*removed"):
        _ = s.stiffness
