"""Boxes that stand: physstep's `pyramid` scene against pymunk (Chipmunk2D) and Box2D 2.3.

    python bench/bench_contact.py [--rows 20] [--seconds 10] [--repeat 3]

All step the same pyramid, one thread each: `rows` rows of unit boxes (1 m x 1 m, density 1,
so 1 kg; 210 boxes for 20 rows) 1.01 m apart in a row, the rows 1 m apart, on a static ground
box 200 m x 2 m whose top is y = 0, friction 0.6 for every pair, gravity 9.81 m/s^2,
dt = 1/60 s, 600 steps for 10 s, no sleeping (each engine once more with it: below).
physstep: the scene as built (`World.from_scene("pyramid")`) under each of its contact
solvers at their default settings (the default `soft-step` first; 8 substeps x 1
iteration: 16 passes a step for each), and the soft step with 4, 3 and 2 substeps (less
work a step, more drift and penetration: the last lines print, for each awake peer,
physstep's fastest soft-step row with equal or smaller drift and overlap, and its ratio).
pymunk: `space.iterations` at its default 10; `collision_slop` 0.005 m (Box2D's linear slop:
pymunk's default 0.1 is meant for pixels and would let a 1 m box sink 10 cm); each shape's
friction sqrt(0.6), as pymunk multiplies the two frictions of a pair where physstep and Box2D
take their geometric mean. Box2D 2.3.10 (`pip install box2d`, `import Box2D`): 8 velocity
and 3 position iterations (its testbed's), sleeping off; each box's core shrunk by Box2D's
polygon radius (1 cm), the ground's too, so that a collision surface, core plus skin, is where
the others' is (the boxes' corners rounded by 1 cm). Each engine runs once more with sleeping
on: physstep's soft step with `sleep_time = 0.5` (Box2D's), pymunk with
`sleep_time_threshold = 0.5`, Box2D with its default sleeping; a resting pyramid that falls
asleep leaves the solver.

Printed per engine: ms per step (the median over `repeat` timed runs of the whole 10 s, fall
and rest, one step a call, no read-out), the top box's drift from where it started after
the 10 s, and the deepest penetration seen over the run (a separate, untimed run that reads
it every step), two ways: (1) as the engine reports it: physstep's `max_penetration`,
pymunk's contact point distances, Box2D's manifold separations (measured from its skin,
which a resting contact overlaps by its linear slop, 5 mm, on purpose); (2) the same
geometric check for all: the deepest overlap of the 1 m boxes, at their stepped poses, with
each other and with the ground (separating axes on the rectangles), also at the end. Then physstep's time per
step over each peer's (below 1: physstep faster). Nothing is asserted: a measurement, not a
test. pymunk is in the `bench` extra (`pip install -e .[bench]`), Box2D too; a peer that
does not import is named and skipped.
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import time
from collections.abc import Callable

import numpy as np
import physstep

DT, G, HALF, GAP, MU = 1.0 / 60.0, 9.81, 0.5, 0.01, 0.6


def layout(rows: int) -> np.ndarray:
    """The boxes' starting centres (n, 2), row by row from the bottom, as the scene lays them."""
    out = []
    for row in range(rows):
        k = rows - row
        out += [((i - (k - 1) / 2) * (2 * HALF + GAP), HALF + row * 2 * HALF) for i in range(k)]
    return np.array(out)


def box_overlap(x: np.ndarray, angle: np.ndarray) -> float:
    """Deepest overlap of the boxes (half extent HALF at centres `x` (n, 2), turned by `angle`
    (n,)) with each other and with the ground's top y = 0, m; 0 when none overlap."""
    c, s = np.cos(angle), np.sin(angle)
    axes = np.stack([np.stack([c, s], -1), np.stack([-s, c], -1)], 1)  # (n, 2 axes, 2)
    reach = HALF * (np.abs(axes[..., 0]) + np.abs(axes[..., 1]))  # (n, 2): half width along x, y
    worst = max(0.0, float((reach[:, 1] - x[:, 1]).max()))
    i, j = np.triu_indices(len(x), 1)
    near = np.linalg.norm(x[i] - x[j], axis=1) < 2 * math.sqrt(2) * HALF
    i, j = i[near], j[near]
    if len(i) == 0:
        return worst
    d = x[j] - x[i]
    depth = np.full(len(i), np.inf)
    for a, b in ((i, j), (j, i)):
        for k in range(2):
            ax = axes[a, k]  # an axis of box a; box a projects onto it as HALF
            other = HALF * (np.abs((axes[b, 0] * ax).sum(1)) + np.abs((axes[b, 1] * ax).sum(1)))
            depth = np.minimum(depth, HALF + other - np.abs((d * ax).sum(1)))
    return max(worst, float(depth.max()))


