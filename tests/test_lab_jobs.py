"""The lab beyond one process: ``jobs=`` and ``executor=`` give the serial results."""

from __future__ import annotations

import concurrent.futures
import json
import math
import subprocess
import sys
from typing import Any

import physstep
import physstep.lab as lab
import pytest
from physstep.lab import parallel

#: The columns that measure wall time: they differ from run to run, in any process.
TIMING = {"ns_per_step", "ns_per_step_runs", "time_s"}


def same(a: Any, b: Any) -> bool:
    """Equal, NaN equal to NaN, timing columns left out (results compared by ``to_dict()``)."""
    if hasattr(a, "to_dict") and hasattr(b, "to_dict"):
        return same(a.to_dict(), b.to_dict())
    if isinstance(a, dict) and isinstance(b, dict):
        keys = set(a) - TIMING
        return keys == set(b) - TIMING and all(same(a[k], b[k]) for k in keys)
    if isinstance(a, list | tuple) and isinstance(b, list | tuple):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return True
    return bool(a == b)


def pendulum_world() -> physstep.World:
    """A user system that pickles (a module-level function)."""
    w = physstep.World(2, method="rk4", dt=0.01)
    w.add_particle([1.0, 0.0], [0.0, 0.0], 1.0)
    w.add_spring(0, [0.0, 0.0], stiffness=4.0)
    return w


@pytest.fixture
def pool_pays(monkeypatch: pytest.MonkeyPatch) -> None:
    """Worker processes whatever the work and the machine: starting them costs nothing and
    there are 4 CPUs (so that small test sweeps do run in processes)."""
    monkeypatch.setattr(parallel, "POOL_START_S", 0.0)
    monkeypatch.setattr(parallel, "cpus", lambda: 4)


def test_sweep_in_processes_gives_the_serial_rows(pool_pays: None) -> None:
    args = ("orbit", ["rk4", "leapfrog", "symplectic-euler"], [0.1, 0.05])
    serial = lab.sweep(*args, until=3.0)
    two = lab.sweep(*args, until=3.0, jobs=2)
    assert two.workers == 2 and serial.workers == 1
    assert same(serial, two)
    assert [r.method for r in two.rows] == [r.method for r in serial.rows]


def test_jobs_1_and_2_give_the_same_bits_in_every_field_but_timing(pool_pays: None) -> None:
    # a scene with a reference run (chain: no exact solution), which travels once per chunk
    args = ("chain", ["rk4", "symplectic-euler", "velocity-verlet", "heun"], [0.004, 0.002])
    one = lab.sweep(*args, until=0.2, jobs=1)
    two = lab.sweep(*args, until=0.2, jobs=2)
    assert two.workers == 2 and one.workers == 1
    for a, b in zip(one.rows, two.rows, strict=True):
        for f in ("method", "dt", "steps", "t_end", "evals", "error", "max_error", "energy_max_rel_error"):
            x, y = getattr(a, f), getattr(b, f)
            assert x == y and (not isinstance(x, float) or x.hex() == y.hex()), f  # bitwise
    assert one.to_dict().keys() == two.to_dict().keys() and one.note == two.note == ""


def test_jobs_on_small_work_runs_here_and_says_so() -> None:
    serial = lab.sweep("spring", ["rk4", "heun"], [0.2, 0.1], until=2.0)
    small = lab.sweep("spring", ["rk4", "heun"], [0.2, 0.1], until=2.0, jobs=2)
    assert small.workers == 1
    assert small.note.startswith("jobs=2 ran here, serially: ")
    assert "too small" in small.note or "one CPU" in small.note
    assert same(serial.rows, small.rows)
    # compare alike; the note is the result's note, beside what "all" skipped
    flow = lab.compare("lorenz", "all", dt=0.01, until=0.1, jobs=3)
    assert flow.workers == 1 and flow.note.startswith("skipped ") and "; jobs=3 ran here" in flow.note


def test_decide_takes_processes_only_where_they_pay() -> None:
    start = parallel.POOL_START_S
    # too little work: here, with the reason
    workers, note = parallel.decide(2, 2, [0.05] * 8)
    assert workers == 1 and "too small to pay" in note and "about 0.4 s" in note
    # enough: as many as asked, no note
    assert parallel.decide(2, 2, [start] * 8) == (2, "")
    # never more than the CPUs, nor more than the rows, and the note says why
    workers, note = parallel.decide(8, 2, [start] * 8)
    assert workers == 2 and note == "jobs=8 ran in 2 processes (2 CPUs, 8 rows after the first)"
    assert parallel.decide(8, 16, [10 * start] * 3)[0] == 3
    assert parallel.decide(4, 1, [10 * start] * 8) == (1, "jobs=4 ran here, serially: one CPU")
    assert parallel.decide(4, 4, [10 * start]) == (1, "jobs=4 ran here, serially: one row left")


def test_the_estimate_follows_the_timing_repetitions() -> None:
    # at least TIMING_MIN_RUNS runs and TIMING_MIN_S s, at most TIMING_MAX_RUNS runs or TIMING_MAX_S s
    assert parallel.timed_cost(0.1) == pytest.approx(3 * 0.1)
    assert parallel.timed_cost(0.01) == pytest.approx(5 * 0.01)
    assert parallel.timed_cost(1e-5) == pytest.approx(25 * 1e-5)
    assert parallel.timed_cost(0.6) == pytest.approx(2 * 0.6)
    assert parallel.timed_cost(3.0) == pytest.approx(3.0)
    # rows scale by their work; the first row's overhead is added to each
    est = parallel.estimate(0.35, 0.1, [1.0, 2.0, 0.5])
    assert est == pytest.approx([0.35, 0.6 + 0.05, 0.15 + 0.05])


