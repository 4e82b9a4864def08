"""The ``physstep`` command line.

Every command takes ``--format json``. Bad input (a flag's value, an output file that
cannot be written) exits with status 2 and one line on stderr (``physstep: error: invalid
--FLAG 'VALUE': ...``), never a traceback; a diverging run exits with status 1, and so does
a non-finite number about to be printed (JSON is strict: no NaN or Infinity); Ctrl-C exits
with status 130 (``physstep: interrupted``). Output files are written whole or not at all
(:mod:`physstep._files`).

The modules import one way: :mod:`~physstep.cli.app` (parser, ``main``, exit statuses)
imports the commands, :mod:`~physstep.cli.basic` (``methods``, ``solvers``, ``scenes``, ``table``,
``run``), :mod:`~physstep.cli.lab` (``compare``, ``order``, ``stability``, ``sweep``) and
:mod:`~physstep.cli.demo` (``demo``: the interactive demos of :mod:`physstep.demos`),
which import :mod:`~physstep.cli.options` (flags and their checks),
:mod:`~physstep.cli.output` (printing) and :mod:`~physstep._files` (writing), which
import only :mod:`physstep`.
"""

from physstep.cli.app import main, parser

__all__ = ["main", "parser"]
