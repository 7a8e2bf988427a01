"""Vehicle files: a vehicle's parameters in TOML.

A file holds these keys (SI units, body axes x forward, y starboard, z down):

``mass`` (number, kg); ``inertia`` (3 numbers, the diagonal, or a 3x3 table);
``weight`` (number, N); ``buoyancy`` (number, N) or ``displaced_volume``
(number, m^3: the buoyancy is then rho g V in the scenario's water, see
``water_density``); ``added_mass`` (6 numbers, the positive
diagonal of M_A, or a 6x6 table); ``linear_damping`` and ``quadratic_damping``
(6 numbers each); optional ``centre_of_gravity`` and ``centre_of_buoyancy``
(3 numbers, m, default zero), ``coriolis_form`` (``"velocity_independent"``, the
default and the paper's eq. 39, or ``"kirchhoff"``), ``name`` and ``source``
(strings).

An optional ``[thrusters]`` table gives the thruster layout, either as
``positions`` and ``directions`` (n rows of 3 numbers each, body axes; the
configuration matrix column is [d; r x d] for a unit direction d at r) or as
an explicit 6 x n ``matrix``; ``max_thrust`` (a number or n numbers, N);
optional ``min_thrust`` (default -max_thrust) and ``time_constant`` (s, a
first-order lag; default 0, none).

Optional ``names`` (n strings) name the thrusters; "port" and "starboard" in
a name must agree with the sign of y (a test checks the shipped files).

A thruster may have a command-to-thrust curve: ``[thrusters.curve]`` (one
curve for every thruster) or ``[[thrusters.curve]]`` (one table per
thruster, n of them), each with ``command`` and ``thrust`` (equally long
lists: commands strictly increasing, e.g. PWM in us; thrust in N at
``reference_voltage``) or a fitted ``polynomial`` (coefficients, lowest order
first, thrust in N) with ``command_range`` (2 numbers) and optional
``points`` (2 to 256, default 256: it is sampled there into a table),
``neutral`` (the command of zero thrust),
``reference_voltage`` (V), and optional ``dead_band`` (command units, default
0), ``voltage_exponent`` (default 2), ``time_constant`` (s) and ``slew_rate``
(N/s, default 0: none). With curves, ``[thrusters]`` needs ``supply_voltage``
(V); ``max_thrust`` and ``min_thrust`` become optional (default: what the
curve gives at its ends at that voltage) and ``time_constant`` belongs to the
curves.

An optional ``[limits]`` table states what a vehicle without a thruster
layout can produce: ``tau_max`` (6 positive numbers, N and N m), the largest
force or moment each DOF can get alone (the Gymnasium environment scales its
actions by it).

Every error names the file and the field.
"""

from __future__ import annotations

import math
import os
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from neurov.errors import ValidationError, VehicleFileError
from neurov.schema import did_you_mean
from neurov.files import PACKAGE_DIR, read_text, read_toml
from neurov._core import SimulationConfig, ThrusterConfig, ThrusterCurveConfig, Vehicle, buoyancy_in_water

if TYPE_CHECKING:
    import neurov._core

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on Python 3.10 only
    import tomli as tomllib

__all__ = [
    "VehicleFile",
    "VehicleFileError",
    "load_limits",
    "load_thrusters",
    "load_vehicle",
    "load_vehicle_parameters",
    "preset_names",
    "preset_path",
    "read_vehicle_file",
]

PRESET_DIR = PACKAGE_DIR / "vehicles"

# key -> (required, shapes accepted); () is a number, "str" a string.
_FIELDS: dict[str, tuple[bool, tuple[Any, ...]]] = {
    "mass": (True, ((),)),
    "inertia": (True, ((3,), (3, 3))),
    "weight": (True, ((),)),
    "buoyancy": (False, ((),)),
    "displaced_volume": (False, ((),)),
    "added_mass": (True, ((6,), (6, 6))),
    "linear_damping": (True, ((6,),)),
    "quadratic_damping": (True, ((6,),)),
    "centre_of_gravity": (False, ((3,),)),
    "centre_of_buoyancy": (False, ((3,),)),
    "coriolis_form": (False, ("str",)),
    "name": (False, ("str",)),
    "source": (False, ("str",)),
}
# Tables read apart from the parameters ([thrusters] for the simulation,
# [limits] for neurov.gym's action scale).
_OTHER_TABLES = {"thrusters", "limits"}
_CORIOLIS_FORMS = ("velocity_independent", "kirchhoff")


