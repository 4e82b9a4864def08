"""The solver lab: contact solvers side by side (lab.compare_solvers, compare --solvers, the table)."""

from __future__ import annotations

import importlib.util
import json
import math
import re
from pathlib import Path

import physstep
import pytest
from conftest import run_cli
from physstep import lab

ROOT = Path(__file__).resolve().parents[1]
SOLVERS = list(physstep.contact_solvers())


def test_every_solver_makes_the_same_passes_a_step_counted_as_they_run() -> None:
    w = physstep.World.from_scene("single-box")
    assert w.contact_passes == 0
    w.step(1)
    assert w.contact_passes == 2 * w.substeps * w.solver_iterations == 16
    res = lab.compare_solvers("single-box", "all", until=0.5, substeps=2, iterations=3)
    assert [r.solver for r in res.rows] == SOLVERS and len(SOLVERS) >= 6
    assert (res.substeps, res.iterations) == (2, 3)
    assert all(r.passes_per_step == 12 for r in res.rows), [r.passes_per_step for r in res.rows]


def test_a_dropped_box_holds_under_every_solver_and_the_result_is_typed() -> None:
    res = lab.compare_solvers("single-box", until=3.0)
    assert not res.standing and res.tracked == 1
    for r in res.rows:
        # Dropped 1 m onto the ground: it moved about a metre, barely into the ground, at rest.
        assert r.verdict == "holds", r
        assert 0.9 < r.drift < 1.1 and r.max_penetration < 0.005 and r.jitter < 1e-6, r
        assert r.energy_change is not None and r.energy_change < 0  # contacts settle
        assert r.joint_error is None and r.friction_error is None and r.diverged is None
    d = res.to_dict()
    assert d["rows"][0]["solver"] == "soft-step" and "joint_error" not in d["rows"][0]
    assert json.loads(json.dumps(d)) == d
    assert res.row("pgs").solver == "pgs"


def test_the_friction_test_meets_the_closed_form_under_every_solver() -> None:
    # Below the friction angle: the slide g (sin a - mu cos a) t^2 / 2 within 1% over the
    # scene's 5 s. A one-step solver's symplectic Euler slides a dt^2 n (n + 1) / 2 in n
    # steps, 1/n farther (0.33% at 5 s, 0.83% at 2 s); the projection, which settles 1.2 mm
    # into its first second, 0.71% at 5 s (1.8% at 2 s).
    res = lab.compare_solvers("ramp", params={"friction": 0.3})
    for r in res.rows:
        assert r.friction_error is not None and abs(r.friction_error) < 0.01, r
        assert r.verdict == "holds", r
    # Above it the box stands.
    res = lab.compare_solvers("ramp", until=2.0)
    assert all(r.friction_error is None and r.verdict == "stands" for r in res.rows), res.rows


def test_the_soft_step_stands_the_pyramid_where_pgs_at_equal_cost_sags() -> None:
    res = lab.compare_solvers("pyramid", ["soft-step", "pgs"])
    soft, pgs = res.row("soft-step"), res.row("pgs")
    assert res.standing and soft.passes_per_step == pgs.passes_per_step == 16
    assert soft.verdict == "stands" and soft.drift < 0.01 and soft.max_penetration < 0.01, soft
    assert pgs.verdict == "falls" and pgs.drift > 5 * soft.drift, pgs


def test_joint_error_is_measured_on_jointed_scenes() -> None:
    # The soft step's joints at its substeps' rate hold the planks within a centimetre; a
    # one-step solver's soft joints (Jacobi's: at most half the step's rate, 30 Hz at 60 Hz)
    # open several times wider (14 mm, measured).
    res = lab.compare_solvers("bridge", ["soft-step", "jacobi"], until=2.0)
    soft, jacobi = res.row("soft-step").joint_error, res.row("jacobi").joint_error
    assert soft is not None and jacobi is not None
    assert 0 < soft < 0.01 < jacobi and jacobi > 2 * soft, (soft, jacobi)


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"solvers": ["soft-step", "nope"]}, "unknown contact solver 'nope'"),
        ({"solvers": []}, "invalid solvers = []"),
        ({"substeps": 0}, "invalid substeps = 0"),
        ({"iterations": 2.5}, "invalid iterations = 2.5"),
        ({"until": -1.0}, "invalid until = -1.0"),
        ({"params": {"height": -1.0}}, "invalid height = -1"),
    ],
)
def test_bad_input_to_the_solver_lab_names_the_field(kwargs: dict, field: str) -> None:
    with pytest.raises(ValueError, match="^" + re.escape(field)):
        lab.compare_solvers("single-box", **({"until": 0.1} | kwargs))


