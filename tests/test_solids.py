"""Solids: rigid bodies with shapes that land, slide, stack and rest (docs/contact.md)."""

import math
import pickle

import numpy as np
import physstep
import pytest

G = 9.81


def ground_2d(w: physstep.World) -> int:
    return w.add_solid(physstep.Box(50.0, 1.0), position=[0.0, -1.0], kind="static")


def box_world() -> physstep.World:
    w = physstep.World(dim=2, dt=1 / 60)
    w.add_gravity([0.0, -G])
    ground_2d(w)
    w.add_solid(physstep.Box(0.5, 0.5), position=[0.0, 2.0])
    return w


def test_a_box_lands_and_rests_on_the_ground_with_its_energy_gone():
    w = box_world()
    peak = 0.0
    for _ in range(600):
        w.step(1)
        peak = max(peak, w.kinetic_energy())
    assert w.kinetic_energy() < 1e-8 * peak
    assert w.max_penetration < 0.005
    assert w.solid_positions()[1] == pytest.approx([0.0, 0.5], abs=5e-3)
    c = w.contacts()
    assert set(c) == {"pairs", "points", "normals", "depths", "normal_impulses", "friction_impulses"}
    assert c["pairs"].tolist() == [[0, 1], [0, 1]]
    assert np.allclose(c["normals"], [[0.0, 1.0], [0.0, 1.0]])
    # The two points carry the box's weight over the step: m g dt (m = 1 kg/m^2 x 1 m^2).
    assert c["normal_impulses"].sum() == pytest.approx(1.0 * G / 60, rel=1e-3)


def test_the_energy_of_a_falling_box_is_kinetic_plus_potential_until_it_lands():
    w = box_world()
    e0 = w.energy()
    w.step(20)  # still falling: 1.5 m to go
    assert w.contacts()["pairs"].shape == (0, 2)
    # Symplectic Euler under constant gravity loses energy at O(dt) per step, exactly known:
    # after n substeps of h, E - E0 = -m g^2 h^2 n / 2.
    n, h = 20 * 8, 1 / 60 / 8
    assert w.energy() - e0 == pytest.approx(-(G**2) * h * h * n / 2, rel=1e-6)


def test_a_box_on_a_ramp_sticks_above_the_friction_angle_and_slides_below_it():
    def ramp(mu: float, seconds: float) -> tuple[float, float]:
        a = 0.5
        w = physstep.World(dim=2, dt=1 / 60)
        w.add_gravity([0.0, -G])
        w.add_solid(physstep.Box(100.0, 0.5), orientation=a, kind="static", friction=mu)
        up = 0.75
        at = [-math.sin(a) * up, math.cos(a) * up]
        w.add_solid(physstep.Box(0.25, 0.25), position=at, orientation=a, friction=mu)
        along = np.array([math.cos(a), math.sin(a)])
        x0 = w.solid_positions()[1] @ along
        w.step(round(seconds * 60))
        return w.solid_positions()[1] @ along - x0, w.solid_velocities()[1] @ along

    moved, _ = ramp(0.6, 5.0)
    assert abs(moved) < 1e-3
    _, v = ramp(0.3, 2.0)
    exact = -G * (math.sin(0.5) - 0.3 * math.cos(0.5))
    assert v / 2.0 == pytest.approx(exact, rel=0.01)


def test_a_cube_thrown_on_a_plane_in_3d_comes_to_rest_on_a_face():
    w = physstep.World(dim=3, dt=1 / 60)
    w.add_gravity([0.0, -G, 0.0])
    w.add_solid(physstep.Plane([0.0, 1.0, 0.0]), kind="static")
    w.add_solid(
        physstep.Box(0.5, 0.5, 0.5),
        position=[0.0, 2.0, 0.0],
        orientation=[1.0, 0.1, 0.2, 0.05],
        velocity=[1.0, 0.0, 0.5],
        angular_velocity=[0.0, 3.0, 1.0],
    )
    w.step(600)
    assert w.solid_positions()[1][1] == pytest.approx(0.5, abs=5e-3)
    assert np.abs(w.solid_velocities()[1]).max() < 1e-6
    q = w.solid_orientations()[1]
    assert np.linalg.norm(q) == pytest.approx(1.0, abs=1e-12)


