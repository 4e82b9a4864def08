"""Dice: cubes thrown spinning onto a plane in 3D, bouncing, tumbling and coming to rest."""

from __future__ import annotations

import numpy as np
import pygame

import physstep
from physstep.demos import base
from physstep.demos.base import Demo, Key, Panel
from physstep.demos.racket import rotation

#: Dice thrown, and the half side of one, m (the dice scene's 20 cm cubes).
COUNT, HALF = 16, 0.1
#: The faces of a die: (vertex indices, outward normal in the die's frame, pips). Opposite
#: faces add up to 7.
FACES = (
    ((4, 5, 7, 6), (1, 0, 0), 1),
    ((0, 2, 3, 1), (-1, 0, 0), 6),
    ((2, 6, 7, 3), (0, 1, 0), 2),
    ((0, 1, 5, 4), (0, -1, 0), 5),
    ((1, 3, 7, 5), (0, 0, 1), 3),
    ((0, 4, 6, 2), (0, 0, -1), 4),
)
#: Where the pips of 1 to 6 sit on a face, in units of the half side along its two axes.
PIPS = {
    1: ((0.0, 0.0),),
    2: ((-0.5, -0.5), (0.5, 0.5)),
    3: ((-0.5, -0.5), (0.0, 0.0), (0.5, 0.5)),
    4: ((-0.5, -0.5), (-0.5, 0.5), (0.5, -0.5), (0.5, 0.5)),
    5: ((-0.5, -0.5), (-0.5, 0.5), (0.0, 0.0), (0.5, -0.5), (0.5, 0.5)),
    6: ((-0.5, -0.55), (-0.5, 0.0), (-0.5, 0.55), (0.5, -0.55), (0.5, 0.0), (0.5, 0.55)),
}
DIE, PIP, FLOOR, FLOOR_LINE = (236, 232, 222), (30, 32, 40), (38, 44, 58), (58, 66, 86)
#: A sleeping die's colour, and the sleep time the ``z`` key turns on, s (Box2D's).
ASLEEP, SLEEP_TIME = (150, 158, 190), 0.5
LIGHT = np.array([0.4, 0.9, 0.5]) / np.linalg.norm([0.4, 0.9, 0.5])


def _camera() -> np.ndarray:
    """Rows: screen right, screen up, towards the eye (from the front right, above the
    y-up floor)."""
    eye = np.array([0.9, 1.1, 1.6])
    eye /= np.linalg.norm(eye)
    right = np.cross([0.0, 1.0, 0.0], eye)
    right /= np.linalg.norm(right)
    return np.array([right, np.cross(eye, right), eye])


CAMERA = _camera()


