"""The Optuna side of a tuning: one Optuna study per controller in one RDB
storage (an SQLite file), the same budget for each, trials asked and told
so that several processes on one storage share the budget without
duplicating trials, and an interrupted tuning resumes from the storage."""

from __future__ import annotations

import hashlib
import json
import math
import signal
import time
import zlib
from collections.abc import Callable
from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np

from neurov.study.running import StudyInterrupted
from neurov.tuning import budget
from neurov.tuning.objective import TrialOutcome, evaluate
from neurov.tuning.signals import deferred, live, stopping
from neurov.tuning.space import hand_set_values, suggest
from neurov.tuning.spec import TuneError, Tuning
from neurov.tuning.storage import STORAGE_NAME, claim, fail_dead_trials, open_storage
from neurov.tuning.trial_runs import TrialRunner
from neurov._core import __version__

__all__ = ["OVER_BUDGET", "STORAGE_NAME", "TuneInterrupted", "counted_trials", "enqueue_hand_set", "open_storage",
           "optuna_study", "pruner", "run_trials", "study_name"]

# The reason of a trial pruned unrun because the budget was spent when it started.
OVER_BUDGET = "over budget"
# Seconds between two looks at other processes' running trials, once this
# process has no budget left to start: the tuning ends when they have.
WAIT_SECONDS = 0.5


class TuneInterrupted(StudyInterrupted):
    """Ctrl-C or SIGTERM during a tuning: says how many trials are saved in
    the storage; `signum` is the signal (``neurov tune`` exits with 128 + it)."""

    def __init__(self, done: int, total: int, storage: Path, signum: int = signal.SIGINT) -> None:
        super().__init__(done, total, storage, signum, what="trials")
        self.done, self.storage = done, storage


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


class _DeferredPruning:
    """The trial as the objective's pruning: what it tells the storage is not
    cut short by a signal (:func:`~neurov.tuning.signals.deferred`)."""

    def __init__(self, trial: Any) -> None:
        self.trial = trial

    def report(self, value: float, step: int) -> None:
        with deferred():
            self.trial.report(value, step)

    def should_prune(self) -> bool:
        with deferred():
            return bool(self.trial.should_prune())


def run_trials(tuning: Tuning, controller: str, storage: Any, runner: TrialRunner,
               on_trial: Callable[[int, TrialOutcome], None] | None = None,
               evaluator: Callable[..., TrialOutcome] = evaluate) -> int:
    """Runs trials of `controller` until its budget is finished (by this
    process or others on the storage); returns how many this process ran.

    Optuna's optimize loop keeps each trial's heartbeat and marks a trial
    interrupted by Ctrl-C or SIGTERM failed; a signal stops the loop only in
    the objective, never in Optuna's bookkeeping
    (:mod:`~neurov.tuning.signals`). A trial that finds the budget spent by
    the time it starts (another process took the last one) is pruned unrun.
    A trial whose process died is marked failed
    (:func:`~neurov.tuning.storage.fail_dead_trials`) and its place run
    again; once no place is left, this waits for the other processes'
    running trials, so that the budget is finished trials when it returns."""
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
        claim(trial)
        ahead = [t for t in counted_trials(study) if t.number < trial.number]
        if budget.spent(tuning, ahead) >= budget.limit(tuning):
            trial.set_user_attr("reason", OVER_BUDGET)
            study.stop()
            raise optuna.TrialPruned()
        values = suggest(trial, params)
        try:
            with live():  # Ctrl-C and SIGTERM stop the trial here (Optuna marks it failed)
                # Optuna reports one objective only: with two, every trial runs whole.
                outcome = evaluator(tuning, controller, values, runner,
                                    pruning=None if s.two_objectives else _DeferredPruning(trial))
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

    with stopping():
        while True:
            fail_dead_trials(study, storage)
            counted = counted_trials(study)
            if budget.spent(tuning, counted) < budget.limit(tuning):
                if s.two_objectives:
                    enqueue_hand_set(tuning, controller, study)
                # Trials started: as many as are left; other units: until the budget is spent
                # (the callback stops).
                left = s.trials - len(counted) if s.budget == "trials_started" else None
                study.sampler = _place_seeded(s.sampler, base_seed)
                with deferred():
                    study.optimize(objective, n_trials=left, callbacks=[stop_when_spent])
            elif any(t.state == optuna.trial.TrialState.RUNNING for t in counted):
                time.sleep(WAIT_SECONDS)  # other processes' trials: they finish, or their process dies
            else:
                return ran
