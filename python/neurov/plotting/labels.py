"""What every figure calls things: thruster names and the axis label (in
words, with its unit) of each run metric, which the metric's own entry in
:data:`neurov.results.metrics.METRICS` gives. One place, so that a figure, its
legend and a failure note never disagree.

Thrusters are numbered as a reader counts, T1 to Tn: T1 is the first column
of the vehicle file's thruster matrix, which scenario files and arrays index
as 0 (``thruster_failures`` ``index = 0``, the CSV column ``thrusts_0``).
"""

from __future__ import annotations

from neurov.results.metrics import metric_label

__all__ = ["metric_label", "thruster_label"]


def thruster_label(index: int) -> str:
    """The figure name of the thruster at 0-based array `index`: ``T{index + 1}``."""
    if index < 0:
        raise ValueError(f"argument 'index' must be a 0-based thruster index >= 0, got {index}")
    return f"T{index + 1}"


