"""Reading the files a user names (scenarios, studies, vehicles, weights):
regular files only, of bounded size, TOML in UTF-8 (a byte-order mark
skipped) and nested at most :data:`MAX_TOML_DEPTH` deep, and every failure an
error that names the file. The bounds on what a file may hold are here.
Writing the files a user names: the path checked before any work
(:func:`check_output_file`), and a failed write (a full disk, a read-only
file system) an :class:`OutputWriteError` naming the user's path, not an
internal temporary file (:func:`writing`).

A path to ``/dev/zero`` or a FIFO would otherwise be read without bound (or
block in ``open``), a directory would give a bare ``IsADirectoryError``, a
decoder error would not say which file it was in, and a TOML file nested 500
deep would end the parser in a ``RecursionError``.
"""
from __future__ import annotations

import contextlib
import errno
import os
import stat
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on Python 3.10 only
    import tomli as tomllib

#: The largest TOML file read, in bytes (4 MiB). The shipped files are a few
#: kB; a scenario of 10^4 waypoints of six numbers is about 0.6 MB.
# The shipped data folders (scenarios/, studies/, tunings/, vehicles/) are here.
PACKAGE_DIR = Path(__file__).resolve().parent

MAX_FILE_BYTES = 4 * 1024 * 1024

#: The deepest nesting of tables and arrays a TOML file may have. The shipped
#: files nest at most 5 deep (a study's ``[controllers.smc.nerov] kd = [...]``); 32
#: leaves room for any hand-written file and keeps the parser and every
#: recursive walk of the table far from Python's recursion limit.
MAX_TOML_DEPTH = 32

#: The largest weights file read, in bytes (24 MiB), and the most bytes its
#: arrays may declare: a network of ``neurov.MAX_CENTRES`` (65536) centres
#: written by ``save_weights`` is 16.3 MB (248 bytes a centre).
MAX_WEIGHTS_FILE_BYTES = 24 * 1024 * 1024

_BOM = "\ufeff"

_KINDS = (
    (stat.S_ISDIR, "a directory"),
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
)


def _kind(mode: int) -> str:
    for test, name in _KINDS:
        if test(mode):
            return name
    return "not a regular file"


def read_bytes(path: str | os.PathLike[str], error: type[Exception] = ValueError,
               limit: int = MAX_FILE_BYTES, name: str | None = None) -> bytes:
    """The contents of the regular file `path`, at most `limit` bytes.

    Raises ``FileNotFoundError`` for a missing file (callers word that one
    themselves) and `error` (``"<name>: ..."``, `name` the path by default)
    for anything else that is not a readable regular file of at most `limit`
    bytes.
    """
    path = Path(path)
    name = str(path) if name is None else name
    try:
        # O_NONBLOCK: a FIFO swapped in after the check must not block open().
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except FileNotFoundError:
        raise
    except IsADirectoryError:
        raise error(f"{name}: is a directory, not a regular file") from None
    except OSError as e:
        raise error(f"{name}: cannot open: {e.strerror}") from None
    info = os.fstat(fd)
    if not stat.S_ISREG(info.st_mode):
        os.close(fd)
        raise error(f"{name}: is {_kind(info.st_mode)}, not a regular file")
    too_large = error(f"{name}: larger than {limit} bytes (the most neurov reads from one file)")
    if info.st_size > limit:
        os.close(fd)
        raise too_large
    with os.fdopen(fd, "rb") as f:
        try:
            # read(n) allocates n bytes first: ask for the file's size (and
            # the rest up to the limit if it grew since fstat).
            data = f.read(info.st_size + 1)
            if len(data) > info.st_size:
                data += f.read(limit + 1 - len(data))
        except OSError as e:
            raise error(f"{name}: cannot read: {e.strerror}") from None
    if len(data) > limit:
        raise too_large
    return data


def read_text(path: str | Path, error: type[Exception] = ValueError,
              limit: int = MAX_FILE_BYTES) -> str:
    """The contents of the regular file `path` as UTF-8 text, a leading
    byte-order mark (which editors on Windows write) removed; errors as
    :func:`read_bytes`'s, and `error` for text that is not UTF-8."""
    data = read_bytes(path, error, limit)
    try:
        return data.decode("utf-8").removeprefix(_BOM)
    except UnicodeDecodeError as e:
        if data[:2] in (b"\xff\xfe", b"\xfe\xff"):
            raise error(f"{path}: UTF-16 text (it starts with a UTF-16 byte-order mark); "
                        "TOML files are UTF-8: save it as UTF-8") from None
        raise error(f"{path}: not UTF-8 text (byte 0x{data[e.start]:02x} at offset "
                    f"{e.start}); TOML files are UTF-8") from None


