"""A tuning's storage, ``DIR/tuning.db``: Optuna's RDB storage in an SQLite
file, opened with its failures named (a file that is not a tuning's
database, a folder, a read-only file or folder, a full disk: each an error
naming the user's path and what was expected, never SQLAlchemy's traceback
or a bare errno on an internal file), and the trials whose process died.

A trial records the process running it (:func:`claim`). A process that
dies without telling its trial's end (SIGKILL, the OOM killer, a power
cut) leaves the trial "running"; :func:`fail_dead_trials` marks it failed
at once when its process is known dead (the same machine, its process gone),
else after Optuna's heartbeat has been silent for :data:`GRACE_SECONDS`,
so that its place in the budget is run again."""

from __future__ import annotations

import contextlib
import errno
import os
import shutil
import socket
import sqlite3
import threading
import warnings
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from neurov.running.folder import check_output_dir

__all__ = ["GRACE_SECONDS", "HEARTBEAT_SECONDS", "STORAGE_NAME", "StorageError", "claim", "fail_dead_trials",
           "open_storage", "storage_errors"]

STORAGE_NAME = "tuning.db"
# A process that dies mid-trial leaves its trial "running"; without a
# heartbeat for this long, the next process marks it failed (and redoes it).
HEARTBEAT_SECONDS = 10
GRACE_SECONDS = 60
_SQLITE_HEADER = b"SQLite format 3\x00"


class StorageError(OSError):
    """The storage (or the folder holding it) cannot be read or written: the
    message names the path and why; ``errno`` is ENOSPC for a full disk."""

    def __init__(self, message: str, code: int | None = None) -> None:
        super().__init__(code or 0, message)

    def __str__(self) -> str:
        return str(self.strerror)


#: Below this many free bytes, an SQLite I/O error on the storage is put down
#: to a full disk (SQLite says "disk I/O error" when it cannot grow its log).
FULL_BELOW_BYTES = 1 << 20


def _free_bytes(folder: Path) -> int | None:
    try:
        return shutil.disk_usage(folder).free
    except OSError:
        return None


def _full(folder: Path) -> StorageError:
    free = _free_bytes(folder)
    left = "" if free is None else f", {free} bytes free"
    return StorageError(f"the disk holding {folder} is full (no space left on device{left}); the trials "
                        f"finished so far are kept in {folder / STORAGE_NAME}: free some space and run the "
                        "same command again to resume", errno.ENOSPC)


def _explain(path: Path, e: BaseException) -> StorageError:
    """An SQLite or OS error on the storage `path`, in words naming it."""
    text = str(getattr(e, "orig", None) or e)
    low = text.lower()
    code = getattr(e, "errno", None)
    free = _free_bytes(path.parent)
    if code == errno.ENOSPC or "disk is full" in low or "no space" in low or (
            "i/o error" in low and free is not None and free < FULL_BELOW_BYTES):
        return _full(path.parent)
    if code in (errno.EACCES, errno.EPERM, errno.EROFS) or "readonly" in low or "read-only" in low:
        return StorageError(f"{path}: the tuning's storage cannot be written (a read-only file or folder); "
                            "make it writable, or use another --out")
    if "not a database" in low or "malformed" in low or "no such table" in low or "corrupt" in low:
        return StorageError(f"{path}: not a tuning's storage (an SQLite database written by neurov tune): "
                            f"{text}; move it away to start again, or use another --out")
    return StorageError(f"{path}: the tuning's storage cannot be used: {text}")


def _storage_cause(e: BaseException) -> BaseException | None:
    """The SQLite or SQLAlchemy error behind `e`, if any: Optuna hands a
    failed commit on as its own error, or as an ``AssertionError`` of its
    bookkeeping raised while handling it."""
    from sqlalchemy.exc import SQLAlchemyError

    seen: set[int] = set()
    cause: BaseException | None = e
    while cause is not None and id(cause) not in seen:
        if isinstance(cause, (SQLAlchemyError, sqlite3.Error)):
            return cause
        seen.add(id(cause))
        cause = cause.__cause__ or cause.__context__
    return None


@contextlib.contextmanager
def storage_errors(out: Path) -> Iterator[None]:
    """SQLite's and SQLAlchemy's errors on ``out/tuning.db`` inside (however
    Optuna hands them on), and a full disk or a read-only folder under any
    file the tuning writes in `out`, raised as :class:`StorageError` naming
    the storage or the folder."""
    try:
        yield
    except StorageError:
        raise
    except OSError as e:
        if e.errno == errno.ENOSPC:
            raise _full(out) from None
        if e.errno in (errno.EROFS, errno.EACCES, errno.EPERM):
            raise StorageError(f"output folder {str(out)!r} cannot be written ({e.strerror}"
                               f"{': ' + Path(e.filename).name if e.filename else ''})", e.errno) from None
        cause = _storage_cause(e)
        if cause is None:
            raise
        raise _explain(out / STORAGE_NAME, cause) from None
    except Exception as e:
        cause = _storage_cause(e)
        if cause is None:
            raise
        raise _explain(out / STORAGE_NAME, cause) from None


