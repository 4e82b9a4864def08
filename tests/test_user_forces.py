"""Forces written in Python (issue 8): one call per evaluation, the built-in physics to
rounding, exceptions propagated with the step rolled back, unknown energy said so."""

from __future__ import annotations

import numpy as np
import physstep
import pytest

K, C, M = 5.0, 0.5, 10.0


def _spring(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
    return -K * x - C * v


def _potential(x: np.ndarray) -> float:
    return 0.5 * K * float((x**2).sum())


def _jacobian(t: float, x: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    n = x.size
    return -K * np.eye(n), -C * np.eye(n)


def _pair(method: str) -> tuple[physstep.World, physstep.World]:
    built = physstep.World(2, method=method, dt=0.1)
    built.add_particle([20.0, -3.0], velocity=[0.0, 1.0], mass=M)
    built.add_spring(0, [0.0, 0.0], K, rest_length=0.0, damping=C)
    user = physstep.World(2, method=method, dt=0.1)
    user.add_particle([20.0, -3.0], velocity=[0.0, 1.0], mass=M)
    user.add_force(_spring, potential=_potential, jacobian=_jacobian)
    return built, user


@pytest.mark.parametrize("method", [m.name for m in physstep.methods()])
def test_a_python_spring_gives_the_built_in_trajectory_and_energy(method: str) -> None:
    built, user = _pair(method)
    for _ in range(20):
        built.step(10)
        user.step(10)
        assert np.abs(built.positions - user.positions).max() <= 1e-12 * 20
        assert np.abs(built.velocities - user.velocities).max() <= 1e-12 * 20
        assert user.energy() == pytest.approx(built.energy(), rel=1e-12)


def test_the_force_is_called_once_per_evaluation_with_all_particles() -> None:
    calls: list[tuple[int, ...]] = []

    def gravity(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        calls.append(x.shape)
        return np.tile([0.0, -9.81], (len(x), 1))

    w = physstep.World(2, method="rk4", dt=0.01)
    w.add_particles(np.random.default_rng(1).random((100, 2)))
    w.add_force(gravity, velocity_dependent=False)
    w.step(5)
    assert len(calls) == w.evals == 1 + 5 * 4  # the initial evaluation, then 4 per RK4 step
    assert set(calls) == {(100, 2)}


def test_an_exception_propagates_unchanged_and_the_step_is_rolled_back() -> None:
    w = physstep.World(1, method="leapfrog", dt=0.1)
    w.add_particle([1.0])
    w.add_force(lambda t, x, v: -x, potential=lambda x: 0.5 * float((x**2).sum()))
    w.step(4)
    h, steps = w.state_hash(), w.steps
    armed = {"on": False}

    class Boom(Exception):
        pass

    def sometimes(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        if armed["on"]:
            raise Boom("from the user's force")
        return np.zeros_like(x)

    w.add_force(sometimes)
    w.step(1)
    h, steps = w.state_hash(), w.steps
    armed["on"] = True
    with pytest.raises(Boom, match="from the user's force"):
        w.step(3)
    assert (w.state_hash(), w.steps) == (h, steps)
    armed["on"] = False
    w.step(1)
    assert w.steps == steps + 1


@pytest.mark.parametrize(
    ("returned", "needle"),
    [
        (lambda x: np.zeros((len(x) + 1, 2)), "must have shape (3, 2), not (4, 2)"),
        (lambda x: np.full_like(x, np.nan), "force[0][0] = NaN is not finite"),
        (lambda x: "abc", "must be an array of numbers of shape (3, 2)"),
    ],
)
def test_a_wrong_shape_or_a_non_finite_force_is_a_value_error_naming_the_force(returned, needle) -> None:
    w = physstep.World(2)
    w.add_particles(np.zeros((3, 2)))
    w.add_force(lambda t, x, v: returned(x), name="wind")
    with pytest.raises(ValueError, match="force 'wind' failed") as info:
        w.step()
    assert needle in str(info.value)
    assert w.steps == 0


def test_without_a_potential_the_energy_is_unknown() -> None:
    w = physstep.World(1)
    w.add_particle([1.0])
    w.add_force(lambda t, x, v: -x)
    assert w.energy() is None
    with pytest.raises(ValueError, match="invalid func = 3: must be callable"):
        w.add_force(3)


# --- the arrays a Python force is handed (issue 22, item 6) ----------------------------------


def test_an_inplace_force_writes_out_and_gives_the_returned_forces_trajectory_bitwise() -> None:
    def into(t: float, x: np.ndarray, v: np.ndarray, out: np.ndarray) -> None:
        assert not out.any(), "out is zeroed before each call"
        np.multiply(x, -K, out=out)
        out -= C * v

    worlds = []
    for force, inplace in ((_spring, False), (into, True)):
        w = physstep.World(2, method="rk4", dt=0.1)
        w.add_particles([[20.0, -3.0], [1.0, 2.0]], velocities=[[0.0, 1.0], [3.0, 0.0]], masses=[M, 2.0])
        w.add_force(force, inplace=inplace)
        w.step(50)
        worlds.append(w)
    assert worlds[0].state_hash() == worlds[1].state_hash()


def test_an_inplace_force_may_still_return_an_array() -> None:
    w = physstep.World(1, dt=0.1)
    w.add_particle([1.0])
    w.add_force(lambda t, x, v, out: -x, inplace=True)
    w.step(3)
    ref = physstep.World(1, dt=0.1)
    ref.add_particle([1.0])
    ref.add_spring(0, [0.0], 1.0, rest_length=0.0)
    ref.step(3)
    assert w.state_hash() == ref.state_hash()


def test_x_and_v_are_read_only_reused_and_a_kept_array_keeps_its_values() -> None:
    seen: list[tuple[int, int]] = []
    kept: list[tuple[np.ndarray, np.ndarray, float]] = []

    def force(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        assert not x.flags.writeable and not v.flags.writeable
        with pytest.raises(ValueError, match="read-only"):
            x[0, 0] = 1.0
        seen.append((id(x), id(v)))
        if len(seen) == 3:
            kept.append((x, v[:, :1], float(x[0, 0])))  # the array itself, and a view of v
        return -x

    w = physstep.World(2, method="symplectic-euler", dt=0.1)
    w.add_particles([[1.0, 0.0], [0.0, 2.0]])
    w.add_force(force)
    w.step(6)
    # The same arrays call after call, until one was kept; then new ones, also reused.
    assert seen[0] == seen[1] == seen[2]
    assert seen[3] != seen[2] and seen[3] == seen[4] == seen[5]
    x, v_col, x00 = kept[0]
    assert float(x[0, 0]) == x00 and v_col.shape == (2, 1)
    assert float(w.positions[0, 0]) != x00  # the world moved on; the kept copy did not


def test_an_inplace_force_with_a_wrong_return_or_exception_fails_as_before() -> None:
    w = physstep.World(2)
    w.add_particles(np.zeros((3, 2)))
    w.add_force(lambda t, x, v, out: np.zeros((4, 2)), name="wind", inplace=True)
    with pytest.raises(ValueError, match=r"force 'wind' failed.*must have shape \(3, 2\), not \(4, 2\)"):
        w.step()

    class Boom(Exception):
        pass

    def boom(t: float, x: np.ndarray, v: np.ndarray, out: np.ndarray) -> None:
        raise Boom("inside")

    w = physstep.World(2)
    w.add_particles(np.zeros((3, 2)))
    w.add_force(boom, inplace=True)
    with pytest.raises(Boom, match="inside"):
        w.step()
    assert w.steps == 0
    with pytest.raises(ValueError, match="invalid inplace"):
        w.add_force(boom, inplace="yes")


def test_an_array_reshaped_in_place_by_the_force_is_replaced_not_refilled() -> None:
    shapes: list[tuple[int, ...]] = []

    def force(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        shapes.append(x.shape)
        f = -np.array(x)
        x.shape = (x.size,)  # in place, on the force's own array
        return f

    w = physstep.World(2, dt=0.1)
    w.add_particles([[1.0, 0.0], [0.0, 2.0]])
    w.add_force(force)
    w.step(3)
    assert shapes == [(2, 2)] * 4
