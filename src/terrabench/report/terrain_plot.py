"""Pictures of terrains: height map, start, target and leader paths."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from terrabench.terrain import sine_sum  # noqa: E402

START = (0.0, 0.0)
TARGET = (9.0, -9.0)


def draw_terrain(ax, terrain, paths: dict[str, tuple[np.ndarray, np.ndarray]] | None = None, colorbar: bool = True):
    """Draw a terrain's height map (world XY) with start, target and paths on ``ax``."""
    p = terrain.params
    h = sine_sum.heights(p)
    x, y = sine_sum.vertex_xy(p)
    im = ax.imshow(h.T, origin="upper", extent=[x[0], x[-1], y[-1], y[0]], cmap="terrain", aspect="equal")
    if colorbar:
        ax.figure.colorbar(im, ax=ax, label="height (m)", shrink=0.8)
    ax.plot(*START, "o", color="white", mec="black", ms=8, label="start")
    ax.plot(*TARGET, "*", color="red", mec="black", ms=14, label="target")
    for label, (px, py) in (paths or {}).items():
        ax.plot(px, py, lw=1.6, label=label)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    s = terrain.stats()
    ax.set_title(f"{terrain.id}: mean axis slope {s['mean_axis_slope_deg']:.1f} deg, max {s['max_slope_deg']:.0f} deg")
    ax.legend(loc="lower left", fontsize=7)
    return im


def plot_terrain(terrain, out: Path, paths=None) -> Path:
    fig, ax = plt.subplots(figsize=(7, 6))
    draw_terrain(ax, terrain, paths)
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out
