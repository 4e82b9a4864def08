"""The world as it was: ``restore`` takes any bytes-like snapshot and refuses a damaged one
leaving the world unchanged; a step that diverges leaves the state hash unchanged."""

from __future__ import annotations

import physstep
import pytest


def test_restore_takes_bytes_like_and_refuses_damage_leaving_the_world_unchanged() -> None:
    w = physstep.World.from_scene("kepler", "leapfrog", 0.01)
    w.step(10)
    snap = w.snapshot()
    w.step(5)
    h = w.state_hash()
    w.restore(bytearray(snap))
    w.restore(memoryview(snap))
    w.step(5)
    assert w.state_hash() == h
    bad = bytearray(snap)
    bad[70] ^= 0xFF
    with pytest.raises(ValueError, match="corrupt snapshot: checksum mismatch"):
        w.restore(bytes(bad))
    assert w.state_hash() == h


@pytest.mark.parametrize("method", ["verlet", "leapfrog"])
def test_a_diverged_step_leaves_the_state_hash_unchanged(method: str) -> None:
    w = physstep.World.from_scene("spring", method, 1.0, params={"k": 1e12, "m": 1.0})
    for _ in range(200):
        h = w.state_hash()
        try:
            w.step()
        except physstep.DivergedError:
            assert w.state_hash() == h
            return
    pytest.fail("no divergence")
