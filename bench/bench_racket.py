"""The tennis-racket free body against MuJoCo, in one process.

A free body with principal inertia 1 : 2 : 3 (mass 12, no gravity), spun at 2 rad/s about
its intermediate axis with a 0.01 rad/s wobble about the others, stepped 144,000 times at
dt = 1/120 (1200 s). physstep's default (symplectic Euler; the momentum form with the
splitting rule) and two of its methods, against MuJoCo's Euler, RK4 and implicitfast
integrators on the same body. Each engine steps in one call of its own loop (physstep
``World.step(n)``, MuJoCo ``mj_step(m, d, nstep=n)``), median of repeats, fresh state each
time; the errors at 1200 s are read from the timed run, the largest energy error from a
second identical run read every 1200 steps. Nothing here is asserted: it prints what it
measured.

The body: physstep's ``Box(2**0.5 / 2, 1/2, 1/400)`` of mass 12, whose principal moments
(1.000025, 2.000025, 3) are given to MuJoCo as its ``diaginertia``, so both engines step
exactly the same body. MuJoCo's free joint holds the angular velocity in the body frame
(``qvel[3:6]``); with the identity orientation that is physstep's world-frame omega0.

MuJoCo's integrators on a lone free body: ``Euler`` is semi-implicit Euler (the new velocity
from the current acceleration, then the position from the new velocity; only joint damping,
none here, is implicit), so the gyroscopic force is explicit; ``RK4`` is the classic
four-stage Runge-Kutta on (qpos, qvel); ``implicitfast`` (MuJoCo 3.11 and later) takes the
linearised implicit velocity step with the gyroscopic derivative of a standalone free body
put back, the same update as ``implicit``: stable, and it damps tumbling.

    python bench/bench_racket.py [--quick]

MuJoCo comes with the ``bench`` extra: ``pip install -e '.[bench]'``.
"""

from __future__ import annotations

import argparse
import statistics
import time
from typing import Any

import numpy as np
import physstep

DT = 1.0 / 120.0
MASS = 12.0
OMEGA0 = np.array([0.01, 2.0, 0.01])  # body frame (= world frame at t = 0), rad/s
HALF = (2**0.5 * 0.5, 0.5, 0.0025)  # a thin plate: moments (1, 2, 3) to 3e-5
SAMPLE = 1200  # steps between energy samples (10 s)


def physstep_world(method: str) -> physstep.World:
    """The racket in physstep: the box whose principal axes are its own."""
    w = physstep.World(3, method=method, dt=DT)
    w.add_body(physstep.Box(*HALF), mass=MASS, angular_velocity=tuple(OMEGA0))
    return w


def moments() -> np.ndarray:
    """The racket's principal moments, as physstep computes them (MuJoCo is given these)."""
    return np.asarray(physstep.Box(*HALF).mass_properties(mass=MASS).principal_moments, dtype=float)


def invariants(omega_body: np.ndarray, inertia: np.ndarray) -> tuple[float, float]:
    """Rotational energy and |L| from the body-frame angular velocity."""
    lb = inertia * omega_body
    return 0.5 * float(omega_body @ lb), float(np.linalg.norm(lb))


def physstep_invariants(w: physstep.World) -> tuple[float, float]:
    """Energy (J) and |L| (kg m^2/s) as physstep reports them."""
    return float(w.energy()), float(np.linalg.norm(w.angular_momentum()))


def result(
    ns: float, e0: float, l0: float, e: float, lnorm: float, max_de: float, div: float
) -> dict[str, Any]:
    """One row of the table."""
    ok = np.isnan(div)
    return {
        "ns": ns,
        "e0": e0,
        "l0": l0,
        "de": abs(e - e0) / e0 if ok else float("inf"),
        "dl": abs(lnorm - l0) / l0 if ok else float("inf"),
        "max_de": max_de,
        "diverged": div,
    }


