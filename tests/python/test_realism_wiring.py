"""The vehicle as it really is, from Python and from scenario files: the
computation delay, the water's density and the displaced volume, the
sensors and the estimator (see docs/realism.md)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import neurov
from neurov import _core
from neurov.config.reading import load_scenario
from neurov.config.scenario import ScenarioError
from neurov.running.simulation import simulate
from test_scenario import write

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
    from neurov.running.plant import build_vehicle

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
    from neurov.running.plant import build_vehicle

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
    boat.write_text("buoyancy = 130.0\n" + text)  # top level: before the first table
    with pytest.raises(neurov.VehicleFileError, match="either 'buoyancy'"):
        neurov.Vehicle.from_file(boat)


# --- sensors and the estimator ------------------------------------------------------

SENSORS = """
[sensors]
usbl = { rate = 1.0, noise = 0.5, latency = 0.5 }
dvl = { rate = 5.0, noise = 0.01, dropout_rate = 0.01 }
depth = { rate = 10.0, noise = 0.02 }
imu = { rate = 50.0, attitude_noise = 0.005, gyro_noise = 0.001, gyro_bias_walk = 1e-5 }
[estimator]
type = "ekf"
"""


def test_the_issues_keys_are_read(tmp_path: Path) -> None:
    s = load_scenario(write(tmp_path, HOVER + SENSORS))
    c = s.simulation
    assert c.sensors.usbl.rate == 1.0 and c.sensors.usbl.noise == 0.5 and c.sensors.usbl.latency == 0.5
    assert c.sensors.dvl.dropout_rate == 0.01 and c.sensors.depth.noise == 0.02
    assert c.sensors.imu.gyro_bias_walk == 1e-5 and c.estimator.type == _core.EstimatorType.ekf
    plain = load_scenario(write(tmp_path, HOVER))
    assert not plain.simulation.sensors.any() and plain.simulation.estimator.type == _core.EstimatorType.none


@pytest.mark.parametrize("change, message", [
    (("rate = 1.0, noise = 0.5", "rate = -1.0, noise = 0.5"), r"sensors\.usbl\.rate = -1: expected > 0"),
    (("latency = 0.5", "latency = -0.5"), r"sensors\.usbl\.latency = -0\.5: expected >= 0"),
    (("noise = 0.02", "noise = -0.02"), r"sensors\.depth\.noise = -0\.02: expected >= 0"),
    (("usbl = { rate = 1.0, noise = 0.5, latency = 0.5 }\n", ""), r"sensors\.usbl: expected an acoustic"),
    (("gyro_noise = 0.001", "gyro_nois = 0.001"), r"sensors\.imu\.gyro_nois: unknown field"),
    (('type = "ekf"', 'type = "ukf"'), r"estimator\.type: expected one of"),
])
def test_bad_sensors_are_named(tmp_path: Path, change: tuple[str, str], message: str) -> None:
    with pytest.raises(ScenarioError, match=message):
        load_scenario(write(tmp_path, HOVER + SENSORS.replace(*change)))


def test_an_ekf_without_sensors_and_noise_with_sensors_are_named(tmp_path: Path) -> None:
    with pytest.raises(ScenarioError, match=r"sensors\.imu: expected an IMU for the ekf estimator"):
        load_scenario(write(tmp_path, HOVER + '[estimator]\ntype = "ekf"\n'))
    with pytest.raises(ScenarioError, match=r"noise\.eta = .*: expected zero noise_eta and noise_nu with sensors"):
        load_scenario(write(tmp_path, HOVER + "[noise]\neta = 0.1\n" + SENSORS))


def test_what_the_controller_was_given_is_exported(tmp_path: Path) -> None:
    r = simulate(load_scenario(write(tmp_path, HOVER + SENSORS)))
    assert r.eta_estimate.shape == r.eta.shape and r.nu_estimate.shape == r.nu.shape
    assert not np.array_equal(r.eta_estimate, r.eta)
    cols = r.columns()
    np.testing.assert_array_equal(cols["eta_estimate_x"], r.eta_estimate[:, 0])
    np.testing.assert_array_equal(cols["nu_estimate_r"], r.nu_estimate[:, 5])
    df = r.to_pandas()
    np.testing.assert_array_equal(df["eta_estimate_psi"].to_numpy(), r.eta_estimate[:, 5])
    np.testing.assert_array_equal(df["nu_estimate_u"].to_numpy(), r.nu_estimate[:, 0])
    with np.load(r.to_npz(tmp_path / "r.npz")) as z:
        np.testing.assert_array_equal(z["eta_estimate"], r.eta_estimate)
    header = (r.to_csv(tmp_path / "r.csv")).read_text().splitlines()[0].replace('"', "").split(",")
    assert "eta_estimate_psi" in header and "nu_estimate_u" in header


def test_the_ideal_default_gives_the_controller_the_measurement(tmp_path: Path) -> None:
    r = simulate(load_scenario(write(tmp_path, HOVER)))
    np.testing.assert_array_equal(r.eta_estimate, r.eta)
    np.testing.assert_array_equal(r.nu_estimate, r.nu)


# --- the EKF in the loop --------------------------------------------------------------

def _sensed_config(seed: int, estimator: str, duration: float) -> _core.SimulationConfig:
    eta0 = np.array([0.0, 0, 5, 0, 0, 0.3])
    c = _core.SimulationConfig(dt=0.2, substeps=10, duration=duration, seed=seed, eta0=eta0,
                               command=_core.Command(times=[0.0], poses=eta0[None, :]))
    c.sensors = _core.SensorsConfig(
        usbl=_core.UsblConfig(rate=1.0, noise=0.5, latency=0.5),
        dvl=_core.DvlConfig(rate=5.0, noise=0.01, dropout_rate=0.01),
        depth=_core.DepthConfig(rate=10.0, noise=0.02),
        imu=_core.ImuConfig(rate=50.0, attitude_noise=0.005, gyro_noise=0.001, gyro_bias_walk=1e-5))
    c.estimator = _core.EstimatorConfig(type=_core.EstimatorType.__members__[estimator])
    return c


def _run_circling(config: _core.SimulationConfig, with_covariance: bool) -> tuple[dict, list]:
    """NEROV driven round a slow circle by a force that depends on time alone
    (the same plant motion whatever the estimate), the EKF's covariance kept."""
    sim = _core.Simulator(_core.Vehicle.nerov(), config)
    covariances = []
    k = 0
    while not sim.done:
        t = 0.2 * k
        if with_covariance:
            covariances.append(sim.estimate_covariance[:12, :12])
        sim.step(np.array([40.0, 30.0 * np.sin(0.05 * t), 10.0 * np.cos(0.1 * t), 0, 0, 8.0 * np.sin(0.02 * t)]))
        k += 1
    return sim.result(), covariances


