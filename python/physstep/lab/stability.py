"""``stability``: the largest stable dt of a method, and the amplification matrix behind it
on the linear scenes."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

import physstep
from physstep.lab.common import EPS, REFERENCE_METHOD, number, positive
from physstep.lab.results import GrowthTest, StabilityResult
from physstep.lab.system import Subject

#: The scenes whose step map is linear or affine in the state (amplification-matrix analysis).
LINEAR_SCENES = ("spring", "drag", "projectile")
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
#: Bounded growth (the nonlinear scenes, the flows and every system): ``steps`` steps without
#: a failed step and with the state within GROWTH_LIMIT of its scales throughout; the grid
#: walk first screens with GROWTH_SCREEN_STEPS / GROWTH_STEPS of them (a tenth: an escape
#: within those is an escape within all).
#: ``steps`` defaults to GROWTH_STEPS on a built-in scene and to GROWTH_STEPS_SYSTEM on a
#: system, whose Python forces cost some microseconds per call (a search makes some 25 runs).
GROWTH_STEPS = 10_000
GROWTH_SCREEN_STEPS = 1_000
GROWTH_STEPS_SYSTEM = 1_000
GROWTH_LIMIT = 10.0
#: A system's state scales come from a run of REFERENCE_METHOD over SCALE_RUN_SCALES natural
#: time scales at SCALE_RUN_STEPS steps per time scale (its largest excursion from x0, v0).
SCALE_RUN_SCALES = 10
SCALE_RUN_STEPS = 200
#: Default bisection tolerances (relative), the range allowed, and the most halvings.
RTOL_LINEAR = 1e-10
RTOL_GROWTH = 1e-4
RTOL_RANGE = (1e-15, 0.1)
MAX_BISECTIONS = 100
#: After bisecting, dt_max * SCAN_FACTORS are checked; an unstable one (an island below the
#: limit found) lowers the bracket and the search repeats, at most SCAN_ROUNDS times. The
#: last percent is scanned finer: near a nonlinear limit the stable set can be a fine comb
#: (Duffing under velocity Verlet: 0.943 s stable, 0.944 to 0.950 s unstable but 0.9501 s
#: stable), and a bisection may end on a tooth above the first failure.
SCAN_FACTORS = (*(0.9 + 0.01 * i for i in range(10)), 0.995, 0.999)
SCAN_ROUNDS = 4
#: Bounded growth: dt_max * ABOVE_FACTORS are checked too. Near its limit a nonlinear system
#: has resonance windows: the Duffing oscillator under velocity Verlet first fails at
#: 0.944 s, runs stable again at 0.972 s (whatever the start near x0 = 1) and fails for good
#: above 1.0 s. dt_max stays where instability first appears; ``stable_above`` lists these.
ABOVE_FACTORS = (1.01, 1.02, 1.03, 1.05, 1.1)
#: Bounded growth is a finite-horizon test, so a limit it finds is checked against a longer
#: horizon: HORIZON_STEPS times the steps at HORIZON_DT dt_max. Where that fails, the search
#: runs again over the longer horizon. A method whose state drifts away at every dt
#: (explicit Euler on an undamped oscillator gains energy by a factor 1 + (w dt)^2 every
#: step, Heun and midpoint by 1 + (w dt)^4 / 4) has a limit that only measures the run's
#: length, falling as steps^(-1/q) for a growth per step of order dt^q: 8 times the steps
#: take it to 0.35 of itself for q = 2 and 0.59 for q = 4, below HORIZON_SHRINK. Such a
#: method is reported unstable at every dt, with the horizon that showed it. A limit that
#: shrinks less (RK4's slow drift on an orbit, 0.71; a chain's long-time resonances) is
#: replaced by the longer horizon's, and the note gives both.
HORIZON_DT = 0.75
HORIZON_STEPS = 8
HORIZON_SHRINK = 0.65


# --------------------------------------------------------------------------------------
# the amplification matrix (linear and affine scenes)


def _map_period(method: str) -> int:
    """Steps after which the method's step map repeats (alternating Euler: two)."""
    return physstep.method(method).period


