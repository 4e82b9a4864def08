"""Every built-in scene has its own default method and dt (``physstep scenes`` lists them):
the flows run under RK4 (a split method does not apply to a flow), the stiff scenes under
backward Euler (explicit methods diverge at their dt), and `simulate`, `World.from_scene`
and the command line all take them when none is given."""

from __future__ import annotations

import json

import physstep
import pytest
from conftest import run_cli


def test_every_scene_runs_at_its_own_defaults() -> None:
    for s in physstep.scenes():
        traj = physstep.simulate(s["name"], until=20 * s["dt"])
        assert traj.method == s["method"] and traj.dt == s["dt"], s["name"]
        assert traj.diverged is None and len(traj.t) == 21, s["name"]


@pytest.mark.parametrize("scene", ["lorenz", "rossler", "thomas"])
def test_the_flows_run_from_the_command_line_by_default(scene: str) -> None:
    r = run_cli("run", scene, "--until", "1", "--format", "json")
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["method"] == "rk4"


def test_stiff_chain_runs_by_default_without_diverging() -> None:
    r = run_cli("run", "stiff-chain", "--until", "1", "--format", "json")
    assert r.returncode == 0, r.stderr
    summary = json.loads(r.stdout)
    assert summary["method"] == "backward-euler" and summary["steps"] == 60


def test_world_from_scene_takes_the_scenes_method_and_dt() -> None:
    w = physstep.World.from_scene("stiff-chain")
    assert (w.method, w.dt) == ("backward-euler", 1 / 60)
    w = physstep.World.from_scene("lorenz")
    assert (w.method, w.dt) == ("rk4", 0.005)
    w = physstep.World.from_scene("top")
    assert (w.method, w.dt) == ("symplectic-euler", 1 / 1200)
    # Given, they win; None is the default.
    w = physstep.World.from_scene("stiff-chain", "implicit-midpoint", 0.01)
    assert (w.method, w.dt) == ("implicit-midpoint", 0.01)
    w = physstep.World.from_scene("stiff-chain", None, None)
    assert (w.method, w.dt) == ("backward-euler", 1 / 60)


def test_the_scene_list_shows_each_scenes_method() -> None:
    r = run_cli("scenes")
    assert r.returncode == 0, r.stderr
    lines = {line.split()[0]: line for line in r.stdout.splitlines() if line and not line.startswith(" ")}
    assert " rk4 dt=0.005 " in lines["lorenz"]
    assert " backward-euler dt=0.0166667 " in lines["stiff-chain"]
    assert " symplectic-euler dt=0.1 " in lines["spring"]
    listed = json.loads(run_cli("scenes", "--format", "json").stdout)
    assert {s["name"]: s["method"] for s in listed}["thomas"] == "rk4"
