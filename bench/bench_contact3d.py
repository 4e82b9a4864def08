"""Boxes dropped on a plane in 3D: physstep's `dice` scene against MuJoCo and pybullet.

    python bench/bench_contact3d.py [--n 1000] [--seconds 10] [--repeat 3]

All step the same 1,000 boxes, one thread each, from the same start: physstep's `dice` scene
(`World.from_scene("dice", params={"n": 1000})`: 20 cm cubes of density 1000 kg/m^3, 8 kg,
on a grid 0.5 m apart at heights 1.0 to 1.2 m, each turned and thrown with a random
velocity and spin; friction 0.6, restitution 0.2; the ground the plane y = 0; gravity 9.81
m/s^2 along -y), its default contact solver (`soft-step`, 8 substeps), dt = 1/60 s, 600 steps
for 10 s. The peers are built from physstep's starting state (positions, quaternions,
velocities, angular velocities, y up in all three): MuJoCo (`mujoco`, in the `bench` extra):
a free body and a box geom per cube, the plane's normal +y, friction 0.6, its default solver
(Newton, `refsafe` keeping a contact's time constant at 2 dt at least), timestep 1/60 s;
pybullet (Bullet's sequential impulses, DIRECT): `setTimeStep(1/60)`, one substep, its
default 50 solver iterations, each cube's friction 0.6 and restitution 0.2, the plane's the
same.

pybullet's wheel is built against numpy 1 and does not import beside numpy 2, so it runs in a
process of its own, from a virtual environment of its own: `.venv-pybullet` in the checkout
(or the Python named by `PHYSSTEP_PYBULLET_PYTHON`), made once with

    python3 -m venv .venv-pybullet && .venv-pybullet/bin/pip install "numpy<2" pybullet

(`--make-pybullet-venv` runs those two commands). That process imports neither physstep
nor numpy 2: this file, run with `--worker pybullet`, reads the starting state from a `.npz`
and prints its figures as one line of JSON.

Printed per engine: ms per step (the median over `repeat` timed runs of the whole run, one
step a call, no read-out), the deepest penetration over the run two ways: (1) as the engine
reports it (physstep's `max_penetration`; MuJoCo's contact distances; pybullet's contact
distances, each negative where shapes overlap) and (2) the same geometric check for all: the
lowest box corner below the plane (box on box overlap not counted: on this grid boxes seldom
meet), over the run (the landing: a box falling 7 cm a step meets the plane inside a step)
and at the end (at rest); and the drift at rest: the largest distance any box's centre moved
over the last 2 s (a box still sliding or rocking shows as drift). physstep and MuJoCo each
run twice: every body awake, and with sleeping on (physstep's `sleep_time = 0.5`, Box2D's;
MuJoCo 4's `mjENBL_SLEEP` at its default tolerance): a box at rest then leaves the solver.
physstep runs again with 6, 4, 2 and 1 substeps (less work a step, more penetration at rest);
the last lines print, for each awake peer, physstep's fastest soft-step row with equal or
smaller drift and penetration (over the run and at the end, by the corners) and its ratio.
Then physstep's time per step over each peer's (below 1: physstep faster). Nothing is asserted: a
measurement, not a test. A peer that does not import is named and skipped.
"""

from __future__ import annotations

import argparse
import functools
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

HALF, DT, G, MU, E, DENSITY = 0.1, 1.0 / 60.0, 9.81, 0.6, 0.2, 1000.0
ROOT = Path(__file__).resolve().parent.parent
REST = 2.0  # s: the drift is measured over the run's last REST seconds


def corners_below(x: Any, q: Any) -> float:
    """Deepest box corner below the plane y = 0, m (0 when none is): boxes of half extent
    HALF at centres `x` (n, 3) turned by unit quaternions `q` (n, 4) as (w, x, y, z)."""
    import numpy as np

    w, qx, qy, qz = q.T
    # The world y of each body axis (the second row of the rotation matrix).
    ry = np.stack([2 * (qx * qy + w * qz), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - w * qx)], 1)
    low = x[:, 1] - HALF * np.abs(ry).sum(1)
    return max(0.0, float(-low.min()))


def run(engine: Any, steps: int, repeat: int, state: dict[str, Any]) -> dict[str, float]:
    """Times `repeat` fresh runs of `steps` steps, then measures one more: reported and
    geometric penetration every step, drift over the last REST s."""
    import numpy as np

    times = []
    for _ in range(repeat):
        e = engine(state)
        t0 = time.perf_counter()
        for _ in range(steps):
            e.step()
        times.append((time.perf_counter() - t0) / steps)
    e = engine(state)
    reported = geometric = 0.0
    rest_from = max(0, steps - round(REST / DT))
    x_rest = None
    for k in range(steps):
        if k == rest_from:
            x_rest = e.poses()[0]
        e.step()
        x, q = e.poses()
        reported = max(reported, e.reported())
        geometric = max(geometric, corners_below(x, q))
    x, q = e.poses()
    drift = float(np.linalg.norm(x - x_rest, axis=1).max()) if x_rest is not None else float("nan")
    return {
        "ms": 1e3 * statistics.median(times),
        "reported": reported,
        "geometric": geometric,
        "end": corners_below(x, q),
        "drift": drift,
    }


