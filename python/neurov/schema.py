"""One schema: the C++ configuration structs, bound field by field, filled from TOML.

A scenario holds the very objects the core runs on (``SimulationConfig``,
``NNAdaptiveConfig``, ...). Their defaults and their validators are the C++
ones; this module only moves a TOML value into a field, choosing the
conversion by the type of the field's current value, and puts the file and
the TOML key in front of every message, including the C++ validator's::

    square.toml: controller.kd[3] = -1: expected >= 0 and finite

"""

from __future__ import annotations

import difflib
import math
from collections.abc import Iterable
from typing import Any

import numpy as np

from neurov.errors import SchemaError

__all__ = ["SchemaError", "as_dict", "convert", "did_you_mean", "field_names"]


def field_names(obj: Any) -> list[str]:
    """The read-write fields of a bound struct, in declaration order."""
    return [name for name, attr in vars(type(obj)).items()
            if isinstance(attr, property) and attr.fset is not None and not name.startswith("_")]


def did_you_mean(name: str, known: Iterable[str]) -> str:
    """``"; did you mean 'x'?"`` with the closest of `known` to a misspelt
    `name`, or ``""`` if none is close: the one suggestion every reader of
    neurov's files appends to its refusal of an unknown name."""
    close = difflib.get_close_matches(name, sorted(known), n=1)
    return f"; did you mean {close[0]!r}?" if close else ""


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


def as_dict(obj: Any) -> Any:
    """A bound struct as plain data (fields by name, enums by name, arrays as
    lists), recursively: for hashing and printing."""
    if hasattr(type(obj), "__members__"):
        return obj.name
    names = field_names(obj) if not isinstance(obj, (int, float, str, bool, type(None))) else []
    if names:
        return {n: as_dict(getattr(obj, n)) for n in names}
    if isinstance(obj, (list, tuple)):
        return [as_dict(x) for x in obj]
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    return obj
