"""Plots: golden-image-free checks of the files, their size and the data behind each line."""

from __future__ import annotations

import dataclasses
import math

import matplotlib.image as mpimg
import numpy as np
import physstep
import pytest
from physstep import lab, plot

ORBIT_METHODS = ["explicit-euler", "backward-euler", "symplectic-euler", "rk4"]


@pytest.fixture(scope="module")
def orbit_runs() -> list[physstep.Trajectory]:
    # the notes' picture: three periods at dt = 0.1 (backward Euler's Newton solve gives up near
    # the centre, so its run stops early: stop_on_diverge)
    return [physstep.simulate("orbit", m, 0.1, 6 * math.pi, stop_on_diverge=True) for m in ORBIT_METHODS]


def _labels(fig) -> list[str]:
    return [t.get_text() for t in fig.axes[-1].get_legend().get_texts()]


def test_orbit_png_size_lines_and_legend(tmp_path, orbit_runs) -> None:
    fig = plot.orbit(orbit_runs)
    path = plot.save(fig, tmp_path / "orbit.png")
    img = mpimg.imread(path)
    w, h = fig.get_size_inches() * fig.dpi
    assert img.shape[:2] == (round(h), round(w))
    ax = fig.axes[0]
    labels = _labels(fig)
    assert [lbl.split(" (")[0] for lbl in labels[: len(ORBIT_METHODS)]] == ORBIT_METHODS
    assert "exact" in labels
    assert ax.get_xlabel() == "x (m)" and ax.get_ylabel() == "y (m)"
    assert "orbit" in ax.get_title() and "dt = 0.1 s" in ax.get_title()
    named = [line for line in ax.get_lines() if not line.get_label().startswith("_")]
    for run, line in zip(orbit_runs, named, strict=False):
        np.testing.assert_array_equal(line.get_xdata(), run.x[:, 0])
        np.testing.assert_array_equal(line.get_ydata(), run.x[:, 1])


def test_orbit_picture_properties(orbit_runs) -> None:
    r = {run.method: np.hypot(run.x[:, 0], run.x[:, 1]) for run in orbit_runs}
    first, last = slice(0, 63), slice(-63, None)  # first and last period (63 steps of 0.1)
    # explicit Euler spirals out: the radius of its last period exceeds that of its first
    assert r["explicit-euler"].max() > 1.5
    assert r["explicit-euler"][last].max() > r["explicit-euler"][first].max()
    # backward Euler spirals in
    assert r["backward-euler"].max() <= 1.0 + 1e-12 and r["backward-euler"][-1] < 0.8
    # symplectic Euler stays on a closed curve: in a band around r = 1 for all three periods
    assert np.abs(r["symplectic-euler"] - 1).max() < 0.1
    # RK4 stays near the circle
    assert np.abs(r["rk4"] - 1).max() < 1e-3


def test_trajectory_plot_lines_match_the_runs(tmp_path) -> None:
    runs = [physstep.simulate("spring", m, 0.1, 10.0) for m in ("explicit-euler", "rk4")]
    fig = plot.trajectory(runs)
    lines = fig.axes[0].get_lines()
    for run, line in zip(runs, lines, strict=False):
        np.testing.assert_array_equal(line.get_xdata(), run.t)
        np.testing.assert_array_equal(line.get_ydata(), run.x[:, 0])
    np.testing.assert_array_equal(lines[2].get_ydata(), runs[0].exact_x[:, 0])
    assert _labels(fig) == ["explicit-euler", "rk4", "exact"]
    assert fig.axes[0].get_xlabel() == "t (s)" and fig.axes[0].get_ylabel() == "x (m)"
    path = plot.save(fig, tmp_path / "traj.svg")
    assert path.read_text().lstrip().startswith("<?xml")


def test_phase_and_energy_plots(tmp_path) -> None:
    runs = [physstep.simulate("spring", m, 0.25, 10.0) for m in ("explicit-euler", "symplectic-euler")]
    fig = plot.phase(runs)
    line = fig.axes[0].get_lines()[1]
    np.testing.assert_array_equal(line.get_xdata(), runs[1].x[:, 0])
    np.testing.assert_array_equal(line.get_ydata(), runs[1].v[:, 0])
    assert fig.axes[0].get_ylabel() == "v (m/s)"
    fig = plot.energy(runs)
    np.testing.assert_array_equal(fig.axes[0].get_lines()[0].get_ydata(), runs[0].energy)
    assert _labels(fig)[:2] == ["explicit-euler", "symplectic-euler"]
    assert fig.axes[0].get_ylabel() == "E (J)"
    img = mpimg.imread(plot.save(fig, tmp_path / "energy.png"))
    assert img.shape[:2] == (500, 800)
    fig = plot.energy(runs, relative=True)
    np.testing.assert_allclose(fig.axes[0].get_lines()[1].get_ydata(), runs[1].energy_error)


