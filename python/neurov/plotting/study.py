"""A study's figures: box plots of the ranking metric and the error bands
over time. Each draws from the runs table (a :class:`pandas.DataFrame`) or
the runs' decimated error series, never from the runs themselves."""

from __future__ import annotations

import inspect
import math
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.ticker import LogFormatter, NullLocator

if TYPE_CHECKING:
    from neurov.config.scenario import Scenario
    from neurov.study.spec import Study

from neurov.plotting.colours import OTHERS_GREY, controller_colours
from neurov.plotting.labels import metric_label
from neurov.units import label_for_people

__all__ = ["FEW_SAMPLES", "BandPlotter", "box_figure", "plot_bands", "plot_boxes"]


#: Below this many finite values a box (quartiles, 5th-95th percentile
#: whiskers) says more than the data can: those runs are drawn as points.
FEW_SAMPLES = 10


# matplotlib 3.10 names it orientation and deprecates vert (3.6-3.9 know only vert).
_HORIZONTAL: dict[str, Any] = ({"orientation": "horizontal"}
                               if "orientation" in inspect.signature(Axes.boxplot).parameters
                               else {"vert": False})


def _spread(n: int) -> np.ndarray:
    """Horizontal offsets that keep `n` points of one box apart; fixed, not
    random, so that a redrawn figure is the same figure."""
    return np.zeros(1) if n <= 1 else np.linspace(-0.18, 0.18, n)


def plot_boxes(study: Study, table: pd.DataFrame, path: Path) -> Path:
    """Draws :func:`box_figure` into `path`."""
    box_figure(study, table).savefig(path, dpi=110)
    return path


class _PlainLog(LogFormatter):
    """Log-axis tick labels as plain numbers (0.3, not 3e-01), choosing which
    ticks to label as matplotlib's own log formatter does."""

    def _num_to_string(self, x: float, vmin: float, vmax: float) -> str:
        return f"{x:g}"


def box_figure(study: Study, table: pd.DataFrame) -> Figure:
    """The ranking metric per controller, one panel per scenario, the
    controllers as rows named at the left of every row of panels (a reader of
    any panel finds the names beside it): a box (quartiles, whiskers
    5th-95th percentile) where a controller has at least :data:`FEW_SAMPLES`
    finite runs, each run as a point (with a median tick when there are two
    or more) where it has fewer; each controller in its colour
    (:func:`neurov.plotting.colours.controller_colours`), the first row on top."""
    metric = study.ranking_metric
    n = len(study.scenarios)
    cols = min(3, n)
    nrows = math.ceil(n / cols)
    names = [study.label(c) for c in study.controllers]
    colours = controller_colours(study.controllers)
    # Fixed margins [in], room for the names at the left: a layout engine
    # measures every label of every panel, several times.
    left = 0.25 + 0.062 * max(len(x) for x in names)
    panel_w, panel_h, gap_w, gap_h = 3.6, 0.24 * len(names) + 0.3, 0.35, 0.95
    width = left + panel_w * cols + gap_w * (cols - 1) + 0.2
    # Two title lines, more where they wrap in a narrow figure.
    top = 0.35 + 0.2 * (1 + math.ceil(7.5 / width))
    height = top + panel_h * nrows + gap_h * (nrows - 1) + 0.6
    fig = Figure(figsize=(width, height))
    fig.subplots_adjust(left=left / width, right=1 - 0.2 / width, bottom=0.6 / height,
                        top=1 - top / height, wspace=gap_w / panel_w, hspace=gap_h / panel_h)
    # Every panel on one scale: the scenarios are compared with each other too.
    axes = fig.subplots(nrows, cols, squeeze=False, sharey=True, sharex=True)
    label, factor = label_for_people(metric_label(metric))
    groups = {key: factor * g[metric].to_numpy(dtype=np.float64)
              for key, g in table.groupby(["scenario", "controller"], sort=False)}
    finite = np.concatenate([v[np.isfinite(v)] for v in groups.values()] or [np.ones(1)])
    log_scale = bool(finite.size) and bool(np.all(finite > 0))
    any_box = any_points = any_median = False
    for ax, s in zip(axes.flat, study.scenarios):
        data: dict[int, np.ndarray] = {}
        failures: dict[int, int] = {}
        for i, c in enumerate(study.controllers):
            vals = groups.get((s.name, c))
            if vals is None or not len(vals):
                continue
            data[i + 1] = vals[np.isfinite(vals)]
            failures[i + 1] = len(vals) - len(data[i + 1])
        boxed = [y for y, d in data.items() if len(d) >= FEW_SAMPLES]
        if boxed:
            parts = ax.boxplot([data[y] for y in boxed], positions=boxed, whis=(5, 95), showfliers=True,
                               manage_ticks=False, patch_artist=True, **_HORIZONTAL,
                               medianprops={"color": "black"})
            for y, box in zip(boxed, parts["boxes"]):
                box.set(facecolor=colours[study.controllers[y - 1]], alpha=0.6,
                        gid=f"controller:{study.controllers[y - 1]}")
            any_box = True
        few = [y for y, d in data.items() if 0 < len(d) < FEW_SAMPLES]
        for y in few:
            c = study.controllers[y - 1]
            ax.scatter(data[y], y + _spread(len(data[y])), s=14, color=colours[c], alpha=0.9, zorder=3,
                       gid=f"controller:{c}")
            if len(data[y]) > 1:
                ax.vlines(float(np.median(data[y])), y - 0.3, y + 0.3, color="black", lw=1.5, zorder=4,
                          gid="median")
                any_median = True
            any_points = True
        if log_scale:
            ax.set_xscale("log")
            # Plain numbers (0.3, not 3 x 10^-1): narrower, so the label beside them fits.
            ax.xaxis.set_major_formatter(_PlainLog())
            ax.xaxis.set_minor_formatter(_PlainLog(labelOnlyBase=False, minor_thresholds=(1, 0.4)))
        for y, nf in failures.items():
            if nf:
                ax.annotate(f"{nf} not finite", (1.0, y), xycoords=("axes fraction", "data"),
                            xytext=(-2, 0), textcoords="offset points", ha="right", va="center",
                            fontsize=7, color="C3")
        ax.set_title(s.name, fontsize=10, y=1.0)
        ax.set_xlabel(label, fontsize=8)
        ax.xaxis.set_tick_params(labelbottom=True)  # shared, but each panel is read on its own
        ax.grid(True, axis="x", alpha=0.3)
        ax.tick_params(which="both", labelsize=7)
        # Every row's first panel names the controllers (sharey hides the others' names).
        ax.yaxis.set_tick_params(labelleft=True)
    axes[0, 0].set_ylim(len(names) + 0.5, 0.5)  # the study's first controller on top
    axes[0, 0].set_yticks(range(1, len(names) + 1), names)
    for ax in axes[:, 1:].flat:
        ax.yaxis.set_tick_params(labelleft=False)
    for ax in axes.flat:
        for t in ax.get_yticklabels():
            t.set(fontsize=8)
    for ax in list(axes.flat)[n:]:
        ax.set_visible(False)
    how = []
    if any_box:
        how.append("boxes: quartiles, whiskers 5th-95th percentile")
    if any_points:
        how.append(("points: the run" if study.samples == 1 else f"points: each run (under {FEW_SAMPLES} per controller)")
                   + (", bar: median" if any_median else ""))
    over = ("one run per scenario and controller" if study.samples == 1 else
            f"over {study.samples} perturbed plants per scenario")
    fig.suptitle(f"{study.name}: {label}, {over}; one scale for every panel\n" + "; ".join(how), fontsize=10,
                 wrap=True, y=1 - 0.12 / height, va="top")
    return fig


