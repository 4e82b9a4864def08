"""The position-based cloth: physstep's projection sweeps against a numba Jakobsen loop doing
the same arithmetic, measured side by side in one run.

    python bench/bench_cloth.py [--quick] [--size 32] [--sweeps 16] [--json FILE]

Both run the `cloth` scene (a W x W grid, structural and shear links, rigid, the top corners
pinned, gravity along -y) with velocityless Verlet at the scene's dt = 1/120 s and
`constraint_iterations` sweeps a step (Jakobsen 2001: Verlet, then Gauss-Seidel projection
of every link in the order added, the velocity the secant of the step). The numba loop is
the 20-line loop a game programmer writes, with physstep's order of operations, so its
positions and velocities are compared bit for bit with physstep's after the timed steps.

Printed: us per step of each, the best (min) of interleaved repeats (the machine may be
shared: the min is the least disturbed run), every repeat's ratio, and the ratio
physstep / numba of the bests (target: at most 1.0). Nothing is asserted.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
import physstep
from common import row, write_json
from numba import njit


@njit(cache=False)
def jakobsen(x, v, g, li, lj, rest, w, pin_i, pin_p, h, steps, sweeps):  # noqa: ANN001, ANN201
    """`steps` Verlet steps of `h` (restarted from x, v each step) each followed by `sweeps`
    Gauss-Seidel projections of the rigid links `li[c]`-`lj[c]` of length `rest[c]` (inverse
    masses `w`, 0 when pinned), the velocity then given the relaxation's motion over h."""
    n, m = x.shape[0], li.shape[0]
    h2, inv_h = h * h, 1.0 / h
    moved = np.empty_like(x)
    for _ in range(steps):
        for p in range(n):
            for k in range(3):
                nxt = 2.0 * x[p, k] - (x[p, k] - v[p, k] * h) + g[k] * h2
                v[p, k] = (nxt - x[p, k]) * inv_h
                x[p, k] = nxt
        moved[:] = x
        for q in range(pin_i.shape[0]):
            x[pin_i[q]] = pin_p[q]
        for _s in range(sweeps):
            for c in range(m):
                i, j = li[c], lj[c]
                d0, d1, d2 = x[i, 0] - x[j, 0], x[i, 1] - x[j, 1], x[i, 2] - x[j, 2]
                r = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
                wsum = w[i] + w[j]
                if wsum == 0.0 or r == 0.0:
                    continue
                s = (-(r - rest[c]) / wsum) / r
                x[i, 0] += w[i] * s * d0
                x[i, 1] += w[i] * s * d1
                x[i, 2] += w[i] * s * d2
                x[j, 0] -= w[j] * s * d0
                x[j, 1] -= w[j] * s * d1
                x[j, 2] -= w[j] * s * d2
        for p in range(n):
            for k in range(3):
                v[p, k] += (x[p, k] - moved[p, k]) * inv_h


def world(size: int, sweeps: int) -> physstep.World:
    w = physstep.World.from_scene("cloth", "verlet", params={"w": size, "h": size})
    w.constraint_iterations = sweeps
    return w


def peer_inputs(size: int, spacing: float = 0.1, mass: float = 0.01) -> tuple[np.ndarray, ...]:
    """The numba loop's arrays: the `cloth` scene's links in the order it adds them
    (structural across and down, then the two shear diagonals of each cell), rest lengths,
    inverse masses (0 at the pinned top corners) and the pins."""
    links: list[tuple[int, int, float]] = []
    diag = spacing * np.sqrt(2.0)
    for r in range(size):
        for c in range(size):
            here = r * size + c
            if c + 1 < size:
                links.append((here, here + 1, spacing))
            if r + 1 < size:
                links.append((here, here + size, spacing))
            if c + 1 < size and r + 1 < size:
                links.append((here, here + size + 1, diag))
                links.append((here + 1, here + size, diag))
    inv = np.full(size * size, 1.0 / mass)
    pin_i = np.array([0, size - 1], dtype=np.int64)
    pin_p = np.array([[0.0, 0.0, 0.0], [(size - 1) * spacing, 0.0, 0.0]])
    inv[pin_i] = 0.0
    li, lj, rest = (np.array(col) for col in zip(*links, strict=True))
    return li.astype(np.int64), lj.astype(np.int64), rest.astype(float), inv, pin_i, pin_p


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer steps and repeats")
    ap.add_argument("--size", type=int, default=32, help="particles across and down (default 32)")
    ap.add_argument("--sweeps", type=int, default=16, help="constraint_iterations (default 16)")
    ap.add_argument("--json", help="write the numbers to this file")
    a = ap.parse_args()
    steps, repeat = (30, 5) if a.quick else (30, 41)

    ours_w = world(a.size, a.sweeps)
    li, lj, rest, inv, pin_i, pin_p = peer_inputs(a.size)
    h = ours_w.dt
    g = np.array([0.0, -9.81, 0.0])
    x, v = np.array(ours_w.positions, dtype=float), np.array(ours_w.velocities, dtype=float)
    jakobsen(x.copy(), v.copy(), g, li, lj, rest, inv, pin_i, pin_p, h, 1, a.sweeps)  # compile

    ours_t, peer_t = [], []
    for _ in range(repeat):
        t0 = time.perf_counter()
        ours_w.step(steps)
        ours_t.append((time.perf_counter() - t0) / steps)
        t0 = time.perf_counter()
        jakobsen(x, v, g, li, lj, rest, inv, pin_i, pin_p, h, steps, a.sweeps)
        peer_t.append((time.perf_counter() - t0) / steps)
    dx = float(np.abs(np.asarray(ours_w.positions) - x).max())
    dv = float(np.abs(np.asarray(ours_w.velocities) - v).max())
    bitwise = bool(
        np.array_equal(np.asarray(ours_w.positions), x) and np.array_equal(np.asarray(ours_w.velocities), v)
    )
    sweeps_taken = ours_w.constraint_stats["last_sweeps"]

    ours, peer = min(ours_t) * 1e6, min(peer_t) * 1e6
    print(
        f"cloth {a.size} x {a.size}: {len(li)} rigid links, {a.sweeps} sweeps (the last step took "
        f"{sweeps_taken}), Verlet dt = 1/120, {steps} steps x {repeat} interleaved repeats, best of each"
    )
    row("numba Jakobsen loop", peer, "us/step")
    row("physstep World.step (verlet, projection)", ours, "us/step", peer, "numba (target <= 1.0)")
    each = [o / p for o, p in zip(ours_t, peer_t, strict=True)]
    spread = f"median {statistics.median(each):.2f}, {min(each):.2f} to {max(each):.2f}"
    print(f"{'':<44} each repeat's ratio: {spread}")
    print(f"{'':<44} after {steps * repeat} steps: |dx| {dx:.3g} m, |dv| {dv:.3g} m/s, bitwise {bitwise}")
    write_json(
        a.json,
        {
            "size": a.size,
            "sweeps": a.sweeps,
            "physstep_us": ours,
            "numba_us": peer,
            "ratio": ours / peer,
            "ratios": each,
            "bitwise": bitwise,
        },
    )


if __name__ == "__main__":
    main()
