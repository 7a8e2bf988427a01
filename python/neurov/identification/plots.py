"""The identification as a figure: each fitted parameter's estimate and
95 % interval relative to the template (as a value where the template's is
zero: a ratio to another scale would hide the move), and, for each held-out log, the
measured body velocities against the fitted and the template vehicle's
free runs."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from neurov import _core

if TYPE_CHECKING:
    from neurov.identification.outcome import Identification

__all__ = ["plot_identification"]

_BODY = ("u [m/s]", "v [m/s]", "w [m/s]", "p [rad/s]", "q [rad/s]", "r [rad/s]")


def panels(r: Identification) -> tuple[list[int], list[int]]:
    """The fitted parameters shown relative to the template (its value is
    not zero) and those shown as absolute values (a template value of zero:
    a ratio would hide a move from 0 to any value)."""
    rel = [i for i in r.fitted if r.theta_template[i] != 0]
    return rel, [i for i in r.fitted if r.theta_template[i] == 0]


def _estimates(ax: Any, r: Identification, idx: list[int], scale: Any, truth: Any, ylabel: str) -> None:
    x = np.arange(len(idx))
    s = np.asarray(scale, dtype=np.float64)
    est = r.theta[idx] / s
    lo, hi = r.interval[idx].T / s
    ax.errorbar(x, est, yerr=[np.maximum(est - lo, 0), np.maximum(hi - est, 0)], fmt="o", color="C0",
                capsize=3, label="estimate, 95 % interval")
    ax.plot(x, r.theta_template[idx] / s, "s", mfc="none", color="C7", label="template")
    if truth is not None:
        ax.plot(x, np.asarray(truth)[idx] / s, "x", color="C3", label="true value")
    ax.set_xticks(x, [_core.THETA_NAMES[i] for i in idx], rotation=60, fontsize=8)
    ax.set_ylabel(ylabel)


def plot_identification(r: Identification, path: str | Path, truth: Any = None) -> Path:
    """Writes the figure to `path` (PNG); `truth` (24,) marks the true
    values when they are known (a simulated log)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    held = r.heldout[0] if r.heldout else None
    fig = plt.figure(figsize=(11, 7.5 if held else 4.5), layout="constrained")
    grid = fig.add_gridspec(3 if held else 1, 2 if held else 1, height_ratios=[1.3, 1, 1] if held else [1])
    rel, absolute = panels(r)
    top = fig.add_subfigure(grid[0, :]).subplots(
        1, 2 if rel and absolute else 1, squeeze=False,
        width_ratios=[max(len(rel), 1), max(len(absolute), 1)] if rel and absolute else None)[0]
    ax = top[0]
    if rel:
        _estimates(ax, r, rel, r.theta_template[rel], truth, "relative to the template")
        ax.axhline(1.0, color="0.85", lw=0.8, zorder=0)
    if absolute:
        a = top[-1]
        _estimates(a, r, absolute, np.ones(len(absolute)), truth, "value (template 0: absolute)")
        a.axhline(0.0, color="0.85", lw=0.8, zorder=0)
        if not rel:
            a.legend(fontsize=8, ncols=3)
    if rel:
        ax.legend(fontsize=8, ncols=3)
    title = f"{r.stages}; condition number {r.condition:.3g}"
    if len(top) > 1:
        fig.suptitle(title, fontsize=9)
    else:
        ax.set_title(title, fontsize=9)
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
