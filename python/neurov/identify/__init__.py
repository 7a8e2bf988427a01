"""Identification: a vehicle file fitted to recorded runs, with a 95 %
interval for each parameter and the fit on held-out logs.

``neurov.identify.identify(logs, vehicle=TEMPLATE.toml, out=FITTED.toml)``;
the method is in docs/identification.md."""

from neurov.identify.errors import IdentificationError, LogError
from neurov.identify.fit import Identification, identify
from neurov.identify.log import Log, make_log
from neurov.identify.readers import read_log
from neurov.identify.report import report_text

__all__ = ["Identification", "IdentificationError", "Log", "LogError", "identify", "make_log",
           "read_log", "report_text"]
