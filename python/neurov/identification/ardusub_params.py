"""An ArduSub vehicle's own parameters, as its logs carry them: the
PARAM_VALUE messages of a telemetry log (``.tlog``) or the PARM messages of
a DataFlash log (``.bin``), both read with ``pymavlink``.

Of them identification uses ``FRAME_CONFIG`` (how many thrusters the frame
has), ``MOT_n_DIRECTION`` (ArduSub reverses motor n's output about the
neutral PWM where it is -1: the thrust along the frame's axis comes from
``neutral + direction * (pwm - neutral)``) and ``MOT_PWM_MIN``/``MOT_PWM_MAX``
(the outputs' range, checked against the template's curve). The meanings are
ArduSub's parameter documentation's (https://www.ardusub.com/ and the
ArduPilot parameter list)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov.identification.errors import LogError
from neurov.laws import ardusub_params as laws_params
from neurov.laws.ardusub_params import ArduSubParameterError, quiet

__all__ = ["FRAMES", "frame_thrusters", "motor_directions", "quiet", "read_log_parameters"]

# FRAME_CONFIG -> (name, number of thrusters): ArduSub's frame list.
FRAMES: dict[int, tuple[str, int]] = {
    0: ("BlueROV1", 6), 1: ("Vectored (BlueROV2)", 6), 2: ("Vectored 6DOF (BlueROV2 Heavy)", 8),
    3: ("Vectored 6DOF 90deg", 8), 4: ("SimpleROV-3", 3), 5: ("SimpleROV-4", 4),
    6: ("SimpleROV-5", 5), 7: ("Custom", 0),
}


def read_log_parameters(path: str | Path) -> dict[str, float]:
    """The vehicle parameters an ArduSub log holds, name -> value: a
    ``.tlog``'s PARAM_VALUE messages (the ground station's parameter
    download) or a DataFlash ``.bin``'s PARM messages; the last value of a
    name wins (a parameter set during the dive). Empty when the log holds
    none. LogError naming `path` when it is missing or unreadable. The
    reader is the ArduSub controller's (``neurov.laws.ardusub_params``)."""
    path = Path(path)
    try:
        return laws_params.read_log_parameters(path, dataflash=path.suffix.lower() == ".bin")
    except ArduSubParameterError as e:
        raise LogError(str(e)) from None


def frame_thrusters(params: dict[str, float]) -> tuple[str, int] | None:
    """The frame's name and thruster count from FRAME_CONFIG (None without it)."""
    if "FRAME_CONFIG" not in params:
        return None
    code = int(params["FRAME_CONFIG"])
    return FRAMES.get(code, (f"FRAME_CONFIG {code}", 0))


def motor_directions(params: dict[str, float], channels: list[int]) -> NDArray[np.float64]:
    """MOT_n_DIRECTION of each thruster's servo output (1 where not logged)."""
    return np.array([-1.0 if params.get(f"MOT_{c}_DIRECTION", 1.0) < 0 else 1.0 for c in channels])


def undo_directions(pwm: NDArray[np.float64], directions: NDArray[np.float64],
                    neutral: float) -> NDArray[np.float64]:
    """The PWM a thruster's curve reads: ArduSub's reversal undone."""
    return neutral + directions * (pwm - neutral)


def parameter_notes(path: Any, params: dict[str, float], n_thrusters: int,
                    channels: list[int]) -> tuple[list[str], NDArray[np.float64]]:
    """What the log's parameters say, in words, and the directions to use.
    A frame whose thruster count differs from the template's is an error
    naming both (the force would be wrong)."""
    if not params:
        return [f"no vehicle parameters in the log: MOT_n_DIRECTION taken as 1 (not reversed)"], np.ones(
            len(channels))
    notes = [f"{len(params)} vehicle parameters read from the log"]
    frame = frame_thrusters(params)
    if frame is not None:
        name, count = frame
        if count and count != n_thrusters:
            raise LogError(f"{path}: the log's FRAME_CONFIG {int(params['FRAME_CONFIG'])} is {name} "
                           f"with {count} thrusters; the template has {n_thrusters}: give a template "
                           "of this frame (--vehicle)")
        notes.append(f"FRAME_CONFIG {int(params['FRAME_CONFIG'])}: {name}")
    directions = motor_directions(params, channels)
    notes.append("MOT_n_DIRECTION " + ", ".join(f"{c}:{int(d):+d}" for c, d in zip(channels, directions))
                 + " (reversed outputs turned back before the thruster curve)")
    lo, hi = params.get("MOT_PWM_MIN"), params.get("MOT_PWM_MAX")
    if lo is not None and hi is not None:
        notes.append(f"MOT_PWM_MIN/MAX {lo:g}/{hi:g} us")
    return notes, directions
