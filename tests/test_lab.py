"""The integrator lab: observed orders, stability limits, compare/sweep data and the CLI."""

from __future__ import annotations

import csv
import io
import json
import math

import physstep
import pytest
from conftest import run_cli
from physstep import lab

METHODS = [m.name for m in physstep.methods()]


# -- order -----------------------------------------------------------------------------


@pytest.mark.parametrize("scene", ["spring", "orbit"])
@pytest.mark.parametrize("method", METHODS)
def test_observed_order_matches_the_registry(scene: str, method: str) -> None:
    res = lab.order(scene, method, levels=4)
    info = physstep.method(method).order
    assert res["order"] is not None, res
    assert abs(res["order"] - info) < 0.15, (res["order"], info, res["runs"])
    assert [r["steps"] % 2 for r in res["runs"]] == [0] * len(res["runs"])  # even step counts
    assert res["error_against"] == "exact solution"


def test_order_without_exact_solution_uses_the_reference() -> None:
    res = lab.order("pendulum", "velocity-verlet", levels=4)
    assert res["error_against"].startswith("reference: rk4 at dt/16")
    assert abs(res["order"] - 2) < 0.15


def test_order_of_a_method_exact_on_the_scene_is_none() -> None:
    res = lab.order("projectile", "velocity-verlet", levels=3)
    assert res["order"] is None and "exact" in res["note"]


# -- stability -------------------------------------------------------------------------

# The undamped spring x'' = -omega^2 x, omega = sqrt(k/m) = sqrt(5/10) = sqrt(0.5). With
# z = i omega dt (y = omega dt) one step multiplies the state by a matrix whose eigenvalues
# are R(z) for the one-stage-map methods (Hairer, Lubich & Wanner, "Geometric Numerical
# Integration", ch. I.1 and VI; Hairer & Wanner, "Solving ODEs II", ch. IV.2):
# - explicit Euler R = 1 + z: |R|^2 = 1 + y^2 > 1 for every dt > 0       -> dt_max = 0
# - midpoint (RK2) and Heun: R = 1 + z + z^2/2, |R|^2 = 1 + y^4/4 > 1    -> dt_max = 0
# - classic RK4: R = 1 + z + ... + z^4/24, |R|^2 = 1 - y^6/72 + y^8/576 <= 1 iff
#   y^2 <= 8, i.e. y <= 2 sqrt(2)                                        -> 2 sqrt(2)/omega
# - symplectic Euler (both orders), Stormer-Verlet (one step = symplectic Euler with its
#   start), velocity Verlet and leapfrog: det M = 1, trace M = 2 - y^2, eigenvalues on the
#   unit circle iff |trace| <= 2, i.e. y <= 2 (HLW I.5, "Geometric Numerical Integration
#   illustrated by the Stormer-Verlet method", Hairer, Lubich & Wanner, Acta Numerica 2003)
#                                                                        -> 2/omega
# - predictor-corrector (explicit Euler fed into backward Euler: y += f(y + f dt) dt):
#   R = 1 + z + z^2, |R|^2 = (1 - y^2)^2 + y^2 = 1 - y^2 + y^4 <= 1 iff y <= 1 -> 1/omega
# - backward Euler R = 1/(1 - z), |R| < 1, and implicit midpoint R = (1 + z/2)/(1 - z/2),
#   |R| = 1: A-stable, stable at every dt (Hairer & Wanner II, IV.3)    -> None (no limit)
OMEGA = math.sqrt(0.5)
SPRING_LIMITS = {
    "explicit-euler": 0.0,
    "midpoint": 0.0,
    "heun": 0.0,
    "symplectic-euler": 2 / OMEGA,
    "symplectic-euler-x": 2 / OMEGA,
    "verlet": 2 / OMEGA,
    "velocity-verlet": 2 / OMEGA,
    "leapfrog": 2 / OMEGA,
    "rk4": 2 * math.sqrt(2) / OMEGA,
    "predictor-corrector": 1 / OMEGA,
    "backward-euler": None,
    "implicit-midpoint": None,
}


@pytest.mark.parametrize("method", sorted(SPRING_LIMITS))
def test_stability_limits_on_the_undamped_spring(method: str) -> None:
    res = lab.stability("spring", method)
    want = SPRING_LIMITS[method]
    assert "spectral radius" in res["criterion"] and res["cap"] > 0
    if want is None:
        assert res["dt_max"] is None
    elif want == 0:
        assert res["dt_max"] == 0.0
    else:
        assert res["dt_max"] == pytest.approx(want, rel=1e-6)


def test_stability_of_alternating_euler_uses_its_two_step_map() -> None:
    # two steps (velocity-first, then position-first) = leapfrog with step 2 dt: 2 dt omega <= 2
    res = lab.stability("spring", "symplectic-euler-alternating")
    assert res["dt_max"] == pytest.approx(1 / OMEGA, rel=1e-6)


def test_stability_on_drag_and_projectile() -> None:
    # drag: eigenvalue -c/m = -0.5; explicit Euler |1 - 0.5 dt| <= 1 iff dt <= 4
    assert lab.stability("drag", "explicit-euler")["dt_max"] == pytest.approx(4.0, rel=1e-6)
    # projectile: free particle plus a constant force, a Jordan block at 1: no limit
    assert lab.stability("projectile", "verlet")["dt_max"] is None


def test_stability_on_a_nonlinear_scene_is_bounded_growth() -> None:
    res = lab.stability("orbit", "symplectic-euler")
    assert res["criterion"].startswith("bounded growth")
    assert 0.1 < res["dt_max"] < 2.0


# -- compare and sweep -----------------------------------------------------------------


