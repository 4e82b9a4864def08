"""mkdocs hook: pages of the site that are sections of the README, kept in one place.

A page under docs/ holds a line ``<!-- readme: HEADING -->``; at build time the line becomes the
README's section under that heading (its body, up to the next heading of the same or a higher
level), with the subheadings raised so the section's own level maps to the page's ``#`` title,
and links written for the README (``docs/x.md``, ``docs/figures/y.png``) made relative to docs/.
Add ``intro`` (``<!-- readme: HEADING intro -->``) to stop at the first subheading. Read on a code
host, the page shows its own text and the comment is invisible.

``SphinxRoles`` (a griffe extension, named in mkdocs.yml) shows the docstrings' Sphinx roles
(``:func:`compare```, ``:mod:`~physstep.lab.system```) as the code spans they stand for, and
``on_post_build`` fails the build when a public object of the API pages has no docstring.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import griffe

README = Path(__file__).resolve().parent.parent / "README.md"
MARKER = re.compile(r"^<!-- readme: (?P<heading>.+?)(?P<intro> intro)? -->$", re.MULTILINE)
HEADING = re.compile(r"^(?P<hashes>#{1,6}) (?P<title>.+)$")


def _sections(text: str) -> list[tuple[int, int, str]]:
    """(line index, level, title) of every heading outside fenced code."""
    out, fenced = [], False
    for i, line in enumerate(text.splitlines()):
        if line.startswith("```"):
            fenced = not fenced
        elif not fenced and (m := HEADING.match(line)):
            out.append((i, len(m["hashes"]), m["title"].strip()))
    return out


def readme_section(heading: str, intro: bool = False) -> str:
    lines = README.read_text(encoding="utf-8").splitlines()
    heads = _sections("\n".join(lines))
    found = [h for h in heads if h[2] == heading]
    if len(found) != 1:
        raise ValueError(f"README.md has {len(found)} headings {heading!r} (a docs page asks for one)")
    start, level, _ = found[0]
    end = len(lines)
    for i, lvl, _ in heads:
        if i > start and (lvl <= level or intro):
            end = i
            break
    body, fenced = [], False
    for line in lines[start + 1 : end]:
        if line.startswith("```"):
            fenced = not fenced
        elif not fenced and (m := HEADING.match(line)):
            line = "#" * max(2, len(m["hashes"]) - level + 1) + " " + m["title"]
        body.append(line)
    text = "\n".join(body).strip("\n")
    return re.sub(r"\]\(docs/", "](", text)


ROLE = re.compile(r":(?:func|class|mod|meth|attr|data|exc|obj):`~?(?P<name>[^`]+)`")


def _role(m: re.Match[str]) -> str:
    name = m["name"]
    return f"`{name.rsplit('.', 1)[-1]}`" if m[0].split("`")[1].startswith("~") else f"`{name}`"


class SphinxRoles(griffe.Extension):
    """``:func:`x``` -> ```x```, ``:mod:`~a.b``` -> ```b``` in every docstring the API pages read."""

    def on_object(self, *, obj: griffe.Object, **kwargs: Any) -> None:
        if obj.docstring is not None:
            obj.docstring.value = ROLE.sub(_role, obj.docstring.value)


def on_page_markdown(markdown: str, **kwargs: Any) -> str:
    return MARKER.sub(lambda m: readme_section(m["heading"], bool(m["intro"])), markdown)


def _undocumented() -> tuple[int, list[str]]:
    """Public functions, classes and methods of the documented modules that have no docstring
    (read as the API pages read them: physstep._core through its stub)."""
    loader = griffe.GriffeLoader(search_paths=[str(README.parent / "python")])
    package = loader.load("physstep")
    loader.resolve_aliases(implicit=False, external=False)
    seen, missing = set(), []

    def walk(obj: Any) -> None:
        for name, member in obj.members.items():
            if name.startswith("_"):
                continue
            try:
                target = member.final_target if member.is_alias else member
            except griffe.AliasResolutionError:
                continue
            if not target.path.startswith("physstep") or target.is_attribute or target.is_module:
                continue
            if target.path in seen:
                continue
            seen.add(target.path)
            if not target.docstring:
                missing.append(target.path)
            if target.is_class:
                walk(target)

    walk(package)
    for module in (
        "plot",
        "lab",
        "lab.compare",
        "lab.order",
        "lab.stability",
        "lab.sweep",
        "lab.reference",
        "lab.system",
        "lab.common",
        "lab.results",
        "lab.parallel",
    ):
        walk(package[module])
    return len(seen), missing


def on_post_build(**kwargs: Any) -> None:
    """A public object of the API pages without a docstring fails the build."""
    from mkdocs.exceptions import PluginError

    count, missing = _undocumented()
    if count < 100 or missing:
        raise PluginError(f"{count} API objects read; without a docstring: {', '.join(missing) or 'none'}")