class Engine:
    """One engine's pyramid: `step()` advances it by DT; `poses()` reads the boxes' centres
    (n, 2) and angles (n,), in `layout` order; `reported()` is the deepest penetration of the
    latest step as the engine reports its contacts, m."""

    name = ""

    def step(self) -> None:
        raise NotImplementedError

    def poses(self) -> tuple[np.ndarray, np.ndarray]:
        raise NotImplementedError

    def reported(self) -> float:
        raise NotImplementedError


class Physstep(Engine):
    name = "physstep"

    def __init__(
        self, rows: int, solver: str = "soft-step", sleep_time: float = 0.0, substeps: int | None = None
    ) -> None:
        self.w = physstep.World.from_scene("pyramid", params={"rows": rows, "g": G}, dt=DT)
        self.w.contact_solver = solver
        self.w.sleep_time = sleep_time
        if substeps is not None:
            self.w.substeps = substeps

    def step(self) -> None:
        self.w.step(1)

    def poses(self) -> tuple[np.ndarray, np.ndarray]:
        return self.w.solid_positions()[1:], self.w.solid_orientations()[1:]  # 0 is the ground

    def reported(self) -> float:
        return self.w.max_penetration


class Pymunk(Engine):
    name = "pymunk"

    def __init__(self, rows: int, sleep: bool = False) -> None:
        import pymunk

        self.space = space = pymunk.Space()
        space.gravity = (0.0, -G)
        space.iterations = 10
        if sleep:
            space.sleep_time_threshold = 0.5
        space.collision_slop = 0.005
        ground = pymunk.Poly(space.static_body, [(-100.0, -2.0), (100.0, -2.0), (100.0, 0.0), (-100.0, 0.0)])
        ground.friction = math.sqrt(MU)
        space.add(ground)
        self.bodies = []
        for p in layout(rows):
            body = pymunk.Body(1.0, pymunk.moment_for_box(1.0, (2 * HALF, 2 * HALF)))
            body.position = (float(p[0]), float(p[1]))
            shape = pymunk.Poly.create_box(body, (2 * HALF, 2 * HALF))
            shape.friction = math.sqrt(MU)
            space.add(body, shape)
            self.bodies.append(body)

    def step(self) -> None:
        self.space.step(DT)

    def poses(self) -> tuple[np.ndarray, np.ndarray]:
        x = np.array([[b.position.x, b.position.y] for b in self.bodies])
        return x, np.array([b.angle for b in self.bodies])

    def reported(self) -> float:
        deepest = [0.0]

        def look(arbiter: object) -> None:
            for p in arbiter.contact_point_set.points:  # type: ignore[attr-defined]
                deepest[0] = max(deepest[0], -p.distance)

        for b in self.bodies:
            b.each_arbiter(look)
        return deepest[0]


class Box2d(Engine):
    name = "Box2D"

    def __init__(self, rows: int, sleep: bool = False) -> None:
        import Box2D

        self.world = world = Box2D.b2World(gravity=(0.0, -G), doSleep=sleep)
        skin = Box2D.b2_polygonRadius
        ground = Box2D.b2PolygonShape(box=(100.0 - skin, 1.0 - skin))
        world.CreateStaticBody(position=(0.0, -1.0), shapes=ground)
        core = HALF - skin
        self.bodies = []
        for p in layout(rows):
            body = world.CreateDynamicBody(position=(float(p[0]), float(p[1])))
            body.CreatePolygonFixture(box=(core, core), density=1.0, friction=MU)
            # The core's area is 0.96 m^2: the mass and inertia of the whole 1 m box instead.
            body.massData = Box2D.b2MassData(mass=1.0, center=(0.0, 0.0), I=(2 * HALF) ** 2 / 6.0)
            self.bodies.append(body)

    def step(self) -> None:
        self.world.Step(DT, 8, 3)

    def poses(self) -> tuple[np.ndarray, np.ndarray]:
        x = np.array([[b.position[0], b.position[1]] for b in self.bodies])
        return x, np.array([b.angle for b in self.bodies])

    def reported(self) -> float:
        """The deepest of the touching contacts' separations, measured as Box2D's position
        solver measures them (b2PositionSolverManifold: from the reference face to each
        clip point, less both skins; pybox2d does not expose b2WorldManifold's)."""
        deepest = 0.0
        for c in self.world.contacts:
            m = c.manifold
            if not c.touching or m.type_ == m.e_circles:
                continue
            a, b = c.fixtureA, c.fixtureB
            if m.type_ == m.e_faceB:
                a, b = b, a
            normal = a.body.GetWorldVector(m.localNormal)
            plane = a.body.GetWorldPoint(m.localPoint)
            skins = a.shape.radius + b.shape.radius
            for p in m.points[: m.pointCount]:
                clip = b.body.GetWorldPoint(p.localPoint)
                deepest = max(deepest, skins - (clip - plane).dot(normal))
        return deepest