def _depth(table: dict[str, Any]) -> int:
    """How deep tables and arrays nest in `table` (a table of numbers: 1),
    without recursion."""
    deepest = 0
    stack: list[tuple[Any, int]] = [(table, 1)]
    while stack:
        value, depth = stack.pop()
        deepest = max(deepest, depth)
        children = value.values() if isinstance(value, dict) else value
        stack.extend((c, depth + 1) for c in children if isinstance(c, (dict, list)))
    return deepest


def read_toml(path: str | Path, error: type[Exception], kind: str) -> dict[str, Any]:
    """The table of the TOML file `path`, read as :func:`read_text` reads;
    `error` (``"<path>: no such <kind> file"``, ``"<path>: not valid TOML:
    ..."``, ``"<path>: nested more than 32 levels deep"``) for a missing
    file, bad TOML or a nesting deeper than :data:`MAX_TOML_DEPTH`."""
    deep = error(f"{path}: tables and arrays nested more than {MAX_TOML_DEPTH} levels deep "
                 "(the most neurov reads)")
    try:
        table = tomllib.loads(read_text(path, error))
    except FileNotFoundError:
        raise error(f"{path}: no such {kind} file") from None
    except tomllib.TOMLDecodeError as e:
        raise error(f"{path}: not valid TOML: {e}") from None
    except RecursionError:
        # The parser recurses once per nested array or inline table.
        raise deep from None
    if _depth(table) > MAX_TOML_DEPTH:
        raise deep
    return table


def shipped_or_path(name_or_path: str | os.PathLike[str], folder: Path, kind: str,
                    error: type[Exception]) -> Path:
    """The file to read for a path or the name of a file shipped in `folder`
    (``paper_fig3``, ``robustness``): the one resolver of scenarios, studies
    and tunings. A ``.toml`` path, a path through a folder (``./x``,
    ``/dev/zero``) or anything else that exists but a folder is taken as
    given (its reader names what is wrong with it); another name must be a
    shipped file's (a folder of that name, say an earlier run's output, does
    not hide it), else `error` listing the shipped `kind` files."""
    path = Path(name_or_path)
    if path.suffix == ".toml" or len(path.parts) > 1 or (path.exists() and not path.is_dir()):
        return path
    shipped = folder / f"{path.name}.toml"
    if shipped.is_file():
        return shipped
    names = sorted(q.stem for q in folder.glob("*.toml"))
    raise error(f"{name_or_path}: no such {kind} file, and no shipped {kind} of that name "
                f"(shipped: {', '.join(names) or 'none'})")



#: What a write's errno means for the user, said after the system's words.
_WRITE_HINTS = {
    errno.ENOSPC: "the disk is full",
    errno.EDQUOT: "the disk quota is used up",
    errno.EROFS: "the folder is on a read-only file system",
    errno.EACCES: "the folder is not writable by this user",
    errno.EPERM: "the folder is not writable by this user",
}


class OutputWriteError(OSError):
    """Writing a file the user asked for failed (a full disk, say): the
    message names the file as the user knows it (`shown`, default the
    file's name); ``errno`` is the cause's."""

    def __init__(self, path: Path, cause: OSError, shown: str | None = None) -> None:
        why = cause.strerror or str(cause)
        hint = _WRITE_HINTS.get(cause.errno or 0)
        super().__init__(cause.errno, f"cannot write {path.name if shown is None else shown}: {why}"
                                      + (f" ({hint})" if hint else ""))
        self.path = path

    def __str__(self) -> str:
        return str(self.strerror)


@contextlib.contextmanager
def writing(path: str | os.PathLike[str], shown: str | None = None) -> Iterator[None]:
    """An OSError raised inside becomes an :class:`OutputWriteError` naming
    `path` (as `shown`, if given: ``"'fit.toml' (--out)"``)."""
    try:
        yield
    except OutputWriteError:
        raise
    except OSError as e:
        raise OutputWriteError(Path(path), e, shown) from e


def check_output_file(path: str | os.PathLike[str], option: str) -> Path:
    """The file `path` that the option `option` (``"--out"``) asks to be
    written, checked before any work: not a folder, in a folder that exists,
    is a folder and can be written. Raises OSError naming the option and the
    path."""
    out = Path(path)
    folder = out.parent if str(out.parent) else Path(".")
    if out.is_dir():
        raise IsADirectoryError(f"{option} {str(out)!r} is an existing folder; {option} names a file to write")
    if not folder.exists():
        raise FileNotFoundError(f"{option} {str(out)!r}: the folder {str(folder)!r} does not exist")
    if not folder.is_dir():
        raise NotADirectoryError(f"{option} {str(out)!r}: {str(folder)!r} is a file, not a folder")
    if not os.access(folder, os.W_OK | os.X_OK):
        ro = os.statvfs(folder).f_flag & os.ST_RDONLY
        raise PermissionError(f"{option} {str(out)!r}: the folder {str(folder)!r} cannot be written ("
                              + ("a read-only file system)" if ro else "no write permission)"))
    return out
