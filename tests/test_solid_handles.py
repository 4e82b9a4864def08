"""Handles of solids, joints, solid springs and forces on solids; removal; the solids'
views (docs/contact.md, "Handles and removal")."""

import copy
import operator
import pickle

import numpy as np
import physstep
import pytest


def pile(dim: int = 2, skip: int | None = None) -> tuple[physstep.World, list]:
    """The ground, a pyramid of six boxes, a ball on a distance joint to the top box, springs
    from box 5 to the ball and from box 4 to the world; solid ``skip`` left out with what
    hangs on it. Returns the World and the handles by pile index (None where skipped)."""
    w = physstep.World(dim=dim)
    w.add_gravity([0.0, -9.81, 0.0][:dim])
    h: list = []

    def add(k: int, shape: object, at: list[float], **kw: object) -> None:
        h.append(None if k == skip else w.add_solid(shape, position=at[:dim], **kw))

    if dim == 2:
        add(0, physstep.Box(50.0, 1.0), [0.0, -1.0], kind="static")
    else:
        add(0, physstep.Plane([0.0, 1.0, 0.0]), [0.0, 0.0, 0.0], kind="static")
    k = 1
    for row in range(3):
        for i in range(3 - row):
            x = (i - (2 - row) / 2) * 1.01
            box = physstep.Box(*[0.5] * dim)
            add(k, box, [x, 0.5 + row * 1.001, 0.0], **({"linear_damping": 0.5} if k == 3 else {}))
            k += 1
    add(7, physstep.Circle(0.25), [0.0, 4.5, 0.0])
    if h[6] is not None and h[7] is not None:
        w.add_joint("distance", h[6], h[7], anchor=[0.0, 3.5, 0.0][:dim], anchor_b=[0.0, 4.5, 0.0][:dim])
    if h[5] is not None and h[7] is not None:
        w.add_solid_spring(h[5], [0.0] * dim, h[7], [0.0] * dim, stiffness=20.0, damping=0.5)
    if h[4] is not None:
        w.add_solid_spring(h[4], [0.0] * dim, None, [-3.0, 2.0, 0.0][:dim], stiffness=5.0)
    return w, h


def motion(w: physstep.World) -> list[bytes]:
    c = w.contacts()
    return [
        w.solid_positions().tobytes(),
        np.asarray(w.solid_orientations()).tobytes(),
        w.solid_velocities().tobytes(),
        np.asarray(w.solid_angular_velocities()).tobytes(),
        c["pairs"].tobytes(),
        c["normal_impulses"].tobytes(),
    ]


@pytest.mark.parametrize("dim", [2, 3])
def test_a_solid_removed_before_any_step_steps_bitwise_as_one_never_added(dim: int) -> None:
    for k in (2, 5, 7):
        w, h = pile(dim)
        w.remove(h[k])
        built, _ = pile(dim, skip=k)
        for _ in range(60):
            w.step()
            built.step()
            assert motion(w) == motion(built), k
        assert len(w.contacts()["pairs"]) > 0


