"""A cloth hanging from its top corners: position constraints relaxed inside the step."""

from __future__ import annotations

import numpy as np
import pygame

import physstep
from physstep.demos import base
from physstep.demos.base import Demo, Key, Panel

#: Particles across and down, and the rest length of a link, m (the cloth scene's defaults).
W, H, SPACING = 12, 12, 0.1
#: The wind the ``w`` key turns on: a uniform acceleration along +z, m/s^2.
WIND = 6.0
FRONT, BACK = (110, 170, 255), (255, 150, 70)


def _camera() -> np.ndarray:
    """Rows: screen right, screen up, towards the eye (orthographic, from the front right,
    a little above: the cloth hangs in the x-y plane, the wind blows it along +z)."""
    eye = np.array([1.0, 0.3, 0.85])
    eye /= np.linalg.norm(eye)
    right = np.cross([0.0, 1.0, 0.0], eye)
    right /= np.linalg.norm(right)
    return np.array([right, np.cross(eye, right), eye])


CAMERA = _camera()
#: The point drawn at the panel's centre, m: the middle of where the cloth may swing (down,
#: and out along +z in the wind).
CENTRE = np.array([(W - 1) * SPACING / 2, -(H - 1) * SPACING / 2, 0.45])
#: Half the height of the view, m.
HALF = 1.05


class ClothDemo(Demo):
    """The ``cloth`` scene: 12 x 12 particles joined by rigid distance constraints
    (structural and shear), the top corners pinned, under gravity, drawn in 3D. The
    constraints are met by ``constraint_iterations`` Gauss-Seidel sweeps a step (``i`` /
    ``shift+i``): with few the cloth stretches, the HUD's max violation says by how much.
    ``w`` turns a wind along +z on and off; the mouse drags a particle."""

    name = "cloth"
    dt = 1.0 / 120.0
    dt_range = (1e-3, 1.0 / 30.0)
    draggable = True
    mouse = "drag a cloth particle (in the plane facing you); the drift restarts on release"
    keys = (
        Key("iterations_up", (pygame.K_i,), "i", "double the constraint sweeps a step", shift=False),
        Key("iterations_down", (pygame.K_i,), "shift+i", "halve the constraint sweeps", shift=True),
        Key("wind", (pygame.K_w,), "w", f"wind along +z on / off ({WIND:g} m/s^2)"),
    )

    def __init__(self) -> None:
        self.iterations = 16
        self.wind = False

    def world(self, method: str, dt: float) -> physstep.World:
        w = physstep.World.from_scene("cloth", method, dt, {"wind": WIND if self.wind else 0.0})
        w.constraint_iterations = self.iterations
        return w

    def act(self, panels: list[Panel], action: str) -> None:
        if action in ("iterations_up", "iterations_down"):
            self.iterations = base.sweeps(self.iterations, action, panels)
        elif action == "wind":
            self.wind = not self.wind
            for p in panels:
                if p.error:
                    continue
                # The wind is part of the scene's gravity: the same state (clock and method
                # memory included) in the scene built with the other wind, same loop.
                parts = p.world.__reduce__()[1][0]
                w = physstep.World.from_scene(
                    "cloth", p.world.method, p.world.dt, {"wind": WIND if self.wind else 0.0}
                )
                w = base.relooped(w, parts["loop"], parts["substeps"])
                w.constraint_iterations = self.iterations
                w.restore(p.world.snapshot())
                p.world = w
                p.restart_drift()
        else:
            super().act(panels, action)

    def hud(self, panel: Panel) -> list[tuple[str, str, tuple[int, int, int]]]:
        wind = f"{WIND:g} m/s^2 along +z (w)" if self.wind else "off (w)"
        return [*base.sweep_rows(panel.world), ("wind", wind, base.TEXT)]

    # A 3D view: orthographic through CAMERA.

    def scale(self, rect: pygame.Rect) -> float:
        return rect.height / (2.0 * HALF)

    def to_screen(self, rect: pygame.Rect, p: object) -> tuple[int, int]:
        c = CAMERA @ (np.asarray(p, dtype=float) - CENTRE)
        s = self.scale(rect)
        return (int(base._clip(rect.centerx + c[0] * s)), int(base._clip(rect.centery - c[1] * s)))

    def hold(self, world: physstep.World, i: int, rect: pygame.Rect, pos: tuple[int, int]) -> bool:
        """Puts particle ``i`` under the pointer at its current depth, at rest."""
        x, v = np.array(world.positions), np.array(world.velocities)
        s = self.scale(rect)
        depth = float(CAMERA[2] @ (x[i] - CENTRE))
        c = np.array([(pos[0] - rect.centerx) / s, (rect.centery - pos[1]) / s, depth])
        x[i] = CENTRE + CAMERA.T @ c
        v[i] = 0.0
        world.positions, world.velocities = x, v
        return True

    def draw(self, surf: pygame.Surface, rect: pygame.Rect, panel: Panel, x: np.ndarray) -> None:
        s = self.scale(rect)
        cam = (x - CENTRE) @ CAMERA.T  # camera coordinates of every particle
        scr = np.column_stack([rect.centerx + cam[:, 0] * s, rect.centery - cam[:, 1] * s])
        scr = np.clip(np.nan_to_num(scr, nan=-30000.0), -30000, 30000).astype(int)
        # Where the cloth hangs at rest without wind (the x-y plane), for depth, then the bar
        # it hangs from.
        rest = [[0.0, 0.0, 0.0], [(W - 1) * SPACING, 0.0, 0.0], [(W - 1) * SPACING, -(H - 1) * SPACING, 0.0]]
        rest.append([0.0, -(H - 1) * SPACING, 0.0])
        pygame.draw.polygon(surf, base.GRID, [self.to_screen(rect, p) for p in rest], 1)
        left, right = self.to_screen(rect, [0.0, 0.0, 0.0]), self.to_screen(rect, [(W - 1) * SPACING, 0, 0])
        pygame.draw.line(surf, base.GRID, left, right, 5)
        # The quads, far first, shaded by their normal: blue the front (+z), orange the back.
        light = np.array([0.3, 0.6, 1.0]) / np.linalg.norm([0.3, 0.6, 1.0])
        quads = []
        for r in range(H - 1):
            for c in range(W - 1):
                a, b, d, e = r * W + c, r * W + c + 1, (r + 1) * W + c + 1, (r + 1) * W + c
                n = np.cross(x[e] - x[b], x[d] - x[a])  # along +z for the cloth at rest
                norm = float(np.linalg.norm(n))
                n = n / norm if norm > 0 else np.array([0.0, 0.0, 1.0])
                facing = float(CAMERA[2] @ n)
                colour = FRONT if facing >= 0 else BACK
                shade = 0.35 + 0.65 * abs(float(n @ light))
                depth = float(cam[[a, b, d, e], 2].mean())
                quads.append((depth, (a, b, d, e), tuple(int(ch * shade) for ch in colour)))
        quads.sort(key=lambda q: q[0])
        for _, idx, colour in quads:
            pts = [tuple(scr[i]) for i in idx]
            pygame.draw.polygon(surf, colour, pts)
            pygame.draw.polygon(surf, base.PANEL, pts, 1)
        for i in (0, W - 1):
            pygame.draw.circle(surf, base.ACCENT, tuple(scr[i]), 6)
        base.text(
            surf,
            base.font(18),
            "orthographic view from the front right; blue: the front (+z), orange the back; grey: at rest",
            (rect.x + 10, rect.bottom - 6),
            base.DIM,
            "bottomleft",
        )
