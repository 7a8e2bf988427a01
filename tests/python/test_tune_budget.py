"""Budgets that are equal: counted in trials started (the default), trials
completed or runs finished, as the tuning file states, and budget.csv says
per controller what was started, pruned, completed and run."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest

optuna = pytest.importorskip("optuna")

from test_tune_pruning import _two_scenarios  # noqa: E402

from neurov.tuning import TuneError, load_tuning, tune  # noqa: E402
from neurov.tuning.budget import limit, runs_per_trial, unit_words  # noqa: E402
from neurov.tuning.search import open_storage, optuna_study  # noqa: E402


def _tuned(folder: Path, budget: str, trials: int = 10) -> tuple[pd.Series, object]:
    path = _two_scenarios(folder, trials, "median")
    path.write_text(path.read_text().replace("[tune]\n", f'[tune]\nbudget = "{budget}"\n'))
    tuning = load_tuning(path)
    assert tuning.settings.budget == budget
    tune(tuning, folder / "out", workers=1, verdict=False, plots=False, progress=False)
    study = optuna_study(tuning, "pd", open_storage(folder / "out"))
    row = pd.read_csv(folder / "out" / "budget.csv").iloc[0]
    S = optuna.trial.TrialState
    assert row["trials_started"] == len(study.trials)
    assert row["trials_pruned"] == sum(t.state == S.PRUNED for t in study.trials) > 0
    assert row["trials_completed"] == sum(t.state == S.COMPLETE for t in study.trials)
    assert row["runs_finished"] == sum(t.user_attrs["runs"] for t in study.trials)
    return row, tuning


def test_a_budget_of_trials_completed_does_not_count_the_pruned_ones(tmp_path: Path) -> None:
    row, tuning = _tuned(tmp_path, "trials_completed")
    assert row["trials_completed"] == 10 == row["budget_spent"] == limit(tuning)
    assert row["trials_started"] == 10 + row["trials_pruned"]
    assert "10 trials completed" in unit_words(tuning)


def test_a_budget_of_runs_finished_counts_a_pruned_trials_runs(tmp_path: Path) -> None:
    row, tuning = _tuned(tmp_path, "runs_finished")
    whole = runs_per_trial(tuning)
    assert whole == 6 and limit(tuning) == 60
    # Spent to the last run, or past it by less than one trial (a trial is never cut short by the budget).
    assert 60 <= row["runs_finished"] == row["budget_spent"] < 60 + whole
    assert row["trials_started"] > 10  # the pruned trials' unrun runs went to more trials


def test_the_default_budget_is_trials_started(tmp_path: Path) -> None:
    path = _two_scenarios(tmp_path, 4, "none")
    assert load_tuning(path).settings.budget == "trials_started"
    path.write_text(path.read_text().replace("[tune]\n", '[tune]\nbudget = "runs"\n'))
    with pytest.raises(TuneError, match="tune.budget"):
        load_tuning(path)
