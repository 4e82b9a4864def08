"""The energy a run reports means something: a runaway run is a divergence, never an infinite
energy, and the energy error is relative to a scale that is not a rounding error."""

from __future__ import annotations

import numpy as np
import physstep
import pytest


def test_a_runaway_run_is_a_divergence_not_an_infinite_energy() -> None:
    # Explicit Euler on the spring at dt = 1 reached an infinite energy by t = 1737, exit 0.
    with pytest.raises(physstep.DivergedError, match="ran away"):
        physstep.simulate("spring", "explicit-euler", 1.0, 3000.0)
    traj = physstep.simulate("spring", "explicit-euler", 1.0, 3000.0, stop_on_diverge=True)
    assert traj.diverged and np.isfinite(traj.energy).all() and np.isfinite(traj.x).all()


def test_energy_is_measured_against_a_meaningful_scale() -> None:
    # The chain starts at rest with E0 ~ 3e-30 J: relative to |E0| its error read 1e24.
    traj = physstep.simulate("chain", "velocity-verlet", 0.001, 0.5)
    assert traj.energy_scale > 0.01
    assert np.abs(traj.energy_error).max() < 1e-2
