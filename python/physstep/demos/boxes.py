"""Boxes: a pyramid of solids standing on the ground; drop a box on it or shoot one at it."""

from __future__ import annotations

import dataclasses

import numpy as np
import pygame

import physstep
from physstep.demos import base
from physstep.demos.base import Demo, Key, Panel

#: Rows of the pyramid, and the half extent of a box, m.
ROWS, HALF = 8, 0.25
#: The substeps the ``n`` key cycles.
SUBSTEPS = (8, 16, 2, 4)
BOX, EDGE, GROUND = (205, 150, 80), (240, 200, 140), (34, 38, 50)
#: A sleeping box's fill and edge (Box2D's testbed greys them too).
ASLEEP, ASLEEP_EDGE = (110, 110, 130), (160, 160, 180)
#: The sleep time the ``z`` key turns on, s (Box2D's).
SLEEP_TIME = 0.5


class BoxesDemo(Demo):
    """A pyramid of 36 boxes (0.5 m, friction 0.6) on the ground, stepped by the contact
    solver (the soft step: its own substeps of symplectic Euler; the world's method moves
    nothing here). ``b`` drops a box from above, ``x`` shoots one at the pyramid from the
    left, ``n`` changes the substeps: at 2 the contacts are soft and the pyramid sags and
    may topple, at 8 (the default) it stands. ``z`` turns sleeping on and off: a pyramid at
    rest falls asleep (drawn grey) and leaves the solver until a box reaches it."""

    name = "boxes"
    #: Whether the panel draws the keys' hint at its top.
    hint = True
    dt = 1.0 / 60.0
    dt_range = (1.0 / 480.0, 1.0 / 15.0)
    view = (0.0, 2.4, 3.0)
    keys: tuple[Key, ...] = (
        Key("drop", (pygame.K_b,), "b", "drop a box from above"),
        Key("shoot", (pygame.K_x,), "x", "shoot a box at the pyramid from the left"),
        Key("substeps", (pygame.K_n,), "n", "next substeps of the contact solver (8, 16, 2, 4)"),
        Key("solver", (pygame.K_c,), "c", "next contact solver (physstep.contact_solvers())"),
        Key("sleep", (pygame.K_z,), "z", "sleeping on / off (islands at rest leave the solver)"),
    )

    def __init__(self) -> None:
        self.sleep_time = 0.0
        self.substeps = SUBSTEPS[0]
        self.solver = base.contact_solver_names()[0]
        self.thrown = 0

    def world(self, method: str, dt: float) -> physstep.World:
        w = physstep.World(2, method, dt)
        w.add_gravity([0.0, -9.81])
        w.add_solid(physstep.Box(20.0, 1.0), position=[0.0, -1.0], kind="static")
        for row in range(ROWS):
            k = ROWS - row
            for i in range(k):
                x = (i - (k - 1) / 2) * (2 * HALF + 0.01)
                w.add_solid(physstep.Box(HALF, HALF), position=[x, HALF + 2 * HALF * row])
        w.substeps = self.substeps
        w.contact_solver = self.solver
        w.sleep_time = self.sleep_time
        self.thrown = 0
        return w

    def act(self, panels: list[Panel], action: str) -> None:
        if action == "substeps":
            k = SUBSTEPS.index(self.substeps) if self.substeps in SUBSTEPS else -1
            self.substeps = SUBSTEPS[(k + 1) % len(SUBSTEPS)]
        if action == "solver":
            self.solver = base.next_contact_solver(self.solver, panels)
            return
        if action == "sleep":
            self.sleep_time = 0.0 if self.sleep_time else SLEEP_TIME
        for p in panels:
            if p.error:
                continue
            w = p.world
            if action == "substeps":
                w.substeps = self.substeps
            elif action == "sleep":
                w.sleep_time = self.sleep_time
            elif action == "drop":
                # Above the pyramid's top, a little to one side each time, turned a little.
                x = 0.15 * ((self.thrown % 5) - 2)
                w.add_solid(physstep.Box(HALF, HALF), position=[x, 2 * HALF * ROWS + 0.45], orientation=0.3)
                self.thrown += 1
            elif action == "shoot":
                w.add_solid(
                    physstep.Box(HALF, HALF),
                    position=[-2.4, 1.0],
                    velocity=[9.0, 2.0],
                    angular_velocity=-3.0,
                    density=4.0,
                )
                self.thrown += 1
            else:
                super().act(panels, action)
            p.restart_drift()

    def hud(self, panel: Panel) -> list[tuple[str, str, tuple[int, int, int]]]:
        w = panel.world
        c = w.contacts()
        touching = int(np.count_nonzero(c["depths"] >= 0.0))
        return [
            ("solids", f"{w.solid_count}", base.TEXT),
            ("solver", f"{w.contact_solver} (c)", base.TEXT),
            ("substeps", f"{w.substeps} (n)", base.TEXT),
            ("contacts", f"{touching}", base.TEXT),
            ("penetration", f"{w.max_penetration * 1000:.2f} mm", base.TEXT),
            ("asleep", f"{int(w.solids_asleep().sum())} (z)" if w.sleep_time else "off (z)", base.TEXT),
        ]

    def draw(self, surf: pygame.Surface, rect: pygame.Rect, panel: Panel, x: np.ndarray) -> None:
        ground = self.to_screen(rect, [0.0, 0.0])[1]
        pygame.draw.rect(surf, GROUND, (rect.x, ground, rect.width, rect.bottom - ground))
        pygame.draw.line(surf, base.DIM, (rect.x, ground), (rect.right, ground), 2)
        pos, ang = base.solid_poses(panel)
        asleep = panel.world.solids_asleep()
        for p, a, z in zip(pos[1:], ang[1:], asleep[1:], strict=True):
            pts = [self.to_screen(rect, c) for c in base.box_corners(p, float(a), HALF, HALF)]
            pygame.draw.polygon(surf, ASLEEP if z else BOX, pts)
            pygame.draw.polygon(surf, ASLEEP_EDGE if z else EDGE, pts, 2)
        if self.hint:
            base.text(
                surf,
                base.font(18),
                "b: drop a box, x: shoot one, n: substeps (2 sag and topple, 8 stand), c: solver, z: sleep",
                (rect.x + 10, rect.y + 8),
                base.DIM,
            )


