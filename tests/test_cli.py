"""The command line: the notes' tables, summaries, method listing and error contracts."""

from __future__ import annotations

import csv
import io
import json

import physstep
import pytest
from conftest import GOLDEN, run_cli

GOLDEN_RUNS = [
    ("spring_euler_dt1.csv", "explicit-euler", "1"),
    ("spring_euler_dt0.5.csv", "explicit-euler", "0.5"),
    ("spring_euler_dt0.25.csv", "explicit-euler", "0.25"),
    ("spring_symplectic_dt1.csv", "symplectic-euler", "1"),
    ("spring_verlet_dt1.csv", "verlet", "1"),
]


def _norm(s: str) -> str:
    return "0.0" if s == "-0.0" else s


@pytest.mark.parametrize(("file", "method", "dt"), GOLDEN_RUNS)
def test_table_reproduces_the_notes_row_for_row(file: str, method: str, dt: str) -> None:
    want = list(csv.reader((GOLDEN / file).read_text().splitlines()))
    until = want[-1][0]
    res = run_cli("table", "spring", "--method", method, "--dt", dt, "--until", until)
    assert res.returncode == 0, res.stderr
    got = [line.split() for line in res.stdout.splitlines()]
    assert got[0] == ["t", "x", "v", "a"]
    assert len(got) == len(want)
    for g, w in zip(got[1:], want[1:], strict=True):
        assert float(g[0]) == float(w[0])
        assert [_norm(c) for c in g[1:]] == [_norm(c) for c in w[1:]], f"{file} at t = {w[0]}"


def test_table_csv_has_full_precision_and_json_has_rows() -> None:
    res = run_cli(
        "table", "spring", "--method", "explicit-euler", "--dt", "0.25", "--until", "1", "--format", "csv"
    )
    rows = list(csv.reader(io.StringIO(res.stdout)))
    assert rows[0] == ["t", "x", "v", "a"]
    assert rows[2] == ["0.25", "20.0", "-2.5", "-10.0"]
    assert rows[3][1] == "19.375"  # printed 19.4 in the notes
    res = run_cli("table", "spring", "--method", "rk4", "--dt", "1", "--until", "1", "--format", "json")
    data = json.loads(res.stdout)
    assert data["columns"] == ["t", "x", "v", "a"]
    assert len(data["rows"]) == 2


def test_table_stages_follow_the_notes_layout() -> None:
    res = run_cli(
        "table", "spring", "--method", "midpoint", "--dt", "1", "--until", "2", "--stages", "--format", "csv"
    )
    rows = list(csv.reader(io.StringIO(res.stdout)))
    assert rows[0] == ["t", "x", "v", "a", "stage"]
    assert [r[-1] for r in rows[1:]] == ["state", "half", "state", "half", "state"]
    # half row of the first step: x + v dt/2, v + a dt/2, a there
    assert rows[2][:4] == ["0.5", "20.0", "-5.0", "-10.0"]
    res = run_cli(
        "table", "spring", "--method", "rk4", "--dt", "1", "--until", "1", "--stages", "--format", "csv"
    )
    rows = list(csv.reader(io.StringIO(res.stdout)))
    assert [r[-1] for r in rows[1:]] == ["state", "xa", "xb", "xc", "state"]
    # The first step's evaluation points are those of the notes' RK4 table.
    assert rows[2][:4] == ["0.5", "20.0", "-5.0", "-10.0"]
    assert rows[3][:4] == ["0.5", "17.5", "-5.0", "-8.75"]
    assert rows[4][:4] == ["1.0", "15.0", "-8.75", "-7.5"]


def test_run_json_summary() -> None:
    res = run_cli(
        "run", "spring", "--method", "velocity-verlet", "--dt", "0.1", "--until", "10", "--format", "json"
    )
    assert res.returncode == 0, res.stderr
    s = json.loads(res.stdout)
    for key in ("scene", "method", "dt", "steps", "t", "final", "energy", "error"):
        assert key in s
    assert s["steps"] == 100
    assert set(s["energy"]) >= {"initial", "final", "max_rel_error"}
    assert s["energy"]["initial"] == 1000.0
    assert 0 < s["energy"]["max_rel_error"] < 0.01
    assert 0 < s["error"]["final_position"] < 0.1


