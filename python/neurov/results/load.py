"""A run loaded back: :func:`load_result` gives the :class:`neurov.Result`
that a run wrote, from its folder (what ``neurov run --out DIR`` writes) or
from one of its files.

- ``result.npz`` (:meth:`Result.to_npz`): every series with its dtype, the
  scenario's name, the controller's label and whether the run diverged;
- ``result.csv`` (:meth:`Result.to_csv`) and a Parquet file
  (:meth:`Result.to_parquet`): the columns of :mod:`neurov.results.columns`; the
  numbers read back exactly (the CSV writes the shortest text of each
  float64).

None of these files holds the scenario, which the result needs (its ``dt``
and duration window the metrics): it is the ``scenario`` argument (a
:class:`neurov.Scenario` or a scenario file), else the ``scenario.toml``
beside the file, which ``neurov run`` copies into its folder (the scenario
file it ran, as it was). A controller's label and whether the run diverged
come from the NPZ, else the folder's metrics.json, else the scenario's
controller and whether the file has fewer rows than the scenario plans.

Each reader is one entry of :data:`READERS`, by suffix.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from neurov import hooks
from neurov.results.columns import npz_series, series_from_columns
from neurov.errors import ResultFileError
from neurov.memory import check_csv_fits
from neurov.results.timeseries import Result
from neurov.config.reading import load_scenario
from neurov.config.scenario import Scenario, scenario_path

__all__ = ["READERS", "RESULT_FILES", "SCENARIO_FILE", "load_result"]

SCENARIO_FILE = "scenario.toml"
"""The scenario file ``neurov run`` copies into its output folder."""

RESULT_FILES = ("result.npz", "result.csv", "result.parquet")
"""A run folder's result files, in the order :func:`load_result` looks for them."""

# The largest result.npz read (a 24-hour run at 5 Hz is some 300 MB).
_MAX_NPZ_BYTES = 1 << 36


def load_result(path: str | Path, scenario: Scenario | str | Path | None = None) -> Result:
    """The :class:`neurov.Result` a run wrote: `path` is a run folder (its
    result.npz, else result.csv, else result.parquet is read) or one of the
    files of :data:`READERS` (``.npz``, ``.csv``, ``.parquet``, ``.mcap``: a
    recording, which holds its scenario). The
    scenario is `scenario` (a Scenario, a scenario file or a shipped
    scenario's name), else the ``scenario.toml`` beside the file (see the
    module). Its arrays equal the written ones (to the last bit) and its
    :meth:`~neurov.Result.metrics` those the run wrote. Anything that does
    not fit (no such file, an unknown suffix, a missing or unexpected column,
    an array of the wrong shape or dtype, rows the scenario cannot have)
    raises :class:`neurov.errors.ResultFileError` naming the file."""
    path = Path(path)
    if path.is_dir():
        found = [path / name for name in RESULT_FILES if (path / name).is_file()]
        if not found:
            raise ResultFileError(f"{path}: a folder without a run's result file (expected one of "
                                  f"{', '.join(RESULT_FILES)})")
        path = found[0]
    elif not path.is_file():
        raise ResultFileError(f"{path}: no such file or folder")
    reader = READERS.get(path.suffix.lower())
    if reader is None:
        raise ResultFileError(f"{path}: unknown kind of result file {path.suffix!r} (expected a run "
                              f"folder or a file ending in {', '.join(READERS)})")
    return reader(path, scenario)


def _scenario(path: Path, given: Scenario | str | Path | None, name: str | None) -> Scenario:
    if isinstance(given, Scenario):
        return given
    if given is not None:
        return load_scenario(scenario_path(given))
    beside = path.parent / SCENARIO_FILE
    if not beside.is_file():
        raise ResultFileError(f"{path}: the file holds no scenario and there is no {SCENARIO_FILE} beside "
                              "it (neurov run writes one in its folder): pass load_result(..., scenario=) "
                              "the scenario of the run")
    found = load_scenario(beside)
    if name is not None and found.name != name:
        raise ResultFileError(f"{path}: the run is of scenario {name!r}, but {beside} is {found.name!r}")
    return found


