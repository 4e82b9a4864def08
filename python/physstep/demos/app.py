"""The demo runner: the window, the game loop, the keys, the HUD and the help.

:func:`run` opens a window (or, headless, a surface of the dummy video driver), and each
frame hands the frame time to ``World.advance`` (the fixed-timestep loop of the notes) and
draws the positions interpolated by ``alpha``. The keys are one table, :data:`KEYS`, which the
handler, the help overlay and docs/demos.md follow.
"""

from __future__ import annotations

import math
import os
import sys
import time
import tomllib
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np
import pygame

import physstep
from physstep import _files as files
from physstep.demos import base, load
from physstep.demos.base import LOOPS, Demo, Key, Panel

__all__ = ["KEYS", "Key", "Runner", "run"]

#: Window size, px.
SIZE = (1000, 640)
#: Width of the HUD column on the left, px.
SIDEBAR = 300
#: The frame time of a headless run, s: fixed, so that a headless run is deterministic.
HEADLESS_FRAME_TIME = 1.0 / 60.0
#: Frames per second an interactive run aims at.
FPS = 60
#: SDL video drivers that open no window: an interactive run under one is refused.
NO_WINDOW_DRIVERS = ("dummy", "offscreen")


#: Every key binding, in the order the help lists them.
KEYS: tuple[Key, ...] = (
    Key("method_next", (pygame.K_m,), "m", "next method (the registry, in order)", shift=False),
    Key("method_prev", (pygame.K_m,), "shift+m", "previous method", shift=True),
    Key(
        "dt_up",
        (pygame.K_RIGHTBRACKET, pygame.K_EQUALS, pygame.K_PLUS, pygame.K_KP_PLUS),
        "] or +",
        "double dt",
    ),
    Key("dt_down", (pygame.K_LEFTBRACKET, pygame.K_MINUS, pygame.K_KP_MINUS), "[ or -", "halve dt"),
    Key("loop", (pygame.K_l,), "l", "next game-loop variant"),
    Key("pause", (pygame.K_SPACE, pygame.K_p), "space or p", "pause / run"),
    Key("step", (pygame.K_s, pygame.K_PERIOD), "s or .", "one step (pauses)"),
    Key("reset", (pygame.K_r,), "r", "reset (keeps method, dt, loop)"),
    Key("panel", (pygame.K_TAB,), "tab", "next panel (compare): the one m changes"),
    Key("help", (pygame.K_h, pygame.K_F1), "h or F1", "show / hide this help"),
    Key("quit", (pygame.K_ESCAPE, pygame.K_q), "esc or q", "quit"),
)


def _one_line(s: str) -> str:
    return " ".join(s.split())


