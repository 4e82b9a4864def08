"""The integrator lab: measure how each method behaves on a scene.

Four measurements, each returning plain data (dicts and lists, JSON-ready):

- :func:`compare`: one row per method (order, force evaluations per step, energy error and
  drift, final error, ns per step).
- :func:`order`: the observed convergence order from successive halvings of dt.
- :func:`stability`: the largest stable dt, from the one-step amplification matrix on the
  linear/affine scenes and from a bounded-growth search on the others.
- :func:`sweep`: work-precision data (error against force evaluations and time).

Errors are measured against the scene's exact solution where it has one and otherwise
against a reference solution (RK4 at a sixteenth of the finest dt, interpolated with cubic
Hermite polynomials between its rows); every result says which in ``error_against``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

import physstep
from physstep import Trajectory

__all__ = [
    "LINEAR_SCENES",
    "REFERENCE_METHOD",
    "REFERENCE_REFINE",
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

_EPS = float(np.finfo(float).eps)


# --------------------------------------------------------------------------------------
# helpers


def _check_method(name: str) -> None:
    physstep.method(name)  # ValueError listing the valid names


def _check_scene(name: str) -> dict[str, Any]:
    return physstep.scene(name)


def _probe(scene: str, params: dict[str, float] | None) -> Trajectory:
    """A zero-length run: the engine validates the scene and ``params`` and answers with the
    resolved parameters (``.params``) and whether an exact solution exists (``.exact_x``)."""
    return physstep.simulate(scene, REFERENCE_METHOD, dt=1.0, until=0.0, params=params)


def _full_params(scene: str, params: dict[str, float] | None) -> dict[str, float]:
    return dict(_probe(scene, params).params)


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
    """The step count physstep.simulate takes for (dt, until)."""
    r = until / dt
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


def reference(scene: str, dt: float, until: float, params: dict[str, float] | None = None) -> Trajectory:
    """The reference run: :data:`REFERENCE_METHOD` at ``dt / REFERENCE_REFINE``."""
    return physstep.simulate(scene, REFERENCE_METHOD, dt / REFERENCE_REFINE, until, params)


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


def _drift(traj: Trajectory) -> float:
    """Least-squares slope of the relative energy error against time, 1/s."""
    if len(traj.t) < 2:
        return 0.0
    err = traj.energy_error
    ok = np.isfinite(err)
    if ok.sum() < 2:
        return float("nan")
    return float(np.polyfit(traj.t[ok], err[ok], 1)[0])


# --------------------------------------------------------------------------------------
# compare


def compare(
    scene: str,
    methods: Sequence[str],
    dt: float | None = None,
    until: float | None = None,
    params: dict[str, float] | None = None,
) -> dict[str, Any]:
    """One row per method on ``scene`` at ``dt`` up to ``until`` (the scene's defaults if None).

    Each row: ``method``, ``order`` (the registry's), ``evals_per_step`` (measured),
    ``energy_max_rel_error``, ``energy_drift`` (least-squares slope of the relative energy
    error, per second), ``final_error`` (max coordinate distance of the final position from
    the exact solution, or from the reference: see ``error_against``), ``ns_per_step``,
    ``steps`` and ``diverged`` (message or None; a diverged run reports its errors up to the
    step before).
    """
    spec = _check_scene(scene)
    if not methods:
        raise ValueError("invalid methods = []: give at least one method")
    for m in methods:
        _check_method(m)
    dt = float(spec["dt"] if dt is None else dt)
    until = float(spec["until"] if until is None else until)
    full = _full_params(scene, params)
    has_exact = _has_exact(scene, params)
    ref = None if has_exact else reference(scene, dt, until, params)
    rows = []
    for m in methods:
        traj = physstep.simulate(scene, m, dt, until, params, stop_on_diverge=True)
        info = physstep.method(m)
        ee = traj.energy_error
        final = _final_error(traj, ref) if len(traj.t) else float("nan")
        rows.append(
            {
                "method": m,
                "order": info.order,
                "evals_per_step": traj.evals / max(traj.steps, 1),
                "energy_max_rel_error": float(np.nanmax(np.abs(ee))) if len(ee) else 0.0,
                "energy_drift": _drift(traj),
                "final_error": final,
                "ns_per_step": traj.ns_per_step,
                "steps": int(traj.steps),
                "t_end": float(traj.t[-1]),
                "diverged": traj.diverged,
            }
        )
    return {
        "scene": scene,
        "dt": dt,
        "until": until,
        "params": full,
        "error_against": _error_against(has_exact, None if ref is None else dt / REFERENCE_REFINE),
        "rows": rows,
    }


# --------------------------------------------------------------------------------------
# order

#: The default run length of :func:`order`, in natural time scales (a third of a period:
#: errors build up, phase errors do not wrap, and it is no multiple of a quarter period,
#: where symplectic Euler's oscillating error cancels to second order).
UNTIL_SCALES = 0.3


def _slope(dts: Sequence[float], errs: Sequence[float]) -> float:
    return float(np.polyfit(np.log(dts), np.log(errs), 1)[0])


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

    Runs ``levels`` step sizes dt, dt/2, dt/4, ... up to ``until`` (dt is adjusted so that
    ``until`` is a whole, even number of steps: symplectic-euler-alternating is second order
    at even step counts only). Defaults: ``until`` = 0.3 natural time scales
    (:func:`time_scale`: a third of the spring's or the orbit's period) and dt = until / 32.
    The error is the final position error (max over coordinates) against the exact solution,
    or against RK4 at a sixteenth of the finest dt. When the finest errors
    reach roundoff (below 1e-10 of the position scale) the window slides to coarser dt; when
    the coarsest are not yet asymptotic (error above 10 % of the position scale, or diverged)
    it slides to finer dt. ``order`` is the least-squares slope of log error on log dt over
    the three finest runs of the window (None if the method is exact to roundoff on this
    scene); ``order_all`` is the slope over every usable run.

    Returns ``scene``, ``method``, ``info_order``, ``order``, ``until``, ``error_against``,
    ``runs`` (list of {``dt``, ``steps``, ``error``, ``order``: the pairwise order from the
    previous run}) and ``note``.
    """
    _check_scene(scene)
    _check_method(method)
    if levels < 2:
        raise ValueError(f"invalid levels = {levels}: must be >= 2")
    until = float(UNTIL_SCALES * time_scale(scene, params) if until is None else until)
    if not (until > 0 and math.isfinite(until)):
        raise ValueError(f"invalid until = {until}: must be a finite number > 0")
    if dt is not None and not (dt > 0 and math.isfinite(dt)):
        raise ValueError(f"invalid dt = {dt}: must be a finite number > 0")
    n0 = 32 if dt is None else max(1, round(until / float(dt)))
    n0 += n0 % 2  # even step counts
    has_exact = _has_exact(scene, params)

    runs: dict[int, Trajectory | None] = {}  # k -> run at n0 * 2**k steps
    refs: dict[int, Trajectory] = {}

    def run(k: int) -> Trajectory | None:
        if k not in runs:
            n = n0 * 2**k if k >= 0 else n0 // 2 ** (-k)
            traj = physstep.simulate(scene, method, until / n, until, params, stop_on_diverge=True)
            runs[k] = None if traj.diverged else traj
        return runs[k]

    def errors(ks: list[int]) -> tuple[list[float], float | None]:
        ref_dt = None
        ref = None
        if not has_exact:
            kmax = max(ks)
            if kmax not in refs:
                refs[kmax] = reference(scene, until / (n0 * 2**kmax) if kmax >= 0 else until, until, params)
            ref = refs[kmax]
            ref_dt = ref.dt
        errs = []
        for k in ks:
            traj = run(k)
            errs.append(math.inf if traj is None else _final_error(traj, ref))
        return errs, ref_dt

    # the position scale: from the exact solution, else from a fine RK4 run
    fine = physstep.simulate(scene, "rk4", until / (n0 * 16), until, params, stop_on_diverge=True)
    xs = fine.exact_x if fine.exact_x is not None else fine.x
    scale = float(np.abs(xs).max()) or 1.0
    floor, ceiling = 1e-10 * scale, 0.1 * scale
    # the smallest k allowed keeps n >= 2 and even; the largest keeps n <= 2**17
    kmin = -int(math.log2(n0 // 2)) if n0 >= 4 and (n0 & (n0 - 1)) == 0 else 0
    kmax = max(0, int(math.log2(2**17 / n0)) - levels + 1)
    lo = 0
    note = ""
    for _ in range(24):
        ks = list(range(lo, lo + levels))
        errs, ref_dt = errors(ks)
        low = errs[-1] < floor
        high = errs[0] > ceiling or not math.isfinite(errs[0])
        if low and not high and lo > kmin:
            lo -= 1
            continue
        if high and not low and lo < kmax:
            lo += 1
            continue
        break
    good = [
        (until / (n0 * 2**k) if k >= 0 else until / (n0 // 2 ** (-k)), e)
        for k, e in zip(ks, errs, strict=True)
    ]
    out_runs = []
    prev = None
    for d, e in good:
        pair = None
        if prev is not None and prev[1] > floor and e > floor and math.isfinite(prev[1]) and math.isfinite(e):
            pair = math.log(prev[1] / e) / math.log(prev[0] / d)
        out_runs.append({"dt": d, "steps": _steps(d, until), "error": e, "order": pair})
        prev = (d, e)
    usable = [(d, e) for d, e in good if floor < e <= ceiling]
    fit = usable[-3:]
    if len(usable) >= 2:
        observed: float | None = _slope([d for d, _ in fit], [e for _, e in fit])
    else:
        observed = None
        note = (
            "errors at roundoff level at every dt tried: the method is exact on this scene"
            if all(e <= floor for _, e in good)
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

#: Stability threshold on the spectral radius of the one-step amplification matrix.
RHO_TOL = 1e-12
#: The cap on the dt search, in units of the scene's natural time scale.
CAP_SCALES = 1000.0
#: The grid runs from cap down to cap * GRID_LOW, with GRID_PER_DECADE points per decade.
GRID_LOW = 1e-6
GRID_PER_DECADE = 8
#: Amplification-matrix entries below this fraction of the largest are rounding noise.
NOISE_REL = 1e-12
#: Steps of the bounded-growth test on nonlinear scenes.
GROWTH_STEPS = 1000


def _map_period(method: str) -> int:
    """Steps after which the method's step map repeats (alternating Euler: two)."""
    return 2 if method == "symplectic-euler-alternating" else 1


def amplification(scene: str, method: str, dt: float, params: dict[str, float] | None = None) -> np.ndarray:
    """The one-step amplification matrix of ``method`` on a linear/affine scene at ``dt``.

    State order (x coordinates, then v coordinates); column i is step(e_i) - step(0), with
    entries below the rounding resolution of that difference, or below 1e-12 of the largest
    entry, set to zero (so that the exact zeros of an affine map, e.g. the projectile's,
    stay zero). For
    symplectic-euler-alternating the map covers its period of two steps.
    """
    n_steps = _map_period(method)
    until = dt * n_steps
    probe = physstep.simulate(scene, method, dt, 0.0, params)
    nc = probe.x.shape[1]

    def step(state: np.ndarray) -> np.ndarray:
        t = physstep.simulate(scene, method, dt, until, params, x0=state[:nc], v0=state[nc:])
        return np.concatenate([t.x[-1], t.v[-1]])

    base = step(np.zeros(2 * nc))
    cols = []
    for i in range(2 * nc):
        e = np.zeros(2 * nc)
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
    try:
        m = amplification(scene, method, dt, params)
    except physstep.StepError:
        return math.inf
    if not np.all(np.isfinite(m)):
        return math.inf
    rho = float(np.abs(np.linalg.eigvals(m)).max())
    return rho ** (1.0 / _map_period(method))


def _bounded(scene: str, method: str, dt: float, params: dict[str, float] | None) -> bool:
    try:
        t = physstep.simulate(scene, method, dt, dt * GROWTH_STEPS, params, stop_on_diverge=True, every=10)
    except physstep.StepError:
        return False
    if t.diverged:
        return False
    err = t.energy_error
    return bool(np.all(np.isfinite(err)) and np.abs(err).max() < 1.0)


def stability(
    scene: str,
    method: str,
    params: dict[str, float] | None = None,
    *,
    cap: float | None = None,
    rtol: float = 1e-10,
) -> dict[str, Any]:
    """The largest stable dt of ``method`` on ``scene``: ``dt_max``.

    On the linear/affine scenes (:data:`LINEAR_SCENES`) dt is stable iff the spectral radius
    of the amplification matrix (:func:`amplification`) is <= 1 + 1e-12. On the others it is
    stable iff :data:`GROWTH_STEPS` steps run without diverging and with relative energy error
    below 1 throughout. The search walks a log grid upwards from ``cap * 1e-6`` to ``cap``
    (default: 1000 natural time scales, :func:`time_scale`) to the first unstable point,
    then bisects to relative ``rtol``: ``dt_max`` bounds the stable interval that starts at
    dt -> 0. ``dt_max`` is 0 if the method is unstable at every grid point (down to
    ``cap * 1e-6``), None if no instability is found below ``cap``.

    Why 1000 scales: at the bottom of the grid omega dt = 2 pi 1e-3, where the growth per step
    of the methods unstable on the undamped oscillator (Heun, midpoint: |R|-1 = (omega dt)^4/8
    = 2e-10) is still well above the 1e-12 threshold.
    """
    _check_scene(scene)
    _check_method(method)
    _full_params(scene, params)
    scale = time_scale(scene, params)
    cap = float(CAP_SCALES * scale if cap is None else cap)
    if not (cap > 0 and math.isfinite(cap)):
        raise ValueError(f"invalid cap = {cap}: must be a finite number > 0")
    linear = scene in LINEAR_SCENES
    if linear:
        criterion = (
            "spectral radius of the one-step amplification matrix M[:, i] = step(e_i) - step(0) "
            f"<= 1 + {RHO_TOL:g}"
        )
        if _map_period(method) == 2:
            criterion += " (two-step map, per-step radius)"

        def stable(d: float) -> bool:
            return _rho(scene, method, d, params) <= 1.0 + RHO_TOL
    else:
        criterion = (
            f"bounded growth: {GROWTH_STEPS} steps without divergence and with "
            "|relative energy error| < 1 throughout"
        )

        def stable(d: float) -> bool:
            return _bounded(scene, method, d, params)

    decades = -math.log10(GRID_LOW)
    n = int(round(decades * GRID_PER_DECADE))
    grid = [cap * GRID_LOW * 10 ** (i / GRID_PER_DECADE) for i in range(n + 1)]
    grid[-1] = cap
    dt_max: float | None
    last_stable = None
    first_unstable = None
    for g in grid:
        if stable(g):
            last_stable = g
        else:
            first_unstable = g
            break
    if first_unstable is None:
        dt_max = None
        note = f"stable at every dt up to the cap {cap:.6g} s"
    elif last_stable is None:
        dt_max = 0.0
        note = f"unstable at every dt down to {grid[0]:.6g} s"
    else:
        lo, hi = last_stable, first_unstable
        while hi - lo > rtol * lo:
            mid = 0.5 * (lo + hi)
            if stable(mid):
                lo = mid
            else:
                hi = mid
        dt_max = lo
        note = f"stable interval (0, {lo:.10g}] s; unstable at {hi:.10g} s"
    out: dict[str, Any] = {
        "scene": scene,
        "method": method,
        "params": _full_params(scene, params),
        "dt_max": dt_max,
        "criterion": criterion,
        "analysis": "amplification matrix" if linear else "bounded growth",
        "cap": cap,
        "time_scale": scale,
        "grid": [grid[0], grid[-1], GRID_PER_DECADE],
        "note": note,
    }
    if linear and dt_max:
        out["spectral_radius_at_dt_max"] = _rho(scene, method, dt_max, params)
    return out


# --------------------------------------------------------------------------------------
# sweep


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

    One row per (method, dt): ``method``, ``dt``, ``steps``, ``evals`` (force evaluations,
    measured), ``time_s`` (the stepping loop's wall time), ``ns_per_step``, ``error`` (final
    position error, max over coordinates, against the exact solution or the reference at
    the smallest dt / 16, interpolated to each run's final time), ``max_error`` (the same,
    maximum over the whole run: free of the cancellations a single time can show),
    ``energy_max_rel_error``
    and ``diverged`` (rows that diverged have ``error`` None). ``progress(done, total, label)``
    is called after each run.
    """
    spec = _check_scene(scene)
    if not methods:
        raise ValueError("invalid methods = []: give at least one method")
    if not dts:
        raise ValueError("invalid dts = []: give at least one dt")
    for m in methods:
        _check_method(m)
    for d in dts:
        if not (d > 0 and math.isfinite(d)):
            raise ValueError(f"invalid dt = {d}: must be a finite number > 0")
    until = float(spec["until"] if until is None else until)
    full = _full_params(scene, params)
    has_exact = _has_exact(scene, params)
    ref = None if has_exact else reference(scene, min(dts), until, params)
    total = len(methods) * len(dts)
    rows = []
    done = 0
    for m in methods:
        for d in sorted(dts, reverse=True):
            traj = physstep.simulate(scene, m, d, until, params, stop_on_diverge=True)
            err = None if traj.diverged else _final_error(traj, ref)
            max_err = None if traj.diverged else _max_error(traj, ref)
            rows.append(
                {
                    "method": m,
                    "dt": float(d),
                    "steps": int(traj.steps),
                    "evals": int(traj.evals),
                    "time_s": traj.elapsed_ns * 1e-9,
                    "ns_per_step": traj.ns_per_step,
                    "error": err,
                    "max_error": max_err,
                    "energy_max_rel_error": float(np.nanmax(np.abs(traj.energy_error))),
                    "diverged": traj.diverged,
                }
            )
            done += 1
            if progress is not None:
                progress(done, total, f"{m} dt={d:g}")
    return {
        "scene": scene,
        "until": until,
        "params": full,
        "error_against": _error_against(has_exact, None if ref is None else ref.dt),
        "rows": rows,
    }
