"""What every demo shares: its panels (a World each), their settings, and the drawing helpers.

A demo is a class with a name, a default ``dt`` and the methods of its panels (one panel, or
several side by side in ``compare``). It builds a fresh :class:`physstep.World` for a method,
a dt and a loop variant (:meth:`Demo.world`) and draws one panel into a rectangle
(:meth:`Demo.draw`); :mod:`physstep.demos.app` runs the game loop, the keys and the HUD.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pygame

import physstep

#: The loop variants the ``l`` key cycles: (name, substeps), as ``World(loop=..., substeps=...)``.
LOOPS: tuple[tuple[str, int], ...] = (
    ("accumulator", 1),
    ("step-per-frame", 1),
    ("steps-per-frame", 4),
    ("frame-time", 1),
    ("consume-frame", 1),
)

BACKGROUND = (18, 20, 26)
PANEL = (26, 29, 38)
GRID = (52, 57, 72)
TEXT = (222, 226, 235)
DIM = (140, 147, 165)
ACCENT = (255, 196, 64)
ERROR = (255, 105, 97)
BODY = (110, 190, 255)
TRAIL = (90, 200, 140)
#: Distinct colours of the panels of a side-by-side demo.
PANEL_COLOURS = ((255, 120, 90), (90, 200, 140), (110, 170, 255), (230, 140, 255))

#: Points kept in a trail.
TRAIL_POINTS = 3000


@dataclass(frozen=True)
class Key:
    """A key binding: the action, the pygame keys, how the help shows them, what it does.
    ``shift``: True only with shift held, False only without it, None either way."""

    action: str
    keys: tuple[int, ...]
    label: str
    doc: str
    shift: bool | None = None


def relooped(world: physstep.World, loop: str, substeps: int) -> physstep.World:
    """``world`` under another loop variant, its state (integrator memory and clock
    included) carried over bitwise: rebuilt from its parts and snapshot, as a pickle is."""
    rebuild, (parts, snapshot) = world.__reduce__()
    parts = dict(parts)
    parts["loop"], parts["substeps"] = loop, substeps
    return rebuild(parts, snapshot)


@dataclass
class Panel:
    """One World on screen: its method, the energy it started from, what it has drawn."""

    world: physstep.World
    info: physstep.MethodInfo
    e0: float | None
    error: str | None = None
    steps: int = 0
    colour: tuple[int, int, int] = TRAIL
    #: Draw between the last two states by ``alpha`` (off while paused or single-stepping).
    interpolate: bool = True
    trail: deque[tuple[float, ...]] = field(default_factory=lambda: deque(maxlen=TRAIL_POINTS))
    #: Frame time handed to ``advance``, the simulated time it advanced, and the time the
    #: clock clamped or dropped (its caps), s: how far the world fell behind real time.
    handed: float = 0.0
    simulated: float = 0.0
    lost: float = 0.0
    drift: deque[float] = field(default_factory=lambda: deque(maxlen=600))
    #: Wall time per step of the latest frames that stepped, s (what the simulation costs).
    cost: deque[float] = field(default_factory=lambda: deque(maxlen=30))

    def step_cost(self) -> float | None:
        """Wall time a step took, s: the median over the latest frames that stepped (None
        before one has)."""
        if not self.cost:
            return None
        return sorted(self.cost)[len(self.cost) // 2]

    def energy(self) -> float | None:
        """The world's energy, J, or None (a flow has none; a diverged world tells no more)."""
        if self.error:
            return None
        try:
            return self.world.energy()
        except physstep.StepError as e:
            self.error = str(e)
            return None

    def restart_drift(self) -> None:
        """Measures the drift from the current energy on (after a change by hand: a new
        method, a drag, a kick, a new world)."""
        self.e0 = self.energy()
        self.drift.clear()

    def drift_now(self) -> float | None:
        """Relative energy drift (E - E0) / |E0| (absolute where |E0| < 1e-12 J: zero up to
        rounding, as a chain at rest length starts), or None."""
        e = self.energy()
        if e is None or self.e0 is None:
            return None
        return (e - self.e0) / (abs(self.e0) if abs(self.e0) >= 1e-12 else 1.0)


def solid_poses(panel: Panel) -> tuple[np.ndarray, np.ndarray]:
    """The solids' positions and orientations to draw: between the last two steps by the
    loop's ``alpha`` (render interpolation) while it runs, as they are otherwise (paused,
    single steps)."""
    w = panel.world
    if panel.interpolate:
        return np.asarray(w.interpolated_solid_positions()), np.asarray(w.interpolated_solid_orientations())
    return np.asarray(w.solid_positions()), np.asarray(w.solid_orientations())


