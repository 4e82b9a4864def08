"""Joints between solids from Python: a hinged rod that keeps its pin, limits and motors,
the jointed scenes, pickles that continue bitwise, and bad joints named in one line."""

import json
import pickle
import re
import subprocess
import sys

import numpy as np
import physstep
import pytest

G = 9.81


def rod_on_a_pin(**joint: object) -> tuple[physstep.World, int]:
    w = physstep.World(dim=2)
    w.add_gravity([0.0, -G])
    # A 1 m rod lying level from the pin at the origin.
    rod = w.add_solid(physstep.Box(0.5, 0.02), position=[0.5, 0.0], density=10.0)
    w.add_joint("revolute", rod, anchor=[0.0, 0.0], **joint)
    return w, rod


def test_a_hinged_rod_swings_down_on_its_pin_and_its_angle_is_its_own() -> None:
    w, rod = rod_on_a_pin()
    w.step(600)
    assert w.joint_count == 1
    assert w.joint_errors()[0] < 1e-3
    # It swung through the bottom: its angle went below -pi/4 at some point; here it is
    # somewhere on its arc, the pin where it was.
    x = w.solid_positions()[rod]
    assert np.hypot(*x) == pytest.approx(0.5, abs=1e-3)


def test_a_lower_limit_stops_the_rod_and_a_motor_turns_it_against_gravity() -> None:
    w, rod = rod_on_a_pin(lower=-0.5)
    w.step(300)
    assert w.solid_orientations()[rod] == pytest.approx(-0.5, abs=0.01)
    w, rod = rod_on_a_pin(motor_speed=1.0, max_motor=1000.0)
    w.step(60)
    assert w.solid_angular_velocities()[rod] == pytest.approx(1.0, abs=1e-3)
    assert w.solid_orientations()[rod] == pytest.approx(60 * w.dt, abs=0.02)


@pytest.mark.parametrize(
    ("change", "field"),
    [
        ({"kind": "rope"}, "joint kind"),
        ({"b": 0}, "b"),
        ({"b": 7}, "b"),
        ({"anchor": [0.0]}, "anchor"),
        ({"anchor": [np.nan, 0.0]}, "anchor[0]"),
        ({"hertz": -1.0}, "hertz"),
        ({"lower": 1.0, "upper": 0.0}, "lower"),
        ({"kind": "prismatic", "axis": [0.0, 0.0]}, "axis"),
        ({"kind": "distance", "length": -1.0}, "length"),
    ],
)
def test_a_bad_joint_is_one_value_error_naming_the_field(change: dict[str, object], field: str) -> None:
    w = physstep.World(dim=2)
    rod = w.add_solid(physstep.Circle(0.1))
    kw: dict[str, object] = {"kind": "ball", "anchor": [0.0, 0.0], **change}
    kind = kw.pop("kind")
    with pytest.raises(ValueError, match=re.escape(field)) as e:
        w.add_joint(kind, rod, **kw)  # type: ignore[arg-type]
    assert "\n" not in str(e.value)
    assert w.joint_count == 0


def test_a_jointed_world_pickles_and_continues_bitwise() -> None:
    w = physstep.World.from_scene("ragdoll-bodies")
    w.step(30)
    copy = pickle.loads(pickle.dumps(w))
    w.step(60)
    copy.step(60)
    assert copy.joint_count == w.joint_count == 11
    assert np.array_equal(copy.solid_positions(), w.solid_positions())
    assert copy.state_hash() == w.state_hash()


def test_joint_settings_are_checked_and_the_projection_tightens_a_whipping_chain() -> None:
    def chain(projection: int) -> float:
        w = physstep.World(dim=2)
        w.add_gravity([0.0, -G])
        w.joint_projection = projection
        prev = None
        for i in range(3):
            b = w.add_solid(physstep.Capsule(0.1, 0.8), position=[i + 0.5, 0.0], orientation=-np.pi / 2)
            w.add_joint("revolute", prev if i else b, b if i else None, anchor=[float(i), 0.0])
            prev = b
        worst = 0.0
        for _ in range(600):
            w.step(1)
            worst = max(worst, float(w.joint_errors().max()))
        return worst

    assert chain(8) < chain(0) / 3
    w = physstep.World(dim=2)
    with pytest.raises(ValueError, match="joint_hertz"):
        w.joint_hertz = -5.0
    with pytest.raises(ValueError, match="joint_projection"):
        w.joint_projection = 5000
    assert w.joint_hertz == 120.0


@pytest.mark.parametrize("scene", ["bridge", "ball-chain", "ragdoll-bodies"])
def test_the_cli_runs_a_jointed_scene_and_reports_its_contacts(scene: str) -> None:
    out = subprocess.run(
        [sys.executable, "-m", "physstep", "run", scene, "--until", "1"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    assert "contacts" in out


def test_the_cli_reports_the_solids_asleep_in_a_scene_file_that_sleeps(tmp_path) -> None:
    w = physstep.World.from_scene("bridge")
    w.sleep_time = 0.5
    path = tmp_path / "bridge.toml"
    path.write_text(physstep.scene_text(w, "a sleeping bridge"))
    run = [sys.executable, "-m", "physstep", "run", str(path), "--until", "15", "--format", "json"]
    out = json.loads(subprocess.run(run, capture_output=True, text=True, check=True).stdout)
    c = out["summary"]["contacts"] if "summary" in out else out["contacts"]
    assert c["asleep"] == c["solids"] == 40 and c["max_speed"] == 0.0
    text = subprocess.run(run[:-2], capture_output=True, text=True, check=True).stdout
    assert "40 asleep" in text
    # Without sleeping the report is as it was: no such key.
    out = subprocess.run(
        [sys.executable, "-m", "physstep", "run", "bridge", "--until", "1", "--format", "json"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    assert "asleep" not in out
