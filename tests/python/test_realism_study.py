"""The realistic standard scenarios (each disturbed one with sensors, the EKF
and one period of delay) and the shipped study that runs every controller
on both (studies/realism.toml, docs/studies.md "Ideal and realistic")."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest

from neurov import _core
from neurov.laws.registry import REGISTRY
from neurov.config.reading import load_scenario
from neurov.running.simulation import simulate
from neurov.study import SCENARIO_DIR, load_study

VEHICLES = ("nerov", "bluerov2")
PATHS = ("square", "helix", "lawnmower", "depth_step", "heading_step")
TWINS = [(f"{v}_{p}_disturbed", f"{v}_{p}_realistic") for v in VEHICLES for p in PATHS]

# What a realistic variant may change in its disturbed twin's file.
REALISM_ONLY = {"name", "description", "noise", "sensors", "estimator", "control_delay", "water_density"}


def _toml(name: str) -> dict:
    with open(SCENARIO_DIR / f"{name}.toml", "rb") as f:
        return tomllib.load(f)


@pytest.mark.parametrize(("ideal", "real"), TWINS, ids=[r for _, r in TWINS])
def test_a_realistic_scenario_is_its_disturbed_twin_with_sensors_ekf_and_delay(ideal: str, real: str) -> None:
    a, b = _toml(ideal), _toml(real)
    assert {k: v for k, v in a.items() if k not in REALISM_ONLY} == \
           {k: v for k, v in b.items() if k not in REALISM_ONLY}
    assert b["vehicle"]["thrusters"] is True and "noise" not in b
    s = load_scenario(SCENARIO_DIR / f"{real}.toml")
    c = s.simulation
    assert s.name == real and s.control_delay == 1 and c.water_density == 1025.0
    assert c.estimator.type == _core.EstimatorType.ekf
    assert (c.sensors.usbl.rate, c.sensors.usbl.noise, c.sensors.usbl.latency) == (1.0, 0.5, 0.5)
    assert (c.sensors.dvl.rate, c.sensors.dvl.noise, c.sensors.dvl.dropout_rate) == (5.0, 0.01, 0.01)
    assert (c.sensors.depth.rate, c.sensors.depth.noise) == (10.0, 0.02)
    assert c.sensors.imu.rate == 50.0
    assert not np.any(s.noise_eta) and not np.any(s.noise_nu)


@pytest.mark.parametrize("real", [r for _, r in TWINS])
def test_a_realistic_scenario_runs_and_its_controller_gets_the_estimate(real: str) -> None:
    s = load_scenario(SCENARIO_DIR / f"{real}.toml").replace(duration=20.0)
    r = simulate(s)
    assert len(r.t) == round(20.0 / s.dt) + 1 and not r.diverged
    assert np.all(np.isfinite(r.eta)) and np.all(np.isfinite(r.tau_applied))
    assert r.eta_estimate.shape == r.eta.shape and r.nu_estimate.shape == r.nu.shape
    assert np.all(np.isfinite(r.eta_estimate)) and np.all(np.isfinite(r.nu_estimate))
    assert not np.array_equal(r.eta_estimate, r.eta)
    # The EKF's position is better than one raw acoustic fix (0.5 m per axis).
    error = np.linalg.norm(r.eta_estimate[:, :3] - r.eta[:, :3], axis=1)
    assert np.median(error) < 0.5


def test_the_realism_study_pairs_each_disturbed_scenario_with_its_realistic_twin() -> None:
    study = load_study("realism")
    names = [s.name for s in study.scenarios]
    # The BlueROV2 square's realistic run also on its tether, after its twins.
    expected = [n for pair in TWINS for n in pair]
    expected.insert(expected.index("bluerov2_square_realistic") + 1, "bluerov2_square_tether")
    assert names == expected
    # Every built-in controller but ArduSub, which flies the BlueROV2 frames only (docs/ardusub.md).
    assert set(study.controllers) == (set(REGISTRY) - {"ardusub"}) | {"linear_nominal"}
    robustness = load_study("robustness")
    assert study.perturbations == robustness.perturbations and study.seed == robustness.seed
    for scenario in study.scenarios:
        for c in study.controllers:
            assert study.spec_for(c, scenario).type == c.removesuffix("_nominal")


def test_the_tethered_square_is_the_realistic_square_on_its_tether() -> None:
    a, b = _toml("bluerov2_square_realistic"), _toml("bluerov2_square_tether")
    assert {k: v for k, v in a.items() if k not in {"name", "description"}} == \
        {k: v for k, v in b.items() if k not in {"name", "description", "tether"}}
    assert b["tether"]["length"] > 0


def test_the_realism_study_gives_every_controller_the_gains_of_the_earlier_studies() -> None:
    study = load_study("realism")
    earlier = {**load_study("sea_state").controller_specs, **load_study("robustness").controller_specs}
    assert study.controller_specs.keys() <= earlier.keys()
    for key, spec in study.controller_specs.items():
        assert repr(spec) == repr(earlier[key]), key  # the bound configs compare by identity
