"""neurov tune: a PD tuned on a scenario whose optimum a grid finds, an
interrupted tuning resumed, two processes on one storage, trials that fail,
and tuning files refused before any run."""

from __future__ import annotations

import math
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

optuna = pytest.importorskip("optuna")

from neurov.tuning import TuneError, load_tuning, tune  # noqa: E402
from neurov.tuning.objective import evaluate  # noqa: E402
from neurov.tuning.search import open_storage, optuna_study, run_trials  # noqa: E402
from neurov.tuning.trial_runs import TrialRunner, run_keys_safely  # noqa: E402

# A 1 m surge step of a BlueROV2 under heavy position noise: too little K_p
# tracks slowly, too much feeds the noise through, so the mean RMSE over the
# plants has its minimum inside the searched range (near a factor of 6).
SCENARIO = """
name = "noisy_step"
duration = 12.0
[vehicle]
preset = "bluerov2_heavy"
thrusters = false
[command]
type = "waypoints"
interpolation = "hold"
times = [0.0, 1.0]
poses = [[0, 0, 1, 0, 0, 0], [1, 0, 1, 0, 0, 0.5]]
[controller]
type = "pd"
kp = 10.0
kd = 10.0
[noise]
eta = [0.15, 0.15, 0.15, 0.002, 0.002, 0.005]
"""

TUNING = """
name = "pd_step"
seed = 3
after = 1.0
scenarios = ["noisy_step.toml"]
[failure]
rmse_position_m = 2.0
[controllers.pd]
type = "pd"
kp = [20, 20, 20, 2, 2, 2]
kd = [25, 25, 40, 1, 1, 1]
[controllers.pd.search]
kp = { scale = [0.05, 20.0], log = true }
[[perturbations]]
parameter = "mass"
relative = 0.2
[tune]
trials = TRIALS
objective = "rmse_position_m"
train_samples = 3
test_samples = 3
seed = 1
"""


def write(folder: Path, trials: int = 8, tuning: str = TUNING) -> Path:
    (folder / "noisy_step.toml").write_text(SCENARIO)
    path = folder / "tuning.toml"
    path.write_text(tuning.replace("TRIALS", str(trials)))
    return path


def test_tuned_pd_lands_within_ten_percent_of_the_grid_optimum(tmp_path: Path) -> None:
    path = write(tmp_path, trials=16)
    tuning = load_tuning(path)
    runner = TrialRunner(1)
    grid = np.geomspace(0.05, 20.0, 25)
    values = [evaluate(tuning, "pd", {"kp": k}, runner).value for k in grid]
    best_grid = min(values)
    i = int(np.argmin(values))
    assert 0 < i < len(grid) - 1, "the optimum must lie inside the range for the test to mean anything"

    out = tune(tuning, tmp_path / "out", workers=1, verdict=False, plots=False, progress=False)
    study = optuna_study(tuning, "pd", open_storage(tmp_path / "out"))
    assert out.ran == 16 == len(study.trials)
    assert study.best_value <= 1.10 * best_grid
    # best.toml holds the tuned vector, the hand-set one times the best factor.
    tuned = tomllib.loads((tmp_path / "out" / "best.toml").read_text())["controllers"]["pd"]
    np.testing.assert_allclose(tuned["kp"], np.array([20, 20, 20, 2, 2, 2]) * study.best_params["kp"])
    assert tuned["kd"] == [25, 25, 40, 1, 1, 1]
    # Evaluated again through the study machinery, the tuned gains give the trial's value.
    assert evaluate(tuning, "pd", study.best_params, runner).value == pytest.approx(study.best_value, rel=1e-12)


class Interrupt:
    """An evaluator that stops the tuning (as Ctrl-C does) at its n-th call."""

    def __init__(self, at: int | None = None) -> None:
        self.at, self.calls, self.seen = at, 0, []

    def __call__(self, tuning, controller, values, runner, **kw):  # type: ignore[no-untyped-def]
        self.calls += 1
        if self.calls == self.at:
            raise KeyboardInterrupt
        self.seen.append(dict(values))
        return evaluate(tuning, controller, values, runner, **kw)


