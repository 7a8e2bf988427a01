"""A CSV of the user's own, read through a mapping file
(:mod:`neurov.identification.mapping`): the named columns, in SI units and
neurov's frames. A column the mapping names and the file lacks is an error
naming both.

Several files with their own clocks: a signal table may name its own
``file`` (relative to the log's folder) and ``time`` column; it is joined
onto the log's clock by ``join`` = ``"hold"`` (default: its latest sample at
or before each row, the zero-order hold of a command) or ``"interpolate"``
(linear between the samples either side), cut where its nearest sample is
older than ``max_age``. Both clocks must count from the same origin (a
``time.offset`` in seconds is added to a file's stamps to make them so).

Irregular sampling (``resample = "auto"``, the default, where more than 1 %
of the steps are gaps by the GAP_FACTOR rule yet shorter than ``max_age``):
the rows are resampled onto a uniform clock at the median step, the pose
and velocity interpolated linearly (angles unwrapped), the force held;
longer gaps stay gaps. ``resample = "off"`` keeps the rows as they are."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov.identification.alignment import hold
from neurov.identification.errors import LogError
from neurov.memory import check_csv_fits
from neurov.identification.log import GAP_FACTOR, Log, make_log
from neurov.identification.mapping import UNITS, Mapping, to_neurov_frames

__all__ = ["read_mapped_csv", "resample_by_mapping", "resample_uniform"]

Array = NDArray[np.float64]


def _frame(path: Path) -> Any:
    import pandas as pd

    if not path.is_file():
        raise LogError(f"{path}: no such file")
    check_csv_fits(path, LogError)  # a file too large for memory refused before pandas reads it
    try:
        return pd.read_csv(path)
    except (ValueError, OSError) as e:
        raise LogError(f"{path}: not a readable CSV: {e}") from None


def _time(frame: Any, spec: Any, path: Path, where: str) -> Array:
    if not isinstance(spec, dict) or not isinstance(spec.get("column"), str):
        raise LogError(f"{where}: time: expected a table {{ column = \"...\", unit = \"s\" }}")
    unit = spec.get("unit", "s")
    if unit not in UNITS["time"]:
        raise LogError(f"{where}: time.unit: expected one of {list(UNITS['time'])}, got {unit!r}")
    offset = spec.get("offset", 0.0)
    if isinstance(offset, bool) or not isinstance(offset, (int, float)):
        raise LogError(f"{where}: time.offset: expected seconds, got {offset!r}")
    if spec["column"] not in frame.columns:
        raise LogError(f"{path}: missing column {spec['column']!r} that {where} names for time")
    return frame[spec["column"]].to_numpy(dtype=np.float64) * UNITS["time"][unit] + float(offset)


def _interpolate(base: Array, t: Array, values: Array, max_age: float, where: str) -> Array:
    hold(base, t, values[:, :1], max_age, where)  # checks the stamps
    out = np.column_stack([np.interp(base, t, values[:, k]) for k in range(values.shape[1])])
    k = np.clip(np.searchsorted(t, base), 1, len(t) - 1)
    near = np.minimum(np.abs(base - t[k - 1]), np.abs(t[k] - base))
    out[(base < t[0]) | (base > t[-1]) | (near > max_age)] = np.nan
    return out


def resample_uniform(t: Array, eta: Array, nu: Array, tau: Array, max_age: float) -> tuple[Array, ...] | None:
    """The rows on a uniform clock at the median step (None where the
    sampling is regular enough): pose (angles unwrapped) and velocity
    interpolated linearly, force held; rows farther than `max_age` from any
    sample are NaN (gaps stay gaps)."""
    ok = np.isfinite(t)
    t, eta, nu, tau = t[ok], eta[ok], nu[ok], tau[ok]
    steps = np.diff(t)
    if len(steps) < 2:
        return None
    dt = float(np.median(steps))
    irregular = (steps > GAP_FACTOR * dt) & (steps <= max_age)
    if dt <= 0 or irregular.mean() <= 0.01:
        return None
    grid = t[0] + dt * np.arange(int(np.floor((t[-1] - t[0]) / dt)) + 1)
    e = eta.copy()
    e[:, 3:] = np.unwrap(e[:, 3:], axis=0)
    e2 = _interpolate(grid, t, e, max_age, "resample")
    e2[:, 3:] = (e2[:, 3:] + np.pi) % (2 * np.pi) - np.pi
    return (grid, e2, _interpolate(grid, t, nu, max_age, "resample"), hold(grid, t, tau, max_age, "resample"),
            np.array([steps.min(), steps.max(), dt]))


def resample_by_mapping(t: Array, eta: Array, nu: Array, tau: Array,
                        mapping: Mapping) -> tuple[Array, Array, Array, Array, list[str]]:
    """The rows resampled as the mapping's ``resample`` says (``"auto"``,
    the default: where the sampling is irregular, :func:`resample_uniform`;
    ``"off"``: as they are), with the note saying the rule used."""
    mode = mapping.data.get("resample", "auto")
    if mode not in ("auto", "off"):
        raise LogError(f"{mapping.where}: resample: expected 'auto' or 'off', got {mode!r}")
    if mode == "auto" and np.all(np.diff(t[np.isfinite(t)]) > 0):
        done = resample_uniform(t, eta, nu, tau, mapping.max_age)
    else:
        done = None  # a clock going backwards is refused by make_log, naming the row
    if done is None:
        return t, eta, nu, tau, []
    t, eta, nu, tau, (lo, hi, dt) = done
    return t, eta, nu, tau, [f"irregular sampling (steps {lo:.3g} to {hi:.3g} s): resampled to {1 / dt:.3g} Hz "
                             "(the median step), pose and velocity interpolated linearly, force held; gaps "
                             f"over {mapping.max_age:g} s (max_age) kept"]


def read_mapped_csv(path: str | Path, mapping: Mapping) -> Log:
    path = Path(path)
    frame = _frame(path)
    mapping.time()  # checked as before
    base = _time(frame, mapping.data["time"], path, mapping.where)
    notes: list[str] = []
    signals = {}
    for name in ("eta", "nu", "tau"):
        cols, factors = mapping.signal(name)
        spec = mapping.data["signals"][name]
        own = path if "file" not in spec else path.parent / str(spec["file"])
        f = frame if own == path else _frame(own)
        missing = [c for c in cols if c not in f.columns]
        if missing:
            raise LogError(f"{own}: missing column(s) {missing} that {mapping.where} names for "
                           f"signals.{name}")
        values = f[cols].to_numpy(dtype=np.float64) * factors
        if own != path:
            where = f"{mapping.where}: signals.{name}"
            t_own = _time(f, spec.get("time"), own, where)
            join = spec.get("join", "hold")
            if join not in ("hold", "interpolate"):
                raise LogError(f"{where}.join: expected 'hold' or 'interpolate', got {join!r}")
            joiner = hold if join == "hold" else _interpolate
            values = joiner(base, t_own, values, mapping.max_age, f"{own}: signals.{name}")
            rule = ("its latest sample at or before each row" if join == "hold"
                    else "interpolated linearly between the samples either side")
            notes.append(f"signals.{name} from {own.name} joined onto {path.name}'s clock: {rule}, "
                         f"cut where older than {mapping.max_age:g} s")
        signals[name] = values
    eta, nu, tau = to_neurov_frames(signals["eta"], signals["nu"], signals["tau"],
                                    mapping.body_frame, mapping.world_frame)
    t, eta, nu, tau, said = resample_by_mapping(base, eta, nu, tau, mapping)
    notes += said
    log = make_log(str(path), t, eta, nu, tau)
    return replace(log, notes=(*notes, *log.notes)) if notes else log
