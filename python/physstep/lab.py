"""The integrator lab: measure how each method behaves on a scene.

Four measurements, each returning plain data (dicts and lists, JSON-ready):

- :func:`compare`: one row per method (order, force evaluations per step, energy error and
  drift, final error, ns per step).
- :func:`order`: the observed convergence order from successive halvings of dt.
- :func:`stability`: the largest stable dt, from the amplification matrix of the repeating
  step map on the linear/affine scenes and from a bounded-growth search on the others.
- :func:`sweep`: work-precision data (error against force evaluations and time).

Errors are measured against the scene's exact solution where it has one and otherwise
against a reference solution (RK4 at a sixteenth of the finest dt, interpolated with cubic
Hermite polynomials between its rows); every result says which in ``error_against``. Every
run the lab would make is checked against :func:`physstep.simulate`'s limits before any is
made: a refusal names the lab's own argument (``dt``, ``dts``, ``until``, ``levels``).
"""

from __future__ import annotations

import math
import statistics
import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

import physstep
from physstep import Trajectory

__all__ = [
    "LINEAR_SCENES",
    "REFERENCE_METHOD",
    "REFERENCE_REFINE",
    "amplification",
    "compare",
    "order",
    "reference",
    "stability",
    "sweep",
    "time_scale",
]

#: The scenes whose step map is linear or affine in the state (amplification-matrix analysis).
LINEAR_SCENES = ("spring", "drag", "projectile")
#: The method and refinement of the reference solution for scenes without an exact one.
REFERENCE_METHOD = "rk4"
REFERENCE_REFINE = 16
#: physstep.simulate's limits: steps per run, and values (t, x, v, a, energy per row) recorded.
MAX_STEPS = 1e9
MAX_RECORDED = 500_000_000
#: How the timings are repeated: at least TIMING_MIN_RUNS runs and TIMING_MIN_S seconds in
#: all, at most TIMING_MAX_RUNS runs or TIMING_MAX_S seconds; the median is reported.
TIMING_MIN_RUNS = 3
TIMING_MIN_S = 0.05
TIMING_MAX_RUNS = 25
TIMING_MAX_S = 1.0
#: What the energy errors are relative to (see :attr:`physstep.Trajectory.energy_scale`).
ENERGY_ERROR = "(E - E0) / energy scale, the scale = max(|E0|, max kinetic energy of the run)"

_EPS = float(np.finfo(float).eps)


# --------------------------------------------------------------------------------------
# validation


def _check_method(name: str) -> None:
    if not isinstance(name, str):
        raise ValueError(f"invalid method = {name!r}: must be a method name (a string)")
    physstep.method(name)  # ValueError listing the valid names


def _check_methods(methods: Sequence[str]) -> list[str]:
    """The list of method names; a bare string (iterable, but not a list) is refused."""
    if isinstance(methods, str | bytes):
        raise ValueError(f"invalid methods = {methods!r}: give a list of method names, e.g. [{methods!r}]")
    try:
        names = list(methods)
    except TypeError:
        raise ValueError(f"invalid methods = {methods!r}: give a list of method names") from None
    if not names:
        raise ValueError("invalid methods = []: give at least one method")
    for m in names:
        _check_method(m)
    return names


def _check_scene(name: str) -> dict[str, Any]:
    return physstep.scene(name)