def test_the_solver_lab_refuses_a_scene_without_solids_and_compare_takes_methods_or_solvers() -> None:
    with pytest.raises(ValueError, match="invalid scene = 'spring': it has no solids"):
        lab.compare_solvers("spring")
    with pytest.raises(ValueError, match="compare methods or solvers, not both"):
        lab.compare("single-box", ["rk4"], solvers="all")
    with pytest.raises(ValueError, match="invalid substeps = 2: it applies with solvers= only"):
        lab.compare("spring", ["rk4"], substeps=2)
    res = lab.compare("single-box", until=0.2, solvers=["pgs"])
    assert isinstance(res, lab.SolverCompareResult) and res.rows[0].solver == "pgs"


def test_compare_solvers_on_the_command_line() -> None:
    out = run_cli(
        "compare", "single-box", "--solvers", "soft-step,tgs-sticky", "--until", "1", "--format", "json"
    )
    assert out.returncode == 0, out.stderr
    res = json.loads(out.stdout)
    assert [r["solver"] for r in res["rows"]] == ["soft-step", "tgs-sticky"]
    assert all(r["passes_per_step"] == 16 and math.isfinite(r["ms_per_step"]) for r in res["rows"])
    text = run_cli("compare", "single-box", "--solvers", "all", "--until", "0.5", "--substeps", "2")
    assert text.returncode == 0, text.stderr
    assert "2 substeps x 1 iterations" in text.stdout and "holds" in text.stdout
    for argv, msg in [
        (["--solvers", "pgs,nope"], "unknown contact solver 'nope'"),
        (["--solvers", "pgs,pgs"], "invalid --solvers 'pgs,pgs'"),
        (["--substeps", "2"], "invalid --substeps 2: it applies with --solvers only"),
        (["--solvers", "pgs", "--substeps", "0"], "invalid --substeps '0'"),
        (["--solvers", "pgs", "--methods", "rk4"], "invalid --methods with --solvers"),
    ]:
        bad = run_cli("compare", "single-box", "--until", "0.1", *argv)
        assert bad.returncode == 2 and msg in bad.stderr and "Traceback" not in bad.stderr, (argv, bad.stderr)
        assert len(bad.stderr.strip().splitlines()) == 1, bad.stderr


def test_the_table_script_writes_every_solver_on_the_scenes_asked(tmp_path: Path) -> None:
    spec = importlib.util.spec_from_file_location("solver_table", ROOT / "scripts" / "solver_table.py")
    assert spec and spec.loader
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    out = tmp_path / "solvers.md"
    assert script.main(["--scenes", "single-box,ramp", "--until", "5", "--out", str(out)]) == 0
    text = out.read_text()
    assert all(f"`{s}`" in text for s in SOLVERS)
    rows = [
        line for line in text.splitlines() if line.startswith("| single-box") or line.startswith("| ramp")
    ]
    assert [r.split(" |")[0] for r in rows] == ["| single-box", "| ramp", "| ramp friction=0.3"]
    assert all(r.count("**holds**") + r.count("**stands**") == len(SOLVERS) for r in rows), rows
    assert (
        "passes over the contacts a step" in text
        and "| solver | stands | sags | falls | holds | drifts | explodes |" in text
    )
    # Written whole or not at all: a directory that does not exist refuses before any run.
    with pytest.raises(Exception, match="--out"):
        script.main(["--scenes", "single-box", "--out", str(tmp_path / "missing" / "x.md")])


