"""A tuning's budget in the unit its file states (``[tune] budget``): trials
started (pruned ones counted), trials completed (pruned ones not counted) or
runs finished (``trials`` x the runs of a whole trial, a pruned trial's runs
counted as run), and what each controller used of it."""

from __future__ import annotations

from typing import Any

import pandas as pd

from neurov.tuning.spec import Tuning

__all__ = ["budget_table", "limit", "runs_per_trial", "spent", "unit_words"]

# The reason a trial stopped without being judged (search.py sets them).
_UNJUDGED = ("over budget", "interrupted")


def runs_per_trial(tuning: Tuning) -> int:
    """The runs of a whole trial: every scenario on every training plant."""
    return tuning.settings.train_samples * len(tuning.study_table.get("scenarios", []))


def limit(tuning: Tuning) -> int:
    """The budget per controller, in its unit."""
    s = tuning.settings
    return s.trials * runs_per_trial(tuning) if s.budget == "runs_finished" else s.trials


def unit_words(tuning: Tuning) -> str:
    s = tuning.settings
    return {"trials_started": f"{s.trials} trials started (a pruned trial counted)",
            "trials_completed": f"{s.trials} trials completed (a pruned trial not counted)",
            "runs_finished": f"{limit(tuning)} runs finished ({s.trials} whole trials of "
                             f"{runs_per_trial(tuning)} runs; a pruned trial's runs counted)"}[s.budget]


def spent(tuning: Tuning, trials: list[Any]) -> int:
    """What `trials` (those that use the budget: finished, pruned by the
    pruner, running) used of it. A running trial, whose end is not known
    yet, counts as whole, so that processes sharing a storage do not
    overspend it."""
    import optuna

    S = optuna.trial.TrialState
    unit = tuning.settings.budget
    if unit == "trials_started":
        return len(trials)
    if unit == "trials_completed":
        return sum(1 for t in trials if t.state in (S.COMPLETE, S.RUNNING))
    whole = runs_per_trial(tuning)
    return sum(whole if t.state == S.RUNNING else int(t.user_attrs.get("runs", whole)) for t in trials)


def budget_table(tuning: Tuning, studies: dict[str, Any]) -> pd.DataFrame:
    """Per controller: the trials started, pruned and completed, the runs
    finished, and the budget in its unit with what was used of it."""
    import optuna

    S = optuna.trial.TrialState
    rows = []
    for controller, study in studies.items():
        trials = study.get_trials(deepcopy=False, states=(S.COMPLETE, S.PRUNED))
        judged = [t for t in trials if t.user_attrs.get("reason") not in _UNJUDGED]
        pruned = [t for t in judged if t.state == S.PRUNED]
        done = [t for t in judged if t.state == S.COMPLETE]
        rows.append({"controller": controller, "trials_started": len(judged), "trials_pruned": len(pruned),
                     "trials_completed": len(done),
                     "runs_finished": sum(int(t.user_attrs.get("runs", 0)) for t in judged),
                     "budget": tuning.settings.budget, "budget_limit": limit(tuning),
                     "budget_spent": spent(tuning, judged)})
    return pd.DataFrame(rows)
