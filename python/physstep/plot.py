"""Plots of the integrator lab, each returning a :class:`matplotlib.figure.Figure`.

The figures are built on matplotlib's object API (no pyplot state, Agg canvas), so they work
headless and never pop up a window; :func:`save` writes PNG or SVG by the file's extension.
Every function takes one trajectory or several (overlaid, one legend entry per method).
Flows (``Trajectory.kind == "flow"``: the attractors, your own :class:`physstep.Flow`) plot
their state ``y`` and its rate ``dy/dt``, without units; :func:`path3d` draws three
coordinates in 3D; :func:`energy` refuses a run whose energy is unknown. Rigid bodies
(``Trajectory.kind == "bodies"``) have :func:`spin`: the body-frame angular velocity, the
energy error and the change of the angular momentum.

>>> import physstep
>>> from physstep import plot
>>> runs = [physstep.simulate("orbit", m, dt=0.1, until=20) for m in ("explicit-euler", "rk4")]
>>> fig = plot.orbit(runs)
>>> plot.save(fig, "orbit.png")  # doctest: +SKIP
"""

from __future__ import annotations

import math
import operator
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from physstep import Trajectory

__all__ = ["LOG_FLOOR", "energy", "orbit", "path3d", "phase", "save", "spin", "trajectory", "work_precision"]

_EXACT_STYLE: dict[str, Any] = {"color": "black", "linestyle": "--", "linewidth": 1.2, "alpha": 0.7}


def _runs(trajs: Trajectory | Iterable[Trajectory]) -> list[Trajectory]:
    runs = [trajs] if isinstance(trajs, Trajectory) else list(trajs)
    if not runs:
        raise ValueError("invalid trajectories = []: give at least one run")
    for i, r in enumerate(runs):
        if not isinstance(r, Trajectory):
            raise TypeError(f"invalid trajectories[{i}]: a {type(r).__name__}, not a physstep.Trajectory")
        if len(r.t) == 0:
            raise ValueError(f"invalid trajectories[{i}] ({r.method}): the trajectory has no rows")
    return runs


def _index(value: Any, name: str) -> int:
    try:
        return operator.index(value)
    except TypeError:
        raise ValueError(f"invalid {name} = {value!r}: must be an integer") from None


def _check_coord(runs: Sequence[Trajectory], coord: int) -> int:
    coord = _index(coord, "coord")
    for r in runs:
        n = r.x.shape[1]
        if not 0 <= coord < n:
            raise ValueError(
                f"invalid coord = {coord}: the {r.scene} run of {r.method} has {n} coordinates "
                f"(0 ... {n - 1})"
            )
    return coord


def _finite(cols: Sequence[np.ndarray], what: str | None) -> tuple[list[np.ndarray], str]:
    """``cols`` with every row that has a non-finite value in any of them set to NaN (a gap in
    the line), and the legend note saying how many rows that hid. ValueError naming ``what``
    when no row is finite (``what`` None: no error, the line is left empty)."""
    ok = np.ones(len(cols[0]), dtype=bool)
    for c in cols:
        ok &= np.isfinite(c)
    bad = int(len(ok) - ok.sum())
    if bad == 0:
        return list(cols), ""
    if bad == len(ok) and what is not None:
        raise ValueError(f"invalid trajectory ({what}): no row has finite values to plot")
    masked = [np.where(ok, c, np.nan) for c in cols]
    return masked, f" ({bad} non-finite row{'s' if bad != 1 else ''} not shown)"


