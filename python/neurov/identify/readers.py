"""Which reader a log goes to: neurov's own files by their suffix, any
other log through its mapping file."""

from __future__ import annotations

from pathlib import Path

from neurov.identify.log import Log
from neurov.identify.neurov_log import read_neurov_log

__all__ = ["read_log"]


def read_log(path: str | Path, mapping: str | Path | None = None) -> Log:
    """A log from `path`: with `mapping`, a CSV of the user's own described
    by the mapping file (:mod:`neurov.identify.csv_mapping`); without, a
    neurov run's result.npz, result.csv or Parquet file."""
    if mapping is not None:
        from neurov.identify.csv_mapping import read_mapped_csv

        return read_mapped_csv(path, mapping)
    return read_neurov_log(path)
