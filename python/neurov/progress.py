"""The one progress bar: tqdm on stderr for runs, studies, plots and files.

Silent when asked (``quiet``, the ``--quiet`` option) and whenever stderr is
not a terminal: a log file or a pipe gets no carriage-return noise.
"""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING, TextIO

if TYPE_CHECKING:
    from tqdm import tqdm

__all__ = ["progress_bar", "shows_progress"]


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
    return tqdm(total=total, desc=description, unit=unit, file=stream,
                disable=not shows_progress(quiet, stream), dynamic_ncols=True)
