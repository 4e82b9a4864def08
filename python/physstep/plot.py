"""Plots of the integrator lab, each returning a :class:`matplotlib.figure.Figure`.

The figures are built on matplotlib's object API (no pyplot state, Agg canvas), so they work
headless and never pop up a window; :func:`save` writes PNG or SVG by the file's extension.
Every function takes one trajectory or several (overlaid, one legend entry per method).

>>> import physstep
>>> from physstep import plot
>>> runs = [physstep.simulate("orbit", m, dt=0.1, until=20) for m in ("explicit-euler", "rk4")]
>>> fig = plot.orbit(runs)
>>> plot.save(fig, "orbit.png")  # doctest: +SKIP
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from physstep import Trajectory

__all__ = ["energy", "orbit", "phase", "save", "trajectory", "work_precision"]

_EXACT_STYLE: dict[str, Any] = {"color": "black", "linestyle": "--", "linewidth": 1.2, "alpha": 0.7}


def _runs(trajs: Trajectory | Iterable[Trajectory]) -> list[Trajectory]:
    runs = [trajs] if isinstance(trajs, Trajectory) else list(trajs)
    if not runs:
        raise ValueError("invalid trajectories = []: give at least one run")
    return runs


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
    if run.dim == 1:
        return "x" if run.x.shape[1] == 1 else f"x[{coord}]"
    axis = "xyz"[coord % run.dim] if run.dim <= 3 else str(coord % run.dim)
    particle = coord // run.dim
    return axis if run.x.shape[1] == run.dim else f"{axis}[{particle}]"


def save(fig: Figure, path: str | Path, **kwargs: Any) -> Path:
    """Writes ``fig`` to ``path``; the format (png, svg, pdf) comes from the extension."""
    path = Path(path)
    fmt = path.suffix.lstrip(".").lower()
    if fmt not in ("png", "svg", "pdf"):
        raise ValueError(f"invalid plot file '{path}': the extension must be .png, .svg or .pdf")
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, format=fmt, **kwargs)
    return path


def trajectory(trajs: Trajectory | Iterable[Trajectory], coord: int = 0) -> Figure:
    """Position coordinate ``coord`` against time, one line per run, the exact solution dashed."""
    runs = _runs(trajs)
    fig = _figure()
    ax = fig.add_subplot()
    for r in runs:
        ax.plot(r.t, r.x[:, coord], label=_label(r, runs))
    ex = next((r for r in runs if r.exact_x is not None), None)
    if ex is not None:
        assert ex.exact_x is not None
        longest = max((r for r in runs if r.exact_x is not None), key=lambda r: r.t[-1])
        assert longest.exact_x is not None
        ax.plot(longest.t, longest.exact_x[:, coord], label="exact", **_EXACT_STYLE)
    name = _coord_name(runs[0], coord)
    ax.set_xlabel("t (s)")
    ax.set_ylabel(f"{name} (m)")
    ax.set_title(_title(f"{name}(t)", runs))
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize="small")
    return fig


def phase(trajs: Trajectory | Iterable[Trajectory], coord: int = 0) -> Figure:
    """Phase portrait: velocity against position of coordinate ``coord``."""
    runs = _runs(trajs)
    fig = _figure((6.5, 6.0))
    ax = fig.add_subplot()
    for r in runs:
        ax.plot(r.x[:, coord], r.v[:, coord], label=_label(r, runs), linewidth=1.2)
    ex = next((r for r in runs if r.exact_x is not None and r.exact_v is not None), None)
    if ex is not None:
        assert ex.exact_x is not None and ex.exact_v is not None
        ax.plot(ex.exact_x[:, coord], ex.exact_v[:, coord], label="exact", **_EXACT_STYLE)
    start = runs[0]
    ax.plot([start.x[0, coord]], [start.v[0, coord]], "ko", markersize=5, label="start")
    name = _coord_name(runs[0], coord)
    ax.set_xlabel(f"{name} (m)")
    ax.set_ylabel("v (m/s)" if name == "x" else f"v_{name} (m/s)")
    ax.set_title(_title("phase portrait", runs))
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize="small")
    return fig


def orbit(trajs: Trajectory | Iterable[Trajectory], particle: int = 0) -> Figure:
    """The path of ``particle`` in the plane (equal axes), the exact path dashed."""
    runs = _runs(trajs)
    if any(r.dim < 2 for r in runs):
        raise ValueError("invalid trajectory: orbit plots need a 2D scene")
    fig = _figure((9.5, 7.0))
    ax = fig.add_subplot()
    i, j = particle * runs[0].dim, particle * runs[0].dim + 1
    for r in runs:
        (line,) = ax.plot(r.x[:, i], r.x[:, j], label=_label(r, runs), linewidth=1.2)
        if r.diverged:
            ax.plot([r.x[-1, i]], [r.x[-1, j]], "x", color=line.get_color(), markersize=8)
    ex = [r for r in runs if r.exact_x is not None]
    if ex:
        longest = max(ex, key=lambda r: r.t[-1])
        assert longest.exact_x is not None
        ax.plot(longest.exact_x[:, i], longest.exact_x[:, j], label="exact", **_EXACT_STYLE)
    ax.plot([0.0], [0.0], marker="+", color="gray", markersize=10, linestyle="none")
    ax.plot([runs[0].x[0, i]], [runs[0].x[0, j]], "ko", markersize=5, label="start")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(_title("path", runs))
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small", borderaxespad=0.0)
    return fig


def energy(trajs: Trajectory | Iterable[Trajectory], relative: bool = False) -> Figure:
    """Total energy against time (``relative``: the relative energy error (E - E0)/|E0|)."""
    runs = _runs(trajs)
    fig = _figure()
    ax = fig.add_subplot()
    for r in runs:
        y = r.energy_error if relative else r.energy
        ax.plot(r.t, y, label=_label(r, runs))
    if not relative:
        e0 = runs[0].energy[0]
        ax.axhline(e0, label="E0 (exact)", **_EXACT_STYLE)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("(E - E0) / |E0|" if relative else "E (J)")
    ax.set_title(_title("relative energy error" if relative else "energy", runs))
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize="small")
    return fig


def work_precision(
    data: dict[str, Any] | Sequence[dict[str, Any]], against: str = "evals", error: str = "max_error"
) -> Figure:
    """Error against work, log-log, one line per method, from :func:`physstep.lab.sweep` data.

    ``against`` is ``"evals"`` (force evaluations), ``"time"`` (wall time of the stepping
    loop, s) or ``"both"`` (two panels side by side); ``error`` is ``"max_error"`` (over the
    run) or ``"error"`` (at the final time). Diverged runs and zero errors are left out.
    """
    rows = data["rows"] if isinstance(data, dict) else list(data)
    meta = data if isinstance(data, dict) else {}
    panels = {"evals": ["evals"], "time": ["time_s"], "both": ["evals", "time_s"]}.get(against)
    if error not in ("max_error", "error"):
        raise ValueError(f"invalid error = '{error}': must be max_error or error")
    if panels is None:
        raise ValueError(f"invalid against = '{against}': must be evals, time or both")
    fig = _figure((6.5 * len(panels) + 1.5, 5.0))
    axes = fig.subplots(1, len(panels), squeeze=False)[0]
    methods = list(dict.fromkeys(r["method"] for r in rows))
    for ax, key in zip(axes, panels, strict=True):
        for m in methods:
            pts = sorted(
                (float(r[key]), float(r[error]))
                for r in rows
                if r["method"] == m and r.get(error) is not None and r[error] > 0 and r[key] > 0
            )
            if not pts:
                continue
            xs, ys = zip(*pts, strict=True)
            ax.loglog(xs, ys, marker="o", markersize=4, label=m)
        ax.set_xlabel("force evaluations" if key == "evals" else "stepping time (s)")
        ax.set_ylabel(
            "max position error over the run (m)" if error == "max_error" else "final position error (m)"
        )
        ax.grid(True, which="major", alpha=0.35)
        ax.grid(True, which="minor", alpha=0.1)
    against_txt = meta.get("error_against", "")
    scene = meta.get("scene", "")
    dts = sorted({float(r["dt"]) for r in rows})
    dt_txt = f"dt = {dts[0]:g} ... {dts[-1]:g} s" if len(dts) > 1 else f"dt = {dts[0]:g} s" if dts else ""
    title = f"work-precision: {scene}, {dt_txt}" + (f" (error vs {against_txt})" if against_txt else "")
    fig.suptitle(title)
    axes[-1].legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="small", borderaxespad=0.0)
    return fig
