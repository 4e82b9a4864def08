"""The integrator lab: observed orders, stability limits, compare/sweep data and the CLI."""

from __future__ import annotations

import contextlib
import csv
import io
import itertools
import json
import math
import re
import signal
import warnings

import numpy as np
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
    assert res.order is not None, res
    assert abs(res.order - info) < 0.15, (res.order, info, res.runs)
    assert [r.steps % 2 for r in res.runs] == [0] * len(res.runs)  # even step counts
    assert res.error_against == "exact solution"


def test_order_without_exact_solution_uses_the_reference() -> None:
    # The notes' rod force (rod = 0): rk4, the reference, keeps its order on it; on the rod
    # constraint rk4 is projected, first order, and no reference.
    res = lab.order("pendulum", "velocity-verlet", params={"rod": 0}, levels=4)
    assert res.error_against.startswith("reference: rk4 at dt/16")
    assert abs(res.order - 2) < 0.15


def test_a_stiff_scenes_reference_goes_finer_where_rk4_is_unstable() -> None:
    # The 100-link stiff chain at dt = 1/60: RK4 diverges at dt/16 and dt/32 (its stability
    # limit is about 2.8 / omega_max); the reference halves its step until it holds, and
    # says so. (It used to fail the whole comparison with the reference's DivergedError.)
    res = lab.compare("stiff-chain", methods=["backward-euler"], until=0.5)
    assert res.error_against == f"reference: rk4 at dt/64 = {1 / 60 / 64:.6g} s"
    (row,) = res.rows
    assert not row.diverged and 0 < row.final_error < 1.0


def test_order_of_a_method_exact_on_the_scene_is_none() -> None:
    res = lab.order("projectile", "velocity-verlet", levels=3)
    assert res.order is None and "exact" in res.note


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
# - linearly implicit Euler: on a linear system the same step as backward Euler -> None
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
    "linearly-implicit-euler": None,
}


@pytest.mark.parametrize("method", sorted(SPRING_LIMITS))
def test_stability_limits_on_the_undamped_spring(method: str) -> None:
    res = lab.stability("spring", method)
    want = SPRING_LIMITS[method]
    assert "spectral radius" in res.criterion and res.cap > 0
    if want is None:
        assert res.dt_max is None
    elif want == 0:
        assert res.dt_max == 0.0
    else:
        assert res.dt_max == pytest.approx(want, rel=1e-6)


def test_stability_of_alternating_euler_uses_its_two_step_map() -> None:
    # two steps (velocity-first, then position-first) = leapfrog with step 2 dt: 2 dt omega <= 2
    res = lab.stability("spring", "symplectic-euler-alternating")
    assert res.dt_max == pytest.approx(1 / OMEGA, rel=1e-6)


def test_stability_on_drag_and_projectile() -> None:
    # drag: eigenvalue -c/m = -0.5; explicit Euler |1 - 0.5 dt| <= 1 iff dt <= 4
    assert lab.stability("drag", "explicit-euler").dt_max == pytest.approx(4.0, rel=1e-6)
    # projectile: free particle plus a constant force, a Jordan block at 1: no limit
    assert lab.stability("projectile", "verlet").dt_max is None


def test_stability_on_a_nonlinear_scene_is_bounded_growth() -> None:
    res = lab.stability("orbit", "symplectic-euler")
    assert res.criterion.startswith("bounded growth")
    assert 0.1 < res.dt_max < 2.0


# -- compare and sweep -----------------------------------------------------------------


def test_compare_rows() -> None:
    res = lab.compare("orbit", ["explicit-euler", "symplectic-euler", "rk4"], 0.05, 6.0)
    assert res.error_against == "exact solution"
    rows = {r.method: r for r in res.rows}
    assert rows["rk4"].evals_per_step == 4.0 and rows["explicit-euler"].evals_per_step == 1.0
    assert rows["explicit-euler"].energy_drift > 0  # gains energy
    assert rows["rk4"].final_error < rows["symplectic-euler"].final_error
    assert rows["explicit-euler"].energy_max_rel_error > rows["symplectic-euler"].energy_max_rel_error


