"""The PID baseline (anti-windup) and the sliding-mode controller (boundary
layer) as bound in neurov._core, against numpy written here from docs/model.md.

J comes from its printed closed form and J_dot from a central difference of
that J, so neither shares code with the library; NEROV's M, C (eq. 39), D and
g are typed in from docs/model.md, so "theta = true" is checked against the model,
not against the regressor itself.
"""

from __future__ import annotations

import numpy as np
import pytest

import neurov
from neurov.config.scenario import ControllerSpec, ScenarioError
from neurov.config.reading import scenario_from_mapping
from neurov.running.simulation import simulate

# This file's own seed (the points its tolerances were set on); `nerov` is
# conftest's.


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20260507)


# --- docs/model.md in numpy --------------------------------------------------


def spec_j(eta: np.ndarray) -> np.ndarray:
    f, t, p = eta[3:]
    cf, sf, ct, st, cp, sp = np.cos(f), np.sin(f), np.cos(t), np.sin(t), np.cos(p), np.sin(p)
    r = np.array([
        [cp * ct, -sp * cf + cp * st * sf, sp * sf + cp * cf * st],
        [sp * ct, cp * cf + sf * st * sp, -cp * sf + st * sp * cf],
        [-st, ct * sf, ct * cf],
    ])
    tt = np.array([[1, sf * st / ct, cf * st / ct], [0, cf, -sf], [0, sf / ct, cf / ct]])
    j = np.zeros((6, 6))
    j[:3, :3] = r
    j[3:, 3:] = tt
    return j


def numeric_j_dot(eta: np.ndarray, nu: np.ndarray) -> np.ndarray:
    h = 1e-6
    eta_dot = spec_j(eta) @ nu
    return (spec_j(eta + h * eta_dot) - spec_j(eta - h * eta_dot)) / (2 * h)


M_NEROV = np.diag([215.0, 265.0, 265.0, 40.0, 80.0, 80.0])


def c_nerov(nu: np.ndarray) -> np.ndarray:
    """eq. 39 with m = 185, X_udot = -30, Y_vdot = Z_wdot = -80, and
    I - (added) = 40, 80, 80."""
    u, v, w, p, q, r = nu
    m, xu, yv, zw = 185.0, -30.0, -80.0, -80.0
    ix, iy, iz = 40.0, 80.0, 80.0
    return np.array([
        [0, -m * r, m * q, 0, -zw * w, yv * v],
        [m * r, 0, -m * p, zw * w, 0, -xu * u],
        [-m * q, m * p, 0, -yv * v, xu * u, 0],
        [0, -zw * w, yv * v, 0, iz * r, -iy * q],
        [zw * w, 0, -xu * u, -iz * r, 0, ix * p],
        [-yv * v, xu * u, 0, iy * q, -ix * p, 0],
    ])


def d_nerov(nu: np.ndarray) -> np.ndarray:
    return np.diag(np.array([70, 100, 100, 30, 50, 50.0]) + np.array([100, 200, 200, 50, 100, 100.0]) * np.abs(nu))


def g_nerov(eta: np.ndarray) -> np.ndarray:
    f, t = eta[3], eta[4]
    return np.array([0, 0, 0, 0.02 * 1800 * np.cos(t) * np.sin(f), 0.02 * 1800 * np.sin(t), 0])


def tracking(eta, nu, eta_d, eta_d_dot, eta_d_ddot, lam):
    j = spec_j(eta)
    j_inv = np.linalg.inv(j)
    et = eta - eta_d
    etd = j @ nu - eta_d_dot
    s = etd + lam * et
    nu_r = j_inv @ (eta_d_dot - lam * et)
    nu_r_dot = j_inv @ ((eta_d_ddot - lam * etd) - numeric_j_dot(eta, nu) @ nu_r)
    return et, etd, s, nu_r, nu_r_dot


def random_pose(rng: np.random.Generator) -> np.ndarray:
    return np.r_[rng.uniform(-10, 10, 3), rng.uniform(-np.pi, np.pi), rng.uniform(-1.2, 1.2),
                 rng.uniform(-np.pi, np.pi)]


# --- PID ---------------------------------------------------------------------