def test_handles_reach_their_solids_after_a_removal_and_a_removed_one_is_refused() -> None:
    w, h = pile()
    w.step(30)
    ball = h[7]
    assert isinstance(ball, physstep.SolidHandle)
    assert (ball.id, operator.index(ball), int(ball), ball.alive, ball.kind) == (7, 7, 7, True, "dynamic")
    before = w.solid_positions()[ball].copy()
    assert w.joint_count == 1 and w.solid_spring_count == 2
    pairs_before = w.contacts()["pairs"]
    w.remove(h[2])
    # The rows after it moved up; the handles follow.
    assert len(w.solids) == 7 == w.solid_count
    assert operator.index(ball) == 6
    assert np.array_equal(w.solid_positions()[ball], before)
    assert np.array_equal(w.solids[ball].position, before)
    assert w.solids[6] == ball and hash(w.solids[6]) == hash(ball)
    assert [s.id for s in w.solids] == [0, 1, 3, 4, 5, 6, 7]
    assert not h[2].alive
    # The latest contacts without it, renumbered.
    kept = [[a - (a > 2), b - (b > 2)] for a, b in pairs_before.tolist() if 2 not in (a, b)]
    assert w.contacts()["pairs"].tolist() == kept
    # Removing a solid takes what hangs on it.
    w.remove(ball)
    assert (w.joint_count, w.solid_spring_count) == (0, 1)
    assert w.solid_springs[0].a == h[4]
    msg = "invalid solid = SolidHandle(id=7): it was removed from its World"
    for use in (
        lambda: w.remove(ball),
        lambda: ball.position,
        lambda: operator.index(ball),
        lambda: w.apply_solid_force(ball, [1.0, 0.0]),
        lambda: w.solids[ball],
        lambda: w.add_joint("ball", ball, anchor=[0.0, 0.0]),
    ):
        with pytest.raises(ValueError, match=f"^{msg.replace('(', '[(]').replace(')', '[)]')}$"):
            use()
    with pytest.raises(IndexError):  # numpy turns the handle's ValueError into its own
        w.solid_positions()[ball]
    w.step(60)
    assert np.isfinite(w.solid_positions()).all()
    # A new solid gets a new id.
    assert w.add_solid(physstep.Circle(0.2), position=[9.0, 9.0]).id == 8


def test_a_world_after_removals_pickles_and_copies_and_steps_bitwise() -> None:
    w, h = pile(3)
    w.step(10)
    w.remove(h[6])
    w.step(5)
    for other in (copy.copy(w), pickle.loads(pickle.dumps(w))):
        assert other.state_hash() == w.state_hash()
        assert [s.id for s in other.solids] == [s.id for s in w.solids]
        other.step(20)
        assert other.solids[h[7]].id == 7  # the handle of w reaches the same solid here
    w.step(20)
    assert other.state_hash() == w.state_hash()
    assert motion(other) == motion(w)
    other.remove(h[7])
    assert other.solid_count == 6 and w.solid_count == 7
    # The same solids built without it: the same motion, other ids, another hash.
    a, ha = pile(2)
    a.remove(ha[6])
    b, _ = pile(2, skip=6)
    assert motion(a) == motion(b)
    assert a.state_hash() != b.state_hash()
    with pytest.raises(ValueError, match="other solids, joints or springs"):
        b.restore(a.snapshot())
    # A pickle written before handles (no contact_ids) loads with the ids in order.
    rebuild, (parts, snap) = b.__reduce__()
    old = rebuild({k: v for k, v in parts.items() if k != "contact_ids"}, snap)
    assert [s.id for s in old.solids] == list(range(7)) and old.state_hash() == b.state_hash()


def test_a_solids_view_writes_are_validated_and_stepped() -> None:
    w, h = pile()
    w.step(30)
    ball = w.solids[-1]
    ball.velocity = [3.0, 0.0]
    ball.angular_velocity = 1.5
    assert list(ball.velocity) == [3.0, 0.0] and ball.angular_velocity == 1.5
    box = w.solids[1]
    box.position = [10.0, 5.0]
    box.angle = 0.5
    assert list(box.position) == [10.0, 5.0] and box.angle == 0.5 == box.orientation
    assert box.shape.kind == "box" and w.solids[0].kind == "static"
    x = w.solid_positions()[box][1]
    # Render interpolation draws a solid moved by hand where it was put.
    w.advance(0.05)
    box.position = [10.0, 5.0]
    assert list(w.interpolated_solid_positions()[box]) == [10.0, 5.0]
    w.step()
    assert 4.9 < w.solid_positions()[box][1] < x
    hash_before = w.state_hash()
    for field, value, msg in [
        ("position", [np.nan, 0.0], r"^invalid position\[0\] = NaN: must be finite"),
        ("velocity", [1.0], r"^invalid len\(velocity\) = 1: must be 2$"),
        ("angle", "x", r"^invalid angle = 'x'"),
    ]:
        with pytest.raises(ValueError, match=msg):
            setattr(box, field, value)
    with pytest.raises(ValueError, match="^invalid velocity = non-zero: must be zero for a static solid"):
        w.solids[0].velocity = [1.0, 0.0]
    assert w.state_hash() == hash_before
    with pytest.raises(IndexError, match="solid index 8 out of range: the World has 8 solids"):
        w.solids[8]
    s3, _ = pile(3)
    top = s3.solids[6]
    top.orientation = [2.0, 0.0, 0.0, 0.0]
    assert list(top.orientation) == [1.0, 0.0, 0.0, 0.0]
    top.angular_velocity = [0.0, 1.0, 0.0]
    assert list(s3.solid_angular_velocities()[6]) == [0.0, 1.0, 0.0]
    with pytest.raises(AttributeError, match="no angle"):
        top.angle  # noqa: B018


