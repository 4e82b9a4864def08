"""The ``physstep`` command line.

Every command takes ``--format json``. Bad input (a flag's value, an output file that
cannot be written) exits with status 2 and one line on stderr (``physstep: error: invalid
--FLAG 'VALUE': ...``), never a traceback; a diverging run exits with status 1, and so does
a non-finite number about to be printed (JSON is strict: no NaN or Infinity); Ctrl-C exits
with status 130 (``physstep: interrupted``). Output files are written whole or not at all
(:mod:`physstep._files`).
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import math
import numbers
import os
import re
import statistics
import sys
from collections.abc import Callable
from decimal import ROUND_HALF_UP, Decimal, localcontext
from typing import Any, NoReturn

import physstep
from physstep import _files


class UsageError(ValueError):
    """Bad command-line input (exit status 2)."""


class NotFiniteError(Exception):
    """A non-finite number about to be printed or written (exit status 1): never printed."""


#: The most decimals ``table`` prints: 17 significant digits round-trip any double, and the
#: CSV output (``--format csv``) prints every digit.
MAX_DECIMALS = 17
#: The most step sizes ``order --levels`` runs (the finest run is 2**(levels-1) times finer).
MAX_LEVELS = 12
#: The largest ``run --every``.
MAX_EVERY = 10**9


def _argument(
    flag: str, kind: type = float, *, low: float, open_low: bool = False, high: float = math.inf
) -> Callable[[str], Any]:
    """An argparse ``type`` for ``flag``: a finite ``kind`` (float or int) in [low, high]
    (``open_low``: > low); a bad value is one line naming the flag and the value as typed."""

    integer = kind is int

    def show(bound: float) -> str:
        return str(int(bound)) if integer else f"{bound:g}"

    def parse(text: str) -> Any:
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"invalid {flag} '{text}': not {'an integer' if integer else 'a number'}"
            ) from None
        finite = integer or math.isfinite(value)  # (an int may be too large for a float)
        if not (finite and (value > low if open_low else value >= low) and value <= high):
            what = "an integer" if integer else "a finite number"
            cmp = ">" if open_low else ">="
            bound = f"from {show(low)} to {show(high)}" if high < math.inf else f"{cmp} {show(low)}"
            raise argparse.ArgumentTypeError(f"invalid {flag} '{text}': must be {what} {bound}")
        return value

    parse.__name__ = flag.lstrip("-")
    return parse


class _Parser(argparse.ArgumentParser):
    """argparse that reports errors in one line and exits with status 2."""

    def error(self, message: str) -> NoReturn:
        # "argument --dt: invalid --dt '0': ..." from the type functions: the flag once
        m = re.match(r"argument [^:]+: (invalid --.*)", message, re.DOTALL)
        raise UsageError(m.group(1) if m else message)


def parse_params(items: list[str] | None) -> dict[str, float]:
    """``["k=5", "m=2"]`` as ``{"k": 5.0, "m": 2.0}``; UsageError naming a malformed item."""
    out: dict[str, float] = {}
    for item in items or []:
        name, sep, value = item.partition("=")
        if not sep or not name.strip():
            raise UsageError(f"invalid --param '{item}': must be NAME=VALUE")
        try:
            number = float(value)
        except ValueError:
            raise UsageError(f"invalid --param '{item}': value '{value}' is not a number") from None
        if not math.isfinite(number):
            raise UsageError(f"invalid --param '{item}': value '{value}' is not a finite number")
        out[name.strip()] = number
    return out


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


def _json_default(obj: Any) -> Any:
    if hasattr(obj, "tolist"):  # numpy scalars and arrays
        return obj.tolist()
    raise TypeError(f"{type(obj).__name__} is not JSON serializable")


def dump(obj: Any) -> str:
    """Strict JSON (no NaN or Infinity token: NotFiniteError naming the field instead)."""
    finite(obj)
    return json.dumps(obj, indent=2, allow_nan=False, default=_json_default)


def requested_until(scene: str, until: float | None) -> float:
    """The end time the user asked for: ``--until`` or the scene's default."""
    return float(physstep.scene(scene)["until"] if until is None else until)


def reached(until: float, steps: int, dt: float, t_end: float) -> str | None:
    """None when the run reached ``until``; otherwise the sentence saying what was run."""
    if abs(t_end - until) <= 1e-9 * max(abs(until), dt):
        return None
    return f"until {until:.10g} s requested: {steps} steps of {dt:g} s reach t = {t_end:.10g} s"


def _cmd_methods(args: argparse.Namespace) -> int:
    rows = [m.__dict__ for m in physstep.methods()]
    if args.format == "json":
        print(dump(rows))
        return 0
    from rich.console import Console
    from rich.table import Table

    table = Table(title="physstep integrators")
    for col in ("name", "order", "symplectic", "implicit", "evals", "doc"):
        table.add_column(col, overflow="fold")
    for r in rows:
        table.add_row(
            r["name"],
            str(r["order"]),
            "yes" if r["symplectic"] else "no",
            "yes" if r["implicit"] else "no",
            str(r["evals"]),
            r["doc"],
        )
    Console(width=max(120, Console().width)).print(table)
    return 0


