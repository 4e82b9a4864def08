"""A stick-figure ragdoll falling onto the ground: rigid bones, joint limits, a ground plane."""

from __future__ import annotations

import numpy as np
import pygame

import physstep
from physstep.demos import base
from physstep.demos.base import Demo, Key, Panel

#: The ragdoll scene's bones (particle pairs): head-neck, spine, arms, legs.
BONES = ((0, 1), (1, 2), (1, 3), (3, 4), (1, 5), (5, 6), (2, 7), (7, 8), (2, 9), (9, 10))
#: Its joint limits (min/max distances), drawn faintly.
LIMITS = ((1, 4), (1, 6), (2, 8), (2, 10), (0, 2), (7, 9), (3, 2), (5, 2))
#: What the ``k`` key adds: an upward speed, m/s, and a spin about the centre of mass, rad/s.
KICK_SPEED, KICK_SPIN = 5.0, 4.0
BONE = (230, 232, 240)
LIMIT = (78, 86, 110)
JOINT = (110, 190, 255)


class RagdollDemo(Demo):
    """The ``ragdoll`` scene: 11 particles, 10 rigid bones (distance constraints), 8 joint
    limits (min/max distances: elbows and knees fold one way far enough), tilted and
    turning, falling onto the ground plane y >= 0. The mouse drags a particle (the bones
    follow); ``k`` kicks it up into the air again."""

    name = "ragdoll"
    dt = 1.0 / 120.0
    dt_range = (1e-3, 1.0 / 30.0)
    draggable = True
    mouse = "drag a joint (kept above the ground); the drift restarts on release"
    view = (0.0, 1.35, 1.5)
    keys = (
        Key("iterations_up", (pygame.K_i,), "i", "double the constraint sweeps a step", shift=False),
        Key("iterations_down", (pygame.K_i,), "shift+i", "halve the constraint sweeps", shift=True),
        Key("kick", (pygame.K_k,), "k", "kick the ragdoll up, spinning"),
    )

    def __init__(self) -> None:
        self.iterations = 16
        self.kicks = 0

    def world(self, method: str, dt: float) -> physstep.World:
        w = physstep.World.from_scene("ragdoll", method, dt)
        w.constraint_iterations = self.iterations
        return w

    def act(self, panels: list[Panel], action: str) -> None:
        if action in ("iterations_up", "iterations_down"):
            self.iterations = base.sweeps(self.iterations, action, panels)
        elif action == "kick":
            self.kicks += 1
            spin = KICK_SPIN if self.kicks % 2 else -KICK_SPIN  # alternate the sense
            for p in panels:
                if p.error:
                    continue
                x, v = np.array(p.world.positions), np.array(p.world.velocities)
                r = x - x.mean(axis=0)
                v += np.column_stack([-spin * r[:, 1], KICK_SPEED + spin * r[:, 0]])
                p.world.velocities = v
                p.restart_drift()
        else:
            super().act(panels, action)

    def hud(self, panel: Panel) -> list[tuple[str, str, tuple[int, int, int]]]:
        return base.sweep_rows(panel.world)

    def hold(self, world: physstep.World, i: int, rect: pygame.Rect, pos: tuple[int, int]) -> bool:
        """Puts the particle under the pointer at rest, not below the ground."""
        x, v = np.array(world.positions), np.array(world.velocities)
        x[i] = self.to_world(rect, pos, 2)
        x[i, 1] = max(0.0, x[i, 1])
        v[i] = 0.0
        world.positions, world.velocities = x, v
        return True

    def draw(self, surf: pygame.Surface, rect: pygame.Rect, panel: Panel, x: np.ndarray) -> None:
        s = self.scale(rect)
        ground = self.to_screen(rect, [0.0, 0.0])[1]
        pygame.draw.rect(surf, (34, 38, 50), (rect.x, ground, rect.width, rect.bottom - ground))
        pygame.draw.line(surf, base.DIM, (rect.x, ground), (rect.right, ground), 2)
        for k in range(-3, 4):  # metre marks along the ground
            gx = self.to_screen(rect, [float(k), 0.0])[0]
            pygame.draw.line(surf, base.GRID, (gx, ground), (gx, ground + 8), 2)
            base.text(surf, base.font(18), f"{k} m", (gx, ground + 10), base.DIM, "midtop")
        pts = [self.to_screen(rect, p) for p in x]
        for a, b in LIMITS:
            pygame.draw.line(surf, LIMIT, pts[a], pts[b], 1)
        for a, b in BONES:
            pygame.draw.line(surf, BONE, pts[a], pts[b], 6)
        for p in pts:
            pygame.draw.circle(surf, JOINT, p, 6)
        pygame.draw.circle(surf, BONE, pts[0], max(10, round(0.12 * s)))
        pygame.draw.circle(surf, JOINT, pts[0], max(10, round(0.12 * s)), 2)
        base.text(
            surf,
            base.font(18),
            "bones: rigid distances; faint lines: joint limits (min/max distances); ground y >= 0",
            (rect.x + 10, rect.y + 8),
            base.DIM,
        )
