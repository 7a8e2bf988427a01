"""``neurov identify``: the command line's arguments and what it prints."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

__all__ = ["add_parser", "run"]

DESCRIPTION = (
    "Fits a vehicle file to logs of the vehicle moving under known forces: neurov runs' result.npz "
    "or result.csv, ArduSub .tlog or DataFlash .bin (no mapping needed: their standard messages and the "
    "vehicle's own parameters), or other logs (CSV, ROS 1/2 bags) described by a --mapping file. "
    "First a log report: each signal's rate, gaps, range and whether it moves, each DOF's share of "
    "thrust and motion, whether the log can tell each free parameter, and an excitation plan where "
    "it cannot (--report: only that). "
    "The free parameters (default: added mass, linear and quadratic damping of every DOF) are "
    "fitted by equation error on the regressor, then by output error over short segments; the "
    "rest is the template's. Prints each parameter's estimate and 95 % interval (a block "
    "bootstrap), the excitation's condition number, warnings, and with --heldout the fit "
    "(NRMSE %) of the fitted vehicle's free run on logs it was not fitted to. A fit with warnings is "
    "written and exits 0; a non-zero exit means nothing was fitted, and says why. See "
    "docs/identification.md.")


def add_parser(sub: Any, epilog: str) -> None:
    p = sub.add_parser("identify", help="fit a vehicle file to logs", description=DESCRIPTION,
                       epilog=epilog, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("logs", nargs="+", metavar="LOG", help="the logs to fit to")
    p.add_argument("--vehicle", required=True, metavar="TEMPLATE.toml",
                   help="the template vehicle file (a shipped preset's name also works)")
    p.add_argument("--out", default=None, metavar="FITTED.toml", help="write the fitted vehicle file")
    p.add_argument("--free", default=None, metavar="LIST",
                   help="comma-separated groups (added_mass, linear_damping, quadratic_damping, "
                        "mass, inertia, restoring) or parameter names to fit")
    p.add_argument("--heldout", nargs="*", default=[], metavar="LOG",
                   help="logs not fitted to, on which the fitted vehicle's free run is scored")
    p.add_argument("--plot", default=None, metavar="FIGURE.png",
                   help="write the estimates, their intervals and the held-out free runs as a figure")
    p.add_argument("--mapping", default=None, metavar="MAPPING.toml",
                   help="what the logs' signals are (for logs that are not neurov's own)")
    p.add_argument("--equation-error-only", action="store_true",
                   help="skip the output-error stage (faster, biased on noisy data)")
    p.add_argument("--substeps", type=int, default=1, metavar="N",
                   help="RK4 steps per log interval in the output error and free runs, 1..10000 "
                        "(neurov.MAX_SUBSTEPS, as a scenario's) (default 1)")
    p.add_argument("--block", type=float, default=5.0, metavar="SECONDS",
                   help="length of the bootstrap's blocks (default 5 s)")
    p.add_argument("--velocity-lag", type=_lag, default=0.0, metavar="SECONDS|auto",
                   help="the estimator's lag of the linear velocity behind the motion, undone "
                        "before fitting; 'auto' estimates it from the data (default 0)")
    p.add_argument("--estimator", choices=("auto", "on", "off", "linear"), default="auto",
                   help="model an estimator that holds the linear velocity between sensor updates "
                        "(an EKF's staircase) and filters the rates in the output error: auto (where "
                        "the logs show one), on, off, or linear (the staircase only, for logged raw "
                        "gyro rates) (default auto)")
    p.add_argument("--report", action="store_true",
                   help="print the log report (signals, excitation per DOF, what the log can tell, "
                        "an excitation plan) and stop before the fit")
    p.add_argument("--water-density", type=float, default=None, metavar="KG_M3",
                   help="the water of the logs, for a template that gives its displaced volume")


_ESTIMATOR: dict[str, bool | str] = {"auto": "auto", "on": True, "off": False, "linear": "linear"}


def _lag(text: str) -> float | str:
    if text == "auto":
        return text
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected seconds or 'auto', got {text!r}") from None


def run(args: argparse.Namespace) -> int:
    # Deferred: this module is imported for `neurov --help`; the fit needs SciPy.
    import sys

    from neurov import _core
    from neurov.files import check_output_file
    from neurov.identification.fit import NothingToFit, identify, report_only
    from neurov.identification.report import report_text
    from neurov.identification.printout import report_and_plan
    from neurov.progress import stage
    from neurov.config.vehicle_file import preset_names, preset_path

    vehicle = args.vehicle
    preset: str | None = None
    if not Path(vehicle).exists() and vehicle in preset_names():
        preset = str(vehicle)
        vehicle = preset_path(preset)
    if not 1 <= args.substeps <= _core.MAX_SUBSTEPS:
        raise ValueError(f"--substeps: expected an integer in 1..{_core.MAX_SUBSTEPS} (neurov.MAX_SUBSTEPS, "
                         f"as a scenario's substeps), got {args.substeps}")
    if args.block <= 0:
        raise ValueError(f"--block: expected seconds > 0, got {args.block}")
    # Before the fit: a path that cannot be written is said now, not after minutes of work.
    for option, path in (("--out", args.out), ("--plot", args.plot)):
        if path is not None:
            check_output_file(path, option)
    if args.report:
        text, written = report_and_plan(report_only(args.logs, vehicle, free=args.free, mapping=args.mapping),
                                        vehicle, preset, args.out)
        print(text + "".join(f"wrote {p}\n" for p in written), end="")
        return 0
    stages = "equation error" + ("" if args.equation_error_only else ", then output error") + \
        ", 95 % intervals by a block bootstrap" + (", then the held-out logs" if args.heldout else "")
    stage(f"identify: fitting {vehicle} to {len(args.logs)} log(s): {stages} (tens of seconds)")
    try:
        result = identify(args.logs, vehicle, free=args.free, heldout=args.heldout, out=args.out,
                          mapping=args.mapping, output_error=not args.equation_error_only,
                          substeps=args.substeps, block_s=args.block, water_density=args.water_density,
                          velocity_lag=args.velocity_lag,
                          estimator=_ESTIMATOR[args.estimator])
    except NothingToFit as e:
        text, written = report_and_plan(e.log_report, vehicle, preset, args.out)
        print(text + "".join(f"wrote {p}\n" for p in written), end="")
        print(f"neurov: error: {e}; no vehicle file written", file=sys.stderr)
        return 1
    text, written = report_and_plan(result.log_report, vehicle, preset, args.out, report_text(result))
    print(text, end="")
    if result.warnings:
        print(f"neurov: {len(result.warnings)} warning(s) above; the fit is written with them in its header",
              file=sys.stderr)
    for p in [result.out, *written] if result.out is not None else written:
        print(f"wrote {p}")
    if args.plot is not None:
        print(f"wrote {_write_plot(result, Path(args.plot))}")
    if result.out is None and args.plot is None:
        print("wrote nothing (--out FITTED.toml writes the fitted vehicle file, --plot FILE the figure)")
    return 0


def _write_plot(result: Any, plot: Path) -> Path:
    """The identification figure into `plot`, drawn beside it and moved in
    whole: a full disk leaves neither half a figure nor the old one cut."""
    import os
    import tempfile

    from neurov.files import writing
    from neurov.identification.plots import plot_identification  # deferred: Matplotlib

    with writing(plot, f"{str(plot)!r} (--plot)"):
        fd, tmp = tempfile.mkstemp(prefix=f".{plot.name}.", suffix=plot.suffix, dir=plot.parent)
        os.close(fd)
        try:
            plot_identification(result, tmp)
            os.replace(tmp, plot)
        finally:
            Path(tmp).unlink(missing_ok=True)
    return plot