def test_work_precision_plot_is_log_log(tmp_path) -> None:
    data = lab.sweep("spring", ["explicit-euler", "rk4"], [0.2, 0.1, 0.05], 5.0)
    fig = plot.work_precision(data, against="both")
    assert len(fig.axes) == 2
    for ax in fig.axes:
        assert ax.get_xscale() == "log" and ax.get_yscale() == "log"
    rk4 = [r for r in data.rows if r.method == "rk4"]
    line = fig.axes[0].get_lines()[1]
    np.testing.assert_array_equal(line.get_xdata(), sorted(r.evals for r in rk4))
    assert _labels(fig) == ["explicit-euler", "rk4"]
    img = mpimg.imread(plot.save(fig, tmp_path / "wp.png"))
    w, h = fig.get_size_inches() * fig.dpi
    assert img.shape[:2] == (round(h), round(w))


def test_bad_plot_input() -> None:
    with pytest.raises(ValueError, match="extension"):
        plot.save(plot.trajectory(physstep.simulate("spring", "rk4", 0.1, 1.0)), "x.jpg")
    with pytest.raises(ValueError, match="2D"):
        plot.orbit(physstep.simulate("spring", "rk4", 0.1, 1.0))


# -- bad data: a ValueError that says what is wrong ---------------------------------------


def _empty(run: physstep.Trajectory) -> physstep.Trajectory:
    none = np.empty((0, run.x.shape[1]))
    return dataclasses.replace(run, t=np.empty(0), x=none, v=none, a=none, energy=np.empty(0), exact_x=None)


@pytest.fixture
def spring_run() -> physstep.Trajectory:
    return physstep.simulate("spring", "rk4", 0.1, 2.0)


@pytest.mark.parametrize("fn", [plot.trajectory, plot.phase, plot.energy, plot.orbit])
def test_no_runs_or_a_run_without_rows_is_a_value_error(fn, spring_run) -> None:
    with pytest.raises(ValueError, match=r"invalid trajectories = \[\]"):
        fn([])
    orbit = physstep.simulate("orbit", "rk4", 0.1, 1.0)
    with pytest.raises(ValueError, match=r"invalid trajectories\[1\] \(rk4\): the trajectory has no rows"):
        fn([orbit, _empty(orbit)])


@pytest.mark.parametrize("fn", [plot.trajectory, plot.phase])
@pytest.mark.parametrize("coord", [1, -1, 2.0])
def test_coordinate_out_of_range(fn, spring_run, coord) -> None:
    with pytest.raises(ValueError, match=f"invalid coord = {coord}"):
        fn(spring_run, coord=coord)


