"""ArduSub's motor stage replayed against a real vehicle's log: the pilot's
inputs the log holds, fed to the ``ardusub`` controller's mixing
(:meth:`neurov.ArduSubController.mix`: the frame's factors,
``MOT_n_DIRECTION``, the PWM range, with the log's own parameters), and its
PWMs set beside the PWMs the log holds.

What the logs allow: both public logs neurov ships (tests/data/logs/
ardusub_log_tools) were flown in ArduSub's MANUAL mode (mode 19) from
start to end, where ArduSub runs none of its controllers and sends the
pilot's inputs straight to the mixer. So they check the mixing and the PWM,
not the attitude, rate, depth or position controllers. A pilot input is the
RC channel's PWM as the log carries it, (PWM - 1500) / 400, in ArduSub's
channel order (``RCMAP_*``; Sub's defaults 1 pitch, 2 roll, 3 throttle,
4 yaw, 5 forward, 6 lateral); the logs show no dead band applied to them in
manual mode (a throttle of 1505 reaches the vertical motors).

* telemetry log (``.tlog``): RC_CHANNELS and SERVO_OUTPUT_RAW, sent together
  (the same millisecond of the vehicle's clock), while the autopilot's
  HEARTBEAT says armed;
* DataFlash log (``.bin``): RCIN and RCOU (the same loop, microseconds
  apart) until the ARM message's disarm (the log starts armed when its first
  ARM message disarms).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov.laws.ardusub_params import ArduSubParameterError, quiet, read_log_parameters

__all__ = ["MANUAL", "Replay", "manual_samples", "replay_mixing"]

#: ArduSub's mode number of MANUAL.
MANUAL = 19
# ArduSub's RCMAP parameters (and their defaults) in the mixer's input order:
# roll, pitch, yaw, throttle, forward, lateral.
_RCMAP = [("RCMAP_ROLL", 2), ("RCMAP_PITCH", 1), ("RCMAP_YAW", 4), ("RCMAP_THROTTLE", 3),
          ("RCMAP_FORWARD", 5), ("RCMAP_LATERAL", 6)]
# (time [s], channel PWMs [us]) of one message.
_Row = tuple[float, list[float]]
# A pair of an input and an output message further apart than this is not one loop's.
_PAIR_S = 0.005


@dataclass(frozen=True)
class Replay:
    """The pilot's inputs of a log against its PWMs, and the model's PWMs."""

    log: str
    frame: int
    t: NDArray[np.float64]
    """Sample times [s] of the vehicle's clock."""
    inputs: NDArray[np.float64]
    """(n, 6): roll, pitch, yaw, throttle, forward, lateral, each -1..1."""
    logged: NDArray[np.float64]
    """(n, motors): the PWMs [us] the log holds."""
    model: NDArray[np.float64]
    """(n, motors): the model's PWMs [us] for the same inputs."""
    modes: frozenset[int]

    @property
    def error(self) -> NDArray[np.float64]:
        return self.model - self.logged


def _channels(params: dict[str, float]) -> list[int]:
    return [int(params.get(name, default)) for name, default in _RCMAP]


