# SPDX-License-Identifier: Apache-2.0
"""The plots (interp/plot.py and its callers), Python only: golden models, no simulator.

Each test makes the figure the command makes and reads it back: the file is a
PNG, the axes are labelled with their units, the path is drawn in the user's
coordinates and the deviation panel's legend names the largest deviation,
which must equal the one computed here from the steps.
"""
from __future__ import annotations

import math

import matplotlib.pyplot as plt
import numpy as np
import pytest

from interp.plots import paths as plot
from interp.cli import main
from interp.commands import gcode
from interp.cores import REGISTRY, load_all

load_all()
PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture
def figures(monkeypatch):
    """The figures the code under test closes (i.e. has finished), newest last."""
    made = []
    close = plt.close

    def keep(fig=None):
        if fig is not None:
            made.append(fig)
        close(fig)

    monkeypatch.setattr(plot.plt, "close", keep)
    return made


def panels(fig):
    """(path axes, deviation axes) of a plot_path figure."""
    axes = [ax for ax in fig.axes if ax.get_ylabel()]
    path = next(ax for ax in axes if ax.get_xlabel().startswith("X ("))
    dev = next(ax for ax in axes if ax.get_ylabel().startswith("deviation"))
    return path, dev


def legend_texts(ax):
    legend = ax.get_legend()
    return [t.get_text() for t in legend.get_texts()] if legend else []


def check(fig, unit="steps"):
    """Labels, band and max-deviation legend of one figure; returns the legend's max |d|."""
    path, dev = panels(fig)
    assert path.get_xlabel() == f"X ({unit})" and path.get_ylabel() == f"Y ({unit})"
    assert dev.get_xlabel() == "step number" and dev.get_ylabel() == "deviation (steps)"
    texts = legend_texts(dev)
    assert any("±0.5 step band" in t for t in texts), texts
    found = [t for t in texts if "max |d| =" in t]
    assert found, f"no maximum deviation in the legend: {texts}"
    assert any("programmed path" in t for t in legend_texts(path))
    for text in [fig._suptitle] + [ax.title for ax in fig.axes]:
        if text is not None and text.get_text():
            assert all(len(line) <= 120 for line in text.get_text().splitlines()), "title not wrapped"
    return float(found[0].split("max |d| =")[1].split()[0])


def test_deviation_of_points_from_a_line_and_a_polyline():
    d = plot.deviations([(0, 1), (5, -2), (10, 0), (12, 0)], [(0, 0), (10, 0)])
    assert np.allclose(d, [1, -2, 0, 2])
    square = [(0, 0), (4, 0), (4, 4)]
    assert np.allclose(plot.deviations([(2, 0.5), (3.5, 2)], square), [0.5, 0.5])


def test_plot_path_writes_png_with_units_and_max_deviation(tmp_path):
    steps = [(k, 1, k % 2) for k in range(10)]
    out = tmp_path / "p.png"
    worst = plot.plot_path(out, steps, [(0, 0), (10, 5)], title="a line")
    assert out.read_bytes()[:8] == PNG
    pts = plot.positions(steps)
    expect = max(abs(p[0] * 5 - p[1] * 10) / math.hypot(10, 5) for p in pts)
    assert worst == pytest.approx(expect)
    fig, worst2 = plot.path_figure(steps, [(0, 0), (10, 5)], title="a line")
    assert check(fig) == pytest.approx(expect, abs=5e-4) and worst2 == worst
    plt.close(fig)


def test_long_title_is_wrapped():
    fig, _ = plot.path_figure([(0, 1, 0)], [(0, 0), (1, 0)], title="word " * 80)
    assert len(fig._suptitle.get_text().splitlines()) > 1
    plt.close(fig)


def test_long_path_has_inset_and_ideal_on_top():
    steps = [(k, 1, 1 if k % 3 == 0 else 0) for k in range(600)]
    fig, _ = plot.path_figure(steps, [(0, 0), (600, 200)])
    path, _ = panels(fig)
    assert path.child_axes, "a long path gets a magnified inset"
    ideal = next(line for line in path.lines if line.get_label() == "programmed path")
    stepped = next(line for line in path.lines if line.get_label().startswith("steps"))
    assert ideal.get_zorder() > stepped.get_zorder() and ideal.get_linewidth() > stepped.get_linewidth()
    plt.close(fig)


