"""Scene files: a world written in TOML (docs/scene-files.md is the schema).

The engine parses and writes them (``physstep::scenes::file``), so the command line,
Python and a Rust game share one loader. :func:`load_scene` gives the World a file
describes; :class:`SceneFile` is a file as a *system* for :func:`physstep.simulate` and
every ``physstep.lab`` function (a callable returning a fresh World, with the file's ``dt``
and ``until``); :func:`scene_text` and :func:`export_scene` write one.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from physstep import _core
from physstep._core import World

__all__ = ["SceneFile", "export_scene", "load_scene", "scene_text"]


def _path(path: Any) -> str:
    try:
        p = os.fspath(path)
    except TypeError:
        raise ValueError(f"invalid path = {path!r}: must be a str or os.PathLike") from None
    if not isinstance(p, str):
        raise ValueError(f"invalid path = {path!r}: must be a str or os.PathLike of str")
    return p


def load_scene(path: str | os.PathLike[str]) -> World:
    """The World the scene file at ``path`` describes, at t = 0.

    Raises ValueError naming the file, the line and the field (and what was expected) for a
    file that cannot be read, is not TOML, has an unknown key, a value of the wrong type or
    out of range, a constraint or spring on a missing particle, or a mesh that is not closed.

    Examples:
        >>> import physstep, pathlib, tempfile
        >>> d = pathlib.Path(tempfile.mkdtemp())
        >>> _ = (d / "s.toml").write_text("dimension = 1\\ndt = 0.1\\n[[particles]]\\nposition = [2.0]\\n")
        >>> len(physstep.load_scene(d / "s.toml"))
        1
    """
    world, _ = _core.read_scene(_path(path))
    return world


class SceneFile:
    """A scene file as a system: calling it returns a fresh World from the file.

    ``name`` is the file's stem, ``dt`` its step and ``until`` its run length (None when the
    file has none). Pass it to :func:`physstep.simulate` and the lab in place of a scene
    name. Raises ValueError as :func:`load_scene` does.
    """

    def __init__(self, path: str | os.PathLike[str]) -> None:
        self.path = _path(path)
        world, until = _core.read_scene(self.path)
        self.name: str = Path(self.path).stem
        self.dt: float = world.dt
        self.until: float | None = until

    def __call__(self) -> World:
        """A fresh World from the file."""
        return load_scene(self.path)

    def __repr__(self) -> str:
        return f"SceneFile({self.path!r})"


def scene_text(world: World, title: str = "physstep world", until: float | None = None) -> str:
    """``world`` (its current state) as the text of a scene file, which loads back into a
    world with bitwise the same state; ``title`` goes in its first comment line.

    Raises ValueError for what a file cannot hold: Python forces and flows, springs and
    forces on bodies, and bodies of a world that has stepped.
    """
    return _core.scene_file_text(world, title, until)


def export_scene(name: str, params: dict[str, float] | None = None) -> str:
    """The built-in scene ``name`` (``params`` override its parameters) as a scene file, with
    its default method, step and run length: loading it gives bitwise the built-in
    trajectory. Raises ValueError for an unknown scene or parameter."""
    import physstep

    spec = physstep.scene(name)
    world = World.from_scene(name, spec["method"], spec["dt"], params or {})
    return scene_text(world, f"{name}: {spec['doc']}", spec["until"])
