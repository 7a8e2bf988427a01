"""A run read back from the MCAP file :func:`neurov.recording.mcap_writer.write_mcap`
wrote: the :class:`neurov.Result` of its ``result.npz`` attachment, with
its scenario (from its ``scenario.toml`` attachment, read as the file it
came from), wall time and extra."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any


from neurov.results.columns import npz_series
from neurov.errors import RecordingError
from neurov.results.timeseries import Result
from neurov.config.scenario import Scenario
from neurov.config.reading import scenario_from_mapping
from neurov.files import tomllib

__all__ = ["MAX_RESULT_BYTES", "read_mcap", "result_from_npz"]

MAX_RESULT_BYTES = 1 << 34
"""The largest result.npz attachment read (16 GiB; a day at 5 Hz is about 100 MB)."""

def read_mcap(path: str | Path, scenario: Scenario | None = None) -> Result:
    """The run recorded in the MCAP file `path`, equal to the result that
    wrote it. The scenario is the recording's own (its scenario file's text,
    read with the file's original path as its origin, so that a vehicle file
    beside it is found), or `scenario` if given (needed for a run of a
    scenario built in Python). Raises :class:`neurov.errors.RecordingError`
    naming the file for one that is missing, not MCAP, or not a neurov run."""
    try:
        from mcap.exceptions import McapError
        from mcap.reader import make_reader
    except ImportError:
        raise RecordingError("reading an MCAP recording needs mcap: pip install 'neurov[ros]'") from None

    path = Path(path)
    if not path.is_file():
        raise RecordingError(f"{path}: no such MCAP file")
    try:
        with path.open("rb") as f:
            reader = make_reader(f)
            attachments = {a.name: a.data for a in reader.iter_attachments()}
            metadata = {m.name: dict(m.metadata) for m in reader.iter_metadata()}
    except (McapError, ValueError, EOFError, OSError) as e:
        raise RecordingError(f"{path}: not a readable MCAP file ({type(e).__name__}: {e})") from None
    if "result.npz" not in attachments:
        raise RecordingError(f"{path}: no attachment 'result.npz': not a run written by neurov "
                             "(Result.to_mcap, neurov run --format mcap) or a run that stopped before "
                             "its end; its messages read with any ROS 2 reader, but not back into a Result")
    info = {**metadata.get("neurov", {}), **metadata.get("scenario", {})}
    if scenario is None:
        scenario = _scenario(attachments, info, path)
    result = result_from_npz(attachments["result.npz"], scenario, f"{path}: attachment result.npz")
    try:
        result.wall_time = float(json.loads(info.get("wall_time", "0")))
        result.extra = dict(json.loads(info.get("extra", "{}")))
    except (ValueError, TypeError) as e:
        raise RecordingError(f"{path}: metadata neurov: wall_time/extra: not JSON ({e})") from None
    return result


def _scenario(attachments: dict[str, bytes], info: dict[str, str], path: Path) -> Scenario:
    text = attachments.get("scenario.toml")
    if text is None:
        raise RecordingError(f"{path}: no attachment 'scenario.toml' (the run's scenario "
                             f"{info.get('scenario', '?')!r} was not read from a file): "
                             "give it, read_mcap(path, scenario=...)")
    try:
        data = tomllib.loads(text.decode("utf-8"))
    except (UnicodeDecodeError, tomllib.TOMLDecodeError) as e:
        raise RecordingError(f"{path}: attachment scenario.toml: not valid TOML ({e})") from None
    # Read with the file's original path as its origin (a vehicle file beside it is found), but
    # what is wrong is the recording's: its errors name the MCAP, not the scenario file it came from.
    origin = info.get("source") or f"{path}:scenario.toml"
    where = f"{path}: attachment scenario.toml" + (f" (the run's scenario, read from {origin})"
                                                    if info.get("source") else "")
    try:
        scenario = scenario_from_mapping(data, origin)
    except (ValueError, TypeError) as e:
        raise RecordingError(f"{where}: {str(e).removeprefix(origin + ': ')}") from None
    # Deferred: the writer's module needs SciPy (its frames' rotations); reading does not.
    from neurov.recording.mcap_writer import plain

    # The file's scenario is the run's unless it was changed in Python after it was read.
    try:
        recorded = json.loads(info.get("describe", "null"))
    except ValueError as e:
        raise RecordingError(f"{path}: metadata scenario: describe: not JSON ({e})") from None
    if recorded is not None and not isinstance(recorded, dict):
        raise RecordingError(f"{path}: metadata scenario: describe: expected a JSON object, got "
                             f"{type(recorded).__name__}")
    rebuilt = plain(scenario.describe())
    if recorded is not None and recorded != rebuilt:
        changed = sorted(k for k in recorded if recorded.get(k) != rebuilt.get(k))
        raise RecordingError(f"{path}: the run's scenario differs from its file scenario.toml in "
                             f"{', '.join(changed)} (changed in Python after it was read): give it, "
                             "read_mcap(path, scenario=...)")
    return scenario


def result_from_npz(data: bytes, scenario: Scenario, where: str) -> Result:
    """The :class:`neurov.Result` of the bytes of a result.npz
    (:meth:`neurov.Result.to_npz`), for `scenario`; errors name `where`."""
    series, meta = npz_series(data, where, RecordingError, MAX_RESULT_BYTES)
    missing = [k for k in ("controller", "diverged") if k not in meta]
    if missing:
        raise RecordingError(f"{where}: no array {missing[0]!r} (not a neurov result)")
    return Result(scenario=scenario, controller=str(meta["controller"]), diverged=bool(meta["diverged"]),
                  **series)
