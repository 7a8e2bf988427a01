"""Writes a fitted vehicle file: a header saying what it was fitted from,
the fitted top-level parameters, and the template's tables (thrusters,
limits) copied as they are. The text is checked by neurov's own reader
before it replaces anything: a file that would not load is never written."""

from __future__ import annotations

import os
import re
import tempfile
from pathlib import Path
from typing import Any

from neurov.files import writing
from neurov.identification.errors import IdentificationError
from neurov.config.vehicle_file import file_fields, read_vehicle_file

__all__ = ["write_vehicle_file"]

_TABLE = re.compile(r"^\[{1,2}[A-Za-z_][\w.\-]*\]{1,2}\s*(#.*)?$")
# The parameters a vehicle file holds, as its reader has them (name and source are written first).
_KEYS = tuple(k for k in file_fields() if k not in ("name", "source"))


def _value(v: Any) -> str:
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    return repr(float(v))


def _tables(template_text: str) -> str:
    lines = template_text.splitlines()
    for i, line in enumerate(lines):
        if _TABLE.match(line):
            return "\n".join(lines[i:]) + "\n"
    return ""


def write_vehicle_file(out: str | Path, template: str | Path, parameters: dict[str, Any],
                       header: list[str], name: str, source: str) -> Path:
    """Writes `out` atomically; `parameters` are Vehicle keyword arguments
    (plus ``displaced_volume`` instead of ``buoyancy`` to keep the template's)."""
    out = Path(out)
    body = [*(f"# {h}" if h else "#" for h in header), "",
            f"name = {_value(name)}", f"source = {_value(source)}"]
    body += [f"{k} = {_value(parameters[k])}" for k in _KEYS if k in parameters]
    text = "\n".join(body) + "\n\n" + _tables(Path(template).read_text(encoding="utf-8"))
    folder = out.parent if str(out.parent) else Path(".")
    if not folder.is_dir():
        raise IdentificationError(f"--out {out}: the folder {folder} does not exist")
    with writing(out, f"{str(out)!r} (--out)"):  # a failure names the user's file, not the temporary one
        fd, tmp = tempfile.mkstemp(prefix=".fitted-", suffix=".toml", dir=folder)
        try:
            with os.fdopen(fd, "w", encoding="utf-8") as f:
                f.write(text)
            read_vehicle_file(tmp).vehicle()
            os.replace(tmp, out)
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise
    return out
