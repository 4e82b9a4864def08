"""Implicit solves from Python: the sparse Newton/CG solve's statistics and settings."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import physstep
import pytest


def test_solve_stats_say_which_solve_ran() -> None:
    w = physstep.World.from_scene("stiff-chain", "backward-euler")
    assert w.solve_stats is not None and w.solve_stats["newton"] == 0
    w.step(3)
    s = w.solve_stats
    assert s["sparse"] and s["newton"] >= 1 and s["cg"] >= s["newton"] and s["residual"] <= 1e-12
    w.set_implicit(dense_up_to=10**9)
    w.step(1)
    assert not w.solve_stats["sparse"] and w.solve_stats["cg"] == 0
    w.method = "symplectic-euler"
    assert w.solve_stats is None


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"tol": -1.0}, "tol"),
        ({"max_iter": 0}, "max_iter"),
        ({"cg_tol": float("nan")}, "cg_tol"),
        ({"cg_max_iter": 0}, "cg_max_iter"),
        ({"dense_up_to": -3}, "dense_up_to"),
        ({"preconditioner": "ilu"}, "preconditioner"),
        ({"preconditioner": 1}, "preconditioner"),
    ],
)
def test_bad_solver_settings_name_the_field(kwargs: dict, field: str) -> None:
    w = physstep.World.from_scene("stiff-chain", "backward-euler")
    with pytest.raises(ValueError, match=rf"invalid {field} = "):
        w.set_implicit(**kwargs)
    w.step(1)  # the world still steps with its old settings
    assert w.solve_stats["sparse"]


def test_the_preconditioner_is_chosen_by_name_and_the_complete_cholesky_factor_is_the_default() -> None:
    # On a cloth the complete factor is the exact solve: one CG iteration a step of the
    # linearly implicit method, where incomplete Cholesky takes dozens and block Jacobi more;
    # all three solve the same linear system, to CG's tolerance.
    def run(**kwargs: str) -> tuple[dict, np.ndarray]:
        w = physstep.World.from_scene("stiff-cloth", "linearly-implicit-euler")
        w.set_implicit(**kwargs)
        w.step(5)
        return w.solve_stats, w.positions

    (full, x_full), (default, x_default) = run(preconditioner="cholesky"), run()
    ic, x_ic = run(preconditioner="incomplete-cholesky")
    jacobi, x_jacobi = run(preconditioner="block-jacobi")
    assert full == default and np.array_equal(x_full, x_default)
    assert full["cg"] <= 2 and ic["cg"] >= 10 and jacobi["cg"] > ic["cg"], (full, ic, jacobi)
    assert np.abs(x_full - x_ic).max() <= 1e-8 and np.abs(x_full - x_jacobi).max() <= 1e-8


def test_symplectic_euler_diverges_on_the_stiff_chain_and_is_reported() -> None:
    w = physstep.World.from_scene("stiff-chain", "symplectic-euler")
    with pytest.raises(physstep.DivergedError, match=r"symplectic-euler.*particle \d+"):
        w.step(600)


def test_the_cli_exits_3_with_one_line_when_a_stiff_run_diverges() -> None:
    import subprocess
    import sys

    res = subprocess.run(
        [sys.executable, "-m", "physstep", "run", "stiff-chain", "--method", "symplectic-euler"],
        capture_output=True,
        text=True,
    )
    assert res.returncode == 3, res
    lines = res.stderr.splitlines()
    assert len(lines) == 1 and "diverged at step" in lines[0] and "particle" in lines[0], res.stderr
    assert "symplectic-euler" in lines[0] and "Traceback" not in res.stderr
    # backward Euler takes the same scene at its game step.
    ok = subprocess.run(
        [
            sys.executable,
            "-m",
            "physstep",
            "run",
            "stiff-chain",
            "--method",
            "backward-euler",
            "--until",
            "1",
        ],
        capture_output=True,
        text=True,
    )
    assert ok.returncode == 0, ok.stderr


def _one_step(method: str, tol: float | None) -> tuple[np.ndarray, np.ndarray]:
    w = physstep.World.from_scene("stiff-chain", method)
    w.dt = 1 / 60
    if tol is not None:
        w.set_implicit(tol=tol)
    w.step()
    return w.positions, w.velocities


def test_the_default_newton_tolerance_meets_what_the_docs_say() -> None:
    # issue 25, item 13: the default tolerance left 7.5e-8 of the velocities on one step and
    # the docs did not say so. They say it now, and what they say is measured here.
    text = (Path(__file__).resolve().parent.parent / "docs" / "stiff.md").read_text()
    said = re.search(r"has velocities `([\d.e-]+)` .*?its positions\s+`([\d.e-]+)`", text, re.S)
    assert said, "docs/stiff.md must say what the default tolerance meets"
    v_said, x_said = float(said.group(1)), float(said.group(2))
    x_ref, v_ref = _one_step("backward-euler", 1e-14)
    x, v = _one_step("backward-euler", None)
    v_err = np.abs(v - v_ref).max() / np.abs(v_ref).max()
    x_err = np.abs(x - x_ref).max() / np.abs(x_ref).max()
    # (A `0` in the docs is the converged step to the bit: the exact Jacobian's last update
    # lands on the rounding floor.)
    assert v_said / 2 <= v_err <= v_said * 2 and x_said / 2 <= x_err <= x_said * 2, (v_err, x_err)
    # the tolerance the docs give for a converged step gives it
    x13, v13 = _one_step("backward-euler", 1e-13)
    assert np.abs(v13 - v_ref).max() <= 1e-10 * np.abs(v_ref).max()
    assert np.abs(x13 - x_ref).max() <= 1e-10 * np.abs(x_ref).max()


def test_the_exact_jacobian_cuts_the_newton_updates_and_can_be_turned_off() -> None:
    # The 12 x 12 cloth's first 30 steps (it falls and folds): backward Euler's updates with
    # the exact Jacobian where it is positive definite (the default) and without it.
    def updates(exact: bool | None) -> tuple[int, np.ndarray]:
        w = physstep.World.from_scene("stiff-cloth", "backward-euler", params={"n": 12})
        if exact is not None:
            w.set_implicit(exact_jacobian=exact)
        total = 0
        for _ in range(30):
            w.step()
            total += w.solve_stats["newton"]
        return total, w.positions.copy()

    default, x_default = updates(None)
    on, x_on = updates(True)
    off, x_off = updates(False)
    assert default == on and np.array_equal(x_default, x_on)
    assert 3 * on <= off, (on, off)
    # The same equation solved to the same tolerance: the cloths agree closely.
    assert np.abs(x_on - x_off).max() <= 1e-6, np.abs(x_on - x_off).max()


@pytest.mark.parametrize("bad", ["yes", 1.5, 2])
def test_exact_jacobian_takes_a_bool_and_names_itself(bad: object) -> None:
    w = physstep.World.from_scene("stiff-chain")
    with pytest.raises(ValueError, match=r"exact_jacobian") as e:
        w.set_implicit(exact_jacobian=bad)
    assert "\n" not in str(e.value)


def test_the_linearly_implicit_step_is_halved_where_it_would_raise_the_energy() -> None:
    # The 100-link stiff chain's first 120 steps under linearly implicit Euler: as it is
    # (energy_halvings=0) one solve a step and the energy rises on a few steps while the links
    # turn fast; with the default halvings those steps are taken as halves (three solves) and
    # the energy never rises.
    def run(halvings: int | None) -> tuple[int, int, list[int]]:
        w = physstep.World.from_scene("stiff-chain", "linearly-implicit-euler")
        if halvings is not None:
            w.set_implicit(energy_halvings=halvings)
        e, rises, solves = w.energy(), 0, []
        for _ in range(120):
            w.step()
            solves.append(w.solve_stats["newton"])
            rises += w.energy() > e + 1e-9 * abs(e)
            e = w.energy()
        return rises, sum(s > 1 for s in solves), solves

    rises, halved, solves = run(0)
    assert rises >= 1 and halved == 0 and set(solves) == {1}, (rises, halved)
    rises, halved, solves = run(None)
    assert rises == 0 and 1 <= halved <= 12 and max(solves) <= 5, (rises, halved, max(solves))
    assert run(4)[2] == solves


@pytest.mark.parametrize("bad", [-1, 17, 2.5, True, "4"])
def test_energy_halvings_takes_a_count_to_16_and_names_itself(bad: object) -> None:
    w = physstep.World.from_scene("stiff-chain", "linearly-implicit-euler")
    said = r"^invalid energy_halvings = .*: must be a whole number from 0 to 16$"
    with pytest.raises(ValueError, match=said) as e:
        w.set_implicit(energy_halvings=bad)
    assert "\n" not in str(e.value)
    # the settings were kept: the same steps as a world never touched
    fresh = physstep.World.from_scene("stiff-chain", "linearly-implicit-euler")
    w.step(5)
    fresh.step(5)
    assert np.array_equal(w.positions, fresh.positions)