def _cmd_scenes(args: argparse.Namespace) -> int:
    rows = physstep.scenes()
    if args.format == "json":
        print(dump(rows))
        return 0
    for s in rows:
        params = ", ".join(f"{p['name']}={p['default']:g}" for p in s["params"])
        print(f"{s['name']:<11} {s['dim']}D  dt={s['dt']:g} until={s['until']:.4g}  {s['doc']}")
        print(f"{'':<15}params: {params}")
    return 0


def _columns(traj: physstep.Trajectory) -> list[str]:
    """Column names of a run's state: x, v, a of particles; y and dy of a flow."""
    n = traj.x.shape[1]
    names = ("y", "dy") if traj.kind == "flow" else ("x", "v", "a")
    if n == 1:
        return list(names)
    return [f"{q}{i}" for q in names for i in range(n)]


def _table_rows(traj: physstep.Trajectory, stages: bool) -> list[list[Any]]:
    rows: list[list[Any]] = []
    by_step: dict[int, list[Any]] = {}
    for k, stage, t, x, v, a in traj.stages or []:
        by_step.setdefault(k, []).append([t, *x, *v, *a, stage])
    for k in range(len(traj.t)):
        row = [float(traj.t[k]), *traj.x[k].tolist(), *traj.v[k].tolist(), *traj.a[k].tolist()]
        rows.append([*row, "state"] if stages else row)
        rows.extend(by_step.get(k, []))
    return rows


def _check_rows(header: list[str], rows: list[list[Any]]) -> None:
    """NotFiniteError naming the column and time of the first non-finite number in ``rows``."""
    for r in rows:
        for name, c in zip(header, r, strict=False):
            if isinstance(c, float) and not math.isfinite(c):
                raise NotFiniteError(f"{name} at t = {r[0]:.10g} s is not finite ({c}): not printed")


def _cmd_table(args: argparse.Namespace) -> int:
    traj = physstep.simulate(
        args.scene, args.method, args.dt, args.until, parse_params(args.param), stages=args.stages
    )
    until = requested_until(args.scene, args.until)
    t_end = float(traj.t[-1])
    header = ["t", *_columns(traj)] + (["stage"] if args.stages else [])
    rows = _table_rows(traj, args.stages)
    _check_rows(header, rows)
    if args.format == "json":
        print(
            dump(
                {
                    "scene": traj.scene,
                    "method": traj.method,
                    "dt": traj.dt,
                    "until": until,
                    "steps": int(traj.steps),
                    "t_end": t_end,
                    "columns": header,
                    "rows": rows,
                }
            )
        )
    elif args.format == "csv":
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow(header)
        for r in rows:
            w.writerow([repr(c) if isinstance(c, float) else c for c in r])
        sys.stdout.write(buf.getvalue())
    else:
        cells = [header] + [
            [
                (round_half_away(c, args.decimals) if i > 0 else f"{c:g}") if isinstance(c, float) else c
                for i, c in enumerate(r)
            ]
            for r in rows
        ]
        widths = [max(len(str(r[i])) for r in cells) for i in range(len(header))]
        for r in cells:
            print("  ".join(str(c).rjust(w) for c, w in zip(r, widths, strict=True)))
        note = reached(until, traj.steps, traj.dt, t_end)
        if note:
            print(f"note: {note}")
    if traj.diverged:
        print(f"physstep: {one_line(traj.diverged)}", file=sys.stderr)
        return 1
    return 0


#: A run faster than this (s) is timed again, ns/step being the median of TIMING_RUNS runs.
TIMING_MIN_S = 0.2
TIMING_RUNS = 5


def _trajectory_csv(traj: physstep.Trajectory) -> str:
    energy = [] if traj.energy is None else ["energy"]
    header = ["t", *_columns(traj), *energy]
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    for k in range(len(traj.t)):
        e = [] if traj.energy is None else [traj.energy[k]]
        row = [float(c) for c in [traj.t[k], *traj.x[k], *traj.v[k], *traj.a[k], *e]]
        _check_rows(header, [row])
        w.writerow([repr(c) for c in row])
    return buf.getvalue()


