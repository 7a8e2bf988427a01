"""The computed-torque controller from Python: tau against the law evaluated
in numpy, with the tracking error written out here and M, C, D, g taken
from the vehicle (its bound functions) or from the independent numpy model
(reference_model.py); its configuration object; bad arguments named."""

from __future__ import annotations

import pickle
from typing import Any

import numpy as np
import pytest

import neurov
import reference_model as ref

N_POINTS = 30


def expected_tau(
    m: np.ndarray,
    c: np.ndarray,
    d: np.ndarray,
    g: np.ndarray,
    eta: np.ndarray,
    nu: np.ndarray,
    desired: tuple[np.ndarray, np.ndarray, np.ndarray],
    lam: np.ndarray,
    kd: np.ndarray,
) -> np.ndarray:
    """tau = M nu_r_dot + C nu_r + D nu_r + g - J^T K_d s, eq. 11 and 14-16 in numpy."""
    eta_d, eta_d_dot, eta_d_ddot = desired
    j, j_inv = ref.jacobian(eta), ref.jacobian_inverse(eta)
    eta_tilde = eta - eta_d
    eta_tilde_dot = j @ nu - eta_d_dot
    s = eta_tilde_dot + lam * eta_tilde
    nu_r = j_inv @ (eta_d_dot - lam * eta_tilde)
    j_dot = neurov.jacobian_dot(eta, nu)
    nu_r_dot = j_inv @ (eta_d_ddot - lam * eta_tilde_dot - j_dot @ nu_r)
    return m @ nu_r_dot + c @ nu_r + d @ nu_r + g - j.T @ (kd * s)


def random_case(rng: np.random.Generator) -> dict[str, Any]:
    eta = ref.random_pose(rng, 1.2)
    return {
        "eta": eta,
        "nu": ref.random_velocity(rng),
        "desired": (eta + rng.uniform(-0.5, 0.5, 6), rng.uniform(-1, 1, 6), rng.uniform(-1, 1, 6)),
        "lam": rng.uniform(0.1, 2.0, 6),
        "kd": rng.uniform(0.0, 300.0, 6),
    }


def test_tau_is_the_inverse_dynamics_of_the_vehicles_own_model(
    general_vehicle: neurov.Vehicle, rng: np.random.Generator
) -> None:
    for _ in range(N_POINTS):
        k = random_case(rng)
        ctl = neurov.ComputedTorqueController(general_vehicle, k["lam"], k["kd"])
        tau = ctl.step(k["eta"], k["nu"], *k["desired"])
        v, nu = general_vehicle, k["nu"]
        expected = expected_tau(
            v.mass_matrix(), v.coriolis(nu), v.damping(nu), v.restoring(k["eta"]), **k
        )
        np.testing.assert_allclose(tau, expected, rtol=1e-9, atol=1e-9 * np.abs(expected).max())


def test_tau_matches_the_independent_numpy_model(
    general_parameters: dict[str, Any], general_vehicle: neurov.Vehicle, rng: np.random.Generator
) -> None:
    p = general_parameters
    for _ in range(N_POINTS):
        k = random_case(rng)
        config = neurov.ComputedTorqueConfig(lambda_=k["lam"], kd=k["kd"], vehicle=general_vehicle)
        ctl = neurov.ComputedTorqueController(config)
        tau = ctl.step(k["eta"], k["nu"], *k["desired"])
        nu = k["nu"]
        m, c, d, g = ref.mass_matrix(p), ref.coriolis(p, nu), ref.damping(p, nu), ref.restoring(p, k["eta"])
        expected = expected_tau(m, c, d, g, **k)
        np.testing.assert_allclose(tau, expected, rtol=1e-9, atol=1e-9 * np.abs(expected).max())
        np.testing.assert_allclose(
            ctl.model_output, expected + ref.jacobian(k["eta"]).T @ (k["kd"] * ctl.s), rtol=1e-9,
            atol=1e-9 * np.abs(expected).max(),
        )


