"""The lab's commands: ``compare``, ``order``, ``stability`` and ``sweep``.

:func:`register` adds them to the ``physstep`` command line (:mod:`physstep.cli.app`). Each
handler returns the exit status; a ValueError it raises becomes status 2 with one line on
stderr. Output follows :mod:`physstep.cli.output`: strict JSON, no non-finite number
printed; ``--out`` and ``--plot`` are checked before the computation and written whole or
not at all (:mod:`physstep._files`).
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import Any

import physstep
from physstep import _files as files
from physstep import lab
from physstep.cli import options, output
from physstep.lab.common import MAX_JOBS
from physstep.lab.order import MAX_LEVELS as ORDER_MAX_LEVELS

#: The most step sizes ``order --levels`` runs (the finest run is 2**(levels-1) times finer):
#: the lab's own bound (:data:`physstep.lab.order.MAX_LEVELS`), so the command line, the API
#: and the docs say the same.
MAX_LEVELS = ORDER_MAX_LEVELS


def _params(args: argparse.Namespace) -> dict[str, float] | None:
    return options.parse_params(args.param) or None


def _methods(text: str) -> list[str] | str:
    """``--methods``: a comma-separated list of names, or ``all`` (passed to the lab as
    ``"all"``: every method that applies, the split methods skipped on a flow)."""
    if text.strip() == "all":
        return "all"
    names = [m.strip() for m in text.split(",")]
    if not any(names):
        raise options.UsageError(
            f"invalid --methods '{text}': give a comma-separated list of methods, or all"
        )
    if not all(names):
        raise options.UsageError(
            f"invalid --methods '{text}': an empty name between commas; "
            "give a comma-separated list of methods"
        )
    twice = sorted({m for m in names if names.count(m) > 1})
    if twice:
        raise options.UsageError(
            f"invalid --methods '{text}': '{twice[0]}' is given twice (each method is one row)"
        )
    return names


def _floats(text: str, flag: str) -> list[float]:
    """A comma-separated list of finite numbers > 0 (the steps of ``--dts``)."""
    out = []
    for item in text.split(","):
        item = item.strip()
        if not item:
            continue
        try:
            value = float(item)
        except ValueError:
            raise options.UsageError(f"invalid {flag} '{text}': '{item}' is not a number") from None
        if not (math.isfinite(value) and value > 0):
            raise options.UsageError(f"invalid {flag} '{text}': '{item}' must be a finite number > 0")
        out.append(value)
    if not out:
        raise options.UsageError(f"invalid {flag} '{text}': give a comma-separated list of numbers")
    return out


def _check_plot(path: str | None) -> None:
    """Before any computation: ``--plot`` ends in .png or .svg and can be written."""
    if path is None:
        return
    if Path(path).suffix.lower() not in (".png", ".svg"):
        raise options.UsageError(f"invalid --plot '{path}': the file must end in .png or .svg")
    files.check(path, "--plot")


def _save_plot(fig: Any, path: str) -> None:
    fmt = Path(path).suffix.lower().lstrip(".")
    files.write(path, lambda fh: fig.savefig(fh, format=fmt), "--plot")


def _span(res: dict[str, Any]) -> tuple[int | None, float | None]:
    """Steps and final time actually run by compare: from the lab's result if it says, else
    from the first row that did not diverge."""
    steps, t_end = res.get("steps"), res.get("t_end")
    if steps is None or t_end is None:
        ok = [r for r in res.get("rows", []) if not r.get("diverged")]
        if ok:
            steps, t_end = ok[0].get("steps"), ok[0].get("t_end")
    return steps, t_end


def _cmd_compare(args: argparse.Namespace) -> int:
    """``physstep compare``: methods side by side on one scene (order, cost, energy, error), or
    with ``--solvers`` the contact solvers (:func:`_cmd_compare_solvers`)."""
    if args.solvers is not None:
        return _cmd_compare_solvers(args)
    for flag, value in (("--substeps", args.substeps), ("--iterations", args.iterations)):
        if value is not None:
            raise options.UsageError(f"invalid {flag} {value}: it applies with --solvers only")
    _check_plot(args.plot)
    methods = _methods(args.methods)
    params = _params(args)
    res = lab.compare(args.scene, methods, args.dt, args.until, params, jobs=args.jobs).to_dict()
    until = options.requested_until(args.scene, args.until)
    steps, t_end = _span(res)
    res.setdefault("until_requested", until)
    if steps is not None and t_end is not None:
        res.setdefault("steps", steps)
        res.setdefault("t_end", t_end)
    output.finite(res)
    if args.plot:
        ran = [r["method"] for r in res["rows"]]
        _compare_plot(args.scene, ran, res["dt"], until, params, args.plot)
        res["plot"] = args.plot
    if args.format == "json":
        print(output.dump(res))
        return 0
    from rich.table import Table

    note = None if steps is None or t_end is None else output.reached(until, steps, res["dt"], t_end)
    span = note or f"until = {until:.10g} s" + ("" if steps is None else f" ({steps} steps)")
    unknown = all(r.get("energy_scale") is None for r in res["rows"])
    caption = (
        f"final error against the {res['error_against']}; energy error relative to |E0| (to the "
        "largest kinetic energy where |E0| is below 1e-3 of it), drift = its least-squares slope per second"
    )
    if res.get("kind") == "bodies":
        caption += (
            "; |dL|/|L| = max |L - L0| / |L0| of the total angular momentum (an error unless a torque acts)"
        )
    lost = {r["method"]: r.get("energy_dissipation") for r in res["rows"] if r.get("energy_dissipation")}
    if lost:
        why = ", ".join(f"{m} ({reason})" for m, reason in lost.items())
        caption += f"; energy lost by design, not an error: {why}"
    table = Table(title=f"{res['scene']}: dt = {res['dt']:g} s, {span}", caption=caption)
    repeats = res.get("ns_per_step_runs", res.get("repeats"))
    timing = "ns/step" if repeats in (None, 1) else f"ns/step (median of {repeats})"
    kind = res.get("kind")
    error = {"flow": "final error", "bodies": "final spin error (rad/s)"}.get(str(kind), "final error (m)")
    bodies = kind == "bodies"
    cols = (
        "method",
        "order",
        "evals/step",
        "max |dE|/scale",
        "drift (1/s)",
        *(["max |dL|/|L|"] if bodies else []),
        error,
        timing,
    )
    widest = max((len(r["method"]) for r in res["rows"]), default=6)
    for col in cols:
        if col == "method":  # names whole: the numeric headers fold instead
            table.add_column(col, justify="left", no_wrap=True, min_width=widest)
        else:
            table.add_column(col, justify="right")
    g = output.number
    for r in res["rows"]:
        where = f" at t = {r['t_end']:g} s" if r.get("t_end") is not None else ""
        table.add_row(
            r["method"] + (f" [red](failed{where})[/red]" if r["diverged"] else ""),
            str(r["order"]),
            g(r["evals_per_step"], ".2f"),
            g(r["energy_max_rel_error"], ".3e"),
            g(r["energy_drift"], ".2e"),
            *([g(r["angular_momentum_max_rel_error"], ".2e")] if bodies else []),
            g(r["final_error"], ".3e"),
            g(r["ns_per_step"], ".0f"),
        )
    con = output.console()
    con.print(table)
    if unknown:
        why = "a flow has none" if res.get("kind") == "flow" else "a force has no potential"
        con.print(f"energy: unknown ({why}): its columns show -", markup=False)
    if res.get("note"):
        con.print(f"note: {output.one_line(res['note'])}", markup=False)
    for r in res["rows"]:
        if r["diverged"]:
            con.print(
                f"{r['method']}: {output.one_line(r['diverged'])}; its row covers the run up to there",
                markup=False,
            )
    if args.plot:
        con.print(f"plot: {args.plot}", markup=False)
    return 0


def _compare_plot(
    scene: str, methods: list[str], dt: float, until: float, params: dict[str, float] | None, path: str
) -> None:
    """The runs of ``compare`` plotted to ``path``: orbits for the 2-D orbit scenes, the path in
    3D for a flow of three or more coordinates (the attractors), the body-frame spin with the
    energy and angular-momentum errors for rigid bodies, else x(t)."""
    from physstep import plot

    runs = [physstep.simulate(scene, m, dt, until, params, stop_on_diverge=True) for m in methods]
    first = runs[0]
    if first.kind == "bodies":
        fig = plot.spin(runs)
    elif first.dim >= 2 and scene in ("orbit", "kepler"):
        fig = plot.orbit(runs)
    elif first.kind == "flow" and first.x.shape[1] >= 3:
        fig = plot.path3d(runs)
    else:
        fig = plot.trajectory(runs)
    _save_plot(fig, path)


def _cmd_compare_solvers(args: argparse.Namespace) -> int:
    """``physstep compare SCENE --solvers a,b``: contact solvers side by side on a contact scene."""
    if args.methods != "all":
        raise options.UsageError("invalid --methods with --solvers: compare methods or solvers, not both")
    if args.dt is not None or args.plot is not None or args.jobs != 1:
        flag = "--dt" if args.dt is not None else "--plot" if args.plot is not None else "--jobs"
        raise options.UsageError(
            f"invalid {flag} with --solvers: the solver lab runs at the scene's dt, serially"
        )
    text = args.solvers.strip()
    names: list[str] | str = "all" if text == "all" else [s.strip() for s in text.split(",")]
    if names != "all" and (not all(names) or len(set(names)) != len(names)):
        raise options.UsageError(
            f"invalid --solvers '{args.solvers}': give a comma-separated list of distinct solvers, or all"
        )
    res = lab.compare_solvers(
        args.scene,
        names,
        args.until,
        _params(args),
        substeps=args.substeps,
        iterations=args.iterations,
    ).to_dict()
    output.finite(res)
    if args.format == "json":
        print(output.dump(res))
        return 0
    from rich.table import Table

    title = (
        f"{res['scene']}: dt = {res['dt']:g} s, until = {res['until']:g} s, {res['substeps']} substeps x "
        f"{res['iterations']} iterations"
    )
    table = Table(title=title, caption=f"tracked solid: row {res['tracked']}; {res['thresholds']}")
    cols = (
        "solver",
        "passes/step",
        "ms/step",
        "max pen. (mm)",
        "drift (mm)",
        "joint err. (mm)",
        "KE last 1 s (J)",
        "dE/|E0|",
        "friction err.",
        "verdict",
    )
    for col in cols:
        table.add_column(
            col, justify="left" if col in ("solver", "verdict") else "right", no_wrap=col == "solver"
        )
    g = output.number
    mm = lambda v: g(None if v is None else 1e3 * v, ".3g")  # noqa: E731
    for r in res["rows"]:
        table.add_row(
            r["solver"],
            g(r["passes_per_step"], ".3g"),
            g(r["ms_per_step"], ".3g"),
            mm(r["max_penetration"]),
            mm(r["drift"]),
            mm(r.get("joint_error")),
            g(r["jitter"], ".2e"),
            g(r.get("energy_change"), ".2e"),
            g(r.get("friction_error"), ".2e"),
            r["verdict"],
        )
    con = output.console()
    con.print(table)
    for r in res["rows"]:
        if r["diverged"]:
            con.print(
                f"{r['solver']}: {output.one_line(r['diverged'])} (after {r['steps']} steps)", markup=False
            )
    return 0


def _cmd_order(args: argparse.Namespace) -> int:
    """``physstep order``: the observed order of convergence over halvings of dt."""
    res = lab.order(
        args.scene,
        args.method,
        args.dt,
        args.until,
        _params(args),
        levels=args.levels,
        time_scale=args.time_scale,
    ).to_dict()
    for r in res.get("runs", []):
        # the lab marks a run that diverged with an infinite error: say so, never print inf
        e = r.get("error")
        if isinstance(e, float) and not math.isfinite(e):
            r["error"] = None
            r["diverged"] = True
    output.finite(res)
    if args.format == "json":
        print(output.dump(res))
        return 0
    from rich.table import Table

    g = output.number
    obs = "-" if res["order"] is None else f"{res['order']:.3f}"
    table = Table(title=f"{res['scene']} / {res['method']}")
    for col in ("dt (s)", "steps", "error" if res.get("kind") == "flow" else "error (m)", "order"):
        table.add_column(col, justify="right")
    for r in res["runs"]:
        err = "diverged" if r.get("diverged") else g(r["error"], ".3e")
        table.add_row(g(r["dt"], ".6g"), str(r["steps"]), err, g(r["order"], ".3f"))
    con = output.console()
    con.print(table)
    con.print(f"observed order [bold]{obs}[/bold] (registry: {res['info_order']}), fit over the finest runs")
    what = res.get("error", "final position error")
    con.print(f"error: {what} at t = {res['until']:g} s against the {res['error_against']}")
    if res["note"]:
        con.print(f"note: {res['note']}", markup=False)
    return 0


def _cmd_stability(args: argparse.Namespace) -> int:
    """``physstep stability``: the largest stable dt of a method on a scene."""
    res = lab.stability(
        args.scene, args.method, _params(args), cap=args.cap, time_scale=args.time_scale
    ).to_dict()
    output.finite(res)
    if args.format == "json":
        print(output.dump(res))
        return 0
    d = res["dt_max"]
    if d is None:
        verdict = f"no limit found below the cap {res['cap']:.6g} s (stable at every dt tried)"
    elif d == 0:
        verdict = "0: unstable at every dt"
    else:
        verdict = f"{d:.10g} s"
    con = output.console()
    con.print(f"[bold]{res['scene']} / {res['method']}[/bold]: largest stable dt = [bold]{verdict}[/bold]")
    con.print(f"criterion: {res['criterion']}")
    con.print(
        f"search: log grid {res['grid'][0]:.3g} ... {res['grid'][1]:.6g} s "
        f"({res['grid'][2]} per decade), then bisection; natural time scale {res['time_scale']:.6g} s"
    )
    con.print(res["note"], markup=False)
    return 0


def _splits(text: str) -> list[tuple[int, int]]:
    """``--splits``: comma-separated ``SUBSTEPSxITERATIONS`` pairs, each from 1 to 1000."""
    out = []
    for item in text.split(","):
        a, sep, b = item.strip().partition("x")
        if not (sep and a.isdigit() and b.isdigit() and 1 <= int(a) <= 1000 and 1 <= int(b) <= 1000):
            raise options.UsageError(
                f"invalid --splits '{text}': '{item.strip()}' must be SUBSTEPSxITERATIONS, "
                "each 1 to 1000 (8x1)"
            )
        out.append((int(a), int(b)))
    return out


def _cmd_sweep_solvers(args: argparse.Namespace) -> int:
    """``physstep sweep SCENE --solvers a,b [--splits 8x1,4x2]``: the solver lab over splits."""
    for flag, given in (("--dts", args.dts is not None), ("--methods", args.methods != "all")):
        if given:
            raise options.UsageError(
                f"invalid {flag} with --solvers: sweep methods over dts, or solvers over splits"
            )
    _check_plot(args.plot)
    if args.out is not None:
        files.check(args.out, "--out")
    names = [s.strip() for s in args.solvers.split(",")] if args.solvers.strip() != "all" else "all"
    splits = _splits(args.splits) if args.splits else list(lab.solvers.DEFAULT_SPLITS)
    res = lab.sweep_solvers(args.scene, names, splits, args.until, _params(args)).to_dict()
    output.finite(res)
    if args.plot:
        from physstep import plot

        _save_plot(plot.solver_sweep(res), args.plot)
        res["plot"] = args.plot
    if args.format == "json":
        text = output.dump(res) + "\n"
    else:
        cols = [
            "solver",
            "substeps",
            "iterations",
            "passes_per_step",
            "ms_per_step",
            "drift",
            "max_penetration",
            "settled_penetration",
            "joint_error",
            "jitter",
            "verdict",
        ]
        text = output.csv_text([cols, *([r.get(c) for c in cols] for r in res["rows"])])
    if args.out is not None:
        files.write_text(args.out, text, "--out")
    else:
        sys.stdout.write(text)
    return 0


def _cmd_sweep(args: argparse.Namespace) -> int:
    """``physstep sweep``: work-precision data over methods and steps, as CSV or JSON; with
    ``--solvers``, the contact solvers over splits of their passes (:func:`_cmd_sweep_solvers`)."""
    if args.solvers is not None:
        return _cmd_sweep_solvers(args)
    if args.splits is not None:
        raise options.UsageError("invalid --splits: it applies with --solvers only")
    if args.dts is None:
        raise options.UsageError("invalid sweep: --dts is required (or --solvers, the solver lab)")
    _check_plot(args.plot)
    if args.out is not None:
        files.check(args.out, "--out")
    methods = _methods(args.methods)
    dts = _floats(args.dts, "--dts")
    params = _params(args)
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    with Progress(
        TextColumn("[progress.description]{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        console=Console(stderr=True),
        disable=not sys.stderr.isatty(),
        transient=True,
    ) as bar:
        task = bar.add_task("sweep", total=len(methods) * len(dts))

        def progress(done: int, total: int, label: str) -> None:
            bar.update(task, completed=done, description=label)

        ran = lab.sweep(args.scene, methods, dts, args.until, params, progress=progress, jobs=args.jobs)
    res = ran.to_dict()
    res.setdefault("until_requested", options.requested_until(args.scene, args.until))
    for r in res["rows"]:
        # where each run ended: dt does not always divide until (the lab may say it itself)
        r.setdefault("t_end", r["steps"] * r["dt"])
    output.finite(res)
    if res.get("note"):
        print(f"physstep: note: {output.one_line(res['note'])}", file=sys.stderr)
    if args.plot:
        from physstep import plot

        _save_plot(plot.work_precision(res, against="both"), args.plot)
        res["plot"] = args.plot
    if args.format == "json":
        text = output.dump(res) + "\n"
    else:
        cols = ["method", "dt", "steps", "t_end", "evals", "time_s", "ns_per_step", "error", "max_error"]
        cols.append("energy_max_rel_error")
        text = output.csv_text(
            [cols + ["diverged"]]
            + [
                ["" if r.get(c) is None else r[c] for c in cols] + [output.one_line(r["diverged"] or "")]
                for r in res["rows"]
            ]
        )
    if args.out:
        files.write_text(args.out, text, "--out")
    else:
        sys.stdout.write(text)
    return 0


def _add_time_scale(p: argparse.ArgumentParser) -> None:
    """Adds ``--time-scale`` (the lab's ``time_scale``) to ``p``."""
    p.add_argument(
        "--time-scale",
        type=options.argument("--time-scale", low=0, open_low=True),
        default=None,
        metavar="S",
        help="natural time scale, s (default: from the scene's parameters; estimated from the initial "
        "state for the attractors)",
    )


def _add_jobs(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--jobs",
        type=options.argument("--jobs", int, low=1, high=MAX_JOBS),
        default=1,
        help=f"run the rows in up to this many local processes, 1 to {MAX_JOBS} (default 1), where the "
        "work pays for starting them (the note says when not); the same results",
    )


def register(subparsers: Any) -> None:
    """Adds ``compare``, ``order``, ``stability`` and ``sweep`` to an argparse subparsers object."""
    c = subparsers.add_parser("compare", help="compare methods on a scene: order, cost, energy, error")
    c.add_argument("scene", help=options.SCENE_HELP)
    c.add_argument(
        "--methods",
        default="all",
        help="comma-separated integrators, e.g. explicit-euler,rk4, or all (the default)",
    )
    c.add_argument("--dt", type=options.DT, default=None, help="step, s (default: the scene's)")
    c.add_argument("--until", type=options.UNTIL, default=None, help=options.UNTIL_HELP)
    c.add_argument("--plot", metavar="FILE.png", help="also plot the runs (.png or .svg)")
    c.add_argument(
        "--solvers",
        default=None,
        help="compare contact solvers instead of methods on a contact scene: comma-separated names "
        "(physstep solvers lists them) or all; penetration, drift, joint error, jitter, cost, verdict",
    )
    c.add_argument(
        "--substeps",
        type=options.argument("--substeps", int, low=1, high=1000),
        default=None,
        help="with --solvers: the substeps every solver runs with, 1 to 1000 (default: the world's, 8)",
    )
    c.add_argument(
        "--iterations",
        type=options.argument("--iterations", int, low=1, high=1000),
        default=None,
        help="with --solvers: the solver iterations, 1 to 1000 (default: the world's, 1)",
    )
    _add_jobs(c)
    options.add_param(c)
    options.add_format(c)
    c.set_defaults(func=_cmd_compare)

    o = subparsers.add_parser("order", help="observed convergence order from halvings of dt")
    o.add_argument("scene", help=options.SCENE_HELP)
    o.add_argument("--method", required=True, help=options.METHOD_HELP)
    o.add_argument("--dt", type=options.DT, default=None, help="coarsest step, s (default: until/32)")
    o.add_argument(
        "--until",
        type=options.argument("--until", low=0, open_low=True),
        default=None,
        help="end time, s (default: 0.3 time scales)",
    )
    o.add_argument(
        "--levels",
        type=options.argument("--levels", int, low=2, high=MAX_LEVELS),
        default=5,
        help=f"number of step sizes, 2 to {MAX_LEVELS} (default 5)",
    )
    _add_time_scale(o)
    options.add_param(o)
    options.add_format(o)
    o.set_defaults(func=_cmd_order)

    s = subparsers.add_parser("stability", help="largest stable dt of a method on a scene")
    s.add_argument("scene", help=options.SCENE_HELP)
    s.add_argument("--method", required=True, help=options.METHOD_HELP)
    s.add_argument(
        "--cap",
        type=options.argument("--cap", low=0, open_low=True),
        default=None,
        help="largest dt searched, s (default: 1000 time scales)",
    )
    _add_time_scale(s)
    options.add_param(s)
    options.add_format(s)
    s.set_defaults(func=_cmd_stability)

    w = subparsers.add_parser("sweep", help="work-precision data: error against work over methods and dts")
    w.add_argument("scene", help=options.SCENE_HELP)
    w.add_argument("--methods", default="all", help="comma-separated integrators, or all (the default)")
    w.add_argument(
        "--dts",
        default=None,
        help="comma-separated steps, s, e.g. 0.1,0.05,0.025 (required without --solvers)",
    )
    w.add_argument(
        "--solvers",
        default=None,
        help="sweep contact solvers over --splits instead (comma-separated names, or all) on a contact scene",
    )
    w.add_argument(
        "--splits",
        default=None,
        help="with --solvers: comma-separated SUBSTEPSxITERATIONS (default 8x1,4x2,2x4,1x8: 16 passes each)",
    )
    w.add_argument("--until", type=options.UNTIL, default=None, help=options.UNTIL_HELP)
    w.add_argument("--out", metavar="FILE", help="write the data here instead of stdout")
    w.add_argument("--plot", metavar="FILE.png", help="also plot work-precision (.png or .svg)")
    _add_jobs(w)
    options.add_param(w)
    options.add_format(w, ("csv", "json"))
    w.set_defaults(func=_cmd_sweep)
