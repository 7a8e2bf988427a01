"""What a tuning writes besides its storage: trials.csv (every trial), the
best trial per controller, best.toml (those as a study file's
``[controllers]``) and the figures."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import pandas as pd

from neurov.study.figures import FIGURE_STATE
from neurov.study.log import LOG_NAME
from neurov.study.tables import write_table
from neurov.tuning.space import apply_values
from neurov.tuning.spec import Tuning
from neurov.tuning.toml_text import toml_text

__all__ = ["best_trial", "best_tables", "discard_stale_verdict", "draw_tuning_figures", "trials_table", "unusable",
           "write_best_toml"]


def _finished(study: Any) -> list[Any]:
    import optuna

    return sorted(study.get_trials(deepcopy=False, states=(optuna.trial.TrialState.COMPLETE,)),
                  key=lambda t: t.number)


def _value(t: Any) -> float:
    """A finished trial's objective (its first, the error, when there are two)."""
    return float(t.values[0])


def _judged(study: Any) -> list[Any]:
    """The finished trials and those the pruner stopped, in number order."""
    import optuna

    S = optuna.trial.TrialState
    return sorted((t for t in study.get_trials(deepcopy=False, states=(S.COMPLETE, S.PRUNED))
                   if t.state == S.COMPLETE or t.user_attrs.get("reason") == "pruned"), key=lambda t: t.number)


def trials_table(tuning: Tuning, studies: dict[str, Any]) -> pd.DataFrame:
    """One row per trial of every controller: its state (``complete`` or
    ``pruned``), parameters, objective, failures (and why) and time. A pruned
    trial has no objective: ``pruned_value`` is its running objective when the
    pruner stopped it after ``runs`` runs. Trials cut short otherwise
    (interrupted, or past the budget) are left out."""
    import optuna

    rows = []
    for controller, study in studies.items():
        for t in _judged(study):
            reasons = t.user_attrs.get("reasons", {})
            pruned = t.state != optuna.trial.TrialState.COMPLETE
            last = t.intermediate_values[max(t.intermediate_values)] if pruned and t.intermediate_values else None
            rows.append({
                "controller": controller, "trial": t.number, "state": "pruned" if pruned else "complete",
                "objective": None if pruned else _value(t), "pruned_value": last,
                "feasible": t.user_attrs.get("feasible", True), "runs": t.user_attrs.get("runs"),
                "failures": t.user_attrs.get("failures"),
                "failure_reasons": "; ".join(f"{n} x {r}" for r, n in reasons.items()),
                "seconds": t.user_attrs.get("seconds"),
                **{f"param_{k}": v for k, v in t.params.items()},
                # With an effort metric: its aggregate (the second objective, or the penalised one's).
                **({"effort": t.user_attrs.get("effort")} if tuning.settings.effort is not None else {}),
            })
    return pd.DataFrame(rows)


def best_trial(study: Any) -> Any | None:
    """The feasible trial of lowest objective (the lowest of all if none is feasible)."""
    trials = _finished(study)
    feasible = [t for t in trials if t.user_attrs.get("feasible", True)]
    pool = feasible or trials
    return min(pool, key=lambda t: (_value(t), t.number)) if pool else None


def unusable(studies: dict[str, Any]) -> dict[str, str]:
    """Controller key -> why its best trial is no tuning at all: no trial was
    feasible, or every run of the best one failed (every trial diverged,
    say); best.toml then holds the least bad gains, not good ones."""
    out = {}
    for controller, study in studies.items():
        best = best_trial(study)
        if best is None:
            continue
        a = best.user_attrs
        reasons = "; ".join(f"{n} x {r}" for r, n in a.get("reasons", {}).items())
        failed = f"{a.get('failures')} of its {a.get('runs')} runs failed ({reasons})"
        if not a.get("feasible", True):
            out[controller] = f"no trial was feasible; the least bad, trial {best.number}: {failed}"
        elif a.get("runs") and a.get("failures") == a.get("runs"):
            out[controller] = f"every run of every trial failed; trial {best.number}: {failed}"
    return out


def best_tables(tuning: Tuning, studies: dict[str, Any]) -> dict[str, dict[str, Any]]:
    """Controller key -> its table with the best trial's values."""
    out = {}
    for controller, study in studies.items():
        best = best_trial(study)
        if best is None:
            continue
        table = tuning.study_table["controllers"][controller]
        out[controller] = apply_values(table, tuning.search[controller], best.params)
    return out


def write_best_toml(tuning: Tuning, studies: dict[str, Any], path: Path,
                    tables: dict[str, dict[str, Any]] | None = None, notes: list[str] | None = None) -> Path:
    """best.toml: the best trials' tables, or `tables` described by `notes`
    (the trials read at equal effort)."""
    s = tuning.settings
    head = [f"# Tuned by `neurov tune` from {Path(tuning.source).name}: {s.trials} trials per controller, "
            f"sampler {s.sampler} (seed {s.seed}),",
            f"# objective: the {s.aggregate} of {s.objective} over {s.train_samples} training plants per "
            f"scenario (a failed run counts {s.failure_penalty:g}).",
            "# Paste the tables into a study file's [controllers]."]
    if tables is not None:
        head += [f"# {n}" for n in notes or []]
    for controller, study in studies.items() if tables is None else ():
        best = best_trial(study)
        if best is not None:
            note = "" if best.user_attrs.get("feasible", True) else " (no trial was feasible: the least bad)"
            head.append(f"# {controller}: trial {best.number}, objective {_value(best):.6g}{note}")
    tables = best_tables(tuning, studies) if tables is None else tables
    path.write_text("\n".join(head) + "\n\n" + toml_text({"controllers": tables}))
    return path