def _figure(size: tuple[float, float] = (8.0, 5.0), dpi: int = 100) -> Figure:
    fig = Figure(figsize=size, dpi=dpi, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def _fmt_dt(runs: Sequence[Trajectory]) -> str:
    dts = sorted({r.dt for r in runs})
    return ", ".join(f"{d:g}" for d in dts) + " s"


def _title(what: str, runs: Sequence[Trajectory]) -> str:
    scenes = sorted({r.scene for r in runs})
    names = ", ".join(dict.fromkeys(r.method for r in runs))
    return f"{what}: {', '.join(scenes)}, dt = {_fmt_dt(runs)}\n{names}"


def _label(run: Trajectory, runs: Sequence[Trajectory]) -> str:
    """The method name; with the dt when the runs mix step sizes of one method, and where
    the run stopped early (``stop_on_diverge``)."""
    same = [r for r in runs if r.method == run.method]
    label = run.method if len(same) == 1 else f"{run.method} (dt = {run.dt:g} s)"
    if run.diverged:
        label += f" (failed at t = {run.t[-1]:.3g} s)"
    return label


def _coord_name(run: Trajectory, coord: int) -> str:
    """How coordinate ``coord`` is called: x, y, z (x[p] for particle p), or y[i] for a flow."""
    if run.kind == "flow":
        return "y" if run.x.shape[1] == 1 else f"y[{coord}]"
    if run.dim == 1:
        return "x" if run.x.shape[1] == 1 else f"x[{coord}]"
    axis = "xyz"[coord % run.dim] if run.dim <= 3 else str(coord % run.dim)
    particle = coord // run.dim
    return axis if run.x.shape[1] == run.dim else f"{axis}[{particle}]"


def _axis(run: Trajectory, coord: int, rate: bool = False) -> str:
    """The axis label of coordinate ``coord`` (``rate``: of its velocity, or a flow's dy/dt),
    with its unit for particles."""
    name = _coord_name(run, coord)
    if run.kind == "flow":
        return f"d{name}/dt" if rate else name
    if rate:
        return "v (m/s)" if name == "x" else f"v_{name} (m/s)"
    return f"{name} (m)"


def _format(path: str | Path) -> str:
    fmt = Path(path).suffix.lstrip(".").lower()
    if fmt not in ("png", "svg", "pdf"):
        raise ValueError(f"invalid plot file '{path}': the extension must be .png, .svg or .pdf")
    return fmt


def save(fig: Figure, path: str | Path, **kwargs: Any) -> Path:
    """Writes ``fig`` to ``path``; the format (png, svg, pdf) comes from the extension.

    Missing parent directories are created. The file is written whole or not at all (a
    temporary file beside it, then renamed): a failed write keeps the old file. Raises
    ValueError for an unknown extension or a file that cannot be written.
    """
    from physstep import _files

    path = Path(path)
    fmt = _format(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    _files.write(str(path), lambda fh: fig.savefig(fh, format=fmt, **kwargs), "plot file")
    return path


def _exact(runs: Sequence[Trajectory]) -> Trajectory | None:
    """The longest run with an exact solution, or None."""
    ex = [r for r in runs if r.exact_x is not None]
    return max(ex, key=lambda r: r.t[-1]) if ex else None


def trajectory(trajs: Trajectory | Iterable[Trajectory], coord: int = 0) -> Figure:
    """Position coordinate ``coord`` against time, one line per run, the exact solution dashed.

    Raises ValueError for no runs, a run with no rows, or ``coord`` out of range.

    Rows holding a non-finite value (a run blowing up) are left out, as a gap in the line,
    and the legend says how many; a run with no finite row at all is a ValueError.
    """
    runs = _runs(trajs)
    coord = _check_coord(runs, coord)
    fig = _figure()
    ax = fig.add_subplot()
    for r in runs:
        (t, y), note = _finite([r.t, r.x[:, coord]], r.method)
        ax.plot(t, y, label=_label(r, runs) + note)
    ex = _exact(runs)
    if ex is not None:
        assert ex.exact_x is not None
        (t, y), note = _finite([ex.t, ex.exact_x[:, coord]], None)
        ax.plot(t, y, label="exact" + note, **_EXACT_STYLE)
    name = _coord_name(runs[0], coord)
    ax.set_xlabel("t (s)")
    ax.set_ylabel(_axis(runs[0], coord))
    ax.set_title(_title(f"{name}(t)", runs))
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize="small")
    return fig


def phase(trajs: Trajectory | Iterable[Trajectory], coord: int = 0) -> Figure:
    """Phase portrait: velocity against position of coordinate ``coord`` (for a flow, dy/dt
    against y).

    Raises ValueError for no runs, a run with no rows, or ``coord`` out of range.

    Rows holding a non-finite value (a run blowing up) are left out, as a gap in the line,
    and the legend says how many; a run with no finite row at all is a ValueError.
    """
    runs = _runs(trajs)
    coord = _check_coord(runs, coord)
    fig = _figure((6.5, 6.0))
    ax = fig.add_subplot()
    for r in runs:
        (x, v), note = _finite([r.x[:, coord], r.v[:, coord]], r.method)
        ax.plot(x, v, label=_label(r, runs) + note, linewidth=1.2)
    ex = next((r for r in runs if r.exact_x is not None and r.exact_v is not None), None)
    if ex is not None:
        assert ex.exact_x is not None and ex.exact_v is not None
        (x, v), note = _finite([ex.exact_x[:, coord], ex.exact_v[:, coord]], None)
        ax.plot(x, v, label="exact" + note, **_EXACT_STYLE)
    start = runs[0]
    x0, v0 = start.x[0, coord], start.v[0, coord]
    if np.isfinite(x0) and np.isfinite(v0):
        ax.plot([x0], [v0], "ko", markersize=5, label="start")
    ax.set_xlabel(_axis(runs[0], coord))
    ax.set_ylabel(_axis(runs[0], coord, rate=True))
    ax.set_title(_title("phase portrait", runs))
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize="small")
    return fig