def test_run_writes_the_trajectory(tmp_path) -> None:
    out = tmp_path / "traj.csv"
    res = run_cli("run", "orbit", "--method", "rk4", "--dt", "0.1", "--until", "1", "--out", str(out))
    assert res.returncode == 0, res.stderr
    rows = list(csv.reader(out.read_text().splitlines()))
    assert rows[0][:3] == ["t", "x0", "x1"]
    assert len(rows) == 12


def test_methods_lists_every_registered_method() -> None:
    res = run_cli("methods", "--format", "json")
    listed = [m["name"] for m in json.loads(res.stdout)]
    assert listed == [m.name for m in physstep.methods()]
    assert len(listed) == 15
    text = run_cli("methods").stdout
    for m in physstep.methods():
        assert m.name in text
        assert m.doc, f"{m.name} has no doc"


SOLVERS = ["soft-step", "pgs", "pgs-ngs", "soft-pgs", "tgs-sticky", "jacobi", "xpbd", "projection"]


def test_solvers_lists_every_contact_solver_with_its_passes() -> None:
    rows = json.loads(run_cli("solvers", "--format", "json").stdout)
    assert [r["name"] for r in rows] == list(physstep.contact_solvers()) == SOLVERS
    assert [r["summary"] for r in rows] == list(physstep.contact_solvers().values())
    assert all("substeps x solver_iterations" in r["passes"] for r in rows)
    assert [s.name for s in physstep.solvers()] == SOLVERS
    families = {"velocity", "velocity + position", "position + velocity", "position"}
    assert {r["family"] for r in rows} == families
    assert [r["name"] for r in rows if "position" in r["family"]] == ["pgs-ngs", "xpbd", "projection"]
    text = run_cli("solvers").stdout
    assert "soft-step" in text and "pgs-ngs" in text and "Baumgarte" in text


@pytest.mark.parametrize("method", [m.name for m in physstep.methods()])
def test_every_method_is_reachable_from_python_and_the_cli(method: str) -> None:
    traj = physstep.simulate("spring", method, dt=0.5, until=2.0)
    assert traj.steps == 4 and traj.method == method
    res = run_cli("run", "spring", "--method", method, "--dt", "0.5", "--until", "2", "--format", "json")
    assert res.returncode == 0, res.stderr
    assert json.loads(res.stdout)["final"]["x"] == traj.x[-1].tolist()


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["table", "spring", "--dt", "0", "--until", "2"], "invalid --dt '0': must be a finite number > 0"),
        (["table", "spring", "--dt", "-1", "--until", "2"], "invalid --dt '-1'"),
        (["table", "spring", "--dt", "nan", "--until", "2"], "invalid --dt 'nan'"),
        (["run", "spring", "--dt", "0.1", "--until", "inf"], "invalid --until 'inf'"),
        (["run", "spring", "--param", "m=0"], "invalid m = 0"),
        (["run", "spring", "--param", "m=-3"], "invalid m = -3"),
        (["run", "spring", "--param", "x0=nan"], "invalid --param 'x0=nan'"),
        (["run", "spring", "--method", "nope"], "unknown method 'nope'; valid methods: explicit-euler"),
        (["run", "nowhere"], "unknown scene 'nowhere'; valid scenes: spring"),
        (["run", "spring", "--param", "q=1"], "unknown param 'q'; valid params: m, k, c, x0, v0"),
        (["run", "spring", "--param", "k"], "invalid --param 'k': must be NAME=VALUE"),
        (["run", "spring", "--param", "k=abc"], "invalid --param 'k=abc'"),
        (["run", "spring", "--dt", "abc"], "invalid --dt 'abc': not a number"),
        (
            ["run", "nbody", "--until", "1e5"],
            "invalid until = 100000: must be such that the recording fits in memory: 100000002 rows",
        ),
        (["run", "spring", "--every", "0"], "invalid --every '0'"),
    ],
)
def test_bad_input_is_one_line_and_status_2(args: list[str], needle: str) -> None:
    res = run_cli(*args)
    assert res.returncode == 2
    assert res.stdout == ""
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1, res.stderr
    assert needle in lines[0]
    assert "Traceback" not in res.stderr


