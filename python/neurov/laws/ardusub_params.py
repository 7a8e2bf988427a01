"""ArduSub parameters by ArduSub's names: read from a vehicle's files, put
into an :class:`neurov.ArduSubConfig`, written back as a ``.param`` file.

The parameters the controller models, with ArduSub's defaults and documented
ranges, are one C++ table (``neurov._core.ARDUSUB_PARAMETERS``, from
``neurov/control/ardusub_parameters.hpp``); this module only reads files:

* ``.param`` / ``.params`` / ``.parm`` / ``.txt``: QGroundControl's
  ``SYS<TAB>COMP<TAB>NAME<TAB>VALUE<TAB>TYPE`` lines or MAVProxy's / Mission
  Planner's ``NAME VALUE`` (or ``NAME,VALUE``); ``#`` starts a comment;
* ``.tlog``: the PARAM_VALUE messages of a MAVLink telemetry log (the last
  value of each name), through pymavlink;
* ``.bin`` / ``.log``: the PARM messages of a DataFlash log, through pymavlink.

Values from a vehicle are taken as ArduSub takes them: one outside the
documented range gives a warning, not a refusal; what ArduSub would not fly
(not a number, a negative gain) is refused by the C++ validator. A name the
controller does not model (a log carries some 900) is left out.
"""

from __future__ import annotations

import io
import math
import re
import warnings
from collections.abc import Iterator, Mapping
from contextlib import contextmanager, redirect_stderr, redirect_stdout
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from neurov import _core
from neurov.errors import NeurovError

__all__ = ["MODES", "PARAMETERS", "ArduSubParameterError", "ArduSubRangeWarning", "Parameter",
           "apply_parameters", "format_param_file", "out_of_range", "quiet", "read_log_parameters", "read_parameters",
           "write_log_parameters"]


class ArduSubParameterError(NeurovError):
    """A parameter file or log that cannot be read, or a value that cannot be used."""


class ArduSubRangeWarning(UserWarning):
    """A value outside ArduSub's documented range, taken as ArduSub takes it."""


@dataclass(frozen=True)
class Parameter:
    """One ArduSub parameter the controller models."""

    name: str
    default: float
    min: float
    max: float
    unit: str
    doc: str


#: The modelled parameters by name, in the C++ table's order.
PARAMETERS: dict[str, Parameter] = {row[0]: Parameter(*row) for row in _core.ARDUSUB_PARAMETERS}

#: The flight modes by their scenario names -> ArduSubConfig.mode.
MODES: dict[str, int] = {"stabilize": 0, "depth_hold": 1, "position_hold": 2}

_TEXT_SUFFIXES = {".param", ".params", ".parm", ".txt"}
_QGC = re.compile(r"^\s*(\d+)\s+(\d+)\s+([A-Za-z0-9_]+)\s+(\S+)\s+(\d+)\s*$")
_PAIR = re.compile(r"^\s*([A-Za-z0-9_]+)\s*[,\s]\s*(\S+)\s*$")


def read_parameters(path: str | Path) -> dict[str, float]:
    """Every parameter a file or log holds, by name (the last value of a
    name that occurs more than once)."""
    path = Path(path)
    if not path.is_file():
        raise ArduSubParameterError(f"{path}: no such file")
    suffix = path.suffix.lower()
    if suffix in _TEXT_SUFFIXES:
        return _read_text(path)
    if suffix in (".tlog", ".bin", ".log"):
        params = read_log_parameters(path)
        if not params:
            message = "PARAM_VALUE" if suffix == ".tlog" else "PARM"
            raise ArduSubParameterError(f"{path}: the log holds no {message} messages (no parameters)")
        return params
    raise ArduSubParameterError(f"{path}: expected a .param/.params/.parm/.txt parameter file, a .tlog "
                                f"or a DataFlash .bin, got a {suffix or 'suffix-less'} file")


