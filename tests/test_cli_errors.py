"""Error contracts of the command line: every flag error names the flag as typed and the
value, in one line; Ctrl-C is status 130 with one line; a closed pipe is quiet."""

from __future__ import annotations

import os
import signal
import subprocess
import sys

import physstep
import pytest
from conftest import run_cli, sigint_default
from physstep import cli
from physstep.cli import output


def _one_line(res: subprocess.CompletedProcess[str]) -> str:
    assert "Traceback" not in res.stderr
    lines = res.stderr.splitlines()
    assert len(lines) == 1, res.stderr
    return lines[0]


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["compare", "spring", "--dt", "0"], "invalid --dt '0': must be a finite number > 0"),
        (["compare", "spring", "--until", "-1"], "invalid --until '-1': must be a finite number >= 0"),
        (["compare", "spring", "--until", "1e999"], "invalid --until '1e999'"),
        (["order", "spring", "--method", "rk4", "--dt", "0"], "invalid --dt '0'"),
        (
            ["order", "spring", "--method", "rk4", "--until", "0"],
            "invalid --until '0': must be a finite number > 0",
        ),
        (
            ["order", "spring", "--method", "rk4", "--levels", "1"],
            "invalid --levels '1': must be an integer from 2",
        ),
        (["order", "spring", "--method", "rk4", "--levels", "40"], "invalid --levels '40'"),
        (["order", "spring", "--method", "rk4", "--levels", "x"], "invalid --levels 'x': not an integer"),
        (
            ["stability", "spring", "--method", "rk4", "--cap", "-1"],
            "invalid --cap '-1': must be a finite number > 0",
        ),
        (["stability", "spring", "--method", "rk4", "--cap", "inf"], "invalid --cap 'inf'"),
        (["sweep", "spring", "--dts", "0.1,-2"], "invalid --dts '0.1,-2': '-2' must be a finite number > 0"),
        (["sweep", "spring", "--dts", "nan"], "invalid --dts 'nan'"),
        (["sweep", "spring", "--dts", "0.1", "--until", "nan"], "invalid --until 'nan'"),
        (["run", "spring", "--every", "1e3"], "invalid --every '1e3': not an integer"),
        (
            ["run", "spring", "--every", "99999999999999999999999"],
            "invalid --every '99999999999999999999999'",
        ),
        (["table", "spring", "--decimals", "30"], "invalid --decimals '30': must be an integer from 0 to 17"),
        (["run", "spring", "--param", "k=inf"], "invalid --param 'k=inf'"),
        (["compare", "spring", "--methods", ""], "invalid --methods ''"),
        (["compare", "spring", "--methods", ","], "invalid --methods ','"),
        (["sweep", "spring", "--dts", "0.1", "--methods", " , "], "invalid --methods ' , '"),
    ],
)
def test_flag_errors_name_the_flag_and_value(args: list[str], needle: str) -> None:
    res = run_cli(*args)
    assert res.returncode == 2
    line = _one_line(res)
    assert line.startswith("physstep: error: ") and needle in line, line
    assert res.stdout == ""


@pytest.mark.parametrize(
    "args",
    [
        ["run", "spring", "--method", "rk4\nTraceback (most recent call last):"],
        ["run", "spr\ning"],
        ["compare", "spring", "--methods", "rk4,a\r\nb"],
        ["table", "spring", "--format", "x\ny"],
        ["run", "spring", "--param", "k\nx=1"],
    ],
)
def test_names_with_newlines_still_give_one_line(args: list[str]) -> None:
    res = run_cli(*args)
    assert res.returncode == 2
    assert len(res.stderr.splitlines()) == 1, res.stderr
    assert "\\n" in res.stderr and res.stderr.startswith("physstep: error: ")


def test_one_line_escapes_control_characters() -> None:
    assert output.one_line("a\nb\r\tc\x1b[31m") == "a\\nb\\r\\tc\\x1b[31m"
    assert output.one_line("héllo — ok") == "héllo — ok"


def test_keyboard_interrupt_is_130_with_one_line(monkeypatch, capsys) -> None:
    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(physstep, "simulate", interrupted)
    assert cli.main(["run", "spring"]) == 130
    assert capsys.readouterr().err == "physstep: interrupted\n"