def box_corners(centre: Any, angle: float, hx: float, hy: float) -> np.ndarray:
    """The four corners (4, 2) of a box of half extents ``hx``, ``hy`` at ``centre`` turned by
    ``angle``, in order round it."""
    c, s = math.cos(angle), math.sin(angle)
    local = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]) * [hx, hy]
    return np.asarray(centre) + local @ np.array([[c, s], [-s, c]])


def start_afresh(
    panels: list[Panel],
    build: Any,
    method: str | None = None,
    dt: float | None = None,
) -> None:
    """Each panel started afresh on the world ``build(method, dt)`` makes, under the panel's
    game-loop variant; ``method`` and ``dt`` are each panel's own unless given."""
    for k, p in enumerate(panels):
        m, h = method or p.world.method, dt or p.world.dt
        parts = p.world.__reduce__()[1][0]
        w = relooped(build(m, h), parts["loop"], parts["substeps"])
        panels[k] = Panel(w, physstep.method(m), None, colour=p.colour)
        panels[k].e0 = panels[k].energy()


class Demo:
    """A demo's description; subclasses set the attributes and fill :meth:`world` and :meth:`draw`."""

    name = ""
    #: Default fixed step, s.
    dt = 0.01
    #: Slowest and fastest dt the ``[`` and ``]`` keys reach, s.
    dt_range = (1e-4, 1.0)
    #: The method of each panel, in order (one panel unless the demo compares).
    methods: tuple[str, ...] = ("symplectic-euler",)
    #: What the HUD says when the world's energy is unknown.
    no_energy = "unknown"
    #: The loop variant (a :data:`LOOPS` name) the demo starts in.
    loop = "accumulator"
    #: What the help says ``r`` does, where the demo's reset differs from the common one.
    reset_doc: str | None = None
    #: Whether the mouse drags a particle.
    draggable = False
    #: What the mouse does in this demo, for the help (when ``draggable``).
    mouse = "move a particle; it is held at rest under the pointer, the drift restarts on release"
    #: The demo's own keys (the help lists them after the common ones; :meth:`act` does them).
    keys: tuple[Key, ...] = ()

    def act(self, panels: list[Panel], action: str) -> None:
        """Does the demo's own key action ``action`` (one of :attr:`keys`) on ``panels``."""
        raise ValueError(f"invalid action '{action}' for demo {self.name}")

    def hud(self, panel: Panel) -> list[tuple[str, str, tuple[int, int, int]]]:
        """The demo's own HUD rows for ``panel``: (label, value, colour)."""
        return []

    def hold(self, world: physstep.World, i: int, rect: pygame.Rect, pos: tuple[int, int]) -> bool:
        """Drags particle ``i`` of ``world`` (drawn in ``rect``) to screen pixel ``pos``: by
        default puts it there at rest. Returns whether it moved it (the frame is then drawn
        from the current positions, not interpolated)."""
        x, v = np.array(world.positions), np.array(world.velocities)
        x[i] = self.to_world(rect, pos, world.dim)
        v[i] = 0.0
        world.positions, world.velocities = x, v
        return True

    def applies(self, info: physstep.MethodInfo) -> bool:
        """Whether method ``info`` applies to this demo's world (the ``m`` key skips others)."""
        return True

    def world(self, method: str, dt: float) -> physstep.World:
        """A fresh World of this demo under ``method`` at step ``dt`` (accumulator loop)."""
        raise NotImplementedError

    def caption(self, panel: Panel) -> tuple[str, str]:
        """The title and the line under it that head ``panel`` where several are shown: its
        method, its order and whether it is symplectic, unless the panels differ in more."""
        info = panel.info
        return info.name, f"order {info.order}, {'symplectic' if info.symplectic else 'not symplectic'}"

    def panel_world(self, k: int, method: str, dt: float) -> physstep.World:
        """The fresh World of panel ``k`` (from 0): :meth:`world`, unless the panels differ in
        more than their method (the solvers demo: each panel its own contact solver)."""
        return self.world(method, dt)

    def record(self, panel: Panel, x: np.ndarray) -> None:
        """Keeps what the trail of ``panel`` needs from this frame's positions ``x``."""

    def draw(self, surf: pygame.Surface, rect: pygame.Rect, panel: Panel, x: np.ndarray) -> None:
        """Draws ``panel`` into ``rect``; ``x`` are the positions to draw (interpolated)."""
        raise NotImplementedError

    # Mapping between world and screen, for the 2D particle demos (``view`` is centre and half width).
    view: tuple[float, float, float] = (0.0, 0.0, 1.0)

    def scale(self, rect: pygame.Rect) -> float:
        """Pixels per metre in ``rect``."""
        return min(rect.width, rect.height) / (2.0 * self.view[2])

    def to_screen(self, rect: pygame.Rect, p: Any) -> tuple[int, int]:
        """Screen pixel of world point ``p`` (1D points lie on the panel's middle line)."""
        s = self.scale(rect)
        px = rect.centerx + (float(p[0]) - self.view[0]) * s
        py = rect.centery - ((float(p[1]) if len(p) > 1 else self.view[1]) - self.view[1]) * s
        return (int(_clip(px)), int(_clip(py)))

    def to_world(self, rect: pygame.Rect, pos: tuple[int, int], dim: int) -> np.ndarray:
        """World point under screen pixel ``pos``, ``dim`` coordinates."""
        s = self.scale(rect)
        x = self.view[0] + (pos[0] - rect.centerx) / s
        y = self.view[1] - (pos[1] - rect.centery) / s
        return np.array([x, y][:dim])

    def pick(self, rect: pygame.Rect, x: np.ndarray, pos: tuple[int, int]) -> int | None:
        """The particle drawn within 20 px of ``pos``, or None."""
        best, best_d = None, 20.0
        for i, p in enumerate(x):
            sx, sy = self.to_screen(rect, p)
            d = math.hypot(sx - pos[0], sy - pos[1])
            if d <= best_d:
                best, best_d = i, d
        return best


