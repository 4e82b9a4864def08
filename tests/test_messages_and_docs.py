"""What users read (issue 25, items 16-18): energy measures that say what they measure,
messages that name the field with readable numbers, lists refused when malformed, and docs
whose claims hold (each claim checked against a run)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import physstep
import pytest
from conftest import ROOT, run_cli


def _summary(*args: str) -> dict:
    r = run_cli("run", *args, "--format", "json")
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)


# -- 16: energy measures ---------------------------------------------------------------------


def test_an_orbit_that_became_unbound_reads_its_error_relative_to_e0() -> None:
    # Explicit Euler on the Kepler ellipse at dt = 0.1: E from -0.5 to +0.40 (unbound);
    # relative to the largest kinetic energy it read below 1, relative to |E0| it is 1.85.
    en = _summary("kepler", "--method", "explicit-euler", "--dt", "0.1")["energy"]
    assert en["initial"] == pytest.approx(-0.5) and en["final"] > 0.3
    assert en["scale_of"] == "|E0|" and en["scale"] == pytest.approx(0.5)
    assert en["max_rel_error"] > 1.8 and en["dissipation"] is None
    text = run_cli("run", "kepler", "--method", "explicit-euler", "--dt", "0.1").stdout
    assert "max rel. error 1.85 of |E0|" in text


def test_scenes_that_lose_energy_by_design_report_the_energy_lost() -> None:
    # The ragdoll hits the ground (it read "max rel. error 0.957"); drag is drag.
    en = _summary("ragdoll")["energy"]
    assert en["dissipation"] == "inelastic ground contact and joint limits"
    assert en["lost"] == pytest.approx(en["initial"] - en["final"]) and en["lost"] > 100
    text = run_cli("run", "ragdoll").stdout
    assert "energy lost 198 J, 0.957 of |E0|: inelastic ground contact and joint limits" in text
    assert "rel. error" not in text
    assert _summary("drag")["energy"]["dissipation"] == "drag"
    assert _summary("drag", "--param", "c=0")["energy"]["dissipation"] is None
    assert _summary("balls", "--param", "restitution=0.5", "--until", "1")["energy"]["dissipation"] == (
        "inelastic collisions"
    )
    # The method's own damping: backward Euler on the stiff chain (E0 = 0 J: no scale).
    en = _summary("stiff-chain", "--until", "2")["energy"]
    assert en["dissipation"] == "backward-euler damps by design"
    assert en["scale_of"] == "the largest kinetic energy"
    assert "energy lost" in run_cli("run", "stiff-chain", "--until", "2").stdout


def test_a_scene_whose_contacts_push_solids_apart_reports_the_energy_gained_not_an_error() -> None:
    # `confined` starts its circles overlapping, without gravity, from rest (E0 = 0 J): the
    # contacts push them apart; it read "max error 8.73e+04 J".
    en = _summary("confined", "--param", "n=20", "--until", "0.5")["energy"]
    assert en["dissipation"] == "contacts pushing apart" and en["initial"] == 0 and en["lost"] < 0
    text = " ".join(run_cli("run", "confined", "--param", "n=20", "--until", "0.5").stdout.split())
    assert f"energy gained {-en['lost']:.3g} J: contacts pushing apart; at most" in text
    assert "error" not in text


def test_the_energy_scale_says_what_it_is() -> None:
    traj = physstep.simulate("chain", "velocity-verlet", 0.001, 0.5)
    assert abs(traj.energy[0]) < 1e-20  # released from the height of its pivot
    assert traj.energy_scale_of == "the largest kinetic energy"
    assert traj.energy_scale == pytest.approx(float(np.max(traj.kinetic)))
    spring = physstep.simulate("spring", until=1.0)
    assert (spring.energy_scale, spring.energy_scale_of) == (1000.0, "|E0|")


# -- 17: messages ----------------------------------------------------------------------------


def test_huge_numbers_are_shown_with_an_exponent() -> None:
    r = run_cli("run", "spring", "--until", "1e308")
    assert r.returncode == 2
    assert r.stderr.startswith("physstep: error: invalid until = 1e308: ") and len(r.stderr) < 150


def test_levels_are_bounded_alike_in_the_cli_the_api_and_the_docs() -> None:
    from physstep.lab.order import MAX_LEVELS

    assert MAX_LEVELS == 20
    r = run_cli("order", "spring", "--method", "rk4", "--levels", "15", "--format", "json")
    assert r.returncode == 0, r.stderr
    assert len(json.loads(r.stdout)["runs"]) == 15
    r = run_cli("order", "spring", "--method", "rk4", "--levels", "21")
    assert r.returncode == 2 and "must be an integer from 2 to 20" in r.stderr
    assert "2 to 20" in (ROOT / "README.md").read_text()


@pytest.mark.parametrize(
    ("methods", "why"),
    [
        ("rk4,,heun", "an empty name between commas"),
        ("rk4,", "an empty name between commas"),
        ("rk4,rk4", "'rk4' is given twice"),
    ],
)
def test_malformed_method_lists_are_refused(methods: str, why: str) -> None:
    r = run_cli("compare", "spring", "--methods", methods, "--until", "1")
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr == f"physstep: error: invalid --methods '{methods}': {why}" + (
        " (each method is one row)\n" if "twice" in why else "; give a comma-separated list of methods\n"
    )


def test_the_lab_refuses_a_method_given_twice() -> None:
    with pytest.raises(ValueError, match=r"'rk4' given twice"):
        physstep.lab.compare("spring", ["rk4", "heun", "rk4"], until=1.0)


def test_a_scene_text_with_an_until_it_could_not_load_is_refused(tmp_path: Path) -> None:
    w = physstep.World.from_scene("spring")
    for bad in (float("nan"), float("inf"), -1.0):
        with pytest.raises(ValueError, match=r"^invalid until = .*: must be a finite number >= 0, s$"):
            physstep.scene_text(w, until=bad)
    path = tmp_path / "s.toml"
    path.write_text(physstep.scene_text(w, until=3.0))
    assert physstep.SceneFile(path).until == 3.0


def test_scene_file_errors_name_the_line_and_the_key(tmp_path: Path) -> None:
    path = tmp_path / "s.toml"
    path.write_text("# title\ndimension = 2\n\n# a comment\n\ndt = 0\n[[particles]]\nposition = [0.0, 0.0]\n")
    r = run_cli("run", str(path), "--until", "1")
    assert r.returncode == 2
    want = f"physstep: error: scene file {path}:6: dt: invalid dt = 0: must be a finite number > 0\n"
    assert r.stderr == want
    path.write_text("dimension = 2\ndt = 0.01\n[[particles]]\nposition = [99999999999999999999, 0]\n")
    assert physstep.load_scene(path).positions[0, 0] == 1e20


# -- 18: docs that were false ------------------------------------------------------------------


def test_the_collisions_doc_says_what_a_first_order_method_does_to_a_bounce() -> None:
    text = (ROOT / "docs" / "collisions.md").read_text()
    claim = re.search(r"the same ball loses (\d+)% of its energy in 10 s at dt = 1/120 s", text)
    assert claim, "docs/collisions.md states the first-order loss"
    assert "Under a\n  second-order method" in text or "second-order method" in text

    def bounce(method: str) -> float:
        w = physstep.World(2, method=method, dt=1 / 120)
        w.add_gravity([0.0, -9.81])
        w.add_walls([0.0, 0.0], [1.0, 2.0])
        w.add_ball([0.5, 1.0], [0.7, 0.0], 0.1, 1.0)
        e0 = w.energy()
        w.step(1200)
        return (w.energy() - e0) / e0

    assert round(-100 * bounce("symplectic-euler")) == int(claim.group(1))
    assert abs(bounce("velocity-verlet")) < 1e-12


def test_the_top_scene_is_described_as_the_slow_top_it_is() -> None:
    doc = physstep.scene("top")["doc"]
    assert doc.startswith("slow top") and "nodding from 17 to 85 degrees" in doc
    w = physstep.World.from_scene("top")
    tilts = []
    for _ in range(600):
        w.step(10)
        c = w.body_positions()[0]
        tilts.append(np.degrees(np.arccos(c[2] / np.linalg.norm(c))))
    assert round(min(tilts)) == 17 and round(max(tilts)) == 85


def test_the_readme_game_loop_runs() -> None:
    text = (ROOT / "README.md").read_text()
    block = re.search(r"### The world and the game loop\n\n```python\n(.*?)```", text, re.DOTALL)
    assert block
    namespace: dict = {}
    exec(compile(block.group(1), "README.md", "exec"), namespace)  # noqa: S102
    assert namespace["w"].time == pytest.approx(10.0, abs=1 / 120)


def test_no_doc_tells_to_install_physstep_from_an_index() -> None:
    for path in [ROOT / "README.md", *(ROOT / "docs").glob("*.md")]:
        assert "pip install 'physstep[demo]'" not in path.read_text(), path


def test_compare_says_where_the_energy_is_lost_by_design() -> None:
    r = run_cli("compare", "drag", "--methods", "rk4,backward-euler", "--until", "1", "--format", "json")
    assert r.returncode == 0, r.stderr
    rows = {row["method"]: row["energy_dissipation"] for row in json.loads(r.stdout)["rows"]}
    assert rows == {"rk4": "drag", "backward-euler": "drag; backward-euler damps by design"}
    res = physstep.lab.compare("spring", ["rk4", "implicit-midpoint"], until=1.0)
    assert [row.energy_dissipation for row in res.rows] == [None, None]
    text = run_cli("compare", "drag", "--methods", "rk4", "--until", "1").stdout
    assert "energy lost by design, not an error: rk4 (drag)" in " ".join(text.split())
