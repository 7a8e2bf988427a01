"""ArduSub's onboard DataFlash logs (``.bin``) through ``pymavlink``
(``mavutil.mavlink_connection`` reads DataFlash with its ``DFReader``).

The messages are ArduPilot's log messages, at their logging rates: the time
base is ATT's ``TimeUS`` (``Roll``, ``Pitch``, ``Yaw`` in degrees); the body
rates are IMU's ``GyrX``, ``GyrY``, ``GyrZ`` [rad/s] of the first IMU
(``I`` = 0); the position and NED velocity are the EKF's: XKF1 (EKF3) of
core ``C`` = 0, or NKF1 (EKF2) in older logs (``PN``, ``PE``, ``PD``, ``VN``,
``VE``, ``VD``; depth from the barometer is fused there), the velocity turned
into the body frame; RCOU's ``C1``..``C14`` are the servo outputs' PWM, which
go through the template's thruster curves and configuration matrix as a
tlog's SERVO_OUTPUT_RAW does (:mod:`neurov.identification.tlog_log`). Each
signal is held onto the time base and cut where older than ``max_age``. The
log's PARM messages give MOT_n_DIRECTION and FRAME_CONFIG as in a tlog; its
ARM messages (each change of ``ArmState``) cut the disarmed rows. No
mapping file is needed; one only overrides::

    format = "dataflash"
    servo_channels = [1, 2, 3, 4, 5, 6, 7, 8]   # the RCOU channel of each thruster (default 1..n)
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov import _core
from neurov.identification.alignment import hold
from neurov.identification.ardusub_params import quiet
from neurov.identification.errors import LogError
from neurov.identification.log import Log, make_log
from neurov.identification.mapping import Mapping
from neurov.identification.tlog_log import (ardusub_force, check_thrusters, cut_disarmed, rate_note,
                                           servo_channels)

__all__ = ["read_dataflash"]

Array = NDArray[np.float64]
_WANTED = ("ATT", "IMU", "XKF1", "NKF1", "RCOU", "ARM")


def _messages(path: Path) -> dict[str, list[Any]]:
    from pymavlink import mavutil

    rows: dict[str, list[Any]] = {name: [] for name in _WANTED}
    try:
        with quiet():
            conn = mavutil.mavlink_connection(str(path))
            try:
                while True:
                    m = conn.recv_match(type=list(_WANTED))
                    if m is None:
                        break
                    rows[m.get_type()].append(m)
            finally:
                conn.close()
    except Exception as e:  # DFReader's own errors for a file that is not DataFlash
        raise LogError(f"{path}: not a readable DataFlash log: {type(e).__name__}: {e}") from None
    return rows


def _first_instance(found: list[Any], field: str) -> list[Any]:
    """The messages of instance 0 (the first IMU, the primary EKF core)."""
    return [m for m in found if int(getattr(m, field, 0)) == 0]


def read_dataflash(path: str | Path, mapping: Mapping | None, thrusters: dict[str, Any] | None) -> Log:
    path = Path(path)
    thrusters = check_thrusters(path, thrusters)
    mapping = mapping or Mapping({"format": "dataflash"}, f"{path} (no mapping: ArduSub's messages)")
    channels = servo_channels(mapping, thrusters["matrix"].shape[1])
    rows = _messages(path)
    ekf = "XKF1" if rows["XKF1"] else "NKF1"
    for name in ("ATT", "IMU", ekf, "RCOU"):
        if not rows[name]:
            what = "XKF1 (EKF3) or NKF1 (EKF2)" if name == ekf else name
            raise LogError(f"{path}: no {what} message (ArduSub logs it with the LOG_BITMASK "
                           "parameter's attitude, IMU, EKF and RC output bits)")
    att = rows["ATT"]
    t_us = np.array([m.TimeUS for m in att], dtype=np.float64)
    t = t_us * 1e-6
    angles = np.radians(np.array([[m.Roll, m.Pitch, m.Yaw] for m in att], dtype=np.float64))
    angles[:, 2] = (angles[:, 2] + np.pi) % (2 * np.pi) - np.pi
    imu = _first_instance(rows["IMU"], "I")
    gyro = hold(t, np.array([m.TimeUS for m in imu], dtype=np.float64) * 1e-6,
                np.array([[m.GyrX, m.GyrY, m.GyrZ] for m in imu], dtype=np.float64),
                mapping.max_age, f"{path}: IMU")
    kf = _first_instance(rows[ekf], "C")
    state = hold(t, np.array([m.TimeUS for m in kf], dtype=np.float64) * 1e-6,
                 np.array([[m.PN, m.PE, m.PD, m.VN, m.VE, m.VD] for m in kf], dtype=np.float64),
                 mapping.max_age, f"{path}: {ekf}")
    rc = rows["RCOU"]
    try:
        pwm = np.array([[getattr(m, f"C{c}") for c in channels] for m in rc], dtype=np.float64)
    except AttributeError as e:
        raise LogError(f"{path}: RCOU has no field for a servo channel of {mapping.where}'s "
                       f"servo_channels ({e})") from None
    rc_t = np.array([m.TimeUS for m in rc], dtype=np.float64) * 1e-6
    tau, notes = ardusub_force(path, t, rc_t, pwm, mapping, thrusters, channels, "RCOU")
    nu = np.full((len(t), 6), np.nan)
    nu[:, 3:] = gyro
    for k in np.flatnonzero(np.all(np.isfinite(state), axis=1)):
        nu[k, :3] = _core.rotation(*angles[k]).T @ state[k, 3:]
    eta = np.hstack([state[:, :3], angles])
    notes.append("signals: " + ", ".join([rate_note("ATT", t), rate_note("IMU", np.array([m.TimeUS for m in imu]) * 1e-6),
                                          rate_note(ekf, np.array([m.TimeUS for m in kf]) * 1e-6),
                                          rate_note("RCOU", rc_t)]))
    problems: list[str] = []
    if rows["ARM"]:
        cut_disarmed(_armed(rows["ARM"], t_us), t, tau, notes, problems, f"{path} (ARM)")
    log = make_log(str(path), t, eta, nu, tau)
    return replace(log, notes=(*notes, *log.notes), problems=tuple(problems))


def _armed(arms: list[Any], t_us: Array) -> NDArray[np.bool_]:
    """Armed at each row from the ARM messages (``ArmState`` at ``TimeUS``,
    logged at each change); before the first, the state it changed from."""
    at = np.array([m.TimeUS for m in arms], dtype=np.float64)
    state = np.array([bool(m.ArmState) for m in arms])
    k = np.searchsorted(at, t_us, side="right") - 1
    return np.where(k >= 0, state[np.clip(k, 0, None)], not state[0])
