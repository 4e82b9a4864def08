"""A World under another thread and under Ctrl-C: a second thread touching a World while one
steps it gets WorldBusyError at once, and SIGINT interrupts a long step after its last whole
step. Neither test waits on the clock: each starts its move when the other side is known to
be inside the step."""

from __future__ import annotations

import signal
import subprocess
import sys
import threading

import numpy as np
import physstep
from conftest import sigint_default

#: How long either side waits for the other before the test fails (s): a bound on a hang,
#: never a measure of anything.
HANG = 60.0


def test_a_world_touched_by_a_second_thread_while_it_steps_raises_world_busy() -> None:
    # The race is forced: the stepping thread's force blocks inside the step (the World
    # held) until the main thread has looked.
    w = physstep.World(1, method="rk4")
    w.add_particle([1.0])
    inside, looked = threading.Event(), threading.Event()

    def force(t: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        if not inside.is_set():
            inside.set()
            assert looked.wait(HANG), "the main thread never looked"
        return -x

    w.add_force(force)
    errors: list[BaseException] = []

    def stepper() -> None:
        try:
            w.step(3)
        except BaseException as e:  # reported by the main thread
            errors.append(e)

    t = threading.Thread(target=stepper)
    t.start()
    try:
        assert inside.wait(HANG), "the step never reached the force"
        try:
            w.positions  # noqa: B018
        except physstep.WorldBusyError as e:
            seen: BaseException | None = e
        else:
            seen = None
    finally:
        looked.set()
        t.join(HANG)
    assert not t.is_alive() and not errors, errors
    assert isinstance(seen, physstep.WorldBusyError) and isinstance(seen, RuntimeError)
    assert str(seen).startswith("this World is in use by another thread")
    # Once the step is over the World answers again, the three steps taken.
    assert w.steps == 3 and w.positions.shape == (1, 1)


def test_ctrl_c_interrupts_a_long_step_after_its_last_whole_step() -> None:
    # The child says "stepping" from a second thread once the World is held by the step
    # (the probe gets WorldBusyError). Where the probe itself holds the World for a moment
    # as the step starts, the step raises WorldBusyError having done nothing, and is called
    # again. The step cannot end by itself (10**9 steps of a 2000-body system), so only the
    # signal ends it.
    code = (
        "import threading, physstep\n"
        "w = physstep.World.from_scene('nbody', 'leapfrog', 0.001, params={'n': 2000})\n"
        "def probe():\n"
        "    while True:\n"
        "        try:\n"
        "            w.positions\n"
        "        except physstep.WorldBusyError:\n"
        "            print('stepping', flush=True)\n"
        "            return\n"
        "threading.Thread(target=probe, daemon=True).start()\n"
        "try:\n"
        "    while True:\n"
        "        try:\n"
        "            w.step(10**9)\n"
        "        except physstep.WorldBusyError:\n"
        "            continue\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted', w.steps > 0, w.steps < 10**9, flush=True)\n"
    )
    p = subprocess.Popen(
        [sys.executable, "-c", code], stdout=subprocess.PIPE, text=True, preexec_fn=sigint_default
    )
    try:
        assert p.stdout is not None
        assert p.stdout.readline().strip() == "stepping"
        p.send_signal(signal.SIGINT)
        out, _ = p.communicate(timeout=HANG)
    finally:
        if p.poll() is None:
            p.kill()
            p.wait()
    assert out.strip() == "interrupted True True"
    assert p.returncode == 0
