"""Do not trust the stability analysis: run the scenes just below and just above dt_max.

For every method with a finite, nonzero ``lab.stability`` limit on the damped spring (c = 1),
the undamped spring, ``drag`` and ``orbit``, a plain ``physstep.simulate`` run at 0.97 dt_max
must stay bounded and one at 1.03 dt_max must grow. Growth is measured here on the runs
themselves, not with the lab's code:

- linear scenes: the largest |x| or |v| over the last tenth of a long run against the largest
  over its first tenth (bounded: at most 2; grows: a failed step or at least 100);
- orbit (a finite-horizon criterion, as documented in ``lab.stability``): over 10 000 steps
  (80 000 where the lab's longer horizon set the limit),
  the largest |x_k - x_0| and |v_k - v_0| in units of the orbit's radius (1 m) and speed
  (1 m/s) (bounded: at most 10; grows: a failed step or more than 10).
"""

from __future__ import annotations

import math

import numpy as np
import physstep
import pytest
from physstep import lab

METHODS = [m.name for m in physstep.methods()]
LINEAR_CASES = {"spring-damped": ("spring", {"c": 1.0}), "spring": ("spring", None), "drag": ("drag", None)}
LINEAR_STEPS = 40_000
ORBIT_STEPS = 10_000
ORBIT_LIMIT = 10.0


@pytest.fixture(scope="module")
def limits() -> dict[tuple[str, str], lab.StabilityResult]:
    """The stability result of every (case, method), computed once."""
    out: dict[tuple[str, str], lab.StabilityResult] = {}
    for case, (scene, params) in {**LINEAR_CASES, "orbit": ("orbit", None)}.items():
        for m in METHODS:
            out[case, m] = lab.stability(scene, m, params)
    return out


def _linear_growth(scene: str, method: str, dt: float, params: dict[str, float] | None) -> float:
    traj = physstep.simulate(
        scene, method, dt, dt * LINEAR_STEPS, params, stop_on_diverge=True, every=LINEAR_STEPS // 400
    )
    if traj.diverged:
        return math.inf
    y = np.abs(np.hstack([traj.x, traj.v])).max(axis=1)
    tenth = len(y) // 10
    return float(y[-tenth:].max() / y[:tenth].max())


def _orbit_growth(method: str, dt: float, steps: int = ORBIT_STEPS) -> float:
    traj = physstep.simulate("orbit", method, dt, dt * steps, stop_on_diverge=True)
    if traj.diverged:
        return math.inf
    assert traj.params["r"] == 1.0 and traj.params["gm"] == 1.0  # radius 1 m, speed 1 m/s
    return float(max(np.abs(traj.x - traj.x[0]).max(), np.abs(traj.v - traj.v[0]).max()))


def _finite(limits: dict[tuple[str, str], lab.StabilityResult], case: str, method: str) -> float:
    d = limits[case, method].dt_max
    if not d:
        pytest.skip(f"{method} on {case}: dt_max = {d}")
    return d


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("case", sorted(LINEAR_CASES))
def test_linear_scene_runs_confirm_dt_max(limits, case: str, method: str) -> None:
    scene, params = LINEAR_CASES[case]
    d = _finite(limits, case, method)
    below = _linear_growth(scene, method, 0.97 * d, params)
    above = _linear_growth(scene, method, 1.03 * d, params)
    assert below <= 2.0, (case, method, d, below)
    assert above >= 100.0, (case, method, d, above)


@pytest.mark.parametrize("method", METHODS)
def test_orbit_runs_confirm_dt_max(limits, method: str) -> None:
    d = _finite(limits, "orbit", method)
    # over the horizon the limit holds for: the test's, or the longer one it was checked
    # against when the first run of that was not bounded (issue 25, item 14)
    h = limits["orbit", method].horizon
    steps = h["steps"] if h["long_dt_max"] else ORBIT_STEPS
    below = _orbit_growth(method, 0.97 * d, steps)
    above = _orbit_growth(method, 1.03 * d, steps)
    assert below <= ORBIT_LIMIT, (method, d, below)
    # 1.03 dt_max grows, unless the lab found a resonance window there (the orbit's stable set
    # near its limit is a comb, as the Duffing oscillator's): then it must say so, and be right.
    window = any(math.isclose(a, 1.03 * d) for a in limits["orbit", method].stable_above)
    assert (above <= ORBIT_LIMIT) == window, (method, d, above, limits["orbit", method].note)


def test_methods_with_finite_limits_are_covered(limits) -> None:
    # the runs above must not all be skipped: most methods have a finite limit on each scene
    for case in [*LINEAR_CASES, "orbit"]:
        finite = [m for m in METHODS if limits[case, m].dt_max]
        assert len(finite) >= 8, (case, finite)


def test_leapfrog_on_drag_is_limited_by_its_repeating_map() -> None:
    # The restart step (v_half = v + a dt/2) read as the map gave 6.17 s. The map that repeats
    # is v_half' = v_half (1 - q + q^2/2), q = c dt / m: at most 1 in size iff q <= 2, i.e.
    # dt <= 2 m / c = 4 s.
    res = lab.stability("drag", "leapfrog")
    assert res.dt_max == pytest.approx(4.0, rel=1e-6)
    assert res.analysis == "amplification matrix" and "memory" in res.criterion