class Physstep:
    sleep_time = 0.0

    def __init__(self, state: dict[str, Any], substeps: int | None = None) -> None:
        import physstep

        self.w = physstep.World.from_scene("dice", params={"n": int(state["n"]), "seed": 1.0, "g": G}, dt=DT)
        self.w.sleep_time = self.sleep_time
        if substeps is not None:
            self.w.substeps = substeps

    def step(self) -> None:
        self.w.step(1)

    def poses(self) -> tuple[Any, Any]:
        return self.w.solid_positions()[1:], self.w.solid_orientations()[1:]  # 0 is the ground

    def reported(self) -> float:
        return self.w.max_penetration


class PhysstepSleeping(Physstep):
    """physstep with sleeping on (Box2D's 0.5 s): a die at rest leaves the solver."""

    sleep_time = 0.5


class Mujoco:
    sleep = False

    def __init__(self, state: dict[str, Any]) -> None:
        import mujoco
        import numpy as np

        n = len(state["x"])
        bodies = "".join(
            f'<body><freejoint/><geom type="box" size="{HALF} {HALF} {HALF}" density="{DENSITY}"/></body>'
            for _ in range(n)
        )
        xml = f"""<mujoco><option timestep="{DT}" gravity="0 {-G} 0"/>
            <default><geom friction="{MU} 0.005 0.0001"/></default>
            <worldbody><geom type="plane" size="0 0 1" zaxis="0 1 0"/>{bodies}</worldbody></mujoco>"""
        self.mj = mujoco
        self.model = mujoco.MjModel.from_xml_string(xml)
        if self.sleep:
            self.model.opt.enableflags |= mujoco.mjtEnableBit.mjENBL_SLEEP
        self.data = d = mujoco.MjData(self.model)
        qpos = d.qpos.reshape(n, 7)
        qvel = d.qvel.reshape(n, 6)
        qpos[:, :3] = state["x"]
        qpos[:, 3:] = state["q"]
        qvel[:, :3] = state["v"]
        for i in range(n):  # a free joint's angular velocity is in the body's frame
            r = np.zeros(9)
            mujoco.mju_quat2Mat(r, np.ascontiguousarray(state["q"][i]))
            qvel[i, 3:] = r.reshape(3, 3).T @ state["w"][i]
        mujoco.mj_forward(self.model, d)

    def step(self) -> None:
        self.mj.mj_step(self.model, self.data)

    def poses(self) -> tuple[Any, Any]:
        n = self.model.nbody - 1
        return self.data.xpos[1:].copy(), self.data.xquat[1:].copy().reshape(n, 4)

    def reported(self) -> float:
        c = self.data.contact[: self.data.ncon]
        return max(0.0, float(-c.dist.min())) if self.data.ncon else 0.0


class MujocoSleeping(Mujoco):
    """MuJoCo with its sleeping on (`mjENBL_SLEEP`, its default tolerance)."""

    sleep = True


class Pybullet:
    def __init__(self, state: dict[str, Any]) -> None:
        import pybullet as p

        self.p = p
        self.c = c = p.connect(p.DIRECT)
        p.setGravity(0, -G, 0, physicsClientId=c)
        p.setTimeStep(DT, physicsClientId=c)
        plane = p.createCollisionShape(p.GEOM_PLANE, planeNormal=[0, 1, 0], physicsClientId=c)
        ground = p.createMultiBody(0, plane, physicsClientId=c)
        p.changeDynamics(ground, -1, lateralFriction=MU, restitution=E, physicsClientId=c)
        box = p.createCollisionShape(p.GEOM_BOX, halfExtents=[HALF] * 3, physicsClientId=c)
        mass = DENSITY * (2 * HALF) ** 3
        self.ids = []
        for x, q, v, w in zip(state["x"], state["q"], state["v"], state["w"], strict=True):
            b = p.createMultiBody(
                mass, box, basePosition=list(x), baseOrientation=[q[1], q[2], q[3], q[0]], physicsClientId=c
            )
            p.changeDynamics(b, -1, lateralFriction=MU, restitution=E, physicsClientId=c)
            p.resetBaseVelocity(b, list(v), list(w), physicsClientId=c)
            self.ids.append(b)

    def step(self) -> None:
        self.p.stepSimulation(physicsClientId=self.c)

    def poses(self) -> tuple[Any, Any]:
        import numpy as np

        xs, qs = [], []
        for b in self.ids:
            x, q = self.p.getBasePositionAndOrientation(b, physicsClientId=self.c)
            xs.append(x)
            qs.append((q[3], q[0], q[1], q[2]))
        return np.array(xs), np.array(qs)

    def reported(self) -> float:
        pts = self.p.getContactPoints(physicsClientId=self.c)
        return max([0.0] + [-pt[8] for pt in pts])


def pybullet_python() -> Path:
    return Path(os.environ.get("PHYSSTEP_PYBULLET_PYTHON", ROOT / ".venv-pybullet" / "bin" / "python"))


