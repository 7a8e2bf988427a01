"""A study's runs on local worker processes, each of which may die.

Each worker is a spawned process fed one batch at a time over a pipe and
sending back each run's record as it finishes, so the parent always knows
which run a worker is in. A worker that dies (a segfault in a user's C
extension, ``os._exit``, the kernel's OOM killer) is replaced; the run it was
in is retried once, alone, on a fresh worker, and recorded as crashed if that
worker dies too; the rest of its batch goes back to the queue. Stopping
(Ctrl-C, SIGTERM, an error) terminates every worker, and kills one that is
still there after :data:`GRACE_SECONDS`."""

from __future__ import annotations

import contextlib
import multiprocessing
import multiprocessing.connection
import os
import signal
import time
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from typing import Any

from neurov.study.one_run import RunKey, error_record, run_batch
from neurov.study.spec import Study, StudyError

__all__ = ["GRACE_SECONDS", "die_with_parent", "run_with_processes"]

OnDone = Callable[[list[dict[str, Any]]], None]

#: Seconds a worker has to end after SIGTERM when the study stops, before SIGKILL.
GRACE_SECONDS = 2.0

# Each worker is one process running one run at a time: a BLAS thread pool in
# every worker only competes for the same cores (Dask's nanny sets the same).
_SINGLE_THREADED = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}

_READY = "ready"


def _worker_main(conn: multiprocessing.connection.Connection, study: Study) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    die_with_parent()
    conn.send(_READY)
    while True:
        try:
            keys = conn.recv()
        except (EOFError, OSError):  # the parent is gone
            return
        if keys is None:
            return
        # The batch's built-in runs are simulated together first: a crash
        # there is charged to the batch's first run, retried alone.
        for record in run_batch(study, keys):
            conn.send(record)


def die_with_parent() -> None:
    """On Linux, the kernel kills this worker process when the process that
    started it (a study's, a tuning's) dies, however it dies (even by
    SIGKILL, which leaves it no time to stop us)."""
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):  # not Linux: the parent's stop still ends the workers
        return
    parent = multiprocessing.parent_process()
    if parent is not None and os.getppid() != parent.pid:  # it died before the prctl
        os._exit(1)


@contextlib.contextmanager
def _children_ignore_sigint() -> Iterator[None]:
    """A worker started here inherits an ignored SIGINT (Python keeps an
    ignored SIGINT ignored), so a Ctrl-C to the process group during its
    first second of imports prints no traceback. A Ctrl-C in the few
    milliseconds of the start itself is lost (blocking it instead would not
    hold it: the kernel hands it to another thread, BLAS's, that ignores it)."""
    in_main = _in_main_thread()
    if in_main:
        previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        if in_main:
            signal.signal(signal.SIGINT, previous)


def _in_main_thread() -> bool:
    import threading

    return threading.current_thread() is threading.main_thread()


class _Worker:
    def __init__(self, ctx: Any, study: Study) -> None:
        self.conn, child = ctx.Pipe(duplex=True)
        with _children_ignore_sigint():
            self.proc = ctx.Process(target=_worker_main, args=(child, study), daemon=True,
                                    name="neurov-study-worker")
            self.proc.start()
        child.close()
        self.ready = False
        self.keys: list[tuple[int, int, int]] = []
        """The runs sent and not yet returned; the first is the one running."""
        self.retry = False
        """Whether `keys` is a run retried alone after its worker died."""

    def collect(self, on_done: OnDone) -> bool:
        """Hands on every record the worker has sent; False once it is dead."""
        while self.conn.poll():
            try:
                rec = self.conn.recv()
            except (EOFError, OSError):
                break
            if rec == _READY:
                self.ready = True
                continue
            self.keys.pop(0)
            on_done([rec])
        return self.proc.is_alive()


def _death(proc: Any) -> str:
    code = proc.exitcode
    if code is not None and code < 0:
        try:
            return f"killed by {signal.Signals(-code).name}"
        except ValueError:
            return f"killed by signal {-code}"
    return f"exited with status {code}"


