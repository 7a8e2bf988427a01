"""The mapping file: which of a log's signals is which, in which units and
frames. A TOML file::

    format = "csv"              # csv | rosbag | tlog | dataflash
    body_frame = "frd"          # frd (x forward, y starboard, z down: neurov's) or flu (ROS)
    world_frame = "ned"         # ned (neurov's) or enu (ROS)
    time = { column = "time", unit = "s" }    # s | ms | us | ns

    [signals.eta]               # x y z roll pitch yaw
    columns = ["north", "east", "down", "roll", "pitch", "yaw"]
    units = ["m", "m", "m", "deg", "deg", "deg"]
    [signals.nu]                # u v w p q r (body)
    columns = [...]
    units = ["m/s", "m/s", "m/s", "deg/s", "deg/s", "deg/s"]
    [signals.tau]               # X Y Z K M N (body), acting over each row's interval
    columns = [...]
    units = ["N", "N", "N", "N m", "N m", "N m"]

The readers of bags and telemetry logs use their own tables
(:mod:`neurov.identification.rosbag_log`, :mod:`neurov.identification.tlog_log`)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov.files import read_toml
from neurov.identification.errors import LogError

__all__ = ["Mapping", "read_mapping", "to_neurov_frames"]

Array = NDArray[np.float64]

UNITS: dict[str, dict[str, float]] = {
    "length": {"m": 1.0, "cm": 0.01, "mm": 0.001},
    "angle": {"rad": 1.0, "deg": np.pi / 180},
    "velocity": {"m/s": 1.0, "cm/s": 0.01, "mm/s": 0.001},
    "rate": {"rad/s": 1.0, "deg/s": np.pi / 180},
    "force": {"N": 1.0, "kgf": 9.80665},
    "moment": {"N m": 1.0, "kgf m": 9.80665},
    "time": {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9},
}
KINDS = {"eta": ("length",) * 3 + ("angle",) * 3, "nu": ("velocity",) * 3 + ("rate",) * 3,
         "tau": ("force",) * 3 + ("moment",) * 3}
_TOP = {"format", "body_frame", "world_frame", "time", "signals", "topics", "servo_channels", "max_age",
        "water_density", "surface_pressure", "thruster_command", "resample", "arrays"}


class Mapping:
    """A mapping file read and checked."""

    def __init__(self, data: dict[str, Any], where: str) -> None:
        for key in data:
            if key not in _TOP:
                raise LogError(f"{where}: unknown field {key!r} (expected one of {sorted(_TOP)})")
        self.where = where
        self.format = _choice(data, "format", ("csv", "rosbag", "tlog", "dataflash"), where, "csv")
        self.body_frame = _choice(data, "body_frame", ("frd", "flu"), where, "frd")
        self.world_frame = _choice(data, "world_frame", ("ned", "enu"), where, "ned")
        if (self.body_frame, self.world_frame) not in (("frd", "ned"), ("flu", "enu")):
            raise LogError(f"{where}: body_frame {self.body_frame!r} with world_frame "
                           f"{self.world_frame!r}: expected frd with ned (neurov, ArduSub) or flu "
                           "with enu (ROS REP 103)")
        self.data = data
        age = data.get("max_age", 0.5)
        if isinstance(age, bool) or not isinstance(age, (int, float)) or not age > 0:
            raise LogError(f"{where}: max_age: expected seconds > 0, got {age!r}")
        self.max_age = float(age)

    def time(self) -> tuple[str, float]:
        t = self.data.get("time")
        if not isinstance(t, dict) or not isinstance(t.get("column"), str):
            raise LogError(f"{self.where}: time: expected a table {{ column = \"...\", unit = \"s\" }}")
        unit = t.get("unit", "s")
        if unit not in UNITS["time"]:
            raise LogError(f"{self.where}: time.unit: expected one of {list(UNITS['time'])}, got {unit!r}")
        return t["column"], UNITS["time"][unit]

    def signal(self, name: str) -> tuple[list[str], Array]:
        """A signal's six column names and the factors to SI."""
        sig = self.data.get("signals", {}).get(name)
        where = f"{self.where}: signals.{name}"
        if not isinstance(sig, dict):
            raise LogError(f"{where}: missing (expected a table with 'columns' and 'units')")
        cols, units = sig.get("columns"), sig.get("units")
        if not (isinstance(cols, list) and len(cols) == 6 and all(isinstance(c, str) for c in cols)):
            raise LogError(f"{where}.columns: expected 6 column names, got {cols!r}")
        if not (isinstance(units, list) and len(units) == 6):
            raise LogError(f"{where}.units: expected 6 units, got {units!r}")
        factors = []
        for k, (kind, unit) in enumerate(zip(KINDS[name], units)):
            if unit not in UNITS[kind]:
                raise LogError(f"{where}.units[{k}]: {unit!r} is not a unit of {kind}; expected one of "
                               f"{list(UNITS[kind])}")
            factors.append(UNITS[kind][unit])
        return cols, np.array(factors)


def _choice(data: dict[str, Any], key: str, choices: tuple[str, ...], where: str, default: str) -> str:
    v = data.get(key, default)
    if v not in choices:
        raise LogError(f"{where}: {key}: expected one of {list(choices)}, got {v!r}")
    return str(v)


def read_mapping(path: str | Path) -> Mapping:
    path = Path(path)
    return Mapping(read_toml(path, LogError, "mapping"), str(path))


def to_neurov_frames(eta: Array, nu: Array, tau: Array, body: str, world: str) -> tuple[Array, Array, Array]:
    """Poses, velocities and forces from a log's frames to neurov's (NED
    world, forward-starboard-down body). From ROS's ENU world and FLU body:
    north = y, east = x, down = -z; body vectors keep x and flip y and z;
    roll is kept, pitch flips, heading = pi/2 - yaw (as MAVROS converts)."""
    eta, nu, tau = eta.copy(), nu.copy(), tau.copy()
    if (body, world) == ("flu", "enu"):
        flip = np.array([1, -1, -1, 1, -1, -1.0])
        nu, tau = nu * flip, tau * flip
        eta[:, [0, 1]] = eta[:, [1, 0]]
        eta[:, 2] *= -1
        eta[:, 4] *= -1
        eta[:, 5] = (np.pi / 2 - eta[:, 5] + np.pi) % (2 * np.pi) - np.pi
    return eta, nu, tau
