"""Forces on solids: drag, springs at points, loads by hand and forces from Python callables
(docs/contact.md, "Forces on solids")."""

import math
import pickle

import numpy as np
import physstep
import pytest
from conftest import run_cli

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
    w.add_solid(
        physstep.Circle(0.5), velocity=v0, angular_velocity=spin, linear_damping=0.5, angular_damping=0.3
    )
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
    assert w.add_solid_spring(0, [0.0] * dim, point_b=top, stiffness=k, rest_length=2.0).row == 0
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
    w.add_solid(
        physstep.Circle(0.5),
        position=[4.0] + [0.0] * (dim - 1),
        density=3.0,
        velocity=[-0.7] + [0.0] * (dim - 1),
    )
    w.add_solid_spring(
        0, [0.0, 0.3] + [0.0] * (dim - 2), 1, [-0.2, 0.1] + [0.0] * (dim - 2), stiffness=50.0, rest_length=3.5
    )
    ends = w.solid_spring_ends()
    assert ends.shape == (1, 2, dim)
    assert np.allclose(ends[0], [[0.0, 0.3] + [0.0] * (dim - 2), [3.8, 0.1] + [0.0] * (dim - 2)], atol=1e-15)
    masses = np.array([ball_mass(dim), ball_mass(dim, rho=3.0)])
    p0 = masses @ w.solid_velocities()
    e0 = w.solid_energy()
    w.step(600)
    ends = w.solid_spring_ends()[0]
    stretch = np.linalg.norm(ends[1] - ends[0]) - 3.5
    spin = w.solid_angular_velocities()
    kinetic = 0.5 * masses @ np.sum(w.solid_velocities() ** 2, axis=1)
    if dim == 2:
        kinetic += 0.5 * masses @ (0.125 * spin**2)
    else:
        kinetic += 0.5 * masses @ (0.1 * np.sum(spin**2, axis=1))
    # Its ends are where the energy says: kinetic plus 0.5 k stretch^2.
    assert w.solid_energy() == pytest.approx(kinetic + 0.5 * 50.0 * stretch**2, rel=1e-12)
    assert np.allclose(masses @ w.solid_velocities(), p0, rtol=0, atol=1e-12)
    assert np.any(w.solid_angular_velocities() != 0.0), "the spring off their centres turns them"
    assert len(w.contacts()["depths"]) == 0, "they never came near each other"
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
    text = physstep.scene_text(fresh, "sprung")
    assert "[[solid_springs]]" in text and "linear_damping = 0.25" in text
    path = tmp_path / "sprung.toml"
    path.write_text(text)
    back = physstep.load_scene(path)
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


