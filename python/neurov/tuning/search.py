"""The Optuna side of a tuning: one Optuna study per controller in one RDB
storage (an SQLite file), the same budget for each, trials asked and told
so that several processes on one storage share the budget without
duplicating trials, and an interrupted tuning resumes from the storage."""

from __future__ import annotations

import contextlib
import hashlib
import json
import math
import warnings
import zlib
from collections.abc import Callable, Iterator
from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np

from neurov.tuning import budget
from neurov.tuning.objective import TrialOutcome, evaluate
from neurov.tuning.space import hand_set_values, suggest
from neurov.tuning.spec import TuneError, Tuning
from neurov.tuning.trial_runs import TrialRunner
from neurov._core import __version__

__all__ = ["OVER_BUDGET", "STORAGE_NAME", "TuneInterrupted", "counted_trials", "enqueue_hand_set", "open_storage",
           "optuna_study", "pruner", "run_trials", "study_name"]

STORAGE_NAME = "tuning.db"
# A process that dies mid-trial leaves its trial "running"; without a
# heartbeat for this long, the next process marks it failed (and redoes it).
HEARTBEAT_SECONDS = 10
GRACE_SECONDS = 60
# The reason of a trial pruned unrun because the budget was spent when it started.
OVER_BUDGET = "over budget"


class TuneInterrupted(KeyboardInterrupt):
    def __init__(self, done: int, total: int, storage: Path) -> None:
        super().__init__(f"interrupted: {done} of {total} trials are saved in {storage}; run the same "
                         "command again to resume")
        self.done, self.total, self.storage = done, total, storage


def open_storage(out: Path) -> Any:
    """Optuna's RDB storage in the SQLite file ``out/tuning.db``."""
    import sqlite3

    import optuna

    # Optuna logs every trial; a tuning reports by its progress bar and its files.
    optuna.logging.set_verbosity(optuna.logging.ERROR)
    path = (out / STORAGE_NAME).resolve()

    def connect() -> sqlite3.Connection:
        # Optuna commits some twenty times per trial. Write-ahead logging with
        # synchronous=NORMAL syncs at checkpoints rather than at each commit
        # (13 ms each on this disk): a process that is killed loses nothing
        # committed, only a power cut can lose the last commits. A long timeout:
        # processes sharing the file wait for each other's lock.
        conn = sqlite3.connect(path, timeout=120, check_same_thread=False)
        conn.execute("PRAGMA journal_mode=WAL")
        conn.execute("PRAGMA synchronous=NORMAL")
        return conn

    # Optuna calls its heartbeat experimental (its interface may change); it
    # is what tells a dead process's trial from a running one, so we use it.
    with _creating(out), warnings.catch_warnings():
        warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
        return optuna.storages.RDBStorage(f"sqlite:///{path}", engine_kwargs={"creator": connect},
                                          heartbeat_interval=HEARTBEAT_SECONDS, grace_period=GRACE_SECONDS)


@contextlib.contextmanager
def _creating(out: Path) -> Iterator[None]:
    """Held while a process creates or opens the storage's tables: two
    processes starting a new tuning at once would both create them (one
    then fails on a unique key of Optuna's schema). Optuna itself copes
    with two processes creating one study."""
    with open(out / f"{STORAGE_NAME}.lock", "a+b") as lock:
        try:
            import fcntl
        except ImportError:  # not on Windows, where processes do not share a folder's storage this way
            yield
            return
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)


def study_name(tuning: Tuning, controller: str) -> str:
    return f"{tuning.name}.{controller}"


def fingerprint(tuning: Tuning, controller: str) -> str:
    """What decides a controller's trials: the study part but the other
    controllers, this controller's table and search, and the settings but the
    budget and the verdict's (a larger budget or another verdict reuses the
    trials made)."""
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
    if name == "nsga2":
        return optuna.samplers.NSGAIISampler(seed=seed)
    return optuna.samplers.RandomSampler(seed=seed)


def place_seed(base: int, study: Any, number: int) -> int:
    """The seed of trial `number`: from its place, the trials finished or
    running before it. One process alone gives the same places (hence the
    same trials) whether or not it was interrupted on the way (an
    interrupted trial failed and is not counted); two processes never give
    two trials one place (the earlier is running or finished when the later
    starts)."""
    place = sum(1 for t in counted_trials(study) if t.number < number)
    return int(np.random.SeedSequence([base, place]).generate_state(1)[0])