def test_chunks_are_consecutive_cover_every_row_and_balance_the_cost() -> None:
    for costs, n in (([1.0] * 10, 4), ([1.0] * 3, 8), ([5.0, 1, 1, 1, 1, 1], 2), ([1.0], 3), ([0.0] * 5, 2)):
        spans = parallel.chunks(costs, n)
        assert spans[0][0] == 0 and spans[-1][1] == len(costs)
        assert all(a < b for a, b in spans)
        assert all(b == c for (_, b), (c, _) in zip(spans[:-1], spans[1:], strict=True))
        assert len(spans) == min(n, len(costs))
    assert parallel.chunks([1.0] * 8, 4) == [(0, 2), (2, 4), (4, 6), (6, 8)]
    assert parallel.chunks([5.0, 1, 1, 1, 1, 1], 2) == [(0, 1), (1, 6)]


def test_compare_on_an_executor_gives_the_serial_rows() -> None:
    serial = lab.compare("drag", "all")
    with concurrent.futures.ThreadPoolExecutor(2) as ex:
        threaded = lab.compare("drag", "all", executor=ex)
        # The executor is the caller's: still usable afterwards.
        assert ex.submit(lambda: 1).result() == 1
    assert same(serial, threaded)


def test_a_system_that_pickles_runs_in_processes(pool_pays: None) -> None:
    methods = ["rk4", "velocity-verlet", "heun"]
    serial = lab.compare(pendulum_world, methods, dt=0.05, until=2.0)
    two = lab.compare(pendulum_world, methods, dt=0.05, until=2.0, jobs=2)
    assert two.workers == 2 and same(serial, two)


def test_progress_is_called_in_order_as_rows_come_in(pool_pays: None) -> None:
    seen: list[tuple[int, int, str]] = []
    res = lab.sweep(
        "spring", ["rk4", "heun"], [0.2, 0.1], until=2.0, jobs=2, progress=lambda *a: seen.append(a)
    )
    assert res.workers == 2
    assert seen == [(1, 4, "rk4 dt=0.2"), (2, 4, "rk4 dt=0.1"), (3, 4, "heun dt=0.2"), (4, 4, "heun dt=0.1")]


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"jobs": 0}, "invalid jobs = 0"),
        ({"jobs": -2}, "invalid jobs = -2"),
        ({"jobs": True}, "invalid jobs = True"),
        ({"jobs": 2.0}, "invalid jobs = 2.0"),
        ({"jobs": 5000}, "invalid jobs = 5000"),
        ({"jobs": 2, "executor": concurrent.futures.ThreadPoolExecutor(1)}, "give jobs or executor"),
        ({"executor": "dask"}, "invalid executor = 'dask'"),
    ],
)
def test_bad_jobs_and_executors_are_refused(kwargs: dict[str, Any], field: str) -> None:
    with pytest.raises(ValueError, match=field):
        lab.sweep("spring", ["rk4"], [0.1], until=1.0, **kwargs)


def test_a_numpy_integer_is_a_number_of_jobs() -> None:
    import numpy as np

    serial = lab.sweep("spring", ["rk4"], [0.2], until=1.0)
    res = lab.sweep("spring", ["rk4"], [0.2], until=1.0, jobs=np.int64(2))
    assert same(serial.rows, res.rows) and res.note == "jobs=2 ran here, serially: no row left"


def test_a_lambda_system_is_refused_before_anything_runs() -> None:
    with pytest.raises(ValueError, match="invalid scene = .*must pickle"):
        lab.compare(lambda: pendulum_world(), ["rk4"], dt=0.1, until=1.0, jobs=2)


def test_a_system_from_an_interactive_session_is_refused_for_local_processes() -> None:
    code = (
        "import physstep, physstep.lab as lab\n"
        "def system():\n"
        "    w = physstep.World(1, method='rk4', dt=0.1)\n"
        "    w.add_particle([1.0], [0.0], 1.0)\n"
        "    return w\n"
        "try:\n"
        "    lab.compare(system, ['rk4'], dt=0.1, until=1.0, jobs=2)\n"
        "except ValueError as e:\n"
        "    print(e)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.stdout.startswith("invalid scene = <function system"), out.stdout + out.stderr
    assert "interactive session" in out.stdout


def test_cli_jobs(cli: Any) -> None:
    one = cli("sweep", "spring", "--methods", "rk4,heun", "--dts", "0.2,0.1", "--format", "json")
    two = cli(
        "sweep", "spring", "--methods", "rk4,heun", "--dts", "0.2,0.1", "--format", "json", "--jobs", "2"
    )
    assert one.returncode == 0 and two.returncode == 0, two.stderr
    a, b = json.loads(one.stdout), json.loads(two.stdout)
    assert same(a["rows"], b["rows"])
    # too little work for two processes: run here, and the note (stderr, and the JSON) says so
    assert a["note"] == "" and b["note"].startswith("jobs=2 ran here, serially")
    assert b["note"] in two.stderr
    bad = cli("compare", "spring", "--jobs", "0")
    assert bad.returncode == 2
    assert bad.stderr.strip().splitlines() == [
        "physstep: error: invalid --jobs '0': must be an integer from 1 to 1024"
    ]


def test_a_local_dask_cluster_gives_the_serial_sweep() -> None:
    distributed = pytest.importorskip("distributed")
    args = ("kepler", ["rk4", "yoshida4"], [0.05, 0.025])
    serial = lab.sweep(*args, until=2.0)
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    )
    try:
        with distributed.Client(cluster) as client:
            remote = lab.sweep(*args, until=2.0, executor=client.get_executor())
    finally:
        cluster.close()
    assert same(serial, remote)
