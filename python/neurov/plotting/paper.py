"""The paper's figures (Figs. 3-5) from the runs ``neurov paper`` makes.

Built as :class:`matplotlib.figure.Figure` directly (no ``pyplot``), like the
run plots in :mod:`neurov.plotting.runs`; the line styles follow the paper's:
the desired path solid black, the controllers dashed, dash-dot and dotted.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure

from neurov.simulation import Result

__all__ = ["figure_inputs", "figure_xy", "figure_yaw"]

_DESIRED = {"color": "black", "linestyle": "-", "linewidth": 1.6}
_STYLES = ({"linestyle": "--", "color": "tab:blue"}, {"linestyle": "-.", "color": "tab:red"},
           {"linestyle": ":", "color": "tab:green"})


def _xy(ax: Any, runs: list[Result]) -> None:
    ax.plot(runs[0].eta_d[:, 1], runs[0].eta_d[:, 0], label="desired", **_DESIRED)
    for r, st in zip(runs, _STYLES):
        ax.plot(r.eta[:, 1], r.eta[:, 0], label=r.controller, **st)
    ax.set_xlabel("Y (east) [m]")
    ax.set_ylabel("X (north) [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=8)


def figure_xy(runs: list[Result], title: str) -> Figure:
    fig = Figure(figsize=(6.0, 5.5), layout="constrained")
    ax = fig.add_subplot()
    _xy(ax, runs)
    ax.set_title(title)
    return fig


def figure_inputs(run: Result) -> Figure:
    has_thrusts = run.thrusts.shape[1] > 0
    fig = Figure(figsize=(8.0, 6.5 if has_thrusts else 4.0), layout="constrained")
    axes = fig.subplots(2 if has_thrusts else 1, 1, sharex=True, squeeze=False)[:, 0]
    names = ("X [N]", "Y [N]", "Z [N]", "K [N m]", "M [N m]", "N [N m]")
    for i, n in enumerate(names):
        axes[0].plot(run.t, run.tau_demanded[:, i], label=n, linewidth=1.0)
    axes[0].set_ylabel("tau demanded")
    axes[0].set_title(f"Control inputs: {run.controller} ({run.scenario.name})")
    axes[0].legend(ncol=6, fontsize=7, loc="upper right")
    axes[0].grid(True, alpha=0.3)
    if has_thrusts:
        for i in range(run.thrusts.shape[1]):
            axes[1].plot(run.t, run.thrusts[:, i], label=f"T{i + 1}", linewidth=1.0)
        axes[1].set_ylabel("thrust [N]")
        axes[1].legend(ncol=6, fontsize=7, loc="upper right")
        axes[1].grid(True, alpha=0.3)
    axes[-1].set_xlabel("t [s]")
    return fig


def figure_yaw(runs: list[Result]) -> Figure:
    fig = Figure(figsize=(11.0, 4.8), layout="constrained")
    ax_xy, ax_yaw = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1, 1.4]})
    _xy(ax_xy, runs)
    ax_xy.set_title("X-Y path")
    ax_yaw.plot(runs[0].t, np.degrees(runs[0].eta_d[:, 5]), label="desired", **_DESIRED)
    for r, st in zip(runs, _STYLES):
        ax_yaw.plot(r.t, np.degrees(r.eta[:, 5]), label=r.controller, **st)
    ax_yaw.set_xlabel("t [s]")
    ax_yaw.set_ylabel("heading psi [deg]")
    ax_yaw.grid(True, alpha=0.3)
    ax_yaw.legend(loc="best", fontsize=8)
    d = runs[0].scenario.disturbances[0]
    ax_yaw.set_title(f"Yaw disturbance {d.amplitude:g} N m at {d.frequency:g} Hz")
    return fig
