"""Error against effort: each controller's front (its non-dominated trials),
over both vehicles together (the two objectives Optuna searched) and per
vehicle (each vehicle's own runs), as pareto.csv and one figure for all
controllers (fronts.png)."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import pandas as pd

from neurov.study.tables import write_table
from neurov.tuning.spec import Tuning

__all__ = ["ALL", "front", "judged_points", "pareto_table", "draw_fronts"]

ALL = "all"
"""The ``front`` of pareto.csv over every vehicle's runs (the searched objectives)."""


def front(points: Sequence[tuple[float, float]]) -> list[int]:
    """The indices of the non-dominated points (both coordinates minimised),
    by increasing effort; of equal points, the first."""
    order = sorted(range(len(points)), key=lambda i: (points[i][1], points[i][0], i))
    out: list[int] = []
    best = math.inf
    for i in order:
        err, eff = points[i]
        if math.isfinite(err) and math.isfinite(eff) and err < best:
            out.append(i)
            best = err
    return out


def judged_points(study: Any) -> list[Any]:
    """The finished trials with an effort, the feasible ones if any is."""
    import optuna

    trials = [t for t in study.get_trials(deepcopy=False, states=(optuna.trial.TrialState.COMPLETE,))
              if t.user_attrs.get("by_vehicle")]
    feasible = [t for t in trials if t.user_attrs.get("feasible", True)]
    return sorted(feasible or trials, key=lambda t: t.number)


def _error_effort(t: Any, where: str) -> tuple[float, float]:
    if where == ALL:
        return float(t.values[0]), float(t.user_attrs["effort"])
    e = t.user_attrs["by_vehicle"].get(where)
    return (math.inf, math.inf) if e is None else (float(e[0]), float(e[1]))


def vehicles_of(studies: Mapping[str, Any]) -> list[str]:
    return sorted({v for s in studies.values() for t in judged_points(s) for v in t.user_attrs["by_vehicle"]})


def pareto_table(tuning: Tuning, studies: Mapping[str, Any]) -> pd.DataFrame:
    """One row per non-dominated trial of each controller on each front:
    ``front`` (``all``, or a vehicle), ``controller``, ``trial``, ``error``
    and ``effort`` (the objective's and the effort metric's aggregates on that
    front's runs), the parameters (``param_<key>``)."""
    s = tuning.settings
    rows = []
    for where in [ALL, *vehicles_of(studies)]:
        for controller, study in studies.items():
            trials = judged_points(study)
            points = [_error_effort(t, where) for t in trials]
            for i in front(points):
                t = trials[i]
                rows.append({"front": where, "controller": controller, "trial": t.number,
                             "error": points[i][0], "effort": points[i][1], "error_metric": s.objective,
                             "effort_metric": s.effort, **{f"param_{k}": v for k, v in t.params.items()}})
    return pd.DataFrame(rows)


def write_pareto(tuning: Tuning, studies: Mapping[str, Any], path: Path) -> Path:
    return write_table(pareto_table(tuning, studies), path)


def draw_fronts(tuning: Tuning, studies: Mapping[str, Any], path: Path, *,
                hand_set: Mapping[str, Mapping[str, Sequence[float]]] | None = None,
                effort_at: Mapping[str, float] | None = None,
                picks: pd.DataFrame | None = None) -> Path:
    """One panel per vehicle: every controller's front (its trials faint), its
    hand-set gains (a cross), the effort where the fronts are read (a dashed
    line) and the trial read there (a ring)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    vehicles = vehicles_of(studies)
    fig, axes = plt.subplots(1, max(1, len(vehicles)), figsize=(5.5 * max(1, len(vehicles)), 4.5), squeeze=False)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for ax, v in zip(axes[0], vehicles):
        shown: list[float] = [effort_at[v]] if effort_at and v in effort_at else []
        for n, (controller, study) in enumerate(studies.items()):
            c = colours[n % len(colours)]
            trials = judged_points(study)
            pts = [_error_effort(t, v) for t in trials]
            ok = [p for p in pts if math.isfinite(p[0]) and math.isfinite(p[1])]
            ax.plot([p[1] for p in ok], [p[0] for p in ok], ".", color=c, alpha=0.2, ms=4)
            f = [pts[i] for i in front(pts)]
            shown += [p[1] for p in f]
            ax.step([p[1] for p in f], [p[0] for p in f], where="post", color=c, marker="o", ms=3,
                    label=controller)
            if hand_set and controller in hand_set and v in hand_set[controller]:
                err, eff = hand_set[controller][v]
                ax.plot([eff], [err], "x", color=c, ms=8, mew=2)
            if picks is not None and len(picks):
                row = picks[(picks["controller"] == controller) & (picks["vehicle"] == v)]
                if len(row):
                    ax.plot(row["effort"], row["error"], "o", mfc="none", mec=c, ms=11, mew=1.5)
        if effort_at and v in effort_at:
            ax.axvline(effort_at[v], color="k", ls="--", lw=1)
        ax.set_xscale("log")
        if shown:  # the fronts, not the diverged trials' thrust far to the right
            ax.set_xlim(min(shown) / 1.3, max(shown) * 1.3)
        ax.set_yscale("log")
        ax.set_xlabel(f"{tuning.settings.aggregate} {tuning.settings.effort} (training plants)")
        ax.set_ylabel(f"{tuning.settings.aggregate} {tuning.settings.objective} (penalised)")
        ax.set_title(f"{v}: error against effort")
    axes[0][0].legend(fontsize=7, loc="upper right")
    fig.suptitle("fronts (x: hand-set gains; ring: the trial read at the dashed effort)", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
