"""Writers of a run's rows to result.csv and result.npz, block by block.

Both take the rows in pieces (a whole :class:`neurov.Result` is one piece, a
streamed run a piece per chunk), so a 24-hour run never needs its whole text
or a second copy of its arrays in memory.
"""

from __future__ import annotations

import csv
import shutil
import tempfile
import zipfile
from pathlib import Path
from types import TracebackType
from typing import IO, Any

import numpy as np

__all__ = ["CSV_BLOCK_ROWS", "CsvWriter", "NpzWriter"]

CSV_BLOCK_ROWS = 20_000
"""Rows per block written by :class:`CsvWriter`."""


class CsvWriter:
    """Writes named columns to a CSV file with a header row, each number as
    the shortest text that reads back to the same float64 (integers and
    strings as they are): through pyarrow's C++ writer when pyarrow is
    installed (``neurov[parquet]``; about four times faster), else Python's
    csv module. `columns` gives the names and the dtypes (a first block of
    rows, say). Use as a context manager; :meth:`write` appends rows."""

    def __init__(self, path: str | Path, columns: dict[str, Any]) -> None:
        self.path = Path(path)
        self.names = list(columns)
        self._file: IO[str] | None = None
        self._csv: Any = None
        self._arrow: Any = None
        try:
            import pyarrow as pa
            import pyarrow.csv as pacsv
        except ImportError:
            self._file = self.path.open("w", newline="")
            self._csv = csv.writer(self._file)
            self._csv.writerow(self.names)
            return
        self._pa = pa
        self._schema = pa.schema([(name, pa.from_numpy_dtype(np.asarray(c).dtype) if np.asarray(c).dtype.kind != "U"
                                   else pa.string()) for name, c in columns.items()])
        options = pacsv.WriteOptions(quoting_style="none")
        self._arrow = pacsv.CSVWriter(str(self.path), self._schema, write_options=options)

    def write(self, columns: dict[str, Any], progress: Any = None) -> None:
        """Appends the rows of `columns` (the names of the constructor, in
        that order, equal lengths), in blocks of :data:`CSV_BLOCK_ROWS`;
        `progress.update(rows)` after each block if given."""
        if list(columns) != self.names:
            raise ValueError(f"columns {list(columns)} are not the file's {self.names}")
        values = list(columns.values())
        rows = len(values[0]) if values else 0
        for start in range(0, rows, CSV_BLOCK_ROWS):
            block = slice(start, start + CSV_BLOCK_ROWS)
            if self._arrow is not None:
                self._arrow.write_batch(self._pa.record_batch(
                    [self._pa.array(c[block], type=f.type) for c, f in zip(values, self._schema)],
                    schema=self._schema))
            else:
                self._csv.writerows(zip(*(c[block].tolist() for c in values)))
            if progress is not None:
                progress.update(len(values[0][block]))

    def close(self) -> None:
        if self._arrow is not None:
            self._arrow.close()
            self._arrow = None
        if self._file is not None:
            self._file.close()
            self._file = None

    def __enter__(self) -> CsvWriter:
        return self

    def __exit__(self, kind: type[BaseException] | None, value: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.close()


class NpzWriter:
    """Writes named arrays to a compressed .npz (zlib level 1: the float
    series barely compress more at numpy's level 6, which takes several times
    longer) that ``numpy.load(path, allow_pickle=False)`` reads. :meth:`append`
    adds rows to each array (the first axis), spooled to a temporary folder
    beside the file; :meth:`close` writes the archive array by array, each
    streamed from its spool, so no array is ever held whole in memory."""

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self._spool = Path(tempfile.mkdtemp(prefix=f".{self.path.name}.", dir=self.path.parent))
        self._arrays: dict[str, tuple[np.dtype[Any], tuple[int, ...], int]] = {}
        self._fixed: dict[str, np.ndarray] = {}

    def set(self, name: str, value: Any) -> None:
        """An array written as it is (e.g. the scenario's name)."""
        self._fixed[name] = np.asanyarray(value)

    def append(self, arrays: dict[str, np.ndarray]) -> None:
        """Appends each array's rows to the array of that name (same dtype
        and trailing shape as before)."""
        for name, value in arrays.items():
            value = np.ascontiguousarray(value)
            known = self._arrays.get(name)
            if known is None:
                known = (value.dtype, value.shape[1:], 0)
            elif (known[0], known[1]) != (value.dtype, value.shape[1:]):
                raise ValueError(f"array {name!r}: rows of {value.dtype} {value.shape[1:]} after "
                                 f"{known[0]} {known[1]}")
            with (self._spool / name).open("ab") as f:
                f.write(value.tobytes())
            self._arrays[name] = (known[0], known[1], known[2] + value.shape[0])

    def close(self, progress: Any = None) -> Path:
        """Writes the archive (the fixed arrays first) and removes the spool;
        `progress.update(1)` after each array if given."""
        try:
            with zipfile.ZipFile(self.path, "w", compression=zipfile.ZIP_DEFLATED, compresslevel=1,
                                 allowZip64=True) as zf:
                for name, value in self._fixed.items():
                    with zf.open(f"{name}.npy", "w", force_zip64=True) as f:
                        np.lib.format.write_array(f, value, allow_pickle=False)
                    if progress is not None:
                        progress.update(1)
                for name, (dtype, tail, rows) in self._arrays.items():
                    header = {"descr": np.lib.format.dtype_to_descr(dtype), "fortran_order": False,
                              "shape": (rows, *tail)}
                    with zf.open(f"{name}.npy", "w", force_zip64=True) as f, \
                            (self._spool / name).open("rb") as raw:
                        np.lib.format.write_array_header_1_0(f, header)
                        shutil.copyfileobj(raw, f, 1 << 22)
                    if progress is not None:
                        progress.update(1)
        except BaseException:
            self.path.unlink(missing_ok=True)  # a half-written archive is no archive
            raise
        finally:
            self.discard()
        return self.path

    def discard(self) -> None:
        """Removes the spool (the archive, if written, stays)."""
        shutil.rmtree(self._spool, ignore_errors=True)

    @property
    def count(self) -> int:
        """How many arrays :meth:`close` writes."""
        return len(self._fixed) + len(self._arrays)
