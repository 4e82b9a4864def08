"""Plots of rigid bodies: :func:`spin`, the body-frame angular velocity with the energy
and angular-momentum errors (re-exported by :mod:`physstep.plot`)."""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np
from matplotlib.figure import Figure

from physstep import Trajectory
from physstep._plotting import _errors, _figure, _finite, _fmt_dt, _index, _legend_on_top, _runs

__all__ = ["spin"]

#: The principal axes of a rigid body, moments ascending (``Trajectory.body_spin``'s order).
_PRINCIPAL = ("smallest", "intermediate", "largest")


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
        spin = r.body_spin
        assert spin is not None  # checked above
        cols, note = _finite([r.t, *(spin[:, b, k] for k in range(3))], r.method)
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
