"""The one progress bar: tqdm on stderr for runs, studies, plots and files.

A sign of life on every step longer than about two seconds: a bar on a
terminal; when stderr is not a terminal (a log file, a pipe), a bar would
be carriage-return noise, so each step says what it does in one line on
stdout instead, flushed at once so that it shows in the log as it happens.
Both are silent when asked (``quiet``, the ``--quiet`` option).
"""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING, TextIO

if TYPE_CHECKING:
    from tqdm import tqdm

__all__ = ["progress_bar", "shows_progress", "stage"]


def shows_progress(quiet: bool = False, stream: TextIO | None = None) -> bool:
    """True when a bar on `stream` (stderr by default) would be seen."""
    stream = sys.stderr if stream is None else stream
    isatty = getattr(stream, "isatty", None)
    return not quiet and callable(isatty) and bool(isatty())


def progress_bar(total: int, description: str, unit: str = "run", quiet: bool = False,
                 stream: TextIO | None = None) -> tqdm:
    """A bar of `total` steps labelled `description`; disabled (every call a
    no-op) unless :func:`shows_progress`."""
    # Deferred: tqdm is some 4.6 MB resident, and `import neurov` draws no bar.
    from tqdm import tqdm

    stream = sys.stderr if stream is None else stream
    shown = shows_progress(quiet, stream)
    if not shown and total > 0:
        stage(f"{description}: {total} {unit}{'' if total == 1 else 's'}", quiet)
    return tqdm(total=total, desc=description, unit=unit, file=stream, disable=not shown, dynamic_ncols=True)


def stage(text: str, quiet: bool = False) -> None:
    """One line on stdout saying what a step without a bar does (or, from
    :func:`progress_bar`, what a bar would show), flushed so that it shows in
    a piped log as it happens; nothing with `quiet`."""
    if not quiet:
        print(text, flush=True)
