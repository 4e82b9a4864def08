"""Issue 13, item 5: plots of all 14 methods stay readable. Every line is told apart (no
(colour, line style) pair repeated, no colour repeated), titles are not cut at the figure's
edges, tick labels do not overlap, and a quantity spanning decades is on a log axis."""

from __future__ import annotations

import itertools

import numpy as np
import physstep
import pytest
from matplotlib.colors import to_hex
from physstep import lab, plot
from physstep._plotting import COLOURS, LINESTYLES, style

METHODS = [m.name for m in physstep.methods()]


@pytest.fixture(scope="module")
def spring_runs() -> list[physstep.Trajectory]:
    return [physstep.simulate("spring", m, 0.1, 20.0, stop_on_diverge=True) for m in METHODS]


def _method_lines(ax) -> list:
    """The lines drawn for runs: labelled, not the exact solution, E0 or the start marker."""
    skip = ("exact", "E0", "start")
    return [ln for ln in ax.get_lines() if not ln.get_label().startswith(("_", *skip))]


def _assert_told_apart(lines: list, n: int) -> None:
    assert len(lines) == n
    pairs = [(to_hex(ln.get_color()), ln.get_linestyle()) for ln in lines]
    assert len(set(pairs)) == n, pairs
    assert len({c for c, _ in pairs}) == n  # never a repeated colour


