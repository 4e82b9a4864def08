"""The package as a user meets it: ``import physstep`` reaches everything, ``help()`` has
something to say about every public name, and the command line's modules import one way."""

from __future__ import annotations

import ast
import importlib
import inspect
import pkgutil
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from types import ModuleType

import physstep
import physstep.cli
import pytest


def _cli_modules() -> list[str]:
    return ["physstep.cli"] + [f"physstep.cli.{m.name}" for m in pkgutil.iter_modules(physstep.cli.__path__)]


MODULES = ["physstep", "physstep.lab", "physstep.plot", *_cli_modules()]


def _doc(obj: object) -> str:
    """The docstring ``help()`` shows first (``__doc__`` itself: not inherited from a base)."""
    return (getattr(obj, "__doc__", None) or "").strip()


def _members(cls: type) -> Iterator[tuple[str, object]]:
    """The public methods and properties ``cls`` defines itself."""
    for name, member in vars(cls).items():
        if name.startswith("_"):
            continue
        if isinstance(member, (staticmethod, classmethod)):
            member = member.__func__
        if inspect.isfunction(member) or isinstance(member, property):
            yield name, member


def _public(module: ModuleType) -> Iterator[tuple[str, object]]:
    """Public functions and classes defined in ``module`` (or exported by its ``__all__``),
    and the public methods and properties of those classes."""
    exported = set(getattr(module, "__all__", ()))
    for name, obj in vars(module).items():
        if name.startswith("_") or not (inspect.isfunction(obj) or inspect.isclass(obj)):
            continue
        if obj.__module__ != module.__name__ and name not in exported:
            continue
        yield f"{module.__name__}.{name}", obj
        if inspect.isclass(obj) and obj is not physstep.World:  # the native class: below
            for member, value in _members(obj):
                yield f"{module.__name__}.{name}.{member}", value


@pytest.mark.parametrize("name", MODULES)
def test_every_public_name_has_a_docstring(name: str) -> None:
    module = importlib.import_module(name)
    assert _doc(module), f"module {name} has no docstring"
    missing = [where for where, obj in _public(module) if not _doc(obj)]
    assert not missing, f"no docstring: {', '.join(missing)}"


def test_every_public_method_of_world_has_a_docstring() -> None:
    # pyo3 puts the Rust `///` comments in __doc__: a missing one is fixed in crates/physstep-py
    world = physstep.World
    assert _doc(world)
    names = [n for n in dir(world) if not n.startswith("_")]
    assert {"step", "advance", "positions", "record", "from_scene"} <= set(names)
    missing = [
        n for n in names if not _doc(getattr(world, n) if callable(getattr(world, n)) else vars(world)[n])
    ]
    assert not missing, f"World members without a Rust doc comment: {', '.join(missing)}"


def test_import_physstep_reaches_lab_and_plot_and_the_cli_loads_no_plotting() -> None:
    code = (
        "import sys, physstep, physstep.cli\n"
        "assert 'matplotlib' not in sys.modules, 'the command line imported matplotlib'\n"
        "assert callable(physstep.lab.compare) and callable(physstep.plot.save)\n"
        "print(physstep.__version__)\n"
    )
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    assert res.stdout.strip() == physstep.__version__


#: Who may import whom inside physstep.cli: the app the commands, the commands the helpers,
#: the helpers nothing of the command line (only physstep itself).
LAYERS = {
    "__init__": {"app"},
    "app": {"basic", "demo", "lab", "options", "output"},
    "basic": {"options", "output"},
    "demo": {"options", "output"},
    "lab": {"options", "output"},
    "options": set(),
    "output": set(),
}


def _cli_imports(path: Path) -> set[str]:
    """The physstep.cli modules that the module at ``path`` imports, anywhere in it."""
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("physstep.cli"):
            if node.module == "physstep.cli":
                found.update(a.name for a in node.names)
            else:
                found.add(node.module.split(".")[2])
        elif isinstance(node, ast.Import):
            found.update(a.name.split(".")[2] for a in node.names if a.name.startswith("physstep.cli."))
    return found


def test_the_command_line_modules_import_one_way() -> None:
    root = Path(physstep.cli.__file__).parent
    files = {p.stem for p in root.glob("*.py")}
    assert files == set(LAYERS), "a module was added or removed: place it in LAYERS"
    for stem in sorted(files):
        extra = _cli_imports(root / f"{stem}.py") - LAYERS[stem]
        assert not extra, f"physstep.cli.{stem} imports {sorted(extra)} against the layering"
