"""A game loop with a fixed physics step and render interpolation.

Frames arrive at an uneven rate (as they do in a game); the World turns each frame's time
into fixed steps (the accumulator of the notes), caps the steps per frame, and hands back
positions interpolated between the last two physics states for drawing.

    python examples/game_loop.py
"""

from __future__ import annotations

import numpy as np
import physstep


def main() -> None:
    w = physstep.World(2, method="velocity-verlet", dt=1 / 120, max_steps_per_frame=8)
    anchor = w.add_particle([0.0, 0.0], static=True)
    bob = w.add_particle([1.0, 0.0], mass=1.0)
    w.add_gravity([0.0, -9.81])
    w.add_spring(bob, anchor, stiffness=200.0, damping=0.0)  # rest length: 1 m, as placed
    e0 = w.energy()

    rng = np.random.default_rng(7)
    drawn = []
    for _frame in range(600):  # about 10 s at 60 fps, with jitter
        frame_time = 1 / 60 + rng.normal(0.0, 0.004)
        w.advance(max(frame_time, 0.0))
        drawn.append(w.interpolated_positions()[bob])  # what the renderer would draw
    frames, steps, clamped, dropped = w.clock_stats
    drift = abs(w.energy() - e0) / (1.0 * 9.81 * 1.0)  # against m g L, the energy that swings
    print(f"{frames} frames, {steps} fixed steps of {w.dt:.5f} s, t = {w.time:.3f} s")
    print(f"clamped {clamped:.3f} s, dropped {dropped:.3f} s; relative energy change {drift:.2e}")
    print(f"last drawn position {np.round(drawn[-1], 4)} (alpha = {w.alpha:.3f})")
    assert drift < 1e-2, "velocity Verlet keeps the energy of the swinging spring bounded"


if __name__ == "__main__":
    main()
