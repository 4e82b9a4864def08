"""Output files (``run --out``, ``sweep --out``, every ``--plot``): checked before the
computation, written whole or not at all, never the scene file read nor another output's
file, a failure one line naming the flag and the path; stdout that cannot be written is one
line naming stdout."""

from __future__ import annotations

import errno
import os
import subprocess
import sys
from pathlib import Path

import physstep
import pytest
from conftest import run_cli
from physstep import _files as files
from physstep import cli, lab, plot


def _bad_path(tmp_path: Path, kind: str, ext: str) -> tuple[str, str]:
    """A path that cannot be written, and the reason the error must give."""
    if kind == "directory":
        directory = tmp_path / f"dir{ext}"
        directory.mkdir()
        return str(directory), "is a directory"
    if kind == "below a regular file":
        regular = tmp_path / "regular.txt"
        regular.write_text("not a directory\n")
        return str(regular / f"x{ext}"), "Not a directory"
    return str(tmp_path / "nope" / f"x{ext}"), "No such file or directory"


COMMANDS = [
    ("--out", ["run", "spring", "--dt", "0.5", "--until", "1"], ".csv"),
    ("--out", ["sweep", "spring", "--methods", "rk4", "--dts", "0.5", "--until", "1"], ".csv"),
    ("--plot", ["compare", "spring", "--methods", "rk4", "--dt", "0.5", "--until", "1"], ".png"),
    ("--plot", ["sweep", "spring", "--methods", "rk4", "--dts", "0.5", "--until", "1"], ".svg"),
]


@pytest.mark.parametrize(("flag", "args", "ext"), COMMANDS)
@pytest.mark.parametrize("kind", ["directory", "below a regular file", "missing parent"])
def test_unwritable_output_is_one_line_naming_flag_and_path(tmp_path, flag, args, ext, kind) -> None:
    path, reason = _bad_path(tmp_path, kind, ext)
    res = run_cli(*args, flag, path)
    assert res.returncode == 2, res.stderr
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1, res.stderr
    assert lines[0].startswith(f"physstep: error: invalid {flag} '{path}': ")
    assert reason in lines[0]
    assert res.stdout == ""


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full")
@pytest.mark.parametrize("args", [COMMANDS[0][1], COMMANDS[1][1]])
def test_out_to_dev_full_is_exit_2(args: list[str]) -> None:
    res = run_cli(*args, "--out", "/dev/full")
    assert res.returncode == 2
    assert res.stderr == "physstep: error: invalid --out '/dev/full': No space left on device\n"


def test_out_to_dev_stdout_writes_through_the_device() -> None:
    res = run_cli("run", "spring", "--dt", "0.5", "--until", "1", "--out", "/dev/stdout", "--format", "json")
    assert res.returncode == 0, res.stderr
    assert res.stdout.startswith("t,x,v,a,energy\n0.0,20.0,0.0,-10.0,1000.0\n")


@pytest.mark.parametrize(
    "command",
    [
        lambda p: ["run", "spring", "--out", p],
        lambda p: ["sweep", "spring", "--dts", "0.1", "--out", p],
        lambda p: ["compare", "spring", "--plot", p],
        lambda p: ["sweep", "spring", "--dts", "0.1", "--plot", p],
    ],
)
def test_output_is_checked_before_the_computation(tmp_path, monkeypatch, capsys, command) -> None:
    def ran(*args, **kwargs):
        raise AssertionError("the computation ran before --out/--plot was checked")

    monkeypatch.setattr(physstep, "simulate", ran)
    monkeypatch.setattr(lab, "compare", ran)
    monkeypatch.setattr(lab, "sweep", ran)
    bad = str(tmp_path / "missing" / "f.png")
    assert cli.main(command(bad)) == 2
    assert f"'{bad}'" in capsys.readouterr().err


def _limited(limit: int):
    def set_limit() -> None:
        import resource

        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

    return set_limit


@pytest.mark.skipif(sys.platform == "win32", reason="RLIMIT_FSIZE is POSIX")
@pytest.mark.parametrize(
    ("flag", "args", "name"),
    [
        ("--out", ["run", "spring", "--dt", "0.01", "--until", "20"], "traj.csv"),
        ("--out", ["sweep", "spring", "--dts", "0.1,0.05", "--until", "2", "--format", "json"], "s.json"),
        ("--plot", ["sweep", "spring", "--methods", "rk4", "--dts", "0.1", "--until", "2"], "wp.png"),
    ],
)
def test_failed_write_keeps_the_old_file(tmp_path, flag, args, name) -> None:
    # a file-size limit of 4 kB: the write fails with EFBIG (Python ignores SIGXFSZ)
    target = tmp_path / name
    target.write_text("the old file\n")
    env = dict(os.environ, MPLBACKEND="Agg")
    res = subprocess.run(
        [sys.executable, "-m", "physstep", *args, flag, str(target)],
        capture_output=True,
        text=True,
        env=env,
        preexec_fn=_limited(4096),
        timeout=300,
    )
    assert res.returncode == 2, res.stderr
    assert res.stderr == f"physstep: error: invalid {flag} '{target}': File too large\n"
    assert target.read_text() == "the old file\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == [name]  # no temporary file left


