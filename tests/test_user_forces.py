"""Forces written in Python (issue 8): one call per evaluation, the built-in physics to
rounding, exceptions propagated with the step rolled back, unknown energy said so."""

from __future__ import annotations

import warnings

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


@pytest.mark.parametrize("method", ["symplectic-euler", "explicit-euler"])
@pytest.mark.parametrize("inplace", [False, True])
def test_accelerations_that_run_away_fail_the_step_without_calling_the_force_again(
    method: str, inplace: bool
) -> None:
    """A force whose result is finite but past the runaway limit (1e100) fails the step it
    was evaluated in, rolled back, named, and the force is not called again for that step."""
    calls = {"n": 0}

    def force(t: float, x: np.ndarray, v: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        calls["n"] += 1
        f = -x
        if calls["n"] == 3:
            f[4, 1] = 1e150
        if out is None:
            return f
        out[:] = f
        return out

    w = physstep.World(2, method=method, dt=0.01)
    w.add_particles(np.linspace(0.5, 1.5, 18).reshape(9, 2))
    w.add_force(force, inplace=inplace)
    with pytest.raises(physstep.DivergedError, match=f"{method}.*diverged.*particle 4") as info:
        w.step(10)
    assert calls["n"] == 3, str(info.value)
    assert calls["n"] == w.evals
    h = w.state_hash()
    ok = physstep.World(2, method=method, dt=0.01)
    ok.add_particles(np.linspace(0.5, 1.5, 18).reshape(9, 2))
    ok.add_force(lambda t, x, v: -x)
    ok.step(w.steps)
    assert ok.state_hash() == h, "rolled back to the last good step"


def test_velocity_verlet_evaluates_a_force_that_ignores_v_once_a_step_with_the_same_bits() -> None:
    """Declared velocity-independent, a force is evaluated once a step by velocity Verlet (the
    step taken from the stored derivative); by default three times (the closing kick is solved at
    the new velocity, a fixed-point pass). A force that ignores v gives the same trajectory, bit
    for bit."""
    worlds, calls = [], []
    for declared in (False, True):
        n = [0]

        def pull(t: float, x: np.ndarray, v: np.ndarray, out: np.ndarray, n: list[int] = n) -> None:
            n[0] += 1
            np.multiply(x, -3.0, out=out)
            out[:, 1] += np.cos(t)

        w = physstep.World(2, method="velocity-verlet", dt=0.01)
        w.add_particles(np.random.default_rng(4).random((70_000, 2)), velocities=np.zeros((70_000, 2)))
        w.add_force(pull, inplace=True, velocity_dependent=declared)
        w.step(7)
        worlds.append(w)
        calls.append(n[0])
    assert calls == [1 + 7, 1 + 3 * 7]
    assert worlds[0].state_hash() == worlds[1].state_hash()


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
        (lambda x: "abc", "must be an array of real numbers of shape (3, 2), not 'abc' (str)"),
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


@pytest.mark.parametrize("method", ["symplectic-euler", "velocity-verlet", "rk4"])
def test_x_and_v_are_read_only_reused_views_of_the_state_where_a_method_evaluates_there(method: str) -> None:
    seen: list[tuple[int, int, type, type]] = []

    def force(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        assert not x.flags.writeable and not v.flags.writeable
        with pytest.raises(ValueError, match="read-only"):
            x[0, 0] = 1.0
        if type(x.base).__name__ == "StateView":  # a view of the World's state stays read-only
            with pytest.raises(ValueError, match="WRITEABLE"):
                x.flags.writeable = True
        seen.append((id(x), id(v), type(x.base), type(v.base)))
        return -x

    w = physstep.World(2, method=method, dt=0.1)
    w.add_particles([[1.0, 0.0], [0.0, 2.0]])
    w.add_force(force)
    w.step(4)
    ref = physstep.World(2, method=method, dt=0.1)
    ref.add_particles([[1.0, 0.0], [0.0, 2.0]])
    ref.add_spring(0, [0.0, 0.0], 1.0, rest_length=0.0)
    ref.add_spring(1, [0.0, 0.0], 1.0, rest_length=0.0)
    ref.step(4)
    assert w.state_hash() == ref.state_hash()
    # Views of the World's own state (no copy) where the method evaluates at the state: every
    # evaluation of symplectic Euler and velocity Verlet, RK4's first of four; RK4's stages
    # are copies, in arrays the force also reuses. Either way, the same arrays call after call.
    views = {(id_x, tx) for id_x, _, tx, _ in seen if tx is not type(None)}
    assert len(views) == 1 and next(iter(views))[1].__name__ == "StateView"
    assert len({s[0] for s in seen}) == (2 if method == "rk4" else 1)
    assert len({s[1] for s in seen}) == (2 if method == "rk4" else 1)


@pytest.mark.parametrize("method", ["symplectic-euler", "rk4"])
@pytest.mark.parametrize("what", ["x", "v[:, :1]", "memoryview(x)"])
def test_a_force_that_keeps_x_or_v_past_its_call_is_warned_once(method: str, what: str) -> None:
    kept: list[object] = []
    keep = {"on": False}

    def force(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        if keep["on"]:
            kept.append(eval(what, {"x": x, "v": v}))
        return -x

    w = physstep.World(2, method=method, dt=0.1)
    w.add_particles([[1.0, 0.0], [0.0, 2.0]])
    w.add_force(force, name="keeper")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        w.step(1)
    keep["on"] = True
    name = "v" if what.startswith("v") else "x"
    message = (
        rf"physstep: force 'keeper' kept its argument {name} \(or a view of it\) after returning: x and v"
        rf" are valid during the call only .*; keep a copy \({name}\.copy\(\)\)"
    )
    with pytest.warns(RuntimeWarning, match=message):
        w.step(3)
    assert w.steps == 4
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        w.step(3)  # once per force
    # Turned into an error, the warning fails the step (rolled back).
    w = physstep.World(2, method=method, dt=0.1)
    w.add_particles([[1.0, 0.0], [0.0, 2.0]])
    w.add_force(force, name="keeper")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(RuntimeWarning, match=message):
            w.step(2)
    assert w.steps == 0


def test_a_kept_view_is_live_and_stays_readable_after_the_world_grows() -> None:
    kept: list[np.ndarray] = []

    def force(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        if not kept:
            kept.append(x)
        return -x

    w = physstep.World(2, dt=0.1)
    w.add_particles([[1.0, 0.0], [0.0, 2.0]])
    w.add_force(force)
    with pytest.warns(RuntimeWarning, match="kept its argument x"):
        w.step(3)
    # A view of the World's positions, as World.positions is: it moved on with the World.
    np.testing.assert_array_equal(kept[0], w.positions)
    before = kept[0].copy()
    w.add_particles(np.ones((1000, 2)))  # reallocates the state: the view keeps the old memory
    w.step()
    np.testing.assert_array_equal(kept[0], before)


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


# --- jacobians, potentials and return types (issue 25, items 7-9) ----------------------------


class _Boom(Exception):
    pass


def _implicit_world(method: str, jacobian) -> physstep.World:
    w = physstep.World(2, method=method, dt=0.1)
    w.add_particles([[1.0, 0.0], [0.0, 2.0]])
    w.add_force(_spring, jacobian=jacobian, name="spring")
    return w


@pytest.mark.parametrize("method", ["backward-euler", "implicit-midpoint"])
def test_an_exception_in_a_jacobian_propagates_unchanged_and_the_step_is_rolled_back(method: str) -> None:
    armed = {"on": False}

    def jacobian(t: float, x: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        if armed["on"]:
            raise _Boom("from the user's jacobian")
        return _jacobian(t, x, v)

    w = _implicit_world(method, jacobian)
    w.step(2)
    h, steps = w.state_hash(), w.steps
    armed["on"] = True
    with pytest.raises(_Boom, match="from the user's jacobian"):
        w.step(3)
    assert (w.state_hash(), w.steps) == (h, steps)
    with pytest.raises(_Boom):
        physstep.simulate(lambda: _implicit_world(method, jacobian), until=0.5)
    armed["on"] = False
    w.step(1)
    assert w.steps == steps + 1


def test_an_exception_in_a_flows_jacobian_propagates_unchanged() -> None:
    def jac(t: float, y: np.ndarray) -> np.ndarray:
        raise _Boom("flow jacobian")

    w = physstep.World.from_flow(lambda t, y: -y, [1.0, 2.0], method="backward-euler", dt=0.1, jacobian=jac)
    with pytest.raises(_Boom, match="flow jacobian"):
        w.step()
    assert w.steps == 0


@pytest.mark.parametrize(
    ("returned", "needle"),
    [
        (
            lambda n: (np.eye(n + 1), np.eye(n + 1)),
            "its jacobian returned dF/dx must have shape (4, 4), not (5, 5)",
        ),
        (
            lambda n: (np.full((n, n), np.nan), np.zeros((n, n))),
            "its jacobian returned dF/dx[0][0] = NaN: must be finite",
        ),
        (lambda n: (np.zeros((n, n)), np.full((n, n), np.inf)), "dF/dv[0][0] = inf: must be finite"),
        (
            lambda n: np.eye(n),
            "its jacobian must return a pair (dF/dx, dF/dv), not an array of float64 of shape (4, 4)",
        ),
        (lambda n: ("a", None), "dF/dx must be an array of real numbers of shape (4, 4), not 'a' (str)"),
        (lambda n: (np.eye(n) * 1j, np.zeros((n, n))), "not an array of complex128 of shape (4, 4)"),
    ],
)
def test_a_jacobian_of_the_wrong_shape_or_not_finite_is_a_value_error_naming_it(
    returned, needle: str
) -> None:
    w = _implicit_world("backward-euler", lambda t, x, v: returned(x.size))
    with pytest.raises(ValueError, match="force 'spring' failed: its jacobian") as info:
        w.step()
    assert needle in str(info.value)
    assert w.steps == 0 and w.time == 0.0


def test_a_flows_bad_jacobian_is_a_value_error_naming_it() -> None:
    w = physstep.World.from_flow(
        lambda t, y: -y,
        [1.0, 2.0],
        method="backward-euler",
        dt=0.1,
        jacobian=lambda t, y: np.eye(3),
        name="decay",
    )
    with pytest.raises(
        ValueError, match=r"force 'decay' failed: its jacobian returned the Jacobian \(2 x 2\)"
    ):
        w.step()
    assert w.steps == 0


@pytest.mark.parametrize(
    ("potential", "got"),
    [
        (lambda x: float("nan"), "= NaN"),
        (lambda x: "abc", "= 'abc' (str)"),
        (lambda x: np.array([1.0, 2.0]), "= an array of float64 of shape (2,)"),
        (lambda x: 1 + 2j, "= (1+2j) (complex)"),
        (lambda x: True, "= True (bool)"),
    ],
)
def test_a_potential_that_returns_no_real_number_is_a_value_error_naming_it(potential, got: str) -> None:
    def well() -> physstep.World:
        w = physstep.World(1)
        w.add_particle([1.0])
        w.add_force(lambda t, x, v: -x, potential=potential, name="well")
        return w

    w = well()
    with pytest.raises(ValueError, match=r"invalid potential of force 'well' ") as info:
        w.energy()
    assert got in str(info.value) and "must be a finite real number" in str(info.value)
    with pytest.raises(ValueError, match="potential of force 'well'"):
        w.energy()  # again: said each time it is asked
    w.step(3)  # stepping needs no potential
    with pytest.raises(ValueError, match="potential of force 'well'"):
        physstep.simulate(well, until=0.05)


def test_a_potential_as_a_numpy_scalar_or_0d_array_or_int_is_read() -> None:
    for potential in (lambda x: np.float64(2.5), lambda x: np.array(2.5), lambda x: 2, lambda x: np.int32(2)):
        w = physstep.World(1)
        w.add_particle([1.0])
        w.add_force(lambda t, x, v: -x, potential=potential)
        assert w.energy() == pytest.approx(float(potential(None)))


@pytest.mark.parametrize(
    ("returned", "needle"),
    [
        (lambda x: -x + 0.5j, "not an array of complex128 of shape (3, 2)"),
        (lambda x: x > 0, "not an array of bool of shape (3, 2)"),
        (lambda x: np.array([["1", "2"]] * 3), "not an array of <U1 of shape (3, 2)"),
    ],
)
def test_a_complex_or_boolean_force_is_refused_not_cast(returned, needle: str) -> None:
    w = physstep.World(2)
    w.add_particles(np.ones((3, 2)))
    w.add_force(lambda t, x, v: returned(x), name="wind")
    with pytest.raises(
        ValueError, match="force 'wind' failed: the returned force must be an array of real"
    ) as info:
        w.step()
    assert needle in str(info.value)
    assert w.steps == 0
    # integers are real numbers: accepted
    w2 = physstep.World(2)
    w2.add_particles(np.ones((3, 2)))
    w2.add_force(lambda t, x, v: np.ones(x.shape, dtype=np.int64))
    w2.step()


def test_a_flow_returning_complex_numbers_is_refused_not_cast() -> None:
    w = physstep.World.from_flow(lambda t, y: -y * 1j, [1.0, 2.0], method="rk4", dt=0.1, name="rot")
    with pytest.raises(
        ValueError, match="force 'rot' failed: the returned derivative must be an array of 2 real"
    ):
        w.step()
    assert w.steps == 0


@pytest.mark.parametrize("what", ["force", "potential", "jacobian"])
def test_a_callback_that_uses_its_own_world_is_told_so(what: str) -> None:
    w = physstep.World(1, method="backward-euler", dt=0.1)
    w.add_particle([1.0])
    seen: list[BaseException] = []

    def peek() -> None:
        try:
            w.positions  # noqa: B018
        except physstep.WorldBusyError as e:
            seen.append(str(e))  # (not e: its traceback would keep the force's x alive)

    def force(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        if what == "force":
            peek()
        return -x

    def potential(x: np.ndarray) -> float:
        if what == "potential":
            peek()
        return 0.5 * float((x**2).sum())

    def jacobian(t: float, x: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        if what == "jacobian":
            peek()
        return -np.eye(x.size), np.zeros((x.size, x.size))

    w.add_force(force, potential=potential, jacobian=jacobian)
    w.step(2)
    w.energy()
    assert seen, "the callback never ran"
    message = str(seen[0])
    assert "in use by another thread" not in message
    assert message.startswith("this World is in use by the call that ran this callback (its own force")
    assert "read the t, x and v it is handed" in message
    # after the step the World answers, from the same thread
    assert w.positions.shape == (1, 1) and w.steps == 2
