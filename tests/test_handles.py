"""Handles (issue 26, item 3): every add_* of a force returns a handle that stays valid while
other forces come and go; ``World.remove(h)`` removes the force and the World steps bitwise as
one that never had it; a force's parameters read and write through its handle, validated as
the add was; bad handles are one clear line."""

from __future__ import annotations

import copy
import pickle

import numpy as np
import physstep
import pytest


def wind(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
    """A module-level Python force: picklable."""
    return 0.3 - 0.1 * v


def _particles(method: str = "velocity-verlet") -> physstep.World:
    w = physstep.World(2, method=method, dt=0.01)
    w.add_particle([0.0, 0.0], static=True)
    w.add_particle([1.0, 0.2], velocity=[0.1, 0.0], mass=1.5)
    w.add_particle([2.0, -0.3], velocity=[0.0, 0.3], mass=0.5)
    w.add_particle([0.5, 1.0], velocity=[-0.2, 0.1], mass=2.0)
    return w


def _bits(w: physstep.World) -> tuple[bytes, bytes, int]:
    return (np.asarray(w.positions).tobytes(), np.asarray(w.velocities).tobytes(), w.state_hash())


ADDS = {
    "gravity": lambda w: w.add_gravity([0.0, -9.81]),
    "spring": lambda w: w.add_spring(1, 2, 40.0, rest_length=0.8, damping=0.2),
    "drag": lambda w: w.add_drag(0.05, 0.01),
    "anchor-spring": lambda w: w.add_spring(3, [0.5, 2.0], 25.0, rest_length=0.5, damping=0.1),
    "central-gravity": lambda w: w.add_central_gravity([5.0, 5.0], 3.0),
    "python": lambda w: w.add_force(wind),
}


@pytest.mark.parametrize("method", ["symplectic-euler", "velocity-verlet", "rk4", "verlet"])
@pytest.mark.parametrize("gone", sorted(ADDS))
def test_a_removed_force_steps_bitwise_as_a_world_that_never_had_it(method: str, gone: str) -> None:
    w = _particles(method)
    handles = {name: add(w) for name, add in ADDS.items()}
    w.remove(handles[gone])
    never = _particles(method)
    for name, add in ADDS.items():
        if name != gone:
            add(never)
    w.step(200)
    never.step(200)
    assert _bits(w) == _bits(never)
    # The others are still reachable through their handles; the removed one is not.
    assert not handles[gone].alive
    assert [h.kind for h in w.forces] == [h.kind for h in never.forces]
    assert all(h.alive for name, h in handles.items() if name != gone)


def test_every_add_of_a_force_returns_a_handle_of_its_kind() -> None:
    w = _particles()
    w.add_rod(1, 3)
    kinds = {name: add(w).kind for name, add in ADDS.items()}
    assert kinds == {
        "gravity": "gravity",
        "spring": "spring",
        "drag": "drag",
        "anchor-spring": "spring",
        "central-gravity": "central-gravity",
        "python": "python",
    }
    assert w.add_nbody_gravity(2.0, 0.1).kind == "nbody"
    rod = w.forces[-2]
    assert rod.kind == "rod" and (rod.i, rod.j) == (1, 3) and rod.length == pytest.approx(np.hypot(0.5, 0.8))
    assert isinstance(rod, physstep.ForceHandle)


def test_a_springs_stiffness_changed_through_its_handle_changes_the_next_step() -> None:
    w = _particles()
    w.add_gravity([0.0, -9.81])
    s = w.add_spring(1, 2, 40.0, rest_length=0.8, damping=0.2)
    before = copy.copy(w)
    s.stiffness = 2e3
    assert s.stiffness == 2e3
    from_start = _particles()
    from_start.add_gravity([0.0, -9.81])
    from_start.add_spring(1, 2, 2e3, rest_length=0.8, damping=0.2)
    for world in (w, from_start, before):
        world.step()
    assert _bits(w) == _bits(from_start)
    assert _bits(w) != _bits(before)


def test_every_parameter_reads_and_writes_through_the_handle() -> None:
    w = _particles()
    g = w.add_gravity([0.0, -9.81])
    d = w.add_drag(0.1)
    c = w.add_central_gravity([1.0, 2.0], 3.0)
    n = w.add_nbody_gravity(1.0, 0.5)
    a = w.add_spring(3, [0.5, 2.0], 25.0)
    g.g = [1.0, -2.0]
    d.linear, d.quadratic = 0.2, 0.3
    c.center, c.gm = [4.0, 5.0], -1.0
    n.g, n.softening = 2.5, 0.25
    a.anchor = [3.0, 4.0]
    a.rest_length, a.damping = 1.5, 0.5
    assert g.g.tolist() == [1.0, -2.0]
    assert (d.linear, d.quadratic) == (0.2, 0.3)
    assert (c.center.tolist(), c.gm) == ([4.0, 5.0], -1.0)
    assert (n.g, n.softening) == (2.5, 0.25)
    assert np.asarray(a.anchor).tolist() == [3.0, 4.0] and (a.i, a.j) == (3, None)
    assert (a.stiffness, a.rest_length, a.damping) == (25.0, 1.5, 0.5)
    # The same world built with those values from the start steps the same bits.
    same = _particles()
    same.add_gravity([1.0, -2.0])
    same.add_drag(0.2, 0.3)
    same.add_central_gravity([4.0, 5.0], -1.0)
    same.add_nbody_gravity(2.5, 0.25)
    same.add_spring(3, [3.0, 4.0], 25.0, rest_length=1.5, damping=0.5)
    w.step(50)
    same.step(50)
    assert _bits(w) == _bits(same)


def test_handles_stay_with_their_forces_while_others_come_and_go() -> None:
    w = _particles()
    s = w.add_spring(2, 1, 10.0)
    g = w.add_gravity([0.0, -1.0])
    d = w.add_drag(0.5)
    w.remove(g)
    # Gravity sorted before the spring: indices moved, handles did not.
    assert (s.i, s.j, s.stiffness) == (1, 2, 10.0)
    assert d.linear == 0.5
    g2 = w.add_gravity([0.0, -2.0])
    assert g2.id not in (s.id, g.id, d.id)
    assert w.forces == [g2, s, d]
    assert w.forces[0] == g2 and hash(w.forces[0]) == hash(g2) and g2 != g


def test_bad_handles_and_values_are_one_line_and_change_nothing() -> None:
    w = _particles()
    s = w.add_spring(1, 2, 40.0, rest_length=0.8)
    g = w.add_gravity([0.0, -9.81])
    r = w.add_rod(1, 3)
    other = _particles()
    foreign = other.add_gravity([0.0, -1.0])
    kept = _bits(w)

    def one_line(exc: pytest.ExceptionInfo[BaseException]) -> str:
        text = str(exc.value)
        assert "\n" not in text
        return text

    for attr, value, field in [
        ("stiffness", -1.0, "invalid stiffness = -1"),
        ("stiffness", "stiff", "invalid stiffness = 'stiff'"),
        ("rest_length", float("nan"), "invalid rest_length = NaN"),
        ("damping", float("inf"), "invalid damping = inf"),
    ]:
        with pytest.raises(ValueError) as e:
            setattr(s, attr, value)
        assert one_line(e).startswith(field)
    with pytest.raises(ValueError) as e:
        g.g = [0.0, float("nan")]
    assert one_line(e).startswith("invalid g[1] = NaN")
    with pytest.raises(ValueError) as e:
        g.g = [0.0, 1.0, 2.0]
    assert one_line(e).startswith("invalid g shape")
    with pytest.raises(ValueError) as e:
        s.anchor = [1.0, 1.0]
    assert "joins two particles" in one_line(e)
    with pytest.raises(AttributeError) as ae:
        _ = g.stiffness
    assert one_line(ae) == "a gravity force has no stiffness"
    with pytest.raises(AttributeError):
        r.length = 2.0  # type: ignore[misc]
    with pytest.raises(ValueError) as e:
        w.remove(foreign)
    expected = "invalid force = ForceHandle(id=0, kind='gravity'): must be a handle of this World"
    assert one_line(e).startswith(expected)
    with pytest.raises(ValueError) as e:
        w.remove(3)  # type: ignore[arg-type]
    assert one_line(e).startswith("invalid handle = 3: must be a ForceHandle")
    assert (s.stiffness, s.rest_length, s.damping) == (40.0, 0.8, 0.0)
    assert g.g.tolist() == [0.0, -9.81]
    w.remove(g)
    for act in (lambda: w.remove(g), lambda: setattr(g, "g", [0.0, 1.0]), lambda: g.g, lambda: w.force(g)):
        with pytest.raises(ValueError) as e:
            act()
        assert "invalid force = " in one_line(e)
    assert _bits(w) == kept


def test_handles_reach_the_same_forces_in_a_copy_and_an_unpickled_world() -> None:
    w = _particles()
    g = w.add_gravity([0.0, -9.81])
    s = w.add_spring(1, 2, 40.0)
    p = w.add_force(wind)
    d = w.add_drag(0.1)
    w.remove(g)  # ids now out of the order a scene file would give them
    for twin in (copy.copy(w), pickle.loads(pickle.dumps(w))):
        assert twin.force(s).stiffness == 40.0 and twin.force(d).linear == 0.1
        assert twin.force(p).kind == "python"
        twin.force(s).stiffness = 80.0
        assert s.stiffness == 40.0  # the original's own force is untouched
        twin.remove(p)
        assert len(twin.forces) == 2 and p.alive
        with pytest.raises(ValueError):
            twin.force(g)
        # A new force never takes an id the original gave.
        assert twin.add_drag(0.2).id not in (g.id, s.id, p.id, d.id)
    # The twin without the Python force steps as the original without it.
    twin = pickle.loads(pickle.dumps(w))
    twin.remove(twin.force(p))
    w.remove(p)
    w.step(20)
    twin.step(20)
    assert _bits(w) == _bits(twin)


def test_a_pickle_written_before_handles_still_loads_with_ids_in_order() -> None:
    w = _particles()
    w.add_gravity([0.0, -9.81])
    w.add_force(wind)
    rebuild, (parts, snapshot) = w.__reduce__()
    for key in ("family", "force_ids", "next_force_id"):
        del parts[key]
    old = rebuild(parts, snapshot)
    assert [(h.id, h.kind) for h in old.forces] == [(0, "gravity"), (1, "python")]
    old.step(10)
    w.step(10)
    assert _bits(old) == _bits(w)


# Per-entity views: w.particles[i], w.bodies[b].


def test_a_particle_set_through_its_view_is_the_state_stepped() -> None:
    for method in ("symplectic-euler", "velocity-verlet", "rk4", "verlet"):
        w = _particles(method)
        w.add_gravity([0.0, -9.81])
        w.add_spring(1, 2, 40.0)
        w.step(10)
        built = copy.copy(w)
        p = w.particles[1]
        p.position = [0.7, -0.4]
        p.velocity = [1.0, 2.0]
        p.mass = 3.0
        assert (p.position.tolist(), p.velocity.tolist(), p.mass) == ([0.7, -0.4], [1.0, 2.0], 3.0)
        # The same through the whole-array setters (which restart a method's memory alike).
        x, v = np.array(built.positions), np.array(built.velocities)
        x[1], v[1] = [0.7, -0.4], [1.0, 2.0]
        built.positions, built.velocities = x, v
        built.particles[-3].mass = 3.0
        w.step(30)
        built.step(30)
        assert _bits(w) == _bits(built), method


def test_the_particles_are_a_sequence_of_views() -> None:
    w = _particles()
    w.add_particle([5.0, 5.0])  # waiting in the batch: counted and reachable
    assert len(w.particles) == 5
    assert [p.index for p in w.particles] == [0, 1, 2, 3, 4]
    assert w.particles[-1].position.tolist() == [5.0, 5.0]
    assert w.particles[0].static and not w.particles[1].static
    with pytest.raises(IndexError, match="particle index 5 out of range: the World has 5 particles"):
        w.particles[5]
    view = w.positions
    w.particles[2].position = [9.0, 9.0]
    assert view[2].tolist() == [9.0, 9.0]  # the zero-copy view shows it


def test_bad_particle_values_are_one_line_and_change_nothing() -> None:
    w = _particles()
    w.add_nbody_gravity()
    kept = (_bits(w), [p.mass for p in w.particles])
    p, fixed = w.particles[1], w.particles[0]
    for attr, value, start in [
        ("position", [0.0, float("nan")], "invalid position[1] = NaN"),
        ("position", [0.0, 1.0, 2.0], "invalid position shape (3,): must be (2,)"),
        ("velocity", [1e200, 0.0], "invalid velocity[0] = 1e200"),
        ("mass", 0.0, "invalid mass = 0: must be > 0"),
        ("mass", float("inf"), "invalid mass[1] = inf: must be finite when n-body gravity is on"),
        ("mass", "heavy", "invalid mass = 'heavy': must be a number"),
    ]:
        with pytest.raises(ValueError) as e:
            setattr(p, attr, value)
        assert str(e.value).startswith(start) and "\n" not in str(e.value)
    with pytest.raises(ValueError, match="must be zero for particle 0, which is static"):
        fixed.velocity = [1.0, 0.0]
    assert (_bits(w), [p.mass for p in w.particles]) == kept


def _bodies() -> physstep.World:
    w = physstep.World(3, method="rk4", dt=0.01)
    w.add_gravity([0.0, 0.0, -9.81])
    w.add_body(physstep.Box(1.0, 0.5, 0.2), mass=2.0, angular_velocity=[0.1, 1.0, 0.2])
    w.add_body(physstep.Sphere(0.3), position=[3.0, 0.0, 0.0])
    return w


def test_a_bodys_velocity_set_through_its_view_is_the_one_stepped() -> None:
    q = [0.9, 0.1, -0.3, 0.2]
    w = _bodies()
    b = w.bodies[0]
    b.position = [1.0, 2.0, 3.0]
    b.velocity = [0.5, -1.0, 2.0]
    b.orientation = q
    b.angular_velocity = [2.0, 0.0, -1.0]
    built = physstep.World(3, method="rk4", dt=0.01)
    built.add_gravity([0.0, 0.0, -9.81])
    built.add_body(
        physstep.Box(1.0, 0.5, 0.2),
        mass=2.0,
        position=[1.0, 2.0, 3.0],
        velocity=[0.5, -1.0, 2.0],
        orientation=q,
        angular_velocity=[2.0, 0.0, -1.0],
    )
    built.add_body(physstep.Sphere(0.3), position=[3.0, 0.0, 0.0])
    assert np.allclose(b.orientation, np.array(q) / np.linalg.norm(q), rtol=0, atol=1e-15)
    assert np.allclose(b.angular_velocity, [2.0, 0.0, -1.0], rtol=0, atol=1e-12)
    w.step(40)
    built.step(40)
    assert w.state_hash() == built.state_hash()
    assert w.bodies.positions.tobytes() == built.body_positions().tobytes()
    for name in ("positions", "velocities", "orientations", "angular_velocities"):
        arr = getattr(w.bodies, name)
        assert arr.shape == (2, 4 if name == "orientations" else 3)
    assert [x.index for x in w.bodies] == [0, 1] and len(w.bodies) == 2 and w.bodies[-1].mass > 0


def test_bad_body_values_are_one_line_and_change_nothing() -> None:
    w = _bodies()
    w.add_body(physstep.Sphere(0.3), position=[0.0, 5.0, 0.0], pivot=[0.0, 0.0, 0.3])
    kept = w.state_hash()
    b, pinned = w.bodies[0], w.bodies[2]
    for attr, value, start in [
        ("position", [0.0, float("nan"), 0.0], "invalid position[1] = NaN"),
        ("velocity", [0.0, 0.0], "invalid velocity shape (2,): must be (3,)"),
        ("orientation", [0.0, 0.0, 0.0, 0.0], "invalid orientation = [0, 0, 0, 0]: must be a quaternion"),
        ("angular_velocity", [0.0, 0.0, float("inf")], "invalid angular_velocity[2] = inf"),
    ]:
        with pytest.raises(ValueError) as e:
            setattr(b, attr, value)
        assert str(e.value).startswith(start) and "\n" not in str(e.value)
    with pytest.raises(ValueError, match="pinned body"):
        pinned.position = [0.0, 0.0, 0.0]
    with pytest.raises(ValueError, match="pinned body"):
        pinned.velocity = [1.0, 0.0, 0.0]
    with pytest.raises(IndexError, match="body index 3 out of range"):
        w.bodies[3]
    assert w.state_hash() == kept


def test_state_set_through_views_is_in_the_snapshot_hash_and_pickle() -> None:
    w = _bodies()
    w.add_particle([0.0, 0.0, 1.0], velocity=[1.0, 0.0, 0.0])
    h = w.state_hash()
    w.bodies[1].velocity = [0.0, 1.0, 0.0]
    w.particles[0].position = [0.0, 0.0, 2.0]
    assert w.state_hash() != h
    twin = pickle.loads(pickle.dumps(w))
    restored = _bodies()
    restored.add_particle([0.0, 0.0, 1.0], velocity=[1.0, 0.0, 0.0])
    restored.restore(w.snapshot())
    assert twin.state_hash() == w.state_hash() == restored.state_hash()
    for world in (w, twin, restored):
        world.step(25)
    assert twin.state_hash() == w.state_hash() == restored.state_hash()