_FONTS: dict[int, pygame.font.Font] = {}


#: The constraint sweeps a demo's keys can set (doubled and halved within this range).
SWEEPS = (1, 256)


def sweeps(current: int, action: str, panels: list[Panel]) -> int:
    """The constraint sweeps after an ``iterations_up`` / ``iterations_down`` action (doubled
    or halved within :data:`SWEEPS`), set on every panel that still runs."""
    n = current * 2 if action == "iterations_up" else current // 2
    n = min(SWEEPS[1], max(SWEEPS[0], n))
    for p in panels:
        if not p.error:
            p.world.constraint_iterations = n
    return n


def sweep_rows(world: physstep.World) -> list[tuple[str, str, tuple[int, int, int]]]:
    """The HUD rows of a world with constraints: its sweeps a step (the keys of
    :func:`sweeps`) and its largest constraint violation."""
    return [
        ("sweeps", f"{world.constraint_iterations} a step (i, shift+i)", TEXT),
        ("violation", f"{world.constraint_violation():.2e} m (max)", TEXT),
    ]


def contact_solver_names() -> list[str]:
    """The contact solvers' names, in registry order (:func:`physstep.contact_solvers`)."""
    return list(physstep.contact_solvers())


def next_contact_solver(current: str, panels: list[Panel]) -> str:
    """The contact solver after ``current`` in the registry (the first after the last; the
    same one while there is one), set on every panel that still runs; returns its name."""
    names = contact_solver_names()
    k = names.index(current) if current in names else -1
    name = names[(k + 1) % len(names)]
    for p in panels:
        if not p.error:
            p.world.contact_solver = name
    return name


def font(size: int) -> pygame.font.Font:
    """pygame's default font at ``size`` px, loaded once per run (:func:`forget_fonts`)."""
    if size not in _FONTS:
        _FONTS[size] = pygame.font.Font(None, size)
    return _FONTS[size]


def forget_fonts() -> None:
    """Drops the loaded fonts (pygame.font is shut down at the end of a run)."""
    _FONTS.clear()


def _clip(v: float) -> float:
    """A pixel coordinate pygame can draw (a run that spirals away is drawn at the edge)."""
    return max(-30000.0, min(30000.0, v)) if math.isfinite(v) else -30000.0


def draw_trail(surf: pygame.Surface, points: list[tuple[int, int]], colour: tuple[int, int, int]) -> None:
    """A trail fading from dim (oldest) to ``colour`` (newest), drawn in a few segments."""
    n = len(points)
    if n < 2:
        return
    chunks = 8
    for c in range(chunks):
        lo, hi = c * n // chunks, min(n, (c + 1) * n // chunks + 1)
        if hi - lo < 2:
            continue
        k = 0.4 + 0.6 * (c + 1) / chunks
        pygame.draw.aalines(surf, tuple(int(ch * k) for ch in colour), False, points[lo:hi])


def text(
    surf: pygame.Surface,
    font: pygame.font.Font,
    s: str,
    pos: tuple[int, int],
    colour: tuple[int, int, int] = TEXT,
    anchor: str = "topleft",
) -> pygame.Rect:
    """Draws ``s`` at ``pos`` (``anchor`` names the corner of its box); returns its box."""
    img = font.render(s, True, colour)
    box = img.get_rect(**{anchor: pos})
    surf.blit(img, box)
    return box
