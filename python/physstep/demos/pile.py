"""Pile: balls dropped into a box under gravity, coming to rest; pour more, shake them up."""

from __future__ import annotations

import numpy as np
import pygame

import physstep
from physstep.demos import base
from physstep.demos.base import Demo, Key, Panel

#: Balls the pile starts with, and their radius, m (the pile scene's).
COUNT, RADIUS = 400, 0.05
#: The restitutions the ``e`` key cycles (the scene's 0.5 first).
RESTITUTIONS = (0.5, 0.2, 0.0, 0.8)
#: A shake: each ball's velocity gets up to this much upward and half of it sideways, m/s.
SHAKE = 3.0
#: Balls a ``b`` drops: a row across the top of the box.
ROW = 12
SLOW, FAST = (70, 130, 230), (255, 150, 70)


class PileDemo(Demo):
    """The ``pile`` scene: 400 balls (5 cm) dropped from a lattice into a box under gravity,
    at restitution 0.5: they bounce, pile up and come to rest, the resting contacts solved
    as constraints (docs/collisions.md). Hold the mouse button down in the box to pour
    balls at the pointer; ``b`` drops a row of balls from the top, ``k`` shakes the box (a
    random kick up to every ball), ``e`` cycles the restitution (0.5, 0.2, 0, 0.8). Balls
    are coloured by speed."""

    name = "pile"
    dt = 1.0 / 120.0
    dt_range = (1.0 / 960.0, 1.0 / 30.0)
    draggable = True
    mouse = "hold the button down in the box to pour balls at the pointer"
    keys = (
        Key("drop", (pygame.K_b,), "b", "drop a row of balls from the top"),
        Key("shake", (pygame.K_k,), "k", "shake: a random kick up to every ball"),
        Key("restitution", (pygame.K_e,), "e", "next restitution (0.5, 0.2, 0, 0.8)"),
    )

    def __init__(self) -> None:
        self.restitution = RESTITUTIONS[0]
        self.shakes = 0
        world = physstep.World.from_scene("pile", params={"n": COUNT, "radius": RADIUS})
        lo, hi = world.walls or (np.zeros(2), np.ones(2))
        self.box = (np.array(lo), np.array(hi))
        mid = (self.box[0] + self.box[1]) / 2
        self.view = (float(mid[0]), float(mid[1]), 0.55 * float(np.max(self.box[1] - self.box[0])))

    def world(self, method: str, dt: float) -> physstep.World:
        w = physstep.World.from_scene(
            "pile", method, dt, {"n": COUNT, "radius": RADIUS, "restitution": self.restitution}
        )
        return w

    def act(self, panels: list[Panel], action: str) -> None:
        if action == "restitution":
            k = RESTITUTIONS.index(self.restitution) if self.restitution in RESTITUTIONS else -1
            self.restitution = RESTITUTIONS[(k + 1) % len(RESTITUTIONS)]
        elif action == "shake":
            self.shakes += 1
        elif action != "drop":
            super().act(panels, action)
            return
        for p in panels:
            if p.error:
                continue
            w = p.world
            if action == "restitution":
                w.restitution = self.restitution
            elif action == "shake":
                rng = np.random.default_rng(self.shakes)
                v = np.array(w.velocities)
                kick = rng.uniform(0.0, 1.0, size=v.shape) * [SHAKE, SHAKE]
                kick[:, 0] -= SHAKE / 2
                v += kick * [0.5, 1.0]
                w.velocities = v
            else:
                self.drop_row(w)
            p.restart_drift()

    def drop_row(self, w: physstep.World) -> int:
        """Adds a row of balls just under the lid where there is room; returns how many."""
        (x0, _), (x1, y1) = self.box
        added = 0
        for x in np.linspace(x0 + 2 * RADIUS, x1 - 2 * RADIUS, ROW):
            added += self.pour(w, np.array([x, y1 - 1.5 * RADIUS]))
        return added

    def pour(self, w: physstep.World, at: np.ndarray) -> int:
        """Adds a ball at ``at`` if it fits there (in the box, touching no other): 1, else 0."""
        (x0, y0), (x1, y1) = self.box
        at = np.clip(at, [x0 + RADIUS, y0 + RADIUS], [x1 - RADIUS, y1 - RADIUS])
        x = np.array(w.positions)
        if len(x) and float(np.min(np.hypot(*(x - at).T))) < 2 * RADIUS:
            return 0
        try:
            w.add_ball(at, velocity=[0.0, -1.0], radius=RADIUS)
        except ValueError:
            return 0
        return 1

    def pick(self, rect: pygame.Rect, x: np.ndarray, pos: tuple[int, int]) -> int | None:
        """Inside the box: pour (0, any index the app hands back to :meth:`hold`)."""
        p = self.to_world(rect, pos, 2)
        inside = bool(np.all(p >= self.box[0]) and np.all(p <= self.box[1]))
        return 0 if inside else None

    def hold(self, world: physstep.World, i: int, rect: pygame.Rect, pos: tuple[int, int]) -> bool:
        """Pours a ball at the pointer, where one fits; nothing else moves."""
        self.pour(world, self.to_world(rect, pos, 2))
        return False

    def hud(self, panel: Panel) -> list[tuple[str, str, tuple[int, int, int]]]:
        w = panel.world
        c = w.collisions
        return [
            ("balls", f"{len(w)}", base.TEXT),
            ("restitution", f"{w.restitution:g} (e)", base.TEXT),
            ("kinetic", f"{w.kinetic_energy():.3e} J", base.TEXT),
            ("collisions", f"{c['count']}", base.TEXT),
            ("max overlap", f"{c['max_overlap']:.1e} m", base.TEXT),
        ]

    def draw(self, surf: pygame.Surface, rect: pygame.Rect, panel: Panel, x: np.ndarray) -> None:
        w = panel.world
        s = self.scale(rect)
        lo, hi = self.to_screen(rect, self.box[0]), self.to_screen(rect, self.box[1])
        box = pygame.Rect(lo[0], hi[1], hi[0] - lo[0], lo[1] - hi[1])
        pygame.draw.rect(surf, base.BACKGROUND, box)
        pygame.draw.rect(surf, base.DIM, box.inflate(4, 4), 2)
        v = np.array(w.velocities)
        speeds = np.hypot(v[:, 0], v[:, 1]) if len(v) else np.zeros(0)
        r = max(2, round(RADIUS * s))
        for i, p in enumerate(x):
            k = min(1.0, float(speeds[i]) / 2.0) if i < len(speeds) else 0.0
            colour = tuple(int(a + (b - a) * k) for a, b in zip(SLOW, FAST, strict=True))
            c = self.to_screen(rect, p)
            pygame.draw.circle(surf, colour, c, r)
            pygame.draw.circle(surf, tuple(min(255, ch + 50) for ch in colour), c, r, 1)
        base.text(
            surf,
            base.font(18),
            "hold the mouse: pour balls, b: drop a row, k: shake, e: restitution",
            (rect.x + 10, rect.y + 8),
            base.DIM,
        )
        base.text(
            surf,
            base.font(18),
            "colour: speed (blue at rest, orange 2 m/s and up)",
            (rect.x + 10, rect.bottom - 6),
            base.DIM,
            "bottomleft",
        )
