"""Position constraints at the boundary: the API, bad input, copies and pickles, the CLI's
report, and the long runs (the engine's physics is tested in crates/physstep/tests)."""

from __future__ import annotations

import copy
import json
import math
import pickle

import numpy as np
import physstep
import pytest
from conftest import run_cli


def _pair(method: str = "verlet") -> physstep.World:
    w = physstep.World(2, method=method, dt=0.01)
    w.add_particle([0.0, 0.0])
    w.add_particle([1.0, 0.0])
    w.add_particle([2.0, 0.0])
    w.add_gravity([0.0, -9.81])
    return w


def test_constraints_are_added_and_held() -> None:
    w = _pair()
    assert w.constraint_count == 0
    assert w.constraint_violation() == 0.0
    assert int(w.add_pin(0, [0.0, 0.0])) == 0
    assert int(w.add_distance_constraint(1, 0)) == 1
    assert int(w.add_rope(2, 1, 1.5)) == 2
    assert int(w.add_plane([0.0, 2.0], -5.0)) == 3
    assert int(w.add_distance_limit(2, 0, 0.5, 3.0)) == 4
    assert int(w.add_distance_constraint(2, [3.0, 0.0], length=1.2, compliance=1e-4)) == 5
    assert w.constraint_count == 6
    assert w.constraint_iterations == 16
    w.constraint_iterations = 40
    assert w.constraint_iterations == 40
    w.step(300)
    x = w.positions
    assert x[0].tolist() == [0.0, 0.0]
    assert abs(np.linalg.norm(x[1] - x[0]) - 1.0) < 1e-6
    assert np.linalg.norm(x[2] - x[1]) <= 1.5 + 1e-6
    assert (x[:, 1] >= -2.5 - 1e-9).all()
    assert 0.0 <= w.constraint_violation() < 0.05


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda w: w.add_distance_constraint(3, 0), "invalid i = 3: must be a particle index < 3"),
        (lambda w: w.add_distance_constraint(-1, 0), "invalid i = -1: must be a particle index >= 0"),
        (
            lambda w: w.add_distance_constraint(1, 1),
            "invalid j = 1: must be a particle index < 3 other than i = 1",
        ),
        (
            lambda w: w.add_distance_constraint(0, 9),
            "invalid j = 9: must be a particle index < 3 other than i = 0",
        ),
        (
            lambda w: w.add_distance_constraint(0, 1, length=-2.0),
            "invalid length = -2: must be a finite number > 0",
        ),
        (
            lambda w: w.add_distance_constraint(0, 1, length=math.nan),
            "invalid length = NaN: must be a finite number > 0",
        ),
        (lambda w: w.add_distance_constraint(0, 1, compliance=-1e-3), "invalid compliance = -0.001: must be"),
        (lambda w: w.add_distance_constraint(0, 1, compliance=math.nan), "invalid compliance = NaN: must be"),
        (
            lambda w: w.add_distance_constraint(0, 1, length="long"),
            "invalid length = 'long': must be a number",
        ),
        (lambda w: w.add_rope(0, 1, 0.0), "invalid max_length = 0: must be a finite number > 0"),
        (lambda w: w.add_pin(4, [0.0, 0.0]), "invalid i = 4: must be a particle index < 3"),
        (lambda w: w.add_pin(0, [0.0, math.inf]), "invalid point[1] = inf: must be finite"),
        (lambda w: w.add_plane([0.0, 0.0]), "invalid normal = (0, 0): must be a nonzero vector"),
        (lambda w: w.add_distance_limit(0, 1, 2.0, 1.0), "invalid max_length = 1: must be >= min_length = 2"),
        (
            lambda w: setattr(w, "constraint_iterations", 0),
            "invalid constraint_iterations = 0: must be a whole",
        ),
        (
            lambda w: setattr(w, "constraint_iterations", 2.5),
            "invalid constraint_iterations = 2.5: must be a whole",
        ),
    ],
)
def test_bad_constraints_are_one_clear_line_and_change_nothing(call: object, message: str) -> None:
    w = _pair()
    w.add_distance_constraint(0, 1)
    before = (w.state_hash(), w.constraint_count, w.constraint_iterations)
    with pytest.raises(ValueError) as err:
        call(w)  # type: ignore[operator]
    text = str(err.value)
    assert text.startswith(message), text
    assert "\n" not in text
    assert (w.state_hash(), w.constraint_count, w.constraint_iterations) == before


def test_a_flow_takes_no_constraint() -> None:
    w = physstep.World.from_scene("lorenz", "rk4", 0.01)
    with pytest.raises(ValueError, match="cannot add a constraint to a world that is the flow 'lorenz'"):
        w.add_plane([0.0, 0.0, 1.0])