def test_interrupted_tuning_resumes_without_repeating_finished_trials(tmp_path: Path) -> None:
    tuning = load_tuning(write(tmp_path, trials=6))
    runner = TrialRunner(1)
    first = Interrupt(at=3)
    with pytest.raises(KeyboardInterrupt):
        run_trials(tuning, "pd", open_storage(tmp_path), runner, evaluator=first)
    assert len(first.seen) == 2
    again = Interrupt()
    assert run_trials(tuning, "pd", open_storage(tmp_path), runner, evaluator=again) == 4
    assert again.calls == 4  # the two finished trials are not run again
    study = optuna_study(tuning, "pd", open_storage(tmp_path))
    done = [t for t in study.trials if t.state == optuna.trial.TrialState.COMPLETE]
    assert len(done) == 6
    assert [t.params for t in done[:2]] == first.seen
    assert [t.user_attrs.get("reason") for t in study.trials if t.state == optuna.trial.TrialState.FAIL] \
        == ["interrupted"]
    # What a rerun reproduces: one process, interrupted or not, makes the same trials.
    (tmp_path / "whole").mkdir()
    whole = Interrupt()
    run_trials(tuning, "pd", open_storage(tmp_path / "whole"), runner, evaluator=whole)
    assert whole.seen == first.seen + again.seen
    # A finished tuning runs nothing more.
    assert run_trials(tuning, "pd", open_storage(tmp_path), runner, evaluator=Interrupt()) == 0


WORKER = """
import sys, time
from pathlib import Path
from neurov.tuning import load_tuning
from neurov.tuning.objective import evaluate
from neurov.tuning.search import open_storage, run_trials
from neurov.tuning.trial_runs import TrialRunner

def slow(tuning, controller, values, runner, **kw):
    time.sleep(0.4)  # long enough that the two processes' trials interleave
    return evaluate(tuning, controller, values, runner, **kw)

out = Path(sys.argv[2])
print(run_trials(load_tuning(sys.argv[1]), "pd", open_storage(out), TrialRunner(1), evaluator=slow))
"""


