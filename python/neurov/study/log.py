"""The run log, ``runs.jsonl``: one JSON record per finished run, appended
as batches finish, so an interrupted study resumes where it stopped."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

__all__ = ["LOG_NAME", "Record", "read_log", "repair_tail"]

LOG_NAME = "runs.jsonl"

Record = dict[str, Any]
"""One run: ``key`` [scenario, controller, sample], ``row``, ``series``, timings."""


def read_log(path: Path) -> dict[tuple[str, str, int], Record]:
    """Records already made. A line cut short by an interrupted write is
    skipped (that run is simply redone)."""
    done: dict[tuple[str, str, int], Record] = {}
    if not path.exists():
        return done
    with path.open() as f:
        for line in f:
            try:
                rec = json.loads(line)
                key = (str(rec["key"][0]), str(rec["key"][1]), int(rec["key"][2]))
                rec["row"], rec["series"]  # noqa: B018 - both must be there
            except (json.JSONDecodeError, KeyError, IndexError, TypeError, ValueError):
                continue
            done[key] = rec
    return done


def repair_tail(path: Path) -> int:
    """Cuts a last line that a crash left without its newline, so the next
    record starts on a line of its own instead of being glued to the broken
    one (and lost with it). Returns the number of bytes removed."""
    if not path.exists():
        return 0
    with path.open("rb+") as f:
        size = f.seek(0, os.SEEK_END)
        if size == 0:
            return 0
        f.seek(size - 1)
        if f.read(1) == b"\n":
            return 0
        # Back to the last complete line, in blocks: the log can be large.
        end = size
        block = 1 << 16
        while end > 0:
            start = max(0, end - block)
            f.seek(start)
            chunk = f.read(end - start)
            cut = chunk.rfind(b"\n")
            if cut >= 0:
                keep = start + cut + 1
                break
            end = start
        else:
            keep = 0
        f.truncate(keep)
        return size - keep