def preset_names() -> list[str]:
    """Names of the vehicle files shipped with neurov (e.g. ``"nerov"``)."""
    return sorted(p.stem for p in PRESET_DIR.glob("*.toml"))


def preset_path(name: str) -> Path:
    """Path of a shipped vehicle file by name; ValueError lists the names."""
    path = PRESET_DIR / f"{name}.toml"
    if not path.is_file():
        raise ValueError(f"unknown vehicle preset {name!r}; expected one of {preset_names()}")
    return path


def _describe(value: Any) -> str:
    if isinstance(value, list):
        return "a list that is not all numbers (or not rectangular)"
    if isinstance(value, dict):
        return "a table"
    return f"{type(value).__name__} {value!r}"


def _shape_of(value: Any) -> tuple[int, ...] | None:
    """Shape of a number or a rectangular nested list of numbers, else None."""
    if isinstance(value, bool):
        return None
    if isinstance(value, (int, float)):
        return ()
    if isinstance(value, list) and value:
        inner = [_shape_of(v) for v in value]
        if all(s is not None and s == inner[0] for s in inner):
            return (len(value), *inner[0])  # type: ignore[misc]
    return None


def _shape_text(shape: Any) -> str:
    if shape == ():
        return "a number"
    if shape == "str":
        return "a string"
    if len(shape) == 1:
        return f"a list of {shape[0]} number{'s' if shape[0] != 1 else ''}"
    return f"a {shape[0]}x{shape[1]} table of numbers"


@dataclass(frozen=True)
class VehicleFile:
    """A vehicle file read and checked whole, once: its path, the keyword
    arguments of :class:`neurov.Vehicle` and its ``[thrusters]`` table (None
    when it has none). A scenario keeps one, so nothing reads the file again."""

    path: Path
    parameters: dict[str, Any]
    thrusters: dict[str, Any] | None
    displaced_volume: float | None = None
    """[m^3] when the file gives it: the buoyancy follows the water."""
    tau_max: Any = None
    """``[limits] tau_max`` as a (6,) array, or None when the file has no
    ``[limits]`` table."""

    def in_water(self, water_density: float) -> VehicleFile:
        """The file as the vehicle is in water of `water_density` [kg/m^3]:
        itself when it gives its buoyancy, else a copy whose buoyancy is
        :func:`neurov._core.buoyancy_in_water` of its displaced volume."""
        if self.displaced_volume is None:
            return self
        from dataclasses import replace

        try:
            b = buoyancy_in_water(water_density, self.displaced_volume)
        except ValueError as e:
            raise VehicleFileError(f"{self.path}: {e}") from None
        return replace(self, parameters={**self.parameters, "buoyancy": b})

    def vehicle(self, overrides: dict[str, Any] | None = None) -> Any:
        """The vehicle, with some parameters overridden (a perturbed plant)."""
        try:
            return Vehicle(**{**self.parameters, **(overrides or {})})
        except ValueError as e:
            raise VehicleFileError(f"{self.path}: {e}") from None


def read_vehicle_file(path: str | Path) -> VehicleFile:
    """Reads and checks every table of a vehicle file, ``[thrusters]``
    included whether or not a scenario uses it (a typo there is an error
    today, not on the day thrusters are switched on). Raises
    :class:`VehicleFileError` naming the file and the field."""
    path = Path(path)
    where = str(path)
    data = read_toml(path, VehicleFileError, "vehicle")
    parameters = parameters_from_mapping(data, where)
    volume = parameters.pop("displaced_volume", None)
    table = data.get("thrusters")
    thrusters = None if table is None else thrusters_from_mapping(table, f"{where}: thrusters")
    file = VehicleFile(path=path, parameters=parameters, thrusters=thrusters,
                       displaced_volume=None if volume is None else float(volume),
                       tau_max=_limits_from_mapping(data.get("limits"), f"{where}: limits"))
    if volume is None:
        return file
    # Standing alone (Vehicle.from_file, a preset), the vehicle is in the
    # default water of a run; a scenario puts it in its own.
    return file.in_water(SimulationConfig().water_density)


def load_vehicle_parameters(path: str | Path) -> dict[str, Any]:
    """The keyword arguments of :class:`neurov.Vehicle` from a vehicle file
    (the whole file is checked). Raises :class:`VehicleFileError`."""
    return read_vehicle_file(path).parameters


