"""The identification's report: the table printed by ``neurov identify``
and written as the fitted file's header."""

from __future__ import annotations

import numpy as np

from neurov import _core
from neurov.identification.outcome import Identification
from neurov.identification.survey import report_lines
from neurov.identification.parameters import UNITS

__all__ = ["header_lines", "report_text"]

_BODY = ("u", "v", "w", "p", "q", "r")


def _table(r: Identification) -> list[str]:
    lines = [f"{'parameter':<16}{'template':>12}{'estimate':>14}{'95 % interval':>30}  unit"]
    for i in sorted(set(r.fitted) | set(r.reasons)):
        name = _core.THETA_NAMES[i]
        if i in r.fitted:
            lo, hi = r.interval[i]
            lines.append(f"{name:<16}{r.theta_template[i]:>12.6g}{r.theta[i]:>14.6g}"
                         f"{f'[{lo:.6g}, {hi:.6g}]':>30}  {UNITS[i]}")
        else:
            lines.append(f"{name:<16}{r.theta_template[i]:>12.6g}{'(template)':>14}  {r.reasons[i]}")
    return lines


def _summary(r: Identification) -> list[str]:
    sources = ", ".join(f"{log.source} ({log.duration:.1f} s, {len(log.t)} rows)" for log in r.logs)
    lines = [f"Fitted by neurov identify from: {sources}",
             f"Template: {r.template.path}",
             f"Method: {r.stages}; 95 % intervals from a block bootstrap over the logs' segments",
             f"Excitation's condition number (scaled information matrix): {r.condition:.4g}"]
    if 22 in r.fitted or 23 in r.fitted:
        lines.append("Restoring: only W - B and z_g W - z_b B act on the motion; W and r_g are the "
                     "template's, B and z_b follow from the fit")
    for h in r.heldout:
        source, fit, base = h.source, h.fit, h.template_fit
        cells = ", ".join(f"{d} {f:.1f} %" for d, f in zip(_BODY, fit) if np.isfinite(f))
        base_cells = ", ".join(f"{d} {f:.1f} %" for d, f in zip(_BODY, base) if np.isfinite(f))
        lines.append(f"Held-out fit (NRMSE, free run, body velocities) on {source}: {cells}")
        lines.append(f"  the template's on the same log: {base_cells}")
    lines += [f"Warning: {w}" for w in r.warnings]
    return lines


def _log_part(r: Identification) -> list[str]:
    return [*report_lines(r.log_report), ""] if r.log_report is not None else []


def report_text(r: Identification) -> str:
    """The report as printed: the log report first, then the fit."""
    return "\n".join([*_log_part(r), *_summary(r), "", *_table(r)]) + "\n"


def header_lines(r: Identification) -> list[str]:
    """The report as the fitted file's header comment lines."""
    return [*_summary(r), "", *_table(r), "", *_log_part(r)]
