"""Which reader a log goes to: neurov's own files by their suffix, any
other log by its mapping file's ``format``."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from neurov.identification.log import Log
from neurov.identification.neurov_log import read_neurov_log
from neurov.identification.csv_mapping import read_mapped_csv
from neurov.identification.dataflash_log import read_dataflash
from neurov.identification.mapping import read_mapping
from neurov.identification.rosbag_log import read_rosbag
from neurov.identification.tlog_log import read_tlog

__all__ = ["read_log"]


def read_log(path: str | Path, mapping: str | Path | None = None, thrusters: Any = None) -> Log:
    """A log from `path`: with `mapping`, a CSV, a ROS bag, an ArduSub
    telemetry log or DataFlash log as the mapping file says (a tlog's or DataFlash log's PWM goes through
    `thrusters`, the template's ``[thrusters]`` table); without, an ArduSub
    ``.tlog`` or ``.bin`` by its standard messages, or a neurov run's
    result.npz, result.csv or Parquet file."""
    if mapping is None:
        suffix = Path(path).suffix.lower()
        if suffix == ".tlog":
            return read_tlog(path, None, thrusters)
        if suffix == ".bin":
            return read_dataflash(path, None, thrusters)
        return read_neurov_log(path)
    m = read_mapping(mapping)
    if m.format == "rosbag":
        return read_rosbag(path, m, thrusters)
    if m.format == "tlog":
        return read_tlog(path, m, thrusters)
    if m.format == "dataflash":
        return read_dataflash(path, m, thrusters)
    return read_mapped_csv(path, m)
