"""Numbers the command line prints: exact rounding at any size, never NaN or Infinity,
the steps and final time actually run, and honest timings."""

from __future__ import annotations

import csv
import dataclasses
import io
import json
import math
import statistics
from decimal import Decimal, localcontext

import numpy as np
import physstep
import pytest
from conftest import run_cli
from physstep import cli, lab
from physstep.cli import basic, output


def _strict(text: str):
    def reject(token: str):
        raise AssertionError(f"non-standard JSON token {token}")

    return json.loads(text, parse_constant=reject)


# -- rounding ----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("value", "places", "want"),
    [
        (2.5, 0, "3"),
        (-2.5, 0, "-3"),
        (0.125, 2, "0.13"),  # exact in binary: a true tie, away from zero
        (1.005, 2, "1.00"),  # the double is 1.00499999999999989...
        (-0.0, 0, "0"),
        (-0.04, 1, "0.0"),
        (1e27, 1, "1000000000000000013287555072.0"),
        (-3.5e300, 0, str(int(-3.5e300))),
        (1.7976931348623157e308, 17, f"{int(1.7976931348623157e308)}.{'0' * 17}"),
        (5e-324, 17, "0.00000000000000000"),
        (0.1, 30, "0.100000000000000005551115123126"),
    ],
)
def test_round_half_away_is_exact_for_any_double(value: float, places: int, want: str) -> None:
    assert output.round_half_away(value, places) == want


def test_round_half_away_refuses_non_finite_values() -> None:
    for bad in (float("nan"), float("inf"), -float("inf")):
        with pytest.raises(ValueError, match="not a finite number"):
            output.round_half_away(bad, 1)


def test_table_prints_huge_values_exactly() -> None:
    # explicit Euler on the spring grows past 1e27 by t = 300 s
    res = run_cli("table", "spring", "--method", "explicit-euler", "--dt", "1", "--until", "300")
    assert res.returncode == 0, res.stderr
    traj = physstep.simulate("spring", "explicit-euler", 1.0, 300.0)
    assert abs(traj.x[-1, 0]) > 1e27
    last = res.stdout.splitlines()[-1].split()
    assert last[0] == "300"
    want = traj.x[-1].tolist() + traj.v[-1].tolist() + traj.a[-1].tolist()
    with localcontext() as ctx:
        ctx.prec = 100
        assert [Decimal(c) for c in last[1:]] == [Decimal(w).quantize(Decimal("0.1")) for w in want]


@pytest.mark.parametrize(
    ("value", "ok"), [("0", True), ("17", True), ("18", False), ("-1", False), ("x", False)]
)
def test_decimals_range(value: str, ok: bool) -> None:
    res = run_cli("table", "spring", "--dt", "1", "--until", "1", "--decimals", value)
    if ok:
        assert res.returncode == 0, res.stderr
        assert res.stdout.splitlines()[1].split()[1] == "20" + (
            "." + "0" * int(value) if value != "0" else ""
        )
    else:
        assert res.returncode == 2
        assert res.stderr.startswith(f"physstep: error: invalid --decimals '{value}': ")
        assert len(res.stderr.splitlines()) == 1


# -- no NaN or Infinity in any output ----------------------------------------------------


@pytest.fixture
def poisoned(monkeypatch):
    """physstep.simulate returning a run whose energy (row 2) and x (row 3) are NaN / inf."""
    real = physstep.simulate

    def simulate(*args, **kwargs):
        traj = real(*args, **kwargs)
        energy, x = traj.energy.copy(), traj.x.copy()
        if len(energy) > 3:
            energy[2] = np.nan
            x[3, 0] = np.inf
        return dataclasses.replace(traj, energy=energy, x=x)

    monkeypatch.setattr(physstep, "simulate", simulate)


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["run", "spring", "--format", "json"], "energy.max_rel_error is not finite (nan)"),
        (["run", "spring"], "energy.max_rel_error is not finite (nan)"),
        (["table", "spring", "--dt", "1", "--until", "5"], "x at t = 3 s is not finite (inf)"),
        (["table", "spring", "--dt", "1", "--until", "5", "--format", "csv"], "x at t = 3 s is not finite"),
        (["table", "spring", "--dt", "1", "--until", "5", "--format", "json"], "x at t = 3 s is not finite"),
    ],
)
def test_non_finite_numbers_are_a_failure_not_output(poisoned, capsys, args, needle) -> None:
    assert cli.main(args) == 1
    out, err = capsys.readouterr()
    assert out == ""
    assert len(err.splitlines()) == 1 and needle in err, err


def test_non_finite_trajectory_is_not_written(poisoned, capsys, tmp_path) -> None:
    out = tmp_path / "t.csv"
    out.write_text("old\n")
    assert cli.main(["run", "spring", "--out", str(out)]) == 1
    assert out.read_text() == "old\n"


@pytest.mark.parametrize("fmt", ["json", "text"])
def test_lab_output_refuses_non_finite_fields(monkeypatch, capsys, fmt) -> None:
    real = lab.compare

    def compare(*args, **kwargs):
        res = real(*args, **kwargs)
        rows = list(res.rows)
        rows[1] = dataclasses.replace(rows[1], energy_drift=float("nan"))
        return dataclasses.replace(res, rows=tuple(rows))

    monkeypatch.setattr(lab, "compare", compare)
    args = ["compare", "spring", "--methods", "rk4,heun", "--dt", "0.5", "--until", "2", "--format", fmt]
    assert cli.main(args) == 1
    out, err = capsys.readouterr()
    assert out == ""
    assert err == "physstep: rows[1].energy_drift is not finite (nan): not printed\n"