def orbit(trajs: Trajectory | Iterable[Trajectory], particle: int = 0) -> Figure:
    """The path of ``particle`` in the plane (equal axes), the exact path dashed (a flow:
    y[0] against y[1]).

    Raises ValueError for no runs, a run with no rows, a 1D scene, or ``particle`` out of
    range.

    Rows holding a non-finite value (a run blowing up) are left out, as a gap in the line,
    and the legend says how many; a run with no finite row at all is a ValueError.
    """
    runs = _runs(trajs)
    if any(r.dim < 2 for r in runs):
        raise ValueError("invalid trajectory: orbit plots need a 2D scene")
    particle = _index(particle, "particle")
    for r in runs:
        n = r.x.shape[1] // r.dim
        if not 0 <= particle < n:
            raise ValueError(
                f"invalid particle = {particle}: the {r.scene} run of {r.method} has {n} particle"
                + (f"s (0 ... {n - 1})" if n != 1 else " (0)")
            )
    fig = _figure((9.5, 7.0))
    ax = fig.add_subplot()
    for r in runs:
        i, j = particle * r.dim, particle * r.dim + 1
        (x, y), note = _finite([r.x[:, i], r.x[:, j]], r.method)
        (line,) = ax.plot(x, y, label=_label(r, runs) + note, linewidth=1.2)
        if r.diverged and np.isfinite(r.x[-1, i]) and np.isfinite(r.x[-1, j]):
            ax.plot([r.x[-1, i]], [r.x[-1, j]], "x", color=line.get_color(), markersize=8)
    ex = _exact(runs)
    if ex is not None:
        assert ex.exact_x is not None
        i, j = particle * ex.dim, particle * ex.dim + 1
        (x, y), note = _finite([ex.exact_x[:, i], ex.exact_x[:, j]], None)
        ax.plot(x, y, label="exact" + note, **_EXACT_STYLE)
    ax.plot([0.0], [0.0], marker="+", color="gray", markersize=10, linestyle="none")
    first = runs[0]
    i, j = particle * first.dim, particle * first.dim + 1
    if np.isfinite(first.x[0, i]) and np.isfinite(first.x[0, j]):
        ax.plot([first.x[0, i]], [first.x[0, j]], "ko", markersize=5, label="start")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(_axis(first, i))
    ax.set_ylabel(_axis(first, j))
    ax.set_title(_title("path", runs))
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small", borderaxespad=0.0)
    return fig


def path3d(
    trajs: Trajectory | Iterable[Trajectory], coords: Sequence[int] = (0, 1, 2), linewidth: float = 0.6
) -> Figure:
    """The path through three coordinates in 3D (an attractor, a particle in space), one line
    per run, the exact path dashed; ``coords`` picks them (default the first three: a flow's
    y[0], y[1], y[2], or particle 0's x, y, z). Drawn with :mod:`mpl_toolkits.mplot3d`.

    Raises ValueError for no runs, a run with no rows, or ``coords`` not three distinct
    coordinates of every run.

    Rows holding a non-finite value (a run blowing up) are left out, as a gap in the line,
    and the legend says how many; a run with no finite row at all is a ValueError.
    """
    runs = _runs(trajs)
    if isinstance(coords, str | bytes) or len(coords) != 3:
        raise ValueError(f"invalid coords = {coords!r}: give three coordinates, e.g. (0, 1, 2)")
    picked = [_check_coord(runs, c) for c in coords]
    if len(set(picked)) != 3:
        raise ValueError(f"invalid coords = {tuple(coords)!r}: the three coordinates must differ")
    fig = _figure((8.0, 7.0))
    ax = fig.add_subplot(projection="3d")
    for r in runs:
        cols, note = _finite([r.x[:, c] for c in picked], r.method)
        (line,) = ax.plot(*cols, label=_label(r, runs) + note, linewidth=linewidth)
        if r.diverged and np.isfinite(r.x[-1, picked]).all():
            ax.plot(*([r.x[-1, c]] for c in picked), "x", color=line.get_color(), markersize=8)
    ex = _exact(runs)
    if ex is not None:
        assert ex.exact_x is not None
        cols, note = _finite([ex.exact_x[:, c] for c in picked], None)
        ax.plot(*cols, label="exact" + note, **_EXACT_STYLE)
    first = runs[0]
    if np.isfinite(first.x[0, picked]).all():
        ax.plot(*([first.x[0, c]] for c in picked), "ko", markersize=5, label="start")
    ax.set_xlabel(_axis(first, picked[0]))
    ax.set_ylabel(_axis(first, picked[1]))
    ax.set_zlabel(_axis(first, picked[2]))
    ax.set_title(_title("path", runs))
    ax.legend(loc="upper left", fontsize="small")
    return fig


