"""The ``[thrusters]`` table of a vehicle file (format:
:mod:`neurov.config.vehicle_file`), read into the bound C++ structs: each
curve a ``ThrusterCurveConfig``, the layout a ``ThrusterConfig``, both judged by
their C++ validators; the allocation matrix of a layout given by positions and
directions is the C++ one (:func:`neurov._core.allocation_matrix`). Also the
few TOML value checks the vehicle file's other tables share (a number, a
rectangular table of numbers). Every error names the file and the field.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from neurov._core import ThrusterConfig, ThrusterCurveConfig, allocation_matrix
from neurov.errors import ValidationError, VehicleFileError
from neurov.schema import did_you_mean

__all__ = ["describe", "shape_of", "shape_text", "thrusters_from_mapping"]


def describe(value: Any) -> str:
    """What a TOML value is, for a message: "a table", "str 'x'", ..."""
    if isinstance(value, list):
        return "a list that is not all numbers (or not rectangular)"
    if isinstance(value, dict):
        return "a table"
    return f"{type(value).__name__} {value!r}"


def shape_of(value: Any) -> tuple[int, ...] | None:
    """Shape of a number or a rectangular nested list of numbers, else None."""
    if isinstance(value, bool):
        return None
    if isinstance(value, (int, float)):
        return ()
    if isinstance(value, list) and value:
        inner = [shape_of(v) for v in value]
        if all(s is not None and s == inner[0] for s in inner):
            return (len(value), *inner[0])  # type: ignore[misc]
    return None


def shape_text(shape: Any) -> str:
    """A shape of :func:`shape_of` (or "str") in words: "a list of 6 numbers"."""
    if shape == ():
        return "a number"
    if shape == "str":
        return "a string"
    if len(shape) == 1:
        return f"a list of {shape[0]} number{'s' if shape[0] != 1 else ''}"
    return f"a {shape[0]}x{shape[1]} table of numbers"


def thrusters_from_mapping(table: Any, where: str) -> dict[str, Any]:
    """Checks a ``[thrusters]`` table already parsed; `where` prefixes errors."""
    if not isinstance(table, dict):
        raise VehicleFileError(f"{where}: expected a table")
    allowed = {"positions", "directions", "matrix", "max_thrust", "min_thrust", "time_constant",
               "description", "curve", "supply_voltage", "names"}
    for key in table:
        if key not in allowed:
            hint = did_you_mean(key, sorted(allowed))
            raise VehicleFileError(f"{where}.{key}: unknown field{hint}")

    def array(key: str, shape: tuple[int, ...] | None) -> Any:
        v = table[key]
        s = shape_of(v)
        if s is None or (shape is not None and s != shape) or len(s) < 1:
            raise VehicleFileError(f"{where}.{key}: expected {shape_text(shape) if shape else 'a table of numbers'}, got {describe(v) if s is None else s}")
        a = np.asarray(v, dtype=np.float64)
        if not np.all(np.isfinite(a)):
            raise VehicleFileError(f"{where}.{key}: expected finite numbers")
        return a

    pos = None
    if "matrix" in table:
        if "positions" in table or "directions" in table:
            raise VehicleFileError(f"{where}: give either 'matrix' or 'positions' and 'directions'")
        matrix = array("matrix", None)
        if matrix.ndim != 2 or matrix.shape[0] != 6:
            raise VehicleFileError(f"{where}.matrix: expected 6 rows, got shape {matrix.shape}")
    else:
        for key in ("positions", "directions"):
            if key not in table:
                raise VehicleFileError(f"{where}: missing field {key!r} (or give 'matrix')")
        pos = array("positions", None)
        dirs = array("directions", None)
        if pos.ndim != 2 or pos.shape[1] != 3 or dirs.shape != pos.shape:
            raise VehicleFileError(f"{where}: 'positions' and 'directions' must both be n rows of 3 numbers")
        norms = np.linalg.norm(dirs, axis=1)
        if np.any(norms == 0):
            raise VehicleFileError(f"{where}.directions: a direction is zero")
        matrix = allocation_matrix(pos, dirs / norms[:, None])
    n = matrix.shape[1]
    names = table.get("names")
    if names is not None and not (isinstance(names, list) and len(names) == n
                                  and all(isinstance(x, str) for x in names)):
        raise VehicleFileError(f"{where}.names: expected {n} strings (one per thruster), got "
                               f"{describe(names)}")
    curves = _curves(table, n, where) if "curve" in table else None
    if "supply_voltage" in table and curves is None:
        raise VehicleFileError(f"{where}.supply_voltage: only with a [thrusters.curve]")
    if "max_thrust" not in table and curves is None:
        raise VehicleFileError(f"{where}: missing field 'max_thrust' (or give a [thrusters.curve])")

    def limits(key: str) -> Any:
        v = table[key]
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            v = [v] * n
        if shape_of(v) != (n,):
            raise VehicleFileError(f"{where}.{key}: expected a number or {n} numbers, got {describe(v)}")
        a = np.asarray(v, dtype=np.float64)
        if not np.all(np.isfinite(a)):
            raise VehicleFileError(f"{where}.{key}: expected finite numbers")
        return a

    voltage = 0.0
    if curves is not None:
        v = table.get("supply_voltage")
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0:
            raise VehicleFileError(f"{where}.supply_voltage: expected a number > 0 (V) with a curve, "
                                   f"got {v!r}")
        voltage = float(v)

    def curve_end(row: int) -> Any:
        # The curves' thrust at their first or last command (the C++ curve evaluates it).
        return np.array([c.static_thrust(c.table[row, 0], voltage) for c in curves or []])

    max_thrust = limits("max_thrust") if "max_thrust" in table else curve_end(-1)
    if "min_thrust" in table:
        min_thrust = limits("min_thrust")
    else:
        min_thrust = -max_thrust if curves is None else curve_end(0)
    tc = table.get("time_constant", 0.0)
    if isinstance(tc, bool) or not isinstance(tc, (int, float)) or not math.isfinite(tc) or tc < 0:
        raise VehicleFileError(f"{where}.time_constant: expected a number >= 0, got {tc!r}")
    if curves is not None and "time_constant" in table:
        raise VehicleFileError(f"{where}.time_constant: with a curve the lag is the curve's "
                               "(give 'time_constant' in [thrusters.curve])")
    # positions: where the thrusters sit (None for a matrix), for drawing them (neurov view).
    out = {"matrix": matrix, "max_thrust": max_thrust, "min_thrust": min_thrust,
           "time_constant": float(tc), "curves": curves, "supply_voltage": voltage, "names": names,
           "positions": pos}
    if curves is not None:
        _check_layout(out, where)
    return out


# A curve's keys: its rows (the C++ field `table`) as `command` and `thrust`, or
# as a `polynomial` sampled at `points` over `command_range`; then every other
# field of its C++ description (ThrusterCurveConfig.FIELDS), a number, under its
# own name; `neutral` and `reference_voltage` must be given.
_CURVE_NUMBERS = tuple(f["name"] for f in ThrusterCurveConfig.FIELDS if f["name"] != "table")
_CURVE_KEYS = ("command", "thrust", "polynomial", "command_range", "points") + _CURVE_NUMBERS
_CURVE_REQUIRED = ("neutral", "reference_voltage")


def _curves(table: dict[str, Any], n: int, where: str) -> list[Any]:
    """The ``curve`` entry as n ThrusterCurveConfig, each checked by the C++
    validator, whose field names are turned into this file's keys."""
    raw = table["curve"]
    if isinstance(raw, dict):
        items = [(f"{where}.curve", raw)] * n
    elif isinstance(raw, list) and all(isinstance(t, dict) for t in raw):
        if len(raw) != n:
            raise VehicleFileError(f"{where}.curve: expected one table or {n} tables (one per "
                                   f"thruster), got {len(raw)}")
        items = [(f"{where}.curve[{i}]", t) for i, t in enumerate(raw)]
    else:
        raise VehicleFileError(f"{where}.curve: expected a table [thrusters.curve] or {n} tables "
                               f"[[thrusters.curve]], got {describe(raw)}")
    built: dict[int, Any] = {}
    return [built.setdefault(id(t), _curve(t, w)) for w, t in items]


