"""Writing the tables best.toml holds (numbers, strings, booleans, lists of
them, nested tables): the standard library reads TOML but does not write it,
and these tables need nothing more."""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping
from typing import Any

__all__ = ["toml_text"]

_BARE = re.compile(r"^[A-Za-z0-9_-]+$")


def _key(k: str) -> str:
    return k if _BARE.match(k) else json.dumps(k)


def _value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)  # the shortest text that reads back exactly
    if isinstance(v, str):
        return json.dumps(v)  # a TOML basic string accepts JSON's escapes
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if hasattr(v, "item"):  # a NumPy scalar
        return _value(v.item())
    raise TypeError(f"cannot write {type(v).__name__} {v!r} as TOML")


def toml_text(table: Mapping[str, Any], prefix: str = "") -> str:
    """`table` as TOML: its values first, then each sub-table as ``[prefix.key]``."""
    lines = [f"{_key(k)} = {_value(v)}" for k, v in table.items() if not isinstance(v, Mapping)]
    out = "\n".join(lines)
    for k, v in table.items():
        if isinstance(v, Mapping):
            name = f"{prefix}.{_key(k)}" if prefix else _key(k)
            body = toml_text(v, name)
            has_values = any(not isinstance(x, Mapping) for x in v.values())
            out += ("\n\n" if out else "") + (f"[{name}]\n" if has_values or not v else "") + body.strip("\n")
    return out.rstrip("\n") + "\n" if out else ""
