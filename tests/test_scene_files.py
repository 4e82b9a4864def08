"""Scene files at the boundary: physstep.load_scene and SceneFile, export of every built-in
scene (loading it gives bitwise the built-in trajectory), the command line's run, compare
and scenes --export on a file, and bad files as one-line ValueErrors and exit status 2
(tests/test_scene_fuzz.py fuzzes load_scene)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import physstep
import pytest
from conftest import run_cli


def _write(tmp_path: Path, text: str, name: str = "s.toml") -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


@pytest.mark.parametrize("name", [s["name"] for s in physstep.scenes()])
def test_every_exported_scene_loads_back_bitwise(tmp_path: Path, name: str) -> None:
    params = {"n": 5.0} if name == "stiff-cloth" else None
    text = physstep.export_scene(name, params)
    loaded = physstep.load_scene(_write(tmp_path, text))
    spec = physstep.scene(name)
    method = loaded.method
    built = physstep.World.from_scene(name, method, spec["dt"], params or {})
    assert loaded.state_hash() == built.state_hash()
    loaded.step(50)
    built.step(50)
    assert loaded.state_hash() == built.state_hash()
    assert (
        physstep.scene_text(physstep.load_scene(tmp_path / "s.toml"), f"{name}: {spec['doc']}", spec["until"])
        == text
    )


def test_a_scene_file_is_a_system_for_simulate_and_the_lab(tmp_path: Path) -> None:
    p = _write(tmp_path, physstep.export_scene("spring"), "spring.toml")
    sf = physstep.SceneFile(p)
    assert (sf.name, sf.dt, sf.until) == ("spring", 0.1, 20.0)
    a = physstep.simulate(sf, "symplectic-euler", sf.dt, 2.0)
    b = physstep.simulate("spring", "symplectic-euler", 0.1, 2.0)
    assert a.scene == "spring"
    assert (a.x == b.x).all() and (a.v == b.v).all()


def test_cli_runs_and_compares_a_scene_file(tmp_path: Path) -> None:
    out = tmp_path / "orbit.toml"
    res = run_cli("scenes", "--export", "orbit", "--out", str(out))
    assert res.returncode == 0, res.stderr
    assert out.read_text().startswith("# orbit: ")
    res = run_cli("run", str(out), "--until", "1", "--format", "json")
    assert res.returncode == 0, res.stderr
    file_run = json.loads(res.stdout)
    builtin = json.loads(run_cli("run", "orbit", "--until", "1", "--format", "json").stdout)
    assert file_run["final"] == builtin["final"]
    assert file_run["steps"] == 100
    res = run_cli(
        "compare", str(out), "--methods", "symplectic-euler,rk4", "--until", "1", "--format", "json"
    )
    assert res.returncode == 0, res.stderr
    # stdout of --export without --out is the file itself.
    assert run_cli("scenes", "--export", "orbit").stdout == out.read_text()


BAD = {
    "empty": ("", "s.toml:1: dimension: is missing"),
    "not toml": ("dimension = 2\nthis is not toml\n", "s.toml:2: not valid TOML"),
    "wrong type": ('dimension = 2\ndt = "fast"\n', "s.toml:2: dt: is string: must be a number"),
    "negative mass": (
        "dimension = 1\n[[particles]]\nposition = [0.0]\nmass = -2.0\n",
        "particles[0]: invalid mass = -2",
    ),
    "unknown key": (
        "dimension = 1\n[[particles]]\npositon = [0.0]\n",
        "s.toml:3: particles[0].positon: unknown key",
    ),
    "missing particle": (
        "dimension = 2\n[[particles]]\nposition = [0.0, 0.0]\n[[springs]]\ni = 0\nj = 3\nstiffness = 1.0\n",
        "s.toml:4: springs[0]: invalid j = 3: must be a particle index < 1",
    ),
    "open mesh": (
        "dimension = 3\n[[bodies]]\nmass = 1.0\n"
        'shape = { kind = "mesh", vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], '
        "triangles = [[0, 2, 1], [0, 1, 3]] }\n",
        "s.toml:4: bodies[0].shape: invalid triangles = 2 triangles",
    ),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_files_are_one_line_value_errors_and_cli_exit_2(tmp_path: Path, case: str) -> None:
    text, want = BAD[case]
    p = _write(tmp_path, text)
    with pytest.raises(ValueError) as e:
        physstep.load_scene(p)
    msg = str(e.value)
    assert msg.startswith(f"scene file {p}"), msg
    assert want in msg, msg
    assert "\n" not in msg
    res = run_cli("run", str(p), "--until", "1")
    assert res.returncode == 2
    assert res.stderr == f"physstep: error: {msg}\n"


def test_cli_refuses_params_and_a_missing_until(tmp_path: Path) -> None:
    p = _write(tmp_path, "dimension = 1\ndt = 0.1\n[[particles]]\nposition = [1.0]\n")
    res = run_cli("run", str(p))
    assert res.returncode == 2
    assert "has no until" in res.stderr and res.stderr.count("\n") == 1
    res = run_cli("run", str(p), "--until", "1", "--param", "k=2")
    assert res.returncode == 2
    assert "a scene file has no parameters" in res.stderr
    assert run_cli("run", str(tmp_path / "missing.toml")).stderr.startswith("physstep: error: scene file ")


def test_a_world_with_a_python_force_cannot_be_exported() -> None:
    w = physstep.World(1)
    w.add_particle([1.0])
    w.add_force(lambda t, x, v: -x)
    with pytest.raises(ValueError, match="cannot be exported"):
        physstep.scene_text(w)


def test_a_path_that_is_not_a_path_is_named() -> None:
    with pytest.raises(ValueError, match="invalid path = 3"):
        physstep.load_scene(3)  # type: ignore[arg-type]


def test_the_readme_example_runs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    text = (Path(__file__).parent.parent / "README.md").read_text()
    section = text[text.index("### Scene files") :]
    start = section.index("```sh") + len("```sh")
    for line in section[start : section.index("```", start)].strip().splitlines():
        argv = line.split("#")[0].split()
        assert argv[0] == "physstep"
        monkeypatch.chdir(tmp_path)
        res = run_cli(*argv[1:])
        assert res.returncode == 0, res.stderr
    start = section.index("```python") + len("```python")
    scope: dict[str, object] = {"physstep": physstep}
    exec(compile(section[start : section.index("```", start)], "README.md", "exec"), scope)  # noqa: S102
    assert len(scope["world"]) == 11  # type: ignore[arg-type]


@pytest.mark.parametrize("name", [s["name"] for s in physstep.scenes()])
def test_the_example_files_are_the_exported_scenes(name: str) -> None:
    """examples/scenes/NAME.toml is `physstep scenes --export NAME`: regenerate them with
    `for s in ...; do physstep scenes --export $s --out examples/scenes/$s.toml; done`."""
    path = Path(__file__).parent.parent / "examples" / "scenes" / f"{name}.toml"
    assert path.read_text() == physstep.export_scene(name)


def _limit_memory() -> None:
    """For ``preexec_fn``: 4 GiB of address space, so that a loader reading an endless file
    fails in the child instead of exhausting the machine."""
    import resource

    resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="FIFOs and /dev/zero are POSIX")
@pytest.mark.parametrize("kind", ["fifo", "/dev/zero", "/dev/urandom", "directory"])
def test_a_scene_file_that_is_not_a_regular_file_is_refused_before_it_is_read(
    tmp_path: Path, kind: str
) -> None:
    # A FIFO used to block the open forever (Ctrl-C ignored); /dev/zero and /dev/urandom,
    # 0 bytes long by their metadata, were read until the memory ran out.
    path = tmp_path / "s.toml"
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "directory":
        path.mkdir()
    else:
        if not os.path.exists(kind):
            pytest.skip(f"no {kind}")
        path.symlink_to(kind)
    what = "a directory" if kind == "directory" else "a device, a FIFO or a socket"
    want = f"scene file {path}: is {what}, not a regular file"
    code = (
        "import sys, physstep\n"
        "try:\n"
        "    physstep.load_scene(sys.argv[1])\n"
        "except ValueError as e:\n"
        "    print(e)\n"
    )
    env = dict(os.environ, MPLBACKEND="Agg")
    for argv in (
        [sys.executable, "-c", code, str(path)],
        [sys.executable, "-m", "physstep", "run", str(path)],
    ):
        res = subprocess.run(
            argv, capture_output=True, text=True, env=env, timeout=60, preexec_fn=_limit_memory
        )
        if argv[1] == "-c":
            assert res.returncode == 0 and res.stdout == f"{want}\n", res.stderr
        else:
            assert res.returncode == 2
            assert res.stderr == f"physstep: error: {want}\n"
            assert res.stdout == ""
