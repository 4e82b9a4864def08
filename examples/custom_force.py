"""A force of your own, written in Python: wind drag towards a wind velocity.

The callable gets all particles at once, (n, dim) arrays, once per force evaluation: never
per particle. With no potential the energy is unknown (None), not wrong.

    python examples/custom_force.py
"""

from __future__ import annotations

import math

import numpy as np
import physstep

C, WIND = 0.5, np.array([3.0, 0.0])


def wind(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
    """F = -c (v - wind) on every particle, N."""
    return -C * (v - WIND)


def wind_jacobian(t: float, x: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """dF/dx = 0, dF/dv = -c I: lets the implicit methods solve exactly."""
    n = x.size
    return np.zeros((n, n)), -C * np.eye(n)


def main() -> None:
    for method in ("rk4", "backward-euler"):
        w = physstep.World(2, method=method, dt=1 / 120)
        w.add_particles(np.array([[0.0, 10.0], [5.0, 10.0]]))
        w.add_gravity([0.0, -9.81])
        w.add_force(wind, jacobian=wind_jacobian)
        w.step(120)
        vx = w.velocities[:, 0]
        exact = 3.0 * (1.0 - math.exp(-C))  # vx(t) = 3 (1 - exp(-c t / m)), m = 1, t = 1
        print(f"{method:>15}: vx after 1 s = {vx[0]:.6f} m/s (exact {exact:.6f}); energy {w.energy()}")
        assert abs(vx[0] - exact) < (1e-9 if method == "rk4" else 1e-2)
        assert w.energy() is None


if __name__ == "__main__":
    main()