#: The command line with a readiness line: "running" on stdout just before the run's
#: ``simulate`` is called.
_SAYS_WHEN_RUNNING = (
    "import sys, physstep\n"
    "from physstep import cli\n"
    "real = physstep.simulate\n"
    "def simulate(*args, **kwargs):\n"
    "    print('running', flush=True)\n"
    "    return real(*args, **kwargs)\n"
    "physstep.simulate = simulate\n"
    "sys.exit(cli.main(sys.argv[1:]))\n"
)


@pytest.mark.skipif(sys.platform == "win32", reason="SIGINT to a child process is POSIX")
def test_sigint_stops_a_long_run_with_status_130_and_one_line() -> None:
    # The signal is sent once the child says it is running, and the run cannot end by itself
    # (1e8 steps of 200 bodies): wherever the signal lands the run ends by it, with status
    # 130, one line on stderr and nothing printed of the run. (That the engine's own loop
    # sees Ctrl-C is held by test_threads_and_ctrl_c.py, with a readiness taken inside it.)
    env = dict(os.environ, MPLBACKEND="Agg")
    argv = ["run", "nbody", "--param", "n=200", "--dt", "0.001", "--until", "1e5", "--every", "1000000"]
    proc = subprocess.Popen(
        [sys.executable, "-c", _SAYS_WHEN_RUNNING, *argv],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
        preexec_fn=sigint_default,
    )
    try:
        assert proc.stdout is not None
        assert proc.stdout.readline() == "running\n"
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 130, err
    assert err == "physstep: interrupted\n"
    assert out == ""


def test_closed_pipe_is_quiet() -> None:
    # 100 001 rows: far more than a pipe buffer, so the writer meets the closed pipe
    env = dict(os.environ, MPLBACKEND="Agg")
    cmd = [sys.executable, "-m", "physstep", "table", "spring", "--dt", "0.001", "--until", "100"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env)
    assert proc.stdout is not None and proc.stderr is not None
    assert proc.stdout.readline().split() == [b"t", b"x", b"v", b"a"]
    proc.stdout.close()
    err = proc.stderr.read()
    assert proc.wait(timeout=120) == 0
    assert err == b""


def test_unexpected_exception_is_one_line(monkeypatch, capsys) -> None:
    def broken(*args, **kwargs):
        raise RuntimeError("boom\nsecond line")

    monkeypatch.setattr(physstep, "simulate", broken)
    assert cli.main(["run", "spring"]) == 1
    err = capsys.readouterr().err
    assert err == "physstep: internal error: RuntimeError: boom\\nsecond line (please report it)\n"


def test_a_scene_too_large_for_memory_is_refused_before_the_work() -> None:
    # stiff-cloth n = 100000 (1e10 particles) ran with growing memory; refused at once, exit
    # 2, one line naming the size. (The timeout bounds a hang, measures nothing.)
    r = subprocess.run(
        [sys.executable, "-m", "physstep", "run", "stiff-cloth", "--param", "n=100000"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert r.returncode == 2, r.stderr
    assert r.stderr == (
        "physstep: error: invalid n x n = 100000 x 100000: must be at most 1000000 particles\n"
    )
    assert r.stdout == ""


def test_a_dt_whose_reference_step_underflows_is_refused_in_one_line(capsys) -> None:
    # The smallest dt, refined for the reference run (dt / 16 or so), is 0: the run would
    # take infinitely many steps. It was a ZeroDivisionError, an internal error (found by
    # scripts/fuzz.sh, round 1, seed 1795842284: compare arch --dt=5e-324 --until=5e-324).
    assert cli.main(["compare", "arch", "--dt=5e-324", "--until=5e-324"]) == 2
    err = capsys.readouterr().err
    assert err == (
        "physstep: error: invalid until = 5e-324 with dt = 5e-324: the reference run would take inf"
        " steps (at most 1e+09); use a larger dt or a shorter until\n"
    )


def test_an_order_run_whose_finest_step_underflows_is_refused_naming_until_and_dt(capsys) -> None:
    # The halvings of dt = 5e-324 are 0: it said "invalid dt = 0", a dt the user never gave.
    assert cli.main(["order", "arch", "--method", "rk4", "--dt=5e-324", "--until=5e-324"]) == 2
    assert capsys.readouterr().err == (
        "physstep: error: invalid until = 5e-324 with dt = 5e-324: the finest run's step, until / 32,"
        " underflows to 0; use a larger until\n"
    )
