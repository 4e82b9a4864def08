"""The documentation site's sources (mkdocs.yml, docs/): the API reference in reading order,
examples that render as code, code blocks that wrap rather than overflow. The strict build
itself runs in scripts/test.sh (mkdocs is the ``docs`` extra)."""

from __future__ import annotations

import importlib
import inspect
import re
from pathlib import Path

import physstep
import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"


def _config() -> str:
    return (ROOT / "mkdocs.yml").read_text()


def test_the_api_reference_reads_world_first_and_names_every_public_object_once() -> None:
    page = (DOCS / "api" / "physstep.md").read_text()
    names = re.findall(r"^::: physstep\.(\w+)$", page, re.MULTILINE)
    assert names[0] == "World" and names[1] == "simulate"
    assert sorted(names) == sorted(physstep.__all__) and len(names) == len(set(names))
    errors = names.index("StepError")
    assert set(names[errors:]) == {
        "StepError",
        "DivergedError",
        "ConvergenceError",
        "WorldBusyError",
        "ConstraintWarning",
    }


def _docstrings() -> list[object]:
    out: list[object] = []
    for modname in ("physstep", "physstep.plot", "physstep.lab", "physstep.lab.results"):
        mod = importlib.import_module(modname)
        out.append(pytest.param(modname, inspect.getdoc(mod) or "", id=modname))
        for name in getattr(mod, "__all__", []):
            obj = getattr(mod, name)
            if (inspect.isclass(obj) or inspect.isfunction(obj)) and obj.__module__.startswith("physstep"):
                where = f"{modname}.{name}"
                out.append(pytest.param(where, inspect.getdoc(obj) or "", id=where))
    return out


@pytest.mark.parametrize(("where", "doc"), _docstrings())
def test_doctest_examples_sit_in_an_examples_section_so_they_render_as_code(where: str, doc: str) -> None:
    # mkdocstrings (Google style) renders ">>>" lines as code only inside "Examples:"; outside
    # one they became nested blockquotes of run-on text
    lines = doc.splitlines()
    for i, line in enumerate(lines):
        if line.lstrip().startswith(">>>"):
            head = next((lines[j] for j in range(i - 1, -1, -1) if not lines[j].startswith(" ")), "")
            assert head.strip() == "Examples:", (where, line)


def test_code_blocks_wrap_instead_of_overflowing() -> None:
    config = _config()
    css = re.findall(r"^extra_css:\n((?:  - .+\n)+)", config, re.MULTILINE)
    assert css, "mkdocs.yml names no stylesheet"
    sheets = [DOCS / line.strip()[2:] for line in css[0].splitlines()]
    text = "".join(s.read_text() for s in sheets)
    rule = re.search(r"\.md-typeset pre > code\s*\{([^}]*)\}", text)
    assert rule and "white-space: pre-wrap" in rule[1] and "overflow-wrap: anywhere" in rule[1]
    # the table of contents in the navigation, so the content column is wide enough for the
    # command line's tables (up to 120 columns) on a 1280-pixel screen
    assert "- toc.integrate" in config
    assert int(re.search(r"\.md-grid\s*\{\s*max-width:\s*(\d+)px", text)[1]) >= 1400