def manual_samples(path: str | Path, params_log: str | Path | None = None) -> tuple[
        NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], frozenset[int], dict[str, float]]:
    """(t, inputs (n, 6), PWMs (n, 8), modes seen while armed, parameters)
    of a log's armed samples, the parameters read from `params_log` when
    given (an excerpt of the same dive that keeps them); ArduSubParameterError
    naming the log when it holds no parameters or no armed sample."""
    from pymavlink import mavutil

    path = Path(path)
    source = Path(params_log) if params_log is not None else path
    params = read_log_parameters(source)
    if not params:
        raise ArduSubParameterError(f"{source}: the log holds no parameters (MOT_n_DIRECTION, FRAME_CONFIG)")
    dataflash = path.suffix.lower() in (".bin", ".log")
    chans = _channels(params)
    rows_in: list[_Row] = []
    rows_out: list[_Row] = []
    modes: set[int | None] = set()
    with quiet():
        conn = mavutil.mavlink_connection(str(path), dialect="ardupilotmega")
        try:
            if dataflash:
                _read_dataflash(conn, rows_in, rows_out, modes)
            else:
                _read_telemetry(conn, rows_in, rows_out, modes)
        finally:
            conn.close()
    t, inputs, pwm = [], [], []
    out_t = np.array([r[0] for r in rows_out])
    for stamp, channels in rows_in:
        if not len(out_t):
            break
        j = int(np.argmin(np.abs(out_t - stamp)))
        if abs(out_t[j] - stamp) > _PAIR_S:
            continue
        t.append(stamp)
        inputs.append([(channels[c - 1] - 1500.0) / 400.0 for c in chans])
        pwm.append(rows_out[j][1])
    if not t:
        raise ArduSubParameterError(f"{path}: no armed sample with both the pilot's inputs and the PWMs")
    return np.array(t), np.array(inputs), np.array(pwm), frozenset(m for m in modes if m is not None), params


def _read_telemetry(conn: Any, rows_in: list[_Row], rows_out: list[_Row], modes: set[int | None]) -> None:
    armed, mode = False, None
    while True:
        m = conn.recv_match(type=["HEARTBEAT", "RC_CHANNELS", "SERVO_OUTPUT_RAW"])
        if m is None:
            return
        kind = m.get_type()
        if kind == "HEARTBEAT":
            if m.autopilot != 8:  # MAV_AUTOPILOT_INVALID: a ground station's
                armed, mode = bool(m.base_mode & 128), int(m.custom_mode)
            continue
        if not armed:
            continue
        modes.add(mode)
        if kind == "RC_CHANNELS":
            rows_in.append((m.time_boot_ms / 1e3, [float(getattr(m, f"chan{k}_raw")) for k in range(1, 19)]))
        else:
            rows_out.append((m.time_usec / 1e6, [float(getattr(m, f"servo{k}_raw")) for k in range(1, 9)]))


def _read_dataflash(conn: Any, rows_in: list[_Row], rows_out: list[_Row], modes: set[int | None]) -> None:
    messages = []
    while True:
        m = conn.recv_match(type=["MODE", "ARM", "RCIN", "RCOU"])
        if m is None:
            break
        messages.append(m)
    arms = [m for m in messages if m.get_type() == "ARM"]
    armed = bool(arms) and not arms[0].ArmState  # the first ARM message disarms: armed before it
    mode = None
    for m in messages:
        kind = m.get_type()
        if kind == "MODE":
            mode = int(m.ModeNum)
        elif kind == "ARM":
            armed = bool(m.ArmState)
        elif armed and kind == "RCIN":
            modes.add(mode)
            rows_in.append((m.TimeUS / 1e6, [float(getattr(m, f"C{k}")) for k in range(1, 15)]))
        elif armed and kind == "RCOU":
            rows_out.append((m.TimeUS / 1e6, [float(getattr(m, f"C{k}")) for k in range(1, 9)]))


def replay_mixing(path: str | Path, params_log: str | Path | None = None) -> Replay:
    """The log's armed samples through the model's motor stage, configured
    by the log's own parameters (FRAME_CONFIG, MOT_n_DIRECTION,
    MOT_PWM_MIN/MAX; from `params_log` when given)."""
    from neurov import _core
    from neurov.laws.ardusub_params import apply_parameters

    t, inputs, pwm, modes, params = manual_samples(path, params_log)
    config = _core.ArduSubConfig()
    apply_parameters(config, {k: v for k, v in params.items() if k.startswith(("MOT_", "FRAME_CONFIG"))},
                     str(path))
    controller = _core.ArduSubController(config)
    model = np.array([controller.mix(row) for row in inputs])
    n = model.shape[1]
    return Replay(log=Path(path).name, frame=int(config.FRAME_CONFIG), t=t, inputs=inputs, logged=pwm[:, :n],
                  model=model, modes=modes)
