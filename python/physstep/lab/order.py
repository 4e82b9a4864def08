"""``order``: the observed convergence order of a method from successive halvings of dt."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

import physstep
from physstep import Trajectory
from physstep.lab.common import EPS, REFERENCE_METHOD, REFERENCE_REFINE, positive, steps
from physstep.lab.reference import error_against, final_error, reference
from physstep.lab.results import OrderResult, OrderRun
from physstep.lab.system import Subject

#: The default run length of :func:`order`, in natural time scales (a third of a period:
#: errors build up, phase errors do not wrap, and it is no multiple of a quarter period,
#: where symplectic Euler's oscillating error cancels to second order).
UNTIL_SCALES = 0.3
#: Most step sizes :func:`order` runs, and most steps of its finest run (the reference, for
#: scenes without an exact solution, takes REFERENCE_REFINE times as many).
MAX_LEVELS = 20
MAX_ORDER_STEPS = 2**22
#: An error below ROUNDOFF * eps * (position scale) * sqrt(steps) is roundoff (a random walk
#: of rounding errors, with a wide margin): left out of the orders.
ROUNDOFF = 100.0


def _slope(dts: Sequence[float], errs: Sequence[float]) -> float:
    """The least-squares slope of log(error) against log(dt), in the closed form with
    correctly rounded sums: the same bits on every CPU (``np.polyfit`` goes through LAPACK,
    whose kernels and their roundings depend on the CPU: its last digits differed between an
    Intel and an AMD machine)."""
    x = [math.log(d) for d in dts]
    y = [math.log(e) for e in errs]
    xm, ym = math.fsum(x) / len(x), math.fsum(y) / len(y)
    sxy = math.fsum((a - xm) * (b - ym) for a, b in zip(x, y, strict=True))
    return sxy / math.fsum((a - xm) ** 2 for a in x)


def _plan(subject: Subject, dt: Any, until: Any, levels: Any, scale: Any) -> tuple[float, int]:
    """Validates :func:`order`'s arguments up front; returns ``until`` and the coarsest step
    count ``n0`` (even), refusing a finest run over :data:`MAX_ORDER_STEPS` steps."""
    if isinstance(levels, bool) or not isinstance(levels, int | np.integer):
        raise ValueError(f"invalid levels = {levels!r}: must be a whole number")
    if not 2 <= levels <= MAX_LEVELS:
        raise ValueError(f"invalid levels = {levels}: must be between 2 and {MAX_LEVELS}")
    if until is None:
        until = UNTIL_SCALES * subject.time_scale(scale)
    until = positive("until", until)
    if dt is not None:
        dt = positive("dt", dt)
        if dt > until:
            raise ValueError(f"invalid dt = {dt!r}: must be <= until = {until!r} (at least one step)")
    if dt is not None and not until / dt <= MAX_ORDER_STEPS:
        raise ValueError(
            f"invalid dt = {dt!r}: until / dt = {until / dt:.4g} steps is more than {MAX_ORDER_STEPS}; "
            "use a larger dt or a shorter until"
        )
    n0 = 32 if dt is None else max(1, round(until / dt))
    n0 += n0 % 2  # even step counts
    finest = n0 * 2 ** (int(levels) - 1)
    if finest > MAX_ORDER_STEPS:
        raise ValueError(
            f"invalid levels = {levels} with dt = {until / n0:.6g} and until = {until:.6g}: the finest "
            f"run would take {n0} * 2^{int(levels) - 1} = {finest:.4g} steps (at most {MAX_ORDER_STEPS}); "
            "use fewer levels, a larger dt or a shorter until"
        )
    if not until / finest > 0:
        given = "" if dt is None else f" with dt = {dt!r}"
        raise ValueError(
            f"invalid until = {until!r}{given}: the finest run's step, until / {finest}, underflows "
            "to 0; use a larger until"
        )
    return until, n0


def order(
    scene: Any,
    method: str,
    dt: float | None = None,
    until: float | None = None,
    params: dict[str, float] | None = None,
    *,
    levels: int = 5,
    time_scale: float | None = None,
) -> OrderResult:
    """The observed convergence order of ``method`` on ``scene`` (a scene's name or a system,
    as :func:`physstep.simulate` takes; a split method on a flow is refused).

    Runs ``levels`` step sizes dt, dt/2, dt/4, ... up to ``until``. dt is adjusted so that
    ``until`` is a whole, even number of steps (symplectic-euler-alternating is second order
    at odd counts too, but with another error constant, which would bend the pairwise order
    between an odd and an even run). Defaults: ``until`` = 0.3 natural time scales
    (``time_scale``, else :func:`physstep.lab.time_scale`: a third of the spring's or the
    orbit's period, estimated for a system) and dt = until / 32. ``levels`` is 2 to
    :data:`MAX_LEVELS` and the finest run at most :data:`MAX_ORDER_STEPS` steps, checked
    before anything runs (ValueError naming ``levels``, ``dt`` and ``until``).

    The error is the final position error (max over coordinates) against the exact solution,
    or against RK4 at a sixteenth of the finest dt. An error below :data:`ROUNDOFF` eps scale
    sqrt(steps) (scale: the largest |x| of the run) is roundoff: when the finest errors reach
    it the window slides to coarser dt; when the coarsest are not yet asymptotic (error above
    10 % of the scale, or diverged) it slides to finer dt. ``order`` is the least-squares
    slope of log error on log dt over the three finest runs of the window (None if the method
    is exact to roundoff on this scene); ``order_all`` is the slope over every usable run.

    Returns an :class:`~physstep.lab.results.OrderResult` (its fields documented there;
    ``.to_dict()`` is what ``physstep order --format json`` prints): ``order``, ``order_all``,
    the registry's ``info_order``, ``error_against``, ``note`` and ``runs``, one
    :class:`~physstep.lab.results.OrderRun` per step size (``dt``, ``steps``, ``error``: inf
    where the run diverged, ``order``: the pairwise order from the previous run).
    """
    subject = Subject(scene, params)
    subject.check_method(method)
    until, n0 = _plan(subject, dt, until, levels, time_scale)
    levels = int(levels)
    has_exact = subject.has_exact

    runs: dict[int, Trajectory | None] = {}  # k -> run at n0 * 2**k steps
    refs: dict[int, Trajectory] = {}
    ref_method = [REFERENCE_METHOD]  # the reference run's method, once one is made

    def count(k: int) -> int:
        return n0 * 2**k if k >= 0 else n0 // 2 ** (-k)

    def run(k: int) -> Trajectory | None:
        if k not in runs:
            n = count(k)  # only the first and the last rows are recorded
            traj = subject.run(method, until / n, until, stop_on_diverge=True, every=n)
            runs[k] = None if traj.diverged else traj
        return runs[k]

    def errors(ks: list[int]) -> tuple[list[float], float | None]:
        ref_dt = None
        ref = None
        if not has_exact:
            kmax = max(ks)
            if kmax not in refs:
                n_ref = count(kmax) * REFERENCE_REFINE
                refs[kmax] = reference(scene, until / count(kmax), until, params, every=n_ref)
            ref = refs[kmax]
            ref_dt = ref.dt
        errs = []
        for k in ks:
            traj = run(k)
            errs.append(math.inf if traj is None else final_error(traj, ref))
        if ref is not None:
            ref_method[0] = ref.method
        return errs, ref_dt

    # the position scale: from the exact solution, else from a fine RK4 run
    n_fine = n0 * 16
    fine = subject.run(
        REFERENCE_METHOD, until / n_fine, until, stop_on_diverge=True, every=max(1, n_fine // 4096)
    )
    xs = fine.exact_x if fine.exact_x is not None else fine.x
    scale = float(np.abs(xs).max()) or 1.0
    ceiling = 0.1 * scale
    refine = 1 if has_exact else REFERENCE_REFINE

    def floor(dt_run: float) -> float:  # the roundoff level of a run (and of its reference)
        return ROUNDOFF * EPS * scale * math.sqrt(refine * steps(dt_run, until))

    # the smallest k allowed keeps n >= 2 and even; the largest keeps n <= 2**17
    kmin = -int(math.log2(n0 // 2)) if n0 >= 4 and (n0 & (n0 - 1)) == 0 else 0
    kmax = max(0, int(math.log2(2**17 / n0)) - levels + 1)
    lo = 0
    note = ""
    for _ in range(24):
        ks = list(range(lo, lo + levels))
        errs, ref_dt = errors(ks)
        low = errs[-1] < floor(until / count(ks[-1]))
        high = errs[0] > ceiling or not math.isfinite(errs[0])
        if low and not high and lo > kmin:
            lo -= 1
            continue
        if high and not low and lo < kmax:
            lo += 1
            continue
        break
    good = [(until / count(k), e) for k, e in zip(ks, errs, strict=True)]
    out_runs = []
    prev = None
    for d, e in good:
        pair = None
        if prev is not None and prev[1] > floor(prev[0]) and e > floor(d) and math.isfinite(prev[1] * e):
            pair = math.log(prev[1] / e) / math.log(prev[0] / d)
        out_runs.append(OrderRun(dt=d, steps=steps(d, until), error=e, order=pair))
        prev = (d, e)
    usable = [(d, e) for d, e in good if floor(d) < e <= ceiling]
    fit = usable[-3:]
    if len(usable) >= 2:
        observed: float | None = _slope([d for d, _ in fit], [e for _, e in fit])
    else:
        observed = None
        note = (
            "errors at roundoff level at every dt tried: the method is exact on this scene"
            if all(e <= floor(d) for d, e in good)
            else "too few runs in the asymptotic range"
        )
    if not note and len(usable) < len(good):
        note = f"{len(good) - len(usable)} run(s) outside the asymptotic range left out of the fit"
    return OrderResult(
        scene=subject.name,
        kind=subject.kind,
        method=method,
        info_order=physstep.method(method).order,
        order=observed,
        order_all=_slope([d for d, _ in usable], [e for _, e in usable]) if len(usable) >= 2 else None,
        until=until,
        params=subject.full_params,
        error_against=error_against(has_exact, ref_dt, ref_method[0], run_dt=until / count(max(ks))),
        error=f"final {'state' if subject.kind == 'flow' else 'position'} error, max over coordinates",
        runs=tuple(out_runs),
        note=note,
    )
