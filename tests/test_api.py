"""The Python API over the engine: registries, simulate, errors, World."""

from __future__ import annotations

import doctest

import numpy as np
import physstep
import pytest


def test_docstring_examples_run() -> None:
    failures, tried = doctest.testmod(physstep, verbose=False)
    assert tried > 0 and failures == 0


def test_methods_carry_their_info() -> None:
    ms = {m.name: m for m in physstep.methods()}
    assert ms["rk4"].order == 4 and ms["rk4"].evals == 4 and not ms["rk4"].symplectic
    assert ms["backward-euler"].implicit and ms["symplectic-euler"].symplectic
    assert physstep.method("leapfrog").order == 2
    with pytest.raises(ValueError, match="unknown method 'x'; valid methods: explicit-euler"):
        physstep.method("x")


def test_simulate_returns_arrays_consistent_with_the_notes() -> None:
    traj = physstep.simulate("spring", "explicit-euler", dt=1.0, until=3.0)
    assert traj.t.tolist() == [0.0, 1.0, 2.0, 3.0]
    assert traj.x[:, 0].tolist() == [20.0, 20.0, 10.0, -10.0]
    assert traj.v[:, 0].tolist() == [0.0, -10.0, -20.0, -25.0]
    assert np.array_equal(traj.a[:, 0], -traj.x[:, 0] / 2)
    assert traj.energy[0] == pytest.approx(1000.0)
    assert traj.exact_x is not None and traj.exact_x[0, 0] == 20.0
    assert traj.evals == 3


def test_simulate_rejects_bad_input_with_the_field_named() -> None:
    with pytest.raises(ValueError, match=r"invalid dt = 0"):
        physstep.simulate("spring", "rk4", dt=0.0, until=1.0)
    with pytest.raises(ValueError, match=r"invalid dt = NaN"):
        physstep.simulate("spring", "rk4", dt=float("nan"), until=1.0)
    with pytest.raises(ValueError, match=r"invalid m = -1"):
        physstep.simulate("spring", "rk4", dt=0.1, until=1.0, params={"m": -1})
    with pytest.raises(ValueError, match=r"unknown scene 'x'"):
        physstep.simulate("x", "rk4", dt=0.1, until=1.0)
    with pytest.raises(ValueError, match=r"invalid x0\[0\] = NaN"):
        physstep.simulate("spring", "rk4", dt=0.1, until=1.0, x0=[float("nan")])
    with pytest.raises(ValueError, match=r"invalid len\(v0\) = 2: must be 1"):
        physstep.simulate("spring", "rk4", dt=0.1, until=1.0, v0=[1.0, 2.0])
    with pytest.raises(ValueError, match=r"invalid params\['m'\] = 'x': must be a number"):
        physstep.simulate("spring", "rk4", dt=0.1, until=1.0, params={"m": "x"})


def test_divergence_is_reported_not_returned() -> None:
    with pytest.raises(physstep.DivergedError, match="explicit-euler.*diverged"):
        physstep.simulate("spring", "explicit-euler", dt=1.0, until=100000.0, every=1000)
    traj = physstep.simulate(
        "spring", "explicit-euler", dt=1.0, until=100000.0, every=1000, stop_on_diverge=True
    )
    assert traj.diverged is not None and "diverged" in traj.diverged
    assert np.isfinite(traj.x).all()


def test_world_api_names() -> None:
    w = physstep.World(2, method="velocity-verlet", dt=0.01)
    i = w.add_particle([0.0, 1.0], velocity=[1.0, 0.0], mass=2.0)
    idx = w.add_particles(np.zeros((3, 2)) + [[2.0, 0.0]], masses=np.ones(3))
    assert int(i) == 0 and np.asarray(idx).tolist() == [1, 2, 3] and idx.ids.tolist() == [1, 2, 3]
    w.add_gravity([0.0, -9.81])
    w.add_spring(0, 1, stiffness=10.0)
    w.add_spring(2, [5.0, 5.0], 1.0, rest_length=0.5, damping=0.1)
    w.add_drag(linear=0.01, quadratic=0.001)
    w.add_central_gravity([0.0, 0.0], 0.1)
    w.add_nbody_gravity(g=1.0, softening=0.1)
    w.add_rod(3, [2.0, 1.0], 1.0)
    e0 = w.energy()
    w.step(10)
    assert w.time == pytest.approx(0.1)
    assert w.positions.shape == (4, 2) and w.velocities.shape == (4, 2)
    assert np.isfinite(w.energy()) and w.energy() != e0
    assert w.momentum().shape == (2,)
    snap = w.snapshot()
    h = w.state_hash()
    w.step(5)
    assert w.state_hash() != h
    w.restore(snap)
    assert w.state_hash() == h
    steps = w.advance(1 / 30)
    assert steps == 3 and 0.0 <= w.alpha < 1.0
    assert w.interpolated_positions().shape == (4, 2)


