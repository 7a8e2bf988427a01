"""Vehicle files: a vehicle's parameters in TOML.

A file holds these keys (SI units, body axes x forward, y starboard, z down):

``mass`` (number, kg); ``inertia`` (3 numbers, the diagonal, or a 3x3 table);
``weight`` and ``buoyancy`` (numbers, N); ``added_mass`` (6 numbers, the positive
diagonal of M_A, or a 6x6 table); ``linear_damping`` and ``quadratic_damping``
(6 numbers each); optional ``centre_of_gravity`` and ``centre_of_buoyancy``
(3 numbers, m, default zero), ``coriolis_form`` (``"velocity_independent"``, the
default and the paper's eq. 39, or ``"kirchhoff"``), ``name`` and ``source``
(strings). Further tables (such as ``[thrusters]``) belong to other readers.

Every error names the file and the field.
"""

from __future__ import annotations

import difflib
import math
import sys
from pathlib import Path
from typing import Any

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on Python 3.10 only
    import tomli as tomllib

__all__ = [
    "VehicleFileError",
    "load_vehicle",
    "load_vehicle_parameters",
    "preset_names",
    "preset_path",
]

PRESET_DIR = Path(__file__).with_name("vehicles")

# key -> (required, shapes accepted); () is a number, "str" a string.
_FIELDS: dict[str, tuple[bool, tuple[Any, ...]]] = {
    "mass": (True, ((),)),
    "inertia": (True, ((3,), (3, 3))),
    "weight": (True, ((),)),
    "buoyancy": (True, ((),)),
    "added_mass": (True, ((6,), (6, 6))),
    "linear_damping": (True, ((6,),)),
    "quadratic_damping": (True, ((6,),)),
    "centre_of_gravity": (False, ((3,),)),
    "centre_of_buoyancy": (False, ((3,),)),
    "coriolis_form": (False, ("str",)),
    "name": (False, ("str",)),
    "source": (False, ("str",)),
}
# Tables other readers own (the simulation reads [thrusters]).
_OTHER_TABLES = {"thrusters"}
_CORIOLIS_FORMS = ("velocity_independent", "kirchhoff")


class VehicleFileError(ValueError):
    """A vehicle file that cannot be read: names the file and the field."""


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
    return f"{type(value).__name__} {value!r}" if not isinstance(value, (list, dict)) else (
        type(value).__name__
    )


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
        return f"a list of {shape[0]} numbers"
    return f"a {shape[0]}x{shape[1]} table of numbers"


def load_vehicle_parameters(path: str | Path) -> dict[str, Any]:
    """Reads and checks a vehicle file; returns the keyword arguments of
    :class:`neurov.Vehicle`. Raises :class:`VehicleFileError`."""
    path = Path(path)
    where = str(path)
    try:
        with path.open("rb") as f:
            data = tomllib.load(f)
    except FileNotFoundError:
        raise VehicleFileError(f"{where}: no such vehicle file") from None
    except tomllib.TOMLDecodeError as e:
        raise VehicleFileError(f"{where}: not valid TOML: {e}") from None
    return parameters_from_mapping(data, where)


def parameters_from_mapping(data: dict[str, Any], where: str) -> dict[str, Any]:
    """Checks a vehicle table already parsed (e.g. inline in a scenario file)."""
    for key in data:
        if key in _FIELDS or key in _OTHER_TABLES:
            continue
        close = difflib.get_close_matches(key, list(_FIELDS), n=1)
        hint = f"; did you mean {close[0]!r}?" if close else ""
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
    from neurov._core import Vehicle

    kwargs = load_vehicle_parameters(path)
    try:
        return Vehicle(**kwargs)
    except ValueError as e:
        raise VehicleFileError(f"{path}: {e}") from None