def test_pid_tau_equals_numpy_with_the_integral_before_the_step(rng: np.random.Generator) -> None:
    for _ in range(10):
        kp, ki, kd = rng.uniform(0, 100, 6), rng.uniform(0.5, 20, 6), rng.uniform(0, 100, 6)
        pid = neurov.PIDController(kp, ki, kd, np.full(6, 1e9), dt=0.2)
        z = np.zeros(6)
        for _ in range(8):
            eta, eta_d = random_pose(rng), random_pose(rng)
            nu, eta_d_dot, eta_d_ddot = rng.uniform(-1, 1, (3, 6))
            tau = pid.step(eta, nu, eta_d, eta_d_dot, eta_d_ddot)
            et = eta - eta_d
            etd = spec_j(eta) @ nu - eta_d_dot
            expected = -spec_j(eta).T @ (kp * et + ki * z + kd * etd)
            np.testing.assert_allclose(tau, expected, rtol=1e-9, atol=1e-9 * np.abs(expected).max())
            z += 0.2 * et
            np.testing.assert_allclose(pid.integral, z, rtol=1e-12, atol=1e-12)


def test_pid_anti_windup_limits_the_integral_and_stops_integrating_into_the_limit() -> None:
    limit, ki = 10.0, 4.0
    pid = neurov.PIDController(np.zeros(6), np.full(6, ki), np.zeros(6), np.full(6, limit), dt=0.2)
    zero = np.zeros(6)
    eta_d = np.array([-1.0, 0, 0, 0, 0, 1.0])  # +1 m in x and -1 rad in yaw, held 100 s
    seen = []
    for _ in range(500):
        tau = pid.step(zero, zero, eta_d, zero, zero)
        seen.append(pid.integral.copy())
    seen_arr = np.array(seen)
    # A plain integrator would be at z = 100 now; this one never passes limit / K_i.
    assert np.abs(seen_arr).max() <= limit / ki
    assert pid.integral[0] == limit / ki and pid.integral[5] == -limit / ki
    np.testing.assert_allclose(tau[[0, 5]], [-limit, limit])
    # It reached the limit after 13 steps and then stayed there exactly.
    first = int(np.argmax(seen_arr[:, 0] >= limit / ki))
    assert first == 12
    assert np.all(seen_arr[first:, 0] == limit / ki)
    # The error reverses: the integral moves off the limit at the next step,
    # with no stored wind-up to unwind first.
    pid.step(zero, zero, np.array([0.5, 0, 0, 0, 0, 0]), zero, zero)
    assert pid.integral[0] == pytest.approx(limit / ki - 0.2 * 0.5)


def test_pid_refused_step_leaves_the_integrator_unchanged(rng: np.random.Generator) -> None:
    pid = neurov.PIDController(np.full(6, 10.0), np.full(6, 2.0), np.full(6, 5.0), np.full(6, 30.0))
    for _ in range(5):
        pid.step(random_pose(rng), rng.normal(size=6), random_pose(rng), np.zeros(6), np.zeros(6))
    before = pid.integral.copy()
    assert np.any(before != 0)
    at_singularity = np.array([0, 0, 0, 0, np.pi / 2, 0])
    with pytest.raises(ValueError, match="singularity"):
        pid.step(at_singularity, np.zeros(6), random_pose(rng), np.zeros(6), np.zeros(6))
    np.testing.assert_array_equal(pid.integral, before)
    bad = random_pose(rng)
    bad[1] = np.nan
    with pytest.raises(ValueError):
        pid.step(bad, np.zeros(6), random_pose(rng), np.zeros(6), np.zeros(6))
    np.testing.assert_array_equal(pid.integral, before)


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"kp": -np.ones(6)}, "kp"),
        ({"ki": np.r_[1, 1, np.nan, 1, 1, 1]}, "ki"),
        ({"kd": np.r_[1, 1, 1, 1, 1, -1]}, "kd"),
        ({"integral_limit": np.zeros(6)}, "integral_limit"),
        ({"dt": 0.0}, "dt"),
    ],
)
def test_pid_bad_configuration_names_the_field(kwargs: dict, field: str) -> None:
    args = {"kp": np.ones(6), "ki": np.ones(6), "kd": np.ones(6), "integral_limit": np.ones(6), "dt": 0.2}
    args.update(kwargs)
    with pytest.raises(ValueError, match=field):
        neurov.PIDController(**args)


# --- sliding mode ---------------------------------------------------------------


