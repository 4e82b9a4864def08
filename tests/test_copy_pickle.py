"""A World copies and pickles (issue 8), as pymunk's Space and REBOUND's Simulation do: the
copy or the unpickled world continues bitwise as the original. A pickle is the engine's own
scene text of the world and its snapshot, Python callables beside them (issue 22, item 7)."""

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


# --- pickles through the engine's scene text and snapshot (issue 22, item 7) ---------------


def _dumps_loads(w: physstep.World) -> physstep.World:
    return pickle.loads(pickle.dumps(w))


def _mesh_world() -> physstep.World:
    """Bodies (a mesh, whose principal frame is turned), springs on them without a rest
    length, a particle spring without one, a rope, balls: every kind of part."""
    w = physstep.World(3, method="velocity-verlet", dt=1 / 120)
    w.add_particle([0.0, 0.0, 3.0], velocity=[0.1, 0.0, 0.0])
    w.add_particle([0.5, 0.0, 3.0], static=True)
    w.add_spring(0, 1, 40.0, damping=0.2)
    w.add_gravity([0.0, 0.0, -9.81])
    verts = np.array([[0, 0, 0], [0.4, 0, 0], [0, 0.2, 0], [0, 0, 0.1]], dtype=float) + [0.1, 0.0, 0.0]
    tris = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]
    b = w.add_body(
        physstep.Mesh(verts, tris), density=500.0, position=(1.0, 0.0, 2.0), angular_velocity=(0.5, 1.0, -2.0)
    )
    w.add_body_spring(b, (0.3, 0.01, 0.02), [1.2, 0.0, 3.0], 50.0, damping=0.1)
    w.add_body_spring(b, (-0.1, 0.05, 0.0), 0, 20.0)
    w.add_rope(0, [0.0, 0.0, 4.0], 2.0)
    return w


@pytest.mark.parametrize(
    "make",
    [
        _mesh_world,
        lambda: physstep.World.from_scene("racket"),
        lambda: physstep.World.from_scene("balls"),
        lambda: physstep.World.from_scene("cloth", "verlet", 1 / 120),
        lambda: physstep.World.from_flow(decay, [1.0, 2.0], "rk4", 0.1),
    ],
)
def test_every_world_that_can_be_built_pickles_and_continues_bitwise(make) -> None:
    w = make()
    w.step(30)
    twin = _dumps_loads(w)
    assert twin.state_hash() == w.state_hash()
    for _ in range(100):
        w.step()
        twin.step()
        assert twin.state_hash() == w.state_hash()


def test_a_spring_without_a_rest_length_pickles() -> None:
    w = physstep.World(3, dt=1 / 120)
    w.add_body(physstep.Box(0.2, 0.1, 0.05), mass=1.0, angular_velocity=(0.5, 1.0, -2.0))
    w.add_particle([0.0, 0.0, 1.0])
    w.add_body_spring(0, (0.2, 0.0, 0.0), [1.0, 0.0, 0.0], 50.0)
    w.add_spring(0, [0.0, 0.0, 0.0], 10.0)
    w.step(5)
    twin = _dumps_loads(w)
    w.step(100)
    twin.step(100)
    assert twin.state_hash() == w.state_hash()


def test_a_pickle_is_the_engines_scene_text_and_snapshot() -> None:
    w = physstep.World(2, dt=0.01)
    w.add_particle([1.0, 0.0])
    w.add_spring(0, [0.0, 0.0], 5.0)
    w.add_force(wind)
    parts, snapshot = w.__reduce__()[1]
    assert "[[springs]]" in parts["scene"] and "rest_length = 1.0" in parts["scene"]
    assert parts["forces"][0][0] is wind and isinstance(snapshot, bytes)


def test_a_python_force_that_does_not_pickle_refuses_in_one_clear_line() -> None:
    w = physstep.World(1)
    w.add_particle([1.0])
    w.add_force(lambda t, x, v: -x, name="pull")
    with pytest.raises(pickle.PicklingError) as info:
        pickle.dumps(w)
    msg = str(info.value)
    assert "\n" not in msg
    assert msg.startswith("this World cannot be pickled: its Python force 0 ('pull') does not pickle")
    assert copy.deepcopy(w).state_hash() == w.state_hash()


def test_a_settled_pile_pickles_and_continues_bitwise() -> None:
    # Settled balls rest about 1e-7 of a radius into each other (and the bottom row a
    # rounding past the floor): a state the engine made, which the rebuild from the pickle
    # takes as it is. Balls added by hand are still checked.
    w = physstep.World.from_scene("pile", params={"n": 400})
    w.step(240)
    twin = _dumps_loads(w)
    assert twin.state_hash() == w.state_hash() and len(twin) == 400
    for world in (copy.deepcopy(w), pickle.loads(pickle.dumps(twin))):
        assert world.state_hash() == w.state_hash()
    w.step(120)
    twin.step(120)
    assert twin.state_hash() == w.state_hash()
    x = np.array(twin.positions)
    with pytest.raises(ValueError, match="balls may not overlap"):
        twin.add_ball(x[0] + [0.01, 0.01], radius=0.05)
    assert len(twin) == 400


def test_a_settled_pile_written_as_a_scene_file_is_still_refused_by_the_loader(tmp_path) -> None:
    # A scene file is user input: its balls may not overlap (docs/collisions.md); only a
    # world's own structure, rebuilt for a pickle or a copy, takes them as they are.
    w = physstep.World.from_scene("pile", params={"n": 400})
    w.step(240)
    path = tmp_path / "pile.toml"
    path.write_text(w.__reduce__()[1][0]["scene"])
    with pytest.raises(ValueError, match="balls may not overlap"):
        physstep.load_scene(path)


def test_a_pickle_keeps_the_implicit_settings() -> None:
    # Settings other than the defaults: the unpickled world steps as the original does, not as
    # a world with the defaults (which halves the stiff chain's second linearly implicit step).
    w = physstep.World.from_scene("stiff-chain", "linearly-implicit-euler")
    w.set_implicit(energy_halvings=0, tol=1e-9, preconditioner="incomplete-cholesky", exact_jacobian=False)
    w.step(1)
    back = pickle.loads(pickle.dumps(w))
    fresh = pickle.loads(pickle.dumps(w))
    default = physstep.World.from_scene("stiff-chain", "linearly-implicit-euler")
    default.step(1)
    for world in (w, back, fresh, default):
        world.step(5)
    assert np.array_equal(back.positions, w.positions)
    assert back.solve_stats == w.solve_stats
    assert not np.array_equal(default.positions, w.positions)
