"""The cost of a force written in Python, per evaluation, beside the built-in force.

Gravity plus linear drag on n particles (3D, symplectic Euler, one evaluation per step):
once as the built-in forces, once as one Python callable `f(t, x, v) -> (n, 3)` computing
the same physics with numpy. Both are measured in the same run (median of repeats); the
ratio says what writing your own force costs. Nothing is asserted.

    python bench/bench_user_force.py [--quick]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
import physstep

G = np.array([0.0, -9.81, 0.0])
C = 0.1


def world(n: int, user: bool) -> physstep.World:
    """n particles under gravity and drag, built-in or as a Python force."""
    w = physstep.World(3, method="symplectic-euler", dt=1 / 120)
    w.add_particles(np.random.default_rng(0).random((n, 3)))
    if user:
        w.add_force(lambda t, x, v: G - C * v)  # unit masses: F = m g - c v
    else:
        w.add_gravity(G.tolist())
        w.add_drag(linear=C)
    return w


def per_eval(n: int, user: bool, steps: int, repeat: int) -> float:
    """Median seconds per force evaluation (one per step) over `repeat` runs."""
    times = []
    for _ in range(repeat):
        w = world(n, user)
        w.step(1)
        t0 = time.perf_counter()
        w.step(steps)
        times.append((time.perf_counter() - t0) / steps)
    return statistics.median(times)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="fewer steps and repeats")
    args = p.parse_args()
    repeat = 3 if args.quick else 7
    # Same physics, same bits? The first steps must agree to rounding.
    a, b = world(1000, False), world(1000, True)
    a.step(10)
    b.step(10)
    gap = float(np.abs(a.positions - b.positions).max())
    print(f"built-in vs Python force after 10 steps, 1000 particles: max |dx| = {gap:.1e} m")
    print(
        f"{'particles':>10} {'built-in':>12} {'Python force':>14} {'ratio':>8}"
        f"   (per evaluation, median of {repeat})"
    )
    for n in (1, 1_000, 100_000):
        steps = max(20, (200 if args.quick else 2000) // max(1, n // 1000))
        ours = per_eval(n, False, steps, repeat)
        theirs = per_eval(n, True, steps, repeat)
        print(f"{n:>10} {ours * 1e6:>10.2f} us {theirs * 1e6:>12.2f} us {theirs / ours:>7.1f}x")


if __name__ == "__main__":
    main()
