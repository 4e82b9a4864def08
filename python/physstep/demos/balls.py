"""Balls in a box: elastic contacts at their time of impact inside the fixed step."""

from __future__ import annotations

import math

import numpy as np
import pygame

import physstep
from physstep.demos import base
from physstep.demos.base import Demo, Key, Panel

#: The box, m: lower and upper corners.
BOX = ((0.0, 0.0), (3.2, 2.8))
#: The restitutions the ``e`` key cycles.
RESTITUTIONS = (1.0, 0.9, 0.7, 0.4)
#: How fast a dragged ball closes on the pointer (s) and the speed it may reach doing so (m/s).
PULL_TIME, PULL_SPEED = 0.1, 6.0
SLOW, FAST = (70, 130, 230), (255, 150, 70)


class BallsDemo(Demo):
    """Balls of several sizes (mass by area) in a 3.2 m x 2.8 m box, no gravity: every
    contact is resolved at its time of impact inside the step, so at restitution 1 the
    kinetic energy is kept to rounding under any method. The ``e`` key lowers the
    restitution; the mouse pulls a ball towards the pointer (by its velocity, so the contacts
    still see it move)."""

    name = "balls"
    dt = 1.0 / 120.0
    dt_range = (1e-3, 0.1)
    draggable = True
    mouse = "pull a ball towards the pointer (sets its velocity); the drift restarts on release"
    view = (1.6, 1.4, 1.5)
    keys = (Key("restitution", (pygame.K_e,), "e", "next restitution (1, 0.9, 0.7, 0.4)"),)

    def __init__(self) -> None:
        self.restitution = RESTITUTIONS[0]

    def world(self, method: str, dt: float) -> physstep.World:
        rng = np.random.default_rng(13)
        (x0, y0), (x1, y1) = BOX
        cell = 0.4
        cols, rows = round((x1 - x0) / cell), round((y1 - y0) / cell)
        centres, radii = [], []
        for r in range(rows):
            for c in range(cols):
                if rng.random() < 0.2:  # some cells empty: room to move
                    continue
                rad = float(rng.uniform(0.06, 0.15))
                slack = cell / 2 - rad - 0.005
                centres.append(
                    (
                        x0 + (c + 0.5) * cell + rng.uniform(-slack, slack),
                        y0 + (r + 0.5) * cell + rng.uniform(-slack, slack),
                    )
                )
                radii.append(rad)
        radii_a = np.array(radii)
        w = physstep.World(2, method, dt)
        w.add_walls(BOX[0], BOX[1])
        w.add_balls(
            np.array(centres),
            radii_a,
            velocities=rng.uniform(-1.2, 1.2, size=(len(radii), 2)),
            masses=(radii_a / 0.1) ** 2,
        )
        w.restitution = self.restitution
        return w

    def act(self, panels: list[Panel], action: str) -> None:
        if action != "restitution":
            super().act(panels, action)
        k = RESTITUTIONS.index(self.restitution) if self.restitution in RESTITUTIONS else -1
        self.restitution = RESTITUTIONS[(k + 1) % len(RESTITUTIONS)]
        for p in panels:
            if not p.error:
                p.world.restitution = self.restitution
                p.restart_drift()

    def hud(self, panel: Panel) -> list[tuple[str, str, tuple[int, int, int]]]:
        c = panel.world.collisions
        return [
            ("balls", f"{len(panel.world)}", base.TEXT),
            ("restitution", f"{panel.world.restitution:g} (e)", base.TEXT),
            ("collisions", f"{c['count']}", base.TEXT),
            ("max overlap", f"{c['max_overlap']:.1e} m", base.TEXT),
        ]

    def hold(self, world: physstep.World, i: int, rect: pygame.Rect, pos: tuple[int, int]) -> bool:
        """Sets the ball's velocity towards the pointer (closing in ``PULL_TIME``, at most
        ``PULL_SPEED``): the contact stage keeps it out of the others and the walls."""
        x, v = np.array(world.positions), np.array(world.velocities)
        want = (self.to_world(rect, pos, 2) - x[i]) / PULL_TIME
        speed = float(np.hypot(*want))
        v[i] = want if speed <= PULL_SPEED else want * (PULL_SPEED / speed)
        world.velocities = v
        return False

    def pick(self, rect: pygame.Rect, x: np.ndarray, pos: tuple[int, int]) -> int | None:
        """The ball under ``pos`` (or within 8 px of its rim), the nearest centre first."""
        s = self.scale(rect)
        radii = self._radii
        best, best_d = None, math.inf
        for i, p in enumerate(x):
            sx, sy = self.to_screen(rect, p)
            d = math.hypot(sx - pos[0], sy - pos[1])
            reach = (radii[i] * s if i < len(radii) else 12.0) + 8.0
            if d <= reach and d < best_d:
                best, best_d = i, d
        return best

    _radii: np.ndarray = np.zeros(0)

    def draw(self, surf: pygame.Surface, rect: pygame.Rect, panel: Panel, x: np.ndarray) -> None:
        w = panel.world
        self._radii = w.radii
        s = self.scale(rect)
        lo, hi = self.to_screen(rect, BOX[0]), self.to_screen(rect, BOX[1])
        box = pygame.Rect(lo[0], hi[1], hi[0] - lo[0], lo[1] - hi[1])
        pygame.draw.rect(surf, base.BACKGROUND, box)
        pygame.draw.rect(surf, base.DIM, box.inflate(4, 4), 2)
        v = np.array(w.velocities)
        speeds = np.hypot(v[:, 0], v[:, 1])
        for i, p in enumerate(x):
            k = min(1.0, float(speeds[i]) / 2.0)
            colour = tuple(int(a + (b - a) * k) for a, b in zip(SLOW, FAST, strict=True))
            c = self.to_screen(rect, p)
            r = max(2, round(self._radii[i] * s))
            pygame.draw.circle(surf, colour, c, r)
            pygame.draw.circle(surf, tuple(min(255, ch + 50) for ch in colour), c, r, 1)
        font = base.font(18)
        base.text(
            surf,
            font,
            "colour: speed (blue slow, orange 2 m/s and up)",
            (rect.x + 10, rect.bottom - 6),
            base.DIM,
            "bottomleft",
        )
