"""Pruning: a seeded tuning on two scenarios where the median rule stops
bad trials after the first scenario, counts them against the budget, writes
them to trials.csv as pruned, and still lands within 10 % of the optimum a
grid finds; and a trial is judged after the same run whatever the
batches its runs come back in."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

optuna = pytest.importorskip("optuna")

from test_tune import SCENARIO, TUNING, write  # noqa: E402

from neurov.tuning import load_tuning, tune  # noqa: E402
from neurov.tuning.objective import evaluate  # noqa: E402
from neurov.tuning.search import open_storage, optuna_study  # noqa: E402
from neurov.tuning.trial_runs import TrialRunner  # noqa: E402

# The same noisy step, 2 m long: a second scenario, so that a trial has a
# first scenario's plants to be judged on before its last run.
FAR = SCENARIO.replace('name = "noisy_step"', 'name = "noisy_far"').replace("[1, 0, 1, 0, 0, 0.5]",
                                                                            "[2, 0, 1, 0, 0, 0.5]")


def _two_scenarios(folder: Path, trials: int, pruner: str) -> Path:
    (folder / "noisy_far.toml").write_text(FAR)
    text = TUNING.replace('scenarios = ["noisy_step.toml"]', 'scenarios = ["noisy_step.toml", "noisy_far.toml"]')
    return write(folder, trials, text.replace("seed = 1\n", f'seed = 1\npruner = "{pruner}"\n'))


def test_pruning_stops_bad_trials_and_keeps_the_optimum(tmp_path: Path) -> None:
    path = _two_scenarios(tmp_path, 12, "median")
    tuning = load_tuning(path)
    assert tuning.settings.pruner == "median"
    # The optimum of the whole objective (every run of every trial), by a grid.
    runner = TrialRunner(1)
    grid = [evaluate(tuning, "pd", {"kp": k}, runner).value for k in np.geomspace(0.05, 20.0, 9)]

    tune(tuning, tmp_path / "out", workers=1, verdict=False, plots=False, progress=False)
    study = optuna_study(tuning, "pd", open_storage(tmp_path / "out"))
    pruned = [t for t in study.trials if t.state == optuna.trial.TrialState.PRUNED]
    complete = [t for t in study.trials if t.state == optuna.trial.TrialState.COMPLETE]
    assert pruned, "the median rule pruned no trial of this seeded tuning"
    assert len(pruned) + len(complete) == 12 == len(study.trials)  # pruned trials use the budget
    for t in pruned:
        # Stopped once the first scenario's 3 plants were in, before the last of the 6 runs.
        assert 3 <= t.user_attrs["runs"] < 6 and max(t.intermediate_values) == t.user_attrs["runs"] - 1
        assert t.user_attrs["reason"] == "pruned"
    assert all(t.number >= 5 for t in pruned)  # five trials run whole before any is judged
    assert study.best_value <= 1.10 * min(grid)

    table = pd.read_csv(tmp_path / "out" / "trials.csv")
    assert sorted(table.loc[table.state == "pruned", "trial"]) == [t.number for t in pruned]
    assert table.loc[table.state == "pruned", "objective"].isna().all()
    assert np.isfinite(table.loc[table.state == "pruned", "pruned_value"]).all()
    assert table.loc[table.state == "complete", "objective"].notna().all()


def test_without_a_pruner_every_trial_runs_whole(tmp_path: Path) -> None:
    tuning = load_tuning(_two_scenarios(tmp_path, 6, "none"))
    tune(tuning, tmp_path / "out", workers=1, verdict=False, plots=False, progress=False)
    study = optuna_study(tuning, "pd", open_storage(tmp_path / "out"))
    assert [t.state for t in study.trials] == [optuna.trial.TrialState.COMPLETE] * 6
    assert {t.user_attrs["runs"] for t in study.trials} == {6}


class Batches:
    """A runner that hands the runs back `size` at a time, as workers do."""

    def __init__(self, size: int) -> None:
        self.size = size

    def run(self, study, on_runs):  # type: ignore[no-untyped-def]
        from neurov.study.one_run import plan_runs
        from neurov.tuning.trial_runs import run_keys_safely

        keys = [(k.scenario, k.controller, k.sample) for k in plan_runs(study)]
        out = []
        for i in range(0, len(keys), self.size):
            new = run_keys_safely(study, keys[i:i + self.size])
            out += new
            if on_runs(new):
                break
        return out


class PruneAtThirdRun:
    def __init__(self) -> None:
        self.steps: list[int] = []

    def report(self, value: float, step: int) -> None:
        self.steps.append(step)

    def should_prune(self) -> bool:
        return self.steps[-1] >= 2


@pytest.mark.parametrize("size", [1, 2, 4])
def test_a_trial_is_pruned_after_the_same_run_whatever_the_batches(tmp_path: Path, size: int) -> None:
    tuning = load_tuning(_two_scenarios(tmp_path, 4, "median"))
    pruning = PruneAtThirdRun()
    outcome = evaluate(tuning, "pd", {"kp": 1.0}, Batches(size), pruning=pruning)  # type: ignore[arg-type]
    assert outcome.pruned and outcome.runs == 3 and pruning.steps == [0, 1, 2]
    whole = evaluate(tuning, "pd", {"kp": 1.0}, Batches(size))  # type: ignore[arg-type]
    assert not whole.pruned and whole.runs == 6
