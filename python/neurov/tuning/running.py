"""Running a tuning: every searched controller's trials, then trials.csv,
best.toml, the figures and the verdict (a study of the tuned controllers on
held-out plants). What ``neurov tune`` does."""

from __future__ import annotations

import json
import os
import signal
import sys
import time
from dataclasses import asdict, replace
from pathlib import Path
from typing import Any

import pandas as pd

from neurov.progress import progress_bar
from neurov.study.running import StudyInterrupted, run_study
from neurov.study.tables import write_table
from neurov.tuning.budget import budget_table, unit_words
from neurov.tuning.closing import TuneOutcome, closing_message
from neurov.tuning.equal_effort import hand_set_points, read_fronts, write_equal_effort
from neurov.tuning.outputs import (best_tables, discard_stale_verdict, draw_tuning_figures, unusable,
                                   write_best_toml, write_trials)
from neurov.tuning.param_file import write_best_params
from neurov.tuning.reading import load_tuning, verdict_study
from neurov.tuning.search import STORAGE_NAME, TuneInterrupted, counted_trials, open_storage, optuna_study, run_trials
from neurov.tuning.signals import stopping
from neurov.tuning.storage import storage_errors
from neurov.tuning.spec import Tuning
from neurov.tuning.trial_runs import TrialRunner

__all__ = ["TuneOutcome", "main_tune", "tune"]


def tune(tuning: Tuning | str | Path, out_dir: str | Path, *, workers: int | None = None,
         scheduler: str | None = None, verdict: bool = True, plots: bool = True, progress: bool = True,
         only: list[str] | None = None) -> TuneOutcome:
    """Tunes every controller of the tuning file that has a ``search`` table
    with the budget of ``[tune]``, in the Optuna storage ``out_dir/tuning.db``
    (a rerun resumes from it; other processes given the same folder share
    the budget), then writes trials.csv, best.toml, the figures and, with
    `verdict`, the study of the tuned controllers on the test plants in
    ``out_dir/verdict``. `only`: tune these controllers (another process may
    take the others)."""
    if not isinstance(tuning, Tuning):
        tuning = load_tuning(tuning)
    workers = int(workers or os.cpu_count() or 1)
    if workers < 1:
        raise ValueError(f"argument 'workers' must be >= 1, got {workers}")
    unknown = sorted(set(only or []) - set(tuning.search))
    if unknown:
        raise ValueError(f"argument 'only': {unknown[0]!r} is not a searched controller of {tuning.source} "
                         f"(searched: {sorted(tuning.search)})")
    out = Path(out_dir)
    storage = open_storage(out)
    mine = [c for c in tuning.search if not only or c in only]
    with stopping(), storage_errors(out):
        try:
            return _tune(tuning, out, storage, mine, workers, scheduler, verdict, plots, progress)
        except StudyInterrupted:
            raise  # the verdict's (or the trials'): it says what it saved
        except KeyboardInterrupt as e:
            total = len(mine) * tuning.settings.trials
            saved = sum(len(counted_trials(optuna_study(tuning, c, storage))) for c in mine)
            raise TuneInterrupted(saved, total, out / STORAGE_NAME,
                                  getattr(e, "signum", signal.SIGINT)) from None


