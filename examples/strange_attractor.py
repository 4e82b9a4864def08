"""The Lorenz attractor, a first-order flow, through the same integrators as F = ma.

Written as your own flow (physstep.Flow) and checked against the built-in scene; the
split methods (symplectic Euler, Verlet, ...) refuse a flow in one line. Pass a file name
to save a picture of the attractor.

    python examples/strange_attractor.py [lorenz.png]
"""

from __future__ import annotations

import sys

import numpy as np
import physstep


def lorenz(t: float, y: np.ndarray) -> np.ndarray:
    """dy/dt of the Lorenz system (sigma = 10, rho = 28, beta = 8/3)."""
    sigma, rho, beta = 10.0, 28.0, 8 / 3
    return np.array([sigma * (y[1] - y[0]), y[0] * (rho - y[2]) - y[1], y[0] * y[1] - beta * y[2]])


def main(out: str | None) -> None:
    flow = physstep.Flow(lorenz, [1.0, 1.0, 1.0], name="lorenz (Python)")
    mine = physstep.simulate(flow, "rk4", dt=0.005, until=20.0)
    built = physstep.simulate("lorenz", "rk4", dt=0.005, until=20.0)
    gap = float(np.abs(mine.x - built.x)[: len(mine.t) // 4].max())
    print(f"{mine.steps} RK4 steps; Python flow vs built-in over the first 5 s: {gap:.1e}")
    assert gap < 1e-9
    try:
        physstep.simulate(flow, "symplectic-euler", dt=0.005, until=1.0)
    except ValueError as e:
        print(f"symplectic Euler: {e}")
    if out:
        plot = physstep.plot
        fig = plot.path3d(built) if hasattr(plot, "path3d") else plot.trajectory(built)
        physstep.plot.save(fig, out)
        print(f"wrote {out}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
