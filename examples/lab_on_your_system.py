"""The integrator lab on your own system: a Duffing oscillator written as a Python force.

x'' = -x - x^3 from x = 1 at rest, with its potential (so the energy is known) and its
Jacobian (for the implicit methods). It has no exact solution: the lab measures the error
against a reference run (RK4 at a sixteenth of the finest dt) and estimates the natural
time scale from the initial state (2 pi sqrt(|x0| / |a0|) = 4.44 s here).

    python examples/lab_on_your_system.py
"""

from __future__ import annotations

import numpy as np
import physstep
from physstep import lab

METHODS = ("explicit-euler", "symplectic-euler", "velocity-verlet", "rk4", "implicit-midpoint")


def duffing() -> physstep.World:
    """A fresh world: one particle at x = 1 under F = -x - x^3 (unit mass)."""
    w = physstep.World(1)
    w.add_particle([1.0])
    w.add_force(
        lambda t, x, v: -x - x**3,
        potential=lambda x: float((x**2 / 2 + x**4 / 4).sum()),
        jacobian=lambda t, x, v: (np.diag(-1.0 - 3.0 * x.ravel() ** 2), np.zeros((x.size, x.size))),
        velocity_dependent=False,
    )
    return w


def main() -> None:
    print(f"natural time scale (estimated): {lab.time_scale(duffing):.4f} s")
    print(f"{'method':<18} {'order':>5} {'observed':>8} {'dt_max (s)':>11}  note")
    for m in METHODS:
        o = lab.order(duffing, m, levels=4)
        s = lab.stability(duffing, m, rtol=1e-3)
        dt_max = "no limit" if s.dt_max is None else f"{s.dt_max:.4f}"
        note = "stable again just above" if s.stable_above else ""
        print(f"{m:<18} {o.info_order:>5} {o.order:>8.3f} {dt_max:>11}  {note}")
        assert abs(o.order - o.info_order) < 0.15
    print(f"errors against the {o.error_against}")
    print(f"stability: {s.criterion}")


if __name__ == "__main__":
    main()
