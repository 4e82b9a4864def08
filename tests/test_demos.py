"""The demos, headless: every registered demo runs with every key action and a mouse drag
and draws a frame that is not blank; the command line's list and its errors."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest
from physstep import demos
from physstep.cli import main

pygame = pytest.importorskip("pygame", reason="the demo extra (pygame-ce) is not installed")

from physstep.demos import app  # noqa: E402  (after the skip: it imports pygame)

FRAMES = 120


@pytest.fixture(autouse=True)
def _headless(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("SDL_VIDEODRIVER", "dummy")
    monkeypatch.setenv("SDL_AUDIODRIVER", "dummy")


def _key(key: app.Key) -> pygame.event.Event:
    mod = pygame.KMOD_SHIFT if key.shift else 0
    return pygame.event.Event(pygame.KEYDOWN, key=key.keys[0], mod=mod, unicode="", scancode=0)


def _script(name: str | None = "orbit") -> dict[int, list[app.Scripted]]:
    """Every key action of demo ``name`` but quit (the common ones and its own; None: a
    scene file's demo, the common ones), twice where it toggles, a drag, and quit on the
    last frame."""
    script: dict[int, list[app.Scripted]] = {}
    frame = 2
    for key in app.KEYS + (demos.load(name).keys if name else ()):
        if key.action == "quit":
            continue
        presses = 2 if key.action in ("help", "pause", "wind") else 1
        for _ in range(presses):
            script.setdefault(frame, []).append(_key(key))
            frame += 3
        if key.action == "step":  # a single step pauses: run again
            script.setdefault(frame, []).append(_key(next(k for k in app.KEYS if k.action == "pause")))
            frame += 3
    loop = next(k for k in app.KEYS if k.action == "loop")
    for _ in range(len(app.LOOPS) - 1):  # every loop variant, back to the first
        script.setdefault(frame, []).append(_key(loop))
        frame += 3
    start = frame

    def press(r: app.Runner) -> pygame.event.Event:
        return pygame.event.Event(pygame.MOUSEBUTTONDOWN, button=1, pos=r.screen_position(0, 0))

    def move(r: app.Runner) -> pygame.event.Event:
        x, y = r.screen_position(0, 0)
        return pygame.event.Event(pygame.MOUSEMOTION, pos=(x + 15, y - 10), rel=(15, -10), buttons=(1, 0, 0))

    script[start] = [press]
    for k in range(1, 5):
        script[start + k] = [move]
    script[start + 5] = [pygame.event.Event(pygame.MOUSEBUTTONUP, button=1, pos=(0, 0))]
    assert start + 6 < FRAMES - 1
    script[FRAMES - 1] = [_key(next(k for k in app.KEYS if k.action == "quit"))]
    return script


def _pixels(path: str) -> np.ndarray:
    from matplotlib.image import imread

    img = imread(path)
    return (img[..., :3] * 255).round().astype(np.uint8)


def _assert_not_blank(path: str) -> None:
    px = _pixels(path).reshape(-1, 3)
    packed = (px[:, 0].astype(np.int32) << 16) | (px[:, 1].astype(np.int32) << 8) | px[:, 2]
    colours, counts = np.unique(packed, return_counts=True)  # one int a colour: fast
    assert len(colours) >= 50, len(colours)  # text, lines, shading: many colours
    top2 = np.sort(counts)[-2:].sum()
    assert counts.max() / len(px) < 0.95  # not one flat fill
    assert (len(px) - top2) / len(px) > 0.01  # beyond the background and the panels: drawing
    assert px.std() > 5


@pytest.mark.parametrize("name", demos.names())
def test_every_demo_runs_every_key_and_draws_a_frame(name: str, tmp_path) -> None:
    shot = str(tmp_path / f"{name}.png")
    summary = app.run(name, headless=True, frames=FRAMES, screenshot=shot, script=_script(name))
    assert summary["frames"] == FRAMES
    assert summary["t"] > 0
    _assert_not_blank(shot)


@pytest.mark.parametrize("name", demos.names())
def test_the_script_presses_every_key_action(name: str) -> None:
    events = [e for es in _script(name).values() for e in es if isinstance(e, pygame.event.Event)]
    pressed = {(e.key, bool(e.mod)) for e in events if e.type == pygame.KEYDOWN}
    keys = app.KEYS + demos.load(name).keys
    assert all((k.keys[0], bool(k.shift)) in pressed for k in keys)
    common = {k for key in app.KEYS for k in key.keys}  # a demo's own keys are keys of its own
    assert not any(k in common for key in demos.load(name).keys for k in key.keys)


def test_a_headless_run_is_deterministic(tmp_path, capsys) -> None:
    shots = [str(tmp_path / f"{k}.png") for k in range(2)]
    for shot in shots:
        argv = ["demo", "orbit", "--headless", "--frames", "30", "--screenshot", shot, "--format", "json"]
        assert main(argv) == 0
        assert json.loads(capsys.readouterr().out)["frames"] == 30
    assert np.array_equal(_pixels(shots[0]), _pixels(shots[1]))


def test_list_in_text_and_json(capsys) -> None:
    assert main(["demo", "--list"]) == 0
    text = capsys.readouterr().out
    assert [line.split()[0] for line in text.splitlines()] == demos.names()
    assert main(["demo", "--list", "--format", "json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert [r["name"] for r in rows] == demos.names() and all(r["doc"] for r in rows)


def _fails(capsys, argv: list[str]) -> str:
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    return err


def test_an_unknown_demo_lists_the_valid_ones(capsys) -> None:
    err = _fails(capsys, ["demo", "pinball"])
    assert "unknown demo 'pinball'" in err and ", ".join(demos.names()) in err
    assert "give a demo NAME, --scene FILE.toml or --list" in _fails(capsys, ["demo"])


def test_bad_frames_and_screenshot_paths_are_one_line(capsys, tmp_path) -> None:
    assert "invalid --frames '0'" in _fails(capsys, ["demo", "spring", "--headless", "--frames", "0"])
    assert "invalid --frames 'many'" in _fails(capsys, ["demo", "spring", "--headless", "--frames", "many"])
    missing = str(tmp_path / "no" / "such" / "dir" / "x.png")
    assert f"invalid --screenshot '{missing}'" in _fails(
        capsys, ["demo", "spring", "--headless", "--screenshot", missing]
    )
    jpg = str(tmp_path / "x.jpg")
    assert "must be a .png file" in _fails(capsys, ["demo", "spring", "--headless", "--screenshot", jpg])


def test_a_method_that_does_not_apply_is_one_line(capsys) -> None:
    assert "does not apply to demo racket" in _fails(
        capsys, ["demo", "racket", "--headless", "--method", "verlet"]
    )
    assert "does not apply to demo lorenz" in _fails(
        capsys, ["demo", "lorenz", "--headless", "--method", "leapfrog"]
    )
    assert "unknown method 'nope'" in _fails(capsys, ["demo", "orbit", "--headless", "--method", "nope"])
    err = _fails(capsys, ["demo", "ragdoll", "--headless", "--dt", "5"])
    assert "invalid --dt '5': must be from 0.001 to 0.03333 s for demo ragdoll" in err


def test_without_pygame_the_demo_says_how_to_install_it(capsys, monkeypatch: pytest.MonkeyPatch) -> None:
    for mod in [m for m in sys.modules if m == "pygame" or m.startswith(("pygame.", "physstep.demos."))]:
        monkeypatch.delitem(sys.modules, mod)
    monkeypatch.setitem(sys.modules, "pygame", None)  # import pygame raises ImportError
    err = _fails(capsys, ["demo", "spring", "--headless"])
    # physstep is on no package index: the hint names what can be installed.
    assert "pip install pygame-ce" in err and "'physstep[demo]'" not in err
    assert main(["demo", "--list"]) == 0  # the list needs no pygame


def test_the_demos_page_lists_every_demo_and_key() -> None:
    from pathlib import Path

    page = (Path(__file__).parent.parent / "docs" / "demos.md").read_text()
    assert all(f"| `{name}` |" in page for name in demos.names())
    for key in app.KEYS + tuple(k for name in demos.names() for k in demos.load(name).keys):
        for token in key.label.split(" or "):
            assert f"`{token}`" in page, token


def test_no_display_is_one_line_pointing_at_headless(capsys, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("SDL_VIDEODRIVER", "no-such-driver")
    err = _fails(capsys, ["demo", "orbit", "--frames", "1"])
    assert "cannot open a window" in err and "--headless" in err


def test_without_a_display_the_demo_exits_2_in_one_line_not_unseen(capfd, monkeypatch) -> None:
    # no display and no driver chosen: SDL would fall back to its offscreen driver and run
    # the demo unseen (exit 0 when it ends), printing its own errors about Wayland first
    for var in ("DISPLAY", "WAYLAND_DISPLAY", "SDL_VIDEODRIVER"):
        monkeypatch.delenv(var, raising=False)
    monkeypatch.setattr(sys, "platform", "linux")
    assert main(["demo", "orbit", "--frames", "1"]) == 2
    err = capfd.readouterr().err  # file descriptor 2: SDL's own writes too
    assert err.splitlines() == [
        "physstep: error: cannot open a window (no display: DISPLAY and WAYLAND_DISPLAY are unset): "
        "run with --headless --screenshot FILE.png"
    ]
    # a driver that shows nothing, asked for without --headless
    monkeypatch.setenv("SDL_VIDEODRIVER", "dummy")
    assert main(["demo", "orbit", "--frames", "1"]) == 2
    err = capfd.readouterr().err
    assert len(err.splitlines()) == 1 and "SDL's video driver is 'dummy', which shows nothing" in err


def test_a_headless_run_says_when_the_frame_cap_slowed_it_below_real_time(capsys) -> None:
    # lorenz at dt = 1 ms: 16.7 steps a frame of 1/60 s, 8 allowed
    slow = app.run("lorenz", headless=True, frames=60, dt=0.001)
    assert slow["t"] == pytest.approx(60 * 8 * 0.001)
    assert slow["slowed"] == (
        "slower than real time: the frame cap (at most 8 steps per frame, frames clamped to 0.1 s) "
        "dropped 0.52 s; 0.48 s simulated in 1 s of frames (48 % of real time)"
    )
    assert main(["demo", "lorenz", "--headless", "--frames", "60", "--dt", "0.001"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 2 and lines[1] == "note: " + slow["slowed"]
    # at its own dt the demo keeps up: nothing to say
    assert app.run("lorenz", headless=True, frames=60)["slowed"] is None
    assert main(["demo", "orbit", "--headless", "--frames", "30", "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)["slowed"] is None


def test_a_drag_holds_the_particle_under_the_pointer_at_rest() -> None:
    seen: dict[str, object] = {}

    def press(r: app.Runner) -> pygame.event.Event:
        x, y = r.screen_position(0, 0)
        seen["target"] = (x + 60, y - 40)
        return pygame.event.Event(pygame.MOUSEBUTTONDOWN, button=1, pos=(x, y))

    def move(r: app.Runner) -> pygame.event.Event:
        return pygame.event.Event(pygame.MOUSEMOTION, pos=seen["target"], rel=(60, -40), buttons=(1, 0, 0))

    def look(r: app.Runner) -> pygame.event.Event:
        w = r.panels[0].world
        seen["x"], seen["v"] = np.array(w.positions[0]), np.array(w.velocities[0])
        seen["want"] = r.demo.to_world(r.rects[0], seen["target"], w.dim)
        return pygame.event.Event(pygame.MOUSEBUTTONUP, button=1, pos=seen["target"])

    app.run("orbit", headless=True, frames=12, script={5: [press], 6: [move], 9: [look]})
    np.testing.assert_allclose(seen["x"], seen["want"])
    np.testing.assert_array_equal(seen["v"], [0.0, 0.0])


def test_a_loop_change_carries_the_state_over_bitwise() -> None:
    import physstep
    from physstep.demos import base

    w = physstep.World.from_scene("spring", "leapfrog", 0.1)
    w.step(3)
    w2 = base.relooped(w, "step-per-frame", 1)
    assert w2.state_hash() == w.state_hash() and w2.time == w.time
    assert w2.advance(0.01) == 1 and w.advance(0.01) == 0  # a step a frame; the accumulator waits


def _runner(name: str) -> app.Runner:
    return app.Runner(demos.load(name)())


def test_balls_pull_a_ball_by_its_velocity_and_e_changes_the_restitution() -> None:
    r = _runner("balls")
    w = r.panels[0].world
    x = np.array(w.positions[0])
    target = r.demo.to_world(r.rects[0], r.screen_position(0, 0), 2) + [0.2, 0.0]
    r.demo.hold(w, 0, r.rects[0], r.demo.to_screen(r.rects[0], target))
    np.testing.assert_array_equal(w.positions[0], x)  # not moved: the contacts see it go
    v = np.array(w.velocities[0])
    assert v[0] > 1.0 and abs(v[1]) < 0.2 * v[0]  # towards the pointer (pixel rounding aside)
    assert w.restitution == 1.0
    r.act("restitution")
    assert r.panels[0].world.restitution == 0.9
    r.reset()  # a demo's settings survive a reset
    assert r.panels[0].world.restitution == 0.9


def test_cloth_sweeps_and_wind_keys_keep_the_state() -> None:
    r = _runner("cloth")
    r.update(1 / 60)
    w = r.panels[0].world
    r.act("iterations_down")
    assert w.constraint_iterations == 8
    x, t = np.array(w.positions), w.time
    r.next_loop()  # the wind rebuild keeps the loop variant too
    r.act("wind")
    w2 = r.panels[0].world
    assert w2 is not w and w2.time == t and w2.constraint_iterations == 8
    np.testing.assert_array_equal(w2.positions, x)
    assert w2.__reduce__()[1][0]["loop"] == app.LOOPS[1][0]
    z = float(w2.positions[:, 2].max())
    for _ in range(30):
        r.update(1 / 60)
    assert float(w2.positions[:, 2].max()) > z + 0.05  # blown along +z
    r.reset()
    assert r.panels[0].world.constraint_iterations == 8


def test_cloth_model_key_switches_between_the_three_cloths_and_back() -> None:
    r = _runner("cloth")
    r.act("iterations_down")  # the position-based cloth's sweeps and dt come back with it
    r.change_dt(0.5)
    pbd_dt = r.dt
    r.update(1 / 60)
    assert r.panels[0].step_cost() is not None
    r.act("model")
    p = r.panels[0]
    w = p.world
    assert w.method == p.info.name == "linearly-implicit-euler" and r.panel_methods == [w.method]
    assert w.dt == r.dt == 1 / 60 and w.time == 0.0 and len(w) == 144 and w.constraint_count == 0
    assert p.step_cost() is None  # a new cloth: its own cost
    r.update(1 / 60)
    assert p.steps == 1 and p.step_cost() > 0 and w.solve_stats["newton"] == 1
    rows = {label: value for label, value, _ in r.demo.hud(p)}
    assert rows["cloth"] == "linearly implicit (c)" and rows["cost"].endswith("ms a step")
    assert rows["solve"].startswith("1 Newton")
    # The spring cloth is drawn turned (hanging from the bar as the other does): a particle
    # dragged there is drawn under the pointer.
    rect, pos = r.rects[0], (600, 300)
    assert r.demo.hold(w, 5, rect, pos)
    assert np.allclose(r.demo.to_screen(rect, w.positions[5]), pos, atol=1)
    r.reset()  # r restarts the cloth shown
    assert r.panels[0].world.method == "linearly-implicit-euler" and r.panels[0].world.constraint_count == 0
    r.act("model")
    assert r.panels[0].world.method == "backward-euler" and r.dt == 1 / 60
    r.update(1 / 60)
    assert r.panels[0].world.solve_stats["newton"] >= 1
    r.act("model")
    w = r.panels[0].world
    assert (w.method, w.dt, r.dt, w.constraint_iterations) == ("symplectic-euler", pbd_dt, pbd_dt, 8)
    assert len(w) == 144 and w.constraint_count > 0 and w.time == 0.0


def test_ragdoll_kick_sends_it_up() -> None:
    r = _runner("ragdoll")
    for _ in range(90):  # 1.5 s: it lands
        r.update(1 / 60)
    r.act("kick")
    v = np.array(r.panels[0].world.velocities)
    assert v[:, 1].mean() > 4.0
    y = float(r.panels[0].world.positions[:, 1].mean())
    for _ in range(12):
        r.update(1 / 60)
    assert float(r.panels[0].world.positions[:, 1].mean()) > y + 0.5


SCENES = sorted((Path(__file__).parent.parent / "examples" / "scenes").glob("*.toml"))


@pytest.mark.parametrize("path", SCENES, ids=[p.stem for p in SCENES])
def test_every_scene_file_runs_in_the_scene_demo(path: Path, tmp_path) -> None:
    shot = str(tmp_path / "shot.png")
    summary = app.run(scene=str(path), headless=True, frames=3, screenshot=shot)
    assert summary["frames"] == 3 and summary["demo"] == "scene" and summary["scene"] == str(path)
    assert not summary["errors"]
    _assert_not_blank(shot)


@pytest.mark.parametrize(("stem", "least"), [("ramp", 5000), ("top-on-floor", 100), ("dice", 100)])
def test_the_scene_demo_draws_a_files_solids(stem: str, least: int, tmp_path) -> None:
    # The solids' shapes come from the file (a box on its ramp, a top's hull, dice as wire
    # boxes), in the dynamic solids' colour; before, a file of solids drew none of them.
    from physstep.demos import scene_solids

    path = Path(__file__).parent.parent / "examples" / "scenes" / f"{stem}.toml"
    shot = str(tmp_path / "shot.png")
    app.run(scene=str(path), headless=True, frames=3, screenshot=shot)
    px = _pixels(shot).reshape(-1, 3)
    dim = 2 if stem == "ramp" else 3
    colour = scene_solids.DYNAMIC if dim == 2 else scene_solids.DYNAMIC_EDGE
    drawn = int(np.count_nonzero((px == colour).all(axis=1)))
    assert drawn > least, drawn
    if stem == "ramp":  # the ramp itself, static: cut to the panel, not bent by pixel clipping
        assert int(np.count_nonzero((px == scene_solids.STILL).all(axis=1))) > 5000


@pytest.mark.parametrize("stem", ["chain", "top", "lorenz"])
def test_the_scene_demo_takes_every_key_and_a_drag(stem: str, tmp_path) -> None:
    path = Path(__file__).parent.parent / "examples" / "scenes" / f"{stem}.toml"
    shot = str(tmp_path / "shot.png")
    summary = app.run(scene=str(path), headless=True, frames=FRAMES, screenshot=shot, script=_script(None))
    assert summary["frames"] == FRAMES and summary["t"] > 0
    _assert_not_blank(shot)


def test_the_scene_demo_methods_and_a_drag() -> None:
    from physstep.demos.scene import SceneDemo

    scenes = Path(__file__).parent.parent / "examples" / "scenes"
    r = app.Runner(SceneDemo(str(scenes / "lorenz.toml")))
    assert all(not m.split for m in r.methods) and r.panels[0].info.name == "rk4"
    r = app.Runner(SceneDemo(str(scenes / "racket.toml")))
    assert all(not m.vector_positions for m in r.methods)
    r = app.Runner(SceneDemo(str(scenes / "stiff-chain.toml")))
    assert r.panels[0].info.name == "backward-euler" and r.dt == pytest.approx(1 / 60)
    r = app.Runner(SceneDemo(str(scenes / "pendulum.toml")))
    w = r.panels[0].world
    target = (r.screen_position(0, 0)[0] + 40, r.screen_position(0, 0)[1] + 30)
    assert r.demo.hold(w, 0, r.rects[0], target)
    assert r.screen_position(0, 0) == target and np.all(w.velocities[0] == 0.0)
    r = app.Runner(SceneDemo(str(scenes / "cloth.toml")))  # 3D: held at its depth
    w = r.panels[0].world
    depth = float(r.demo.camera[2] @ w.positions[70])
    target = (r.screen_position(0, 70)[0] - 25, r.screen_position(0, 70)[1] + 15)
    r.demo.hold(w, 70, r.rects[0], target)
    assert np.abs(np.subtract(r.screen_position(0, 70), target)).max() <= 1  # pixel rounding
    assert float(r.demo.camera[2] @ w.positions[70]) == pytest.approx(depth)


def test_reset_reloads_the_scene_file(tmp_path) -> None:
    from physstep.demos.scene import SceneDemo

    path = tmp_path / "s.toml"
    path.write_text("dimension = 2\ndt = 0.01\n[[particles]]\nposition = [1.0, 0.0]\n")
    r = app.Runner(SceneDemo(str(path)))
    r.act("method_next")
    method = r.panels[0].info.name
    path.write_text("dimension = 2\ndt = 0.01\n[[particles]]\nposition = [0.0, 2.0]\n")
    r.act("reset")
    np.testing.assert_array_equal(r.panels[0].world.positions[0], [0.0, 2.0])
    assert r.panels[0].info.name == method  # a reset keeps the method
    path.write_text("dimension = 2\n[[particles]]\nmass = -1\n")  # broken: the last good file runs
    r.act("reset")
    np.testing.assert_array_equal(r.panels[0].world.positions[0], [0.0, 2.0])
    assert r.demo.reload_error and "s.toml" in r.demo.reload_error


def test_a_bad_scene_file_is_one_line_naming_it(capsys, tmp_path) -> None:
    missing = str(tmp_path / "nope.toml")
    err = _fails(capsys, ["demo", "--scene", missing, "--headless"])
    assert f"scene file {missing}" in err and "cannot be read" in err
    bad = tmp_path / "bad.toml"
    bad.write_text("dimension = 2\n[[particles]]\npositon = [1.0, 2.0]\n")
    err = _fails(capsys, ["demo", "--scene", str(bad), "--headless"])
    assert f"scene file {bad}:3: particles[0].positon: unknown key" in err
    err = _fails(capsys, ["demo", "orbit", "--scene", str(bad)])
    assert "give a demo NAME or --scene FILE.toml, not both" in err


def test_the_scene_demo_on_the_command_line(capsys) -> None:
    path = str(Path(__file__).parent.parent / "examples" / "scenes" / "pendulum.toml")
    assert main(["demo", "--scene", path, "--headless", "--frames", "2", "--format", "json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["scene"] == path and out["demo"] == "scene" and out["frames"] == 2
    assert main(["demo", "--scene", path, "--headless", "--frames", "2", "--method", "rk4"]) == 0
    assert capsys.readouterr().out.startswith(f"scene {path}: 2 frames")


def test_the_scene_view_widens_to_follow_and_a_reset_restores_it() -> None:
    from physstep.demos.scene import SceneDemo

    r = app.Runner(SceneDemo(str(Path(__file__).parent.parent / "examples" / "scenes" / "tumble.toml")))
    fitted = r.demo.bounds
    for _ in range(120):  # 2 s: past the file's until = 1 s, the box falls below the fitted view
        r.update(1 / 60)
    centre = r.screen_position(0, 0)  # no particles: the panel's centre
    assert r.demo.bounds[1][1] > fitted[1][1]
    x, y = r.demo.to_screen(r.rects[0], r.panels[0].world.body_positions()[0])
    assert r.rects[0].collidepoint(x, y) and centre == r.rects[0].center
    r.act("reset")
    assert r.demo.bounds is r.demo.fitted


def test_ramp_keys_change_the_angle_and_friction_and_the_box_follows_the_closed_form() -> None:
    from physstep.demos.ramp import closed_form

    r = _runner("ramp")
    rows = {label: value for label, value, _ in r.demo.hud(r.panels[0])}
    assert rows["closed form"] == "0.0000 m/s^2 (sticks)"  # mu 0.6 > tan 0.5
    for _ in range(6):
        r.act("smoother")  # mu 0.6 -> 0.3: below tan 0.5, it slides
    r.act("steeper")
    w = r.panels[0].world
    assert (r.demo.angle, r.demo.friction) == (0.55, 0.3) and w.time == 0.0
    for _ in range(120):
        r.update(1 / 60)
    exact = closed_form(0.55, 0.3)
    assert exact == pytest.approx(9.81 * (np.sin(0.55) - 0.3 * np.cos(0.55)))
    assert r.demo.measured(r.panels[0].world) == pytest.approx(exact, rel=0.01)
    rows = {label: value for label, value, _ in r.demo.hud(r.panels[0])}
    assert rows["closed form"] == f"{exact:.4f} m/s^2 (slides)" and "% off" in rows["measured"]
    for _ in range(40):
        r.act("flatter")  # clamped at 0: flat, and the box stays
    assert r.demo.angle == 0.0
    for _ in range(60):
        r.update(1 / 60)
    assert abs(r.demo.measured(r.panels[0].world)) < 1e-6


def test_dice_throw_again_starts_the_next_seed() -> None:
    r = _runner("dice")
    for _ in range(30):
        r.update(1 / 60)
    x = r.panels[0].world.solid_positions()
    r.act("throw")
    w = r.panels[0].world
    assert r.demo.seed == 2 and w.time == 0.0 and w.solid_count == x.shape[0]
    assert not np.array_equal(w.solid_positions(), x)
    for _ in range(240):  # 4 s: the dice are at rest on the plane
        r.update(1 / 60)
    w = r.panels[0].world
    assert w.kinetic_energy() < 1e-3 and w.max_penetration < 1e-3
    # None below its face's height; all but one on a face (with this seed one die comes to
    # rest on an edge, leaning on its neighbour: 0.138 m up, since continuous collision).
    y = w.solid_positions()[1:, 1]
    assert np.all(y > 0.1 - 2e-3) and np.sum(np.abs(y - 0.1) < 2e-3) >= len(y) - 1, y


def test_pile_pours_drops_and_shakes_balls() -> None:
    r = _runner("pile")
    w = r.panels[0].world
    n = len(w)
    (x0, _), (x1, y1) = r.demo.box
    top = r.demo.to_screen(r.rects[0], [(x0 + x1) / 2, y1 - 0.2])
    assert r.demo.pick(r.rects[0], np.zeros((0, 2)), top) == 0
    assert r.demo.pick(r.rects[0], np.zeros((0, 2)), (r.rects[0].x + 2, r.rects[0].y + 2)) is None
    assert r.demo.hold(w, 0, r.rects[0], top) is False and len(w) == n + 1  # poured
    r.demo.hold(w, 0, r.rects[0], top)
    assert len(w) == n + 1  # no room: the ball just poured is still there
    r.act("drop")
    assert len(w) == n + 1 + 12
    for _ in range(120):
        r.update(1 / 60)
    vy = float(np.mean(np.array(w.velocities)[:, 1]))
    r.act("shake")
    assert float(np.mean(np.array(w.velocities)[:, 1])) > vy + 1.0
    r.act("restitution")
    assert w.restitution == 0.2
    r.reset()  # the restitution survives a reset; the balls poured do not
    assert r.panels[0].world.restitution == 0.2 and len(r.panels[0].world) == n


@pytest.mark.parametrize("name", ["boxes", "ramp", "dice", "bridge"])
def test_the_solver_key_cycles_the_contact_solvers(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    import physstep
    from physstep.demos import base

    r = _runner(name)
    names = list(physstep.contact_solvers())
    assert r.panels[0].world.contact_solver == names[0] == r.demo.solver
    r.act("solver")  # the next solver in the registry, shown in the HUD
    assert r.panels[0].world.contact_solver == names[1] == r.demo.solver
    rows = {label: value for label, value, _ in r.demo.hud(r.panels[0])}
    assert rows["solver"] == f"{names[1]} (c)"
    for _ in range(5):
        r.update(1 / 60)  # the demo steps under it
    assert r.panels[0].world.steps > 0
    for _ in names[1:]:
        r.act("solver")  # through the rest and round to the first
    assert r.panels[0].world.contact_solver == names[0] == r.demo.solver
    # With more solvers the key walks the registry in order and wraps round.
    monkeypatch.setattr(physstep, "contact_solvers", lambda: {"a": "", "b": "", "c": ""})

    class Stub:
        contact_solver = "a"

    panels = [base.Panel(Stub(), physstep.method("symplectic-euler"), None)]  # type: ignore[arg-type]
    assert [base.next_contact_solver(s, panels) for s in ("a", "b", "c", "x")] == ["b", "c", "a", "a"]
    assert panels[0].world.contact_solver == "a"


def test_a_loop_change_carries_a_settled_pile_over_bitwise() -> None:
    # A settled pile's balls rest a rounding into each other: the rebuild behind the loop
    # change (the pickle's) takes them as they are, where it stopped the panel.
    r = _runner("pile")
    for _ in range(180):
        r.update(1 / 60)
    before = r.panels[0].world.state_hash()
    r.next_loop()
    p = r.panels[0]
    assert p.error is None
    assert p.world.__reduce__()[1][0]["loop"] == app.LOOPS[1][0] and p.world.state_hash() == before


def test_a_loop_change_a_world_cannot_take_stops_its_panel_in_one_line(monkeypatch) -> None:
    from physstep.demos import base

    def refuse(*_: object) -> None:
        raise ValueError("this World cannot be rebuilt\n(a second line)")

    r = _runner("pile")
    monkeypatch.setattr(base, "relooped", refuse)
    r.next_loop()  # the l key: that panel stops with the reason (r restarts it), not a raise
    p = r.panels[0]
    assert p.error is not None and p.error.startswith("cannot change the loop variant: this World")
    assert "\n" not in p.error
    monkeypatch.undo()
    r.reset()
    assert r.panels[0].error is None and r.panels[0].world.__reduce__()[1][0]["loop"] == app.LOOPS[1][0]


def test_bridge_sags_under_a_heavy_box_and_its_joints_hold() -> None:
    from physstep.demos.bridge import PLANKS, hinges

    r = _runner("bridge")
    w = r.panels[0].world
    assert w.solid_count == PLANKS + 1 and w.joint_count == PLANKS + 1  # the planks, the ground
    for _ in range(600):  # 10 s: swung down from its arc into the catenary, settled
        r.update(1 / 60)
    w = r.panels[0].world
    middle = hinges(w)[PLANKS // 2].copy()
    assert w.kinetic_energy() < 1e-2
    r.act("heavy")
    assert w.solid_count == PLANKS + 2 and r.demo.dropped == [("heavy", (0.6,))]
    worst, heights = 0.0, []
    for frame in range(600):  # 10 s: landed on the middle, the bridge swinging down under it
        r.update(1 / 60)
        worst = max(worst, float(w.joint_errors().max()))
        if frame >= 300:
            heights.append(hinges(w)[PLANKS // 2][1])
    box = w.solid_positions()[-1]
    sag = middle[1] - float(np.mean(heights))  # over its last 5 s of swinging
    assert sag > 0.4, sag  # the middle lower by its load (0.6 m)
    assert abs(box[0] - middle[0]) < 1.0 and box[1] > hinges(w)[PLANKS // 2][1]  # on it, above
    assert worst < 0.02, worst  # the hinges held (soft: 6 mm apart as the box lands)
    rows = {label: value for label, value, _ in r.demo.hud(r.panels[0])}
    assert rows["worst joint"] == f"{float(w.joint_errors().max()) * 1000:.2f} mm"
    assert rows["step"].endswith(" ms")


def test_bridge_click_drops_a_box_or_a_ball_at_the_pointer() -> None:
    r = _runner("bridge")
    rect = r.rects[0]
    at = (rect.centerx + 40, rect.y + 60)
    want = r.demo.to_world(rect, at, 2)
    r.handle(pygame.event.Event(pygame.MOUSEBUTTONDOWN, button=1, pos=at))
    r.update(0.0)  # the frame after the click drops one solid, at rest where it was clicked
    r.update(0.0)  # held down: no second one
    r.handle(pygame.event.Event(pygame.MOUSEBUTTONUP, button=1, pos=at))
    w = r.panels[0].world
    n = w.solid_count
    np.testing.assert_allclose(w.solid_positions()[-1], want)
    assert r.demo.dropped == [("box", (0.45,))]
    r.act("shape")
    r.handle(pygame.event.Event(pygame.MOUSEBUTTONDOWN, button=1, pos=at))
    r.update(0.0)
    r.handle(pygame.event.Event(pygame.MOUSEBUTTONUP, button=1, pos=at))
    assert w.solid_count == n + 1 and r.demo.dropped[-1] == ("ball", (0.4,))
    r.handle(pygame.event.Event(pygame.MOUSEBUTTONDOWN, button=1, pos=(rect.x - 5, rect.y + 5)))
    r.update(0.0)  # outside the panel: nothing
    assert w.solid_count == n + 1
    r.reset()  # a reset starts the bridge bare
    assert r.panels[0].world.solid_count == n - 1 and r.demo.dropped == []


def test_bridge_ragdoll_lands_on_it_in_one_piece() -> None:
    from physstep.demos.bridge import PLANKS, hinges

    r = _runner("bridge")
    for _ in range(600):  # 10 s: settled
        r.update(1 / 60)
    w = r.panels[0].world
    solids, joints = w.solid_count, w.joint_count
    r.act("ragdoll")  # the ragdoll-bodies scene's, its feet 2 m above the middle
    assert (w.solid_count - solids, w.joint_count - joints) == (12, 11)
    assert [k for k, _ in r.demo.dropped].count("capsule") == 11
    worst = 0.0
    for _ in range(360):  # 6 s: fallen onto the bridge, tumbled into its middle
        r.update(1 / 60)
        worst = max(worst, float(w.joint_errors()[joints:].max()))
    assert worst < 0.02, worst  # its hinges held (5 mm at the landing)
    h = hinges(w)
    parts = w.solid_positions()[solids:]
    under = np.interp(parts[:, 0], h[:, 0], h[:, 1])  # the planks' middle line below each part
    assert np.all(parts[:, 1] > under), parts[:, 1] - under  # on the bridge, none through it
    assert np.all(np.abs(parts[:, 0] - h[PLANKS // 2, 0]) < 4.0)


def test_the_solvers_demo_shows_four_solvers_side_by_side_on_the_same_boxes() -> None:
    import physstep

    r = _runner("solvers")
    names = list(physstep.contact_solvers())
    start = ["soft-step", "pgs", "tgs-sticky", "jacobi"]
    assert [p.world.contact_solver for p in r.panels] == start == r.demo.solvers
    for _ in range(3):
        r.update(1 / 60)
    # Each panel's caption names its solver and the passes it made (the same for all).
    assert [r.demo.caption(p)[0] for p in r.panels] == start
    assert all(r.demo.caption(p)[1].startswith("16 passes a step") for p in r.panels)
    n = r.panels[0].world.solid_count
    r.act("drop")  # the same box into every panel
    assert [p.world.solid_count for p in r.panels] == [n + 1] * 4
    r.act("solver")  # every panel on to its next solver
    after = [names[(names.index(s) + 1) % len(names)] for s in start]
    assert [p.world.contact_solver for p in r.panels] == after == r.demo.solvers
    r.reset()  # a reset keeps each panel's solver
    assert [p.world.contact_solver for p in r.panels] == after


def test_boxes_sleep_key_puts_the_resting_pyramid_to_sleep_and_a_dropped_box_wakes_it() -> None:
    r = _runner("boxes")
    rows = {label: value for label, value, _ in r.demo.hud(r.panels[0])}
    assert rows["asleep"] == "off (z)"
    r.act("sleep")
    w = r.panels[0].world
    assert w.sleep_time == 0.5
    for _ in range(150):
        r.update(1 / 60)
    assert w.solids_asleep()[1:].all()
    rows = {label: value for label, value, _ in r.demo.hud(r.panels[0])}
    assert rows["asleep"] == f"{w.solid_count - 1} (z)"
    r.act("drop")
    for _ in range(40):
        r.update(1 / 60)
    assert not w.solids_asleep()[1:].all()
    r.reset()  # sleeping survives a reset
    assert r.panels[0].world.sleep_time == 0.5
    r.act("sleep")
    assert r.panels[0].world.sleep_time == 0.0


def test_dice_sleep_key_puts_the_dice_at_rest_to_sleep_and_a_throw_keeps_it() -> None:
    r = _runner("dice")
    r.act("sleep")
    w = r.panels[0].world
    assert w.sleep_time == 0.5
    for _ in range(240):  # 4 s: the dice are at rest on the plane, asleep
        r.update(1 / 60)
    assert w.solids_asleep()[1:].all() and w.kinetic_energy() == 0.0
    rows = {label: value for label, value, _ in r.demo.hud(r.panels[0])}
    assert rows["asleep"] == f"{w.solid_count - 1} (z)"
    r.act("throw")  # thrown again, still sleeping once at rest
    assert r.panels[0].world.sleep_time == 0.5 and not r.panels[0].world.solids_asleep().any()
    r.act("sleep")
    assert r.panels[0].world.sleep_time == 0.0
