"""The notes' spring, 144,000 steps recorded: physstep.simulate against a numba loop
recording the same arrays, in one run.

    python bench/bench_spring.py [--quick]

Both run the `spring` scene (m = 10 kg, k = 5 N/m, x0 = 20 m, a zero-rest spring to the
origin) with symplectic Euler at dt = 1/120 s for 1200 s, and record every step: t, x, v, a,
the energy, the kinetic energy and the exact solution. physstep does it in one call of
`physstep.simulate` (the recording loop in Rust, the arrays handed to numpy); the numba loop
fills preallocated arrays with physstep's arithmetic. Printed: ns per recorded step (median
of repeats), the ratio, and the largest difference of the trajectories (0 = bitwise).
"""

from __future__ import annotations

import argparse

import numpy as np
import physstep
from common import median_time, row
from numba import njit

M, K, X0, DT = 10.0, 5.0, 20.0, 1.0 / 120.0


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
    ref = median_time(lambda: record(steps, DT), repeat) / steps * 1e9
    ours = (
        median_time(lambda: physstep.simulate("spring", "symplectic-euler", dt=DT, until=until), repeat)
        / steps
        * 1e9
    )
    tr = physstep.simulate("spring", "symplectic-euler", dt=DT, until=until)
    nb = record(steps, DT)
    gap = np.abs(tr.x[:, 0] - nb[1]).max()
    print(f"spring, symplectic Euler, dt = 1/120, {steps} steps, every step recorded")
    row("numba loop recording t x v a E K exact", ref, "ns/step")
    row("physstep.simulate", ours, "ns/step", ref, "numba")
    print(f"largest difference of x: {gap:.1e} m (0 = bitwise the same)")


if __name__ == "__main__":
    main()
