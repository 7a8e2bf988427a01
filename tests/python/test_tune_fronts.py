"""Error and effort together: a short two-objective tuning gives its front
(checked against the trials by an independent dominance test), reads it at
the hand-set gains' effort, runs that trial in the verdict and says so; an
effort-penalised single objective is the error plus the stated weight times
the effort; two-objective files that cannot work are refused before any run."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

optuna = pytest.importorskip("optuna")

from test_tune import TUNING, write  # noqa: E402

from neurov.tuning import TuneError, load_tuning, tune  # noqa: E402
from neurov.tuning.objective import evaluate  # noqa: E402
from neurov.tuning.pareto import front  # noqa: E402
from neurov.tuning.tables import markdown_table  # noqa: E402
from neurov.tuning.trial_runs import TrialRunner  # noqa: E402

TWO = TUNING.replace('objective = "rmse_position_m"',
                     'objective = ["rmse_position_m", "mean_abs_tau"]\neffort_at = "pd"').replace(
    "kp = { scale = [0.05, 20.0], log = true }",
    "kp = { scale = [0.05, 20.0], log = true }\nkd = { scale = [0.1, 10.0], log = true }")


def _dominated(p: tuple[float, float], others: list[tuple[float, float]]) -> bool:
    return any(q[0] <= p[0] and q[1] <= p[1] and q != p for q in others)


def test_front_keeps_exactly_the_non_dominated_points() -> None:
    rng = np.random.default_rng(4)
    for _ in range(50):
        pts = [(float(a), float(b)) for a, b in rng.integers(0, 6, size=(12, 2))]
        kept = front(pts)
        distinct = {pts[i] for i in kept}
        assert len(distinct) == len(kept)  # of equal points, one
        assert distinct == {p for p in pts if not _dominated(p, pts)}
        assert [pts[i][1] for i in kept] == sorted(pts[i][1] for i in kept)
    assert front([(1.0, math.inf), (2.0, 1.0)]) == [1]  # an infinite effort is never on it
    assert front([(1.0, 2.0), (1.0, 2.0), (0.5, 3.0)]) == [0, 2] and front([]) == []


def test_two_objectives_give_a_front_read_at_the_hand_set_effort(tmp_path: Path) -> None:
    path = write(tmp_path, trials=10, tuning=TWO)
    tuning = load_tuning(path)
    s = tuning.settings
    assert s.two_objectives and s.objectives == ("rmse_position_m", "mean_abs_tau") and s.pruner == "none"
    out = tune(tuning, tmp_path / "out", workers=1, progress=False)
    folder = tmp_path / "out"

    trials = pd.read_csv(folder / "trials.csv")
    assert len(trials) == 10 and (trials["state"] == "complete").all()
    points = list(zip(trials["objective"], trials["effort"]))
    pareto = pd.read_csv(folder / "pareto.csv")
    on_all = pareto[pareto["front"] == "all"]
    # The front is exactly the trials no other trial dominates (one vehicle: its front is the same).
    expected = {int(t) for t, p in zip(trials["trial"], points) if not _dominated(p, points)}
    assert set(on_all["trial"]) == expected
    assert set(pareto[pareto["front"] == "bluerov2_heavy"]["trial"]) == expected
    assert {"param_kp", "param_kd", "error", "effort"} <= set(pareto.columns)

    # The level: the hand-set gains' effort on the training plants, as a trial of them is judged.
    hand = evaluate(tuning, "pd", {"kp": 1.0, "kd": 1.0}, TrialRunner(1))
    # The first trial is the hand-set gains (a factor of 1 on each vector), judged as any trial.
    first = trials[trials["trial"] == 0].iloc[0]
    assert (first["param_kp"], first["param_kd"]) == (1.0, 1.0)
    assert (first["objective"], first["effort"]) == pytest.approx((hand.value, hand.effort), rel=1e-12)
    picks = pd.read_csv(folder / "picks.csv")
    (pick,) = picks.itertuples()
    assert pick.effort_at == pytest.approx(hand.by_vehicle["bluerov2_heavy"][1], rel=1e-12)
    within = trials[trials["effort"] <= pick.effort_at]
    if len(within):
        best = within.sort_values(["objective", "trial"]).iloc[0]
        assert pick.within and pick.trial == best["trial"] and pick.error == pytest.approx(best["objective"])
    else:
        assert not pick.within and pick.trial == trials.sort_values("effort").iloc[0]["trial"]
    # The verdict runs the trial read there.
    picked = trials[trials["trial"] == pick.trial].iloc[0]
    assert out.best["pd"]["kp"] == pytest.approx([20 * picked["param_kp"], 20 * picked["param_kp"],
                                                  20 * picked["param_kp"], 2 * picked["param_kp"],
                                                  2 * picked["param_kp"], 2 * picked["param_kp"]])
    equal = pd.read_csv(folder / "equal_effort.csv")
    assert list(equal["controller"]) == ["pd"] and list(equal["rank"]) == [1]
    assert equal["effort_at"].iloc[0] == pytest.approx(pick.effort_at)
    assert "read at an effort of" in out.equal_effort_words and "pd's hand-set gains" in out.equal_effort_words
    assert (folder / "fronts.png").stat().st_size > 0
    table = markdown_table([folder], "fronts")
    assert table.count("\n") == 2 and "| pd | bluerov2_heavy |" in table
    budget = pd.read_csv(folder / "budget.csv")
    assert budget.iloc[0][["trials_started", "trials_pruned", "trials_completed", "runs_finished"]].tolist() == \
        [10, 0, 10, 30]


def test_an_effort_penalised_objective_adds_the_stated_weight_times_the_effort(tmp_path: Path) -> None:
    two = load_tuning(write(tmp_path, tuning=TWO))
    text = TUNING.replace('objective = "rmse_position_m"', 'objective = "rmse_position_m"\n'
                          'effort_penalty = { metric = "mean_abs_tau", weight = 0.05 }')
    one = load_tuning(write(tmp_path, tuning=text))
    assert not one.settings.two_objectives and one.settings.objectives == ("rmse_position_m",)
    runner = TrialRunner(1)
    values = {"kp": 3.0, "kd": 1.0}
    both = evaluate(two, "pd", values, runner)
    penalised = evaluate(one, "pd", {"kp": 3.0}, runner)
    assert both.failures == 0
    assert penalised.value == pytest.approx(both.value + 0.05 * both.effort, rel=1e-12)


@pytest.mark.parametrize(("old", "new", "words"), [
    ('objective = ["rmse_position_m", "mean_abs_tau"]', 'objective = ["rmse_position_m", "x", "y"]',
     "expected a metric or a list of two"),
    ('objective = ["rmse_position_m", "mean_abs_tau"]', 'objective = ["rmse_position_m", "mean_abs_taus"]',
     "did you mean 'mean_abs_tau'"),
    ('effort_at = "pd"', 'effort_at = "pid"', "tune.effort_at: 'pid' is not a controller"),
    ('effort_at = "pd"', 'effort_at = { bluerov2_heavy = -1.0 }', "expected a controller's key"),
    ('effort_at = "pd"', 'effort_at = "pd"\npruner = "median"', "pruners judge one objective"),
    ('effort_at = "pd"', 'effort_at = "pd"\nsampler = "cmaes"', "CMA-ES searches one objective"),
    ('effort_at = "pd"', 'effort_at = "pd"\neffort_penalty = { metric = "mean_abs_tau", weight = 1.0 }',
     "beside a single objective"),
    ('effort_at = "pd"', 'effort_at = "pd"\nbudget = "runs"', "budget"),
])
def test_two_objective_files_that_cannot_work_are_refused(tmp_path: Path, old: str, new: str, words: str) -> None:
    path = write(tmp_path, tuning=TWO.replace(old, new))
    with pytest.raises(TuneError, match="tune") as e:
        load_tuning(path)
    assert words in str(e.value)


def test_effort_at_needs_two_objectives(tmp_path: Path) -> None:
    path = write(tmp_path, tuning=TUNING.replace('seed = 1\n', 'seed = 1\neffort_at = "pd"\n'))
    with pytest.raises(TuneError, match="effort_at: reads the fronts of two objectives"):
        load_tuning(path)


def test_the_tables_refuse_folders_they_cannot_read(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="argument 'folders'"):
        markdown_table([tmp_path / "missing"], "budget")
    with pytest.raises(ValueError, match="argument 'table'"):
        markdown_table([tmp_path], "nothing")
    a, b = tmp_path / "x" / "seed1", tmp_path / "y" / "seed1"
    for f in (a, b):
        f.mkdir(parents=True)
    with pytest.raises(ValueError, match="repeat"):
        markdown_table([a, b], "spread")


def test_nsga2_searches_two_objectives(tmp_path: Path) -> None:
    tuning = load_tuning(write(tmp_path, trials=4, tuning=TWO.replace("seed = 1\n", 'seed = 1\nsampler = "nsga2"\n')))
    assert tuning.settings.sampler == "nsga2"
    tune(tuning, tmp_path / "out", workers=1, verdict=False, plots=False, progress=False)
    trials = pd.read_csv(tmp_path / "out" / "trials.csv")
    assert len(trials) == 4 and trials["effort"].notna().all() and len(set(trials["param_kp"])) == 4


def test_a_two_objective_tuning_resumes_with_its_hand_set_trial_once(tmp_path: Path) -> None:
    first = tune(load_tuning(write(tmp_path, trials=3, tuning=TWO)), tmp_path / "out", workers=1, verdict=False,
                 plots=False, progress=False)
    more = tune(load_tuning(write(tmp_path, trials=5, tuning=TWO)), tmp_path / "out", workers=1, verdict=False,
                plots=False, progress=False)
    assert (first.ran, more.ran) == (3, 2)
    trials = pd.read_csv(tmp_path / "out" / "trials.csv")
    hand = trials[(trials["param_kp"] == 1.0) & (trials["param_kd"] == 1.0)]
    assert list(trials["trial"]) == [0, 1, 2, 3, 4] and list(hand["trial"]) == [0]
