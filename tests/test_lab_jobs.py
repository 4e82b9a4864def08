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

#: The columns that measure wall time: they differ from run to run, in any process.
TIMING = {"ns_per_step", "ns_per_step_runs", "time_s"}


def same(a: Any, b: Any) -> bool:
    """Equal, NaN equal to NaN, timing columns left out."""
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


def test_sweep_in_processes_gives_the_serial_rows() -> None:
    args = ("orbit", ["rk4", "leapfrog", "symplectic-euler"], [0.1, 0.05])
    serial = lab.sweep(*args, until=3.0)
    parallel = lab.sweep(*args, until=3.0, jobs=2)
    assert same(serial, parallel)
    assert [r["method"] for r in parallel["rows"]] == [r["method"] for r in serial["rows"]]


def test_compare_on_an_executor_gives_the_serial_rows() -> None:
    serial = lab.compare("drag", "all")
    with concurrent.futures.ThreadPoolExecutor(2) as ex:
        threaded = lab.compare("drag", "all", executor=ex)
        # The executor is the caller's: still usable afterwards.
        assert ex.submit(lambda: 1).result() == 1
    assert same(serial, threaded)


def test_a_system_that_pickles_runs_in_processes() -> None:
    serial = lab.compare(pendulum_world, ["rk4", "velocity-verlet"], dt=0.05, until=2.0)
    parallel = lab.compare(pendulum_world, ["rk4", "velocity-verlet"], dt=0.05, until=2.0, jobs=2)
    assert same(serial, parallel)


def test_progress_is_called_in_order_as_rows_come_in() -> None:
    seen: list[tuple[int, int, str]] = []
    lab.sweep("spring", ["rk4"], [0.2, 0.1], until=2.0, jobs=2, progress=lambda *a: seen.append(a))
    assert seen == [(1, 2, "rk4 dt=0.2"), (2, 2, "rk4 dt=0.1")]


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
    assert same(serial, lab.sweep("spring", ["rk4"], [0.2], until=1.0, jobs=np.int64(2)))


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
    assert same(json.loads(one.stdout), json.loads(two.stdout))
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