def _fixed_positions(ax: Any) -> None:
    """Axis labels at fixed places beside the axes: placed automatically,
    each is moved clear of its axis's (and every shared axis's) tick labels
    at every draw, which costs more than drawing the panel."""
    ax.xaxis.set_label_coords(0.5, -0.16)
    ax.yaxis.set_label_coords(-0.2, 0.5)


def _curves(study: Study, records: Mapping[tuple[str, str, int], Mapping[str, Any]],
            scenario: Scenario) -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
    """Per controller with runs: time, and the median, 5th and 95th
    percentile of the position error over the samples."""
    out = {}
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
        if np.isnan(e).any():
            with np.errstate(all="ignore"), warnings.catch_warnings():
                # All-nan columns (every sample diverged there) warn; they plot as gaps.
                warnings.simplefilter("ignore", RuntimeWarning)
                lo, med, hi = np.nanpercentile(e, [5, 50, 95], axis=0)
        else:
            # The same numbers; nanpercentile goes column by column in Python.
            lo, med, hi = np.percentile(e, [5, 50, 95], axis=0)
        out[c] = (t, med, lo, hi)
    return out


def _finite_runs(t: np.ndarray, y: np.ndarray) -> list[np.ndarray]:
    """The stretches of the curve (t, y) between its gaps (nan), as (k, 2)
    arrays: a collection does not break a line at a nan as a Line2D does."""
    ok = np.isfinite(y)
    edges = np.flatnonzero(np.diff(np.concatenate([[False], ok, [False]]).astype(np.int8)))
    return [np.column_stack([t[a:b], y[a:b]]) for a, b in zip(edges[::2], edges[1::2]) if b - a > 1]


