"""Noise-free recovery (docs/identification.md, "Measured"): the shipped
excitation scenarios run, fitted from the vehicle that made them, by stage
1 alone and by both stages, with the default free parameters and with all
of them; prints the largest relative error of the fitted parameters (a
parameter whose true value is zero is measured against its group's largest)
and the condition number, and what was set aside.

    PYTHONPATH=python python examples/identify_noise_free.py
"""

from __future__ import annotations

import numpy as np

import neurov
from neurov.identification.neurov_log import log_from_result
from neurov.identification.parameters import GROUPS
from neurov.study.spec import SCENARIO_DIR
from neurov.config.vehicle_file import preset_path

ALL = "added_mass,linear_damping,quadratic_damping,mass,inertia,restoring"

for vehicle, preset in (("bluerov2", "bluerov2_heavy"), ("nerov", "nerov")):
    log = log_from_result(neurov.simulate(neurov.load_scenario(SCENARIO_DIR / f"{vehicle}_excitation.toml")))
    true = np.asarray(neurov.regressor_parameters(neurov.Vehicle.preset(preset)))
    group = {i: g for g in GROUPS.values() for i in g}
    scale = np.array([max(abs(true[i]), max(abs(true[j]) for j in group[i])) for i in range(24)])
    for free in (None, ALL):
        for stage2 in (False, True):
            r = neurov.identify(log, preset_path(preset), free=free, output_error=stage2, replicates=50)
            err = np.abs(r.theta - true)[r.fitted] / scale[r.fitted]
            print(f"{vehicle}: {'all' if free else 'default'} free, {'both stages' if stage2 else 'stage 1'}: "
                  f"{len(r.fitted)} fitted, largest relative error {err.max():.2e}, "
                  f"condition number {r.condition:.3g}")
            if free and stage2:
                for i, why in r.reasons.items():
                    print(f"    {neurov.THETA_NAMES[i]}: {why}")
