"""The tennis-racket free body against MuJoCo, in one process.

A free body with principal inertia 1 : 2 : 3 (mass 12, no gravity), spun at 2 rad/s about
its intermediate axis with a 0.01 rad/s wobble about the others, stepped 144,000 times at
dt = 1/120 (1200 s). physstep's default (symplectic Euler; the momentum form with the
splitting rule) and two of its methods, against MuJoCo's Euler and RK4 integrators on the
same body. Each engine steps in one call of its own loop (physstep ``World.step(n)``,
MuJoCo ``mj_step(..., nstep=n)``), median of repeats; the energy and ``|L|`` errors are
read at the end and every 1200 steps. Nothing here is asserted: it prints what it measured.

    python bench/bench_racket.py [--quick]

MuJoCo comes with the ``bench`` extra: ``pip install -e '.[bench]'``.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
import physstep

DT = 1.0 / 120.0
MASS = 12.0
OMEGA0 = np.array([0.01, 2.0, 0.01])  # body frame, rad/s
HALF = (2**0.5 * 0.5, 0.5, 0.0025)  # a thin plate: moments (1, 2, 3) to 3e-5


def physstep_world(method: str) -> physstep.World:
    """The racket in physstep: the box whose principal axes are its own."""
    w = physstep.World(3, method=method, dt=DT)
    w.add_body(physstep.Box(*HALF), mass=MASS, angular_velocity=tuple(OMEGA0))
    return w


def moments() -> np.ndarray:
    """The racket's principal moments, as physstep computes them (MuJoCo gets the same)."""
    return physstep.Box(*HALF).mass_properties(mass=MASS).principal_moments


def invariants(omega_body: np.ndarray, inertia: np.ndarray) -> tuple[float, float]:
    """Rotational energy and |L| from the body-frame angular velocity."""
    lb = inertia * omega_body
    return 0.5 * float(omega_body @ lb), float(np.linalg.norm(lb))


