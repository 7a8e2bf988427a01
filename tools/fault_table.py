"""The table of docs/reliability.md ("Faults during a run"): each fault
scenario of examples/scenarios/faults/ run whole, beside the same scenario
with its faults removed.

    python tools/fault_table.py

Per fault: its interval (from the scenario file) and the time by which the
run must have recovered (``tests/python/test_faults.py`` checks it); the
worst position error from the fault's start to that time, against the
fault-free run's over the same window; the largest position and yaw errors
after it; the largest weight norm; the largest surge force and yaw moment
applied; and the refused controller steps. A few seconds of CPU.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import neurov
from neurov.results.timeseries import Result
from neurov.units import for_people

ROOT = Path(__file__).resolve().parent.parent
FAULTS = ROOT / "examples" / "scenarios" / "faults"
#: file: (what the fault is, seconds after it clears by which the run has recovered)
CASES = {
    "thruster_failure": ("thruster {index} dead, then repaired", 30.0),
    "sensor_freeze": ("η and ν frozen", 20.0),
    "sensor_dropout": ("η and ν NaN, last force held", 20.0),
    "noise_burst": ("noise burst, {noise}", 20.0),
    "current_step": ("{current:g} m/s cross current on, then off", 30.0),
}
DEG, PER_RAD = for_people("rad")


def interval(s: neurov.Scenario) -> tuple[float, float]:
    """When the scenario's fault starts and ends [s]."""
    if s.sensor_faults:
        return min(f.start for f in s.sensor_faults), max(f.end for f in s.sensor_faults)
    times = [f.time for f in s.thruster_failures] or [c.time for c in s.current_steps]
    if len(times) < 2:
        raise ValueError("a fault scenario must give the fault's start and its end")
    return min(times), max(times)


def _position(r: Result) -> np.ndarray:
    return np.linalg.norm(r.error[:, :3], axis=1)


def describe(name: str, s: neurov.Scenario) -> str:
    """What the fault is, with its size from the scenario file."""
    noise = ""
    if s.sensor_faults:
        f = s.sensor_faults[0]
        noise = f"{f.noise_eta[0]:g} m / {f.noise_eta[5] * PER_RAD:.1f} {DEG} / {f.noise_nu[0]:g} m/s"
    return CASES[name][0].format(index=s.thruster_failures[0].index if s.thruster_failures else "",
                                 current=float(np.linalg.norm(s.current_steps[0].velocity)) if s.current_steps else 0.0,
                                 noise=noise)


def row(name: str) -> str:
    _, settle = CASES[name]
    s = neurov.load_scenario(FAULTS / f"{name}.toml")
    what = describe(name, s)
    r = neurov.simulate(s)
    free = neurov.simulate(s.replace(thruster_failures=[], sensor_faults=[], current_steps=[]))
    start, end = interval(s)
    lasts = (r.t >= start) & (r.t < end + settle)
    after = r.t >= end + settle
    worst, worst_free = _position(r)[lasts].max(), _position(free)[lasts].max()
    tau = np.abs(np.nan_to_num(r.tau_applied))
    return (f"| {what} (`{name}.toml`) | {start:g}–{end:g} s, by {end + settle:g} s | {worst:.2f} m ({worst_free:.2f}) | "
            f"{_position(r)[after].max():.3f} m, {np.abs(r.error[after, 5]).max() * PER_RAD:.1f} {DEG} | "
            f"{r.adaptive_norm.max():.1f} ({free.adaptive_norm.max():.1f}) | {tau[:, 0].max():.0f} / {tau[:, 5].max():.0f} | "
            f"{r.metrics()['refused_steps']} |")


def main() -> int:
    print("| fault (file) | interval, recovered by | worst position error while it lasts (fault-free) | after recovery "
          "| max ‖Ŵ‖ (fault-free) | max \\|τ_applied\\| surge / yaw [N, N m] | refused steps |")
    print("|---|---|---|---|---|---|---|")
    for name in CASES:
        print(row(name))
    return 0


if __name__ == "__main__":
    sys.exit(main())