def test_readme_method_table_is_generated_from_the_registry() -> None:
    import subprocess
    import sys

    from conftest import ROOT

    res = subprocess.run(
        [sys.executable, str(ROOT / "scripts" / "readme_methods.py"), "--check", str(ROOT / "README.md")],
        capture_output=True,
        text=True,
    )
    assert res.returncode == 0, res.stdout
    readme = (ROOT / "README.md").read_text()
    for m in physstep.methods():
        assert f"| `{m.name}` | {m.order} |" in readme


def test_version_prints_the_package_version_and_exits_0(capsys) -> None:
    from physstep import cli

    with pytest.raises(SystemExit) as exit_:
        cli.main(["--version"])
    assert exit_.value.code == 0
    assert capsys.readouterr().out == f"physstep {physstep.__version__}\n"
    res = run_cli("--version")
    assert (res.returncode, res.stdout, res.stderr) == (0, f"physstep {physstep.__version__}\n", "")


# -- rigid bodies --------------------------------------------------------------------------


def test_run_racket_json_reports_an_exact_angular_momentum() -> None:
    res = run_cli("run", "racket", "--until", "120", "--format", "json")
    assert res.returncode == 0, res.stderr
    s = json.loads(res.stdout)
    assert s["method"] == "symplectic-euler" and s["steps"] == 14400
    ang = s["angular_momentum"]
    assert set(ang) == {"initial", "final", "max_rel_error"}
    assert ang["max_rel_error"] < 1e-12
    assert abs(ang["initial"][1] - 4.0) < 1e-3  # 2 rad/s about the intermediate axis (moment 2)
    assert 0 < s["energy"]["max_rel_error"] < 1e-5  # bounded, not exact: L's column is its own
    text = run_cli("run", "racket", "--until", "10")
    assert text.returncode == 0 and "angular momentum" in text.stdout


@pytest.mark.parametrize("command", ["run", "table"])
def test_verlet_on_a_body_scene_is_one_line_and_status_2(command: str) -> None:
    res = run_cli(command, "racket", "--method", "verlet", "--until", "1")
    assert res.returncode == 2, res.stderr
    lines = res.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("physstep: error: ") and "'verlet'" in lines[0]
    assert "Traceback" not in res.stderr and res.stdout == ""


def test_compare_top_with_two_methods() -> None:
    res = run_cli("compare", "top", "--methods", "rk4,velocity-verlet", "--until", "0.5")
    assert res.returncode == 0, res.stderr
    assert "max |dL|/|L|" in res.stdout and "final spin error" in res.stdout
    rows = [line for line in res.stdout.splitlines() if line.startswith("│")]
    assert [r.split("│")[1].strip() for r in rows] == ["rk4", "velocity-verlet"]
    res = run_cli("compare", "top", "--methods", "rk4,velocity-verlet", "--until", "0.5", "--format", "json")
    assert res.returncode == 0, res.stderr
    data = json.loads(res.stdout)
    assert data["kind"] == "bodies" and data["steps"] == 600 and data["skipped"] == []
    for r in data["rows"]:
        assert r["diverged"] is None and r["energy_max_rel_error"] < 1e-5
        # gravity turns the top's L: the column measures that change, the same for both
        assert 0.1 < r["angular_momentum_max_rel_error"] < 10
    a, b = (r["angular_momentum_max_rel_error"] for r in data["rows"])
    assert a == pytest.approx(b, rel=1e-3)


def test_compare_racket_names_verlet_in_one_line() -> None:
    res = run_cli("compare", "racket", "--methods", "rk4,verlet", "--until", "1")
    assert res.returncode == 2
    lines = res.stderr.splitlines()
    assert len(lines) == 1 and "'verlet'" in lines[0] and "Traceback" not in res.stderr


def test_run_table_cuts_a_long_state_and_json_keeps_it() -> None:
    args = ("run", "cloth", "--until", "0.05")
    res = run_cli(*args)
    assert res.returncode == 0, res.stderr
    assert "(432 numbers in all: --format json lists them)" in res.stdout
    data = json.loads(run_cli(*args, "--format", "json").stdout)
    assert len(data["final"]["x"]) == 432
    short = run_cli("run", "spring", "--until", "1").stdout
    assert "numbers in all" not in short
