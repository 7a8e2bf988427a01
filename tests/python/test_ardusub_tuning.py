"""Tuning ArduSub by its parameters' names: bounds outside ArduSub's
documented range refused, best.param written beside best.toml (only the
parameters the tuning set, with its header), and the tuned file loading back
into a scenario to give the tuner's number."""

from __future__ import annotations

from pathlib import Path

import pytest

pytest.importorskip("optuna")

from neurov.config.reading import read_scenario  # noqa: E402
from neurov.laws import ardusub_params as ap  # noqa: E402
from neurov.running.simulation import simulate  # noqa: E402
from neurov.tuning import load_tuning, tune  # noqa: E402
from neurov.tuning.objective import evaluate  # noqa: E402
from neurov.tuning.spec import TuneError  # noqa: E402
from neurov.tuning.trial_runs import TrialRunner  # noqa: E402

SCENARIO = """
name = "depth_step"
duration = 20.0
[vehicle]
preset = "bluerov2_heavy"
thrusters = true
[command]
type = "waypoints"
interpolation = "hold"
times = [0.0, 1.0]
poses = [[0, 0, 0, 0, 0, 0], [0, 0, 1, 0, 0, 0]]
[controller]
type = "ardusub"
mode = "depth_hold"
FRAME_CONFIG = 2
"""

TUNING = """
name = "ardusub_depth"
seed = 3
after = 1.0
scenarios = ["depth_step.toml"]
[failure]
rmse_position_m = 2.0
[controllers.ardusub]
type = "ardusub"
mode = "depth_hold"
params = "vehicle.param"
[controllers.ardusub.search]
PSC_POSZ_P = { range = RANGE }
PSC_ACCZ_P = { range = [0.2, 1.5] }
[tune]
trials = 3
objective = "rmse_position_m"
train_samples = 1
test_samples = 1
seed = 1
"""


def write(folder: Path, posz_range: str = "[1.0, 3.0]") -> Path:
    (folder / "depth_step.toml").write_text(SCENARIO)
    (folder / "vehicle.param").write_text("FRAME_CONFIG 2\nPSC_VELZ_P 8\n")
    path = folder / "tuning.toml"
    path.write_text(TUNING.replace("RANGE", posz_range))
    return path


def test_a_range_outside_the_documented_one_is_refused(tmp_path):
    with pytest.raises(TuneError, match=r"PSC_POSZ_P.*\[0\.5, 3\] leaves ArduSub's documented range of "
                                        r"PSC_POSZ_P, \[1, 3\] 1/s"):
        load_tuning(write(tmp_path, "[0.5, 3.0]"))


def test_best_param_holds_the_tuned_parameters_and_loads_back(tmp_path):
    tuning = load_tuning(write(tmp_path))
    out = tune(tuning, tmp_path / "out", workers=1, verdict=False, plots=False, progress=False)
    path = tmp_path / "out" / "best.param"
    assert out.param_files == [(path, True)]
    text = path.read_text()
    assert "tuned by `neurov tune tuning.toml`" in text and "on top of vehicle.param" in text
    params = ap.read_parameters(path)
    assert sorted(params) == ["PSC_ACCZ_P", "PSC_POSZ_P"]
    best = out.best["ardusub"]
    assert params == pytest.approx({k: best[k] for k in params}, rel=1e-8)
    # The values read back from the file give the tuner's best objective (the file keeps 9
    # significant digits), and the file loads into a scenario beside the vehicle's own.
    runner = TrialRunner(1)
    tuned = evaluate(tuning, "ardusub", params, runner).value
    (tmp_path / "tuned.toml").write_text(SCENARIO.replace('FRAME_CONFIG = 2', 'params = "out/best.param"\n'
                                                          'FRAME_CONFIG = 2\nPSC_VELZ_P = 8'))
    assert tuned == pytest.approx(min(t.value for t in out_trials(tmp_path)), rel=1e-6)
    assert simulate(read_scenario(tmp_path / "tuned.toml")).metrics()["rmse_position_m"] < 2.0


def out_trials(tmp_path: Path) -> list:
    from neurov.tuning.search import open_storage, optuna_study

    return optuna_study(load_tuning(tmp_path / "tuning.toml"), "ardusub", open_storage(tmp_path / "out")).trials


def test_a_two_objective_tuning_writes_the_trial_read_at_the_stated_effort(tmp_path):
    """With objective = [error, effort] best.param holds the trial best.toml
    holds, the one picks.csv names at the stated effort, and says so; a front
    that does not reach the effort is said in capitals."""
    import pandas as pd

    from neurov.tuning.equal_effort import Fronts, equal_effort_picks
    from neurov.tuning.param_file import write_best_params
    from neurov.tuning.search import open_storage, optuna_study

    path = write(tmp_path)
    path.write_text(path.read_text().replace('objective = "rmse_position_m"',
                                             'objective = ["rmse_position_m", "mean_abs_tau"]\n'
                                             'effort_at = { bluerov2_heavy = 1000.0 }'))
    tuning = load_tuning(path)
    out = tune(tuning, tmp_path / "out", workers=1, verdict=False, plots=False, progress=False)
    picks = pd.read_csv(tmp_path / "out" / "picks.csv")
    trial = int(picks.loc[picks["controller"] == "ardusub", "trial"].iloc[0])
    text = (tmp_path / "out" / "best.param").read_text()
    assert out.param_files == [(tmp_path / "out" / "best.param", True)]
    assert "two objectives, the mean of rmse_position_m and of mean_abs_tau" in text
    assert "Read at equal effort (the stated effort; picks.csv)" in text
    assert f"On bluerov2_heavy: trial {trial}, " in text and "at the level 1000 (within it)." in text
    study = optuna_study(tuning, "ardusub", open_storage(tmp_path / "out"))
    chosen = next(t for t in study.trials if t.number == trial)
    assert ap.read_parameters(tmp_path / "out" / "best.param") == pytest.approx(chosen.params, rel=1e-8)
    assert chosen.params == pytest.approx({k: out.best["ardusub"][k] for k in chosen.params}, rel=1e-12)
    # Read below every trial's effort: the one over it least, said so.
    levels = {"bluerov2_heavy": 1e-9}
    tables, low = equal_effort_picks(tuning, {"ardusub": study}, levels)
    (tmp_path / "low").mkdir()
    write_best_params(tuning, {"ardusub": study}, tmp_path / "low", Fronts(levels, "the stated effort", tables, low, {}))
    assert "(OVER IT: the front does not reach that effort)." in (tmp_path / "low" / "best.param").read_text()
