"""A run's series as the flat, named columns of its tables (the CSV,
Parquet and :meth:`neurov.Result.to_pandas`), and back.

Everything here is made from the one list of series,
:data:`neurov._core.RESULT_SERIES` (``cpp/include/neurov/sim/result.hpp``):
a column is ``<series>`` for a one-column series and ``<series>_<label>``
otherwise (``eta_x`` ... ``eta_psi``, ``tau_applied_X`` ... ``tau_applied_N``,
``thrusts_0`` ..., ``theta_m`` ..., ``current_N``); the statuses are written
as their :class:`neurov.Status` names, the fault bits as an integer. The
CSV's header is ``t`` and then the columns of ``to_pandas()`` (whose index is
``t``), in the same order, with the same values.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from neurov import _core
from neurov.errors import NeurovError, ResultFileError
from neurov.npz_file import NpzFile

__all__ = ["RESULT_SERIES", "SERIES", "ResultSeries", "STATUS_NAMES", "column_names", "npz_series",
           "series_from_columns", "table_columns"]

class ResultSeries(NamedTuple):
    """One logged series: an entry of the C++ table."""

    name: str
    """The array's name: a :class:`neurov.Result` attribute, an NPZ key."""
    width: int | None
    """Columns; None where they vary (see `varies_with`)."""
    varies_with: str
    """``"thrusters"`` (one column per thruster, numbered from 0),
    ``"parameters"`` (one per logged controller parameter, ``THETA_NAMES``)
    or ``""`` (a fixed width)."""
    labels: tuple[str, ...]
    """The columns' labels (a column is ``<name>_<label>``); () for one
    column or numbered ones."""
    unit: str
    """SI units of the columns ('' for none)."""
    dtype: str
    """The array's numpy dtype (the C++ member's scalar)."""
    kind: str
    """``"real"`` values, ``"status"`` (:class:`neurov.Status` codes, written
    by name in tables) or ``"bits"`` (the fault bits, an integer)."""
    description: str
    """One sentence on the series."""


RESULT_SERIES = tuple(ResultSeries(*entry) for entry in _core.RESULT_SERIES)
"""The logged series, from the C++ table ``NEUROV_RESULT_SERIES``
(:data:`neurov._core.RESULT_SERIES`), in the order of the CSV's columns."""

SERIES = tuple(spec.name for spec in RESULT_SERIES)
"""The series' names: the :class:`neurov.Result` arrays and the NPZ keys."""

STATUS_NAMES = tuple(s.name for s in sorted(_core.Status.__members__.values(), key=int))
"""The :class:`neurov.Status` names by code: the values of a status column."""

_STATUS_CODES = {name: code for code, name in enumerate(STATUS_NAMES)}


def is_result(obj: Any) -> bool:
    """Whether `obj` is a run's result (a :class:`neurov.Result`): it has a
    scenario, a controller label and every series of :data:`SERIES`. The
    bridges (:mod:`neurov.control`, :mod:`neurov.replay`), which the
    result's own methods call, check their argument with this: importing the
    class back would make the results layer and the bridges import each
    other."""
    return all(hasattr(obj, name) for name in ("scenario", "controller", *SERIES))


def column_names(spec: Any, columns: int) -> list[str]:
    """The table columns of series `spec` whose array has `columns` columns."""
    if spec.varies_with == "thrusters":
        return [f"{spec.name}_{i}" for i in range(columns)]
    if spec.width == 1:
        return [spec.name]
    return [f"{spec.name}_{label}" for label in spec.labels[:columns]]