def test_config_object_and_keyword_constructor_build_the_same_controller(nerov: neurov.Vehicle) -> None:
    lam, kd = np.full(6, 0.8), np.array([200.0, 200.0, 200.0, 50.0, 50.0, 50.0])
    a = neurov.ComputedTorqueController(nerov, lam, kd)
    config = neurov.ComputedTorqueConfig()
    assert config.vehicle is None
    np.testing.assert_array_equal(config.lambda_, np.full(6, 0.5))  # the C++ default
    config.lambda_, config.kd, config.vehicle = lam, kd, nerov
    b = neurov.ComputedTorqueController(config)
    eta, nu = np.array([1.0, -2.0, 0.5, 0.1, -0.2, 0.3]), np.array([0.3, -0.1, 0.05, 0.02, -0.03, 0.1])
    z = np.zeros(6)
    np.testing.assert_array_equal(a.step(eta, nu, z, z, z), b.step(eta, nu, z, z, z))
    np.testing.assert_array_equal(a.config.kd, kd)
    assert a.config.vehicle.parameters().keys() == nerov.parameters().keys()
    np.testing.assert_array_equal(a.config.vehicle.mass_matrix(), nerov.mass_matrix())
    copy = pickle.loads(pickle.dumps(config))
    np.testing.assert_array_equal(copy.kd, kd)
    np.testing.assert_array_equal(copy.vehicle.mass_matrix(), nerov.mass_matrix())


def test_bad_arguments_are_named(nerov: neurov.Vehicle) -> None:
    good = np.ones(6)
    with pytest.raises(ValueError, match=r"computed-torque controller: kd\[2\] = -1: expected >= 0"):
        neurov.ComputedTorqueController(nerov, good, [1, 1, -1, 1, 1, 1])
    with pytest.raises(ValueError, match=r"lambda\[0\] = 0: expected > 0"):
        neurov.ComputedTorqueController(nerov, np.r_[0.0, good[1:]], good)
    with pytest.raises(ValueError, match="'lambda_' must have shape \\(6,\\)"):
        neurov.ComputedTorqueController(nerov, np.ones(5), good)
    with pytest.raises(TypeError, match="lamda"):
        neurov.ComputedTorqueController(nerov, lamda=good, kd=good)  # type: ignore[call-overload]
    with pytest.raises(TypeError, match="unexpected keyword argument 'lamda'.*lambda_, kd, vehicle"):
        neurov.ComputedTorqueConfig(lamda=good)
    with pytest.raises(TypeError, match="ComputedTorqueConfig.vehicle must be a Vehicle"):
        neurov.ComputedTorqueConfig(vehicle=nerov.parameters())
    with pytest.raises(ValueError, match=r"ComputedTorqueConfig.kd must have shape \(6,\), got \(7,\)"):
        neurov.ComputedTorqueConfig(kd=np.ones(7))
    # Without a vehicle the validator names the first bad vehicle field.
    with pytest.raises(ValueError, match="computed-torque controller: mass = 0"):
        neurov.ComputedTorqueConfig().validate()
    with pytest.raises(ValueError, match="computed-torque controller: mass"):
        neurov.ComputedTorqueController(neurov.ComputedTorqueConfig())
    assert neurov.ComputedTorqueConfig(vehicle=nerov).validate() is None


def test_refused_step_raises_and_changes_nothing(nerov: neurov.Vehicle) -> None:
    ctl = neurov.ComputedTorqueController(nerov, np.ones(6), np.full(6, 100.0))
    eta, nu, z = np.array([1.0, 0, 0, 0.1, 0.2, 0.3]), np.full(6, 0.1), np.zeros(6)
    ctl.step(eta, nu, z, z, z)
    before = ctl.tracking
    with pytest.raises(ValueError, match="'nu' must be finite"):
        ctl.step(eta, np.r_[np.nan, nu[1:]], z, z, z)
    with pytest.raises(ValueError, match="singularity"):
        ctl.step(np.r_[eta[:4], np.pi / 2, eta[5]], nu, z, z, z)
    after = ctl.tracking
    for key in before:
        np.testing.assert_array_equal(before[key], after[key], err_msg=key)


