"""The engine's commands: ``methods``, ``solvers``, ``scenes``, ``table`` and ``run``.

:func:`register` adds them to the ``physstep`` command line (:mod:`physstep.cli.app`). Each
handler returns the exit status: 0, or 1 when the run diverged.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import warnings
from typing import Any

import physstep
from physstep import _files as files
from physstep.cli import options, output

#: The most decimals ``table`` prints: 17 significant digits round-trip any double, and the
#: CSV output (``--format csv``) prints every digit.
MAX_DECIMALS = 17
#: The largest ``run --every``.
MAX_EVERY = 10**9
#: A run faster than this (s) is timed again, ns/step being the median of TIMING_RUNS runs.
TIMING_MIN_S = 0.2
TIMING_RUNS = 5


def _registry(
    args: argparse.Namespace, rows: list[dict[str, Any]], title: str, columns: dict[str, Any]
) -> int:
    """A registry, one row per entry: the rows as JSON (``--format json``), or a table whose
    columns are ``columns`` (heading -> the cell's text from a row)."""
    if args.format == "json":
        print(output.dump(rows))
        return 0
    from rich.table import Table

    table = Table(title=title)
    for col in columns:
        table.add_column(col, overflow="fold")
    for r in rows:
        table.add_row(*(cell(r) for cell in columns.values()))
    output.console().print(table)
    return 0


def _cmd_methods(args: argparse.Namespace) -> int:
    """``physstep methods``: the integrator registry."""
    yes = {True: "yes", False: "no"}
    columns = {
        "name": lambda r: r["name"],
        "order": lambda r: str(r["order"]),
        "symplectic": lambda r: yes[r["symplectic"]],
        "implicit": lambda r: yes[r["implicit"]],
        "evals": lambda r: str(r["evals"]),
        "doc": lambda r: r["doc"],
    }
    return _registry(args, [m.__dict__ for m in physstep.methods()], "physstep integrators", columns)


def _cmd_solvers(args: argparse.Namespace) -> int:
    """``physstep solvers``: the contact solver registry."""
    columns = {
        "name": lambda r: r["name"],
        "family": lambda r: r["family"],
        "passes a step": lambda r: r["passes"],
        "summary": lambda r: r["summary"],
    }
    title = "physstep contact solvers (World.contact_solver)"
    return _registry(args, [s.__dict__ for s in physstep.solvers()], title, columns)


def _cmd_scenes(args: argparse.Namespace) -> int:
    """``physstep scenes``: the built-in scenes and their parameters; with ``--export NAME``
    the scene as a scene file, to ``--out`` (written whole) or stdout."""
    if args.export is not None:
        if args.out is not None:
            files.check(args.out, "--out")
        text = physstep.export_scene(args.export, options.parse_params(args.param))
        if args.out is None:
            sys.stdout.write(text)
        else:
            files.write_text(args.out, text, "--out")
            print(f"wrote {args.out}")
        return 0
    rows = physstep.scenes()
    if args.format == "json":
        print(output.dump(rows))
        return 0
    for s in rows:
        params = ", ".join(f"{p['name']}={p['default']:g}" for p in s["params"])
        print(f"{s['name']:<11} {s['dim']}D  {s['method']} dt={s['dt']:g} until={s['until']:.4g}  {s['doc']}")
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
    """One row per recorded step (t, x, v, a), each followed by its stages if ``stages``."""
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
    """``physstep table``: the state at every step, as the notes print it."""
    params = options.parse_params(args.param)
    traj = physstep.simulate(args.scene, args.method, args.dt, args.until, params, stages=args.stages)
    until = options.requested_until(args.scene, args.until)
    t_end = float(traj.t[-1])
    header = ["t", *_columns(traj)] + (["stage"] if args.stages else [])
    rows = _table_rows(traj, args.stages)
    output.check_rows(header, rows)
    if args.format == "json":
        doc = {
            "scene": traj.scene,
            "method": traj.method,
            "dt": traj.dt,
            "until": until,
            "steps": int(traj.steps),
            "t_end": t_end,
            "columns": header,
            "rows": rows,
        }
        print(output.dump(doc))
    elif args.format == "csv":
        sys.stdout.write(
            output.csv_text([header] + [[repr(c) if isinstance(c, float) else c for c in r] for r in rows])
        )
    else:
        cells = [header] + [
            [
                (output.round_half_away(c, args.decimals) if i > 0 else f"{c:g}")
                if isinstance(c, float)
                else str(c)
                for i, c in enumerate(r)
            ]
            for r in rows
        ]
        print(output.aligned(cells))
        note = output.reached(until, traj.steps, traj.dt, t_end)
        if note:
            print(f"note: {note}")
    if traj.diverged:
        print(f"physstep: {output.one_line(traj.diverged)}", file=sys.stderr)
        return 1
    return 0


def _trajectory_csv(traj: physstep.Trajectory) -> str:
    """The run as CSV (t, the state, the energy if known), every digit of every double."""
    energy = [] if traj.energy is None else ["energy"]
    header = ["t", *_columns(traj), *energy]
    rows: list[list[Any]] = [header]
    for k in range(len(traj.t)):
        e = [] if traj.energy is None else [traj.energy[k]]
        row = [float(c) for c in [traj.t[k], *traj.x[k], *traj.v[k], *traj.a[k], *e]]
        output.check_rows(header, [row])
        rows.append([repr(c) for c in row])
    return output.csv_text(rows)


def _cmd_run(args: argparse.Namespace) -> int:
    """``physstep run``: one run, summarised (energy, error, cost), its trajectory to ``--out``."""
    if args.out is not None:
        files.check(args.out, "--out")
    params = options.parse_params(args.param)

    def once() -> physstep.Trajectory:
        return physstep.simulate(args.scene, args.method, args.dt, args.until, params, every=args.every)

    # Constraints that cannot all be met are a line of the summary, not a Python warning.
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", physstep.ConstraintWarning)
        traj = once()
        timings = [traj.ns_per_step]
        if traj.elapsed_ns * 1e-9 < TIMING_MIN_S:
            timings += [once().ns_per_step for _ in range(TIMING_RUNS - 1)]
        summary = physstep.summarize(traj)
    conflicts = list(
        dict.fromkeys(str(w.message) for w in caught if issubclass(w.category, physstep.ConstraintWarning))
    )
    for w in caught:
        if not issubclass(w.category, physstep.ConstraintWarning):
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    until = options.requested_until(args.scene, args.until)
    summary["until"] = until
    summary["ns_per_step"] = statistics.median(timings)
    summary["ns_per_step_runs"] = len(timings)
    if conflicts:
        summary.setdefault("constraints", {})["conflicts"] = conflicts
    output.finite(summary)
    if args.out is not None:
        files.write_text(args.out, _trajectory_csv(traj), "--out")
        summary["out"] = args.out
    if args.format == "json":
        print(output.dump(summary))
        return 0
    from rich.console import Console
    from rich.table import Table

    table = Table(title=f"{traj.scene} with {traj.method}, dt = {traj.dt:g}", show_header=False)
    table.add_column("", style="bold")
    table.add_column("")
    table.add_row("steps", f"{summary['steps']} (t = {summary['t']:.10g} s)")
    note = output.reached(until, summary["steps"], traj.dt, summary["t"])
    if note:
        table.add_row("note", note)
    table.add_row("params", ", ".join(f"{k}={v:g}" for k, v in summary["params"].items()))
    if summary["final"]["x"]:
        table.add_row("final x", _vector(summary["final"]["x"]))
        table.add_row("final v", _vector(summary["final"]["v"]))
    en = summary["energy"]
    if en is None:
        why = "a flow has none" if traj.kind == "flow" else "a force has no potential"
        table.add_row("energy", f"unknown ({why})")
    else:
        table.add_row("energy", f"{en['initial']:.6g} -> {en['final']:.6g} J ({_energy_note(en)})")
    if "angular_momentum" in summary:
        ang = summary["angular_momentum"]
        table.add_row(
            "angular momentum",
            f"|L| {math.hypot(*ang['initial']):.6g} -> {math.hypot(*ang['final']):.6g} kg m^2/s "
            f"(max rel. error {ang['max_rel_error']:.3g})",
        )
    if "max_violation" in summary.get("constraints", {}):
        table.add_row(
            "constraints", f"max violation {summary['constraints']['max_violation']:.3g} m over the run"
        )
    for line in summary.get("constraints", {}).get("conflicts", []):
        table.add_row("constraints", output.one_line(line))
    if "collisions" in summary:
        col = summary["collisions"]
        table.add_row("collisions", f"{col['count']} contacts, max overlap {col['max_overlap']:.3g} m")
    if "contacts" in summary:
        con = summary["contacts"]
        table.add_row(
            "contacts",
            f"{con['count']} points touching among {con['solids']} solids at the end, max penetration "
            f"{con['max_penetration']:.3g} m, fastest solid {con['max_speed']:.3g} m/s"
            + (f", {con['asleep']} asleep (their contacts not counted)" if "asleep" in con else ""),
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


def _energy_note(en: dict[str, Any]) -> str:
    """How the energy changed, in words: the energy lost (or gained) where the run does not
    conserve it by design (and why), else the largest error and the scale it is relative to."""
    scale_of = en["scale_of"]
    if en["dissipation"] and en["lost"] > 0:
        share = "" if scale_of == "1 J" else f", {en['lost'] / en['scale']:.3g} of {scale_of}"
        return f"energy lost {en['lost']:.3g} J{share}: {en['dissipation']}"
    if en["dissipation"]:
        # Not conserved by design, and it rose (contacts pushing overlapping solids apart):
        # what changed, not an error.
        widest = en["max_rel_error"] * en["scale"]
        return (
            f"energy gained {-en['lost']:.3g} J: {en['dissipation']}; at most {widest:.3g} J from the start"
        )
    if scale_of == "1 J":
        return f"max error {en['max_rel_error']:.3g} J"
    return f"max rel. error {en['max_rel_error']:.3g} of {scale_of}"


def _add_run_args(p: argparse.ArgumentParser) -> None:
    """The arguments ``table`` and ``run`` share: scene, method, dt, until and params."""
    p.add_argument("scene", help=options.SCENE_HELP)
    p.add_argument(
        "--method",
        default=None,
        help=options.METHOD_HELP + " (default: the scene's own, as physstep scenes lists, or the file's)",
    )
    p.add_argument("--dt", type=options.DT, default=None, help="step, s (default: the scene's)")
    p.add_argument("--until", type=options.UNTIL, default=None, help=options.UNTIL_HELP)
    options.add_param(p)


def register(subparsers: Any) -> None:
    """Adds ``methods``, ``solvers``, ``scenes``, ``table`` and ``run`` to an argparse subparsers
    object."""
    m = subparsers.add_parser("methods", help="list the integrators")
    options.add_format(m)
    m.set_defaults(func=_cmd_methods)

    c = subparsers.add_parser("solvers", help="list the contact solvers")
    options.add_format(c)
    c.set_defaults(func=_cmd_solvers)

    s = subparsers.add_parser("scenes", help="list the built-in scenes and their parameters")
    options.add_format(s)
    s.add_argument("--export", metavar="NAME", help="write built-in scene NAME as a scene file (TOML)")
    s.add_argument("--out", metavar="FILE.toml", help="with --export: the file to write (default: stdout)")
    options.add_param(s)
    s.set_defaults(func=_cmd_scenes)

    t = subparsers.add_parser("table", help="the state at every step, as the notes print it")
    _add_run_args(t)
    t.add_argument("--stages", action="store_true", help="also print intermediate evaluation points")
    t.add_argument(
        "--decimals",
        type=options.argument("--decimals", int, low=0, high=MAX_DECIMALS),
        default=1,
        help=f"decimals of the text output, 0 to {MAX_DECIMALS} (default 1; --format csv prints every digit)",
    )
    options.add_format(t, ("text", "csv", "json"))
    t.set_defaults(func=_cmd_table)

    r = subparsers.add_parser("run", help="run a scene and summarise energy and error")
    _add_run_args(r)
    r.add_argument("--out", metavar="FILE.csv", help="write the trajectory as CSV")
    r.add_argument(
        "--every",
        type=options.argument("--every", int, low=1, high=MAX_EVERY),
        default=1,
        metavar="N",
        help="record every N-th step (energy error over those)",
    )
    options.add_format(r)
    r.set_defaults(func=_cmd_run)


# Most numbers of a state vector the run summary's table prints.
SHOWN = 12


def _vector(values: list[float]) -> str:
    """A state vector for the table: the first `SHOWN` numbers, and how many more there are
    (`--format json` has them all)."""
    head = ", ".join(f"{c:.6g}" for c in values[:SHOWN])
    if len(values) <= SHOWN:
        return head
    return f"{head}, ... ({len(values)} numbers in all: --format json lists them)"
