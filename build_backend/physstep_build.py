"""physstep's build backend: maturin's own (PEP 517 / 660), refusing to start without a Rust
toolchain instead of downloading one.

maturin's backend installs Rust into a temporary directory when `cargo` is not on PATH and
then compiles for minutes without a word. Building physstep from source needs a Rust
toolchain; without one, this backend stops at its first hook with one line saying so and
where the prebuilt wheel is (`scripts/build-wheel.sh` makes it; README, "Install from a
wheel"). Every hook is maturin's, called after that check.
"""

from __future__ import annotations

import os
import shutil
from collections.abc import Mapping
from typing import Any

import maturin

# maturin reads this when a hook runs: never bootstrap a toolchain of its own.
os.environ["MATURIN_NO_INSTALL_RUST"] = "1"

NO_CARGO = (
    "physstep: building from source needs a Rust toolchain (cargo on PATH: https://rustup.rs); "
    "without one, install the prebuilt wheel: pip install dist/physstep-*.whl "
    "(made by scripts/build-wheel.sh on a machine with Rust)"
)


def _need_cargo() -> None:
    if shutil.which("cargo") is None:
        raise SystemExit(NO_CARGO)


Config = Mapping[str, Any] | None


def get_requires_for_build_wheel(config_settings: Config = None) -> list[str]:
    _need_cargo()
    return maturin.get_requires_for_build_wheel(config_settings)


def get_requires_for_build_editable(config_settings: Config = None) -> list[str]:
    _need_cargo()
    return maturin.get_requires_for_build_wheel(config_settings)


def get_requires_for_build_sdist(config_settings: Config = None) -> list[str]:
    _need_cargo()
    return maturin.get_requires_for_build_sdist(config_settings)


def prepare_metadata_for_build_wheel(metadata_directory: str, config_settings: Config = None) -> str:
    _need_cargo()
    return maturin.prepare_metadata_for_build_wheel(metadata_directory, config_settings)


def prepare_metadata_for_build_editable(metadata_directory: str, config_settings: Config = None) -> str:
    _need_cargo()
    return maturin.prepare_metadata_for_build_wheel(metadata_directory, config_settings)


def build_wheel(
    wheel_directory: str, config_settings: Config = None, metadata_directory: str | None = None
) -> str:
    _need_cargo()
    return maturin.build_wheel(wheel_directory, config_settings, metadata_directory)


def build_editable(
    wheel_directory: str, config_settings: Config = None, metadata_directory: str | None = None
) -> str:
    _need_cargo()
    return maturin.build_editable(wheel_directory, config_settings, metadata_directory)


def build_sdist(sdist_directory: str, config_settings: Config = None) -> str:
    _need_cargo()
    return maturin.build_sdist(sdist_directory, config_settings)
