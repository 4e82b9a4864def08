"""A World under another thread and under Ctrl-C: a second thread touching a World while one
steps it gets WorldBusyError at once, and SIGINT interrupts a long call after its last whole
step, heard inside a step (between the pair blocks of n-body gravity), in Python and in the
command line. Neither test waits on the clock: each starts its move when the other side is known to
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
    # The state after the interrupt is that of its whole steps, bitwise (the step under way
    # rolled back; it may be the first). The child says "stepping" from a second thread once
    # the World is held by the step (the probe gets WorldBusyError). Where the probe itself
    # holds the World for a moment as the step starts, the step raises WorldBusyError having
    # done nothing, and is called again. The step cannot end by itself (10**9 steps of a
    # 2000-body system), so only the signal ends it.
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
        "    fresh = physstep.World.from_scene('nbody', 'leapfrog', 0.001, params={'n': 2000})\n"
        "    fresh.step(w.steps) if w.steps else None\n"
        "    same = (w.positions == fresh.positions).all() and (w.velocities == fresh.velocities).all()\n"
        "    print('interrupted', bool(same), w.steps < 10**9, flush=True)\n"
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


def _interrupt_when(p: subprocess.Popen[str], sign: str) -> tuple[str, str]:
    """Sends SIGINT once the child printed ``sign`` on stderr; its output (a child that does
    not end within HANG seconds of the signal fails the test: it did not hear it)."""
    assert p.stderr is not None
    assert p.stderr.readline().strip() == sign
    p.send_signal(signal.SIGINT)
    try:
        out, err = p.communicate(timeout=HANG)
    finally:
        if p.poll() is None:
            p.kill()
            p.wait()
    return out, err


def test_ctrl_c_is_heard_inside_one_long_step_of_n_body_gravity() -> None:
    # ONE step of 40,000 bodies (8e8 pairs, seconds of work): the signal arrives while it
    # runs, and is heard between pair blocks: the step is rolled back bitwise (no step
    # counted, the positions and velocities those before it) and KeyboardInterrupt raised.
    # A signal heard only when the step ended would leave one step counted.
    code = (
        "import sys, threading, physstep\n"
        "w = physstep.World.from_scene('nbody', 'leapfrog', 0.001, params={'n': 40000})\n"
        "x0, v0 = w.positions.copy(), w.velocities.copy()\n"
        "def probe():\n"
        "    while True:\n"
        "        try:\n"
        "            w.positions\n"
        "        except physstep.WorldBusyError:\n"
        "            print('stepping', file=sys.stderr, flush=True)\n"
        "            return\n"
        "threading.Thread(target=probe, daemon=True).start()\n"
        "try:\n"
        "    w.step(1)\n"
        "    print('finished the step', w.steps, flush=True)\n"
        "except KeyboardInterrupt:\n"
        "    same = (w.positions == x0).all() and (w.velocities == v0).all()\n"
        "    print('interrupted', w.steps, bool(same), flush=True)\n"
    )
    p = subprocess.Popen(
        [sys.executable, "-c", code],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=sigint_default,
    )
    out, err = _interrupt_when(p, "stepping")
    assert out.strip() == "interrupted 0 True", err


def test_the_command_line_exits_130_at_the_first_ctrl_c_inside_a_long_step() -> None:
    # `physstep run nbody --param n=20000`: the child says "stepping" as the run is handed to
    # the engine (a profile hook on the call); one SIGINT ends it with status 130 and one line.
    code = (
        "import sys, physstep._core as core\n"
        "from physstep.cli import main\n"
        "def hook(frame, event, arg):\n"
        "    if event == 'c_call' and arg is core.simulate:\n"
        "        sys.setprofile(None)\n"
        "        print('stepping', file=sys.stderr, flush=True)\n"
        "sys.setprofile(hook)\n"
        "sys.exit(main(['run', 'nbody', '--param', 'n=20000', '--until', '1']))\n"
    )
    p = subprocess.Popen(
        [sys.executable, "-c", code],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=sigint_default,
    )
    # (The whole run is a thousand such steps, far beyond HANG: only a signal heard during
    # the run ends it in time.)
    out, err = _interrupt_when(p, "stepping")
    assert p.returncode == 130, (p.returncode, err)
    assert err == "physstep: interrupted\n" and out == ""


def test_ctrl_c_inside_a_python_force_of_a_watched_call_is_not_lost() -> None:
    # The force sends SIGINT to its own process on its 50th call, in a call long enough to
    # be watched: Python raises KeyboardInterrupt inside the force while the engine is asked
    # to stop; the step is rolled back and the KeyboardInterrupt reaches the caller (it was
    # not swallowed and the run did not go on).
    code = (
        "import os, signal, physstep\n"
        "w = physstep.World(1, method='rk4', dt=0.01)\n"
        "w.add_particle([1.0])\n"
        "calls = [0]\n"
        "def force(t, x, v):\n"
        "    calls[0] += 1\n"
        "    if calls[0] == 50:\n"
        "        os.kill(os.getpid(), signal.SIGINT)\n"
        "    return -x\n"
        "w.add_force(force)\n"
        "try:\n"
        "    w.step(100000)\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted', w.steps < 20, calls[0] < 100, flush=True)\n"
    )
    p = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=HANG, preexec_fn=sigint_default
    )
    assert p.stdout.strip() == "interrupted True True", p.stderr
