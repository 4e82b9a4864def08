"""The commands' flags and their checks: a bad value is one line naming the flag.

Every check raises :class:`UsageError` (a ValueError: exit status 2), or, inside argparse,
``argparse.ArgumentTypeError``, which :mod:`physstep.cli.app` turns into the same line.
"""

from __future__ import annotations

import argparse
import math
import os
import stat
from collections.abc import Callable
from typing import Any

import physstep

SCENE_HELP = "built-in scene (physstep scenes lists them), or a scene file FILE.toml"
METHOD_HELP = "integrator (physstep methods lists them)"
UNTIL_HELP = (
    "end time, s (default: the scene's); a whole number of steps is run, the output says where "
    "the last one ends"
)


class UsageError(ValueError):
    """Bad command-line input (exit status 2)."""


def argument(
    flag: str, kind: type = float, *, low: float, open_low: bool = False, high: float = math.inf
) -> Callable[[str], Any]:
    """An argparse ``type`` for ``flag``: a finite ``kind`` (float or int) in [low, high]
    (``open_low``: > low); a bad value is one line naming the flag and the value as typed."""

    integer = kind is int

    def show(bound: float) -> str:
        return str(int(bound)) if integer else f"{bound:g}"

    what = "an integer" if integer else "a finite number"
    cmp = ">" if open_low else ">="
    bound = f"from {show(low)} to {show(high)}" if high < math.inf else f"{cmp} {show(low)}"

    def parse(text: str) -> Any:
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"invalid {flag} '{text}': not {'an integer' if integer else 'a number'}"
            ) from None
        finite = integer or math.isfinite(value)  # (an int may be too large for a float)
        if not (finite and (value > low if open_low else value >= low) and value <= high):
            raise argparse.ArgumentTypeError(f"invalid {flag} '{text}': must be {what} {bound}")
        return value

    parse.__name__ = flag.lstrip("-")
    parse.__doc__ = f"``{flag}``: {what} {bound}; argparse.ArgumentTypeError naming it otherwise."
    return parse


#: ``--dt``: a step, s, > 0.
DT = argument("--dt", low=0, open_low=True)
#: ``--until``: an end time, s, >= 0.
UNTIL = argument("--until", low=0)


def parse_params(items: list[str] | None) -> dict[str, float]:
    """``["k=5", "m=2"]`` as ``{"k": 5.0, "m": 2.0}``; UsageError naming a malformed item."""
    out: dict[str, float] = {}
    for item in items or []:
        name, sep, value = item.partition("=")
        if not sep or not name.strip():
            raise UsageError(f"invalid --param '{item}': must be NAME=VALUE")
        try:
            number = float(value)
        except ValueError:
            raise UsageError(f"invalid --param '{item}': value '{value}' is not a number") from None
        if not math.isfinite(number):
            raise UsageError(f"invalid --param '{item}': value '{value}' is not a finite number")
        out[name.strip()] = number
    return out


def requested_until(scene: Any, until: float | None) -> float:
    """The end time the user asked for, s: ``--until`` or the scene's default (a scene
    file's ``until``)."""
    if until is not None:
        return float(until)
    if isinstance(scene, physstep.SceneFile):
        return float(scene.until) if scene.until is not None else 0.0
    return float(physstep.scene(scene)["until"])


def is_scene_file(scene: Any) -> bool:
    """Whether a command's scene argument names a scene file (it ends in ``.toml``)."""
    return isinstance(scene, str) and scene.lower().endswith(".toml")


def resolve_scene(args: argparse.Namespace) -> None:
    """Replaces a scene-file argument (``FILE.toml``) by its :class:`physstep.SceneFile`, with
    ``--dt`` and ``--until`` defaulting to the file's; ValueError (exit status 2) naming the
    file, line and field for a bad file, or the file when it has no ``until`` and none is
    given. A built-in scene's name is left as it is."""
    if not is_scene_file(getattr(args, "scene", None)):
        return
    if getattr(args, "param", None):
        raise UsageError(
            f"invalid --param for scene file '{args.scene}': a scene file has no parameters (edit the file)"
        )
    sf = physstep.SceneFile(args.scene)
    args.scene = sf
    if hasattr(args, "dt") and args.dt is None:
        args.dt = sf.dt
    if hasattr(args, "until") and args.until is None:
        if sf.until is None:
            raise UsageError(f"scene file '{sf.path}' has no until: give --until or add until = SECONDS")
        args.until = sf.until


#: The arguments naming the scene file a command reads (argparse dests).
INPUTS = ("scene", "scene_file")
#: The flags naming files a command writes.
OUTPUTS = (("out", "--out"), ("plot", "--plot"), ("screenshot", "--screenshot"))


def _file_key(path: str) -> tuple[int, int] | str | None:
    """What ``path`` names: an existing regular file's (device, inode), so that a symbolic or
    hard link to it is the same file; a missing file's resolved path; None for a device, a
    FIFO or a directory, which writing cannot destroy (or :mod:`physstep._files` refuses)."""
    try:
        st = os.stat(path)
    except OSError:
        return os.path.realpath(path)
    return (st.st_dev, st.st_ino) if stat.S_ISREG(st.st_mode) else None


def check_paths(args: argparse.Namespace) -> None:
    """UsageError (exit status 2) when an output file is an input file (``run cloth.toml --out
    cloth.toml``) or two outputs are one file (``sweep --out s.png --plot s.png``): either
    would write over the user's file. Called before the scene file is read."""
    seen: dict[tuple[int, int] | str, tuple[str, str, bool]] = {}
    for dest in INPUTS:
        path = getattr(args, dest, None)
        if isinstance(path, str) and path and (dest != "scene" or is_scene_file(path)):
            key = _file_key(path)
            if key is not None:
                seen[key] = ("scene file", path, True)
    for dest, flag in OUTPUTS:
        path = getattr(args, dest, None)
        if not (isinstance(path, str) and path):
            continue
        key = _file_key(path)
        if key is None:
            continue
        if key in seen:
            other, other_path, is_input = seen[key]
            if is_input:
                raise UsageError(
                    f"invalid {flag} '{path}': is the scene file read ('{other_path}'); write to another file"
                )
            raise UsageError(
                f"invalid {flag} '{path}': is also {other} ('{other_path}'); give each output its own file"
            )
        seen[key] = (flag, path, False)


def add_format(p: argparse.ArgumentParser, formats: tuple[str, ...] = ("text", "json")) -> None:
    """Adds ``--format`` (the first of ``formats`` is the default) to ``p``."""
    p.add_argument(
        "--format", choices=formats, default=formats[0], help=f"output format (default: {formats[0]})"
    )


def add_param(p: argparse.ArgumentParser) -> None:
    """Adds the repeatable ``--param NAME=VALUE`` (read by :func:`parse_params`) to ``p``."""
    p.add_argument("--param", action="append", metavar="NAME=VALUE", help="override a scene parameter")