def timed(make: Callable[[], Engine], steps: int, repeat: int) -> float:
    """Median over `repeat` fresh runs of the time per step, ms (building not timed)."""
    times = []
    for _ in range(repeat):
        e = make()
        t0 = time.perf_counter()
        for _ in range(steps):
            e.step()
        times.append((time.perf_counter() - t0) / steps)
    return 1e3 * statistics.median(times)


def measured(make: Callable[[], Engine], steps: int) -> tuple[float, float, float, float]:
    """An untimed run: the top box's drift at the end, m; the deepest penetration the engine
    reported and the deepest box overlap, over all steps, m; the deepest overlap at the end."""
    e = make()
    x0, _ = e.poses()
    reported = geometric = 0.0
    for _ in range(steps):
        e.step()
        reported = max(reported, e.reported())
        geometric = max(geometric, box_overlap(*e.poses()))
    x, angle = e.poses()
    return float(np.linalg.norm(x[-1] - x0[-1])), reported, geometric, box_overlap(x, angle)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows", type=int, default=20)
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    os.environ.setdefault("RAYON_NUM_THREADS", "1")  # rayon's pool starts at its first use
    steps = round(args.seconds / DT)
    n = args.rows * (args.rows + 1) // 2
    print(f"pyramid of {args.rows} rows ({n} unit boxes), dt = 1/60 s, {steps} steps, one thread")
    print(f"{'':<24} {'':>8} {'':>11} {'deepest, over the run':>25} {'at the end':>11}")
    print(f"{'engine':<24} {'ms/step':>8} {'top drift':>11} {'reported':>12} {'overlap':>12} {'overlap':>11}")
    # Every contact solver of physstep at its default settings (16 passes over the contacts a
    # step each: `physstep solvers`), the default first.
    solvers = [s.name for s in physstep.solvers()]
    # And the soft step with fewer substeps: the cost at the peers' drift and penetration.
    fewer = [(f"physstep ({k} substeps)", k) for k in (4, 3, 2)]
    engines: list[tuple[str, Callable[[], Engine]]] = [
        *((f"physstep ({s})", lambda s=s: Physstep(args.rows, s)) for s in solvers),
        *((label, lambda k=k: Physstep(args.rows, solvers[0], substeps=k)) for label, k in fewer),
        ("physstep (soft, sleeps)", lambda: Physstep(args.rows, solvers[0], sleep_time=0.5)),
        ("pymunk (10 iterations)", lambda: Pymunk(args.rows)),
        ("pymunk (10, sleeps)", lambda: Pymunk(args.rows, sleep=True)),
        ("Box2D 2.3 (8+3, awake)", lambda: Box2d(args.rows)),
        ("Box2D 2.3 (8+3, sleeps)", lambda: Box2d(args.rows, sleep=True)),
    ]
    ms: dict[str, float] = {}
    quality: dict[str, tuple[float, float]] = {}  # top drift, deepest overlap over the run
    for label, make in engines:
        try:
            make()
        except ImportError as err:
            print(f"{label:<24} skipped: {err.name} does not import here ({err}; pip install -e .[bench])")
            continue
        ms[label] = timed(make, steps, args.repeat)
        drift, reported, peak, end = measured(make, steps)
        quality[label] = (drift, peak)
        print(f"{label:<24} {ms[label]:8.3f} {drift:9.2e} m {reported:10.2e} m {peak:10.2e} m {end:9.2e} m")
    peers = {label: t for label, t in ms.items() if not label.startswith("physstep")}
    for label in (label for label in ms if label.startswith("physstep")):
        print(f"{label}: " + ", ".join(f"{ms[label] / t:.2f}x {peer}" for peer, t in peers.items()))
    # The comparison: physstep's time per step at equal or smaller drift and
    # penetration than the peer's (its fastest awake soft-step row that matches both).
    soft = [f"physstep ({solvers[0]})", *(label for label, _ in fewer)]
    for peer in (p for p in peers if "sleeps" not in p):
        drift, overlap = quality[peer]
        ok = [s for s in soft if s in ms and quality[s][0] <= drift and quality[s][1] <= overlap]
        if ok:
            best = min(ok, key=ms.__getitem__)
            ratio = ms[best] / ms[peer]
            print(f"at {peer}'s drift and overlap or less: {best}, {ratio:.2f}x its time per step")
        else:
            print(f"at {peer}'s drift and overlap or less: no soft-step row here matches both")


if __name__ == "__main__":
    main()
