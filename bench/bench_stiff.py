"""Stiff spring networks under backward Euler: steps per second against the size, with the
Newton and conjugate-gradient iteration counts, the sparse solve against the dense one.

    python bench/bench_stiff.py [--quick]

The `stiff-chain` scene (k = 1e5 N/m, 10 g particles: k / m dt^2 = 2800 at dt = 1/60 s,
where symplectic Euler diverges within 30 steps) for 60 steps (1 s) from rest at each size,
with the sparse solve (3 x 3 blocks, block-Jacobi conjugate gradients) and, where it fits,
the dense LU. Printed: ms per step, Newton updates and CG iterations per step, and the
dense/sparse ratio measured in the same run.

Then the memory of the sparse solve on `stiff-cloth` grids up to 100 x 100 (10,000
particles, 60,000 unknowns, whose dense Jacobian would take 28.8 GB): each size in a fresh
process, the peak resident memory while backward Euler takes its first steps less the
resident memory of the built world, per particle. Nothing is asserted.
"""

from __future__ import annotations

import argparse
import time

import physstep
from common import in_subprocess, row

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


# Peak resident memory (VmHWM) less resident memory (VmRSS) once the world is built: what
# the steps allocated. Linux's /proc; the bench prints nothing for this part elsewhere.
MEMORY = """
import json, time, physstep
def status(key):
    with open('/proc/self/status') as f:
        return next(int(l.split()[1]) * 1024 for l in f if l.startswith(key + ':'))
w = physstep.World.from_scene('stiff-cloth', 'backward-euler', params={{'n': {n}}})
w.set_implicit(dense_up_to=0, cg_max_iter=100_000)
base = status('VmRSS')
t0 = time.perf_counter()
w.step({steps})
ms = (time.perf_counter() - t0) / {steps} * 1e3
print(json.dumps({{'bytes': status('VmHWM') - base, 'ms': ms, 'cg': w.solve_stats['cg'],
                  'newton': w.solve_stats['newton']}}))
"""


def memory(sizes: list[int], steps: int) -> None:
    """Prints the memory the first `steps` backward-Euler steps of each cloth size took."""
    try:
        open("/proc/self/status").close()
    except OSError:
        print("(memory: /proc/self/status not available here)")
        return
    print(f"stiff-cloth, backward Euler, sparse solve: memory of the first {steps} steps")
    for n in sizes:
        r = in_subprocess(MEMORY.format(n=n, steps=steps), threads=1)
        particles, unknowns = n * n, 6 * n * n
        dense_gb = unknowns**2 * 8 / 1e9
        label = f"{n:3d} x {n:<3d} ({particles} particles)"
        row(label, r["bytes"] / particles, "bytes/particle")
        print(
            f"{'':44} {r['bytes'] / 1e6:10.1f} MB in all, {r['ms']:.0f} ms/step "
            f"({r['newton']} Newton, {r['cg']} CG the last step); dense Jacobian {dense_gb:.3g} GB"
        )


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
    memory([25, 50] if a.quick else [25, 50, 100], steps=2)


if __name__ == "__main__":
    main()
