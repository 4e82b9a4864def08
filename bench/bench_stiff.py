"""Stiff spring networks under the implicit methods: ms per step against the size, with the
Newton and conjugate-gradient iteration counts of every row.

    python bench/bench_stiff.py [--quick]

The `stiff-chain` scene (k = 1e5 N/m, 10 g particles: k / m dt^2 = 2800 at dt = 1/60 s,
where symplectic Euler diverges within 30 steps) under backward Euler for 60 steps (1 s)
from rest at each size, with the sparse solve (3 x 3 blocks, conjugate gradients
preconditioned by the complete sparse Cholesky factor, the default, by block incomplete
Cholesky and by block Jacobi) and, where it fits, the dense LU. Printed: ms per step, Newton
updates and CG iterations per step, and the ratios measured in the same run.

Then `linearly-implicit-euler` on the `stiff-cloth` (k = 1e5 N/m, dt = 1/60 s; 32 x 32 and
100 x 100) with the complete factor and with incomplete Cholesky, beside a scipy.sparse
direct solve (SuperLU) of the same linear system, assembled from the same state with the
same semidefinite spring blocks (scipy is a bench-only extra: `pip install -e .[bench]`;
its rows are skipped without it), and backward Euler on the 32 x 32 cloth's first steps
with both.

Then the memory of the sparse solve on `stiff-cloth` grids up to 100 x 100 (10,000
particles, 60,000 unknowns, whose dense Jacobian would take 28.8 GB): each size in a fresh
process, the peak resident memory while backward Euler takes its first steps less the
resident memory of the built world, per particle. Nothing is asserted.
"""

from __future__ import annotations

import argparse
import os
import time

# numpy's OpenBLAS threads, woken by the bench's own numpy work, spin in this process and take
# a core from the factorisation's second thread (docs/stiff.md): one BLAS thread, unless set.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402
import physstep
from common import in_subprocess, row

STEPS = 60


def run(n: int, dense: bool, preconditioner: str = "cholesky") -> tuple[float, float, float]:
    """ms/step, Newton updates/step, CG iterations/step of `n` moving links."""
    w = physstep.World.from_scene("stiff-chain", "backward-euler", params={"n": n})
    w.set_implicit(dense_up_to=10**9 if dense else 0, cg_max_iter=100_000, preconditioner=preconditioner)
    return steps(w, STEPS)


def steps(w: physstep.World, count: int) -> tuple[float, float, float]:
    """Steps `w` `count` times: ms/step, Newton updates/step, CG iterations/step."""
    newton = cg = 0
    t0 = time.perf_counter()
    for _ in range(count):
        w.step(1)
        s = w.solve_stats
        newton += s["newton"]
        cg += s["cg"]
    return (time.perf_counter() - t0) / count * 1e3, newton / count, cg / count