def _metrics_json(path: Path) -> dict[str, Any]:
    """The metrics.json beside a run's file, {} if none or unreadable."""
    try:
        data = json.loads((path.parent / "metrics.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def _result(path: Path, series: dict[str, Any], given: Scenario | str | Path | None,
            meta: dict[str, Any]) -> Result:
    """The Result of `series`, its scenario found and the rows checked against it."""
    written = _metrics_json(path) if path.name in RESULT_FILES else {}
    scenario = _scenario(path, given, meta.get("scenario", written.get("scenario")))
    rows = len(series["t"])
    planned = round(scenario.duration / scenario.dt) + 1
    if rows > planned:
        raise ResultFileError(f"{path}: {rows} rows, more than the {planned} of scenario {scenario.name!r} "
                              f"({scenario.duration:g} s at dt = {scenario.dt:g} s): not its run")
    config = scenario.simulation
    thrusters = config.thrusters.matrix.shape[1] if config.use_thrusters else 0
    if series["thrusts"].shape[1] != thrusters:
        raise ResultFileError(f"{path}: {series['thrusts'].shape[1]} thrust columns, but scenario "
                              f"{scenario.name!r} has {thrusters} thrusters")
    controller = meta.get("controller", written.get("controller", scenario.controller.name))
    # Only a divergence ends a run early, unless it was stopped (a partial folder).
    diverged = meta.get("diverged", written.get("diverged", rows < planned and written.get("partial") is not True))
    return Result(scenario=scenario, controller=str(controller), diverged=bool(diverged),
                  extra={"loaded_from": str(path)}, **series)


def _read_npz(path: Path, scenario: Scenario | str | Path | None) -> Result:
    series, meta = npz_series(path, str(path), ResultFileError, _MAX_NPZ_BYTES)
    return _result(path, series, scenario, meta)


def _read_mcap(path: Path, scenario: Scenario | str | Path | None) -> Result:
    given = load_scenario(scenario_path(scenario)) if isinstance(scenario, (str, Path)) else scenario
    return hooks.provided("read_mcap")(path, given)  # type: ignore[no-any-return]


def _read_csv(path: Path, scenario: Scenario | str | Path | None) -> Result:
    import pandas as pd

    check_csv_fits(path, ResultFileError)
    try:
        frame = pd.read_csv(path)
    except (ValueError, OSError, pd.errors.ParserError) as e:
        raise ResultFileError(f"{path}: not a readable CSV ({e})") from None
    return _result(path, _frame_series(frame, path), scenario, {})


def _read_parquet(path: Path, scenario: Scenario | str | Path | None) -> Result:
    import pandas as pd

    try:
        frame = pd.read_parquet(path)
    except (ValueError, OSError) as e:
        raise ResultFileError(f"{path}: not a readable Parquet file ({e})") from None
    if frame.index.name == "t":
        frame = frame.reset_index()
    return _result(path, _frame_series(frame, path), scenario, {})


def _frame_series(frame: Any, path: Path) -> dict[str, np.ndarray]:
    columns = {str(k): (frame[k].astype(str).to_numpy() if str(frame[k].dtype) == "category"
                        else frame[k].to_numpy()) for k in frame.columns}
    if len(columns) != len(frame.columns):
        raise ResultFileError(f"{path}: column names repeat")
    return series_from_columns(columns, str(path))


READERS: dict[str, Callable[[Path, Any], Result]] = {
    ".npz": _read_npz,
    ".csv": _read_csv,
    ".parquet": _read_parquet,
    ".mcap": _read_mcap,
}
"""The readers of :func:`load_result` by file suffix: ``reader(path,
scenario)`` (`scenario` as given to load_result, or None) -> Result. A
reader of another format (an MCAP recording, say) is one more entry."""
