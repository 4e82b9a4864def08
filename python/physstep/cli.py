"""The ``physstep`` command line.

Every command takes ``--format json``. Bad input exits with status 2 and one line on
stderr (``physstep: error: ...``), never a traceback; a diverging run exits with status 1.
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import math
import sys
from decimal import ROUND_HALF_UP, Decimal
from typing import Any, NoReturn

import physstep


class UsageError(ValueError):
    """Bad command-line input (exit status 2)."""


class _Parser(argparse.ArgumentParser):
    """argparse that reports errors in one line and exits with status 2."""

    def error(self, message: str) -> NoReturn:
        raise UsageError(message)


def parse_params(items: list[str] | None) -> dict[str, float]:
    """``["k=5", "m=2"]`` as ``{"k": 5.0, "m": 2.0}``; ValueError naming a malformed item."""
    out: dict[str, float] = {}
    for item in items or []:
        name, sep, value = item.partition("=")
        if not sep or not name.strip():
            raise UsageError(f"invalid --param '{item}': must be NAME=VALUE")
        try:
            number = float(value)
        except ValueError:
            raise UsageError(f"invalid --param '{item}': value '{value}' is not a number") from None
        out[name.strip()] = number
    return out


def round_half_away(value: float, places: int = 1) -> str:
    """``value`` rounded half away from zero on the exact double, as the notes print it."""
    if not math.isfinite(value):
        return str(value)
    q = Decimal(value).quantize(Decimal(1).scaleb(-places), rounding=ROUND_HALF_UP)
    s = f"{q:.{places}f}"
    return "0." + "0" * places if s.lstrip("-").strip("0.") == "" else s


def _dump(obj: Any) -> str:
    return json.dumps(obj, indent=2, allow_nan=True)


def _cmd_methods(args: argparse.Namespace) -> int:
    rows = [m.__dict__ for m in physstep.methods()]
    if args.format == "json":
        print(_dump(rows))
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
        print(_dump(rows))
        return 0
    for s in rows:
        params = ", ".join(f"{p['name']}={p['default']:g}" for p in s["params"])
        print(f"{s['name']:<11} {s['dim']}D  dt={s['dt']:g} until={s['until']:.4g}  {s['doc']}")
        print(f"{'':<15}params: {params}")
    return 0


def _columns(n: int) -> list[str]:
    if n == 1:
        return ["x", "v", "a"]
    return [f"{q}{i}" for q in ("x", "v", "a") for i in range(n)]


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


def _cmd_table(args: argparse.Namespace) -> int:
    traj = physstep.simulate(
        args.scene, args.method, args.dt, args.until, parse_params(args.param), stages=args.stages
    )
    n = traj.x.shape[1]
    header = ["t", *_columns(n)] + (["stage"] if args.stages else [])
    rows = _table_rows(traj, args.stages)
    if args.format == "json":
        print(
            _dump(
                {"scene": traj.scene, "method": traj.method, "dt": traj.dt, "columns": header, "rows": rows}
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
    if traj.diverged:
        print(f"physstep: {traj.diverged}", file=sys.stderr)
        return 1
    return 0


def _cmd_run(args: argparse.Namespace) -> int:
    if args.every < 1:
        raise UsageError(f"invalid --every = {args.every}: must be at least 1")
    traj = physstep.simulate(
        args.scene, args.method, args.dt, args.until, parse_params(args.param), every=args.every
    )
    summary = physstep.summarize(traj)
    if args.out:
        header = ["t", *_columns(traj.x.shape[1]), "energy"]
        with open(args.out, "w", newline="") as fh:
            w = csv.writer(fh, lineterminator="\n")
            w.writerow(header)
            for k in range(len(traj.t)):
                w.writerow(
                    [repr(float(c)) for c in [traj.t[k], *traj.x[k], *traj.v[k], *traj.a[k], traj.energy[k]]]
                )
        summary["out"] = args.out
    if args.format == "json":
        print(_dump(summary))
        return 0
    from rich.console import Console
    from rich.table import Table

    table = Table(title=f"{traj.scene} with {traj.method}, dt = {traj.dt:g}", show_header=False)
    table.add_column("", style="bold")
    table.add_column("")
    table.add_row("steps", f"{summary['steps']} (t = {summary['t']:.6g} s)")
    table.add_row("params", ", ".join(f"{k}={v:g}" for k, v in summary["params"].items()))
    table.add_row("final x", ", ".join(f"{c:.6g}" for c in summary["final"]["x"]))
    table.add_row("final v", ", ".join(f"{c:.6g}" for c in summary["final"]["v"]))
    en = summary["energy"]
    table.add_row(
        "energy", f"{en['initial']:.6g} -> {en['final']:.6g} J (max rel. error {en['max_rel_error']:.3g})"
    )
    if "error" in summary:
        table.add_row("position error", f"{summary['error']['final_position']:.3g} m at the end (vs exact)")
    table.add_row("cost", f"{summary['evals']} force evaluations, {summary['ns_per_step']:.0f} ns/step")
    if args.out:
        table.add_row("trajectory", args.out)
    Console().print(table)
    return 0


def _add_common(p: argparse.ArgumentParser, *, formats: tuple[str, ...] = ("text", "json")) -> None:
    p.add_argument("--format", choices=formats, default="text", help="output format (default: text)")


def _add_run_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("scene", help="built-in scene (physstep scenes lists them)")
    p.add_argument("--method", default="symplectic-euler", help="integrator (physstep methods lists them)")
    p.add_argument("--dt", type=float, default=None, help="step, s (default: the scene's)")
    p.add_argument("--until", type=float, default=None, help="end time, s (default: the scene's)")
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
    t.add_argument("--decimals", type=int, default=1, help="decimals of the text output (default 1)")
    _add_common(t, formats=("text", "csv", "json"))
    t.set_defaults(func=_cmd_table)

    r = sub.add_parser("run", help="run a scene and summarise energy and error")
    _add_run_args(r)
    r.add_argument("--out", metavar="FILE.csv", help="write the trajectory as CSV")
    r.add_argument(
        "--every", type=int, default=1, metavar="N", help="record every N-th step (energy error over those)"
    )
    _add_common(r)
    r.set_defaults(func=_cmd_run)

    from physstep import lab_cli

    lab_cli.register(sub)
    return p


def main(argv: list[str] | None = None) -> int:
    """Runs the command line; returns the exit status."""
    try:
        args = parser().parse_args(argv)
        if getattr(args, "decimals", 1) < 0:
            raise UsageError(f"invalid --decimals = {args.decimals}: must be >= 0")
        return int(args.func(args))
    except (ValueError, OverflowError) as e:
        print(f"physstep: error: {e}", file=sys.stderr)
        return 2
    except physstep.StepError as e:
        print(f"physstep: {e}", file=sys.stderr)
        return 1
    except BrokenPipeError:
        return 0
    except KeyboardInterrupt:
        return 130
