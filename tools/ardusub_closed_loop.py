"""Prints, as a Markdown table, ArduSub with the stock parameters of a
BlueROV2 Heavy (python/neurov/vehicles/bluerov2_heavy_stock.param) on the
shipped BlueROV2 scenarios: each scenario's own plant and path, its
[controller] replaced by the ardusub controller in the mode named. Used by
docs/ardusub.md:

    python tools/ardusub_closed_loop.py
"""

from __future__ import annotations

import tomllib

from neurov.config.reading import scenario_from_mapping
from neurov.config.scenario import SCENARIO_DIR
from neurov.config.vehicle_file import PRESET_DIR
from neurov.running.simulation import simulate

# (scenario, mode, control period: None for the scenario's 0.2 s, or ArduSub's own 1/400 s
# with one plant substep)
RUNS = [("bluerov2_depth_step", "depth_hold", None), ("bluerov2_depth_step", "depth_hold", 0.0025),
        ("bluerov2_square", "position_hold", None), ("bluerov2_square", "position_hold", 0.0025),
        ("bluerov2_heading_step", "depth_hold", None), ("bluerov2_helix", "position_hold", None),
        ("bluerov2_depth_step_disturbed", "depth_hold", None),
        ("bluerov2_depth_step_disturbed", "position_hold", None),
        ("bluerov2_square_disturbed", "position_hold", None), ("bluerov2_helix_disturbed", "position_hold", None),
        ("bluerov2_heading_step_disturbed", "position_hold", None)]


def main() -> None:
    print("| scenario | mode | loop [s] | RMS position error [m] | max position error [m] | RMS yaw error [rad] "
          "| diverged |")
    print("|---|---|---|---|---|---|---|")
    for name, mode, dt in RUNS:
        data = tomllib.loads((SCENARIO_DIR / f"{name}.toml").read_text())
        if dt is not None:
            data["dt"], data["substeps"] = dt, 1
        data["controller"] = {"type": "ardusub", "mode": mode,
                              "params": str(PRESET_DIR / "bluerov2_heavy_stock.param")}
        m = simulate(scenario_from_mapping(data, str(SCENARIO_DIR / f"{name}.toml"))).metrics()
        print(f"| {name} | {mode} | {data['dt']:g} | {m['rmse_position_m']:.3f} | {m['max_position_error_m']:.3f} | "
              f"{m['rmse_yaw_rad']:.4f} | {'yes' if m['diverged'] else 'no'} |")


if __name__ == "__main__":
    main()
