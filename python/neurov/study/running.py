"""Running a study: the runs not yet in the output folder, on the chosen
executor, logged as they finish; then the tables, the league table and the
figures. What ``neurov study`` does."""

from __future__ import annotations

import contextlib
import json
import os
import signal
import threading
import time
import warnings
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pandas as pd

from neurov.progress import progress_bar
from neurov.study.executors import dask_available, default_batch_size, run_with_dask, run_with_processes, split_batches
from neurov.study.figures import draw_figures
from neurov.study.log import LOG_NAME, Record, StudyLogWarning, read_log, repair_tail
from neurov.study.one_run import plan_runs, run_batch
from neurov.study.reading import load_study
from neurov.study.report import league_markdown
from neurov.study.spec import Study, StudyError, identity_differences
from neurov.study.tables import failure_counts, runs_table, summary_table, write_table
from neurov.study.verdict import vehicle_verdicts, verdict_text

__all__ = ["StudyInterrupted", "StudyOutcome", "main_study", "run_study"]


def _load_average() -> float | None:
    try:
        return round(os.getloadavg()[0], 2)
    except (AttributeError, OSError):  # not on every platform
        return None


class StudyInterrupted(KeyboardInterrupt):
    """Ctrl-C or SIGTERM during a study: says how many runs are saved;
    rerunning the same study into the same folder resumes from them.
    `signum` is the signal (``neurov study`` exits with 128 + it)."""

    def __init__(self, saved: int, total: int, log: Path, signum: int = signal.SIGINT, what: str = "runs") -> None:
        how = "interrupted" if signum == signal.SIGINT else f"stopped by {signal.Signals(signum).name}"
        super().__init__(f"{how}: {saved} of {total} {what} are saved in {log}; "
                         "run the same command again to resume")
        self.saved, self.total, self.log, self.signum = saved, total, log, signum


class _Terminated(KeyboardInterrupt):
    """SIGTERM, raised where the study is, to stop it as Ctrl-C does."""