class Runner:
    """One demo's state between frames: its panels, settings, and what the user holds."""

    def __init__(self, demo: Demo, method: str | None = None, dt: float | None = None) -> None:
        self.demo = demo
        self.methods = [m for m in physstep.methods() if demo.applies(m)]
        names = [m.name for m in self.methods]
        if method is not None and method not in names:
            physstep.method(method)  # an unknown name: ValueError listing the registry
            raise ValueError(
                f"invalid --method '{method}': does not apply to demo {demo.name}; "
                f"use one of: {', '.join(names)}"
            )
        self.panel_methods = list(demo.methods)
        if method is not None:
            self.panel_methods[0] = method
        lo, hi = demo.dt_range
        if dt is not None and not lo <= dt <= hi:  # the range the [ and ] keys keep to
            raise ValueError(f"invalid --dt '{dt:g}': must be from {lo:g} to {hi:.4g} s for demo {demo.name}")
        self.dt = float(demo.dt if dt is None else dt)
        self.loop = [name for name, _ in LOOPS].index(demo.loop) if demo.loop in dict(LOOPS) else 0
        self.paused = False
        self.help = False
        self.running = True
        self.focus = 0
        self.frames = 0
        self.frame_time = HEADLESS_FRAME_TIME
        self.fps: float | None = None
        self.drag: int | None = None
        self.drag_to: tuple[int, int] | None = None
        self.panels: list[Panel] = []
        self.rects: list[pygame.Rect] = []
        self.layout(pygame.Rect(SIDEBAR, 0, SIZE[0] - SIDEBAR, SIZE[1]))
        self.reset()

    # Settings -------------------------------------------------------------------------------

    def layout(self, area: pygame.Rect) -> None:
        """Panel rectangles in ``area``: one, or a grid of two columns."""
        n = len(self.panel_methods)
        cols = 1 if n == 1 else 2
        rows = math.ceil(n / cols)
        w, h = (area.width - 10) // cols, (area.height - 10) // rows
        self.rects = [
            pygame.Rect(area.x + 5 + (k % cols) * w + 5, area.y + 5 + (k // cols) * h + 5, w - 10, h - 10)
            for k in range(n)
        ]

    def _panel(self, method: str, colour: tuple[int, int, int], k: int) -> Panel:
        """A fresh panel ``k`` under ``method`` (the demo's world for that panel)."""
        world = self.demo.panel_world(k, method, self.dt)
        name, substeps = LOOPS[self.loop]
        if name != world.__reduce__()[1][0]["loop"]:  # a scene file's own loop is kept as it is
            world = base.relooped(world, name, substeps)
        panel = Panel(world, physstep.method(method), None, colour=colour)
        panel.e0 = panel.energy()
        return panel

    def reset(self) -> None:
        """Fresh worlds with the current methods, dt and loop variant."""
        colours = base.PANEL_COLOURS if len(self.panel_methods) > 1 else (base.TRAIL,)
        self.panels = [self._panel(m, colours[k % len(colours)], k) for k, m in enumerate(self.panel_methods)]
        self.drag = None
        for p in self.panels:
            self.demo.record(p, self._positions(p))

    def switch_method(self, step: int) -> None:
        """The focused panel's next (``step`` 1) or previous (-1) applicable method, live:
        the state carries over and the energy drift restarts from here."""
        names = [m.name for m in self.methods]
        p = self.panels[self.focus]
        k = names.index(p.info.name) if p.info.name in names else -1
        name = names[(k + step) % len(names)]
        self.panel_methods[self.focus] = name
        if p.error:  # a failed world starts again under the new method
            self.panels[self.focus] = self._panel(name, p.colour, self.focus)
            return
        p.world.method = name
        p.info = physstep.method(name)
        p.restart_drift()

    def change_dt(self, factor: float) -> None:
        """dt times ``factor`` within the demo's range, for every panel."""
        lo, hi = self.demo.dt_range
        self.dt = min(hi, max(lo, self.dt * factor))
        for p in self.panels:
            if not p.error:
                p.world.dt = self.dt

    def next_loop(self) -> None:
        """The next loop variant for every panel, the state carried over (rebuilt from its
        parts and snapshot, as a pickle is). A world that cannot be rebuilt so stops with the
        reason in one line; ``r`` restarts it."""
        self.loop = (self.loop + 1) % len(LOOPS)
        name, substeps = LOOPS[self.loop]
        for p in self.panels:
            if p.error:
                continue
            try:
                p.world = base.relooped(p.world, name, substeps)
            except ValueError as e:
                p.error = _one_line(f"cannot change the loop variant: {e}")

    def single_step(self) -> None:
        """Pauses and takes one fixed step in every panel."""
        self.paused = True
        for p in self.panels:
            p.steps = 0
            if p.error:
                continue
            try:
                wall = time.perf_counter()
                p.world.step(1)
                p.cost.append(time.perf_counter() - wall)
                p.steps = 1
            except physstep.StepError as e:
                p.error = _one_line(str(e))
            p.interpolate = False
            self._after_frame(p)

    # Events ---------------------------------------------------------------------------------

    def handle(self, event: pygame.event.Event) -> None:
        """Acts on one pygame event (a key of :data:`KEYS`, the mouse, closing the window)."""
        if event.type == pygame.QUIT:
            self.running = False
        elif event.type == pygame.KEYDOWN:
            shift = bool(event.mod & pygame.KMOD_SHIFT)
            for key in KEYS + self.demo.keys:
                if event.key in key.keys and key.shift in (None, shift):
                    self.act(key.action)
                    break
        elif event.type == pygame.MOUSEBUTTONDOWN and event.button == 1 and self.demo.draggable:
            p, rect = self.panels[self.focus], self.rects[self.focus]
            if not p.error:  # a demo of solids (no particles) may pick too: bridge drops one
                self.drag = self.demo.pick(rect, self._positions(p), event.pos)
                self.drag_to = event.pos
        elif event.type == pygame.MOUSEMOTION and self.drag is not None:
            self.drag_to = event.pos
        elif event.type == pygame.MOUSEBUTTONUP and event.button == 1 and self.drag is not None:
            self.drag = None
            p = self.panels[self.focus]
            p.restart_drift()

    def act(self, action: str) -> None:
        """Does what key action ``action`` (a :data:`KEYS` name) says."""
        if action == "method_next":
            self.switch_method(1)
        elif action == "method_prev":
            self.switch_method(-1)
        elif action == "dt_up":
            self.change_dt(2.0)
        elif action == "dt_down":
            self.change_dt(0.5)
        elif action == "loop":
            self.next_loop()
        elif action == "pause":
            self.paused = not self.paused
        elif action == "step":
            self.single_step()
        elif action == "reset":
            self.reset()
        elif action == "panel":
            self.focus = (self.focus + 1) % len(self.panels)
        elif action == "help":
            self.help = not self.help
        elif action == "quit":
            self.running = False
        elif action in (k.action for k in self.demo.keys):
            self.demo.act(self.panels, action)
            # A demo's key may give a panel a world of another method or dt (the cloth's
            # model key): the settings a reset and the HUD use follow the panels.
            for k, p in enumerate(self.panels):
                if not p.error:
                    self.panel_methods[k] = p.world.method
            if not self.panels[self.focus].error:
                self.dt = self.panels[self.focus].world.dt
        else:
            raise ValueError(f"invalid action '{action}': not one of {', '.join(k.action for k in KEYS)}")

    # The frame ------------------------------------------------------------------------------

    def _positions(self, p: Panel) -> np.ndarray:
        w = p.world
        return w.interpolated_positions() if p.interpolate else np.array(w.positions)

    def _hold(self, p: Panel) -> None:
        """Drags the dragged particle to the mouse, as the demo does it (:meth:`Demo.hold`)."""
        assert self.drag is not None and self.drag_to is not None
        if self.demo.hold(p.world, self.drag, self.rects[self.focus], self.drag_to):
            p.interpolate = False

    def _after_frame(self, p: Panel) -> None:
        self.demo.record(p, self._positions(p))
        d = p.drift_now()
        if d is not None and p.steps:
            p.drift.append(d)

    def update(self, frame_time: float) -> None:
        """One frame of the game loop: ``advance(frame_time)`` in every running panel."""
        self.frame_time = frame_time
        self.frames += 1
        for k, p in enumerate(self.panels):
            if self.paused or p.error:
                if self.paused and self.drag is not None and k == self.focus and not p.error:
                    self._hold(p)
                    self.demo.record(p, self._positions(p))
                p.steps = 0
                continue
            t0, (_, _, clamped, dropped) = p.world.time, p.world.clock_stats
            wall = time.perf_counter()
            try:
                p.steps = p.world.advance(frame_time)
            except physstep.StepError as e:
                p.error, p.steps = _one_line(str(e)), 0
                continue
            if p.steps:
                p.cost.append((time.perf_counter() - wall) / p.steps)
            _, _, clamped1, dropped1 = p.world.clock_stats
            p.handed += frame_time
            p.simulated += p.world.time - t0
            p.lost += (clamped1 - clamped) + (dropped1 - dropped)
            p.interpolate = True
            if self.drag is not None and k == self.focus:
                self._hold(p)
            self._after_frame(p)

    # Drawing --------------------------------------------------------------------------------

    def draw(self, surf: pygame.Surface) -> None:
        """The whole frame: panels, HUD column, help overlay."""
        surf.fill(base.BACKGROUND)
        many = len(self.panels) > 1
        for k, (p, rect) in enumerate(zip(self.panels, self.rects, strict=True)):
            pygame.draw.rect(surf, base.PANEL, rect, border_radius=6)
            clip = surf.get_clip()
            surf.set_clip(rect)
            x = self._positions(p)
            self.demo.draw(surf, rect, p, x)
            if many:
                self._caption(surf, rect, p)
            if p.error:
                self._error(surf, rect, p.error)
            if k == self.focus and self.drag is not None and self.drag_to is not None and self.drag < len(x):
                at = self.demo.to_screen(rect, x[self.drag])
                pygame.draw.line(surf, base.ACCENT, at, self.drag_to, 1)
                pygame.draw.circle(surf, base.ACCENT, self.drag_to, 5, 1)
            surf.set_clip(clip)
            if many and k == self.focus:
                pygame.draw.rect(surf, base.ACCENT, rect, 2, border_radius=6)
        self._hud(surf)
        if self.help:
            self._help(surf)

    def _caption(self, surf: pygame.Surface, rect: pygame.Rect, p: Panel) -> None:
        f = base.font(20)
        d = p.drift_now()
        title, tags = self.demo.caption(p)
        base.text(surf, base.font(22), title, (rect.x + 10, rect.y + 8), p.colour)
        base.text(surf, f, tags, (rect.x + 10, rect.y + 30), base.DIM)
        if d is not None:
            base.text(surf, f, f"drift {d:+.2e}", (rect.right - 10, rect.y + 8), base.TEXT, "topright")

    def _error(self, surf: pygame.Surface, rect: pygame.Rect, message: str) -> None:
        f = base.font(20)
        lines = wrap(f, f"stopped: {message} (r resets, m picks another method)", rect.width - 24)
        y = rect.bottom - 10 - 20 * len(lines)
        box = pygame.Rect(rect.x + 6, y - 6, rect.width - 12, 20 * len(lines) + 10)
        pygame.draw.rect(surf, (60, 24, 28), box, border_radius=4)
        for line in lines:
            base.text(surf, f, line, (rect.x + 12, y), base.ERROR)
            y += 20

    def _hud(self, surf: pygame.Surface) -> None:
        pygame.draw.rect(surf, base.PANEL, (0, 0, SIDEBAR - 4, SIZE[1]))
        f, big = base.font(21), base.font(30)
        x, y = 14, 12
        base.text(surf, big, f"physstep demo: {self.demo.name}", (x, y), base.ACCENT)
        y += 36
        p = self.panels[self.focus]
        rows: list[tuple[str, str, tuple[int, int, int]]] = []
        if len(self.panels) > 1:
            rows.append(("panel", f"{self.focus + 1} of {len(self.panels)} (tab)", base.TEXT))
        rows.append(("method", p.info.name, p.colour if len(self.panels) > 1 else base.TEXT))
        sym = "symplectic" if p.info.symplectic else "not symplectic"
        rows.append(("", f"order {p.info.order}, {sym}", base.DIM))
        loop, substeps = LOOPS[self.loop]
        rows.append(("dt", f"{self.dt:.4g} s", base.TEXT))
        rows.append(("loop", loop + (f" ({substeps})" if loop == "steps-per-frame" else ""), base.TEXT))
        rows.append(("steps/frame", f"{p.steps}   alpha {p.world.alpha:.2f}", base.TEXT))
        rows.append(("time", f"{p.world.time:.2f} s", base.TEXT))
        e, d = p.energy(), p.drift_now()
        if e is None:
            rows.append(("energy", self.demo.no_energy, base.DIM))
        else:
            rows.append(("energy", f"{e:.6g} J", base.TEXT))
            rows.append(("drift", "-" if d is None else f"{d:+.3e}", base.TEXT))
        rows.extend(self.demo.hud(p))
        fps = "fixed 60 (headless)" if self.fps is None else f"{self.fps:.0f}"
        rows.append(("fps", fps, base.TEXT))
        state = "paused" if self.paused else "running"
        if p.error:
            state = "stopped (step failed)"
        rows.append(("state", state, base.ERROR if p.error else base.TEXT))
        for label, value, colour in rows:
            base.text(surf, f, label, (x, y), base.DIM)
            base.text(surf, f, value, (x + 100, y), colour)
            y += 24
        if len(p.drift) > 1:
            y += 6
            self._drift_graph(surf, pygame.Rect(x, y + 18, SIDEBAR - 36, 110), p)
        base.text(surf, f, "h or F1: help", (x, SIZE[1] - 12), base.DIM, "bottomleft")

    def _drift_graph(self, surf: pygame.Surface, box: pygame.Rect, p: Panel) -> None:
        f = base.font(18)
        top = max(abs(v) for v in p.drift) or 1.0
        base.text(surf, f, "energy drift (E - E0) / |E0|", (box.x, box.y - 4), base.DIM, "bottomleft")
        pygame.draw.rect(surf, base.BACKGROUND, box)
        pygame.draw.line(surf, base.GRID, (box.x, box.centery), (box.right - 1, box.centery))
        n = len(p.drift)
        pts = [
            (
                box.x + int(i * (box.width - 1) / max(n - 1, 1)),
                int(box.centery - v / top * (box.height / 2 - 3)),
            )
            for i, v in enumerate(p.drift)
        ]
        if len(pts) > 1:
            pygame.draw.lines(surf, base.ACCENT, False, pts, 2)
        note = f"scale +-{top:.1e}, {n} frames"
        base.text(surf, f, note, (box.x, box.bottom + 4), base.DIM)

    def _help(self, surf: pygame.Surface) -> None:
        f, big = base.font(22), base.font(28)
        reset = self.demo.reset_doc
        lines = [(k.label, reset if k.action == "reset" and reset else k.doc) for k in KEYS + self.demo.keys]
        if self.demo.draggable:
            lines.append(("drag", self.demo.mouse))
        w = 60 + max(f.size(label)[0] for label, _ in lines) + max(f.size(doc)[0] for _, doc in lines) + 40
        h = 70 + 26 * len(lines)
        box = pygame.Rect((SIZE[0] - w) // 2, (SIZE[1] - h) // 2, w, h)
        shade = pygame.Surface(SIZE, pygame.SRCALPHA)
        shade.fill((0, 0, 0, 150))
        surf.blit(shade, (0, 0))
        pygame.draw.rect(surf, base.PANEL, box, border_radius=8)
        pygame.draw.rect(surf, base.ACCENT, box, 2, border_radius=8)
        base.text(surf, big, "keys", (box.x + 20, box.y + 16), base.ACCENT)
        y = box.y + 54
        for label, doc in lines:
            base.text(surf, f, label, (box.x + 24, y), base.ACCENT)
            base.text(surf, f, doc, (box.x + 24 + 40 + max(f.size(lab)[0] for lab, _ in lines), y), base.TEXT)
            y += 26

    def screen_position(self, panel: int = 0, particle: int = 0) -> tuple[int, int]:
        """Where particle ``particle`` of panel ``panel`` is drawn, px (for scripted drags);
        the panel's centre in a world without particles."""
        x = self._positions(self.panels[panel])
        if particle >= len(x):
            return self.rects[panel].center
        return self.demo.to_screen(self.rects[panel], self._positions(self.panels[panel])[particle])


def no_display() -> bool:
    """On Linux and the BSDs: no X11 or Wayland display to open a window on (DISPLAY and
    WAYLAND_DISPLAY unset) and no video driver chosen (SDL_VIDEODRIVER unset)."""
    if not sys.platform.startswith(("linux", "freebsd", "openbsd", "netbsd")):
        return False
    return not any(os.environ.get(v) for v in ("DISPLAY", "WAYLAND_DISPLAY", "SDL_VIDEODRIVER"))


def slowed(runner: Runner) -> str | None:
    """Where a panel's simulation fell behind the frame time handed to it (by more than the
    accumulator's leftover, a step): why, as a sentence (the frame cap, or the loop variant's
    own pace); None when every panel kept real time. The panel furthest behind is told."""
    behind = [p for p in runner.panels if p.handed - p.simulated > p.world.dt * (1 + 1e-9) + 1e-12]
    if not behind:
        return None
    p = min(behind, key=lambda q: q.simulated / q.handed)
    parts = p.world.__reduce__()[1][0]
    clock = tomllib.loads(parts["scene"]).get("loop", {})  # the world's scene text: its caps
    pace = (
        f"{p.simulated:.4g} s simulated in {p.handed:.4g} s of frames "
        f"({100 * p.simulated / p.handed:.0f} % of real time)"
    )
    if p.lost > 0:
        caps = []
        if "max_steps_per_frame" in clock:
            caps.append(f"at most {clock['max_steps_per_frame']} steps per frame")
        if "max_frame_time" in clock:
            caps.append(f"frames clamped to {clock['max_frame_time']:g} s")
        what = f" ({', '.join(caps)})" if caps else ""
        return f"slower than real time: the frame cap{what} dropped {p.lost:.4g} s; {pace}"
    loop, substeps = parts.get("loop"), parts.get("substeps")
    return (
        f"slower than real time: the {loop} loop takes {substeps} step(s) per frame whatever the frame "
        f"time; {pace}"
    )


def wrap(f: pygame.font.Font, s: str, width: int) -> list[str]:
    """``s`` broken at spaces into lines at most ``width`` px wide in font ``f``."""
    lines: list[str] = []
    line = ""
    for word in s.split():
        cand = f"{line} {word}" if line else word
        if line and f.size(cand)[0] > width:
            lines.append(line)
            line = word
        else:
            line = cand
    return [*lines, line] if line else lines


#: A scripted event: an event, or a function of the runner making one (its positions).
Scripted = pygame.event.Event | Callable[[Runner], pygame.event.Event]


def run(
    name: str | None = None,
    *,
    scene: str | None = None,
    headless: bool = False,
    frames: int | None = None,
    screenshot: str | None = None,
    method: str | None = None,
    dt: float | None = None,
    script: Mapping[int, Sequence[Scripted]] | None = None,
) -> dict[str, Any]:
    """Runs demo ``name``, or the generic demo of the scene file ``scene``
    (:class:`physstep.demos.scene.SceneDemo`), and returns a summary of its last frame.

    ``headless``: the dummy video driver and a fixed frame time (deterministic), 120 frames
    unless ``frames`` says otherwise; ``screenshot`` saves the last frame as PNG, written
    whole (temp file + rename). The summary's ``slowed`` says when a panel fell behind real
    time (:func:`slowed`: the frame cap dropped steps, or the loop variant's own pace), else
    None. ``script`` maps a frame number to events posted before that frame (the smoke
    test's key presses and drags). ValueError for a bad name, setting or scene file (the
    loader's one line naming the file), and, without ``headless``, where there is no display
    or SDL's video driver shows nothing (pointing at ``--headless``).
    """
    if scene is not None:
        from physstep.demos.scene import SceneDemo

        demo: Demo = SceneDemo(scene)
    else:
        demo = load(name or "")()
    if screenshot is not None:
        files.check(screenshot, "--screenshot")
    if headless:
        os.environ["SDL_VIDEODRIVER"] = "dummy"
        frames = 120 if frames is None else frames
    elif no_display():
        # Before SDL looks for one: it would fall back to its offscreen driver (a demo running
        # unseen, for ever) after printing its own errors about Wayland.
        raise ValueError(
            "cannot open a window (no display: DISPLAY and WAYLAND_DISPLAY are unset): "
            "run with --headless --screenshot FILE.png"
        )
    os.environ.setdefault("SDL_AUDIODRIVER", "dummy")
    base.forget_fonts()
    try:
        try:
            pygame.display.init()
            pygame.font.init()
            driver = pygame.display.get_driver()
            if not headless and driver in NO_WINDOW_DRIVERS:
                # SDL fell back to (or was told to use) a driver that shows nothing: the demo
                # would run unseen, for ever.
                raise pygame.error(f"no display: SDL's video driver is {driver!r}, which shows nothing")
            screen = pygame.display.set_mode(SIZE)
        except pygame.error as e:
            raise ValueError(
                f"cannot open a window ({_one_line(str(e))}): run with --headless --screenshot FILE.png"
            ) from None
        title = f"--scene {scene}" if scene is not None else name
        pygame.display.set_caption(f"physstep demo {title} (h: help)")
        runner = Runner(demo, method, dt)
        clock = pygame.time.Clock()
        n = 0
        while runner.running and (frames is None or n < frames):
            for item in (script or {}).get(n, ()):
                pygame.event.post(item(runner) if callable(item) else item)
            if headless:
                frame_time = HEADLESS_FRAME_TIME
            else:
                frame_time = clock.tick(FPS) / 1000.0
                runner.fps = clock.get_fps()
            for event in pygame.event.get():
                runner.handle(event)
            runner.update(frame_time)
            runner.draw(screen)
            if not headless:
                pygame.display.flip()
            n += 1
        if screenshot is not None:
            files.write(screenshot, lambda fh: pygame.image.save(screen, fh, "shot.png"), "--screenshot")
        p = runner.panels[0]
        return {
            "demo": demo.name,
            "scene": scene,
            "frames": n,
            "methods": [q.info.name for q in runner.panels],
            "dt": runner.dt,
            "loop": LOOPS[runner.loop][0],
            "t": p.world.time,
            "errors": [q.error for q in runner.panels if q.error],
            "screenshot": screenshot,
            "slowed": slowed(runner),
        }
    finally:
        base.forget_fonts()
        pygame.font.quit()
        pygame.display.quit()