def _number(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise ValueError(f"invalid {name} = {value!r}: must be a number")
    return float(value)


def _positive(name: str, value: Any) -> float:
    """``value`` as a float, or ValueError naming ``name`` unless it is finite and > 0."""
    x = _number(name, value)
    if not (x > 0 and math.isfinite(x)):
        raise ValueError(f"invalid {name} = {x!r}: must be a finite number > 0")
    return x


def _check_run(
    dt: float,
    until: float,
    coords: int,
    *,
    every: int = 1,
    refine: int = 1,
    dt_name: str = "dt",
    what: str = "the run",
) -> int:
    """Steps of ``dt / refine`` up to ``until``, or ValueError naming ``until`` and ``dt_name``
    when :func:`physstep.simulate` would refuse the run (more than :data:`MAX_STEPS` steps, or
    more than :data:`MAX_RECORDED` values recorded at one row every ``every`` steps)."""
    n = _steps(dt / refine, until)
    fix = f"use a larger {'dt in dts' if dt_name == 'dts' else dt_name} or a shorter until"
    if n > MAX_STEPS:
        raise ValueError(
            f"invalid until = {until!r} with {dt_name} = {dt!r}: {what} would take {n:.4g} steps "
            f"(at most {MAX_STEPS:.0e}); {fix}"
        )
    values = (n // every + 2) * (3 * coords + 2)
    if values > MAX_RECORDED:
        raise ValueError(
            f"invalid until = {until!r} with {dt_name} = {dt!r}: {what} would record {values} values "
            f"(at most {MAX_RECORDED}); {fix}"
        )
    return n


# --------------------------------------------------------------------------------------
# helpers


def _probe(scene: str, params: dict[str, float] | None) -> Trajectory:
    """A zero-length run: the engine validates the scene and ``params`` and answers with the
    resolved parameters (``.params``), the initial state and whether an exact solution exists
    (``.exact_x``)."""
    return physstep.simulate(scene, REFERENCE_METHOD, dt=1.0, until=0.0, params=params)


def _full_params(scene: str, params: dict[str, float] | None) -> dict[str, float]:
    return dict(_probe(scene, params).params)


def _coords(scene: str, params: dict[str, float] | None) -> int:
    """The number of coordinates of the scene's state (particles times dimensions)."""
    return int(_probe(scene, params).x.shape[1])


def time_scale(scene: str, params: dict[str, float] | None = None) -> float:
    """The scene's natural time scale, s: its period where it oscillates or orbits, its decay
    time m/c under drag, otherwise its default run length."""
    spec = _check_scene(scene)
    p = _full_params(scene, params)
    tau = 2.0 * math.pi
    if scene == "spring":
        if p["k"] > 0:
            return tau * math.sqrt(p["m"] / p["k"])
        if p["c"] > 0:
            return p["m"] / p["c"]
    elif scene == "drag" and p["c"] > 0:
        return p["m"] / p["c"]
    elif scene == "orbit":
        return tau * math.sqrt(p["r"] ** 3 / p["gm"])
    elif scene == "kepler":
        return tau
    elif scene == "pendulum" and p["g"] > 0:
        return tau * math.sqrt(p["length"] / p["g"])
    elif scene == "chain" and p["k"] > 0:
        return tau * math.sqrt(p["m"] / p["k"])
    return float(spec["until"])


def _steps(dt: float, until: float) -> int:
    """The step count physstep.simulate takes for (dt, until): until / dt rounded down, a
    quotient within 1e-9 of a whole number counting as that number."""
    r = until / dt
    if not math.isfinite(r):
        return math.inf  # type: ignore[return-value]
    return int(round(r)) if abs(r - round(r)) <= 1e-9 * max(r, 1.0) else int(math.floor(r))


def _hermite(traj: Trajectory, times: np.ndarray) -> np.ndarray:
    """Positions of ``traj`` at ``times`` by cubic Hermite interpolation of (x, v) between rows."""
    t = traj.t
    times = np.atleast_1d(np.asarray(times, dtype=float))
    i = np.clip(np.searchsorted(t, times, side="right") - 1, 0, len(t) - 2)
    h = t[i + 1] - t[i]
    s = ((times - t[i]) / h)[:, None]
    h = h[:, None]
    x0, x1, v0, v1 = traj.x[i], traj.x[i + 1], traj.v[i], traj.v[i + 1]
    h00 = 2 * s**3 - 3 * s**2 + 1
    h10 = s**3 - 2 * s**2 + s
    h01 = -2 * s**3 + 3 * s**2
    h11 = s**3 - s**2
    out = h00 * x0 + h10 * h * v0 + h01 * x1 + h11 * h * v1
    # rows hit exactly (to rounding) are taken as they are
    exact = np.isclose(
        times, t[np.clip(np.searchsorted(t, times), 0, len(t) - 1)], rtol=0, atol=1e-9 * h[:, 0]
    )
    j = np.clip(np.searchsorted(t, times), 0, len(t) - 1)
    out[exact] = traj.x[j[exact]]
    return out


def reference(
    scene: str, dt: float, until: float, params: dict[str, float] | None = None, *, every: int = 1
) -> Trajectory:
    """The reference run: :data:`REFERENCE_METHOD` at ``dt / REFERENCE_REFINE``, one row every
    ``every`` of its steps (the last always)."""
    return physstep.simulate(scene, REFERENCE_METHOD, dt / REFERENCE_REFINE, until, params, every=every)


def _final_error(traj: Trajectory, ref: Trajectory | None) -> float:
    """Max-coordinate distance of the final position from the exact or reference one."""
    if traj.exact_x is not None:
        return float(np.abs(traj.x[-1] - traj.exact_x[-1]).max())
    assert ref is not None
    want = _hermite(ref, np.array([traj.t[-1]]))[0]
    return float(np.abs(traj.x[-1] - want).max())


def _max_error(traj: Trajectory, ref: Trajectory | None) -> float:
    """Max over the run (and over coordinates) of the distance from the exact/reference path."""
    if traj.exact_x is not None:
        return float(np.abs(traj.x - traj.exact_x).max())
    assert ref is not None
    return float(np.abs(traj.x - _hermite(ref, traj.t)).max())


def _has_exact(scene: str, params: dict[str, float] | None) -> bool:
    return _probe(scene, params).exact_x is not None


def _error_against(has_exact: bool, ref_dt: float | None) -> str:
    if has_exact:
        return "exact solution"
    return f"reference: {REFERENCE_METHOD} at dt/{REFERENCE_REFINE} = {ref_dt:.6g} s"


def _drift(traj: Trajectory) -> float | None:
    """Least-squares slope of the relative energy error (:data:`ENERGY_ERROR`) against time,
    1/s, over the finite rows; None with fewer than two finite rows or a non-finite slope
    (computed in closed form: no SVD to fail on huge data)."""
    if len(traj.t) < 2:
        return None
    t = np.asarray(traj.t, dtype=float)
    err = np.asarray(traj.energy_error, dtype=float)
    ok = np.isfinite(err) & np.isfinite(t)
    if ok.sum() < 2:
        return None
    t, err = t[ok], err[ok]
    with np.errstate(all="ignore"):
        tc = t - t.mean()
        den = float(np.dot(tc, tc))
        slope = float(np.dot(tc, err - err.mean())) / den if den > 0 else math.nan
    return slope if math.isfinite(slope) else None


def _max_abs(a: np.ndarray) -> float | None:
    """The largest finite |a|, or None when there is none."""
    a = np.asarray(a, dtype=float)
    a = a[np.isfinite(a)]
    return float(np.abs(a).max()) if len(a) else None


def _timed(run: Callable[[], Trajectory]) -> tuple[Trajectory, float, int]:
    """Runs ``run`` repeatedly for the timing (see :data:`TIMING_MIN_RUNS`); returns the first
    run, the median ns per step over the runs and the number of runs."""
    start = time.perf_counter()
    first = run()
    times = [first.ns_per_step]
    while len(times) < TIMING_MAX_RUNS:
        spent = time.perf_counter() - start
        if spent >= TIMING_MAX_S or (len(times) >= TIMING_MIN_RUNS and spent >= TIMING_MIN_S):
            break
        times.append(run().ns_per_step)
    return first, float(statistics.median(times)), len(times)


def _timing_note() -> str:
    return (
        f"ns_per_step: median over ns_per_step_runs timed runs (at least {TIMING_MIN_RUNS} runs and "
        f"{TIMING_MIN_S:g} s in all, at most {TIMING_MAX_RUNS} runs or {TIMING_MAX_S:g} s)"
    )


# --------------------------------------------------------------------------------------
# compare


def _run_args(scene: str, dt: Any, until: Any, dt_name: str = "dt") -> tuple[float, float]:
    """The (dt, until) of a compare run: the scene's defaults for None, both finite > 0, and at
    least one step (dt <= until)."""
    spec = _check_scene(scene)
    dt = _positive(dt_name, spec["dt"] if dt is None else dt)
    until = _positive("until", spec["until"] if until is None else until)
    if dt > until:
        raise ValueError(f"invalid {dt_name} = {dt!r}: must be <= until = {until!r} (at least one step)")
    return dt, until


def compare(
    scene: str,
    methods: Sequence[str],
    dt: float | None = None,
    until: float | None = None,
    params: dict[str, float] | None = None,
) -> dict[str, Any]:
    """One row per method on ``scene`` at ``dt`` up to ``until`` (the scene's defaults if None).

    Each row: ``method``, ``order`` (the registry's), ``evals_per_step`` (measured),
    ``energy_max_rel_error`` (max |relative energy error|, finite rows), ``energy_drift``
    (least-squares slope of the relative energy error, per second; None without two finite
    rows), ``energy_scale`` (J: what the energy error is relative to, :data:`ENERGY_ERROR`),
    ``final_error`` (max coordinate distance of the final position from the exact solution,
    or from the reference: see ``error_against``), ``ns_per_step`` (median of
    ``ns_per_step_runs`` timed runs), ``steps`` and ``t_end`` (what the run took and reached)
    and ``diverged`` (message or None; a diverged run reports its errors up to the step
    before).

    The result also has ``until_requested`` (= ``until``), ``steps`` and ``t_end`` (the run
    takes until / dt steps rounded down: ``t_end`` can fall short of ``until``),
    ``energy_error`` and ``timing`` (how the numbers were made). ValueError naming ``dt`` or
    ``until`` before anything runs if a run would be refused (no whole step, too many steps,
    too large a recording).
    """
    names = _check_methods(methods)
    dt, until = _run_args(scene, dt, until)
    full = _full_params(scene, params)
    coords = _coords(scene, params)
    steps = _check_run(dt, until, coords)
    has_exact = _has_exact(scene, params)
    ref = None
    if not has_exact:
        _check_run(
            dt, until, coords, every=REFERENCE_REFINE, refine=REFERENCE_REFINE, what="the reference run"
        )
        ref = reference(scene, dt, until, params, every=REFERENCE_REFINE)
    rows = [_compare_row(scene, m, dt, until, params, ref) for m in names]
    t_end = next((r["t_end"] for r in rows if not r["diverged"]), steps * dt)
    return {
        "scene": scene,
        "dt": dt,
        "until": until,
        "until_requested": until,
        "steps": steps,
        "t_end": t_end,
        "params": full,
        "error_against": _error_against(has_exact, None if ref is None else dt / REFERENCE_REFINE),
        "energy_error": ENERGY_ERROR,
        "timing": _timing_note(),
        "rows": rows,
    }


def _compare_row(
    scene: str, method: str, dt: float, until: float, params: dict[str, float] | None, ref: Trajectory | None
) -> dict[str, Any]:
    """One row of :func:`compare`."""
    traj, ns, runs = _timed(lambda: physstep.simulate(scene, method, dt, until, params, stop_on_diverge=True))
    final = _final_error(traj, ref) if len(traj.t) else math.nan
    return {
        "method": method,
        "order": physstep.method(method).order,
        "evals_per_step": traj.evals / max(traj.steps, 1),
        "energy_max_rel_error": _max_abs(traj.energy_error),
        "energy_drift": _drift(traj),
        "energy_scale": traj.energy_scale,
        "final_error": final,
        "ns_per_step": ns,
        "ns_per_step_runs": runs,
        "steps": int(traj.steps),
        "t_end": float(traj.t[-1]),
        "diverged": traj.diverged,
    }


# --------------------------------------------------------------------------------------
# order

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
    return float(np.polyfit(np.log(dts), np.log(errs), 1)[0])


def _order_plan(
    scene: str, dt: Any, until: Any, params: dict[str, float] | None, levels: Any
) -> tuple[float, int]:
    """Validates :func:`order`'s arguments up front; returns ``until`` and the coarsest step
    count ``n0`` (even), refusing a finest run over :data:`MAX_ORDER_STEPS` steps."""
    if isinstance(levels, bool) or not isinstance(levels, int | np.integer):
        raise ValueError(f"invalid levels = {levels!r}: must be a whole number")
    if not 2 <= levels <= MAX_LEVELS:
        raise ValueError(f"invalid levels = {levels}: must be between 2 and {MAX_LEVELS}")
    until = _positive("until", UNTIL_SCALES * time_scale(scene, params) if until is None else until)
    if dt is not None:
        dt = _positive("dt", dt)
        if dt > until:
            raise ValueError(f"invalid dt = {dt!r}: must be <= until = {until!r} (at least one step)")
    n0 = 32 if dt is None else max(1, round(until / dt))
    n0 += n0 % 2  # even step counts
    finest = n0 * 2 ** (int(levels) - 1)
    if finest > MAX_ORDER_STEPS:
        raise ValueError(
            f"invalid levels = {levels} with dt = {until / n0:.6g} and until = {until:.6g}: the finest "
            f"run would take {n0} * 2^{int(levels) - 1} = {finest:.4g} steps (at most {MAX_ORDER_STEPS}); "
            "use fewer levels, a larger dt or a shorter until"
        )
    return until, n0


def order(
    scene: str,
    method: str,
    dt: float | None = None,
    until: float | None = None,
    params: dict[str, float] | None = None,
    *,
    levels: int = 5,
) -> dict[str, Any]:
    """The observed convergence order of ``method`` on ``scene``.

    Runs ``levels`` step sizes dt, dt/2, dt/4, ... up to ``until``. dt is adjusted so that
    ``until`` is a whole, even number of steps (symplectic-euler-alternating is second order
    at odd counts too, but with another error constant, which would bend the pairwise order
    between an odd and an even run). Defaults: ``until`` = 0.3 natural time scales
    (:func:`time_scale`: a third of the spring's or the orbit's period) and dt = until / 32.
    ``levels`` is 2 to :data:`MAX_LEVELS` and the finest run at most :data:`MAX_ORDER_STEPS`
    steps, checked before anything runs (ValueError naming ``levels``, ``dt`` and ``until``).

    The error is the final position error (max over coordinates) against the exact solution,
    or against RK4 at a sixteenth of the finest dt. An error below :data:`ROUNDOFF` eps scale
    sqrt(steps) (scale: the largest |x| of the run) is roundoff: when the finest errors reach
    it the window slides to coarser dt; when the coarsest are not yet asymptotic (error above
    10 % of the scale, or diverged) it slides to finer dt. ``order`` is the least-squares
    slope of log error on log dt over the three finest runs of the window (None if the method
    is exact to roundoff on this scene); ``order_all`` is the slope over every usable run.

    Returns ``scene``, ``method``, ``info_order``, ``order``, ``order_all``, ``until``,
    ``error_against``, ``runs`` (list of {``dt``, ``steps``, ``error``, ``order``: the pairwise
    order from the previous run}) and ``note``.
    """
    _check_scene(scene)
    _check_method(method)
    until, n0 = _order_plan(scene, dt, until, params, levels)
    levels = int(levels)
    has_exact = _has_exact(scene, params)

    runs: dict[int, Trajectory | None] = {}  # k -> run at n0 * 2**k steps
    refs: dict[int, Trajectory] = {}

    def count(k: int) -> int:
        return n0 * 2**k if k >= 0 else n0 // 2 ** (-k)

    def run(k: int) -> Trajectory | None:
        if k not in runs:
            n = count(k)  # only the first and the last rows are recorded
            traj = physstep.simulate(scene, method, until / n, until, params, stop_on_diverge=True, every=n)
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
            errs.append(math.inf if traj is None else _final_error(traj, ref))
        return errs, ref_dt

    # the position scale: from the exact solution, else from a fine RK4 run
    n_fine = n0 * 16
    fine = physstep.simulate(
        scene, "rk4", until / n_fine, until, params, stop_on_diverge=True, every=max(1, n_fine // 4096)
    )
    xs = fine.exact_x if fine.exact_x is not None else fine.x
    scale = float(np.abs(xs).max()) or 1.0
    ceiling = 0.1 * scale
    refine = 1 if has_exact else REFERENCE_REFINE

    def floor(dt_run: float) -> float:  # the roundoff level of a run (and of its reference)
        return ROUNDOFF * _EPS * scale * math.sqrt(refine * _steps(dt_run, until))

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
        out_runs.append({"dt": d, "steps": _steps(d, until), "error": e, "order": pair})
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
    return {
        "scene": scene,
        "method": method,
        "info_order": physstep.method(method).order,
        "order": observed,
        "order_all": _slope([d for d, _ in usable], [e for _, e in usable]) if len(usable) >= 2 else None,
        "until": until,
        "params": _full_params(scene, params),
        "error_against": _error_against(has_exact, ref_dt),
        "error": "final position error, max over coordinates",
        "runs": out_runs,
        "note": note,
    }


# --------------------------------------------------------------------------------------
# stability

#: Stability threshold on the (per-step) spectral radius of the amplification matrix.
RHO_TOL = 1e-12
#: The default cap on the dt search, in units of the scene's natural time scale.
CAP_SCALES = 1000.0
#: The largest cap allowed, in natural time scales.
MAX_CAP_SCALES = 1e12
#: The grid starts at GRID_LOW_SCALES natural time scales (whatever the cap) and rises with
#: GRID_PER_DECADE points per decade up to the cap.
GRID_LOW_SCALES = 1e-3
GRID_PER_DECADE = 8
#: Amplification-matrix entries below this fraction of the largest are rounding noise.
NOISE_REL = 1e-12
#: Eigenvalues closer than this (relative) are one cluster, counted as its mean (see
#: :func:`_spectral_radius`).
CLUSTER_TOL = 1e-5
#: Bounded growth (nonlinear scenes): GROWTH_STEPS steps without a failed step and with the
#: state within GROWTH_LIMIT of its scale throughout; the grid walk first screens with
#: GROWTH_SCREEN_STEPS steps (an escape within those is an escape within GROWTH_STEPS).
GROWTH_STEPS = 10_000
GROWTH_SCREEN_STEPS = 1_000
GROWTH_LIMIT = 10.0
#: Default bisection tolerances (relative), the range allowed, and the most halvings.
RTOL_LINEAR = 1e-10
RTOL_GROWTH = 1e-4
RTOL_RANGE = (1e-15, 0.1)
MAX_BISECTIONS = 100
#: After bisecting, dt_max * SCAN_FACTORS are checked; an unstable one (an island below the
#: limit found) lowers the bracket and the search repeats, at most SCAN_ROUNDS times.
SCAN_FACTORS = tuple(0.9 + 0.01 * i for i in range(10))
SCAN_ROUNDS = 4


def _map_period(method: str) -> int:
    """Steps after which the method's step map repeats (alternating Euler: two)."""
    return 2 if method == "symplectic-euler-alternating" else 1


def amplification(scene: str, method: str, dt: float, params: dict[str, float] | None = None) -> np.ndarray:
    """The amplification matrix of ``method``'s repeating step map on a linear/affine scene.

    The map acts on the full phase vector of :meth:`physstep.World.phase_state`: positions,
    velocities, then the integrator's memory (Verlet's previous positions, leapfrog's
    half-step velocities). A world from the scene takes :func:`_map_period` warm-up steps (so
    a stateful method is started: the restart step, e.g. leapfrog's half-step start, is not
    the map that repeats), then column i is step(e_i) - step(0) over one period (two steps for
    symplectic-euler-alternating), each from :meth:`~physstep.World.set_phase_state`, which
    does not restart the integrator. The map is affine, so the base point 0 gives the exact
    columns with the least rounding. Entries below the rounding resolution of that difference,
    or below 1e-12 of the largest entry, are set to zero (so that the exact zeros of an affine
    map, e.g. the projectile's, stay zero).
    """
    period = _map_period(method)
    world = physstep.World.from_scene(scene, method, dt, params or {})
    world.step(period)  # warm-up: start the method's memory
    size = len(world.phase_state())

    def step(z: np.ndarray) -> np.ndarray:
        world.set_phase_state(z)
        world.step(period)
        return np.asarray(world.phase_state(), dtype=float)

    base = step(np.zeros(size))
    cols = []
    for i in range(size):
        e = np.zeros(size)
        e[i] = 1.0
        s = step(e)
        col = s - base
        col[np.abs(col) <= 4 * _EPS * (np.abs(s) + np.abs(base))] = 0.0
        cols.append(col)
    m = np.array(cols).T
    # Rounding noise (e.g. Verlet's backward-difference velocity, eps |x| / dt) would split
    # the Jordan blocks of a free particle into eigenvalues 1 +- sqrt(noise): drop it.
    m[np.abs(m) <= NOISE_REL * np.abs(m).max(initial=0.0)] = 0.0
    return m


def _rho(scene: str, method: str, dt: float, params: dict[str, float] | None) -> float:
    """The per-step spectral radius of the repeating map (inf if a step fails)."""
    try:
        m = amplification(scene, method, dt, params)
    except physstep.StepError:
        return math.inf
    if not np.all(np.isfinite(m)):
        return math.inf
    return _spectral_radius(m) ** (1.0 / _map_period(method))


def _spectral_radius(m: np.ndarray) -> float:
    """The largest |eigenvalue| of ``m``, a cluster of eigenvalues (within
    :data:`CLUSTER_TOL` of each other) counting as its mean.

    A defective eigenvalue comes out of the eigensolver split by about sqrt(eps ||M||): the
    Jordan block at 1 of a free particle under Verlet (x_{n+1} = 2 x_n - x_{n-1}) gives
    1 +- 1e-8, which would read as unstable. The mean of a cluster (its trace over its size)
    is well conditioned."""
    ev = np.linalg.eigvals(m)
    if len(ev) == 0:
        return 0.0
    groups: list[list[complex]] = []
    for z in sorted(ev, key=lambda z: (z.real, z.imag)):
        near = [g for g in groups if min(abs(z - w) for w in g) <= CLUSTER_TOL * max(1.0, abs(z))]
        merged = [z] + [w for g in near for w in g]
        groups = [g for g in groups if not any(g is h for h in near)] + [merged]
    return max(abs(complex(np.mean(g))) for g in groups)


def _state_scales(scene: str, params: dict[str, float] | None) -> tuple[float, float]:
    """(amplitude A, m; angular frequency w, 1/s) of the bounded-growth test: w = 2 pi / the
    natural time scale and A = max(max |x0|, max |v0| / w), the oscillator amplitude scale
    (1 m if the initial state is all zero); velocities are measured against w A."""
    probe = _probe(scene, params)
    w = 2.0 * math.pi / time_scale(scene, params)
    amp = max(float(np.abs(probe.x[0]).max(initial=0.0)), float(np.abs(probe.v[0]).max(initial=0.0)) / w)
    return (amp if amp > 0 else 1.0), w


def _growth(
    scene: str,
    method: str,
    dt: float,
    params: dict[str, float] | None,
    steps: int,
    scales: tuple[float, float],
) -> float:
    """max over ``steps`` steps of max(|x_k - x_0| / A, |v_k - v_0| / (w A)) (max norms; inf if
    a step fails)."""
    amp, w = scales
    try:
        t = physstep.simulate(scene, method, dt, dt * steps, params, stop_on_diverge=True)
    except physstep.StepError:
        return math.inf
    if t.diverged:
        return math.inf
    with np.errstate(all="ignore"):
        g = max(float(np.abs(t.x - t.x[0]).max()) / amp, float(np.abs(t.v - t.v[0]).max()) / (w * amp))
    return g if math.isfinite(g) else math.inf


def _check_rtol(rtol: Any, linear: bool) -> float:
    if rtol is None:
        return RTOL_LINEAR if linear else RTOL_GROWTH
    r = _number("rtol", rtol)
    lo, hi = RTOL_RANGE
    if not lo <= r <= hi:  # also NaN
        raise ValueError(f"invalid rtol = {r!r}: must be between {lo:g} and {hi:g}")
    return r


def _grid(scale: float, cap: float) -> list[float]:
    """The log grid from GRID_LOW_SCALES natural time scales up to ``cap`` (the last point)."""
    low = GRID_LOW_SCALES * scale
    n = math.ceil(math.log10(cap / low) * GRID_PER_DECADE - 1e-9)
    grid = [low * 10 ** (i / GRID_PER_DECADE) for i in range(n)]
    return [*grid, cap]


def _bisect(stable: Callable[[float], bool], lo: float, hi: float, rtol: float) -> tuple[float, float]:
    """Halves [lo, hi] (lo stable, hi unstable) to relative width ``rtol`` (at most
    :data:`MAX_BISECTIONS` halvings)."""
    for _ in range(MAX_BISECTIONS):
        if hi - lo <= rtol * lo:
            break
        mid = 0.5 * (lo + hi)
        if stable(mid):
            lo = mid
        else:
            hi = mid
    return lo, hi


def _below(stable: Callable[[float], bool], hi: float, floor: float) -> tuple[float, float] | None:
    """A bracket (stable lo, unstable hi) at or below the unstable point ``hi``, walking down the
    grid spacing; None if none is found down to ``floor``."""
    ratio = 10 ** (1 / GRID_PER_DECADE)
    while hi / ratio >= floor * (1 - 1e-12):
        lo = hi / ratio
        if stable(lo):
            return lo, hi
        hi = lo
    return None


def _search(
    stable: Callable[[float], bool], screen: Callable[[float], bool], grid: list[float], rtol: float
) -> tuple[float | None, float | None]:
    """(dt_max, the unstable point above it): the grid is walked up with ``screen`` (a
    necessary condition for ``stable``) to its first failure, the bracket below it confirmed
    with ``stable`` and bisected; then dt_max * SCAN_FACTORS are checked and an unstable one
    restarts the bisection below it. (None, None): stable at every grid point; (0, grid[0]):
    unstable at the lowest."""
    k = next((i for i, g in enumerate(grid) if not screen(g)), None)
    if k is None:
        return None, None
    bracket = None
    if k > 0:
        bracket = (grid[k - 1], grid[k]) if stable(grid[k - 1]) else _below(stable, grid[k - 1], grid[0])
    for round_ in range(SCAN_ROUNDS + 1):
        if bracket is None:
            return 0.0, grid[0]
        lo, hi = _bisect(stable, *bracket, rtol)
        if round_ == SCAN_ROUNDS:
            break
        scan = [lo * f for f in SCAN_FACTORS]
        j = next((i for i, p in enumerate(scan) if not stable(p)), None)
        if j is None:
            break
        bracket = (scan[j - 1], scan[j]) if j > 0 else _below(stable, scan[0], grid[0])
    return lo, hi


def _criterion(
    scene: str, method: str, params: dict[str, float] | None, linear: bool
) -> tuple[str, Callable[[float], bool], Callable[[float], bool]]:
    """(the criterion as a sentence, the stability test dt -> bool, the screening test)."""
    if linear:
        text = (
            "spectral radius of the amplification matrix of the repeating step map, over the phase "
            "vector (state and integrator memory, after warm-up steps): M[:, i] = step(e_i) - step(0), "
            f"radius <= 1 + {RHO_TOL:g}"
        )
        if _map_period(method) == 2:
            text += " (two-step map, per-step radius)"

        def stable(d: float) -> bool:
            return _rho(scene, method, d, params) <= 1.0 + RHO_TOL

        return text, stable, stable
    scales = _state_scales(scene, params)
    amp, w = scales
    text = (
        f"bounded growth: {GROWTH_STEPS} steps without a failed step and with max|x_k - x_0| <= "
        f"{GROWTH_LIMIT:g} A and max|v_k - v_0| <= {GROWTH_LIMIT:g} w A throughout, A = max(|x0|, |v0|/w) "
        f"= {amp:.6g} m, w = 2 pi / time scale = {w:.6g} 1/s"
    )

    def stable(d: float) -> bool:
        return _growth(scene, method, d, params, GROWTH_STEPS, scales) <= GROWTH_LIMIT

    def screen(d: float) -> bool:
        return _growth(scene, method, d, params, GROWTH_SCREEN_STEPS, scales) <= GROWTH_LIMIT

    return text, stable, screen


def _memo(f: Callable[[float], bool]) -> Callable[[float], bool]:
    seen: dict[float, bool] = {}

    def g(d: float) -> bool:
        if d not in seen:
            seen[d] = f(d)
        return seen[d]

    return g


def stability(
    scene: str,
    method: str,
    params: dict[str, float] | None = None,
    *,
    cap: float | None = None,
    rtol: float | None = None,
) -> dict[str, Any]:
    """The largest stable dt of ``method`` on ``scene``: ``dt_max``.

    ``analysis`` says which test was used and ``criterion`` spells it out:

    - ``"amplification matrix"`` on the linear/affine scenes (:data:`LINEAR_SCENES`): dt is
      stable iff the per-step spectral radius of the repeating step map's amplification
      matrix (:func:`amplification`, over positions, velocities and the integrator's memory)
      is <= 1 + :data:`RHO_TOL`.
    - ``"bounded growth"`` on the others: dt is stable iff :data:`GROWTH_STEPS` steps run
      without a failed step and the state stays within :data:`GROWTH_LIMIT` of its own scale:
      max|x_k - x_0| <= 10 A and max|v_k - v_0| <= 10 w A (max norms), with w = 2 pi / the
      natural time scale and A = max(max|x0|, max|v0|/w). It needs no energy (meaningful when
      E0 is about 0, as on the chain) and is a finite-horizon test: a method whose error
      drifts (explicit Euler's energy gain, backward Euler's inward spiral) gets a limit that
      depends on the horizon, or 0.

    The search walks a log grid up from :data:`GRID_LOW_SCALES` natural time scales
    (:func:`time_scale`) to ``cap`` (default :data:`CAP_SCALES` time scales) to the first
    unstable point, bisects to relative ``rtol`` (default 1e-10 for the matrix, 1e-4 for
    bounded growth; allowed 1e-15 to 0.1), then checks 0.90 ... 0.99 dt_max and searches
    again below any unstable one: ``dt_max`` bounds the stable interval that starts at dt ->
    0. ``dt_max`` is 0 if the lowest grid point is unstable already, None if no instability
    is found up to ``cap``. ValueError naming ``cap`` unless it is above the grid's lowest
    point, naming ``rtol`` outside its range.

    Why the grid starts at 1e-3 time scales: there omega dt = 2 pi 1e-3, where the growth per
    step of the methods unstable on the undamped oscillator (Heun, midpoint: |R| - 1 =
    (omega dt)^4/8 = 2e-10) is still well above the 1e-12 threshold.
    """
    _check_scene(scene)
    _check_method(method)
    full = _full_params(scene, params)
    scale = time_scale(scene, params)
    linear = scene in LINEAR_SCENES
    rtol = _check_rtol(rtol, linear)
    low = GRID_LOW_SCALES * scale
    cap = _positive("cap", CAP_SCALES * scale if cap is None else cap)
    if cap > MAX_CAP_SCALES * scale:
        raise ValueError(
            f"invalid cap = {cap!r}: must be at most {MAX_CAP_SCALES:g} natural time scales "
            f"({MAX_CAP_SCALES * scale:.6g} s): beyond, a step's arithmetic overflows"
        )
    if not cap > low:
        raise ValueError(
            f"invalid cap = {cap!r}: must be above the search grid's lowest point {low:.6g} s "
            f"({GRID_LOW_SCALES:g} natural time scales)"
        )
    criterion, test, screen = _criterion(scene, method, params, linear)
    stable = _memo(test)
    grid = _grid(scale, cap)
    dt_max, hi = _search(stable, stable if screen is test else _memo(screen), grid, rtol)
    if dt_max is None:
        note = f"stable at every dt up to the cap {cap:.6g} s"
    elif dt_max == 0:
        note = f"unstable at every dt down to {grid[0]:.6g} s ({GRID_LOW_SCALES:g} natural time scales)"
    else:
        note = f"stable interval (0, {dt_max:.12g}] s; unstable at {hi:.12g} s"
    out: dict[str, Any] = {
        "scene": scene,
        "method": method,
        "params": full,
        "dt_max": dt_max,
        "analysis": "amplification matrix" if linear else "bounded growth",
        "criterion": criterion,
        "cap": cap,
        "rtol": rtol,
        "time_scale": scale,
        "grid": [grid[0], grid[-1], GRID_PER_DECADE],
        "note": note,
    }
    if linear and dt_max:
        out["spectral_radius_at_dt_max"] = _rho(scene, method, dt_max, params)
    return out


# --------------------------------------------------------------------------------------
# sweep


def _check_dts(dts: Sequence[float]) -> list[float]:
    if isinstance(dts, str | bytes):
        raise ValueError(f"invalid dts = {dts!r}: give a list of numbers")
    try:
        values = list(dts)
    except TypeError:
        raise ValueError(f"invalid dts = {dts!r}: give a list of numbers") from None
    if not values:
        raise ValueError("invalid dts = []: give at least one dt")
    return [_positive("dts", d) for d in values]


def sweep(
    scene: str,
    methods: Sequence[str],
    dts: Sequence[float],
    until: float | None = None,
    params: dict[str, float] | None = None,
    *,
    progress: Callable[[int, int, str], None] | None = None,
) -> dict[str, Any]:
    """Work-precision data: every method at every dt up to ``until``.

    One row per (method, dt): ``method``, ``dt``, ``steps`` and ``t_end`` (what the run took and
    reached: until / dt steps rounded down), ``evals`` (force evaluations, measured),
    ``time_s`` (the stepping loop's wall time, from the median ``ns_per_step``),
    ``ns_per_step`` (median of ``ns_per_step_runs`` timed runs), ``error`` (final position
    error, max over coordinates, against the exact solution or the reference at the smallest
    dt / 16, interpolated to each run's final time), ``max_error`` (the same, maximum over the
    whole run: free of the cancellations a single time can show), ``energy_max_rel_error``
    (:data:`ENERGY_ERROR`) and ``diverged`` (rows that diverged have ``error`` None).
    ``progress(done, total, label)`` is called after each run.

    Every dt must be <= ``until`` (at least one step); a run that :func:`physstep.simulate`
    would refuse is a ValueError naming ``dts`` and ``until`` before anything runs.
    """
    spec = _check_scene(scene)
    names = _check_methods(methods)
    values = _check_dts(dts)
    until = _positive("until", spec["until"] if until is None else until)
    for d in values:
        if d > until:
            raise ValueError(f"invalid dts: dt = {d!r} must be <= until = {until!r} (at least one step)")
    full = _full_params(scene, params)
    coords = _coords(scene, params)
    for d in values:
        _check_run(d, until, coords, dt_name="dts")
    has_exact = _has_exact(scene, params)
    ref = None
    if not has_exact:
        _check_run(
            min(values), until, coords, refine=REFERENCE_REFINE, dt_name="dts", what="the reference run"
        )
        ref = reference(scene, min(values), until, params)
    total = len(names) * len(values)
    rows = []
    for m in names:
        for d in sorted(values, reverse=True):
            rows.append(_sweep_row(scene, m, d, until, params, ref))
            if progress is not None:
                progress(len(rows), total, f"{m} dt={d:g}")
    return {
        "scene": scene,
        "until": until,
        "until_requested": until,
        "params": full,
        "error_against": _error_against(has_exact, None if ref is None else ref.dt),
        "energy_error": ENERGY_ERROR,
        "timing": _timing_note(),
        "rows": rows,
    }


def _sweep_row(
    scene: str, method: str, dt: float, until: float, params: dict[str, float] | None, ref: Trajectory | None
) -> dict[str, Any]:
    """One row of :func:`sweep`."""
    traj, ns, runs = _timed(lambda: physstep.simulate(scene, method, dt, until, params, stop_on_diverge=True))
    return {
        "method": method,
        "dt": dt,
        "steps": int(traj.steps),
        "t_end": float(traj.t[-1]),
        "evals": int(traj.evals),
        "time_s": float(f"{ns * traj.steps * 1e-9:.12g}"),  # 12 digits: no float noise (e.g. ...0001)
        "ns_per_step": ns,
        "ns_per_step_runs": runs,
        "error": None if traj.diverged else _final_error(traj, ref),
        "max_error": None if traj.diverged else _max_error(traj, ref),
        "energy_max_rel_error": _max_abs(traj.energy_error),
        "diverged": traj.diverged,
    }
