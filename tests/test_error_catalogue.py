"""docs/errors.md, the catalogue of every error message: each names the tests that trigger
it, and every test it names exists (in the file it names, when it names one)."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def _defines(source: str, name: str) -> bool:
    return re.search(rf"(?:fn|def) {name}\b", source) is not None


def test_every_test_the_error_catalogue_names_exists_where_it_says() -> None:
    text = (ROOT / "docs" / "errors.md").read_text()
    sources = [p.read_text() for p in [*ROOT.glob("tests/*.py"), *ROOT.glob("crates/physstep/**/*.rs")]]
    # `path/to/file.rs::name`: the name in that file
    placed = re.findall(r"`([\w/.]+\.(?:rs|py))::(\w+)`", text)
    wrong = [
        f"{p}::{n}" for p, n in placed if not (ROOT / p).is_file() or not _defines((ROOT / p).read_text(), n)
    ]
    # a bare `name` of a test: anywhere
    bare = set(re.findall(r"`((?:test)_\w+|\w+_is_\w+|\w+_names?_\w+)`", text))
    missing = [n for n in sorted(bare) if not any(_defines(s, n) for s in sources)]
    assert len(placed) + len(bare) > 30
    assert not wrong, wrong
    assert not missing, missing