def test_substeps_beat_iterations_at_equal_cost_the_avian_question() -> None:
    res = lab.sweep_solvers("stack", ["soft-step", "pgs"], until=3.0)
    assert [(r.solver, r.substeps, r.iterations) for r in res.rows] == [
        (s, n, k) for s in ("soft-step", "pgs") for n, k in lab.solvers.DEFAULT_SPLITS
    ]
    assert all(r.passes_per_step == 16 for r in res.rows)
    soft = [r for r in res.rows if r.solver == "soft-step"]
    # The soft step: the more of its passes are substeps, the stiffer its contacts and the
    # less the stack sinks (8 x 1 stands, 1 x 8 falls).
    drifts = [r.drift for r in soft]
    assert drifts == sorted(drifts) and drifts[-1] > 10 * drifts[0], drifts
    assert soft[0].verdict == "stands" and soft[-1].verdict == "falls"
    # PGS lays out 2 x substeps x iterations passes in one step: every split is the same run.
    pgs = {r.drift for r in res.rows if r.solver == "pgs"}
    assert len(pgs) == 1, pgs


@pytest.mark.parametrize(
    ("splits", "message"),
    [([], "invalid splits = []"), ([(0, 1)], "invalid substeps = 0"), ([(1,)], "invalid splits entry (1,)")],
)
def test_a_bad_split_names_the_field(splits: list, message: str) -> None:
    with pytest.raises(ValueError, match="^" + re.escape(message)):
        lab.sweep_solvers("single-box", "pgs", splits, until=0.1)


def test_sweep_solvers_on_the_command_line_with_a_plot(tmp_path: Path) -> None:
    png = tmp_path / "sweep.png"
    out = run_cli(
        "sweep", "single-box", "--solvers", "pgs,soft-step", "--splits", "2x1,1x2", "--until", "0.5",
        "--format", "json", "--plot", str(png),
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    rows = json.loads(out.stdout)["rows"]
    assert [(r["solver"], r["substeps"], r["iterations"], r["passes_per_step"]) for r in rows] == [
        ("pgs", 2, 1, 4), ("pgs", 1, 2, 4), ("soft-step", 2, 1, 4), ("soft-step", 1, 2, 4),
    ]  # fmt: skip
    assert png.stat().st_size > 10_000
    text = run_cli("sweep", "single-box", "--solvers", "pgs", "--splits", "1x1", "--until", "0.1").stdout
    assert text.splitlines()[0].startswith("solver,substeps,iterations,passes_per_step")
    for argv, msg in [
        (["--solvers", "pgs", "--splits", "8y1"], "invalid --splits '8y1'"),
        (["--splits", "2x1"], "invalid --splits: it applies with --solvers only"),
        ([], "invalid sweep: --dts is required"),
        (["--solvers", "pgs", "--dts", "0.1"], "invalid --dts with --solvers"),
    ]:
        bad = run_cli("sweep", "single-box", "--until", "0.1", *argv)
        assert bad.returncode == 2 and msg in bad.stderr and len(bad.stderr.strip().splitlines()) == 1, (
            bad.stderr
        )


def test_xpbd_holds_the_chain_with_a_ball_a_hundred_times_a_link_closer_than_the_soft_step() -> None:
    # ball-chain: 30 capsule links (0.2366 m^2 each) and a ball of radius 2.744 m (23.65 m^2,
    # the same density): 1:100. Measured over 10 s: xpbd's joints open at most 18 mm (each
    # hinge's anchors brought together through the point's whole effective mass), the soft
    # step's 29 mm, the one-step solvers' 46-158 mm.
    res = lab.compare_solvers("ball-chain", ["soft-step", "xpbd", "pgs"], params={"radius": 2.744})
    soft, xpbd, pgs = (res.row(s).joint_error for s in ("soft-step", "xpbd", "pgs"))
    assert soft is not None and xpbd is not None and pgs is not None
    assert xpbd < 0.025 and soft < 0.04 and xpbd < soft < pgs, (xpbd, soft, pgs)