def test_failed_fsync_keeps_the_old_file_in_process(tmp_path, monkeypatch, capsys) -> None:
    target = tmp_path / "traj.csv"
    target.write_text("old\n")

    def full(fd: int) -> None:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(os, "fsync", full)
    assert cli.main(["run", "spring", "--out", str(target)]) == 2
    assert capsys.readouterr().err == f"physstep: error: invalid --out '{target}': No space left on device\n"
    assert target.read_text() == "old\n"
    assert [p.name for p in tmp_path.iterdir()] == ["traj.csv"]
    fig = plot.trajectory(physstep.simulate("spring", "rk4", 0.5, 1.0))
    with pytest.raises(ValueError, match="No space left on device"):
        plot.save(fig, target.with_suffix(".png"))
    assert [p.name for p in tmp_path.iterdir()] == ["traj.csv"]


def test_write_replaces_whole_files_and_keeps_links_and_modes(tmp_path) -> None:
    real = tmp_path / "real.csv"
    real.write_text("old\n")
    real.chmod(0o640)
    link = tmp_path / "link.csv"
    link.symlink_to(real)
    files.write_text(str(link), "new\n", "--out")
    assert link.is_symlink() and real.read_text() == "new\n"
    assert real.stat().st_mode & 0o777 == 0o640
    fresh = tmp_path / "fresh.csv"
    files.write_text(str(fresh), "x\n", "--out")
    umask = os.umask(0)
    os.umask(umask)
    assert fresh.stat().st_mode & 0o777 == 0o666 & ~umask  # not mkstemp's 0600
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fresh.csv", "link.csv", "real.csv"]


def _scene_file(tmp_path: Path) -> Path:
    path = tmp_path / "cloth.toml"
    path.write_text(physstep.export_scene("spring"))
    return path


@pytest.mark.parametrize("link", ["same", "relative", "symlink", "hardlink"])
def test_an_output_that_is_the_scene_file_read_is_refused_and_the_file_kept(
    tmp_path: Path, link: str
) -> None:
    scene = _scene_file(tmp_path)
    before = scene.read_bytes()
    out = {
        "same": scene,
        "relative": tmp_path / "." / "cloth.toml",
        "symlink": tmp_path / "link.csv",
        "hardlink": tmp_path / "hard.csv",
    }[link]
    if link == "symlink":
        out.symlink_to(scene)
    elif link == "hardlink":
        os.link(scene, out)
    res = run_cli("run", str(scene), "--until", "1", "--out", str(out))
    assert res.returncode == 2
    assert res.stderr == (
        f"physstep: error: invalid --out '{out}': is the scene file read ('{scene}'); write to another file\n"
    )
    assert res.stdout == ""
    assert scene.read_bytes() == before


@pytest.mark.parametrize(
    "args",
    [
        [
            "sweep",
            "spring",
            "--methods",
            "rk4",
            "--dts",
            "0.5",
            "--until",
            "1",
            "--out",
            "{p}",
            "--plot",
            "{p}",
        ],
        [
            "sweep",
            "spring",
            "--methods",
            "rk4",
            "--dts",
            "0.5",
            "--until",
            "1",
            "--plot",
            "{p}",
            "--out",
            "{p}",
        ],
    ],
    ids=["out-then-plot", "plot-then-out"],
)
def test_two_outputs_on_one_path_are_refused_and_the_file_kept(tmp_path: Path, args: list[str]) -> None:
    path = tmp_path / "s.png"
    path.write_bytes(b"the user's plot")
    res = run_cli(*[str(path) if a == "{p}" else a for a in args])
    assert res.returncode == 2
    assert res.stderr == (
        f"physstep: error: invalid --plot '{path}': is also --out ('{path}'); give each output its own file\n"
    )
    assert path.read_bytes() == b"the user's plot"


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full")
@pytest.mark.parametrize(
    "args",
    [
        ["run", "spring", "--dt", "0.5", "--until", "1"],
        ["table", "spring", "--dt", "0.001", "--until", "10"],
        ["scenes", "--format", "json"],
    ],
    ids=["run", "table", "scenes"],
)
def test_stdout_that_cannot_be_written_is_one_line_naming_stdout(args: list[str]) -> None:
    env = dict(os.environ, MPLBACKEND="Agg", COLUMNS="200")
    with open("/dev/full", "w") as full:
        res = subprocess.run(
            [sys.executable, "-m", "physstep", *args], stdout=full, stderr=subprocess.PIPE, text=True, env=env
        )
    assert res.returncode == 2
    assert res.stderr == "physstep: error: cannot write to stdout: No space left on device\n"


def test_stdout_past_the_file_size_limit_is_one_line_naming_stdout(tmp_path: Path) -> None:
    import resource

    def limit() -> None:
        resource.setrlimit(resource.RLIMIT_FSIZE, (1000, 1000))

    env = dict(os.environ, MPLBACKEND="Agg")
    with open(tmp_path / "out.txt", "w") as fh:
        res = subprocess.run(
            [sys.executable, "-m", "physstep", "table", "spring", "--dt", "0.001", "--until", "10"],
            stdout=fh,
            stderr=subprocess.PIPE,
            text=True,
            env=env,
            preexec_fn=limit,
        )
    assert res.returncode == 2
    assert res.stderr == "physstep: error: cannot write to stdout: File too large\n"
