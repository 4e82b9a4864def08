"""Bad arguments at the Python boundary: each is a ValueError of one line naming the argument
and its value (a wrong type, a number out of range, a dt that cannot advance the time, a
mass whose inverse is not finite, the wrong field of a spring or a rod)."""

from __future__ import annotations

import physstep
import pytest


@pytest.mark.parametrize(
    ("call", "needle"),
    [
        (lambda: physstep.World(2.5), "invalid dim = 2.5: must be a whole number from 1 to 3"),
        (lambda: physstep.World("2"), "invalid dim = '2'"),
        (lambda: physstep.World(2, dt="x"), "invalid dt = 'x': must be a number"),
        (lambda: physstep.World(2, max_steps_per_frame=2**40), "invalid max_steps_per_frame = 1099511627776"),
        (lambda: physstep.World(2, method=3), "invalid method = 3: must be a string"),
        (lambda: physstep.World(2).step(2**64), "invalid n = 18446744073709551616"),
        (lambda: physstep.World(2).step(1.5), "invalid n = 1.5"),
        (lambda: physstep.World(2).step(-1), "invalid n = -1"),
        (lambda: physstep.World(2).advance("1"), "invalid frame_time = '1'"),
        (lambda: physstep.World(2).restore(42), "invalid data = 42"),
        (lambda: physstep.World(2).add_drag(linear="a"), "invalid linear = 'a'"),
        (lambda: physstep.simulate("spring", "rk4", 0.1, 1.0, every=-1), "invalid every = -1"),
        (lambda: physstep.simulate("spring", "rk4", 0.1, 1.0, every=2.5), "invalid every = 2.5"),
        (lambda: physstep.simulate("spring", "rk4", "a", 1.0), "invalid dt = 'a'"),
        (lambda: physstep.simulate(3), "invalid scene = 3"),
        (lambda: physstep.simulate("spring", params={"m": "x"}), "invalid params['m'] = 'x'"),
        (lambda: physstep.World.from_scene("spring", params={"m": -1.0}), "invalid m = -1"),
        (lambda: physstep.World.from_scene("spring", params=5), "invalid params = 5"),
    ],
)
def test_every_bad_argument_is_a_value_error_naming_it(call, needle: str) -> None:
    with pytest.raises(ValueError) as info:
        call()
    assert needle in str(info.value)
    assert "\n" not in str(info.value)


def test_bad_types_in_forces_and_particles_name_the_argument() -> None:
    w = physstep.World(2)
    w.add_particle([0.0, 0.0])
    w.add_particle([1.0, 0.0])
    with pytest.raises(ValueError, match=r"invalid i = 1180591620717411303424"):
        w.add_spring(2**70, 1, 1.0)
    with pytest.raises(ValueError, match=r"invalid stiffness = 'k'"):
        w.add_spring(0, 1, "k")
    with pytest.raises(ValueError, match=r"invalid mass = 'heavy'"):
        w.add_particle([0.0, 0.0], mass="heavy")
    with pytest.raises(ValueError, match=r"invalid static = 'yes'"):
        w.add_particle([0.0, 0.0], static="yes")
    assert len(w) == 2


def test_params_are_taken_as_a_dict_or_as_pairs() -> None:
    w = physstep.World.from_scene("spring", "rk4", 0.1, params={"k": 2.0, "m": 1.0})
    assert w.accelerations[0, 0] == pytest.approx(-40.0)
    pairs = physstep.World.from_scene("spring", "rk4", 0.1, params=[("k", 2.0), ("m", 1.0)])
    assert pairs.state_hash() == w.state_hash()


def test_anchors_and_rods_name_the_right_field() -> None:
    w = physstep.World(2)
    w.add_particle([1.0, 0.0])
    with pytest.raises(ValueError, match=r"invalid j_or_anchor\[0\] = NaN: must be finite"):
        w.add_spring(0, [float("nan"), 0.0], 1.0)
    with pytest.raises(
        ValueError, match=r"invalid j_or_anchor = 0: must be a particle index < 1 other than i = 0"
    ):
        w.add_rod(0, 0, 5.0)
    with pytest.raises(ValueError, match=r"unknown method 'rk\\n4'"):
        physstep.World(2, method="rk\n4")


def test_a_dt_that_cannot_advance_is_refused() -> None:
    with pytest.raises(ValueError, match=r"invalid dt = 1e-310: must be at least max_frame_time / 2\^53"):
        physstep.World(1, dt=1e-310)


def test_a_mass_with_an_infinite_inverse_is_refused() -> None:
    w = physstep.World(1)
    with pytest.raises(ValueError, match=r"invalid mass = 5e-324: must be > 0 with a finite inverse"):
        w.add_particle([0.0], mass=5e-324)
    assert len(w) == 0
