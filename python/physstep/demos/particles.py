"""The particle demos: the notes' spring (with its phase portrait) and the circular orbit."""

from __future__ import annotations

import math

import numpy as np
import pygame

import physstep
from physstep.demos import base
from physstep.demos.base import Demo, Panel


class SpringDemo(Demo):
    """The notes' spring, m = 10 kg, k = 5 N/m, x0 = 20 m: the mass above, its phase portrait
    (x, v / omega) below, where the exact motion is a circle: explicit Euler spirals out,
    backward Euler in, the symplectic methods keep a closed curve."""

    name = "spring"
    dt = 0.1
    dt_range = (1e-3, 2.0)
    draggable = True
    view = (0.0, 0.0, 26.0)
    omega = math.sqrt(5.0 / 10.0)

    def world(self, method: str, dt: float) -> physstep.World:
        return physstep.World.from_scene("spring", method, dt)

    def strip(self, rect: pygame.Rect) -> pygame.Rect:
        """The band where the mass moves (the top third of the panel)."""
        return pygame.Rect(rect.x, rect.y, rect.width, rect.height // 3)

    def phase_rect(self, rect: pygame.Rect) -> pygame.Rect:
        """The square of the phase portrait, below the band."""
        top = rect.y + rect.height // 3
        side = min(rect.width, rect.bottom - top) - 20
        return pygame.Rect(rect.centerx - side // 2, top + 10, side, side)

    def scale(self, rect: pygame.Rect) -> float:
        return rect.width / (2.0 * self.view[2])

    def to_screen(self, rect: pygame.Rect, p: object) -> tuple[int, int]:
        return super().to_screen(self.strip(rect), p)

    def to_world(self, rect: pygame.Rect, pos: tuple[int, int], dim: int) -> np.ndarray:
        return super().to_world(self.strip(rect), pos, dim)

    def record(self, panel: Panel, x: np.ndarray) -> None:
        """The phase portrait records states (x, v) after steps, not interpolated points."""
        w = panel.world
        point = (float(w.positions[0, 0]), float(w.velocities[0, 0]) / self.omega)
        if not panel.trail or panel.trail[-1] != point:
            panel.trail.append(point)

    def draw(self, surf: pygame.Surface, rect: pygame.Rect, panel: Panel, x: np.ndarray) -> None:
        font = base.font(20)
        band = self.strip(rect)
        y = band.centery
        wall = band.x + 14
        pygame.draw.rect(surf, base.GRID, (band.x + 4, y - 30, 10, 60))
        zero = self.to_screen(rect, [0.0])
        pygame.draw.line(surf, base.GRID, (zero[0], y - 36), (zero[0], y + 36))
        base.text(surf, font, "x = 0", (zero[0], y + 40), base.DIM, "midtop")
        mass = self.to_screen(rect, x[0])
        coils = 14
        pts: list[tuple[float, float]] = [(wall, y)]
        for k in range(1, 2 * coils):
            pts.append((wall + (mass[0] - wall) * k / (2 * coils), y + (10 if k % 2 else -10)))
        pts.append((mass[0], y))
        pygame.draw.lines(surf, base.DIM, False, pts, 2)
        pygame.draw.rect(surf, base.BODY, (mass[0] - 14, y - 14, 28, 28), border_radius=4)
        # Phase portrait: the exact motion is the circle of radius x0 (v / omega against x).
        ph = self.phase_rect(rect)
        pygame.draw.rect(surf, base.GRID, ph, 1)
        c, s = ph.center, ph.width / (2.0 * self.view[2])
        pygame.draw.circle(surf, base.GRID, c, int(20.0 * s), 1)
        pygame.draw.line(surf, base.GRID, (ph.x, c[1]), (ph.right - 1, c[1]))
        pygame.draw.line(surf, base.GRID, (c[0], ph.y), (c[0], ph.bottom - 1))
        base.text(
            surf,
            font,
            "phase portrait: v / omega against x (exact: the circle)",
            (ph.x + 6, ph.y + 4),
            base.DIM,
        )
        trail = [(int(base._clip(c[0] + px * s)), int(base._clip(c[1] - pv * s))) for px, pv in panel.trail]
        base.draw_trail(surf, trail, base.TRAIL)
        if trail:
            pygame.draw.circle(surf, base.ACCENT, trail[-1], 4)


class OrbitDemo(Demo):
    """A circular orbit (GM = 1, r = 1, period 2 pi s) with its trail and the exact circle."""

    name = "orbit"
    dt = 0.05
    dt_range = (1e-3, 1.0)
    draggable = True
    view = (0.0, 0.0, 1.7)

    def world(self, method: str, dt: float) -> physstep.World:
        return physstep.World.from_scene("orbit", method, dt)

    def record(self, panel: Panel, x: np.ndarray) -> None:
        point = (float(x[0, 0]), float(x[0, 1]))
        if not panel.trail or panel.trail[-1] != point:
            panel.trail.append(point)

    def draw(self, surf: pygame.Surface, rect: pygame.Rect, panel: Panel, x: np.ndarray) -> None:
        centre = self.to_screen(rect, [0.0, 0.0])
        pygame.draw.circle(surf, base.GRID, centre, int(self.scale(rect)), 1)
        pygame.draw.circle(surf, base.ACCENT, centre, 9)
        colour = panel.colour
        base.draw_trail(surf, [self.to_screen(rect, p) for p in panel.trail], colour)
        pygame.draw.circle(surf, base.BODY, self.to_screen(rect, x[0]), 7)
