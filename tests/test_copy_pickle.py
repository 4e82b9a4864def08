"""A World copies and pickles (issue 8), as pymunk's Space and REBOUND's Simulation do: the
copy or the unpickled world continues bitwise as the original."""

from __future__ import annotations

import copy
import pickle

import numpy as np
import physstep
import pytest


def wind(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
    """A module-level Python force: picklable."""
    return -0.5 * v


def decay(t: float, y: np.ndarray) -> np.ndarray:
    """A module-level flow: picklable."""
    return -y


def _worlds() -> list[physstep.World]:
    chain = physstep.World.from_scene("chain", "leapfrog", 0.001)
    chain.add_force(wind)
    game = physstep.World(2, method="verlet", dt=1 / 60, loop="steps-per-frame", substeps=3)
    game.add_particle([0.0, 1.0], velocity=[1.0, 0.0])
    game.add_particle([0.0, 0.0], static=True)
    game.add_spring(0, 1, 10.0, damping=0.1)
    game.add_rod(0, [0.0, 2.0])
    return [
        chain,
        game,
        physstep.World.from_scene("lorenz", "rk4", 0.01),
        physstep.World.from_flow(decay, [1.0, 2.0], "heun", 0.1),
    ]


@pytest.mark.parametrize("how", ["copy", "deepcopy", "pickle"])
def test_a_copy_continues_bitwise_as_the_original(how: str) -> None:
    dup = {"copy": copy.copy, "deepcopy": copy.deepcopy, "pickle": lambda w: pickle.loads(pickle.dumps(w))}[
        how
    ]
    for w in _worlds():
        w.step(7)
        w.advance(0.05)
        twin = dup(w)
        assert twin.method == w.method and twin.dt == w.dt and len(twin) == len(w)
        w.step(20)
        twin.step(20)
        assert twin.state_hash() == w.state_hash(), repr(w)
        # The copy is independent.
        twin.step(1)
        assert twin.state_hash() != w.state_hash()


def test_a_lambda_force_does_not_pickle_and_says_so() -> None:
    w = physstep.World(1)
    w.add_particle([1.0])
    w.add_force(lambda t, x, v: -x)
    with pytest.raises((pickle.PicklingError, AttributeError)):
        pickle.dumps(w)
    assert copy.deepcopy(w).state_hash() == w.state_hash()
