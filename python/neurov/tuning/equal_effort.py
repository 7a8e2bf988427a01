"""Controllers compared at equal effort: each controller's front read at a
stated effort per vehicle (``[tune] effort_at``: a controller's hand-set
effort on the training plants, or numbers), the trial read there run in the
verdict on the held-out plants, and the verdict's statistics among these
controllers alone, as data and a few sentences."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import pandas as pd

from neurov.study.spec import Study
from neurov.study.tables import summary_table, write_table
from neurov.tuning.objective import evaluate
from neurov.tuning.pareto import draw_fronts, judged_points, write_pareto
from neurov.tuning.space import apply_values
from neurov.tuning.spec import Tuning
from neurov.tuning.trial_runs import TrialRunner

__all__ = ["Fronts", "at_equal_effort", "effort_levels", "equal_effort_picks", "hand_set_points", "read_fronts",
           "write_equal_effort"]


def hand_set_points(tuning: Tuning, studies: Mapping[str, Any], runner: TrialRunner) -> dict[str, Any]:
    """Controller -> vehicle -> [error, effort] of its hand-set gains on the
    training plants (as a trial is judged): its trial of them, or a run of
    them kept in its Optuna study, so that a resumed tuning does not run
    them again."""
    import optuna

    out = {}
    for controller, study in studies.items():
        known = study.user_attrs.get("hand_set")
        first = [t for t in study.get_trials(deepcopy=False, states=(optuna.trial.TrialState.COMPLETE,))
                 if t.user_attrs.get("hand_set") and t.user_attrs.get("by_vehicle")]
        if known is None and first:
            known = first[0].user_attrs["by_vehicle"]  # the hand-set gains were its first trial
        if known is None:
            plain = dataclasses.replace(tuning, search={**tuning.search, controller: []})
            known = evaluate(plain, controller, {}, runner).by_vehicle
            study.set_user_attr("hand_set", known)
        out[controller] = known
    return out


def effort_levels(tuning: Tuning, hand_set: Mapping[str, Mapping[str, Any]]) -> dict[str, float]:
    """Vehicle -> the effort where the fronts are read."""
    at = tuning.settings.effort_at
    if isinstance(at, tuple):
        return dict(at)
    key = at if isinstance(at, str) else next(iter(tuning.search))
    if key in hand_set:
        return {v: float(p[1]) for v, p in hand_set[key].items()}
    plain = dataclasses.replace(tuning, search={**tuning.search, key: []})
    with TrialRunner(1) as runner:
        return {v: float(p[1]) for v, p in evaluate(plain, key, {}, runner).by_vehicle.items()}


def _best_under(trials: list[Any], vehicles: list[str], levels: Mapping[str, float]) -> tuple[Any, bool]:
    """The trial of least mean error whose effort is at most the level on
    every vehicle of `vehicles`; without one, the trial that exceeds its
    levels least (False: not within them)."""
    def point(t: Any, v: str) -> tuple[float, float]:
        e = t.user_attrs["by_vehicle"].get(v, [math.inf, math.inf])
        return float(e[0]), float(e[1])

    within = [t for t in trials if all(point(t, v)[1] <= levels[v] for v in vehicles)]
    if within:
        return min(within, key=lambda t: (sum(point(t, v)[0] for v in vehicles), t.number)), True
    return min(trials, key=lambda t: (max(point(t, v)[1] / levels[v] for v in vehicles), t.number)), False


def equal_effort_picks(tuning: Tuning, studies: Mapping[str, Any],
                       levels: Mapping[str, float]) -> tuple[dict[str, dict[str, Any]], pd.DataFrame]:
    """Per controller, its table read at `levels` and one row per vehicle of
    the trial read there. A controller whose searched parameters are all one
    vehicle's or another's is read per vehicle (a vehicle's runs depend on
    its own gains alone, so each vehicle's gains come from the trial best on
    it); one with a common parameter (the NN's width) is read at one trial."""
    tables, rows = {}, []
    for controller, study in studies.items():
        trials = judged_points(study)
        if not trials:
            continue
        params = tuning.search[controller]
        vehicles = [v for v in levels if any(v in t.user_attrs["by_vehicle"] for t in trials)]
        per_vehicle = all(p.vehicle is not None for p in params)
        chosen = {v: _best_under(trials, [v], levels) for v in vehicles} if per_vehicle else \
            dict.fromkeys(vehicles, _best_under(trials, vehicles, levels))
        values = {}
        for p in params:
            t = chosen[p.vehicle][0] if p.vehicle is not None and p.vehicle in chosen else \
                next(iter(chosen.values()))[0]
            values[p.key] = t.params[p.key]
        tables[controller] = apply_values(tuning.study_table["controllers"][controller], params, values)
        for v, (t, ok) in chosen.items():
            err, eff = t.user_attrs["by_vehicle"][v]
            rows.append({"controller": controller, "vehicle": v, "trial": t.number, "error": float(err),
                         "effort": float(eff), "effort_at": levels[v], "within": ok})
    return tables, pd.DataFrame(rows)


def at_equal_effort(study: Study, runs: pd.DataFrame, picks: pd.DataFrame, levels: Mapping[str, float],
                    effort_metric: str, source: str = "") -> tuple[pd.DataFrame, str]:
    """The verdict's statistics among the controllers read at equal effort
    alone (their ranks, medians, intervals and paired ratios, as a study's
    summary), per scenario with its vehicle and each controller's median
    effort on the held-out plants; and a few sentences that say so."""
    tuned = [c for c in study.controllers if c in set(picks["controller"])]
    sub = dataclasses.replace(study, controllers=tuned, head_to_head=[],
                              reference=study.reference if study.reference in tuned else tuned[0],
                              also_show=list(dict.fromkeys([*study.also_show, effort_metric])))
    summary = summary_table(sub, runs[runs["controller"].isin(tuned)])
    vehicle = dict(zip(runs["scenario"], runs["vehicle"]))
    summary.insert(1, "vehicle", summary["scenario"].map(vehicle))
    summary["effort_at"] = summary["vehicle"].map(levels)
    within = {(r.controller, r.vehicle): bool(r.within) for r in picks.itertuples()}
    summary["within"] = [within.get((c, v), False) for c, v in zip(summary["controller"], summary["vehicle"])]
    return summary, equal_effort_words(summary, source)


def equal_effort_words(summary: pd.DataFrame, source: str = "") -> str:
    """What the table says, vehicle by vehicle: who ranks first on how many
    of its scenarios, and which fronts did not reach the stated effort."""
    said = []
    for v, g in summary.groupby("vehicle", sort=True):
        n = g["scenario"].nunique()
        firsts = g[g["rank"] == 1]["controller"].value_counts()
        lead = ", ".join(f"{c} ({k} of {n})" for c, k in firsts.items())
        level = float(g["effort_at"].iloc[0])
        said.append(f"On {v}, read at an effort of {level:.3g}{' (' + source + ')' if source else ''}, "
                    f"rank 1 on its {n} scenario(s): {lead}.")
        over = sorted(set(g[~g["within"]]["controller"]))
        if over:
            said.append(f"On {v} the front of {', '.join(over)} does not reach that effort: the least-effort "
                        f"trial was read instead.")
    return " ".join(said)


@dataclasses.dataclass
class Fronts:
    """A two-objective tuning's fronts read at equal effort (what the verdict runs)."""

    levels: dict[str, float]
    source: str
    """Where the levels come from, in words."""
    tables: dict[str, dict[str, Any]]
    picks: pd.DataFrame
    hand_set: dict[str, Any]


def read_fronts(tuning: Tuning, studies: Mapping[str, Any], hand_set: dict[str, Any], out: Path,
                plots: bool = True) -> Fronts:
    """pareto.csv, picks.csv (the trials read at equal effort) and fronts.png."""
    levels = effort_levels(tuning, hand_set)
    at = tuning.settings.effort_at
    source = "the stated effort" if isinstance(at, tuple) else \
        f"the effort of {at if isinstance(at, str) else next(iter(tuning.search))}'s hand-set gains on the " \
        "training plants"
    tables, picks = equal_effort_picks(tuning, studies, levels)
    write_pareto(tuning, studies, out / "pareto.csv")
    write_table(picks, out / "picks.csv")
    if plots:
        draw_fronts(tuning, studies, out / "fronts.png", hand_set=hand_set, effort_at=levels, picks=picks)
    return Fronts(levels, source, tables, picks, hand_set)


def write_equal_effort(tuning: Tuning, fronts: Fronts, study: Study, runs: pd.DataFrame,
                       out: Path) -> tuple[pd.DataFrame, str]:
    """equal_effort.csv (the verdict among the controllers read at equal
    effort) and equal_effort.md (its sentences)."""
    summary, words = at_equal_effort(study, runs, fronts.picks, fronts.levels, str(tuning.settings.effort),
                                     fronts.source)
    write_table(summary, out / "equal_effort.csv")
    (out / "equal_effort.md").write_text(words + "\n")
    return summary, words
