"""Zero-copy reads (docs/views.md): ``World.positions`` and ``World.velocities`` are read-only
views of the world's own memory. Steps and assignments show through a view; adding particles
or bodies detaches it (it keeps its values and stays readable, never dangles)."""

from __future__ import annotations

import copy
import gc
import pickle
import threading

import numpy as np
import physstep
import pytest

METHODS = [m.name for m in physstep.methods()]


def address(a: np.ndarray) -> int:
    return a.__array_interface__["data"][0]


def bits(a: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(a).view(np.uint64)


def spring_world(method: str = "symplectic-euler", n: int = 5) -> physstep.World:
    w = physstep.World(2, method=method, dt=0.01)
    w.add_particles(np.arange(2.0 * n).reshape(n, 2), velocities=np.ones((n, 2)))
    w.add_particle([0.0, 5.0], static=True)
    w.add_spring(0, n, 3.0, damping=0.1)
    w.add_gravity([0.0, -9.8])
    return w


def body_world(method: str) -> physstep.World:
    w = physstep.World(3, method=method, dt=0.01)
    w.add_particles([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]], velocities=[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    w.add_gravity([0.0, 0.0, -9.8])
    w.add_body(physstep.Sphere(0.5), mass=2.0, angular_velocity=[0.1, 2.0, 0.3])
    return w


@pytest.mark.parametrize("part", ["positions", "velocities"])
def test_a_read_is_a_view_of_the_same_memory(part: str) -> None:
    w = spring_world()
    a, b = getattr(w, part), getattr(w, part)
    assert a is not b and np.shares_memory(a, b) and address(a) == address(b)
    assert a.shape == (6, 2) and a.dtype == np.float64 and a.flags.c_contiguous
    assert not a.flags.owndata and a.base is not None
    assert not np.shares_memory(w.positions, w.velocities)
    # Copies are copies: interpolated positions, accelerations, the phase.
    assert not np.shares_memory(w.interpolated_positions(), w.positions)
    assert not np.shares_memory(w.accelerations, w.velocities)


def test_the_values_are_the_states_bitwise() -> None:
    w = spring_world("rk4")
    w.step(7)
    n, d = len(w), w.dim
    phase = w.phase_state()  # a copy of [x; v], from another path
    assert np.array_equal(bits(w.positions), bits(phase[: n * d].reshape(n, d)))
    assert np.array_equal(bits(w.velocities), bits(phase[n * d : 2 * n * d].reshape(n, d)))
    assert np.array_equal(bits(np.array(w.positions)), bits(w.positions))
    assert w.positions.tolist() == np.array(w.positions).tolist()


@pytest.mark.parametrize("part", ["positions", "velocities"])
def test_a_view_refuses_writes(part: str) -> None:
    w = spring_world()
    a = getattr(w, part)
    before = a.copy()
    assert not a.flags.writeable
    with pytest.raises(ValueError, match="read-only"):
        a[0, 0] = 1.0
    with pytest.raises(ValueError, match="read-only"):
        a += 1.0
    with pytest.raises(ValueError, match="read-only"):
        np.multiply(a, 2.0, out=a)
    with pytest.raises(ValueError, match="read-only"):
        a[1:][0, 0] = 1.0
    with pytest.raises(ValueError):
        a.setflags(write=True)
    with pytest.raises(ValueError):
        a[1:].setflags(write=True)
    assert np.array_equal(a, before) and np.array_equal(getattr(w, part), before)
    # A copy is the user's to write.
    c = a.copy()
    c[0, 0] = 42.0
    assert c.flags.writeable and getattr(w, part)[0, 0] == before[0, 0]


def test_assignment_sets_and_shows_through_a_view() -> None:
    w = spring_world()
    x, v = w.positions, w.velocities
    new_x = np.full((6, 2), 0.25)
    w.positions = new_x
    assert np.array_equal(x, new_x) and np.array_equal(w.positions, new_x)
    w.velocities = np.full((6, 2), -2.0)
    assert v[:5].tolist() == [[-2.0, -2.0]] * 5 and v[5].tolist() == [0.0, 0.0]  # static stays 0
    # A view can be assigned from, itself included.
    w.positions = x + 1.0
    assert np.array_equal(x, new_x + 1.0)
    w.positions = w.positions
    assert np.array_equal(x, new_x + 1.0)
    with pytest.raises(ValueError):
        w.positions = np.zeros((3, 2))
    assert np.array_equal(x, new_x + 1.0)


def test_a_step_updates_a_view_in_place() -> None:
    w = spring_world()
    x, v = w.positions, w.velocities
    x0, v0 = x.copy(), v.copy()
    w.step(3)
    assert not np.array_equal(x, x0) and not np.array_equal(v, v0)
    assert np.array_equal(bits(x), bits(w.positions)) and np.array_equal(bits(v), bits(w.velocities))
    w.advance(0.05)
    assert np.array_equal(bits(x), bits(w.positions)) and address(x) == address(w.positions)


def test_restore_shows_through_a_view() -> None:
    w = spring_world()
    x = w.positions
    snap, x0 = w.snapshot(), x.copy()
    w.step(10)
    assert not np.array_equal(x, x0)
    w.restore(snap)
    assert np.array_equal(bits(x), bits(x0))


def test_a_failed_step_rolls_the_view_back() -> None:
    w = spring_world()
    x = w.positions
    w.positions = np.full((6, 2), 0.999e100)
    w.velocities = np.full((6, 2), 1e100)
    before = x.copy()
    with pytest.raises(physstep.DivergedError):
        w.step()
    assert np.array_equal(bits(x), bits(before))


def _in_place_worlds() -> list[tuple[str, physstep.World]]:
    worlds = []
    for m in METHODS:
        worlds.append((f"{m} particles", spring_world(m)))
        try:
            worlds.append((f"{m} body", body_world(m)))
        except ValueError:
            pass  # a method that refuses bodies
        try:
            worlds.append((f"{m} lorenz", physstep.World.from_scene("lorenz", m, 0.01)))
        except ValueError:
            pass  # a split method refuses flows
    return worlds


def test_every_method_writes_the_viewed_memory_in_place() -> None:
    """What "valid until particles or bodies are added" rests on: nothing else moves it."""
    worlds = _in_place_worlds()
    assert any("body" in n for n, _ in worlds) and any("lorenz" in n for n, _ in worlds)
    for name, w in worlds:
        x, v = w.positions, w.velocities
        at = (address(x), address(v))
        snap = w.snapshot()
        w.step(3)
        w.advance(0.05)
        w.record(0.03)
        w.restore(snap)
        w.set_phase_state(w.phase_state())
        if "lorenz" not in name:  # a flow's positions are not assignable (len(w) == 0)
            w.positions = w.positions
            w.velocities = w.velocities
        w.accelerations  # noqa: B018 (evaluates the derivative)
        w.step()
        assert (address(w.positions), address(w.velocities)) == at, name
        assert np.array_equal(bits(x), bits(w.positions)), name
        assert np.array_equal(bits(v), bits(w.velocities)), name


def test_flow_views() -> None:
    w = physstep.World.from_scene("lorenz", "rk4", 0.01)
    x, v = w.positions, w.velocities
    assert x.shape == (1, 3) and v.shape == (1, 3) and not x.flags.writeable
    w.step(5)
    assert np.array_equal(x, w.positions) and np.array_equal(v, w.velocities)


def test_an_empty_world_has_empty_views() -> None:
    w = physstep.World(3)
    assert w.positions.shape == (0, 3) and w.velocities.shape == (0, 3)
    assert not w.positions.flags.writeable


def _churn(nbytes: int) -> list[np.ndarray]:
    """Allocations of the size of a freed buffer, filled: memory freed under a view would
    be reused and overwritten."""
    return [np.full(nbytes // 8, -7.0) for _ in range(4)]


@pytest.mark.parametrize("how", ["add_particles", "add_particle", "add_body"])
def test_a_view_kept_across_a_reallocation_keeps_its_values(how: str) -> None:
    dim = 3
    w = physstep.World(dim, dt=0.01)
    rng = np.random.default_rng(1)
    w.add_particles(rng.standard_normal((20_000, dim)), velocities=rng.standard_normal((20_000, dim)))
    w.add_gravity([0.0, 0.0, -9.8])
    kept: list[tuple[np.ndarray, np.ndarray]] = []
    for k in range(25):
        x, v = w.positions, w.velocities
        kept.append((x, x.copy()))
        kept.append((v, v.copy()))
        n = len(w)
        if how == "add_particles":
            w.add_particles(rng.standard_normal((1000, dim)))
        elif how == "add_particle":
            for _ in range(10):
                w.add_particle(rng.standard_normal(dim))
        else:
            w.add_body(physstep.Sphere(0.1), mass=1.0, position=[float(k), 0.0, 0.0])
        w.step(2)
        assert len(w) > n or how == "add_body"
        junk = _churn(w.positions.nbytes * 2)
        if k % 5 == 0:
            del x, v
            # Drop a random half of the old views, as a program would.
            for i in sorted(rng.choice(len(kept), len(kept) // 2, replace=False), reverse=True):
                del kept[i]
            gc.collect()
        del junk
        for view, values in kept:
            assert np.array_equal(bits(view), bits(values))
    # A fresh view is the current state, apart from the old ones.
    fresh = w.positions
    assert fresh.shape == (len(w), dim) and not any(np.shares_memory(fresh, a) for a, _ in kept)


def test_adding_forces_or_changing_settings_does_not_detach() -> None:
    w = spring_world()
    x = w.positions
    w.add_spring(1, 2, 5.0)
    w.add_rod(3, 4)
    w.add_drag(0.1)
    w.add_force(lambda t, x, v: -0.1 * v)
    w.method = "rk4"
    w.dt = 0.005
    w.step(3)
    assert np.shares_memory(x, w.positions) and np.array_equal(bits(x), bits(w.positions))


def test_the_base_is_a_state_view() -> None:
    w = spring_world()
    x = w.positions
    assert type(x.base).__name__ == "StateView" and type(x.base).__module__ == "physstep._core"
    assert x[1:].base is x


def test_a_detached_view_is_no_longer_updated() -> None:
    w = spring_world()
    x = w.positions
    w.add_particle([9.0, 9.0])
    w.step()  # the batch is added here: x detaches with the values it had
    assert x.shape == (6, 2) and w.positions.shape == (7, 2)
    assert not np.shares_memory(x, w.positions)
    before = x.copy()
    w.step(5)
    assert np.array_equal(x, before) and not np.array_equal(w.positions[:6], before)


def test_adding_from_a_view_of_the_world_itself() -> None:
    w = spring_world()
    x, v = w.positions, w.velocities
    x0, v0 = x.copy(), v.copy()
    w.add_particles(x, velocities=v)  # reads x, v, then reallocates under them
    assert np.array_equal(w.positions, np.vstack([x0, x0]))
    assert np.array_equal(x, x0) and np.array_equal(v, v0)


def test_a_view_outlives_its_world() -> None:
    w = spring_world()
    w.step(3)
    x, v = w.positions, w.velocities
    x0, v0 = x.copy(), v.copy()
    del w
    gc.collect()
    _churn(x.nbytes * 4)
    assert np.array_equal(bits(x), bits(x0)) and np.array_equal(bits(v), bits(v0))
    tail = x[2:]
    del x
    gc.collect()
    assert np.array_equal(tail, x0[2:])


def test_views_outlive_a_world_across_reallocations() -> None:
    views = []
    for _ in range(20):
        w = spring_world(n=2000)
        views.append((w.positions, w.positions.copy()))
        w.add_particles(np.zeros((10, 2)))
        views.append((w.positions, w.positions.copy()))
        del w
        gc.collect()
        _churn(views[-2][0].nbytes * 2)  # the size of the buffer detached from
        _churn(views[-1][0].nbytes * 2)
    for view, values in views:
        assert np.array_equal(bits(view), bits(values))


@pytest.mark.parametrize("how", ["copy", "deepcopy", "pickle"])
def test_copy_and_pickle_are_not_views(how: str) -> None:
    w = spring_world()
    w.step(4)
    x = w.positions
    other = {
        "copy": copy.copy,
        "deepcopy": copy.deepcopy,
        "pickle": lambda w: pickle.loads(pickle.dumps(w)),
    }[how](w)
    assert np.array_equal(bits(other.positions), bits(x))
    assert not np.shares_memory(other.positions, x)
    before = x.copy()
    other.step(10)
    assert np.array_equal(x, before)
    w.step(10)
    assert other.state_hash() == w.state_hash()
    assert np.array_equal(bits(x), bits(other.positions))


def test_a_view_read_while_another_thread_steps() -> None:
    """Allowed and memory-safe; the values are those of some moment of the steps (see
    docs/views.md), and after the steps, the last state."""
    w = spring_world(n=5000)
    x = w.positions
    errors: list[BaseException] = []

    def stepper() -> None:
        try:
            w.step(300)
        except BaseException as e:  # pragma: no cover - reported below
            errors.append(e)

    t = threading.Thread(target=stepper)
    t.start()
    sums = []
    while t.is_alive():
        sums.append(float(x.sum()))
    t.join()
    assert not errors and all(np.isfinite(sums))
    assert w.steps == 300 and np.array_equal(bits(x), bits(w.positions))
