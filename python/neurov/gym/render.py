"""The environment's top view, drawn with Matplotlib's Agg canvas."""

from __future__ import annotations

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from numpy.typing import NDArray

__all__ = ["top_view"]


def top_view(poses: NDArray[np.float64], track: NDArray[np.float64], heading: float,
             box_low: NDArray[np.float64], box_high: NDArray[np.float64], *, t: float, depth: float,
             depth_desired: float) -> NDArray[np.uint8]:
    """An RGB image (480 x 480): north (x) up, east (y) right, and beside it
    the depth (down) within the box's depth range, the vehicle's against the
    desired, so that leaving the box in depth is seen too; the time and the
    depth are written above. `track` holds rows (x, y, x_d, y_d) of the true
    and the desired position."""
    fig = Figure(figsize=(4.8, 4.8), dpi=100)
    canvas = FigureCanvasAgg(fig)
    ax = fig.add_axes((0.13, 0.1, 0.62, 0.78))
    ax.plot(poses[:, 1], poses[:, 0], "o", color="0.6", ms=3, label="commanded poses")
    ax.plot(track[:, 3], track[:, 2], "--", color="tab:blue", label="desired")
    ax.plot(track[:, 1], track[:, 0], "-", color="tab:red", label="vehicle")
    x, y = track[-1, 0], track[-1, 1]
    size = 0.05 * float(np.max(box_high[:2] - box_low[:2]))
    ax.annotate("", xy=(y + size * np.sin(heading), x + size * np.cos(heading)), xytext=(y, x),
                arrowprops={"arrowstyle": "->", "color": "tab:red"})
    ax.set_xlim(box_low[1], box_high[1])
    ax.set_ylim(box_low[0], box_high[0])
    ax.set_aspect("equal")
    ax.set_xlabel("east y [m]")
    ax.set_ylabel("north x [m]")
    ax.legend(loc="upper right", fontsize="small")
    # Depth: the box's range, down the page as the vehicle sees it.
    dz = fig.add_axes((0.82, 0.1, 0.05, 0.78))
    dz.set_ylim(box_high[2], box_low[2])
    dz.set_xlim(0.0, 1.0)
    dz.set_xticks([])
    dz.axhline(depth_desired, color="tab:blue", ls="--", lw=1.5)
    inside = box_low[2] <= depth <= box_high[2]
    dz.plot([0.5], [min(max(depth, box_low[2]), box_high[2])], marker="o" if inside else "X", ms=8,
            color="tab:red")
    dz.set_ylabel("depth z [m]", fontsize="small")
    dz.yaxis.set_label_position("right")
    dz.yaxis.tick_right()
    dz.tick_params(labelsize="small")
    where = "" if inside else " (outside the box)"
    fig.text(0.5, 0.965, f"t = {t:.1f} s   depth {depth:.2f} m{where} (desired {depth_desired:.2f} m)",
             ha="center", va="top", fontsize=9)
    canvas.draw()
    return np.asarray(canvas.buffer_rgba())[:, :, :3].copy()