def parameters_from_mapping(data: dict[str, Any], where: str) -> dict[str, Any]:
    """Checks a vehicle table already parsed (e.g. inline in a scenario file)."""
    for key in data:
        if key in _FIELDS or key in _OTHER_TABLES:
            continue
        hint = did_you_mean(key, list(_FIELDS))
        raise VehicleFileError(f"{where}: unknown field {key!r}{hint}")
    kwargs: dict[str, Any] = {}
    for key, (required, shapes) in _FIELDS.items():
        if key not in data:
            if required:
                raise VehicleFileError(
                    f"{where}: missing field {key!r} ({' or '.join(map(_shape_text, shapes))})"
                )
            continue
        value = data[key]
        expected = " or ".join(map(_shape_text, shapes))
        if shapes == ("str",):
            if not isinstance(value, str):
                raise VehicleFileError(
                    f"{where}: field {key!r}: expected {expected}, got {_describe(value)}"
                )
        else:
            shape = _shape_of(value)
            if shape is None or shape not in shapes:
                got = _describe(value) if shape is None else _shape_text(shape)
                raise VehicleFileError(f"{where}: field {key!r}: expected {expected}, got {got}")
            bad = [x for x in _flatten(value) if not math.isfinite(x)]
            if bad:
                raise VehicleFileError(f"{where}: field {key!r}: expected finite numbers, got {bad[0]}")
        if key in ("name", "source"):
            continue
        kwargs[key] = value
    if ("buoyancy" in kwargs) == ("displaced_volume" in kwargs):
        raise VehicleFileError(f"{where}: give either 'buoyancy' (N) or 'displaced_volume' (m^3)")
    form = kwargs.get("coriolis_form", "velocity_independent")
    if form not in _CORIOLIS_FORMS:
        raise VehicleFileError(
            f"{where}: field 'coriolis_form': expected one of {list(_CORIOLIS_FORMS)}, got {form!r}"
        )
    return kwargs


def _flatten(value: Any) -> list[Any]:
    if isinstance(value, list):
        return [x for v in value for x in _flatten(v)]
    return [value]


def load_vehicle(path: str | Path) -> Any:
    """Builds a :class:`neurov.Vehicle` from a file. A non-physical value (for
    example a negative mass) raises :class:`VehicleFileError` naming the file
    and the field."""
    return read_vehicle_file(path).vehicle()


def load_limits(path: str | Path) -> Any:
    """``tau_max`` of a vehicle file's ``[limits]`` table as a (6,) array, or
    None if the file has no such table. Errors name the file and the field."""
    return read_vehicle_file(path).tau_max


def _limits_from_mapping(table: Any, where: str) -> Any:
    import numpy as np

    if table is None:
        return None
    if not isinstance(table, dict):
        raise VehicleFileError(f"{where}: expected a table")
    for key in table:
        if key != "tau_max":
            raise VehicleFileError(f"{where}.{key}: unknown field (the table holds 'tau_max')")
    if "tau_max" not in table:
        raise VehicleFileError(f"{where}: missing field 'tau_max' (6 positive numbers)")
    v = table["tau_max"]
    if _shape_of(v) != (6,):
        raise VehicleFileError(f"{where}.tau_max: expected 6 numbers, got {_describe(v)}")
    a = np.asarray(v, dtype=np.float64)
    if not np.all(np.isfinite(a) & (a > 0)):
        raise VehicleFileError(f"{where}.tau_max: expected 6 finite numbers > 0, got {a.tolist()}")
    return a


def load_thrusters(path: str | Path) -> dict[str, Any] | None:
    """The ``[thrusters]`` table of a vehicle file as arrays (``matrix``
    (6, n), ``max_thrust``, ``min_thrust`` (n,), ``time_constant``, ``curves``
    (n ThrusterCurveConfig, or None), ``supply_voltage``, ``names`` (or
    None) and ``positions`` ((n, 3), or None for a file that gives a
    ``matrix``)), or None if the
    file has none. With curves, absent limits are the curves' thrust at their
    end commands. Errors name the file and the field."""
    return read_vehicle_file(path).thrusters