@contextlib.contextmanager
def _sigterm_stops_the_study() -> Iterator[None]:
    """SIGTERM stops the study as Ctrl-C does (its workers ended, what
    finished saved) instead of killing this process and leaving them."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def stop(signum: int, frame: object) -> None:
        raise _Terminated

    previous = signal.signal(signal.SIGTERM, stop)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


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
    figures: list[Path] = field(default_factory=list)
    """The figures this call drew (those whose data changed)."""
    study: Study | None = None
    """The study run."""

    @property
    def without_result(self) -> int:
        """Runs that raised or whose worker died (the table's ``error_kind``)."""
        return int(failure_counts(self.table)[0].sum()) if len(self.table) else 0

    @property
    def runs_per_second(self) -> float:
        return self.ran / self.seconds if self.seconds > 0 else float("nan")


def workers_phrase(workers: int, executor: str) -> str:
    """``2 local processes``, ``1 Dask worker``."""
    if executor == "processes":
        return f"{workers} local process{'es' if workers != 1 else ''}"
    return f"{workers} Dask worker{'s' if workers != 1 else ''}"


def _read_meta(path: Path) -> tuple[dict[str, Any] | None, str]:
    """study.json, or None and what is wrong with it."""
    try:
        meta = json.loads(path.read_bytes())
    except FileNotFoundError:
        return None, "missing"
    except (json.JSONDecodeError, UnicodeDecodeError) as e:
        return None, f"not readable JSON ({e})"
    except OSError as e:
        return None, f"not readable ({e.strerror or e})"
    if not isinstance(meta, dict) or not isinstance(meta.get("fingerprint"), str):
        return None, "not a study's description (no fingerprint)"
    return meta, ""


def _check_folder(study: Study, out: Path, log: Path, meta_path: Path, records: dict[Any, Record]) -> None:
    """Refuses a folder whose log holds runs of another study, naming what
    differs; then writes study.json. The records' own fingerprints decide
    (study.json may be gone or broken); study.json says which field differs."""
    fingerprint = study.fingerprint()
    meta, problem = _read_meta(meta_path)
    logged = {rec.get("study") for rec in records.values()}
    theirs = {f for f in logged if isinstance(f, str)}
    if None in logged:
        # Records of a neurov that did not log the fingerprint: study.json says whose they are.
        if meta is None:
            raise StudyError(f"{log}: holds runs without their study's fingerprint (written by an older neurov) "
                             f"and {meta_path} is {problem}, so whose runs they are cannot be told; use another "
                             f"--out, or delete {log} to start again")
        theirs.add(meta["fingerprint"])
    others = sorted(theirs - {fingerprint})
    if others:
        if meta is not None and meta["fingerprint"] in others and isinstance(meta.get("identity"), dict):
            diffs = identity_differences(meta["identity"], study.identity())
            what = f"; differs in {', '.join(diffs)}" if diffs else ""
        elif meta is None:
            what = f"; {meta_path} is {problem}, so which field differs cannot be said"
        else:
            what = " (seed, scenarios, controllers, perturbations or neurov version differ)"
        raise StudyError(f"{out}: holds runs of a different study (fingerprint {', '.join(others)} in {log}, "
                         f"{fingerprint} for this one){what}; use another --out, or delete {log} to start again")
    if records and meta is None and problem != "missing":
        warnings.warn(f"{meta_path}: {problem}; written again from this study, whose fingerprint every run in "
                      f"{log} carries", StudyLogWarning, stacklevel=3)
    new = {"name": study.name, "source": study.source, "fingerprint": fingerprint, "identity": study.identity(),
           "seed": study.seed, "samples": study.samples, "scenarios": [s.name for s in study.scenarios],
           "controllers": study.controllers, "ranking_metric": study.ranking_metric,
           "failure": study.failure}
    tmp = meta_path.with_name(meta_path.name + ".tmp")
    tmp.write_text(json.dumps(new, indent=2) + "\n")
    os.replace(tmp, meta_path)


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
    Ctrl-C, or SIGTERM (while this runs in the main thread), raises
    :class:`StudyInterrupted` once the workers are ended and the finished
    runs saved. A run that raises or whose worker dies is a failed run of
    the table (columns ``error_kind``, ``error``), not the end of the study.
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
    # A crash can leave the last record cut short; the next one must not be
    # appended onto it.
    repair_tail(log)
    records = read_log(log)
    _check_folder(study, out, log, out / "study.json", records)
    fingerprint = study.fingerprint()
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
            with log.open("a") as f, progress_bar(len(todo), f"{study.name}: runs", quiet=quiet) as bar, \
                    _sigterm_stops_the_study():
                def on_done(recs: list[Record]) -> None:
                    for rec in recs:
                        rec["study"] = fingerprint
                        records[tuple(rec["key"])] = rec  # type: ignore[index]
                        f.write(json.dumps(rec) + "\n")
                    # A finished batch is on disk before the next is awaited: an
                    # interrupted study resumes from here.
                    f.flush()
                    bar.update(len(recs))

                if executor == "dask":
                    used_workers = run_with_dask(study, work, workers, scheduler, on_done, dask_processes)
                elif workers == 1 and not study.factories:
                    # One worker needs no pool; running here also keeps tracebacks
                    # plain. A user's controller (which may crash its process) runs
                    # in a worker process even then.
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
    except KeyboardInterrupt as e:
        # Every finished run is in `records` and, flushed, in the log.
        saved = len(set(records) & names)
        signum = signal.SIGTERM if isinstance(e, _Terminated) else signal.SIGINT
        raise StudyInterrupted(saved, len(plan), log, signum) from None
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
                        table_path=table_path, summary_path=summary_path, league=league, figures=drawn,
                        study=study)


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
    if outcome.without_result:
        print(f"{outcome.without_result} run(s) gave no result (raised, or their worker died): each counts as "
              f"failed; their errors are listed in {outcome.league}")
    print(written_message(outcome))
    text = verdict_text(vehicle_verdicts(study, outcome.table))
    if text:
        print(f"\n{text}")
    return outcome


def written_message(outcome: StudyOutcome) -> str:
    """Everything a study wrote into its folder, one line per kind."""
    out = outcome.out_dir
    drawn = sorted(p.name for p in outcome.figures)
    figures = (f"\n  {len(drawn)} figure(s) drawn: {', '.join(drawn)}" if drawn else
               "\n  figures: none drawn (unchanged since the last run, or --no-plots)")
    return (f"wrote to {out}/:\n  table: {outcome.table_path.name} (one row per run)\n"
            f"  summary: {outcome.summary_path.name}\n  league table: {outcome.league.name} (the verdict first)\n"
            f"  log: {LOG_NAME}, study.json, timing.json{figures}")
