"""The paper's figures (Figs. 3-5) from the runs ``neurov paper`` makes.

Built as :class:`matplotlib.figure.Figure` directly (no ``pyplot``), like the
run plots in :mod:`neurov.plotting.runs`; the line styles follow the paper's:
the desired path solid black, the controllers dashed, dash-dot and dotted.
Every axis carries its unit; the X-Y paths show where they start and which
way they go; thrusters are T1 to Tn (:mod:`neurov.plotting.labels`).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure

from neurov.plotting.labels import thruster_label
from neurov.plotting.paths import mark_start_and_direction
from neurov.plotting.runs import demanded_and_applied
from neurov.results.timeseries import Result

__all__ = ["figure_inputs", "figure_xy", "figure_yaw"]

_DESIRED = {"color": "black", "linestyle": "-", "linewidth": 1.6}
_STYLES = ({"linestyle": "--", "color": "tab:blue"}, {"linestyle": "-.", "color": "tab:red"},
           {"linestyle": ":", "color": "tab:green"})


def _xy(ax: Any, runs: list[Result]) -> None:
    ax.plot(runs[0].eta_d[:, 1], runs[0].eta_d[:, 0], label="desired", **_DESIRED)
    mark_start_and_direction(ax, runs[0].eta_d[:, 1], runs[0].eta_d[:, 0])
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
    """Fig. 4: the forces [N] and moments [N m] on separate axes, demanded
    against applied (:func:`neurov.plotting.runs.demanded_and_applied`: one
    line where they agree, the gap shaded where the thrusters saturate), then
    each thruster's thrust [N] when the run used thrusters."""
    has_thrusts = run.thrusts.shape[1] > 0
    panels = 3 if has_thrusts else 2
    fig = Figure(figsize=(9.5, 2.3 * panels + 0.6), layout="constrained")
    axes = fig.subplots(panels, 1, sharex=True, squeeze=False)[:, 0]
    for ax, dofs, what in ((axes[0], range(0, 3), "force [N]"), (axes[1], range(3, 6), "moment [N m]")):
        demanded_and_applied(ax, run.t, run.tau_demanded, run.tau_applied, dofs)
        ax.set_ylabel(what)
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
        ax.grid(True, alpha=0.3)
    axes[0].set_title(f"Control inputs: {run.controller} ({run.scenario.name})")
    if has_thrusts:
        for i in range(run.thrusts.shape[1]):
            axes[2].plot(run.t, run.thrusts[:, i], label=thruster_label(i), linewidth=1.0)
        axes[2].set_ylabel("thrust [N]")
        axes[2].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
        axes[2].grid(True, alpha=0.3)
    axes[-1].set_xlabel("t [s]")
    return fig


def figure_yaw(runs: list[Result], caption: str | None = None) -> Figure:
    """Fig. 5: the X-Y paths and the heading under the scenario's yaw
    disturbance; `caption`, if given, is written under the two panels (which
    controller has the lower error: :func:`neurov.paper.experiments.fig5_caption`)."""
    fig = Figure(figsize=(11.0, 5.2 if caption else 4.8), layout="constrained")
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
    if caption:
        # One clause a line: a caption one figure wide would break inside a number.
        fig.supxlabel(caption.replace("; ", ";\n"), fontsize=9)
    return fig