def thrusters_from_mapping(table: Any, where: str) -> dict[str, Any]:
    """Checks a ``[thrusters]`` table already parsed; `where` prefixes errors."""
    import numpy as np

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
        s = _shape_of(v)
        if s is None or (shape is not None and s != shape) or len(s) < 1:
            raise VehicleFileError(f"{where}.{key}: expected {_shape_text(shape) if shape else 'a table of numbers'}, got {_describe(v) if s is None else s}")
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
        dirs = dirs / norms[:, None]
        matrix = np.vstack([dirs.T, np.cross(pos, dirs).T])
    n = matrix.shape[1]
    names = table.get("names")
    if names is not None and not (isinstance(names, list) and len(names) == n
                                  and all(isinstance(x, str) for x in names)):
        raise VehicleFileError(f"{where}.names: expected {n} strings (one per thruster), got "
                               f"{_describe(names)}")
    curves = _curves(table, n, where) if "curve" in table else None
    if "supply_voltage" in table and curves is None:
        raise VehicleFileError(f"{where}.supply_voltage: only with a [thrusters.curve]")
    if "max_thrust" not in table and curves is None:
        raise VehicleFileError(f"{where}: missing field 'max_thrust' (or give a [thrusters.curve])")

    def limits(key: str) -> Any:
        v = table[key]
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            v = [v] * n
        if _shape_of(v) != (n,):
            raise VehicleFileError(f"{where}.{key}: expected a number or {n} numbers, got {_describe(v)}")
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


_CURVE_KEYS = {"command": False, "thrust": False, "polynomial": False, "command_range": False,
               "points": False, "neutral": True, "reference_voltage": True, "dead_band": False,
               "voltage_exponent": False, "time_constant": False, "slew_rate": False}


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
                               f"[[thrusters.curve]], got {_describe(raw)}")
    built: dict[int, Any] = {}
    return [built.setdefault(id(t), _curve(t, w)) for w, t in items]


def _curve(t: dict[str, Any], where: str) -> Any:
    for key in t:
        if key not in _CURVE_KEYS:
            hint = did_you_mean(key, list(_CURVE_KEYS))
            raise VehicleFileError(f"{where}.{key}: unknown field{hint}")
    for key, required in _CURVE_KEYS.items():
        if required and key not in t:
            raise VehicleFileError(f"{where}: missing field {key!r}")
    command, thrust = _curve_rows(t, where)
    for key, v in (("command", command), ("thrust", thrust)):
        s = _shape_of(v)
        if s is None or len(s) != 1:
            raise VehicleFileError(f"{where}.{key}: expected a list of numbers, got {_describe(v)}")
    if len(command) != len(thrust):
        raise VehicleFileError(f"{where}.thrust: expected {len(command)} numbers (one per command), "
                               f"got {len(thrust)}")
    c = ThrusterCurveConfig()
    try:
        c.table = [[float(a), float(b)] for a, b in zip(command, thrust)]
        for key in ("neutral", "reference_voltage", "dead_band", "voltage_exponent", "time_constant",
                    "slew_rate"):
            if key in t:
                v = t[key]
                if isinstance(v, bool) or not isinstance(v, (int, float)):
                    raise VehicleFileError(f"{where}.{key}: expected a number, got {_describe(v)}")
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
    import numpy as np

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
    if _shape_of(coefficients) is None or len(_shape_of(coefficients) or ()) != 1:
        raise VehicleFileError(f"{where}.polynomial: expected a list of numbers (lowest order "
                               f"first), got {_describe(coefficients)}")
    if _shape_of(span) != (2,) or not (span[0] < span[1]):
        raise VehicleFileError(f"{where}.command_range: expected 2 increasing numbers with "
                               f"'polynomial', got {_describe(span) if span is not None else None}")
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


def _attach_file_constructors() -> None:
    """``Vehicle.from_file`` and ``Vehicle.preset`` read files, which is this
    package's work: they are attached here so that the compiled core never
    imports the Python package."""
    # Annotated with importable names: the stub of neurov._core is generated
    # from these functions too (tools/generate_stubs.py).
    def from_file(path: str | os.PathLike[str]) -> neurov._core.Vehicle:
        """Loads a vehicle TOML file (format: :mod:`neurov.config.vehicle_file`). A
        missing, misspelt or wrongly typed field raises
        :class:`neurov.VehicleFileError` naming the file and the field."""
        return load_vehicle(path)

    def preset(name: str) -> neurov._core.Vehicle:
        """A vehicle shipped with neurov by name: ``'nerov'`` or
        ``'bluerov2_heavy'`` (:func:`preset_names` lists them)."""
        return load_vehicle(preset_path(name))

    Vehicle.from_file = staticmethod(from_file)
    Vehicle.preset = staticmethod(preset)


_attach_file_constructors()
