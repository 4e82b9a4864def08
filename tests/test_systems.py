"""The user's own systems (issue 8): flows, and callables returning a World or a Flow,
wherever a scene name is taken."""

from __future__ import annotations

import numpy as np
import physstep
import pytest


def test_lorenz_under_rk4_converges() -> None:
    a = physstep.simulate("lorenz", "rk4", dt=1e-3, until=5.0, every=100)
    b = physstep.simulate("lorenz", "rk4", dt=5e-4, until=5.0, every=200)
    assert a.kind == b.kind == "flow" and a.energy is None
    np.testing.assert_allclose(a.t, b.t, rtol=0, atol=1e-12)
    assert np.abs(a.x - b.x).max() < 1e-6


def _lorenz(t: float, y: np.ndarray) -> np.ndarray:
    return np.array([10.0 * (y[1] - y[0]), y[0] * (28.0 - y[2]) - y[1], y[0] * y[1] - 8.0 / 3.0 * y[2]])


def test_a_python_flow_gives_the_built_in_attractor() -> None:
    flow = physstep.Flow(_lorenz, [1.0, 1.0, 1.0], name="my-lorenz")
    mine = physstep.simulate(flow, "rk4", dt=1e-3, until=2.0)
    built = physstep.simulate("lorenz", "rk4", dt=1e-3, until=2.0)
    assert mine.scene == "my-lorenz"
    assert np.abs(mine.x - built.x).max() < 1e-9


def test_split_methods_refuse_a_flow_in_one_line() -> None:
    with pytest.raises(ValueError, match=r"^method 'velocity-verlet' needs a second-order system"):
        physstep.simulate(physstep.Flow(_lorenz, [1.0, 1.0, 1.0]), "velocity-verlet", dt=0.01, until=1.0)


def test_an_exception_in_a_flow_propagates_unchanged() -> None:
    def bad(t: float, y: np.ndarray) -> np.ndarray:
        if t > 0.25:
            raise ArithmeticError("the model broke")
        return -y

    with pytest.raises(ArithmeticError, match="the model broke"):
        physstep.simulate(physstep.Flow(bad, [1.0]), "rk4", dt=0.1, until=1.0)


def _duffing() -> physstep.World:
    w = physstep.World(1, method="velocity-verlet", dt=0.01)
    w.add_particle([1.0])
    w.add_force(
        lambda t, x, v: -x - x**3,
        potential=lambda x: float((x**2 / 2 + x**4 / 4).sum()),
        velocity_dependent=False,
    )
    return w


def test_a_callable_system_runs_with_its_own_forces() -> None:
    traj = physstep.simulate(_duffing, "rk4", dt=0.005, until=10.0)
    assert traj.scene == "_duffing" and traj.method == "rk4" and traj.steps == 2000
    assert np.abs(traj.energy_error).max() < 1e-8

    # Without a potential the energy is unknown, and said so.
    def no_potential() -> physstep.World:
        w = physstep.World(1)
        w.add_particle([1.0])
        w.add_force(lambda t, x, v: -x)
        return w

    traj = physstep.simulate(no_potential, until=1.0)
    assert traj.energy is None and traj.energy_error is None
    assert physstep.summarize(traj)["energy"] is None


@pytest.mark.parametrize(
    ("system", "kwargs", "needle"),
    [
        (lambda: 3, {"until": 1.0}, "must be a Flow or a callable returning a fresh World or Flow"),
        (_duffing, {}, "invalid until = None"),
        (_duffing, {"until": 1.0, "params": {"k": 1.0}}, "a system has no scene parameters"),
    ],
)
def test_bad_systems_are_named(system, kwargs, needle: str) -> None:
    with pytest.raises(ValueError, match=needle):
        physstep.simulate(system, **kwargs)


def test_the_readme_example_of_your_own_forces_and_systems_runs() -> None:
    from pathlib import Path

    text = (Path(__file__).parent.parent / "README.md").read_text()
    start = text.index("```python", text.index("### Your own forces and systems")) + len("```python")
    code = text[start : text.index("```", start)]
    scope: dict[str, object] = {}
    exec(compile(code, "README.md", "exec"), scope)  # noqa: S102 - the README's own example
    traj = scope["traj"]
    assert isinstance(traj, physstep.Trajectory) and traj.steps == 2000
