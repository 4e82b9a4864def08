"""Forces on solids: drag, springs at points, loads by hand and forces from Python callables
(docs/contact.md, "Forces on solids")."""

import math
import pickle

import numpy as np
import physstep
import pytest

G = 9.81
DT = 1 / 60


def world(dim: int, g: float = G) -> physstep.World:
    w = physstep.World(dim=dim, dt=DT)
    if g:
        w.add_gravity([0.0, -g] + [0.0] * (dim - 2))
    return w


def ball_mass(dim: int, r: float = 0.5, rho: float = 1.0) -> float:
    return rho * (math.pi * r * r if dim == 2 else 4 / 3 * math.pi * r**3)


@pytest.mark.parametrize("dim", [2, 3])
def test_drag_decays_speed_and_spin_as_exp_minus_c_t(dim: int) -> None:
    w = world(dim, 0.0)
    spin = 3.0 if dim == 2 else [0.0, 0.0, 3.0]
    v0 = [2.0] + [0.0] * (dim - 1)
    w.add_solid(physstep.Circle(0.5), velocity=v0, angular_velocity=spin, linear_damping=0.5, angular_damping=0.3)
    w.step(120)
    t = 120 * DT
    assert w.solid_velocities()[0, 0] == pytest.approx(2.0 * math.exp(-0.5 * t), rel=0.01)
    om = w.solid_angular_velocities()
    om = om[0] if dim == 2 else om[0, 2]
    assert om == pytest.approx(3.0 * math.exp(-0.3 * t), rel=0.01)


@pytest.mark.parametrize(("key", "value"), [("linear_damping", -1.0), ("angular_damping", math.nan)])
def test_bad_drag_names_the_field_and_the_world_is_unchanged(key: str, value: float) -> None:
    w = world(2)
    w.add_solid(physstep.Circle(0.5))
    with pytest.raises(ValueError, match=key) as e:
        w.add_solid(physstep.Circle(0.5), position=[3.0, 0.0], **{key: value})
    assert len(str(e.value).splitlines()) == 1
    assert w.solid_count == 1


def hanging(dim: int, k: float) -> tuple[physstep.World, float]:
    """A ball on a spring from y = 1, let go 0.2 m below where it rests; and its mass."""
    w = world(dim)
    m = ball_mass(dim)
    y = 1.0 - 2.0 - m * G / k - 0.2
    w.add_solid(physstep.Circle(0.5), position=[0.0, y] + [0.0] * (dim - 2))
    top = [0.0, 1.0] + [0.0] * (dim - 2)
    assert w.add_solid_spring(0, [0.0] * dim, point_b=top, stiffness=k, rest_length=2.0) == 0
    return w, m


@pytest.mark.parametrize("dim", [2, 3])
def test_a_sprung_solid_keeps_its_energy_and_oscillates_at_sqrt_k_over_m(dim: int) -> None:
    k = 40.0
    w, m = hanging(dim, k)
    e0 = w.solid_energy()
    assert w.energy() == pytest.approx(e0, rel=1e-15)
    worst, vy, crossings = 0.0, [], []
    last = w.solid_velocities()[0, 1]
    for step in range(1, 10_001):
        w.step(1)
        worst = max(worst, abs(w.solid_energy() - e0))
        v = w.solid_velocities()[0, 1]
        if (last < 0) != (v < 0) and step > 1:
            crossings.append((step - 1 + last / (last - v)) * DT)
        last = v
        vy.append(v)
    omega = math.pi * (len(crossings) - 1) / (crossings[-1] - crossings[0])
    assert omega == pytest.approx(math.sqrt(k / m), rel=0.01)
    # Symplectic Euler in 8 substeps: the energy swings by about h omega / 2 of the
    # oscillation's 0.5 k 0.2^2 and does not drift; bound h omega of it.
    h = DT / 8
    assert worst < h * math.sqrt(k / m) * 0.5 * k * 0.2**2


