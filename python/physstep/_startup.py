"""Ctrl-C while the ``physstep`` command is still loading (numpy, the engine: a few tenths of
a second) ends it as Ctrl-C does later: ``physstep: interrupted`` and exit status 130, not a
traceback of the import under way.

Imported first by the package, before numpy, and only stdlib itself. It acts only in the
``physstep`` command's own process (the console script: ``sys.argv[0]`` is the ``physstep``
script that ``__main__`` runs); an ``import physstep`` anywhere else leaves SIGINT alone.
The command's ``main`` hands SIGINT back to Python (:func:`loaded`) before it starts work, so
a Ctrl-C from then on is the KeyboardInterrupt it reports.
"""

from __future__ import annotations

import os
import signal
import sys


def _is_the_command() -> bool:
    main = sys.modules.get("__main__")
    script = getattr(main, "__file__", None)
    name = os.path.basename(sys.argv[0]) if sys.argv and sys.argv[0] else ""
    return script is not None and name in ("physstep", "physstep.exe") and os.path.basename(script) == name


def _interrupted(signum: int, frame: object) -> None:
    try:
        os.write(2, b"physstep: interrupted\n")
    finally:
        os._exit(130)


def quiet_interrupt_while_the_cli_loads() -> None:
    """In the ``physstep`` command's process, until :func:`loaded`: Ctrl-C exits 130 at once."""
    if _is_the_command() and signal.getsignal(signal.SIGINT) is signal.default_int_handler:
        signal.signal(signal.SIGINT, _interrupted)


def loaded() -> None:
    """The command is loaded: Ctrl-C is Python's KeyboardInterrupt again (if it was ours)."""
    if signal.getsignal(signal.SIGINT) is _interrupted:
        signal.signal(signal.SIGINT, signal.default_int_handler)


quiet_interrupt_while_the_cli_loads()
