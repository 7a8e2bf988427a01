"""Running a study: the runs not yet in the output folder, on the chosen
executor, logged as they finish; then the tables, the league table and the
figures. What ``neurov study`` does."""

from __future__ import annotations

import json
import os
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pandas as pd

from neurov.progress import progress_bar
from neurov.study.executors import dask_available, default_batch_size, run_with_dask, run_with_processes, split_batches
from neurov.study.figures import draw_figures
from neurov.study.log import LOG_NAME, Record, read_log, repair_tail
from neurov.study.one_run import plan_runs, run_batch
from neurov.study.reading import load_study
from neurov.study.report import league_markdown
from neurov.study.spec import Study, StudyError
from neurov.study.tables import runs_table, summary_table, write_table

__all__ = ["StudyInterrupted", "StudyOutcome", "main_study", "run_study"]


def _load_average() -> float | None:
    try:
        return round(os.getloadavg()[0], 2)
    except (AttributeError, OSError):  # not on every platform
        return None


class StudyInterrupted(KeyboardInterrupt):
    """Ctrl-C during a study: says how many runs are saved; rerunning the
    same study into the same folder resumes from them."""

    def __init__(self, saved: int, total: int, log: Path) -> None:
        super().__init__(f"interrupted: {saved} of {total} runs are saved in {log}; "
                         "run the same command again to resume")
        self.saved, self.total, self.log = saved, total, log


@dataclass
class StudyOutcome:
    out_dir: Path
    total: int
    ran: int
    skipped: int
    executor: str
    workers: int
    seconds: float
    table: pd.DataFrame
    """The runs table, one row per run (what ``table_path`` holds)."""
    summary: pd.DataFrame
    """Per scenario and controller: rank, median, percentiles, failure rate."""
    table_path: Path
    summary_path: Path
    league: Path

    @property
    def runs_per_second(self) -> float:
        return self.ran / self.seconds if self.seconds > 0 else float("nan")


def workers_phrase(workers: int, executor: str) -> str:
    """``2 local processes``, ``1 Dask worker``."""
    if executor == "processes":
        return f"{workers} local process{'es' if workers != 1 else ''}"
    return f"{workers} Dask worker{'s' if workers != 1 else ''}"


def _check_folder(study: Study, out: Path, log: Path, meta_path: Path) -> None:
    fingerprint = study.fingerprint()
    if meta_path.exists() and log.exists():
        try:
            old = json.loads(meta_path.read_text()).get("fingerprint")
        except json.JSONDecodeError:
            old = None
        if old != fingerprint:
            raise StudyError(f"{out}: holds runs of a different study (seed, scenarios, controllers, "
                             f"perturbations or neurov version differ); use another --out, or delete "
                             f"{log} to start again")
    meta = {"name": study.name, "source": study.source, "fingerprint": fingerprint, "seed": study.seed,
            "samples": study.samples, "scenarios": [s.name for s in study.scenarios],
            "controllers": study.controllers, "ranking_metric": study.ranking_metric,
            "failure": study.failure}
    meta_path.write_text(json.dumps(meta, indent=2) + "\n")


