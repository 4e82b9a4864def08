"""``physstep demo``: the interactive demos (:mod:`physstep.demos`), or their list.

pygame-ce is the optional extra ``demo`` (``pip install pygame-ce``): without it ``physstep demo NAME`` says
how to install it in one line (exit status 2); ``--list`` needs no pygame.
"""

from __future__ import annotations

import argparse
import os
from typing import Any

import physstep
from physstep import _files as files
from physstep import demos
from physstep.cli import options, output

#: The most frames ``--frames`` takes (about 4.6 hours at 60 frames per second).
MAX_FRAMES = 10**6


def _cmd_demo(args: argparse.Namespace) -> int:
    """``physstep demo NAME`` runs a demo; ``physstep demo --list`` lists them."""
    if args.list:
        rows = [d.as_dict() for d in demos.DEMOS]
        if args.format == "json":
            print(output.dump(rows))
        else:
            for r in rows:
                print(f"{r['name']:<9} {r['doc']}")
        return 0
    if args.name is not None and args.scene_file is not None:
        raise options.UsageError(f"give a demo NAME or --scene FILE.toml, not both (got '{args.name}')")
    if args.scene_file is not None:
        physstep.load_scene(args.scene_file)  # a bad file: the loader's one line, before pygame
    elif args.name is None:
        raise options.UsageError(
            f"give a demo NAME, --scene FILE.toml or --list; valid demos: {', '.join(demos.names())}"
        )
    else:
        demos.entry(args.name)  # an unknown name lists the valid ones, before pygame is needed
    if args.screenshot is not None:
        if not args.screenshot.lower().endswith(".png"):
            raise options.UsageError(f"invalid --screenshot '{args.screenshot}': must be a .png file")
        files.check(args.screenshot, "--screenshot")
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    try:
        import pygame  # noqa: F401  (the optional extra)
    except ImportError:
        raise options.UsageError(demos.INSTALL_HINT) from None
    from physstep.demos import app

    summary = app.run(
        args.name,
        scene=args.scene_file,
        headless=args.headless,
        frames=args.frames,
        screenshot=args.screenshot,
        method=args.method,
        dt=args.dt,
    )
    if args.format == "json":
        print(output.dump(summary))
    else:
        shot = f", screenshot {summary['screenshot']}" if summary["screenshot"] else ""
        what = f"scene {summary['scene']}" if summary["scene"] else f"demo {summary['demo']}"
        print(
            f"{what}: {summary['frames']} frames, t = {summary['t']:.4g} s, "
            f"{', '.join(summary['methods'])} at dt = {summary['dt']:g} s{shot}"
        )
        if summary["slowed"]:
            print(f"note: {output.one_line(summary['slowed'])}")
    return 0


def register(subparsers: Any) -> None:
    """Adds ``demo`` to an argparse subparsers object."""
    d = subparsers.add_parser("demo", help="interactive demos (pygame-ce): physstep demo --list")
    d.add_argument("name", nargs="?", help="the demo (physstep demo --list lists them)")
    d.add_argument("--list", action="store_true", help="list the demos")
    d.add_argument(
        "--scene",
        dest="scene_file",
        metavar="FILE.toml",
        default=None,
        help="open the world a scene file describes in a generic demo (instead of NAME)",
    )
    d.add_argument(
        "--headless",
        action="store_true",
        help="no window (SDL's dummy driver) and a fixed frame time of 1/60 s: deterministic",
    )
    d.add_argument(
        "--frames",
        type=options.argument("--frames", int, low=1, high=MAX_FRAMES),
        default=None,
        metavar="N",
        help="stop after N frames (headless default: 120)",
    )
    d.add_argument("--screenshot", metavar="FILE.png", help="save the last frame as PNG")
    d.add_argument("--method", default=None, help="the first panel's starting method (default: the demo's)")
    d.add_argument("--dt", type=options.DT, default=None, help="the starting step, s (default: the demo's)")
    options.add_format(d)
    d.set_defaults(func=_cmd_demo)