class DiceDemo(Demo):
    """The ``dice`` scene: 16 dice (20 cm cubes, restitution 0.2, friction 0.6) thrown
    spinning from a grid 1 m above a plane, drawn in 3D (an orthographic view from the front
    right, above) with their pips. They bounce, tumble and come to rest on a face. ``t``
    throws them again (the next seed of the scene), ``c`` cycles the contact solver, ``z``
    turns sleeping on and off (a die at rest falls asleep, drawn blue-grey, and leaves the
    solver). The HUD shows the kinetic energy, the contact points touching, the deepest
    penetration and the dice asleep."""

    name = "dice"
    dt = 1.0 / 60.0
    dt_range = (1.0 / 480.0, 1.0 / 15.0)
    keys = (
        Key("throw", (pygame.K_t,), "t", "throw the dice again (the next seed)"),
        Key("solver", (pygame.K_c,), "c", "next contact solver (physstep.contact_solvers())"),
        Key("sleep", (pygame.K_z,), "z", "sleeping on / off (dice at rest leave the solver)"),
    )

    def __init__(self) -> None:
        self.sleep_time = 0.0
        self.seed = 1
        self.solver = base.contact_solver_names()[0]

    def world(self, method: str, dt: float) -> physstep.World:
        w = physstep.World.from_scene("dice", method, dt, {"n": COUNT, "seed": self.seed})
        w.contact_solver = self.solver
        w.sleep_time = self.sleep_time
        return w

    def act(self, panels: list[Panel], action: str) -> None:
        if action == "solver":
            self.solver = base.next_contact_solver(self.solver, panels)
        elif action == "sleep":
            self.sleep_time = 0.0 if self.sleep_time else SLEEP_TIME
            for p in panels:
                if not p.error:
                    p.world.sleep_time = self.sleep_time
        elif action == "throw":
            self.seed += 1
            base.start_afresh(panels, self.world)
        else:
            super().act(panels, action)

    def hud(self, panel: Panel) -> list[tuple[str, str, tuple[int, int, int]]]:
        w = panel.world
        touching = int(np.count_nonzero(w.contacts()["depths"] >= 0.0))
        return [
            ("solver", f"{w.contact_solver} (c)", base.TEXT),
            ("throw", f"seed {self.seed} (t)", base.TEXT),
            ("kinetic", f"{w.kinetic_energy():.3e} J", base.TEXT),
            ("contacts", f"{touching}", base.TEXT),
            ("penetration", f"{w.max_penetration * 1000:.2f} mm", base.TEXT),
            ("asleep", f"{int(w.solids_asleep().sum())} (z)" if w.sleep_time else "off (z)", base.TEXT),
        ]

    def draw(self, surf: pygame.Surface, rect: pygame.Rect, panel: Panel, x: np.ndarray) -> None:
        scale = min(rect.width, rect.height) / 3.6
        cx, cy = rect.centerx, rect.centery + int(0.12 * rect.height)

        def project(p: np.ndarray) -> tuple[int, int]:
            c = CAMERA @ p
            return (int(cx + c[0] * scale), int(cy - c[1] * scale))

        # The floor: a 4 m square with a line every 0.5 m.
        span = 2.0
        quad = [np.array([sx * span, 0.0, sz * span]) for sx, sz in quad_signs()]
        pygame.draw.polygon(surf, FLOOR, [project(q) for q in quad])
        for t in np.arange(-span, span + 1e-9, 0.5):
            for p0, p1 in (([t, 0, -span], [t, 0, span]), ([-span, 0, t], [span, 0, t])):
                pygame.draw.line(surf, FLOOR_LINE, project(np.array(p0)), project(np.array(p1)))
        pos, quats = (a[1:] for a in base.solid_poses(panel))
        asleep = panel.world.solids_asleep()[1:]
        # Shadows under the dice, then the dice far to near.
        for p in pos:
            shadow = [project(np.array([p[0] + sx * HALF, 0.0, p[2] + sz * HALF])) for sx, sz in quad_signs()]
            pygame.draw.polygon(surf, (26, 30, 40), shadow)
        order = np.argsort(pos @ CAMERA[2])
        signs = [(sx, sy, sz) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
        for i in order:
            r = rotation(quats[i])
            corners = [pos[i] + r @ (HALF * np.array(sg, dtype=float)) for sg in signs]
            for idx, normal, pips in FACES:
                n = r @ np.array(normal, dtype=float)
                if CAMERA[2] @ n <= 0:
                    continue
                shade = 0.5 + 0.5 * max(0.0, float(n @ LIGHT))
                pts = [project(corners[k]) for k in idx]
                colour = ASLEEP if asleep[i] else DIE
                pygame.draw.polygon(surf, tuple(int(c * shade) for c in colour), pts)
                pygame.draw.polygon(surf, base.BACKGROUND, pts, 1)
                # Pips: on the face's two in-plane axes (along its first and last edges).
                centre = sum(corners[k] for k in idx) / 4.0
                u = (corners[idx[1]] - corners[idx[0]]) / 2.0
                v = (corners[idx[3]] - corners[idx[0]]) / 2.0
                radius = max(1, int(0.16 * HALF * scale * (0.4 + 0.6 * float(CAMERA[2] @ n))))
                for a, b in PIPS[pips]:
                    pygame.draw.circle(surf, PIP, project(centre + a * u + b * v), radius)
        base.text(
            surf,
            base.font(18),
            "t: throw again, c: contact solver, z: sleep",
            (rect.x + 10, rect.y + 8),
            base.DIM,
        )


def quad_signs() -> tuple[tuple[int, int], ...]:
    """The corners of a square, in order round it."""
    return ((-1, -1), (1, -1), (1, 1), (-1, 1))
