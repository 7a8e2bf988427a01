"""The log report: what a log holds and what it can tell, before any fit.

Per signal (the 18 columns of pose, body velocity and force): how often its
value changes (a signal held between a sensor's updates changes at the
sensor's rate, whatever the log's row rate), its largest gap, its range, and
whether it moves at all. Per DOF: the share of the rows with thrust outside
the thrusters' dead band (a force that is not zero) and the share with
motion (speed above MOVING). Per free parameter: whether the log can tell it
(``excited``), hardly (``too quiet``: fitted, with a warning) or not at all
(``no``: left at the template's value, never written as a fitted number).
The thresholds are ours, stated here and in docs/identification.md."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from neurov import _core
from neurov.identification.log import Log

__all__ = ["DOFS", "LogReport", "analyse_logs", "dof_of", "report_lines"]

Array = NDArray[np.float64]
DOFS = ("surge", "sway", "heave", "roll", "pitch", "yaw")
_COLUMNS = (("x", "m"), ("y", "m"), ("z", "m"), ("roll", "rad"), ("pitch", "rad"), ("yaw", "rad"),
            ("u", "m/s"), ("v", "m/s"), ("w", "m/s"), ("p", "rad/s"), ("q", "rad/s"), ("r", "rad/s"),
            ("X", "N"), ("Y", "N"), ("Z", "N"), ("K", "N m"), ("M", "N m"), ("N", "N m"))
# A signal whose peak-to-peak stays below this (its unit's) never moves.
STILL = (1e-3,) * 3 + (1e-3,) * 3 + (1e-3,) * 3 + (1e-4,) * 3 + (1e-6,) * 6
# A DOF moves on a row where its speed exceeds this [m/s or rad/s].
MOVING = (0.02, 0.02, 0.02, 0.02, 0.02, 0.02)
# Shares of the rows (thrust outside the dead band and motion, the smaller
# of the two): below NOT_AT_ALL the log cannot tell the DOF's parameters,
# below QUIET it hardly can.
NOT_AT_ALL = 0.02
QUIET = 0.10
# Fewer samples of a DOF's force outside the dead band than this (counting
# a value held over several rows once): the log cannot tell its parameters.
MIN_SAMPLES = 20
# Plausible sample rates [Hz] of a vehicle's log; outside, the time unit is suspect.
RATE_RANGE = (0.5, 2000.0)


@dataclass
class LogReport:
    """What :func:`analyse_logs` found. `verdicts` maps a free parameter's
    index to (``excited`` | ``too quiet`` | ``no``, why); `problems` are said
    first, in words a pilot understands."""

    signals: list[tuple[str, str, float, float, float, float, bool]]
    thrust_share: Array
    motion_share: Array
    verdicts: dict[int, tuple[str, str]]
    thrust_samples: Array  #: per DOF: distinct logged values of the force outside the dead band
    problems: list[str] = field(default_factory=list)
    rows: int = 0
    duration: float = 0.0
    notes: list[str] = field(default_factory=list)  #: what the readers used (parameters, rates)
    absent: tuple[str, ...] = ()  #: the signals no log has (held at zero), as Log.absent

    def absent_dofs(self) -> list[int]:
        """The DOFs whose body velocity is not in the logs (no flight tells them)."""
        return [d for d in range(3) if "uvw"[d] in self.absent]

    def weak_dofs(self) -> list[int]:
        """The DOFs whose parameters the log tells too quietly or not at all
        (those not in the log are not: flying them again would not help)."""
        return [d for d in range(6) if d not in self.absent_dofs()
                and (min(self.thrust_share[d], self.motion_share[d]) < QUIET
                     or self.thrust_samples[d] < MIN_SAMPLES)]

    def untold(self) -> dict[int, str]:
        """The free parameters the log cannot tell, with why."""
        return {i: why for i, (v, why) in self.verdicts.items() if v == "no"}


def _updates_hz(t: Array, x: Array) -> float:
    changes = np.count_nonzero(np.diff(x) != 0)
    span = t[-1] - t[0]
    return changes / span if span > 0 else float("nan")


def dof_of(i: int) -> tuple[int, ...]:
    """The DOFs a parameter acts in (mass: the linear ones, W - B: heave,
    the restoring moment: roll and pitch)."""
    if i == 0:
        return (0, 1, 2)
    if 1 <= i <= 3:
        return (i + 2,)
    if 4 <= i <= 21:
        return ((i - 4) % 6,)
    return (2,) if i == 22 else (3, 4)


def _verdict(i: int, thrust: Array, motion: Array, peak: Array, samples: Array,
             absent: tuple[str, ...] = ()) -> tuple[str, str]:
    dofs = dof_of(i)
    if all(d < 3 and "uvw"[d] in absent for d in dofs):
        return "no", (f"not in this log: {', '.join('uvw'[d] for d in dofs)} not logged (no linear velocity "
                      "or position), so its DOF cannot be told")
    if max(samples[d] for d in dofs) < MIN_SAMPLES:
        d = max(dofs, key=lambda k: samples[k])
        return "no", (f"the log cannot tell it ({DOFS[d]}: the force outside the dead band was logged "
                      f"only {int(samples[d])} times; {MIN_SAMPLES} at least)")
    share = max(min(thrust[d], motion[d]) for d in dofs)
    d = max(dofs, key=lambda k: min(thrust[k], motion[k]))
    words = (f"{DOFS[d]}: thrust outside the dead band on {100 * thrust[d]:.1f} % of the log, "
             f"motion on {100 * motion[d]:.1f} %")
    if share < NOT_AT_ALL:
        return "no", f"the log cannot tell it ({words})"
    if 16 <= i <= 21 and peak[d] < 5 * MOVING[d]:
        return "too quiet", (f"the {DOFS[d]} speed never exceeds {peak[d]:.3g}: too slow to tell "
                             "quadratic from linear damping")
    if share < QUIET:
        return "too quiet", words
    return "excited", words


def analyse_logs(logs: list[Log], free: list[int]) -> LogReport:
    """The log report of `logs` for the free parameters `free` (indices of
    ``neurov._core.THETA_NAMES``)."""
    t = np.concatenate([log.t for log in logs])
    data = np.concatenate([np.hstack([log.eta, log.nu, log.tau]) for log in logs])
    rows = len(t)
    signals = []
    problems: list[str] = [f"{log.source}: {p}" for log in logs for p in log.problems]
    # A signal some log lacks is not in the data (held at zero there).
    absent = tuple(n for n, _ in _COLUMNS[:12] if any(n in log.absent for log in logs))
    gone = [DOFS[d] for d in range(3) if "uvw"[d] in absent]
    if absent:
        kept = [DOFS[d] for d in range(6) if DOFS[d] not in gone]
        problems.append(f"the log has no {', '.join(absent)} (no DVL or positioning logged): "
                        + (f"{', '.join(gone)} left out of the fit, their parameters kept at the "
                           "template's values (\"not in this log\"); " if gone else "")
                        + f"{', '.join(kept)} identified with the missing linear velocities taken as zero "
                        "(their coupling into the rotation is not measured)"
                        + ("; the depth is logged, but its rate is the heave velocity only while u and v "
                           "are zero: a vehicle heaving as it pitches moves along its own x, so heave is not "
                           "fitted from the depth alone" if "w" in absent and "z" not in absent else ""))
    for k, (name, unit) in enumerate(_COLUMNS):
        x = data[:, k]
        hz = float(np.nanmean([_updates_hz(log.t, np.hstack([log.eta, log.nu, log.tau])[:, k]) for log in logs]))
        gap = max(float(np.max(np.diff(log.t))) if len(log.t) > 1 else 0.0 for log in logs)
        moves = bool(np.ptp(x) > STILL[k])
        signals.append((name, unit, hz, gap, float(np.min(x)), float(np.max(x)), moves))
        if not moves and k >= 6 and name not in absent:
            problems.append(f"{name} [{unit}] never moves (range {np.min(x):.3g} to {np.max(x):.3g}): "
                            + ("no thrust in this DOF" if k >= 12 else "a dead signal, or a DOF that was never driven"))
    tau = data[:, 12:]
    nu = data[:, 6:12]
    thrust = np.mean(np.abs(tau) > 1e-9 * max(1.0, float(np.max(np.abs(tau)))), axis=0)
    motion = np.mean(np.abs(nu) > np.array(MOVING), axis=0)
    peak = np.percentile(np.abs(nu), 95, axis=0)
    for log in logs:
        hz = 1.0 / log.dt if log.dt > 0 else float("inf")
        if not RATE_RANGE[0] <= hz <= RATE_RANGE[1]:
            problems.append(f"{log.source}: the rows come at {hz:.3g} Hz, implausible for a vehicle's log "
                            f"(expected {RATE_RANGE[0]:g} to {RATE_RANGE[1]:g} Hz): is the time column in "
                            "milliseconds (or microseconds) but labelled seconds? (the mapping's time.unit)")
        ratio = None if log.absent else _kinematic_ratio(log)
        if ratio is not None and not 0.2 <= ratio <= 5.0:
            problems.append(f"{log.source}: the position changes {ratio:.3g} times as fast as the logged "
                            "velocity says: a time or velocity unit is wrong (the mapping's units)")
    samples = np.zeros(6)
    for log in logs:
        on = np.abs(log.tau) > 1e-9 * max(1.0, float(np.max(np.abs(tau))))
        fresh = np.vstack([np.ones((1, 6), bool), np.diff(log.tau, axis=0) != 0])
        for a, b in log.segments:
            fresh[a] = True
        samples += np.sum(on & fresh, axis=0)
    verdicts = {i: _verdict(i, thrust, motion, peak, samples, absent) for i in free}
    for d in range(6):
        if DOFS[d] in gone:
            continue
        if thrust[d] < QUIET and any(d in dof_of(i) for i in free):
            problems.append(f"{DOFS[d]}: the thrusters push in this DOF on only {100 * thrust[d]:.1f} % of "
                            "the log (the rest is inside the dead band or zero)")
        elif samples[d] < MIN_SAMPLES and any(d in dof_of(i) for i in free):
            problems.append(f"{DOFS[d]}: the force outside the dead band was logged only {int(samples[d])} "
                            "times (the thruster outputs are logged too slowly, or pushed too briefly)")
    notes = [f"{log.source}: {n}" for log in logs for n in log.notes]
    return LogReport(signals, thrust, motion, verdicts, samples, problems, rows,
                     float(sum(log.duration for log in logs)), notes, absent)


def _kinematic_ratio(log: Log, window_s: float = 2.0) -> float | None:
    """Median over windows of `window_s` of the position's change over the
    logged velocity's integral (world frame); None where the vehicle moves
    too little to tell. About 1 when time and velocity units agree."""
    v = np.einsum("kij,kj->ki", np.array([_core.rotation(*e[3:]) for e in log.eta]), log.nu[:, :3])
    ratios = []
    for a, b in log.segments:
        step = max(2, int(round(window_s / log.dt)))
        for k in range(a, b - step, step):
            dt = np.diff(log.t[k:k + step + 1])
            path = np.linalg.norm(np.sum(v[k:k + step] * dt[:, None], axis=0))
            if path > 0.05:
                ratios.append(np.linalg.norm(log.eta[k + step, :3] - log.eta[k, :3]) / path)
    return float(np.median(ratios)) if len(ratios) >= 3 else None


def report_lines(r: LogReport) -> list[str]:
    """The report in words and two tables."""
    lines = [f"Log report: {r.rows} rows, {r.duration:.1f} s"]
    lines += [f"Problem: {p}" for p in r.problems]
    lines += [f"Read: {n}" for n in r.notes]
    lines += ["", f"{'signal':<8}{'unit':<7}{'changes/s':>10}{'largest gap s':>14}{'min':>11}{'max':>11}  moves"]
    for name, unit, hz, gap, lo, hi, moves in r.signals:
        said = "not logged" if name in r.absent else "yes" if moves else "NO"
        lines.append(f"{name:<8}{unit:<7}{hz:>10.3g}{gap:>14.3g}{lo:>11.4g}{hi:>11.4g}  {said}")
    lines += ["", f"{'DOF':<8}{'thrust outside dead band':>26}{'its samples':>13}{'motion':>10}"]
    for d in range(6):
        motion = "not logged" if d in r.absent_dofs() else f"{100 * r.motion_share[d]:.1f}%"
        lines.append(f"{DOFS[d]:<8}{100 * r.thrust_share[d]:>25.1f}%{int(r.thrust_samples[d]):>13d}"
                     f"{motion:>10}")
    lines += ["", f"{'parameter':<16}{'can the log tell it':<22}why"]
    for i, (v, why) in sorted(r.verdicts.items()):
        lines.append(f"{_core.THETA_NAMES[i]:<16}{v:<22}{why}")
    return lines
