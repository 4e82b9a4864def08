"""Interactive demos: watch the integrators behave, as the notes teach (``physstep demo NAME``).

Each demo is a small class over the core (:mod:`physstep.demos.base`) drawn with pygame-ce,
driven by the World's fixed-timestep loop (``World.advance(frame_time)``) with render
interpolation. They are registered by name in :data:`DEMOS`, the one table that the command
line, ``physstep demo --list`` and the headless smoke test read: adding a demo is a file and
a line here.

This module imports no pygame, so the list works without the ``demo`` extra; pygame-ce is
loaded with the demo (``pip install pygame-ce``; in a checkout, ``pip install -e '.[demo]'``:
physstep is not on a package index).
"""

from __future__ import annotations

import importlib
import os
from dataclasses import dataclass
from typing import Any

__all__ = ["DEMOS", "INSTALL_HINT", "DemoEntry", "entry", "load", "names"]

os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")  # pygame's banner would go to stdout

#: What ``physstep demo`` says when pygame-ce is not installed.
INSTALL_HINT = (
    "the demos need pygame-ce: pip install pygame-ce (in a checkout of physstep: pip install -e '.[demo]')"
)


@dataclass(frozen=True)
class DemoEntry:
    """A registered demo: its name, the module and class that draw it, and a one-line doc."""

    name: str
    module: str
    cls: str
    doc: str

    def as_dict(self) -> dict[str, str]:
        """``name`` and ``doc``, as ``physstep demo --list --format json`` prints them."""
        return {"name": self.name, "doc": self.doc}


#: The demos, in the order ``--list`` shows them.
DEMOS: tuple[DemoEntry, ...] = (
    DemoEntry(
        "spring", "particles", "SpringDemo", "the notes' spring (m = 10, k = 5, x0 = 20); drag the mass"
    ),
    DemoEntry(
        "orbit", "particles", "OrbitDemo", "a circular orbit with its trail: who spirals out, who keeps it"
    ),
    DemoEntry(
        "racket",
        "racket",
        "RacketDemo",
        "the tennis-racket flip: a box in 3D, its body-frame angular velocity",
    ),
    DemoEntry(
        "lorenz", "lorenz", "LorenzDemo", "the Lorenz attractor, a first-order flow, through the same methods"
    ),
    DemoEntry(
        "compare",
        "compare",
        "CompareDemo",
        "one orbit under four methods side by side (the notes' picture, live)",
    ),
    DemoEntry(
        "balls",
        "balls",
        "BallsDemo",
        "balls in a box, contacts at their time of impact; pull a ball, e: restitution",
    ),
    DemoEntry(
        "cloth",
        "cloth",
        "ClothDemo",
        "a cloth hung from two corners, in 3D; i: constraint sweeps, w: wind; drag a particle",
    ),
    DemoEntry(
        "ragdoll", "ragdoll", "RagdollDemo", "a ragdoll falling onto the ground; drag a joint, k: kick it up"
    ),
    DemoEntry(
        "boxes",
        "boxes",
        "BoxesDemo",
        "a pyramid of solid boxes; b: drop a box, x: shoot one, n: substeps, c: solver, z: sleep",
    ),
    DemoEntry(
        "solvers",
        "boxes",
        "SolversDemo",
        "the pyramid under four contact solvers side by side; b: drop a box into all, c: next solvers",
    ),
    DemoEntry(
        "ramp",
        "ramp",
        "RampDemo",
        "a box on a tilted plank, sticking or sliding; a, f: angle, friction; the closed form in the HUD",
    ),
    DemoEntry(
        "dice",
        "dice",
        "DiceDemo",
        "dice thrown spinning onto a plane in 3D; t: throw again, c: solver, z: sleep",
    ),
    DemoEntry(
        "pile",
        "pile",
        "PileDemo",
        "balls piling up in a box under gravity; hold the mouse to pour, b: drop a row, k: shake",
    ),
    DemoEntry(
        "bridge",
        "bridge",
        "BridgeDemo",
        "planks hinged end to end; click: drop a box or ball (o), b: heavy box, d: ragdoll, c: solver",
    ),
)


def names() -> list[str]:
    """The registered demos' names, in order."""
    return [d.name for d in DEMOS]


def entry(name: str) -> DemoEntry:
    """The demo registered as ``name``; ValueError listing the valid names otherwise."""
    for d in DEMOS:
        if d.name == name:
            return d
    raise ValueError(f"unknown demo {name!r}; valid demos: {', '.join(names())}")


def load(name: str) -> Any:
    """The class of demo ``name`` (imports pygame); ValueError for an unknown name."""
    d = entry(name)
    return getattr(importlib.import_module(f"physstep.demos.{d.module}"), d.cls)