def test_a_stack_of_ten_boxes_stands():
    w = physstep.World(dim=2, dt=1 / 60)
    w.add_gravity([0.0, -G])
    ground_2d(w)
    for i in range(10):
        w.add_solid(physstep.Box(0.5, 0.5), position=[0.0, 0.5 + i])
    top0 = w.solid_positions()[10].copy()
    w.step(600)
    assert np.linalg.norm(w.solid_positions()[10] - top0) < 0.01
    assert w.max_penetration < 0.01


def test_the_same_inputs_give_the_same_bits():
    runs = []
    for _ in range(2):
        w = physstep.World(dim=2, dt=1 / 60)
        w.add_gravity([0.0, -G])
        ground_2d(w)
        for i in range(6):
            w.add_solid(physstep.Circle(0.3), position=[0.1 * i, 1.0 + 0.7 * i], restitution=0.3)
        w.step(200)
        runs.append((w.solid_positions().tobytes(), w.solid_velocities().tobytes()))
    assert runs[0] == runs[1]


def test_a_solid_that_runs_away_is_rolled_back_and_named():
    def fast() -> physstep.World:
        w = physstep.World(dim=2, dt=1.0)
        w.add_solid(physstep.Circle(0.5), velocity=[4e99, 0.0])
        w.add_solid(physstep.Circle(0.5), position=[5.0, 0.0])
        return w

    w = fast()
    # 4e99, 8e99, then 1.2e100: past the runaway limit of 1e100 in the third step.
    ran_away = "diverged at step 2 .* solid 0 became non-finite or ran away"
    with pytest.raises(physstep.DivergedError, match=ran_away):
        w.step(5)
    assert w.steps == 2
    # Rolled back to the end of the second step, bitwise.
    two = fast()
    two.step(2)
    assert w.solid_positions().tobytes() == two.solid_positions().tobytes()
    assert w.solid_velocities().tobytes() == two.solid_velocities().tobytes()


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"shape": physstep.Box(1.0, 1.0), "friction": -0.1}, "invalid friction = -0.1"),
        ({"shape": physstep.Box(1.0, 1.0), "restitution": 1.5}, "invalid restitution = 1.5"),
        ({"shape": physstep.Box(1.0, 1.0), "density": 0.0}, "invalid density = 0"),
        ({"shape": physstep.Box(1.0, 1.0), "position": [0.0, math.nan]}, r"invalid position\[1\] = NaN"),
        ({"shape": physstep.Box(1.0, 1.0), "kind": "floating"}, "kind"),
        ({"shape": physstep.Plane([0.0, 1.0])}, "invalid kind = dynamic"),
        ({"shape": physstep.Polygon([[0, 0], [2, 0], [1, 0.2], [2, 2], [0, 2]])}, "invalid points"),
        ({"shape": physstep.Polygon([[0, 0], [1, 0], [2, 0]])}, "invalid points"),
        ({"shape": physstep.Box(1.0, 1.0, 1.0)}, r"invalid len\(half\) = 3"),
        ({"shape": physstep.Cylinder(1.0, 1.0)}, "invalid shape"),
        ({"shape": physstep.Box(1.0, 1.0), "kind": "static", "velocity": [1.0, 0.0]}, "invalid velocity"),
    ],
)
def test_bad_solids_are_refused_in_one_line_naming_the_field(kwargs, field):
    w = physstep.World(dim=2)
    with pytest.raises(ValueError, match=field) as e:
        w.add_solid(**kwargs)
    assert "\n" not in str(e.value)
    assert w.solid_count == 0


