"""Identification: a vehicle file fitted to recorded runs, with a 95 %
interval for each parameter and the fit on held-out logs (the method:
docs/identification.md).

``neurov.identify(logs, vehicle, out=...)`` is :func:`identify`. Nothing
heavy (SciPy's optimiser, the log readers) is imported until used, so that
``import neurov`` stays cheap."""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from neurov.identification.outcome import Identification

__all__ = ["Identification", "IdentificationError", "Log", "LogError", "NothingToFit", "identify",
           "make_log", "read_log", "read_log_parameters", "report_only", "report_text"]

_WHERE = {"Identification": "outcome", "IdentificationError": "errors", "LogError": "errors",
          "Log": "log", "make_log": "log", "read_log": "readers", "report_text": "report",
          "NothingToFit": "fit", "report_only": "fit", "read_log_parameters": "ardusub_params"}


def __getattr__(name: str) -> Any:
    if name in _WHERE:
        return getattr(importlib.import_module(f"{__name__}.{_WHERE[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def identify(*args: Any, **kwargs: Any) -> Identification:
    """Fits a vehicle file to logs: :func:`neurov.identification.fit.identify`
    (its arguments and what it returns are documented there)."""
    # Deferred: the fit needs SciPy; `import neurov` stays cheap.
    from neurov.identification.fit import identify as fit

    return fit(*args, **kwargs)