def _number(text: str, where: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise ArduSubParameterError(f"{where}: expected a number, got {text!r}") from None


def _read_text(path: Path) -> dict[str, float]:
    params: dict[str, float] = {}
    try:
        text = path.read_text(encoding="utf-8", errors="strict")
    except UnicodeDecodeError:
        raise ArduSubParameterError(f"{path}: not a text parameter file (not UTF-8)") from None
    for number, line in enumerate(text.splitlines(), start=1):
        body = line.split("#", 1)[0].strip()
        if not body:
            continue
        where = f"{path}:{number}"
        m = _QGC.match(body)
        if m:
            params[m.group(3)] = _number(m.group(4), f"{where}: {m.group(3)}")
            continue
        m = _PAIR.match(body)
        if m:
            params[m.group(1)] = _number(m.group(2), f"{where}: {m.group(1)}")
            continue
        raise ArduSubParameterError(f"{where}: expected 'NAME VALUE' (MAVProxy) or 'SYS COMP NAME VALUE "
                                    f"TYPE' (QGroundControl), got {body!r}")
    if not params:
        raise ArduSubParameterError(f"{path}: no parameters in the file")
    return params


def read_log_parameters(path: str | Path, dataflash: bool | None = None) -> dict[str, float]:
    """The vehicle parameters an ArduSub log holds, name -> value: a
    telemetry log's PARAM_VALUE messages (the ground station's parameter
    download) or a DataFlash log's PARM messages, through pymavlink; the last
    value of a name wins (a parameter set during the dive). `dataflash`
    says which kind the log is (None: by its suffix, ``.bin``/``.log``
    DataFlash, ``.tlog`` telemetry). Empty when the log holds none.
    ArduSubParameterError naming `path` when it is missing or unreadable, or
    pymavlink is not installed."""
    path = Path(path)
    if not path.is_file():
        raise ArduSubParameterError(f"{path}: no such file")
    if dataflash is None:
        suffix = path.suffix.lower()
        if suffix not in (".tlog", ".bin", ".log"):
            raise ArduSubParameterError(f"{path}: expected a .tlog or a DataFlash .bin/.log, got a "
                                        f"{suffix or 'suffix-less'} file")
        dataflash = suffix != ".tlog"
    # Deferred: pymavlink is an optional dependency (the identify extra).
    try:
        from pymavlink import mavutil
    except ImportError:
        raise ArduSubParameterError(f"{path}: reading a log's parameters needs pymavlink "
                                    "(pip install 'neurov[identify]')") from None
    kind, name_field, value_field = ("PARM", "Name", "Value") if dataflash else (
        "PARAM_VALUE", "param_id", "param_value")
    params: dict[str, float] = {}
    try:
        with quiet():
            conn = mavutil.mavlink_connection(str(path), dialect="ardupilotmega")
            try:
                while True:
                    msg = conn.recv_match(type=kind)
                    if msg is None:
                        break
                    name = getattr(msg, name_field)
                    name = name.decode(errors="replace") if isinstance(name, bytes) else str(name)
                    params[name.rstrip("\x00")] = float(getattr(msg, value_field))
            finally:
                conn.close()
    except Exception as e:  # pymavlink's own errors for a file that is not a log
        raise ArduSubParameterError(f"{path}: not a readable {'DataFlash' if dataflash else 'telemetry'} "
                                    f"log ({type(e).__name__}: {e})") from None
    return params


@contextmanager
def quiet() -> Iterator[None]:
    """pymavlink's readers print their diagnostics (a DataFlash log's "bad
    header" per byte of garbage, on stderr): kept off neurov's output."""
    with redirect_stdout(io.StringIO()), redirect_stderr(io.StringIO()):
        yield


def out_of_range(name: str, value: float) -> str | None:
    """A sentence when `value` lies outside `name`'s documented range but is
    one ArduSub flies, else None."""
    p = PARAMETERS[name]
    if p.min <= value <= p.max or not math.isfinite(value) or (value < 0 <= p.min):
        return None  # inside, or refused by the validator (not a number, a negative gain)
    return (f"{name} = {value:g} is outside ArduSub's documented range [{p.min:g}, {p.max:g}]"
            f"{' ' + p.unit if p.unit else ''}; taken as ArduSub takes it")


def apply_parameters(config: Any, params: Mapping[str, float], origin: str,
                     skip: frozenset[str] | set[str] = frozenset()) -> list[str]:
    """Sets the modelled parameters of `params` on `config` (names in `skip`
    left alone: a scenario's own keys override the file), warning once per
    value outside its documented range; returns the names not modelled."""
    ignored = []
    for name, value in params.items():
        if name not in PARAMETERS:
            ignored.append(name)
            continue
        if name in skip:
            continue
        if not math.isfinite(value):
            raise ArduSubParameterError(f"{origin}: {name} = {value}: expected a finite number")
        note = out_of_range(name, value)
        if note:
            warnings.warn(f"{origin}: {note}", ArduSubRangeWarning, stacklevel=2)
        setattr(config, name, float(value))
    return ignored


def format_param_file(params: Mapping[str, float], header: list[str]) -> str:
    """A parameter file QGroundControl's "Load from file" reads: comment
    lines, then ``1<TAB>1<TAB>NAME<TAB>VALUE<TAB>9`` (9: a 32-bit float),
    names sorted."""
    lines = [f"# {h}" if h else "#" for h in header]
    lines.append("# Vehicle-Id\tComponent-Id\tName\tValue\tType")
    for name in sorted(params):
        lines.append(f"1\t1\t{name}\t{params[name]:.9g}\t9")
    return "\n".join(lines) + "\n"


def write_log_parameters(log: str | Path, out: str | Path | None = None) -> Path:
    """Every parameter of `log` (a log or parameter file) as a QGroundControl
    .param file at `out` (default: beside the log, suffix .param); its path."""
    log = Path(log)
    params = read_parameters(log)
    target = Path(out) if out is not None else log.with_suffix(".param")
    if target.resolve() == log.resolve():
        raise ArduSubParameterError(f"{target}: the output would overwrite the input; give --out")
    modelled = sum(1 for name in params if name in PARAMETERS)
    header = [f"Parameters of {log.name}, written by `neurov params`: {len(params)} parameters,",
              f"{modelled} of them read by neurov's ardusub controller. Types written as 9 (float)."]
    target.write_text(format_param_file(params, header))
    return target