def make_pybullet_venv() -> None:
    venv = ROOT / ".venv-pybullet"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    subprocess.run([str(venv / "bin" / "pip"), "install", "-q", "numpy<2", "pybullet"], check=True)


def pybullet_in_its_process(state: dict[str, Any], steps: int, repeat: int) -> dict[str, float] | str:
    """The pybullet figures from its own interpreter, or why not."""
    import numpy as np

    py = pybullet_python()
    if not py.exists():
        return f"no {py} (--make-pybullet-venv makes it)"
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "start.npz"
        np.savez(path, **state)
        args = [str(py), __file__, "--worker", "pybullet", "--state", str(path)]
        args += ["--steps", str(steps), "--repeat", str(repeat)]
        out = subprocess.run(args, capture_output=True, text=True, env={**os.environ, "OMP_NUM_THREADS": "1"})
    if out.returncode != 0:
        return "its process failed: " + (out.stderr.strip().splitlines() or ["no output"])[-1]
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1000)
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--worker", choices=["pybullet"], help=argparse.SUPPRESS)
    ap.add_argument("--state", help=argparse.SUPPRESS)
    ap.add_argument("--steps", type=int, help=argparse.SUPPRESS)
    ap.add_argument("--make-pybullet-venv", action="store_true", help="make .venv-pybullet first")
    args = ap.parse_args()
    if args.worker == "pybullet":
        import numpy as np

        state = dict(np.load(args.state))
        print(json.dumps(run(Pybullet, args.steps, args.repeat, state)))
        return
    if args.make_pybullet_venv:
        make_pybullet_venv()
    os.environ.setdefault("RAYON_NUM_THREADS", "1")  # rayon's pool starts at its first use
    import physstep

    steps = round(args.seconds / DT)
    w = physstep.World.from_scene("dice", params={"n": args.n, "seed": 1.0, "g": G}, dt=DT)
    state = {
        "n": args.n,
        "x": w.solid_positions()[1:],
        "q": w.solid_orientations()[1:],
        "v": w.solid_velocities()[1:],
        "w": w.solid_angular_velocities()[1:],
    }
    print(f"{args.n} boxes (20 cm) dropped on a plane, dt = 1/60 s, {steps} steps, one thread")
    head = ("", "", "deepest, over the run", "at the end", "drift, last")
    print(f"{head[0]:<26} {head[1]:>8} {head[2]:>25} {head[3]:>12} {head[4]:>12}")
    head = ("engine", "ms/step", "reported", "corners", "corners", f"{REST:.0f} s")
    print(f"{head[0]:<26} {head[1]:>8} {head[2]:>12} {head[3]:>12} {head[4]:>12} {head[5]:>12}")
    # The soft step with fewer substeps too: the cost at the peers' drift and penetration.
    fewer = {f"physstep (soft-step, {k})": k for k in (6, 4, 2, 1)}
    engines: dict[str, Any] = {
        "physstep (soft-step, 8)": Physstep,
        "physstep (sleeps)": PhysstepSleeping,
        **{label: functools.partial(Physstep, substeps=k) for label, k in fewer.items()},
        "MuJoCo (Newton)": Mujoco,
        "MuJoCo (Newton, sleeps)": MujocoSleeping,
    }
    got: dict[str, dict[str, float]] = {}
    for label, engine in engines.items():
        try:
            engine(state)
        except ImportError as err:
            print(f"{label:<26} skipped: {err.name} does not import here (pip install -e .[bench])")
            continue
        got[label] = run(engine, steps, args.repeat, state)
    pb = pybullet_in_its_process(state, steps, args.repeat)
    pb_label = "pybullet (50 iterations)"
    if isinstance(pb, str):
        print(f"{pb_label:<26} skipped: {pb}")
    else:
        got[pb_label] = pb
    for label, r in got.items():
        print(
            f"{label:<26} {r['ms']:8.3f} {r['reported']:10.2e} m {r['geometric']:10.2e} m"
            f" {r['end']:10.2e} m {r['drift']:10.2e} m"
        )
    peers = [label for label in got if not label.startswith("physstep")]
    for mine in ("physstep (soft-step, 8)", "physstep (sleeps)"):
        for label in peers:
            if mine in got:
                print(f"{mine} / {label}: {got[mine]['ms'] / got[label]['ms']:.2f}x the time per step")
    # The comparison: physstep's time per step at equal or smaller drift and
    # penetration (the deepest over the run and at the end, by the corners) than the peer's:
    # its fastest awake soft-step row that matches all three.
    keys = ("drift", "geometric", "end")
    soft = ["physstep (soft-step, 8)", *fewer]
    for peer in (p for p in peers if "sleeps" not in p):
        ok = [s for s in soft if s in got and all(got[s][k] <= got[peer][k] for k in keys)]
        if ok:
            best = min(ok, key=lambda s: got[s]["ms"])
            ratio = got[best]["ms"] / got[peer]["ms"]
            print(f"at {peer}'s drift and penetration or less: {best}, {ratio:.2f}x its time per step")
        else:
            print(f"at {peer}'s drift and penetration or less: no soft-step row here matches all three")


if __name__ == "__main__":
    main()
