"""Shared pytest helpers: run the command line as a user would."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
GOLDEN = ROOT / "crates" / "physstep" / "tests" / "golden"


def sigint_default() -> None:
    """For ``preexec_fn``: the child takes SIGINT as a fresh process does. A shell runs a
    background job with SIGINT ignored, and children inherit that (Python then installs no
    KeyboardInterrupt handler): a CI started in the background must not make Ctrl-C tests hang."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def run_cli(*args: str) -> subprocess.CompletedProcess[str]:
    env = dict(os.environ, MPLBACKEND="Agg", COLUMNS="200")
    return subprocess.run(
        [sys.executable, "-m", "physstep", *args], capture_output=True, text=True, env=env, timeout=300
    )


@pytest.fixture
def cli():
    return run_cli