def test_copies_and_pickles_keep_the_constraints_bitwise() -> None:
    w = physstep.World.from_scene("ragdoll", "velocity-verlet", 1 / 120)
    w.constraint_iterations = 12
    w.step(20)
    for other in (copy.copy(w), copy.deepcopy(w), pickle.loads(pickle.dumps(w))):
        assert other.constraint_count == w.constraint_count == 19
        assert other.constraint_iterations == 12
        assert other.state_hash() == w.state_hash()
    clone = pickle.loads(pickle.dumps(w))
    w.step(100)
    clone.step(100)
    assert clone.state_hash() == w.state_hash()
    assert np.array_equal(clone.positions, w.positions)


def test_pendulum_keeps_its_rod_and_energy_for_144000_steps() -> None:
    # The scene's default dt (0.01 s), velocity Verlet: SHAKE/RATTLE.
    w = physstep.World.from_scene("pendulum", "velocity-verlet", 0.01)
    e0 = w.energy()
    assert e0 is not None
    tenths = []
    worst = 0.0
    for _ in range(10):
        de = 0.0
        for _ in range(144):
            w.step(100)
            worst = max(worst, abs(float(np.linalg.norm(w.positions[0])) - 1.0))
            e = w.energy()
            assert e is not None
            de = max(de, abs(e - e0))
        tenths.append(de)
    assert w.steps == 144_000
    assert worst < 1e-9
    assert 0 < tenths[0] < 1e-3 * abs(e0)
    assert tenths[-1] <= 1.1 * tenths[0], tenths


def test_the_force_rod_is_still_there() -> None:
    force = physstep.World.from_scene("pendulum", "rk4", 0.01, {"rod": 0})
    rod = physstep.World.from_scene("pendulum", "rk4", 0.01)
    assert force.constraint_count == 0
    assert rod.constraint_count == 1


def test_cli_run_reports_the_constraints() -> None:
    res = run_cli("run", "cloth", "--method", "verlet", "--until", "0.5", "--param", "w=6", "--param", "h=6")
    assert res.returncode == 0, res.stderr
    assert "max violation" in res.stdout
    res = run_cli("run", "pendulum", "--method", "velocity-verlet", "--format", "json")
    assert res.returncode == 0, res.stderr
    doc = json.loads(res.stdout)
    assert 0 <= doc["constraints"]["max_violation"] < 1e-9
    res = run_cli("run", "spring", "--format", "json")
    assert "constraints" not in json.loads(res.stdout)


def test_cli_bad_constraint_params_exit_2() -> None:
    res = run_cli("run", "cloth", "--param", "compliance=-1")
    assert res.returncode == 2
    assert res.stderr.strip().count("\n") == 0
    assert "compliance = -1" in res.stderr


def test_the_readme_example_runs() -> None:
    from pathlib import Path

    text = (Path(__file__).parent.parent / "README.md").read_text()
    start = text.index("```python", text.index("### Constraints")) + len("```python")
    code = text[start : text.index("```", start)]
    scope: dict[str, object] = {"physstep": physstep}
    exec(compile(code, "README.md", "exec"), scope)  # noqa: S102 - the README's own example
    w = scope["w"]
    assert isinstance(w, physstep.World)
    assert w.constraint_count == 2


@pytest.mark.parametrize(("method", "order"), [("velocity-verlet", 2), ("symplectic-euler", 1)])
def test_the_lab_measures_the_rod_constraint_against_rattle(method: str, order: int) -> None:
    from physstep import lab

    res = lab.order("pendulum", method, levels=4)
    assert res.error_against.startswith("reference: velocity-verlet at dt/16")
    assert abs(res.order - order) < 0.15, res.order
    table = lab.compare("pendulum", [method, "rk4"], dt=0.01, until=1.0)
    assert table.error_against.startswith("reference: velocity-verlet")


# --- issue 25, item 12: SHAKE's sweep cap is said, with the violation it left -------------


def _double_pendulum(sweeps: int | None = None) -> physstep.World:
    """Two rods of 1 m from the origin, held out horizontally, under velocity Verlet (RATTLE)."""
    w = physstep.World(2, method="velocity-verlet", dt=0.01)
    w.add_particles([[1.0, 0.0], [2.0, 0.0]])
    w.add_gravity([0.0, -9.81])
    w.add_distance_constraint(0, [0.0, 0.0])
    w.add_distance_constraint(0, 1)
    if sweeps is not None:
        w.constraint_iterations = sweeps
    return w


