"""Bridge: planks hinged end to end between two fixed points, sagging under what is dropped
on them; the joints' worst error in the HUD."""

from __future__ import annotations

import math

import numpy as np
import pygame

import physstep
from physstep.demos import base
from physstep.demos.base import Demo, Key, Panel

#: Planks of the bridge (the scene's 40), each 1 m long and 0.125 m half thick.
PLANKS, HALF_LENGTH, HALF_THICK = 40, 0.5, 0.125
#: What the mouse drops: a box of this half side (m), or a ball of this radius (m).
BOX_HALF, BALL_RADIUS = 0.45, 0.4
#: The heavy box ``b`` drops: its half side, m, and density (kg/m^2; the planks' is 20).
HEAVY_HALF, HEAVY_DENSITY = 0.6, 60.0
#: Depth of the ground under the bridge's ends, m: below its lowest sag (11.8 m bare).
GROUND_DEPTH = 16.0
PLANK, PLANK_EDGE = (150, 112, 72), (205, 165, 115)
BOX, BOX_EDGE = (205, 150, 80), (240, 200, 140)
BALL, BALL_EDGE = (90, 150, 235), (160, 200, 255)
HEAVY, HEAVY_EDGE = (170, 80, 80), (230, 140, 130)
DOLL, DOLL_EDGE = (120, 190, 140), (180, 235, 195)
#: The ``ragdoll-bodies`` scene's ragdoll (1.8 m, about 70 kg): the lengths of its shin,
#: thigh, torso, upper arm, forearm and head, m, its density (kg/m^2), the joint friction
#: (N m) and the spin it is dropped with (rad/s).
SHIN, THIGH, TORSO, UPPER_ARM, FOREARM, HEAD = 0.45, 0.45, 0.6, 0.3, 0.3, 0.25
DOLL_DENSITY, DOLL_FRICTION, DOLL_SPIN = 200.0, 5.0, 1.0
HINGE, GROUND = (235, 235, 240), (34, 38, 50)


def plank_ends(w: physstep.World) -> tuple[np.ndarray, np.ndarray]:
    """Each plank's left and right end, (PLANKS, 2) each, m: where its hinges hold it."""
    p, a = w.solid_positions()[:PLANKS], w.solid_orientations()[:PLANKS]
    along = np.stack([np.cos(a), np.sin(a)], axis=1) * HALF_LENGTH
    return p - along, p + along


def hinges(w: physstep.World) -> np.ndarray:
    """The hinge points (PLANKS + 1, 2), m: the outer ends, and between planks the middle of
    the two ends a joint holds together (they part by the joint's error)."""
    left, right = plank_ends(w)
    inner = (right[:-1] + left[1:]) / 2
    return np.vstack([left[:1], inner, right[-1:]])


def capsule_ends(centre: np.ndarray, angle: float, half_height: float) -> tuple[np.ndarray, np.ndarray]:
    """The two centres of a 2D capsule's caps: its axis is its local y."""
    axis = half_height * np.array([-math.sin(angle), math.cos(angle)])
    return centre - axis, centre + axis