def run_physstep(method: str, steps: int, repeats: int) -> dict[str, float]:
    """Time per step (one call), then the errors along a second identical run."""
    times = []
    for _ in range(repeats):
        w = physstep_world(method)
        t0 = time.perf_counter_ns()
        w.step(steps)
        times.append((time.perf_counter_ns() - t0) / steps)
    w = physstep_world(method)
    e0, l0 = w.energy(), float(np.linalg.norm(w.angular_momentum()))
    max_de = 0.0
    chunk = max(steps // 120, 1)
    for _ in range(steps // chunk):
        w.step(chunk)
        max_de = max(max_de, abs(w.energy() - e0) / e0)
    e, lnorm = w.energy(), float(np.linalg.norm(w.angular_momentum()))
    return {
        "ns": statistics.median(times),
        "e0": e0,
        "l0": l0,
        "de": abs(e - e0) / e0,
        "dl": abs(lnorm - l0) / l0,
        "max_de": max_de,
        "diverged": float("nan"),
    }


def mujoco_model(integrator: str):  # noqa: ANN201 - mujoco is optional
    """The racket in MuJoCo: a free joint, the same mass and principal moments."""
    import mujoco

    i = moments()
    diag = " ".join(repr(float(c)) for c in i)
    xml = f"""
    <mujoco>
      <option timestep="{DT!r}" gravity="0 0 0" integrator="{integrator}"/>
      <worldbody>
        <body name="racket">
          <freejoint/>
          <inertial pos="0 0 0" mass="{MASS!r}" diaginertia="{diag}"/>
        </body>
      </worldbody>
    </mujoco>"""
    return mujoco.MjModel.from_xml_string(xml)


def run_mujoco(integrator: str, steps: int, repeats: int) -> dict[str, float]:
    """MuJoCo's free joint: qvel[3:6] is the angular velocity in the body's frame."""
    import mujoco

    m = mujoco_model(integrator)
    inertia = moments()

    def fresh():  # noqa: ANN202
        d = mujoco.MjData(m)
        d.qvel[3:6] = OMEGA0
        return d

    times = []
    for _ in range(repeats):
        d = fresh()
        t0 = time.perf_counter_ns()
        mujoco.mj_step(m, d, nstep=steps)
        times.append((time.perf_counter_ns() - t0) / steps)
    d = fresh()
    e0, l0 = invariants(np.array(d.qvel[3:6]), inertia)
    max_de, diverged = 0.0, float("nan")
    chunk = max(steps // 120, 1)
    for k in range(steps // chunk):
        mujoco.mj_step(m, d, nstep=chunk)
        w = np.array(d.qvel[3:6])
        # MuJoCo resets an unstable simulation (a warning, time back to 0) rather than stop.
        unstable = d.warning[mujoco.mjtWarning.mjWARN_BADQACC].number > 0
        if unstable or not np.all(np.isfinite(w)) or np.linalg.norm(w) > 1e6 * np.linalg.norm(OMEGA0):
            diverged = (k + 1) * chunk * DT
            break
        max_de = max(max_de, abs(invariants(w, inertia)[0] - e0) / e0)
    e, lnorm = invariants(np.array(d.qvel[3:6]), inertia)
    return {
        "ns": statistics.median(times),
        "e0": e0,
        "l0": l0,
        "de": abs(e - e0) / e0 if np.isnan(diverged) else float("inf"),
        "dl": abs(lnorm - l0) / l0 if np.isnan(diverged) else float("inf"),
        "max_de": max_de,
        "diverged": diverged,
    }


def main() -> None:
    """Measures, checks the engines computed the same body, prints the table."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="1,200 steps, one repeat (a smoke run)")
    args = ap.parse_args()
    steps, repeats = (1200, 1) if args.quick else (144_000, 5)
    rows: dict[str, dict[str, float]] = {}
    for method in ("symplectic-euler", "rk4", "yoshida4"):
        rows[f"physstep {method}"] = run_physstep(method, steps, repeats)
    try:
        import mujoco  # noqa: F401
    except ImportError:
        print("MuJoCo is not installed: pip install -e '.[bench]' to compare against it")
    else:
        for integrator in ("Euler", "RK4", "implicitfast"):
            rows[f"MuJoCo {integrator}"] = run_mujoco(integrator, steps, repeats)
    ref = rows["physstep symplectic-euler"]
    for name, r in rows.items():
        same_e = abs(r["e0"] - ref["e0"]) / ref["e0"]
        same_l = abs(r["l0"] - ref["l0"]) / ref["l0"]
        if max(same_e, same_l) > 1e-4:
            print(f"warning: {name} starts from another body (E0 {r['e0']:.6g}, |L|0 {r['l0']:.6g})")
    print(
        f"racket: inertia {np.round(moments(), 6).tolist()}, omega0 {OMEGA0.tolist()} rad/s, "
        f"dt = 1/120, {steps} steps ({steps * DT:g} s); E0 = {ref['e0']:.6f} J, |L|0 = {ref['l0']:.6f}"
    )
    head = (
        f"{'engine':28} {'ns/step':>9} {'x default':>10} {'dE/E end':>10} {'max dE/E':>10} {'d|L|/|L|':>10}"
    )
    print(head)
    print("-" * len(head))
    for name, r in rows.items():
        end = (
            f"{r['de']:10.2e}"
            if np.isnan(r["diverged"])
            else f"{'div ' + format(r['diverged'], '.0f') + ' s':>10}"
        )
        print(
            f"{name:28} {r['ns']:9.1f} {r['ns'] / ref['ns']:10.2f} {end} {r['max_de']:10.2e} {r['dl']:10.2e}"
        )
    if "MuJoCo Euler" in rows:
        print(f"MuJoCo Euler time / physstep default time: {rows['MuJoCo Euler']['ns'] / ref['ns']:.2f}")


if __name__ == "__main__":
    main()