def run_physstep(method: str, steps: int, repeats: int) -> dict[str, Any]:
    """Median time of `World.step(steps)` in one call; errors at the end and along the run."""
    times, e0, l0 = [], 0.0, 0.0
    physstep_world(method).step(SAMPLE)  # warm-up, untimed
    for _ in range(repeats):
        w = physstep_world(method)
        e0, l0 = physstep_invariants(w)
        t0 = time.perf_counter_ns()
        w.step(steps)
        times.append((time.perf_counter_ns() - t0) / steps)
    e, lnorm = physstep_invariants(w)
    end_hash = w.state_hash()
    w = physstep_world(method)
    max_de = 0.0
    for _ in range(steps // SAMPLE):
        w.step(SAMPLE)
        max_de = max(max_de, abs(physstep_invariants(w)[0] - e0) / e0)
    w.step(steps % SAMPLE)
    max_de = max(max_de, abs(e - e0) / e0)
    if w.state_hash() != end_hash:
        print(f"note: physstep {method} stepped in chunks ends in another state than in one call")
    return result(statistics.median(times), e0, l0, e, lnorm, max_de, float("nan"))


def mujoco_model(integrator: str) -> Any:
    """The racket in MuJoCo: a free joint, the same mass and principal moments."""
    import mujoco

    diag = " ".join(repr(float(c)) for c in moments())
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


def mujoco_fresh(m: Any) -> Any:
    """New data at rest at the origin, spinning at omega0 (qvel[3:6] is in the body frame)."""
    import mujoco

    d = mujoco.MjData(m)
    d.qvel[3:6] = OMEGA0
    return d


def mujoco_blown(d: Any, n: int) -> bool:
    """After n steps: MuJoCo flagged a bad value (and reset the data, time back to 0), or a
    non-finite or runaway omega."""
    import mujoco

    bad = (
        mujoco.mjtWarning.mjWARN_BADQPOS,
        mujoco.mjtWarning.mjWARN_BADQVEL,
        mujoco.mjtWarning.mjWARN_BADQACC,
    )
    w = np.array(d.qvel[3:6])
    return (
        any(d.warning[k].number > 0 for k in bad)
        or abs(d.time - n * DT) > 1e-6 * max(1.0, n * DT)
        or not np.all(np.isfinite(w))
        or float(np.linalg.norm(w)) > 1e6 * float(np.linalg.norm(OMEGA0))
    )


def run_mujoco(integrator: str, steps: int, repeats: int) -> dict[str, Any]:
    """Median time of `mj_step(m, d, nstep=steps)` on fresh data; errors from qvel (body frame).

    MuJoCo's warnings (printed at every reset of an unstable run) are kept, the first reported."""
    import mujoco

    messages: list[str] = []
    previous = mujoco.get_mju_user_warning()
    mujoco.set_mju_user_warning(lambda text: messages.append(str(text).strip()))
    try:
        m = mujoco_model(integrator)
        inertia = np.array(m.body_inertia[1])
        mujoco.mj_step(m, mujoco_fresh(m), nstep=SAMPLE)  # warm-up, untimed
        times = []
        for _ in range(repeats):
            last = mujoco_fresh(m)
            t0 = time.perf_counter_ns()
            mujoco.mj_step(m, last, nstep=steps)
            times.append((time.perf_counter_ns() - t0) / steps)
        # The same-body check from MuJoCo's own quantities: its kinetic energy (from its mass
        # matrix) and its subtree angular momentum.
        d = mujoco_fresh(m)
        mujoco.mj_forward(m, d)
        mujoco.mj_energyVel(m, d)
        mujoco.mj_subtreeVel(m, d)
        native = float(d.energy[1]), float(np.linalg.norm(d.subtree_angmom[1]))
        # The errors from the body-frame omega: E = w.I w / 2, |L| = |I w|.
        e0, l0 = invariants(np.array(d.qvel[3:6]), inertia)
        e, lnorm = invariants(np.array(last.qvel[3:6]), inertia)
        # A second run read every SAMPLE steps; if it blows up, replay that chunk a step at a time.
        d = mujoco_fresh(m)
        max_de, div, doubled, done = 0.0, float("nan"), float("nan"), 0
        while done < steps:
            n = min(SAMPLE, steps - done)
            mujoco.mj_step(m, d, nstep=n)
            if mujoco_blown(d, done + n):
                d = mujoco_fresh(m)
                if done:
                    mujoco.mj_step(m, d, nstep=done)
                while not mujoco_blown(d, done):
                    mujoco.mj_step(m, d)
                    done += 1
                div = done * DT
                break
            done += n
            de = abs(invariants(np.array(d.qvel[3:6]), inertia)[0] - e0) / e0
            max_de = max(max_de, de)
            if de > 1.0 and np.isnan(doubled):
                doubled = done * DT
    finally:
        mujoco.set_mju_user_warning(previous)
    r = result(statistics.median(times), e0, l0, e, lnorm, max_de, div)
    r["e0"], r["l0"] = native
    r["doubled"], r["warning"] = doubled, (messages or [""])[0]
    return r


def main() -> None:
    """Measures, checks the engines computed the same body, prints the table."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="12,000 steps (100 s), one repeat (a smoke run)")
    args = ap.parse_args()
    steps, repeats = (12_000, 1) if args.quick else (144_000, 5)
    rows: dict[str, dict[str, Any]] = {}
    for method in ("symplectic-euler", "rk4", "yoshida4"):
        rows[f"physstep {method}"] = run_physstep(method, steps, repeats)
    try:
        import mujoco
    except ImportError:
        version = None
        print("MuJoCo is not installed: pip install -e '.[bench]' to compare against it")
    else:
        version = mujoco.__version__
        for integrator in ("Euler", "RK4", "implicitfast"):
            rows[f"MuJoCo {integrator}"] = run_mujoco(integrator, steps, repeats)
    ref = rows["physstep symplectic-euler"]
    print(
        f"racket: inertia {moments().tolist()} kg m^2, mass {MASS:g} kg, omega0 {OMEGA0.tolist()} rad/s,"
        f" dt = 1/120 s, {steps} steps ({steps * DT:g} s), median of {repeats}"
        + (f", MuJoCo {version}" if version else "")
    )
    print("initial state (must agree to 1e-4):")
    for name, r in rows.items():
        gap = max(abs(r["e0"] - ref["e0"]) / ref["e0"], abs(r["l0"] - ref["l0"]) / ref["l0"])
        flag = "" if gap <= 1e-4 else "   <-- NOT the same body"
        print(f"  {name:28} E0 = {r['e0']:.12f} J   |L|0 = {r['l0']:.12f}   gap {gap:.1e}{flag}")
    head = (
        f"{'engine / integrator':28} {'ns/step':>9} {'x default':>10} {'dE/E 1200s':>12}"
        f" {'d|L|/|L|':>10} {'max dE/E':>10}"
    )
    print(head.replace("1200s", f"{steps * DT:g}s"))
    print("-" * len(head))
    for name, r in rows.items():
        if np.isnan(r["diverged"]):
            end, dl = f"{r['de']:12.2e}", f"{r['dl']:10.2e}"
        else:
            end, dl = f"{'div ' + format(r['diverged'], '.2f') + ' s':>12}", f"{'-':>10}"
        print(f"{name:28} {r['ns']:9.1f} {r['ns'] / ref['ns']:10.2f} {end} {dl} {r['max_de']:10.2e}")
    if "MuJoCo Euler" in rows:
        ratio = rows["MuJoCo Euler"]["ns"] / ref["ns"]
        print(f"MuJoCo Euler time / physstep default time: {ratio:.2f}")
    for name, r in rows.items():
        if not np.isnan(r["diverged"]):
            k = round(r["diverged"] / DT)
            print(
                f"{name}: blew up in step {k} (t = {(k - 1) * DT:.4f} -> {k * DT:.4f} s); its energy error"
                f" first passed 100% at the sample t = {r['doubled']:.0f} s; max dE/E is"
                " over the samples before the blow-up, and the timed runs go on from MuJoCo's reset state"
            )
        if r.get("warning"):
            print(f"  MuJoCo said: {r['warning']}")


if __name__ == "__main__":
    main()
