"""Any scene file in a generic demo (``physstep demo --scene FILE.toml``).

The World is :func:`physstep.load_scene`'s; what it does not expose (which particles a
spring or a constraint joins, a body's shape, a flow's kind) is read from the same file with
``tomllib`` once the loader has accepted it. Particles are dots (balls circles at their radii,
the walls a rectangle), springs zigzags, constraints lines, bodies their oriented bounding box
and axes, a flow its trail; 1D and 2D in the plane, 3D in an orthographic view looking down
against gravity. The view is fitted to where the scene goes under its own method: a copy of
the world is stepped ahead (at most :data:`FIT_STEPS` steps) before the first frame.
"""

from __future__ import annotations

import copy
import math
import tomllib
from pathlib import Path
from typing import Any

import numpy as np
import pygame

import physstep
from physstep.demos import base, scene_solids
from physstep.demos.balls import PULL_SPEED, PULL_TIME
from physstep.demos.base import Demo, Panel
from physstep.demos.racket import AXIS_COLOURS, rotation

#: The view is fitted to a run ahead of the file's ``until`` (at most FIT_TIME s), within
#: FIT_WORK particle-steps (at least FIT_STEPS steps; an implicit method FIT_STEPS_IMPLICIT,
#: its Newton solves are dear).
FIT_TIME, FIT_WORK, FIT_STEPS, FIT_STEPS_IMPLICIT = 10.0, 150_000, 200, 20
#: The view widens, when something leaves it, to at most this many times its fitted extent.
GROW_MAX = 50.0
#: Trails are drawn for at most this many moving points (particles and body centres).
TRAIL_MAX = 16
#: The plane a flow is drawn in: the coordinates across and up.
FLOW_AXES = {"lorenz": (0, 2), "rossler": (0, 1), "thomas": (0, 1)}
#: The corners of a box as (x, y, z) bits: the high or low side of each axis.
_CORNERS = [np.array([sx, sy, sz], dtype=bool) for sx in (0, 1) for sy in (0, 1) for sz in (0, 1)]
PARTICLE = (232, 234, 242)
SPRING = (90, 200, 140)
LINK = (150, 170, 215)
SLACK = (95, 102, 125)


def _camera(up: np.ndarray) -> np.ndarray:
    """Rows: screen right, screen up, towards the eye; ``up`` (a unit vector) drawn upwards,
    seen from a little above, from the front right."""
    k = int(np.argmax(np.abs(up)))
    e1, e2 = np.eye(3)[(k + 1) % 3], np.eye(3)[(k + 2) % 3]
    eye = e2 + 0.85 * e1 + 0.3 * up
    eye /= np.linalg.norm(eye)
    right = np.cross(up, eye)
    right /= np.linalg.norm(right)
    return np.array([right, np.cross(eye, right), eye])


def _end(entry: dict[str, Any], dim: int) -> tuple[int | None, np.ndarray | None]:
    """The second end of a spring or constraint: particle ``j``, or the point ``anchor``."""
    if "j" in entry:
        return int(entry["j"]), None
    anchor = entry.get("anchor", entry.get("point"))
    return None, (np.array(anchor, dtype=float) if anchor is not None else np.zeros(dim))


def _box_half(shape: dict[str, Any]) -> np.ndarray:
    """Half extents of a body shape's bounding box in its body frame, m (cylinders and
    capsules along z)."""
    kind = shape.get("kind")
    if kind == "box":
        return np.array(shape["half_extents"], dtype=float)
    if kind == "sphere":
        return np.full(3, float(shape["radius"]))
    if kind in ("cylinder", "capsule"):
        r, h = float(shape["radius"]), float(shape["height"])
        return np.array([r, r, h / 2 + (r if kind == "capsule" else 0.0)])
    v = np.abs(np.array(shape.get("vertices", [[0.1, 0.1, 0.1]]), dtype=float))
    return v.max(axis=0)