def test_world_bad_input_leaves_it_unchanged() -> None:
    w = physstep.World(3)
    w.add_particle([0.0, 0.0, 0.0])
    h = w.state_hash()
    with pytest.raises(ValueError, match=r"invalid position\[1\] = NaN"):
        w.add_particle([0.0, float("nan"), 0.0])
    with pytest.raises(ValueError, match=r"invalid mass = 0"):
        w.add_particle([1.0, 0.0, 0.0], mass=0.0)
    with pytest.raises(ValueError, match=r"invalid mass = -2"):
        w.add_particle([1.0, 0.0, 0.0], mass=-2.0)
    with pytest.raises(ValueError, match=r"invalid j_or_anchor = 5"):
        w.add_spring(0, 5, 1.0)
    with pytest.raises(ValueError, match=r"invalid length = 0"):
        w.add_rod(0, [1.0, 0.0, 0.0], 0.0)
    with pytest.raises(ValueError, match=r"invalid position shape \(1,\): must be \(3,\)"):
        w.add_particle([1.0])
    with pytest.raises(ValueError, match=r"invalid positions shape \(4,\): must be \(n, 3\)"):
        w.add_particles(np.zeros(4))
    with pytest.raises(ValueError, match=r"invalid velocities shape \(2, 3\): must be \(1, 3\)"):
        w.add_particles([[1.0, 2.0, 3.0]], velocities=np.zeros((2, 3)))
    with pytest.raises(ValueError, match=r"invalid masses shape \(2,\): must be \(1,\)"):
        w.add_particles([[1.0, 2.0, 3.0]], masses=[1.0, 2.0])
    with pytest.raises(ValueError, match=r"invalid positions shape \(3, 1\): must be \(1, 3\)"):
        w.positions = np.zeros((3, 1))
    with pytest.raises(ValueError, match=r"invalid i = -1: must be a particle index >= 0"):
        w.add_spring(-1, 0, 1.0)
    assert len(w) == 1 and w.state_hash() == h
    for dim in (0, 4, -1):
        with pytest.raises(ValueError, match=rf"invalid dim = {dim}"):
            physstep.World(dim)
    with pytest.raises(ValueError, match="unknown method"):
        physstep.World(2, method="eulr")
    with pytest.raises(ValueError, match="invalid frame_time = -1"):
        w.advance(-1.0)
    with pytest.raises(ValueError, match="corrupt snapshot"):
        w.restore(b"garbage")


def test_static_particles_do_not_move() -> None:
    w = physstep.World(2, dt=0.01)
    w.add_particle([0.0, 0.0], mass=float("inf"))
    w.add_particle([1.0, 0.0], static=True, velocity=[3.0, 0.0])
    w.add_particle([2.0, 0.0])
    w.add_gravity([0.0, -9.81])
    w.step(100)
    assert w.positions[:2].tolist() == [[0.0, 0.0], [1.0, 0.0]]
    assert w.positions[2, 1] < -4.0


def test_bulk_add_is_vectorised() -> None:
    n = 200_000
    w = physstep.World(3, method="symplectic-euler", dt=0.01)
    rng = np.random.default_rng(1)
    idx = w.add_particles(rng.random((n, 3)), rng.random((n, 3)), np.full(n, 2.0))
    assert int(idx[-1]) == n - 1 and len(idx) == n and len(w) == n
    w.add_gravity([0.0, 0.0, -9.81])
    w.step(2)
    assert w.positions.shape == (n, 3)


def _chain_world() -> physstep.World:
    return physstep.World.from_scene("chain", "velocity-verlet", 1 / 240, [("n", 6.0)])


@pytest.mark.parametrize("fps", [30, 60, 144])
def test_frame_rate_independence_through_python(fps: int) -> None:
    reference = _chain_world()
    reference.step(480)
    w = _chain_world()
    for _ in range(2 * fps):  # two seconds of frames
        w.advance(1 / fps)
    # Frame times never add up to exactly 2 s in binary; step the remainder by hand.
    w.step(480 - w.steps)
    assert w.state_hash() == reference.state_hash()
    assert np.array_equal(w.positions, reference.positions)


def test_interpolation_lies_between_states_and_overload_is_capped() -> None:
    w = physstep.World(1, method="symplectic-euler", dt=0.01, max_steps_per_frame=4)
    w.add_particle([0.0], velocity=[1.0])
    before = w.positions[0, 0]
    assert w.advance(0.025) == 2
    after = w.positions[0, 0]
    alpha = w.alpha
    assert alpha == pytest.approx(0.5)
    x = w.interpolated_positions()[0, 0]
    assert before < x < after
    assert x == pytest.approx(after - 0.5 * 0.01)
    # Frames 10 times longer than the physics can keep up with: at most 4 steps each.
    for _ in range(5):
        assert w.advance(0.1) <= 4
    frames, steps, clamped, dropped = w.clock_stats
    assert frames == 6 and steps == 2 + 20 and dropped > 0
    assert w.advance(5.0) == 4
    assert w.clock_stats[2] == pytest.approx(4.9)