def test_bad_sizes_and_settings_are_refused():
    with pytest.raises(ValueError, match="invalid radius = 0"):
        physstep.Circle(0.0)
    with pytest.raises(ValueError, match=r"invalid half\[1\] = -1"):
        physstep.Box(1.0, -1.0)
    w = physstep.World(dim=2)
    with pytest.raises(ValueError, match="invalid substeps = 0"):
        w.substeps = 0
    with pytest.raises(ValueError, match="invalid solver_iterations = 1001"):
        w.solver_iterations = 1001
    with pytest.raises(ValueError, match="soft-step"):
        w.contact_solver = "bogus"
    assert (w.substeps, w.solver_iterations, w.contact_solver) == (8, 1, "soft-step")
    with pytest.raises(ValueError, match="invalid dim = 1"):
        physstep.World(dim=1).add_solid(physstep.Circle(1.0))
    with pytest.raises(ValueError, match=r"Box\(hx, hy\) is a 2D box"):
        physstep.World(dim=3).add_body(physstep.Box(1.0, 1.0))


def test_a_2d_box_pickles_and_prints_as_a_2d_box():
    b = physstep.Box(0.5, 0.25)
    assert repr(b) == "Box(hx=0.5, hy=0.25)"
    assert pickle.loads(pickle.dumps(b)) == b
    assert list(physstep.contact_solvers()) == [
        "soft-step",
        "pgs",
        "pgs-ngs",
        "soft-pgs",
        "tgs-sticky",
        "jacobi",
        "xpbd",
        "projection",
    ]
    assert "Box2D v3's soft step" in physstep.contact_solvers()["soft-step"]
    assert "Baumgarte" in physstep.contact_solvers()["pgs"]


def test_each_solver_is_chosen_by_name_and_rests_a_box_where_the_soft_step_does():
    rest = {}
    for solver in physstep.contact_solvers():
        w = box_world()
        w.contact_solver = solver
        assert w.contact_solver == solver
        w.step(300)
        rest[solver] = (w.solid_positions()[-1][1], float(np.abs(w.solid_velocities()).max()))
        # A snapshot keeps the solver; a pickle too.
        assert pickle.loads(pickle.dumps(w)).contact_solver == solver
    # At rest 4 s after landing: the soft step to rounding, PGS to 1e-7 m/s, PGS with NGS
    # (its position passes turn the box a little each step) to 2e-6, halving every 2.5 s.
    for solver, (y, speed) in rest.items():
        assert abs(y - rest["soft-step"][0]) < 5e-3 and speed < 1e-5, (solver, y, speed)
    assert rest["soft-step"][1] < 1e-12


def test_more_substeps_make_a_stiffer_contact():
    # A soft contact holds its load at a depth of g / omega^2 (omega = 2 pi hertz): the
    # substep rate caps the stiffness, so 2 substeps sink deeper than 8.
    depths = []
    for n in (2, 8):
        w = box_world()
        w.substeps = n
        w.step(300)
        depths.append(w.max_penetration)
    assert depths[0] > 2 * depths[1] > 0


def test_a_world_of_solids_pickles_mid_run_and_continues_bitwise():
    w = box_world()
    w.add_solid(physstep.Circle(0.25), position=[0.3, 3.0], restitution=0.5)
    w.step(45)  # landed: contacts and warm starts carry over
    copy = pickle.loads(pickle.dumps(w))
    assert copy.state_hash() == w.state_hash()
    w.step(30)
    copy.step(30)
    assert copy.solid_positions().tobytes() == w.solid_positions().tobytes()
    assert copy.solid_velocities().tobytes() == w.solid_velocities().tobytes()
    # The hash sees the solids: a step moves it.
    h = w.state_hash()
    w.step(1)
    assert w.state_hash() != h


def _first_block(text: str, after: str) -> str:
    start = text.index("```python\n", text.index(after)) + len("```python\n")
    return text[start : text.index("```", start)]