class SceneDemo(Demo):
    """The world a scene file describes, drawn generically; ``r`` reloads the file."""

    name = "scene"
    draggable = True
    mouse = "move a particle (a ball: pull it by its velocity); the drift restarts on release"
    reset_doc = "reload the file (keeps method, dt, loop)"

    def __init__(self, path: str) -> None:
        self.path = str(path)
        self.reload_error: str | None = None
        self._fitted_text: str | None = None
        self._template = self._load()  # ValueError naming the file for a bad one
        self.dt = self._template.dt
        self.dt_range = (self.dt / 64.0, self.dt * 16.0)
        self.methods = (self._template.method,)

    # The file -------------------------------------------------------------------------------

    def _load(self) -> physstep.World:
        """Loads the file (ValueError, the loader's message, for a bad one) and reads what
        the World does not expose from it; refits the view when the text changed."""
        world = physstep.load_scene(self.path)
        text = Path(self.path).read_text(encoding="utf-8")
        if text != self._fitted_text:
            doc = tomllib.loads(text)
            first = text.splitlines()[0] if text else ""
            self.title = first.lstrip("#").strip() if first.startswith("#") else Path(self.path).name
            self.dim = int(doc["dimension"])
            self.loop = str(doc.get("loop", {}).get("mode", "accumulator"))
            self.until = float(doc.get("until", FIT_TIME))
            self.springs = [(int(s["i"]), *_end(s, self.dim)) for s in doc.get("springs", [])]
            self.links: list[tuple[int, int | None, np.ndarray | None, bool]] = []
            self.planes: list[tuple[np.ndarray, float]] = []
            self.pins: list[np.ndarray] = []
            for c in doc.get("constraints", []) + [f for f in doc.get("forces", []) if f["kind"] == "rod"]:
                if c["kind"] == "plane":
                    self.planes.append((np.array(c["normal"], dtype=float), float(c["offset"])))
                elif c["kind"] == "pin":
                    self.pins.append(np.array(c["point"], dtype=float))
                else:  # distance, rope, limit, rod: a line; a rope or limit is slack-coloured
                    self.links.append((int(c["i"]), *_end(c, self.dim), c["kind"] in ("distance", "rod")))
            self.static = [
                k
                for k, p in enumerate(doc.get("particles", []))
                if p.get("static") or p.get("mass") == math.inf
            ]
            self.body_halves = [_box_half(b.get("shape", {})) for b in doc.get("bodies", [])]
            self.pivots = [b.get("pivot") for b in doc.get("bodies", [])]
            self.solids = scene_solids.read(doc)
            self.flow = str(doc["flow"]["kind"]) if "flow" in doc else None
            self.no_energy = "none (a flow)" if self.flow is not None else "unknown"
            gravity = [f["g"] for f in doc.get("forces", []) if f["kind"] == "gravity"]
            up = -np.array(gravity[0], dtype=float) if gravity and self.dim == 3 else np.zeros(3)
            if not np.any(up):
                up = (
                    np.array([0.0, 0.0, 1.0])
                    if self.body_halves and not self.solids
                    else np.array([0.0, 1.0, 0.0])
                )
            self.camera = _camera(up / np.linalg.norm(up))
            self._fit(world)
            self._fitted_text = text
        return world

    def world(self, method: str, dt: float) -> physstep.World:
        """The file reloaded (``r``), under ``method`` at ``dt``; a file that no longer loads
        keeps the last good one (the HUD says why)."""
        try:
            w = self._load()
            self._template, self.reload_error = w, None
        except (ValueError, OSError) as e:
            self.reload_error = " ".join(str(e).split())
        w = copy.copy(self._template)
        self.bounds = self.fitted
        try:
            w.method, w.dt = method, dt
        except ValueError:
            pass
        return w

    def applies(self, info: physstep.MethodInfo) -> bool:
        if self.flow is not None:
            return not info.split
        if self.body_halves:
            return not info.vector_positions
        return True

    # Where things are drawn ------------------------------------------------------------------

    def plane(self, p: Any) -> tuple[float, float]:
        """The drawing-plane coordinates of world point ``p``."""
        if self.flow is not None:
            a, b = FLOW_AXES.get(self.flow, (0, 1))
            return float(p[a]), float(p[b])
        if self.dim == 3:
            c = self.camera[:2] @ np.asarray(p, dtype=float)
            return float(c[0]), float(c[1])
        return float(p[0]), float(p[1]) if self.dim == 2 else 0.0

    def _points(self, w: physstep.World) -> list[tuple[float, float]]:
        """Plane points the view must hold for world ``w``'s present state."""
        if self.flow is not None:
            return [self.plane(w.positions[0])]
        pts = [self.plane(p) for p in np.array(w.positions)]
        radii = w.radii if len(w) else np.zeros(0)
        for p, r in zip(np.array(w.positions), radii, strict=False):
            if r > 0:
                q = self.plane(p)
                pts += [(q[0] - r, q[1] - r), (q[0] + r, q[1] + r)]
        if w.body_count:
            reach = float(max(np.linalg.norm(h) for h in self.body_halves))
            for c in np.array(w.body_positions()):
                for d in np.vstack([np.eye(3), -np.eye(3)]):
                    pts.append(self.plane(c + reach * 1.2 * d))
        if w.solid_count:
            # The dynamic solids (a static ground 200 m wide would shrink the rest to dots),
            # or the static ones where nothing moves.
            moving = [k for k, s in enumerate(self.solids) if s.dynamic] or range(len(self.solids))
            centres = np.array(w.solid_positions())
            for k in moving:
                r = scene_solids.reach(self.solids[k].shape)
                if r is not None and k < len(centres):
                    # Room around each (a lone box on a ramp shows the ramp, not only itself).
                    for d in np.vstack([np.eye(self.dim), -np.eye(self.dim)]):
                        pts.append(self.plane(centres[k] + 3 * r * d))
        return pts

    def _fit(self, world: physstep.World) -> None:
        """Fits the view to the anchors, walls and where a copy of ``world`` goes."""
        pts = self._points(world)
        for _, _, a in self.springs:
            if a is not None:
                pts.append(self.plane(a))
        pts += [self.plane(a) for _, _, a, _ in self.links if a is not None]
        pts += [self.plane(p) for p in self.pins]
        walls = world.walls if len(world) else None
        if walls is not None:  # every corner: in 3D the box's outline is their projection
            lo, hi = np.array(walls[0], dtype=float), np.array(walls[1], dtype=float)
            pts += [self.plane(np.where(bits[: self.dim], hi, lo)) for bits in _CORNERS]
        w = copy.copy(world)
        cap = max(FIT_STEPS, FIT_WORK // max(1, len(w) + w.body_count + w.solid_count))
        if physstep.method(w.method).implicit:
            cap = FIT_STEPS_IMPLICIT
        n = min(cap, math.ceil(min(FIT_TIME, self.until) / w.dt))
        chunk = max(1, n // 80)
        for _ in range(0, n, chunk):
            try:
                w.step(chunk)
            except physstep.StepError:
                break
            pts += self._points(w)
        a = np.array([p for p in pts if math.isfinite(p[0]) and math.isfinite(p[1])] or [(0.0, 0.0)])
        lo, hi = a.min(axis=0), a.max(axis=0)
        size = np.maximum(hi - lo, 1e-3 * max(1.0, float(np.abs(a).max())))
        self.fitted = ((lo + hi) / 2, size * 1.12)  # the centre and the extent, with a margin
        self.bounds = self.fitted

    def _follow(self, w: physstep.World) -> None:
        """Widens the view (never narrows it) to hold what has left it, up to GROW_MAX times
        the fitted extent: a box falling past the file's ``until``, an orbit spiralling out."""
        a = np.array([p for p in self._points(w) if math.isfinite(p[0]) and math.isfinite(p[1])])
        if not len(a):
            return
        (c, size), limit = self.bounds, self.fitted[1] * GROW_MAX
        lo, hi = np.minimum(a.min(axis=0), c - size / 2), np.maximum(a.max(axis=0), c + size / 2)
        if np.all(hi - lo <= size * (1 + 1e-9)) or np.any(size >= limit):
            return
        grown = np.minimum((hi - lo) * 1.12, limit)
        self.bounds = ((lo + hi) / 2, grown)

    def area(self, rect: pygame.Rect) -> pygame.Rect:
        """The part of the panel the scene is drawn in (room for the captions)."""
        return pygame.Rect(rect.x + 10, rect.y + 30, rect.width - 20, rect.height - 58)

    def scale(self, rect: pygame.Rect) -> float:
        r, size = self.area(rect), self.bounds[1]
        return min(r.width / size[0], r.height / size[1])

    def to_screen(self, rect: pygame.Rect, p: Any) -> tuple[int, int]:
        return self._screen(rect, self.plane(p))

    def _screen(self, rect: pygame.Rect, q: tuple[float, float]) -> tuple[int, int]:
        px, py = self._pixel(rect, q)
        return (int(base._clip(px)), int(base._clip(py)))

    def _pixel(self, rect: pygame.Rect, q: tuple[float, float]) -> tuple[float, float]:
        """Plane point ``q`` in pixels, unclipped."""
        s, c, r = self.scale(rect), self.bounds[0], self.area(rect)
        return r.centerx + (q[0] - c[0]) * s, r.centery - (q[1] - c[1]) * s

    def to_world(self, rect: pygame.Rect, pos: tuple[int, int], dim: int) -> np.ndarray:
        s, c, r = self.scale(rect), self.bounds[0], self.area(rect)
        return np.array([c[0] + (pos[0] - r.centerx) / s, c[1] - (pos[1] - r.centery) / s])

    def hold(self, world: physstep.World, i: int, rect: pygame.Rect, pos: tuple[int, int]) -> bool:
        """A ball (2D) is pulled by its velocity, as in ``balls``; another particle is put
        under the pointer at rest (in 3D at its depth)."""
        x, v = np.array(world.positions), np.array(world.velocities)
        q = self.to_world(rect, pos, 2)
        if self.dim == 2 and world.radii[i] > 0:
            want = (q - x[i]) / PULL_TIME
            speed = float(np.hypot(*want))
            v[i] = want if speed <= PULL_SPEED else want * (PULL_SPEED / speed)
            world.velocities = v
            return False
        if self.dim == 3:
            x[i] = self.camera.T @ np.array([q[0], q[1], float(self.camera[2] @ x[i])])
        else:
            x[i] = q[: self.dim]
        v[i] = 0.0
        world.positions, world.velocities = x, v
        return True

    def pick(self, rect: pygame.Rect, x: np.ndarray, pos: tuple[int, int]) -> int | None:
        return None if self.flow is not None else super().pick(rect, x, pos)

    # Drawing --------------------------------------------------------------------------------

    def _movers(self, panel: Panel, x: np.ndarray) -> list[tuple[float, float]]:
        """The plane points whose trails are drawn (none when there are too many)."""
        w = panel.world
        if self.flow is not None:
            return [self.plane(x[0])]
        if self.dim == 1:
            return []
        if (self.springs or self.links) and len(x):  # a connected structure: its last particle
            return [self.plane(x[-1])]
        pts = [self.plane(p) for k, p in enumerate(x) if k not in self.static]
        pts += [self.plane(c) for c in np.array(w.body_positions())] if w.body_count else []
        if w.solid_count:
            centres = np.array(w.solid_positions())
            pts += [
                self.plane(centres[k]) for k, s in enumerate(self.solids) if s.dynamic and k < len(centres)
            ]
        return pts if len(pts) <= TRAIL_MAX else []

    def record(self, panel: Panel, x: np.ndarray) -> None:
        if not panel.error:
            self._follow(panel.world)
        point = tuple(c for q in self._movers(panel, x) for c in q)
        if point and (not panel.trail or panel.trail[-1] != point):
            panel.trail.append(point)

    def hud(self, panel: Panel) -> list[tuple[str, str, tuple[int, int, int]]]:
        w = panel.world
        name = Path(self.path).name
        rows = [("file", name if len(name) <= 22 else name[:21] + "~", base.TEXT)]
        if self.flow is not None:
            rows.append(("flow", self.flow, base.TEXT))
        elif len(w):
            balls = int(np.count_nonzero(w.radii > 0))
            rows.append(
                (
                    "particles",
                    f"{len(w)}" + (f" ({balls} ball{'s' if balls > 1 else ''})" if balls else ""),
                    base.TEXT,
                )
            )
        for n, word in (
            (w.body_count, "bodies"),
            (len(self.springs), "springs"),
            (w.constraint_count, "constraints"),
        ):
            if n:
                rows.append((word, f"{n}", base.TEXT))
        rows += scene_solids.hud_rows(w)
        if w.constraint_count:
            rows.append(("violation", f"{w.constraint_violation():.2e} m (max)", base.TEXT))
        if len(w) and self.flow is None and np.any(w.radii > 0):
            rows.append(("collisions", f"{w.collisions['count']}", base.TEXT))
        if self.reload_error:
            rows.append(("reload", "failed: the last good file runs", base.ERROR))
        return rows

    def draw(self, surf: pygame.Surface, rect: pygame.Rect, panel: Panel, x: np.ndarray) -> None:
        w = panel.world
        f = base.font(19)
        if self.flow is not None:
            self._draw_flow(surf, rect, panel, x)
        else:
            self._draw_frame(surf, rect, w)
            self._draw_trails(surf, rect, panel)
            self._draw_links(surf, rect, x)
            self._draw_bodies(surf, rect, panel)
            self._draw_solids(surf, rect, panel)
            self._draw_particles(surf, rect, w, x)
        title = self.title
        while len(title) > 4 and f.size(title)[0] > rect.width - 20:
            title = title[: len(title) - 4] + "..."
        base.text(surf, f, title, (rect.x + 10, rect.y + 8), base.DIM)
        if self.flow is not None:
            a, b = ("xyz"[k] for k in FLOW_AXES.get(self.flow, (0, 1)))
            y = x[0]
            note = f"x {y[0]:+.2f}  y {y[1]:+.2f}  z {y[2]:+.2f}   (drawn: {a} across, {b} up)"
        elif self.dim == 3:
            note = "orthographic view, up against gravity; axes at the origin: x red, y green, z blue"
        else:
            note = (
                "x across"
                + (", y up" if self.dim == 2 else " (1D)")
                + f"; {1 / self.scale(rect):.3g} m a pixel"
            )
        if self.reload_error:
            note = f"reload failed: {self.reload_error}"
        base.text(
            surf,
            f,
            note,
            (rect.x + 10, rect.bottom - 6),
            base.ERROR if self.reload_error else base.DIM,
            "bottomleft",
        )

    def _draw_flow(self, surf: pygame.Surface, rect: pygame.Rect, panel: Panel, x: np.ndarray) -> None:
        pts = [self._screen(rect, (p[0], p[1])) for p in panel.trail]
        base.draw_trail(surf, pts, panel.colour)
        pygame.draw.circle(surf, base.ACCENT, self.to_screen(rect, x[0]), 6)

    def _draw_frame(self, surf: pygame.Surface, rect: pygame.Rect, w: physstep.World) -> None:
        """The axis (1D), the planes (2D), the world axes (3D) and the walls."""
        r = self.area(rect)
        if self.dim == 1:
            y = self._screen(rect, (0.0, 0.0))[1]
            pygame.draw.line(surf, base.GRID, (r.x, y), (r.right, y), 1)
        if self.dim == 2:
            for n, off in self.planes:
                foot, along = n * off / float(n @ n), np.array([-n[1], n[0]]) * 1e4
                a, b = self.to_screen(rect, foot - along), self.to_screen(rect, foot + along)
                pygame.draw.line(surf, base.DIM, a, b, 2)
        if self.dim == 3:
            o = self.to_screen(rect, np.zeros(3))
            length = 0.15 * float(max(self.bounds[1]))
            for k in range(3):
                pygame.draw.line(surf, AXIS_COLOURS[k], o, self.to_screen(rect, np.eye(3)[k] * length), 2)
        walls = w.walls if len(w) else None
        if walls is not None:
            lo, hi = np.array(walls[0], dtype=float), np.array(walls[1], dtype=float)
            if self.dim == 2:
                a, b = self.to_screen(rect, lo), self.to_screen(rect, hi)
                box = pygame.Rect(a[0], b[1], b[0] - a[0], a[1] - b[1])
                pygame.draw.rect(surf, base.BACKGROUND, box)
                pygame.draw.rect(surf, base.DIM, box.inflate(4, 4), 2)
            else:
                corners = [np.where(bits[: self.dim], hi, lo) for bits in _CORNERS]
                self._wire(surf, rect, corners, base.DIM)

    def _wire(
        self, surf: pygame.Surface, rect: pygame.Rect, corners: list[Any], colour: tuple[int, int, int]
    ) -> None:
        """The 12 edges of a box given its 8 corners (each index bit one axis: an edge joins
        two corners one bit apart)."""
        s = [self.to_screen(rect, c) for c in corners]
        for a in range(8):
            for bit in (1, 2, 4):
                if not a & bit:
                    pygame.draw.aaline(surf, colour, s[a], s[a | bit])

    def _draw_trails(self, surf: pygame.Surface, rect: pygame.Rect, panel: Panel) -> None:
        if not panel.trail:
            return
        hist = list(panel.trail)[-1500:]
        n = len(hist[-1]) // 2
        for k in range(n):
            colour = base.PANEL_COLOURS[k % len(base.PANEL_COLOURS)] if n > 1 else base.TRAIL
            pts = [self._screen(rect, (h[2 * k], h[2 * k + 1])) for h in hist if len(h) == 2 * n]
            base.draw_trail(surf, pts, (int(colour[0] * 0.7), int(colour[1] * 0.7), int(colour[2] * 0.7)))

    def _at(self, rect: pygame.Rect, x: np.ndarray, i: int | None, a: np.ndarray | None) -> tuple[int, int]:
        return self.to_screen(rect, x[i] if i is not None else a)

    def _draw_links(self, surf: pygame.Surface, rect: pygame.Rect, x: np.ndarray) -> None:
        """Constraints as lines (ropes and limits dim), springs as zigzags (lines when many),
        anchors and pins as small squares."""
        anchors = []
        for i, j, a, rigid in self.links:
            pygame.draw.aaline(
                surf, LINK if rigid else SLACK, self._at(rect, x, i, None), self._at(rect, x, j, a)
            )
            if a is not None:
                anchors.append(self.to_screen(rect, a))
        many = len(self.springs) > 40
        for i, j, a in self.springs:
            p, q = self._at(rect, x, i, None), self._at(rect, x, j, a)
            if many:
                pygame.draw.aaline(surf, SPRING, p, q)
            else:
                pygame.draw.aalines(surf, SPRING, False, _zigzag(p, q))
            if a is not None:
                anchors.append(self.to_screen(rect, a))
        anchors += [self.to_screen(rect, p) for p in self.pins]
        for c in anchors:
            pygame.draw.rect(surf, base.ACCENT, pygame.Rect(c[0] - 5, c[1] - 5, 10, 10), 2)

    def _draw_bodies(self, surf: pygame.Surface, rect: pygame.Rect, panel: Panel) -> None:
        """A body's oriented bounding box, its axes (x red, y green, z blue) and its pivot."""
        w = panel.world
        if not w.body_count:
            return
        qs = w.interpolated_body_orientations() if panel.interpolate else w.body_orientations()
        for c, q, half, pivot in zip(
            np.array(w.body_positions()), qs, self.body_halves, self.pivots, strict=False
        ):
            r = rotation(q)
            corners = [c + r @ (half * [sx, sy, sz]) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
            self._wire(surf, rect, corners, base.BODY)
            centre = self.to_screen(rect, c)
            for k in range(3):
                end = self.to_screen(rect, c + r[:, k] * half[k] * 1.4)
                pygame.draw.line(surf, AXIS_COLOURS[k], centre, end, 3)
            pygame.draw.circle(surf, base.TEXT, centre, 4)
            if pivot is not None:
                p = self.to_screen(rect, c + r @ np.array(pivot, dtype=float))
                pygame.draw.rect(surf, base.ACCENT, pygame.Rect(p[0] - 5, p[1] - 5, 10, 10), 2)

    def _draw_solids(self, surf: pygame.Surface, rect: pygame.Rect, panel: Panel) -> None:
        """The solids, their shapes read from the file."""
        if not panel.world.solid_count:
            return
        poses = base.solid_poses(panel)
        scale, extent = self.scale(rect), float(max(self.bounds[1]))
        screen = lambda p: self.to_screen(rect, p)  # noqa: E731
        if self.dim == 2:
            pixel = lambda p: self._pixel(rect, self.plane(p))  # noqa: E731
            scene_solids.draw_2d(surf, screen, pixel, self.area(rect), scale, self.solids, poses, extent)
        else:
            wire = lambda corners, colour: self._wire(surf, rect, corners, colour)  # noqa: E731
            scene_solids.draw_3d(surf, screen, scale, wire, self.solids, poses, extent)

    def _draw_particles(
        self, surf: pygame.Surface, rect: pygame.Rect, w: physstep.World, x: np.ndarray
    ) -> None:
        if not len(x):
            return
        s = self.scale(rect)
        radii = w.radii
        dot = 3 if len(x) > 60 else 5
        static = set(self.static)
        for k, p in enumerate(x):
            c = self.to_screen(rect, p)
            if radii[k] > 0:
                rad = max(2, round(radii[k] * s))
                pygame.draw.circle(surf, (70, 130, 230), c, rad)
                pygame.draw.circle(surf, (150, 190, 255), c, rad, 1)
            elif k in static:
                pygame.draw.rect(surf, base.DIM, pygame.Rect(c[0] - dot, c[1] - dot, 2 * dot, 2 * dot))
            else:
                pygame.draw.circle(surf, PARTICLE, c, dot)


def _zigzag(
    p: tuple[int, int], q: tuple[int, int], coils: int = 8, width: float = 5.0
) -> list[tuple[int, int]]:
    """A spring drawn from ``p`` to ``q``: straight ends, ``coils`` zigzags between."""
    dx, dy = q[0] - p[0], q[1] - p[1]
    length = math.hypot(dx, dy)
    if length < 1:
        return [p, q]
    nx, ny = -dy / length * width, dx / length * width
    pts = [p, (int(p[0] + dx * 0.1), int(p[1] + dy * 0.1))]
    for k in range(1, 2 * coils):
        t = 0.1 + 0.8 * k / (2 * coils)
        side = 1 if k % 2 else -1
        pts.append((int(p[0] + dx * t + side * nx), int(p[1] + dy * t + side * ny)))
    pts += [(int(p[0] + dx * 0.9), int(p[1] + dy * 0.9)), q]
    return pts