def test_particles_added_one_by_one_match_a_bulk_add() -> None:
    rng = np.random.default_rng(7)
    x, v, m = rng.random((500, 2)), rng.random((500, 2)), 1.0 + rng.random(500)
    one = physstep.World(2, method="leapfrog", dt=0.01)
    ids = [one.add_particle(x[i], velocity=v[i], mass=m[i], static=(i % 97 == 0)) for i in range(500)]
    assert [h.id for h in ids] == [int(h) for h in ids] == list(range(500)) and len(one) == 500
    bulk = physstep.World(2, method="leapfrog", dt=0.01)
    for start in range(0, 500, 97):
        bulk.add_particles(x[start : start + 1], v[start : start + 1], m[start : start + 1], static=True)
        bulk.add_particles(x[start + 1 : start + 97], v[start + 1 : start + 97], m[start + 1 : start + 97])
    for w in (one, bulk):
        w.add_gravity([0.0, -1.0])
        w.add_spring(1, 2, 10.0)
        w.step(20)
    assert one.state_hash() == bulk.state_hash()
    assert one.positions[0].tolist() == x[0].tolist()  # static: never moves


def test_add_particle_checks_at_once_and_mixes_with_bulk_adds() -> None:
    w = physstep.World(2)
    assert int(w.add_particle([0.0, 0.0])) == 0
    with pytest.raises(ValueError, match=r"invalid mass = -1"):
        w.add_particle([1.0, 0.0], mass=-1.0)
    assert w.add_particles(np.ones((2, 2))).rows.tolist() == [1, 2]
    assert int(w.add_particle([3.0, 0.0])) == 3
    w.add_nbody_gravity()
    assert int(w.add_particle([4.0, 0.0])) == 4
    with pytest.raises(ValueError, match=r"invalid mass\[5\] = inf: must be finite when n-body"):
        w.add_particle([5.0, 0.0], mass=float("inf"))
    assert len(w) == 5 and w.positions[:, 0].tolist() == [0.0, 1.0, 1.0, 3.0, 4.0]


def test_simulate_computes_the_exact_solution_and_kinetic_energy_when_read() -> None:
    """Issue 22, item 6: a recording pays for the exact solution and the kinetic energy only
    when they are read; read, they are what an eager recording gives, bit for bit."""
    import dataclasses

    tr = physstep.simulate("spring", "symplectic-euler", dt=0.01, until=2.0)
    assert "_exact_x" in vars(tr) and not isinstance(vars(tr)["_exact_x"], np.ndarray)
    assert not isinstance(vars(tr)["_kinetic"], np.ndarray)
    # The eager path: the same scene recorded by World.record.
    eager = physstep.simulate(
        lambda: physstep.World.from_scene("spring", "symplectic-euler", 0.01), until=2.0
    )
    assert isinstance(vars(eager)["_kinetic"], np.ndarray)
    assert tr.kinetic is not None and eager.kinetic is not None
    assert tr.kinetic.tobytes() == eager.kinetic.tobytes()
    assert tr.energy is not None and eager.energy is not None
    assert tr.energy.tobytes() == eager.energy.tobytes()
    p = {q["name"]: q["default"] for q in physstep.scene("spring")["params"]}
    m, k, x0 = p["m"], p["k"], p["x0"]
    w0 = np.sqrt(k / m)
    assert tr.exact_x is not None and tr.exact_v is not None
    assert tr.exact_x.shape == tr.x.shape and tr.exact_v.shape == tr.v.shape
    np.testing.assert_allclose(tr.exact_x[:, 0], x0 * np.cos(w0 * tr.t), rtol=0, atol=1e-12 * x0)
    np.testing.assert_allclose(tr.exact_v[:, 0], -x0 * w0 * np.sin(w0 * tr.t), rtol=0, atol=1e-12 * x0)
    assert tr.exact_x is tr.exact_x  # computed once, then kept
    assert tr.position_error is not None and tr.position_error.shape == tr.t.shape
    # A scene without an exact solution says None; replace() and == see the values.
    assert physstep.simulate("chain", "leapfrog", dt=0.01, until=0.1).exact_x is None
    twin = dataclasses.replace(tr, method="other")
    assert twin.exact_x is not None and twin.exact_x.tobytes() == tr.exact_x.tobytes()
    assert twin.kinetic is not None and twin.kinetic.tobytes() == tr.kinetic.tobytes()
