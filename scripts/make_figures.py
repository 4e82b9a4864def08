"""Regenerates the figures of the README's lab section in docs/figures/.

python scripts/make_figures.py [--out docs/figures] [NAME ...]

With names (e.g. ``lorenz``), only those figures; the work-precision figures time the runs,
so regenerating them changes their time panels.
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable
from pathlib import Path

import physstep
from matplotlib.figure import Figure
from physstep import lab, plot

ROOT = Path(__file__).resolve().parent.parent
ORBIT_METHODS = ("explicit-euler", "backward-euler", "symplectic-euler", "rk4")
SPRING_METHODS = ("explicit-euler", "symplectic-euler", "velocity-verlet", "rk4", "backward-euler")
WP_METHODS = (
    "explicit-euler",
    "symplectic-euler",
    "velocity-verlet",
    "midpoint",
    "rk4",
    "yoshida4",
    "implicit-midpoint",
)


def orbit_paths() -> Figure:
    """The notes' picture: three periods of the circular orbit at a coarse dt."""
    until = 3 * 2 * math.pi
    runs = [physstep.simulate("orbit", m, 0.1, until, stop_on_diverge=True) for m in ORBIT_METHODS]
    return plot.orbit(runs)


def spring_energy() -> Figure:
    """Energy of the notes' spring (m = 10, k = 5, x0 = 20) at dt = 0.1 s."""
    return plot.energy([physstep.simulate("spring", m, 0.1, 40.0) for m in SPRING_METHODS])


def spring_phase() -> Figure:
    """Phase portrait of the spring at a coarse dt = 0.25 s (omega dt = 0.18), two periods."""
    methods = ("explicit-euler", "symplectic-euler", "rk4")
    return plot.phase([physstep.simulate("spring", m, 0.25, 17.75) for m in methods])


def work_precision(scene: str, until: float) -> Callable[[], Figure]:
    """Work-precision on ``scene`` up to ``until``: eight halvings of dt from 0.4 s."""

    def make() -> Figure:
        data = lab.sweep(scene, WP_METHODS, [0.4 / 2**i for i in range(8)], until)
        return plot.work_precision(data, against="both")

    return make


def lorenz() -> Figure:
    """The Lorenz attractor, a first-order flow: 40 s of RK4 at dt = 0.005 s from (1, 1, 1)."""
    return plot.path3d(physstep.simulate("lorenz", "rk4", 0.005, 40.0))


def racket() -> Figure:
    """The tennis-racket flip for 1200 s at dt = 1/120 under symplectic Euler, twice: the
    default (momentum form, splitting rule) keeps flipping at the exact period with its energy
    error bounded and ``|L|`` exact; the notes' quaternion update (``orientation_rule =
    "quaternion"``) pumps energy in until the body spins about its smallest moment and the
    flips die out. The runs are systems (callables returning the configured World)."""

    def body(rule: str, name: str) -> Callable[[], physstep.World]:
        def make() -> physstep.World:
            w = physstep.World.from_scene("racket", "symplectic-euler", 1 / 120)
            w.angular_form = "momentum"
            w.orientation_rule = rule
            return w

        make.__name__ = name
        return make

    runs = [
        physstep.simulate(body(rule, name), until=1200.0, every=6)
        for rule, name in (
            ("splitting", "racket with the default splitting rule"),
            ("quaternion", "racket with the notes' quaternion rule"),
        )
    ]
    return plot.spin(runs)


#: Every figure by its file name (without .png).
FIGURES: dict[str, Callable[[], Figure]] = {
    "orbit_paths": orbit_paths,
    "spring_energy": spring_energy,
    "spring_phase": spring_phase,
    "work_precision_spring": work_precision("spring", 20.0),
    "work_precision_orbit": work_precision("orbit", 2 * math.pi),
    "lorenz": lorenz,
    "racket": racket,
}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "figures")
    ap.add_argument(
        "names", nargs="*", metavar="NAME", help=f"figures to make: {', '.join(FIGURES)} (default: all)"
    )
    args = ap.parse_args()
    unknown = [n for n in args.names if n not in FIGURES]
    if unknown:
        ap.error(f"unknown figure '{unknown[0]}'; valid: {', '.join(FIGURES)}")
    out: Path = args.out
    out.mkdir(parents=True, exist_ok=True)
    for name in args.names or FIGURES:
        path = plot.save(FIGURES[name](), out / f"{name}.png")
        print(path.relative_to(ROOT) if path.is_relative_to(ROOT) else path)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
