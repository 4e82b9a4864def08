"""Writes docs/solvers.md: every contact solver on every contact scene (the solver lab's table).

    python scripts/solver_table.py                # every scene with solids, every solver
    python scripts/solver_table.py --until 2 --scenes pyramid,ramp --out /tmp/t.md

Each scene runs under each solver at the world's default settings (8 substeps x 1 iteration:
16 passes over the contacts a step for every solver, counted) through
``physstep.lab.compare_solvers``; each cell gives the verdict and the measures it rests on.
The whole table takes a few minutes on a 2-core machine. The file is written whole or not at
all.
"""

from __future__ import annotations

import argparse
import platform
import sys
import time
from collections import Counter
from pathlib import Path

import physstep
from physstep import _files as files
from physstep import lab
from physstep.lab import solvers as solver_lab

ROOT = Path(__file__).resolve().parents[1]

#: Scenes run again with other parameters: the ramp below its friction angle (the friction
#: test against the closed form), and the 30-link ball chain with a ball 100 times as heavy
#: as a link (radius 2.744 m against links of 0.2366 m^2, the same density).
VARIANTS = {"ramp": [{"friction": 0.3}], "ball-chain": [{"radius": 2.744}]}


def contact_scenes() -> list[str]:
    """The built-in scenes whose worlds have solids, in registry order."""
    out = []
    for s in physstep.scenes():
        if s["dim"] in (2, 3) and physstep.World.from_scene(s["name"]).solid_count > 0:
            out.append(s["name"])
    return out


def mm(x: float | None) -> str:
    return "-" if x is None else f"{1e3 * x:.3g}"


def cell(r: lab.SolverRow) -> str:
    """One table cell: the verdict, then drift / penetration (deepest, and in the last second:
    mm), joint error, friction error."""
    parts = [f"**{r.verdict}**", f"{mm(r.drift)} / {mm(r.max_penetration)} ({mm(r.settled_penetration)})"]
    if r.joint_error is not None:
        parts.append(f"j {mm(r.joint_error)}")
    if r.friction_error is not None:
        parts.append(f"f {r.friction_error:+.1e}")
    if r.diverged:
        parts.append(f"failed at step {r.steps + 1}")
    return " ".join(parts)


def table(scenes: list[str], until: float | None) -> tuple[str, Counter, dict[str, list[float]]]:
    """The markdown rows, the verdict counts per solver, and each solver's ms a step per run."""
    names = [s.name for s in physstep.solvers()]
    head = "| scene | " + " | ".join(f"`{n}`" for n in names) + " |"
    lines = [head, "|" + "---|" * (len(names) + 1)]
    counts: Counter = Counter()
    ms: dict[str, list[float]] = {n: [] for n in names}
    passes: set[float] = set()
    for scene in scenes:
        for params in [None, *VARIANTS.get(scene, [])]:
            res = lab.compare_solvers(scene, names, until, params)
            label = scene + (
                "" if params is None else " " + ", ".join(f"{k}={v:g}" for k, v in params.items())
            )
            own = {r.passes_per_step for r in res.rows}
            if own != {16.0}:  # a scene that sets its own substeps or iterations
                label += " (" + ", ".join(f"{p:g}" for p in sorted(own)) + " passes)"
            lines.append(f"| {label} | " + " | ".join(cell(r) for r in res.rows) + " |")
            for r in res.rows:
                counts[(r.solver, r.verdict)] += 1
                ms[r.solver].append(r.ms_per_step)
                passes.add(round(r.passes_per_step, 6))
            print(f"{label}: " + ", ".join(f"{r.solver} {r.verdict}" for r in res.rows), file=sys.stderr)
    return "\n".join(lines), counts, {"passes": sorted(passes), **ms}


def summary(counts: Counter) -> str:
    names = [s.name for s in physstep.solvers()]
    verdicts = ["stands", "sags", "falls", "holds", "drifts", "explodes"]
    lines = ["| solver | " + " | ".join(verdicts) + " |", "|" + "---|" * (len(verdicts) + 1)]
    for n in names:
        lines.append(f"| `{n}` | " + " | ".join(str(counts[(n, v)]) for v in verdicts) + " |")
    return "\n".join(lines)


#: Where the README keeps the summary the full table writes.
README_MARKS = ("<!-- solver-summary: written by scripts/solver_table.py -->", "<!-- end solver-summary -->")


def with_summary(readme: str, block: str) -> str:
    """``readme`` with the text between :data:`README_MARKS` replaced by ``block``."""
    start, end = README_MARKS
    i, j = readme.find(start), readme.find(end)
    if i < 0 or j < i:
        raise ValueError(f"the README has no {start} ... {end} block")
    return readme[: i + len(start)] + "\n" + block + "\n" + readme[j:]


#: The scene of the page's figure: every solver over splits of its passes.
SWEEP_SCENE = "stack"


