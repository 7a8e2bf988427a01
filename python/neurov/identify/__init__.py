"""Identification: a vehicle file fitted to recorded runs, with a 95 %
interval for each parameter and the fit on held-out logs.

``neurov.identify(logs, vehicle, out=...)`` calls :func:`identify` (this
package is callable, so that the command's name is the function's); the
method is in docs/identification.md. Nothing heavy is imported until used:
``import neurov`` stays cheap."""

from __future__ import annotations

import importlib
import sys
import types
from typing import Any

__all__ = ["Identification", "IdentificationError", "Log", "LogError", "identify", "make_log",
           "read_log", "report_text"]

_WHERE = {"Identification": "fit", "identify": "fit", "IdentificationError": "errors",
          "LogError": "errors", "Log": "log", "make_log": "log", "read_log": "readers",
          "report_text": "report"}


def __getattr__(name: str) -> Any:
    if name in _WHERE:
        return getattr(importlib.import_module(f"{__name__}.{_WHERE[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


class _CallablePackage(types.ModuleType):
    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        from neurov.identify.fit import identify

        return identify(*args, **kwargs)


sys.modules[__name__].__class__ = _CallablePackage