def _importance(study: Any) -> list[str]:
    """The searched parameters, the most important first (Optuna's PED-ANOVA
    evaluator: its fANOVA one needs scikit-learn); in search order when
    there are too few trials to tell."""
    names = list(_finished(study)[0].params) if _finished(study) else []
    if len(names) < 2 or len(_finished(study)) < 3:
        return names
    import warnings

    import optuna
    from optuna.importance import PedAnovaImportanceEvaluator, get_param_importances

    try:
        with warnings.catch_warnings():
            # Experimental in Optuna (its interface may change), not in what it computes.
            warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
            warnings.simplefilter("ignore", UserWarning)  # with two objectives: "low target values" is meant
            ranked = get_param_importances(study, evaluator=PedAnovaImportanceEvaluator(),
                                           target=_value if len(study.directions) > 1 else None)
    except (ValueError, RuntimeError, ZeroDivisionError):  # a parameter that never varied, for one
        return names
    return list(ranked)


def draw_tuning_figures(tuning: Tuning, studies: dict[str, Any], out: Path) -> list[Path]:
    """Per controller: the best objective against the trial number, and the
    objective over the two most important parameters."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    drawn = []
    for controller, study in studies.items():
        trials = _finished(study)
        if not trials:
            continue
        numbers = [t.number for t in trials]
        values = [_value(t) for t in trials]
        best = [min(values[: i + 1]) for i in range(len(values))]
        fig, ax = plt.subplots(figsize=(6, 3.5))
        ax.plot(numbers, values, "o", ms=3, alpha=0.5, label="trial")
        ax.step(numbers, best, where="post", label="best so far")
        ax.set_xlabel("trial")
        ax.set_ylabel(f"{tuning.settings.aggregate} {tuning.settings.objective} (penalised)")
        ax.set_title(f"{controller}: best objective against the trial")
        ax.legend()
        fig.tight_layout()
        path = out / f"history_{controller}.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        drawn.append(path)

        names = _importance(study)
        if not names:
            continue
        fig, ax = plt.subplots(figsize=(5.5, 4.5))
        finite = [v if math.isfinite(v) else float("nan") for v in values]
        x = [t.params.get(names[0]) for t in trials]
        if len(names) >= 2:
            y = [t.params.get(names[1]) for t in trials]
            sc = ax.scatter(x, y, c=finite, cmap="viridis_r", s=18)
            fig.colorbar(sc, ax=ax, label=tuning.settings.objective)
            ax.set_ylabel(names[1])
        else:
            ax.plot(x, finite, "o", ms=4)
            ax.set_ylabel(tuning.settings.objective)
        ax.set_xlabel(names[0])
        for name, axis in zip(names[:2], ("x", "y") if len(names) >= 2 else ("x",)):
            p = next(q for q in tuning.search[controller] if q.key == name)
            if p.log:
                getattr(ax, f"set_{axis}scale")("log")
        ax.set_title(f"{controller}: objective over its two most important parameters"
                     if len(names) >= 2 else f"{controller}: objective over {names[0]}")
        fig.tight_layout()
        path = out / f"parameters_{controller}.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        drawn.append(path)
    return drawn


def write_trials(tuning: Tuning, studies: dict[str, Any], path: Path) -> Path:
    return write_table(trials_table(tuning, studies), path)


# --- the verdict's folder ----------------------------------------------------------------------

# What a study writes in its folder besides its figures (figures.json lists those).
_STUDY_FILES = ("study.json", LOG_NAME, "runs.csv", "runs.parquet", "summary.csv", "league.md", "timing.json",
                FIGURE_STATE)


def discard_stale_verdict(folder: Path, fingerprint: str) -> list[Path]:
    """A verdict of other tuned gains (more trials since, another process's
    better trial) is derived from the storage and best.toml alone: its files
    are removed (and the verdict run again) rather than refused as a study
    folder would be. Only the study's own files go (those it writes, its
    figures as figures.json lists them); anything else in the folder, a
    user's notes say, stays. Returns the paths removed."""
    meta = folder / "study.json"
    if not meta.exists():
        return []
    try:
        old = json.loads(meta.read_text()).get("fingerprint")
    except (json.JSONDecodeError, AttributeError, UnicodeDecodeError):
        old = None
    if old == fingerprint:
        return []
    try:
        drawn = json.loads((folder / FIGURE_STATE).read_text())
    except (OSError, json.JSONDecodeError, UnicodeDecodeError):
        drawn = {}
    figures = [n for n in drawn if isinstance(n, str) and Path(n).name == n and n.endswith(".png")] \
        if isinstance(drawn, dict) else []
    removed = []
    # study.json last: a stop half-way leaves a folder still known as the stale verdict.
    for name in [*figures, *_STUDY_FILES[1:], _STUDY_FILES[0]]:
        path = folder / name
        if path.is_file() or path.is_symlink():
            path.unlink()
            removed.append(path)
    return removed