def cloth_springs(n: int, k: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The `stiff-cloth` scene's springs (as crates/physstep/src/scenes/stiff.rs builds
    them): `(i, j, rest)` arrays, structural then shear, and `k`."""
    sp = 1.0 / (n - 1)
    ii, jj, rest = [], [], []
    for r in range(n):
        for c in range(n):
            here = r * n + c
            if c + 1 < n:
                ii.append(here), jj.append(here + 1), rest.append(sp)
            if r + 1 < n:
                ii.append(here), jj.append(here + n), rest.append(sp)
            if r + 1 < n and c + 1 < n:
                ii.append(here), jj.append(here + n + 1), rest.append(sp * np.sqrt(2))
                ii.append(here + 1), jj.append(here + n), rest.append(sp * np.sqrt(2))
    return np.array(ii), np.array(jj), np.array(rest)


class ScipyStep:
    """The linearly implicit Euler step of `stiff-cloth` by scipy.sparse: the system
    `(M - dt^2 K) dv = dt (F + dt K v)` assembled with physstep's spring blocks (a compressed
    spring's sideways term left out: `-k ((1 - r0/r) I + r0/r u u^T)`, `r0/r` at most 1),
    the pinned corners' rows left out, solved by SuperLU (`spsolve`)."""

    def __init__(self, n: int, k: float = 1e5, m: float = 0.01, g: float = 9.81) -> None:
        self.i, self.j, self.rest = cloth_springs(n, k)
        self.n, self.k, self.m, self.g = n * n, k, m, g
        pinned = np.zeros(n * n, bool)
        pinned[[(n - 1) * n, n * n - 1]] = True
        self.free = np.repeat(~pinned, 3)
        self.solve_s = 0.0

    def step(self, x: np.ndarray, v: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
        import scipy.sparse as sp
        import scipy.sparse.linalg as spla

        d = x[self.i] - x[self.j]
        r = np.linalg.norm(d, axis=1)
        u = d / r[:, None]
        ratio = np.minimum(self.rest / r, 1.0)
        # F on i: -k (r - rest) u; blocks B = dF_i/dx_i.
        f = np.zeros_like(x)
        fs = -self.k * (r - self.rest)[:, None] * u
        np.add.at(f, self.i, fs)
        np.add.at(f, self.j, -fs)
        f[:, 2] -= self.m * self.g
        eye = np.eye(3)
        uu = u[:, :, None] * u[:, None, :]
        b = -self.k * ((1 - ratio)[:, None, None] * eye + ratio[:, None, None] * uu)
        # K as a sparse 3n x 3n matrix: [[B, -B], [-B, B]] per spring.
        rows, cols, vals = [], [], []
        ar = np.arange(3)
        ends = ((self.i, self.i, 1.0), (self.j, self.j, 1.0), (self.i, self.j, -1.0), (self.j, self.i, -1.0))
        for p, q, s in ends:
            rows.append((3 * p[:, None, None] + ar[None, :, None]).repeat(3, axis=2).ravel())
            cols.append((3 * q[:, None, None] + ar[None, None, :]).repeat(3, axis=1).ravel())
            vals.append((s * b).ravel())
        size = 3 * self.n
        entries = (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols)))
        kmat = sp.csr_matrix(entries, (size, size))
        free = self.free
        a = (sp.identity(size, format="csr") * self.m - dt * dt * kmat)[free][:, free]
        rhs = (dt * (f.ravel() + dt * (kmat @ v.ravel())))[free]
        t0 = time.perf_counter()
        dv_free = spla.spsolve(a.tocsc(), rhs)
        self.solve_s += time.perf_counter() - t0
        dv = np.zeros(size)
        dv[free] = dv_free
        v_new = v + dv.reshape(-1, 3)
        return x + dt * v_new, v_new


def cloth_lie(n: int, count: int) -> None:
    """`linearly-implicit-euler` on the n x n stiff cloth: physstep's ms/step with its counts
    (the complete Cholesky factor, the default, and incomplete Cholesky), beside scipy's
    direct solve of the same system (`count` steps after the first, from the same state)."""
    w = physstep.World.from_scene("stiff-cloth", "linearly-implicit-euler", params={"n": n})
    dt = w.dt
    # The first step apart: it orders the factor (once while the springs stay the same).
    first = steps(w, 1)[0]
    x0, v0 = w.positions.copy(), w.velocities.copy()
    ms, newton, cg = steps(w, count)
    label = f"{n} x {n} linearly-implicit-euler ({newton:.2f} solves, {cg:.2f} CG / step)"
    row(label, ms, "ms/step")
    print(f"{'':44} (after a first step of {first:.0f} ms, which orders the factor)")
    w = physstep.World.from_scene("stiff-cloth", "linearly-implicit-euler", params={"n": n})
    w.set_implicit(preconditioner="incomplete-cholesky")
    steps(w, 1)
    ms_ic, _, cg_ic = steps(w, count)
    row(f"{'':4}incomplete Cholesky ({cg_ic:.0f} CG / step)", ms_ic, "ms/step", ms, "physstep")
    try:
        import scipy  # noqa: F401
    except ImportError:
        print(f"{'':44} scipy.sparse: skipped (pip install -e .[bench])")
        return
    ref = ScipyStep(n)
    x, v = x0, v0
    t0 = time.perf_counter()
    for _ in range(count):
        x, v = ref.step(x, v, dt)
    sms = (time.perf_counter() - t0) / count * 1e3
    row(f"{'':4}scipy.sparse, the same system (SuperLU)", sms, "ms/step", ms, "physstep")
    row(f"{'':4}scipy.sparse, its solves alone", ref.solve_s / count * 1e3, "ms/step", ms, "physstep")
    # One step from the same state (scipy's last, mid-fall): the two agree to the CG
    # tolerance (1e-10 relative), which says the system is the same.
    w2 = physstep.World.from_scene("stiff-cloth", "linearly-implicit-euler", params={"n": n})
    w2.positions, w2.velocities = x, v
    w2.step(1)
    x1, v1 = ScipyStep(n).step(x, v, dt)
    gap = float(np.abs(w2.velocities - v1).max() / np.abs(v1 - v).max())
    print(f"{'':44} one step from step {count}'s state: dv {gap:.1e} apart (relative)")