def test_smc_tau_with_the_true_theta_is_the_model_minus_jt_of_kd_s_plus_k_sat(
    rng: np.random.Generator, nerov: neurov.Vehicle
) -> None:
    theta = neurov.regressor_parameters(nerov)
    inside = outside = 0
    for _ in range(100):
        lam, kd = rng.uniform(0.1, 2, 6), rng.uniform(0, 200, 6)
        k, phi = rng.uniform(0, 100, 6), rng.uniform(0.05, 2, 6)
        smc = neurov.SlidingModeController(lam, kd, k, phi, theta)
        eta = random_pose(rng)
        eta_d = eta + rng.uniform(-0.5, 0.5, 6)
        nu, eta_d_dot, eta_d_ddot = rng.uniform(-1, 1, (3, 6))
        tau = smc.step(eta, nu, eta_d, eta_d_dot, eta_d_ddot)
        _, _, s, nu_r, nu_r_dot = tracking(eta, nu, eta_d, eta_d_dot, eta_d_ddot, lam)
        f = M_NEROV @ nu_r_dot + c_nerov(nu) @ nu_r + d_nerov(nu) @ nu_r + g_nerov(eta)
        x = s / phi
        inside += int(np.sum(np.abs(x) < 1))
        outside += int(np.sum(np.abs(x) >= 1))
        expected = f - spec_j(eta).T @ (kd * s + k * np.clip(x, -1, 1))
        scale = max(np.abs(expected).max(), np.abs(f).max(), 1.0)
        np.testing.assert_allclose(tau, expected, rtol=0, atol=1e-6 * scale)
        np.testing.assert_allclose(smc.model_output, f, rtol=0, atol=1e-6 * scale)
        np.testing.assert_allclose(smc.s, s, rtol=0, atol=1e-9 * max(1, np.abs(s).max()))
    assert inside > 50 and outside > 50


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"lambda_": np.zeros(6)}, "lambda"),
        ({"kd": -np.ones(6)}, "kd"),
        ({"k": np.r_[0, 0, -1, 0, 0, 0]}, "k"),
        ({"phi": np.zeros(6)}, "phi"),
        ({"theta": np.full(24, np.inf)}, "theta"),
    ],
)
def test_smc_bad_configuration_names_the_field(kwargs: dict, field: str) -> None:
    args = {"lambda_": np.ones(6), "kd": np.ones(6), "k": np.ones(6), "phi": np.ones(6),
            "theta": np.zeros(24)}
    args.update(kwargs)
    with pytest.raises(ValueError, match=field):
        neurov.SlidingModeController(**args)


# --- in scenario files ------------------------------------------------------------


def _scenario(controller: dict) -> dict:
    return {
        "duration": 60.0,
        "command": {"type": "waypoints", "times": [0.0, 5.0], "poses": [[0] * 6, [2, 1, 1, 0, 0, 0.5]]},
        "controller": controller,
    }


def test_pid_and_smc_scenarios_track_a_step() -> None:
    pid = scenario_from_mapping(_scenario({
        "type": "pid", "kp": [100, 100, 100, 40, 40, 40], "ki": [10, 10, 10, 4, 4, 4],
        "kd": [200, 200, 200, 50, 50, 50], "integral_limit": 100.0}))
    smc = scenario_from_mapping(_scenario({
        "type": "smc", "lambda": 0.5, "kd": [200, 200, 200, 50, 50, 50], "k": 20.0, "phi": 0.1}))
    for s in (pid, smc):
        r = simulate(s)
        assert not r.diverged
        # The last 10 s: settled on the commanded pose.
        assert r.metrics(after=50.0)["rmse_position_m"] < 0.05


def test_bad_pid_field_in_a_scenario_file_is_named() -> None:
    with pytest.raises(ScenarioError, match=r"controller\.integral_limit"):
        scenario_from_mapping(_scenario({"type": "pid", "kp": 1.0, "ki": 1.0, "integral_limit": -1.0}),
                              "x.toml")
    with pytest.raises(ScenarioError, match=r"x\.toml: controller\.k\[2\] = -1: expected >= 0"):
        scenario_from_mapping(_scenario({"type": "smc", "phi": 0.1, "k": [0, 0, -1, 0, 0, 0]}), "x.toml")
    assert ControllerSpec(type="smc").name == "sliding mode"