def amplification(scene: Any, method: str, dt: float, params: dict[str, float] | None = None) -> np.ndarray:
    """The amplification matrix of ``method``'s repeating step map on a linear/affine scene
    (or on your own system, as :func:`physstep.simulate` takes it: the matrix is exact only
    where the system's step map is linear or affine in the state, as with springs and
    dampers; :func:`stability` uses it only on :data:`LINEAR_SCENES`).

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
    subject = Subject(scene, params)
    subject.check_method(method)
    subject.refuse_bodies("amplification")
    return _amplification(subject, method, positive("dt", dt))


def _amplification(subject: Subject, method: str, dt: float) -> np.ndarray:
    period = _map_period(method)
    world = subject.world(method, dt)
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
        col[np.abs(col) <= 4 * EPS * (np.abs(s) + np.abs(base))] = 0.0
        cols.append(col)
    m = np.array(cols).T
    # Rounding noise (e.g. Verlet's backward-difference velocity, eps |x| / dt) would split
    # the Jordan blocks of a free particle into eigenvalues 1 +- sqrt(noise): drop it.
    m[np.abs(m) <= NOISE_REL * np.abs(m).max(initial=0.0)] = 0.0
    return m


def _rho(subject: Subject, method: str, dt: float) -> float:
    """The per-step spectral radius of the repeating map (inf if a step fails)."""
    try:
        m = _amplification(subject, method, dt)
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


# --------------------------------------------------------------------------------------
# bounded growth (everything else)


@dataclass(frozen=True)
class Growth:
    """The bounded-growth test: ``steps`` steps, with |x_k - x_0| <= limit * ``x_scale`` and
    |v_k - v_0| <= limit * ``v_scale`` throughout (max norms)."""

    steps: int
    x_scale: float
    v_scale: float
    how: str

    def measure(self, subject: Subject, method: str, dt: float, steps: int) -> float:
        """max over ``steps`` steps of max(|x_k - x_0| / x_scale, |v_k - v_0| / v_scale) (inf
        if a step fails)."""
        try:
            t = subject.run(method, dt, dt * steps, stop_on_diverge=True)
        except physstep.StepError:
            return math.inf
        if t.diverged:
            return math.inf
        with np.errstate(all="ignore"):
            g = max(
                float(np.abs(t.x - t.x[0]).max(initial=0.0)) / self.x_scale,
                float(np.abs(t.v - t.v[0]).max(initial=0.0)) / self.v_scale,
            )
        return g if math.isfinite(g) else math.inf

    def test(self) -> GrowthTest:
        """The numbers of the test, as the result reports them."""
        return GrowthTest(steps=self.steps, limit=GROWTH_LIMIT, x_scale=self.x_scale, v_scale=self.v_scale)


def _growth(subject: Subject, scale: float, steps: int, given: bool) -> Growth:
    """The scales of the bounded-growth test.

    w = 2 pi / the natural time scale. A built-in particle scene: A = max(max|x0|, max|v0|/w)
    (1 if the state is all zero), V = w A. A system or a flow scene, whose initial state may
    be far from where its motion goes (Lorenz from (1, 1, 1) swings out to |z| = 45): also a
    run of :data:`REFERENCE_METHOD` over :data:`SCALE_RUN_SCALES` time scales, A at least its
    largest |x_k - x_0| and V = max(w A, its largest |v_k - v_0|).
    """
    probe = subject.probe
    w = 2.0 * math.pi / scale
    x0 = float(np.abs(probe.x[0]).max(initial=0.0))
    v0 = float(np.abs(probe.v[0]).max(initial=0.0))
    amp = max(x0, v0 / w)
    dx = dv = 0.0
    how = "A = max(|x0|, |v0|/w)"
    if subject.estimated:
        n = SCALE_RUN_SCALES * SCALE_RUN_STEPS
        run = subject.run(
            REFERENCE_METHOD, scale / SCALE_RUN_STEPS, SCALE_RUN_SCALES * scale, stop_on_diverge=True
        )
        if run.diverged:
            what = f"invalid time_scale = {scale!r}" if given else f"the estimated time scale {scale:.6g} s"
            raise ValueError(
                f"{what} is too long for {subject.name}: the scale run ({REFERENCE_METHOD}, {n} steps of "
                f"{scale / SCALE_RUN_STEPS:.6g} s) failed ({run.diverged}); give a shorter time_scale"
            )
        dx = float(np.abs(run.x - run.x[0]).max(initial=0.0))
        dv = float(np.abs(run.v - run.v[0]).max(initial=0.0))
        amp = max(amp, dx)
        how = (
            f"A = max(|x0|, |v0|/w, the largest |x_k - x_0| of {REFERENCE_METHOD} over "
            f"{SCALE_RUN_SCALES} time scales)"
        )
    amp = amp if amp > 0 else 1.0
    vel = max(w * amp, dv)
    how += f" = {amp:.6g}, V = " + ("max(w A, its largest |v_k - v_0|)" if subject.estimated else "w A")
    how += f" = {vel:.6g}, w = 2 pi / time scale = {w:.6g} 1/s"
    return Growth(steps, amp, vel, how)


# --------------------------------------------------------------------------------------
# the search


def _check_rtol(rtol: Any, linear: bool) -> float:
    if rtol is None:
        return RTOL_LINEAR if linear else RTOL_GROWTH
    r = number("rtol", rtol)
    lo, hi = RTOL_RANGE
    if not lo <= r <= hi:  # also NaN
        raise ValueError(f"invalid rtol = {r!r}: must be between {lo:g} and {hi:g}")
    return r


def _check_steps(steps: Any, subject: Subject) -> int:
    if steps is None:
        return GROWTH_STEPS_SYSTEM if subject.is_system else GROWTH_STEPS
    if isinstance(steps, bool) or not isinstance(steps, int | np.integer) or not 10 <= steps <= 10**7:
        raise ValueError(f"invalid steps = {steps!r}: must be a whole number from 10 to 1e7")
    return int(steps)


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


def _memo(f: Callable[[float], bool]) -> Callable[[float], bool]:
    seen: dict[float, bool] = {}

    def g(d: float) -> bool:
        if d not in seen:
            seen[d] = f(d)
        return seen[d]

    return g


def _criterion(
    subject: Subject, method: str, linear: bool, growth: Growth | None
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

        def by_radius(d: float) -> bool:
            return _rho(subject, method, d) <= 1.0 + RHO_TOL

        return text, by_radius, by_radius
    assert growth is not None
    n = growth.steps
    text = (
        f"bounded growth: {n} steps without a failed step and with max|x_k - x_0| <= "
        f"{GROWTH_LIMIT:g} A and max|v_k - v_0| <= {GROWTH_LIMIT:g} V throughout, {growth.how}"
    )

    def stable(d: float) -> bool:
        return growth.measure(subject, method, d, n) <= GROWTH_LIMIT

    def screen(d: float) -> bool:
        return (
            growth.measure(subject, method, d, max(1, n * GROWTH_SCREEN_STEPS // GROWTH_STEPS))
            <= GROWTH_LIMIT
        )

    return text, stable, screen


def _only(horizon: dict[str, Any]) -> str:
    """How far the longer horizon's limit got, in words."""
    d = horizon["long_dt_max"]
    return "at no dt of the grid" if not d else f"only up to {d:.6g} s"