#: The solvers of the side-by-side demo's four panels, at the start.
SIDE_BY_SIDE = ("soft-step", "pgs", "tgs-sticky", "jacobi")


class SolversDemo(BoxesDemo):
    """The pyramid of :class:`BoxesDemo` four times side by side, each panel under its own
    contact solver (the soft step, PGS, sticky TGS and Jacobi at the start; the HUD names
    each), every one making the same passes a step: ``b`` and ``x`` drop or shoot the same box
    into all four, ``n`` changes every panel's substeps, ``c`` moves every panel on to its next
    solver in the registry. The solver lab's comparison (``physstep compare pyramid --solvers
    all``), live."""

    name = "solvers"
    methods = ("symplectic-euler",) * len(SIDE_BY_SIDE)
    view = (0.0, 2.2, 3.2)
    keys: tuple[Key, ...] = tuple(
        dataclasses.replace(k, doc="every panel's next contact solver") if k.action == "solver" else k
        for k in BoxesDemo.keys
    )

    hint = False  # the panels' captions take the hint's place

    def __init__(self) -> None:
        super().__init__()
        self.solvers = list(SIDE_BY_SIDE)

    def caption(self, panel: Panel) -> tuple[str, str]:
        w = panel.world
        return w.contact_solver, f"{w.contact_passes} passes a step, {w.max_penetration * 1000:.2f} mm deep"

    def panel_world(self, k: int, method: str, dt: float) -> physstep.World:
        w = self.world(method, dt)
        w.contact_solver = self.solvers[k % len(self.solvers)]
        return w

    def act(self, panels: list[Panel], action: str) -> None:
        if action != "solver":
            super().act(panels, action)
            return
        names = base.contact_solver_names()
        for k, p in enumerate(panels):
            now = self.solvers[k]
            self.solvers[k] = names[(names.index(now) + 1) % len(names)] if now in names else names[0]
            if not p.error:
                p.world.contact_solver = self.solvers[k]