def test_compare_without_exact_solution_uses_a_reference() -> None:
    res = lab.compare("chain", ["symplectic-euler", "rk4"], 0.001, 0.1)
    assert res.error_against.startswith("reference: rk4 at dt/16")
    assert all(r.final_error >= 0 for r in res.rows)


def test_sweep_rows_and_errors_fall_with_dt() -> None:
    res = lab.sweep("spring", ["velocity-verlet", "rk4"], [0.2, 0.1, 0.05], 10.0)
    assert len(res.rows) == 6
    rk4 = [r for r in res.rows if r.method == "rk4"]
    assert [r.dt for r in rk4] == [0.2, 0.1, 0.05]
    assert rk4[0].max_error > rk4[1].max_error > rk4[2].max_error
    assert rk4[2].evals == 4 * rk4[2].steps


def test_bad_input_raises_value_error() -> None:
    with pytest.raises(ValueError, match="bogus"):
        lab.compare("spring", ["bogus"], 0.1, 1.0)
    with pytest.raises(ValueError, match="nope"):
        lab.order("spring", "rk4", params={"nope": 1.0})


# -- review fixes: stability ---------------------------------------------------------


@contextlib.contextmanager
def _time_limit(seconds: int):
    """Fails (instead of hanging) a call that does not return in time."""

    def fail(signum, frame):
        raise TimeoutError(f"did not return within {seconds} s")

    old = signal.signal(signal.SIGALRM, fail)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


def test_amplification_covers_the_integrator_memory() -> None:
    # leapfrog's phase vector is [x; v; v_half]: the matrix is 3 x 3 on the 1D spring, and on
    # drag its repeating map has v_half' = (1 - c dt / m) v_half + ..., eigenvalue -1 at 4 s
    m = lab.amplification("drag", "leapfrog", 4.1)
    assert m.shape == (3, 3)
    assert max(abs(np.linalg.eigvals(m))) == pytest.approx(1.05125, rel=1e-9)
    assert lab.amplification("spring", "velocity-verlet", 1.0).shape == (2, 2)


def test_a_large_cap_still_finds_the_limit() -> None:
    # the grid starts at 1e-3 natural time scales whatever the cap (it used to start at cap * 1e-6)
    assert lab.stability("spring", "rk4", cap=1e9).dt_max == pytest.approx(4.0, rel=1e-6)
    assert lab.stability("drag", "leapfrog", cap=1e9).dt_max == pytest.approx(4.0, rel=1e-6)
    assert lab.stability("spring", "explicit-euler", cap=1e9).dt_max == 0.0


@pytest.mark.parametrize("cap", [5e-324, 1e-3, 0.0, -1.0, math.inf, math.nan, 1e300])
def test_a_cap_outside_the_grid_is_refused(cap: float) -> None:
    with pytest.raises(ValueError, match="invalid cap"):
        lab.stability("spring", "rk4", cap=cap)


@pytest.mark.parametrize("rtol", [0.0, -1e-3, math.nan, 1e-17, 0.5, math.inf])
def test_a_bad_rtol_is_refused_not_looped_on(rtol: float) -> None:
    with _time_limit(20), pytest.raises(ValueError, match="invalid rtol"):
        lab.stability("spring", "rk4", rtol=rtol)


def test_stability_on_the_chain_uses_the_state_not_the_energy() -> None:
    # the chain's E0 is 3e-30 J (rounding): a criterion relative to E0 said "unstable at every dt"
    res = lab.stability("chain", "symplectic-euler")
    assert res.analysis == "bounded growth"
    assert "|x_k - x_0|" in res.criterion and "energy" not in res.criterion
    assert 0.001 < res.dt_max < lab.time_scale("chain")


