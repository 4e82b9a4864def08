"""A cloth hanging from its top corners: position constraints relaxed inside the step, or
stiff springs under a linearly implicit or a converged implicit step (the ``c`` key)."""

from __future__ import annotations

from dataclasses import dataclass

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
#: Particles along a side of the stiff spring cloth (the ``stiff-cloth`` scene: 1 m square).
N_STIFF = 12


@dataclass(frozen=True)
class Model:
    """A cloth the ``c`` key switches to: its name, its scene, its method (None: the one
    the position-based cloth last had) and its step, s."""

    name: str
    scene: str
    method: str | None
    dt: float
    doc: str


#: The cloths the ``c`` key cycles, in order.
MODELS = (
    Model("position-based", "cloth", None, 1.0 / 120.0, "rigid links, projected"),
    Model(
        "linearly implicit",
        "stiff-cloth",
        "linearly-implicit-euler",
        1.0 / 60.0,
        "k 1e5 N/m, 1 solve a step",
    ),
    Model(
        "converged implicit",
        "stiff-cloth",
        "backward-euler",
        1.0 / 60.0,
        "k 1e5 N/m, Newton to tol",
    ),
)


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
    ``w`` turns a wind along +z on and off; the mouse drags a particle. ``c`` switches to the
    same cloth made of stiff springs (``stiff-cloth``, 12 x 12, k = 1e5 N/m, starting flat
    and swinging down from its pinned edge) under the linearly implicit step, then under
    backward Euler, then back; the HUD shows what a step costs."""

    name = "cloth"
    dt = 1.0 / 120.0
    dt_range = (1e-3, 1.0 / 30.0)
    draggable = True
    mouse = "drag a cloth particle (in the plane facing you); the drift restarts on release"
    keys = (
        Key("iterations_up", (pygame.K_i,), "i", "double the constraint sweeps a step", shift=False),
        Key("iterations_down", (pygame.K_i,), "shift+i", "halve the constraint sweeps", shift=True),
        Key("wind", (pygame.K_w,), "w", f"wind along +z on / off ({WIND:g} m/s^2; the position-based cloth)"),
        Key(
            "model",
            (pygame.K_c,),
            "c",
            "next cloth: position-based, linearly implicit, converged implicit (restarts it)",
        ),
    )

    def __init__(self) -> None:
        self.iterations = 16
        self.wind = False
        self.model = 0
        #: The position-based cloth's method and dt, kept while another cloth is shown.
        self.pbd: tuple[str, float] | None = None

    @property
    def stiff(self) -> bool:
        """Whether the cloth shown is the spring cloth (drawn turned: see :meth:`viewed`)."""
        return MODELS[self.model].scene == "stiff-cloth"

    def world(self, method: str, dt: float) -> physstep.World:
        if self.stiff:
            return physstep.World.from_scene("stiff-cloth", method, dt, {"n": N_STIFF})
        w = physstep.World.from_scene("cloth", method, dt, {"wind": WIND if self.wind else 0.0})
        w.constraint_iterations = self.iterations
        return w

    def act(self, panels: list[Panel], action: str) -> None:
        if action in ("iterations_up", "iterations_down"):
            self.iterations = base.sweeps(self.iterations, action, panels)
        elif action == "wind":
            self.wind = not self.wind
            if self.stiff:
                return  # the spring cloth has no wind: kept for the position-based one
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
        elif action == "model":
            self.switch(panels)
        else:
            super().act(panels, action)

    def switch(self, panels: list[Panel]) -> None:
        """The next cloth of :data:`MODELS`, started afresh in every panel under its method
        and step (the position-based cloth's own method and dt are kept for its return); the
        game-loop variant carries over."""
        p0 = panels[0]
        if not self.stiff and not p0.error:
            self.pbd = (p0.world.method, p0.world.dt)
        self.model = (self.model + 1) % len(MODELS)
        m = MODELS[self.model]
        method, dt = (m.method, m.dt) if m.method else (self.pbd or (self.methods[0], m.dt))
        base.start_afresh(panels, self.world, method, dt)

    def hud(self, panel: Panel) -> list[tuple[str, str, tuple[int, int, int]]]:
        m = MODELS[self.model]
        cost = panel.step_cost()
        rows = [
            ("cloth", f"{m.name} (c)", base.ACCENT),
            ("", m.doc, base.DIM),
            ("cost", "-" if cost is None else f"{1e3 * cost:.2f} ms a step", base.TEXT),
        ]
        if not self.stiff:
            wind = f"{WIND:g} m/s^2 along +z (w)" if self.wind else "off (w)"
            return [*rows, *base.sweep_rows(panel.world), ("wind", wind, base.TEXT)]
        stats = None if panel.error else panel.world.solve_stats
        if stats:
            rows.append(("solve", f"{stats['newton']} Newton, {stats['cg']} CG a step", base.TEXT))
        if not panel.error:
            most = stretch(np.asarray(panel.world.positions))
            rows.append(("stretch", f"{most:.2e} (max, relative)", base.TEXT))
        return rows

    # A 3D view: orthographic through CAMERA.

    def viewed(self, x: np.ndarray) -> np.ndarray:
        """World positions (n, 3) as the view shows them. The spring cloth lies in the plane
        z = 0 with its pinned edge at y = 1 and falls along -z: it is turned so that it
        hangs as the position-based cloth does (its pinned edge on the bar, down along -y,
        its free edge starting out towards +z)."""
        x = np.asarray(x, dtype=float)
        if not self.stiff:
            return x
        return np.stack([x[..., 0], x[..., 2], 1.0 - x[..., 1]], axis=-1)

    def unview(self, p: np.ndarray) -> np.ndarray:
        """The world position of view point ``p`` (the inverse of :meth:`viewed`)."""
        if not self.stiff:
            return p
        return np.array([p[0], 1.0 - p[2], p[1]])

    def scale(self, rect: pygame.Rect) -> float:
        return rect.height / (2.0 * HALF)

    def screen(self, rect: pygame.Rect, p: object) -> tuple[int, int]:
        """Screen pixel of view point ``p``."""
        c = CAMERA @ (np.asarray(p, dtype=float) - CENTRE)
        s = self.scale(rect)
        return (int(base._clip(rect.centerx + c[0] * s)), int(base._clip(rect.centery - c[1] * s)))

    def to_screen(self, rect: pygame.Rect, p: object) -> tuple[int, int]:
        return self.screen(rect, self.viewed(np.asarray(p, dtype=float)))

    def hold(self, world: physstep.World, i: int, rect: pygame.Rect, pos: tuple[int, int]) -> bool:
        """Puts particle ``i`` under the pointer at its current depth, at rest."""
        x, v = np.array(world.positions), np.array(world.velocities)
        s = self.scale(rect)
        depth = float(CAMERA[2] @ (self.viewed(x[i]) - CENTRE))
        c = np.array([(pos[0] - rect.centerx) / s, (rect.centery - pos[1]) / s, depth])
        x[i] = self.unview(CENTRE + CAMERA.T @ c)
        v[i] = 0.0
        world.positions, world.velocities = x, v
        return True

    def draw(self, surf: pygame.Surface, rect: pygame.Rect, panel: Panel, x: np.ndarray) -> None:
        s = self.scale(rect)
        x = self.viewed(x)
        n = N_STIFF if self.stiff else W
        side = 1.0 if self.stiff else (W - 1) * SPACING
        pins = (n * (n - 1), n * n - 1) if self.stiff else (0, W - 1)
        cam = (x - CENTRE) @ CAMERA.T  # camera coordinates of every particle
        scr = np.column_stack([rect.centerx + cam[:, 0] * s, rect.centery - cam[:, 1] * s])
        scr = np.clip(np.nan_to_num(scr, nan=-30000.0), -30000, 30000).astype(int)
        # Where the cloth hangs at rest without wind (the x-y plane), for depth, then the bar
        # it hangs from.
        rest = [[0.0, 0.0, 0.0], [side, 0.0, 0.0], [side, -side, 0.0], [0.0, -side, 0.0]]
        pygame.draw.polygon(surf, base.GRID, [self.screen(rect, p) for p in rest], 1)
        pygame.draw.line(surf, base.GRID, self.screen(rect, rest[0]), self.screen(rect, rest[1]), 5)
        # The quads, far first, shaded by their normal: blue the front (+z at rest), orange the
        # back.
        light = np.array([0.3, 0.6, 1.0]) / np.linalg.norm([0.3, 0.6, 1.0])
        flip = -1.0 if self.stiff else 1.0  # the spring cloth's rows run up, not down
        quads = []
        for r in range(n - 1):
            for c in range(n - 1):
                a, b, d, e = r * n + c, r * n + c + 1, (r + 1) * n + c + 1, (r + 1) * n + c
                nrm = flip * np.cross(x[e] - x[b], x[d] - x[a])  # along +z for the cloth at rest
                norm = float(np.linalg.norm(nrm))
                nrm = nrm / norm if norm > 0 else np.array([0.0, 0.0, 1.0])
                facing = float(CAMERA[2] @ nrm)
                colour = FRONT if facing >= 0 else BACK
                shade = 0.35 + 0.65 * abs(float(nrm @ light))
                depth = float(cam[[a, b, d, e], 2].mean())
                shaded = (int(colour[0] * shade), int(colour[1] * shade), int(colour[2] * shade))
                quads.append((depth, (a, b, d, e), shaded))
        quads.sort(key=lambda q: q[0])
        for _, idx, colour in quads:
            pts = [tuple(scr[i]) for i in idx]
            pygame.draw.polygon(surf, colour, pts)
            pygame.draw.polygon(surf, base.PANEL, pts, 1)
        for i in pins:
            pygame.draw.circle(surf, base.ACCENT, tuple(scr[i]), 6)
        base.text(
            surf,
            base.font(18),
            "orthographic view from the front right; blue: the front (+z), orange the back; grey: at rest",
            (rect.x + 10, rect.bottom - 6),
            base.DIM,
            "bottomleft",
        )


def stretch(x: np.ndarray, n: int = N_STIFF) -> float:
    """The largest relative stretch |len / rest - 1| of the structural links of an n x n
    spring cloth 1 m square at positions ``x`` (n^2, 3)."""
    g = np.asarray(x).reshape(n, n, 3)
    rest = 1.0 / (n - 1)
    across = np.linalg.norm(np.diff(g, axis=1), axis=-1)
    down = np.linalg.norm(np.diff(g, axis=0), axis=-1)
    return float(max(np.abs(across / rest - 1).max(), np.abs(down / rest - 1).max()))
