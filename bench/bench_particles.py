"""Particles under gravity and drag: physstep against numba loops doing the same arithmetic,
and the memory floor, in one run.

    python bench/bench_particles.py [--n 1000000] [--quick] [--json FILE]

Workload: N particles in 3D (f64), gravity (0, 0, -9.81) and linear drag 0.1 N s/m on unit
masses, dt = 1/120, 10 steps per call, for symplectic Euler, velocity Verlet and RK4. The
peers are `numba.njit(parallel=True)` loops over the particles (`prange`) with the steps
outside, written operation for operation as physstep computes them (no fastmath), on the
same number of threads. The memory floor is the least traffic a step needs: a numba loop
that reads every position and velocity and writes them back (96 bytes per particle-step),
with no physics. Printed: ns per particle-step (median of repeats) and the ratios; after
the timed calls, how far physstep's and numba's states are apart (0 = bitwise equal).
"""

from __future__ import annotations

import argparse

import numba
import numpy as np
import physstep
from common import median_time, row, write_json
from numba import njit, prange

H, C, G = 1.0 / 120.0, 0.1, np.array([0.0, 0.0, -9.81])
STEPS = 10


@njit(inline="always")
def acc(v: float, s: float, im: float, g: float) -> float:
    """physstep's per-element acceleration: (0 + s v) / m + g."""
    return (0.0 + s * v) * im + g


@njit(parallel=True)
def floor_kernel(x, v, c, steps):  # noqa: ANN001, ANN201
    for _ in range(steps):
        for i in prange(x.shape[0]):
            for k in range(3):
                a = x[i, k]
                b = v[i, k]
                x[i, k] = a * c
                v[i, k] = b * c


@njit(parallel=True)
def se_kernel(x, v, s, g, h, steps):  # noqa: ANN001, ANN201
    for _ in range(steps):
        for i in prange(x.shape[0]):
            for k in range(3):
                a = acc(v[i, k], s, 1.0, g[k])
                v[i, k] += h * a
                x[i, k] += h * v[i, k]


@njit(parallel=True)
def vv_kernel(x, v, s, g, h, steps):  # noqa: ANN001, ANN201
    # Velocity Verlet with a velocity-dependent force, as physstep takes it: the closing kick
    # at the velocity predicted by two fixed-point passes.
    hh = 0.5 * h
    for _ in range(steps):
        for i in prange(x.shape[0]):
            for k in range(3):
                vi = v[i, k] + hh * acc(v[i, k], s, 1.0, g[k])
                x[i, k] += h * vi
                a = acc(vi, s, 1.0, g[k])
                v_half = vi
                for _p in range(2):
                    vi = v_half + hh * a
                    a = acc(vi, s, 1.0, g[k])
                v[i, k] = vi


@njit(parallel=True)
def rk4_kernel(x, v, s, g, h, steps):  # noqa: ANN001, ANN201
    hh, h6 = 0.5 * h, h / 6.0
    for _ in range(steps):
        for i in prange(x.shape[0]):
            for k in range(3):
                x0, v0 = x[i, k], v[i, k]
                a0 = acc(v0, s, 1.0, g[k])
                va = v0 + hh * a0
                aa = acc(va, s, 1.0, g[k])
                vb = v0 + hh * aa
                ab = acc(vb, s, 1.0, g[k])
                vc = v0 + (1.0 * h) * ab
                ac = acc(vc, s, 1.0, g[k])
                x[i, k] = x0 + h6 * (v0 + 2.0 * va + 2.0 * vb + vc)
                v[i, k] = v0 + h6 * (a0 + 2.0 * aa + 2.0 * ab + ac)


KERNELS = {"symplectic-euler": se_kernel, "velocity-verlet": vv_kernel, "rk4": rk4_kernel}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--n", type=int, default=1_000_000)
    p.add_argument("--quick", action="store_true", help="N = 100,000 and fewer repeats")
    p.add_argument("--json", help="also write the table to this file")
    a = p.parse_args()
    n, repeat = (100_000, 3) if a.quick else (a.n, 7)
    rng = np.random.default_rng(1)
    x0, v0 = rng.random((n, 3)), rng.random((n, 3))
    s = -(C + 0.0 * 0.0)  # physstep's drag factor with no quadratic term
    per = 1e9 / (STEPS * n)
    print(f"N = {n}, 3D f64, gravity + linear drag, dt = 1/120, {STEPS} steps per call")
    print(f"threads: numba {numba.get_num_threads()}, physstep (rayon) the same machine's default")
    x, v = x0.copy(), v0.copy()
    floor = median_time(lambda: floor_kernel(x, v, 1.0, STEPS), repeat) * per
    row("memory floor (numba, read + write x and v)", floor, "ns/particle-step")
    out: dict[str, object] = {"n": n, "floor": floor}
    for method, kernel in KERNELS.items():
        xn, vn = x0.copy(), v0.copy()
        kernel(xn, vn, s, G, H, 1)  # compile
        xn, vn = x0.copy(), v0.copy()
        ref = median_time(lambda k=kernel, xn=xn, vn=vn: k(xn, vn, s, G, H, STEPS), repeat, 0) * per
        w = physstep.World(3, method=method, dt=H)
        w.add_particles(x0, v0, np.ones(n))
        w.add_gravity(list(G))
        w.add_drag(C)
        ours = median_time(lambda w=w: w.step(STEPS), repeat, 0) * per
        # Both took `repeat` calls of STEPS steps from the same state.
        dx = np.abs(w.positions - xn).max() / np.abs(xn).max()
        dv = np.abs(w.velocities - vn).max() / np.abs(vn).max()
        row(f"numba prange, {method}", ref, "ns/particle-step")
        row(f"physstep, {method}", ours, "ns/particle-step", ref, "numba")
        if method == "symplectic-euler":
            print(f"{'':<44} {ours / floor:6.2f}x the memory floor")
        print(f"{'':<44} state apart after the run: x {dx:.1e}, v {dv:.1e} (relative)")
        out[method] = {"physstep": ours, "numba": ref, "dx": dx, "dv": dv}
    write_json(a.json, out)


if __name__ == "__main__":
    main()
