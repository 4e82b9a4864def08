"""What the plots of :mod:`physstep.plot` and :mod:`physstep.plot_bodies` share: checking
the runs, the figure, titles and labels, the style of each line, legends, log axes.

Every line of a figure is told apart by its colour *and* its line style (a work-precision
line also by its marker): :data:`COLOURS` holds 20 distinct colours, so up to 20 runs (the
14 methods of the registry with room to spare) never repeat a colour, and the line styles
cycle over 4 so that a reader who cannot tell two colours apart still can tell the lines.
"""

from __future__ import annotations

import math
import operator
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.ticker import FuncFormatter, NullFormatter

from physstep import Trajectory

#: Distinct line colours, in order: matplotlib's tab10, then ten strong colours apart from
#: them (dark and saturated: no pastel, so that the methods late in the registry, such as
#: backward Euler and predictor-corrector, whose orbits leave the pack, are not drawn pale).
COLOURS = (
    "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
    "#bcbd22", "#17becf", "#393b79", "#637939", "#843c39", "#e7298a", "#1b9e77", "#e6ab02",
    "#7b4173", "#66a61e", "#a6761d", "#000080",
)  # fmt: skip
#: Line styles, cycled alongside the colours.
LINESTYLES = ("-", "--", "-.", ":")
#: Markers of the work-precision points, cycled alongside the colours.
MARKERS = ("o", "s", "^", "v", "D", "P", "X", "*")
#: More legend entries than this go to the right of the axes, not inside them.
LEGEND_INSIDE = 6


def style(k: int, marker: bool = False) -> dict[str, Any]:
    """The ``k``-th line's style: a colour and a line style (and a marker), distinct pairs
    for every ``k`` below ``len(COLOURS) * len(LINESTYLES)``."""
    s: dict[str, Any] = {
        "color": COLOURS[k % len(COLOURS)],
        "linestyle": LINESTYLES[(k + k // len(COLOURS)) % len(LINESTYLES)],
    }
    if marker:
        s["marker"] = MARKERS[k % len(MARKERS)]
    return s


def legend(ax: Any, entries: int) -> None:
    """The legend of ``ax``: inside (``best``) for a few entries, to the right for more."""
    if entries > LEGEND_INSIDE:
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small", borderaxespad=0.0)
    else:
        ax.legend(loc="best", fontsize="small")


def readable_log_ticks(ax: Any) -> None:
    """On the log axes of ``ax``: where an axis spans less than two decades (one or no
    labelled power of ten), label 2 and 5 of each decade as well; elsewhere only the powers
    of ten. matplotlib's default labels every minor tick on a short axis, and those overlap."""
    for axis, (lo, hi) in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
        if axis.get_scale() != "log" or not (lo > 0 and hi > 0):
            continue
        if math.log10(hi / lo) >= 2:
            axis.set_minor_formatter(NullFormatter())
            continue

        def fmt(x: float, _pos: int) -> str:
            e = math.floor(math.log10(x) + 1e-9)
            m = round(x / 10**e, 6)
            return f"${m:g}\\times10^{{{e}}}$" if m in (2.0, 5.0) else ""

        axis.set_minor_formatter(FuncFormatter(fmt))


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
    """``what: scenes, dt = ...``: what is drawn, of which scene, at which steps. The methods
    are the legend's, not the title's (14 names made a title of five lines)."""
    scenes = sorted({r.scene for r in runs})
    return f"{what}: {', '.join(scenes)}, dt = {_fmt_dt(runs)}"


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


#: Relative errors below this (the rounding of doubles) are drawn at it on a log axis.
LOG_FLOOR = 1e-16


def _legend_on_top(ax: Any, drawn: list[np.ndarray], entries: int, ncols: int, log: bool = False) -> None:
    """The legend of ``ax`` at its top, in headroom above the ``drawn`` values (y limits
    widened to make it, in log space on a log axis), so it never hides a line."""
    kept = [d[np.isfinite(d) & (d > 0 if log else True)] for d in drawn]
    vals = np.concatenate(kept) if kept else np.empty(0)
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
    side: bool = False,
    log: bool | None = None,
) -> None:
    """The relative errors ``values`` (one per run, None: unknown) against time on ``ax``.

    A log axis of ``|error|`` where the errors span two decades or more (the first row, zero
    by definition, left out; other values below :data:`LOG_FLOOR`, exact zeros included,
    drawn at it; ``log`` True or False decides instead), else a linear axis of the error
    itself (``signed`` names it). The legend says which runs are unknown, below the floor
    throughout, or have non-finite rows; it goes above the lines, or with ``side`` to the
    right of the axes (many runs)."""
    mags = [np.abs(v[1:][np.isfinite(v[1:])]) for v in values if v is not None]
    pos = np.concatenate([m[m > 0] for m in mags]) if mags else np.empty(0)
    if log is None:
        log = len(pos) > 0 and float(pos.max()) >= 100 * max(float(pos.min()), LOG_FLOOR)
    drawn = []
    for k, (r, label, v) in enumerate(zip(runs, labels, values, strict=True)):
        if v is None:
            ax.plot([], [], label=f"{label} (unknown)", **style(k))
            continue
        (t, y), note = _finite([r.t, v], None)
        if log and len(y) > 1:
            t, y = t[1:], y[1:]  # the start, zero by definition: no dip to the floor
            if bool(np.all((np.abs(y) < LOG_FLOOR) | ~np.isfinite(y))):
                note += f" (below {LOG_FLOOR:g} throughout)"
            y = np.maximum(np.abs(y), LOG_FLOOR)
        elif len(y) and bool(np.all(y[np.isfinite(y)] == 0)):
            note += " (0 throughout)"
        ax.plot(t, y, label=label + note, lw=1.2, **style(k))
        drawn.append(y)
    if log:
        ax.set_yscale("log")
    ax.set_ylabel(name if log else signed)
    ax.grid(True, which="major", alpha=0.3)
    if side:
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small", borderaxespad=0.0)
    else:
        _legend_on_top(ax, drawn, len(runs), 1 if len(runs) <= 3 else 2, log=log)
