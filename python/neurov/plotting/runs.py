"""Plots of closed-loop runs (:class:`neurov.Result`).

Every function returns a :class:`matplotlib.figure.Figure` built directly, not
through ``pyplot``: no global figure registry, no GUI backend, safe in scripts,
tests and threads. Write one with :func:`save` (or ``fig.savefig``)::

    from neurov.plotting import runs as plot
    fig = plot.xy_path([nn_result, linear_result])
    plot.save(fig, "xy.png")

Conventions: the desired trajectory is a solid black line and each run gets
its own colour and a dashed, dash-dot or dotted line, as in the paper's
Figs. 3 and 5. Positions are in metres; angles are shown in degrees (the
results hold radians). The horizontal path is drawn as a map: Y (east) to the
right, X (north) up, with its start and direction marked. Thrusters are
T1 to Tn (:func:`neurov.plotting.labels.thruster_label`).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from neurov.results.decimation import for_plotting
from neurov.plotting.labels import thruster_label
from neurov.plotting.paths import mark_start_and_direction
from neurov.results.timeseries import Result

__all__ = ["adaptive_norm", "control_inputs", "demanded_and_applied", "dof_time", "errors", "save", "xy_path"]

DOF_LABELS = ("x (north)", "y (east)", "z (depth)", "roll φ", "pitch θ", "yaw ψ")
DOF_UNITS = ("m", "m", "m", "deg", "deg", "deg")
FORCE_NAMES = ("X (surge)", "Y (sway)", "Z (heave)", "K (roll)", "M (pitch)", "N (yaw)")

_DESIRED = {"color": "black", "linestyle": "-", "linewidth": 1.5}
_COLOURS = ("tab:blue", "tab:red", "tab:green", "tab:orange", "tab:purple", "tab:brown",
            "tab:pink", "tab:olive", "tab:cyan", "tab:gray")
_DASHES = ("--", "-.", ":")
_GRID = {"alpha": 0.3}
_METRIC_DOFS = ("x", "y", "z", "roll", "pitch", "yaw")  # the keys of Result.metrics()["rmse"]


def _as_list(results: Result | Sequence[Result]) -> list[Result]:
    runs = [results] if isinstance(results, Result) else list(results)
    if not runs:
        raise ValueError("argument 'results' must hold at least one Result")
    for r in runs:
        if not isinstance(r, Result):
            raise TypeError(f"argument 'results' must hold neurov.Result, got {type(r).__name__}")
    return runs


def _drawn(results: Result | Sequence[Result]) -> list[Result]:
    """The rows of each run a plot draws (a long run's are decimated: see
    :mod:`neurov.results.decimation`)."""
    return [for_plotting(r) for r in _as_list(results)]


def _labels(runs: list[Result], labels: Sequence[str] | None) -> list[str]:
    if labels is not None:
        labels = list(labels)
        if len(labels) != len(runs):
            raise ValueError(f"argument 'labels' has {len(labels)} entries for {len(runs)} results")
        return [str(x) for x in labels]
    out = [r.controller for r in runs]
    # Two runs of the same controller (e.g. two scenarios) would otherwise be
    # indistinguishable in the legend.
    if len(set(out)) < len(out):
        out = [f"{r.controller} ({r.scenario.name})" for r in runs]
    if len(set(out)) < len(out):
        out = [f"{lab} #{i + 1}" for i, lab in enumerate(out)]
    return out


def _style(i: int) -> dict[str, Any]:
    return {"color": _COLOURS[i % len(_COLOURS)], "linestyle": _DASHES[i % len(_DASHES)],
            "linewidth": 1.3}


def _desired_shared(runs: list[Result]) -> bool:
    """True when every run was given the same desired trajectory, so one
    black line stands for all of them."""
    first = runs[0].eta_d
    return all(r.eta_d.shape == first.shape and np.allclose(r.eta_d, first, rtol=0, atol=1e-9)
               for r in runs[1:])


def _dofs(dofs: Sequence[int]) -> list[int]:
    out = [int(d) for d in dofs]
    if not out or any(not 0 <= d <= 5 for d in out):
        raise ValueError(f"argument 'dofs' must be a non-empty list of DOF indices 0..5, got {list(dofs)}")
    return out


def _display(values: np.ndarray, dof: int) -> np.ndarray:
    return np.degrees(values) if dof >= 3 else values


def _default_title(runs: list[Result], what: str) -> str:
    names = sorted({r.scenario.name for r in runs})
    return f"{what}: {', '.join(names)}"


def _warn_diverged(ax: Axes, runs: list[Result], labels: list[str]) -> None:
    bad = [lab for r, lab in zip(runs, labels) if r.diverged]
    if bad:
        ax.text(0.01, 0.01, "diverged: " + ", ".join(bad), transform=ax.transAxes, color="tab:red",
                fontsize=8, va="bottom", ha="left")


def xy_path(results: Result | Sequence[Result], labels: Sequence[str] | None = None,
            title: str | None = None) -> Figure:
    """The horizontal path as a map: desired (solid black) against each run
    (dashed, dash-dot, ...), with Y (east) [m] to the right and X (north) [m]
    up, equal scales. A filled black circle labelled "start" and arrow heads
    mark where the desired path starts and which way it goes; a hollow circle
    marks where each run starts.

    One axes; its lines are one desired path (one per run if the runs were
    given different desired paths) and then one path per run."""
    runs = _drawn(results)
    names = _labels(runs, labels)
    fig = Figure(figsize=(6.5, 6.0), layout="constrained")
    ax = fig.add_subplot()
    if _desired_shared(runs):
        ax.plot(runs[0].eta_d[:, 1], runs[0].eta_d[:, 0], label="desired", **_DESIRED)
        mark_start_and_direction(ax, runs[0].eta_d[:, 1], runs[0].eta_d[:, 0])
    else:
        for i, (r, lab) in enumerate(zip(runs, names)):
            colour = _COLOURS[i % len(_COLOURS)]
            ax.plot(r.eta_d[:, 1], r.eta_d[:, 0], label=f"desired ({lab})",
                    **{**_DESIRED, "color": colour, "alpha": 0.5})
            mark_start_and_direction(ax, r.eta_d[:, 1], r.eta_d[:, 0], colour, label_start=i == 0)
    for i, (r, lab) in enumerate(zip(runs, names)):
        ax.plot(r.eta[:, 1], r.eta[:, 0], label=lab, **_style(i))
        if len(r.t):
            ax.scatter([r.eta[0, 1]], [r.eta[0, 0]], s=25, facecolors="none",
                       edgecolors=_COLOURS[i % len(_COLOURS)], zorder=3)
    ax.set_xlabel("Y, east [m]")
    ax.set_ylabel("X, north [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, **_GRID)
    ax.legend(loc="best", fontsize=8)
    ax.set_title(title or _default_title(runs, "X-Y path"))
    _warn_diverged(ax, runs, names)
    return fig


def dof_time(results: Result | Sequence[Result], dofs: Sequence[int] = (0, 1, 2, 5),
             labels: Sequence[str] | None = None, title: str | None = None) -> Figure:
    """Each DOF of eta over time: desired eta_d (solid black) against the
    actual eta of each run. Positions in m, angles in deg.

    One axes per DOF in `dofs` (0..5: x, y, z, roll, pitch, yaw), stacked with
    a shared time axis; each holds one desired line (one per run if their
    desired trajectories differ) and one line per run."""
    runs = _drawn(results)
    names = _labels(runs, labels)
    dofs = _dofs(dofs)
    shared = _desired_shared(runs)
    fig = Figure(figsize=(8.0, 1.9 * len(dofs) + 0.8), layout="constrained")
    axes = fig.subplots(len(dofs), 1, sharex=True, squeeze=False)[:, 0]
    for ax, d in zip(axes, dofs):
        if shared:
            ax.plot(runs[0].t, _display(runs[0].eta_d[:, d], d), label="desired", **_DESIRED)
        for i, (r, lab) in enumerate(zip(runs, names)):
            if not shared:
                ax.plot(r.t, _display(r.eta_d[:, d], d), label=f"desired ({lab})",
                        **{**_DESIRED, "color": _COLOURS[i % len(_COLOURS)], "alpha": 0.5})
            ax.plot(r.t, _display(r.eta[:, d], d), label=lab, **_style(i))
        ax.set_ylabel(f"{DOF_LABELS[d]} [{DOF_UNITS[d]}]")
        ax.grid(True, **_GRID)
    axes[0].legend(loc="best", fontsize=8)
    axes[-1].set_xlabel("t [s]")
    axes[0].set_title(title or _default_title(runs, "Pose, desired and actual"))
    _warn_diverged(axes[0], runs, names)
    return fig


def errors(results: Result | Sequence[Result], dofs: Sequence[int] | None = None,
           labels: Sequence[str] | None = None, title: str | None = None) -> Figure:
    """Tracking error eta - eta_d per DOF over time (m for positions, deg for
    angles), one line per run; the legend gives each run's RMS error over the
    metrics window of ``Result.metrics()`` (t >= 10 s, stated there) and the
    skipped transient is shaded.

    One axes per DOF in `dofs`, one line per run in each. Without `dofs`:
    x, y, z and yaw, less those no run has an error in (a depth step's x, y
    and yaw), which the title names instead of drawing three flat panels; a
    DOF asked for in `dofs` is drawn, with a note if it has no error."""
    runs = _as_list(results)
    names = _labels(runs, labels)
    quiet: list[int] = []
    if dofs is None:
        asked = [0, 1, 2, 5]
        flat = [d for d in asked if all(_no_error(r, d) for r in runs)]
        dofs = [d for d in asked if d not in flat] or asked[:1]
        quiet = [d for d in flat if d not in dofs]
    dofs = _dofs(dofs)
    fig = Figure(figsize=(8.0, 1.9 * len(dofs) + 0.8), layout="constrained")
    axes = fig.subplots(len(dofs), 1, sharex=True, squeeze=False)[:, 0]
    # The RMS of the whole run over the metrics window, not of the rows drawn.
    window = [r.metrics() for r in runs]
    drawn = [for_plotting(r) for r in runs]
    for ax, d in zip(axes, dofs):
        for i, (r, lab) in enumerate(zip(drawn, names)):
            rms, start = float(_display(window[i]["rmse"][_METRIC_DOFS[d]], d)), window[i]["window_start_s"]
            ax.plot(r.t, _display(r.error[:, d], d), **_style(i),
                    label=f"{lab} (RMS {rms:.3g} {DOF_UNITS[d]} over t ≥ {start:g} s)")
            if i == 0 and start > r.t[0]:
                ax.axvspan(r.t[0], start, color="0.92", zorder=0)
        if all(_no_error(r, d) for r in runs):
            ax.text(0.5, 0.5, f"no {DOF_LABELS[d].split()[0]} error in any run", transform=ax.transAxes,
                    ha="center", va="center", fontsize=9, color="0.3")
        ax.set_ylabel(f"{DOF_LABELS[d].split()[0]} error [{DOF_UNITS[d]}]")
        ax.grid(True, **_GRID)
        ax.legend(loc="best", fontsize=7)
    axes[-1].set_xlabel("t [s]")
    heading = title or _default_title(runs, "Tracking error η − η_d")
    if quiet:
        heading += f"\nno error in {', '.join(DOF_LABELS[d].split()[0] for d in quiet)} (not drawn)"
    axes[0].set_title(heading)
    _warn_diverged(axes[0], runs, names)
    return fig


def _no_error(r: Result, dof: int) -> bool:
    """True if the run's `dof` error stays within 1e-9 (m or rad) all run."""
    e = r.error[:, dof]
    return bool(np.all(np.abs(e[np.isfinite(e)]) <= 1e-9)) and bool(np.isfinite(e).all())


