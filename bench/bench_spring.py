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
reading both is compared). Printed: CPU ns per recorded step (median of interleaved
repeats), the ratios, and the largest difference of the trajectories (0 = bitwise).
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
import physstep
from common import row
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

    def sim() -> physstep.Trajectory:
        return physstep.simulate("spring", "symplectic-euler", dt=DT, until=until)

    def sim_read() -> physstep.Trajectory:
        tr = sim()
        _ = tr.kinetic, tr.exact_x, tr.exact_v
        return tr

    # Interleaved rounds, CPU time of this process: on a loaded machine both sides then see
    # the same conditions, and time spent waiting for a core is not counted.
    runs = {"peer": lambda: record_state(steps, DT), "full": lambda: record(steps, DT), "ours": sim}
    runs["ours_read"] = sim_read
    times: dict[str, list[float]] = {k: [] for k in runs}
    for fn in runs.values():
        fn()
    for _ in range(repeat):
        for k, fn in runs.items():
            t0 = time.process_time()
            fn()
            times[k].append(time.process_time() - t0)
    peer, full, ours, ours_read = (statistics.median(times[k]) / steps * 1e9 for k in runs)
    tr = sim()
    nb = record(steps, DT)
    gap = max(
        float(np.abs(tr.x[:, 0] - nb[1]).max()),
        float(np.abs(tr.energy - nb[4]).max()),
        float(np.abs(tr.kinetic - nb[5]).max()),
    )
    print(f"spring, symplectic Euler, dt = 1/120, {steps} steps, every step recorded")
    row("numba loop recording t x v a E", peer, "CPU ns/step")
    row("physstep.simulate (K and exact when read)", ours, "CPU ns/step", peer, "numba txvaE (target 1.3x)")
    row("numba loop recording t x v a E K exact", full, "CPU ns/step", peer, "numba t x v a E")
    row("physstep.simulate, then K and exact read", ours_read, "CPU ns/step", full, "numba with K and exact")
    print(f"largest difference of x, E and K: {gap:.1e} (0 = bitwise the same)")


if __name__ == "__main__":
    main()
