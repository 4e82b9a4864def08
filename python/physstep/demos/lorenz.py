"""The Lorenz attractor: a first-order flow through the same integrators (the flow methods)."""

from __future__ import annotations

import numpy as np
import pygame

import physstep
from physstep.demos import base
from physstep.demos.base import Demo, Panel


class LorenzDemo(Demo):
    """The ``lorenz`` scene (sigma 10, rho 28, beta 8/3 from (1, 1, 1)) drawn in its x-z
    plane, the butterfly, with a fading trail. The split methods need positions and
    velocities, which a flow has not: the ``m`` key cycles the flow methods only."""

    name = "lorenz"
    dt = 0.005
    dt_range = (1e-4, 0.05)
    methods = ("rk4",)
    view = (0.0, 25.0, 28.0)
    no_energy = "none (a flow)"

    def applies(self, info: physstep.MethodInfo) -> bool:
        return not info.split

    def world(self, method: str, dt: float) -> physstep.World:
        return physstep.World.from_scene("lorenz", method, dt)

    def record(self, panel: Panel, x: np.ndarray) -> None:
        point = (float(x[0, 0]), float(x[0, 2]))
        if not panel.trail or panel.trail[-1] != point:
            panel.trail.append(point)

    def draw(self, surf: pygame.Surface, rect: pygame.Rect, panel: Panel, x: np.ndarray) -> None:
        font = base.font(20)
        for fixed in (-8.485, 8.485):  # the two unstable fixed points, (+-sqrt(beta (rho - 1)), rho - 1)
            pygame.draw.circle(surf, base.GRID, self.to_screen(rect, [fixed, 27.0]), 4, 1)
        base.draw_trail(surf, [self.to_screen(rect, p) for p in panel.trail], panel.colour)
        pygame.draw.circle(surf, base.ACCENT, self.to_screen(rect, [x[0, 0], x[0, 2]]), 6)
        y = x[0]
        base.text(
            surf,
            font,
            f"x {y[0]:+7.2f}   y {y[1]:+7.2f}   z {y[2]:6.2f}   (drawn: x across, z up)",
            (rect.x + 10, rect.bottom - 8),
            base.DIM,
            "bottomleft",
        )
