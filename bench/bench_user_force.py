"""The cost of a force written in Python, per evaluation, beside the built-in force and
beside the same numpy expression timed alone.

Gravity plus linear drag on n particles (3D, symplectic Euler, one evaluation per step):
once as the built-in forces, once as a Python callable computing the same physics with
numpy, returned (`f(t, x, v) -> G - C * v`) or written in place (`add_force(f,
inplace=True)`, `f(t, x, v, out)`), and once as the bare numpy expression on an (n, 3)
array. The Python force's own cost is a step with it minus a step of the same world with no
force at all. All are measured in the same run (median of interleaved repeats); nothing is asserted.

Issue 22's targets, printed as ratios: at 1e5 particles the Python force costs at most 1.3x
the numpy expression alone; at n = 1, at most 2 us per evaluation.

    python bench/bench_user_force.py [--quick]
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable

import numpy as np
import physstep

G = np.array([0.0, -9.81, 0.0])
C = 0.1


def returned(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Unit masses: F = m g - c v, a new array."""
    return G - C * v


def inplace(t: float, x: np.ndarray, v: np.ndarray, out: np.ndarray) -> None:
    """The same force written into `out`."""
    np.multiply(v, -C, out=out)
    out += G


def world(n: int, kind: str) -> physstep.World:
    """n particles under gravity and drag: built-in, a Python force, or no force."""
    w = physstep.World(3, method="symplectic-euler", dt=1 / 120)
    w.add_particles(np.random.default_rng(0).random((n, 3)))
    if kind == "returned":
        w.add_force(returned)
    elif kind == "inplace":
        w.add_force(inplace, inplace=True)
    elif kind == "built-in":
        w.add_gravity(G.tolist())
        w.add_drag(linear=C)
    return w


def per_eval(n: int, kinds: list[str], steps: int, repeat: int) -> dict[str, float]:
    """Median seconds per step (one force evaluation each) of each kind of world, over
    `repeat` interleaved rounds (on a loaded machine every kind then sees the same load)."""
    times: dict[str, list[float]] = {k: [] for k in kinds}
    for _ in range(repeat):
        for kind in kinds:
            w = world(n, kind)
            w.step(1)
            t0 = time.perf_counter()
            w.step(steps)
            times[kind].append((time.perf_counter() - t0) / steps)
    return {k: statistics.median(v) for k, v in times.items()}


def alone(fn: Callable[[], object], calls: int, repeat: int) -> float:
    """Median seconds per call of `fn`."""
    fn()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(calls):
            fn()
        times.append((time.perf_counter() - t0) / calls)
    return statistics.median(times)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="fewer steps and repeats")
    args = p.parse_args()
    repeat = 3 if args.quick else 7
    # Same physics, same bits? The first steps must agree to rounding.
    ref = world(1000, "built-in")
    ref.step(10)
    for kind in ("returned", "inplace"):
        b = world(1000, kind)
        b.step(10)
        gap = float(np.abs(ref.positions - b.positions).max())
        print(f"built-in vs Python force ({kind}) after 10 steps, 1000 particles: max |dx| = {gap:.1e} m")
    print(
        f"{'particles':>10} {'built-in':>11} {'no force':>11} {'returned':>11} {'inplace':>11}"
        f" {'numpy alone':>12} {'returned/np':>12} {'inplace/np':>11}"
        f"   (us per evaluation, median of {repeat})"
    )
    for n in (1, 1_000, 100_000):
        steps = max(20, (200 if args.quick else 2000) // max(1, n // 1000))
        t = per_eval(n, ["built-in", "none", "returned", "inplace"], steps, repeat)
        v = np.random.default_rng(1).random((n, 3))
        out = np.empty_like(v)
        np_ret = alone(lambda v=v: G - C * v, steps, repeat)
        np_in = alone(lambda v=v, out=out: inplace(0.0, v, v, out), steps, repeat)
        own_ret, own_in = t["returned"] - t["none"], t["inplace"] - t["none"]
        print(
            f"{n:>10} {t['built-in'] * 1e6:>11.2f} {t['none'] * 1e6:>11.2f} {t['returned'] * 1e6:>11.2f}"
            f" {t['inplace'] * 1e6:>11.2f} {np_ret * 1e6:>12.2f} {own_ret / np_ret:>11.2f}x"
            f" {own_in / np_in:>10.2f}x"
        )
        if n == 1:
            print(
                f"{'':>10} target at n = 1: at most 2 us per evaluation: returned {own_ret * 1e6:.2f} us,"
                f" inplace {own_in * 1e6:.2f} us (the force's own cost; a whole step"
                f" {t['returned'] * 1e6:.2f} / {t['inplace'] * 1e6:.2f} us)"
            )
        if n == 100_000:
            print(
                f"{'':>10} target at 1e5: at most 1.3x the numpy expression alone: returned"
                f" {own_ret / np_ret:.2f}x (numpy {np_ret * 1e6:.0f} us), inplace {own_in / np_in:.2f}x"
                f" (numpy in place {np_in * 1e6:.0f} us)"
            )


if __name__ == "__main__":
    main()