class BandPlotter:
    """A study's error-band figures, one per scenario: position error over
    time, one panel per controller, its median over the samples with the
    5th-95th percentile band, over the other controllers' medians in grey.

    Every scenario's figure has the same panels, so one figure object is
    built (axes, ticks, fixed margins, one line per controller and panel)
    and each scenario's data swapped into it: building and laying out the
    panels, not drawing the curves, is what costs time."""

    def __init__(self, study: Study) -> None:
        self.study = study
        names = study.controllers
        cols = min(5, len(names))
        rows = math.ceil(len(names) / cols)
        # The title wraps in a narrow figure (few controllers): room for its lines.
        width = 3.2 * cols
        top = 0.3 + 0.2 * math.ceil(11.0 / width)
        height = 2.6 * rows + 0.3 + top
        self.fig = fig = Figure(figsize=(width, height))
        # Fixed margins [in] instead of a layout engine: laid out once, not per figure.
        fig.subplots_adjust(left=0.75 / width, right=1 - 0.2 / width, bottom=0.55 / height,
                            top=1 - top / height, wspace=0.12, hspace=0.22)
        axes = fig.subplots(rows, cols, squeeze=False, sharex=True, sharey=True)
        self.axes = dict(zip(names, axes.flat))
        for ax in list(axes.flat)[len(names):]:
            ax.set_visible(False)
        self.others: dict[str, LineCollection] = {}
        self.median: dict[str, Any] = {}
        self.band: dict[str, Any] = {}
        colours = controller_colours(names)
        for i, (c, ax) in enumerate(self.axes.items()):
            # One artist for the nine or so grey lines: drawn per artist, not per point.
            self.others[c] = ax.add_collection(LineCollection([], colors=OTHERS_GREY, linewidths=0.6,
                                                              gid="others"),
                                               autolim=False)
            self.median[c] = ax.plot([], [], color=colours[c], lw=1.2, gid=f"controller:{c}")[0]
            ax.axvline(study.after, color="0.5", lw=0.6, ls=":")
            _fixed_positions(ax)
            ax.set_yscale("log")
            ax.yaxis.set_minor_locator(NullLocator())
            ax.set_title(study.label(c), fontsize=8, y=1.0)
            ax.grid(True, alpha=0.3)
            if i % cols == 0:
                ax.set_ylabel("position error [m]", fontsize=8)
            # The bottom panel of each column, even above an empty cell of the last row.
            if i + cols >= len(names):
                ax.set_xlabel("t [s]", fontsize=8)
                ax.xaxis.set_tick_params(labelbottom=True)
            ax.tick_params(labelsize=7)
        # wrap: a study of two controllers is narrower than its title.
        self.title = fig.suptitle("", fontsize=10, wrap=True, y=1 - 0.12 / height, va="top")

    def draw(self, records: Mapping[tuple[str, str, int], Mapping[str, Any]], scenario: Scenario,
             path: Path, dpi: int = 100) -> Path:
        """Draws `scenario`'s figure from the runs' `records` into `path`."""
        study = self.study
        curves = _curves(study, records, scenario)
        for c, ax in self.axes.items():
            if c in self.band:
                self.band.pop(c).remove()
            ax.set_visible(c in curves)
            if c not in curves:
                continue
            self.others[c].set_segments([seg for other, m in curves.items() if other != c
                                         for seg in _finite_runs(m[0], m[1])])
            t, med, lo, hi = curves[c]
            self.median[c].set_data(t, med)
            if study.samples > 1:
                self.band[c] = ax.fill_between(t, lo, hi, color=self.median[c].get_color(), alpha=0.25,
                                               lw=0, gid=f"controller:{c}")
        shown = np.concatenate([m[i] for m in curves.values() for i in (1, 3)] or [np.ones(1)])
        positive = shown[np.isfinite(shown) & (shown > 0)]
        medians = np.concatenate([m[1] for m in curves.values()] or [np.ones(1)])
        medians = medians[np.isfinite(medians) & (medians > 0)]
        bottom = max(1e-4, float(np.percentile(medians, 1)) / 3) if medians.size else 1e-4
        top = float(np.max(positive)) * 1.5 if positive.size else 1.0
        ax = next(iter(self.axes.values()))
        ax.set_ylim(bottom, max(top, bottom * 10))
        times = [m[0] for m in curves.values() if len(m[0])]
        if times:
            ax.set_xlim(min(float(t[0]) for t in times), max(float(t[-1]) for t in times))
        if study.samples == 1:
            self.title.set_text(f"{scenario.name}: each controller's one run; grey: the other controllers' runs")
        else:
            self.title.set_text(f"{scenario.name}: median and 5th-95th percentile over {study.samples} "
                                "perturbed plants; grey: the other controllers' medians")
        self.fig.savefig(path, dpi=dpi)
        return path


def plot_bands(study: Study, records: Mapping[tuple[str, str, int], Mapping[str, Any]],
               scenario: Scenario, path: Path) -> Path:
    """One scenario's error-band figure (:class:`BandPlotter`); for several,
    build one :class:`BandPlotter` and call its ``draw`` for each."""
    return BandPlotter(study).draw(records, scenario, path)
