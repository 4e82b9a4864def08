"""The parser of every command, :func:`main`, and the exit statuses.

``main`` maps what a command raises to one line on stderr and a status: 0 done, 1 a failed
run (:class:`physstep.StepError`, a diverged ``table``) or a non-finite number about to be
printed (:class:`~physstep.cli.output.NotFiniteError`), 2 bad input (any ValueError: a
flag's value, an output file that cannot be written, an output that is an input) or a
stdout that cannot be written (:class:`~physstep.cli.output.StdoutError`), 130
interrupted; anything else is an internal error, still one line (status 1).
"""

from __future__ import annotations

import argparse
import os
import re
import sys
import warnings
from typing import NoReturn

import physstep
from physstep.cli import basic, demo, lab, options, output
from physstep.cli.options import UsageError


class _Parser(argparse.ArgumentParser):
    """argparse that reports errors in one line and exits with status 2."""

    def error(self, message: str) -> NoReturn:
        """Raises UsageError with ``message`` (the flag named once, as its check wrote it)."""
        # "argument --dt: invalid --dt '0': ..." from the type functions: the flag once
        m = re.match(r"argument [^:]+: (invalid --.*)", message, re.DOTALL)
        raise UsageError(m.group(1) if m else message)


def parser() -> argparse.ArgumentParser:
    """The argument parser of every command (``--version`` exits 0 as ``--help`` does)."""
    p = _Parser(prog="physstep", description="Game-physics integration engine and integrator lab.")
    p.add_argument("--version", action="version", version=f"physstep {physstep.__version__}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)
    basic.register(sub)
    lab.register(sub)
    demo.register(sub)
    return p


def _say(message: str) -> None:
    try:
        print(f"physstep: {output.one_line(message)}", file=sys.stderr)
    except OSError:  # stderr closed: nothing left to tell
        pass


def _silence_stdout() -> None:
    """Points stdout at /dev/null so that the interpreter's final flush after a closed
    pipe (``physstep ... | head -1``) neither fails nor prints."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):
        pass


def main(argv: list[str] | None = None) -> int:
    """Runs the command line; returns the exit status (0 done, 1 a step that failed otherwise
    (Newton did not converge, contacts did not end) or a non-finite number about to be
    printed, 2 bad input or an output that cannot be written (a file, or stdout itself), 3
    a step that diverged (rolled back and reported: step, particle, method), 130
    interrupted).

    ``--help`` and ``--version`` print and raise SystemExit(0), as argparse does.
    """
    from physstep import _startup

    _startup.loaded()
    stdout = sys.stdout
    if stdout is not None:
        sys.stdout = output.GuardedStdout(stdout)  # type: ignore[assignment]
    try:
        return _run(argv)
    finally:
        sys.stdout = stdout


def _run(argv: list[str] | None) -> int:
    try:
        args = parser().parse_args(argv)
        options.check_paths(args)
        with warnings.catch_warnings():
            # (a Python warning is two lines on stderr: run gives constraints that cannot
            # all be met as a line of its summary instead)
            warnings.filterwarnings("ignore", category=physstep.ConstraintWarning)
            options.resolve_scene(args)
            status = int(args.func(args))
        sys.stdout.flush()
        return status
    except BrokenPipeError:
        _silence_stdout()
        return 0
    except output.StdoutError as e:
        # Status 2, as for an --out file that cannot be written: the output was refused,
        # not the run. What is left in the buffer is dropped (the exit's flush would fail).
        _silence_stdout()
        _say(f"error: cannot write to stdout: {e.reason}")
        return 2
    except KeyboardInterrupt:
        _say("interrupted")
        return 130
    except (ValueError, OverflowError) as e:
        _say(f"error: {e}")
        return 2
    except physstep.DivergedError as e:
        _say(str(e))
        return 3
    except (physstep.StepError, output.NotFiniteError) as e:
        _say(str(e))
        return 1
    except Exception as e:  # the contract is one line, never a traceback
        _say(f"internal error: {type(e).__name__}: {e} (please report it)")
        return 1