@pytest.mark.parametrize("dim", [2, 3])
def test_two_solids_on_a_spring_keep_their_momentum(dim: int) -> None:
    w = world(dim, 0.0)
    w.add_solid(physstep.Circle(0.5), velocity=[0.0, 0.3] + [0.0] * (dim - 2))
    w.add_solid(physstep.Circle(0.5), position=[2.0] + [0.0] * (dim - 1), density=3.0, velocity=[-0.7] + [0.0] * (dim - 1))
    w.add_solid_spring(0, [0.0, 0.3] + [0.0] * (dim - 2), 1, [-0.2, 0.1] + [0.0] * (dim - 2), stiffness=50.0, rest_length=1.0)
    masses = np.array([ball_mass(dim), ball_mass(dim, rho=3.0)])
    p0 = masses @ w.solid_velocities()
    e0 = w.solid_energy()
    w.step(600)
    assert np.allclose(masses @ w.solid_velocities(), p0, rtol=0, atol=1e-12)
    assert np.any(w.solid_angular_velocities() != 0.0), "the spring off their centres turns them"
    assert w.solid_energy() == pytest.approx(e0, rel=0.02)


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"a": 5}, "a"),
        ({"b": 0}, "b"),
        ({"b": 9}, "b"),
        ({"stiffness": -1.0}, "stiffness"),
        ({"damping": -0.5}, "damping"),
        ({"rest_length": -2.0}, "rest_length"),
        ({"rest_length": math.inf}, "rest_length"),
        ({"point_a": [0.0, 0.0, 0.0]}, "point_a"),
        ({"point_b": [0.0, math.nan]}, "point_b"),
        ({"stiffness": "stiff"}, "stiffness"),
    ],
)
def test_bad_springs_name_the_field_and_the_world_is_unchanged(kwargs: dict, field: str) -> None:
    w = world(2)
    w.add_solid(physstep.Circle(0.5))
    w.add_solid(physstep.Circle(0.5), position=[2.0, 0.0])
    h = w.state_hash()
    args = {"a": 0, "point_a": [0.0, 0.0], "b": 1, "point_b": [0.0, 0.0], "stiffness": 10.0} | kwargs
    with pytest.raises(ValueError, match=field) as e:
        w.add_solid_spring(**args)
    assert len(str(e.value).splitlines()) == 1
    assert w.solid_spring_count == 0
    assert w.state_hash() == h


def sprung_world(dim: int) -> physstep.World:
    w = world(dim)
    w.add_solid(physstep.Box(*[5.0] * dim), position=[0.0, -10.0] + [0.0] * (dim - 2), kind="static")
    w.add_solid(physstep.Box(*[0.3] * dim), linear_damping=0.25, angular_damping=0.125)
    w.add_solid(physstep.Circle(0.4), position=[1.5] + [0.0] * (dim - 1))
    w.add_solid_spring(1, [0.3, 0.3] + [0.0] * (dim - 2), 2, [0.0] * dim, stiffness=20.0, damping=0.75)
    w.add_solid_spring(1, [0.0] * dim, point_b=[0.0, 3.0] + [0.0] * (dim - 2), stiffness=35.0)
    return w


@pytest.mark.parametrize("dim", [2, 3])
def test_drag_and_springs_survive_pickles_snapshots_and_scene_files_bitwise(dim: int, tmp_path) -> None:
    w = sprung_world(dim)
    w.step(30)
    copy = pickle.loads(pickle.dumps(w))
    assert copy.state_hash() == w.state_hash()
    assert copy.solid_spring_count == 2
    snap = w.snapshot()
    w.step(50)
    copy.step(50)
    assert copy.solid_positions().tobytes() == w.solid_positions().tobytes()
    assert copy.state_hash() == w.state_hash()
    w.restore(snap)
    w.step(50)
    assert w.state_hash() == copy.state_hash()
    fresh = sprung_world(dim)
    text = physstep.scene_file_text(fresh, "sprung")
    assert "[[solid_springs]]" in text and "linear_damping = 0.25" in text
    path = tmp_path / "sprung.toml"
    path.write_text(text)
    back, _ = physstep.read_scene(str(path))
    assert back.state_hash() == fresh.state_hash()
    back.step(80)
    fresh.step(80)
    assert back.state_hash() == fresh.state_hash()


@pytest.mark.parametrize("dim", [2, 3])
def test_a_force_applied_by_hand_acts_for_one_step_at_its_point(dim: int) -> None:
    w = world(dim, 0.0)
    w.add_solid(physstep.Circle(0.5))
    m = ball_mass(dim)
    w.apply_solid_force(0, [3.0] + [0.0] * (dim - 1), point=[0.0, 0.5] + [0.0] * (dim - 2))
    w.step(1)
    v = w.solid_velocities()[0, 0]
    assert v == pytest.approx(3.0 * DT / m, rel=1e-12)
    inertia = m * 0.25 / 2 if dim == 2 else 2 * m * 0.25 / 5
    spin = w.solid_angular_velocities().ravel()[-1]
    assert spin == pytest.approx(-1.5 * DT / inertia, rel=1e-12)
    w.step(1)
    assert w.solid_velocities()[0, 0] == v
    w.apply_solid_torque(0, 2.0 if dim == 2 else [0.0, 0.0, 2.0])
    w.step(1)
    assert w.solid_angular_velocities().ravel()[-1] == pytest.approx(spin + 2.0 * DT / inertia, rel=1e-12)
    with pytest.raises(ValueError, match="solid"):
        w.apply_solid_force(4, [1.0] * dim)
    with pytest.raises(ValueError, match="force"):
        w.apply_solid_force(0, [math.inf] * dim)
    with pytest.raises(ValueError, match="torque"):
        w.apply_solid_torque(0, [1.0, 2.0])
