# SPDX-License-Identifier: Apache-2.0
"""Speed plots of a run: the path speed and each axis's speed against time, with the limits.

The speeds are the motion monitor's (interp.simulation.monitor): the steps CSV's cumulative
distance differenced over the monitor's grid of T clocks.  Top panel: the path speed (mm/s),
the commands' planned cruise, the cap in force (cruise x the override at that moment, a
step at each override change, at most the axes' ceiling) and the ceiling; vertical lines
mark the feed holds, resumes and override changes; an S-curve run's title gives the jerk
limit and the filter's window; middle: each axis's speed and its max rate; bottom: the path
acceleration (the difference of the speeds) and the commands' acceleration limit.
"""
from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

AXIS_COLOURS = ("tab:red", "tab:green", "tab:blue")


CONTROL_STYLES = {"hold": ("tab:red", "--", "feed hold"), "resume": ("tab:green", "--", "resume"),
                  "override": ("tab:purple", ":", "override change")}


def _mark_controls(panels, controls) -> None:
    """Vertical lines at the holds, resumes and override changes (one legend entry each kind)."""
    seen = set()
    for seconds, kind, value in controls:
        colour, style, name = CONTROL_STYLES[kind]
        for n, panel in enumerate(panels):
            label = None
            if n == 0 and kind not in seen:
                label = name
                seen.add(kind)
            panel.axvline(seconds, color=colour, ls=style, lw=0.9, label=label)
        if kind == "override":
            panels[0].annotate(f"{value}%", (seconds, 1.0), xycoords=("data", "axes fraction"), fontsize=7,
                               color=colour, ha="left", va="top")


def plot_speed(path, report, title: str = "path and axis speeds") -> None:
    """Write the PNG of a monitor report's series (report.series)."""
    s = report.series
    fig, (top, middle, bottom) = plt.subplots(3, 1, figsize=(10, 8.5), sharex=True)
    if not s:
        top.text(0.5, 0.5, "no motion", ha="center", va="center", transform=top.transAxes)
    else:
        t = s["t"]
        top.plot(t, s["path"], color="black", lw=1.2, label="path speed (measured)")
        top.plot(t, s["cruise"], color="tab:blue", lw=0.8, ls="--", label="planned cruise (cmd_feed)")
        top.step(t, s["cap"], where="mid", color="tab:orange", lw=0.8, ls=":",
                 label="cap in force: cruise x override, <= ceiling")
        top.plot(t, s["limit"], color="tab:red", lw=0.8, ls="-.", label="axes' ceiling (cmd_limit)")
        top.set_ylabel("path speed, mm/s")
        _mark_controls((top, middle, bottom), s.get("controls", ()))
        top.legend(loc="upper right", fontsize=8)
        for k, (speed, colour) in enumerate(zip(s["axes"], AXIS_COLOURS)):
            middle.plot(t, speed, color=colour, lw=1, label=f"{'xyz'[k]} (measured)")
            middle.axhline(s["axis_max"][k], color=colour, lw=0.8, ls="--", label=f"{'xyz'[k]} max rate")
        middle.set_ylabel("axis speed, mm/s")
        middle.legend(loc="upper right", fontsize=8, ncol=2)
        grid = (t[1] - t[0]) if len(t) > 1 else 1.0
        accel = np.diff(s["path"]) / grid
        bottom.plot(t[1:], accel, color="black", lw=1, label="path acceleration (measured)")
        bottom.plot(t, s["accel"], color="tab:red", lw=0.8, ls="--", label="+- the commands' acceleration")
        bottom.plot(t, -s["accel"], color="tab:red", lw=0.8, ls="--")
        bottom.set_ylabel("mm/s^2")
        bottom.legend(loc="upper right", fontsize=8)
    bottom.set_xlabel(f"time, s (grid {report.grid} clocks)")
    if s and s.get("jerk_mm_s3"):
        title += (f"\nS-curve: jerk limit {s['jerk_mm_s3']:g} mm/s^3, filter window "
                  f"{s['window_s'] * 1e3:.4g} ms")
    top.set_title(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