def test_order_prints_diverged_runs_without_infinity(monkeypatch, capsys) -> None:
    real = lab.order

    def order(*args, **kwargs):
        res = real(*args, **kwargs)
        runs = list(res.runs)
        runs[0] = dataclasses.replace(runs[0], error=float("inf"))  # how the lab marks a run that diverged
        return dataclasses.replace(res, runs=tuple(runs))

    monkeypatch.setattr(lab, "order", order)
    assert cli.main(["order", "spring", "--method", "rk4", "--levels", "3", "--format", "json"]) == 0
    data = _strict(capsys.readouterr().out)
    assert data["runs"][0]["error"] is None and data["runs"][0]["diverged"] is True
    assert cli.main(["order", "spring", "--method", "rk4", "--levels", "3"]) == 0
    out = capsys.readouterr().out
    assert "diverged" in out and "inf" not in out


def test_dump_names_the_nested_field() -> None:
    with pytest.raises(output.NotFiniteError, match=r"rows\[0\]\.error is not finite \(inf\)"):
        output.dump({"rows": [{"error": float("inf")}]})
    assert output.dump({"a": [1, 2.5, None]}) == json.dumps({"a": [1, 2.5, None]}, indent=2)


def test_sweep_json_is_strict_with_diverged_rows() -> None:
    res = run_cli("sweep", "spring", "--methods", "explicit-euler,rk4", "--dts", "3,0.1", "--until", "1000",
                  "--format", "json")  # fmt: skip
    assert res.returncode == 0, res.stderr
    rows = _strict(res.stdout)["rows"]
    assert any(r["diverged"] for r in rows)


# -- what was actually run ---------------------------------------------------------------

NOTE = "until 18.85 s requested: 188 steps of 0.1 s reach t = 18.8 s"
ORBIT = ["orbit", "--dt", "0.1", "--until", "18.85"]


def test_compare_says_where_the_run_ended() -> None:
    res = run_cli("compare", *ORBIT, "--methods", "rk4")
    assert res.returncode == 0, res.stderr
    assert NOTE in res.stdout and "until = 18.85" not in res.stdout
    data = _strict(run_cli("compare", *ORBIT, "--methods", "rk4", "--format", "json").stdout)
    assert data["steps"] == 188 and data["t_end"] == pytest.approx(18.8)
    assert data.get("until_requested", data["until"]) == 18.85
    whole = run_cli("compare", "orbit", "--dt", "0.1", "--until", "18.8", "--methods", "rk4").stdout
    assert "requested" not in whole and "188 steps" in whole


def test_run_says_where_the_run_ended() -> None:
    res = run_cli("run", *ORBIT)
    assert res.returncode == 0, res.stderr
    assert NOTE in res.stdout
    data = _strict(run_cli("run", *ORBIT, "--format", "json").stdout)
    assert data["until"] == 18.85 and data["steps"] == 188 and data["t"] == pytest.approx(18.8)
    assert "requested" not in run_cli("run", "orbit", "--dt", "0.1", "--until", "18.8").stdout


def test_table_says_where_the_run_ended() -> None:
    res = run_cli("table", *ORBIT)
    assert res.stdout.splitlines()[-1] == f"note: {NOTE}"
    data = _strict(run_cli("table", *ORBIT, "--format", "json").stdout)
    assert data["until"] == 18.85 and data["steps"] == 188 and data["t_end"] == pytest.approx(18.8)
    rows = list(csv.reader(io.StringIO(run_cli("table", *ORBIT, "--format", "csv").stdout)))
    assert float(rows[-1][0]) == pytest.approx(18.8)


def test_sweep_rows_say_where_each_run_ended() -> None:
    res = run_cli("sweep", "orbit", "--methods", "rk4", "--dts", "0.1,0.05", "--until", "18.85")
    rows = list(csv.DictReader(io.StringIO(res.stdout)))
    assert [float(r["t_end"]) for r in rows] == pytest.approx([18.8, 18.85])
    assert [int(r["steps"]) for r in rows] == [188, 377]


@pytest.mark.parametrize(("min_s", "runs", "said"), [(math.inf, 5, "median of 5 runs"), (0.0, 1, "one run")])
def test_run_ns_per_step_is_the_median_of_five_runs_when_the_first_is_short(
    monkeypatch, capsys, min_s: float, runs: int, said: str
) -> None:
    # How many runs follows from the first run's time against TIMING_MIN_S: the bound is set
    # above (inf) or below (0) any run's time, so the count is fixed.
    monkeypatch.setattr(basic, "TIMING_MIN_S", min_s)
    monkeypatch.setenv("COLUMNS", "200")
    timed: list[float] = []
    real = physstep.simulate

    def simulate(*args, **kwargs):
        traj = real(*args, **kwargs)
        timed.append(traj.ns_per_step)
        return traj

    monkeypatch.setattr(physstep, "simulate", simulate)
    assert cli.main(["run", "spring", "--dt", "0.1", "--until", "1", "--format", "json"]) == 0
    data = _strict(capsys.readouterr().out)
    assert data["ns_per_step_runs"] == runs == len(timed)
    assert data["ns_per_step"] == statistics.median(timed) > 0
    assert cli.main(["run", "spring", "--dt", "0.1", "--until", "1"]) == 0
    assert f"ns/step ({said})" in capsys.readouterr().out
