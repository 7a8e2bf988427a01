"""A run read back for the replay: :func:`read_result`, the one reader
``neurov view`` uses (``neurov.load_result`` takes its place when it reads
runs back in general).

What it reads is a run folder of ``neurov run --out DIR`` (its
``result.npz``) or that ``result.npz`` itself, each array's shape checked
before it is read (:class:`neurov.npz_file.NpzFile`). The file holds the
series and the scenario's name, not the scenario: a shipped scenario's name
gives its file (so the vehicle, its thrusters and their layout); another
name gives a bare scenario of that name, marked ``extra["vehicle_known"] =
False`` so that the replay draws a plain body and the applied force rather
than guessing a vehicle.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from neurov.errors import ResultFileError
from neurov.npz_file import NpzFile
from neurov.result import SERIES, Result
from neurov.scenario import SCENARIO_DIR, Scenario, load_scenario

__all__ = ["MAX_RESULT_FILE_BYTES", "read_result"]

MAX_RESULT_FILE_BYTES = 4 * 1024**3
"""The largest result.npz read (4 GiB: a day at 5 Hz is about 0.3 GB)."""

# Columns per row of each series (None: any number: thrusters, parameters).
_COLUMNS: dict[str, int | None] = {
    "t": 0, "eta": 6, "nu": 6, "eta_d": 6, "eta_d_dot": 6, "tau_demanded": 6, "tau_applied": 6,
    "disturbance": 6, "s": 6, "thrusts": None, "theta": None, "adaptive_norm": 0, "controller_status": 0,
    "plant_status": 0, "faults": 0, "current": 3, "wave_velocity": 3, "wave_elevation": 0,
    "payload_mass": 0, "eta_estimate": 6, "nu_estimate": 6,
}
_CODES = ("controller_status", "plant_status", "faults")
Check = Callable[[tuple[int, ...], np.dtype], None]
_NAMES = ("scenario", "controller", "diverged")


def read_result(path: str | Path, name: str | None = None) -> Result:
    """The run in the folder or result.npz at `path`; any problem raises
    :class:`neurov.errors.ResultFileError` whose message starts with `name`
    (default: the path) and says what was expected."""
    path = Path(path)
    name = str(path) if name is None else name
    if path.is_dir():
        if not (path / "result.npz").is_file():
            raise ResultFileError(f"{name}: a folder without result.npz (expected a run folder written by "
                                  "'neurov run --out DIR', or a result.npz)")
        path = path / "result.npz"
        name = f"{name}: result.npz"
    elif not path.exists():
        raise ResultFileError(f"{name}: no such file or folder (expected a run folder written by "
                              "'neurov run --out DIR', or its result.npz)")
    elif path.suffix.lower() != ".npz":
        kind = f"a {path.suffix} file" if path.suffix else "a file without the .npz suffix"
        raise ResultFileError(f"{name}: {kind}, not a run (expected a run folder written by "
                              "'neurov run --out DIR', or its result.npz)")
    with NpzFile(path, ResultFileError, MAX_RESULT_FILE_BYTES, name) as npz:
        held = {n[:-4] for n in npz.zip.namelist() if n.endswith(".npy")}
        missing = [k for k in (*_NAMES, *SERIES) if k not in held]
        if missing:
            listed = ", ".join(missing[:4]) + (f" and {len(missing) - 4} more" if len(missing) > 4 else "")
            raise ResultFileError(f"{name}: not a neurov result: missing array(s) {listed} "
                                  "(a result.npz of 'neurov run' holds them all)")
        labels = {k: str(npz.array(k, _scalar(name, k))[()]) for k in ("scenario", "controller")}
        diverged = bool(npz.array("diverged", _scalar(name, "diverged"))[()])
        rows = npz.header("t")[0]
        if len(rows) != 1:
            raise ResultFileError(f"{name}: array 't' has the shape {rows}, expected one row per step")
        series: dict[str, Any] = {k: np.array(npz.array(k, _series(name, k, rows[0]))) for k in SERIES}
    return Result(scenario=_scenario(labels["scenario"]), controller=labels["controller"],
                  diverged=diverged, extra={} if _shipped(labels["scenario"]) else {"vehicle_known": False},
                  **series)


def _scalar(name: str, array: str) -> Check:
    def check(shape: tuple[int, ...], dtype: np.dtype) -> None:
        if shape != () or dtype.kind not in ("U", "b"):
            raise ResultFileError(f"{name}: array '{array}' is {shape} {dtype}, expected a single "
                                  "string or boolean")
    return check


def _series(name: str, array: str, rows: int) -> Check:
    columns = _COLUMNS[array]
    kind = "u" if array in _CODES else "f"

    def check(shape: tuple[int, ...], dtype: np.dtype) -> None:
        if columns == 0:
            fits, said = shape == (rows,), f"{rows} values"
        else:
            fits = len(shape) == 2 and shape[0] == rows and columns in (None, shape[1])
            said = f"{rows} rows of {columns if columns else 'n'} columns"
        if not fits or dtype.kind != kind:
            raise ResultFileError(f"{name}: array '{array}' is {shape} {dtype}, expected {said} of "
                                  f"{'unsigned integers' if kind == 'u' else 'floats'}")
    return check


def _shipped(scenario: str) -> bool:
    return bool(scenario) and Path(scenario).name == scenario and (SCENARIO_DIR / f"{scenario}.toml").is_file()


def _scenario(scenario: str) -> Scenario:
    """The shipped scenario of that name, else a bare one of that name."""
    if _shipped(scenario):
        return load_scenario(SCENARIO_DIR / f"{scenario}.toml")
    return Scenario(name=scenario)
