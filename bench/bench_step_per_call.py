"""One step per call, the game loop's pattern: physstep's `World.step(1)` against numba loops
doing the same arithmetic, and the memory floor, in one run.

    python bench/bench_step_per_call.py [--quick] [--json FILE]

Workload: particles in 3D (f64) under gravity (0, 0, -9.81) and linear drag 0.1 N s/m on
unit masses, symplectic Euler at dt = 1/120, as `bench_particles.py`, but each call takes ONE
step (a game loop calls the engine once per fixed step). Peers, called the same way, once per
step, from the same Python loop:

- at 1e6 particles: numba's fused `prange` loop over the particles (one step a call) and the
  memory floor (a `prange` read-modify-write of x and v, no physics); physstep with masses
  that differ (1 to 2 kg: its kernel then reads an inverse mass a particle, where equal
  masses are one number) against the floor; and, for the record, ten steps per call against
  numba's ten;
- at 1e3 and 1e5 particles: a serial numba loop (`njit`, no threads).

Printed: ns per particle-step (median of repeats, the contenders timed in turn within each
repeat, so a change of load falls on all alike) and the ratios. At 1e6 the same three are
timed again each alone in a fresh process, in turn (the rounds' medians and ratios): numba's
OpenMP workers spin for some milliseconds after each call, and on a machine of few cores
that takes a core from whatever the same process times next. Nothing is asserted: the
numbers vary with the machine, the ratios less.
"""

from __future__ import annotations

import argparse
import statistics
from pathlib import Path

import numba
import numpy as np
import physstep
from bench_particles import C, G, H, acc, floor_kernel
from bench_particles import se_kernel as se_parallel
from common import in_subprocess, median_times, row, write_json
from numba import njit


@njit
def se_serial(x, v, s, g, h, steps):  # noqa: ANN001, ANN201
    for _ in range(steps):
        for i in range(x.shape[0]):
            for k in range(3):
                a = acc(v[i, k], s, 1.0, g[k])
                v[i, k] += h * a
                x[i, k] += h * v[i, k]


def calls(fn, k: int):  # noqa: ANN001, ANN201
    """`k` calls of `fn`, as a game loop makes them."""

    def run() -> None:
        for _ in range(k):
            fn()

    return run


# One contender alone in a fresh interpreter: `k` calls of one step, timed in blocks after a
# warm-up; prints the median ns per particle-step.
ALONE = """
import json, statistics, sys, time
import numpy as np
sys.path.insert(0, {bench!r})
n, k, who = {n}, {k}, {who!r}
rng = np.random.default_rng(1)
x, v = rng.random((n, 3)), rng.random((n, 3))
if who == "physstep":
    import physstep
    w = physstep.World(3, method="symplectic-euler", dt={h!r})
    w.add_particles(x, v, np.ones(n))
    w.add_gravity([0.0, 0.0, -9.81])
    w.add_drag({c!r})
    step = lambda: w.step(1)
elif who == "numba":
    from bench_particles import G, H, se_kernel
    step = lambda: se_kernel(x, v, -({c!r} + 0.0 * 0.0), G, H, 1)
else:
    from bench_particles import floor_kernel
    step = lambda: floor_kernel(x, v, 1.0, 1)
step()
blocks = []
for _ in range(9):
    t0 = time.perf_counter()
    for _ in range(k):
        step()
    blocks.append((time.perf_counter() - t0) / (k * n) * 1e9)
print(json.dumps({{"ns": statistics.median(blocks)}}))
"""


def apart(n: int, k: int, rounds: int) -> dict[str, float]:
    """physstep's and numba's one step a call and the memory floor, each alone in its own
    process, `rounds` times in turn: the medians of each (ns per particle-step) and the
    medians of physstep's ratios to the other two in the same round."""
    bench = str(Path(__file__).resolve().parent)
    threads = numba.get_num_threads()
    runs: dict[str, list[float]] = {"physstep": [], "numba": [], "floor": []}
    for _ in range(rounds):
        for who, into in runs.items():
            code = ALONE.format(bench=bench, n=n, k=k, who=who, h=H, c=C)
            into.append(in_subprocess(code, threads)["ns"])
    out = {who: statistics.median(r) for who, r in runs.items()}
    for peer in ("numba", "floor"):
        pairs = zip(runs["physstep"], runs[peer], strict=True)
        out[f"to_{peer}"] = statistics.median(a / b for a, b in pairs)
    return out


