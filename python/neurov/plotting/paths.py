"""Where an X-Y path starts and which way it goes, so that a reader of a map
plot need not guess: a filled marker labelled "start" at the first point and
arrow heads along the path. Shared by the run plots and the paper's figures.

The artists carry gids ("start", "direction") so that tests and readers of
a figure object can find them.
"""

from __future__ import annotations

import numpy as np
from matplotlib.axes import Axes
from matplotlib.patches import FancyArrowPatch

__all__ = ["ARROWS", "mark_start_and_direction"]

#: Arrow heads per path, at 1/8, 3/8, 5/8 and 7/8 of its length: on a square
#: that starts at a corner, one in the middle of each side.
ARROWS = 4
# Shorter paths (a hold at one point) have no direction to show [m].
_MIN_LENGTH = 1e-3


def mark_start_and_direction(ax: Axes, east: np.ndarray, north: np.ndarray, colour: str = "black",
                             label_start: bool = True) -> None:
    """Marks the start of the path (`east`, `north`) [m] and its direction on
    the map axes `ax` (east to the right, north up)."""
    east = np.asarray(east, dtype=np.float64)
    north = np.asarray(north, dtype=np.float64)
    ok = np.isfinite(east) & np.isfinite(north)
    east, north = east[ok], north[ok]
    if not len(east):
        return
    ax.scatter([east[0]], [north[0]], s=40, color=colour, marker="o", zorder=4, gid="start")
    if label_start:
        ax.annotate("start", (east[0], north[0]), xytext=(6, 6), textcoords="offset points",
                    fontsize=8, color=colour, gid="start")
    steps = np.hypot(np.diff(east), np.diff(north))
    along = np.concatenate([[0.0], np.cumsum(steps)])
    length = along[-1]
    if length < _MIN_LENGTH:
        return
    half = 0.02 * length
    for k in range(ARROWS):
        s = (2 * k + 1) / (2 * ARROWS) * length
        tail = (np.interp(s - half, along, east), np.interp(s - half, along, north))
        head = (np.interp(s + half, along, east), np.interp(s + half, along, north))
        ax.add_patch(FancyArrowPatch(tail, head, arrowstyle="-|>", mutation_scale=14, color=colour,
                                     linewidth=0, zorder=4, gid="direction"))
