"""Stiff spring networks under backward Euler: steps per second against the size, with the
Newton and conjugate-gradient iteration counts, the sparse solve against the dense one.

    python bench/bench_stiff.py [--quick]

The `stiff-chain` scene (k = 1e5 N/m, 10 g particles: k / m dt^2 = 2800 at dt = 1/60 s,
where symplectic Euler diverges within 30 steps) for 60 steps (1 s) from rest at each size,
with the sparse solve (3 x 3 blocks, block-Jacobi conjugate gradients) and, where it fits,
the dense LU. Printed: ms per step, Newton updates and CG iterations per step, and the
dense/sparse ratio measured in the same run. Nothing is asserted.
"""

from __future__ import annotations

import argparse
import time

import physstep
from common import row

STEPS = 60


def run(n: int, dense: bool) -> tuple[float, float, float]:
    """ms/step, Newton updates/step, CG iterations/step of `n` moving links."""
    w = physstep.World.from_scene("stiff-chain", "backward-euler", params={"n": n})
    w.set_implicit(dense_up_to=10**9 if dense else 0, cg_max_iter=100_000)
    newton = cg = 0
    t0 = time.perf_counter()
    for _ in range(STEPS):
        w.step(1)
        s = w.solve_stats
        newton += s["newton"]
        cg += s["cg"]
    return (time.perf_counter() - t0) / STEPS * 1e3, newton / STEPS, cg / STEPS


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="smaller sizes")
    a = p.parse_args()
    sizes = [10, 40, 100] if a.quick else [10, 40, 100, 400, 1000]
    print(f"stiff-chain, backward Euler, dt = 1/60 s, {STEPS} steps from rest")
    for n in sizes:
        ms, newton, cg = run(n, dense=False)
        label = f"n = {n:5d} sparse ({newton:.1f} Newton, {cg:.0f} CG / step)"
        if 4 * (n + 1) <= 1024:
            ms_dense, _, _ = run(n, dense=True)
            row(label, ms, "ms/step", ms_dense, "dense")
        else:
            row(label, ms, "ms/step")


if __name__ == "__main__":
    main()
