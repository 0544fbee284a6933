# SPDX-License-Identifier: Apache-2.0
"""Plots of stepped paths over the programmed path, with the deviation at every step.

Every figure has two panels: the path in the user's coordinates (absolute
positions; the arc's or curve's centre where the command gives one; G-code in
program units) with the programmed path drawn on top of the steps, and the
deviation of each visited point from the programmed path against the step
number, with the +-0.5 step band and the largest deviation in the legend.
The deviation is in steps (the interpolator's unit) and signed: + is left of
the programmed path's direction.
"""
from __future__ import annotations

import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

STEPS_COLOUR, IDEAL_COLOUR, BAND_COLOUR = "tab:red", "tab:blue", "tab:green"
MARKERS_UP_TO = 150         # steps drawn with a dot at each point up to this many (or while the
                            # path is small enough for dots to be seen, up to 4 times as many)
STRETCH_ABOVE = 6          # a path longer than this many times its width is drawn not to scale
INSET_ABOVE = 150           # a path wider than this many steps (drawn to scale) gets an inset:
INSET_STEPS = 24            # this many steps a third of the way along, magnified
CORNERS = {(0.6, 0.06): "lower right", (0.06, 0.06): "lower left", (0.6, 0.56): "upper right",
           (0.06, 0.56): "upper left", (0.32, 0.31): "center"}


def positions(steps, start=(0, 0)):
    """Visited points from (cycle, dx, dy, ...) rows."""
    x, y = start
    pts = [(x, y)]
    for row in steps:
        x, y = x + row[1], y + row[2]
        pts.append((x, y))
    return pts