def test_compare_rows() -> None:
    res = lab.compare("orbit", ["explicit-euler", "symplectic-euler", "rk4"], 0.05, 6.0)
    assert res["error_against"] == "exact solution"
    rows = {r["method"]: r for r in res["rows"]}
    assert rows["rk4"]["evals_per_step"] == 4.0 and rows["explicit-euler"]["evals_per_step"] == 1.0
    assert rows["explicit-euler"]["energy_drift"] > 0  # gains energy
    assert rows["rk4"]["final_error"] < rows["symplectic-euler"]["final_error"]
    assert rows["explicit-euler"]["energy_max_rel_error"] > rows["symplectic-euler"]["energy_max_rel_error"]


def test_compare_without_exact_solution_uses_a_reference() -> None:
    res = lab.compare("chain", ["symplectic-euler", "rk4"], 0.001, 0.1)
    assert res["error_against"].startswith("reference: rk4 at dt/16")
    assert all(r["final_error"] >= 0 for r in res["rows"])


def test_sweep_rows_and_errors_fall_with_dt() -> None:
    res = lab.sweep("spring", ["velocity-verlet", "rk4"], [0.2, 0.1, 0.05], 10.0)
    assert len(res["rows"]) == 6
    rk4 = [r for r in res["rows"] if r["method"] == "rk4"]
    assert [r["dt"] for r in rk4] == [0.2, 0.1, 0.05]
    assert rk4[0]["max_error"] > rk4[1]["max_error"] > rk4[2]["max_error"]
    assert rk4[2]["evals"] == 4 * rk4[2]["steps"]


def test_bad_input_raises_value_error() -> None:
    with pytest.raises(ValueError, match="bogus"):
        lab.compare("spring", ["bogus"], 0.1, 1.0)
    with pytest.raises(ValueError, match="nope"):
        lab.order("spring", "rk4", params={"nope": 1.0})


# -- CLI -------------------------------------------------------------------------------


def test_cli_compare_json() -> None:
    res = run_cli("compare", "spring", "--methods", "explicit-euler,rk4", "--dt", "0.1", "--until", "2",
                  "--param", "k=2", "--format", "json")  # fmt: skip
    assert res.returncode == 0, res.stderr
    data = json.loads(res.stdout)
    assert data["params"]["k"] == 2.0
    assert [r["method"] for r in data["rows"]] == ["explicit-euler", "rk4"]
    assert {
        "order",
        "evals_per_step",
        "energy_max_rel_error",
        "energy_drift",
        "final_error",
        "ns_per_step",
    } <= set(data["rows"][0])


def test_cli_compare_text_and_plot(tmp_path) -> None:
    out = tmp_path / "c.png"
    res = run_cli("compare", "orbit", "--methods", "symplectic-euler,rk4", "--dt", "0.1", "--until", "3",
                  "--plot", str(out))  # fmt: skip
    assert res.returncode == 0, res.stderr
    assert "symplectic-euler" in res.stdout and "exact solution" in res.stdout
    assert out.stat().st_size > 0


def test_cli_order_json() -> None:
    res = run_cli("order", "spring", "--method", "velocity-verlet", "--levels", "4", "--format", "json")
    assert res.returncode == 0, res.stderr
    data = json.loads(res.stdout)
    assert abs(data["order"] - 2) < 0.15
    assert all({"dt", "error"} <= set(r) for r in data["runs"]) and len(data["runs"]) == 4


def test_cli_stability_json() -> None:
    res = run_cli("stability", "spring", "--method", "leapfrog", "--format", "json")
    assert res.returncode == 0, res.stderr
    data = json.loads(res.stdout)
    assert data["dt_max"] == pytest.approx(2 / OMEGA, rel=1e-6)
    assert "criterion" in data and "cap" in data
    res = run_cli("stability", "spring", "--method", "backward-euler", "--format", "json")
    assert json.loads(res.stdout)["dt_max"] is None


def test_cli_sweep_csv_and_json(tmp_path) -> None:
    res = run_cli("sweep", "spring", "--methods", "rk4,heun", "--dts", "0.1,0.05")
    assert res.returncode == 0, res.stderr
    rows = list(csv.DictReader(io.StringIO(res.stdout)))
    assert len(rows) == 4 and rows[0]["method"] == "rk4"
    out, png = tmp_path / "s.json", tmp_path / "wp.png"
    res = run_cli("sweep", "orbit", "--methods", "rk4", "--dts", "0.1,0.05", "--format", "json",
                  "--out", str(out), "--plot", str(png))  # fmt: skip
    assert res.returncode == 0, res.stderr
    assert res.stderr == ""  # no progress bar when stderr is not a terminal
    assert len(json.loads(out.read_text())["rows"]) == 2 and png.stat().st_size > 0


@pytest.mark.parametrize(
    "args",
    [
        ("compare", "spring", "--methods", "explicit-euler,bogus"),
        ("order", "spring", "--method", "bogus"),
        ("stability", "spring", "--method", "bogus"),
        ("sweep", "spring", "--methods", "bogus", "--dts", "0.1"),
    ],
)
def test_cli_bad_method_exits_2_with_one_line(args: tuple[str, ...]) -> None:
    res = run_cli(*args)
    assert res.returncode == 2
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("physstep: error:") and "bogus" in lines[0]


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (("order", "spring", "--method", "rk4", "--dt", "0"), "invalid --dt '0'"),
        (("order", "spring", "--method", "rk4", "--param", "q=1"), "unknown param 'q'"),
        (("stability", "spring", "--method", "rk4", "--cap", "-1"), "invalid --cap '-1'"),
        (("sweep", "spring", "--dts", "abc"), "invalid --dts 'abc'"),
    ],
)
def test_cli_bad_values_exit_2_with_one_line(args: tuple[str, ...], needle: str) -> None:
    res = run_cli(*args)
    assert res.returncode == 2
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and needle in lines[0], res.stderr