def _curve(t: dict[str, Any], where: str) -> Any:
    for key in t:
        if key not in _CURVE_KEYS:
            hint = did_you_mean(key, list(_CURVE_KEYS))
            raise VehicleFileError(f"{where}.{key}: unknown field{hint}")
    for key in _CURVE_REQUIRED:
        if key not in t:
            raise VehicleFileError(f"{where}: missing field {key!r}")
    command, thrust = _curve_rows(t, where)
    for key, v in (("command", command), ("thrust", thrust)):
        s = shape_of(v)
        if s is None or len(s) != 1:
            raise VehicleFileError(f"{where}.{key}: expected a list of numbers, got {describe(v)}")
    if len(command) != len(thrust):
        raise VehicleFileError(f"{where}.thrust: expected {len(command)} numbers (one per command), "
                               f"got {len(thrust)}")
    c = ThrusterCurveConfig()
    try:
        c.table = [[float(a), float(b)] for a, b in zip(command, thrust)]
        for key in _CURVE_NUMBERS:
            if key in t:
                v = t[key]
                if isinstance(v, bool) or not isinstance(v, (int, float)):
                    raise VehicleFileError(f"{where}.{key}: expected a number, got {describe(v)}")
                setattr(c, key, float(v))
        c.validate()
    except VehicleFileError:
        raise
    except ValidationError as e:
        # The C++ validator names `thruster_curve.x`: say which key of this file that is.
        file, _, key = where.rpartition(": ")
        field = e.field.replace("thruster_curve.", key + ".", 1)
        at = f"[{e.index}]" if e.index >= 0 else ""
        value = "" if e.value is None else f" = {e.value:.9g}"
        sampled = (f" (the polynomial sampled at {len(command)} commands over command_range)"
                   if "polynomial" in t else "")
        raise VehicleFileError(f"{file + ': ' if file else ''}{field}{at}{value}: expected {e.expected}"
                               f"{sampled}") from None
    except ValueError as e:
        raise VehicleFileError(f"{where}: {e}") from None
    return c