def test_the_ekf_in_the_loop_is_consistent_and_beats_the_raw_fixes() -> None:
    from scipy.stats import chi2

    runs, duration, start = 20, 120.0, 20.0
    nees = []
    for seed in range(runs):
        r, p = _run_circling(_sensed_config(seed, "ekf", duration), True)
        e = np.hstack([r["eta"] - r["eta_estimate"], r["nu"] - r["nu_estimate"]])
        e[:, 3:6] = np.remainder(e[:, 3:6] + np.pi, 2 * np.pi) - np.pi
        nees.append([x @ np.linalg.solve(pk, x) for x, pk in zip(e, p)])
    t = r["t"]
    mean = np.mean(nees, axis=0)[t >= start]
    # The 12 states of (eta, nu) averaged over the runs: 12 * runs degrees of
    # freedom, the two-sided 99% interval. (The filter is a little
    # conservative here, mean NEES 10.9 against 12: the motion is smoother
    # than its random-walk model.)
    low, high = chi2.ppf([0.005, 0.995], 12 * runs) / runs
    inside = np.mean((mean >= low) & (mean <= high))
    assert inside >= 0.9, f"mean NEES inside [{low:.2f}, {high:.2f}] {inside:.0%} of the time"

    # The position given to the controller, the EKF's against the raw fixes'.
    ekf, _ = _run_circling(_sensed_config(7, "ekf", 600.0), False)
    raw, _ = _run_circling(_sensed_config(7, "none", 600.0), False)
    np.testing.assert_array_equal(ekf["eta"], raw["eta"])  # the same plant motion
    after = ekf["t"] >= start

    def rms(r: dict) -> float:
        return float(np.sqrt(np.mean(np.sum((r["eta_estimate"][after, :3] - r["eta"][after, :3]) ** 2, axis=1))))

    assert rms(ekf) < 0.5 * rms(raw), (rms(ekf), rms(raw))
