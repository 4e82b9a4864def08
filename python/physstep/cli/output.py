"""What the commands print: strict JSON, CSV, aligned text tables and rounded numbers.

No non-finite number is ever printed: :func:`finite` and :func:`check_rows` raise
:class:`NotFiniteError` (exit status 1) naming the field first, and JSON is strict (no NaN
or Infinity token). Text that came from elsewhere (an error message, a method's note) goes
through :func:`one_line`, so that it cannot break a line or carry a terminal escape.
"""

from __future__ import annotations

import csv
import io
import json
import math
import numbers
from collections.abc import Iterable
from decimal import ROUND_HALF_UP, Decimal, localcontext
from typing import Any


class StdoutError(Exception):
    """Standard output could not be written (a full disk, ``> /dev/full``, a file-size limit):
    ``reason`` says why. A closed pipe is not one (BrokenPipeError, quiet)."""

    def __init__(self, reason: str) -> None:
        super().__init__(reason)
        self.reason = reason


class GuardedStdout:
    """``stream`` (sys.stdout) whose ``write`` and ``flush`` raise :class:`StdoutError` for an
    OSError but a broken pipe: so that a failed write is told apart from a failure of
    anything else (an OSError elsewhere is a bug: an internal error)."""

    def __init__(self, stream: Any) -> None:
        self._stream = stream

    def write(self, text: str) -> int:
        """Writes ``text``; StdoutError when the stream fails."""
        try:
            return self._stream.write(text)
        except BrokenPipeError:
            raise
        except OSError as e:
            raise StdoutError(e.strerror or str(e)) from None

    def flush(self) -> None:
        """Flushes; StdoutError when the stream fails."""
        try:
            self._stream.flush()
        except BrokenPipeError:
            raise
        except OSError as e:
            raise StdoutError(e.strerror or str(e)) from None

    def __getattr__(self, name: str) -> Any:
        return getattr(self._stream, name)


class NotFiniteError(Exception):
    """A non-finite number about to be printed or written (exit status 1): never printed."""


def one_line(text: str) -> str:
    """``text`` with newlines and other control characters escaped, so it prints as one line."""
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in str(text))


def finite(obj: Any, where: str = "") -> Any:
    """``obj`` (nested dicts and lists) unchanged; NotFiniteError naming the first field that
    holds a NaN or an infinity (``rows[1].energy_drift``)."""
    if isinstance(obj, dict):
        for k, v in obj.items():
            finite(v, f"{where}.{k}" if where else str(k))
    elif isinstance(obj, (list, tuple)):
        for i, v in enumerate(obj):
            finite(v, f"{where}[{i}]")
    elif hasattr(obj, "ndim") and hasattr(obj, "tolist") and getattr(obj, "ndim", 0) > 0:  # numpy arrays
        finite(obj.tolist(), where)
    elif isinstance(obj, numbers.Real) and not isinstance(obj, numbers.Integral):
        if not math.isfinite(float(obj)):
            raise NotFiniteError(f"{where or 'value'} is not finite ({float(obj)}): not printed")
    return obj


def check_rows(header: list[str], rows: Iterable[list[Any]]) -> None:
    """NotFiniteError naming the column and time (the first cell) of the first non-finite
    number in ``rows``."""
    for r in rows:
        for name, c in zip(header, r, strict=False):
            if isinstance(c, float) and not math.isfinite(c):
                raise NotFiniteError(f"{name} at t = {r[0]:.10g} s is not finite ({c}): not printed")


def _json_default(obj: Any) -> Any:
    if hasattr(obj, "tolist"):  # numpy scalars and arrays
        return obj.tolist()
    raise TypeError(f"{type(obj).__name__} is not JSON serializable")


def dump(obj: Any) -> str:
    """Strict JSON (no NaN or Infinity token: NotFiniteError naming the field instead)."""
    finite(obj)
    return json.dumps(obj, indent=2, allow_nan=False, default=_json_default)


def round_half_away(value: float, places: int = 1) -> str:
    """``value`` rounded half away from zero on the exact double, as the notes print it.

    Works for every finite double and any ``places`` >= 0 (the arithmetic is exact: its
    precision grows with the value's magnitude and ``places``); negative zero prints as
    zero. Raises ValueError for a non-finite value or negative ``places``.
    """
    if not math.isfinite(value):
        raise ValueError(f"invalid value = {value}: not a finite number")
    if places < 0:
        raise ValueError(f"invalid places = {places}: must be >= 0")
    exact = Decimal(value)
    with localcontext() as ctx:
        ctx.prec = max(28, exact.adjusted() + places + 3)
        q = exact.quantize(Decimal(1).scaleb(-places), rounding=ROUND_HALF_UP)
        if q.is_zero():
            q = abs(q)
        return f"{q:.{places}f}"


def number(x: float | None, spec: str = ".3g") -> str:
    """``x`` formatted with ``spec``, ``-`` for None; NotFiniteError for a NaN or an infinity
    (:func:`finite` has run before: a guard, never reached)."""
    if x is None:
        return "-"
    if isinstance(x, float) and not math.isfinite(x):
        raise NotFiniteError(f"non-finite value {x} in the text output: not printed")
    return format(x, spec)


def csv_text(rows: Iterable[list[Any]]) -> str:
    """``rows`` (the header first) as CSV text, one ``\\n`` per row; cells printed by ``str``."""
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerows(rows)
    return buf.getvalue()


def aligned(rows: list[list[str]]) -> str:
    """``rows`` (the header first) as text, each column right-aligned, two spaces apart."""
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    return "\n".join("  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)) for r in rows)


def reached(until: float, steps: int, dt: float, t_end: float) -> str | None:
    """None when the run reached ``until`` (s); otherwise the sentence saying what was run."""
    if abs(t_end - until) <= 1e-9 * max(abs(until), dt):
        return None
    return f"until {until:.10g} s requested: {steps} steps of {dt:g} s reach t = {t_end:.10g} s"


def console() -> Any:
    """A rich console at least 120 columns wide (tables fold rather than wrap)."""
    from rich.console import Console

    return Console(width=max(120, Console().width))
