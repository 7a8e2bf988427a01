"""The white-noise example of docs/identification.md: the BlueROV2 Heavy
with its damping +40 % and its added mass -30 %, measured as its true
state plus white noise, fitted from the shipped template and held out on
the _heldout scenario; prints the report and writes the figure.

    PYTHONPATH=python python examples/identify_white_noise.py docs/images/identify_bluerov2_noise.png
"""

from __future__ import annotations

import sys

import neurov
from neurov.identification.plots import plot_identification
from neurov.identification.neurov_log import log_from_result
from neurov.identification.report import report_text
from neurov.study.spec import SCENARIO_DIR
from neurov.config.vehicle_file import preset_path, read_vehicle_file

q = read_vehicle_file(preset_path("bluerov2_heavy")).parameters
other = {"linear_damping": [1.4 * x for x in q["linear_damping"]],
         "quadratic_damping": [1.4 * x for x in q["quadratic_damping"]],
         "added_mass": [0.7 * x for x in q["added_mass"]]}
runs = []
for name in ("bluerov2_excitation", "bluerov2_excitation_heldout"):
    s = neurov.load_scenario(SCENARIO_DIR / f"{name}.toml")
    s.vehicle_parameters = other
    s.noise_nu = [0.01, 0.01, 0.01, 0.002, 0.002, 0.002]
    s.noise_eta = [0, 0, 0, 0.002, 0.002, 0.002]
    runs.append(log_from_result(neurov.simulate(s), name))
fit = neurov.identify(runs[0], preset_path("bluerov2_heavy"), heldout=[runs[1]])
print(report_text(fit))
truth = neurov.regressor_parameters(read_vehicle_file(preset_path("bluerov2_heavy")).vehicle(other))
plot_identification(fit, sys.argv[1] if len(sys.argv) > 1 else "identify_bluerov2_noise.png", truth=truth)
