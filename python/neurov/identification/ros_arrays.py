"""Array-typed ROS topics (``std_msgs/msg/Float32MultiArray`` or
``Float64MultiArray``, such as an EKF's state published as a flat array)
mapped by element index. In a bag's mapping file::

    [[arrays]]
    topic = "/ekf/state"
    elements = { roll = 0, pitch = 1, yaw = 2, p = 3, q = 4, r = 5 }
    units = { roll = "deg", pitch = "deg", yaw = "deg", p = "deg/s", q = "deg/s", r = "deg/s" }

The names are the pose and body velocity's (x y z roll pitch yaw u v w p q
r, in the mapping's frames); a unit not named is SI (m, rad, m/s, rad/s).
The messages have no header: they are stamped by the bag's receive time and
held onto the time base as the other signals are. An array value given for
a signal replaces the odometry's."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov.identification.errors import LogError
from neurov.identification.mapping import UNITS, Mapping

__all__ = ["ARRAY_TYPES", "SIGNALS", "array_specs"]

ARRAY_TYPES = ("std_msgs/msg/Float64MultiArray", "std_msgs/msg/Float32MultiArray")
# name -> (column of [eta | nu], kind of unit)
SIGNALS: dict[str, tuple[int, str]] = {
    **{n: (k, "length") for k, n in enumerate(("x", "y", "z"))},
    **{n: (3 + k, "angle") for k, n in enumerate(("roll", "pitch", "yaw"))},
    **{n: (6 + k, "velocity") for k, n in enumerate(("u", "v", "w"))},
    **{n: (9 + k, "rate") for k, n in enumerate(("p", "q", "r"))},
}


def array_specs(mapping: Mapping) -> list[tuple[str, dict[int, tuple[int, float]]]]:
    """Each ``[[arrays]]`` table checked: (topic, {column: (element, factor to SI)})."""
    tables = mapping.data.get("arrays", [])
    if not isinstance(tables, list):
        raise LogError(f"{mapping.where}: arrays: expected [[arrays]] tables")
    out = []
    for n, table in enumerate(tables):
        where = f"{mapping.where}: arrays[{n}]"
        if not isinstance(table, dict) or not isinstance(table.get("topic"), str):
            raise LogError(f"{where}.topic: expected a topic name")
        elements, units = table.get("elements"), table.get("units", {})
        if not isinstance(elements, dict) or not elements:
            raise LogError(f"{where}.elements: expected a table such as {{ roll = 0, pitch = 1 }}")
        if not isinstance(units, dict):
            raise LogError(f"{where}.units: expected a table such as {{ roll = \"deg\" }}")
        cols: dict[int, tuple[int, float]] = {}
        for name, index in elements.items():
            if name not in SIGNALS:
                raise LogError(f"{where}.elements.{name}: unknown (expected some of {list(SIGNALS)})")
            if isinstance(index, bool) or not isinstance(index, int) or index < 0:
                raise LogError(f"{where}.elements.{name}: expected an element index >= 0, got {index!r}")
            col, kind = SIGNALS[name]
            unit = units.get(name, next(iter(UNITS[kind])))
            if unit not in UNITS[kind]:
                raise LogError(f"{where}.units.{name}: {unit!r} is not a unit of {kind}; expected one of "
                               f"{list(UNITS[kind])}")
            cols[col] = (index, UNITS[kind][unit])
        out.append((table["topic"], cols))
    return out


def array_rows(msgs: list[Any], cols: dict[int, tuple[int, float]], where: str) -> NDArray[np.float64]:
    """(n, 12) values of [eta | nu] from array messages (NaN where not mapped)."""
    out = np.full((len(msgs), 12), np.nan)
    for k, m in enumerate(msgs):
        data = np.asarray(m.data, dtype=np.float64)
        for col, (index, factor) in cols.items():
            if index >= data.size:
                raise LogError(f"{where}: message {k} has {data.size} elements; the mapping reads element "
                               f"{index}")
            out[k, col] = data[index] * factor
    return out