def deviations(points, ideal) -> np.ndarray:
    """Signed distance of each point from the polyline `ideal` (+ left of its direction)."""
    p = np.asarray(points, dtype=float).reshape(-1, 2)
    q = np.asarray(ideal, dtype=float).reshape(-1, 2)
    if len(q) == 1:
        return np.hypot(*(p - q[0]).T)
    a, d = q[:-1], q[1:] - q[:-1]
    length2 = np.maximum((d * d).sum(1), 1e-30)
    out = np.empty(len(p))
    chunk = max(1, 2_000_000 // len(a))
    for lo in range(0, len(p), chunk):
        r = p[lo:lo + chunk, None, :] - a[None, :, :]                 # point - segment start
        t = np.clip((r * d).sum(2) / length2, 0.0, 1.0)
        off = r - t[..., None] * d
        dist = np.hypot(off[..., 0], off[..., 1])
        best = dist.argmin(1)
        rows = np.arange(len(best))
        cross = d[best, 0] * r[rows, best, 1] - d[best, 1] * r[rows, best, 0]
        out[lo:lo + chunk] = np.where(cross < 0, -1.0, 1.0) * dist[rows, best]
    return out


def _inset(ax, pts, ideal) -> str:
    """Magnify INSET_STEPS steps a third of the way along a long path, in the emptiest corner;
    returns the next emptiest corner (for the legend)."""
    mid = len(pts) // 3
    part = pts[max(0, mid - INSET_STEPS // 2): mid + INSET_STEPS // 2 + 1]
    lo, hi = part.min(0), part.max(0)
    side = max(hi - lo) / 2 + 0.6
    centre = (lo + hi) / 2
    (x0, x1), (y0, y1) = ax.dataLim.intervalx, ax.dataLim.intervaly
    u = (pts[:, 0] - x0) / max(x1 - x0, 1e-9)
    v = (pts[:, 1] - y0) / max(y1 - y0, 1e-9)
    corners = {(0.6, 0.06): (u > 0.55) & (v < 0.45), (0.06, 0.06): (u < 0.45) & (v < 0.45),
               (0.6, 0.56): (u > 0.55) & (v > 0.55), (0.06, 0.56): (u < 0.45) & (v > 0.55),
               (0.32, 0.31): (u > 0.28) & (u < 0.72) & (v > 0.27) & (v < 0.71)}     # inside a closed path
    where, free = sorted(corners, key=lambda c: corners[c].sum())[:2]
    inset = ax.inset_axes([*where, 0.36, 0.36])
    inset.plot(pts[:, 0], pts[:, 1], color=STEPS_COLOUR, lw=0.9, marker="o", ms=2.5, zorder=2)
    if ideal is not None:
        inset.plot(ideal[:, 0], ideal[:, 1], color=IDEAL_COLOUR, lw=1.4, alpha=0.85, zorder=3)
    inset.set_xlim(centre[0] - side, centre[0] + side)
    inset.set_ylim(centre[1] - side, centre[1] + side)
    inset.set_aspect("equal")
    inset.tick_params(labelsize=6)
    inset.grid(True, lw=0.3)
    inset.set_title(f"steps {max(0, mid - INSET_STEPS // 2)}-{min(len(pts) - 1, mid + INSET_STEPS // 2)}",
                    fontsize=7, pad=2)
    ax.indicate_inset_zoom(inset, edgecolor="0.3")
    return CORNERS[free]


def wrap(title: str, width: int) -> str:
    return "\n".join(textwrap.wrap(title, width)) if title else ""


def draw(ax_path, ax_dev, steps, ideal=None, title="", start=(0, 0), band: float | None = 0.5,
         unit: str = "steps", scale: float = 1.0, title_width: int = 60, fontsize: float = 9,
         centre=None, inset: bool = True) -> float | None:
    """Both panels of one run on the given axes; the largest |deviation| (steps), or None."""
    pts = np.asarray(positions(steps, start), dtype=float)
    every = pts if ideal is None or not len(ideal) else np.vstack([pts, np.asarray(ideal, dtype=float)])
    span = np.ptp(every, axis=0)
    many = len(steps) > MARKERS_UP_TO and (span.max() > INSET_ABOVE or len(steps) > 4 * MARKERS_UP_TO)
    to_scale = span.min() * STRETCH_ABOVE >= span.max()
    ax_path.plot(pts[:, 0] / scale, pts[:, 1] / scale, color=STEPS_COLOUR, lw=0.7 if many else 0.9,
                 marker=None if many else "o", ms=2.2, zorder=2, label=f"steps ({len(steps)})")
    ax_path.plot(*(pts[0] / scale), "o", color="black", ms=4, zorder=4, label="start")
    legend_at = "best"
    if inset and to_scale and span.max() > INSET_ABOVE:    # steps too small to see: magnify some
        legend_at = _inset(ax_path, pts / scale, None if ideal is None else np.asarray(ideal, dtype=float) / scale)
    if centre is not None:
        ax_path.plot(centre[0] / scale, centre[1] / scale, "+", color="black", ms=9, mew=1.2, zorder=4,
                     label=f"centre ({centre[0] / scale:g}, {centre[1] / scale:g})")
    worst = None
    if ideal is not None and len(ideal):
        q = np.asarray(ideal, dtype=float)
        ax_path.plot(q[:, 0] / scale, q[:, 1] / scale, color=IDEAL_COLOUR, lw=1.4, alpha=0.85, zorder=3,
                     label="programmed path")
        dev = deviations(pts, q)
        worst = float(np.abs(dev).max())
        k = np.arange(len(dev))
        ax_dev.plot(k, dev, color=STEPS_COLOUR, lw=0.7 if many else 0.9, marker=None if many else "o", ms=2,
                    label=f"deviation, max |d| = {worst:.3f} step")
        if band:
            ax_dev.axhspan(-band, band, color=BAND_COLOUR, alpha=0.12, lw=0, label=f"±{band:g} step band")
            ax_dev.axhline(band, color=BAND_COLOUR, lw=0.6)
            ax_dev.axhline(-band, color=BAND_COLOUR, lw=0.6)
        lim = max(worst, band or 0) * 1.2 or 1
        ax_dev.set_ylim(-lim, lim * 1.9)                # room for the legend above the band
        ax_dev.set_xlim(0, max(1, len(dev) - 1))
        ax_dev.legend(fontsize=fontsize - 1.5, loc="upper right", ncol=2, framealpha=0.85)
    ax_dev.set_xlabel("step number", fontsize=fontsize)
    ax_dev.set_ylabel("deviation (steps)", fontsize=fontsize)
    ax_dev.grid(True, lw=0.3)
    if to_scale:
        ax_path.set_aspect("equal", adjustable="datalim")
    else:                       # a long thin path: stretched to be seen, and said so
        ax_path.text(0.01, 0.01, "axes not to scale", transform=ax_path.transAxes, fontsize=fontsize - 2,
                     color="0.35", va="bottom")
    ax_path.grid(True, lw=0.3)
    ax_path.set_xlabel(f"X ({unit})", fontsize=fontsize)
    ax_path.set_ylabel(f"Y ({unit})", fontsize=fontsize)
    ax_path.set_title(wrap(title, title_width), fontsize=fontsize)
    ax_path.legend(fontsize=fontsize - 1.5, loc=legend_at, framealpha=0.85)
    for ax in (ax_path, ax_dev):
        ax.tick_params(labelsize=fontsize - 1)
    return worst


def plot_path(path, steps, ideal=None, title="", start=(0, 0), band: float | None = 0.5,
              unit: str = "steps", scale: float = 1.0, centre=None) -> float | None:
    """PNG of one run: the path (left) and its deviation against the step number (right).

    `steps` and `ideal` are in steps; with `scale` (steps per unit) the path panel is
    drawn in `unit`.  Returns the largest |deviation| in steps (None without `ideal`)."""
    fig, worst = path_figure(steps, ideal, title, start, band, unit, scale, centre)
    fig.savefig(path)
    plt.close(fig)
    return worst


def path_figure(steps, ideal=None, title="", start=(0, 0), band: float | None = 0.5,
                unit: str = "steps", scale: float = 1.0, centre=None):
    """The figure `plot_path` saves, and the largest |deviation|."""
    fig, (ax_path, ax_dev) = plt.subplots(1, 2, figsize=(11, 5.2), dpi=100,
                                          gridspec_kw={"width_ratios": [1.15, 1]})
    worst = draw(ax_path, ax_dev, steps, ideal, "", start, band, unit, scale, centre=centre)
    fig.suptitle(wrap(title, 110), fontsize=10)
    ax_dev.set_title("deviation from the programmed path (+ = left of it)", fontsize=9)
    fig.tight_layout()
    return fig, worst


def plot_overview(path, panels: list[dict], title: str = "", dpi: int = 80) -> None:
    """Several runs in one PNG, two per row: each a path over a short deviation strip.

    `panels`: keyword arguments of `draw` (steps, ideal, title, start, band, unit, scale, centre)."""
    cols = 2
    rows = (len(panels) + cols - 1) // cols
    fig = plt.figure(figsize=(11, 6 * rows), dpi=dpi)
    grid = fig.add_gridspec(2 * rows, cols, height_ratios=[3.4, 1] * rows, hspace=0.38, wspace=0.22)
    for n, panel in enumerate(panels):
        r, c = divmod(n, cols)
        ax_path = fig.add_subplot(grid[2 * r, c])
        ax_dev = fig.add_subplot(grid[2 * r + 1, c])
        draw(ax_path, ax_dev, title_width=55, fontsize=9, inset=False, **panel)
    if title:
        fig.suptitle(wrap(title, 100), fontsize=12)
    fig.subplots_adjust(left=0.07, right=0.98, top=0.95 if title else 0.97, bottom=0.05)
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
