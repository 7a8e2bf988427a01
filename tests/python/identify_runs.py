"""Runs of the shipped excitation scenarios that the identification tests
fit to, shortened so that the tests stay fast."""

from __future__ import annotations

from functools import lru_cache
from typing import Any

import numpy as np

import neurov
from neurov.study.spec import SCENARIO_DIR
from neurov.config.vehicle_file import preset_path, read_vehicle_file

PRESETS = {"bluerov2": "bluerov2_heavy", "nerov": "nerov"}


def perturbed(vehicle: str) -> dict[str, Any]:
    """The issue's other vehicle: damping +40 %, added mass -30 %."""
    p = read_vehicle_file(preset_path(PRESETS[vehicle])).parameters
    return {"linear_damping": [1.4 * x for x in p["linear_damping"]],
            "quadratic_damping": [1.4 * x for x in p["quadratic_damping"]],
            "added_mass": [0.7 * x for x in p["added_mass"]]}


def true_theta(vehicle: str, overrides: dict[str, Any] | None = None) -> Any:
    v = read_vehicle_file(preset_path(PRESETS[vehicle])).vehicle(overrides)
    return np.asarray(neurov.regressor_parameters(v))


@lru_cache(maxsize=None)
def excitation_run(vehicle: str, duration: float, *, heldout: bool = False, noise: float = 0.0,
                   seed: int = 0, perturb: bool = False) -> neurov.Result:
    name = f"{vehicle}_excitation{'_heldout' if heldout else ''}.toml"
    s = neurov.load_scenario(SCENARIO_DIR / name)
    s.duration = duration
    s.seed = seed
    if perturb:
        s.vehicle_parameters = perturbed(vehicle)
    if noise:
        s.noise_nu = np.array([noise] * 3 + [noise / 5] * 3)
        s.noise_eta = np.array([0.0] * 3 + [noise / 5] * 3)
    return neurov.simulate(s)
