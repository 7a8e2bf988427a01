"""A NumPy ``.npz`` archive read with every size bounded before anything is
allocated, and every failure an error that names the file and the array.

``np.load`` trusts the archive: a member's header may declare any shape (a
375 kB file of compressed zeros inflates to 384 MB, a 3.7 MB one asks for
3.6 GiB), a path to a FIFO blocks it, a truncated or damaged file surfaces as
a raw ``BadZipFile``, ``EOFError`` or ``zlib.error``, and a single ``.npy``
file is handed back as an array. Here the file is read as
:func:`neurov.files.read_bytes` reads (a regular file, at most a given
size), each member's header is read first with
``numpy.lib.format.read_array_header_*`` so that its shape and dtype can be
checked, and only then is the array read; its CRC is checked to the end.
"""

from __future__ import annotations

import io
import math
import os
import struct
import zipfile
import zlib
from collections.abc import Callable
from typing import IO

import numpy as np
from numpy.lib import format as npy

from neurov.files import read_bytes

# What a damaged archive raises from zipfile, zlib and numpy's reader.
_DAMAGED = (zipfile.BadZipFile, zipfile.LargeZipFile, zlib.error, EOFError, ValueError,
            OSError, NotImplementedError, struct.error, UnicodeDecodeError, RuntimeError)
_NPY_MAGIC = b"\x93NUMPY"
# The longest .npy header read (numpy's own default limit).
_MAX_HEADER = 10_000


class NpzFile:
    """An open ``.npz`` archive read from memory; `error` is raised, as
    ``error("<name>: ...")``, for anything wrong with it."""

    def __init__(self, path: str | os.PathLike[str] | bytes, error: type[Exception], limit: int, name: str,
                 single_array_hint: str = "") -> None:
        self.name = name
        self.error = error
        self.limit = limit
        # bytes: an archive already read (e.g. an MCAP file's attachment), bounded by the caller.
        data = path if isinstance(path, bytes) else read_bytes(path, error, limit, name)
        if data.startswith(_NPY_MAGIC):
            raise error(f"{name}: a single .npy array, not a .npz archive of named arrays"
                        f"{single_array_hint}")
        try:
            self.zip = zipfile.ZipFile(io.BytesIO(data))
        except _DAMAGED as e:
            raise error(f"{name}: not a .npz archive ({_said(e)}; truncated, damaged or "
                        "another kind of file)") from None

    def __enter__(self) -> NpzFile:
        return self

    def __exit__(self, *exc: object) -> None:
        self.zip.close()

    def _open(self, array: str) -> IO[bytes]:
        try:
            info = self.zip.getinfo(f"{array}.npy")
        except KeyError:
            raise self.error(f"{self.name}: array '{array}' is missing") from None
        if info.file_size > self.limit:
            raise self.error(f"{self.name}: array '{array}' declares {info.file_size} bytes, more "
                             f"than the {self.limit} a file of this kind may hold")
        return self.zip.open(info)

    def _damaged(self, array: str, e: BaseException) -> Exception:
        return self.error(f"{self.name}: array '{array}' is damaged or truncated ({_said(e)})")

    def _header(self, f: IO[bytes], array: str) -> tuple[tuple[int, ...], bool, np.dtype]:
        version = npy.read_magic(f)
        if version == (1, 0):
            shape, fortran, dtype = npy.read_array_header_1_0(f, max_header_size=_MAX_HEADER)
        elif version == (2, 0):
            shape, fortran, dtype = npy.read_array_header_2_0(f, max_header_size=_MAX_HEADER)
        else:
            raise self.error(f"{self.name}: array '{array}' is in .npy format version "
                             f"{version[0]}.{version[1]} (1.0 and 2.0 are read)")
        if any(n < 0 for n in shape):
            raise self.error(f"{self.name}: array '{array}' declares the shape {tuple(shape)}")
        if dtype.hasobject:
            raise self.error(f"{self.name}: array '{array}' holds Python objects (dtype {dtype}), "
                             "which are refused, never unpickled")
        return tuple(int(n) for n in shape), bool(fortran), dtype

    def header(self, array: str) -> tuple[tuple[int, ...], np.dtype]:
        """The shape and dtype `array` declares, read without its data; an
        array of Python objects (never unpickled) is an error."""
        try:
            with self._open(array) as f:
                shape, _, dtype = self._header(f, array)
        except self.error:
            raise
        except _DAMAGED as e:
            raise self._damaged(array, e) from None
        return shape, dtype

    def array(self, array: str, check: Callable[[tuple[int, ...], np.dtype], None]) -> np.ndarray:
        """`array`'s data (a read-only array over the bytes read), read once
        `check(shape, dtype)` (which raises for a shape or dtype not wanted,
        so bounding what is allocated) passed; the member's CRC is checked
        to its end."""
        try:
            with self._open(array) as f:
                shape, fortran, dtype = self._header(f, array)
                check(shape, dtype)
                size = math.prod(shape) * dtype.itemsize
                data = f.read(size)
                if len(data) != size:
                    raise self.error(f"{self.name}: array '{array}' is truncated: {len(data)} of "
                                     f"the {size} bytes its shape {shape} declares")
                # Read to the member's end (bounded by its declared size) so
                # that zipfile checks the CRC: a flipped bit is an error.
                while f.read(1 << 16):
                    pass
        except self.error:
            raise
        except _DAMAGED as e:
            raise self._damaged(array, e) from None
        return np.frombuffer(data, dtype=dtype).reshape(shape, order="F" if fortran else "C")


def _said(e: BaseException) -> str:
    return f"{type(e).__name__}: {e}" if str(e) else type(e).__name__