def test_shake_stopped_by_its_sweep_cap_is_counted_with_the_violation_it_left() -> None:
    w = _double_pendulum()
    assert w.constraint_stats == {"last_sweeps": 0, "capped_steps": 0, "capped_violation": 0.0}
    worst = 0.0
    for _ in range(1000):
        w.step()
        worst = max(worst, w.constraint_violation())
    stats = w.constraint_stats
    # 16 sweeps (the default) do not reach SHAKE's 1e-13 on this chain of two rods: the
    # violation reaches 1e-7 m, and the world says so instead of staying silent
    assert worst > 1e-9
    assert stats["capped_steps"] > 0 and stats["capped_violation"] == pytest.approx(worst, rel=1e-6)
    assert 1 <= stats["last_sweeps"] <= 16
    # with enough sweeps SHAKE meets its tolerance, and no step is capped
    w = _double_pendulum(64)
    worst = 0.0
    for _ in range(1000):
        w.step()
        worst = max(worst, w.constraint_violation())
    assert worst <= 1e-12
    assert w.constraint_stats["capped_steps"] == 0 and w.constraint_stats["capped_violation"] == 0.0


def test_a_plane_normal_too_short_to_square_is_a_direction_all_the_same() -> None:
    # [1e-300, 0] is a nonzero vector: it used to be refused as "not a nonzero vector"
    w = physstep.World(2)
    w.add_particle([-1.0, 0.0])
    w.add_plane([1e-300, 0.0], 0.0)
    w.add_plane([0.0, 5e-324], -10.0)
    w.step()
    assert w.positions[0, 0] == pytest.approx(0.0, abs=1e-12)
    with pytest.raises(ValueError, match=r"invalid normal = \(0, 0\): must be a nonzero vector"):
        w.add_plane([0.0, 0.0])


# --- issue 25, item 11: constraints that cannot all be met are reported ---------------------


@pytest.mark.parametrize(
    ("build", "needle"),
    [
        (
            lambda w: (
                w.add_balls([[0.0, 0.0], [3.0, 0.0]], radii=0.5),
                w.add_pin(0, [1, 1]),
                w.add_pin(1, [1, 1]),
            ),
            "constraints 0 and 1 pin balls 0 and 1 0 m apart, closer than their radii add to (1)",
        ),
        (
            lambda w: (w.add_particle([0.0, 0.0]), w.add_plane([1, 0], 1.0), w.add_plane([-1, 0], 0.0)),
            "constraints 0 and 1 are opposite planes with no point between them (1 m apart)",
        ),
        (
            lambda w: (w.add_particles([[0.0, 0.0], [0.0, 0.0]]), w.add_distance_constraint(0, 1, 1.0)),
            "constraint 0: the ends of a distance of 1 m coincide (particle 0 at [0, 0])",
        ),
        (
            lambda w: (w.add_particle([0.0, 0.0]), w.add_pin(0, [0, 0]), w.add_pin(0, [2, 0])),
            "constraints 0 and 1 pin particle 0 to two points, [0, 0] and [2, 0]",
        ),
        (
            lambda w: (w.add_particle([0.0, 0.0]), w.add_pin(0, [0, -1]), w.add_plane([0, 1], 0.0)),
            "constraint 0 pins particle 0 at [0, -1], 1 m behind the plane of constraint 1",
        ),
        (
            lambda w: (
                w.add_particles([[0.0, 0.0], [1.0, 0.0]]),
                w.add_distance_constraint(0, 1),
                w.add_pin(0, [0, 0]),
                w.add_pin(1, [3, 0]),
            ),
            "constraint 0: its ends are held 3 m apart (pinned, static or an anchor): 1 m cannot be met",
        ),
    ],
)
def test_constraints_that_cannot_all_be_met_warn_and_keep_their_violation(build, needle: str) -> None:
    w = physstep.World(2, dt=0.01)
    with pytest.warns(physstep.ConstraintWarning) as caught:
        build(w)
    said = [str(c.message) for c in caught]
    assert any(needle in m for m in said), said
    assert all(m.startswith("the constraints cannot all be met: ") and "\n" not in m for m in said)
    assert any(needle in c for c in w.constraint_conflicts())
    # the world still steps, and the violation stays to be seen
    w.step(10)
    assert w.constraint_violation() > 0.1


def test_constraints_that_can_be_met_do_not_warn() -> None:
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for name in ["pendulum", "cloth", "ragdoll"]:
            assert physstep.World.from_scene(name).constraint_conflicts() == []
        w = physstep.World(2)
        w.add_particles([[0.0, 0.0], [1.0, 0.0]])
        w.add_distance_constraint(0, 1)
        w.add_pin(0, [0, 0])
        w.add_pin(1, [1, 0])  # held 1 m apart, the rod's length
        w.add_plane([1, 0], -1.0)
        w.add_plane([-1, 0], -1.0)  # -1 <= x <= 1: room between them
    assert w.constraint_conflicts() == []


