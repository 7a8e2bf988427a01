"""Tuning: every controller of a study file tuned with the same budget by
the same optimiser (Optuna), then judged on plants it never saw.

A tuning file is a study file (scenarios, perturbations, metrics window,
failure bounds) plus, per controller, the parameters to search and a
``[tune]`` table (docs/tuning.md)::

    [tune]
    trials = 100                   # per controller
    objective = "rmse_position_m"  # any metric of a study; or ["rmse_position_m", "mean_abs_tau"]
    train_samples = 20             # plants of the study's seed, for the trials
    test_samples = 50              # plants of another seed, for the verdict

    [controllers.pd]
    type = "pd"
    kp = [100.0, 100.0, 100.0, 25.0, 25.0, 25.0]
    [controllers.pd.search]
    kp = { scale = [0.05, 20.0], log = true }    # one factor on the vector
    "kd[2]" = { range = [10.0, 1000.0], log = true }

The modules, in the order a tuning goes through them:
:mod:`~neurov.tuning.spec` (what a tuning is), :mod:`~neurov.tuning.reading`
(file to :class:`Tuning`, and the studies a trial and the verdict run),
:mod:`~neurov.tuning.space` (a trial's values into a controller table),
:mod:`~neurov.tuning.trial_runs` (a trial's runs on workers kept for the
whole tuning), :mod:`~neurov.tuning.objective` (runs to a penalised
aggregate), :mod:`~neurov.tuning.search` (Optuna: storage, budget, samplers),
:mod:`~neurov.tuning.budget` (the budget in its unit, budget.csv),
:mod:`~neurov.tuning.outputs` (trials.csv, best.toml, figures), with two
objectives :mod:`~neurov.tuning.pareto` (the fronts, pareto.csv, fronts.png)
and :mod:`~neurov.tuning.equal_effort` (the fronts read at a stated effort,
the verdict among them), and :mod:`~neurov.tuning.running` (all of it,
``neurov tune``); over tuning seeds, :mod:`~neurov.tuning.seeds`, and the
Markdown of kept outputs, :mod:`~neurov.tuning.tables` (``neurov tune-table``).
"""

from neurov.tuning.reading import load_tuning, trial_study, tuning_from_mapping, verdict_study
from neurov.tuning.running import TuneOutcome, main_tune, tune
from neurov.tuning.search import STORAGE_NAME, TuneInterrupted
from neurov.tuning.spec import SearchParameter, TuneError, TuneSettings, Tuning

__all__ = ["STORAGE_NAME", "SearchParameter", "TuneError", "TuneInterrupted", "TuneOutcome", "TuneSettings",
           "Tuning", "load_tuning", "main_tune", "trial_study", "tune", "tuning_from_mapping", "verdict_study"]
