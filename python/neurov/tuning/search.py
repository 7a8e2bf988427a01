"""The Optuna side of a tuning: one Optuna study per controller in one RDB
storage (an SQLite file), the same budget for each, trials asked and told
so that several processes on one storage share the budget without
duplicating trials, and an interrupted tuning resumes from the storage."""

from __future__ import annotations

import hashlib
import json
import warnings
import zlib
from collections.abc import Callable
from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np

from neurov.tuning.objective import TrialOutcome, evaluate
from neurov.tuning.space import suggest
from neurov.tuning.spec import TuneError, Tuning
from neurov.tuning.trial_runs import TrialRunner

__all__ = ["STORAGE_NAME", "TuneInterrupted", "counted_trials", "open_storage", "optuna_study", "run_trials", "study_name"]

STORAGE_NAME = "tuning.db"
# A process that dies mid-trial leaves its trial "running"; without a
# heartbeat for this long, the next process marks it failed (and redoes it).
HEARTBEAT_SECONDS = 10
GRACE_SECONDS = 60


class TuneInterrupted(KeyboardInterrupt):
    def __init__(self, done: int, total: int, storage: Path) -> None:
        super().__init__(f"interrupted: {done} of {total} trials are saved in {storage}; run the same "
                         "command again to resume")
        self.done, self.total, self.storage = done, total, storage


def open_storage(out: Path) -> Any:
    import optuna

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    url = f"sqlite:///{(out / STORAGE_NAME).resolve()}"
    # Optuna calls its heartbeat experimental (its interface may change); it
    # is what tells a dead process's trial from a running one, so we use it.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
        # A long timeout: two processes writing one SQLite file wait for each other's lock.
        return optuna.storages.RDBStorage(url, engine_kwargs={"connect_args": {"timeout": 120}},
                                          heartbeat_interval=HEARTBEAT_SECONDS, grace_period=GRACE_SECONDS)


def study_name(tuning: Tuning, controller: str) -> str:
    return f"{tuning.name}.{controller}"


def fingerprint(tuning: Tuning, controller: str) -> str:
    """What decides a controller's trials: the study part but the other
    controllers, this controller's table and search, and the settings but the
    budget and the verdict's (a larger budget or another verdict reuses the
    trials made)."""
    from neurov import __version__

    study = {k: v for k, v in tuning.study_table.items() if k not in ("controllers", "ranking", "head_to_head")}
    settings = {k: v for k, v in asdict(tuning.settings).items()
                if k not in ("trials", "test_samples", "test_seed", "test_scenarios", "hand_set_in_verdict")}
    payload = {"version": __version__, "study": study, "controller": tuning.study_table["controllers"][controller],
               "search": [asdict(p) for p in tuning.search[controller]], "settings": settings}
    return hashlib.sha256(json.dumps(payload, sort_keys=True, default=str).encode()).hexdigest()[:16]


def _sampler(name: str, seed: int) -> Any:
    import optuna

    if name == "tpe":
        # constant_liar: a trial running in another process counts as a bad
        # one, so that parallel workers do not all try the same point.
        return optuna.samplers.TPESampler(seed=seed, constant_liar=True)
    if name == "cmaes":
        return optuna.samplers.CmaEsSampler(seed=seed)
    if name == "gp":
        return optuna.samplers.GPSampler(seed=seed)
    return optuna.samplers.RandomSampler(seed=seed)


def optuna_study(tuning: Tuning, controller: str, storage: Any) -> Any:
    import optuna

    name = study_name(tuning, controller)
    study = optuna.create_study(storage=storage, study_name=name, direction="minimize", load_if_exists=True)
    fp = fingerprint(tuning, controller)
    old = study.user_attrs.get("fingerprint")
    if old is None:
        study.set_user_attr("fingerprint", fp)
    elif old != fp:
        raise TuneError(f"{tuning.source}: the storage holds trials of controller {controller!r} for another "
                        f"tuning (its table, search, scenarios, plants, objective or sampler differ); use "
                        f"another --out, or delete the storage to start again")
    return study


def counted_trials(study: Any) -> list[Any]:
    """The trials that use the budget: finished or running, in number order."""
    import optuna

    states = (optuna.trial.TrialState.COMPLETE, optuna.trial.TrialState.RUNNING)
    return sorted(study.get_trials(deepcopy=False, states=states), key=lambda t: t.number)


def run_trials(tuning: Tuning, controller: str, storage: Any, runner: TrialRunner,
               on_trial: Callable[[int, TrialOutcome], None] | None = None,
               evaluator: Callable[..., TrialOutcome] = evaluate) -> int:
    """Runs trials of `controller` until its budget is used (by this process
    or others on the storage); returns how many this process ran.

    Optuna's optimize loop keeps each trial's heartbeat (a process that dies
    leaves a trial the next one marks failed and redoes) and marks a trial
    interrupted by Ctrl-C failed; a trial that finds the budget spent by the
    time it starts (another process took the last one) is pruned unrun."""
    import optuna

    study = optuna_study(tuning, controller, storage)
    s = tuning.settings
    params = tuning.search[controller]
    base_seed = s.seed ^ zlib.crc32(controller.encode())
    ran = 0

    def reseed(study: Any, _trial: Any = None) -> None:
        # A sampler seeded by the next trial's place: one process reproduces
        # the same trials whether or not it was interrupted on the way.
        n = len(study.get_trials(deepcopy=False))
        study.sampler = _sampler(s.sampler, int(np.random.SeedSequence([base_seed, n]).generate_state(1)[0]))
        if len(counted_trials(study)) >= s.trials:
            study.stop()

    def objective(trial: Any) -> float:
        nonlocal ran
        ahead = [t for t in counted_trials(study) if t.number < trial.number]
        if len(ahead) >= s.trials:
            trial.set_user_attr("reason", "over budget")
            study.stop()
            raise optuna.TrialPruned()
        outcome = evaluator(tuning, controller, suggest(trial, params), runner)
        for k, v in {"runs": outcome.runs, "failures": outcome.failures, "feasible": outcome.feasible,
                     "seconds": outcome.seconds, "reasons": outcome.reasons}.items():
            trial.set_user_attr(k, v)
        ran += 1
        if on_trial is not None:
            on_trial(trial.number, outcome)
        return outcome.value

    left = s.trials - len(counted_trials(study))
    if left <= 0:
        return 0
    reseed(study)
    study.optimize(objective, n_trials=left, callbacks=[reseed], gc_after_trial=False)
    return ran
