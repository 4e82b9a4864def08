"""The lab, the plots and the command line on rigid-body scenes."""

from __future__ import annotations

import json
import subprocess
import sys

import matplotlib
import physstep
import pytest
from physstep import lab, plot

matplotlib.use("Agg")


def _cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "physstep", *args], capture_output=True, text=True, check=False
    )


def test_compare_on_the_racket_has_an_angular_momentum_column_and_skips_verlet() -> None:
    res = lab.compare("racket", "all", until=20.0)
    rows = {r.method: r for r in res.rows}
    assert "verlet" not in rows and res.skipped == ("verlet",)
    assert "orientations" in res.note
    assert rows["symplectic-euler"].angular_momentum_max_rel_error < 1e-12
    # The free body under rk4 is accurate: its final body-frame spin is near the reference.
    assert rows["rk4"].final_error < 1e-4
    assert rows["explicit-euler"].final_error > 100 * rows["rk4"].final_error


def test_compare_refuses_verlet_on_a_body_scene_in_one_line() -> None:
    with pytest.raises(ValueError, match="verlet.*orientations"):
        lab.compare("racket", ["verlet"], until=1.0)


def test_particle_scenes_have_no_angular_momentum_column() -> None:
    res = lab.compare("spring", ["rk4"], until=1.0)
    assert res.rows[0].angular_momentum_max_rel_error is None


def test_spin_plots_the_body_frame_angular_velocity() -> None:
    traj = physstep.simulate("racket", "symplectic-euler", until=30.0, every=4)
    fig = plot.spin(traj)
    first = fig.axes[0]
    assert len(first.lines) == 3
    assert "intermediate" in first.get_legend().get_texts()[1].get_text()
    with pytest.raises(ValueError, match="no rigid bodies"):
        plot.spin(physstep.simulate("spring", "rk4", until=1.0))
    with pytest.raises(ValueError, match="body = 1"):
        plot.spin(traj, body=1)


def test_run_reports_angular_momentum_and_refuses_verlet() -> None:
    out = _cli("run", "racket", "--until", "60", "--format", "json")
    assert out.returncode == 0, out.stderr
    summary = json.loads(out.stdout)
    assert summary["angular_momentum"]["max_rel_error"] < 1e-12
    assert summary["energy"]["max_rel_error"] < 1e-5
    bad = _cli("run", "racket", "--method", "verlet")
    assert bad.returncode == 2
    assert bad.stderr.count("\n") == 1 and "verlet" in bad.stderr and "Traceback" not in bad.stderr


def test_compare_on_the_top_from_the_command_line() -> None:
    out = _cli("compare", "top", "--methods", "rk4,velocity-verlet", "--until", "0.5")
    assert out.returncode == 0, out.stderr
    assert "max |dL|/|L|" in out.stdout and "velocity-verlet" in out.stdout


def test_stability_refuses_body_scenes_rather_than_call_every_dt_stable() -> None:
    with pytest.raises(ValueError, match="not measured on rigid bodies"):
        lab.stability("racket", "rk4")
    out = _cli("stability", "top", "--method", "rk4")
    assert out.returncode == 2 and "rigid bodies" in out.stderr


def test_sweep_and_order_measure_bodies_against_the_reference() -> None:
    res = lab.sweep("racket", ["rk4", "symplectic-euler"], [0.02, 0.01], until=20.0)
    err = {(r.method, r.dt): r.max_error for r in res.rows}
    # Halving dt cuts rk4's body-spin error by 16 or more (measured 32), and the splitting
    # drift's (a free body: no kicks) by 4: it is second order whatever the split method.
    assert err[("rk4", 0.02)] / err[("rk4", 0.01)] > 12.0
    assert 3.5 < err[("symplectic-euler", 0.02)] / err[("symplectic-euler", 0.01)] < 4.5
