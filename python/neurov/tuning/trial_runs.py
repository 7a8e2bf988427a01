"""The runs of a trial, on workers kept for the whole tuning: a study's runs
in its batches (:func:`neurov.study.one_run.run_batch`: the built-in
controllers' runs of a batch together in C++, the same plants and records),
where a run that raises becomes a record of its error instead of ending the
trial.

A study starts its pool of processes (or its Dask cluster) once per study;
a tuning runs hundreds of small studies, one per trial, so it keeps one pool
for all of them (starting a spawned worker costs about a second)."""

from __future__ import annotations

import concurrent.futures as cf
from concurrent.futures.process import BrokenProcessPool
import os
import signal
import time
from collections.abc import Callable, Sequence
from typing import Any

from neurov.study.executors import default_batch_size, split_batches
from neurov.study.one_run import RunKey, plan_runs, run_batch, run_one
from neurov.study.processes import GRACE_SECONDS, die_with_parent
from neurov.study.spec import Study
from neurov.tuning.signals import deferred

__all__ = ["TrialRunner", "run_keys_safely"]

# As a study's workers: one run at a time per process, no BLAS threads.
_ONE_THREAD = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}


def run_keys_safely(study: Study, keys: Sequence[tuple[int, int, int]]) -> list[dict[str, Any]]:
    """The records of `keys`, simulated as one batch; a run that raises
    gives its study record of the error (:func:`~neurov.study.one_run.run_one`),
    or ``{"key", "error"}`` (its exception's type and message) where even
    that fails, and the others still run."""
    try:
        return run_batch(study, keys)
    except Exception:  # noqa: BLE001, S110 - run by run below, where each run's error is its own
        pass
    out = []
    for k in keys:
        key = RunKey(*k)
        try:
            out.append(run_one(study, key))
        except Exception as e:  # noqa: BLE001 - a trial's wild guess may fail anywhere; it is a result
            out.append({"key": [study.scenarios[key.scenario].name, study.controllers[key.controller],
                                key.sample], "error": f"{type(e).__name__}: {e}"})
    return out


def _start_worker() -> None:
    # Ctrl-C reaches the process group; the parent answers it. A worker dies
    # with the tuning's process, however that is stopped (SIGKILL included).
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    die_with_parent()


def _end_workers(pool: cf.ProcessPoolExecutor) -> None:
    """Ends the pool's workers at once, busy or not: SIGTERM, and SIGKILL to
    one still there after GRACE_SECONDS (a run that hangs)."""
    # The executor's processes by pid (Python 3.14 adds terminate_workers for this).
    procs = list((getattr(pool, "_processes", None) or {}).values())
    for p in procs:
        p.terminate()
    deadline = time.monotonic() + GRACE_SECONDS
    for p in procs:
        p.join(max(0.0, deadline - time.monotonic()))
    for p in procs:
        if p.is_alive():
            p.kill()
            p.join()


class TrialRunner:
    """Runs every run of a study (one trial) on `workers`: in this process
    (1), on local processes, or on the Dask cluster at `scheduler`."""

    def __init__(self, workers: int = 1, scheduler: str | None = None) -> None:
        if workers < 1:
            raise ValueError(f"argument 'workers' must be >= 1, got {workers}")
        self.workers = workers
        self.scheduler = scheduler
        self._pool: cf.ProcessPoolExecutor | None = None
        self._client: Any = None
        self._added_env: list[str] = []

    @property
    def executor(self) -> str:
        return "dask" if self.scheduler else ("processes" if self.workers > 1 else "this process")

    def __enter__(self) -> TrialRunner:
        return self

    def __exit__(self, kind: object, *exc: object) -> None:
        # Stopped (Ctrl-C, SIGTERM, an error): the workers are ended, not awaited.
        self.close(stop=kind is not None)

    def _processes(self) -> cf.ProcessPoolExecutor:
        if self._pool is None:
            import multiprocessing

            added = {k: v for k, v in _ONE_THREAD.items() if k not in os.environ}
            os.environ.update(added)
            self._added_env = list(added)
            previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
            try:
                # spawn, as a study's pool: forking a process with threads can deadlock.
                self._pool = cf.ProcessPoolExecutor(max_workers=self.workers,
                                                    mp_context=multiprocessing.get_context("spawn"),
                                                    initializer=_start_worker)
            finally:
                signal.signal(signal.SIGINT, previous)
        return self._pool

    def run(self, study: Study, on_runs: Callable[[list[dict[str, Any]]], bool] | None = None,
            ) -> list[dict[str, Any]]:
        """The runs of `study` in the study's order. `on_runs` is given each
        next records in that order as they come in (a run or a batch at a
        time); when it returns True the runs not yet started are cancelled
        and the records so far returned (a pruned trial)."""
        keys = plan_runs(study)
        batches = split_batches(keys, default_batch_size(len(keys), self.workers))
        if self.workers == 1 and not self.scheduler:
            out: list[dict[str, Any]] = []
            for b in batches:
                new = run_keys_safely(study, b)
                out += new
                if on_runs is not None and on_runs(new):
                    break
            return out
        try:
            futures = self._submit_dask(study, batches) if self.scheduler else \
                [self._processes().submit(run_keys_safely, study, b) for b in batches]
            out = []
            for i, f in enumerate(futures):
                new = f.result()
                out += new
                if on_runs is not None and on_runs(new):
                    for g in futures[i + 1:]:
                        g.cancel()  # those already running finish unread
                    break
            return out
        except BrokenProcessPool:
            # A worker that died (a user's extension crashing) takes the pool
            # with it: the trial's runs are failures, and a new pool serves the next.
            self._pool = None
            return [{"key": [study.scenarios[k.scenario].name, study.controllers[k.controller], k.sample],
                     "error": "a worker process died during the trial"} for k in keys]

    def _submit_dask(self, study: Study, batches: list[list[tuple[int, int, int]]]) -> list[Any]:
        if self._client is None:
            from dask.distributed import Client

            self._client = Client(self.scheduler)
        future = self._client.scatter(study, broadcast=True)
        return [self._client.submit(run_keys_safely, future, b, pure=False) for b in batches]

    def close(self, stop: bool = False) -> None:
        """Ends the workers: once their runs are done, or with `stop` at once."""
        if self._pool is not None:
            with deferred():  # a second Ctrl-C must not leave workers running
                if stop:
                    _end_workers(self._pool)
                self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None
        if self._client is not None:
            self._client.close()
            self._client = None
        for k in self._added_env:
            os.environ.pop(k, None)
        self._added_env = []
