"""Where a study's batches run: a Dask cluster (local or by address) or
local processes (:mod:`~neurov.study.processes`). Both hand each finished
batch to the same callback, so the table does not depend on the executor,
and both record a run whose worker died as crashed rather than stop."""

from __future__ import annotations

import math
import signal
from collections.abc import Callable, Sequence
from typing import Any

from neurov.study.one_run import RunKey, error_record, run_batch
from neurov.study.processes import run_with_processes
from neurov.study.spec import Study

__all__ = ["split_batches", "dask_available", "default_batch_size", "run_with_dask", "run_with_processes"]

OnDone = Callable[[list[dict[str, Any]]], None]


def dask_available() -> bool:
    try:
        import dask.distributed  # noqa: F401
    except ImportError:
        return False
    return True


def split_batches(keys: Sequence[RunKey], size: int) -> list[list[tuple[int, int, int]]]:
    flat = [(k.scenario, k.controller, k.sample) for k in keys]
    return [flat[i:i + size] for i in range(0, len(flat), size)]


def default_batch_size(runs: int, workers: int) -> int:
    """Runs per task. A run costs about 10 ms of CPU and a Dask task about
    4 ms of worker CPU on top (the league study: 2.6 s with one run per task,
    1.8 s with 50), so a task of up to 64 runs keeps that under 1 %; at least
    eight tasks per worker keep the load balanced and the progress bar moving."""
    return max(1, min(64, math.ceil(runs / (8 * max(1, workers)))))


def run_with_dask(study: Study, batches: list[list[tuple[int, int, int]]], workers: int,
                  scheduler: str | None, on_done: OnDone, dask_processes: bool) -> int:
    """Runs the batches on a Dask cluster; returns the number of workers used."""
    import dask
    from dask.distributed import Client, LocalCluster, as_completed
    from distributed.scheduler import KilledWorker

    cluster = None
    if scheduler:
        client = Client(scheduler)
    else:
        # One thread per worker: a run holds the GIL for its Python set-up, and
        # the C++ loop is single-threaded, so threads add nothing per core.
        # Port 0 lets the OS pick the HTTP port: Dask's default 8787 may be
        # taken (another cluster), and None still binds 8787 for health checks.
        # Worker processes talk over loopback TCP; threads in this process
        # use Dask's in-process transport, which takes no host.
        local = {"host": "127.0.0.1"} if dask_processes else {}
        # Worker processes inherit an ignored SIGINT (and then asyncio installs
        # no handler of its own): Ctrl-C reaches the whole process group, and
        # only this process should answer it.
        previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
        try:
            with dask.config.set(_FAIL_AT_FIRST_DEATH):
                cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=dask_processes,
                                       dashboard_address="127.0.0.1:0", **local)
        finally:
            signal.signal(signal.SIGINT, previous)
        client = Client(cluster)
    try:
        n_workers = len(client.scheduler_info().get("workers", {})) or workers
        # The study as a task's result, not scattered data: a worker that dies
        # takes its copy with it, and the scheduler can compute a task again
        # where scattered data is lost for good (and every task needing it).
        study_future = client.submit(_the_study, study, pure=False)
        futures = [client.submit(run_batch, study_future, b, pure=False) for b in batches]
        batch_of = dict(zip(futures, batches))
        suspects: list[tuple[int, int, int]] = []
        for fut in as_completed(futures):
            try:
                records = fut.result()
            except KilledWorker:
                suspects += batch_of[fut]
                continue
            on_done(records)
            fut.release()
        # A worker died in those tasks, the one that killed it or one that was
        # only queued there beside it: their runs again, one at a time alone on
        # the cluster, so that a run whose worker dies now is the one to blame.
        for key in suspects:
            single = client.submit(run_batch, study_future, [key], pure=False)
            try:
                on_done(single.result())
            except KilledWorker as e:
                on_done([error_record(study, RunKey(*key), "crash", "KilledWorker",
                                      f"its Dask worker died in this run, and again when the run was retried "
                                      f"alone ({e})")])
    except KeyboardInterrupt:
        # Closing the cluster mid-task makes the workers and the scheduler log
        # every task cancelled and every connection lost; the study says in
        # one line what was saved.
        _quiet_dask()
        if cluster is not None:
            try:
                client.run(_quiet_dask)
            except Exception:  # noqa: BLE001 - a worker already gone has nothing to say
                pass
        raise
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    return n_workers


# The scheduler of a study's own LocalCluster marks a task as failed the first
# time a worker dies in it (Dask's default retries it on three more workers):
# its runs are then retried alone, once. A cluster at --scheduler keeps its
# own setting, so there a run is tried as often as it allows, in its batch
# and then alone.
_FAIL_AT_FIRST_DEATH = {"distributed.scheduler.allowed-failures": 0}


def _the_study(study: Study) -> Study:
    return study


def _quiet_dask() -> None:
    import logging

    for name in ("distributed", "tornado", "asyncio"):
        logging.getLogger(name).setLevel(logging.CRITICAL)
