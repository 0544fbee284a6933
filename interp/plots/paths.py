"""Plots of stepped paths over the programmed path."""
from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def positions(steps, start=(0, 0)):
    """Visited points from (cycle, dx, dy, ...) rows."""
    x, y = start
    pts = [(x, y)]
    for row in steps:
        x, y = x + row[1], y + row[2]
        pts.append((x, y))
    return pts


def plot_path(path, steps, ideal=None, title="", start=(0, 0), band: float | None = None):
    pts = positions(steps, start)
    fig, ax = plt.subplots(figsize=(6, 6), dpi=110)
    if ideal:
        ix, iy = zip(*ideal)
        ax.plot(ix, iy, color="tab:blue", lw=1.2, label="programmed path")
        if band:
            ax.fill_between(ix, [v - band for v in iy], [v + band for v in iy],
                            color="tab:blue", alpha=0.12, label=f"±{band} step band")
    px, py = zip(*pts)
    ax.plot(px, py, color="tab:red", lw=1, marker="o", ms=2.5, label=f"steps ({len(steps)})")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, lw=0.3)
    ax.set_xlabel("X (steps)")
    ax.set_ylabel("Y (steps)")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
