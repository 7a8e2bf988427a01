"""One table of a TOML file read key by key, each error naming the file and
``where.key`` (:class:`TableReader`), a bound C++ struct filled from a table
by the fields its description lists (:func:`fill`, :func:`read_struct`), and a
C++ validator's refusal turned into the same kind of error (:func:`validated`). The readers of scenarios
(:mod:`neurov.config.reading`, :mod:`neurov.config.sea`), studies and
tunings all read through these."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov.errors import ScenarioError, ValidationError
from neurov.schema import SchemaError, convert, did_you_mean

__all__ = ["TableReader", "fill", "read_struct", "tables", "validated"]


class TableReader:
    """Reads one table of a scenario, naming `where.field` in every error."""

    def __init__(self, table: Mapping[str, Any], where: str, origin: str) -> None:
        if not isinstance(table, Mapping):
            raise ScenarioError(f"{origin}: {where}: expected a table, got {type(table).__name__}")
        self.table = table
        self.where = where
        self.origin = origin
        # Every key asked for, present or not: finish() suggests from these.
        self.used: set[str] = set()

    def _name(self, key: str) -> str:
        return f"{self.where}.{key}" if self.where else key

    def error(self, key: str, message: str) -> ScenarioError:
        return ScenarioError(f"{self.origin}: {self._name(key)}: {message}")

    def has(self, key: str) -> bool:
        self.used.add(key)
        return key in self.table

    def raw(self, key: str, default: Any = None) -> Any:
        self.used.add(key)
        return self.table.get(key, default)

    def _lookup(self, key: str, default: Any, expected: str) -> tuple[bool, Any]:
        """(True, the value) when the table has `key`; else (False, the
        default), or an error naming what was `expected` without one."""
        self.used.add(key)
        if key in self.table:
            return True, self.table[key]
        if default is None:
            raise self.error(key, f"missing (expected {expected})")
        return False, default

    def number(self, key: str, default: float | None = None, *, minimum: float | None = None,
               positive: bool = False) -> float:
        found, v = self._lookup(key, default, "a number")
        if not found:
            return v
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise self.error(key, f"expected a number, got {type(v).__name__} {v!r}")
        v = float(v)
        if not math.isfinite(v):
            raise self.error(key, f"expected a finite number, got {v}")
        if positive and not v > 0:
            raise self.error(key, f"expected a number > 0, got {v}")
        if minimum is not None and v < minimum:
            raise self.error(key, f"expected a number >= {minimum}, got {v}")
        return v

    def integer(self, key: str, default: int | None = None, *, minimum: int = 0,
                maximum: tuple[int, str] | None = None) -> int:
        """`maximum`: a count's bound and its name, checked before the
        count is used (it would not fit a C++ int, or would allocate)."""
        found, v = self._lookup(key, default, "an integer")
        if not found:
            return v
        if isinstance(v, bool) or not isinstance(v, int):
            raise self.error(key, f"expected an integer, got {type(v).__name__} {v!r}")
        if v < minimum:
            raise self.error(key, f"expected an integer >= {minimum}, got {v}")
        if maximum is not None and v > maximum[0]:
            raise self.error(key, f"expected an integer <= {maximum[0]} ({maximum[1]}), got {v}")
        return v

    def string(self, key: str, default: str | None = None, choices: Sequence[str] | None = None) -> str:
        found, v = self._lookup(key, default, "a string")
        if not found:
            return v
        if not isinstance(v, str):
            raise self.error(key, f"expected a string, got {type(v).__name__} {v!r}")
        if choices is not None and v not in choices:
            raise self.error(key, f"expected one of {list(choices)}, got {v!r}")
        return v

    def boolean(self, key: str, default: bool) -> bool:
        self.used.add(key)
        if key not in self.table:
            return default
        v = self.raw(key)
        if not isinstance(v, bool):
            raise self.error(key, f"expected true or false, got {type(v).__name__} {v!r}")
        return v

    def array(self, key: str, length: int | None, default: Any = None, *, non_negative: bool = False,
              positive: bool = False, broadcast: bool = True) -> NDArray[np.float64]:
        """A list of `length` numbers (or, with broadcast, one number for all)."""
        found, v = self._lookup(key, default, f"{length} numbers")
        if not found:
            return np.array(v, dtype=np.float64)
        want = f"{length} numbers" + (" or one number" if broadcast else "") if length else "numbers"
        if broadcast and length and isinstance(v, (int, float)) and not isinstance(v, bool):
            v = [v] * length
        if not isinstance(v, list) or any(isinstance(x, bool) or not isinstance(x, (int, float)) for x in v):
            raise self.error(key, f"expected {want}, got {type(v).__name__} {v!r}")
        a = np.asarray(v, dtype=np.float64)
        if length is not None and a.shape != (length,):
            raise self.error(key, f"expected {want}, got {len(v)}")
        if not np.all(np.isfinite(a)):
            raise self.error(key, "expected finite numbers")
        if non_negative and np.any(a < 0):
            raise self.error(key, f"expected numbers >= 0, got {v}")
        if positive and np.any(a <= 0):
            raise self.error(key, f"expected numbers > 0, got {v}")
        return a

    def table_of(self, key: str) -> TableReader:
        v = self.raw(key, {})
        return TableReader(v, self._name(key), self.origin)

    def finish(self, allowed_extra: Sequence[str] = ()) -> None:
        """Unknown keys are errors (a misspelt field must not be ignored)."""
        known = self.used | set(allowed_extra)
        for key in self.table:
            if key not in known:
                hint = did_you_mean(key, sorted(known))
                raise self.error(key, f"unknown field{hint}")


def validated(config: Any, origin: str, keys: Mapping[str, str], lists: Sequence[str] = ()) -> None:
    """Runs the config's C++ validator; its refusal comes back naming the
    file and the TOML key (`keys`: config field -> TOML key; for the `lists`
    of tables, ``name.field[i]`` reads ``name[i].field``)."""
    try:
        config.validate()
    except ValidationError as e:
        name, index = e.field, (e.index if e.index >= 0 else None)
        head, _, sub = name.partition(".")
        if head in lists and index is not None:
            key = f"{keys.get(head, head)}[{index}]" + (f".{sub}" if sub else "")
        else:
            key = keys.get(name, name) + (f"[{index}]" if index is not None else "")
        value = "" if e.value is None else f" = {e.value:.9g}"
        raise ScenarioError(f"{origin}: {key}{value}: expected {e.expected}") from None


def tables(r: TableReader, key: str) -> list[TableReader]:
    items = r.raw(key, [])
    if not isinstance(items, list):
        raise r.error(key, f"expected an array of tables [[{key}]]")
    return [TableReader(t, f"{key}[{k}]", r.origin) for k, t in enumerate(items)]


def fill(r: TableReader, target: Any) -> None:
    """Every field of the bound struct `target` that the table gives, under
    the field's own name, converted by the kind of the field's default; an
    empty optional vector by its described length, a count within its
    described maximum (a larger one would not reach the validator)."""
    for field in type(target).FIELDS:
        key = field["name"]
        if not r.has(key):
            continue
        current = getattr(target, key)
        try:
            if current is None and field["shape"] is not None:
                value: Any = r.array(key, field["shape"][0], broadcast=False)
            else:
                value = convert(current, r.raw(key), r._name(key))
                if isinstance(value, int) and not isinstance(value, bool) and value > field["max"]:
                    raise r.error(key, f"expected an integer <= {field['max']:.0f}, got {value}")
            setattr(target, key, value)
        except SchemaError as e:
            raise ScenarioError(f"{r.origin}: {e}") from None
        except (TypeError, ValueError, OverflowError) as e:
            if isinstance(e, ScenarioError):
                raise
            raise r.error(key, str(e)) from None


def read_struct(r: TableReader, kind: Any) -> Any:
    """A new bound struct `kind` with the fields table `r` gives (:func:`fill`);
    any other key of the table is refused (:meth:`TableReader.finish`)."""
    value = kind()
    fill(r, value)
    r.finish()
    return value