def _horizon(
    subject: Subject,
    method: str,
    growth: Growth,
    grid: list[float],
    rtol: float,
    dt_max: float,
    hi: float | None,
) -> tuple[float, float | None, dict[str, Any], Callable[[float], bool] | None]:
    """A bounded-growth limit checked against a longer horizon: (dt_max, the unstable point
    above it, what the check found). The limit stands when HORIZON_STEPS times the steps at
    HORIZON_DT dt_max stay within the limit. Otherwise the search runs again over the longer
    horizon: a limit that shrinks below HORIZON_DT of the first (a drift: the method's state
    leaves at every dt, sooner the larger the dt) below HORIZON_SHRINK of the first is
    reported as 0, unstable at every dt;
    one that shrinks less (the system's own long-time reach, a resonance) replaces it, and the
    longer horizon's test is returned for the checks above it."""
    steps = HORIZON_STEPS * growth.steps
    g_long = growth.measure(subject, method, HORIZON_DT * dt_max, steps)
    out: dict[str, Any] = {
        "steps": steps,
        "dt": HORIZON_DT * dt_max,
        "growth": g_long,
        "first_dt_max": dt_max,
    }
    if g_long <= GROWTH_LIMIT:
        out.update(long_dt_max=None, dt_max=dt_max)
        return dt_max, hi, out, None
    longer = Growth(steps, growth.x_scale, growth.v_scale, growth.how)
    _, test, screen = _criterion(subject, method, False, longer)
    test = _memo(test)
    d_long, hi_long = _search(test, _memo(screen), grid, rtol)
    d_long = d_long if d_long is not None else dt_max
    out["long_dt_max"] = d_long
    if d_long == 0:
        # Even the grid's lowest dt leaves the scales over the longer horizon: the system's own
        # reach (bodies flung out of a cluster), not a drift that can be told from it.
        out["dt_max"] = dt_max
        out["long_dt_max"] = None
        out["note"] = (
            f"over {steps} steps the state leaves its scales at every dt of the grid (the "
            "system's own reach), so the longer horizon cannot judge the limit"
        )
        return dt_max, hi, out, None
    if d_long < HORIZON_SHRINK * dt_max:
        out["dt_max"] = 0.0
        return 0.0, hi_long if d_long == 0 else d_long, out, None
    out["dt_max"] = d_long
    return d_long, hi_long, out, test


