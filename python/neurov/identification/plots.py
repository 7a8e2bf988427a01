"""The identification as a figure: each fitted parameter's estimate and
95 % interval relative to the template, and, for each held-out log, the
measured body velocities against the fitted and the template vehicle's
free runs."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from neurov import _core
from neurov.identification.parameters import GROUPS

if TYPE_CHECKING:
    from neurov.identification.fit import Identification

__all__ = ["plot_identification"]

_BODY = ("u [m/s]", "v [m/s]", "w [m/s]", "p [rad/s]", "q [rad/s]", "r [rad/s]")


def _scale(r: Identification, i: int) -> float:
    # A template value of zero is shown against its group's largest value.
    group = next(g for g in GROUPS.values() if i in g)
    v = abs(r.theta_template[i])
    return v if v > 0 else max(abs(r.theta_template[j]) for j in group) or 1.0


def plot_identification(r: Identification, path: str | Path, truth: Any = None) -> Path:
    """Writes the figure to `path` (PNG); `truth` (24,) marks the true
    values when they are known (a simulated log)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    held = r.heldout[0] if r.heldout else None
    fig = plt.figure(figsize=(11, 7.5 if held else 4.5), layout="constrained")
    grid = fig.add_gridspec(3 if held else 1, 2 if held else 1, height_ratios=[1.3, 1, 1] if held else [1])
    ax = fig.add_subplot(grid[0, :])
    x = np.arange(len(r.fitted))
    s = np.array([_scale(r, i) for i in r.fitted])
    est = r.theta[r.fitted] / s
    lo, hi = r.interval[r.fitted].T / s
    ax.errorbar(x, est, yerr=[est - lo, hi - est], fmt="o", color="C0", capsize=3,
                label="estimate, 95 % interval")
    ax.plot(x, r.theta_template[r.fitted] / s, "s", mfc="none", color="C7", label="template")
    if truth is not None:
        ax.plot(x, np.asarray(truth)[r.fitted] / s, "x", color="C3", label="true value")
    ax.set_xticks(x, [_core.THETA_NAMES[i] for i in r.fitted], rotation=60, fontsize=8)
    ax.set_ylabel("relative to the template")
    ax.axhline(1.0, color="0.85", lw=0.8, zorder=0)
    ax.legend(fontsize=8, ncols=3)
    ax.set_title(f"{r.stages}; condition number {r.condition:.3g}", fontsize=9)
    if held:
        axes = fig.add_subfigure(grid[1:, :]).subplots(2, 3, sharex=True)
        for d, a in enumerate(axes.flat):
            a.plot(held.t, held.measured[:, d], color="k", lw=0.8, label="measured")
            a.plot(held.t, held.template_run[:, d], color="C7", lw=0.8, ls="--", label="template")
            a.plot(held.t, held.fitted_run[:, d], color="C0", lw=0.9, label="fitted")
            a.set_title(f"{_BODY[d]}: fit {held.fit[d]:.1f} % (template {held.template_fit[d]:.1f} %)",
                        fontsize=8)
            a.tick_params(labelsize=7)
        axes[0, 0].legend(fontsize=7)
        for a in axes[1]:
            a.set_xlabel("t [s]", fontsize=8)
    path = Path(path)
    try:
        fig.savefig(path, dpi=110)
    finally:  # a failed write (a full disk) leaves no figure open in pyplot
        plt.close(fig)
    return path
