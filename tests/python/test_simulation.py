"""The closed loop (neurov.simulate, run in C++) against the plant stepped from
Python; currents, disturbances, measurement noise; Result's metrics and export."""

from __future__ import annotations

import csv
import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

import neurov
from neurov.config.scenario import CommandSpec, ControllerSpec, Disturbance, Scenario
from neurov.results.timeseries import SERIES
from neurov.results.timeseries import Result
from neurov.running.simulation import simulate

ZERO_GAINS = ControllerSpec(type="pd", kp=np.zeros(6), kd=np.zeros(6))
# A pose with all three angles non-zero and a velocity in every DOF, so a
# mismatch in any part of J or of the dynamics shows.
ETA0 = np.array([1.0, -2.0, 3.0, 0.2, -0.15, 0.6])
NU0 = np.array([0.5, -0.3, 0.2, 0.1, -0.08, 0.15])


def hold(pose: np.ndarray) -> CommandSpec:
    """A command that stays at `pose`."""
    return CommandSpec(type="waypoints", times=np.array([0.0]), poses=np.asarray(pose, dtype=float)[None, :])


def free_scenario(**changes: object) -> Scenario:
    """tau = 0 from a PD controller with zero gains: the plant runs open loop."""
    base = Scenario(name="free", duration=6.0, dt=0.2, substeps=5, eta0=ETA0, nu0=NU0,
                    command=hold(ETA0), controller=ZERO_GAINS)
    return base.replace(**changes)


def python_loop(scenario: Scenario, force: object = None) -> tuple[np.ndarray, np.ndarray]:
    """The plant stepped by neurov.rk4_step with the closed loop's timing:
    `substeps` RK4 steps of dt/substeps per control period; `force(t)` is the
    body force held over each substep."""
    vehicle = neurov.Vehicle.nerov()
    steps = round(scenario.duration / scenario.dt) + 1
    h = scenario.dt / scenario.substeps
    eta, nu = scenario.eta0.copy(), scenario.nu0.copy()
    etas, nus = [eta], [nu]
    for k in range(steps - 1):
        for j in range(scenario.substeps):
            t = k * scenario.dt + j * h
            tau = np.zeros(6) if force is None else force(t)  # type: ignore[operator]
            eta, nu = neurov.rk4_step(vehicle, eta, nu, tau, h, scenario.current)
        etas.append(eta)
        nus.append(nu)
    return np.array(etas), np.array(nus)


# --- the closed loop with tau = 0 is the plant --------------------------------


