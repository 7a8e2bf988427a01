"""A study's figures: box plots of the ranking metric and the error bands
over time. Each draws from the runs table (a :class:`pandas.DataFrame`) or
the runs' decimated error series, never from the runs themselves."""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

if TYPE_CHECKING:
    from neurov.scenario import Scenario
    from neurov.study import Study

__all__ = ["plot_bands", "plot_boxes"]


def plot_boxes(study: Study, table: pd.DataFrame, path: Path) -> Path:
    """Box plots of the ranking metric per controller, one panel per scenario."""
    metric = study.ranking_metric
    n = len(study.scenarios)
    cols = min(3, n)
    nrows = math.ceil(n / cols)
    fig = Figure(figsize=(4.8 * cols, 3.6 * nrows), layout="constrained")
    axes = fig.subplots(nrows, cols, squeeze=False)
    groups = {key: g[metric].to_numpy(dtype=np.float64)
              for key, g in table.groupby(["scenario", "controller"], sort=False)}
    for ax, s in zip(axes.flat, study.scenarios):
        data, labels, failures = [], [], []
        for c in study.controllers:
            vals = groups.get((s.name, c))
            if vals is None or not len(vals):
                continue
            finite = vals[np.isfinite(vals)]
            data.append(finite if len(finite) else np.array([np.nan]))
            labels.append(study.label(c))
            failures.append(len(vals) - len(finite))
        ax.boxplot(data, whis=(5, 95), showfliers=True)
        ax.set_xticks(range(1, len(labels) + 1), labels, rotation=40, ha="right", fontsize=8)
        if all(v > 0 for d in data for v in d if math.isfinite(v)):
            ax.set_yscale("log")
        for i, nf in enumerate(failures):
            if nf:
                ax.annotate(f"{nf} not finite", (i + 1, 1.0), xycoords=("data", "axes fraction"),
                            ha="center", va="top", fontsize=7, color="C3")
        ax.set_title(s.name, fontsize=10)
        ax.set_ylabel(metric, fontsize=8)
        ax.grid(True, axis="y", alpha=0.3)
    for ax in list(axes.flat)[n:]:
        ax.set_visible(False)
    fig.suptitle(f"{study.name}: {metric} over {study.samples} sample(s); whiskers 5th-95th percentile")
    fig.savefig(path, dpi=110)
    return path


def _colour(i: int) -> str:
    # Matplotlib's cycle with black for its grey (C7): grey marks the other controllers.
    return ("C0", "C1", "C2", "C3", "C4", "C5", "C6", "C8", "C9", "k")[i % 10]


def plot_bands(study: Study, records: Mapping[tuple[str, str, int], Mapping[str, Any]],
               scenario: Scenario, path: Path) -> Path:
    """Position error over time, one panel per controller: its median over
    the samples with the 5th-95th percentile band, over the other
    controllers' medians in grey for comparison."""
    curves: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    for c in study.controllers:
        series = [records[(scenario.name, c, k)]["series"] for k in range(study.samples)
                  if (scenario.name, c, k) in records]
        if not series:
            continue
        # A diverged run stops early and its last errors are inf or nan: it
        # leaves the statistics from there on (nan), not the whole plot.
        n = max(len(x["position_error"]) for x in series)
        e = np.full((len(series), n), np.nan)
        for k, x in enumerate(series):
            e[k, :len(x["position_error"])] = x["position_error"]
        e = np.where(np.isfinite(e), e, np.nan)
        t = series[0]["t0"] + series[0]["dt"] * np.arange(n)
        curves[c] = (t, e)
    n = max(1, len(curves))
    cols = min(5, n)
    rows = math.ceil(n / cols)
    fig = Figure(figsize=(3.2 * cols, 2.6 * rows + 0.6), layout="constrained")
    axes = fig.subplots(rows, cols, squeeze=False, sharex=True, sharey=True)
    medians = {}
    with np.errstate(all="ignore"):
        with warnings.catch_warnings():
            # All-nan columns (every sample diverged there) warn; they plot as gaps.
            warnings.simplefilter("ignore", RuntimeWarning)
            for c, (t, e) in curves.items():
                medians[c] = (t, np.nanmedian(e, axis=0), np.nanpercentile(e, 5, axis=0),
                              np.nanpercentile(e, 95, axis=0))
    positive = np.concatenate([m[1][np.isfinite(m[1]) & (m[1] > 0)] for m in medians.values()] or [np.ones(1)])
    bottom = max(1e-4, float(np.percentile(positive, 1)) / 3) if positive.size else 1e-4
    for i, (ax, c) in enumerate(zip(axes.flat, curves)):
        for other, (t, med, _, _) in medians.items():
            if other != c:
                ax.plot(t, med, color="0.8", lw=0.6)
        t, med, lo, hi = medians[c]
        color = _colour(study.controllers.index(c))
        if study.samples > 1:
            ax.fill_between(t, lo, hi, color=color, alpha=0.25, lw=0)
        ax.plot(t, med, color=color, lw=1.2)
        ax.axvline(study.after, color="0.5", lw=0.6, ls=":")
        ax.set_yscale("log")
        ax.set_ylim(bottom=bottom)
        ax.set_title(study.label(c), fontsize=8)
        ax.grid(True, alpha=0.3)
        if i % cols == 0:
            ax.set_ylabel("position error [m]", fontsize=8)
        if i >= (rows - 1) * cols:
            ax.set_xlabel("t [s]", fontsize=8)
        ax.tick_params(labelsize=7)
    for ax in list(axes.flat)[len(curves):]:
        ax.set_visible(False)
    fig.suptitle(f"{scenario.name}: median and 5th-95th percentile over {study.samples} sample(s); "
                 "grey: the other controllers' medians", fontsize=10)
    fig.savefig(path, dpi=100)
    return path
