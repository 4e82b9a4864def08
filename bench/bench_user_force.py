"""The cost of a force written in Python, per evaluation, beside the built-in force and
beside the same numpy expression timed alone.

Gravity plus linear drag on n particles (3D, symplectic Euler, one evaluation per step):
once as the built-in forces, once as a Python callable computing the same physics with
numpy, returned (`f(t, x, v) -> G - C * v`) or written in place (`add_force(f,
inplace=True)`, `f(t, x, v, out)`), and once as the bare numpy expression on an (n, 3)
array. The Python force's own cost is a step with it minus a step of the same world with no
force at all; at 1e5 it is split into the numpy expression timed inside the step (by a force
that times itself) and the rest (physstep's passes for the force, and the call). All are
measured in the same run, in rounds: each round times every world and then the numpy
expressions alone, and a ratio is taken within a round (the printed ratio is the median over
the rounds, the times are medians too); nothing is asserted.

Issue 22's targets, printed as ratios: at 1e5 particles the Python force costs at most 1.3x
the numpy expression alone; at n = 1, at most 2 us per evaluation.

    python bench/bench_user_force.py [--quick]
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable

import numpy as np
import physstep

G = np.array([0.0, -9.81, 0.0])
C = 0.1


def returned(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Unit masses: F = m g - c v, a new array."""
    return G - C * v


def inplace(t: float, x: np.ndarray, v: np.ndarray, out: np.ndarray) -> None:
    """The same force written into `out`."""
    np.multiply(v, -C, out=out)
    out += G


class Timed:
    """`inplace`, timing its own numpy expression: how long the same expression takes inside
    a step (the arrays as the step leaves them) against alone."""

    def __init__(self) -> None:
        self.seconds = 0.0
        self.calls = 0

    def __call__(self, t: float, x: np.ndarray, v: np.ndarray, out: np.ndarray) -> None:
        t0 = time.perf_counter()
        inplace(t, x, v, out)
        self.seconds += time.perf_counter() - t0
        self.calls += 1


def world(n: int, kind: str, timed: Timed | None = None) -> physstep.World:
    """n particles under gravity and drag: built-in, a Python force (`timed` for the in-place
    one when given), or no force."""
    w = physstep.World(3, method="symplectic-euler", dt=1 / 120)
    w.add_particles(np.random.default_rng(0).random((n, 3)))
    if kind == "returned":
        w.add_force(returned)
    elif kind == "inplace":
        w.add_force(timed if timed is not None else inplace, inplace=True)
    elif kind == "built-in":
        w.add_gravity(G.tolist())
        w.add_drag(linear=C)
    return w


def rounds(n: int, steps: int, repeat: int) -> list[dict[str, float]]:
    """`repeat` rounds, each timing every kind of world (seconds per step, one force evaluation
    each) and then the numpy expressions alone (seconds per call) on arrays of the same shape:
    a round's figures are taken within moments of each other, so on a loaded machine they see
    the same load, and a ratio is taken within a round."""
    v = np.random.default_rng(1).random((n, 3))
    out = np.empty_like(v)
    bare: dict[str, Callable[[], object]] = {
        "np returned": lambda: G - C * v,
        "np inplace": lambda: inplace(0.0, v, v, out),
    }
    got = []
    for _ in range(repeat):
        row = {}
        for kind in ("built-in", "none", "returned", "inplace", "inplace timed"):
            timed = Timed() if kind == "inplace timed" else None
            w = world(n, kind.split()[0], timed)
            w.step(1)
            if timed is not None:
                timed.seconds, timed.calls = 0.0, 0
            t0 = time.perf_counter()
            w.step(steps)
            row[kind] = (time.perf_counter() - t0) / steps
            if timed is not None:
                row["np inside"] = timed.seconds / max(timed.calls, 1)
        for name, fn in bare.items():
            fn()
            t0 = time.perf_counter()
            for _ in range(steps):
                fn()
            row[name] = (time.perf_counter() - t0) / steps
        got.append(row)
    return got


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="fewer steps and repeats")
    args = p.parse_args()
    repeat = 3 if args.quick else 7
    # Same physics, same bits? The first steps must agree to rounding.
    ref = world(1000, "built-in")
    ref.step(10)
    for kind in ("returned", "inplace"):
        b = world(1000, kind)
        b.step(10)
        gap = float(np.abs(ref.positions - b.positions).max())
        print(f"built-in vs Python force ({kind}) after 10 steps, 1000 particles: max |dx| = {gap:.1e} m")
    print(
        f"{'particles':>10} {'built-in':>11} {'no force':>11} {'returned':>11} {'inplace':>11}"
        f" {'numpy alone':>12} {'returned/np':>12} {'inplace/np':>11}"
        f"   (us per evaluation, medians of {repeat} rounds; the ratios round by round)"
    )
    for n in (1, 1_000, 100_000):
        steps = max(20, (200 if args.quick else 2000) // max(1, n // 1000))
        got = rounds(n, steps, repeat)
        t = {k: statistics.median(r[k] for r in got) for k in got[0]}
        # The force's own cost over the numpy expression, round by round.
        forms = ("returned", "inplace")
        ratio = {form: sorted((r[form] - r["none"]) / r[f"np {form}"] for r in got) for form in forms}
        mid = {form: statistics.median(q) for form, q in ratio.items()}
        own_ret, own_in = t["returned"] - t["none"], t["inplace"] - t["none"]
        print(
            f"{n:>10} {t['built-in'] * 1e6:>11.2f} {t['none'] * 1e6:>11.2f} {t['returned'] * 1e6:>11.2f}"
            f" {t['inplace'] * 1e6:>11.2f} {t['np returned'] * 1e6:>12.2f} {mid['returned']:>11.2f}x"
            f" {mid['inplace']:>10.2f}x"
        )
        if n == 1:
            print(
                f"{'':>10} target at n = 1: at most 2 us per evaluation: returned {own_ret * 1e6:.2f} us,"
                f" inplace {own_in * 1e6:.2f} us (the force's own cost; a whole step"
                f" {t['returned'] * 1e6:.2f} / {t['inplace'] * 1e6:.2f} us)"
            )
        if n == 100_000:
            # Where the in-place force's own cost goes: its numpy expression timed inside the
            # step (a world of its own, the same force timing itself), and the rest, physstep's.
            inside = statistics.median(r["np inside"] / r["np inplace"] for r in got)
            rest = statistics.median(r["inplace timed"] - r["none"] - r["np inside"] for r in got)
            print(
                f"{'':>10} in place, its numpy expression inside a step: {inside:.2f}x its time alone;"
                f" the rest of its own cost (physstep's passes for it, the call): {rest * 1e6:.0f} us"
                f" = {rest / t['np inplace']:.2f}x the expression alone"
            )
            spread = {form: f"{q[0]:.2f}-{q[-1]:.2f}x" for form, q in ratio.items()}
            print(
                f"{'':>10} target at 1e5: at most 1.3x the numpy expression alone: returned"
                f" {mid['returned']:.2f}x (rounds {spread['returned']};"
                f" numpy {t['np returned'] * 1e6:.0f} us),"
                f" inplace {mid['inplace']:.2f}x (rounds {spread['inplace']}; numpy in place"
                f" {t['np inplace'] * 1e6:.0f} us)"
            )


if __name__ == "__main__":
    main()
