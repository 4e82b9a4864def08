"""The tennis-racket flip: a thin box spun about its intermediate axis, drawn in 3D from its
interpolated orientation, with its angular velocity in the body frame."""

from __future__ import annotations

import math

import numpy as np
import pygame

import physstep
from physstep.demos import base
from physstep.demos.base import Demo, Panel

#: Half edges of the racket scene's plate, m (principal moments 1 : 2 : 3 along x, y, z).
HALF = (math.sqrt(2.0) * 0.5, 0.5, 0.0025)
#: Half edges drawn: the plate thickened so that its rim shows (the physics keeps HALF).
DRAWN = (HALF[0], HALF[1], 0.03)
#: The box's faces: (vertex indices, outward normal in the body frame, colour).
FACES = (
    ((4, 5, 7, 6), (1, 0, 0), (150, 150, 160)),
    ((0, 2, 3, 1), (-1, 0, 0), (150, 150, 160)),
    ((2, 6, 7, 3), (0, 1, 0), (150, 150, 160)),
    ((0, 1, 5, 4), (0, -1, 0), (150, 150, 160)),
    ((1, 3, 7, 5), (0, 0, 1), (255, 150, 70)),
    ((0, 4, 6, 2), (0, 0, -1), (90, 160, 255)),
)
AXIS_COLOURS = ((255, 105, 97), (120, 220, 120), (110, 170, 255))
AXIS_NAMES = ("1 (smallest I)", "2 (intermediate)", "3 (largest I)")


def rotation(q: np.ndarray) -> np.ndarray:
    """The rotation matrix of the unit quaternion ``q`` = (w, x, y, z)."""
    w, x, y, z = (float(c) for c in q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def _camera() -> np.ndarray:
    """Rows: screen right, screen up, towards the eye (a view from above the x-y plane)."""
    eye = np.array([1.0, -1.5, 1.1])
    eye /= np.linalg.norm(eye)
    right = np.cross([0.0, 0.0, 1.0], eye)
    right /= np.linalg.norm(right)
    return np.array([right, np.cross(eye, right), eye])


CAMERA = _camera()


class RacketDemo(Demo):
    """The ``racket`` scene: a free thin plate, principal moments 1 : 2 : 3, spun at 2 rad/s
    about its intermediate axis (green) with a 0.01 rad/s wobble; it flips over and back,
    the orange and blue faces trading places. Below, the angular velocity in the body frame:
    omega_2 changes sign at each flip."""

    name = "racket"
    dt = 1.0 / 120.0
    dt_range = (1e-3, 0.2)

    def applies(self, info: physstep.MethodInfo) -> bool:
        return not info.vector_positions

    def world(self, method: str, dt: float) -> physstep.World:
        # As the racket scene builds it, with add_body so that the loop key can rebuild it.
        w = physstep.World(3, method, dt)
        w.add_body(physstep.Box(*HALF), mass=12.0, angular_velocity=[0.01, 2.0, 0.01])
        return w

    def orientation(self, panel: Panel) -> np.ndarray:
        w = panel.world
        q = w.interpolated_body_orientations() if panel.interpolate else w.body_orientations()
        return q[0]

    def spin(self, panel: Panel) -> np.ndarray:
        """Angular velocity in the body frame, rad/s: R^T omega."""
        w = panel.world
        r = rotation(w.body_orientations()[0])
        return r.T @ w.body_angular_velocities()[0]

    def record(self, panel: Panel, x: np.ndarray) -> None:
        if panel.steps or not panel.trail:
            panel.trail.append(tuple(float(c) for c in self.spin(panel)))

    def draw(self, surf: pygame.Surface, rect: pygame.Rect, panel: Panel, x: np.ndarray) -> None:
        font = base.font(20)
        view = pygame.Rect(rect.x, rect.y, rect.width, int(rect.height * 0.62))
        chart = pygame.Rect(rect.x + 50, view.bottom + 24, rect.width - 70, rect.bottom - view.bottom - 44)
        r = rotation(self.orientation(panel))
        scale = min(view.width, view.height) * 0.42
        cx, cy = view.center

        def project(p: np.ndarray) -> tuple[int, int]:
            c = CAMERA @ p
            k = scale / (1.0 - 0.15 * c[2])  # a mild perspective
            return (int(cx + c[0] * k), int(cy - c[1] * k))

        signs = [(sx, sy, sz) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
        corners = [r @ np.array([sx * DRAWN[0], sy * DRAWN[1], sz * DRAWN[2]]) for sx, sy, sz in signs]
        # Axes behind the plate first, then the faces that face the eye, then the axes in front.
        axes = [(r[:, k], AXIS_COLOURS[k]) for k in range(3)]
        for a, colour in axes:
            if CAMERA[2] @ a < 0:
                pygame.draw.line(surf, colour, project(np.zeros(3)), project(1.1 * a), 3)
        light = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
        for idx, normal, colour in FACES:
            n = r @ np.array(normal, dtype=float)
            if CAMERA[2] @ n <= 0:
                continue
            shade = 0.45 + 0.55 * abs(float(n @ light))
            pygame.draw.polygon(
                surf, tuple(int(c * shade) for c in colour), [project(corners[i]) for i in idx]
            )
            pygame.draw.polygon(surf, base.BACKGROUND, [project(corners[i]) for i in idx], 1)
        for k, (a, colour) in enumerate(axes):
            if CAMERA[2] @ a >= 0:
                pygame.draw.line(surf, colour, project(np.zeros(3)), project(1.1 * a), 3)
            label = project(1.22 * a)
            pygame.draw.circle(surf, base.BACKGROUND, label, 10)
            base.text(surf, font, str(k + 1), label, colour, "center")
        # The body-frame angular velocity over the last frames.
        omega = self.spin(panel)
        pygame.draw.rect(surf, base.GRID, chart, 1)
        top = 2.2
        mid = chart.centery
        pygame.draw.line(surf, base.GRID, (chart.x, mid), (chart.right - 1, mid))
        for v in (top, 0.0, -top):
            base.text(
                surf,
                font,
                f"{v:+.1f}",
                (chart.x - 6, int(mid - v / top * chart.height / 2)),
                base.DIM,
                "midright",
            )
        base.text(
            surf,
            font,
            f"angular velocity in the body frame, rad/s (last {min(len(panel.trail), chart.width)} frames)",
            (chart.x, chart.y - 4),
            base.DIM,
            "bottomleft",
        )
        hist = list(panel.trail)[-chart.width :]
        for k in range(3):
            pts = [
                (chart.x + i, int(mid - max(-1.0, min(1.0, h[k] / top)) * (chart.height / 2 - 2)))
                for i, h in enumerate(hist)
            ]
            if len(pts) > 1:
                pygame.draw.lines(surf, AXIS_COLOURS[k], False, pts, 2)
            base.text(
                surf,
                font,
                f"omega_{AXIS_NAMES[k]} {omega[k]:+.3f}",
                (view.right - 10, view.y + 10 + 20 * k),
                AXIS_COLOURS[k],
                "topright",
            )
