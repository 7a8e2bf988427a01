"""Studies: every controller on every scenario, over many perturbed plants.

A study file (TOML) names scenarios, controllers and how to perturb the
plant; :func:`run_study` runs every (scenario x controller x sample) and
writes a tidy table (one row per run), a league table and plots. The runs go
through Dask when it is installed (a local cluster, or an existing one by
address) and through local processes otherwise; both give the same table for
the same seed. See docs/studies.md for the file format::

    name = "robustness"
    seed = 2026                 # with the sample index, fixes every plant and noise draw
    samples = 20                # perturbed plants per scenario
    after = 10.0                # metrics over t >= after [s]
    scenarios = ["nerov_square_disturbed", "../my_scenario.toml"]

    [ranking]
    metric = "rmse_position_m"  # controllers ranked per scenario by its median

    [failure]                   # a run fails if a metric exceeds its bound or is not finite
    rmse_position_m = 1.0

    [controllers.nn]            # fields as in a scenario's [controller]
    type = "nn"
    [controllers.nn.nerov]      # per vehicle (the vehicle file's stem): merged over the above
    kd = [200, 200, 200, 50, 50, 50]

    [[perturbations]]
    parameter = "added_mass"    # a vehicle parameter, scaled by a factor per element
    relative = 0.3              # uniform in [0.7, 1.3]
    [[perturbations]]
    parameter = "current_speed" # an absolute quantity
    range = [0.0, 0.5]          # m/s

The controller is built for the nominal vehicle file; only the plant, the
current, the noise and the disturbances change from sample to sample.

The package's modules, in the order a study goes through them:
:mod:`~neurov.study.spec` (what a study is), :mod:`~neurov.study.reading`
(study file to :class:`Study`), :mod:`~neurov.study.sampling` (the plant of
one sample), :mod:`~neurov.study.one_run` (one run to a record),
:mod:`~neurov.study.executors` (Dask or local processes,
:mod:`~neurov.study.processes`), :mod:`~neurov.study.log` (runs.jsonl), :mod:`~neurov.study.tables` (the runs
table and its statistics, as DataFrames), :mod:`~neurov.study.report`
(league.md), :mod:`~neurov.study.figures` (the plots, redrawn only when their
data changed) and :mod:`~neurov.study.running` (all of it, ``neurov study``).
"""


from neurov.study.executors import dask_available, default_batch_size
from neurov.study.log import LOG_NAME, StudyLogWarning
from neurov.study.one_run import SERIES_POINTS, RunKey, plan_runs, run_batch, run_one
from neurov.study.reading import load_study, shipped_studies, study_from_mapping, study_path
from neurov.study.report import league_markdown
from neurov.study.running import StudyInterrupted, StudyOutcome, main_study, run_study
from neurov.study.sampling import draw_sample, sample_plant, sample_seeds
# What a study is: every public name of spec (its __all__, listed there once).
from neurov.study.spec import *  # noqa: F403
from neurov.study.tables import (
    Summary,
    failed,
    failed_runs,
    failure_counts,
    head_to_head,
    percentile,
    read_table,
    runs_table,
    summarise,
    summary_table,
    write_table,
)

__all__ = [
    "ENVIRONMENT_PARAMETERS",
    "LOG_NAME",
    "NORMAL_TRUNCATION",
    "SCENARIO_DIR",
    "SERIES_POINTS",
    "STUDY_DIR",
    "VEHICLE_PARAMETERS",
    "Perturbation",
    "RunKey",
    "Study",
    "StudyError",
    "StudyInterrupted",
    "StudyLogWarning",
    "StudyOutcome",
    "Summary",
    "dask_available",
    "default_batch_size",
    "draw_sample",
    "failed",
    "failed_runs",
    "failure_counts",
    "head_to_head",
    "league_markdown",
    "load_study",
    "main_study",
    "metric_names",
    "percentile",
    "plan_runs",
    "read_table",
    "run_batch",
    "run_one",
    "run_study",
    "runs_table",
    "sample_plant",
    "sample_seeds",
    "shipped_studies",
    "study_from_mapping",
    "study_path",
    "summarise",
    "summary_table",
    "vehicle_key",
    "write_table",
]
