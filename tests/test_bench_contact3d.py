"""The 3D contact bench's own measures (bench/bench_contact3d.py): the geometric penetration
check and the peers' starting state, which its ratios rest on."""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parent.parent


def bench():
    spec = importlib.util.spec_from_file_location("bench_contact3d", ROOT / "bench" / "bench_contact3d.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_corner_check_finds_the_lowest_corner_of_a_turned_box() -> None:
    b = bench()
    half = b.HALF
    # Resting flat, its bottom at y = 0.01: nothing below the plane.
    assert b.corners_below(np.array([[0.0, half + 0.01, 0.0]]), np.array([[1.0, 0.0, 0.0, 0.0]])) == 0.0
    # Turned 45 degrees about z: a corner edge reaches half * sqrt(2) below its centre.
    s = math.sin(math.pi / 8)
    q = np.array([[math.cos(math.pi / 8), 0.0, 0.0, s]])
    depth = b.corners_below(np.array([[0.0, half, 0.0]]), q)
    assert depth == pytest.approx(half * (math.sqrt(2) - 1), rel=1e-12)
    # Turned about x and z both: the deepest of its eight corners, from the rotation matrix.
    q = np.array([[0.9, 0.3, 0.1, 0.3]])
    q /= np.linalg.norm(q)
    w, x, y, z = q[0]
    r = np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )
    corners = np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)]) * half
    low = (corners @ r.T)[:, 1].min() + 0.05
    assert b.corners_below(np.array([[0.0, 0.05, 0.0]]), q) == pytest.approx(-low, rel=1e-12)


def test_mujoco_starts_from_physstep_s_state_with_its_spin_in_the_world_frame() -> None:
    pytest.importorskip("mujoco")
    import physstep

    b = bench()
    w = physstep.World.from_scene("dice", params={"n": 4})
    state = {
        "n": 4,
        "x": w.solid_positions()[1:],
        "q": w.solid_orientations()[1:],
        "v": w.solid_velocities()[1:],
        "w": w.solid_angular_velocities()[1:],
    }
    m = b.Mujoco(state)
    x, q = m.poses()
    np.testing.assert_allclose(x, state["x"], atol=1e-12)
    np.testing.assert_allclose(q, state["q"], atol=1e-12)
    # cvel is (angular, linear) in the world frame, the linear part about the world origin.
    np.testing.assert_allclose(m.data.cvel[1:, :3], state["w"], atol=1e-9)
    assert np.abs(state["w"]).max() > 1.0  # the dice spin: the check is not of zeros
