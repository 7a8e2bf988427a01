"""The log report and excitation plan as ``neurov identify`` prints and
writes them: in the fitted file's header and, when a DOF is too weak, the
plan as ``FITTED_excitation.toml`` beside it; without a fit (``--report``, or
a log that tells nothing) as ``FITTED.report.txt`` beside ``--out``; nothing
is written without ``--out``."""

from __future__ import annotations

from pathlib import Path

from neurov.identification.excitation_plan import plan
from neurov.identification.survey import LogReport, report_lines

__all__ = ["report_and_plan"]


def report_and_plan(report: LogReport | None, vehicle: str | Path, preset: str | None, out: str | Path | None,
                    fit_text: str = "") -> tuple[str, list[Path]]:
    """The text to print and the files written: the log report (or
    `fit_text`, the fit's, which holds it), the plan's pilot steps, and beside
    `out` the plan's scenario and (without a fit) the report."""
    from neurov.config.vehicle_file import read_vehicle_file
    from neurov.identification.parameters import template_theta

    if report is None:
        return fit_text, []
    template = read_vehicle_file(vehicle)
    theta0 = template_theta(template.vehicle(), str(vehicle))
    lines, scenario = plan(report, vehicle, preset, template, float(theta0[23]))
    base = Path(out) if out is not None else None
    written: list[Path] = []
    text = fit_text or "\n".join(report_lines(report)) + "\n"
    if lines:
        text += "\n" + "\n".join(lines) + "\n"
    if scenario is not None and base is None:
        text += "Give --out FITTED.toml to have the plan written as a neurov scenario to rehearse.\n"
    elif scenario is not None and base is not None:
        path = base.with_name(base.stem + "_excitation.toml")
        path.write_text(scenario)
        written.append(path)
        text += f"The same as a neurov scenario to rehearse: neurov run {path} --out rehearsal\n"
    if base is not None and not fit_text:  # a fit carries the report in its header
        path = base.with_name(base.stem + ".report.txt")
        path.write_text(text)
        written.append(path)
    return text, written
