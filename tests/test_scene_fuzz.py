"""Fuzzing physstep.load_scene (hypothesis): any text, and files put together from the
schema's keys and values, either load into a World that steps or raise one ValueError line
naming the scene file. In the ``long`` profile with ``scripts/fuzz.sh``; crashes found go to
the end of this file as regression cases."""

from __future__ import annotations

import tempfile
from pathlib import Path

import physstep
from hypothesis import given
from hypothesis import strategies as st
from test_properties import fuzz

_DIR = Path(tempfile.mkdtemp(prefix="physstep-scene-fuzz-"))


@fuzz(100)
@given(st.text(max_size=300))
def test_fuzz_any_text_loads_or_is_one_line_value_error(text: str) -> None:
    p = _DIR / "f.toml"
    p.write_text(text, encoding="utf-8")
    try:
        physstep.load_scene(p)
    except ValueError as e:
        assert "\n" not in str(e)
        assert str(e).startswith("scene file ")


_KEYS = [
    "dimension",
    "dt",
    "method",
    "until",
    "particles",
    "springs",
    "constraints",
    "forces",
    "mass",
    "i",
    "j",
]
_VALUES = [
    "1",
    "2",
    "3",
    "-1",
    "0.5",
    "inf",
    "nan",
    '"rk4"',
    "[0.0, 1.0]",
    "[1]",
    "true",
    "{}",
    "[[0, 1, 2]]",
]


@fuzz(100)
@given(
    st.lists(st.tuples(st.sampled_from(_KEYS), st.sampled_from(_VALUES)), max_size=6),
    st.lists(
        st.tuples(
            st.sampled_from(["particles", "springs", "constraints", "forces", "bodies"]),
            st.lists(
                st.tuples(
                    st.sampled_from([*_KEYS, "kind", "position", "stiffness", "length"]),
                    st.sampled_from([*_VALUES, '"pin"', '"gravity"', '"distance"']),
                ),
                max_size=4,
            ),
        ),
        max_size=4,
    ),
)
def test_fuzz_structured_files_load_or_are_one_line_value_errors(top: list, tables: list) -> None:
    lines = ["dimension = 2"] + [f"{k} = {v}" for k, v in dict(top).items() if k != "dimension"]
    for name, fields in tables:
        lines.append(f"[[{name}]]")
        lines += [f"{k} = {v}" for k, v in dict(fields).items()]
    p = _DIR / "f.toml"
    p.write_text("\n".join(lines) + "\n")
    try:
        w = physstep.load_scene(p)
    except ValueError as e:
        assert "\n" not in str(e) and str(e).startswith("scene file "), str(e)
        return
    try:
        w.step(3)
    except (ValueError, physstep.StepError):
        pass


def test_regressions_stay_fixed() -> None:
    """Inputs that once misbehaved (none yet from the Python side: the Rust proptest's are in
    crates/physstep/tests/it/scene_fuzz.rs)."""
    for text in ["dimension = 99999999999999999999\n", "dimension = 2\nconstraint_iterations = 5000000000\n"]:
        p = _DIR / "r.toml"
        p.write_text(text)
        try:
            physstep.load_scene(p)
        except ValueError as e:
            assert "\n" not in str(e)
