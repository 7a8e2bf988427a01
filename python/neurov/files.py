"""Reading the TOML files a user names (scenarios, studies, vehicles): regular
files only, at most :data:`MAX_FILE_BYTES`, UTF-8, and every failure an error
that names the file.

A path to ``/dev/zero`` or a FIFO would otherwise be read without bound (or
block in ``open``), a directory would give a bare ``IsADirectoryError``, and a
decoder error would not say which file it was in.
"""
from __future__ import annotations

import os
import stat
import sys
from pathlib import Path
from typing import Any

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on Python 3.10 only
    import tomli as tomllib

#: The largest file read, in bytes (4 MiB). The shipped files are a few kB; a
#: scenario of 10^4 waypoints of six numbers is about 0.6 MB.
MAX_FILE_BYTES = 4 * 1024 * 1024

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


def read_text(path: str | Path, error: type[Exception] = ValueError,
              limit: int = MAX_FILE_BYTES) -> str:
    """The contents of the regular file `path` as UTF-8 text.

    Raises ``FileNotFoundError`` for a missing file (callers word that one
    themselves) and `error` (``"<path>: ..."``) for anything else that is not
    a readable UTF-8 file of at most `limit` bytes.
    """
    path = Path(path)
    try:
        # O_NONBLOCK: a FIFO swapped in after the check must not block open().
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except FileNotFoundError:
        raise
    except IsADirectoryError:
        raise error(f"{path}: is a directory, not a regular file") from None
    except OSError as e:
        raise error(f"{path}: cannot open: {e.strerror}") from None
    mode = os.fstat(fd).st_mode
    if not stat.S_ISREG(mode):
        os.close(fd)
        raise error(f"{path}: is {_kind(mode)}, not a regular file")
    with os.fdopen(fd, "rb") as f:
        try:
            data = f.read(limit + 1)
        except OSError as e:
            raise error(f"{path}: cannot read: {e.strerror}") from None
    if len(data) > limit:
        raise error(f"{path}: larger than {limit} bytes (the most neurov reads from one file)")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        raise error(f"{path}: not UTF-8 text (byte 0x{data[e.start]:02x} at offset "
                    f"{e.start}); TOML files are UTF-8") from None


def read_toml(path: str | Path, error: type[Exception], kind: str) -> dict[str, Any]:
    """The table of the TOML file `path`, read as :func:`read_text` reads;
    `error` (``"<path>: no such <kind> file"``, ``"<path>: not valid TOML:
    ..."``) for a missing file or bad TOML."""
    try:
        return tomllib.loads(read_text(path, error))
    except FileNotFoundError:
        raise error(f"{path}: no such {kind} file") from None
    except tomllib.TOMLDecodeError as e:
        raise error(f"{path}: not valid TOML: {e}") from None
