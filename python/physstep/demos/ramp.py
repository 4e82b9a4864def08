"""Ramp: a box on a tilted plank, sticking or sliding as Coulomb says, its acceleration
against the closed form ``g (sin a - mu cos a)``."""

from __future__ import annotations

import math

import numpy as np
import pygame

import physstep
from physstep.demos import base
from physstep.demos.base import Demo, Key, Panel

#: The ramp scene's gravity, m/s^2, and the box's half side, m.
G, HALF = 9.81, 0.25
#: The plank's half thickness, m (the scene's).
PLANK = 0.5
#: Steps of the angle (rad) and of the friction coefficient the keys take, and their ranges.
ANGLE_STEP, FRICTION_STEP = 0.05, 0.05
ANGLES, FRICTIONS = (0.0, 1.2), (0.0, 1.5)
BOX, EDGE, WOOD, MARK = (205, 150, 80), (240, 200, 140), (70, 78, 98), (110, 120, 145)


def closed_form(angle: float, friction: float, g: float = G) -> float:
    """The box's acceleration down the plank, m/s^2: 0 where friction holds it
    (``friction >= tan(angle)``), else ``g (sin a - mu cos a)``."""
    if friction >= math.tan(angle):
        return 0.0
    return g * (math.sin(angle) - friction * math.cos(angle))


class RampDemo(Demo):
    """The ``ramp`` scene: a 0.5 m box at rest on a long plank tilted by ``angle`` (0.5 rad),
    both of friction ``mu`` (0.6). Above the friction angle (``mu < tan a``) it slides at
    ``g (sin a - mu cos a)``; below it, it sticks. ``a``/``shift+a`` and ``f``/``shift+f``
    change the angle and the friction (the scene built afresh: the box starts at rest); the
    HUD shows the closed form and the acceleration measured (the box's speed along the plank
    over the time since it started). The view follows the box; the marks on the plank are
    0.5 m apart."""

    name = "ramp"
    dt = 1.0 / 60.0
    dt_range = (1.0 / 480.0, 1.0 / 15.0)
    view = (0.0, 0.0, 1.6)
    keys = (
        Key("steeper", (pygame.K_a,), "a", "tilt the plank 0.05 rad more (up to 1.2)", shift=False),
        Key("flatter", (pygame.K_a,), "shift+a", "tilt it 0.05 rad less", shift=True),
        Key("rougher", (pygame.K_f,), "f", "friction 0.05 more (up to 1.5)", shift=False),
        Key("smoother", (pygame.K_f,), "shift+f", "friction 0.05 less", shift=True),
        Key("solver", (pygame.K_c,), "c", "next contact solver (physstep.contact_solvers())"),
    )

    def __init__(self) -> None:
        self.angle, self.friction = 0.5, 0.6
        self.solver = base.contact_solver_names()[0]

    def world(self, method: str, dt: float) -> physstep.World:
        w = physstep.World.from_scene(
            "ramp", method, dt, {"angle": self.angle, "friction": self.friction, "g": G}
        )
        w.contact_solver = self.solver
        return w

    def act(self, panels: list[Panel], action: str) -> None:
        if action == "solver":
            self.solver = base.next_contact_solver(self.solver, panels)
            return
        if action in ("steeper", "flatter"):
            step = ANGLE_STEP if action == "steeper" else -ANGLE_STEP
            self.angle = round(min(ANGLES[1], max(ANGLES[0], self.angle + step)), 10)
        elif action in ("rougher", "smoother"):
            step = FRICTION_STEP if action == "rougher" else -FRICTION_STEP
            self.friction = round(min(FRICTIONS[1], max(FRICTIONS[0], self.friction + step)), 10)
        else:
            super().act(panels, action)
            return
        # A static plank does not turn: the scene is built afresh at the new angle and
        # friction, under each panel's method, dt and loop variant.
        base.start_afresh(panels, self.world)

    def down(self) -> np.ndarray:
        """Unit vector down the plank."""
        return -np.array([math.cos(self.angle), math.sin(self.angle)])

    def measured(self, w: physstep.World) -> float | None:
        """The box's mean acceleration down the plank since it started at rest, m/s^2."""
        if w.time <= 0.0:
            return None
        return float(w.solid_velocities()[1] @ self.down()) / w.time

    def hud(self, panel: Panel) -> list[tuple[str, str, tuple[int, int, int]]]:
        w = panel.world
        a, mu = self.angle, self.friction
        exact = closed_form(a, mu)
        got = self.measured(w)
        regime = "sticks" if exact == 0.0 else "slides"
        rows = [
            ("solver", f"{w.contact_solver} (c)", base.TEXT),
            ("angle", f"{a:.2f} rad, tan a = {math.tan(a):.3f} (a)", base.TEXT),
            ("friction", f"mu = {mu:.2f} (f)", base.TEXT),
            ("closed form", f"{exact:.4f} m/s^2 ({regime})", base.ACCENT),
        ]
        if got is not None:
            err = abs(got - exact) / abs(exact) if exact else None
            off = f" ({100 * err:.2f} % off)" if err is not None else ""
            rows.append(("measured", f"{got:.4f} m/s^2{off}", base.TEXT))
        return rows

    def draw(self, surf: pygame.Surface, rect: pygame.Rect, panel: Panel, x: np.ndarray) -> None:
        pos, ang = base.solid_poses(panel)
        box, turn = pos[1], float(ang[1])
        self.view = (float(box[0]), float(box[1]), self.view[2])  # follow the box
        c, s = math.cos(self.angle), math.sin(self.angle)
        along, normal = np.array([c, s]), np.array([-s, c])
        # The plank: the part in view, its top face with a mark every 0.5 m.
        t0 = float(box @ along)
        ends = [t0 - 4.0, t0 + 4.0]
        corners = [along * t + normal * h for t in ends for h in (PLANK, -PLANK)]
        pts = [self.to_screen(rect, corners[k]) for k in (0, 2, 3, 1)]
        pygame.draw.polygon(surf, WOOD, pts)
        pygame.draw.line(surf, base.DIM, pts[0], pts[1], 2)
        k0 = math.floor(ends[0] / 0.5)
        for k in range(k0, k0 + 18):
            p = along * (0.5 * k) + normal * PLANK
            q = along * (0.5 * k) + normal * (PLANK - 0.12)
            pygame.draw.line(surf, MARK, self.to_screen(rect, p), self.to_screen(rect, q), 2)
        # The box.
        pts = [self.to_screen(rect, c) for c in base.box_corners(box, turn, HALF, HALF)]
        pygame.draw.polygon(surf, BOX, pts)
        pygame.draw.polygon(surf, EDGE, pts, 2)
        base.text(
            surf,
            base.font(18),
            "a / shift+a: angle, f / shift+f: friction, c: contact solver (the view follows the box)",
            (rect.x + 10, rect.y + 8),
            base.DIM,
        )
