"""N-body gravity: physstep against REBOUND, same bodies, same step, same threads.

    python bench/bench_nbody.py [--n 1000] [--steps 200] [--quick]

Both integrate the same N bodies (3D, G = 1, total mass 1 in a unit ball, softening 0.05,
dt = 1e-3) with a leapfrog (physstep `leapfrog`, kick-drift-kick; REBOUND `leapfrog`,
drift-kick-drift) and direct summation. physstep runs with 1 and with 2 threads (each in its
own process: rayon's pool is global); REBOUND from PyPI is built without OpenMP, so it runs
on 1 thread. Printed: ms per step (median of repeats), the ratio REBOUND / physstep (above 1:
physstep faster), the relative energy error of each after the run, and how far apart the two
trajectories are (the same physics to the integrators' own error).
"""

from __future__ import annotations

import argparse
import json
import sys

import numpy as np
from common import in_subprocess, row

G, EPS, DT = 1.0, 0.05, 1e-3


def energy(x: np.ndarray, v: np.ndarray, m: np.ndarray) -> float:
    """Kinetic plus softened potential energy, one formula for both engines."""
    d = x[:, None, :] - x[None, :, :]
    inv = 1.0 / np.sqrt((d**2).sum(-1) + EPS**2)
    np.fill_diagonal(inv, 0.0)
    return 0.5 * float((m * (v**2).sum(1)).sum()) - 0.5 * G * float(m @ inv @ m)


def bodies(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """N bodies in a unit ball, small random velocities, equal masses summing to 1."""
    rng = np.random.default_rng(1)
    x = rng.normal(size=(n, 3))
    x *= (rng.random(n) ** (1 / 3) / np.linalg.norm(x, axis=1))[:, None]
    v = 0.1 * rng.normal(size=(n, 3))
    return x, v, np.full(n, 1.0 / n)


PHYSSTEP = """
import json, sys, time, statistics
import numpy as np, physstep
sys.path.insert(0, {bench!r})
from bench_nbody import bodies, G, EPS, DT
x, v, m = bodies({n})
w = physstep.World(3, method="leapfrog", dt=DT)
w.add_particles(x, v, m)
w.add_nbody_gravity(G, EPS)
w.step(2)
times = []
for _ in range({repeat}):
    t0 = time.perf_counter(); w.step({steps}); times.append(time.perf_counter() - t0)
print(json.dumps({{"ms": statistics.median(times) / {steps} * 1e3,
                  "x": w.positions.tolist(), "v": w.velocities.tolist()}}))
"""


def rebound_run(n: int, steps: int, repeat: int) -> dict[str, object]:
    import rebound

    x, v, m = bodies(n)
    sim = rebound.Simulation()
    sim.G, sim.softening, sim.dt = G, EPS, DT
    sim.integrator, sim.gravity = "leapfrog", "basic"
    for i in range(n):
        sim.add(m=m[i], x=x[i, 0], y=x[i, 1], z=x[i, 2], vx=v[i, 0], vy=v[i, 1], vz=v[i, 2])
    sim.steps(2)
    import statistics
    import time

    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        sim.steps(steps)
        times.append(time.perf_counter() - t0)
    pos = np.array([[p.x, p.y, p.z] for p in sim.particles])
    vel = np.array([[p.vx, p.vy, p.vz] for p in sim.particles])
    return {"ms": statistics.median(times) / steps * 1e3, "x": pos.tolist(), "v": vel.tolist()}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--n", type=int, default=1000)
    p.add_argument("--steps", type=int, default=100)
    p.add_argument("--quick", action="store_true", help="N = 300, fewer steps and repeats")
    a = p.parse_args()
    n, steps, repeat = (300, 20, 3) if a.quick else (a.n, a.steps, 5)
    try:
        import rebound
    except ImportError:
        sys.exit("REBOUND is not installed: pip install -e .[bench]")
    bench = str(__import__("pathlib").Path(__file__).parent)
    code = PHYSSTEP.format(bench=bench, n=n, steps=steps, repeat=repeat)
    ours = {t: in_subprocess(code, t) for t in (1, 2)}
    ref = rebound_run(n, steps, repeat)
    print(f"n-body N = {n}, leapfrog, dt = {DT}, softening {EPS}, {steps} steps per call")
    print(f"REBOUND {rebound.__version__} (basic gravity, 1 thread: the PyPI build has no OpenMP)")
    row("REBOUND, 1 thread", ref["ms"], "ms/step")
    for t, r in ours.items():
        row(f"physstep, {t} thread{'s' if t > 1 else ''}", r["ms"], "ms/step", ref["ms"], "of REBOUND")
        print(f"{'':<44} speed-up over REBOUND: {ref['ms'] / r['ms']:.2f}x")
    # Same physics: the two leapfrogs differ by O(dt^2) per unit time, far below the spread.
    gap = np.abs(np.array(ours[1]["x"]) - np.array(ref["x"])).max()
    x0, v0, m = bodies(n)
    e0 = energy(x0, v0, m)

    def de(r: dict[str, object]) -> float:
        return abs(energy(np.array(r["x"]), np.array(r["v"]), m) - e0) / abs(e0)

    print(f"relative energy error after the run: physstep {de(ours[1]):.2e}, REBOUND {de(ref):.2e}")
    print(f"largest position difference physstep vs REBOUND: {gap:.2e} (bodies span ~2)")
    same = np.array_equal(np.array(ours[1]["x"]), np.array(ours[2]["x"]))
    print(f"physstep 1 vs 2 threads bitwise identical: {same}")
    print(json.dumps({"physstep_1": ours[1]["ms"], "physstep_2": ours[2]["ms"], "rebound": ref["ms"]}))


if __name__ == "__main__":
    main()