def run_with_processes(study: Study, batches: list[list[tuple[int, int, int]]], workers: int,
                       on_done: OnDone) -> None:
    # spawn, not fork: forking a process that has threads (a Dask client, BLAS)
    # can deadlock, and spawn behaves the same on every platform. Spawned
    # children take the environment as it is when they start (a replaced
    # worker too), so the variables stay set until the workers are done; a
    # user's own setting wins.
    ctx = multiprocessing.get_context("spawn")
    added = {k: v for k, v in _SINGLE_THREADED.items() if k not in os.environ}
    os.environ.update(added)
    pool: list[_Worker] = []
    try:
        pool = [_Worker(ctx, study) for _ in range(min(workers, len(batches)))]
        _drive(ctx, study, pool, deque(batches), on_done)
    finally:
        _stop(pool)
        for k in added:
            os.environ.pop(k, None)


def _drive(ctx: Any, study: Study, pool: list[_Worker], queue: deque[list[tuple[int, int, int]]],
           on_done: OnDone) -> None:
    retries: deque[tuple[int, int, int]] = deque()
    failed_starts = 0
    while queue or retries or any(w.keys for w in pool):
        for w in pool:
            if not w.keys and (retries or queue):
                w.retry = bool(retries)
                w.keys = [retries.popleft()] if retries else list(queue.popleft())
                try:
                    w.conn.send(w.keys)
                except OSError:  # died while idle: found dead below
                    pass
        busy = [w for w in pool if w.keys]
        multiprocessing.connection.wait([w.conn for w in busy] + [w.proc.sentinel for w in busy])
        for i, w in enumerate(pool):
            if not w.keys or w.collect(on_done):
                continue
            w.proc.join()
            how = _death(w.proc)
            if not w.keys:
                pass  # it died after its batch's last run: no run is to blame
            elif not w.ready:
                # It died importing, before any run: no run is to blame.
                failed_starts += 1
                if failed_starts >= 2:
                    raise StudyError(f"local worker processes die before their first run ({how}); their "
                                     "output above says why")
                queue.appendleft(w.keys)
            elif w.retry:
                failed_starts = 0
                on_done([error_record(study, RunKey(*w.keys[0]), "crash", "WorkerDied",
                                      f"its worker process died in this run ({how}), and again when the run "
                                      "was retried alone")])
            else:
                failed_starts = 0
                retries.append(w.keys[0])
                if len(w.keys) > 1:
                    queue.appendleft(w.keys[1:])
            w.conn.close()
            pool[i] = _Worker(ctx, study)


def _stop(pool: Sequence[_Worker]) -> None:
    """Ends every worker: an idle one is asked to, a busy one (a study
    stopped mid-run, or a run that hangs) gets SIGTERM, and SIGKILL after
    GRACE_SECONDS. Ctrl-C and SIGTERM are ignored meanwhile: one suffices."""
    with _signals_held():
        for w in pool:
            if w.keys:
                w.proc.terminate()
            else:
                with contextlib.suppress(OSError):
                    w.conn.send(None)
        deadline = time.monotonic() + GRACE_SECONDS
        for w in pool:
            w.proc.join(max(0.0, deadline - time.monotonic()))
        for w in pool:
            if w.proc.is_alive():
                w.proc.kill()
                w.proc.join()
            w.conn.close()


@contextlib.contextmanager
def _signals_held() -> Iterator[None]:
    """SIGINT and SIGTERM ignored while the workers are ended: a second
    Ctrl-C must not interrupt that and leave them running (the first one
    already stops the study)."""
    stops = (signal.SIGINT, signal.SIGTERM)
    previous = [signal.signal(s, signal.SIG_IGN) for s in stops] if _in_main_thread() else []
    try:
        yield
    finally:
        for s, handler in zip(stops, previous):
            signal.signal(s, handler)