@pytest.mark.parametrize("current", [np.zeros(3), np.array([0.3, -0.2, 0.1])], ids=["still", "current"])
def test_zero_control_matches_rk4_in_python(current: np.ndarray) -> None:
    scenario = free_scenario(current=current)
    result = simulate(scenario)
    eta, nu = python_loop(scenario)
    assert result.t.shape == (31,)
    np.testing.assert_array_equal(result.tau_demanded, 0.0)
    np.testing.assert_array_equal(result.tau_applied, 0.0)
    # The motion is not trivial: otherwise "equal" would prove nothing.
    assert np.linalg.norm(eta[-1, :3] - ETA0[:3]) > 1.0
    assert abs(eta[-1, 5] - ETA0[5]) > 0.2
    np.testing.assert_allclose(result.eta, eta, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(result.nu, nu, rtol=1e-12, atol=1e-12)
    assert not result.diverged


def test_substeps_matter() -> None:
    # The comparison above would pass for any substeps if the loop ignored
    # them; a coarser plant step must give a measurably different state.
    fine = simulate(free_scenario(substeps=5))
    coarse = simulate(free_scenario(substeps=1))
    assert np.max(np.abs(fine.nu - coarse.nu)) > 1e-9


# --- current ----------------------------------------------------------------------


def test_vehicle_at_rest_drifts_with_the_current() -> None:
    current = np.array([0.3, -0.2, 0.1])
    eta0 = np.array([0.0, 0.0, 5.0, 0.0, 0.0, 0.4])
    scenario = Scenario(name="drift", duration=120.0, dt=0.2, substeps=4, eta0=eta0, command=hold(eta0),
                        controller=ZERO_GAINS, current=current)
    result = simulate(scenario)

    def earth_velocity(k: int) -> np.ndarray:
        eta, nu = result.eta[k], result.nu[k]
        return neurov.rotation(*eta[3:]) @ nu[:3]

    np.testing.assert_allclose(earth_velocity(0), 0.0)
    # After a few damping time constants (mass/linear damping ~ 3 s) the
    # vehicle moves with the water: relative velocity zero.
    np.testing.assert_allclose(earth_velocity(-1), current, atol=1e-4)
    rel_body = result.nu[-1, :3] - neurov.rotation(*result.eta[-1, 3:]).T @ current
    np.testing.assert_allclose(rel_body, 0.0, atol=1e-4)
    np.testing.assert_allclose(result.nu[-1, 3:], 0.0, atol=1e-4)
    # And it has been carried along: the displacement over the last 60 s is
    # the current times 60 s.
    half = len(result.t) // 2
    np.testing.assert_allclose(result.eta[-1, :3] - result.eta[half, :3],
                               current * (result.t[-1] - result.t[half]), rtol=1e-3)


def test_no_current_no_drift() -> None:
    eta0 = np.array([0.0, 0.0, 5.0, 0.0, 0.0, 0.4])
    result = simulate(Scenario(name="still", duration=20.0, eta0=eta0, command=hold(eta0), controller=ZERO_GAINS))
    np.testing.assert_allclose(result.eta, np.tile(eta0, (len(result.t), 1)), atol=1e-12)


# --- disturbance ----------------------------------------------------------------


def test_disturbance_column_is_the_sinusoid_in_its_dof() -> None:
    yaw = Disturbance(dof=5, amplitude=20.0, frequency=0.1, phase=0.3)
    sway = Disturbance(dof=1, amplitude=-7.0, frequency=0.25, phase=-1.0, start=2.0)
    scenario = free_scenario(disturbances=[yaw, sway])
    result = simulate(scenario)
    t = result.t
    np.testing.assert_allclose(result.disturbance[:, 5], 20.0 * np.sin(2 * np.pi * 0.1 * t + 0.3), atol=1e-12)
    expected_sway = np.where(t >= 2.0, -7.0 * np.sin(2 * np.pi * 0.25 * (t - 2.0) - 1.0), 0.0)
    np.testing.assert_allclose(result.disturbance[:, 1], expected_sway, atol=1e-12)
    np.testing.assert_array_equal(result.disturbance[:, [0, 2, 3, 4]], 0.0)


def test_disturbance_acts_on_the_plant_at_every_substep() -> None:
    d = Disturbance(dof=5, amplitude=20.0, frequency=0.1, phase=0.3)
    scenario = free_scenario(disturbances=[d])
    result = simulate(scenario)

    def force(t: float) -> np.ndarray:
        tau = np.zeros(6)
        tau[5] = d.amplitude * math.sin(2 * math.pi * d.frequency * t + d.phase)
        return tau

    eta, nu = python_loop(scenario, force)
    np.testing.assert_allclose(result.eta, eta, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(result.nu, nu, rtol=1e-12, atol=1e-12)
    # Sanity: the disturbance moved the vehicle compared with no disturbance.
    assert np.max(np.abs(result.nu[:, 5] - simulate(free_scenario()).nu[:, 5])) > 0.01


# --- measurement noise ------------------------------------------------------------


def closed_loop(**changes: object) -> Scenario:
    """A PD loop holding a pose; the controller sees the noisy measurements."""
    target = np.array([1.0, 1.0, 2.0, 0.0, 0.0, 0.3])
    base = Scenario(name="hold", duration=10.0, command=hold(target),
                    controller=ControllerSpec(type="pd", kp=np.full(6, 200.0), kd=np.full(6, 300.0)))
    return base.replace(**changes)


NOISE = {"noise_eta": np.full(6, 0.02), "noise_nu": np.full(6, 0.01)}


def test_same_seed_same_run() -> None:
    a = simulate(closed_loop(seed=3, **NOISE))
    b = simulate(closed_loop(seed=3, **NOISE))
    np.testing.assert_array_equal(a.eta, b.eta)
    np.testing.assert_array_equal(a.tau_demanded, b.tau_demanded)


def test_different_seed_different_run() -> None:
    a = simulate(closed_loop(seed=3, **NOISE))
    b = simulate(closed_loop(seed=4, **NOISE))
    assert np.max(np.abs(a.tau_demanded - b.tau_demanded)) > 1.0
    assert not np.array_equal(a.eta, b.eta)


def test_noise_reaches_the_controller_not_the_record() -> None:
    noisy = simulate(closed_loop(seed=3, **NOISE))
    clean = simulate(closed_loop(seed=3))
    # The recorded eta is the true state: at t = 0 it is eta0 exactly even
    # though the controller saw eta0 plus noise, and its tau differed.
    np.testing.assert_array_equal(noisy.eta[0], clean.eta[0])
    assert np.max(np.abs(noisy.tau_demanded[0] - clean.tau_demanded[0])) > 0.1


def test_zero_noise_ignores_the_seed() -> None:
    a = simulate(closed_loop(seed=0))
    b = simulate(closed_loop(seed=12345))
    np.testing.assert_array_equal(a.eta, b.eta)
    np.testing.assert_array_equal(a.nu, b.nu)
    np.testing.assert_array_equal(a.tau_demanded, b.tau_demanded)


# --- metrics and export -----------------------------------------------------------


@pytest.fixture(scope="module")
def result() -> Result:
    return simulate(closed_loop(duration=20.0, **NOISE, seed=1))


METRIC_KEYS = {
    "rmse_position_m", "max_position_error_m", "rmse_yaw_rad", "max_yaw_error_rad", "rmse",
    "max_abs_error", "iae", "mean_abs_tau", "max_abs_tau", "mean_abs_tau_dof", "max_abs_tau_dof",
    "control_energy", "final_adaptive_norm", "max_adaptive_norm", "refused_steps", "diverged",
}


def _numbers(value: object) -> list[float]:
    if isinstance(value, dict):
        return [x for v in value.values() for x in _numbers(v)]
    if isinstance(value, list):
        return [x for v in value for x in _numbers(v)]
    if value is None:  # diverged_at_s of a run that did not diverge
        return []
    return [float(value)]  # type: ignore[arg-type]


def test_metrics_keys_present_and_finite(result: Result) -> None:
    m = result.metrics()
    assert METRIC_KEYS <= set(m)
    assert set(m["rmse"]) == {"x", "y", "z", "roll", "pitch", "yaw"}
    assert all(math.isfinite(x) for x in _numbers(m))
    assert m["diverged"] is False and m["diverged_at_s"] is None
    assert m["rmse_position_m"] > 0 and m["control_energy"] > 0


def test_metrics_after_uses_only_the_later_samples(result: Result) -> None:
    after = 8.0
    m = result.metrics(after=after)
    keep = result.t >= after
    e = result.error[keep]
    pos = np.linalg.norm(e[:, :3], axis=1)
    assert m["rmse_position_m"] == pytest.approx(np.sqrt(np.mean(pos**2)), rel=1e-12)
    assert m["max_abs_tau"] == pytest.approx(np.max(np.abs(result.tau_demanded[keep])), rel=1e-12)
    # Spoiling every sample before `after` changes nothing after it.
    spoilt_eta = result.eta.copy()
    spoilt_eta[~keep] += 1000.0
    spoilt_tau = result.tau_demanded.copy()
    spoilt_tau[~keep] = 1e6
    spoilt = dataclasses.replace(result, eta=spoilt_eta, tau_demanded=spoilt_tau)
    assert spoilt.metrics(after=after) == m
    assert spoilt.metrics(after=0.0)["rmse_position_m"] > 100


@pytest.mark.parametrize("after", [20.01, 1e9, float("nan")])
def test_metrics_bad_after(result: Result, after: float) -> None:
    with pytest.raises(ValueError, match="after"):
        result.metrics(after=after)


def test_metrics_of_a_diverged_run_cover_what_was_simulated(result: Result) -> None:
    # Was: a diverged run's errors were all inf. Now its metrics are those of
    # its rows, flagged; a window it never reached falls back to every row.
    cut = dataclasses.replace(result, diverged=True, **{k: getattr(result, k)[:21] for k in SERIES})
    m = cut.metrics()
    assert m["diverged"] is True and m["diverged_at_s"] == pytest.approx(4.0)
    assert m["window_start_s"] == 0.0 and m["window_end_s"] == pytest.approx(4.0)
    pos = np.linalg.norm(cut.error[:, :3], axis=1)
    assert m["rmse_position_m"] == pytest.approx(np.sqrt(np.mean(pos**2)), rel=1e-12)
    assert dataclasses.replace(result, diverged=True).metrics(after=8.0)["window_start_s"] == pytest.approx(8.0)


def test_to_csv_has_a_header_and_one_row_per_step(result: Result, tmp_path: Path) -> None:
    path = result.to_csv(tmp_path / "r.csv")
    with path.open(newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    assert header[0] == "t" and "eta_x" in header and "tau_demanded_N" in header and "adaptive_norm" in header
    assert len(body) == len(result.t)
    assert all(len(r) == len(header) for r in body)
    col = header.index("eta_psi")
    np.testing.assert_allclose([float(r[col]) for r in body], result.eta[:, 5], rtol=1e-15)
    np.testing.assert_allclose([float(r[0]) for r in body], result.t, rtol=1e-15)


def test_to_npz_round_trips(result: Result, tmp_path: Path) -> None:
    path = result.to_npz(tmp_path / "r.npz")
    with np.load(path) as data:
        # Every series the Result holds, including any added later.
        names = [f.name for f in dataclasses.fields(Result) if isinstance(getattr(result, f.name), np.ndarray)]
        assert {"t", "eta", "nu", "tau_demanded", "thrusts", "theta", "adaptive_norm"} <= set(names)
        for name in names:
            np.testing.assert_array_equal(data[name], getattr(result, name), err_msg=name)
            assert data[name].dtype == getattr(result, name).dtype, name
        assert str(data["scenario"]) == "hold"
        assert str(data["controller"]) == "PD"
        assert not bool(data["diverged"])