def run_study(study: Study | str | Path, out_dir: str | Path, *, workers: int | None = None,
              scheduler: str | None = None, executor: str = "auto", batch_size: int | None = None,
              table_format: str = "csv", plots: bool = True, progress: bool = True,
              dask_processes: bool = True) -> StudyOutcome:
    """Runs every (scenario x controller x sample) not already in `out_dir`
    and writes runs.csv (or runs.parquet), summary.csv, league.md,
    study.json and, with `plots`, box and band plots (those whose data
    changed). With `progress`, bars on stderr while it is a terminal.

    executor: ``"dask"`` (a LocalCluster of `workers`, or the cluster at
    `scheduler`), ``"processes"`` (local processes) or ``"auto"`` (Dask if
    installed, else processes). The table is the same whichever runs it.
    Ctrl-C raises :class:`StudyInterrupted` once the finished runs are saved.
    """
    if not isinstance(study, Study):
        study = load_study(study)
    if executor not in ("auto", "dask", "processes"):
        raise ValueError(f"argument 'executor' must be 'auto', 'dask' or 'processes', got {executor!r}")
    if table_format not in ("csv", "parquet"):
        raise ValueError(f"argument 'table_format' must be 'csv' or 'parquet', got {table_format!r}")
    if scheduler and executor == "processes":
        raise ValueError("a scheduler address needs the Dask executor")
    if executor == "auto":
        executor = "dask" if (scheduler or dask_available()) else "processes"
    if executor == "dask" and not dask_available():
        raise StudyError('the Dask executor needs dask.distributed: pip install "neurov[distributed]"')
    workers = int(workers or os.cpu_count() or 1)
    if workers < 1:
        raise ValueError(f"argument 'workers' must be >= 1, got {workers}")
    quiet = not progress

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    log = out / LOG_NAME
    _check_folder(study, out, log, out / "study.json")
    # A crash can leave the last record cut short; the next one must not be
    # appended onto it.
    repair_tail(log)
    records = read_log(log)
    before = set(records)
    plan = plan_runs(study)
    names = {(s.name, c, k) for s in study.scenarios for c in study.controllers for k in range(study.samples)}
    todo = [k for k in plan if (study.scenarios[k.scenario].name, study.controllers[k.controller], k.sample)
            not in records]
    skipped = len(plan) - len(todo)
    size = batch_size or default_batch_size(len(todo), workers)
    work = split_batches(todo, size)

    used_workers = workers
    load_start = _load_average()
    start = time.perf_counter()
    try:
        if todo:
            with log.open("a") as f, progress_bar(len(todo), f"{study.name}: runs", quiet=quiet) as bar:
                def on_done(recs: list[Record]) -> None:
                    for rec in recs:
                        records[tuple(rec["key"])] = rec  # type: ignore[index]
                        f.write(json.dumps(rec) + "\n")
                    # A finished batch is on disk before the next is awaited: an
                    # interrupted study resumes from here.
                    f.flush()
                    bar.update(len(recs))

                if executor == "dask":
                    used_workers = run_with_dask(study, work, workers, scheduler, on_done, dask_processes)
                elif workers == 1:
                    # One worker needs no pool; running here also keeps tracebacks plain.
                    for b in work:
                        on_done(run_batch(study, b))
                else:
                    run_with_processes(study, work, workers, on_done)
        seconds = time.perf_counter() - start

        keep = {k: v for k, v in records.items() if k in names}
        new_keys = [k for k in keep if k not in before]
        with progress_bar(3, f"{study.name}: tables", unit="file", quiet=quiet) as bar:
            table = runs_table(study, keep)
            table_path = write_table(table, out / f"runs.{table_format}")
            bar.update(1)
            summary = summary_table(study, table)
            summary_path = write_table(summary, out / "summary.csv")
            bar.update(1)
            league = out / "league.md"
            league.write_text(league_markdown(study, table))
            bar.update(1)
        plot_start = time.perf_counter()
        drawn = draw_figures(study, table, keep, out, quiet=quiet) if plots and len(table) else []
        plot_seconds = time.perf_counter() - plot_start
    except KeyboardInterrupt:
        saved = len(set(read_log(log)) & names)
        raise StudyInterrupted(saved, len(plan), log) from None
    timing: dict[str, Any] = {
        "executor": executor, "workers": used_workers, "batch_size": size, "runs": len(todo),
        "skipped": skipped, "seconds": seconds, "cpus": os.cpu_count(),
        "load_average_at_start_and_end": [load_start, _load_average()],
        "runs_per_second": len(todo) / seconds if seconds > 0 and todo else None,
        # CPU seconds the workers spent on this invocation's runs: on a shared
        # machine the wall-clock rate depends on the other load, runs per CPU
        # second does not.
        "worker_cpu_seconds": sum(records[k].get("cpu_time", 0.0) for k in new_keys),
        "loop_wall_seconds": sum(records[k].get("wall_time", 0.0) for k in new_keys),
        "figures_drawn": len(drawn),
        "plot_seconds": plot_seconds,
    }
    if timing["worker_cpu_seconds"]:
        timing["runs_per_cpu_second"] = len(todo) / timing["worker_cpu_seconds"]
    (out / "timing.json").write_text(json.dumps(timing, indent=2) + "\n")
    return StudyOutcome(out_dir=out, total=len(plan), ran=len(todo), skipped=skipped, executor=executor,
                        workers=used_workers, seconds=seconds, table=table, summary=summary,
                        table_path=table_path, summary_path=summary_path, league=league)


def main_study(path: str, out_dir: str | None, workers: int | None, scheduler: str | None,
               executor: str = "auto", table_format: str = "csv", plots: bool = True,
               batch_size: int | None = None, quiet: bool = False) -> StudyOutcome:
    """What ``neurov study`` does: run, then print where things are."""
    study = load_study(path)
    out = out_dir or f"study-{study.name}"
    outcome = run_study(study, out, workers=workers, scheduler=scheduler, executor=executor,
                        table_format=table_format, plots=plots, batch_size=batch_size, progress=not quiet)
    rate = f", {outcome.runs_per_second:.2f} runs/s" if outcome.ran else ""
    print(f"{study.name}: {outcome.total} runs ({outcome.skipped} already done, {outcome.ran} run in "
          f"{outcome.seconds:.1f} s on {workers_phrase(outcome.workers, outcome.executor)}{rate})")
    print(f"table: {outcome.table_path}\nleague table: {outcome.league}")
    return outcome
