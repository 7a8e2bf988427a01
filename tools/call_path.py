"""The way a ``neurov`` command goes through the package: runs the command
in this process under :func:`sys.setprofile` and counts the Python calls
into neurov's modules.

    python tools/call_path.py -- run paper_fig3 --out /tmp/fig3
    python tools/call_path.py --modules --count neurov.config.scenario:Scenario.replace -- run paper_fig3

What it counts (the code run while a module is imported is not a call of
the run, and is left out, as is everything outside ``python/neurov``):

- **calls**: every call of a Python function of a neurov module;
- **modules**: the neurov modules those functions are in;
- **stays**: calls from a function of the same module (the caller is the
  nearest neurov function up the stack);
- **returns**: calls into another module that the run has already been in
  and left, so ``calls = stays + modules + returns`` (the first call into
  each module is the rest);
- how often some functions ran (``MODULE:QUALNAME``, ``--count`` adds more):
  the scenario's configuration built (``Scenario._sync``), the vehicle file
  asked for, read and put in water, the output folder checked, and the run's
  configuration validated (``SimulationConfig.validate``, the C++ validator,
  counted however it is called).

The command's own output goes to /dev/null (``--show-output`` keeps it); the
counts go to stdout, and the exit status is the command's.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
from collections import Counter
from pathlib import Path
from types import FrameType
from typing import Any

import neurov
from neurov import _core
from neurov.cli import main

PACKAGE = Path(neurov.__file__).resolve().parent

NAMED = (
    "neurov.config.scenario:Scenario._sync",
    "neurov.config.scenario:Scenario.vehicle_data",
    "neurov.config.vehicle_file:read_vehicle_file",
    "neurov.config.vehicle_file:VehicleFile.in_water",
    "neurov.running.folder:check_output_dir",
)
"""The functions counted by name unless ``--count`` names others too."""

VALIDATE = "neurov._core:SimulationConfig.validate"


class CallPath:
    """The profile function: counts every call into neurov (see the module)."""

    def __init__(self) -> None:
        self.calls = 0
        self.stays = 0
        self.returns = 0
        self.per_module: Counter[str] = Counter()
        self.by_name: Counter[str] = Counter()
        self._modules: dict[str, str | None] = {}
        self._importing = 0

    def module(self, filename: str) -> str | None:
        """The dotted name of the neurov module in `filename` (None: not neurov's)."""
        name = self._modules.get(filename, "")
        if name == "":
            try:
                parts = Path(filename).resolve().relative_to(PACKAGE).with_suffix("").parts
            except ValueError:
                name = None
            else:
                name = ".".join(("neurov", *parts[:-1]) if parts[-1] == "__init__" else ("neurov", *parts))
            self._modules[filename] = name
        return name

    def __call__(self, frame: FrameType, event: str, arg: Any) -> None:
        code = frame.f_code
        if code.co_name == "<module>":  # a module being imported: its code is not the run's
            self._importing += 1 if event == "call" else -1 if event == "return" else 0
            return
        if event != "call" or self._importing:
            return
        callee = self.module(code.co_filename)
        if callee is None:
            return
        caller = None
        back = frame.f_back
        while back is not None and caller is None:
            caller = self.module(back.f_code.co_filename)
            back = back.f_back
        self.calls += 1
        if caller == callee:
            self.stays += 1
        elif callee in self.per_module:
            self.returns += 1
        self.per_module[callee] += 1
        self.by_name[f"{callee}:{code.co_qualname}"] += 1


@contextlib.contextmanager
def counted_validation(path: CallPath) -> Any:
    """``SimulationConfig.validate`` (compiled, so invisible to the profile
    function) counted into `path` while the block runs."""
    original = _core.SimulationConfig.validate

    def validate(self: Any) -> None:
        path.by_name[VALIDATE] += 1
        return original(self)

    _core.SimulationConfig.validate = validate
    try:
        yield
    finally:
        _core.SimulationConfig.validate = original


def measure(argv: list[str], show_output: bool = False) -> tuple[CallPath, int]:
    """Runs ``neurov ARGV`` here; its call path and its exit status."""
    path = CallPath()
    with contextlib.ExitStack() as stack:
        if not show_output:
            sink = stack.enter_context(open(os.devnull, "w", encoding="utf-8"))
            stack.enter_context(contextlib.redirect_stdout(sink))
            stack.enter_context(contextlib.redirect_stderr(sink))
        stack.enter_context(counted_validation(path))
        sys.setprofile(path)
        try:
            status = main(argv)
        except SystemExit as e:
            status = e.code if isinstance(e.code, int) else 1
        finally:
            sys.setprofile(None)
    return path, status


def report(path: CallPath, names: list[str], modules: bool) -> str:
    lines = [f"calls: {path.calls}",
             f"modules: {len(path.per_module)}",
             f"stays (calls within a module): {path.stays}",
             f"returns (calls into a module already left): {path.returns}"]
    for name in [*names, VALIDATE]:
        lines.append(f"{name}: {path.by_name[name]}")
    if modules:
        lines += [f"  {count:5d}  {name}" for name, count in sorted(path.per_module.items(),
                                                                     key=lambda item: (-item[1], item[0]))]
    return "\n".join(lines)


def parse(argv: list[str]) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     usage="python tools/call_path.py [options] -- NEUROV_ARGS ...")
    parser.add_argument("--count", action="append", default=[], metavar="MODULE:QUALNAME",
                        help="a function to count besides the default ones (repeatable)")
    parser.add_argument("--modules", action="store_true", help="also list the calls into each module")
    parser.add_argument("--show-output", action="store_true", help="let the command's own output through")
    parser.add_argument("command", nargs="+", help="the neurov command's arguments (after --)")
    args = parser.parse_args(argv)
    for name in args.count:
        if ":" not in name or not name.startswith("neurov"):
            parser.error(f"argument --count: expected MODULE:QUALNAME, e.g. {NAMED[0]}, got {name!r}")
    return args


if __name__ == "__main__":
    options = parse(sys.argv[1:])
    measured, code = measure(options.command, options.show_output)
    print(report(measured, [*NAMED, *options.count], options.modules))
    sys.exit(code)
