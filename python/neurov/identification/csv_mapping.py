"""A CSV of the user's own, read through a mapping file
(:mod:`neurov.identification.mapping`): the named columns, in SI units and
neurov's frames. A column the mapping names and the file lacks is an error
naming both."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from neurov.identification.errors import LogError
from neurov.memory import check_csv_fits
from neurov.identification.log import Log, make_log
from neurov.identification.mapping import Mapping, to_neurov_frames

__all__ = ["read_mapped_csv"]


def read_mapped_csv(path: str | Path, mapping: Mapping) -> Log:
    import pandas as pd

    path = Path(path)
    if not path.is_file():
        raise LogError(f"{path}: no such file")
    check_csv_fits(path, LogError)  # a file too large for memory refused before pandas reads it
    try:
        frame = pd.read_csv(path)
    except (ValueError, OSError) as e:
        raise LogError(f"{path}: not a readable CSV: {e}") from None
    time_col, time_factor = mapping.time()
    signals = {}
    for name in ("eta", "nu", "tau"):
        cols, factors = mapping.signal(name)
        missing = [c for c in cols if c not in frame.columns]
        if missing:
            raise LogError(f"{path}: missing column(s) {missing} that {mapping.where} names for "
                           f"signals.{name}")
        signals[name] = frame[cols].to_numpy(dtype=np.float64) * factors
    if time_col not in frame.columns:
        raise LogError(f"{path}: missing column {time_col!r} that {mapping.where} names for time")
    eta, nu, tau = to_neurov_frames(signals["eta"], signals["nu"], signals["tau"],
                                    mapping.body_frame, mapping.world_frame)
    return make_log(str(path), frame[time_col].to_numpy(dtype=np.float64) * time_factor, eta, nu, tau)
