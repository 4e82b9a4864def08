"""Side-by-side speed of physstep against what people would otherwise write.

Prints, for each case, the time per step of physstep and of the reference measured in the
same run, and their ratio (reference / physstep: above 1 means physstep is faster). Nothing
here is asserted: speed lives in benchmarks, never in tests.

    python bench/bench_peers.py [--quick]

References: a vectorised numpy symplectic-Euler loop (the usual "fast Python" particle
update), a plain-Python loop over the notes' spring, a numpy all-pairs n-body, and, when
scipy is installed (`pip install -e .[bench]`), scipy's RK45 on the orbit.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable

import numpy as np
import physstep


def best(fn: Callable[[], object], repeat: int) -> float:
    """Best wall time of `repeat` calls, s."""
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def row(name: str, ours: float, ref: float, ref_name: str, unit: str) -> None:
    print(
        f"{name:<34} physstep {ours:10.3g} {unit}   {ref_name} {ref:10.3g} {unit}   ratio {ref / ours:6.2f}x"
    )


def particles_gravity(n: int, steps: int, repeat: int) -> None:
    rng = np.random.default_rng(1)
    x0, v0 = rng.random((n, 3)), rng.random((n, 3))
    w = physstep.World(3, method="symplectic-euler", dt=0.01)
    w.add_particles(x0, v0, np.ones(n))
    w.add_gravity([0.0, 0.0, -9.81])
    ours = best(lambda: w.step(steps), repeat) / steps / n * 1e9
    x, v, g = x0.copy(), v0.copy(), np.array([0.0, 0.0, -9.81])

    def numpy_loop() -> None:
        nonlocal x, v
        for _ in range(steps):
            v += g * 0.01
            x += v * 0.01

    ref = best(numpy_loop, repeat) / steps / n * 1e9
    row(f"{n} particles, gravity", ours, ref, "numpy", "ns/particle-step")


def spring_single(steps: int, repeat: int) -> None:
    ours = best(lambda: physstep.simulate("spring", "symplectic-euler", dt=0.01, until=steps * 0.01), repeat)

    def python_loop() -> None:
        x, v, xs = 20.0, 0.0, []
        for _ in range(steps):
            v += -x / 2 * 0.01
            x += v * 0.01
            xs.append(x)

    ref = best(python_loop, repeat)
    row("1D spring, recorded trajectory", ours / steps * 1e9, ref / steps * 1e9, "python", "ns/step")


def nbody(n: int, steps: int, repeat: int) -> None:
    w = physstep.World.from_scene("nbody", "velocity-verlet", 1e-3, [("n", float(n))])
    ours = best(lambda: w.step(steps), repeat) / steps * 1e6
    x = w.positions
    m = np.full(n, 1.0 / n)

    def numpy_accel() -> np.ndarray:
        d = x[None, :, :] - x[:, None, :]
        r2 = (d**2).sum(-1) + 0.05**2
        return (d * (m[None, :, None] / r2[..., None] ** 1.5)).sum(1)

    ref = best(lambda: [numpy_accel() for _ in range(steps)], repeat) / steps * 1e6
    row(f"n-body n={n} (accel per step)", ours, ref, "numpy", "us/step")


def orbit_scipy(repeat: int) -> None:
    try:
        from scipy.integrate import solve_ivp
    except ImportError:
        print("orbit vs scipy RK45: skipped (pip install -e .[bench])")
        return
    traj = physstep.simulate("orbit", "rk4", dt=0.01, until=2 * np.pi * 10, every=100)
    ours = best(lambda: physstep.simulate("orbit", "rk4", dt=0.01, until=2 * np.pi * 10, every=100), repeat)

    def f(_t: float, y: np.ndarray) -> np.ndarray:
        r3 = (y[0] ** 2 + y[1] ** 2) ** 1.5
        return np.array([y[2], y[3], -y[0] / r3, -y[1] / r3])

    ref = best(lambda: solve_ivp(f, (0, 2 * np.pi * 10), [1, 0, 0, 1], rtol=1e-9, atol=1e-12), repeat)
    print(f"  (physstep rk4 final position error {traj.position_error[-1]:.2e})")
    row("orbit, 10 periods", ours * 1e3, ref * 1e3, "scipy RK45", "ms/run")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="small sizes, one repeat")
    a = p.parse_args()
    repeat = 1 if a.quick else 3
    particles_gravity(100_000 if a.quick else 1_000_000, 10, repeat)
    spring_single(10_000 if a.quick else 100_000, repeat)
    nbody(200 if a.quick else 1000, 5, repeat)
    orbit_scipy(repeat)


if __name__ == "__main__":
    main()
