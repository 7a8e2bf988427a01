"""The output folder of ``neurov run --out DIR`` and ``neurov paper --out DIR``:
a folder holds one run.

The files are written into a staging folder beside DIR (``.DIR.running-*``;
inside DIR when DIR's parent cannot be written) and put in place only when
the run has finished, so an old run in DIR stays whole until the new one is
complete:

- DIR missing: the staging folder is renamed to DIR;
- DIR there (an old run, ``--out .``, a folder with the user's notes): the
  new run's files are moved in one by one, and the old run's files that the
  new run did not write (its figures, say) are removed, so that the run's
  files in DIR are of one run; any other file is never touched, and DIR
  itself stays the folder it was (a shell inside it stays there).

A run that stops (Ctrl-C, an error, a full disk) leaves DIR as it was and
keeps what it wrote in ``DIR.partial`` (beside DIR, or in DIR when staged
there), its metrics.json saying ``"partial": true`` and why.
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import secrets
import shutil
import sys
from collections.abc import Iterator
from pathlib import Path
import math
from typing import Any

from neurov.files import OutputWriteError, writing

__all__ = ["OutputWriteError", "RunFolder", "check_output_dir", "finite_or_none", "kept_files", "stop_reason",
           "stopped_run", "stopping", "write_metrics", "writing"]


def check_output_dir(out_dir: str | Path, *, create: bool = True) -> Path:
    """The folder `out_dir` names, checked before anything is computed: not
    an existing file, not a symbolic link loop or a link to nothing, and
    creatable (its parents are created, and with `create` the folder).
    Raises OSError naming the folder."""
    out = Path(out_dir)
    try:
        os.stat(out)
    except FileNotFoundError:
        if out.is_symlink():
            raise FileNotFoundError(f"output folder {str(out)!r} is a symbolic link to "
                                    f"{os.readlink(out)!r}, which does not exist") from None
    except OSError as e:
        if e.errno == errno.ELOOP:
            raise OSError(f"output folder {str(out)!r} is a symbolic link loop "
                          "(following its links never reaches a folder)") from None
        # anything else (a file where a parent folder should be) is named below
    if out.exists() and not out.is_dir():
        raise NotADirectoryError(f"output folder {str(out)!r} is an existing file, not a folder")
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        if not out.exists():
            out.mkdir()
            if not create:
                out.rmdir()  # only a check: RunFolder makes DIR when the run has finished
    except OSError as e:
        raise OSError(f"output folder {str(out)!r} cannot be created: {e.strerror or e}") from e
    if out.exists() and not os.access(out, os.W_OK | os.X_OK):
        raise PermissionError(f"output folder {str(out)!r} is not writable")
    return out


def stop_reason(exc: BaseException) -> str:
    """Why a run stopped, in words for metrics.json and messages."""
    if isinstance(exc, KeyboardInterrupt):
        return "interrupted (Ctrl-C)"
    return f"{type(exc).__name__}: {exc}"


def finite_or_none(value: Any) -> Any:
    """JSON has no inf or NaN (a diverged run has inf errors): write null."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: finite_or_none(v) for k, v in value.items()}
    if isinstance(value, list):
        return [finite_or_none(v) for v in value]
    return value


def write_metrics(metrics: dict[str, Any], out: Path) -> Path:
    """metrics.json in `out` (non-finite numbers as null)."""
    path = out / "metrics.json"
    with writing(path):
        path.write_text(json.dumps(finite_or_none(metrics), indent=2) + "\n", encoding="utf-8")
    return path