def test_the_readme_and_the_contact_page_examples_run_and_say_true():
    from pathlib import Path

    root = Path(__file__).resolve().parent.parent
    scope: dict[str, object] = {"physstep": physstep}
    exec(_first_block((root / "README.md").read_text(), "### Solids: contact"), scope)  # noqa: S102
    w = scope["w"]
    assert isinstance(w, physstep.World)
    assert w.solid_positions()[10][1] == pytest.approx(9.5, abs=0.01)  # the stack stands
    assert w.max_penetration == pytest.approx(1.6e-3, rel=0.1)  # "the deepest contact 1.6 mm"
    page: dict[str, object] = {"print": lambda *a: None}
    exec(_first_block((root / "docs" / "contact.md").read_text(), "# Contact"), page)  # noqa: S102
    w = page["w"]
    assert isinstance(w, physstep.World)
    assert w.solid_positions()[1] == pytest.approx([0.0, 0.5], abs=1e-3)
    assert w.max_penetration == pytest.approx(2.2e-5, rel=0.1)  # "0.02 mm in it"


@pytest.mark.parametrize("dim", [2, 3])
def test_solids_are_drawn_between_the_last_two_steps_of_a_frame(dim: int) -> None:
    # A sphere drifting and turning at constant rates: the drawn pose is (1 - alpha) of a
    # step behind the current one; outside a frame (after step()) it is the current one.
    dt, spin = 1 / 60, 3.0
    w = physstep.World(dim, dt=dt)
    v = [2.0, -1.0, 0.5][:dim]
    w.add_solid(
        physstep.Circle(0.5),
        position=[0.0] * dim,
        velocity=v,
        angular_velocity=[0.0, 0.0, spin] if dim == 3 else spin,
    )
    w.advance(0.05 + 0.4 * dt)  # three steps, 0.4 of one left over
    assert w.alpha == pytest.approx(0.4, abs=1e-9)
    back = (1 - w.alpha) * dt
    np.testing.assert_allclose(
        w.interpolated_solid_positions(), w.solid_positions() - back * np.array(v), atol=1e-12
    )
    angle = spin * (w.time - back)
    if dim == 2:
        np.testing.assert_allclose(w.interpolated_solid_orientations(), [angle], atol=1e-12)
    else:
        want = [math.cos(angle / 2), 0.0, 0.0, math.sin(angle / 2)]
        np.testing.assert_allclose(w.interpolated_solid_orientations(), [want], atol=1e-12)
    w.step(1)
    np.testing.assert_array_equal(w.interpolated_solid_positions(), w.solid_positions())
    np.testing.assert_array_equal(w.interpolated_solid_orientations(), w.solid_orientations())


def _thrown_box(continuous: bool | None) -> float:
    """A 1 m box thrown flat at the ground at 20 m/s from 3 m up: the deepest its lowest
    point went below the ground's top (y = 0) in 2 s."""
    w = physstep.World(dim=2, dt=1 / 60)
    w.add_gravity([0.0, -G])
    ground_2d(w)
    if continuous is not None:
        w.continuous_collision = continuous
    b = w.add_solid(physstep.Box(0.5, 0.5), position=[0.0, 3.0], velocity=[0.0, -20.0])
    deepest = 0.0
    for _ in range(120):
        w.step(1)
        a = float(w.solid_orientations()[b])
        reach = 0.5 * (abs(math.cos(a)) + abs(math.sin(a)))
        deepest = max(deepest, reach - float(w.solid_positions()[b][1]))
    return deepest


def test_a_fast_box_thrown_at_the_ground_stops_on_it_with_continuous_collision_on():
    # 20 m/s is 33 cm a step: the step that begins clear of the ground's speculative contact
    # (2 cm) ends deep inside unless the box is swept and put back to where it met it.
    assert physstep.World(dim=2).continuous_collision is True  # the default
    assert _thrown_box(None) < 0.005
    assert _thrown_box(True) == _thrown_box(None)
    assert _thrown_box(False) > 0.1  # about 30 cm


