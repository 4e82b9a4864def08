"""The build backend: maturin's, but without a Rust toolchain it stops at its first hook with
one line naming what is needed and the wheel, instead of downloading a toolchain."""

from __future__ import annotations

import importlib
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture
def backend(monkeypatch: pytest.MonkeyPatch):  # noqa: ANN201
    monkeypatch.syspath_prepend(str(ROOT / "build_backend"))
    return importlib.import_module("physstep_build")


def test_the_backend_is_the_one_pyproject_names() -> None:
    text = (ROOT / "pyproject.toml").read_text()
    assert 'build-backend = "physstep_build"' in text
    assert 'backend-path = ["build_backend"]' in text


@pytest.mark.parametrize(
    "hook",
    [
        "get_requires_for_build_wheel",
        "get_requires_for_build_editable",
        "get_requires_for_build_sdist",
        "prepare_metadata_for_build_wheel",
        "prepare_metadata_for_build_editable",
        "build_wheel",
        "build_editable",
        "build_sdist",
    ],
)
def test_every_hook_stops_without_cargo(
    backend, monkeypatch: pytest.MonkeyPatch, tmp_path: Path, hook: str
) -> None:  # noqa: ANN001
    monkeypatch.setattr(shutil, "which", lambda name, *a, **k: None)
    args = [] if hook.startswith("get_requires") else [str(tmp_path)]
    with pytest.raises(SystemExit) as e:
        getattr(backend, hook)(*args)
    msg = str(e.value.code)
    assert msg.startswith("physstep: building from source needs a Rust toolchain (cargo on PATH")
    assert "pip install dist/physstep-*.whl" in msg and "\n" not in msg


def test_the_backend_never_lets_maturin_download_a_toolchain(backend) -> None:  # noqa: ANN001
    assert os.environ["MATURIN_NO_INSTALL_RUST"] == "1"
    # With cargo, the hooks are maturin's (no toolchain bootstrap among the requirements).
    if shutil.which("cargo") is not None:
        assert "puccinialin" not in backend.get_requires_for_build_wheel()


def test_pip_without_cargo_stops_with_the_line(tmp_path: Path) -> None:
    # The real thing, through pip's own subprocess: a PATH with no cargo or rustc.
    keep = [
        d
        for d in os.environ["PATH"].split(os.pathsep)
        if not any((Path(d) / t).exists() for t in ("cargo", "rustc"))
    ]
    env = {**os.environ, "PATH": os.pathsep.join([str(Path(sys.executable).parent), *keep])}
    r = subprocess.run(
        [sys.executable, "-m", "pip", "install", "--no-deps", "--no-build-isolation", "--dry-run", str(ROOT)],
        capture_output=True,
        text=True,
        env=env,
        cwd=tmp_path,
        timeout=300,
    )
    assert r.returncode != 0
    assert "physstep: building from source needs a Rust toolchain" in r.stdout + r.stderr
