"""The extension's allocator (`physstep::alloc::HugePages`): blocks of 1 MiB and more (a long
recording's columns, a large world's state) are mapped on their own and advised to use huge
pages, and freed blocks are kept for reuse; what is handed out is never memory still in use."""

from __future__ import annotations

import sys

import numpy as np
import physstep
import pytest

STEPS = 144_000  # a column of 144,001 doubles: 1.1 MiB
DT = 1 / 120


def _spring(method: str = "symplectic-euler") -> physstep.Trajectory:
    return physstep.simulate("spring", method, dt=DT, until=STEPS * DT)


def _vm_flags(address: int) -> list[str]:
    """The kernel's flags of the mapping that holds `address` (this process's smaps)."""
    with open("/proc/self/smaps") as f:
        inside = False
        for line in f:
            head = line.split()[0]
            if "-" in head and ":" not in head:
                lo, hi = (int(v, 16) for v in head.split("-"))
                inside = lo <= address < hi
            elif inside and line.startswith("VmFlags:"):
                return line.split()[1:]
    raise AssertionError(f"no mapping holds {address:#x}")


@pytest.mark.skipif(sys.platform != "linux", reason="huge pages are asked for on Linux only")
def test_a_long_recordings_columns_lie_in_memory_advised_for_huge_pages() -> None:
    tr = _spring()
    for name in ("t", "x", "v", "energy"):
        column = np.asarray(getattr(tr, name))
        assert column.nbytes >= 1 << 20
        # `hg`: the mapping was given MADV_HUGEPAGE (the system allocator's heap is not).
        assert "hg" in _vm_flags(column.ctypes.data), name


@pytest.mark.skipif(sys.platform != "linux", reason="huge pages are asked for on Linux only")
def test_a_large_worlds_state_lies_in_memory_advised_for_huge_pages() -> None:
    w = physstep.World(3, method="symplectic-euler", dt=DT)
    w.add_particles(np.zeros((100_000, 3)))  # 2.4 MB of positions
    assert "hg" in _vm_flags(w.positions.ctypes.data)
    # (No claim about small blocks: they are the system allocator's, on its heap, where numpy
    # itself advises huge pages for its arrays of 4 MiB and more, so a small block may lie in
    # a stretch of the heap numpy advised.)


def test_recordings_made_while_others_live_never_share_their_memory() -> None:
    first = _spring()
    kept = {k: np.array(getattr(first, k)) for k in ("t", "x", "v", "a", "energy")}
    # Another method's run while the first is alive, then the first freed and run again: the
    # second's columns are the first's freed blocks.
    other = _spring("velocity-verlet")
    for k, values in kept.items():
        np.testing.assert_array_equal(getattr(first, k), values, err_msg=k)
    assert not np.array_equal(other.x, first.x)
    del first
    again = _spring()
    for k, values in kept.items():
        np.testing.assert_array_equal(getattr(again, k), values, err_msg=k)
    assert not np.array_equal(other.x, again.x)


def test_a_world_grown_past_a_mebibyte_and_cut_back_keeps_its_particles() -> None:
    rng = np.random.default_rng(5)
    w = physstep.World(3, method="symplectic-euler", dt=DT)
    batches = [rng.random((k, 3)) for k in (10, 1_000, 50_000, 60_000)]
    handles = [w.add_particles(b) for b in batches]
    np.testing.assert_array_equal(w.positions, np.concatenate(batches))
    # Removing the two large batches takes the state back below the threshold.
    w.remove(handles[3])
    w.remove(handles[2])
    np.testing.assert_array_equal(w.positions, np.concatenate(batches[:2]))
    w.add_gravity([0.0, -9.81, 0.0])
    w.step(3)
    x = np.concatenate(batches[:2])
    v = np.zeros_like(x)
    for _ in range(3):
        v[:, 1] += DT * -9.81
        x += DT * v
    np.testing.assert_allclose(w.positions, x, rtol=0, atol=1e-12)
