"""ArduSub telemetry logs (``.tlog``, or a DataFlash ``.bin`` that
pymavlink reads with the same message names) through ``pymavlink``.

The time base is ATTITUDE's ``time_boot_ms`` (roll, pitch, yaw and the body
rates p, q, r); LOCAL_POSITION_NED (the autopilot's position and NED
velocity, from its EKF: DVL, depth and IMU where logged) is held onto it and
its velocity turned into the body frame (a log without it is fitted in roll,
pitch and yaw: :func:`neurov.identification.log.fill_absent`); SERVO_OUTPUT_RAW's PWM goes through
the template's thruster curves (``ThrusterCurveConfig.static_thrust`` at the
template's supply voltage) and its configuration matrix to the force, after
the log's own MOT_n_DIRECTION reversals are undone
(:mod:`neurov.identification.ardusub_params`). A message older than the
mapping's ``max_age`` at a row cuts the row. No mapping file is needed; one
only overrides::

    format = "tlog"
    servo_channels = [1, 2, 3, 4, 5, 6, 7, 8]   # the servo output of each thruster (default 1..n)
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov import _core
from neurov.identification.alignment import hold
from neurov.identification.ardusub_params import parameter_notes, quiet, read_log_parameters, undo_directions
from neurov.identification.errors import LogError
from neurov.identification.log import Log, fill_absent, make_log
from neurov.identification.mapping import Mapping

__all__ = ["ardusub_force", "armed_rows", "cut_disarmed", "pwm_force", "rate_note", "read_tlog", "servo_channels"]

Array = NDArray[np.float64]


def servo_channels(mapping: Mapping, n: int) -> list[int]:
    """The servo output (1..16) of each of the `n` thrusters, from the mapping."""
    ch = mapping.data.get("servo_channels", list(range(1, n + 1)))
    if not (isinstance(ch, list) and len(ch) == n and all(isinstance(c, int) and 1 <= c <= 16 for c in ch)):
        raise LogError(f"{mapping.where}: servo_channels: expected {n} servo numbers from 1 to 16 "
                       f"(one per thruster), got {ch!r}")
    return ch


def check_thrusters(path: Path, thrusters: dict[str, Any] | None) -> dict[str, Any]:
    """`thrusters`, checked: LogError naming `path` when it is missing or
    when the template has no thruster curves to turn PWM into thrust."""
    if not path.is_file():
        raise LogError(f"{path}: no such file")
    if thrusters is None or thrusters.get("curves") is None:
        raise LogError(f"{path}: a telemetry log's PWM needs the template's [thrusters] with a "
                       "[thrusters.curve] to become a force")
    return thrusters


def pwm_force(pwm: Array, thrusters: dict[str, Any]) -> Array:
    """The body wrench (n, 6) of PWM rows (n, thrusters) through the
    template's thruster curves at its supply voltage and its configuration
    matrix; a row with a missing PWM stays NaN."""
    curves, volts = thrusters["curves"], thrusters["supply_voltage"]
    thrust = np.full_like(pwm, np.nan)
    ok = np.all(np.isfinite(pwm), axis=1)
    for i, c in enumerate(curves):
        thrust[ok, i] = [c.static_thrust(float(x), volts) for x in pwm[ok, i]]
    return thrust @ thrusters["matrix"].T


def rate_note(name: str, t: Array) -> str:
    """'NAME at R Hz' from a message's stamps (its median interval)."""
    step = float(np.median(np.diff(t))) if len(t) > 1 else float("nan")
    return f"{name} at {1.0 / step:.3g} Hz" if step > 0 else f"{name}: {len(t)} sample(s)"


def ardusub_force(path: Path, t: Array, pwm_t: Array, pwm: Array, mapping: Mapping,
                  thrusters: dict[str, Any], channels: list[int], what: str) -> tuple[Array, list[str]]:
    """The body wrench on the time base `t` from the servo outputs' PWM, with
    the log's MOT_n_DIRECTION undone, and the notes saying what was used."""
    notes, directions = parameter_notes(path, read_log_parameters(path), thrusters["matrix"].shape[1],
                                        channels)
    neutral = float(getattr(thrusters["curves"][0], "neutral", 1500.0))
    pwm = undo_directions(pwm, directions, neutral)
    held = hold(t, pwm_t, pwm, mapping.max_age, f"{path}: {what}")
    return pwm_force(held, thrusters), notes


# MAVLink: a HEARTBEAT of a ground station has autopilot MAV_AUTOPILOT_INVALID
# (8); base_mode's bit MAV_MODE_FLAG_SAFETY_ARMED (128) is set while armed.
_AUTOPILOT_INVALID = 8
_ARMED = 128


def armed_rows(beats: list[Any], stamps: Array) -> NDArray[np.bool_]:
    """Whether the vehicle was armed at each row (by the log's receive
    stamps `stamps`): the latest autopilot HEARTBEAT's armed flag."""
    bt = np.array([m._timestamp for m in beats])
    flag = np.array([bool(m.base_mode & _ARMED) for m in beats])
    k = np.searchsorted(bt, stamps, side="right") - 1
    return np.where(k >= 0, flag[np.clip(k, 0, None)], False)


