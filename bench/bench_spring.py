"""The notes' spring, 144,000 steps recorded: physstep.simulate against a numba loop
recording the same arrays, in one run.

    python bench/bench_spring.py [--quick]

Both run the `spring` scene (m = 10 kg, k = 5 N/m, x0 = 20 m, a zero-rest spring to the
origin) with symplectic Euler at dt = 1/120 s for 1200 s, and record every step. physstep
does it in one call of `physstep.simulate` (the recording loop in Rust, the arrays handed to
numpy), which records t, x, v, a and the energy and computes the kinetic energy and the
exact solution when they are first read; the numba loops fill preallocated arrays with
physstep's arithmetic, one with t, x, v, a and E (issue 22's peer: target at most 1.3x it),
one with the kinetic energy and the exact solution as well (against which `simulate` then
reading both is compared). Printed: ns per recorded step (median of repeats), the ratios,
and the largest difference of the trajectories (0 = bitwise).
"""

from __future__ import annotations

import argparse

import numpy as np
import physstep
from common import median_time, row
from numba import njit

M, K, X0, DT = 10.0, 5.0, 20.0, 1.0 / 120.0


@njit
def record_state(steps, dt):  # noqa: ANN001, ANN201
    n = steps + 1
    t, x, v, a, e = np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    im = 1.0 / M
    xi, vi = X0, 0.0
    for s in range(n):
        ai = (0.0 + (-K * (xi - 0.0) - 0.0 * vi)) * im + 0.0
        t[s], x[s], v[s], a[s] = s * dt, xi, vi, ai
        e[s] = 0.5 * M * (vi * vi) + 0.5 * K * ((xi - 0.0) * (xi - 0.0))
        vi += dt * ai
        xi += dt * vi
    return t, x, v, a, e


@njit
def record(steps, dt):  # noqa: ANN001, ANN201
    n = steps + 1
    t, x, v, a = np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    e, ke, ex, ev = np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    im, w0 = 1.0 / M, np.sqrt(K / M)
    xi, vi = X0, 0.0
    for s in range(n):
        ai = (0.0 + (-K * (xi - 0.0) - 0.0 * vi)) * im + 0.0
        kin = 0.5 * M * (vi * vi)
        t[s], x[s], v[s], a[s] = s * dt, xi, vi, ai
        ke[s], e[s] = kin, kin + 0.5 * K * ((xi - 0.0) * (xi - 0.0))
        ex[s], ev[s] = X0 * np.cos(w0 * s * dt), -X0 * w0 * np.sin(w0 * s * dt)
        vi += dt * ai
        xi += dt * vi
    return t, x, v, a, e, ke, ex, ev


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="14,400 steps, fewer repeats")
    a = p.parse_args()
    until, repeat = (120.0, 3) if a.quick else (1200.0, 5)
    steps = round(until / DT)
    record(10, DT)  # compile
    record_state(10, DT)
    peer = median_time(lambda: record_state(steps, DT), repeat) / steps * 1e9
    full = median_time(lambda: record(steps, DT), repeat) / steps * 1e9

    def sim() -> physstep.Trajectory:
        return physstep.simulate("spring", "symplectic-euler", dt=DT, until=until)

    def sim_read() -> physstep.Trajectory:
        tr = sim()
        _ = tr.kinetic, tr.exact_x, tr.exact_v
        return tr

    ours = median_time(sim, repeat) / steps * 1e9
    ours_read = median_time(sim_read, repeat) / steps * 1e9
    tr = sim()
    nb = record(steps, DT)
    gap = max(
        float(np.abs(tr.x[:, 0] - nb[1]).max()),
        float(np.abs(tr.energy - nb[4]).max()),
        float(np.abs(tr.kinetic - nb[5]).max()),
    )
    print(f"spring, symplectic Euler, dt = 1/120, {steps} steps, every step recorded")
    row("numba loop recording t x v a E", peer, "ns/step")
    row("physstep.simulate (K and exact when read)", ours, "ns/step", peer, "numba t x v a E (target 1.3x)")
    row("numba loop recording t x v a E K exact", full, "ns/step", peer, "numba t x v a E")
    row("physstep.simulate, then K and exact read", ours_read, "ns/step", full, "numba with K and exact")
    print(f"largest difference of x, E and K: {gap:.1e} (0 = bitwise the same)")


if __name__ == "__main__":
    main()
