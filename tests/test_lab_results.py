"""The lab's typed results: frozen dataclasses whose ``to_dict()`` is exactly the dict the
lab returned before they were typed, so the command line's JSON is unchanged."""

from __future__ import annotations

import dataclasses
import json
import pickle
import re
from pathlib import Path
from typing import Any

import numpy as np
import physstep
import physstep.lab as lab
import pytest
from physstep import cli, plot
from physstep.lab import results

#: The CLI's JSON before the results were typed (``argv`` and its output), timing masked.
GOLDEN = Path(__file__).parent / "data" / "lab_json"
#: The columns that measure wall time: masked (None) in the recorded output.
TIMING = {"ns_per_step", "ns_per_step_runs", "time_s"}
CLASSES = (
    results.CompareResult,
    results.CompareRow,
    results.SweepResult,
    results.SweepRow,
    results.OrderResult,
    results.OrderRun,
    results.StabilityResult,
    results.GrowthTest,
)


def _mask(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {k: None if k in TIMING else _mask(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_mask(v) for v in obj]
    return obj


@pytest.mark.parametrize("path", sorted(GOLDEN.glob("*.json")), ids=lambda p: p.stem)
def test_cli_json_is_what_it_was_before_the_results_were_typed(path: Path, capsys) -> None:
    golden = json.loads(path.read_text())
    assert cli.main(golden["argv"]) == 0
    got = _mask(json.loads(capsys.readouterr().out))
    # the same keys in the same order, the same values to the bit (floats as JSON prints them)
    assert json.dumps(got) == json.dumps(golden["output"])


def test_results_are_frozen_dataclasses_read_by_attribute() -> None:
    res = lab.compare("orbit", ["symplectic-euler", "rk4"], dt=0.1, until=2.0)
    assert isinstance(res, lab.CompareResult) and all(isinstance(r, lab.CompareRow) for r in res.rows)
    assert res.row("rk4").evals_per_step == 4.0 and res.row("rk4") is res.rows[1]
    with pytest.raises(KeyError, match="'heun': no such row .*symplectic-euler, rk4"):
        res.row("heun")
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.dt = 1.0  # type: ignore[misc]
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.rows[0].final_error = 0.0  # type: ignore[misc]
    assert isinstance(res.rows, tuple) and isinstance(res.skipped, tuple)
    order = lab.order("spring", "rk4", levels=3)
    assert isinstance(order, lab.OrderResult) and all(isinstance(r, lab.OrderRun) for r in order.runs)
    sweep = lab.sweep("spring", ["rk4"], [0.2, 0.1], until=2.0)
    assert isinstance(sweep, lab.SweepResult) and [r.dt for r in sweep.rows] == [0.2, 0.1]
    st = lab.stability("orbit", "symplectic-euler", rtol=1e-2)
    assert isinstance(st, lab.StabilityResult) and isinstance(st.growth, lab.GrowthTest)
    assert st.growth.limit == lab.GROWTH_LIMIT and isinstance(st.grid, tuple)


def test_to_dict_is_plain_json_ready_data_and_a_fresh_copy() -> None:
    res = lab.compare("racket", ["rk4"], until=0.2)
    d = res.to_dict()
    assert list(d) == [
        "scene", "kind", "until", "until_requested", "params", "error_against", "energy_error",
        "timing", "skipped", "note", "rows", "angular_momentum_error", "dt", "steps", "t_end",
    ]  # fmt: skip
    assert isinstance(d["rows"][0], dict) and d["skipped"] == [] and "workers" not in d
    assert json.loads(json.dumps(d)) == d  # nothing but JSON types
    d["rows"][0]["final_error"] = -1.0
    d["params"]["x"] = 1.0
    assert res.rows[0].final_error >= 0 and "x" not in res.params and res.to_dict() != d


def test_keys_that_do_not_apply_are_left_out_of_the_dict() -> None:
    linear = lab.stability("spring", "rk4")
    assert linear.growth is None and linear.stable_above is None
    assert linear.spectral_radius_at_dt_max is not None
    d = linear.to_dict()
    assert "growth" not in d and "stable_above" not in d and d["spectral_radius_at_dt_max"] <= 1 + 1e-12
    never = lab.stability("projectile", "verlet")  # stable up to the cap: no dt_max, no radius
    assert never.dt_max is None and "spectral_radius_at_dt_max" not in never.to_dict()
    flow = lab.compare("lorenz", ["rk4"], dt=0.01, until=0.1)
    assert flow.angular_momentum_error is None and "angular_momentum_error" not in flow.to_dict()


def test_indexing_still_works_but_warns() -> None:
    res = lab.stability("spring", "rk4")
    with pytest.warns(DeprecationWarning, match=r"read the attribute \(\.dt_max\)"):
        assert res["dt_max"] == res.dt_max
    with pytest.warns(DeprecationWarning):
        assert "growth" not in res
    sweep = lab.sweep("spring", ["rk4"], [0.2], until=1.0)
    with pytest.warns(DeprecationWarning):
        assert sweep["rows"][0]["error"] == sweep.rows[0].error
    with pytest.raises(TypeError):
        iter(res)


@pytest.mark.parametrize("cls", CLASSES, ids=lambda c: c.__name__)
def test_every_field_is_documented(cls: type) -> None:
    doc = cls.__doc__ or ""
    assert "Attributes:" in doc
    documented = set(re.findall(r"^        (\w+):", doc, re.MULTILINE))
    assert documented == {f.name for f in dataclasses.fields(cls)}


def test_a_reference_run_pickles_its_deferred_columns() -> None:
    # chain has no exact solution: the lab's reference run, which jobs= sends to its workers
    ref = physstep.simulate("chain", "rk4", dt=0.001, until=0.05)
    back = pickle.loads(pickle.dumps(ref))
    assert np.array_equal(back.x, ref.x) and np.array_equal(back.kinetic, ref.kinetic)
    orbit = physstep.simulate("orbit", "rk4", dt=0.1, until=1.0)
    back = pickle.loads(pickle.dumps(orbit))
    assert np.array_equal(back.exact_x, orbit.exact_x) and np.array_equal(back.exact_v, orbit.exact_v)


def test_work_precision_takes_the_typed_sweep_its_dict_or_its_rows() -> None:
    sweep = lab.sweep("spring", ["rk4", "heun"], [0.2, 0.1], until=2.0)
    for data in (sweep, sweep.to_dict()):
        fig = plot.work_precision(data)
        assert fig.get_suptitle().startswith("work-precision: spring") and len(fig.axes[0].get_lines()) == 2
    assert len(plot.work_precision(list(sweep.rows)).axes[0].get_lines()) == 2