# Peak resident memory (VmHWM) less resident memory (VmRSS) once the world is built: what
# the steps allocated. Linux's /proc; the bench prints nothing for this part elsewhere.
MEMORY = """
import json, time, physstep
def status(key):
    with open('/proc/self/status') as f:
        return next(int(l.split()[1]) * 1024 for l in f if l.startswith(key + ':'))
w = physstep.World.from_scene('stiff-cloth', 'backward-euler', params={{'n': {n}}})
w.set_implicit(dense_up_to=0, cg_max_iter=100_000)
base = status('VmRSS')
t0 = time.perf_counter()
w.step({steps})
ms = (time.perf_counter() - t0) / {steps} * 1e3
print(json.dumps({{'bytes': status('VmHWM') - base, 'ms': ms, 'cg': w.solve_stats['cg'],
                  'newton': w.solve_stats['newton']}}))
"""


def memory(sizes: list[int], steps: int) -> None:
    """Prints the memory the first `steps` backward-Euler steps of each cloth size took."""
    try:
        open("/proc/self/status").close()
    except OSError:
        print("(memory: /proc/self/status not available here)")
        return
    print(f"stiff-cloth, backward Euler, sparse solve: memory of the first {steps} steps")
    for n in sizes:
        r = in_subprocess(MEMORY.format(n=n, steps=steps), threads=1)
        particles, unknowns = n * n, 6 * n * n
        dense_gb = unknowns**2 * 8 / 1e9
        label = f"{n:3d} x {n:<3d} ({particles} particles)"
        row(label, r["bytes"] / particles, "bytes/particle")
        print(
            f"{'':44} {r['bytes'] / 1e6:10.1f} MB in all, {r['ms']:.0f} ms/step "
            f"({r['newton']} Newton, {r['cg']} CG the last step); dense Jacobian {dense_gb:.3g} GB"
        )


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="smaller sizes")
    a = p.parse_args()
    sizes = [10, 40, 100] if a.quick else [10, 40, 100, 400, 1000, 2000]
    print(f"stiff-chain, backward Euler, dt = 1/60 s, {STEPS} steps from rest")
    for n in sizes:
        ms, newton, cg = run(n, dense=False)
        label = f"n = {n:5d} Cholesky ({newton:.1f} Newton, {cg:.1f} CG / step)"
        if 4 * (n + 1) <= 1024:
            ms_dense, _, _ = run(n, dense=True)
            row(label, ms, "ms/step", ms_dense, "dense")
        else:
            row(label, ms, "ms/step")
        for name, pre in (("IC", "incomplete-cholesky"), ("block Jacobi", "block-jacobi")):
            ms_p, newton_p, cg_p = run(n, dense=False, preconditioner=pre)
            label = f"{'':8} {name} ({newton_p:.1f} Newton, {cg_p:.0f} CG / step)"
            row(label, ms_p, "ms/step", ms, "Cholesky")
    print("stiff-cloth, k = 1e5 N/m, dt = 1/60 s, from rest")
    cloth_lie(32, 60 if a.quick else 300)
    cloth_lie(100, 5 if a.quick else 20)
    w = physstep.World.from_scene("stiff-cloth", "backward-euler", params={"n": 32})
    ms, newton, cg = steps(w, 10 if a.quick else 90)
    row(f"32 x 32 backward-euler ({newton:.1f} Newton, {cg:.0f} CG / step)", ms, "ms/step")
    w = physstep.World.from_scene("stiff-cloth", "backward-euler", params={"n": 32})
    w.set_implicit(preconditioner="incomplete-cholesky")
    ms_ic, newton_ic, cg_ic = steps(w, 10 if a.quick else 90)
    label = f"{'':4}incomplete Cholesky ({newton_ic:.1f} Newton, {cg_ic:.0f} CG / step)"
    row(label, ms_ic, "ms/step", ms, "Cholesky")
    memory([25, 50] if a.quick else [25, 50, 100], steps=2)


if __name__ == "__main__":
    main()
