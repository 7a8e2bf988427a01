"""A neurov run's own log (``result.npz``, ``result.csv`` or a Parquet
file of :meth:`neurov.Result.to_pandas`, :meth:`neurov.Result.to_parquet`)
as a :class:`Log`; the columns are named as in :mod:`neurov.results.columns`.

The pose and velocity are the ones the controller was given
(``eta_estimate``, ``nu_estimate``: what a real vehicle's sensors and
estimator give); the force is ``tau_applied`` (the thrusters' wrench over
the row's interval) plus ``disturbance`` (a known force in a simulation:
the excitation scenarios use it as their multisine input)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from neurov.memory import check_csv_fits
from neurov.npz_file import NpzFile
from neurov.results.columns import RESULT_SERIES, column_names
from neurov.identification.errors import LogError
from neurov.identification.log import Log, make_log

__all__ = ["read_neurov_log", "log_from_result"]

_SPECS = {spec.name: spec for spec in RESULT_SERIES}


def log_from_result(result: Any, source: str = "<result>") -> Log:
    """A :class:`neurov.Result` (or any object with its arrays) as a log."""
    return make_log(source, result.t, result.eta_estimate, result.nu_estimate,
                    np.asarray(result.tau_applied) + np.asarray(result.disturbance),
                    result.current)


def _columns(frame: dict[str, Any], path: Path) -> Log:
    def block(name: str) -> Any:
        names = column_names(_SPECS[name], _SPECS[name].width)
        missing = [c for c in names if c not in frame]
        if missing:
            raise LogError(f"{path}: missing column(s) {missing} (a neurov result.csv has them)")
        return np.column_stack([np.asarray(frame[c], dtype=np.float64) for c in names])

    if "t" not in frame:
        raise LogError(f"{path}: missing column 't'")
    current = block("current") if "current_N" in frame else None
    disturbance = block("disturbance") if "disturbance_X" in frame else 0.0
    return make_log(str(path), frame["t"], block("eta_estimate"), block("nu_estimate"),
                    block("tau_applied") + disturbance, current)


#: The largest result.npz read, as :func:`neurov.load_result` reads one.
_MAX_NPZ_BYTES = 1 << 36


def _npz_log(path: Path) -> Log:
    """A result.npz read as :class:`neurov.npz_file.NpzFile` reads (random
    bytes, a single .npy, Python objects: a LogError naming the file, never
    numpy's advice to unpickle), each array real before it is read."""
    with NpzFile(path, LogError, _MAX_NPZ_BYTES, str(path),
                 " (a neurov run's result.npz holds named arrays)") as z:
        names = {n.removesuffix(".npy") for n in z.zip.namelist()}
        missing = [k for k in ("t", "eta_estimate", "nu_estimate", "tau_applied") if k not in names]
        if missing:
            raise LogError(f"{path}: missing array(s) {missing} (a neurov result.npz has them)")

        def real(name: str) -> Any:
            def check(shape: tuple[int, ...], dtype: np.dtype) -> None:
                if dtype.kind not in "fiu" or len(shape) != (1 if name == "t" else 2):
                    raise LogError(f"{path}: array {name!r} is {dtype} {shape}, expected real numbers "
                                   f"({'one' if name == 't' else 'a row'} per sample)")
            return np.array(z.array(name, check), dtype=np.float64)

        disturbance = real("disturbance") if "disturbance" in names else 0.0
        current = real("current") if "current" in names else None
        return make_log(str(path), real("t"), real("eta_estimate"), real("nu_estimate"),
                        real("tau_applied") + disturbance, current)


def read_neurov_log(path: str | Path) -> Log:
    """Reads a neurov run's ``.npz``, ``.csv`` or ``.parquet``; a missing
    signal raises :class:`LogError` naming the file and the signal."""
    path = Path(path)
    if not path.is_file():
        raise LogError(f"{path}: no such file")
    suffix = path.suffix.lower()
    if suffix == ".npz":
        return _npz_log(path)
    if suffix == ".csv":
        import pandas as pd

        check_csv_fits(path, LogError)
        try:
            frame = pd.read_csv(path)
        except (ValueError, OSError) as e:
            raise LogError(f"{path}: not a readable CSV: {e}") from None
        return _columns({str(k): frame[k].to_numpy() for k in frame.columns}, path)
    if suffix == ".parquet":
        import pandas as pd

        frame = pd.read_parquet(path)
        if frame.index.name == "t":
            frame = frame.reset_index()
        return _columns({str(k): frame[k].to_numpy() for k in frame.columns}, path)
    raise LogError(f"{path}: unknown log format {suffix!r} (expected .npz, .csv or .parquet from "
                   "neurov run, or a mapping file for other logs)")