def world(x0: np.ndarray, v0: np.ndarray, masses: np.ndarray | None = None) -> physstep.World:
    w = physstep.World(3, method="symplectic-euler", dt=H)
    w.add_particles(x0, v0, np.ones(len(x0)) if masses is None else masses)
    w.add_gravity(list(G))
    w.add_drag(C)
    return w


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="fewer calls and repeats")
    p.add_argument("--json", help="also write the table to this file")
    a = p.parse_args()
    repeat = 3 if a.quick else 7
    s = -(C + 0.0 * 0.0)
    rng = np.random.default_rng(1)
    out: dict[str, object] = {}
    print(f"symplectic Euler, gravity + linear drag, dt = 1/120, numba threads {numba.get_num_threads()}")

    n = 1_000_000
    k = 10 if a.quick else 40
    x0, v0 = rng.random((n, 3)), rng.random((n, 3))
    per = 1e9 / (k * n)
    x, v = x0.copy(), v0.copy()
    xn, vn = x0.copy(), v0.copy()
    w = world(x0, v0)
    # Masses that differ: the kernel then reads an inverse mass a particle (8 bytes more than
    # the floor's 48 read and 48 written), where equal masses are one number.
    mixed = world(x0, v0, 1.0 + rng.random(n))
    t = median_times(
        {
            "floor": calls(lambda: floor_kernel(x, v, 1.0, 1), k),
            "fused": calls(lambda: se_parallel(xn, vn, s, G, H, 1), k),
            "ours": calls(lambda: w.step(1), k),
            "unequal": calls(lambda: mixed.step(1), k),
        },
        repeat,
    )
    floor, fused, ours, unequal = (t[c] * per for c in ("floor", "fused", "ours", "unequal"))
    print(f"\nN = {n:,}, one step per call ({k} calls a repeat)")
    row("memory floor (numba prange, read + write x, v)", floor, "ns/particle-step")
    row("numba prange, one step a call", fused, "ns/particle-step")
    row("physstep World.step(1)", ours, "ns/particle-step", fused, "numba prange")
    print(f"{'':<44} {ours / floor:6.2f}x the memory floor   (targets: 1.0x numba, 1.15x floor)")
    row("physstep World.step(1), masses 1-2 kg", unequal, "ns/particle-step", floor, "the memory floor")
    t = median_times({"ten": lambda: w.step(10), "ten_ref": lambda: se_parallel(xn, vn, s, G, H, 10)}, repeat)
    ten, ten_ref = (t[c] * 1e9 / (10 * n) for c in ("ten", "ten_ref"))
    row("physstep World.step(10)", ten, "ns/particle-step", ten_ref, "numba prange, 10 a call")
    sep = apart(n, k, 3 if a.quick else 7)
    print(f"\nN = {n:,}, one step per call, each contender alone in its own process, in turn")
    print(
        f"{'':<44} (in one process numba's OpenMP workers spin for some milliseconds after each"
        f"\n{'':<44} call, holding a core from whatever is timed next: physstep above)"
    )
    row("memory floor (numba prange, read + write x, v)", sep["floor"], "ns/particle-step")
    row("numba prange, one step a call", sep["numba"], "ns/particle-step")
    row("physstep World.step(1)", sep["physstep"], "ns/particle-step")
    print(
        f"{'':<44} {sep['to_numba']:6.2f}x numba prange, {sep['to_floor']:.2f}x the memory floor"
        f"\n{'':<44} (medians of each round's ratios; targets: 1.0x numba, 1.15x floor)"
    )
    out["1e6"] = {
        "floor": floor,
        "numba_prange": fused,
        "physstep": ours,
        "physstep_unequal_masses": unequal,
        "ten": ten,
        "ten_numba": ten_ref,
        "apart": sep,
    }

    for n, k in ((1_000, 2_000), (100_000, 100)):
        if a.quick:
            k //= 4
        x0, v0 = rng.random((n, 3)), rng.random((n, 3))
        per = 1e9 / (k * n)
        xs, vs = x0.copy(), v0.copy()
        w = world(x0, v0)
        t = median_times(
            {
                "serial": calls(lambda xs=xs, vs=vs: se_serial(xs, vs, s, G, H, 1), k),
                "ours": calls(lambda w=w: w.step(1), k),
            },
            repeat,
        )
        serial, ours = t["serial"] * per, t["ours"] * per
        print(f"\nN = {n:,}, one step per call ({k} calls a repeat)")
        row("numba serial, one step a call", serial, "ns/particle-step")
        row("physstep World.step(1)", ours, "ns/particle-step", serial, "numba serial")
        print(f"{'':<44} (target: 1.2x numba serial)")
        out[f"{n:.0e}"] = {"numba_serial": serial, "physstep": ours}
    write_json(a.json, out)


if __name__ == "__main__":
    main()
