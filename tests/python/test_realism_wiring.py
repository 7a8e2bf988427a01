"""The vehicle as it really is, from Python and from scenario files: the
computation delay, the water's density and the displaced volume, the
sensors and the estimator (see docs/realism.md)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import neurov
from neurov import _core
from neurov.scenario import ScenarioError, load_scenario
from neurov.simulation import simulate

HOVER = """
name = "hover"
duration = 20.0
dt = 0.2
seed = 3
[vehicle]
preset = "nerov"
[initial]
eta = [0.5, -0.5, 2.0, 0, 0, 0.2]
[command]
type = "waypoints"
times = [0.0]
poses = [[0, 0, 2, 0, 0, 0]]
[controller]
type = "pd"
kp = 100.0
kd = [200, 200, 200, 50, 50, 50]
"""


def write(tmp_path: Path, text: str, name: str = "s.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.mark.parametrize("delay", [1, 3])
def test_the_force_applied_at_row_k_is_the_one_demanded_at_row_k_minus_n(tmp_path: Path, delay: int) -> None:
    s = load_scenario(write(tmp_path, f"control_delay = {delay}\n" + HOVER))
    assert s.control_delay == delay and s.simulation.control_delay == delay
    r = simulate(s)
    assert not r.diverged and np.any(r.tau_demanded != 0)
    # tau_applied is the mean over the substeps: equal up to its rounding.
    np.testing.assert_allclose(r.tau_applied[delay:], r.tau_demanded[:-delay], rtol=1e-14, atol=1e-12)
    np.testing.assert_array_equal(r.tau_applied[:delay], 0.0)


def test_no_delay_is_the_default(tmp_path: Path) -> None:
    s = load_scenario(write(tmp_path, HOVER))
    assert s.control_delay == 0
    r = simulate(s)
    np.testing.assert_allclose(r.tau_applied, r.tau_demanded, rtol=1e-14, atol=1e-12)


@pytest.mark.parametrize("value, message", [
    ("1.5", r"control_delay: expected an integer, got float 1\.5"),
    ("-1", r"control_delay = -1: expected a whole number of control periods in 0\.\.16"),
    ("17", r"control_delay = 17: expected a whole number of control periods in 0\.\.16"),
    ('"one"', r"control_delay: expected an integer"),
])
def test_a_bad_delay_in_a_file_is_named(tmp_path: Path, value: str, message: str) -> None:
    with pytest.raises(ScenarioError, match=message):
        load_scenario(write(tmp_path, f"control_delay = {value}\n" + HOVER))


def test_a_bad_delay_from_python_is_named(tmp_path: Path) -> None:
    s = load_scenario(write(tmp_path, HOVER))
    with pytest.raises(TypeError, match="SimulationConfig.control_delay"):
        s.control_delay = 1.5
    s.control_delay = -2
    with pytest.raises(ValueError, match="control_delay"):
        simulate(s)
    with pytest.raises(ValueError, match="control_delay"):
        neurov.Scenario(control_delay=17).simulation.validate()


# --- the water -------------------------------------------------------------------

BLUEROV2 = HOVER.replace('preset = "nerov"', 'preset = "bluerov2_heavy"')
G = 9.81


@pytest.mark.parametrize("rho", [1000.0, 1025.0])
def test_buoyancy_is_rho_g_v_in_the_scenarios_water(tmp_path: Path, rho: float) -> None:
    from neurov.simulation import build_vehicle

    s = load_scenario(write(tmp_path, f"water_density = {rho}\n" + BLUEROV2))
    assert s.water_density == rho
    b = build_vehicle(s).buoyancy
    assert b == pytest.approx(rho * G * 0.0134, rel=1e-12)
    assert b == _core.buoyancy_in_water(rho, 0.0134)
    # The vehicle's weight is trimmed for neither: in fresh water it sinks,
    # in sea water it rises, from rest at the rate (W - B) / (m + Z_wdot).
    v = build_vehicle(s)
    sim = _core.Simulator(v, _core.SimulationConfig(
        dt=0.01, substeps=1, duration=0.01, eta0=[0, 0, 5, 0, 0, 0],
        command=_core.Command(times=[0.0], poses=[[0, 0, 5, 0, 0, 0]])))
    sim.step(np.zeros(6))
    w = sim.state[1][2]
    expected = (v.weight - b) / (v.mass + v.added_mass[2, 2]) * 0.01
    assert np.sign(w) == (1.0 if rho == 1000.0 else -1.0)
    assert w == pytest.approx(expected, rel=1e-2)


def test_sea_water_is_the_default_and_a_given_buoyancy_stays(tmp_path: Path) -> None:
    from neurov.simulation import build_vehicle

    assert _core.SimulationConfig().water_density == 1025.0
    assert neurov.Vehicle.preset("bluerov2_heavy").buoyancy == pytest.approx(1025.0 * G * 0.0134, rel=1e-12)
    fresh = load_scenario(write(tmp_path, "water_density = 1000.0\n" + HOVER))
    assert build_vehicle(fresh).buoyancy == 1800.0  # NEROV's file gives B itself


def test_bad_water_is_named(tmp_path: Path) -> None:
    with pytest.raises(ScenarioError, match=r"water_density = 0: expected > 0 and finite"):
        load_scenario(write(tmp_path, "water_density = 0.0\n" + HOVER))
    with pytest.raises(ValueError, match="displaced_volume"):
        _core.buoyancy_in_water(1025.0, -1.0)
    text = (Path(neurov.__file__).parent / "vehicles" / "bluerov2_heavy.toml").read_text()
    boat = tmp_path / "boat.toml"
    boat.write_text(text + "\nbuoyancy = 130.0\n")
    with pytest.raises(neurov.VehicleFileError, match="either 'buoyancy'"):
        neurov.Vehicle.from_file(boat)