def cut_disarmed(armed: NDArray[np.bool_], t: Array, tau: Array, notes: list[str],
                 problems: list[str], where: str) -> None:
    """Cuts (NaN force) the rows where the vehicle was disarmed, and says so:
    a note, or a problem where it was armed on less than half of the log;
    LogError naming `where` when it was never armed."""
    if not armed.any():
        raise LogError(f"{where}: the vehicle was never armed in this log: its thrusters never pushed, so "
                       "the log holds nothing to identify")
    tau[~armed] = np.nan
    text = (f"the vehicle was armed on only {100 * armed.mean():.1f} % of the log ({armed.sum()} of "
            f"{len(t)} rows, {t[armed][0] - t[0]:.1f} s to {t[armed][-1] - t[0]:.1f} s after the "
            "first): the disarmed rows are cut (no thrust; the vehicle may be out of the water)")
    if armed.mean() >= 0.5:
        notes.append(text.replace("only ", ""))
    else:
        problems.append(text)


def read_tlog(path: str | Path, mapping: Mapping | None, thrusters: dict[str, Any] | None) -> Log:
    from pymavlink import mavutil

    path = Path(path)
    thrusters = check_thrusters(path, thrusters)
    mapping = mapping or Mapping({"format": "tlog"}, f"{path} (no mapping: ArduSub's messages)")
    channels = servo_channels(mapping, thrusters["matrix"].shape[1])
    rows: dict[str, list[Any]] = {"ATTITUDE": [], "LOCAL_POSITION_NED": [], "SERVO_OUTPUT_RAW": [],
                                  "HEARTBEAT": []}
    try:
        with quiet():
            conn = mavutil.mavlink_connection(str(path), dialect="ardupilotmega")
            try:
                while True:
                    m = conn.recv_match(type=list(rows), blocking=False)
                    if m is None:
                        break
                    rows[m.get_type()].append(m)
            finally:
                conn.close()
    except Exception as e:  # pymavlink's own errors on a file that is not a telemetry log
        raise LogError(f"{path}: not a readable telemetry log: {type(e).__name__}: {e}") from None
    beats = [m for m in rows.pop("HEARTBEAT") if m.autopilot != _AUTOPILOT_INVALID]
    if beats and not any(m.base_mode & _ARMED for m in beats):
        raise LogError(f"{path}: the vehicle was never armed in this log (HEARTBEAT): its thrusters never "
                       "pushed, so the log holds nothing to identify")
    for name, found in rows.items():
        if not found and name != "LOCAL_POSITION_NED":  # without it: no position or linear velocity
            raise LogError(f"{path}: no {name} message (ArduSub sends it at the stream rates of its "
                           "SR*_ parameters)")
    att = rows["ATTITUDE"]
    t = np.array([m.time_boot_ms for m in att], dtype=np.float64) * 1e-3
    angles = np.array([[m.roll, m.pitch, m.yaw] for m in att], dtype=np.float64)
    rates = np.array([[m.rollspeed, m.pitchspeed, m.yawspeed] for m in att], dtype=np.float64)
    lp = rows["LOCAL_POSITION_NED"]
    lp_t = np.array([m.time_boot_ms for m in lp], dtype=np.float64) * 1e-3
    lp_v = np.array([[m.x, m.y, m.z, m.vx, m.vy, m.vz] for m in lp], dtype=np.float64)
    held = (hold(t, lp_t, lp_v, mapping.max_age, f"{path}: LOCAL_POSITION_NED") if lp
            else np.full((len(t), 6), np.nan))
    so = rows["SERVO_OUTPUT_RAW"]
    so_t = np.array([m.time_usec for m in so], dtype=np.float64) * 1e-6
    pwm = np.array([[getattr(m, f"servo{c}_raw") for c in channels] for m in so], dtype=np.float64)
    tau, notes = ardusub_force(path, t, so_t, pwm, mapping, thrusters, channels, "SERVO_OUTPUT_RAW")
    problems: list[str] = []
    if beats:
        cut_disarmed(armed_rows(beats, np.array([m._timestamp for m in att])), t, tau, notes, problems,
                     f"{path} (HEARTBEAT)")
    nu = np.full((len(t), 6), np.nan)
    nu[:, 3:] = rates
    for k in np.flatnonzero(np.all(np.isfinite(held), axis=1)):
        nu[k, :3] = _core.rotation(*angles[k]).T @ held[k, 3:]
    eta = np.hstack([held[:, :3], angles])
    notes.append("signals: " + ", ".join([rate_note("ATTITUDE", t)]
                                         + ([rate_note("LOCAL_POSITION_NED", lp_t)] if lp else [])
                                         + [rate_note("SERVO_OUTPUT_RAW", so_t)])
                 + ("" if lp else "; no LOCAL_POSITION_NED (no position or linear velocity)"))
    absent = fill_absent(str(path), eta, nu, mapping.where) if not lp else ()
    log = make_log(str(path), t, eta, nu, tau, absent=absent)
    return replace(log, notes=(*notes, *log.notes), problems=tuple(problems))