def stability(
    scene: Any,
    method: str,
    params: dict[str, float] | None = None,
    *,
    cap: float | None = None,
    rtol: float | None = None,
    time_scale: float | None = None,
    steps: int | None = None,
) -> StabilityResult:
    """The largest stable dt of ``method`` on ``scene``: ``dt_max``.

    Returns a :class:`~physstep.lab.results.StabilityResult` (its fields documented there;
    ``.to_dict()`` is what ``physstep stability --format json`` prints).

    ``scene`` is a built-in scene's name or a system (a :class:`physstep.Flow`, or a
    zero-argument callable returning a fresh World or Flow); a split method on a flow is
    refused. ``analysis`` says which test was used and ``criterion`` spells it out:

    - ``"amplification matrix"`` on the built-in linear/affine scenes (:data:`LINEAR_SCENES`):
      dt is stable iff the per-step spectral radius of the repeating step map's amplification
      matrix (:func:`amplification`, over positions, velocities and the integrator's memory)
      is <= 1 + :data:`RHO_TOL`.
    - ``"bounded growth"`` on the others, flows and systems: dt is stable iff ``steps`` steps
      (default :data:`GROWTH_STEPS`, :data:`GROWTH_STEPS_SYSTEM` on a system) run without a
      failed step and the state stays within :data:`GROWTH_LIMIT` of its own scales:
      max|x_k - x_0| <= 10 A and max|v_k - v_0| <= 10 V (max norms), with w = 2 pi / the
      natural time scale, A = max(max|x0|, max|v0|/w) and V = w A on a built-in scene; on a
      system or a flow A is at least the largest excursion |x_k - x_0| of an RK4 run over
      :data:`SCALE_RUN_SCALES` time scales and V = max(w A, its largest |v_k - v_0|)
      (``growth`` has the numbers). It needs no energy (meaningful when E0 is about 0, as on
      the chain, and for a flow, which has none) and is a finite-horizon test: a method whose
      error drifts (explicit Euler's energy gain, backward Euler's inward spiral) gets a limit
      that depends on the horizon, or 0.

    The search walks a log grid up from :data:`GRID_LOW_SCALES` natural time scales
    (``time_scale``, else :func:`physstep.lab.time_scale`, estimated for a system) to ``cap``
    (default :data:`CAP_SCALES` time scales) to the first unstable point, bisects to relative
    ``rtol`` (default 1e-10 for the matrix, 1e-4 for bounded growth; allowed 1e-15 to 0.1),
    then checks 0.90 ... 0.99 dt_max and searches again below any unstable one: ``dt_max``
    bounds the stable interval that starts at dt -> 0. ``dt_max`` is 0 if the lowest grid
    point is unstable already, None if no instability is found up to ``cap``; ``dt_unstable``
    is the unstable point found just above it. A bounded-growth limit is also checked at
    :data:`ABOVE_FACTORS` times dt_max: near its limit a nonlinear system can have resonance
    windows, stable again above where it first failed; ``stable_above`` lists those dts (and
    ``note`` says so), dt_max staying where instability first appears. ValueError
    naming ``cap`` unless it is above the grid's lowest point, naming ``rtol`` outside its
    range, ``steps`` unless 10 to 1e7.

    A bounded-growth limit is checked against a longer horizon (``horizon``: :data:`HORIZON_STEPS`
    times the steps at :data:`HORIZON_DT` dt_max, its growth and whether it stayed within the
    limit): a method whose state drifts away at every dt (explicit Euler on an oscillator)
    fails there and gets ``dt_max`` 0 with ``note`` saying "unstable at every dt" and the
    horizon tested, instead of a number that only measures the length of the run.

    Why the grid starts at 1e-3 time scales: there omega dt = 2 pi 1e-3, where the growth per
    step of the methods unstable on the undamped oscillator (Heun, midpoint: |R| - 1 =
    (omega dt)^4/8 = 2e-10) is still well above the 1e-12 threshold.
    """
    subject = Subject(scene, params)
    subject.check_method(method)
    subject.refuse_bodies("stability")
    scale = subject.time_scale(time_scale)
    linear = not subject.is_system and scene in LINEAR_SCENES
    rtol = _check_rtol(rtol, linear)
    n = _check_steps(steps, subject)
    low = GRID_LOW_SCALES * scale
    cap = positive("cap", CAP_SCALES * scale if cap is None else cap)
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
    growth = None if linear else _growth(subject, scale, n, time_scale is not None)
    criterion, test, screen = _criterion(subject, method, linear, growth)
    stable = _memo(test)
    grid = _grid(scale, cap)
    dt_max, hi = _search(stable, stable if screen is test else _memo(screen), grid, rtol)
    above = []
    horizon = None
    if growth is not None and dt_max:
        dt_max, hi, horizon, long_test = _horizon(subject, method, growth, grid, rtol, dt_max, hi)
        stable = long_test or stable
    if horizon is not None and horizon["dt_max"] == 0:
        note = (
            f"unstable at every dt (the horizon tested: {horizon['steps']} steps): "
            f"{growth.steps if growth else 0} steps stay within the limit up to "
            f"{horizon['first_dt_max']:.6g} s, {horizon['steps']} steps {_only(horizon)}: "
            "the limit shrinks as the run grows (the state drifts away whatever the dt)"
        )
    elif dt_max is None:
        note = f"stable at every dt up to the cap {cap:.6g} s"
    elif dt_max == 0:
        note = f"unstable at every dt down to {grid[0]:.6g} s ({GRID_LOW_SCALES:g} natural time scales)"
    else:
        note = f"stable interval (0, {dt_max:.12g}] s; unstable at {hi:.12g} s"
        if horizon is not None and "note" in horizon:
            note += f" ({horizon['note']})"
        if horizon is not None and horizon["long_dt_max"] is not None:
            note += (
                f" over the longer horizon of {horizon['steps']} steps ({horizon['first_dt_max']:.6g} s "
                f"over {growth.steps if growth else 0})"
            )
        if not linear:
            above = [f for f in ABOVE_FACTORS if f * dt_max <= cap and stable(f * dt_max)]
        if above:
            note += (
                f"; stable again at {', '.join(f'{f:g}' for f in above)} dt_max (a resonance window: "
                "the edge is not sharp, dt_max is where instability first appears)"
            )
    return StabilityResult(
        scene=subject.name,
        kind=subject.kind,
        method=method,
        params=subject.full_params,
        dt_max=dt_max,
        dt_unstable=hi,
        analysis="amplification matrix" if linear else "bounded growth",
        criterion=criterion,
        cap=cap,
        rtol=rtol,
        time_scale=scale,
        grid=(grid[0], grid[-1], GRID_PER_DECADE),
        note=note,
        growth=None if growth is None else growth.test(),
        stable_above=None if growth is None else tuple(f * (dt_max or 0.0) for f in above),
        horizon=None if growth is None else horizon,
        spectral_radius_at_dt_max=_rho(subject, method, dt_max) if linear and dt_max else None,
    )