def sweep_section(figure: Path, page: Path) -> str:
    """Runs every solver over the default splits on :data:`SWEEP_SCENE`, writes the figure
    (whole or not at all) and returns the page's section on it."""
    from physstep import plot

    names = [s.name for s in physstep.solvers()]
    res = lab.sweep_solvers(SWEEP_SCENE, names)
    fig = plot.solver_sweep(res)
    files.write(str(figure), lambda fh: fig.savefig(fh, format="png", dpi=110), "--figure")
    soft = [r for r in res.rows if r.solver == "soft-step"]
    verdicts = ", ".join(f"{r.substeps} x {r.iterations} {r.verdict} ({1e3 * r.drift:.3g} mm)" for r in soft)
    rel = Path(figure).resolve().relative_to(page.resolve().parent)
    splits = ", ".join(f"{n} x {k}" for n, k in lab.solvers.DEFAULT_SPLITS)
    return f"""## Substeps or iterations?

The same 16 passes a step split into substeps x iterations ({splits}) on `{SWEEP_SCENE}`
(`physstep sweep {SWEEP_SCENE} --solvers all --plot FILE.png`, `physstep.lab.sweep_solvers`):
the soft step: {verdicts}. Every other solver lays its passes out by their number alone
(`2 x substeps x iterations`: one step of them, or as many substeps of one pass), so every
split is the same run for it (the flat lines).

![Every solver over splits of 16 passes a step on the stack]({rel})
"""


def document(scenes: list[str], until: float | None, sweep: str = "") -> tuple[str, str]:
    """The whole page (with ``sweep``, the figure's section, at its end) and its summary table."""
    start = time.perf_counter()
    rows, counts, ms = table(scenes, until)
    took = time.perf_counter() - start
    names = [s.name for s in physstep.solvers()]
    passes = ms.pop("passes")
    cost = " | ".join(f"`{n}` {sum(ms[n]):.0f}" for n in names)
    standing = ", ".join(sorted(solver_lab.STANDING))
    brief = summary(counts)
    infos = "\n".join(f"- `{s.name}` ({s.family}): {s.summary}." for s in physstep.solvers())
    return (
        brief,
        f"""# The contact solvers, side by side

Generated by `python scripts/solver_table.py` (do not edit by hand): every contact solver on
every built-in scene with solids, each at the scene's step, its contact settings (the world's
default 8 substeps x 1 iteration unless the scene sets its own) and {
            "its own duration" if until is None else f"{until:g} s"
        }. On a scene every solver made the same passes over the contacts a step,
counted as they ran (equal cost, measured): 16, or as many as a scene that sets its own says
beside its name (all: {", ".join(f"{p:g}" for p in passes)}). The same run from Python:
`physstep.lab.compare_solvers(scene)`; from the command line: `physstep compare SCENE
--solvers all`.

The solvers (`physstep solvers`):

{infos}

Each cell: the **verdict**, then the tracked solid's drift / the deepest penetration over the
run (in brackets: over its last second), mm; `j` the largest joint error (mm) where the scene
has joints; `f` the friction test's relative error where the ramp slides. The tracked solid is
the dynamic solid highest when the run starts (the top box of a stack or a pyramid).
Verdicts ({solver_lab.__name__}): {solver_lab.THRESHOLDS}. The standing scenes:
{standing}.

{rows}

## Summary

{brief}

Wall time a step summed over the scenes, ms (one run each, {platform.machine()}, {took:.0f} s for
the whole table; timings move by 30% between runs on this 2-core machine): {cost}.
{sweep}""",
    )


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", default=str(ROOT / "docs" / "solvers.md"))
    p.add_argument(
        "--until", type=float, default=None, help="end time of every run, s (default: each scene's)"
    )
    p.add_argument("--scenes", default=None, help="comma-separated scenes (default: every scene with solids)")
    p.add_argument(
        "--readme",
        default=None,
        help="also write the summary into this README's solver-summary block (default: the repository's "
        "README when the whole table is made: no --scenes, no --until)",
    )
    p.add_argument(
        "--figure",
        default=None,
        help="also sweep every solver over splits of its passes and plot it here (default: "
        "docs/figures/solver_sweep.png when the whole table is made)",
    )
    args = p.parse_args(argv)
    scenes = contact_scenes() if args.scenes is None else args.scenes.split(",")
    readme, figure = args.readme, args.figure
    if args.scenes is None and args.until is None:
        readme = readme or str(ROOT / "README.md")
        figure = figure or str(ROOT / "docs" / "figures" / "solver_sweep.png")
    files.check(args.out, "--out")
    if readme is not None:
        with_summary(Path(readme).read_text(), "")  # the block is there, before any run
        files.check(readme, "--readme")
    if figure is not None:
        files.check(figure, "--figure")
    sweep = "" if figure is None else "\n" + sweep_section(Path(figure), Path(args.out))
    brief, text = document(scenes, args.until, sweep)
    files.write_text(args.out, text, "--out")
    print(f"wrote {args.out}", file=sys.stderr)
    if readme is not None:
        files.write_text(readme, with_summary(Path(readme).read_text(), brief), "--readme")
        print(f"wrote the summary into {readme}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
