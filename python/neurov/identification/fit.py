"""``neurov.identify``: logs and a template vehicle file in, a fitted
vehicle file with the uncertainty of each parameter out."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov import _core
from neurov.identification.equation_error import equation_rows, fit_linear
from neurov.identification.blocks import small_sample_scale
from neurov.identification.errors import IdentificationError
from neurov.identification.heldout import held_out
from neurov.identification.estimator_model import staircase
from neurov.identification.lag import profile_lag
from neurov.identification.log import Log, advance_linear_velocity
from neurov.identification.output_error import bounds, fit_output_error
from neurov.identification.parameters import free_indices, template_theta
from neurov.identification.readers import read_log
from neurov.config.vehicle_file import read_vehicle_file
from neurov.files import read_toml
from neurov.identification.outcome import Identification
from neurov.identification.report import header_lines
from neurov.identification.guards import MIN_BLOCKS, WIDE, fit_warnings, inseparable, verdict_warnings
from neurov.identification.heldout import free_run, nrmse_fit
from neurov.identification.survey import LogReport, analyse_logs
from neurov.identification.vehicle_writer import write_vehicle_file
from neurov.threads import one_blas_thread

__all__ = ["Identification", "NothingToFit", "identify", "report_only", "MIN_BLOCKS", "WIDE"]

Array = NDArray[np.float64]


class NothingToFit(IdentificationError):
    """The logs cannot tell any free parameter: nothing fitted; `log_report` says why."""

    def __init__(self, message: str, log_report: LogReport) -> None:
        super().__init__(message)
        self.log_report = log_report


@one_blas_thread
def identify(logs: list[str | Path | Log] | str | Path | Log, vehicle: str | Path, *,
             free: str | list[str] | None = None, heldout: list[str | Path | Log] | None = None,
             out: str | Path | None = None, mapping: str | Path | None = None,
             output_error: bool = True, substeps: int = 1, window_s: float = 0.5,
             block_s: float = 5.0, replicates: int = 1000, seed: int = 0,
             water_density: float | None = None, segment_s: float = 2.0,
             velocity_lag: float | str = 0.0, estimator: bool | str = "auto") -> Identification:
    """Fits the `free` parameters (default: added mass, linear and quadratic
    damping of every DOF; also ``mass``, ``inertia``, ``restoring`` for W - B
    and z_g W - z_b B) of the template vehicle file `vehicle` to `logs`
    (neurov's result.npz/.csv/.parquet, or other formats with a `mapping`
    file), by equation error and then (`output_error`) output error;
    95 % intervals from a block bootstrap over `block_s`-second blocks
    (`replicates` draws: with 200 the percentiles' own noise lowered the
    coverage of 12 blocks' intervals by a point, tests/python/test_identify_blocks.py);
    with `heldout` logs, the NRMSE fit % per DOF of the fitted vehicle's
    free run on each; with `out`, writes the fitted vehicle file.
    Stage 2's shooting segments are `segment_s` seconds long.
    `velocity_lag` [s] moves the logs' linear velocities that much earlier,
    for an estimator's lag; ``"auto"`` estimates it from the data
    (:mod:`neurov.identification.lag`). `estimator` models in stage 2 an
    estimator that holds the linear velocity between a sensor's updates
    (:mod:`neurov.identification.estimator_model`): ``"auto"`` where a log's
    linear velocity is such a staircase, True, or False (docs/identification.md,
    the worked example); the rates go through the estimator's filter with it,
    except with ``"linear"`` (the staircase alone: a log of raw gyro rates)."""
    read = _read(logs, mapping, vehicle)
    template = read_vehicle_file(vehicle)
    if water_density is not None:
        template = template.in_water(water_density)
    theta0 = template_theta(template.vehicle(), str(vehicle))
    asked = free_indices(free)
    log_report = analyse_logs(read, asked)
    untold = log_report.untold()
    free_idx = [i for i in asked if i not in untold]
    if not free_idx:
        raise NothingToFit("none of the free parameters can be identified from the logs: "
                           + "; ".join(f"{_core.THETA_NAMES[i]}: "
                                       + ("not in this log" if why.startswith("not in this log") else "not excited")
                                       for i, why in untold.items())
                           + " (the log report says why); nothing fitted: fly the excitation plan and "
                           "identify again", log_report)
    model_rates = estimator != "linear"
    if estimator == "auto":
        # A log with no linear velocity has no staircase to model (its zeros are not updates).
        model_estimator = output_error and any(staircase(log) for log in read
                                               if not set("uvw") & set(log.absent))
    elif isinstance(estimator, bool):
        model_estimator = estimator and output_error
    elif estimator == "linear":
        model_estimator = output_error
    else:
        raise IdentificationError(f"estimator: expected True, False, 'auto' or 'linear', got {estimator!r}")

    def stages(logs_: list[Log]) -> _Stages:
        return _fit_stages(logs_, template.parameters, theta0, free_idx, output_error,
                           window_s=window_s, block_s=block_s, segment_s=segment_s, substeps=substeps,
                           estimator=model_estimator, rates=model_rates)

    lag_note: list[str] = []
    if velocity_lag == "auto":
        if not output_error:
            raise IdentificationError("velocity_lag='auto' is judged by the output-error residual: "
                                      "it needs the output-error stage")
        lag, read, st, profile = profile_lag(read, stages, lambda x: x.rms)
        lag_note.append("velocity lag estimated from the data: " + f"{lag:g} s (output-error RMS " +
                        ", ".join(f"{r:.4g} at {l:g} s" for l, r in profile) + ")")
    elif isinstance(velocity_lag, (int, float)) and not isinstance(velocity_lag, bool):
        read = [advance_linear_velocity(log, float(velocity_lag)) for log in read]
        st = stages(read)
    else:
        raise IdentificationError(f"velocity_lag: expected seconds >= 0 or 'auto', got {velocity_lag!r}")
    rows, lin, theta, blocks, offset = st.rows, st.lin, st.theta, st.blocks, st.offset
    lo, hi = bounds(lin.fitted, template.parameters)
    stages_done = "equation error, then output error" if output_error else "equation error"
    if blocks.count < 2:
        raise IdentificationError(f"the logs are too short for a bootstrap: {blocks.count} block of "
                                  f"{block_s:g} s; record longer or pass a shorter block_s")
    try:
        samples = blocks.bootstrap(replicates, seed)
    except np.linalg.LinAlgError:
        raise IdentificationError("the logs are too short for a bootstrap: resampled blocks leave a "
                                  "free parameter unexcited; "
                                  + inseparable(blocks.gram.sum(axis=0)[:len(lin.fitted), :len(lin.fitted)],
                                                lin.fitted)) from None
    if st.fallback:
        output_error = False
        stages_done = "equation error (the output-error stage failed: " + st.fallback + ")"
    if output_error:
        samples = samples + offset[lin.fitted]
    interval = np.full((24, 2), np.nan)
    q = np.percentile(samples, [2.5, 97.5], axis=0).T
    # Few blocks: the percentiles' distances from the estimate (before the
    # bounds, as the samples are) stretched (blocks.py).
    try:
        centre = (blocks.solve() + (offset[lin.fitted] if output_error else 0.0))[:, None]
    except np.linalg.LinAlgError:
        raise IdentificationError(inseparable(blocks.gram.sum(axis=0)[:len(lin.fitted), :len(lin.fitted)],
                                              lin.fitted) + ": fix one of each with --free") from None
    q = centre + small_sample_scale(blocks.count) * (q - centre)
    interval[lin.fitted] = np.clip(q, lo[:, None], hi[:, None])
    reasons = {**lin.reasons, **{i: (f"{why}: left at the template's value" if why.startswith("not in this log")
                                     else f"not excited: left at the template's value, {why}")
                                 for i, why in untold.items()}}
    result = Identification(template=template, logs=read, theta_template=theta0, theta=theta,
                            theta_stage1=lin.theta, fitted=lin.fitted, reasons=reasons,
                            interval=interval, condition=lin.condition, stages=stages_done,
                            log_report=log_report)
    if st.gain is not None:
        lag_note.append("the logs' linear velocity is held between sensor updates (an estimator's "
                        "staircase): modelled in the output error, update gains (u, v, w) "
                        + ", ".join(f"{g:.3f}" for g in st.gain[:3])
                        + (", (p, q, r) " + ", ".join(f"{g:.3f}" for g in st.gain[3:])
                           if len(st.gain) > 3 else ""))
    dead = [n for n in st.dead if n not in log_report.absent]
    if dead:
        lag_note.append(f"output error: {', '.join(dead)} never move in the logs (a dead signal): "
                        "left out of its residual, the simulated motion compared on the others")
    if log_report.absent:
        lag_note.append(f"{', '.join(log_report.absent)} not in the logs: held at zero in the equation error, "
                        "left out of the output error's residual and the free runs' verdict (simulated "
                        "with the template's values there)")
    if st.rejected:
        lag_note.append(f"output error: {st.rejected} trial step(s) overflowed in the simulation and were "
                        "rejected (the solver went on from the last good point)")
    if st.fallback:
        lag_note.append(f"the output-error stage failed ({st.fallback}): the equation-error estimate is "
                        "written; it is biased on noisy data")
    reader_problems = {f"{log.source}: {p}" for log in read for p in log.problems}
    result.warnings = (lag_note + [p for p in log_report.problems if p not in reader_problems]
                       + fit_warnings(read, rows, lin, interval, theta, theta0, lo, hi))
    fitted_vehicle = result.vehicle()
    result.warnings += _self_verdict(read, fitted_vehicle, substeps)
    for h in heldout or []:
        hl = _read(h, mapping, vehicle)[0]
        result.heldout.append(held_out(hl, fitted_vehicle, template.vehicle(), substeps))
        moved = np.ptp(hl.nu, axis=0) > 1e-3
        result.warnings += verdict_warnings(hl.source, result.heldout[-1].fit, moved,
                                            "held-out fit (free run)")
    if out is not None:
        result.out = write_vehicle_file(out, vehicle, result.parameters(), header_lines(result),
                                        name=f"{_name(vehicle)} (fitted)",
                                        source=f"neurov identify from {', '.join(l.source for l in read)}")
    return result


def _self_verdict(logs: list[Log], vehicle: Any, substeps: int) -> list[str]:
    """The fitted vehicle's free run on the logs it was fitted to, judged."""
    out = []
    for log in logs:
        try:
            run = free_run(vehicle, log, substeps)
        except ValueError as e:  # the free run overflowed: the model is far off
            out.append(f"the fitted vehicle's free run on {log.source} fails ({e}): the template's "
                       "structure or the log is wrong")
            continue
        out += verdict_warnings(log.source, nrmse_fit(log.nu, run), np.ptp(log.nu, axis=0) > 1e-3,
                                "fit of the free run on the fitted log")
    return out


@dataclass
class _Stages:
    rows: Any
    lin: Any
    theta: Array
    blocks: Any
    offset: Array
    rms: float
    gain: Array | None = None
    rejected: int = 0
    fallback: str = ""
    dead: tuple[str, ...] = ()


def _fit_stages(logs: list[Log], template: dict[str, Any], theta0: Array, free_idx: list[int],
                output_error: bool, *, window_s: float, block_s: float, segment_s: float,
                substeps: int, estimator: bool, rates: bool = True) -> _Stages:
    """Stage 1, then (`output_error`) stage 2 from it: the estimate, the
    blocks of its bootstrap and the offset their samples are taken from."""
    rows = equation_rows(logs, window_s=window_s, block_s=block_s)
    lin = fit_linear(rows, theta0, free_idx)
    theta1 = lin.theta.copy()
    lo, hi = bounds(lin.fitted, template)
    theta1[lin.fitted] = np.clip(theta1[lin.fitted], lo, hi)
    if not output_error:
        return _Stages(rows, lin, theta1, lin.blocks, np.zeros(24), float("nan"))
    try:
        oe = fit_output_error(logs, template, theta1, lin.fitted, segment_s=segment_s,
                              substeps=substeps, block_s=block_s, estimator=estimator, rates=rates)
    except (ValueError, IdentificationError) as e:  # LinAlgError is a ValueError
        return _Stages(rows, lin, theta1, lin.blocks, np.zeros(24), float("nan"), fallback=str(e))
    return _Stages(rows, lin, oe.theta, oe.blocks, oe.at, oe.rms, gain=oe.gain, rejected=oe.rejected,
                   dead=oe.dead)


def _name(path: str | Path) -> str:
    data = read_toml(Path(path), IdentificationError, "vehicle")
    return str(data.get("name", Path(path).stem))


def _thrusters(path: str | Path) -> Any:
    return read_vehicle_file(path).thrusters


def report_only(logs: list[str | Path | Log] | str | Path | Log, vehicle: str | Path, *,
                free: str | list[str] | None = None, mapping: str | Path | None = None) -> LogReport:
    """The log report of `logs` for the `free` parameters, without a fit."""
    return analyse_logs(_read(logs, mapping, vehicle), free_indices(free))


def _read(logs: list[str | Path | Log] | str | Path | Log, mapping: str | Path | None,
          vehicle: str | Path) -> list[Log]:
    """The logs read (a Log as it is)."""
    items = logs if isinstance(logs, list) else [logs]
    read = [x if isinstance(x, Log) else read_log(x, mapping, _thrusters(vehicle)) for x in items]
    if not read:
        raise IdentificationError("no log given")
    return read
