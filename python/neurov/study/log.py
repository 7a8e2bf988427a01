"""The run log, ``runs.jsonl``: one JSON record per finished run, appended
as batches finish, so an interrupted study resumes where it stopped. Each
record carries the fingerprint of the study that made it (``study``), so the
log, not an optional file beside it, says whose runs it holds."""

from __future__ import annotations

import json
import math
import os
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from neurov.results.metrics import metric_names

__all__ = ["LOG_NAME", "Record", "StudyLogWarning", "read_log", "repair_tail"]

LOG_NAME = "runs.jsonl"

Record = dict[str, Any]
"""One run: ``key`` [scenario, controller, sample], ``row``, ``series``
(None for a run without a result), ``error`` (for those: kind, type,
message), ``study`` (the study's fingerprint), timings."""

# Bad lines named in the warning; the count says how many more.
_NAMED = 5


class StudyLogWarning(UserWarning):
    """Records of a study's log that are not runs: skipped, and so redone."""


def read_log(path: Path) -> dict[tuple[str, str, int], Record]:
    """Records already made. A record that is not a run (a line that is not
    UTF-8 or not JSON, a row without its metrics, a metric that is not a
    number, ...) is skipped with a :class:`StudyLogWarning` naming the file
    and its line: that run is redone."""
    done: dict[tuple[str, str, int], Record] = {}
    if not path.exists():
        return done
    bad: list[str] = []
    with path.open("rb") as f:
        for number, raw in enumerate(f, start=1):
            if not raw.strip():
                continue
            try:
                rec = json.loads(raw.decode("utf-8"))
                key = _check(rec)
            except UnicodeDecodeError as e:
                bad.append(f"line {number}: not UTF-8 text (byte 0x{raw[e.start]:02x} at column {e.start + 1})")
                continue
            except json.JSONDecodeError as e:
                bad.append(f"line {number}: not JSON ({e.msg} at column {e.colno})")
                continue
            except ValueError as e:
                bad.append(f"line {number}: {e}")
                continue
            done[key] = rec
    if bad:
        more = f"; and {len(bad) - _NAMED} more" if len(bad) > _NAMED else ""
        warnings.warn(f"{path}: skipped {len(bad)} record(s) that are not runs (those runs are redone): "
                      + "; ".join(bad[:_NAMED]) + more, StudyLogWarning, stacklevel=2)
    return done


def _number(x: Any) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def _check(rec: Any) -> tuple[str, str, int]:
    """The run's key; ValueError saying what is wrong with the record."""
    if not isinstance(rec, Mapping):
        raise ValueError(f"a JSON {type(rec).__name__}, not a record")
    key = rec.get("key")
    if not (isinstance(key, list) and len(key) == 3 and isinstance(key[0], str) and isinstance(key[1], str)
            and isinstance(key[2], int) and not isinstance(key[2], bool)):
        raise ValueError("no key [scenario, controller, sample]")
    row = rec.get("row")
    if not isinstance(row, Mapping) or not row:
        raise ValueError("no row" if row is None else "an empty row" if isinstance(row, Mapping) else
                         f"a row that is a {type(row).__name__}")
    if [row.get("scenario"), row.get("controller"), row.get("sample")] != key or not isinstance(row.get("vehicle"), str):
        raise ValueError("a row whose scenario, vehicle, controller or sample does not match its key")
    for name in metric_names():
        if name not in row:
            raise ValueError(f"a row without the metric {name!r}")
    for name, v in row.items():
        if name not in ("scenario", "vehicle", "controller") and not _number(v):
            raise ValueError(f"{name!r} is {v!r}, not a number")
    error = rec.get("error")
    if error is not None:
        if not (isinstance(error, Mapping) and error.get("kind") in ("error", "crash")
                and isinstance(error.get("type"), str) and isinstance(error.get("message"), str)):
            raise ValueError("an error that is not {kind: error|crash, type, message}")
    series = rec.get("series")
    if series is None and error is None:
        raise ValueError("no series")
    if series is not None:
        if not (isinstance(series, Mapping) and _number(series.get("t0")) and _number(series.get("dt"))
                and math.isfinite(series["dt"])):
            raise ValueError("a series without its time grid (t0, dt)")
        for name in ("position_error", "yaw_error"):
            values = series.get(name)
            if not (isinstance(values, list) and all(_number(x) for x in values)):
                raise ValueError(f"a series whose {name!r} is not a list of numbers")
    study = rec.get("study")
    if study is not None and not isinstance(study, str):
        raise ValueError(f"a study fingerprint {study!r} that is not a string")
    return key[0], key[1], key[2]


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