def push_up(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
    """A constant force up (module level: it pickles)."""
    f = np.zeros_like(x)
    f[0, 1] = 4.0
    return f


def spring_to_origin(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
    return -30.0 * x - 0.5 * v


def spring_potential(x: np.ndarray) -> float:
    return 15.0 * float(np.sum(x * x))


@pytest.mark.parametrize("dim", [2, 3])
def test_a_python_force_is_held_over_the_step_as_a_load_by_hand_is(dim: int) -> None:
    by_hand, by_func = world(dim), world(dim)
    for w in (by_hand, by_func):
        w.add_solid(physstep.Box(*[0.3] * dim), angular_velocity=1.0 if dim == 2 else [0.0, 0.0, 1.0])
    point = [0.3, 0.1] + [0.0] * (dim - 2)
    assert by_func.add_solid_force(0, push_up, point).row == 0
    assert by_func.solid_force_count == 1
    for _ in range(40):
        # Where the point is now, in the world: the force acts there.
        at = by_hand.solid_positions()[0].copy()
        if dim == 2:
            c, s = math.cos(by_hand.solid_orientations()[0]), math.sin(by_hand.solid_orientations()[0])
            at += [c * point[0] - s * point[1], s * point[0] + c * point[1]]
        else:
            wq, *u = by_hand.solid_orientations()[0]
            u = np.array(u)
            p = np.array(point)
            at += p + 2 * wq * np.cross(u, p) + 2 * np.cross(u, np.cross(u, p))
        by_hand.apply_solid_force(0, [0.0, 4.0] + [0.0] * (dim - 2), point=at)
        by_hand.step(1)
        by_func.step(1)
    assert by_func.solid_velocities()[0] == pytest.approx(by_hand.solid_velocities()[0], rel=1e-12, abs=1e-12)
    assert by_func.solid_angular_velocities() == pytest.approx(by_hand.solid_angular_velocities(), rel=1e-9)
    assert by_func.solid_velocities()[0, 1] > -G * 40 * DT + 1.0, "it pushed up"


def test_a_python_force_sees_the_point_where_it_is_and_turns_the_solid() -> None:
    w = world(2, 0.0)
    w.add_solid(physstep.Circle(0.5), position=[1.0, 2.0], orientation=math.pi / 2)
    seen = []

    def record(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        seen.append((t, x.copy(), v.copy()))
        return np.array([[1.0, 0.0]])

    w.add_solid_force(0, record, [0.5, 0.0])
    w.step(2)
    assert len(seen) == 2, "once a step"
    t, x, v = seen[0]
    assert t == 0.0
    assert np.allclose(x, [[1.0, 2.5]], rtol=0, atol=1e-15)  # (0.5, 0) turned a quarter turn
    assert np.all(v == 0.0)
    assert seen[1][0] == DT
    # (0, 0.5) x (1, 0) = -0.5: clockwise.
    assert w.solid_angular_velocities()[0] < 0.0


def test_a_python_force_with_a_potential_keeps_the_energy_known() -> None:
    w = world(2, 0.0)
    w.add_solid(physstep.Circle(0.5), position=[0.5, 0.0])
    w.add_solid_force(0, spring_to_origin, potential=spring_potential)
    e0 = w.energy()
    assert e0 == pytest.approx(w.solid_energy() + 15.0 * 0.25)
    w.step(60)
    assert w.energy() < e0, "its damping took energy"
    w.add_solid_force(0, push_up)
    assert w.energy() is None


def test_an_exception_in_a_python_force_propagates_and_rolls_the_step_back() -> None:
    w = world(3)
    w.add_solid(physstep.Circle(0.5))
    calls = []

    def fails(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        calls.append(t)
        if len(calls) == 3:
            raise KeyError("boom")
        return np.zeros((1, 3))

    w.add_solid_force(0, fails)
    w.step(1)
    h, steps = w.state_hash(), w.steps
    with pytest.raises(KeyError, match="boom"):
        w.step(5)
    assert w.steps == steps + 1
    w2 = world(3)
    w2.add_solid(physstep.Circle(0.5))
    w2.step(2)
    assert w.solid_positions().tobytes() == w2.solid_positions().tobytes(), "the failing step left no trace"
    assert h != w.state_hash()


def test_a_python_force_that_is_not_finite_is_a_value_error_naming_it() -> None:
    w = world(2)
    w.add_solid(physstep.Circle(0.5))

    def wild(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        return np.array([[math.nan, 0.0]])

    w.add_solid_force(0, wild, name="wild wind")
    h = w.state_hash()
    with pytest.raises(ValueError, match="force 'wild wind' failed: force.0..0. = NaN is not finite") as e:
        w.step(1)
    assert len(str(e.value).splitlines()) == 1
    assert w.state_hash() == h and w.steps == 0


def test_python_forces_on_solids_pickle_copy_and_refuse_export() -> None:
    w = world(2)
    w.add_solid(physstep.Box(0.3, 0.3))
    w.add_solid_force(0, push_up, [0.3, 0.0])
    w.step(10)
    back = pickle.loads(pickle.dumps(w))
    import copy as copying

    twin = copying.copy(w)
    assert back.solid_force_count == twin.solid_force_count == 1
    for other in (back, twin):
        other.step(20)
    w.step(20)
    assert back.state_hash() == w.state_hash() == twin.state_hash()
    w.add_solid_force(0, lambda t, x, v: np.zeros((1, 2)))
    with pytest.raises(pickle.PicklingError, match="solid's point"):
        pickle.dumps(w)
    fresh = world(2)
    fresh.add_solid(physstep.Circle(0.5))
    fresh.add_solid_force(0, push_up)
    with pytest.raises(ValueError, match="user forces"):
        physstep.scene_text(fresh, "t")


def test_bad_python_forces_on_solids_are_refused() -> None:
    w = world(2)
    w.add_solid(physstep.Circle(0.5))
    with pytest.raises(ValueError, match="solid"):
        w.add_solid_force(3, push_up)
    with pytest.raises(ValueError, match="func"):
        w.add_solid_force(0, 3.0)
    with pytest.raises(ValueError, match="point"):
        w.add_solid_force(0, push_up, [0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="potential"):
        w.add_solid_force(0, push_up, potential=1.0)
    assert w.solid_force_count == 0


def test_the_contact_page_example_of_forces_runs() -> None:
    from pathlib import Path

    text = (Path(__file__).resolve().parent.parent / "docs" / "contact.md").read_text()
    start = text.index("```python\n", text.index("## Forces on solids")) + len("```python\n")
    printed: list[float] = []
    scope: dict[str, object] = {"physstep": physstep, "print": printed.append}
    exec(text[start : text.index("```", start)], scope)  # noqa: S102
    w = scope["w"]
    assert isinstance(w, physstep.World)
    assert w.solid_spring_count == 2
    assert printed == [w.solid_energy()]
    assert math.isfinite(printed[0])
    # The push up at the circle's edge turned it.
    assert w.solid_angular_velocities()[1] != 0.0


SPRUNG_FILE = """dimension = 2
dt = 0.0166

[[solids]]
shape = { kind = "circle", radius = 0.5 }
position = [0, 0]
linear_damping = 0.5

[[solid_springs]]
a = 0
point_a = [0, 0.5]
point_b = [0, 2]
stiffness = 40
"""


@pytest.mark.parametrize(
    ("old", "new", "want"),
    [
        (
            "linear_damping = 0.5",
            "linear_damping = -0.5",
            "s.toml:4: solids[0]: invalid linear_damping = -0.5",
        ),
        ("stiffness = 40", "stiffness = -40", "s.toml:9: solid_springs[0]: invalid stiffness = -40"),
        ("a = 0", "a = 4", "s.toml:9: solid_springs[0]: invalid a = 4: must be an existing solid"),
        ("point_b = [0, 2]", "point_b = [0, 2, 1]", "solid_springs[0].point_b: has 3 numbers: must have 2"),
    ],
)
def test_the_cli_refuses_bad_drag_and_springs_in_a_file_in_one_line_exit_2(
    tmp_path, old: str, new: str, want: str
) -> None:
    good = tmp_path / "good.toml"
    good.write_text(SPRUNG_FILE)
    ran = run_cli("run", str(good), "--until", "1")
    assert ran.returncode == 0, ran.stderr
    p = tmp_path / "s.toml"
    p.write_text(SPRUNG_FILE.replace(old, new))
    res = run_cli("run", str(p), "--until", "1")
    assert res.returncode == 2
    assert res.stderr.count("\n") == 1 and "Traceback" not in res.stderr
    assert want in res.stderr, res.stderr
