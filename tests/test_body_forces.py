"""Python forces at body points and per-body angular drag."""

from __future__ import annotations

import math
import pickle

import numpy as np
import physstep
import pytest

ANCHOR = np.array([1.0, 0.5, 0.0])
POINT = (0.3, 0.2, 0.1)
K = 8.0


def tether(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
    """A zero-rest spring from the body point to ANCHOR."""
    return K * (ANCHOR - x)


def tether_energy(x: np.ndarray) -> float:
    """Its potential."""
    return 0.5 * K * float(np.sum((x - ANCHOR) ** 2))


def _world(with_force: bool) -> physstep.World:
    w = physstep.World(3, method="velocity-verlet", dt=0.01)
    w.add_body(physstep.Box(0.3, 0.2, 0.1), mass=1.5, angular_velocity=(0.2, 0.0, 0.5))
    if with_force:
        w.add_body_force(0, tether, point=POINT, potential=tether_energy, velocity_dependent=False)
    else:
        w.add_body_spring(0, POINT, ANCHOR, K, rest_length=0.0)
    return w


def test_a_python_force_at_a_body_point_matches_the_built_in_spring() -> None:
    a, b = _world(False), _world(True)
    assert b.energy() == pytest.approx(a.energy(), abs=1e-12)
    a.step(300)
    b.step(300)
    np.testing.assert_allclose(b.body_positions(), a.body_positions(), atol=1e-12)
    np.testing.assert_allclose(b.body_angular_momenta(), a.body_angular_momenta(), atol=1e-12)
    assert b.energy() == pytest.approx(a.energy(), abs=1e-12)


def test_a_body_force_without_potential_makes_the_energy_unknown_and_its_errors_propagate() -> None:
    w = physstep.World(3, method="rk4", dt=0.01)
    w.add_body(physstep.Sphere(0.5), mass=1.0)
    w.add_body_force(0, tether)
    assert w.energy() is None

    def broken(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        raise ZeroDivisionError("my own bug")

    w.add_body_force(0, broken)
    with pytest.raises(ZeroDivisionError, match="my own bug"):
        w.step(1)
    assert w.time == 0.0


@pytest.mark.parametrize(
    "kwargs, field",
    [({"body": 3}, "body"), ({"func": 1.0}, "func"), ({"point": (0.0, math.nan, 0.0)}, "point")],
)
def test_bad_body_forces_name_the_field(kwargs: dict, field: str) -> None:
    w = physstep.World(3, dt=0.01)
    w.add_body(physstep.Sphere(0.5), mass=1.0)
    args = {"body": 0, "func": tether} | kwargs
    body, func = args.pop("body"), args.pop("func")
    with pytest.raises(ValueError, match=field):
        w.add_body_force(body, func, **args)


def test_a_world_with_a_body_force_pickles_and_continues_bitwise() -> None:
    w = _world(True)
    w.step(20)
    twin = pickle.loads(pickle.dumps(w))
    w.step(100)
    twin.step(100)
    assert twin.state_hash() == w.state_hash()


def test_angular_drag_slows_a_sphere_exponentially() -> None:
    m, r, c = 2.0, 0.5, 0.3
    inertia = 0.4 * m * r * r
    w = physstep.World(3, method="rk4", dt=0.01)
    w.add_body(physstep.Sphere(r), mass=m, angular_velocity=(1.0, -2.0, 0.5), angular_drag=c)
    w.step(300)
    expected = np.array([1.0, -2.0, 0.5]) * math.exp(-c * w.time / inertia)
    np.testing.assert_allclose(w.body_angular_velocities()[0], expected, atol=1e-9)
    with pytest.raises(ValueError, match="angular_drag"):
        w.add_body(physstep.Sphere(r), angular_drag=-1.0)
