"""Prints the fields of configuration structs as Markdown tables (field,
default or "required", unit, rule, meaning) from their one description beside each struct
in C++ (config_fields, neurov/core/field_spec.hpp), which the bindings give
as the class's ``FIELDS``. Used by docs/disturbances.md and docs/model.md::

    python tools/field_table.py TetherConfig SteadyForceConfig
"""

from __future__ import annotations

import argparse
import math
from typing import Any

import numpy as np

from neurov import _core


def _value(v: Any) -> str:
    if v is None:
        return "none"
    if hasattr(type(v), "__members__"):
        return str(v.name)
    if isinstance(v, np.ndarray):
        return "(" + ", ".join(f"{x:g}" for x in v.ravel()) + ")" if v.size else "empty"
    if isinstance(v, float):
        return f"{v:g}"
    return str(v)


def table(name: str) -> str:
    """The Markdown table of the bound struct `name` (a class of neurov._core)."""
    cls = getattr(_core, name, None)
    if cls is None or not hasattr(cls, "FIELDS"):
        raise SystemExit(f"field_table.py: {name!r} is not a described struct of neurov._core")
    default = cls()
    rows = [f"| `{name}` field | default | unit | valid | meaning |", "|---|---|---|---|---|"]
    for f in cls.FIELDS:
        rule = f["rule"] or "–"
        if math.isfinite(f["min"]) and math.isfinite(f["max"]):
            rule = f"{f['min']:g} to {f['max']:g}" if not f["rule"] else f"{rule}, {f['min']:g} to {f['max']:g}"
        given = "required" if f["required"] else _value(getattr(default, f["name"]))
        rows.append(f"| `{f['name']}` | {given} | {f['unit'] or '–'} | {rule} "
                    f"| {f['doc'].rstrip('.')} |")
    return "\n".join(rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("structs", nargs="+", help="bound struct names, e.g. TetherConfig")
    args = parser.parse_args()
    print("\n\n".join(table(n) for n in args.structs))


if __name__ == "__main__":
    main()