def energy(trajs: Trajectory | Iterable[Trajectory], relative: bool = False) -> Figure:
    """Total energy against time (``relative``: the relative energy error (E - E0) / the
    run's energy scale, see :attr:`physstep.Trajectory.energy_scale`).

    Raises ValueError for no runs, a run with no rows, or a run whose energy is unknown (a
    flow, or a force without a potential).

    Rows holding a non-finite value (a run blowing up) are left out, as a gap in the line,
    and the legend says how many; a run with no finite row at all is a ValueError.
    """
    runs = _runs(trajs)
    for i, r in enumerate(runs):
        if r.energy is None:
            raise ValueError(
                f"invalid trajectories[{i}] ({r.scene}, {r.method}): the energy of this {r.kind} run "
                "is unknown (a flow, or a force without a potential): nothing to plot"
            )
    fig = _figure()
    ax = fig.add_subplot()
    for r in runs:
        y = r.energy_error if relative else r.energy
        (t, y), note = _finite([r.t, y], r.method)
        ax.plot(t, y, label=_label(r, runs) + note)
    e0 = runs[0].energy[0]  # type: ignore[index]
    if not relative and np.isfinite(e0):
        ax.axhline(e0, label="E0 (exact)", **_EXACT_STYLE)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("(E - E0) / energy scale" if relative else "E (J)")
    ax.set_title(_title("relative energy error" if relative else "energy", runs))
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize="small")
    return fig


#: The principal axes of a rigid body, moments ascending (``Trajectory.body_spin``'s order).
_PRINCIPAL = ("smallest", "intermediate", "largest")
#: Relative errors below this (the rounding of doubles) are drawn at it on a log axis.
LOG_FLOOR = 1e-16


def _spin_label(run: Trajectory, runs: Sequence[Trajectory]) -> str:
    """``scene: method`` (the scene only where the runs mix scenes or systems), with the dt
    where the runs mix step sizes, and where the run stopped early."""
    label = f"{run.scene}: {run.method}" if len({r.scene for r in runs}) > 1 else run.method
    if len({r.dt for r in runs}) > 1:
        label += f" (dt = {run.dt:g} s)"
    if run.diverged:
        label += f" (failed at t = {run.t[-1]:.3g} s)"
    return label


def _l_change(run: Trajectory) -> np.ndarray | None:
    """``|L - L0| / |L0|`` of the total angular momentum at every row (``|L - L0|`` when
    ``L0 = 0``), or None without it."""
    ang = run.angular_momentum
    if ang is None:
        return None
    ang = np.asarray(ang, dtype=float)
    l0 = float(np.linalg.norm(ang[0])) if np.isfinite(ang[0]).all() else 0.0
    with np.errstate(all="ignore"):
        return np.linalg.norm(ang - ang[0], axis=1) / (l0 if l0 > 0 else 1.0)