def _thrust_limits(result: Result) -> tuple[np.ndarray, np.ndarray] | None:
    """The vehicle file's thrust limits, if the run used its thrusters."""
    if not result.scenario.use_thrusters:
        return None
    try:
        t = result.scenario.vehicle_data().thrusters
    except (OSError, ValueError):
        return None
    if t is None or len(t["max_thrust"]) != result.thrusts.shape[1]:
        return None
    return t["min_thrust"], t["max_thrust"]


def demanded_and_applied(ax: Axes, t: np.ndarray, demanded: np.ndarray, applied: np.ndarray,
                         dofs: Sequence[int]) -> None:
    """Draws, for each DOF in `dofs`, the tau the controller demanded and the
    tau the plant received, one colour per DOF: a DOF whose applied tau is
    the demanded one all run is one solid line ("applied = demanded"); where
    they differ (saturation, allocation, lag, a failed thruster) the applied
    tau is solid, the demanded dashed on top of it and the gap between them
    shaded, so that a saturated stretch is seen. One legend entry per line."""
    for j, i in enumerate(dofs):
        colour = _COLOURS[j % len(_COLOURS)]
        d, a = demanded[:, i], applied[:, i]
        scale = max(1.0, float(np.max(np.abs(d), initial=0.0)))
        gap = np.abs(d - a) > 1e-6 * scale
        if not gap.any():
            ax.plot(t, a, color=colour, linewidth=1.2, label=f"{FORCE_NAMES[i]} applied = demanded")
            continue
        ax.plot(t, a, color=colour, linewidth=1.6, label=f"{FORCE_NAMES[i]} applied", gid="applied")
        ax.plot(t, d, color=colour, linewidth=1.0, linestyle=(0, (4, 2)), label=f"{FORCE_NAMES[i]} demanded",
                gid="demanded")
        ax.fill_between(t, d, a, where=gap, color=colour, alpha=0.2, linewidth=0, interpolate=True)