def test_stability_says_which_analysis() -> None:
    assert lab.stability("spring", "rk4").analysis == "amplification matrix"
    assert lab.stability("orbit", "rk4").analysis == "bounded growth"


# -- review fixes: order -------------------------------------------------------------


def _no_runs(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """Makes every run of the lab record itself instead of running: refused arguments must
    be refused before any run starts."""
    from physstep.lab import system

    runs: list[str] = []

    def run(self: object, method: str, *args: object, **kwargs: object) -> None:
        runs.append(method)
        raise AssertionError(f"the lab ran {method} before refusing its arguments")

    monkeypatch.setattr(system.Subject, "run", run)
    return runs


@pytest.mark.parametrize(
    ("kwargs", "needle"),
    [
        ({"levels": 40}, "invalid levels = 40"),
        ({"levels": 1}, "invalid levels = 1"),
        ({"levels": 2.5}, "invalid levels = 2.5"),
        ({"levels": 18, "dt": 0.01}, "invalid levels = 18 with dt = "),
        ({"dt": 1e-9}, "invalid dt = 1e-09: until / dt = "),
        ({"dt": 1e-320}, "invalid dt = 1e-320: until / dt = inf steps"),
        ({"dt": 1e200}, "invalid dt = 1e+200"),
    ],
)
def test_order_refuses_oversized_runs_up_front(kwargs: dict, needle: str, monkeypatch) -> None:
    runs = _no_runs(monkeypatch)
    with pytest.raises(ValueError, match=re.escape(needle)):
        lab.order("spring", "rk4", **kwargs)
    assert runs == []  # refused before running anything


def test_yoshida4_on_drag_tends_to_fourth_order() -> None:
    # pre-asymptotic, not an order loss: the local order rises towards 4 as dt falls
    res = lab.order("drag", "yoshida4", levels=8)
    pairs = [r.order for r in res.runs if r.order is not None]
    assert pairs[1] < 3.2  # 3.06 from dt 0.15 to 0.075
    assert pairs[1:] == sorted(pairs[1:]) and 3.95 < pairs[-1] < 4.0  # ... 3.87, 3.94, 3.97
    assert 3.9 < res.order < 4.0


@pytest.mark.parametrize("scene", ["spring", "orbit", "drag"])
def test_alternating_euler_is_second_order_at_odd_step_counts(scene: str) -> None:
    until = 0.3 * lab.time_scale(scene)
    counts = [65, 129, 257, 513]
    errs = []
    for n in counts:
        traj = physstep.simulate(scene, "symplectic-euler-alternating", until / n, until, every=n)
        errs.append(float(abs(traj.x[-1] - traj.exact_x[-1]).max()))
    for (n1, e1), (n2, e2) in itertools.pairwise(zip(counts, errs, strict=True)):
        assert math.log(e1 / e2) / math.log(n2 / n1) == pytest.approx(2.0, abs=0.02)


# -- review fixes: compare and sweep ---------------------------------------------------


def test_a_bare_string_is_not_a_list_of_methods() -> None:
    with pytest.raises(ValueError, match="invalid methods = 'rk4'"):
        lab.compare("spring", methods="rk4")
    with pytest.raises(ValueError, match="invalid methods = 'rk4'"):
        lab.sweep("spring", "rk4", [0.1])
    with pytest.raises(ValueError, match="invalid dts = '0.1'"):
        lab.sweep("spring", ["rk4"], "0.1")


@pytest.mark.parametrize(
    ("call", "needle"),
    [
        (lambda: lab.compare("spring", ["rk4"], dt=1e200), "invalid dt = 1e+200"),
        (lambda: lab.compare("spring", ["rk4"], dt=1e-9, until=100.0), "with dt = 1e-09"),
        (
            lambda: lab.compare("nbody", ["rk4"], dt=1e-6, until=100.0),
            "invalid until = 100.0 with dt = 1e-06",
        ),
        (lambda: lab.sweep("spring", ["rk4"], [0.1, 1e-9], 100.0), "with dts = 1e-09"),
        (lambda: lab.sweep("nbody", ["rk4"], [1e-5], 100.0), "invalid until = 100.0 with dts = 1e-05"),
        (lambda: lab.sweep("spring", ["rk4"], [50.0]), "invalid dts: dt = 50.0"),
    ],
)
def test_long_runs_are_refused_before_running_naming_the_lab_argument(call, needle: str, monkeypatch) -> None:
    runs = _no_runs(monkeypatch)
    with pytest.raises(ValueError, match=re.escape(needle)) as err:
        call()
    assert "every" not in str(err.value)
    assert runs == []


def test_drift_is_none_without_finite_data() -> None:
    traj = physstep.simulate("spring", "rk4", 0.1, 1.0)
    assert lab._drift(traj) is not None
    traj.energy = np.full_like(traj.energy, np.nan)
    assert lab._drift(traj) is None
    traj.energy = np.array([1.0] + [1e300] * (len(traj.t) - 1))
    assert lab._drift(traj) is None or math.isfinite(lab._drift(traj))


def test_compare_of_a_diverging_run_reports_cleanly() -> None:
    # explicit Euler at dt = 5 s on the spring grows 3.7x a step until a state passes 1e100
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res = lab.compare("spring", ["explicit-euler", "rk4"], dt=5.0, until=5000.0)
    rows = {r.method: r for r in res.rows}
    assert rows["explicit-euler"].diverged and rows["explicit-euler"].t_end < 5000.0
    drift = rows["explicit-euler"].energy_drift
    assert drift is None or math.isfinite(drift)


def test_compare_and_sweep_say_what_was_run(monkeypatch) -> None:
    # The timing repeats until TIMING_MIN_S has passed (at least TIMING_MIN_RUNS runs) or
    # TIMING_MAX_S: with 0 and inf the count is TIMING_MIN_RUNS whatever the clock says.
    monkeypatch.setattr(lab.common, "TIMING_MIN_S", 0.0)
    monkeypatch.setattr(lab.common, "TIMING_MAX_S", math.inf)
    res = lab.compare("orbit", ["symplectic-euler", "rk4"], 0.1, 18.85)
    assert res.until_requested == 18.85 and res.steps == 188 and res.t_end == pytest.approx(18.8)
    for r in res.rows:
        assert r.steps == 188 and r.t_end == pytest.approx(18.8)
        assert r.ns_per_step_runs == lab.TIMING_MIN_RUNS == 3 and r.ns_per_step > 0
    assert "median" in res.timing and "kinetic" in res.energy_error
    sw = lab.sweep("orbit", ["rk4"], [0.3, 0.1], 1.0)
    assert sw.until_requested == 1.0
    assert [(r.steps, round(r.t_end, 9)) for r in sw.rows] == [(3, 0.9), (10, 1.0)]
    assert all(r.ns_per_step_runs == 3 for r in sw.rows)


def test_compare_energy_errors_on_the_chain_are_meaningful() -> None:
    # E0 = 3e-30 J: relative to E0 the errors read 1e24; relative to the kinetic energy they are small
    res = lab.compare("chain", ["symplectic-euler", "rk4"], 0.001, 0.5)
    rows = {r.method: r for r in res.rows}
    assert rows["rk4"].energy_max_rel_error < 1e-5
    assert rows["symplectic-euler"].energy_max_rel_error < 0.05
    assert rows["rk4"].energy_scale > 1.0  # J: the chain's kinetic energy, not |E0|


# -- compare on rigid bodies: the |L| column ------------------------------------------


def test_compare_on_the_racket_has_an_angular_momentum_column() -> None:
    res = lab.compare("racket", ["rk4", "symplectic-euler"], until=30.0)
    rows = {r.method: r for r in res.rows}
    assert set(rows) == {"rk4", "symplectic-euler"} and res.kind == "bodies"
    # the default keeps L exact (drifts never change it, a free body has no torque) ...
    assert rows["symplectic-euler"].angular_momentum_max_rel_error < 1e-12
    assert isinstance(rows["rk4"].angular_momentum_max_rel_error, float)
    # ... while its energy error is bounded but not zero: the column is not the energy's
    assert 1e-8 < rows["symplectic-euler"].energy_max_rel_error < 1e-5
    assert "|L - L0| / |L0|" in res.angular_momentum_error
    assert res.skipped == () and res.note == ""


def test_the_angular_momentum_column_sees_an_angular_form_that_breaks_l() -> None:
    # the same racket with the explicit gyroscopic term (velocity form): symplectic Euler's L
    # drifts, and the column says by how much, against the scene run's exact L
    def gyroscopic() -> physstep.World:
        w = physstep.World.from_scene("racket", "symplectic-euler", 1 / 120)
        w.angular_form = "velocity-gyroscopic"
        return w

    res = lab.compare(gyroscopic, ["symplectic-euler"], dt=1 / 120, until=30.0)
    assert res.kind == "bodies" and res.angular_momentum_error is not None
    assert res.rows[0].angular_momentum_max_rel_error > 1e-3


def test_compare_all_on_a_body_scene_skips_verlet_with_a_note() -> None:
    res = lab.compare("racket", "all", until=0.5)
    ran = [r.method for r in res.rows]
    assert "verlet" not in ran and res.skipped == ("verlet",)
    assert ran == [m for m in METHODS if m != "verlet"]
    assert "verlet" in res.note and "rigid bodies" in res.note
    assert all(r.angular_momentum_max_rel_error is not None for r in res.rows)
    with pytest.raises(ValueError, match=r"method 'verlet' .*orientations"):
        lab.compare("racket", ["rk4", "verlet"], until=0.5)


def test_particle_and_flow_tables_have_no_angular_momentum_description() -> None:
    for scene in ("spring", "lorenz"):
        res = lab.compare(scene, ["rk4"], dt=0.01, until=0.1)
        assert res.angular_momentum_error is None and "angular_momentum_error" not in res.to_dict()
        assert res.rows[0].angular_momentum_max_rel_error is None


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


def test_cli_compare_on_a_body_scene_shows_the_l_column_in_text_and_json() -> None:
    res = run_cli("compare", "racket", "--methods", "rk4,symplectic-euler", "--until", "5")
    assert res.returncode == 0, res.stderr
    assert "max |dL|/|L|" in res.stdout and "|L - L0| / |L0|" in res.stdout
    header = next(line for line in res.stdout.splitlines() if "order" in line)
    assert header.index("max |dE|/scale") < header.index("max |dL|/|L|")  # beside the energy
    res = run_cli(
        "compare", "racket", "--methods", "rk4,symplectic-euler", "--until", "5", "--format", "json"
    )
    assert res.returncode == 0, res.stderr
    data = json.loads(res.stdout)
    rows = {r["method"]: r for r in data["rows"]}
    assert rows["symplectic-euler"]["angular_momentum_max_rel_error"] < 1e-12
    assert "angular_momentum_error" in data
    spring = run_cli("compare", "spring", "--methods", "rk4", "--until", "1")
    assert spring.returncode == 0 and "|dL|" not in spring.stdout and "L0" not in spring.stdout


def test_cli_compare_plot_of_a_body_scene_is_the_spin_figure(tmp_path) -> None:
    out = tmp_path / "racket.png"
    res = run_cli(
        "compare", "racket", "--methods", "rk4,symplectic-euler", "--until", "5", "--plot", str(out)
    )
    assert res.returncode == 0, res.stderr
    import matplotlib.image as mpimg

    h, w = mpimg.imread(out).shape[:2]
    # spin: two omega panels above the energy and |L| panels, 10 in wide (x(t) would be 8 x 5)
    assert w == 1000 and h > 900