def _assert_readable(fig) -> None:
    """Every title inside the figure; no two tick labels of one axis overlapping."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    box = fig.bbox
    for ax in fig.axes:
        title = ax.title
        if title.get_text():
            ext = title.get_window_extent(renderer)
            assert ext.x0 >= box.x0 - 1 and ext.x1 <= box.x1 + 1, title.get_text()
        for axis in (ax.xaxis, ax.yaxis):
            labels = [t for t in axis.get_ticklabels(which="both") if t.get_visible() and t.get_text()]
            exts = sorted((t.get_window_extent(renderer) for t in labels), key=lambda e: (e.x0, e.y0))
            for a, b in itertools.combinations(exts, 2):
                assert not a.overlaps(b), (axis.axis_name, a, b)


def test_the_styles_are_distinct_pairs_with_distinct_colours() -> None:
    pairs = [(style(k)["color"], style(k)["linestyle"]) for k in range(len(COLOURS) * len(LINESTYLES))]
    assert len(set(pairs)) == len(pairs)
    assert len({style(k)["color"] for k in range(len(COLOURS))}) == len(COLOURS) >= len(METHODS)


@pytest.mark.parametrize("kind", ["trajectory", "phase", "energy", "energy_relative"])
def test_all_methods_on_the_spring_are_told_apart(kind: str, spring_runs) -> None:
    if kind == "energy_relative":
        fig = plot.energy(spring_runs, relative=True)
    else:
        fig = getattr(plot, kind)(spring_runs)
    _assert_told_apart(_method_lines(fig.axes[0]), len(METHODS))
    _assert_readable(fig)
    if kind == "energy_relative":  # explicit Euler ~1, implicit midpoint ~1e-15: decades apart
        assert fig.axes[0].get_yscale() == "log"


def test_the_orbit_and_lorenz_paths_of_every_method_are_told_apart() -> None:
    runs = [physstep.simulate("orbit", m, 0.1, 10.0, stop_on_diverge=True) for m in METHODS]
    fig = plot.orbit(runs)
    _assert_told_apart(_method_lines(fig.axes[0]), len(METHODS))
    _assert_readable(fig)
    flows = [m for m in METHODS if not physstep.method(m).split]
    fig = plot.path3d([physstep.simulate("lorenz", m, 0.01, 2.0) for m in flows])
    _assert_told_apart(_method_lines(fig.axes[0]), len(flows))


def test_work_precision_of_every_method_is_told_apart_on_readable_log_axes() -> None:
    data = lab.sweep("spring", "all", [0.2, 0.1, 0.05], until=5.0)
    fig = plot.work_precision(data, against="both")
    for ax in fig.axes[:2]:
        lines = _method_lines(ax)
        _assert_told_apart(lines, len(METHODS))
        assert len({ln.get_marker() for ln in lines}) > 1
        assert ax.get_xscale() == ax.get_yscale() == "log"
    _assert_readable(fig)


def test_spin_errors_of_every_method_are_told_apart() -> None:
    methods = [m for m in METHODS if not physstep.method(m).vector_positions]
    runs = [physstep.simulate("racket", m, 1 / 60, 5.0, stop_on_diverge=True) for m in methods]
    fig = plot.spin(runs)
    for ax in fig.axes[-2:]:
        _assert_told_apart(_method_lines(ax), len(methods))
    assert np.isfinite(fig.get_size_inches()).all()


def _contrast_on_white(colour: str) -> float:
    """WCAG contrast ratio of ``colour`` on the white background (1 to 21)."""
    from matplotlib.colors import to_rgb

    lin = [c / 12.92 if c <= 0.03928 else ((c + 0.055) / 1.055) ** 2.4 for c in to_rgb(colour)]
    return 1.05 / (0.2126 * lin[0] + 0.7152 * lin[1] + 0.0722 * lin[2] + 0.05)


def test_no_line_colour_is_a_pale_pastel() -> None:
    # tab20's light halves (#aec7e8 1.7, #ffbb78 1.7, #98df8a 1.6) drew the last methods of the
    # registry, backward Euler and predictor-corrector among them, faint on white
    weakest = min(COLOURS, key=_contrast_on_white)
    assert _contrast_on_white(weakest) >= 2.0, weakest


def test_orbit_draws_the_paths_that_leave_the_pack_strong_and_its_title_lists_no_methods() -> None:
    until = 3 * 2 * np.pi
    runs = [physstep.simulate("orbit", m, 0.1, until, stop_on_diverge=True) for m in METHODS]
    fig = plot.orbit(runs)
    ax = fig.axes[0]
    assert ax.get_title() == "path: orbit, dt = 0.1 s"  # the legend names the methods, not the title
    lines = {ln.get_label().split(" (")[0]: ln for ln in _method_lines(ax)}
    wide = {name for name, ln in lines.items() if ln.get_linewidth() == plot.LEAVING_WIDTH}
    # explicit Euler spirals out, backward Euler in, predictor-corrector and linearly implicit
    # Euler are flung away
    assert wide == {"explicit-euler", "backward-euler", "linearly-implicit-euler", "predictor-corrector"}
    for name in wide:
        assert _contrast_on_white(to_hex(lines[name].get_color())) >= 3.0, name
        assert lines[name].get_zorder() > lines["rk4"].get_zorder()
    assert lines["rk4"].get_linewidth() == 1.2


def test_a_path_flung_far_away_runs_out_of_a_view_that_frames_the_others() -> None:
    # Linearly implicit Euler at dt = 0.1 is flung about 30 km out of the 1 m orbit: the view
    # frames the other paths (predictor-corrector's 25 m excursion included) and the legend
    # says which path leaves it; without it, no view is set.
    until = 3 * 2 * np.pi
    runs = [physstep.simulate("orbit", m, 0.1, until, stop_on_diverge=True) for m in METHODS]
    ax = plot.orbit(runs).axes[0]
    leaving = [ln.get_label() for ln in _method_lines(ax) if "leaves the view" in ln.get_label()]
    assert leaving == ["linearly-implicit-euler (leaves the view)"]
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    assert max(abs(x0), abs(x1), abs(y0), abs(y1)) < plot.VIEW_FACTOR * 1.05
    assert x0 < -10 and y0 < -20  # predictor-corrector's excursion stays in view
    kept = [r for r in runs if r.method != "linearly-implicit-euler"]
    ax = plot.orbit(kept).axes[0]
    assert not any("leaves the view" in ln.get_label() for ln in _method_lines(ax))


@pytest.mark.parametrize("kind", ["trajectory", "phase", "energy"])
def test_titles_are_one_line_naming_no_method(spring_runs, kind: str) -> None:
    fig = getattr(plot, kind)(spring_runs)
    title = fig.axes[0].get_title()
    assert "\n" not in title and not any(m in title for m in METHODS), title