def control_inputs(result: Result, show_thrusts: bool = True, title: str | None = None) -> Figure:
    """The control of one run: demanded tau and the tau the plant actually
    received (after thrust allocation, saturation, lag and failures, mean
    over each control interval; :func:`demanded_and_applied`), forces [N] in
    the first panel and moments [N m] in the second, one colour per DOF. With
    thrusters and `show_thrusts`, a third panel holds each thruster's thrust
    [N] with the limits as dotted grey lines (one per distinct limit value).

    Axes: 2, or 3 with thrusts. Lines: one per DOF where applied = demanded,
    two (applied, demanded) where they differ; the thrust panel has one per
    thruster plus the limit lines."""
    if not isinstance(result, Result):
        raise TypeError(f"argument 'result' must be a neurov.Result, got {type(result).__name__}")
    result = for_plotting(result)
    has_thrusts = show_thrusts and result.thrusts.shape[1] > 0
    panels = 3 if has_thrusts else 2
    fig = Figure(figsize=(9.5, 2.5 * panels + 0.6), layout="constrained")
    axes = fig.subplots(panels, 1, sharex=True, squeeze=False)[:, 0]
    for ax, block, unit in ((axes[0], range(0, 3), "N"), (axes[1], range(3, 6), "N m")):
        demanded_and_applied(ax, result.t, result.tau_demanded, result.tau_applied, block)
        ax.set_ylabel(f"{'force' if unit == 'N' else 'moment'} [{unit}]")
        ax.grid(True, **_GRID)
        # Outside the axes: inside, a legend hides the largest values, which
        # are the interesting ones (saturation, wind-up).
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7, borderaxespad=0)
    if has_thrusts:
        ax = axes[2]
        n = result.thrusts.shape[1]
        for i in range(n):
            ax.plot(result.t, result.thrusts[:, i], color=_COLOURS[i % len(_COLOURS)], linewidth=1.0,
                    label=thruster_label(i))
        limits = _thrust_limits(result)
        if limits is not None:
            for k, v in enumerate(sorted(set(np.concatenate(limits).tolist()))):
                ax.axhline(v, color="0.5", linestyle=":", linewidth=1.0, label="limit" if k == 0 else None)
        for f in result.scenario.thruster_failures:
            ax.axvline(f.time, color="tab:red", alpha=0.4, linewidth=4, zorder=0)
            what = "fails" if f.efficiency == 0 else f"at {f.efficiency:.0%}"
            ax.annotate(f"{thruster_label(f.index)} {what}", xy=(f.time, 1.0), xycoords=("data", "axes fraction"),
                        xytext=(3, -3), textcoords="offset points", va="top", fontsize=7, color="tab:red")
        ax.set_ylabel("thrust [N]")
        ax.grid(True, **_GRID)
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7, borderaxespad=0,
                  title="thruster", title_fontsize=7)
    axes[-1].set_xlabel("t [s]")
    axes[0].set_title(title or f"Control inputs: {result.controller} ({result.scenario.name})")
    return fig


