"""The memory a request would need, checked before it is allocated: a
vector environment of 10^7 envs or a CSV of 10^7 rows is refused with an
error that names its size, the memory it would need and the memory there
is, instead of ending in a raw ``MemoryError`` (or the OOM killer) part way.

The memory there is: the smaller of what the system has available
(``MemAvailable`` of ``/proc/meminfo``) and what the process's address-space
limit (``ulimit -v``, ``RLIMIT_AS``) leaves beyond what it has mapped
already. Where neither can be read (not Linux), nothing is refused.
"""

from __future__ import annotations

import ctypes
import os
import resource
from pathlib import Path

__all__ = ["CSV_ADDRESS_BYTES_PER_VALUE", "CSV_BYTES_PER_VALUE", "available_memory", "check_csv_fits",
           "heap_bytes", "memory_limits", "require_memory"]

#: Bytes a CSV's value takes at the peak of pandas reading it (its float64
#: column, the parser's text and chunks): 26-36 measured (the peak RSS of
#: ``pandas.read_csv`` on 10^6-row files of 19 columns, 174 and 365 MB,
#: pandas 3.1), rounded up.
CSV_BYTES_PER_VALUE = 40

#: The same in address space, which ``ulimit -v`` bounds: 106 measured (the
#: peak virtual size, VmPeak, over the 174 MB file: pandas' reading threads
#: each take a heap arena of their own), rounded up.
CSV_ADDRESS_BYTES_PER_VALUE = 112


def _gib(n: float) -> str:
    return f"{n / 2**30:.1f} GiB" if n >= 2**30 else f"{n / 2**20:.0f} MiB"


def memory_limits() -> list[tuple[int, str, bool]]:
    """What the process may still allocate, each as (bytes, how they were
    found, whether it bounds address space rather than memory): the
    machine's available memory and what the address-space limit leaves.
    Empty where neither can be told."""
    limits = []
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                free = int(line.split()[1]) * 1024
                limits.append((free, f"{_gib(free)} available on this machine", False))
    except (OSError, ValueError, IndexError):
        pass
    soft, _ = resource.getrlimit(resource.RLIMIT_AS)
    if soft != resource.RLIM_INFINITY:
        try:
            mapped = int(Path("/proc/self/statm").read_text().split()[0]) * os.sysconf("SC_PAGE_SIZE")
        except (OSError, ValueError, IndexError):
            mapped = 0
        left = max(soft - mapped, 0)
        limits.append((left, f"{_gib(left)} left under this process's address-space limit of {_gib(soft)} "
                             f"(ulimit -v; {_gib(mapped)} mapped already)", True))
    return limits


def available_memory() -> tuple[int | None, str]:
    """(bytes, how they were found): the least of :func:`memory_limits`,
    or (None, "") where none can be told."""
    limits = memory_limits()
    if not limits:
        return None, ""
    have, said, _ = min(limits)
    return have, said


class _MallInfo2(ctypes.Structure):
    _fields_ = [(name, ctypes.c_size_t) for name in ("arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks",
                                                     "fsmblks", "uordblks", "fordblks", "keepcost")]


def heap_bytes() -> int | None:
    """Bytes the C heap holds in use now (glibc's ``mallinfo2``: the arena's
    chunks in use and the mapped ones), None where it cannot be told: what
    a compiled object allocates is the difference of two readings."""
    try:
        call = ctypes.CDLL(None).mallinfo2
    except (OSError, AttributeError):
        return None
    call.restype = _MallInfo2
    info = call()
    return int(info.uordblks + info.hblkhd)


def require_memory(need: int, what: str, error: type[Exception] = MemoryError,
                   address_space: int | None = None) -> None:
    """Raises `error` (``"<what> would need about N GiB of memory; ..."``)
    if `need` bytes exceed what the machine has available, or
    `address_space` (default `need`) bytes what the address-space limit
    leaves, before anything is allocated."""
    for have, said, virtual in sorted(memory_limits()):  # the tightest first: the one to name
        wanted = address_space if virtual and address_space is not None else need
        if wanted > have:
            raise error(f"{what} would need about {_gib(wanted)} of {'address space' if virtual else 'memory'}, "
                        f"but there is {said}; ask for less")


def check_csv_fits(path: str | os.PathLike[str], error: type[Exception] = MemoryError) -> None:
    """Refuses (`error` naming the file, its rows and columns and the memory
    they would need) a CSV file whose values would not fit in memory as
    pandas reads them: the rows estimated from the file's size and its
    first lines, the columns from its header, :data:`CSV_BYTES_PER_VALUE`
    a value (:data:`CSV_ADDRESS_BYTES_PER_VALUE` against an address-space
    limit). Reads at most 64 kB."""
    path = Path(path)
    try:
        size = path.stat().st_size
        with open(path, "rb") as f:
            head = f.read(1 << 16)
    except OSError:
        return  # the reader names a file it cannot open
    lines = head.split(b"\n")
    if len(lines) < 3 or size <= len(head):
        return  # small: read as it is
    header, sample = lines[0], lines[1:-1]
    columns = header.count(b",") + 1
    per_row = max(sum(len(x) + 1 for x in sample) / len(sample), 1.0)
    rows = int((size - len(header) - 1) / per_row)
    require_memory(rows * columns * CSV_BYTES_PER_VALUE,
                   f"{path}: reading about {rows:,} rows of {columns} columns ({_gib(size)} of CSV)", error,
                   address_space=rows * columns * CSV_ADDRESS_BYTES_PER_VALUE)
