"""Writes docs/figures/demo-NAME.png: the last frame of each demo, run headless.

Usage: python scripts/demo_shots.py [NAME ...] (default: every registered demo). Needs the
demo extra (pip install -e '.[demo]'). The runs are headless at the fixed frame time of
1/60 s, so the pictures are the same on every run of the same build.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")

from physstep import demos  # noqa: E402
from physstep.demos import app  # noqa: E402

#: Frames each picture runs (at 60 per second): long enough to show what the demo teaches.
FRAMES = {
    "spring": 540,  # one period of the spring (8.9 s): the closed curve of the phase portrait
    "orbit": 420,  # a period of the orbit (6.3 s)
    "racket": 1500,  # 25 s: a flip and back, omega_2 changing sign
    "lorenz": 1800,  # 30 s: both wings
    "compare": 420,  # a period: Euler out, backward Euler in (and stopped), the others on it
    "balls": 600,  # 10 s of contacts at restitution 1: the drift at rounding
    "cloth": 150,  # 2.5 s after the wind is turned on: blown out along +z, swinging
    "ragdoll": 30,  # 0.5 s: falling, a foot about to touch the ground
    "boxes": 120,  # 2 s: the pyramid standing
    "ramp": 150,  # 2.5 s at mu 0.3: sliding, the measured acceleration on the closed form
    "dice": 40,  # 0.67 s: tumbling on the plane
    "pile": 240,  # 2 s: the pile settling
    "bridge": 480,  # 8 s: a box, a ball, the ragdoll (at 3.3 s) and the heavy box (5 s) on it
}
#: Keys pressed on the first frame of a picture (a demo's own keys).
KEYS = {"cloth": ("wind",), "ramp": ("smoother",) * 6}
#: Later in a picture: (frame, a demo's own key action, or a click at (x, y) as fractions of
#: the panel).
LATER: dict[str, tuple[tuple[int, str | tuple[float, float]], ...]] = {
    "bridge": ((60, (0.3, 0.2)), (90, "shape"), (100, (0.7, 0.2)), (200, "ragdoll"), (300, "heavy")),
}
OUT = Path(__file__).parent.parent / "docs" / "figures"


def _press(key: app.Key) -> object:
    import pygame

    mod = pygame.KMOD_SHIFT if key.shift else 0
    return pygame.event.Event(pygame.KEYDOWN, key=key.keys[0], mod=mod, unicode="", scancode=0)


def _click(x: float, y: float) -> list[object]:
    """A click at (x, y), fractions of the first panel: the button down, then up a frame on."""
    import pygame

    def at(r: app.Runner) -> tuple[int, int]:
        rect = r.rects[0]
        return (rect.x + round(x * rect.width), rect.y + round(y * rect.height))

    def down(r: app.Runner) -> object:
        return pygame.event.Event(pygame.MOUSEBUTTONDOWN, button=1, pos=at(r))

    def up(r: app.Runner) -> object:
        return pygame.event.Event(pygame.MOUSEBUTTONUP, button=1, pos=at(r))

    return [down, up]


def main(names: list[str]) -> None:
    for name in names or demos.names():
        path = OUT / f"demo-{name}.png"
        keys = demos.load(name).keys
        script = {1: [_press(next(k for k in keys if k.action == a)) for a in KEYS.get(name, ())]}
        for frame, what in LATER.get(name, ()):
            if isinstance(what, str):
                script.setdefault(frame, []).append(_press(next(k for k in keys if k.action == what)))
            else:
                down, up = _click(*what)
                script.setdefault(frame, []).append(down)
                script.setdefault(frame + 1, []).append(up)
        summary = app.run(
            name, headless=True, frames=FRAMES.get(name, 600), screenshot=str(path), script=script
        )
        print(f"{path}: {summary['frames']} frames, t = {summary['t']:.4g} s")


if __name__ == "__main__":
    main(sys.argv[1:])
