"""Shared helpers of the side-by-side benchmarks: timing, rows, running in a subprocess.

Nothing here asserts a time: benchmarks print ratios measured in the same run.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np


def median_time(fn: Callable[[], object], repeat: int, warmup: int = 1) -> float:
    """Median wall time of `repeat` calls of `fn` after `warmup` untimed ones, s."""
    for _ in range(warmup):
        fn()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def median_times(fns: dict[str, Callable[[], object]], repeat: int, warmup: int = 1) -> dict[str, float]:
    """Median wall time of each of `fns`, s, over `repeat` rounds that time each once in turn
    (interleaved: a change of the machine's load falls on every contender alike)."""
    for fn in fns.values():
        for _ in range(warmup):
            fn()
    times: dict[str, list[float]] = {k: [] for k in fns}
    for _ in range(repeat):
        for k, fn in fns.items():
            t0 = time.perf_counter()
            fn()
            times[k].append(time.perf_counter() - t0)
    return {k: statistics.median(v) for k, v in times.items()}


def row(name: str, value: float, unit: str, ref: float | None = None, ref_name: str = "") -> str:
    """One printed line: `name  value unit  (x.xx x ref_name)`."""
    line = f"{name:<44} {value:10.3f} {unit}"
    if ref is not None:
        line += f"   {value / ref:6.2f}x {ref_name}"
    print(line)
    return line


def in_subprocess(code: str, threads: int) -> dict[str, float]:
    """Runs `code` (which prints one JSON dict) in a fresh interpreter with `threads` rayon
    and numba threads, and returns the dict: rayon's pool is global, so a thread count is
    chosen per process."""
    env = dict(os.environ, RAYON_NUM_THREADS=str(threads), NUMBA_NUM_THREADS=str(threads))
    env["OPENBLAS_NUM_THREADS"] = "1"
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def write_json(path: str | None, data: dict[str, object]) -> None:
    """Writes `data` to `path` (whole, via a temporary file) when a path is given."""
    if not path:
        return
    p = Path(path)
    tmp = p.with_suffix(p.suffix + ".tmp")
    tmp.write_text(json.dumps(data, indent=2) + "\n")
    tmp.replace(p)


def deepest_overlap(x: np.ndarray, radius: float) -> float:
    """The deepest overlap ``2 radius - distance`` of any pair of balls of one ``radius`` at
    positions ``x`` (n, dim), m; 0 when none overlap (all pairs, in blocks of rows)."""
    x = np.asarray(x)
    worst = 0.0
    for a in range(0, len(x), 500):
        d = np.linalg.norm(x[a : a + 500, None, :] - x[None, :, :], axis=-1)
        rows = np.arange(a, min(a + 500, len(x)))
        d[rows - a, rows] = np.inf
        worst = max(worst, float((2 * radius - d).max()))
    return worst
