"""Where a study's batches run: a Dask cluster (local or by address) or
local processes. Both hand each finished batch to the same callback, so the
table does not depend on the executor."""

from __future__ import annotations

import math
import os
import signal
from collections.abc import Callable, Sequence
from typing import Any

from neurov.study.one_run import RunKey, run_batch
from neurov.study.spec import Study

__all__ = ["split_batches", "dask_available", "default_batch_size", "run_with_dask", "run_with_processes"]

OnDone = Callable[[list[dict[str, Any]]], None]

# Local-process workers keep the study from their initialiser, so each task
# ships only its run indices.
_WORKER_STUDY: Study | None = None


def _init_process_worker(study: Study) -> None:
    global _WORKER_STUDY
    _WORKER_STUDY = study
    # Ctrl-C reaches the whole process group; the parent answers it (saves
    # what is done and says so), the workers must not print tracebacks.
    _ignore_sigint()


def _ignore_sigint() -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _run_batch_in_process(keys: Sequence[tuple[int, int, int]]) -> list[dict[str, Any]]:
    assert _WORKER_STUDY is not None, "worker started without its study"
    return run_batch(_WORKER_STUDY, keys)

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


# Each worker is one process running one run at a time: a BLAS thread pool in
# every worker only competes for the same cores (Dask's nanny sets the same).
_SINGLE_THREADED = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}


def run_with_processes(study: Study, batches: list[list[tuple[int, int, int]]], workers: int,
                       on_done: OnDone) -> None:
    import concurrent.futures as cf
    import multiprocessing

    # spawn, not fork: forking a process that has threads (a Dask client, BLAS)
    # can deadlock, and spawn behaves the same on every platform. Spawned
    # children take the environment as it is when they start, and the pool
    # starts them on the first submits, so the variables stay set until the
    # pool is done; a user's own setting wins.
    ctx = multiprocessing.get_context("spawn")
    added = {k: v for k, v in _SINGLE_THREADED.items() if k not in os.environ}
    os.environ.update(added)
    try:
        pool = cf.ProcessPoolExecutor(max_workers=workers, mp_context=ctx, initializer=_init_process_worker,
                                      initargs=(study,))
        try:
            # The pool starts its workers in these submits. A spawned worker
            # takes a second or more to import before its initializer ignores
            # SIGINT, and a Ctrl-C in that time printed its traceback; started
            # with SIGINT ignored, it inherits that (Python keeps an ignored
            # SIGINT ignored). A Ctrl-C during the submits themselves is lost.
            previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
            try:
                futures = [pool.submit(_run_batch_in_process, b) for b in batches]
            finally:
                signal.signal(signal.SIGINT, previous)
            for fut in cf.as_completed(futures):
                on_done(fut.result())
        except BaseException:
            # Ctrl-C or a failed run: the queued batches are not waited for.
            pool.shutdown(wait=True, cancel_futures=True)
            raise
        pool.shutdown(wait=True)
    finally:
        for k in added:
            os.environ.pop(k, None)


def run_with_dask(study: Study, batches: list[list[tuple[int, int, int]]], workers: int,
                  scheduler: str | None, on_done: OnDone, dask_processes: bool) -> int:
    """Runs the batches on a Dask cluster; returns the number of workers used."""
    from dask.distributed import Client, LocalCluster, as_completed

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
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=dask_processes,
                                   dashboard_address="127.0.0.1:0", **local)
        finally:
            signal.signal(signal.SIGINT, previous)
        client = Client(cluster)
    try:
        n_workers = len(client.scheduler_info().get("workers", {})) or workers
        study_future = client.scatter(study, broadcast=True)
        futures = [client.submit(run_batch, study_future, b, pure=False) for b in batches]
        for fut in as_completed(futures):
            on_done(fut.result())
            fut.release()
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


def _quiet_dask() -> None:
    import logging

    for name in ("distributed", "tornado", "asyncio"):
        logging.getLogger(name).setLevel(logging.CRITICAL)
