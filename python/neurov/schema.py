"""One schema: the C++ configuration structs, bound field by field, filled from TOML.

A scenario holds the very objects the core runs on (``SimulationConfig``,
``NNAdaptiveConfig``, ...). Their defaults and their validators are the C++
ones; this module only moves a TOML value into a field, choosing the
conversion by the type of the field's current value, and puts the file and
the TOML key in front of every message, including the C++ validator's::

    square.toml: controller.kd[3] = -1: expected >= 0 and finite

It also makes every bound struct copyable and picklable (a study sends its
scenarios to worker processes), from the fields themselves.
"""

from __future__ import annotations

import copyreg
import math
import re
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

__all__ = ["SchemaError", "assign", "field_names", "register_copy", "validated"]


class SchemaError(ValueError):
    """A value that does not fit its field; the message names file and key."""


def field_names(obj: Any) -> list[str]:
    """The read-write fields of a bound struct, in declaration order."""
    return [name for name, attr in vars(type(obj)).items()
            if isinstance(attr, property) and attr.fset is not None and not name.startswith("_")]


def _describe(v: Any) -> str:
    return f"{type(v).__name__} {v!r}"


def _numbers(value: Any, shape: tuple[int, ...], where: str) -> np.ndarray:
    """value as a float array of `shape`; a lone number fills a vector."""
    if len(shape) == 1 and isinstance(value, (int, float)) and not isinstance(value, bool):
        value = [value] * shape[0]
    want = (f"{shape[0]} numbers or one number" if len(shape) == 1
            else f"a {' x '.join(map(str, shape))} table of numbers")
    flat: list[Any] = []

    def collect(v: Any) -> None:
        if isinstance(v, list):
            for x in v:
                collect(x)
        else:
            flat.append(v)

    collect(value)
    if not isinstance(value, list) or any(isinstance(x, bool) or not isinstance(x, (int, float)) for x in flat):
        raise SchemaError(f"{where}: expected {want}, got {_describe(value)}")
    try:
        a = np.asarray(value, dtype=np.float64)
    except ValueError:
        raise SchemaError(f"{where}: expected {want}, got a ragged list") from None
    if a.shape != shape:
        raise SchemaError(f"{where}: expected {want}, got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise SchemaError(f"{where}: expected finite numbers")
    return a


def convert(prototype: Any, value: Any, where: str) -> Any:
    """`value` converted to the kind of `prototype` (the field's current value)."""
    members = getattr(type(prototype), "__members__", None)
    if members is not None:  # a bound C++ enum: by name
        if not isinstance(value, str) or value not in members:
            raise SchemaError(f"{where}: expected one of {sorted(members)}, got {value!r}")
        return members[value]
    if isinstance(prototype, bool):
        if not isinstance(value, bool):
            raise SchemaError(f"{where}: expected true or false, got {_describe(value)}")
        return value
    if isinstance(prototype, int):
        if isinstance(value, bool) or not isinstance(value, int):
            raise SchemaError(f"{where}: expected an integer, got {_describe(value)}")
        return value
    if isinstance(prototype, float):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise SchemaError(f"{where}: expected a number, got {_describe(value)}")
        if not math.isfinite(value):
            raise SchemaError(f"{where}: expected a finite number, got {value}")
        return float(value)
    if isinstance(prototype, np.ndarray):
        shape = prototype.shape
        if any(n == 0 for n in shape) or prototype.ndim == 0:
            # A dynamic-size field not yet filled: any non-empty list of numbers.
            arr = np.asarray(value if isinstance(value, list) else [value], dtype=object)
            shape = arr.shape
        return _numbers(value, tuple(shape), where)
    raise SchemaError(f"{where}: cannot be set from a file")


def assign(obj: Any, table: Mapping[str, Any], where: str, *, keys: Mapping[str, str] | None = None,
           skip: tuple[str, ...] = ()) -> set[str]:
    """Sets obj's fields from `table` (TOML key -> value). `keys` maps a TOML
    key to a field whose name differs (``lambda`` -> ``lambda_``); keys in
    `skip` are left to the caller. Returns the TOML keys used."""
    keys = keys or {}
    names = set(field_names(obj))
    used: set[str] = set()
    for key, value in table.items():
        if key in skip:
            continue
        name = keys.get(key, key)
        if name not in names:
            continue
        setattr(obj, name, convert(getattr(obj, name), value, f"{where}.{key}" if where else key))
        used.add(key)
    return used


_FIELD = re.compile(r"^(?:[\w -]+: )?([A-Za-z_][\w.]*)(\[\d+\])?")


def validated(obj: Any, where: str, *, keys: Mapping[str, str] | None = None) -> Any:
    """obj after its C++ validator; a refusal is re-raised naming `where` and
    the TOML key of the field (`keys` maps field -> TOML key)."""
    try:
        obj.validate()
    except ValueError as e:
        message = str(e)
        m = _FIELD.match(message)
        if m is None:
            raise SchemaError(f"{where}: {message}") from None
        field = m.group(1)
        key = (keys or {}).get(field, field)
        rest = message[m.end(1):]
        prefix = f"{where}." if where and not where.endswith(": ") else where
        raise SchemaError(f"{prefix}{key}{rest}") from None
    return obj


def _rebuild(cls: type, state: dict[str, Any]) -> Any:
    obj = cls()
    for name, value in state.items():
        setattr(obj, name, value)
    return obj


def register_copy(*classes: type) -> None:
    """copy.copy, copy.deepcopy and pickle for bound structs, through their
    fields (nested structs and lists of them follow, each registered too)."""
    for cls in classes:
        reducer: Callable[[Any], tuple[Any, ...]] = (
            lambda obj, cls=cls: (_rebuild, (cls, {n: getattr(obj, n) for n in field_names(obj)})))
        copyreg.pickle(cls, reducer)