def test_particle_out_of_range() -> None:
    run = physstep.simulate("chain", "rk4", 0.001, 0.01)
    plot.orbit(run, particle=run.x.shape[1] // 2 - 1)
    with pytest.raises(ValueError, match=r"invalid particle = 10: the chain run of rk4 has 10 particles"):
        plot.orbit(run, particle=10)
    with pytest.raises(ValueError, match="invalid particle = -1"):
        plot.orbit(run, particle=-1)


def test_non_finite_rows_are_left_out_and_the_legend_says_so(tmp_path, spring_run) -> None:
    x, v, e = spring_run.x.copy(), spring_run.v.copy(), spring_run.energy.copy()
    x[5:8, 0] = np.inf
    v[10, 0] = np.nan
    e[3] = -np.inf
    bad = dataclasses.replace(spring_run, x=x, v=v, energy=e)
    fig = plot.trajectory(bad)
    assert _labels(fig)[0] == "rk4 (3 non-finite rows not shown)"
    y = fig.axes[0].get_lines()[0].get_ydata()
    assert np.isnan(y[5:8]).all() and np.isfinite(np.delete(y, [5, 6, 7])).all()
    assert _labels(plot.phase(bad))[0] == "rk4 (4 non-finite rows not shown)"
    assert _labels(plot.energy(bad))[0] == "rk4 (1 non-finite row not shown)"
    plot.save(fig, tmp_path / "bad.png")
    plot.save(plot.phase(bad), tmp_path / "bad.svg")


@pytest.mark.parametrize("fn", [plot.trajectory, plot.phase, plot.energy])
def test_a_run_with_no_finite_row_is_a_value_error(fn, spring_run) -> None:
    nan = np.full_like(spring_run.x, np.nan)
    bad = dataclasses.replace(spring_run, x=nan, v=nan, energy=np.full_like(spring_run.energy, np.inf))
    with pytest.raises(ValueError, match=r"invalid trajectory \(rk4\): no row has finite values"):
        fn([spring_run, bad])


def _rows(errors: list[float | None]) -> list[dict]:
    return [
        {
            "method": "rk4",
            "dt": 0.1 / 2**i,
            "evals": 100 * 2**i,
            "time_s": 1e-5 * 2**i,
            "max_error": e,
            "error": e,
        }
        for i, e in enumerate(errors)
    ]


@pytest.mark.parametrize(
    ("data", "needle"),
    [
        ({}, "invalid data: no 'rows'"),
        ({"rows": []}, "invalid data: no rows"),
        ([], "invalid data: no rows"),
        ([{"method": "rk4", "dt": 0.1, "max_error": 1.0}], "invalid data: row 0 has no 'evals'"),
        (_rows([None, None]), "no row has a finite, positive max_error"),
        (_rows([float("nan"), float("inf"), 0.0, -1.0]), "no row has a finite, positive max_error"),
    ],
)
def test_work_precision_bad_data(data, needle) -> None:
    with pytest.raises(ValueError, match=needle):
        plot.work_precision(data)


def test_work_precision_leaves_out_non_finite_points(tmp_path) -> None:
    fig = plot.work_precision(_rows([1e-2, float("inf"), 1e-4, float("nan")]), against="both")
    assert _labels(fig) == ["rk4 (2 of 4 points left out)"]
    for ax in fig.axes:
        assert list(ax.get_lines()[0].get_ydata()) == [1e-2, 1e-4]  # sorted by work
    plot.save(fig, tmp_path / "wp.png")


def test_save_failure_keeps_the_old_file(tmp_path, monkeypatch, spring_run) -> None:
    target = tmp_path / "x.png"
    target.write_bytes(b"old")
    fig = plot.trajectory(spring_run)

    def full(*args, **kwargs):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(fig, "savefig", full)
    with pytest.raises(ValueError, match=f"invalid plot file '{target}': No space left on device"):
        plot.save(fig, target)
    assert target.read_bytes() == b"old" and [p.name for p in tmp_path.iterdir()] == ["x.png"]


# -- spin: rigid bodies ------------------------------------------------------------------


@pytest.fixture(scope="module")
def racket_run() -> physstep.Trajectory:
    return physstep.simulate("racket", "symplectic-euler", until=60.0, every=4)


def test_spin_draws_the_body_frame_axes_then_the_energy_and_l_errors(tmp_path, racket_run) -> None:
    fig = plot.spin(racket_run)
    omega, energy, ang = fig.axes
    assert len(omega.lines) == 3
    labels = [t.get_text() for t in omega.get_legend().get_texts()]
    assert labels == ["axis 1 (smallest moment)", "axis 2 (intermediate moment)", "axis 3 (largest moment)"]
    for k, line in enumerate(omega.lines):
        np.testing.assert_array_equal(line.get_xdata(), racket_run.t)
        np.testing.assert_array_equal(line.get_ydata(), racket_run.body_spin[:, 0, k])
    # the flip: the intermediate axis's spin changes sign within the minute
    w2 = racket_run.body_spin[:, 0, 1]
    assert w2.max() > 1.9 and w2.min() < -1.9
    assert omega.get_xlabel() == "" and ang.get_xlabel() == "t (s)"
    # the energy error spans decades: |error| on a log axis, the zero start left out
    assert energy.get_yscale() == "log" and "|E - E0|" in energy.get_ylabel()
    e = energy.lines[0].get_ydata()
    np.testing.assert_allclose(e, np.maximum(np.abs(racket_run.energy_error[1:]), plot.LOG_FLOOR))
    # L is exact: zero throughout, drawn on a linear axis, and the legend says so
    assert ang.get_yscale() == "linear" and ang.get_ylabel() == "|L - L0| / |L0|"
    assert np.all(ang.lines[0].get_ydata() == 0)
    assert ang.get_legend().get_texts()[0].get_text() == "symplectic-euler (0 throughout)"
    img = mpimg.imread(plot.save(fig, tmp_path / "spin.png"))
    w, h = fig.get_size_inches() * fig.dpi
    assert img.shape[:2] == (round(h), round(w))


def test_spin_puts_an_l_error_that_spans_decades_on_a_zero_safe_log_axis(racket_run) -> None:
    ang = racket_run.angular_momentum.copy()
    ang[5:, 1] *= 1 + np.geomspace(1e-15, 1e-3, len(ang) - 5)  # a drift over 12 decades
    ang[50] = ang[0]  # an exact zero in the middle: drawn at the floor, no -inf, no warning
    drifting = dataclasses.replace(racket_run, angular_momentum=ang, method="rk4")
    exact = dataclasses.replace(racket_run, angular_momentum=np.repeat(ang[:1], len(ang), axis=0))
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fig = plot.spin([drifting, exact])
    assert len(fig.axes) == 2 + 2 and len(fig.axes[0].lines) == 3
    ang_ax = fig.axes[-1]
    assert ang_ax.get_yscale() == "log"
    drawn = ang_ax.lines[0].get_ydata()
    assert np.isfinite(drawn).all() and drawn.min() == plot.LOG_FLOOR
    want = np.linalg.norm(ang[1:] - ang[0], axis=1) / np.linalg.norm(ang[0])
    np.testing.assert_allclose(drawn, np.maximum(want, plot.LOG_FLOOR))
    assert drawn.max() == pytest.approx(1e-3, rel=1e-3)
    texts = [t.get_text() for t in ang_ax.get_legend().get_texts()]
    assert texts == ["rk4", f"symplectic-euler (below {plot.LOG_FLOOR:g} throughout)"]
    assert [ax.get_title() for ax in fig.axes[:2]] == ["rk4", "symplectic-euler"]


def test_spin_refuses_runs_without_bodies_and_bodies_out_of_range(racket_run) -> None:
    spring = physstep.simulate("spring", "rk4", 0.1, 1.0)
    with pytest.raises(
        ValueError, match=r"invalid trajectories\[0\] \(spring, rk4\): a particles run has no rigid"
    ):
        plot.spin(spring)
    lorenz = physstep.simulate("lorenz", "rk4", 0.01, 0.1)
    with pytest.raises(
        ValueError, match=r"invalid trajectories\[1\] \(lorenz, rk4\): a flow run has no rigid"
    ):
        plot.spin([racket_run, lorenz])
    for body in (1, -1):
        with pytest.raises(
            ValueError, match=rf"invalid body = {body}: the racket run of symplectic-euler has 1 body"
        ):
            plot.spin(racket_run, body=body)
    with pytest.raises(ValueError, match="invalid body = 0.5: must be an integer"):
        plot.spin(racket_run, body=0.5)
    with pytest.raises(ValueError, match=r"invalid trajectories = \[\]"):
        plot.spin([])


def test_the_readme_racket_figure_shows_the_flips_go_on_and_die_out() -> None:
    import importlib.util

    from conftest import ROOT

    spec = importlib.util.spec_from_file_location("make_figures", ROOT / "scripts" / "make_figures.py")
    assert spec is not None and spec.loader is not None
    figures = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(figures)
    fig = figures.racket()
    default, quaternion, energy, ang = fig.axes
    assert "default" in default.get_title() and "quaternion" in quaternion.get_title()
    late = default.lines[1].get_xdata() > 1000.0
    # the default still flips at the end: the intermediate axis swings from +2 to -2 rad/s
    w2 = default.lines[1].get_ydata()[late]
    assert w2.max() > 1.9 and w2.min() < -1.9
    # the quaternion rule: no flip left, the body spins about its smallest moment
    assert np.abs(quaternion.lines[1].get_ydata()[late]).max() < 0.05
    assert np.abs(quaternion.lines[0].get_ydata()[late]).min() > 3.5
    # as its energy drifts up by half the scale, while the default's stays below 1e-5
    assert energy.lines[0].get_ydata().max() < 1e-5 and energy.lines[1].get_ydata()[-1] > 0.4
