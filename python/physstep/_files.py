"""Output files that are either written whole or not at all.

:func:`check` is called before a computation, so that a bad ``--out`` or ``--plot`` fails
at once; :func:`write` writes a regular file through a temporary file beside it (flushed,
fsynced, then renamed over the target), so that a failed write (full disk, file-size
limit) leaves the old file in place and no partial file behind. A target that exists and
is not a regular file (``/dev/stdout``, ``/dev/full``, a FIFO) is written directly: a
device is never renamed over. Both raise :class:`OutputError` (a ValueError: the command
line's exit status 2) naming the flag and the path.
"""

from __future__ import annotations

import contextlib
import os
import stat
import tempfile
from collections.abc import Callable
from typing import BinaryIO

__all__ = ["OutputError", "check", "write", "write_text"]


class OutputError(ValueError):
    """An output file that cannot be written: ``invalid --out 'PATH': reason``."""


def _error(flag: str, path: str, reason: str) -> OutputError:
    return OutputError(f"invalid {flag} '{path}': {reason}")


def _reason(e: OSError) -> str:
    return e.strerror or str(e)


def _is_special(path: str) -> bool:
    """True if ``path`` exists and is not a regular file (a device, a FIFO, /proc/self/fd/1)."""
    try:
        return not stat.S_ISREG(os.stat(path).st_mode)
    except OSError:
        return False


def check(path: str, flag: str) -> None:
    """Raises OutputError unless ``path`` can be written: not a directory, its parent an
    existing, writable directory (a regular file is replaced, so its directory must be
    writable); an existing device or FIFO must be writable itself."""
    if not path:
        raise _error(flag, path, "empty file name")
    if path.endswith(("/", os.sep)):
        raise _error(flag, path, "names a directory, not a file")
    try:
        st = os.stat(path)
    except FileNotFoundError:
        st = None
    except OSError as e:  # a path below a regular file: ENOTDIR; a loop: ELOOP
        raise _error(flag, path, _reason(e)) from None
    if st is not None and stat.S_ISDIR(st.st_mode):
        raise _error(flag, path, "is a directory")
    if st is not None and not stat.S_ISREG(st.st_mode):
        if not os.access(path, os.W_OK):
            raise _error(flag, path, "permission denied")
        return
    if st is not None and not os.access(path, os.W_OK):
        raise _error(flag, path, "permission denied")
    parent = os.path.dirname(os.path.realpath(path)) or "."
    try:
        pst = os.stat(parent)
    except OSError as e:
        raise _error(flag, path, f"directory '{parent}': {_reason(e)}") from None
    if not stat.S_ISDIR(pst.st_mode):
        raise _error(flag, path, f"'{parent}' is not a directory")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise _error(flag, path, f"directory '{parent}' is not writable")


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write(path: str, fill: Callable[[BinaryIO], object], flag: str = "file") -> None:
    """Writes ``path`` with ``fill(fh)`` (``fh`` a binary file): whole or not at all.

    A regular (or missing) target is written through a temporary file in its directory,
    then renamed over it; it keeps its permissions (a new file gets 0666 less the umask).
    A symbolic link is followed, and the file it names is replaced. Raises OutputError
    naming ``flag`` and ``path`` on any OSError; the old file is then left as it was.
    """
    check(path, flag)
    if _is_special(path):
        try:
            with open(path, "wb") as fh:
                fill(fh)
        except OSError as e:
            raise _error(flag, path, _reason(e)) from None
        return
    target = os.path.realpath(path)
    directory, name = os.path.split(target)
    try:
        mode = stat.S_IMODE(os.stat(target).st_mode)
    except FileNotFoundError:
        mode = 0o666 & ~_umask()
    tmp = None
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{name}.", suffix=".tmp", dir=directory)
        with os.fdopen(fd, "wb") as fh:
            fill(fh)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, mode)
        os.replace(tmp, target)
        tmp = None
    except OSError as e:
        raise _error(flag, path, _reason(e)) from None
    finally:
        if tmp is not None:
            with contextlib.suppress(OSError):
                os.unlink(tmp)


def write_text(path: str, text: str, flag: str = "file") -> None:
    """Writes ``text`` (UTF-8) to ``path`` as :func:`write` does."""
    data = text.encode()
    write(path, lambda fh: fh.write(data), flag)
