"""A pile that comes to rest: physstep's `pile` scene against pymunk (Chipmunk2D).

    python bench/bench_pile.py [--n 1000] [--restitution 0.5] [--seconds 10]

Both step the same N balls (2D, radius 0.05 m, 1 kg, dropped from the scene's jittered
lattice into its box under gravity 9.81 m/s^2, restitution 0.5, dt = 1/120 s, one thread).
physstep keeps each impact an event at its time of impact and solves the contacts of balls
that rest together as constraints (docs/collisions.md, "Balls that rest"); pymunk solves every
contact with its iterative impulse solver (10 iterations, elasticity as the restitution, no
friction, rotation locked: physstep's balls are frictionless particles), the way a game would
set it up. Printed: ms per step over the whole run (fall and rest), the ratio pymunk /
physstep (above 1: physstep faster), the kinetic energy at the end over its peak, and the
deepest overlap at the end. Nothing is asserted: a measurement, not a test. pymunk is an
optional extra (`pip install -e .[bench]`); without it only physstep's line is printed.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import physstep
from common import deepest_overlap

DT, R, G = 1.0 / 120.0, 0.05, 9.81


def overlap(x: np.ndarray) -> float:
    """Deepest overlap of two balls (all of radius R), m: 0 when none overlap."""
    return deepest_overlap(x, R)


def run_physstep(n: int, e: float, steps: int) -> tuple[float, float, float]:
    w = physstep.World.from_scene("pile", params={"n": n, "restitution": e, "radius": R, "g": G}, dt=DT)
    peak, start = 0.0, time.perf_counter()
    for _ in range(steps):
        w.step(1)
        peak = max(peak, 0.5 * float((w.velocities**2).sum()))
    elapsed = time.perf_counter() - start
    end = 0.5 * float((w.velocities**2).sum())
    return 1e3 * elapsed / steps, end / peak, overlap(w.positions.copy())


def run_pymunk(n: int, e: float, steps: int) -> tuple[float, float, float] | None:
    try:
        import pymunk
    except ImportError:
        return None
    w = physstep.World.from_scene("pile", params={"n": n, "restitution": e, "radius": R, "g": G}, dt=DT)
    x, v = w.positions.copy(), w.velocities.copy()
    lo, hi = w.walls
    space = pymunk.Space()
    space.gravity = (0.0, -G)
    space.iterations = 10
    corners = [(lo[0], lo[1]), (hi[0], lo[1]), (hi[0], hi[1]), (lo[0], hi[1])]
    for a, b in zip(corners, corners[1:] + corners[:1], strict=True):
        wall = pymunk.Segment(space.static_body, a, b, 0.0)
        wall.elasticity, wall.friction = e, 0.0
        space.add(wall)
    bodies = []
    for p, u in zip(x, v, strict=True):
        body = pymunk.Body(1.0, float("inf"))
        body.position, body.velocity = (float(p[0]), float(p[1])), (float(u[0]), float(u[1]))
        shape = pymunk.Circle(body, R)
        shape.elasticity, shape.friction = e, 0.0
        space.add(body, shape)
        bodies.append(body)

    def kinetic() -> float:
        return 0.5 * sum(b.velocity.x**2 + b.velocity.y**2 for b in bodies)

    peak, start = 0.0, time.perf_counter()
    for _ in range(steps):
        space.step(DT)
        peak = max(peak, kinetic())
    elapsed = time.perf_counter() - start
    xs = np.array([[b.position.x, b.position.y] for b in bodies])
    return 1e3 * elapsed / steps, kinetic() / peak, overlap(xs)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1000)
    ap.add_argument("--restitution", type=float, default=0.5)
    ap.add_argument("--seconds", type=float, default=10.0)
    args = ap.parse_args()
    steps = round(args.seconds / DT)
    print(f"pile N = {args.n}, restitution {args.restitution}, dt = 1/120 s, {steps} steps, one thread")
    ours = run_physstep(args.n, args.restitution, steps)
    print(f"physstep: {ours[0]:.3f} ms/step, end/peak kinetic {ours[1]:.2e}, overlap {ours[2]:.2e} m")
    theirs = run_pymunk(args.n, args.restitution, steps)
    if theirs is None:
        print("pymunk: not installed (pip install -e .[bench])")
        return
    print(f"pymunk:   {theirs[0]:.3f} ms/step, end/peak kinetic {theirs[1]:.2e}, overlap {theirs[2]:.2e} m")
    print(f"ratio pymunk / physstep: {theirs[0] / ours[0]:.2f}x")


if __name__ == "__main__":
    main()