def _cmd_run(args: argparse.Namespace) -> int:
    if args.out is not None:
        _files.check(args.out, "--out")
    params = parse_params(args.param)

    def once() -> physstep.Trajectory:
        return physstep.simulate(args.scene, args.method, args.dt, args.until, params, every=args.every)

    traj = once()
    timings = [traj.ns_per_step]
    if traj.elapsed_ns * 1e-9 < TIMING_MIN_S:
        timings += [once().ns_per_step for _ in range(TIMING_RUNS - 1)]
    summary = physstep.summarize(traj)
    until = requested_until(args.scene, args.until)
    summary["until"] = until
    summary["ns_per_step"] = statistics.median(timings)
    summary["ns_per_step_runs"] = len(timings)
    finite(summary)
    if args.out is not None:
        _files.write_text(args.out, _trajectory_csv(traj), "--out")
        summary["out"] = args.out
    if args.format == "json":
        print(dump(summary))
        return 0
    from rich.console import Console
    from rich.table import Table

    table = Table(title=f"{traj.scene} with {traj.method}, dt = {traj.dt:g}", show_header=False)
    table.add_column("", style="bold")
    table.add_column("")
    table.add_row("steps", f"{summary['steps']} (t = {summary['t']:.10g} s)")
    note = reached(until, summary["steps"], traj.dt, summary["t"])
    if note:
        table.add_row("note", note)
    table.add_row("params", ", ".join(f"{k}={v:g}" for k, v in summary["params"].items()))
    table.add_row("final x", ", ".join(f"{c:.6g}" for c in summary["final"]["x"]))
    table.add_row("final v", ", ".join(f"{c:.6g}" for c in summary["final"]["v"]))
    en = summary["energy"]
    if en is None:
        table.add_row(
            "energy", f"unknown ({'a flow has none' if traj.kind == 'flow' else 'a force has no potential'})"
        )
    else:
        table.add_row(
            "energy", f"{en['initial']:.6g} -> {en['final']:.6g} J (max rel. error {en['max_rel_error']:.3g})"
        )
    if "error" in summary:
        table.add_row("position error", f"{summary['error']['final_position']:.3g} m at the end (vs exact)")
    runs = len(timings)
    timing = "one run" if runs == 1 else f"median of {runs} runs"
    table.add_row(
        "cost", f"{summary['evals']} force evaluations, {summary['ns_per_step']:.0f} ns/step ({timing})"
    )
    if args.out:
        table.add_row("trajectory", args.out)
    Console().print(table)
    return 0


def _add_common(p: argparse.ArgumentParser, *, formats: tuple[str, ...] = ("text", "json")) -> None:
    p.add_argument("--format", choices=formats, default="text", help="output format (default: text)")


def _add_run_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("scene", help="built-in scene (physstep scenes lists them)")
    p.add_argument("--method", default="symplectic-euler", help="integrator (physstep methods lists them)")
    p.add_argument(
        "--dt",
        type=_argument("--dt", low=0, open_low=True),
        default=None,
        help="step, s (default: the scene's)",
    )
    p.add_argument(
        "--until",
        type=_argument("--until", low=0),
        default=None,
        help="end time, s (default: the scene's); a whole number of steps is run, the output says "
        "where the last one ends",
    )
    p.add_argument("--param", action="append", metavar="NAME=VALUE", help="override a scene parameter")


def parser() -> argparse.ArgumentParser:
    """The argument parser of every command."""
    p = _Parser(prog="physstep", description="Game-physics integration engine and integrator lab.")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)

    m = sub.add_parser("methods", help="list the integrators")
    _add_common(m)
    m.set_defaults(func=_cmd_methods)

    s = sub.add_parser("scenes", help="list the built-in scenes and their parameters")
    _add_common(s)
    s.set_defaults(func=_cmd_scenes)

    t = sub.add_parser("table", help="the state at every step, as the notes print it")
    _add_run_args(t)
    t.add_argument("--stages", action="store_true", help="also print intermediate evaluation points")
    t.add_argument(
        "--decimals",
        type=_argument("--decimals", int, low=0, high=MAX_DECIMALS),
        default=1,
        help=f"decimals of the text output, 0 to {MAX_DECIMALS} (default 1; --format csv prints every digit)",
    )
    _add_common(t, formats=("text", "csv", "json"))
    t.set_defaults(func=_cmd_table)

    r = sub.add_parser("run", help="run a scene and summarise energy and error")
    _add_run_args(r)
    r.add_argument("--out", metavar="FILE.csv", help="write the trajectory as CSV")
    r.add_argument(
        "--every",
        type=_argument("--every", int, low=1, high=MAX_EVERY),
        default=1,
        metavar="N",
        help="record every N-th step (energy error over those)",
    )
    _add_common(r)
    r.set_defaults(func=_cmd_run)

    from physstep import lab_cli

    lab_cli.register(sub)
    return p


def _say(message: str) -> None:
    try:
        print(f"physstep: {one_line(message)}", file=sys.stderr)
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
    """Runs the command line; returns the exit status (0 done, 1 a failed or non-finite
    run, 2 bad input or an output file that cannot be written, 130 interrupted)."""
    try:
        args = parser().parse_args(argv)
        status = int(args.func(args))
        sys.stdout.flush()
        return status
    except BrokenPipeError:
        _silence_stdout()
        return 0
    except KeyboardInterrupt:
        _say("interrupted")
        return 130
    except (ValueError, OverflowError) as e:
        _say(f"error: {e}")
        return 2
    except (physstep.StepError, NotFiniteError) as e:
        _say(str(e))
        return 1
    except Exception as e:  # the contract is one line, never a traceback
        _say(f"internal error: {type(e).__name__}: {e} (please report it)")
        return 1