def _legend_on_top(ax: Any, drawn: list[np.ndarray], entries: int, ncols: int, log: bool = False) -> None:
    """The legend of ``ax`` at its top, in headroom above the ``drawn`` values (y limits
    widened to make it, in log space on a log axis), so it never hides a line."""
    vals = [d[np.isfinite(d) & (d > 0 if log else True)] for d in drawn]
    vals = np.concatenate(vals) if vals else np.empty(0)
    rows = -(-entries // ncols)
    frac = min(0.65, 0.12 + 0.11 * rows)  # the part of the axis the legend takes
    if len(vals):
        lo, hi = float(vals.min()), float(vals.max())
        if log:
            lo, hi = math.log10(lo), math.log10(hi)
        span = (hi - lo) or max(abs(hi), 1.0)
        bottom, top = lo - 0.05 * span, hi + span * frac / (1 - frac)
        ax.set_ylim(*((10**bottom, 10**top) if log else (bottom, top)))
    ax.legend(loc="upper center", ncols=ncols, fontsize="small", framealpha=0.9)


def _errors(
    ax: Any,
    runs: Sequence[Trajectory],
    labels: list[str],
    values: list[np.ndarray | None],
    name: str,
    signed: str,
) -> None:
    """The relative errors ``values`` (one per run, None: unknown) against time on ``ax``.

    A log axis of ``|error|`` where the errors span two decades or more (the first row, zero
    by definition, left out; other values below :data:`LOG_FLOOR`, exact zeros included,
    drawn at it), else a linear axis of the error itself (``signed`` names it). The legend
    says which runs are unknown, below the floor throughout, or have non-finite rows."""
    mags = [np.abs(v[1:][np.isfinite(v[1:])]) for v in values if v is not None]
    pos = np.concatenate([m[m > 0] for m in mags]) if mags else np.empty(0)
    log = len(pos) > 0 and float(pos.max()) >= 100 * max(float(pos.min()), LOG_FLOOR)
    drawn = []
    for r, label, v in zip(runs, labels, values, strict=True):
        if v is None:
            ax.plot([], [], label=f"{label} (unknown)")
            continue
        (t, y), note = _finite([r.t, v], None)
        if log and len(y) > 1:
            t, y = t[1:], y[1:]  # the start, zero by definition: no dip to the floor
            if bool(np.all((np.abs(y) < LOG_FLOOR) | ~np.isfinite(y))):
                note += f" (below {LOG_FLOOR:g} throughout)"
            y = np.maximum(np.abs(y), LOG_FLOOR)
        elif len(y) and bool(np.all(y[np.isfinite(y)] == 0)):
            note += " (0 throughout)"
        ax.plot(t, y, label=label + note, lw=1.2)
        drawn.append(y)
    if log:
        ax.set_yscale("log")
    ax.set_ylabel(name if log else signed)
    ax.grid(True, which="major", alpha=0.3)
    _legend_on_top(ax, drawn, len(runs), 1 if len(runs) <= 3 else 2, log=log)


def spin(trajs: Trajectory | Iterable[Trajectory], body: int = 0) -> Figure:
    """Rigid bodies: the body-frame angular velocity of ``body`` against time, then the
    relative energy error and the relative change of the total angular momentum.

    One panel per run (the first is run 0's) with a line per principal axis, moments
    ascending (axis 1 the smallest moment, 2 the intermediate, 3 the largest): the
    tennis-racket flips show as the intermediate axis's line changing sign. Below, every
    run's relative energy error (see :attr:`physstep.Trajectory.energy_scale`) and
    ``|L - L0| / |L0|`` of its total angular momentum about the origin (an error where no
    external torque acts, as on the racket; under gravity, as on the top, it is the physics).
    Each of the two is drawn as ``|error|`` on a log axis where the values span two decades or
    more (values below :data:`LOG_FLOOR`, exact zeros included, are drawn at it, and the
    legend says which runs stay below it), else linearly.

    Raises ValueError for no runs, a run with no rows or without rigid bodies (a particle or
    flow run: nothing to plot), a ``body`` out of range, or a run with no finite spin.
    """
    runs = _runs(trajs)
    b = _index(body, "body")
    for i, r in enumerate(runs):
        if r.body_spin is None:
            raise ValueError(
                f"invalid trajectories[{i}] ({r.scene}, {r.method}): a {r.kind} run has no rigid bodies: "
                "nothing to plot (spin plots body scenes such as racket)"
            )
        n = r.body_spin.shape[1]
        if not 0 <= b < n:
            raise ValueError(
                f"invalid body = {b}: the {r.scene} run of {r.method} has {n} bod"
                + (f"ies (0 ... {n - 1})" if n != 1 else "y (0)")
            )
    labels = [_spin_label(r, runs) for r in runs]
    err = 0.9 + 0.12 * max(0, -(-len(runs) // (1 if len(runs) <= 3 else 2)) - 2)  # room for the legends
    heights = [1.0] * len(runs) + [err, err]
    fig = _figure((10.0, 2.4 * sum(heights) + 0.6))
    axes = fig.subplots(len(runs) + 2, 1, sharex=True, gridspec_kw={"height_ratios": heights})
    for ax, r, label in zip(axes, runs, labels, strict=False):
        cols, note = _finite([r.t, *(r.body_spin[:, b, k] for k in range(3))], r.method)
        for k, name in enumerate(_PRINCIPAL):
            ax.plot(cols[0], cols[k + 1], label=f"axis {k + 1} ({name} moment)", lw=1.0)
        ax.set_ylabel("omega, body frame (rad/s)")
        ax.set_title(label + note, fontsize="medium")
        ax.grid(True, alpha=0.3)
        _legend_on_top(ax, cols[1:], 3, 3)
    _errors(
        axes[-2],
        runs,
        labels,
        [r.energy_error for r in runs],
        "|E - E0| / energy scale",
        "(E - E0) / energy scale",
    )
    _errors(axes[-1], runs, labels, [_l_change(r) for r in runs], "|L - L0| / |L0|", "|L - L0| / |L0|")
    axes[-1].set_xlabel("t (s)")
    fig.suptitle(
        f"body-frame angular velocity of body {b}, energy and angular momentum: dt = {_fmt_dt(runs)}"
    )
    return fig


def _positive(value: Any) -> float | None:
    """``value`` as a float if it is a finite number > 0, else None."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) and x > 0 else None


def work_precision(
    data: dict[str, Any] | Sequence[dict[str, Any]], against: str = "evals", error: str = "max_error"
) -> Figure:
    """Error against work, log-log, one line per method, from :func:`physstep.lab.sweep` data.

    ``against`` is ``"evals"`` (force evaluations), ``"time"`` (wall time of the stepping
    loop, s) or ``"both"`` (two panels side by side); ``error`` is ``"max_error"`` (over the
    run) or ``"error"`` (at the final time). Points without a finite, positive error and work
    (diverged runs, zero errors, non-finite values) are left out, and the legend says how
    many for each method. Raises ValueError for data without rows, a row without a method,
    dt or the plotted keys, or data where no point is left to plot.
    """
    panels = {"evals": ["evals"], "time": ["time_s"], "both": ["evals", "time_s"]}.get(against)
    if error not in ("max_error", "error"):
        raise ValueError(f"invalid error = '{error}': must be max_error or error")
    if panels is None:
        raise ValueError(f"invalid against = '{against}': must be evals, time or both")
    if isinstance(data, dict):
        if "rows" not in data:
            raise ValueError("invalid data: no 'rows' (give the result of physstep.lab.sweep)")
        rows, meta = list(data["rows"]), data
    else:
        rows, meta = list(data), {}
    if not rows:
        raise ValueError("invalid data: no rows to plot")
    for n, r in enumerate(rows):
        missing = [k for k in ("method", "dt", error, *panels) if not isinstance(r, dict) or k not in r]
        if missing:
            raise ValueError(f"invalid data: row {n} has no '{missing[0]}'")
    fig = _figure((6.5 * len(panels) + 1.5, 5.0))
    axes = fig.subplots(1, len(panels), squeeze=False)[0]
    methods = list(dict.fromkeys(r["method"] for r in rows))
    plotted = 0
    for ax, key in zip(axes, panels, strict=True):
        for m in methods:
            mine = [r for r in rows if r["method"] == m]
            pts = sorted(
                (w, e)
                for w, e in ((_positive(r[key]), _positive(r[error])) for r in mine)
                if w is not None and e is not None
            )
            left = len(mine) - len(pts)
            label = m if not left else f"{m} ({left} of {len(mine)} points left out)"
            if not pts:
                ax.plot([], [], marker="o", markersize=4, label=label)
                continue
            plotted += len(pts)
            xs, ys = zip(*pts, strict=True)
            ax.loglog(xs, ys, marker="o", markersize=4, label=label)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("force evaluations" if key == "evals" else "stepping time (s)")
        ax.set_ylabel(
            "max position error over the run (m)" if error == "max_error" else "final position error (m)"
        )
        ax.grid(True, which="major", alpha=0.35)
        ax.grid(True, which="minor", alpha=0.1)
    if plotted == 0:
        raise ValueError(
            f"invalid data: no row has a finite, positive {error} and work to plot (did every run diverge?)"
        )
    against_txt = meta.get("error_against", "")
    scene = meta.get("scene", "")
    dts = sorted({d for d in (_positive(r["dt"]) for r in rows) if d is not None})
    dt_txt = f"dt = {dts[0]:g} ... {dts[-1]:g} s" if len(dts) > 1 else f"dt = {dts[0]:g} s" if dts else ""
    title = f"work-precision: {scene}, {dt_txt}" + (f" (error vs {against_txt})" if against_txt else "")
    fig.suptitle(title)
    axes[-1].legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="small", borderaxespad=0.0)
    return fig