def test_every_controller_config_round_trips_and_names_an_unknown_field() -> None:
    for cls in (
        neurov.PDConfig,
        neurov.PIDConfig,
        neurov.SlidingModeConfig,
        neurov.LinearAdaptiveConfig,
        neurov.NNAdaptiveConfig,
        neurov.ComputedTorqueConfig,
    ):
        config = cls()
        fields = [n for n, v in vars(cls).items() if isinstance(v, property)]
        state = pickle.loads(pickle.dumps(config))
        for name in fields:
            a, b = getattr(config, name), getattr(state, name)
            if isinstance(a, np.ndarray):
                np.testing.assert_array_equal(a, b, err_msg=f"{cls.__name__}.{name}")
            else:
                assert a == b or (a is None and b is None), f"{cls.__name__}.{name}"
        with pytest.raises(TypeError, match=f"{cls.__name__}\\(\\) got an unexpected keyword argument 'nope'"):
            cls(nope=1)
        assert cls.__name__ in repr(config)


def test_controllers_are_built_from_their_config_objects(nerov: neurov.Vehicle) -> None:
    """The same configuration through the keyword constructor and the config object."""
    eta, nu, z = np.array([1.0, -2.0, 0.5, 0.1, -0.2, 0.3]), np.full(6, 0.1), np.zeros(6)
    kp, kd = np.full(6, 50.0), np.full(6, 20.0)
    theta = neurov.regressor_parameters(nerov)
    pairs = [
        (neurov.PDController(kp, kd), neurov.PDController(neurov.PDConfig(kp=kp, kd=kd))),
        (
            neurov.PIDController(kp, kp / 10, kd, np.full(6, 30.0), 0.1),
            neurov.PIDController(
                neurov.PIDConfig(kp=kp, ki=kp / 10, kd=kd, integral_limit=np.full(6, 30.0), dt=0.1)
            ),
        ),
        (
            neurov.SlidingModeController(np.ones(6), kd, kp, np.full(6, 0.1), theta),
            neurov.SlidingModeController(
                neurov.SlidingModeConfig(lambda_=np.ones(6), kd=kd, k=kp, phi=np.full(6, 0.1), theta=theta)
            ),
        ),
        (
            neurov.LinearAdaptiveController(np.ones(6), kd, 2.0, 0.1, theta),
            neurov.LinearAdaptiveController(
                neurov.LinearAdaptiveConfig(lambda_=np.ones(6), kd=kd, gamma=2.0, dt=0.1, theta0=theta)
            ),
        ),
    ]
    net = neurov.RbfNetwork(np.random.default_rng(1).uniform(-1, 1, (8, 24)), 2.0)
    nn_config = neurov.NNAdaptiveConfig(kd=kd, modification="sigma", sigma_m=0.1)
    assert nn_config.modification == neurov.RobustModification.sigma
    pairs.append(
        (
            neurov.NNAdaptiveController(net, np.full(6, 0.5), kd, modification="sigma", sigma_m=0.1),
            neurov.NNAdaptiveController(net, nn_config),
        )
    )
    for a, b in pairs:
        for _ in range(3):
            np.testing.assert_array_equal(a.step(eta, nu, z, z, z), b.step(eta, nu, z, z, z))
    with pytest.raises(ValueError, match=r"PD controller: kp\[0\] = -1: expected >= 0"):
        neurov.PDController(neurov.PDConfig(kp=np.r_[-1.0, kp[1:]]))
    with pytest.raises(ValueError, match=r"sigma_m = 0: expected > 0 with modification 'sigma'"):
        neurov.NNAdaptiveConfig(modification=neurov.RobustModification.sigma).validate()
