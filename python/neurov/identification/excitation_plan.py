"""The excitation plan: what to fly so that a log can tell what the last one
could not. Written as a neurov scenario to rehearse (``neurov run``: a weak
PD holds the start pose while a sum of two sines drives each weak DOF, as
python/neurov/scenarios/bluerov2_excitation.toml does for all six) and as
plain steps for an ArduSub pilot.

Amplitudes (ours): each weak linear DOF gets 15 % of what the template's
thrusters give in it (split 60/40 over the two sines); yaw 5 %; roll and
pitch the smaller of 15 % and the restoring moment at 10 degrees of tilt,
so that the vehicle stays within a safe attitude."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from neurov.identification.survey import DOFS, dof_of

__all__ = ["capacity", "plan", "plan_scenario", "pilot_steps"]

_FREQS = ((0.07, 0.31), (0.09, 0.37), (0.06, 0.29), (0.13, 0.43), (0.11, 0.47), (0.08, 0.34))
_SHARE = (0.15, 0.15, 0.15, 0.15, 0.15, 0.05)
_TILT = np.radians(10.0)
_STICK = ("forward/back stick (x)", "lateral stick (y)", "throttle (z)", "roll input (in ArduSub's "
          "roll/pitch mode)", "pitch input (in ArduSub's roll/pitch mode)", "yaw stick (r)")


def capacity(thrusters: dict[str, Any] | None) -> np.ndarray:
    """The largest force (N) or moment (N m) the thrusters give in each DOF
    alone: each thruster at the end of its range that pushes that way."""
    if thrusters is None:
        return np.full(6, np.nan)
    b = np.asarray(thrusters["matrix"])
    hi, lo = np.asarray(thrusters["max_thrust"]), np.abs(np.asarray(thrusters["min_thrust"]))
    return np.sum(np.abs(b) * np.minimum(hi, lo)[None, :], axis=1)


def amplitudes(thrusters: dict[str, Any] | None, restoring_moment: float) -> np.ndarray:
    """The total sine amplitude per DOF (N or N m)."""
    cap = capacity(thrusters)
    amp = cap * np.array(_SHARE)
    if restoring_moment > 0:
        amp[3:5] = np.minimum(amp[3:5], restoring_moment * np.sin(_TILT))
    return amp


def plan_scenario(weak: list[int], vehicle: str | Path, preset: str | None, amp: np.ndarray,
                  name: str = "excitation_plan") -> str:
    """A scenario file (TOML text) driving the DOFs `weak` with two sines each."""
    where = f'preset = "{preset}"' if preset else f'file = "{Path(vehicle).resolve().as_posix()}"'
    lines = [f"# Excitation plan written by neurov identify: rehearse with `neurov run {name}.toml --out rehearsal`,",
             "# then fly the same on the water (the pilot steps in the log report) and identify again.",
             f'name = "{name}"',
             f'description = "excite {", ".join(DOFS[d] for d in weak)}: two sines each, a weak PD holding the start pose"',
             "duration = 120.0", "dt = 0.05", "substeps = 1", "seed = 0", "",
             "[vehicle]", where, "thrusters = true", "",
             "[command]", 'type = "waypoints"', 'interpolation = "hold"', "times = [0.0]",
             "poses = [[0, 0, 0, 0, 0, 0]]", "",
             "[controller]", 'type = "pd"', "kp = [4, 4, 4, 3.0, 3.0, 0.5]", "kd = [8, 8, 8, 1.0, 1.0, 0.3]"]
    for d in weak:
        for k, (share, phase) in enumerate(((0.6, 0.0), (0.4, 1.0 + d))):
            lines += ["", "[[disturbances]]", f'dof = "{DOFS[d]}"', f"amplitude = {amp[d] * share:.3g}",
                      f"frequency = {_FREQS[d][k]}", f"phase = {phase:g}"]
    return "\n".join(lines) + "\n"


def pilot_steps(weak: list[int], amp: np.ndarray, cap: np.ndarray) -> list[str]:
    """Plain steps for an ArduSub pilot (or a script sending MANUAL_CONTROL)."""
    steps = ["Excitation plan for the pilot (ArduSub): in DEPTH HOLD (STABILIZE for heave), one DOF at a time,",
             "2 minutes each, the other sticks centred, roll and pitch within 15 degrees, away from walls:"]
    for n, d in enumerate(weak, 1):
        pct = 100 * amp[d] / cap[d] if np.isfinite(cap[d]) and cap[d] > 0 else 15.0
        steps.append(f"{n}. {DOFS[d]}: {_STICK[d]} to about {max(pct, 10):.0f} % one way for 3 s, then the "
                     "other way for 3 s, then 1.5 s each way; repeat for 2 minutes (a script: MANUAL_CONTROL "
                     f"at 10 Hz with that input as a square wave of 6 s and 3 s periods)")
    steps.append("Record the telemetry log (.tlog) with SERVO_OUTPUT_RAW and ATTITUDE at 10 Hz or more "
                 "(SR0_RC_CHAN, SR0_EXTRA1) and keep the onboard .bin log.")
    return steps


def plan(report: Any, vehicle: str | Path, preset: str | None, template: Any,
         restoring_moment: float) -> tuple[list[str], str | None]:
    """The plan's lines for the report and the scenario's text (None when
    every DOF of a free parameter is excited)."""
    weak = [d for d in report.weak_dofs() if any(v != "excited" and d in dof_of(i)
                                                 for i, (v, _) in report.verdicts.items())]
    if not weak:
        return [], None
    thrusters = template.thrusters
    amp = amplitudes(thrusters, restoring_moment)
    if not np.all(np.isfinite(amp[weak])):
        return ["No excitation plan: the template has no [thrusters] to size the manoeuvres with."], None
    lines = [f"This log cannot identify {', '.join(DOFS[d] for d in weak)}: the vehicle was not pushed "
             "(or did not move) enough in those directions. Fly this and identify again:"]
    return lines + pilot_steps(weak, amp, capacity(thrusters)), plan_scenario(weak, vehicle, preset, amp)
