"""Regenerates the figures of the README's lab section in docs/figures/.

python scripts/make_figures.py [--out docs/figures]
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import physstep
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


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "figures")
    out: Path = ap.parse_args().out
    out.mkdir(parents=True, exist_ok=True)

    # The notes' picture: three periods of the circular orbit at a coarse dt.
    until = 3 * 2 * math.pi
    runs = [physstep.simulate("orbit", m, 0.1, until, stop_on_diverge=True) for m in ORBIT_METHODS]
    plot.save(plot.orbit(runs), out / "orbit_paths.png")

    # Energy of the notes' spring (m = 10, k = 5, x0 = 20) at dt = 0.1 s.
    spring = [physstep.simulate("spring", m, 0.1, 40.0) for m in SPRING_METHODS]
    plot.save(plot.energy(spring), out / "spring_energy.png")

    # Phase portrait of the spring at a coarse dt = 0.25 s (omega dt = 0.18), two periods.
    coarse = [
        physstep.simulate("spring", m, 0.25, 17.75) for m in ("explicit-euler", "symplectic-euler", "rk4")
    ]
    plot.save(plot.phase(coarse), out / "spring_phase.png")

    # Work-precision on the spring and the orbit.
    dts = [0.4 / 2**i for i in range(8)]
    for scene, until_s in (("spring", 20.0), ("orbit", 2 * math.pi)):
        data = lab.sweep(scene, WP_METHODS, dts, until_s)
        plot.save(plot.work_precision(data, against="both"), out / f"work_precision_{scene}.png")

    for p in sorted(out.glob("*.png")):
        print(p.relative_to(ROOT) if p.is_relative_to(ROOT) else p)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