def _place_seeded(name: str, base: int) -> Any:
    """An Optuna sampler that is the sampler `name` seeded anew for each
    trial by :func:`place_seed`: a seed alone fixes one sampler's sequence only
    in one uninterrupted process."""
    import optuna

    class PlaceSeeded(optuna.samplers.BaseSampler):
        def __init__(self) -> None:
            self.inner = _sampler(name, base)

        def before_trial(self, study: Any, trial: Any) -> None:
            self.inner = _sampler(name, place_seed(base, study, trial.number))
            self.inner.before_trial(study, trial)

        def infer_relative_search_space(self, study: Any, trial: Any) -> Any:
            return self.inner.infer_relative_search_space(study, trial)

        def sample_relative(self, study: Any, trial: Any, space: Any) -> Any:
            return self.inner.sample_relative(study, trial, space)

        def sample_independent(self, study: Any, trial: Any, name: str, distribution: Any) -> Any:
            return self.inner.sample_independent(study, trial, name, distribution)

        def after_trial(self, study: Any, trial: Any, state: Any, values: Any) -> None:
            self.inner.after_trial(study, trial, state, values)

    return PlaceSeeded()


def optuna_study(tuning: Tuning, controller: str, storage: Any) -> Any:
    import optuna

    name = study_name(tuning, controller)
    # Two objectives (error, effort): Optuna's multi-objective study; its pruners judge one objective only.
    study = optuna.create_study(storage=storage, study_name=name, directions=["minimize"] * len(
        tuning.settings.objectives), load_if_exists=True,
        pruner=pruner(tuning.settings.pruner, tuning.settings.train_samples))
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
    """The trials that use the budget: finished, pruned by the pruner or
    running (not those pruned unrun past the budget), in number order."""
    import optuna

    S = optuna.trial.TrialState
    return sorted((t for t in study.get_trials(deepcopy=False, states=(S.COMPLETE, S.PRUNED, S.RUNNING))
                   if t.user_attrs.get("reason") != OVER_BUDGET), key=lambda t: t.number)


def enqueue_hand_set(tuning: Tuning, controller: str, study: Any) -> None:
    """With two objectives, a controller's first trial is its hand-set gains
    (where they are inside the searched ranges): its front then holds them or
    what beats them, and the fronts are read where the hand-set gains are."""
    if study.user_attrs.get("hand_set_enqueued") or study.trials:
        return
    values = hand_set_values(tuning.study_table["controllers"][controller], tuning.search[controller])
    study.set_user_attr("hand_set_enqueued", values is not None)
    if values is not None:
        study.enqueue_trial(values, user_attrs={"hand_set": True})


def pruner(name: str, train_samples: int) -> Any:
    """Optuna's pruner for ``[tune] pruner``. The median rule judges a trial
    at each run against the finished trials' running objective at the same
    run (the same scenario and plant, hence fair), from the sixth trial on
    and once the first scenario's plants are all in."""
    import optuna

    if name == "none":
        return optuna.pruners.NopPruner()
    return optuna.pruners.MedianPruner(n_startup_trials=5, n_warmup_steps=train_samples - 1)


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

    def stop_when_spent(study: Any, _trial: Any) -> None:
        # Other processes' trials count too.
        if budget.spent(tuning, counted_trials(study)) >= budget.limit(tuning):
            study.stop()

    def objective(trial: Any) -> float | tuple[float, float]:
        nonlocal ran
        ahead = [t for t in counted_trials(study) if t.number < trial.number]
        if budget.spent(tuning, ahead) >= budget.limit(tuning):
            trial.set_user_attr("reason", OVER_BUDGET)
            study.stop()
            raise optuna.TrialPruned()
        try:
            # Optuna reports one objective only: with two, every trial runs whole.
            outcome = evaluator(tuning, controller, suggest(trial, params), runner,
                                pruning=None if s.two_objectives else trial)
        except BaseException:
            trial.set_user_attr("reason", "interrupted")  # Optuna marks it failed
            raise
        for k, v in {"runs": outcome.runs, "failures": outcome.failures, "feasible": outcome.feasible,
                     "seconds": outcome.seconds, "reasons": outcome.reasons, "effort": outcome.effort,
                     "by_vehicle": outcome.by_vehicle}.items():
            trial.set_user_attr(k, v)
        ran += 1
        if on_trial is not None:
            on_trial(trial.number, outcome)
        if outcome.pruned:
            trial.set_user_attr("reason", "pruned")
            raise optuna.TrialPruned()  # Optuna keeps its last reported value
        if s.two_objectives:
            return outcome.value, math.inf if outcome.effort is None else outcome.effort
        return outcome.value

    if budget.spent(tuning, counted_trials(study)) >= budget.limit(tuning):
        return 0
    if s.two_objectives:
        enqueue_hand_set(tuning, controller, study)
    # Trials started: as many as are left; other units: until the budget is spent (the callback stops).
    left = s.trials - len(counted_trials(study)) if s.budget == "trials_started" else None
    study.sampler = _place_seeded(s.sampler, base_seed)
    study.optimize(objective, n_trials=left, callbacks=[stop_when_spent])
    return ran