def _curve_rows(t: dict[str, Any], where: str) -> tuple[Any, Any]:
    """The curve's (command, thrust) rows: its table, or its polynomial (thrust =
    sum of polynomial[k] * command^k) sampled at `points` evenly spaced commands
    over command_range (default 256, the most a curve holds), which the C++
    curve then interpolates linearly."""
    if "polynomial" not in t:
        for key in ("command", "thrust"):
            if key not in t:
                raise VehicleFileError(f"{where}: missing field {key!r} (or give 'polynomial' and "
                                       "'command_range')")
        for key in ("command_range", "points"):
            if key in t:
                raise VehicleFileError(f"{where}.{key}: only with 'polynomial'")
        return t["command"], t["thrust"]
    for key in ("command", "thrust"):
        if key in t:
            raise VehicleFileError(f"{where}.{key}: give either 'command' and 'thrust' or "
                                   "'polynomial', not both")
    coefficients, span = t["polynomial"], t.get("command_range")
    if shape_of(coefficients) is None or len(shape_of(coefficients) or ()) != 1:
        raise VehicleFileError(f"{where}.polynomial: expected a list of numbers (lowest order "
                               f"first), got {describe(coefficients)}")
    if shape_of(span) != (2,) or not (span[0] < span[1]):
        raise VehicleFileError(f"{where}.command_range: expected 2 increasing numbers with "
                               f"'polynomial', got {describe(span) if span is not None else None}")
    points = t.get("points", 256)
    if isinstance(points, bool) or not isinstance(points, int) or not 2 <= points <= 256:
        raise VehicleFileError(f"{where}.points: expected an integer from 2 to 256, got {points!r}")
    command = np.linspace(float(span[0]), float(span[1]), points)
    return command.tolist(), np.polynomial.polynomial.polyval(command, coefficients).tolist()


def _check_layout(thrusters: dict[str, Any], where: str) -> None:
    """The layout with its curves through the C++ validator (limits inside the curves)."""
    try:
        ThrusterConfig(matrix=thrusters["matrix"], max_thrust=thrusters["max_thrust"],
                       min_thrust=thrusters["min_thrust"], curves=thrusters["curves"],
                       supply_voltage=thrusters["supply_voltage"]).validate()
    except ValueError as e:
        raise VehicleFileError(f"{where}: {e}") from None
