"""Plots of the integrator lab, each returning a :class:`matplotlib.figure.Figure`.

The figures are built on matplotlib's object API (no pyplot state, Agg canvas), so they work
headless and never pop up a window; :func:`save` writes PNG or SVG by the file's extension.
Every function takes one trajectory or several (overlaid, one legend entry per method).
Flows (``Trajectory.kind == "flow"``: the attractors, your own :class:`physstep.Flow`) plot
their state ``y`` and its rate ``dy/dt``, without units; :func:`path3d` draws three
coordinates in 3D; :func:`energy` refuses a run whose energy is unknown. Rigid bodies
(``Trajectory.kind == "bodies"``) have :func:`spin`: the body-frame angular velocity, the
energy error and the change of the angular momentum.

Examples:
    >>> import physstep
    >>> from physstep import plot
    >>> runs = [physstep.simulate("orbit", m, dt=0.1, until=20) for m in ("explicit-euler", "rk4")]
    >>> fig = plot.orbit(runs)
    >>> plot.save(fig, "orbit.png")  # doctest: +SKIP
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from physstep import Trajectory
from physstep._plotting import (
    LOG_FLOOR,
    _axis,
    _check_coord,
    _coord_name,
    _errors,
    _figure,
    _finite,
    _index,
    _label,
    _runs,
    _title,
    legend,
    readable_log_ticks,
    style,
)
from physstep.plot_bodies import spin

__all__ = [
    "LOG_FLOOR",
    "energy",
    "orbit",
    "path3d",
    "phase",
    "save",
    "solver_sweep",
    "spin",
    "trajectory",
    "work_precision",
]

_EXACT_STYLE: dict[str, Any] = {"color": "black", "linestyle": "--", "linewidth": 1.2, "alpha": 0.7}


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
    for k, r in enumerate(runs):
        (t, y), note = _finite([r.t, r.x[:, coord]], r.method)
        ax.plot(t, y, label=_label(r, runs) + note, **style(k))
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
    legend(ax, len(runs) + (ex is not None))
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
    for k, r in enumerate(runs):
        (x, v), note = _finite([r.x[:, coord], r.v[:, coord]], r.method)
        ax.plot(x, v, label=_label(r, runs) + note, linewidth=1.2, **style(k))
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
    legend(ax, len(runs) + 2)
    return fig


#: The line width of a path that leaves the pack (:func:`_leaving`); the others are 1.2.
LEAVING_WIDTH = 2.2
#: A path leaves the pack when its largest distance from the exact path is above this many
#: times the runs' median of it, and above this fraction of the exact path's size.
LEAVING_FACTOR = 5.0
LEAVING_SIZE = 0.05


def _leaving(runs: Sequence[Trajectory], particle: int) -> set[int]:
    """The runs whose path of ``particle`` leaves the pack (explicit Euler's outward spiral,
    backward Euler's inward one, predictor-corrector flung out on the orbit): their largest
    distance from the exact path (as a curve: a phase error along it does not count) is
    above :data:`LEAVING_FACTOR` times the runs' median and above :data:`LEAVING_SIZE` of
    the path's size. Drawn wider and on top, so that a line the eye follows away from the
    others is never a faint one. Without an exact solution: none."""
    ex_run = _exact(runs)
    if len(runs) < 3 or ex_run is None or ex_run.exact_x is None:
        return set()
    i, j = particle * ex_run.dim, particle * ex_run.dim + 1
    curve = np.asarray(ex_run.exact_x)[:, [i, j]]
    curve = curve[np.isfinite(curve).all(axis=1)][:: max(1, len(curve) // 2000)]
    if not len(curve):
        return set()
    size = float(np.abs(curve).max())
    dev = []
    for r in runs:
        pts = r.x[:, [i, j]]
        pts = pts[np.isfinite(pts).all(axis=1)][:: max(1, len(pts) // 2000)]
        if not len(pts):
            dev.append(0.0)
            continue
        d = np.hypot(pts[:, None, 0] - curve[None, :, 0], pts[:, None, 1] - curve[None, :, 1]).min(axis=1)
        dev.append(float(d.max()))
    median = float(np.median(dev))
    return {k for k, d in enumerate(dev) if d > LEAVING_FACTOR * median and d > LEAVING_SIZE * size}


#: A path that goes further than this many times the exact path's size is left to run out of
#: the view (its legend says so), which frames the others and the exact path.
VIEW_FACTOR = 30.0


def _framed(runs: Sequence[Trajectory], particle: int) -> tuple[set[int], tuple[float, ...] | None]:
    """The runs whose path of ``particle`` goes past :data:`VIEW_FACTOR` times the exact path's
    size (linearly implicit Euler flung 30 km out of a 1 m orbit), and the view that frames
    every other path and the exact one (x0, x1, y0, y1); none and None when no path goes that
    far, or without an exact solution."""
    ex = _exact(runs)
    if ex is None or ex.exact_x is None:
        return set(), None
    i, j = particle * ex.dim, particle * ex.dim + 1
    curve = np.asarray(ex.exact_x)[:, [i, j]]
    curve = curve[np.isfinite(curve).all(axis=1)]
    if not len(curve):
        return set(), None
    bound = VIEW_FACTOR * max(float(np.abs(curve).max()), 1e-300)
    kept, out = [curve], set()
    for k, r in enumerate(runs):
        pts = r.x[:, [i, j]]
        pts = pts[np.isfinite(pts).all(axis=1)]
        if len(pts) and float(np.abs(pts).max()) > bound:
            out.add(k)
        elif len(pts):
            kept.append(pts)
    if not out:
        return set(), None
    box = np.concatenate(kept)
    (x0, y0), (x1, y1) = box.min(axis=0), box.max(axis=0)
    pad = 0.05 * max(x1 - x0, y1 - y0)
    return out, (x0 - pad, x1 + pad, y0 - pad, y1 + pad)


def orbit(trajs: Trajectory | Iterable[Trajectory], particle: int = 0) -> Figure:
    """The path of ``particle`` in the plane (equal axes), the exact path dashed (a flow:
    y[0] against y[1]).

    Raises ValueError for no runs, a run with no rows, a 1D scene, or ``particle`` out of
    range.

    The paths that leave the pack (far from the exact path where most runs stay near it:
    explicit Euler spiralling out, backward Euler in) are drawn wider and on top. A path that
    goes past :data:`VIEW_FACTOR` times the exact path's size runs out of the view, which
    frames the others, and its legend says "leaves the view".

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
    far = _leaving(runs, particle)
    out, view = _framed(runs, particle)
    for k, r in enumerate(runs):
        i, j = particle * r.dim, particle * r.dim + 1
        (x, y), note = _finite([r.x[:, i], r.x[:, j]], r.method)
        if k in out:
            note += " (leaves the view)"
        width, z = (LEAVING_WIDTH, 3) if k in far else (1.2, 2)
        (line,) = ax.plot(x, y, label=_label(r, runs) + note, linewidth=width, zorder=z, **style(k))
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
    if view is None:
        ax.set_aspect("equal", adjustable="datalim")
    else:
        # a fixed view: the axes' box takes the equal aspect (datalim would move the view)
        ax.set_xlim(view[0], view[1])
        ax.set_ylim(view[2], view[3])
        ax.set_aspect("equal", adjustable="box")
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
    for k, r in enumerate(runs):
        cols, note = _finite([r.x[:, c] for c in picked], r.method)
        (line,) = ax.plot(*cols, label=_label(r, runs) + note, linewidth=linewidth, **style(k))
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
    if len(runs) + 2 > 6:
        ax.legend(loc="upper left", bbox_to_anchor=(1.05, 1.0), fontsize="small", borderaxespad=0.0)
    else:
        ax.legend(loc="upper left", fontsize="small")
    return fig


def _peak(values: np.ndarray | None) -> float:
    """The largest finite ``|value|``, 0 when there is none."""
    if values is None:
        return 0.0
    finite = np.abs(values[np.isfinite(values)])
    return float(finite.max()) if len(finite) else 0.0


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
    labels = [_label(r, runs) for r in runs]
    if relative:
        # |error| on a log axis where the runs' largest errors span two decades or more (the
        # 14 methods span 1e-16 to 1), else the signed error on a linear one
        peaks = [_peak(r.energy_error) for r in runs]
        big = [p for p in peaks if p > 0]
        log = bool(big) and max(big) >= 100 * max(min(peaks), LOG_FLOOR)
        _errors(
            ax,
            runs,
            labels,
            [r.energy_error for r in runs],
            "|E - E0| / energy scale",
            "(E - E0) / energy scale",
            side=len(runs) > 3,
            log=log,
        )
    else:
        drawn = []
        for k, (r, label) in enumerate(zip(runs, labels, strict=True)):
            assert r.energy is not None  # checked above
            (t, y), note = _finite([r.t, r.energy], r.method)
            ax.plot(t, y, label=label + note, **style(k))
            drawn.append(y[np.isfinite(y)])
        e0 = runs[0].energy[0]  # type: ignore[index]
        if np.isfinite(e0):
            ax.axhline(e0, label="E0 (exact)", **_EXACT_STYLE)
        values = np.concatenate(drawn)
        if len(values) and values.min() > 0 and values.max() >= 100 * values.min():
            ax.set_yscale("log")  # energies spanning decades (explicit Euler's growth)
        ax.set_ylabel("E (J)")
        ax.grid(True, alpha=0.3)
        legend(ax, len(runs) + 1)
    ax.set_xlabel("t (s)")
    ax.set_title(_title("relative energy error" if relative else "energy", runs))
    readable_log_ticks(ax)
    return fig


def _positive(value: Any) -> float | None:
    """``value`` as a float if it is a finite number > 0, else None."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) and x > 0 else None


def work_precision(data: Any, against: str = "evals", error: str = "max_error") -> Figure:
    """Error against work, log-log, one line per method, from :func:`physstep.lab.sweep` data:
    its :class:`~physstep.lab.SweepResult`, that result's ``to_dict()``, or a list of rows
    (:class:`~physstep.lab.SweepRow` or their dicts).

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
    if callable(getattr(data, "to_dict", None)):  # a SweepResult
        data = data.to_dict()
    if isinstance(data, dict):
        if "rows" not in data:
            raise ValueError("invalid data: no 'rows' (give the result of physstep.lab.sweep)")
        rows, meta = list(data["rows"]), data
    else:
        rows, meta = [r.to_dict() if callable(getattr(r, "to_dict", None)) else r for r in data], {}
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
        for k, m in enumerate(methods):
            mine = [r for r in rows if r["method"] == m]
            pts = sorted(
                (w, e)
                for w, e in ((_positive(r[key]), _positive(r[error])) for r in mine)
                if w is not None and e is not None
            )
            left = len(mine) - len(pts)
            label = m if not left else f"{m} ({left} of {len(mine)} points left out)"
            if not pts:
                ax.plot([], [], markersize=4, label=label, **style(k, marker=True))
                continue
            plotted += len(pts)
            xs, ys = zip(*pts, strict=True)
            ax.loglog(xs, ys, markersize=4, label=label, **style(k, marker=True))
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("force evaluations" if key == "evals" else "stepping time (s)")
        ax.set_ylabel(
            "max position error over the run (m)" if error == "max_error" else "final position error (m)"
        )
        ax.grid(True, which="major", alpha=0.35)
        ax.grid(True, which="minor", alpha=0.1)
        readable_log_ticks(ax)
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


def solver_sweep(data: Any) -> Figure:
    """The contact solvers over splits of their passes into substeps and iterations, from
    :func:`physstep.lab.sweep_solvers` (its result or that result's ``to_dict()``): three
    panels (the tracked solid's drift and the deepest penetration of the last second, log
    scales; ms a step, linear from zero)
    against the split ("8x1": 8 substeps of 1 iteration), one line per solver. Values at or
    below zero are drawn at :data:`LOG_FLOOR`'s floor of the log axis. ValueError for data
    without rows or a row without the plotted keys.
    """
    if callable(getattr(data, "to_dict", None)):
        data = data.to_dict()
    if not isinstance(data, dict) or not data.get("rows"):
        raise ValueError("invalid data: no rows (give the result of physstep.lab.sweep_solvers)")
    rows = data["rows"]
    keys = ["solver", "substeps", "iterations", "drift", "settled_penetration", "ms_per_step"]
    keys.append("passes_per_step")
    for n, r in enumerate(rows):
        missing = [k for k in keys if k not in r]
        if missing:
            raise ValueError(f"invalid data: row {n} has no '{missing[0]}'")
    splits = list(dict.fromkeys((r["substeps"], r["iterations"]) for r in rows))
    labels = [f"{n}x{k}" for n, k in splits]
    solvers = list(dict.fromkeys(r["solver"] for r in rows))
    panels = [
        ("drift", "tracked solid's drift (m)"),
        ("settled_penetration", "deepest penetration, last second (m)"),
        ("ms_per_step", "ms a step"),
    ]
    fig = _figure((15.0, 4.8))
    axes = fig.subplots(1, len(panels), squeeze=False)[0]
    for ax, (key, name) in zip(axes, panels, strict=True):
        for k, solver in enumerate(solvers):
            by = {(r["substeps"], r["iterations"]): r[key] for r in rows if r["solver"] == solver}
            xs = [i for i, s in enumerate(splits) if s in by]
            if key == "ms_per_step":  # a cost: linear from zero
                ax.plot(
                    xs,
                    [float(by[splits[i]]) for i in xs],
                    markersize=5,
                    label=solver,
                    **style(k, marker=True),
                )
            else:
                ys = [max(float(by[splits[i]]), LOG_FLOOR) for i in xs]
                ax.semilogy(xs, ys, markersize=5, label=solver, **style(k, marker=True))
        if key == "ms_per_step":  # after every line, so that the top fits them all
            ax.set_ylim(0.0, 1.1 * max(float(r[key]) for r in rows))
        ax.set_xticks(range(len(splits)), labels)
        ax.set_xlabel("substeps x iterations")
        ax.set_ylabel(name)
        ax.grid(True, which="major", alpha=0.35)
    passes = sorted({r["passes_per_step"] for r in rows})
    span = f"{passes[0]:g}" if len(passes) == 1 else f"{passes[0]:g}-{passes[-1]:g}"
    cost = f"{span} passes a step"
    fig.suptitle(f"contact solvers on {data.get('scene', '')}: {cost}, {data.get('until', 0):g} s")
    axes[-1].legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="small", borderaxespad=0.0)
    return fig