def test_joint_and_spring_handles_read_and_write_their_parameters() -> None:
    w = physstep.World(dim=2)
    wheel = w.add_solid(physstep.Circle(0.5))
    j = w.add_joint("revolute", wheel, anchor=[0.0, 0.0], max_motor=100.0)
    assert isinstance(j, physstep.JointHandle)
    assert (j.kind, j.a, j.b, j.lower, j.motor_speed, j.max_motor) == (
        "revolute",
        wheel,
        None,
        None,
        0.0,
        100.0,
    )
    j.motor_speed = 2.0
    w.step(60)
    assert w.solids[wheel].angular_velocity == pytest.approx(2.0, abs=1e-6)
    j.lower, j.upper = -0.1, 0.1
    assert (j.lower, j.upper) == (-0.1, 0.1)
    with pytest.raises(ValueError, match=r"^invalid lower = 1: must be <= upper \(0.1\)$"):
        j.lower = 1.0
    with pytest.raises(ValueError, match=r"^invalid max_motor = -1: must be finite and >= 0$"):
        j.max_motor = -1.0
    assert (j.lower, j.max_motor) == (-0.1, 100.0)
    w.remove(j)
    assert not j.alive and w.joint_count == 0
    with pytest.raises(
        ValueError, match=r"^invalid joint = JointHandle\(id=0\): it was removed from its World$"
    ):
        j.motor_speed  # noqa: B018

    def pulled(k: float | None) -> float:
        w, h = pile()
        s = w.solid_springs[1]
        assert isinstance(s, physstep.SolidSpringHandle) and s.a == h[4] and s.b is None
        if k is not None:
            s.stiffness = k
            assert s.stiffness == k
        w.step()
        return float(w.solid_velocities()[h[4]][0])

    assert pulled(500.0) < pulled(None)
    w, h = pile()
    s = w.solid_springs[0]
    with pytest.raises(ValueError, match=r"^invalid stiffness = -1: must be a number in \[0, 1e12\]$"):
        s.stiffness = -1.0
    s.rest_length, s.damping = 0.5, 2.0
    assert (s.stiffness, s.rest_length, s.damping) == (20.0, 0.5, 2.0)
    w.remove(s)
    assert w.solid_spring_count == 1 and not s.alive


def push(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
    """A force of 1 N along x (module level: it pickles)."""
    return np.array([[1.0, 0.0]])


def test_a_force_on_a_solid_is_removed_by_its_handle_and_with_its_solid() -> None:
    w, h = pile()
    f = w.add_solid_force(h[7], push)
    g = w.add_solid_force(h[1], push)
    assert isinstance(f, physstep.SolidForceHandle) and (f.id, g.id, f.name, g.solid) == (0, 1, "push", h[1])
    w.remove(h[7])
    assert not f.alive and g.alive and w.solid_force_count == 1
    assert g.solid == h[1]
    w.step(2)
    for other in (copy.copy(w), pickle.loads(pickle.dumps(w))):
        assert other.solid_force_count == 1
        other.step(5)
    w.step(5)
    assert motion(other) == motion(w)
    w.remove(g)
    assert w.solid_force_count == 0
    with pytest.raises(ValueError, match=r"^invalid force = SolidForceHandle\(id=1\): it was removed"):
        w.remove(g)
    other, _ = pile()
    foreign = r"^invalid solid = SolidHandle\(id=4\): must be a handle of this World's solids \(it is another"
    foreign += r" World's;"
    with pytest.raises(ValueError, match=foreign):
        other.remove(h[4])