class BridgeDemo(Demo):
    """The ``bridge`` scene: 40 planks (1 m, density 20) hinged end to end between two fixed
    points 30 m apart, swinging down into their catenary and settling (joint friction). Click
    to drop a box or a ball at the pointer (``o`` switches which), ``b`` drops a heavy box
    onto the middle, ``d`` a ragdoll (the ``ragdoll-bodies`` scene's: 12 solids, 11 hinges
    with angle limits), ``c`` cycles the contact solver. The HUD shows the worst joint error (the
    hinged ends apart, mm: the soft joints stretch under load) and the wall time a step
    takes. A ground far below catches what falls off."""

    name = "bridge"
    dt = 1.0 / 60.0
    dt_range = (1.0 / 480.0, 1.0 / 15.0)
    view = (0.0, -8.0, 15.5)
    draggable = True
    mouse = "click to drop a box or a ball (o) at the pointer"
    keys = (
        Key("shape", (pygame.K_o,), "o", "switch the object a click drops: a box or a ball"),
        Key("heavy", (pygame.K_b,), "b", "drop a heavy box onto the middle of the bridge"),
        Key("ragdoll", (pygame.K_d,), "d", "drop a ragdoll (ragdoll-bodies') onto the middle, spinning"),
        Key("solver", (pygame.K_c,), "c", "next contact solver (physstep.contact_solvers())"),
    )

    def __init__(self) -> None:
        self.solver = base.contact_solver_names()[0]
        self.shape = "box"
        #: What was dropped, in the order of the solids after the planks and the ground:
        #: (kind, sizes): box and heavy (half side,), ball (radius,), capsule (half height of
        #: its axis, radius), head (radius,).
        self.dropped: list[tuple[str, tuple[float, ...]]] = []
        self.armed = False  # a click not yet turned into a drop

    def world(self, method: str, dt: float) -> physstep.World:
        w = physstep.World.from_scene("bridge", method, dt, {"n": PLANKS})
        w.add_solid(physstep.Plane([0.0, 1.0]), position=[0.0, -GROUND_DEPTH], kind="static")
        w.contact_solver = self.solver
        self.dropped = []
        return w

    def drop(self, w: physstep.World, at: np.ndarray, kind: str) -> int:
        """Drops a solid of ``kind`` (box, ball or heavy) at rest at ``at``; its index."""
        if kind == "ball":
            i = w.add_solid(physstep.Circle(BALL_RADIUS), position=at).row
            self.dropped.append(("ball", (BALL_RADIUS,)))
        elif kind == "heavy":
            box = physstep.Box(HEAVY_HALF, HEAVY_HALF)
            i = w.add_solid(box, position=at, density=HEAVY_DENSITY, orientation=0.2).row
            self.dropped.append(("heavy", (HEAVY_HALF,)))
        else:
            i = w.add_solid(physstep.Box(BOX_HALF, BOX_HALF), position=at, orientation=0.3).row
            self.dropped.append(("box", (BOX_HALF,)))
        return i

    def ragdoll(self, w: physstep.World, feet: np.ndarray) -> int:
        """Adds the ``ragdoll-bodies`` scene's ragdoll standing with its feet at ``feet``,
        spinning at DOLL_SPIN: 12 solids (torso, head, upper and lower arms and legs, feet)
        and 11 hinges with its angle limits and joint friction. Returns the torso's index."""
        x, y0 = float(feet[0]), float(feet[1])
        hip = y0 + SHIN + THIGH
        neck = hip + TORSO

        def part(
            shape: physstep.SolidShape | physstep.Shape,
            at: list[float],
            sizes: tuple[float, ...],
            kind: str,
            turn: float = 0.0,
            spin: float = 0.0,
        ) -> int:
            self.dropped.append((kind, sizes))
            return w.add_solid(
                shape, position=at, orientation=turn, angular_velocity=spin, density=DOLL_DENSITY
            ).row

        def capsule(
            at: list[float], half_height: float, radius: float, turn: float = 0.0, spin: float = 0.0
        ) -> int:
            shape = physstep.Capsule(radius, 2 * half_height)
            return part(shape, at, (half_height, radius), "capsule", turn, spin)

        def hinge(a: int, b: int, at: list[float], lower: float, upper: float) -> None:
            w.add_joint("revolute", a, b, anchor=at, lower=lower, upper=upper, max_motor=DOLL_FRICTION)

        def limb(
            parent: int, top: list[float], length: float, radius: float, lower: float, upper: float
        ) -> int:
            b = capsule([top[0], top[1] - length / 2], length / 2 - radius, radius)
            hinge(parent, b, top, lower, upper)
            return b

        torso = capsule([x, hip + TORSO / 2], TORSO / 2 - 0.15, 0.15, spin=DOLL_SPIN)
        head = part(physstep.Circle(HEAD / 2), [x, neck + HEAD / 2], (HEAD / 2,), "head")
        hinge(torso, head, [x, neck], -0.5, 0.5)
        for side in (-1.0, 1.0):
            arm = limb(torso, [x + 0.25 * side, neck - 0.05], UPPER_ARM, 0.06, -2.5, 2.5)
            limb(arm, [x + 0.25 * side, neck - 0.05 - UPPER_ARM], FOREARM, 0.05, -2.5, 0.0)
            leg = limb(torso, [x + 0.1 * side, hip], THIGH, 0.09, -0.5, 1.5)
            shin = limb(leg, [x + 0.1 * side, hip - THIGH], SHIN - 0.08, 0.07, -2.0, 0.0)
            heel = [x + 0.1 * side, y0 + 0.08]
            foot = capsule([heel[0] + 0.08 * side, y0 + 0.04], 0.08, 0.04, turn=math.pi / 2)
            hinge(shin, foot, heel, -0.5, 0.5)
        return torso

    def act(self, panels: list[Panel], action: str) -> None:
        if action == "solver":
            self.solver = base.next_contact_solver(self.solver, panels)
            return
        if action == "shape":
            self.shape = "ball" if self.shape == "box" else "box"
            return
        if action not in ("heavy", "ragdoll"):
            super().act(panels, action)
            return
        for p in panels:
            if p.error:
                continue
            middle = hinges(p.world)[PLANKS // 2]
            if action == "heavy":
                self.drop(p.world, middle + [0.0, 3.0], "heavy")
            else:
                self.ragdoll(p.world, middle + [0.0, 2.0])
            p.restart_drift()

    def pick(self, rect: pygame.Rect, x: np.ndarray, pos: tuple[int, int]) -> int | None:
        """A click anywhere in the panel drops (the first :meth:`hold` after it)."""
        self.armed = rect.collidepoint(pos)
        return 0 if self.armed else None

    def hold(self, world: physstep.World, i: int, rect: pygame.Rect, pos: tuple[int, int]) -> bool:
        """Drops one solid at the pointer per click, at rest."""
        if self.armed:
            self.armed = False
            self.drop(world, self.to_world(rect, pos, 2), self.shape)
        return False

    def hud(self, panel: Panel) -> list[tuple[str, str, tuple[int, int, int]]]:
        w = panel.world
        errors = w.joint_errors()
        worst = float(errors.max()) if len(errors) else 0.0
        cost = panel.step_cost()
        return [
            ("solver", f"{w.contact_solver} (c)", base.TEXT),
            ("planks", f"{PLANKS}, {PLANKS + 1} hinges", base.TEXT),
            ("joints", f"{w.joint_count} (the ragdolls' too)", base.TEXT),
            ("dropped", f"{len(self.dropped)} solids (click: {self.shape}, o)", base.TEXT),
            ("worst joint", f"{worst * 1000:.2f} mm", base.ACCENT),
            ("step", "-" if cost is None else f"{cost * 1000:.2f} ms", base.TEXT),
        ]

    def draw(self, surf: pygame.Surface, rect: pygame.Rect, panel: Panel, x: np.ndarray) -> None:
        w = panel.world
        ground = self.to_screen(rect, [0.0, -GROUND_DEPTH])[1]
        pygame.draw.rect(surf, GROUND, (rect.x, ground, rect.width, rect.bottom - ground))
        pygame.draw.line(surf, base.DIM, (rect.x, ground), (rect.right, ground), 2)
        pos, ang = base.solid_poses(panel)
        for p, a in zip(pos[:PLANKS], ang[:PLANKS], strict=True):
            pts = [self.to_screen(rect, c) for c in base.box_corners(p, float(a), HALF_LENGTH, HALF_THICK)]
            pygame.draw.polygon(surf, PLANK, pts)
            pygame.draw.polygon(surf, PLANK_EDGE, pts, 1)
        s = self.scale(rect)
        for (kind, size), p, a in zip(self.dropped, pos[PLANKS + 1 :], ang[PLANKS + 1 :], strict=False):
            if kind in ("ball", "head"):
                fill, edge = (BALL, BALL_EDGE) if kind == "ball" else (DOLL, DOLL_EDGE)
                c, r = self.to_screen(rect, p), max(2, round(size[0] * s))
                pygame.draw.circle(surf, fill, c, r)
                pygame.draw.circle(surf, edge, c, r, 1)
                tip = p + size[0] * np.array([math.cos(a), math.sin(a)])  # a radius shows the spin
                pygame.draw.line(surf, edge, c, self.to_screen(rect, tip), 2)
                continue
            if kind == "capsule":
                hh, radius = size
                pts = [self.to_screen(rect, c) for c in base.box_corners(p, float(a), radius, hh)]
                pygame.draw.polygon(surf, DOLL, pts)
                r = max(1, round(radius * s))
                for end in capsule_ends(p, float(a), hh):
                    pygame.draw.circle(surf, DOLL, self.to_screen(rect, end), r)
                continue
            fill, edge = (HEAVY, HEAVY_EDGE) if kind == "heavy" else (BOX, BOX_EDGE)
            pts = [self.to_screen(rect, c) for c in base.box_corners(p, float(a), size[0], size[0])]
            pygame.draw.polygon(surf, fill, pts)
            pygame.draw.polygon(surf, edge, pts, 2)
        points = hinges(w)
        for k, h in enumerate(points):
            c = self.to_screen(rect, h)
            if k in (0, len(points) - 1):  # hinged to the world
                pygame.draw.rect(surf, base.ACCENT, pygame.Rect(c[0] - 5, c[1] - 5, 11, 11), 2)
            else:
                pygame.draw.circle(surf, HINGE, c, 3)
        base.text(
            surf,
            base.font(18),
            "click: drop a box or a ball (o switches), b: a heavy box, d: a ragdoll, c: contact solver",
            (rect.x + 10, rect.y + 8),
            base.DIM,
        )
        base.text(
            surf,
            base.font(18),
            "dots: the hinges; squares: hinged to the world",
            (rect.x + 10, rect.bottom - 6),
            base.DIM,
            "bottomleft",
        )