def adaptive_norm(results: Result | Sequence[Result], labels: Sequence[str] | None = None,
                  title: str | None = None) -> Figure:
    """How far each controller's adaptive part has moved: the Frobenius norm
    of the NN weights ||W||_F, or ||theta_hat|| for the linear adaptive
    controller (always 0 for PD), over time. Steady growth means drift
    (the pure gradient law with an approximation error or a disturbance).

    One axes, one line per run."""
    runs = _drawn(results)
    names = _labels(runs, labels)
    fig = Figure(figsize=(8.0, 3.6), layout="constrained")
    ax = fig.add_subplot()
    for i, (r, lab) in enumerate(zip(runs, names)):
        what = {"nn": "‖Ŵ‖_F", "linear": "‖θ̂‖", "pd": "none"}.get(_kind(r), "norm")
        ax.plot(r.t, r.adaptive_norm, label=f"{lab}: {what}", **{**_style(i), "linestyle": "-"})
    ax.set_xlabel("t [s]")
    # The weights (or theta_hat) carry the units of different regressor
    # columns: their norm has no single unit.
    ax.set_ylabel("norm of the adapted parameters [mixed units]")
    ax.grid(True, **_GRID)
    ax.legend(loc="best", fontsize=8)
    ax.set_title(title or _default_title(runs, "Adaptive parameters"))
    _warn_diverged(ax, runs, names)
    return fig


def _kind(r: Result) -> str:
    """The run's controller type; the scenario's own unless the run was given
    another controller (its name then differs from the scenario's)."""
    spec = r.scenario.controller
    if r.controller == spec.name:
        return spec.type
    if r.theta.shape[1] > 0:
        return "linear"
    return {"NN adaptive": "nn", "linear adaptive": "linear", "PD": "pd"}.get(r.controller, "")


def save(fig: Figure, path: str | Path, dpi: int = 120) -> Path:
    """Writes `fig` to `path` (format from the suffix, e.g. .png, .pdf, .svg),
    creating missing parent folders; returns the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=dpi)
    return path
