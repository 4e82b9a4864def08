"""Ctrl-C while the ``physstep`` command is still loading (numpy, the engine) ends it with
``physstep: interrupted`` and status 130, not a traceback of the import under way; an
``import physstep`` in any other program leaves SIGINT alone."""

from __future__ import annotations

import signal
import subprocess
import sys
from pathlib import Path

import physstep

SCRIPT = """\
import os, signal, sys, time
import physstep._startup  # what the package imports first
os.kill(os.getpid(), signal.SIGINT)
time.sleep(10)  # the rest of the loading: the signal arrives here
print("not interrupted")
"""


def _run(tmp_path: Path, name: str) -> subprocess.CompletedProcess[str]:
    script = tmp_path / name
    script.write_text(SCRIPT)
    # SIGINT as a terminal gives it (a shell that started the tests in the background passes
    # it on ignored, and Python then installs no handler of its own)
    return subprocess.run(
        [sys.executable, str(script)],
        capture_output=True,
        text=True,
        timeout=60,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )


def test_ctrl_c_while_the_command_loads_is_one_line_and_status_130(tmp_path: Path) -> None:
    r = _run(tmp_path, "physstep")
    assert (r.returncode, r.stderr, r.stdout) == (130, "physstep: interrupted\n", "")


def test_another_program_keeps_python_s_own_ctrl_c(tmp_path: Path) -> None:
    r = _run(tmp_path, "game.py")
    assert r.returncode != 130 and "KeyboardInterrupt" in r.stderr
    # and in this process (pytest imported physstep): not the command's handler
    from physstep import _startup

    assert physstep.__name__ == "physstep"
    assert signal.getsignal(signal.SIGINT) is not _startup._interrupted


def test_the_command_hands_ctrl_c_back_to_python_once_loaded() -> None:
    from physstep import _startup

    signal.signal(signal.SIGINT, _startup._interrupted)
    try:
        _startup.loaded()
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    finally:
        signal.signal(signal.SIGINT, signal.default_int_handler)