def test_continuous_collision_is_a_flag_kept_by_pickles_and_scene_files(tmp_path):
    w = box_world()
    with pytest.raises(ValueError, match="continuous_collision") as e:
        w.continuous_collision = 1
    assert "\n" not in str(e.value)
    assert w.continuous_collision is True
    w.continuous_collision = False
    assert pickle.loads(pickle.dumps(w)).continuous_collision is False
    text = physstep.scene_text(w, "off")
    assert "continuous = false" in text
    assert "continuous" not in physstep.scene_text(box_world(), "on")
    path = tmp_path / "off.toml"
    path.write_text(text)
    assert physstep.load_scene(path).continuous_collision is False
    path.write_text(text.replace("continuous = false", 'continuous = "no"'))
    with pytest.raises(ValueError, match=r"contact\.continuous.*must be true or false") as e:
        physstep.load_scene(path)
    assert "\n" not in str(e.value)


def test_a_bullet_stops_at_a_dynamic_plank_that_a_plain_fast_ball_passes_through():
    # Continuous collision sweeps a fast solid against static and kinematic solids; a bullet
    # against dynamic ones too. The ball moves 1 m a step, the plank is 20 cm thick.
    def shoot(bullet: bool) -> float:
        w = physstep.World(dim=2, dt=1 / 60)
        plank = w.add_solid(physstep.Box(0.1, 1.0), position=[2.0, 0.0], density=0.4)
        ball = w.add_solid(physstep.Circle(0.05), position=[0.3, 0.0], velocity=[60.0, 0.0], bullet=bullet)
        w.step(10)
        x = w.solid_positions()
        return float(x[ball][0] - x[plank][0])  # the ball's centre from the plank's

    assert shoot(False) > 0.15  # past the plank's far face
    assert shoot(True) < -0.15 + 0.005  # at its near face
    w = physstep.World(dim=2)
    with pytest.raises(ValueError, match="invalid bullet = true: must be false for a static solid"):
        w.add_solid(physstep.Box(1.0, 1.0), kind="static", bullet=True)
    with pytest.raises(ValueError, match="bullet"):
        w.add_solid(physstep.Circle(0.1), bullet="yes")
    assert w.solid_count == 0
    w.add_solid(physstep.Circle(0.1), bullet=True)
    assert "bullet = true" in physstep.scene_text(w)


def test_a_resting_box_falls_asleep_and_a_dropped_one_wakes_it():
    w, awake = box_world(), box_world()
    assert w.sleep_time == 0.0
    w.sleep_time = 0.5
    w.step(120)
    awake.step(120)
    assert w.solids_asleep().tolist() == [False, True]
    rest = w.solid_positions().copy()
    assert np.all(w.solid_velocities() == 0.0)
    w.step(60)
    awake.step(60)
    assert np.array_equal(w.solid_positions(), rest)
    # A box dropped onto it wakes it before it lands; both rest and sleep again, where they
    # rest in a world that never sleeps.
    for world in (w, awake):
        world.add_solid(physstep.Box(0.5, 0.5), position=[0.0, 3.0])
    woke = False
    for _ in range(240):
        w.step(1)
        awake.step(1)
        woke = woke or not w.solids_asleep()[1]
    assert woke and w.solids_asleep().tolist() == [False, True, True]
    assert not awake.solids_asleep().any()
    assert w.solid_positions() == pytest.approx(awake.solid_positions(), abs=1e-3)
    assert w.solid_positions()[2, 1] == pytest.approx(1.5, abs=0.01)
    # Kept by pickles, bitwise.
    twin = pickle.loads(pickle.dumps(w))
    assert twin.sleep_time == 0.5 and twin.state_hash() == w.state_hash()
    w.step(30)
    twin.step(30)
    assert twin.state_hash() == w.state_hash()


@pytest.mark.parametrize("bad", [-1.0, float("nan"), float("inf"), "soon"])
def test_a_bad_sleep_time_is_refused_in_one_line(bad):
    w = box_world()
    with pytest.raises((ValueError, TypeError)) as info:
        w.sleep_time = bad
    assert "sleep_time" in str(info.value) and "\n" not in str(info.value)
    assert w.sleep_time == 0.0