def test_two_processes_on_one_storage_do_not_duplicate_trials(tmp_path: Path) -> None:
    path = write(tmp_path, trials=8)
    env = dict(os.environ)  # the neurov under test, installed or on PYTHONPATH
    procs = [subprocess.Popen([sys.executable, "-W", "error", "-c", WORKER, str(path), str(tmp_path)],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
             for _ in range(2)]
    outputs = [p.communicate(timeout=120) for p in procs]
    assert [p.returncode for p in procs] == [0, 0], [e for _, e in outputs]
    ran = [int(o.strip().splitlines()[-1]) for o, _ in outputs]
    assert sum(ran) == 8 and min(ran) >= 1, ran  # the budget shared, each process took part
    study = optuna_study(load_tuning(path), "pd", open_storage(tmp_path))
    done = [t for t in study.trials if t.state == optuna.trial.TrialState.COMPLETE]
    assert len(done) == 8
    assert len({t.params["kp"] for t in done}) == 8


def test_a_failing_run_is_penalised_with_its_reason(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    tuning = load_tuning(write(tmp_path))
    runner = TrialRunner(1)
    import neurov.study.one_run as one_run

    real = one_run.simulate

    def flaky(plant, *args, **kwargs):  # type: ignore[no-untyped-def]
        if plant.seed == one_run.sample_plant(study, study.scenarios[0], 1)[0].seed:
            raise RuntimeError("tensor conversion failed")
        return real(plant, *args, **kwargs)

    def batch_fails(*args, **kwargs):  # type: ignore[no-untyped-def]
        raise RuntimeError("the batch is refused")

    from neurov.tuning.reading import trial_study

    study = trial_study(tuning, "pd", {"kp": 1.0})
    # The trial's batch fails, so its runs are run one by one, where sample 1 raises.
    monkeypatch.setattr(one_run, "simulate_many", batch_fails)
    monkeypatch.setattr(one_run, "simulate", flaky)
    ok = evaluate(tuning, "pd", {"kp": 1.0}, TrialRunner(1))
    assert ok.failures == 1 and ok.reasons == {"RuntimeError: tensor conversion failed": 1}
    monkeypatch.undo()
    clean = evaluate(tuning, "pd", {"kp": 1.0}, runner)
    assert clean.failures == 0
    # The mean counts the failed run as the penalty (10) in place of its metric.
    # (samples 0 and 2 are the same runs in both)
    assert ok.value == pytest.approx(clean.value + (10.0 - _metric_of_sample(tuning, 1)) / 3)
    # A factor on K_p that makes the discrete loop diverge: every run fails, and says why.
    wild = evaluate(tuning, "pd", {"kp": 2000.0}, runner)
    assert wild.failures == 3 and wild.value == 10.0
    assert set(wild.reasons) <= {"diverged", "rmse_position_m > 2"}


def _metric_of_sample(tuning, sample):  # type: ignore[no-untyped-def]
    from neurov.tuning.reading import trial_study

    study = trial_study(tuning, "pd", {"kp": 1.0})
    return [r["row"]["rmse_position_m"] for r in run_keys_safely(study, [(0, 0, sample)])][0]


@pytest.mark.parametrize(("change", "field", "words"), [
    ('kp = { scale = [0.05, 20.0], log = true }', 'kdd = { scale = [0.05, 20.0] }',
     ("controllers.pd.search.kdd", "unknown parameter", "did you mean 'kd'")),
    ('kp = { scale = [0.05, 20.0], log = true }', 'kp = { scale = [2.0, 2.0] }',
     ("controllers.pd.search.kp.scale", "low < high")),
    ('kp = { scale = [0.05, 20.0], log = true }', '"kd[2]" = { range = [0.0, 100.0], log = true }',
     ("controllers.pd.search.kd[2].range", "above zero")),
    ('kp = [20, 20, 20, 2, 2, 2]', 'kp = 20.0',
     ("controllers.pd.search.kp.scale", "scalar gain")),
    ('"kd[2]"', '"kd[6]"', ()),
    ('trials = 8', 'trials = 0', ("tune.trials", ">= 1")),
    ('objective = "rmse_position_m"', 'objective = "rmse"', ("tune.objective", "not a metric")),
    ('seed = 1\n', 'seed = 1\nsampler = "anneal"\n', ("tune.sampler", "'tpe'")),
    ('seed = 1\n', 'seed = 1\npruner = "hyperband"\n', ("tune.pruner", "'median'", "'none'")),
    ('[controllers.pd.search]\nkp = { scale = [0.05, 20.0], log = true }', '',
     ("controllers: no controller has a search table",)),
    ('kp = { scale = [0.05, 20.0], log = true }', '"kd[2]" = { range = [-10.0, 100.0] }',
     ("controllers.pd.search", "at the low end", "kd[2]")),
])
def test_bad_tuning_files_are_refused_before_any_run(tmp_path: Path, change: str, field: str,
                                                     words: tuple[str, ...]) -> None:
    text = TUNING.replace("TRIALS", "8")
    if change == '"kd[2]"':
        text = text.replace('kp = { scale = [0.05, 20.0], log = true }', '"kd[6]" = { range = [1.0, 10.0] }')
        words = ("controllers.pd.search.kd[6]", "past the end")
    else:
        assert change in text
        text = text.replace(change, field)
    path = write(tmp_path, tuning=text)
    with pytest.raises(TuneError) as e:
        tune(path, tmp_path / "out", workers=1, progress=False)
    for w in words:
        assert w in str(e.value), str(e.value)
    assert str(path) in str(e.value)
    assert not (tmp_path / "out").exists()  # refused before anything is written


def test_the_verdict_runs_tuned_and_hand_set_gains_on_other_plants(tmp_path: Path) -> None:
    out = tune(write(tmp_path, trials=3), tmp_path / "out", workers=1, plots=False, progress=False)
    assert out.verdict is not None
    table = out.verdict.table
    assert sorted(set(table["controller"])) == ["pd", "pd_hand_set"]
    train = load_tuning(tmp_path / "tuning.toml")
    # The test plants come from another seed than the training plants.
    assert out.verdict.summary is not None
    assert train.settings.test_seed == 4  # the study seed (3) plus one
    runs = (tmp_path / "out" / "trials.csv").read_text().splitlines()
    assert runs[0].startswith("controller,trial,state,objective,pruned_value,feasible,runs,failures,failure_reasons,"
                              "seconds,param_kp")
    assert len(runs) == 4
    assert math.isfinite(float(runs[1].split(",")[3]))
    # A larger budget later: the new trials only, and the verdict of the new best gains.
    more = tune(write(tmp_path, trials=5), tmp_path / "out", workers=1, plots=False, progress=False)
    assert more.ran == 2 and more.verdict is not None
    best = tomllib.loads((tmp_path / "out" / "best.toml").read_text())["controllers"]["pd"]
    assert more.verdict.table.loc[more.verdict.table["controller"] == "pd", "rmse_position_m"].notna().all()
    assert best == more.best["pd"]


def test_a_vehicles_gains_are_searched_on_their_own() -> None:
    from neurov.tuning.space import apply_values
    from neurov.tuning.spec import SearchParameter

    table = {"type": "pd", "kd": [1.0, 2.0], "nerov": {"kp": [10.0, 20.0]}, "bluerov2_heavy": {"kp": [1.0, 2.0]},
             "search": {}}
    params = [SearchParameter("bluerov2_heavy.kp", ("kp",), "scale", 0.1, 10.0, vehicle="bluerov2_heavy"),
              SearchParameter("nerov.kd", ("kd",), "scale", 0.1, 10.0, vehicle="nerov"),
              SearchParameter("kd[1]", ("kd",), "range", 0.0, 5.0, index=1)]
    out = apply_values(table, params, {"bluerov2_heavy.kp": 3.0, "nerov.kd": 2.0, "kd[1]": 4.0})
    assert out["bluerov2_heavy"]["kp"] == [3.0, 6.0] and out["nerov"]["kp"] == [10.0, 20.0]
    # NEROV's kd came from the common table: scaled into NEROV's own.
    assert out["nerov"]["kd"] == [2.0, 4.0] and out["kd"] == [1.0, 4.0]
    assert "search" not in out and table["bluerov2_heavy"]["kp"] == [1.0, 2.0]  # the input is untouched


def test_the_shipped_tuned_league_reads() -> None:
    tuning = load_tuning("tuned_league")
    # Issue 42 added super-twisting (every built-in controller: test_tune_league.py).
    assert set(tuning.search) == {"pd", "pid", "smc", "computed_torque", "linear", "nn", "nn_network",
                                  "super_twisting"}
    assert all(p.vehicle in ("nerov", "bluerov2_heavy") for p in tuning.search["pd"])
    assert tuning.settings.test_seed != tuning.study_table["seed"]
    realistic = load_tuning("tuned_realism")
    assert set(realistic.search) == set(tuning.search)
    assert all(s.endswith("_realistic") for s in realistic.study_table["scenarios"])


def test_cli_tune_names_a_bad_file_and_exits_1(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from neurov import cli

    path = write(tmp_path, tuning=TUNING.replace("TRIALS", "0"))
    assert cli.main(["tune", str(path), "--out", str(tmp_path / "out"), "--workers", "1"]) == 1
    err = capsys.readouterr().err
    assert "tune.trials: expected an integer >= 1, got 0" in err and str(path) in err


FACTORY_TUNING = TUNING.replace('''[controllers.pd]
type = "pd"
kp = [20, 20, 20, 2, 2, 2]
kd = [25, 25, 40, 1, 1, 1]
[controllers.pd.search]
kp = { scale = [0.05, 20.0], log = true }''', '''[controllers.mine]
factory = "user_controllers.factories:tunable_pd"
label = "my PD"
[controllers.mine.arguments]
gain = 1.0
[controllers.mine.search]
GAIN''')


def test_a_factory_is_tuned_over_its_keyword_arguments(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.syspath_prepend(str(Path(__file__).resolve().parent))
    search = "gain = { range = [0.01, 0.15], log = true }"  # above about 0.15 the loop diverges
    path = write(tmp_path, trials=4, tuning=FACTORY_TUNING.replace("GAIN", search))
    out = tune(path, tmp_path / "out", workers=1, verdict=False, plots=False, progress=False)
    study = optuna_study(load_tuning(path), "mine", open_storage(tmp_path / "out"))
    values = [t.value for t in study.trials]
    assert out.ran == 4 and len(set(values)) == 4  # the argument reached the controller
    best = tomllib.loads((tmp_path / "out" / "best.toml").read_text())["controllers"]["mine"]
    assert best["arguments"]["gain"] == study.best_params["gain"]
    assert best["factory"] == "user_controllers.factories:tunable_pd"
    # An argument the factory does not take is named before any run.
    bad = write(tmp_path, tuning=FACTORY_TUNING.replace("GAIN", "gian = { range = [0.1, 1.0] }"))
    with pytest.raises(TuneError, match=r"controllers\.mine\.search: at the low end.*keyword argument 'gian'"):
        tune(bad, tmp_path / "bad", workers=1, progress=False)


CMAES_TUNING = TUNING.replace('kp = { scale = [0.05, 20.0], log = true }',
                              'kp = { scale = [0.05, 20.0], log = true }\nkd = { scale = [0.2, 5.0], log = true }'
                              ).replace("seed = 1\n", 'seed = 1\nsampler = "cmaes"\n')


def test_cmaes_searches_the_gains_and_one_seed_gives_one_search(tmp_path: Path) -> None:
    pytest.importorskip("cmaes")
    found = []
    for run in ("a", "b"):
        folder = tmp_path / run
        folder.mkdir()
        tuning = load_tuning(write(folder, trials=8, tuning=CMAES_TUNING))
        tune(tuning, folder / "out", workers=1, verdict=False, plots=False, progress=False)
        study = optuna_study(tuning, "pd", open_storage(folder / "out"))
        assert len(study.trials) == 8
        # CMA-ES proposed the trials after its first (its state is kept in the study).
        assert any(k.startswith("cma:") for t in study.trials for k in t.system_attrs)
        found.append([t.params for t in study.trials])
    assert found[0] == found[1]


GP_TUNING = CMAES_TUNING.replace('sampler = "cmaes"', 'sampler = "gp"')


@pytest.mark.slow  # 25 s on an idle core, most of it importing PyTorch and fitting the process
def test_gp_searches_the_gains_and_one_seed_gives_one_search(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # Optuna's GPSampler needs PyTorch, which CI does not install: exercised where torch is.
    pytest.importorskip("torch")
    proposed: list[dict[str, float]] = []
    real = optuna.samplers.GPSampler.sample_relative

    def spy(self, study, trial, space):  # type: ignore[no-untyped-def]
        out = real(self, study, trial, space)
        proposed.append(out)
        return out

    monkeypatch.setattr(optuna.samplers.GPSampler, "sample_relative", spy)
    found = []
    for run in ("a", "b"):
        folder = tmp_path / run
        folder.mkdir()
        tuning = load_tuning(write(folder, trials=12, tuning=GP_TUNING))
        tune(tuning, folder / "out", workers=1, verdict=False, plots=False, progress=False)
        study = optuna_study(tuning, "pd", open_storage(folder / "out"))
        assert len(study.trials) == 12
        found.append([t.params for t in study.trials])
    # The Gaussian process proposed the trials after its ten random ones (both parameters at once).
    assert sum(1 for p in proposed if set(p) == {"kp", "kd"}) >= 2
    assert found[0] == found[1]