# One example per core through `interp model ... --plot` (the same code as `interp run`).
EXAMPLES = {
    "circ-arc": ["--cx", "5", "--cy", "-5", "--x0", "25", "--y0", "-5", "--x1", "-15", "--y1", "-5", "--dir", "cw"],
    "su1571551": ["--x", "-40", "--y", "23", "--mode", "exact"],
    "curve": ["--curve", "circle", "--a", "20", "--mode", "improved"],
    "su1665343": ["--r", "20", "--x0", "12", "--y0", "16"],
    "circ-std": ["--x0", "20", "--y0", "0", "--x1", "0", "--y1", "20"],
    "lin-accel": ["--x", "5", "--y", "3"],
}


@pytest.mark.parametrize("name", sorted(REGISTRY))
def test_every_core_plots_in_user_coordinates(name, tmp_path, figures):
    core = REGISTRY[name]
    options = EXAMPLES.get(name, core.examples[0] if core.examples else None)
    if options is None:
        pytest.skip(f"{name} has no example")
    png = tmp_path / f"{name}.png"
    assert main(["model", name, *options, "--steps", str(tmp_path / "s.csv"), "--plot", str(png)]) == 0
    assert png.read_bytes()[:8] == PNG
    fig = figures[-1]
    worst = check(fig)
    assert 0 <= worst < 2, f"{name}: deviation {worst} steps"
    path, _ = panels(fig)
    start = next(line for line in path.lines if line.get_label() == "start")
    args = dict(zip([o.lstrip("-").replace("-", "_") for o in options[::2]], options[1::2]))
    if "x0" in args and name != "curve":
        assert (start.get_xdata()[0], start.get_ydata()[0]) == (int(args["x0"]), int(args["y0"])), \
            "the path starts at the command's start point (absolute coordinates)"
    if "cx" in args:
        centre = next(line for line in path.lines if line.get_label().startswith("centre"))
        assert (centre.get_xdata()[0], centre.get_ydata()[0]) == (int(args["cx"]), int(args["cy"]))


def test_gcode_plot_is_in_program_units(tmp_path, figures):
    from interp.gcode.machine import load_machine
    from interp.gcode.moves import Line, Program

    prog = Program([Line((0, 0, 0), (10, 5, 0), 50, 2)])                # G01 X10 Y5 at 10 steps per mm
    machine = load_machine(sets=["axis.x.steps_per_mm=10", "axis.y.steps_per_mm=10"])
    rows, y = [], 0
    for k in range(1, 101):                                             # a DDA of (100, 50) steps
        ny = round(k * 50 / 100)
        rows.append((k, 1, ny - y))
        y = ny
    png = tmp_path / "g.png"
    worst = gcode.plot_program(png, prog, rows, machine, "line.nc")
    assert png.read_bytes()[:8] == PNG
    fig = figures[-1]
    assert check(fig, unit="mm") == pytest.approx(worst, abs=5e-4) and worst <= 0.5
    path, _ = panels(fig)
    stepped = next(line for line in path.lines if line.get_label().startswith("steps"))
    assert max(stepped.get_xdata()) == pytest.approx(10.0), "steps drawn in mm, not in steps"
    assert "10 steps/mm" in fig._suptitle.get_text()


def test_overview_has_four_panels(tmp_path):
    line = [(k, 1, k % 2) for k in range(20)]
    panel = {"steps": line, "ideal": [(0, 0), (20, 10)], "title": "line"}
    out = tmp_path / "o.png"
    plot.plot_overview(out, [panel, {**panel, "unit": "mm", "scale": 2.0}, panel, panel])
    assert out.read_bytes()[:8] == PNG and out.stat().st_size < 300_000


def test_long_thin_path_is_stretched_and_says_so():
    steps = [(k, 1, 1 if k % 100 == 0 else 0) for k in range(1000)]     # 1000 x 10 steps
    fig, _ = plot.path_figure(steps, [(0, 0), (1000, 10)])
    path, _ = panels(fig)
    assert path.get_aspect() == "auto" and not path.child_axes
    assert any(t.get_text() == "axes not to scale" for t in path.texts)
    plt.close(fig)