class RunFolder:
    """Where a run's files go while it runs (:attr:`path`) and how they
    reach `out_dir` (:meth:`commit`) or are kept when it stops
    (:meth:`keep_partial`); `names` are the file names a run writes (see the
    module)."""

    def __init__(self, out_dir: str | Path, names: tuple[str, ...]) -> None:
        self.out = check_output_dir(out_dir, create=False)
        if self.out.is_symlink() or self.out.name in ("", ".."):
            # A link to a folder: the folder is DIR (the link stays); "." and "..": the folder they are.
            self.out = self.out.resolve()
        self.names = names
        parent = self.out.parent
        beside = os.access(parent, os.W_OK | os.X_OK)
        where = parent if beside or not self.out.exists() else self.out
        try:
            self.path = _new_folder(where, f".{self.out.name}.running-")
        except OSError as e:
            raise OSError(f"output folder {str(self.out)!r} cannot be written: {e.strerror or e}") from e
        self._beside = where == parent

    def commit(self) -> Path:
        """Puts the finished run in DIR (see the module); returns DIR."""
        if self._beside and not self.out.exists():
            os.rename(self.path, self.out)
            return self.out
        self.out.mkdir(exist_ok=True)
        written = {p.name for p in self.path.iterdir()}
        for name in written:
            os.replace(self.path / name, self.out / name)
        for name in set(self.names) - written:
            (self.out / name).unlink(missing_ok=True)  # the old run's, not of this one
        self.path.rmdir()
        return self.out

    @property
    def partial_path(self) -> Path:
        """Where :meth:`keep_partial` keeps a stopped run."""
        return self.path.parent / f"{self.out.name}.partial"

    def keep_partial(self, reason: str) -> Path | None:
        """Keeps what a stopped run wrote in :attr:`partial_path` (replacing
        an older partial run there), its metrics.json (the one written, or a
        new one) marked ``"partial": true`` with `reason`; returns that
        folder, or None (and removes the staging folder) if nothing was
        written. DIR is not touched."""
        if not any(self.path.iterdir()):
            self.path.rmdir()
            return None
        try:
            path = self.path / "metrics.json"
            metrics: Any = None
            if path.is_file():
                try:
                    metrics = json.loads(path.read_text(encoding="utf-8"))
                except (OSError, ValueError):
                    metrics = None
            if not isinstance(metrics, dict):
                metrics = {}
            metrics = {**metrics, "partial": True, "partial_reason": reason}
            path.write_text(json.dumps(metrics, indent=2) + "\n", encoding="utf-8")
        except OSError:
            pass  # a full disk: the rows written are kept, the mark could not be
        target = self.partial_path
        if target.is_dir() and _is_partial(target):
            shutil.rmtree(target, ignore_errors=True)
        try:
            os.rename(self.path, target)
        except OSError:
            return self.path  # an older folder of that name that is not ours: keep the staging name
        return target


def _new_folder(parent: Path, prefix: str) -> Path:
    """A new folder `prefix` + random letters in `parent`, with the
    permissions a plain mkdir gives (tempfile.mkdtemp's are owner-only, and
    the folder becomes DIR)."""
    for _ in range(100):
        path = parent / f"{prefix}{secrets.token_hex(4)}"
        try:
            path.mkdir()
        except FileExistsError:
            continue
        return path
    raise FileExistsError(errno.EEXIST, f"no free name {prefix}* in {parent}")


def _is_partial(folder: Path) -> bool:
    """Whether `folder` is a partial run kept by :meth:`RunFolder.keep_partial`."""
    try:
        return json.loads((folder / "metrics.json").read_text(encoding="utf-8")).get("partial") is True
    except (OSError, ValueError, AttributeError):
        return False


def stopped_run(folder: RunFolder, exc: BaseException) -> BaseException:
    """Keeps what a stopped run wrote (see :mod:`neurov.running.folder`) and
    returns the exception to raise: for Ctrl-C and OSError (a full disk) one
    whose message says where the run is kept and that DIR is unchanged;
    any other exception as it was, that news printed to stderr."""
    kept = folder.keep_partial(stop_reason(exc))
    out = f"{str(folder.out)!r} {'is unchanged' if folder.out.exists() else 'was not created'}"
    if kept is None:
        news = f"nothing was written; {out}"
    else:
        news = (f"{out}; the run so far is kept in {str(kept)!r}"
                f" ({kept_files(kept)}; its metrics.json says \"partial\": true)")
    if isinstance(exc, KeyboardInterrupt):
        return KeyboardInterrupt(f"interrupted: {news}")
    if isinstance(exc, OSError):
        error = OSError(f"{exc}; {news}")
        error.errno = exc.errno
        return error
    print(f"neurov: the run stopped ({stop_reason(exc)}): {news}", file=sys.stderr)
    return exc


def kept_files(folder: Path) -> str:
    """The files in `folder`, with how far result.csv got if metrics.json says."""
    names = sorted(p.name for p in folder.iterdir())
    try:
        upto = json.loads((folder / "metrics.json").read_text(encoding="utf-8")).get("result_csv_to_s")
    except (OSError, ValueError, AttributeError):
        upto = None
    if upto is not None and "result.csv" in names:
        names[names.index("result.csv")] = f"result.csv (rows to t = {upto:g} s)"
    return ", ".join(names) or "no files"


@contextlib.contextmanager
def stopping(folder: RunFolder | None) -> Iterator[None]:
    """Around writing a run into `folder` (None: a run without files): a
    run that stops keeps what it wrote and raises what :func:`stopped_run`
    makes of its exception."""
    try:
        yield
    except BaseException as exc:
        stopped = exc if folder is None else stopped_run(folder, exc)
        if stopped is exc:
            raise
        raise stopped from exc