def table_columns(arrays: Mapping[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The series in `arrays` (by name, every one of :data:`SERIES`) as
    named columns in the table's order: numbers as float64, statuses as
    their names, fault bits as uint8."""
    names = np.asarray(STATUS_NAMES)
    cols: dict[str, np.ndarray] = {}
    for spec in RESULT_SERIES:
        arr = np.asarray(arrays[spec.name])
        if spec.kind == "status":
            cols[spec.name] = names[arr]
        elif arr.ndim == 1:
            cols[spec.name] = arr
        else:
            cols.update(zip(column_names(spec, arr.shape[1]), arr.T))
    return cols


def _varying_count(spec: Any, present: set[str]) -> int:
    """How many columns of a varying-width series the table has."""
    if spec.varies_with == "thrusters":
        n = 0
        while f"{spec.name}_{n}" in present:
            n += 1
        return n
    return len(spec.labels) if any(c in present for c in column_names(spec, len(spec.labels))) else 0


def series_from_columns(columns: Mapping[str, Any], where: str) -> dict[str, np.ndarray]:
    """The inverse of :func:`table_columns`: the arrays of :data:`SERIES`
    from named columns (array-likes of equal length, statuses as names or
    codes). A missing or unexpected column, or an unknown status name, raises
    :class:`neurov.errors.ResultFileError` naming `where`."""
    present = set(columns)
    out: dict[str, np.ndarray] = {}
    used: set[str] = set()
    missing: list[str] = []
    for spec in RESULT_SERIES:
        n = spec.width if spec.width is not None else _varying_count(spec, present)
        names = column_names(spec, n)
        used.update(names)
        absent = [c for c in names if c not in present]
        if absent:
            missing += absent
            continue
        if spec.kind == "status":
            out[spec.name] = _codes(columns[spec.name], f"{where}: column {spec.name!r}")
        elif spec.kind == "bits":
            out[spec.name] = _integers(columns[spec.name], f"{where}: column {spec.name!r}")
        elif spec.width == 1:
            out[spec.name] = np.asarray(columns[spec.name], dtype=np.float64)
        else:
            rows = len(columns["t"]) if "t" in present else 0
            out[spec.name] = (np.column_stack([np.asarray(columns[c], dtype=np.float64) for c in names])
                              if names else np.zeros((rows, 0)))
    if missing:
        raise ResultFileError(f"{where}: missing column(s) {missing} (a neurov result table has the "
                              "columns of neurov._core.RESULT_SERIES, see docs/running.md)")
    unexpected = sorted(present - used)
    if unexpected:
        raise ResultFileError(f"{where}: unexpected column(s) {unexpected}: not of a neurov result "
                              "(a series' columns are all there or none, thrusts_0 ... numbered from 0)")
    return out


def _codes(values: Any, where: str) -> np.ndarray:
    values = np.asarray(values)
    if values.dtype.kind in "iu" or not len(values):
        return _integers(values, where, limit=len(STATUS_NAMES))
    codes = [_STATUS_CODES.get(str(v), -1) for v in values]
    bad = [str(v) for v, c in zip(values, codes) if c < 0]
    if bad:
        raise ResultFileError(f"{where}: unknown status {bad[0]!r} (expected one of {list(STATUS_NAMES)})")
    return np.asarray(codes, dtype=np.uint8)


def _integers(values: Any, where: str, limit: int = 256) -> np.ndarray:
    values = np.asarray(values)
    if not len(values):
        return np.zeros(0, dtype=np.uint8)
    if values.dtype.kind not in "iu" or (len(values) and (values.min() < 0 or values.max() >= limit)):
        raise ResultFileError(f"{where}: expected integers 0 ... {limit - 1}, got {values.dtype} values")
    return values.astype(np.uint8)


def markdown_table() -> str:
    """The series and their columns as a Markdown table (the docs include
    it, generated at build time, so that the list cannot go stale)."""
    rows = ["| series | columns | unit | what |", "|---|---|---|---|"]
    for spec in RESULT_SERIES:
        if spec.varies_with == "thrusters":
            cols = f"`{spec.name}_0`, `{spec.name}_1`, … (one per thruster; none without thrusters)"
        elif spec.varies_with == "parameters":
            first, last = column_names(spec, len(spec.labels))[::len(spec.labels) - 1]
            cols = f"`{first}` … `{last}` ({len(spec.labels)}, `THETA_NAMES`; for the linear adaptive controller)"
        else:
            cols = ", ".join(f"`{c}`" for c in column_names(spec, spec.width or 1))
        if spec.kind == "status":
            cols += " (a `neurov.Status` name)"
        elif spec.kind == "bits":
            cols += " (an integer, its bits)"
        cells = (f"`{spec.name}`", cols, spec.unit or "–", spec.description)
        rows.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")  # a | inside splits a cell
    return "\n".join(rows) + "\n"


def npz_series(source: Path | bytes, where: str, error: type[NeurovError] = ResultFileError,
               max_bytes: int = 1 << 36) -> tuple[dict[str, Any], dict[str, Any]]:
    """The series of a ``result.npz`` (a file, or its bytes: an MCAP
    recording's attachment), each array's dtype and shape checked against
    the table before it is read, and the run's scalars it holds
    (``scenario``, ``controller``, ``diverged``; those present). A misfit
    raises `error` naming `where`."""
    with NpzFile(source, error, max_bytes, where) as npz:
        rows: list[int] = []

        def check(spec: Any) -> Callable[[tuple[int, ...], np.dtype], None]:
            def fits(shape: tuple[int, ...], dtype: np.dtype) -> None:
                ndim = 1 if spec.width == 1 else 2
                if (dtype != np.dtype(spec.dtype) or len(shape) != ndim or (rows and shape[0] != rows[0])
                        or (spec.width not in (None, 1) and shape[1] != spec.width)):
                    want = f"({rows[0] if rows else 'N'}{'' if ndim == 1 else ', ' + str(spec.width or 'n')})"
                    raise error(f"{where}: array {spec.name!r} is {dtype} {shape}, expected {spec.dtype} {want}")
                rows[:] = rows or [shape[0]]
            return fits

        series = {spec.name: np.array(npz.array(spec.name, check(spec))) for spec in RESULT_SERIES}
        meta: dict[str, Any] = {}
        for key, kind in (("scenario", "U"), ("controller", "U"), ("diverged", "b")):
            if f"{key}.npy" in npz.zip.namelist():
                meta[key] = npz.array(key, functools.partial(_scalar, where, error, key, kind)).item()
    return series, meta


def _scalar(where: str, error: type[NeurovError], key: str, kind: str, shape: tuple[int, ...],
            dtype: np.dtype) -> None:
    if shape != () or dtype.kind != kind:
        raise error(f"{where}: array {key!r} is {dtype} {shape}, expected a single "
                    f"{'string' if kind == 'U' else 'bool'}")
