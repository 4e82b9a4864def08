"""A run's summary comes from the world that ran: a scene file named like a built-in scene
is measured by its own constraints (none: no constraint row), and a file of its own name
reports the violation its contradictory rods leave."""

from __future__ import annotations

import json
from pathlib import Path

import physstep
from conftest import run_cli

FREE = "dimension = 2\ndt = 0.01\nuntil = 1\n[[particles]]\nposition = [1.0, 0.0]\nvelocity = [0.0, 1.0]\n"

# Three particles in a row, 1 m apart, joined 0-1 and 1-2 by rods of 1 m and 0-2 by one of
# 1 m too: no position meets all three.
CONTRADICTORY = """dimension = 2
dt = 0.01
until = 0.5
[[particles]]
position = [0.0, 0.0]
[[particles]]
position = [1.0, 0.0]
[[particles]]
position = [2.0, 0.0]
[[constraints]]
kind = "distance"
i = 0
j = 1
length = 1.0
[[constraints]]
kind = "distance"
i = 1
j = 2
length = 1.0
[[constraints]]
kind = "distance"
i = 0
j = 2
length = 1.0
"""


def _summary(path: Path) -> dict:
    r = run_cli("run", str(path), "--format", "json")
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)


def test_a_scene_file_named_like_a_built_in_is_summarised_by_its_own_world(tmp_path: Path) -> None:
    path = tmp_path / "pendulum.toml"
    path.write_text(FREE)
    summary = _summary(path)
    assert summary["scene"] == "pendulum"
    assert "constraints" not in summary  # one free particle: no constraint at all
    text = run_cli("run", str(path))
    assert text.returncode == 0 and "constraints" not in text.stdout and "max violation" not in text.stdout


def test_contradictory_rods_in_a_file_report_the_violation_they_leave(tmp_path: Path) -> None:
    path = tmp_path / "rods.toml"
    path.write_text(CONTRADICTORY)
    summary = _summary(path)
    violation = summary["constraints"]["max_violation"]
    assert violation > 0.1  # the rods cannot all hold
    # The same number the file's own world gives at the final state.
    w = physstep.load_scene(path)
    w.step(50)
    assert w.constraint_violation() <= violation
    text = run_cli("run", str(path))
    assert "max violation" in text.stdout


def test_a_systems_trajectory_carries_the_world_that_ran(tmp_path: Path) -> None:
    path = tmp_path / "pendulum.toml"
    path.write_text(FREE)
    traj = physstep.simulate(physstep.SceneFile(path), until=0.1)
    assert traj.world is not None and traj.world.steps == 10
    assert physstep.summarize(traj).get("constraints") is None
    builtin = physstep.simulate("pendulum", until=0.1)
    assert builtin.world is None and physstep.summarize(builtin)["constraints"]["max_violation"] < 1e-6
