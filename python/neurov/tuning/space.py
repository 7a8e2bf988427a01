"""The search space of one controller: the values a trial suggests, and the
controller table (as a study file's ``[controllers.KEY]``) they make."""

from __future__ import annotations

import copy
from collections.abc import Mapping, Sequence
from typing import Any

from neurov.tuning.spec import SearchParameter

__all__ = ["apply_values", "suggest", "vehicle_tables"]


def vehicle_tables(table: Mapping[str, Any]) -> list[str]:
    """The keys of a controller table's per-vehicle sub-tables (a study
    file's convention: every sub-table but ``centres`` and ``search``)."""
    return [k for k, v in table.items() if isinstance(v, Mapping) and k not in ("centres", "search")]


def suggest(trial: Any, params: Sequence[SearchParameter]) -> dict[str, Any]:
    """The values of an Optuna trial, by search key."""
    out: dict[str, Any] = {}
    for p in params:
        if p.kind == "choices":
            out[p.key] = trial.suggest_categorical(p.key, list(p.choices))
        elif p.integer:
            out[p.key] = trial.suggest_int(p.key, int(p.low), int(p.high), log=p.log)
        else:
            out[p.key] = trial.suggest_float(p.key, p.low, p.high, log=p.log)
    return out


def _places(table: dict[str, Any], name: str) -> list[dict[str, Any]]:
    """The tables (the common one, then each vehicle's) that give `name`."""
    return [t for t in [table, *(table[v] for v in vehicle_tables(table))] if name in t]


def apply_values(table: Mapping[str, Any], params: Sequence[SearchParameter],
                 values: Mapping[str, Any]) -> dict[str, Any]:
    """A copy of the controller table with the searched values in place: a
    scale multiplies the vector wherever the table gives it (each vehicle's
    own gains keep their proportions), a range or a choice sets the value
    there (or in the common table when no table gives it)."""
    out = copy.deepcopy(dict(table))
    out.pop("search", None)
    for p in params:
        v = values[p.key]
        name = p.path[-1]
        if len(p.path) > 1:
            # A sub-table: the network's centres, a factory's arguments.
            sub = out.setdefault(p.path[0], {})
            for part in p.path[1:-1]:
                sub = sub.setdefault(part, {})
            places = [sub]
        else:
            places = [out[p.vehicle]] if p.vehicle is not None else (_places(out, name) or [out])
        for t in places:
            # A vehicle's own table may leave the field to the common one
            # (the reader checked that one of them gives it).
            base = t[name] if name in t else out.get(name, [])
            if p.kind == "scale":
                t[name] = [float(x) * float(v) for x in base]
            elif p.index is not None:
                vec = list(base)
                vec[p.index] = v
                t[name] = vec
            else:
                t[name] = v
    return out


def hand_set_values(table: Mapping[str, Any], params: Sequence[SearchParameter]) -> dict[str, Any] | None:
    """The values of the search that give the controller's table as written
    (a factor of 1, the table's own value, its own choice), or None where
    one of them is not in its range or not given."""
    out: dict[str, Any] = {}
    for p in params:
        if p.kind == "scale":
            v: Any = 1.0
        else:
            t = table[p.vehicle] if p.vehicle is not None else table
            for part in p.path[:-1]:
                t = t.get(part, {}) if isinstance(t, Mapping) else {}
            v = t.get(p.path[-1], table.get(p.path[-1]) if len(p.path) == 1 else None)
            if p.index is not None and isinstance(v, list) and p.index < len(v):
                v = v[p.index]
        if p.kind == "choices":
            if v not in p.choices:
                return None
        elif isinstance(v, bool) or not isinstance(v, (int, float)) or not p.low <= float(v) <= p.high:
            return None
        out[p.key] = int(v) if p.integer else v
    return out
