"""The environment's top view, drawn with Matplotlib's Agg canvas."""

from __future__ import annotations

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from numpy.typing import NDArray

__all__ = ["top_view"]


def top_view(poses: NDArray[np.float64], track: NDArray[np.float64], heading: float,
             box_low: NDArray[np.float64], box_high: NDArray[np.float64]) -> NDArray[np.uint8]:
    """An RGB image (480 x 480): north (x) up, east (y) right. `track` holds
    rows (x, y, x_d, y_d) of the true and the desired position."""
    fig = Figure(figsize=(4.8, 4.8), dpi=100)
    canvas = FigureCanvasAgg(fig)
    ax = fig.add_subplot()
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
    canvas.draw()
    return np.asarray(canvas.buffer_rgba())[:, :, :3].copy()
