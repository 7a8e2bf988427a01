"""Running a tuning: every searched controller's trials, then trials.csv,
best.toml, the figures and the verdict (a study of the tuned controllers on
held-out plants). What ``neurov tune`` does."""

from __future__ import annotations

import json
import os
import shutil
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from neurov.progress import progress_bar
from neurov.study.running import StudyOutcome, run_study
from neurov.tuning.outputs import best_tables, draw_tuning_figures, write_best_toml, write_trials
from neurov.tuning.param_file import write_best_params
from neurov.tuning.reading import load_tuning, verdict_study
from neurov.tuning.search import STORAGE_NAME, TuneInterrupted, counted_trials, open_storage, optuna_study, run_trials
from neurov.tuning.spec import Tuning
from neurov.tuning.trial_runs import TrialRunner

__all__ = ["TuneOutcome", "main_tune", "tune"]


@dataclass
class TuneOutcome:
    out_dir: Path
    ran: int
    """Trials this call ran (the others were in the storage, or run by other processes)."""
    seconds: float
    best: dict[str, dict[str, Any]]
    """Controller key -> its tuned table (as in best.toml)."""
    trials_path: Path
    best_path: Path
    figures: list[Path]
    verdict: StudyOutcome | None
    param_files: list[tuple[Path, bool]] = field(default_factory=list)
    """(path, feasible) of each ArduSub parameter file written beside best.toml."""


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
    out.mkdir(parents=True, exist_ok=True)
    storage = open_storage(out)
    mine = [c for c in tuning.search if not only or c in only]
    s = tuning.settings
    start = time.perf_counter()
    ran = 0
    with TrialRunner(workers, scheduler) as runner:
        for controller in mine:
            done = len(counted_trials(optuna_study(tuning, controller, storage)))
            with progress_bar(s.trials, f"{tuning.name}: {controller}", unit="trial", quiet=not progress) as bar:
                bar.update(min(done, s.trials))
                try:
                    ran += run_trials(tuning, controller, storage, runner, on_trial=lambda n, o: bar.update(1))
                except KeyboardInterrupt:
                    total = len(mine) * s.trials
                    saved = sum(len(counted_trials(optuna_study(tuning, c, storage))) for c in mine)
                    raise TuneInterrupted(saved, total, out / STORAGE_NAME) from None
    seconds = time.perf_counter() - start
    studies = {c: optuna_study(tuning, c, storage) for c in tuning.search}
    trials_path = write_trials(tuning, studies, out / "trials.csv")
    best_path = write_best_toml(tuning, studies, out / "best.toml")
    param_files = write_best_params(tuning, studies, out)
    best = best_tables(tuning, studies)
    figures = draw_tuning_figures(tuning, studies, out) if plots else []
    (out / "tuning.json").write_text(json.dumps({
        "name": tuning.name, "source": tuning.source, "settings": asdict(tuning.settings),
        "search": {c: [asdict(p) for p in ps] for c, ps in tuning.search.items()},
        "trials_run_by_this_call": ran, "seconds": seconds, "workers": workers,
        "executor": runner.executor}, indent=2, default=str) + "\n")
    outcome = None
    if verdict and best:
        judged = verdict_study(tuning, best)
        _discard_stale_verdict(out / "verdict", judged.fingerprint())
        outcome = run_study(judged, out / "verdict", workers=workers, scheduler=scheduler,
                            executor="dask" if scheduler else "processes", plots=plots, progress=progress)
    return TuneOutcome(out_dir=out, ran=ran, seconds=seconds, best=best, trials_path=trials_path,
                       best_path=best_path, figures=figures, verdict=outcome, param_files=param_files)


def _discard_stale_verdict(folder: Path, fingerprint: str) -> None:
    """A verdict of other tuned gains (more trials since, another process's
    better trial) is derived from the storage and best.toml alone: it is
    removed and run again rather than refused as a study folder would be."""
    meta = folder / "study.json"
    if not meta.exists():
        return
    try:
        old = json.loads(meta.read_text()).get("fingerprint")
    except (json.JSONDecodeError, AttributeError):
        old = None
    if old != fingerprint:
        shutil.rmtree(folder)


def main_tune(path: str, out_dir: str | None, workers: int | None, scheduler: str | None, *,
              verdict: bool = True, plots: bool = True, quiet: bool = False,
              only: list[str] | None = None) -> TuneOutcome:
    """What ``neurov tune`` does: tune, then print where things are."""
    tuning = load_tuning(path)
    out = out_dir or f"tune-{tuning.name}"
    outcome = tune(tuning, out, workers=workers, scheduler=scheduler, verdict=verdict, plots=plots,
                   progress=not quiet, only=only)
    print(f"{tuning.name}: {len(tuning.search)} controller(s) x {tuning.settings.trials} trials "
          f"({outcome.ran} run now in {outcome.seconds:.1f} s)")
    print(f"trials: {outcome.trials_path}\ntuned gains: {outcome.best_path}")
    for path, feasible in outcome.param_files:
        note = "" if feasible else " (no trial was feasible: the least bad values)"
        print(f"ArduSub parameters: {path}{note}")
    if outcome.verdict is not None:
        print(f"verdict on {tuning.settings.test_samples} held-out plants: {outcome.verdict.league}")
    return outcome