def _tune(tuning: Tuning, out: Path, storage: Any, mine: list[str], workers: int, scheduler: str | None,
          verdict: bool, plots: bool, progress: bool) -> TuneOutcome:
    s = tuning.settings
    start = time.perf_counter()
    ran = 0
    with TrialRunner(workers, scheduler) as runner:
        for controller in mine:
            done = len(counted_trials(optuna_study(tuning, controller, storage)))
            with progress_bar(s.trials, f"{tuning.name}: {controller}", unit="trial", quiet=not progress) as bar:
                bar.update(min(done, s.trials))
                ran += run_trials(tuning, controller, storage, runner, on_trial=lambda n, o: bar.update(1))
        studies = {c: optuna_study(tuning, c, storage) for c in tuning.search}
        # Two objectives: the hand-set gains on the training plants, where the fronts are read.
        hand_set = hand_set_points(tuning, studies, runner) if s.two_objectives else {}
    seconds = time.perf_counter() - start
    trials_path = write_trials(tuning, studies, out / "trials.csv")
    write_table(budget_table(tuning, studies), out / "budget.csv")
    fronts = read_fronts(tuning, studies, hand_set, out, plots) if s.two_objectives else None
    if fronts is not None:
        best = fronts.tables
        best_path = write_best_toml(tuning, studies, out / "best.toml", best, [
            f"read at equal effort ({fronts.source}: " + ", ".join(f"{v} {e:.4g}" for v, e in fronts.levels.items())
            + "); the trials per vehicle are in picks.csv"])
    else:
        best_path = write_best_toml(tuning, studies, out / "best.toml")
        best = best_tables(tuning, studies)
    bad = unusable(studies)
    # ArduSub's parameter files: of the best trials, or of those read at equal effort.
    param_files = write_best_params(tuning, studies, out, fronts)
    figures = draw_tuning_figures(tuning, studies, out) if plots else []
    (out / "tuning.json").write_text(json.dumps({
        "name": tuning.name, "source": tuning.source, "settings": asdict(tuning.settings),
        "search": {c: [asdict(p) for p in ps] for c, ps in tuning.search.items()},
        "trials_run_by_this_call": ran, "seconds": seconds, "workers": workers,
        "executor": runner.executor, "unusable": bad}, indent=2, default=str) + "\n")
    outcome, equal, words = None, None, ""
    if verdict and best:
        judged = verdict_study(tuning, best, unusable=bad)
        discard_stale_verdict(out / "verdict", judged.fingerprint())
        outcome = run_study(judged, out / "verdict", workers=workers, scheduler=scheduler,
                            executor="dask" if scheduler else "processes", plots=plots, progress=progress)
        if fronts is not None:
            equal, words = write_equal_effort(tuning, fronts, judged, outcome.table, out)
    return TuneOutcome(out_dir=out, ran=ran, seconds=seconds, best=best, trials_path=trials_path,
                       best_path=best_path, figures=figures, verdict=outcome, unusable=bad, equal_effort=equal,
                       equal_effort_words=words, param_files=param_files)


def main_tune(path: str, out_dir: str | None, workers: int | None, scheduler: str | None, *,
              verdict: bool = True, plots: bool = True, quiet: bool = False,
              only: list[str] | None = None, seed: int | None = None) -> TuneOutcome:
    """What ``neurov tune`` does: tune (with `seed`, the sampler's seed instead
    of the file's), then print where things are."""
    tuning = load_tuning(path)
    if seed is not None:
        tuning = replace(tuning, settings=replace(tuning.settings, seed=seed))
    out = out_dir or f"tune-{tuning.name}"
    outcome = tune(tuning, out, workers=workers, scheduler=scheduler, verdict=verdict, plots=plots,
                   progress=not quiet, only=only)
    print(f"{tuning.name}: {len(tuning.search)} controller(s) x {tuning.settings.trials} trials "
          f"({outcome.ran} run now in {outcome.seconds:.1f} s)")
    print(f"budget: {unit_words(tuning)} per controller ({outcome.out_dir / 'budget.csv'}):")
    for r in pd.read_csv(outcome.out_dir / "budget.csv").itertuples():
        print(f"  {r.controller}: {r.trials_started} trials started, {r.trials_pruned} pruned, "
              f"{r.trials_completed} completed, {r.runs_finished} runs finished")
    for path, feasible in outcome.param_files:
        note = "" if feasible else " (no trial was feasible: the least bad values)"
        print(f"ArduSub parameters: {path}{note}")
    for controller, why in outcome.unusable.items():
        print(f"neurov: warning: {controller} is not tuned: {why}; {outcome.best_path} holds its least bad "
              "gains, not usable ones", file=sys.stderr)
    print(closing_message(outcome, tuning.settings.test_samples))
    return outcome