def test_run_reports_constraints_that_cannot_all_be_met(tmp_path) -> None:
    scene = tmp_path / "rods.toml"
    scene.write_text(
        'dimension = 2\nmethod = "symplectic-euler"\ndt = 0.01\nuntil = 0.1\n'
        "[[particles]]\nposition = [0.0, 0.0]\n[[particles]]\nposition = [0.0, 0.0]\n"
        '[[constraints]]\nkind = "distance"\ni = 0\nj = 1\nlength = 1.0\n'
    )
    out = run_cli("run", str(scene))
    assert out.returncode == 0, out.stderr
    assert "Warning" not in out.stderr
    assert (
        "the constraints cannot all be met: constraint 0: the ends of a distance of 1 m coincide"
        in out.stdout
    )
    data = json.loads(run_cli("run", str(scene), "--format", "json").stdout)
    assert any("coincide" in c for c in data["constraints"]["conflicts"])


def _jakobsen(w: int, h: int, steps: int, sweeps: int) -> tuple[list[list[float]], list[list[float]]]:
    """The cloth scene (spacing 0.1 m, 0.01 kg, top corners pinned, g along -y) stepped by
    the plain Jakobsen loop a game programmer writes, in Python floats: Verlet from (x, v),
    `sweeps` Gauss-Seidel projections of the links in the scene's order, then the velocity
    given the projection's motion. Returns the positions and velocities."""
    s, dt = 0.1, 1.0 / 120.0
    links = []
    for r in range(h):
        for c in range(w):
            at = r * w + c
            if c + 1 < w:
                links.append((at, at + 1, s))
            if r + 1 < h:
                links.append((at, at + w, s))
            if c + 1 < w and r + 1 < h:
                links.append((at, at + w + 1, s * math.sqrt(2.0)))
                links.append((at + 1, at + w, s * math.sqrt(2.0)))
    x = [[c * s, -(r * s), 0.0] for r in range(h) for c in range(w)]
    v = [[0.0, 0.0, 0.0] for _ in x]
    inv = [1.0 / 0.01] * len(x)
    pins = {0: [0.0, 0.0, 0.0], w - 1: [(w - 1) * s, 0.0, 0.0]}
    for p in pins:
        inv[p] = 0.0
    g = [0.0, -9.81, 0.0]
    for _ in range(steps):
        for xp, vp in zip(x, v, strict=True):
            for k in range(3):
                nxt = 2.0 * xp[k] - (xp[k] - vp[k] * dt) + g[k] * (dt * dt)
                vp[k] = (nxt - xp[k]) * (1.0 / dt)
                xp[k] = nxt
        moved = [list(p) for p in x]
        for p, point in pins.items():
            x[p] = list(point)
        for _ in range(sweeps):
            for i, j, length in links:
                d = [x[i][k] - x[j][k] for k in range(3)]
                r = math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
                wsum = inv[i] + inv[j]
                if wsum == 0.0 or r == 0.0:
                    continue
                f = (-(r - length) / wsum) / r
                for k in range(3):
                    x[i][k] += inv[i] * f * d[k]
                    x[j][k] -= inv[j] * f * d[k]
        for p in range(len(x)):
            for k in range(3):
                v[p][k] += (x[p][k] - moved[p][k]) * (1.0 / dt)
    return x, v


def test_the_verlet_cloth_is_the_jakobsen_loop_bit_for_bit() -> None:
    # What bench/bench_cloth.py times physstep against: the plain loop, the same bits.
    world = physstep.World.from_scene("cloth", "verlet", params={"w": 6, "h": 5})
    world.step(40)
    x, v = _jakobsen(6, 5, 40, 16)
    assert world.constraint_stats["last_sweeps"] == 16
    np.testing.assert_array_equal(world.positions, np.array(x))
    np.testing.assert_array_equal(world.velocities, np.array(v))


@pytest.mark.parametrize("method", ["verlet", "symplectic-euler"])
def test_a_capped_cloth_step_reports_exactly_the_violation_it_left(method: str) -> None:
    world = physstep.World.from_scene("cloth", method, params={"w": 8, "h": 8})
    world.constraint_iterations = 2
    world.step(1)
    stats = world.constraint_stats
    assert stats["capped_steps"] == 1 and stats["last_sweeps"] == 2
    assert stats["capped_violation"] == world.constraint_violation() > 0.0
