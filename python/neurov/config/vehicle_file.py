"""Vehicle files: a vehicle's parameters in TOML.

A file holds the fields of :class:`neurov.VehicleParameters`, read from its
description in C++ (``VehicleParameters.FIELDS``: name, unit, rule, shape; a
square matrix may be given as its diagonal; those ``required`` must be
given; docs/model.md prints them), as TOML numbers, lists and tables (SI units,
body axes x forward, y starboard, z down), and keys of the file alone:
``displaced_volume`` (number, m^3), given instead of ``buoyancy``: the
buoyancy is then rho g V in the scenario's water, see ``water_density``;
``name`` and ``source`` (strings).

An optional ``[thrusters]`` table gives the thruster layout, either as
``positions`` and ``directions`` (n rows of 3 numbers each, body axes; the
configuration matrix column is [d; r x d] for the unit direction d at r,
computed by :func:`neurov._core.allocation_matrix`) or as
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
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from neurov.config.thruster_table import describe, shape_of, shape_text, thrusters_from_mapping
from neurov.errors import VehicleFileError
from neurov.schema import did_you_mean
from neurov.files import PACKAGE_DIR, read_toml
from neurov._core import SimulationConfig, Vehicle, VehicleParameters, buoyancy_in_water

if TYPE_CHECKING:
    import neurov._core

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

# The keys of a file alone -> shapes accepted; () is a number, "str" a string.
_FILE_ONLY: dict[str, tuple[Any, ...]] = {"displaced_volume": ((),), "name": ("str",), "source": ("str",)}


def file_fields(parameters: Any = VehicleParameters) -> dict[str, tuple[bool, tuple[Any, ...]]]:
    """A vehicle file's keys -> (required, shapes accepted): the fields of
    the bound struct `parameters` as its ``FIELDS`` describe them (a number,
    a string by its default, an array of its shape or a square matrix's
    diagonal), then the keys of the file alone. ``buoyancy`` is not
    required: ``displaced_volume`` may give it instead (checked apart)."""
    default = parameters()
    table: dict[str, tuple[bool, tuple[Any, ...]]] = {}
    for f in parameters.FIELDS:
        shape = tuple(f["shape"] or ())
        shapes: tuple[Any, ...] = ((shape[0],), shape) if f["diagonal"] else (shape,)
        if isinstance(getattr(default, f["name"]), str):
            shapes = ("str",)
        table[f["name"]] = (f["required"] and f["name"] != "buoyancy", shapes)
    return table | {key: (False, shapes) for key, shapes in _FILE_ONLY.items()}


_FIELDS = file_fields()
# Tables read apart from the parameters ([thrusters] for the simulation,
# [limits] for neurov.gym's action scale).
_OTHER_TABLES = {"thrusters", "limits"}


def preset_names() -> list[str]:
    """Names of the vehicle files shipped with neurov (e.g. ``"nerov"``)."""
    return sorted(p.stem for p in PRESET_DIR.glob("*.toml"))


def preset_path(name: str) -> Path:
    """Path of a shipped vehicle file by name; ValueError lists the names."""
    path = PRESET_DIR / f"{name}.toml"
    if not path.is_file():
        raise ValueError(f"unknown vehicle preset {name!r}; expected one of {preset_names()}")
    return path


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
    probe = VehicleParameters()
    for key, (required, shapes) in _FIELDS.items():
        if key not in data:
            if required:
                raise VehicleFileError(
                    f"{where}: missing field {key!r} ({' or '.join(map(shape_text, shapes))})"
                )
            continue
        value = data[key]
        expected = " or ".join(map(shape_text, shapes))
        if shapes == ("str",):
            if not isinstance(value, str):
                raise VehicleFileError(
                    f"{where}: field {key!r}: expected {expected}, got {describe(value)}"
                )
        else:
            shape = shape_of(value)
            if shape is None or shape not in shapes:
                got = describe(value) if shape is None else shape_text(shape)
                raise VehicleFileError(f"{where}: field {key!r}: expected {expected}, got {got}")
            bad = [x for x in _flatten(value) if not math.isfinite(x)]
            if bad:
                raise VehicleFileError(f"{where}: field {key!r}: expected finite numbers, got {bad[0]}")
        if key in ("name", "source"):
            continue
        if key not in _FILE_ONLY:
            try:  # the field's own setter: a choice such as coriolis_form's
                setattr(probe, key, value)
            except (TypeError, ValueError) as e:
                raise VehicleFileError(f"{where}: field {key!r}: {e}") from None
        kwargs[key] = value
    if ("buoyancy" in kwargs) == ("displaced_volume" in kwargs):
        raise VehicleFileError(f"{where}: give either 'buoyancy' (N) or 'displaced_volume' (m^3)")
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
    if shape_of(v) != (6,):
        raise VehicleFileError(f"{where}.tau_max: expected 6 numbers, got {describe(v)}")
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
