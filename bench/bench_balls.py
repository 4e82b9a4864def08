"""Elastic balls in a box: physstep against pymunk (Chipmunk2D), same balls, same step.

    python bench/bench_balls.py [--n 5000] [--steps 240] [--quick]

Both step the same N balls (2D, radius 0.05 m, 1 kg, 30% of the box's area, random velocities
up to 1 m/s per component, restitution 1, no gravity, dt = 1/120 s), placed by physstep's
`balls` scene. physstep resolves each contact at its time of impact inside the step (its
scan of the grid runs on the rayon pool above 16,384 balls); pymunk resolves contacts with its iterative
impulse solver (10 iterations, elasticity 1 on balls and walls, no friction, rotation
locked), the way a game would set it up. Each is run on one thread and on two (physstep
with RAYON_NUM_THREADS; pymunk with `Space(threaded=True)`, `space.threads = 2`), and the
pairs compared thread count for thread count. Printed: ms per step (median of repeats), the
ratios pymunk / physstep (above 1: physstep faster), the relative kinetic-energy drift of
each after the whole run, and the deepest overlap left at the end.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time

import numpy as np
from common import deepest_overlap, in_subprocess, row

DT, R, FRACTION = 1.0 / 120.0, 0.05, 0.3


def scene(n: int) -> dict[str, object]:
    """The balls of physstep's scene: positions, velocities, radius, box side."""
    import physstep

    w = physstep.World.from_scene("balls", params={"n": n, "radius": R, "fraction": FRACTION})
    lo, hi = w.walls
    return {"x": w.positions.copy(), "v": w.velocities.copy(), "side": float(hi[0] - lo[0])}


def kinetic(v: np.ndarray) -> float:
    return 0.5 * float((v**2).sum())


def overlap(x: np.ndarray) -> float:
    """Deepest overlap of two balls (all of radius R), m: 0 when none overlap."""
    return deepest_overlap(x, R)


PHYSSTEP = """
import json, sys, time, statistics
import physstep
w = physstep.World.from_scene("balls", params={{"n": {n}, "radius": {r}, "fraction": {f}}})
w.step(2)
times = []
for _ in range({repeat}):
    t0 = time.perf_counter(); w.step({steps}); times.append(time.perf_counter() - t0)
print(json.dumps({{"ms": statistics.median(times) / {steps} * 1e3, "v": w.velocities.tolist(),
                  "x": w.positions.tolist(), "steps": w.steps, "collisions": w.collisions}}))
"""


def pymunk_run(n: int, steps: int, repeat: int, threads: int = 1) -> dict[str, object]:
    import pymunk

    s = scene(n)
    x, v, side = s["x"], s["v"], s["side"]
    space = pymunk.Space(threaded=threads > 1)
    if threads > 1:
        space.threads = threads
    space.iterations = 10
    walls = [((0, 0), (side, 0)), ((side, 0), (side, side)), ((side, side), (0, side)), ((0, side), (0, 0))]
    for a, b in walls:
        seg = pymunk.Segment(space.static_body, a, b, 0.0)
        seg.elasticity, seg.friction = 1.0, 0.0
        space.add(seg)
    bodies = []
    for i in range(n):
        body = pymunk.Body(1.0, float("inf"))
        body.position = tuple(x[i])
        body.velocity = tuple(v[i])
        shape = pymunk.Circle(body, R)
        shape.elasticity, shape.friction = 1.0, 0.0
        space.add(body, shape)
        bodies.append(body)
    for _ in range(2):
        space.step(DT)
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(steps):
            space.step(DT)
        times.append(time.perf_counter() - t0)
    vel = np.array([tuple(b.velocity) for b in bodies])
    pos = np.array([tuple(b.position) for b in bodies])
    return {"ms": statistics.median(times) / steps * 1e3, "v": vel.tolist(), "x": pos.tolist()}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--n", type=int, default=5000)
    p.add_argument("--steps", type=int, default=240)
    p.add_argument("--quick", action="store_true", help="N = 1000, fewer steps and repeats")
    a = p.parse_args()
    n, steps, repeat = (1000, 60, 3) if a.quick else (a.n, a.steps, 5)
    try:
        import pymunk
    except ImportError:
        sys.exit("pymunk is not installed: pip install -e .[bench]")
    code = PHYSSTEP.format(n=n, r=R, f=FRACTION, steps=steps, repeat=repeat)
    ours = {t: in_subprocess(code, t) for t in (1, 2)}
    ref = {t: pymunk_run(n, steps, repeat, t) for t in (1, 2)}
    k0 = kinetic(scene(n)["v"])
    total = 2 + steps * repeat
    print(f"balls N = {n}, 2D, radius {R} m, {FRACTION:.0%} of the area, dt = 1/120 s, {total} steps")
    print(f"pymunk {pymunk.version} (Chipmunk2D, 10 iterations, elasticity 1)")
    speedup = {}
    for t in (1, 2):
        threads = f"{t} thread{'s' * (t > 1)}"
        row(f"pymunk ({threads})", ref[t]["ms"], "ms/step")
        row(f"physstep (time of impact, {threads})", ours[t]["ms"], "ms/step", ref[t]["ms"], "of pymunk")
        speedup[t] = ref[t]["ms"] / ours[t]["ms"]
        print(f"{'':<44} speed-up over pymunk, {t} against {t}: {speedup[t]:.2f}x")
    if ours[1]["x"] != ours[2]["x"] or ours[1]["v"] != ours[2]["v"]:
        sys.exit("physstep on 1 and 2 threads differ")

    def drift(r: dict[str, object]) -> float:
        return abs(kinetic(np.array(r["v"])) - k0) / k0

    print(
        f"relative kinetic-energy drift after the run: physstep {drift(ours[1]):.2e}, "
        f"pymunk {drift(ref[1]):.2e}"
    )
    print(
        f"deepest overlap at the end: physstep {overlap(np.array(ours[1]['x'])):.2e} m, "
        f"pymunk {overlap(np.array(ref[1]['x'])):.2e} m (radius {R} m)"
    )
    count = ours[1]["collisions"]["count"]
    print(f"physstep contacts resolved: {count} (bitwise the same on 1 and 2 threads)")
    summary = {"physstep_1": ours[1]["ms"], "pymunk_1": ref[1]["ms"], "speedup_1": speedup[1]}
    summary |= {"physstep_2": ours[2]["ms"], "pymunk_2": ref[2]["ms"], "speedup_2": speedup[2]}
    summary |= {"drift_physstep": drift(ours[1]), "drift_pymunk": drift(ref[1])}
    print(json.dumps(summary))


if __name__ == "__main__":
    main()