def _check_file(path: Path) -> None:
    """A storage that is not a file, or a file that is not SQLite, named before SQLite opens it."""
    if not path.exists() and not path.is_symlink():
        return
    if path.is_dir():
        raise StorageError(f"{path}: is a folder; the tuning's storage must be a file (an SQLite database "
                           "written by neurov tune): move it away, or use another --out")
    if not path.is_file():
        raise StorageError(f"{path}: is not a regular file; the tuning's storage must be an SQLite database "
                           "written by neurov tune")
    with path.open("rb") as f:
        head = f.read(100)
    if not head:
        return  # an empty file: SQLite makes it a database
    what = f"{path}: not a tuning's storage (an SQLite database written by neurov tune)"
    if not head.startswith(_SQLITE_HEADER):
        raise StorageError(f"{what}: its first bytes are not SQLite's; move it away to start again, or use "
                           "another --out")
    # SQLite's header: the page size at byte 16 (1 for 65536), the pages at 28,
    # valid when the change counter (24) equals the version-valid-for number (92).
    size = path.stat().st_size
    page = int.from_bytes(head[16:18], "big") if len(head) >= 18 else 0
    page = 65536 if page == 1 else page
    pages = int.from_bytes(head[28:32], "big") if len(head) >= 32 else 0
    valid = len(head) == 100 and head[24:28] == head[92:96]
    if len(head) < 100 or (valid and size < page * pages):
        raise StorageError(f"{what}: truncated ({size} bytes of the {page * pages} its header declares); "
                           "move it away to start again, or use another --out")


def open_storage(out: Path) -> Any:
    """Optuna's RDB storage in the SQLite file ``out/tuning.db``; errors
    name the file or the folder (:class:`StorageError`)."""
    import optuna

    # Optuna logs every trial; a tuning reports by its progress bar and its files.
    optuna.logging.set_verbosity(optuna.logging.ERROR)
    try:
        check_output_dir(out)
    except FileExistsError:
        raise NotADirectoryError(f"output folder {str(out)!r} is an existing file, not a folder") from None
    path = (out / STORAGE_NAME).resolve()
    _check_file(path)

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
    with storage_errors(out), _creating(out), warnings.catch_warnings():
        warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
        storage = optuna.storages.RDBStorage(f"sqlite:///{path}", engine_kwargs={"creator": connect},
                                             heartbeat_interval=HEARTBEAT_SECONDS, grace_period=GRACE_SECONDS)
        # Read every table once: a truncated file fails here, not in the first trial.
        storage.get_all_studies()
        return storage


@contextlib.contextmanager
def _creating(out: Path) -> Iterator[None]:
    """Held while a process creates or opens the storage's tables: two
    processes starting a new tuning at once would both create them (one
    then fails on a unique key of Optuna's schema). Optuna itself copes
    with two processes creating one study."""
    lock_path = out / f"{STORAGE_NAME}.lock"
    try:
        lock = open(lock_path, "a+b")  # noqa: SIM115 - closed below
    except OSError as e:
        if e.errno == errno.ENOSPC:
            raise _full(out) from None
        raise StorageError(f"output folder {str(out)!r} cannot be written ({e.strerror or e}): the tuning keeps "
                           f"its storage and a lock file ({lock_path.name}) there; use a writable --out") from None
    with lock:
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


# --- trials whose process died ---------------------------------------------------------------


def _machine() -> str:
    """This machine: its name and, on Linux, its boot (a pid is only meaningful within one boot)."""
    try:
        boot = Path("/proc/sys/kernel/random/boot_id").read_text().strip()
    except OSError:
        boot = ""
    return f"{socket.gethostname()}/{boot}"


def _started(pid: int) -> int | None:
    """When process `pid` started (clock ticks since boot, Linux), to tell it from a later one with its pid."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    return int(stat[stat.rindex(")") + 2:].split()[19])


def claim(trial: Any) -> None:
    """Records in `trial` the process (and the thread) running it."""
    trial.set_user_attr("process", {"machine": _machine(), "pid": os.getpid(), "started": _started(os.getpid()),
                                    "thread": threading.get_ident()})


def _dead(owner: Any) -> bool:
    """Whether the process of a trial's ``process`` record is known dead."""
    if not isinstance(owner, dict) or owner.get("machine") != _machine():
        return False  # another machine's: its heartbeat tells
    pid = int(owner.get("pid", 0))
    if pid <= 0:
        return False
    if pid == os.getpid() and owner.get("started") == _started(pid):
        # This process's: an earlier call that failed (a full disk), unless
        # another thread runs it now (this one is between trials).
        thread = owner.get("thread")
        return thread == threading.get_ident() or thread not in {t.ident for t in threading.enumerate()}
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    except PermissionError:  # someone else's process by that pid: not ours
        return True
    started = owner.get("started")
    return started is not None and _started(pid) not in (None, started)


def fail_dead_trials(study: Any, storage: Any) -> int:
    """Marks failed the running trials of `study` (in `storage`) whose
    process is dead (known dead on this machine, or silent for Optuna's
    grace period); returns how many this call failed."""
    import optuna

    S = optuna.trial.TrialState
    failed = 0
    study_id = storage.get_study_id_from_name(study.study_name)
    for t in study.get_trials(deepcopy=False, states=(S.RUNNING,)):
        if not _dead(t.user_attrs.get("process")):
            continue
        trial_id = storage.get_trial_id_from_study_id_trial_number(study_id, t.number)
        with contextlib.suppress(optuna.exceptions.UpdateFinishedTrialError):  # another process was first
            storage.set_trial_user_attr(trial_id, "reason", "its process died")
            failed += bool(storage.set_trial_state_values(trial_id, state=S.FAIL))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
        optuna.storages.fail_stale_trials(study)
    return failed
